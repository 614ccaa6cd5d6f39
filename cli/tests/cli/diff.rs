//! `hipop diff`: two plans compared, per agent, as JSON, as a unified diff.

use super::*;

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
