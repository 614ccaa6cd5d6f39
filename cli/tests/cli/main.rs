//! End-to-end tests of the `hipop` binary: exit statuses, the output formats
//! (snapshots) and the handling of bad inputs. Every command runs from the
//! workspace root with relative paths, so the snapshots hold no machine path.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

const E0102: &str = "samples/broken/E0102-undefined-predicate.pddl";
/// A fixture with one warning and no error.
const WARNING_ONLY: &str = "samples/broken/W0201-unused-declaration.pddl";

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn hipop(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hipop"))
        .args(args)
        .current_dir(workspace_root())
        .env_remove("NO_COLOR")
        .env_remove("CLICOLOR_FORCE")
        .output()
        .expect("the hipop binary runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).expect("stdout is UTF-8")
}

fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).expect("stderr is UTF-8")
}

fn status(o: &Output) -> i32 {
    o.status.code().expect("hipop exits with a status, not a signal")
}

fn assert_no_panic(o: &Output) {
    let err = stderr(o);
    assert!(!err.contains("panicked"), "hipop panicked:\n{err}");
}

mod check;
mod diff;
mod fmt;
mod hostile;
mod lsp;
mod plan;
mod repair;
mod validate;

/// A temporary file removed on drop.
struct TempFile(PathBuf);

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// A temporary folder removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("hipop-cli-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp folder created");
        TempDir(dir)
    }

    /// Copies a file of the workspace into the folder; returns its new path.
    fn copy(&self, rel: &str) -> PathBuf {
        let to = self.0.join(Path::new(rel).file_name().expect("a file name"));
        std::fs::copy(workspace_root().join(rel), &to).expect("fixture copied");
        to
    }

    fn path(&self) -> &str {
        self.0.to_str().expect("UTF-8 temp path")
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn help_succeeds() {
    let o = hipop(&["--help"]);
    assert_eq!(status(&o), 0);
    let out = stdout(&o);
    assert!(out.contains("check"), "--help lists the check command:\n{out}");

    let o = hipop(&["check", "--help"]);
    assert_eq!(status(&o), 0);
    let out = stdout(&o);
    assert!(out.contains("--format") && out.contains("--deny"), "check --help lists its options:\n{out}");
}

/// docs/cli.md documents every subcommand and every flag the binary has (as
/// its `--help` lists them), so that `--help`'s pointers to it lead somewhere.
#[test]
fn docs_cli_md_documents_every_command_and_flag() {
    let doc = std::fs::read_to_string(workspace_root().join("docs/cli.md")).expect("docs/cli.md");
    let help = stdout(&hipop(&["--help"]));
    let commands: Vec<&str> = help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert_eq!(commands, ["check", "diff", "validate", "plan", "repair", "fmt", "lsp"]);
    for command in commands {
        assert!(doc.contains(&format!("## `hipop {command}`")), "no section for `hipop {command}`");
        let help = stdout(&hipop(&[command, "--help"]));
        let flags: Vec<&str> = help
            .lines()
            .filter_map(|l| {
                l.trim_start().split_once("--").filter(|(short, _)| short.is_empty() || short.ends_with(", "))
            })
            .filter_map(|(_, rest)| rest.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-')).next())
            .filter(|f| *f != "help")
            .collect();
        assert!(!flags.is_empty() || command == "lsp", "no flags read from `hipop {command} --help`");
        for flag in flags {
            assert!(
                doc.contains(&format!("--{flag}")),
                "docs/cli.md does not mention `hipop {command} --{flag}`"
            );
        }
    }
}
