//! `hipop repair` on the fixtures of `tests/repair/`, one folder per stage
//! of the repair (their list: `tests/repair/README.md`): the report and the
//! repaired plan as a user sees them (snapshots), the stage that found the
//! plan and why each step was removed (asserted), and the repaired plan
//! valid for the new problem (`hipop validate`).

use hipop_analyzer::AnalysisHost;

use super::*;

/// A repair run on a fixture.
struct Run {
    status: i32,
    /// Standard error: the report.
    report: String,
    /// Standard output: the repaired plan.
    plan: String,
}

impl Run {
    /// The stage that found the plan, from the plan's header.
    fn found_by(&self) -> &str {
        let line = self.plan.lines().find_map(|l| l.strip_prefix("; found by ")).expect("a `found by` line");
        line.split(", configuration").next().unwrap_or(line)
    }

    /// Each stage's line of the report: `stage: …, outcome, …`.
    fn stages(&self) -> Vec<&str> {
        self.report
            .lines()
            .filter(|l| l.starts_with("stage ") || l.starts_with("the full replan: "))
            .collect()
    }

    /// The steps removed, `(call, why)`, in the order of the report.
    fn removed(&self) -> Vec<(&str, &str)> {
        self.report
            .lines()
            .filter_map(|l| l.strip_prefix("  removed "))
            .map(|l| {
                let (call, rest) = l.split_once(" (step ").expect("`(step N)` after the call");
                (call, rest.split_once("): ").expect("the reason").1)
            })
            .collect()
    }

    /// The repaired plan's steps: `(call, start, method)`, read as hipop
    /// reads plans (a hierarchical plan's abstract steps have a method).
    fn steps(&self) -> Vec<(String, f64, Option<String>)> {
        steps_of(&self.plan)
    }

    fn start(&self, call: &str) -> f64 {
        let steps = self.steps();
        steps.iter().find(|s| s.0 == call).unwrap_or_else(|| panic!("no {call} in\n{}", self.plan)).1
    }
}

fn steps_of(text: &str) -> Vec<(String, f64, Option<String>)> {
    let mut host = AnalysisHost::new();
    let f = host.set_file_text("plan.plan", text.to_string());
    let plan = host.analysis().plan(f, None).expect("not cancelled");
    assert!(plan.diagnostics.is_empty(), "the plan reads without a diagnostic:\n{text}");
    plan.steps
        .iter()
        .map(|s| {
            (
                s.call(),
                s.start.as_ref().map_or(f64::NAN, |n| n.value),
                s.decomposition.as_ref().map(|d| d.method.text.to_string()),
            )
        })
        .collect()
}

/// The fixture's files: the domain and problem before and after the event
/// (`new-domain.pddl`, `new-problem.pddl` only when the event changes
/// them), the old plan.
fn files(name: &str) -> [String; 5] {
    let dir = format!("tests/repair/{name}");
    let exists = |f: &str| workspace_root().join(&dir).join(f).exists();
    let old = ["old.plan", "old.json"].into_iter().find(|f| exists(f)).expect("an old plan");
    let new_domain = if exists("new-domain.pddl") { "new-domain.pddl" } else { "domain.pddl" };
    let new_problem = if exists("new-problem.pddl") { "new-problem.pddl" } else { "problem.pddl" };
    ["domain.pddl", "problem.pddl", old, new_domain, new_problem].map(|f| format!("{dir}/{f}"))
}

/// Repairs the fixture's old plan for its new problem with `args`;
/// snapshots what the user sees (as `repair@NAME`, `repair@NAME-SUFFIX`
/// with options) and validates the repaired plan. The old plan is checked
/// first: it solves the old problem.
fn repair(name: &str, suffix: &str, args: &[&str]) -> Run {
    let [domain, problem, old, new_domain, new_problem] = files(name);
    let o = hipop(&["validate", &domain, &problem, &old]);
    assert_eq!(status(&o), 0, "{old} solves {problem}:\n{}{}", stdout(&o), stderr(&o));
    let mut argv = vec!["repair", &new_domain, &new_problem, &old, "--color", "never"];
    argv.extend_from_slice(args);
    let o = hipop(&argv);
    assert_no_panic(&o);
    let run = Run { status: status(&o), report: stderr(&o), plan: stdout(&o) };
    let shown = format!(
        "$ hipop {}\nexit status {}\n--- the report (standard error)\n{}--- the repaired plan (standard output)\n{}",
        argv.join(" "),
        run.status,
        run.report,
        run.plan
    );
    let snapshot = if suffix.is_empty() { name.to_string() } else { format!("{name}-{suffix}") };
    insta::with_settings!({
        snapshot_suffix => snapshot,
        filters => vec![(r"expanded in \d+\.\d+ s", "expanded in [elapsed] s")],
    }, {
        insta::assert_snapshot!("repair", shown);
    });
    if run.status == 0 {
        let dir = TempDir::new(&format!("repair-{name}-{suffix}"));
        let path = dir.0.join("repaired.plan");
        std::fs::write(&path, &run.plan).expect("written");
        let v = hipop(&["validate", &new_domain, &new_problem, path.to_str().expect("UTF-8 temp path")]);
        assert_eq!(status(&v), 0, "the repaired plan is valid:\n{}{}\n{}", stdout(&v), stderr(&v), run.plan);
    }
    run
}

/// An object gone (the kit k1): the steps that name it are obsolete, and so
/// is a step that could only run after them (m1 can no longer be
/// calibrated); the sample goes to the other machine, in stage 1.
#[test]
fn repair_obsolete_object_gone() {
    let run = repair("obsolete-object-gone", "", &[]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "stage 1 (obsolete steps removed)");
    assert_eq!(
        run.removed(),
        [
            ("(calibrate m1 k1)", "obsolete: `k1` is not an object of the problem"),
            (
                "(analyze m1 s1)",
                "obsolete: it can never be executed in the new problem (a condition of it can never hold)"
            ),
        ]
    );
    assert_eq!(run.start("(calibrate m2 k2)"), 0.01, "kept at its time");
    assert_eq!(run.start("(analyze m2 s2)"), 3.02, "kept at its time");
    run.start("(analyze m2 s1)");
}

/// An action removed from the domain (`calibrate`): its steps are obsolete;
/// the analyses stay and the search supports them with the action that
/// replaces it. The old plan is hipop's JSON plan.
#[test]
fn repair_obsolete_action_removed() {
    let run = repair("obsolete-action-removed", "", &[]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "stage 1 (obsolete steps removed)");
    let removed = run.removed();
    assert!(!removed.is_empty());
    for (call, why) in &removed {
        assert!(call.starts_with("(calibrate "), "{removed:?}");
        assert_eq!(*why, "obsolete: the domain has no action or task of that name");
    }
    let steps = run.steps();
    assert!(steps.iter().all(|s| !s.0.starts_with("(calibrate ")), "{}", run.plan);
    assert!(steps.iter().any(|s| s.0.starts_with("(self-test ")), "{}", run.plan);
}

/// Stage 2, the first ring: without k3, the analysis on m1 cannot be kept
/// (the one kit left, k1, is used up by m2's calibration): stage 1's
/// search fails; the ring around the obsolete calibration removes that
/// analysis, and the sample goes to m2. The rest of the plan stays.
#[test]
fn repair_ring_after_obsolete_step() {
    let run = repair("ring-after-obsolete-step", "", &[]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "stage 2 (ring 1 of steps around those removed)");
    let stages = run.stages();
    assert_eq!(stages.len(), 2, "{stages:?}");
    assert!(
        stages[0].starts_with("stage 1 (obsolete steps removed): 3 steps of the old plan kept"),
        "{stages:?}"
    );
    assert!(stages[0].contains(", no plan from there,"), "{stages:?}");
    assert!(stages[1].contains(": 2 steps of the old plan kept, 2 goals, repaired,"), "{stages:?}");
    assert_eq!(
        run.removed(),
        [
            ("(calibrate m1 k3)", "obsolete: `k3` is not an object of the problem"),
            ("(analyze m1 s1)", "ring 1: next to a step removed"),
        ]
    );
    assert_eq!(run.start("(calibrate m2 k1)"), 0.01);
    assert_eq!(run.start("(analyze m2 s2)"), 3.02);
    run.start("(analyze m2 s1)");
}

/// An abstract step un-refined: one subtask of `inspect r1 w2` used the
/// lost probe; every step of its method goes (the report too, un-refined),
/// the abstract step stays and is refined again, by another method. The
/// other inspection is untouched.
#[test]
fn repair_unrefine_abstract_step() {
    let run = repair("unrefine-abstract-step", "", &[]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "stage 1 (obsolete steps removed)");
    assert_eq!(
        run.removed(),
        [
            ("(probe r1 w2 p1)", "obsolete: `p1` is not an object of the problem"),
            ("(report r1 w2)", "its abstract step was un-refined"),
        ]
    );
    let steps = run.steps();
    let method = |call: &str| {
        steps.iter().find(|s| s.0 == call).and_then(|s| s.2.clone()).unwrap_or_else(|| panic!("{}", run.plan))
    };
    assert_eq!(method("(inspect r1 w2)"), "inspect-by-eye", "refined again, with the other method");
    assert_eq!(method("(inspect r2 w1)"), "inspect-by-eye", "unchanged");
    assert_eq!(run.start("(look r2 w1)"), 0.0);
    assert_eq!(run.start("(report r2 w1)"), 6.01);
    run.start("(look r1 w2)");
}

/// Phantom links: the photograph of z1 is dropped, and with it the reason
/// why the drilling of z2 came after the camera's set-up (the photograph
/// needed quiet, the drilling came after it). The order is kept: drilling
/// starts after the set-up, where a plan from scratch starts it at once.
#[test]
fn repair_phantom_link_keeps_order() {
    let run = repair("phantom-link-keeps-order", "", &[]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "stage 1 (obsolete steps removed)");
    assert_eq!(run.removed(), [("(photograph c1 z1)", "it supported nothing any more")]);
    assert_eq!(run.start("(set-up c1)"), 0.0);
    assert!(run.start("(drill z2)") >= 2.0 + 0.01 - 1e-9, "after the set-up:\n{}", run.plan);
    assert!(run.start("(photograph c1 z3)") > run.start("(drill z2)"), "{}", run.plan);
    // Nothing in the new problem orders them: a plan from scratch does not.
    let [_, _, _, domain, problem] = files("phantom-link-keeps-order");
    let o = hipop(&["plan", &domain, &problem, "-q", "--first"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    let scratch = steps_of(&stdout(&o));
    let drill = scratch.iter().find(|s| s.0 == "(drill z2)").expect("drilling");
    assert!(drill.1 < 2.0, "{}", stdout(&o));
}

/// Executed steps kept: at time 3 (`--now 3`) the camera c1 was set up and
/// the drilling is running. No photograph is needed any more: the set-up
/// supports nothing, but it was executed, so it stays at its time; the
/// photographs, not started, go. The new camera's set-up starts at 3, not
/// in the past. `--executed 0` keeps the set-up the same way; without
/// either, it is removed.
#[test]
fn repair_executed_steps_kept() {
    let run = repair("executed-steps-kept", "now", &["--now", "3"]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "stage 1 (obsolete steps removed)");
    let removed = run.removed();
    assert_eq!(
        removed,
        [
            ("(photograph c1 z1)", "it supported nothing any more"),
            ("(photograph c1 z3)", "it supported nothing any more")
        ]
    );
    assert_eq!(run.start("(set-up c1)"), 0.0, "executed: at its old time");
    assert_eq!(run.start("(drill z2)"), 0.01, "running: at its old time");
    assert!(run.start("(set-up c2)") >= 3.0 - 1e-9, "nothing new starts before now:\n{}", run.plan);

    let run = repair("executed-steps-kept", "executed", &["--executed", "0"]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.start("(set-up c1)"), 0.0, "executed: kept");
    assert!(!run.removed().iter().any(|r| r.0 == "(set-up c1)"), "{}", run.report);

    let [_, _, old, domain, problem] = files("executed-steps-kept");
    let o = hipop(&["repair", &domain, &problem, &old, "--color", "never", "-q"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    assert!(!steps_of(&stdout(&o)).iter().any(|s| s.0 == "(set-up c1)"), "not executed: removed");
}

/// Executed steps at time 0, as other planners write plans (hipop's start
/// 0.01 after the initial state when they read it): at time 1, m2's
/// calibration is under way and has used k1 up. It stays at 0, reading the
/// initial state there, and its use of k1 at 0 forbids calibrating m1 with
/// k1 again: the ring moves the analysis of s1 to m2.
#[test]
fn repair_executed_at_time_zero() {
    let run = repair("executed-at-time-zero", "", &["--now", "1"]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "stage 2 (ring 1 of steps around those removed)");
    assert_eq!(run.start("(calibrate m2 k1)"), 0.0, "running: at its old time");
    assert!(!run.steps().iter().any(|s| s.0 == "(calibrate m1 k1)"), "k1 is used up:\n{}", run.plan);
    run.start("(analyze m2 s1)");
}

/// An unreachable agent's steps frozen (`--unreachable r1`): r1 goes on
/// with its inspection of w2 although nothing needs it any more, and the
/// repair gives r1 nothing new: both new wells go to r2.
#[test]
fn repair_unreachable_agent_frozen() {
    let run = repair("unreachable-agent-frozen", "", &["--unreachable", "r1"]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "stage 1 (obsolete steps removed)");
    assert!(run.removed().is_empty(), "{}", run.report);
    let [_, _, old, _, _] = files("unreachable-agent-frozen");
    let old = std::fs::read_to_string(workspace_root().join(old)).expect("the old plan");
    let of_r1 = |steps: Vec<(String, f64, Option<String>)>| {
        let mut v: Vec<_> = steps.into_iter().filter(|s| s.0.contains(" r1 ")).collect();
        v.sort_by(|a, b| a.0.cmp(&b.0));
        v
    };
    assert_eq!(of_r1(run.steps()), of_r1(steps_of(&old)), "r1's steps as they were, and no other");
    for w in ["w3", "w4"] {
        let steps = run.steps();
        let inspect = steps.iter().find(|s| s.0.starts_with("(inspect ") && s.0.ends_with(&format!(" {w})")));
        assert_eq!(inspect.map(|s| s.0.clone()), Some(format!("(inspect r2 {w})")), "{}", run.plan);
    }
}

/// The full replan: without k3, s1 can only be analysed on m1, whose only
/// kit left the old plan uses on m2; stage 1 and the ring around the
/// obsolete step fail, no step is left next to those removed, and the last
/// stage plans from scratch. With the steps of m3 executed (`--executed
/// 2,5`), the full replan keeps them at their times; with `--now`, it
/// starts nothing before now.
#[test]
fn repair_full_replan() {
    let run = repair("full-replan", "", &[]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "the full replan");
    let stages = run.stages();
    assert_eq!(stages.len(), 3, "{stages:?}");
    assert!(stages[..2].iter().all(|s| s.contains("no plan from there")), "{stages:?}");
    assert!(
        stages[2].starts_with("the full replan: 0 steps of the old plan kept, 3 goals, repaired"),
        "{stages:?}"
    );
    assert_eq!(
        run.removed(),
        [
            ("(calibrate m1 k3)", "obsolete: `k3` is not an object of the problem"),
            ("(analyze m1 s1)", "ring 1: next to a step removed"),
        ]
    );
    run.start("(calibrate m1 k1)");

    let run = repair("full-replan", "executed", &["--executed", "2,5"]);
    assert_eq!(run.status, 0, "{}", run.report);
    assert_eq!(run.found_by(), "the full replan");
    let stages = run.stages();
    assert!(
        stages[2].starts_with("the full replan: 2 steps of the old plan kept, 3 goals, repaired"),
        "{stages:?}"
    );
    assert_eq!(run.start("(calibrate m3 k4)"), 0.5, "executed: at its old time");
    assert_eq!(run.start("(analyze m3 s3)"), 4.0, "executed: at its old time");

    // The old plan 10 s later, repaired at 5, before any step started: the
    // full replan starts nothing before 5 either.
    let [_, _, old, domain, problem] = files("full-replan");
    let text = std::fs::read_to_string(workspace_root().join(&old)).expect("the old plan");
    let later: String = text
        .lines()
        .map(|l| match l.split_once(": ") {
            Some((t, rest)) if !l.starts_with(';') => {
                format!("{}: {rest}\n", t.parse::<f64>().expect("a time") + 10.0)
            }
            _ => format!("{l}\n"),
        })
        .collect();
    let dir = TempDir::new("repair-full-replan-later");
    let path = dir.0.join("later.plan");
    std::fs::write(&path, later).expect("written");
    let path = path.to_str().expect("UTF-8 temp path");
    let o = hipop(&["repair", &domain, &problem, path, "--now", "5", "--color", "never"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).contains("; found by the full replan"), "{}", stdout(&o));
    let steps = steps_of(&stdout(&o));
    assert!(steps.iter().all(|s| s.1 >= 5.0 - 1e-9), "nothing before now:\n{}", stdout(&o));
}

/// No plan: each sample suits one machine, and one kit is left for both:
/// every stage fails, the full replan too; exit status 1, with why.
#[test]
fn repair_no_plan() {
    let run = repair("no-plan", "", &[]);
    assert_eq!(run.status, 1, "{}", run.report);
    assert_eq!(run.plan, "", "no plan written");
    let stages = run.stages();
    assert_eq!(stages.len(), 3, "{stages:?}");
    assert!(stages.iter().all(|s| s.contains("no plan from there")), "{stages:?}");
    assert!(stages[2].starts_with("the full replan: "), "{stages:?}");
    assert!(run.report.contains("error[E0502]"), "{}", run.report);
    assert!(run.report.ends_with("error: no plan, even after the full replan\n"), "{}", run.report);
}

/// The case study with a robot out of service mid-mission (section 5.5 of
/// the HiPOP paper, `samples/surveillance/problem-lost-mona2.pddl`): mona2
/// can no longer observe from 3000 s; the repair with `--now 3000` removes
/// its observations and then its second patrol, another large UGV patrols
/// (mona1, free first once the other robots' work is kept as it was),
/// nothing new starts before 3000 s, and the plan is valid; with mona3 out
/// of communication too, also mona1.
#[test]
fn repair_of_a_robot_out_of_service() {
    let dir = TempDir::new("repair-lost");
    let domain = "samples/surveillance/domain.pddl";
    let old = dir.0.join("old.plan");
    let old_s = old.to_str().expect("UTF-8 temp path");
    let o = hipop(&["plan", domain, "samples/surveillance/problem.pddl", "-o", old_s, "-q", "--first"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    let lost = "samples/surveillance/problem-lost-mona2.pddl";
    let repaired = dir.0.join("repaired.plan");
    let repaired_s = repaired.to_str().expect("UTF-8 temp path");
    for (unreachable, taker) in [(None, "mona1"), (Some("mona3"), "mona1")] {
        let mut args = vec!["repair", domain, lost, old_s, "--now", "3000", "-o", repaired_s];
        if let Some(u) = unreachable {
            args.extend(["--unreachable", u]);
        }
        let o = hipop(&args);
        assert_no_panic(&o);
        assert_eq!(status(&o), 0, "{}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains("removed (patrol-ugv-large-3 mona2) (step 255): ring 1"), "{err}");
        assert!(
            err.contains("a condition that only the initial state and timed literals give never holds again")
        );
        let o = hipop(&["validate", domain, lost, repaired_s]);
        assert_eq!(status(&o), 0, "{}", stderr(&o));
        let plan = std::fs::read_to_string(&repaired).expect("the repaired plan");
        let old_text = std::fs::read_to_string(&old).expect("the old plan");
        assert!(plan.lines().any(|l| l.contains(&format!("patrol-ugv-large-3 {taker}"))), "{plan}");
        // Every step of the repaired plan that the old plan does not have
        // starts at 3000 s or later.
        let steps = |t: &str| -> Vec<(String, f64)> {
            let calls: std::collections::HashMap<String, String> = t
                .lines()
                .filter_map(|l| {
                    let (id, rest) = l.split_once(' ')?;
                    id.parse::<u32>().ok()?;
                    Some((id.to_string(), rest.split(" -> ").next()?.to_string()))
                })
                .collect();
            t.lines()
                .filter_map(|l| {
                    let mut w = l.strip_prefix(";@ ")?.split_whitespace();
                    let (id, start) = (w.next()?, w.next()?.parse().ok()?);
                    Some((calls.get(id)?.clone(), start))
                })
                .collect()
        };
        let before = steps(&old_text);
        let new: Vec<(String, f64)> = steps(&plan)
            .into_iter()
            .filter(|(call, t)| !before.iter().any(|(c, u)| c == call && (t - u).abs() < 0.001))
            .collect();
        assert!(!new.is_empty());
        assert!(new.iter().all(|(_, t)| *t >= 3000.0), "{new:?}");
    }
}
