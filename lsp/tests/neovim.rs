//! A real editor as the client: Neovim (0.7 or later) headless, with the
//! configuration users load (`editors/neovim/hipop.lua`), opens files and
//! reports what it received from `hipop lsp`. Skipped, with a message, when
//! `nvim` is not installed.

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

/// Neovim with the config users load (`editors/neovim/hipop.lua`, as is):
/// file types, one server per workspace, diagnostics in a domain and a plan,
/// a hover, and a domain changed on disk behind Neovim (which does not watch
/// files for servers) re-checking its open problem.
#[test]
fn neovim_with_the_shipped_config() {
    let Some(version) = nvim_version() else {
        eprintln!("SKIP: neovim (nvim) not installed; .ci/run installs it");
        return;
    };
    eprintln!("running {version}");
    // A problem and its domain in a folder of their own, to change on disk.
    let scratch = common::Scratch::with_fixture("nvim-blocks", "blocks", &["domain.pddl", "problem.pddl"]);
    let (report, status) = run_nvim(
        "diagnostics.lua",
        &[
            ("HIPOP_FILE", fixture("unicode/domain.pddl")),
            // On `été` in `:precondition (été ?x)`.
            ("HIPOP_HOVER_LINE", "6".into()),
            ("HIPOP_HOVER_CHAR", "20".into()),
            ("HIPOP_PLAN", fixture("plan/problem.plan")),
            ("HIPOP_PROBLEM", scratch.join("problem.pddl")),
            ("HIPOP_DOMAIN", scratch.join("domain.pddl")),
        ],
    );
    let lines: Vec<&str> = report.lines().filter(|l| !l.starts_with("hover")).collect();
    let scratch_name = scratch.file_name().and_then(|n| n.to_str()).expect("a folder name");
    assert_eq!(
        lines,
        [
            "open domain.pddl: filetype pddl, clients hipop at unicode",
            // Byte columns, converted by Neovim from UTF-16: `été` is 3 units but 5 bytes.
            "diagnostic 3:27-3:32 W0201 predicate `prêt` is never used",
            "diagnostic 7:29-7:33 E0102 undefined predicate `😀`",
            "open problem.plan: filetype hipop-plan, clients hipop at plan",
            "plan 2:0-2:34 E0419 the goal is not reached at the end of the plan (10.01): `(at r dock)` is false: deleted at 5.01 by the start of the step on line 3 `(drive r dock home)`",
            &format!("open problem.pddl: filetype pddl, clients hipop at {scratch_name}"),
            "problem before: 0 diagnostics",
            "problem after 4:10-4:14 E0102 undefined predicate `held`",
        ],
        "{report}"
    );
    assert!(report.lines().any(|l| l == "hover predicate (été ?x)"), "{report}");
    assert!(status.success(), "nvim exited with {status}");
}

/// Runs Neovim headless with the config users load (`editors/neovim/hipop.lua`,
/// as is) and the test script `script` of `tests/neovim/`; returns what the
/// script reported (`$HIPOP_OUT`) and how Neovim exited.
fn run_nvim(script: &str, env: &[(&str, std::path::PathBuf)]) -> (String, std::process::ExitStatus) {
    let root = common::workspace_root();
    let out = std::env::temp_dir().join(format!("hipop-nvim-{script}-{}.txt", std::process::id()));
    let _ = std::fs::remove_file(&out);
    let bin = hipop_bin().to_str().expect("UTF-8 path").replace('\'', "''");
    let mut nvim = Command::new("nvim")
        .args(["--headless", "-u", "NONE", "-i", "NONE", "-n"])
        // The settings a user would put in init.lua: the binary, and no
        // workspace markers, so that each fixture folder is its own workspace.
        .args(["--cmd", &format!("let g:hipop_cmd = ['{bin}', 'lsp']")])
        .args(["--cmd", "let g:hipop_root_markers = ['hipop-no-such-marker']"])
        .arg("-c")
        .arg(format!("luafile {}", root.join("editors/neovim/hipop.lua").display()))
        .arg("-c")
        .arg(format!(
            "luafile {}",
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/neovim").join(script).display()
        ))
        .envs(env.iter().map(|(k, v)| (*k, v.as_os_str())))
        .env("HIPOP_OUT", &out)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .spawn()
        .expect("spawning nvim");
    let deadline = Instant::now() + Duration::from_secs(120);
    let status = loop {
        if let Some(status) = nvim.try_wait().expect("waiting for nvim") {
            break status;
        }
        if Instant::now() > deadline {
            let _ = nvim.kill();
            panic!("nvim did not finish in 120 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let report =
        std::fs::read_to_string(&out).unwrap_or_else(|e| panic!("no report from nvim ({status}): {e}"));
    let _ = std::fs::remove_file(&out);
    (report, status)
}

/// Saving a problem plans it: the plan's hints beside the problem's lines,
/// `:HipopPlan` shows the plan; completion offers the domain's predicates;
/// a rename from the problem changes the domain too; formatting gives
/// `hipop fmt`'s text, once.
#[test]
fn neovim_plans_on_save_completes_renames_and_formats() {
    let Some(version) = nvim_version() else {
        eprintln!("SKIP: neovim (nvim) not installed; .ci/run installs it");
        return;
    };
    eprintln!("running {version}");
    let scratch =
        common::Scratch::with_fixture("nvim-planning", "planning", &["domain.pddl", "problem.pddl"]);
    let sample = scratch.join("surveillance");
    std::fs::create_dir_all(&sample).expect("scratch folder");
    for file in ["domain.pddl", "problem.pddl"] {
        let from = common::workspace_root().join("samples/surveillance").join(file);
        std::fs::copy(from, sample.join(file)).expect("copying the sample");
    }
    let (report, status) = run_nvim(
        "planning.lua",
        &[
            ("HIPOP_PROBLEM", scratch.join("problem.pddl")),
            ("HIPOP_SURVEILLANCE", sample.join("problem.pddl")),
        ],
    );
    let lines: Vec<&str> = report.lines().collect();
    assert_eq!(
        lines,
        [
            "hint 1 plan: 3 actions, makespan 9.03, T s",
            "hint 5 ← (observe r1 a p1) @ 0.01  ← (observe r1 b p2) @ 7.03",
            "plan buffer: hipop-plan, modifiable false, has the move true",
            "completion in the goal: at true, visible true, observed true",
            "renamed in problem.pddl: 2 seen, 0 observed",
            "renamed in domain.pddl: 2 seen, 0 observed",
            "format: changed true, as hipop fmt true, idempotent true",
            "surveillance: 10 plan: 242 actions, makespan 5528.04, T s; 31 goal hints",
        ],
        "{report}"
    );
    assert!(status.success(), "nvim exited with {status}");
}
