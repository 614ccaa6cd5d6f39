//! Plan repair on random small temporal problems (the generator of
//! `planner_props`, `common/random_problem.rs`): each problem is planned
//! (with the default configuration or one of `Config::MAIN`), an event
//! changes it (none; a goal added or removed; an initial fact added or
//! removed; an object removed; an action removed from the allowed actions
//! or from the domain, one the plan uses when it has one), and the plan,
//! as VAL text or JSON, is repaired for the new problem, sometimes partly
//! executed (`now` within the old plan, after a change of goals).
//!
//! - Every repaired plan is valid for the new problem (hipop's validator, on
//!   its VAL text at tolerances 0.01 and 0.0001, and on its JSON).
//! - Without an execution, where the planner finds a plan for the new
//!   problem, the repair finds one (its last stage is that search, with the
//!   same node limit).
//! - Without an event, the old plan comes back in stage 1, without the
//!   steps that supported nothing (as the old schedule links them) and
//!   with nothing added.
//! - Partly executed, the steps started before now are in the repaired
//!   plan at their times, and no other step starts before now.
//! - The repair never panics, whatever the old plan's steps have become.
//!
//! `HIPOP_REPAIR_PROPS_CASES` sets the number of random problems (default
//! 200, about two seconds), `HIPOP_REPAIR_PROPS_SEED` the seed (a number).

use std::cell::RefCell;
use std::time::Duration;

use hipop_analyzer::planner::{Config, PlannerLimits, Status};
use hipop_analyzer::repair::{Execution, RepairOptions, Stage, Why};
use hipop_analyzer::{AnalysisHost, Severity};
use proptest::prelude::*;
use proptest::test_runner::{Config as RunnerConfig, RngAlgorithm, TestCaseError, TestRng, TestRunner};

#[allow(dead_code)]
#[path = "common/random_problem.rs"]
mod problem;

use problem::*;

/// The node limit decides (the same for each stage of the repair and for
/// the planner); the time limit only bounds slow expansions.
fn limits() -> PlannerLimits {
    PlannerLimits { time: Some(Duration::from_secs(20)), nodes: Some(2_000), ..Default::default() }
}

/// A disruptive event, as raw choices resolved against the problem.
#[derive(Debug, Clone)]
struct RawEvent {
    kind: u8,
    pick: u16,
    args: [u8; 2],
    old_as_json: bool,
    /// `Some(x)`: executed until `x / 255` of the old plan's makespan
    /// (goal events only: the past stays valid).
    now: Option<u8>,
    /// The configuration of the planning and the repair: the default one
    /// for half the cases, else one of `Config::MAIN`.
    config: u8,
}

fn raw_event() -> impl Strategy<Value = RawEvent> {
    (
        0u8..8,
        any::<u16>(),
        any::<[u8; 2]>(),
        any::<bool>(),
        prop::option::weighted(0.25, any::<u8>()),
        any::<u8>(),
    )
        .prop_map(|(kind, pick, args, old_as_json, now, config)| RawEvent {
            kind,
            pick,
            args,
            old_as_json,
            now,
            config,
        })
}

/// What an event did (the object or action, for the messages).
#[derive(Debug)]
#[allow(dead_code)] // the fields are read through `Debug`, in messages
enum Event {
    /// Nothing: the plan comes back unchanged.
    Nothing,
    GoalAdded,
    GoalRemoved,
    InitChanged,
    ObjectRemoved(usize),
    NotAllowed(usize),
    ActionRemoved(usize),
}

/// The ground atoms some action makes true (the generator's goals).
fn effect_atoms(p: &Problem) -> Vec<(usize, Vec<usize>)> {
    let mut out = Vec::new();
    for a in &p.actions {
        for objs in tuples(p, &a.params) {
            for l in a.effs.iter().filter(|l| !l.neg) {
                out.push((l.pred, l.args.iter().map(|&k| objs[k]).collect()));
            }
        }
    }
    out
}

/// The new problem's text after the event, and the event. An object or
/// an action removed is one the old plan uses (`used`: the names of its
/// steps and their arguments), when it has one.
fn apply(p: &Problem, e: &RawEvent, used: &[String]) -> (String, Event) {
    let prefer = |all: Vec<usize>, name: &dyn Fn(usize) -> String| {
        let hit: Vec<usize> = all.iter().copied().filter(|&i| used.contains(&name(i))).collect();
        if hit.is_empty() { all } else { hit }
    };
    let mut q = p.clone();
    let pick = e.pick as usize;
    let allowed: Vec<usize> = p.allowed.clone().unwrap_or_else(|| (0..p.actions.len()).collect());
    let kind = match e.kind {
        1 if p.goal.len() < 2 => 0,
        // An object whose type keeps another one.
        4 if !(0..p.objects.len()).any(|o| p.objects.iter().filter(|&&t| t == p.objects[o]).count() > 1) => 0,
        5 | 6 if allowed.len() < 2 => 0,
        k => k,
    };
    let event = match kind {
        0 => {
            let atoms = effect_atoms(p);
            let (pred, objs) = if atoms.is_empty() {
                p.atom(e.pick as usize, &e.args)
            } else {
                atoms[pick % atoms.len()].clone()
            };
            q.goal.push((false, pred, objs));
            Event::GoalAdded
        }
        1 => {
            q.goal.remove(pick % p.goal.len());
            Event::GoalRemoved
        }
        2 | 3 => {
            let fact = if kind == 2 && !p.init.is_empty() {
                p.init[pick % p.init.len()].clone()
            } else {
                p.atom(e.pick as usize, &e.args)
            };
            match q.init.iter().position(|f| *f == fact) {
                Some(i) => {
                    q.init.remove(i);
                }
                None => q.init.push(fact),
            }
            Event::InitChanged
        }
        4 => {
            let candidates: Vec<usize> = prefer(
                (0..p.objects.len())
                    .filter(|&o| p.objects.iter().filter(|&&t| t == p.objects[o]).count() > 1)
                    .collect(),
                &|o| format!("o{o}"),
            );
            let o = candidates[pick % candidates.len()];
            q.init.retain(|(_, args)| !args.contains(&o));
            q.goal.retain(|(_, _, args)| !args.contains(&o));
            let text = q.text();
            let declared = format!(" o{o} - t{}", p.objects[o]);
            let at = text.find("(:objects").expect("objects");
            let end = at + text[at..].find(')').expect("the end of the objects");
            let objects = text[at..end].replacen(&declared, "", 1);
            return (format!("{}{}{}", &text[..at], objects, &text[end..]), Event::ObjectRemoved(o));
        }
        5 => {
            let candidates = prefer(allowed.clone(), &|a| format!("a{a}"));
            let k = candidates[pick % candidates.len()];
            q.allowed = Some(allowed.iter().copied().filter(|&a| a != k).collect());
            Event::NotAllowed(k)
        }
        6 => {
            // From the domain: its text goes, and its name from 𝒜.
            let candidates = prefer(allowed.clone(), &|a| format!("a{a}"));
            let k = candidates[pick % candidates.len()];
            if p.allowed.is_some() {
                q.allowed = Some(allowed.iter().copied().filter(|&a| a != k).collect());
            }
            let text = q.text();
            let start = text
                .find(&format!("  (:durative-action a{k}\n"))
                .or_else(|| text.find(&format!("  (:action a{k}\n")))
                .expect("the action");
            let effect = start + text[start..].find("\n    :effect").expect("its effect") + 1;
            let end = effect + text[effect..].find('\n').expect("the end of its effect") + 1;
            return (format!("{}{}", &text[..start], &text[end..]), Event::ActionRemoved(k));
        }
        _ => Event::Nothing,
    };
    (q.text(), event)
}

#[derive(Debug, Default)]
struct Counts {
    cases: usize,
    old_unsolved: usize,
    repaired: usize,
    by_stage: Vec<(String, usize)>,
    executed: usize,
    no_plan_both: usize,
    planner_limit: usize,
    refused: usize,
}

fn check(p: &Problem, e: &RawEvent, counts: &mut Counts) -> Result<(), String> {
    let k = e.config as usize % (2 * Config::MAIN.len());
    let config = Config::parse(if k < Config::MAIN.len() {
        Config::DEFAULT
    } else {
        Config::MAIN[k - Config::MAIN.len()]
    })
    .expect("a configuration");
    let mut host = AnalysisHost::new();
    let old_file = host.set_file_text("old-problem.pddl", p.text());
    let planned = host
        .analysis()
        .run_planner(old_file, &config, &limits(), &|| false, &mut |_| {})
        .expect("not cancelled")
        .expect("a problem");
    counts.cases += 1;
    let Some(old) = planned.plan.filter(|_| planned.status == Status::Solved) else {
        counts.old_unsolved += 1;
        return Ok(());
    };
    let used: Vec<String> = old
        .primitive()
        .flat_map(|s| std::iter::once(s.name.to_lowercase()).chain(s.args.iter().cloned()))
        .collect();
    let (text, event) = apply(p, e, &used);
    let new_file = host.set_file_text("new-problem.pddl", text.clone());
    let errors: Vec<_> = host
        .analysis()
        .check_diagnostics(new_file)
        .expect("not cancelled")
        .into_iter()
        .filter(|d| d.severity == Severity::Error)
        .collect();
    if !errors.is_empty() {
        return Err(format!("the new problem ({event:?}) has errors:\n{}{text}", show(&host, &errors)));
    }
    let old_text = if e.old_as_json { old.to_json() } else { old.to_val("") };
    let old_plan = host.set_file_text("old.plan", old_text.clone());
    let goal_event = matches!(event, Event::GoalAdded | Event::GoalRemoved);
    let now = e.now.filter(|_| goal_event).map(|x| old.makespan * x as f64 / 255.0);
    let options =
        RepairOptions { execution: Execution { now, ..Execution::default() }, ..RepairOptions::default() };
    let result = host
        .analysis()
        .run_repair(new_file, old_plan, None, &config, &limits(), &options, &|| false, &mut |_| {})
        .expect("not cancelled")
        .expect("a problem");
    let context = || {
        format!(
            "event {event:?}, now {now:?}, {}\nold plan:\n{old_text}\nnew problem:\n{text}",
            config.name()
        )
    };
    if let Some(plan) = &result.plan {
        if result.status != Status::Solved {
            return Err(format!("a plan with the status {:?}", result.status));
        }
        validate(&mut host, new_file, "repaired.plan", &plan.to_val(""))
            .and_then(|()| validate(&mut host, new_file, "repaired.json", &plan.to_json()))
            .map_err(|m| format!("the repaired plan is not valid: {m}\n{}", context()))?;
        if let Some(now) = now {
            // The steps started before now stay at their times; nothing
            // else starts before now.
            let mut past: Vec<(String, f64)> = old
                .primitive()
                .filter(|s| s.start < now)
                .map(|s| (format!("({} {})", s.name, s.args.join(" ")), s.start))
                .collect();
            for s in plan.primitive() {
                let call = format!("({} {})", s.name, s.args.join(" "));
                match past.iter().position(|(c, t)| *c == call && (t - s.start).abs() < 1e-6) {
                    Some(i) => {
                        past.remove(i);
                    }
                    None if s.start < now - 1e-6 => {
                        return Err(format!(
                            "{call} starts at {} before now:\n{}{}",
                            s.start,
                            plan.to_val(""),
                            context()
                        ));
                    }
                    None => {}
                }
            }
            if !past.is_empty() {
                return Err(format!("executed steps lost: {past:?}\n{}{}", plan.to_val(""), context()));
            }
        }
        if matches!(event, Event::Nothing) {
            // Only steps that supported nothing (as the old schedule links
            // them) may go; nothing is added.
            let calls = |p: &hipop_analyzer::planner::output::SolvedPlan| {
                let mut v: Vec<String> =
                    p.primitive().map(|s| format!("({} {})", s.name, s.args.join(" "))).collect();
                v.sort();
                v
            };
            let mut left = calls(&old);
            let added = calls(plan).into_iter().filter(|c| match left.iter().position(|x| x == c) {
                Some(i) => {
                    left.remove(i);
                    false
                }
                None => true,
            });
            let idle = |w: &Why| matches!(w, Why::SupportsNothing | Why::UnderRemoved | Why::Unrefined);
            if result.stage != Some(Stage::Obsolete)
                || !result.removed.iter().all(|r| idle(&r.why))
                || added.count() > 0
                || left.len() > result.removed.len()
            {
                return Err(format!(
                    "repaired for its own problem, the plan changed ({:?}, removed {:?}):\n{}{}",
                    result.stage,
                    result.removed,
                    plan.to_val(""),
                    context()
                ));
            }
        }
        counts.repaired += 1;
        let stage = result.stage.map_or("?".to_string(), |s| s.describe());
        match counts.by_stage.iter_mut().find(|(s, _)| *s == stage) {
            Some(c) => c.1 += 1,
            None => counts.by_stage.push((stage, 1)),
        }
        if now.is_some() {
            counts.executed += 1;
        }
        return Ok(());
    }
    if result.status == Status::Solved {
        return Err("solved without a plan".into());
    }
    if now.is_some() {
        counts.executed += 1;
        return Ok(());
    }
    // No repaired plan: the planner finds none either.
    let replanned = host
        .analysis()
        .run_planner(new_file, &config, &limits(), &|| false, &mut |_| {})
        .expect("not cancelled")
        .expect("a problem");
    match replanned.status {
        Status::Solved => Err(format!(
            "the planner finds a plan, the repair ends with {:?} (stages {:?}):\n{}{}",
            result.status,
            result.stages.iter().map(|s| (s.stage, s.status.clone())).collect::<Vec<_>>(),
            show(&host, &result.diagnostics),
            context()
        )),
        Status::Limit(_) => {
            counts.planner_limit += 1;
            Ok(())
        }
        Status::Refused => {
            counts.refused += 1;
            Ok(())
        }
        Status::NoPlan => {
            counts.no_plan_both += 1;
            Ok(())
        }
    }
}

fn runner() -> TestRunner {
    let cases = std::env::var("HIPOP_REPAIR_PROPS_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(200);
    let seed: u64 = std::env::var("HIPOP_REPAIR_PROPS_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x0000_5245_5041_4952);
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let config =
        RunnerConfig { cases, failure_persistence: None, max_shrink_iters: 1000, ..RunnerConfig::default() };
    TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &bytes))
}

#[test]
fn random_events_repaired_into_valid_plans() {
    let counts = RefCell::new(Counts::default());
    let result = runner().run(&(problem(), raw_event()), |(p, e)| {
        check(&p, &e, &mut counts.borrow_mut()).map_err(TestCaseError::fail)
    });
    let c = counts.into_inner();
    eprintln!(
        "cases {}, old problem unsolved {}, repaired {} (partly executed {}), no plan for the repair nor the planner {}, \
         planner limits {}, refused {}",
        c.cases, c.old_unsolved, c.repaired, c.executed, c.no_plan_both, c.planner_limit, c.refused
    );
    for (stage, n) in &c.by_stage {
        eprintln!("  found by {stage}: {n}");
    }
    if let Err(e) = result {
        panic!("{e}");
    }
    assert!(c.repaired * 2 >= c.cases - c.old_unsolved, "most events are repaired: {c:?}");
}
