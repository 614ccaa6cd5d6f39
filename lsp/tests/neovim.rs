//! A real editor as the client: Neovim (0.7 or later) headless opens a file,
//! attaches `hipop lsp`, and reports the diagnostics and a hover it received.
//! Skipped, with a message, when `nvim` is not installed.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{fixture, hipop_bin};

fn nvim_version() -> Option<String> {
    let output = Command::new("nvim").arg("--version").output().ok()?;
    let version = String::from_utf8_lossy(&output.stdout);
    output.status.success().then(|| version.lines().next().unwrap_or("").to_string())
}

#[test]
fn neovim_shows_the_diagnostics() {
    let Some(version) = nvim_version() else {
        eprintln!("SKIP: neovim (nvim) not installed; .ci/run installs it");
        return;
    };
    eprintln!("running {version}");
    let out = std::env::temp_dir().join(format!("hipop-nvim-{}.txt", std::process::id()));
    let _ = std::fs::remove_file(&out);
    let mut nvim = Command::new("nvim")
        .args(["--headless", "-u", "NONE", "-i", "NONE", "-n", "-c"])
        .arg(format!(
            "luafile {}",
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/neovim/diagnostics.lua").display()
        ))
        .env("HIPOP_BIN", hipop_bin())
        .env("HIPOP_FILE", fixture("unicode/domain.pddl"))
        .env("HIPOP_OUT", &out)
        // On `été` in `:precondition (été ?x)`.
        .env("HIPOP_HOVER_LINE", "6")
        .env("HIPOP_HOVER_CHAR", "20")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .spawn()
        .expect("spawning nvim");
    let deadline = Instant::now() + Duration::from_secs(60);
    let status = loop {
        if let Some(status) = nvim.try_wait().expect("waiting for nvim") {
            break status;
        }
        if Instant::now() > deadline {
            let _ = nvim.kill();
            panic!("nvim did not finish in 60 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let report =
        std::fs::read_to_string(&out).unwrap_or_else(|e| panic!("no report from nvim ({status}): {e}"));
    let _ = std::fs::remove_file(&out);
    let lines: Vec<&str> = report.lines().collect();
    // Byte columns, converted by Neovim from UTF-16: `été` is 3 units but 5 bytes.
    assert_eq!(
        lines[..2],
        [
            "diagnostic 3:27-3:32 W0201 predicate `prêt` is never used",
            "diagnostic 7:29-7:33 E0102 undefined predicate `😀`",
        ],
        "{report}"
    );
    assert!(lines.contains(&"hover predicate (été ?x)"), "{report}");
    assert!(status.success(), "nvim exited with {status}");
}
