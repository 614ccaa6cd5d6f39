//! Test support: the `hipop` binary, and a JSON-RPC client speaking LSP to it
//! over stdio, with a timeout on every wait so that a hang fails the test.

#![allow(dead_code, reason = "each test file uses a different part")]

use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::OnceLock;
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

pub const TIMEOUT: Duration = Duration::from_secs(30);

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("lsp/ is inside the workspace").to_path_buf()
}

pub fn fixture(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(rel)
}

/// A fresh folder in the temporary directory, removed with what it holds
/// when the test is done (even when it fails).
pub struct Scratch(PathBuf);

impl Scratch {
    pub fn new(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("hipop-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch folder");
        Scratch(dir)
    }

    /// With copies of `files` of the fixture folder `from`.
    pub fn with_fixture(name: &str, from: &str, files: &[&str]) -> Scratch {
        let dir = Scratch::new(name);
        for file in files {
            std::fs::copy(fixture(from).join(file), dir.join(file)).expect("copying a fixture");
        }
        dir
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

pub fn file_uri(path: &Path) -> String {
    let mut uri = String::from("file://");
    for b in path.to_str().expect("UTF-8 path").bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => uri.push(b as char),
            _ => uri.push_str(&format!("%{b:02X}")),
        }
    }
    uri
}

/// The `hipop` binary: `$HIPOP_BIN`, else the workspace's, built once per test
/// process with `cargo build -p hipop` (a no-op when up to date) so that the
/// test never runs a stale server.
pub fn hipop_bin() -> &'static Path {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        if let Some(bin) = std::env::var_os("HIPOP_BIN") {
            return PathBuf::from(bin);
        }
        // The test executable is `target/<profile>/deps/<test>-<hash>`.
        let exe = std::env::current_exe().expect("the test executable");
        let profile_dir = exe.parent().and_then(Path::parent).expect("target/<profile>/deps");
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let mut build = Command::new(cargo);
        build.current_dir(workspace_root()).args(["build", "-p", "hipop"]);
        if profile_dir.file_name().is_some_and(|n| n == "release") {
            build.arg("--release");
        }
        let status = build.status().expect("running cargo build -p hipop");
        assert!(status.success(), "cargo build -p hipop failed");
        let bin = profile_dir.join(format!("hipop{}", std::env::consts::EXE_SUFFIX));
        assert!(bin.exists(), "{} does not exist after the build", bin.display());
        bin
    })
}

/// An LSP client talking to `hipop lsp` over its stdin/stdout.
pub struct Client {
    child: Child,
    stdin: ChildStdin,
    incoming: Receiver<Value>,
    /// Notifications received while waiting for something else.
    pub notifications: VecDeque<Value>,
    /// Every notification and server request received, in order.
    pub log: Vec<Value>,
    /// The server's requests answered with an error instead of `null`.
    pub refuse: Vec<&'static str>,
    next_id: i64,
}

fn read_message(reader: &mut impl BufRead) -> Option<Value> {
    let mut length = None;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).ok()? == 0 {
            return None;
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(v) = line.strip_prefix("Content-Length:") {
            length = v.trim().parse::<usize>().ok();
        }
    }
    let mut body = vec![0; length?];
    reader.read_exact(&mut body).ok()?;
    serde_json::from_slice(&body).ok()
}

impl Client {
    pub fn spawn() -> Client {
        Client::spawn_with_env(&[])
    }

    /// A server with extra environment variables.
    pub fn spawn_with_env(env: &[(&str, &str)]) -> Client {
        let mut child = Command::new(hipop_bin())
            .arg("lsp")
            .envs(env.iter().copied())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("spawning hipop lsp");
        let stdin = child.stdin.take().expect("stdin");
        let stdout = child.stdout.take().expect("stdout");
        let (tx, incoming) = channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            while let Some(message) = read_message(&mut reader) {
                if tx.send(message).is_err() {
                    break;
                }
            }
        });
        Client {
            child,
            stdin,
            incoming,
            notifications: VecDeque::new(),
            log: Vec::new(),
            refuse: Vec::new(),
            next_id: 1,
        }
    }

    fn send(&mut self, message: &Value) {
        let body = message.to_string();
        write!(self.stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).expect("writing to the server");
        self.stdin.flush().expect("flushing to the server");
    }

    pub fn notify(&mut self, method: &str, params: Value) {
        self.send(&json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// The next message; the server's own requests are answered with `null`,
    /// or an error for those in `refuse` (and returned too, for tests that
    /// check them).
    fn next(&mut self, deadline: Instant) -> Value {
        let left = deadline.saturating_duration_since(Instant::now());
        let message = match self.incoming.recv_timeout(left) {
            Ok(m) => m,
            Err(RecvTimeoutError::Timeout) => panic!("timed out; messages so far: {:#?}", self.log),
            Err(RecvTimeoutError::Disconnected) => panic!("the server closed its output"),
        };
        if message.get("method").is_some() && message.get("id").is_some() {
            let id = message["id"].clone();
            if message["method"].as_str().is_some_and(|m| self.refuse.contains(&m)) {
                let error = json!({"code": -32601, "message": "not supported by this client"});
                self.send(&json!({"jsonrpc": "2.0", "id": id, "error": error}));
            } else {
                self.send(&json!({"jsonrpc": "2.0", "id": id, "result": null}));
            }
        }
        message
    }

    pub fn is_response(message: &Value) -> bool {
        message.get("method").is_none()
    }

    /// The next message from the server, whatever it is.
    pub fn recv(&mut self) -> Value {
        let message = self.next(Instant::now() + TIMEOUT);
        self.log.push(message.clone());
        message
    }

    /// Sends a request without waiting for its response; returns its id.
    pub fn send_request(&mut self, method: &str, params: Value) -> i64 {
        let id = self.next_id;
        self.next_id += 1;
        self.send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        id
    }

    /// Sends a request and returns the whole response (`result` or `error`).
    pub fn request_raw(&mut self, method: &str, params: Value) -> Value {
        let id = self.send_request(method, params);
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let message = self.next(deadline);
            if Client::is_response(&message) && message.get("id") == Some(&json!(id)) {
                return message;
            }
            self.log.push(message.clone());
            self.notifications.push_back(message);
        }
    }

    /// Sends a request and returns its result; an error response fails the test.
    pub fn request(&mut self, method: &str, params: Value) -> Value {
        let response = self.request_raw(method, params);
        assert!(response.get("error").is_none(), "{method} failed: {response}");
        response["result"].clone()
    }

    /// Waits for a notification satisfying `pred`, consuming the ones before it.
    pub fn wait_for(&mut self, what: &str, pred: impl Fn(&Value) -> bool) -> Value {
        while let Some(n) = self.notifications.pop_front() {
            if pred(&n) {
                return n;
            }
        }
        let deadline = Instant::now() + TIMEOUT;
        loop {
            let message = self.next(deadline);
            if Client::is_response(&message) {
                panic!("unexpected response while waiting for {what}: {message}");
            }
            self.log.push(message.clone());
            if pred(&message) {
                return message;
            }
        }
    }

    /// Waits for the diagnostics of `uri` at `version`.
    pub fn diagnostics(&mut self, uri: &str, version: Option<i64>) -> Vec<Value> {
        let what = format!("diagnostics of {uri} v{version:?}");
        let n = self.wait_for(&what, |n| {
            n["method"] == "textDocument/publishDiagnostics"
                && n["params"]["uri"] == uri
                && version.is_none_or(|v| n["params"]["version"] == v)
        });
        n["params"]["diagnostics"].as_array().cloned().unwrap_or_default()
    }

    /// Every version published for `uri` so far.
    pub fn published_versions(&self, uri: &str) -> Vec<i64> {
        self.log
            .iter()
            .filter(|n| n["method"] == "textDocument/publishDiagnostics" && n["params"]["uri"] == uri)
            .filter_map(|n| n["params"]["version"].as_i64())
            .collect()
    }

    pub fn initialize(&mut self, root: &Path, capabilities: Value) -> Value {
        self.initialize_as(root, capabilities, Value::Null)
    }

    /// `initialize` with a `clientInfo` (`null` for none).
    pub fn initialize_as(&mut self, root: &Path, capabilities: Value, client_info: Value) -> Value {
        self.initialize_with(root, capabilities, client_info, Value::Null)
    }

    /// `initialize` with a `clientInfo` and `initializationOptions` (`null` for none).
    pub fn initialize_with(
        &mut self,
        root: &Path,
        capabilities: Value,
        client_info: Value,
        options: Value,
    ) -> Value {
        let uri = file_uri(root);
        let result = self.request(
            "initialize",
            json!({
                "processId": null,
                "clientInfo": client_info,
                "rootUri": uri,
                "capabilities": capabilities,
                "workspaceFolders": [{"uri": uri, "name": "root"}],
                "initializationOptions": options,
            }),
        );
        self.notify("initialized", json!({}));
        result
    }

    pub fn open(&mut self, uri: &str, text: &str) {
        self.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": "pddl", "version": 1, "text": text}}),
        );
    }

    /// One incremental change replacing `range` by `text`.
    pub fn change(&mut self, uri: &str, version: i64, range: Value, text: &str) {
        self.notify(
            "textDocument/didChange",
            json!({
                "textDocument": {"uri": uri, "version": version},
                "contentChanges": [{"range": range, "text": text}],
            }),
        );
    }

    /// `shutdown` then `exit`; the server must exit successfully and promptly.
    pub fn shutdown(mut self) {
        assert_eq!(self.request("shutdown", Value::Null), Value::Null);
        self.notify("exit", Value::Null);
        let deadline = Instant::now() + TIMEOUT;
        loop {
            if let Some(status) = self.child.try_wait().expect("waiting for the server") {
                assert!(status.success(), "the server exited with {status}");
                return;
            }
            assert!(Instant::now() < deadline, "the server did not exit after `exit`");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Client {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A position as JSON.
pub fn pos(line: u32, character: u32) -> Value {
    json!({"line": line, "character": character})
}

/// `{textDocument, position}` params.
pub fn at(uri: &str, line: u32, character: u32) -> Value {
    json!({"textDocument": {"uri": uri}, "position": pos(line, character)})
}

/// A range as JSON.
pub fn range(l1: u32, c1: u32, l2: u32, c2: u32) -> Value {
    json!({"start": pos(l1, c1), "end": pos(l2, c2)})
}
