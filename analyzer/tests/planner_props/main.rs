//! The HiPOP planner against the validator and a brute-force search, on
//! random small temporal problems.
//!
//! - Every plan the planner returns is valid for the validator (its VAL text,
//!   its JSON and its hierarchical form read back).
//! - A breadth-first search over sequential executions (one action at a
//!   time), with its own grounding, is the reference: when it finds a plan
//!   (itself checked by the validator), the planner finds one too or stops
//!   at a limit (few limits are tolerated); when the planner says there is
//!   no plan, the search finds none.
//! - The planner never panics, also on random mutations of the problems.
//!
//! `HIPOP_PROPS_CASES` sets the number of random problems (default 300),
//! `HIPOP_PROPS_SEED` the seed (a number), `HIPOP_PROPS_SECONDS` the
//! planner's time limit per problem (default 2; the node limit is 20,000).
//! `HIPOP_PROPS_CONFIG` plans every problem with one configuration (by
//! default, half with the default one, half with one of `Config::MAIN`).
//! With `HIPOP_PROPS_STRICT` set, a limit where the breadth-first search
//! found a plan fails (and shrinks) like any other disagreement. Regressions are the fixtures of
//! `tests/planner/props/`.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::time::Duration;

use hipop_analyzer::planner::output::SolvedPlan;
use hipop_analyzer::planner::{Config, PlannerLimits, Status};
use hipop_analyzer::{AnalysisHost, Diagnostic, PlanningResult, Severity, SourceFile};
use proptest::prelude::*;
use proptest::test_runner::{Config as RunnerConfig, RngAlgorithm, TestCaseError, TestRng, TestRunner};

mod mutation;
#[path = "../common/random_problem.rs"]
mod problem;
mod reference;

use mutation::*;
use problem::*;
use reference::*;

// ---------------------------------------------------------------------------
// Running the planner and the validator.

const PROBLEM: &str = "problem.pddl";

/// The node limit decides; the time limit (`HIPOP_PROPS_SECONDS`, default
/// 2) only bounds the few searches whose expansions get slow.
fn limits(nodes: u64) -> PlannerLimits {
    let seconds = std::env::var("HIPOP_PROPS_SECONDS").ok().and_then(|s| s.parse().ok()).unwrap_or(2.0);
    PlannerLimits { time: Some(Duration::from_secs_f64(seconds)), nodes: Some(nodes), ..Default::default() }
}

fn plan(host: &AnalysisHost, file: SourceFile, config: &Config, nodes: u64) -> PlanningResult {
    host.analysis()
        .run_planner(file, config, &limits(nodes), &|| false, &mut |_| {})
        .expect("not cancelled")
        .expect("the file has a problem")
}

/// Validates a solved plan in VAL's format, as JSON and in the IPC 2020
/// hierarchical format with hipop's timing.
fn validate_solved(host: &mut AnalysisHost, problem: SourceFile, plan: &SolvedPlan) -> Result<(), String> {
    validate(host, problem, "planner.plan", &plan.to_val("hipop"))?;
    validate(host, problem, "planner-json.plan", &plan.to_json())?;
    validate(host, problem, "planner-hierarchical.plan", &plan.to_hierarchical("hipop"))
}

fn model_errors(host: &AnalysisHost, file: SourceFile) -> Vec<Diagnostic> {
    host.analysis()
        .check_diagnostics(file)
        .unwrap()
        .into_iter()
        .filter(|d| d.severity == Severity::Error)
        .collect()
}

// ---------------------------------------------------------------------------
// The random properties.

#[derive(Debug, Default)]
struct Counts {
    cases: usize,
    solved: usize,
    plans_validated: usize,
    bfs_plans: usize,
    bfs_plans_validated: usize,
    agreements: usize,
    limits_with_bfs_plan: usize,
    planner_only: usize,
    no_plan: usize,
    no_plan_limit: usize,
    refused_unreachable: usize,
    by_config: Vec<(String, usize, usize)>,
    known_bugs: Vec<&'static str>,
    disagreements: Vec<String>,
}

fn cases() -> u32 {
    std::env::var("HIPOP_PROPS_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(300)
}

fn runner(cases: u32) -> TestRunner {
    let seed: u64 =
        std::env::var("HIPOP_PROPS_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(0x0048_4950_4f50);
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let config =
        RunnerConfig { cases, failure_persistence: None, max_shrink_iters: 2000, ..RunnerConfig::default() };
    TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &bytes))
}

const NODES: u64 = 20_000;

/// The bugs already reported (with their fixture), recognised on a problem
/// that fails: the random properties count them and go on looking for
/// others. None at present: a bug found gets a recogniser here and a
/// fixture with a `; bug:` line until it is fixed (the last ones, conditions
/// supported by the action's own start and the equal-f plateaus, are).
fn known_bug(_p: &Problem) -> Option<&'static str> {
    None
}

/// Plans `p` with `config`, checks the properties, and counts; a failure
/// that is a known bug is counted, not reported.
fn check(p: &Problem, config: &Config, counts: &mut Counts) -> Result<(), String> {
    check_new(p, config, counts).or_else(|e| match known_bug(p) {
        Some(bug) => {
            counts.known_bugs.push(bug);
            Ok(())
        }
        None => Err(e),
    })
}

fn check_new(p: &Problem, config: &Config, counts: &mut Counts) -> Result<(), String> {
    let text = p.text();
    let mut host = AnalysisHost::new();
    let file = host.set_file_text(PROBLEM, text.clone());
    let errors = model_errors(&host, file);
    if !errors.is_empty() {
        return Err(format!("the generated model has errors:\n{}", show(&host, &errors)));
    }
    let r = reference(p);
    let found = bfs(&r);
    // The reference's plan is a valid temporal plan.
    let sequential = found.plan.as_ref().map(|seq| sequential_val(p, &r, seq));
    if let Some(seq) = &sequential {
        validate(&mut host, file, "bfs.plan", seq)
            .map_err(|e| format!("the sequential plan of the breadth-first search is not valid: {e}"))?;
        counts.bfs_plans += 1;
        counts.bfs_plans_validated += 1;
    }
    // Provably unsolvable sequentially: a smaller node budget is enough.
    let nodes = if found.plan.is_none() && found.complete { NODES / 10 } else { NODES };
    let result = plan(&host, file, config, nodes);
    counts.cases += 1;
    let entry = match counts.by_config.iter().position(|c| c.0 == config.name()) {
        Some(i) => i,
        None => {
            counts.by_config.push((config.name(), 0, 0));
            counts.by_config.len() - 1
        }
    };
    counts.by_config[entry].1 += 1;
    match (&result.status, &result.plan) {
        (Status::Solved, Some(solved)) => {
            counts.solved += 1;
            validate_solved(&mut host, file, solved)
                .map_err(|e| format!("the planner's plan ({}) is not valid: {e}", config.name()))?;
            counts.plans_validated += 1;
            if found.plan.is_some() {
                counts.agreements += 1;
            } else {
                // Valid, so it needs concurrency (or more steps than the bound).
                counts.planner_only += 1;
            }
        }
        (Status::Solved, None) => return Err("Solved without a plan".into()),
        (Status::NoPlan, _) => {
            counts.no_plan += 1;
            if let Some(seq) = &sequential {
                return Err(format!(
                    "the planner ({}) says there is no plan, the breadth-first search found one:\n{seq}{}",
                    config.name(),
                    show(&host, &result.diagnostics)
                ));
            }
        }
        (Status::Limit(kind), _) => {
            if let Some(seq) = &sequential {
                let what = format!(
                    "limit ({}, {}, {} expanded{}) where the breadth-first search found\n{seq}",
                    kind.as_str(),
                    config.name(),
                    result.stats.expanded,
                    known_bug(p).map_or(String::new(), |b| format!(", known bug {b}")),
                );
                if std::env::var_os("HIPOP_PROPS_STRICT").is_some() {
                    return Err(what);
                }
                counts.limits_with_bfs_plan += 1;
                counts.by_config[entry].2 += 1;
                counts.disagreements.push(format!("{what}on\n{text}"));
            } else {
                counts.no_plan_limit += 1;
            }
        }
        (Status::Refused, _) => {
            if relaxed_reachable(&r) {
                return Err(format!(
                    "the planner refuses a supported problem whose goal is reachable:\n{}",
                    show(&host, &result.diagnostics)
                ));
            }
            counts.refused_unreachable += 1;
        }
    }
    Ok(())
}

/// Half the problems with the default configuration, the others with one of
/// [`Config::MAIN`]; `HIPOP_PROPS_CONFIG` names one for all.
fn pick_config(k: u8) -> Config {
    if let Ok(name) = std::env::var("HIPOP_PROPS_CONFIG") {
        return Config::parse(&name).expect("HIPOP_PROPS_CONFIG is a configuration");
    }
    let k = k as usize % (2 * Config::MAIN.len());
    Config::parse(if k < Config::MAIN.len() { Config::DEFAULT } else { Config::MAIN[k - Config::MAIN.len()] })
        .unwrap()
}

#[test]
fn random_problems_against_the_validator_and_bfs() {
    let counts = RefCell::new(Counts::default());
    let mut runner = runner(cases());
    let result = runner.run(&(problem(), any::<u8>()), |(p, k)| {
        check(&p, &pick_config(k), &mut counts.borrow_mut()).map_err(TestCaseError::fail)
    });
    let c = counts.into_inner();
    eprintln!(
        "cases {}, solved {} (plans validated {}, {} without a sequential plan), reference plans {} (validated {}), \
         agreements {}, limits where the reference has a plan {}, no plan {}, limits without a reference plan {}, \
         refused as unreachable {}",
        c.cases,
        c.solved,
        c.plans_validated,
        c.planner_only,
        c.bfs_plans,
        c.bfs_plans_validated,
        c.agreements,
        c.limits_with_bfs_plan,
        c.no_plan,
        c.no_plan_limit,
        c.refused_unreachable
    );
    let mut known = c.known_bugs.clone();
    known.sort();
    known.dedup();
    for bug in known {
        eprintln!("  known bug {bug}: {} cases", c.known_bugs.iter().filter(|b| **b == bug).count());
    }
    for (name, n, l) in &c.by_config {
        eprintln!("  {name}: {n} cases, {l} limits with a reference plan");
    }
    if let Err(e) = result {
        panic!("{e}");
    }
    for d in &c.disagreements {
        eprintln!("---\n{d}");
    }
    // A few limits are tolerated (the search is heuristic), not many.
    assert!(
        c.limits_with_bfs_plan * 50 <= c.bfs_plans.max(1),
        "{} limits out of {} problems with a sequential plan",
        c.limits_with_bfs_plan,
        c.bfs_plans
    );
}

// ---------------------------------------------------------------------------
// Mutations: the planner never panics.

/// Random mutations of the problems: unbalanced parentheses, unknown names,
/// unsupported constructs. The planner answers (a refusal has a diagnostic)
/// and never panics; nor does the validator on the plans it returns. Every
/// plan it returns is valid: a mutation that makes an unsupported construct
/// the planner reads wrongly (an `over all` effect, a goal only a late timed
/// literal makes true, both found here) shows up as an invalid plan.
#[test]
fn mutated_problems_never_panic() {
    let mut runner = runner(cases());
    let outcomes = RefCell::new([0usize; 5]);
    let invalid = RefCell::new(Vec::new());
    let quick =
        PlannerLimits { time: Some(Duration::from_millis(500)), nodes: Some(1_000), ..Default::default() };
    let result = runner.run(
        &(problem(), prop::collection::vec(mutation(), 1..=2), any::<u8>()),
        |(p, mutations, k)| {
            let mut text = p.text();
            for m in &mutations {
                mutate(&mut text, m);
            }
            let mut host = AnalysisHost::new();
            let file = host.set_file_text(PROBLEM, text.clone());
            let Some(result) = host
                .analysis()
                .run_planner(file, &pick_config(k), &quick, &|| false, &mut |_| {})
                .expect("not cancelled")
            else {
                return Ok(());
            };
            let mut o = outcomes.borrow_mut();
            match (&result.status, &result.plan) {
                (Status::Solved, Some(solved)) => match validate_solved(&mut host, file, solved) {
                    Ok(()) => o[0] += 1,
                    Err(e) => {
                        o[1] += 1;
                        invalid.borrow_mut().push(format!("{e}on\n{text}"));
                    }
                },
                (Status::Solved, None) => prop_assert!(false, "solved without a plan:\n{text}"),
                (Status::Refused, _) => {
                    o[2] += 1;
                    prop_assert!(!result.diagnostics.is_empty(), "refused without a diagnostic:\n{text}");
                }
                (Status::NoPlan, _) => o[3] += 1,
                (Status::Limit(_), _) => o[4] += 1,
            }
            Ok(())
        },
    );
    let o = outcomes.into_inner();
    eprintln!(
        "mutated problems: {} solved (validated), {} solved with a plan the validator rejects, {} refused, {} no plan, {} limits",
        o[0], o[1], o[2], o[3], o[4]
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    let invalid = invalid.into_inner();
    assert!(invalid.is_empty(), "{} plans the validator rejects:\n{}", invalid.len(), invalid.join("---\n"));
}

// ---------------------------------------------------------------------------
// Regressions: the minimal problems the properties found.

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/planner/props")
}

/// `; expect: solved` (the planner finds a plan and the validator accepts it)
/// or `; expect: no-plan` (no plan exists: the planner must not return one;
/// a limit or a refusal is fine).
fn check_fixture(path: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(path).unwrap();
    let expect = text
        .lines()
        .find_map(|l| l.strip_prefix("; expect: "))
        .unwrap_or_else(|| panic!("{}: no `; expect:` line", path.display()))
        .trim()
        .to_string();
    let mut host = AnalysisHost::new();
    let file = host.set_file_text(PROBLEM, text.clone());
    let result = plan(&host, file, &Config::default(), NODES);
    if let Some(solved) = &result.plan {
        validate_solved(&mut host, file, solved)?;
    }
    match (expect.as_str(), &result.status) {
        ("solved", Status::Solved) | ("no-plan", Status::NoPlan | Status::Limit(_) | Status::Refused) => {
            Ok(())
        }
        (e, s) => Err(format!("expected {e}, got {s:?}:\n{}", show(&host, &result.diagnostics))),
    }
}

fn fixture_paths() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(fixtures())
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    paths.retain(|p| p.extension().is_some_and(|e| e == "pddl"));
    paths.sort();
    paths
}

/// The bug a fixture shows, while it is not fixed: its `; bug:` line.
fn fixture_bug(path: &Path) -> Option<String> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .find_map(|l| l.strip_prefix("; bug: "))
        .map(|b| b.split_whitespace().next().unwrap_or("").to_string())
}

/// The fixtures, without those of known bugs (`known_bugs` runs them).
#[test]
fn regressions() {
    let mut failures = Vec::new();
    let paths: Vec<PathBuf> = fixture_paths().into_iter().filter(|p| fixture_bug(p).is_none()).collect();
    assert!(!paths.is_empty(), "no fixture in {}", fixtures().display());
    for path in paths {
        if let Err(e) = check_fixture(&path) {
            failures.push(format!("{}: {e}", path.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// The fixtures of the bugs reported and not fixed yet: each fails until its
/// bug is fixed; then remove its `; bug:` line (and its signature in
/// [`known_bug`]) so that `regressions` keeps it.
#[test]
#[ignore = "no known planner bug at present: a fixture with a `; bug:` line goes here until it is fixed"]
fn known_bugs() {
    let mut fixed = Vec::new();
    let mut failures = Vec::new();
    for path in fixture_paths().into_iter().filter(|p| fixture_bug(p).is_some()) {
        match check_fixture(&path) {
            Ok(()) => fixed.push(path.display().to_string()),
            Err(e) => failures.push(format!("{}: {e}", path.display())),
        }
    }
    eprintln!("fixed (remove their `; bug:` line): {fixed:?}");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

// ---------------------------------------------------------------------------
// Hand-written cases.

/// Plans a domain and problem that must be solved; the plan is validated.
fn solve(text: &str) -> SolvedPlan {
    let mut host = AnalysisHost::new();
    let file = host.set_file_text(PROBLEM, text.to_string());
    let errors = model_errors(&host, file);
    assert!(errors.is_empty(), "{}", show(&host, &errors));
    let result = plan(&host, file, &Config::default(), NODES);
    let Some(solved) = result.plan else {
        panic!("{:?}:\n{}", result.status, show(&host, &result.diagnostics))
    };
    if let Err(e) = validate_solved(&mut host, file, &solved) {
        panic!("{e}");
    }
    eprint!("{}", solved.to_val(""));
    solved
}

fn step<'p>(plan: &'p SolvedPlan, name: &str) -> &'p hipop_analyzer::planner::output::SolvedStep {
    plan.primitive().find(|s| s.name == name).unwrap_or_else(|| panic!("no `{name}` in\n{}", plan.to_val("")))
}

#[test]
fn negative_preconditions_hold_in_the_closed_world_initial_state() {
    let plan = solve(
        "(define (domain d) (:requirements :durative-actions :negative-preconditions)
           (:predicates (blocked) (done))
           (:durative-action go :parameters () :duration (= ?duration 2)
             :condition (and (at start (not (blocked))) (over all (not (blocked))))
             :effect (at end (done))))
         (define (problem p) (:domain d) (:init) (:goal (done)))",
    );
    assert_eq!(plan.primitive().count(), 1, "{}", plan.to_val(""));
}

#[test]
fn an_over_all_condition_is_protected_from_a_threat() {
    // `cut` deletes `power`, which `work` needs all along: `cut` must end
    // after `work` (it cannot come first, `work` needs `power` at its start).
    let plan = solve(
        "(define (domain d) (:requirements :durative-actions)
           (:predicates (power) (worked) (cut))
           (:durative-action work :parameters () :duration (= ?duration 5)
             :condition (and (at start (power)) (over all (power)))
             :effect (at end (worked)))
           (:durative-action cut :parameters () :duration (= ?duration 1)
             :condition (at start (power))
             :effect (and (at end (not (power))) (at end (cut)))))
         (define (problem p) (:domain d) (:init (power)) (:goal (and (worked) (cut))))",
    );
    let (work, cut) = (step(&plan, "work"), step(&plan, "cut"));
    assert!(cut.end >= work.end - 1e-9, "{}", plan.to_val(""));
}

#[test]
fn a_timed_initial_literal_opens_a_window() {
    let plan = solve(
        "(define (domain d) (:requirements :durative-actions :timed-initial-literals)
           (:predicates (open) (went))
           (:durative-action go :parameters () :duration (= ?duration 2)
             :condition (at start (open))
             :effect (at end (went))))
         (define (problem p) (:domain d) (:init (at 10 (open))) (:goal (went)))",
    );
    let go = step(&plan, "go");
    assert!(go.start >= 10.0 - 1e-9, "{}", plan.to_val(""));
}

#[test]
fn instantaneous_actions_mix_with_durative_ones() {
    let plan = solve(
        "(define (domain d) (:requirements :durative-actions)
           (:predicates (on) (hot) (served))
           (:action switch-on :parameters () :precondition (and) :effect (on))
           (:durative-action heat :parameters () :duration (= ?duration 3)
             :condition (and (at start (on)) (over all (on)))
             :effect (at end (hot)))
           (:action serve :parameters () :precondition (hot) :effect (served)))
         (define (problem p) (:domain d) (:init) (:goal (served)))",
    );
    let (on, heat, serve) = (step(&plan, "switch-on"), step(&plan, "heat"), step(&plan, "serve"));
    assert!(on.start + 0.01 <= heat.start + 1e-9, "{}", plan.to_val(""));
    assert!(heat.end + 0.01 <= serve.start + 1e-9, "{}", plan.to_val(""));
    assert!(!on.durative && heat.durative && !serve.durative);
}

#[test]
fn interfering_actions_are_separated() {
    // Both could start at 0, but `b`'s start deletes what `a`'s start reads:
    // one happening would be a mutex, so `b` starts at least 0.01 after `a`.
    let plan = solve(
        "(define (domain d) (:requirements :durative-actions :negative-preconditions)
           (:predicates (ready) (did-a) (did-b))
           (:durative-action a :parameters () :duration (= ?duration 2)
             :condition (at start (ready))
             :effect (at end (did-a)))
           (:durative-action b :parameters () :duration (= ?duration 2)
             :condition (at start (not (did-b)))
             :effect (and (at start (not (ready))) (at end (did-b)))))
         (define (problem p) (:domain d) (:init (ready)) (:goal (and (did-a) (did-b))))",
    );
    let (a, b) = (step(&plan, "a"), step(&plan, "b"));
    assert!(b.start >= a.start + 0.01 - 1e-9, "{}", plan.to_val(""));
}

/// Not a test: `HIPOP_PROPS_FILE=path cargo test -p hipop-analyzer --test
/// planner_props every_configuration_on_a_file -- --ignored --nocapture`
/// plans a file with each main configuration and prints what happened.
#[test]
#[ignore = "a tool, run on demand with HIPOP_PROPS_FILE"]
fn every_configuration_on_a_file() {
    let Some(path) = std::env::var_os("HIPOP_PROPS_FILE") else { return };
    let text = std::fs::read_to_string(&path).unwrap();
    let mut host = AnalysisHost::new();
    let file = host.set_file_text(PROBLEM, text.clone());
    eprint!("diagnostics:\n{}", show(&host, &host.analysis().diagnostics(file).unwrap()));
    for name in Config::MAIN {
        let mut host = AnalysisHost::new();
        let file = host.set_file_text(PROBLEM, text.clone());
        let result = plan(&host, file, &Config::parse(name).unwrap(), NODES);
        eprintln!("{name}: {:?}, {:?}", result.status, result.stats);
        eprint!("{}", show(&host, &result.diagnostics));
        if let Some(solved) = &result.plan {
            eprint!("{}", solved.to_val(""));
            if let Err(e) = validate_solved(&mut host, file, solved) {
                eprintln!("{e}");
            }
        }
    }
}
