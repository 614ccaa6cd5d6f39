//! `hipop lsp`: the transports it accepts and those it refuses.

use super::*;

/// Speaks LSP to `hipop lsp ARGS` over its stdin and stdout: initialize,
/// shutdown, exit. Returns the initialize result and the exit status.
fn lsp_session(args: &[&str]) -> (Value, i32) {
    use std::io::{BufRead, BufReader, Write};
    use std::process::Stdio;

    fn send(stdin: &mut impl Write, message: Value) {
        let body = message.to_string();
        write!(stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).expect("writing to the server");
        stdin.flush().expect("flushing");
    }
    /// The next response with this id (notifications and requests from the server skipped).
    fn response(reader: &mut impl BufRead, id: i64) -> Value {
        loop {
            let mut length = None;
            loop {
                let mut line = String::new();
                assert!(
                    reader.read_line(&mut line).expect("reading a header") > 0,
                    "the server closed stdout"
                );
                let line = line.trim_end();
                if line.is_empty() {
                    break;
                }
                if let Some(v) = line.strip_prefix("Content-Length:") {
                    length = Some(v.trim().parse::<usize>().expect("a length"));
                }
            }
            let mut body = vec![0; length.expect("a Content-Length header")];
            reader.read_exact(&mut body).expect("reading a body");
            let message: Value = serde_json::from_slice(&body).expect("a JSON message");
            if message["id"] == id && message.get("method").is_none() {
                return message;
            }
        }
    }

    let mut child = Command::new(env!("CARGO_BIN_EXE_hipop"))
        .arg("lsp")
        .args(args)
        .current_dir(workspace_root())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("hipop lsp starts");
    let mut stdin = child.stdin.take().expect("stdin");
    let mut stdout = BufReader::new(child.stdout.take().expect("stdout"));
    send(
        &mut stdin,
        serde_json::json!({"jsonrpc": "2.0", "id": 1, "method": "initialize",
            "params": {"processId": null, "rootUri": null, "capabilities": {}}}),
    );
    let init = response(&mut stdout, 1);
    send(&mut stdin, serde_json::json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}));
    send(&mut stdin, serde_json::json!({"jsonrpc": "2.0", "id": 2, "method": "shutdown"}));
    let shutdown = response(&mut stdout, 2);
    assert_eq!(shutdown["result"], Value::Null, "{shutdown}");
    send(&mut stdin, serde_json::json!({"jsonrpc": "2.0", "method": "exit"}));
    drop(stdin);
    let status = child.wait().expect("hipop lsp exits").code().expect("an exit status");
    (init, status)
}

/// Language clients add `--stdio` to the server's command line (VS Code's
/// vscode-languageclient does with `transport: stdio`): refusing it as an
/// unknown argument left VS Code with no server at all.
#[test]
fn lsp_serves_with_and_without_stdio() {
    for args in [&[][..], &["--stdio"][..]] {
        let (init, status) = lsp_session(args);
        assert_eq!(init["result"]["capabilities"]["hoverProvider"], true, "hipop lsp {args:?}: {init}");
        assert_eq!(init["result"]["serverInfo"]["name"], "hipop", "hipop lsp {args:?}: {init}");
        assert_eq!(status, 0, "hipop lsp {args:?}");
    }
}

/// The other transports of the convention are refused by name, as a usage
/// error, before anything is read from standard input.
#[test]
fn lsp_refuses_other_transports() {
    for (args, shown) in [
        (&["--socket=5007"][..], "`--socket=5007`"),
        (&["--socket", "5007"][..], "`--socket=5007`"),
        (&["--pipe=/tmp/hipop.sock"][..], "`--pipe=/tmp/hipop.sock`"),
        (&["--node-ipc"][..], "`--node-ipc`"),
        (&["--stdio", "--socket=5007"][..], "`--socket=5007`"),
    ] {
        let mut full = vec!["lsp"];
        full.extend_from_slice(args);
        let o = hipop(&full);
        assert_no_panic(&o);
        assert_eq!(status(&o), 2, "hipop {full:?}: {}", stderr(&o));
        assert_eq!(stdout(&o), "", "hipop {full:?}: nothing goes to the client");
        let err = stderr(&o);
        assert!(
            err.contains(shown) && err.contains("serves only standard input and output"),
            "hipop {full:?}:\n{err}"
        );
    }
}
