use super::super::{Options, TimedStep, validate_temporal};
use crate::AnalysisHost;
use crate::db::file_units;

const DOMAIN: &str = "(define (domain lights)
  (:requirements :typing :durative-actions :fluents :timed-initial-literals :negative-preconditions)
  (:types room)
  (:predicates (lit ?r - room) (open ?r - room) (busy))
  (:functions (power) (uses ?r - room))
  (:durative-action light :parameters (?r - room) :duration (= ?duration 2)
    :condition (and (at start (not (lit ?r))) (over all (open ?r)))
    :effect (and (at end (lit ?r)) (at start (increase (power) 1))))
  (:durative-action work :parameters (?r - room) :duration (<= ?duration 5)
    :condition (and (at start (lit ?r)) (over all (lit ?r)) (at end (open ?r)))
    :effect (and (at start (busy)) (at end (not (busy))) (at end (increase (uses ?r) ?duration))))
  (:action close :parameters (?r - room) :precondition (open ?r) :effect (not (open ?r)))
  (:action all-off :parameters () :effect (and (assign (power) 0) (forall (?r - room) (not (lit ?r)))))
  (:action reset :parameters () :effect (assign (power) 0)))";

const PROBLEM: &str = "(define (problem p) (:domain lights)
  (:objects r1 r2 - room)
  (:init (open r1) (open r2) (= (power) 0) (= (uses r1) 0) (at 10 (not (open r1))) (at 20 (open r1)))
  (:goal (lit r1))
  (:metric minimize (+ (total-time) (power))))";

/// Steps from `[time:] (name args…) [[duration]]` lines, without spans.
fn steps(plan: &str) -> Vec<TimedStep> {
    plan.lines()
        .enumerate()
        .filter(|(_, l)| l.contains('('))
        .map(|(k, l)| {
            let (head, rest) = l.split_once('(').expect("a step");
            let (call, tail) = rest.split_once(')').expect("a closed step");
            let words: Vec<&str> = call.split_whitespace().collect();
            let time = head.trim().trim_end_matches(':').trim().parse().ok();
            let duration = tail.trim().trim_start_matches('[').trim_end_matches(']').parse().ok();
            TimedStep {
                line: k + 1,
                ..TimedStep::new(words[0], &words[1..], time, duration, Default::default())
            }
        })
        .collect()
}

/// The verdict, the value and the failures (`CODE message`).
fn run(plan: &str, options: Options) -> (bool, Option<f64>, Vec<String>) {
    let mut host = AnalysisHost::new();
    host.set_file_text("m/domain.pddl", DOMAIN);
    let p = host.set_file_text("m/problem.pddl", PROBLEM);
    let db = host.db();
    let report = validate_temporal(db, file_units(db, p)[0], &steps(plan), &options);
    let failures = report.failures.iter().map(|f| format!("{} {}", f.code.id, f.message)).collect();
    (report.valid, report.value, failures)
}

fn check(plan: &str) -> (bool, Option<f64>, Vec<String>) {
    run(plan, Options::default())
}

#[test]
fn a_valid_plan_has_the_metric_as_value() {
    assert_eq!(check("0: (light r1) [2]"), (true, Some(3.0), vec![]));
    // Simultaneous increases commute.
    assert_eq!(check("0: (light r1) [2]\n0: (light r2) [2]"), (true, Some(4.0), vec![]));
    // Untimed steps happen at 1, 2, 3…: `light` ends at 3.
    assert_eq!(check("(light r1) [2]"), (true, Some(4.0), vec![]));
}

#[test]
fn timed_initial_literals_happen_at_their_time_until_the_plan_ends() {
    let (valid, _, failures) = check("9: (light r1) [2]");
    assert!(!valid);
    assert_eq!(
        failures,
        [
            "E0416 the step on line 1 `(light r1)` runs from 9.0 to 11.0, but its `over all` condition `(open r1)` is false from 10.0: deleted at 10.0 by the timed initial literal at 10.0"
        ]
    );
    // The literal at 20 opens r1 again.
    assert!(check("20: (light r1) [2]").0);
    // Literals after the last step are not applied: r1 stays open.
    assert!(check("0: (light r1) [2]\n3: (close r2)").0);
}

#[test]
fn culprits_are_named() {
    let (_, _, failures) = check("(close r2)\n(close r2)\n0: (light r1) [2]");
    assert_eq!(
        failures,
        [
            "E0415 the step on line 2 `(close r2)` at 2.0: precondition `(open r2)` is false: deleted at 1.0 by the step on line 1 `(close r2)`"
        ]
    );
    let (_, _, failures) = check("");
    assert_eq!(
        failures,
        [
            "E0419 the goal is not reached at the end of the plan (0.0): `(lit r1)` is false: it is not in the initial state and nothing makes it true before"
        ]
    );
    let (_, _, failures) = check("0: (light r1) [2]\n3: (light r1) [2]");
    assert_eq!(
        failures,
        [
            "E0415 the step on line 2 `(light r1)` at 3.0: `at start` condition `(lit r1)` is true: added at 2.0 by the end of the step on line 1 `(light r1)`"
        ]
    );
}

/// Steps are named by their id in the file (hierarchical and JSON plans),
/// else by their line (VAL plans), never by their index in the list.
#[test]
fn steps_are_named_by_their_id_or_else_their_line() {
    let mut host = AnalysisHost::new();
    host.set_file_text("m/domain.pddl", DOMAIN);
    let p = host.set_file_text("m/problem.pddl", PROBLEM);
    let db = host.db();
    let mut plan = steps("(close r2)\n(close r2)");
    let failure = |plan: &[TimedStep]| {
        let report = validate_temporal(db, file_units(db, p)[0], plan, &Options::default());
        report.failures.iter().map(|f| f.message.clone()).collect::<Vec<_>>()
    };
    let by_line = "the step on line 2 `(close r2)` at 2.0: precondition `(open r2)` is false: deleted at 1.0 by the step on line 1 `(close r2)`";
    assert_eq!(failure(&plan), [by_line]);
    (plan[0].id, plan[1].id) = (Some(0), Some(7));
    let by_id = "step 7 `(close r2)` at 2.0: precondition `(open r2)` is false: deleted at 1.0 by step 0 `(close r2)`";
    assert_eq!(failure(&plan), [by_id]);
}

#[test]
fn over_all_holds_strictly_between_start_and_end() {
    // Closing r1 when `light` ends is fine: `over all` excludes the end.
    assert!(check("0: (light r1) [2]\n2: (close r1)").0);
    // Closing it when `light` starts is not: the state after the start
    // happening is inside the interval. No mutex: invariants are not
    // part of a happening.
    let (_, _, failures) = check("0: (light r1) [2]\n0: (close r1)");
    assert_eq!(failures.len(), 1);
    assert!(failures[0].starts_with("E0416"), "{failures:?}");
}

#[test]
fn mutual_exclusion_within_a_happening() {
    let (valid, _, failures) = check("0: (light r1) [2]\n0: (reset)");
    assert!(!valid);
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].contains("both change `(power)` (`increase` and `assign`)"), "{failures:?}");
    let (_, _, failures) = check("0: (light r1) [2]\n0: (all-off)");
    assert_eq!(
        failures,
        [
            "E0418 the step on line 2 `(all-off)` at 0.0 interferes with the start of the step on line 1 `(light r1)` at 0.0: the step on line 2 deletes `(lit r1)`, which the start of the step on line 1 reads"
        ]
    );
    // A zero duration puts a step's start and end in one happening.
    let (_, _, failures) = check("0: (light r1) [2]\n2.01: (work r1) [0]");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].starts_with("E0418"), "{failures:?}");
    assert!(
        failures[0].contains(
            "the start of the step on line 2 adds `(busy)`, which the end of the step on line 2 deletes"
        ),
        "{failures:?}"
    );
}

#[test]
fn duration_inequalities_use_the_tolerance() {
    assert!(check("0: (light r1) [2]\n2.01: (work r1) [5.005]").0);
    let (_, _, failures) = check("0: (light r1) [2]\n2.01: (work r1) [6]");
    assert_eq!(
        failures,
        [
            "E0417 the step on line 2 `(work r1)` lasts 6.0, but its duration constraint `(<= ?duration 5)` requires at most 5.0"
        ]
    );
    assert!(!check("0: (light r1) [2.02]").0);
    assert!(check("0: (light r1) [2.009]").0);
}

#[test]
fn names_are_case_insensitive_and_lenient_with_underscores() {
    assert!(check("0: (LIGHT R1) [2]").0);
    let plan = "0: (light r1) [2]\n3: (all_off)\n4: (light r1) [2]";
    let (valid, _, failures) = check(plan);
    assert!(!valid && failures[0].starts_with("E0410"), "{failures:?}");
    let (valid, _, failures) = run(plan, Options { lenient: true, ..Options::default() });
    assert!(valid, "{failures:?}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 200, ..Default::default() })]
    /// Any steps, however wrong (unknown names, wrong arities, times and
    /// durations that are negative, zero or not numbers, events at the
    /// same time), give a verdict without panicking, and the verdict is
    /// "valid" exactly when no failure is an error.
    #[test]
    fn any_steps_get_a_consistent_verdict(
        raw in proptest::collection::vec(
            (0..8usize, proptest::collection::vec(0..4usize, 0..3), 0..9usize, 0..9usize),
            0..12,
        ),
        keep_going in proptest::bool::ANY,
    ) {
        const NAMES: [&str; 8] = ["light", "work", "close", "all-off", "reset", "LIGHT", "nope", "all_off"];
        const ARGS: [&str; 4] = ["r1", "r2", "x", "R1"];
        const NUMBERS: [f64; 9] = [0.0, 0.0005, 0.005, 1.0, 2.0, 10.0, -1.0, f64::NAN, f64::INFINITY];
        let plan: Vec<TimedStep> = raw
            .iter()
            .map(|(n, args, t, d)| {
                let args: Vec<&str> = args.iter().map(|&a| ARGS[a]).collect();
                let time = (*t != 0).then(|| NUMBERS[*t - 1]);
                let duration = (*d != 0).then(|| NUMBERS[*d - 1]);
                TimedStep::new(NAMES[*n], &args, time, duration, Default::default())
            })
            .collect();
        let mut host = AnalysisHost::new();
        host.set_file_text("m/domain.pddl", DOMAIN);
        let p = host.set_file_text("m/problem.pddl", PROBLEM);
        let db = host.db();
        let options = Options { keep_going, ..Options::default() };
        let report = validate_temporal(db, file_units(db, p)[0], &plan, &options);
        let errors = report.failures.iter().filter(|f| f.code.severity == crate::Severity::Error).count();
        proptest::prop_assert_eq!(report.valid, errors == 0);
        proptest::prop_assert!(report.valid || report.value.is_none());
    }
}

#[test]
fn keep_going_reports_later_failures() {
    let plan = "(close r2)\n(close r2)\n(close r2)\n0: (light r1) [2]";
    assert_eq!(check(plan).2.len(), 1);
    let (valid, _, failures) = run(plan, Options { keep_going: true, ..Options::default() });
    assert!(!valid);
    assert_eq!(failures.len(), 2, "{failures:?}");
}
