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

#[test]
fn clean_samples_check_without_diagnostics() {
    let o = hipop(&["check", "samples/rover-mission", "samples/transport-htn", "samples/surveillance"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "stderr:\n{}", stderr(&o));
    assert!(stderr(&o).contains("0 errors, 0 warnings"), "stderr:\n{}", stderr(&o));
}

/// `samples/` holds the deliberately broken fixtures of `samples/broken/`: checking
/// the whole folder fails, and only because of them.
#[test]
fn samples_folder_fails_only_in_broken_fixtures() {
    let o = hipop(&["check", "samples/", "--format", "json"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let doc: Value = serde_json::from_str(&stdout(&o)).expect("JSON output");
    let diagnostics = doc["diagnostics"].as_array().expect("diagnostics array");
    assert!(!diagnostics.is_empty());
    // The clean samples have information (their position families), no error or warning.
    for d in diagnostics.iter().filter(|d| d["severity"] != "info") {
        let file = d["location"]["file"].as_str().expect("file");
        assert!(file.starts_with("samples/broken/"), "unexpected diagnostic outside samples/broken/: {d}");
    }
}

#[test]
fn human_format() {
    let o = hipop(&["check", E0102, "--format", "human", "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    assert_eq!(stdout(&o), "", "human diagnostics go to stderr");
    insta::assert_snapshot!(stderr(&o));
}

#[test]
fn human_is_the_default_format() {
    let default = hipop(&["check", E0102, "--color", "never"]);
    let human = hipop(&["check", E0102, "--format", "human", "--color", "never"]);
    assert_eq!(stderr(&default), stderr(&human));
    assert_eq!(status(&default), 1);
}

#[test]
fn json_format() {
    let o = hipop(&["check", E0102, "--format", "json"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let out = stdout(&o);
    let doc: Value = serde_json::from_str(&out).expect("one JSON document");
    assert_eq!(doc["diagnostics"][0]["code"], "E0102");
    assert_eq!(doc["summary"]["errors"], 1);
    insta::assert_snapshot!(out);
}

#[test]
fn github_format() {
    let o = hipop(&["check", E0102, "--format", "github"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let out = stdout(&o);
    assert!(out.lines().all(|l| l.starts_with("::")), "only workflow commands on stdout:\n{out}");
    insta::assert_snapshot!(out);
}

#[test]
fn sarif_format() {
    let o = hipop(&["check", E0102, "--format", "sarif"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let mut doc: Value = serde_json::from_str(&stdout(&o)).expect("one JSON document");
    assert_eq!(doc["version"], "2.1.0");
    let run = &doc["runs"][0];
    assert_eq!(run["tool"]["driver"]["name"], "hipop");
    let rule_ids: Vec<&str> = run["tool"]["driver"]["rules"]
        .as_array()
        .expect("rules array")
        .iter()
        .map(|r| r["id"].as_str().expect("rule id"))
        .collect();
    let results = run["results"].as_array().expect("results array");
    assert!(!results.is_empty());
    for r in results {
        let id = r["ruleId"].as_str().expect("ruleId");
        assert!(rule_ids.contains(&id), "result rule `{id}` is not among the driver's rules");
        let index = r["ruleIndex"].as_u64().expect("ruleIndex") as usize;
        assert_eq!(rule_ids[index], id, "ruleIndex points at the result's rule");
    }
    assert_eq!(results[0]["ruleId"], "E0102");
    // The tool version changes with every release: keep it out of the snapshot.
    doc["runs"][0]["tool"]["driver"]["version"] = Value::from("[version]");
    insta::assert_snapshot!(serde_json::to_string_pretty(&doc).expect("serialisable"));
}

#[test]
fn deny_warnings_turns_warnings_into_failure() {
    let without = hipop(&["check", WARNING_ONLY, "--color", "never"]);
    assert_no_panic(&without);
    assert_eq!(status(&without), 0, "a warning alone does not fail:\n{}", stderr(&without));
    assert!(stderr(&without).contains("0 errors, 1 warning"), "stderr:\n{}", stderr(&without));

    let with = hipop(&["check", WARNING_ONLY, "--deny", "warnings", "--color", "never"]);
    assert_no_panic(&with);
    assert_eq!(status(&with), 1, "with --deny warnings a warning fails:\n{}", stderr(&with));
}

#[test]
fn allow_silences_a_code_by_id_or_name() {
    for code in ["W0201", "unused-declaration"] {
        let o = hipop(&["check", "--deny", "warnings", "--allow", code, WARNING_ONLY]);
        assert_no_panic(&o);
        assert_eq!(status(&o), 0, "{code}: {}", stderr(&o));
        assert!(!stderr(&o).contains("W0201"), "{}", stderr(&o));
    }
    // Other codes are still reported.
    let o = hipop(&["check", "--allow", "W0201", E0102]);
    assert_eq!(status(&o), 1);
    let o = hipop(&["check", "--allow", "W9999", E0102]);
    assert_eq!(status(&o), 2, "an unknown code is a usage error");
    assert!(stderr(&o).contains("`W9999` is not a diagnostic code"), "{}", stderr(&o));
}

#[test]
fn allow_comments_silence_an_occurrence_or_a_file() {
    let dir = std::env::temp_dir().join(format!("hipop-allow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let original = std::fs::read_to_string(workspace_root().join(WARNING_ONLY)).unwrap();
    let path = dir.join("d.pddl");
    let check = |text: &str| {
        std::fs::write(&path, text).unwrap();
        let o = hipop(&["check", "--deny", "warnings", path.to_str().unwrap()]);
        assert_no_panic(&o);
        status(&o)
    };
    assert_eq!(check(&original), 1);
    assert_eq!(check(&format!("{original}\n; hipop-allow-file: unused-declaration\n")), 0);
    assert_eq!(check(&format!("{original}\n; hipop-allow-file: W0202\n")), 1, "another code");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn nonexistent_path_is_a_usage_error() {
    let o = hipop(&["check", "samples/no-such-mission.pddl"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2);
    let err = stderr(&o);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("samples/no-such-mission.pddl")).collect();
    assert_eq!(lines.len(), 1, "one line names the missing path:\n{err}");
    assert!(lines[0].starts_with("error:"), "stderr:\n{err}");
    assert!(lines[0].contains("no such file"), "stderr:\n{err}");
}

/// A temporary file removed on drop.
struct TempFile(PathBuf);

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

#[test]
fn non_utf8_file_is_reported_without_panic() {
    let path = std::env::temp_dir().join(format!("hipop-cli-test-{}-not-utf8.pddl", std::process::id()));
    std::fs::write(&path, [0xff, 0xfe]).expect("temp file written");
    let file = TempFile(path);
    let o = hipop(&["check", file.0.to_str().expect("UTF-8 temp path"), "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2);
    let err = stderr(&o);
    let line = err.lines().find(|l| l.contains("not-utf8.pddl")).expect("a line names the file");
    assert!(line.starts_with("error:"), "stderr:\n{err}");
    assert!(line.contains("UTF-8"), "the message says what is wrong:\n{err}");
}

/// A file that starts with a UTF-8 byte-order mark reads without error, and
/// its columns are the editor's: the mark is not one.
#[test]
fn a_byte_order_mark_is_not_a_column() {
    let file = "tests/reading/byte-order-mark.pddl";
    let o = hipop(&["check", file, "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "stderr:\n{}", stderr(&o));
    assert!(stderr(&o).contains(&format!("{file}:1:51")), "stderr:\n{}", stderr(&o));
    let o = hipop(&["check", file, "--format", "json"]);
    let doc: Value = serde_json::from_str(&stdout(&o)).expect("JSON output");
    let d = &doc["diagnostics"][0];
    assert_eq!(d["code"], "W0201");
    assert_eq!(d["location"]["start"], serde_json::json!({"line": 1, "column": 51, "offset": 53}));
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
fn fix_applies_fixes_then_checks_again() {
    let dir = TempDir::new("fix");
    let conflicts = dir.copy("samples/broken/E0301-uncovered-conflict.hddl");
    let typo = dir.copy("samples/broken/E0105-undefined-task.hddl");
    let before = std::fs::read_to_string(&conflicts).unwrap();

    let o = hipop(&["check", "--fix", dir.path(), "--color", "never"]);
    assert_no_panic(&o);
    let err = stderr(&o);
    assert_eq!(status(&o), 0, "everything was fixed:\n{err}");
    assert!(err.contains("fixed 2 diagnostics in 2 files"), "stderr:\n{err}");
    assert!(err.contains("checked 2 files: 0 errors, 0 warnings"), "the check after the fixes:\n{err}");

    // Only the `:conflicts` line changed, comments and layout kept.
    let after = std::fs::read_to_string(&conflicts).unwrap();
    assert_eq!(
        after,
        before.replace(":conflicts (and (at-r ?r ?home)))", ":conflicts (and (at-r ?r ?home) (at-r ?r ?w)))")
    );
    assert!(std::fs::read_to_string(&typo).unwrap().contains(":task (goto ?r ?to)"));

    let again = hipop(&["check", "--fix", dir.path(), "--color", "never"]);
    assert_eq!(status(&again), 0);
    assert!(stderr(&again).contains("nothing to fix"), "stderr:\n{}", stderr(&again));
}

#[test]
fn fix_leaves_what_it_cannot_fix_and_fails() {
    let dir = TempDir::new("fix-remaining");
    let cycle = dir.copy("samples/broken/E0113-ordering-cycle.hddl");
    let before = std::fs::read_to_string(&cycle).unwrap();
    let o = hipop(&["check", "--fix", dir.path(), "--color", "never"]);
    assert_no_panic(&o);
    let err = stderr(&o);
    assert_eq!(status(&o), 1, "the error remains:\n{err}");
    assert!(err.contains("nothing to fix") && err.contains("E0113"), "stderr:\n{err}");
    assert_eq!(std::fs::read_to_string(&cycle).unwrap(), before, "the file is untouched");
}

#[test]
fn fix_skips_overlapping_fixes() {
    // Two literals to add to a single-atom `:conflicts`: both fixes wrap it
    // into `(and …)`, so only the first is applied; a second run applies the other.
    let dir = TempDir::new("fix-overlap");
    let path = dir.0.join("d.hddl");
    let domain = "; two uncovered literals
(define (domain d)
  (:requirements :hierarchy)
  (:predicates (at ?r ?w) (busy ?r) (seen ?w))
  (:action move :parameters (?r ?a ?b)
    :precondition (and (at ?r ?a) (busy ?r) (seen ?a))
    :effect (and (not (at ?r ?a)) (not (busy ?r)) (at ?r ?b) (seen ?b)))
  (:task goto :parameters (?r ?to) :conflicts (seen ?to))
  (:method m :parameters (?r ?from ?to) :task (goto ?r ?to)
    :subtasks (and (move ?r ?from ?to))))
";
    std::fs::write(&path, domain).unwrap();
    let run = || hipop(&["check", "--fix", dir.path(), "--color", "never"]);

    let o = run();
    assert_no_panic(&o);
    let err = stderr(&o);
    assert!(err.contains("fixed 1 diagnostic in 1 file"), "stderr:\n{err}");
    assert!(err.contains("skipped 1 fix that would overlap another"), "stderr:\n{err}");
    assert_eq!(status(&o), 1, "one E0301 remains:\n{err}");
    assert!(err.contains("checked 1 file: 1 error, 1 warning"), "stderr:\n{err}");

    let o = run();
    let err = stderr(&o);
    assert!(err.contains("fixed 1 diagnostic in 1 file"), "stderr:\n{err}");
    assert!(!err.contains("skipped"), "stderr:\n{err}");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains(":conflicts (and (seen ?to) (at ?r ?from) (busy ?r))"),
        "both literals added, one `and`:\n{text}"
    );
    // `(seen ?to)` is added by `move` but deleted by nothing: W0302 remains.
    assert_eq!(status(&o), 0, "stderr:\n{err}");
    assert!(err.contains("W0302"), "stderr:\n{err}");
}

const DIFF_A: &str = "tests/plans/diff/temporal/a.plan";
const DIFF_B: &str = "tests/plans/diff/temporal/b.plan";
const DIFF_DOMAIN: &str = "tests/plans/diff/temporal/domain.hddl";

#[test]
fn diff_human_per_agent() {
    let o = hipop(&["diff", DIFF_A, DIFF_B, "--domain", DIFF_DOMAIN]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1, "different plans: status 1\n{}", stderr(&o));
    assert_eq!(stderr(&o), "", "nothing to report on stderr");
    insta::assert_snapshot!(stdout(&o));
}

#[test]
fn diff_json() {
    let o = hipop(&["diff", DIFF_A, DIFF_B, "--domain", DIFF_DOMAIN, "--format", "json"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let out = stdout(&o);
    let doc: Value = serde_json::from_str(&out).expect("one JSON document");
    assert_eq!(doc["instability"], 6);
    assert_eq!(doc["distance"], 5);
    assert_eq!(doc["same"], false);
    insta::assert_snapshot!(out);
}

#[test]
fn diff_unified_with_method_change() {
    let o = hipop(&[
        "diff",
        "tests/plans/diff/hierarchical/a.plan",
        "tests/plans/diff/hierarchical/b.plan",
        "--domain",
        "samples/rover-mission/domain.hddl",
        "--format",
        "unified",
    ]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let out = stdout(&o);
    assert!(out.starts_with("--- tests/plans/diff/hierarchical/a.plan\n+++ "), "{out}");
    insta::assert_snapshot!(out);
}

/// Steps with ids (hierarchical, JSON plans) are named by them, as the
/// validators name them; VAL steps by their place only (a line).
#[test]
fn diff_names_steps_by_their_ids() {
    let (a, b) = ("tests/plans/diff/hierarchical/a.plan", "tests/plans/diff/hierarchical/b.plan");
    let o = hipop(&["diff", a, b, "--domain", "samples/rover-mission/domain.hddl"]);
    assert_no_panic(&o);
    let out = stdout(&o);
    assert!(out.contains(&format!("{a}:2:1  step 0 (move rover1 base ridge)")), "{out}");
    assert!(
        out.contains("step 3 → step 5 (inspect rover1 rock1 base): inspect-direct → inspect-via"),
        "{out}"
    );
    let o = hipop(&["diff", "tests/plans/diff/cross-format/a.plan", "tests/plans/diff/cross-format/b.json"]);
    assert!(
        stdout(&o).contains("  step 2 → step 12 (move rover1 ridge base): start 46.000 → 50.0"),
        "{}",
        stdout(&o)
    );
    let o = hipop(&["diff", DIFF_A, DIFF_B]);
    assert!(!stdout(&o).contains("step "), "VAL steps have no ids:\n{}", stdout(&o));
}

#[test]
fn diff_same_plans_exit_zero() {
    let o = hipop(&["diff", "tests/plans/diff/same/a.plan", "tests/plans/diff/same/b.plan"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "{}", stdout(&o));
    assert!(stdout(&o).contains("the plans are the same"), "{}", stdout(&o));
    // Across formats: a timed hierarchical plan and its JSON form.
    let o = hipop(&["diff", "tests/plans/ok/timed-hierarchical.plan", "tests/plans/ok/plan.json"]);
    assert_eq!(status(&o), 0, "{}", stdout(&o));
}

#[test]
fn diff_reports_malformed_plans_with_their_place() {
    let o = hipop(&["diff", "tests/plans/E0403-unknown-step-id.plan", DIFF_B, "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2);
    assert_eq!(stdout(&o), "", "no diff when a plan cannot be read");
    let err = stderr(&o);
    assert!(err.contains("error[E0403]"), "{err}");
    assert!(err.contains("tests/plans/E0403-unknown-step-id.plan:7:51"), "{err}");
    // Usage and I/O errors.
    let o = hipop(&["diff", "tests/plans/no-such.plan", DIFF_B]);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("no such file"), "{}", stderr(&o));
    let o = hipop(&["diff", DIFF_A]);
    assert_eq!(status(&o), 2, "a missing argument is a usage error");
    let o = hipop(&["diff", DIFF_A, DIFF_B, "--domain", DIFF_B]);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("no `(define (domain"), "{}", stderr(&o));
}

/// The VAL Depots sample (`../shared/corpora/val-samples`), relative to the
/// workspace root, or `None` (with a visible message) when the corpus is absent.
fn depots_sample() -> Option<[&'static str; 3]> {
    const DIR: &str = "../shared/corpora/val-samples/samples/IPC/Depots/Strips";
    if !workspace_root().join(DIR).is_dir() {
        eprintln!("SKIP: ../shared/corpora is absent");
        return None;
    }
    Some([
        "../shared/corpora/val-samples/samples/IPC/Depots/Strips/Depots.pddl",
        "../shared/corpora/val-samples/samples/IPC/Depots/Strips/pfile1",
        "../shared/corpora/val-samples/samples/IPC/Depots/Strips/pfile1.plan",
    ])
}

#[test]
fn validate_agrees_with_val_on_the_depots_sample_and_its_tolerance() {
    let Some([d, p, plan]) = depots_sample() else { return };
    // Steps 0.001 apart: one happening at VAL's default tolerance 0.01.
    let o = hipop(&["validate", d, p, plan, "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("error[E0418]"), "{}", stderr(&o));
    assert!(stderr(&o).ends_with("pfile1.plan: invalid: 3 errors\n"), "{}", stderr(&o));
    let o = hipop(&["validate", d, p, plan, "-t", "0.0001"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("pfile1.plan: valid: makespan 0.004"), "{}", stderr(&o));
    // A regression suite of known-bad plans.
    let o = hipop(&["validate", d, p, plan, "--expect", "invalid"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("invalid (as expected)"), "{}", stderr(&o));
}

#[test]
fn validate_json_reports_each_plan_and_the_worst_status() {
    let Some([d, p, plan]) = depots_sample() else { return };
    let o = hipop(&["validate", d, p, plan, "no/such.plan", "--format", "json", "-t", "0.0001"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2, "an unreadable plan is a usage error: {}", stderr(&o));
    let doc: Value = serde_json::from_str(&stdout(&o)).expect("one JSON document");
    let verdicts: Vec<&str> =
        doc["plans"].as_array().unwrap().iter().map(|p| p["verdict"].as_str().unwrap()).collect();
    assert_eq!(verdicts, ["valid", "unreadable"]);
    assert_eq!(doc["plans"][1]["io_error"], "no/such.plan: no such file");
}

#[test]
fn validate_refuses_a_model_with_errors_and_an_unreadable_plan() {
    let o = hipop(&["validate", E0102, E0102, "tests/plans/ok/temporal.plan", "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("fix them before validating plans"), "{}", stderr(&o));
    let Some([d, p, _]) = depots_sample() else { return };
    let o = hipop(&["validate", d, p, "tests/plans/E0401-malformed-step.plan", "--color", "never"]);
    assert_eq!(status(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("not validated: the plan cannot be read"), "{}", stderr(&o));
}

/// Runs `hipop validate` on a PDDL+ model and plan, with `--expect valid`
/// and `--expect invalid`: each gets no verdict (exit 2). Returns the human
/// output of the first run.
fn validate_pddl_plus(domain: &str, problem: &str, plan: &str) -> String {
    let o = hipop(&["validate", domain, problem, plan, "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2, "{}", stderr(&o));
    let e = hipop(&["validate", domain, problem, plan, "--expect", "invalid", "--color", "never"]);
    assert_eq!(status(&e), 2, "no verdict, so not the expected one either: {}", stderr(&e));
    stderr(&o)
}

const PDDL_PLUS: &str = "tests/validate/models/pddl-plus";

#[test]
fn validate_gives_no_verdict_on_a_pddl_plus_process() {
    let d = format!("{PDDL_PLUS}-process.pddl");
    let (p, plan) =
        (format!("{PDDL_PLUS}-problem.pddl"), "tests/validate/E0421-unsupported-in-plan-process.plan");
    let err = validate_pddl_plus(&d, &p, plan);
    // The domain is only a warning for `hipop check` (W0207): the plan is
    // read, and the validator says it cannot judge it.
    assert!(err.contains("error[E0421]") && err.contains("not validated"), "{err}");
}

#[test]
fn validate_gives_no_verdict_on_a_pddl_plus_event() {
    let d = format!("{PDDL_PLUS}-event.pddl");
    let (p, plan) =
        (format!("{PDDL_PLUS}-problem.pddl"), "tests/validate/E0421-unsupported-in-plan-event.plan");
    let err = validate_pddl_plus(&d, &p, plan);
    // The domain is only a warning for `hipop check` (W0207): the plan is
    // read, and the validator says it cannot judge it.
    assert!(err.contains("error[E0421]") && err.contains("not validated"), "{err}");
}

/// `#t` without a process or an event: the model checks, the plan is read,
/// and validation says it cannot judge it (E0421), in every format.
#[test]
fn validate_gives_no_verdict_on_a_continuous_effect() {
    let d = format!("{PDDL_PLUS}-continuous.pddl");
    let (p, plan) =
        (format!("{PDDL_PLUS}-problem.pddl"), "tests/validate/E0421-unsupported-in-plan-continuous.plan");
    let err = validate_pddl_plus(&d, &p, plan);
    assert!(err.contains("error[E0421]"), "{err}");
    assert!(
        err.ends_with(&format!(
            "{plan}: not validated: it needs what the validator does not check (E0421)\n"
        )),
        "{err}"
    );
    let o = hipop(&["validate", &d, &p, plan, "--format", "json"]);
    assert_eq!(status(&o), 2, "{}", stderr(&o));
    let doc: Value = serde_json::from_str(&stdout(&o)).expect("one JSON document");
    assert_eq!(doc["plans"][0]["verdict"], "unsupported");
    assert_eq!(doc["plans"][0]["makespan"], Value::Null);
    for format in ["sarif", "github"] {
        assert_eq!(status(&hipop(&["validate", &d, &p, plan, "--format", format])), 2, "{format}");
    }
}

/// VAL's PDDL+ samples: those with processes and events, and the Tanks
/// sample (continuous effects only), are read but not judged (E0421); the
/// Drive sample, plain PDDL 2.1 in that folder, gets a verdict.
#[test]
fn validate_gives_no_verdict_on_vals_pddl_plus_samples() {
    const DIR: &str = "../shared/corpora/val-samples/samples/domainsWithEventsAndProcesses";
    if !workspace_root().join(DIR).is_dir() {
        eprintln!("SKIP: ../shared/corpora is absent");
        return;
    }
    let sample = |folder: &str, files: [&str; 3]| files.map(|f| format!("{DIR}/{folder}/{f}"));
    let refused = [
        sample("Coffee", ["coffeemaking.pddl", "coffeeproblem.pddl", "coffeeplan.txt"]),
        sample(
            "VendingMachine",
            ["vendingmachine.pddl", "vendingmachine-problem.pddl", "vendingmachineplan.txt"],
        ),
        sample(
            "Sleeping Beauty with Capacitor",
            ["sleepingbeauty.pddl", "sleepingbeauty-problem.pddl", "sleepingbeautyplan.txt"],
        ),
    ];
    for [d, p, plan] in &refused {
        let err = validate_pddl_plus(d, p, plan);
        assert!(err.contains("error[E0421]") && !err.contains("W0207"), "{plan}: {err}");
    }
    let [d, p, plan] =
        sample("Tanks and a Bucket Toricelli", ["tank-domain.pddl", "tank-problem.pddl", "tankplan.txt"]);
    let err = validate_pddl_plus(&d, &p, &plan);
    assert!(err.contains("error[E0421]") && err.contains("continuous effects (`#t`)"), "{err}");
    assert!(err.ends_with("not validated: it needs what the validator does not check (E0421)\n"), "{err}");
    let [d, p, plan] = sample("Drive", ["drivedomain.pddl", "drive-problem.pddl", "driveplan.txt"]);
    let o = hipop(&["validate", &d, &p, &plan]);
    assert_eq!(status(&o), 1, "VAL says the Drive plan is invalid at tolerance 0.01: {}", stderr(&o));
}

/// `hipop validate` on every plan of tests/validate and tests/validate-htn
/// (one defect each, or valid): the human and the JSON output, as snapshots. Each plan's header
/// names its domain, problem and tolerance (`corpus:` is ../shared/corpora).
#[test]
fn validate_output_for_each_kind_of_defect() {
    if !workspace_root().join("../shared/corpora").is_dir() {
        eprintln!("SKIP: ../shared/corpora is absent");
        return;
    }
    validate_fixtures("tests/validate", 20);
    validate_fixtures("tests/validate-htn", 20);
}

fn validate_fixtures(folder: &str, at_least: usize) {
    let dir = workspace_root().join(folder);
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".plan"))
        .collect();
    names.sort();
    assert!(names.len() >= at_least, "{names:?}");
    for name in names {
        let text = std::fs::read_to_string(dir.join(&name)).unwrap();
        let header = |key: &str| {
            text.lines().find_map(|l| l.strip_prefix(&format!("; {key}:")).map(|v| v.trim().to_string()))
        };
        let model = |v: String| match v.strip_prefix("corpus:") {
            Some(rest) => format!("../shared/corpora/{rest}"),
            None => format!("{folder}/{v}"),
        };
        let (Some(d), Some(p)) = (header("domain").map(model), header("problem").map(model)) else {
            panic!("{name}: no `; domain:` or `; problem:` header")
        };
        let tolerance = header("tolerance").unwrap_or_else(|| "0.01".into());
        let plan = format!("{folder}/{name}");
        let mut args = vec!["validate", &d, &p, &plan, "-t", &tolerance, "--color", "never"];
        if header("ignore-listed-order").is_some() {
            args.push("--ignore-listed-order");
        }
        let human = hipop(&args);
        assert_no_panic(&human);
        let expect_valid = header("expect").is_some_and(|e| e.starts_with("valid"));
        // No verdict (exit 2): a model with errors (E0422's broken domain) is
        // refused before any plan is read; a plan that needs what the
        // validator does not check (E0421: a PDDL+ domain, only a warning for
        // `hipop check`, W0207) is read but not judged.
        let not_judged = name.starts_with("E0422") || name.starts_with("E0421");
        let wanted = if not_judged {
            2
        } else if expect_valid {
            0
        } else {
            1
        };
        assert_eq!(status(&human), wanted, "{name}: {}", stderr(&human));
        insta::assert_snapshot!(format!("validate_human@{name}"), stderr(&human));
        let refused = stderr(&human).contains("fix them before validating plans");
        if !refused {
            let json = hipop(&[&args[..], &["--format", "json"][..]].concat());
            let doc: Value = serde_json::from_str(&stdout(&json)).expect("one JSON document");
            insta::assert_json_snapshot!(format!("validate_json@{name}"), doc);
        }
    }
}

const TIMELINE: [&str; 2] = ["tests/plans/timeline/domain.hddl", "tests/plans/timeline/problem.hddl"];

/// `--gantt` draws each plan after its verdict (on standard output, the
/// verdict on standard error), `--svg FILE` writes the picture.
#[test]
fn validate_gantt_and_svg() {
    let tmp = TempDir::new("timeline");
    let picture = format!("{}/plan.svg", tmp.path());
    let [d, p] = TIMELINE;
    let plan = "tests/plans/timeline/hierarchical.plan";
    let o = hipop(&["validate", d, p, plan, "--gantt", "--gantt-width", "80", "--svg", &picture]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    assert_eq!(stderr(&o), format!("{plan}: valid: makespan 32.000, value 32.000\n"));
    insta::assert_snapshot!(stdout(&o));
    // docs/plan-formats.md shows this very chart.
    let doc = std::fs::read_to_string(workspace_root().join("docs/plan-formats.md")).unwrap();
    let chart = stdout(&o).trim_start().strip_prefix(&format!("{plan}\n")).unwrap().to_string();
    assert!(doc.contains(&chart), "docs/plan-formats.md, Timelines: update the example to\n{chart}");
    let svg = std::fs::read_to_string(&picture).expect("the picture is written");
    assert!(svg.starts_with("<?xml") && svg.trim_end().ends_with("</svg>"), "{svg}");
    assert!(svg.contains("(communicate r1 r2 hill lake)"), "{svg}");

    // ASCII, several plans (an invalid one is drawn too), each under its path.
    let seq = "tests/plans/timeline/sequential.plan";
    let o = hipop(&["validate", d, p, seq, plan, "--gantt=ascii", "--gantt-width", "70", "--color", "never"]);
    assert_eq!(status(&o), 1, "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.is_ascii(), "{out}");
    assert!(out.starts_with(&format!("\n{seq}\nstep")), "{out}");
    assert!(out.contains(&format!("\n{plan}\ntime")), "{out}");
}

#[test]
fn validate_timeline_flags_refuse_what_they_cannot_do() {
    let [d, p] = TIMELINE;
    let plan = "tests/plans/timeline/temporal.plan";
    let o = hipop(&["validate", d, p, plan, "--format", "json", "--gantt"]);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("`--gantt` draws for people"), "{}", stderr(&o));
    assert_eq!(stdout(&o), "");
    let o = hipop(&["validate", d, p, plan, plan, "--svg", "never-written.svg"]);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("`--svg FILE` draws one plan, and 2 are given"), "{}", stderr(&o));
    assert!(!workspace_root().join("never-written.svg").exists());
    let o = hipop(&["validate", d, p, plan, "--svg", "no/such/folder/plan.svg"]);
    assert_eq!(status(&o), 2, "a picture that cannot be written");
    assert!(stderr(&o).contains("cannot write the SVG picture"), "{}", stderr(&o));
    // A plan that cannot be read is not drawn.
    let o =
        hipop(&["validate", d, p, "tests/plans/E0401-malformed-step.plan", "--gantt", "--color", "never"]);
    assert_eq!(status(&o), 2);
    assert!(
        stderr(&o).contains("E0401-malformed-step.plan: not drawn: the plan cannot be read"),
        "{}",
        stderr(&o)
    );
    assert_eq!(stdout(&o), "");
    // The flags are explained.
    let help = stdout(&hipop(&["validate", "--help"]));
    assert!(help.contains("--gantt[=<STYLE>]") && help.contains("--svg <FILE>"), "{help}");
}

// ---------------------------------------------------------------- plan

/// `hipop plan`: 0 with a plan that `hipop validate` accepts, 1 when no plan
/// exists, 3 when a limit stops the search, 2 for a usage error.
#[test]
fn plan_exit_statuses() {
    let rover = ["samples/rover-mission/domain.hddl", "samples/rover-mission/problem.hddl"];
    let dir = TempDir::new("plan-exit");
    let out = format!("{}/rover.plan", dir.path());
    let o = hipop(&["plan", rover[0], rover[1], "-o", &out, "--quiet"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    let v = hipop(&["validate", rover[0], rover[1], &out]);
    assert_eq!(status(&v), 0, "the plan written does not validate:\n{}{}", stdout(&v), stderr(&v));

    let no_plan = "tests/planner/no-plan.pddl";
    let o = hipop(&["plan", no_plan, no_plan, "--color", "never"]);
    assert_eq!(status(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("E0502"), "{}", stderr(&o));

    let survivors = ["samples/survivors/domain.pddl", "samples/survivors/p-t3-r4-z16-s5.pddl"];
    let o = hipop(&["plan", survivors[0], survivors[1], "--node-limit", "10", "--color", "never"]);
    assert_eq!(status(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("the node limit"), "{}", stderr(&o));

    // The memory limit is the heap the process holds: 1 MiB is gone before
    // the search starts, so it stops at its first check.
    let o = hipop(&["plan", survivors[0], survivors[1], "--memory-limit", "1", "--color", "never"]);
    assert_eq!(status(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("the memory limit"), "{}", stderr(&o));

    let o = hipop(&["plan", rover[0], rover[1], "--config", "AR-fast"]);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("unknown part `fast`"), "{}", stderr(&o));
}

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
    assert_eq!(commands, ["check", "diff", "validate", "plan", "lsp"]);
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

/// The codes of `hipop check --format json` on one generated file, and the output.
fn check_generated(name: &str, text: &str, extra: &[&str]) -> (Vec<String>, Value, Output) {
    let dir = TempDir::new(name);
    let path = dir.0.join(format!("{name}.pddl"));
    std::fs::write(&path, text).expect("generated file written");
    let mut args = vec!["check", path.to_str().expect("UTF-8 temp path"), "--format", "json"];
    args.extend_from_slice(extra);
    let o = hipop(&args);
    assert_no_panic(&o);
    let doc: Value =
        serde_json::from_str(&stdout(&o)).unwrap_or_else(|e| panic!("{name}: {e}: {}", stderr(&o)));
    let codes = doc["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|d| d["code"].as_str().expect("a code").to_string())
        .collect();
    (codes, doc, o)
}

/// A million nested lists, or a million `(`, are one located error each, not
/// a stack overflow: lists deeper than 256 are kept as text (E0007).
#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let n = 1_000_000;
    let precondition = format!("{}(p ?x){}", "(and ".repeat(n), ")".repeat(n));
    let domain = format!(
        "(define (domain deep) (:predicates (p ?x))\n  (:action a :parameters (?x) :precondition {precondition} :effect (p ?x)))\n"
    );
    let (codes, doc, o) = check_generated("deep-and", &domain, &[]);
    assert_eq!(status(&o), 1);
    assert_eq!(codes, ["E0007"]);
    let location = &doc["diagnostics"][0]["location"];
    // The `(and` one level too deep: define, action and 254 `(and` enclose it;
    // the first `(and` is at column 45.
    let start = &location["start"];
    assert_eq!((start["line"].as_u64(), start["column"].as_u64()), (Some(2), Some(45 + 5 * 254)));

    for n in [200_000, 1_000_000] {
        let (codes, doc, o) = check_generated("open-parens", &"(".repeat(n), &[]);
        assert_eq!(status(&o), 1);
        assert_eq!(codes, ["E0003", "E0007", "E0001"], "{n}");
        assert_eq!(
            doc["diagnostics"][2]["message"],
            format!("missing {n} `)`: a list and the lists around it are not closed")
        );
    }
}

/// 200,000 `)` are one E0002 (a run of the same error is reported once, with
/// its count), in every format.
#[test]
fn a_run_of_extra_parens_is_one_diagnostic() {
    let (codes, doc, o) = check_generated("close-parens", &")".repeat(200_000), &[]);
    assert_eq!(status(&o), 1);
    assert_eq!(codes, ["E0002"]);
    assert_eq!(
        doc["diagnostics"][0]["message"],
        "unexpected `)` (200000 in a row): there is no open `(` to close"
    );
    assert_eq!(doc["diagnostics"][0]["location"]["end"]["column"], 200_001);
    let dir = TempDir::new("close-parens-human");
    let path = dir.0.join("close.pddl");
    std::fs::write(&path, ")".repeat(200_000)).expect("generated file written");
    let o = hipop(&["check", path.to_str().expect("UTF-8 temp path"), "--color", "never"]);
    assert_eq!(status(&o), 1);
    let err = stderr(&o);
    assert_eq!(err.matches("error[E0002]").count(), 1);
    assert!(
        err.ends_with("checked 1 file: 1 error, 0 warnings\n"),
        "{}",
        &err[err.len().saturating_sub(300)..]
    );
}

/// At most 200 diagnostics per file are printed (`--max-diagnostics`), errors
/// first, then one I0008 with how many more; the summary counts them all.
#[test]
fn at_most_max_diagnostics_per_file_are_printed() {
    // 1000 extra `)` that no run joins (an atom between), and the atoms: 1001 errors.
    let text = ") x".repeat(1000);
    let (codes, doc, o) = check_generated("many", &text, &[]);
    assert_eq!(status(&o), 1);
    assert_eq!(codes.len(), 201);
    assert!(codes[..200].iter().all(|c| c == "E0002" || c == "E0003"), "{codes:?}");
    assert_eq!(codes[200], "I0008");
    assert_eq!(
        doc["diagnostics"][200]["message"],
        "801 more diagnostics in this file not shown (801 errors), the first of them here: hipop shows at most 200 per file"
    );
    assert_eq!(doc["summary"]["errors"], 1001);

    let (codes, _, _) = check_generated("many", &text, &["--max-diagnostics", "3"]);
    assert_eq!(codes, ["E0002", "E0003", "E0002", "I0008"]);
    let (codes, _, _) = check_generated("many", &text, &["--max-diagnostics", "0"]);
    assert_eq!(codes.len(), 1001);

    let o = hipop(&[
        "check",
        "tests/limits/five-undefined-predicates.pddl",
        "--max-diagnostics",
        "2",
        "--color",
        "never",
    ]);
    assert_eq!(status(&o), 1);
    let err = stderr(&o);
    assert_eq!(err.matches("error[E0102]").count(), 2, "{err}");
    assert!(
        err.contains("note[I0008]: 4 more diagnostics in this file not shown (3 errors, 1 warning)"),
        "{err}"
    );
    assert!(err.ends_with("checked 1 file: 5 errors, 1 warning\n"), "{err}");
}

/// Columns count characters, not bytes, after characters of two and four bytes.
#[test]
fn columns_count_characters() {
    let line =
        "  (:action a :parameters (?x) :precondition (and (p ?x) (é ?x) (😀 ?x) (q ?x)) :effect (p ?x)))";
    let text = format!("(define (domain d) (:predicates (p ?x)) ; ö ü\n{line}\n");
    let (codes, doc, _) = check_generated("columns", &text, &[]);
    assert_eq!(codes, ["E0102", "E0102", "E0102"]);
    for (d, name) in doc["diagnostics"].as_array().expect("diagnostics").iter().zip(["é", "😀", "q"]) {
        let byte = line.find(&format!("({name} ")).expect("the name") + 1;
        let column = line[..byte].chars().count() as u64 + 1;
        let location = &d["location"];
        assert_eq!(location["start"]["line"], 2);
        assert_eq!(location["start"]["column"].as_u64(), Some(column), "{name}");
        assert_eq!(location["end"]["column"].as_u64(), Some(column + 1), "{name}");
    }
}
