//! Plan repair (section 5 of the HiPOP paper): a plan repaired for the
//! problem it solves comes back unchanged; steps the new problem cannot
//! have are removed; the repaired plans are valid.

use std::path::Path;

use hipop_analyzer::planner::output::SolvedPlan;
use hipop_analyzer::planner::{Config, PlannerLimits, Status};
use hipop_analyzer::repair::{RepairOptions, Stage, Why};
use hipop_analyzer::{AnalysisHost, RepairResult};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(root().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// Plans `problem`, then repairs that plan for `new_problem` (the same
/// problem when `None`): the old plan's primitive steps, the repair and the
/// repaired plan's validation errors.
fn plan_then_repair(
    domain: &str,
    problem: &str,
    new_problem: Option<&str>,
    options: &RepairOptions,
) -> (Vec<String>, RepairResult, Vec<String>) {
    let (old, result, errors) = plan_then_repair_plan(domain, problem, new_problem, options);
    let old_steps = old.primitive().map(|s| format!("({} {})", s.name, s.args.join(" "))).collect();
    (old_steps, result, errors)
}

/// [`plan_then_repair`], with the old plan itself.
fn plan_then_repair_plan(
    domain: &str,
    problem: &str,
    new_problem: Option<&str>,
    options: &RepairOptions,
) -> (SolvedPlan, RepairResult, Vec<String>) {
    let mut host = AnalysisHost::new();
    host.set_file_text("domain.pddl", domain.to_string());
    let p = host.set_file_text("problem.pddl", problem.to_string());
    let limits = PlannerLimits { time: Some(std::time::Duration::from_secs(30)), ..PlannerLimits::default() };
    let config = Config::default();
    let planned = host.analysis().run_planner(p, &config, &limits, &|| false, &mut |_| {}).unwrap().unwrap();
    assert_eq!(planned.status, Status::Solved);
    let old = planned.plan.unwrap();
    let text = if old.is_hierarchical() { old.to_hierarchical("") } else { old.to_val("") };
    let np = match new_problem {
        Some(t) => host.set_file_text("new-problem.pddl", t.to_string()),
        None => p,
    };
    let f = host.set_file_text("old.plan", text);
    let result = host
        .analysis()
        .run_repair(np, f, None, &config, &limits, options, &|| false, &mut |_| {})
        .unwrap()
        .unwrap();
    let mut errors = Vec::new();
    if let Some(plan) = &result.plan {
        let text = if plan.is_hierarchical() { plan.to_hierarchical("") } else { plan.to_val("") };
        let r = host.set_file_text("repaired.plan", text);
        let v = host.analysis().validate_plan(r, None, np, &Default::default()).unwrap().unwrap();
        errors = v
            .diagnostics
            .iter()
            .filter(|d| d.severity == hipop_analyzer::Severity::Error)
            .map(|d| format!("{} {}", d.code.id, d.message))
            .collect();
    }
    (old, result, errors)
}

fn primitive(result: &RepairResult) -> Vec<String> {
    let plan = result.plan.as_ref().expect("a plan");
    plan.primitive().map(|s| format!("({} {})", s.name, s.args.join(" "))).collect()
}

fn sorted(mut v: Vec<String>) -> Vec<String> {
    v.sort();
    v
}

#[test]
fn a_plan_repaired_for_its_own_problem_comes_back_unchanged() {
    for dir in ["samples/surveillance", "samples/satellite-abstract"] {
        let domain = read(&format!("{dir}/domain.pddl"));
        let problem_file = if dir.ends_with("surveillance") { "problem.pddl" } else { "instance-1.pddl" };
        let problem = read(&format!("{dir}/{problem_file}"));
        let (old, result, errors) = plan_then_repair(&domain, &problem, None, &RepairOptions::default());
        assert_eq!(result.status, Status::Solved, "{dir}");
        assert_eq!(result.stage, Some(Stage::Obsolete), "{dir}");
        assert!(result.removed.is_empty(), "{dir}: {:?}", result.removed);
        assert_eq!(sorted(primitive(&result)), sorted(old), "{dir}: instability 0");
        assert!(errors.is_empty(), "{dir}: {errors:?}");
    }
}

fn satellite() -> (String, String) {
    (read("samples/satellite-abstract/domain.pddl"), read("samples/satellite-abstract/instance-1.pddl"))
}

/// A new goal (a new survivor, in the paper's words): the old steps stay,
/// steps are added for it, in stage 1.
#[test]
fn a_new_goal_keeps_the_old_steps() {
    let (domain, problem) = satellite();
    let new = problem.replace(
        "(have_image Phenomenon6 thermograph0)",
        "(have_image Phenomenon6 thermograph0)\n\t(have_image Star0 thermograph0)",
    );
    assert_ne!(new, problem);
    let (old, result, errors) = plan_then_repair(&domain, &problem, Some(&new), &RepairOptions::default());
    assert_eq!(result.status, Status::Solved);
    assert_eq!(result.stage, Some(Stage::Obsolete));
    assert!(result.removed.is_empty(), "{:?}", result.removed);
    let mut repaired = primitive(&result);
    for step in &old {
        let k =
            repaired.iter().position(|s| s == step).unwrap_or_else(|| panic!("{step} kept: {repaired:?}"));
        repaired.remove(k);
    }
    assert!(repaired.iter().any(|s| s.contains("Star0")), "added for the new goal: {repaired:?}");
    assert!(errors.is_empty(), "{errors:?}");
}

/// The primitive steps of a plan with their start times.
fn timed(plan: &SolvedPlan) -> Vec<String> {
    sorted(plan.primitive().map(|s| format!("{:.3} ({} {})", s.start, s.name, s.args.join(" "))).collect())
}

fn survivors(event: &str) -> (String, String, String) {
    let dir = "samples/survivors/repair";
    (
        read(&format!("{dir}/domain.pddl")),
        read(&format!("{dir}/p-t2-r2-z4-s2.pddl")),
        read(&format!("{dir}/p-t2-r2-z4-s2-{event}.pddl")),
    )
}

/// With geometric reasoning, the robots' itineraries are replayed from the
/// old plan: a new survivor (the paper's newSurvivor event) is rescued once
/// its team's old work is done, and every old action keeps its time. Before,
/// the itineraries were planned again from the start and the rescue went in
/// the middle, delaying every later action of its team.
#[test]
fn a_new_survivor_is_rescued_after_the_old_work_which_keeps_its_times() {
    let (domain, problem, new) = survivors("newSurvivor");
    let (old, result, errors) =
        plan_then_repair_plan(&domain, &problem, Some(&new), &RepairOptions::default());
    assert_eq!(result.status, Status::Solved);
    assert_eq!(result.stage, Some(Stage::Obsolete));
    assert!(result.removed.is_empty(), "{:?}", result.removed);
    let old_timed = timed(&old);
    let mut repaired = timed(result.plan.as_ref().expect("a plan"));
    for step in &old_timed {
        let k = repaired
            .iter()
            .position(|s| s == step)
            .unwrap_or_else(|| panic!("{step} at its time: {repaired:?}"));
        repaired.remove(k);
    }
    assert!(repaired.iter().any(|s| s.contains("s3")), "added for the new survivor: {repaired:?}");
    // Every step for s3 starts once its robots' old steps have ended.
    for s in result.plan.as_ref().expect("a plan").primitive().filter(|s| s.args.iter().any(|a| a == "s3")) {
        let team_end = old
            .primitive()
            .filter(|o| o.agents.iter().any(|a| s.agents.contains(a)))
            .map(|o| o.end)
            .fold(0.0, f64::max);
        assert!(
            s.start >= team_end,
            "({} {}) starts at {}, before {team_end}",
            s.name,
            s.args.join(" "),
            s.start
        );
    }
    assert!(errors.is_empty(), "{errors:?}");
}

/// A robot that starts elsewhere (startingPos): its old moves up to its
/// first visit leave from where it is not, and are rerouted: the replay of
/// its itinerary goes from where it is to its first old visit by the
/// shortest route, then on through its old visits; the other team's
/// itineraries are replayed whole, their actions at their old times.
#[test]
fn a_robot_that_starts_elsewhere_leaves_the_other_team_as_it_was() {
    let (domain, problem, new) = survivors("startingPos");
    assert!(new.contains("robot r4 starts at l1_3"), "the event of the sample");
    let (old, result, errors) =
        plan_then_repair_plan(&domain, &problem, Some(&new), &RepairOptions::default());
    assert_eq!(result.status, Status::Solved);
    assert_eq!(result.stage, Some(Stage::Obsolete));
    let plan = result.plan.as_ref().expect("a plan");
    let team = |p: &SolvedPlan, robot: &str| -> Vec<String> {
        sorted(
            p.primitive()
                .filter(|s| s.agents.iter().any(|a| a == robot))
                .map(|s| format!("{:.3} ({} {})", s.start, s.name, s.args.join(" ")))
                .collect(),
        )
    };
    // r4's teammate is the robot it carries with; the others are r1 and r2
    // or r3, whichever is not on its team.
    let others: Vec<&str> = ["r1", "r2", "r3"]
        .into_iter()
        .filter(|r| {
            !old.primitive().any(|s| s.agents.iter().any(|a| a == "r4") && s.agents.iter().any(|a| a == r))
        })
        .collect();
    assert!(!others.is_empty(), "a team without r4");
    for r in others {
        assert_eq!(team(plan, r), team(&old, r), "{r} keeps its actions and times");
    }
    assert!(
        plan.primitive().any(|s| s.name == "move" && s.args[0] == "r4" && s.args[1] == "l1_3"),
        "r4 leaves l1_3"
    );
    // r4's old moves up to its first visit leave from where it no longer
    // is: they are rerouted, and nothing else is removed.
    assert!(!result.removed.is_empty());
    for r in &result.removed {
        let call = &result.old[r.step].call;
        assert_eq!(r.why, Why::Rerouted, "{call}");
        assert!(call.starts_with("(move r4 "), "{call}");
    }
    assert!(errors.is_empty(), "{errors:?}");
}

/// A goal dropped: the abstract step that achieved it supports nothing any
/// more and is removed with its subtasks; the rest stays.
#[test]
fn a_step_that_supports_nothing_is_removed() {
    let (domain, problem) = satellite();
    let new = problem.replace("(have_image Star5 thermograph0)", "");
    let (old, result, errors) = plan_then_repair(&domain, &problem, Some(&new), &RepairOptions::default());
    assert_eq!(result.status, Status::Solved);
    assert_eq!(result.stage, Some(Stage::Obsolete));
    let removed: Vec<(&str, Why)> =
        result.removed.iter().map(|r| (result.old[r.step].call.as_str(), r.why)).collect();
    assert!(
        removed.iter().any(
            |(call, why)| call.starts_with("(get_image satellite0 Star5") && *why == Why::SupportsNothing
        ),
        "{removed:?}"
    );
    assert!(
        removed
            .iter()
            .any(|(call, why)| call.starts_with("(take_image satellite0 Star5") && *why == Why::UnderRemoved)
    );
    let repaired = primitive(&result);
    assert!(!repaired.iter().any(|s| s.contains("take_image satellite0 Star5")), "{repaired:?}");
    assert!(repaired.len() < old.len());
    assert!(errors.is_empty(), "{errors:?}");
}

/// An action no longer allowed: its top-level steps are obsolete; without
/// it the goals cannot be reached, even by the full replan: no plan.
#[test]
fn obsolete_steps_are_removed_and_no_plan_is_a_verdict() {
    let (domain, problem) = satellite();
    let new = problem.replace("calibrate_instrument get_image)", "calibrate_instrument)");
    assert_ne!(new, problem);
    let (_, result, _) = plan_then_repair(&domain, &problem, Some(&new), &RepairOptions::default());
    assert_eq!(result.status, Status::NoPlan);
    assert!(result.plan.is_none());
    let why: Vec<Why> = result.removed.iter().filter(|r| r.stage == Stage::Obsolete).map(|r| r.why).collect();
    assert!(why.contains(&Why::NotAllowed), "{why:?}");
    assert_eq!(result.stages.last().map(|s| s.stage), Some(Stage::Replan));
}

/// repairFlat: the hierarchy is discarded, the primitive steps stay.
#[test]
fn repair_flat_discards_the_hierarchy() {
    let (domain, problem) = satellite();
    let options = RepairOptions { flat: true, ..RepairOptions::default() };
    let (_, result, errors) = plan_then_repair(&domain, &problem, None, &options);
    assert_eq!(result.status, Status::Solved);
    assert!(
        result.removed.iter().all(|r| r.why == Why::Flat || r.stage != Stage::Obsolete),
        "{:?}",
        result.removed
    );
    assert!(result.removed.iter().any(|r| r.why == Why::Flat));
    assert!(errors.is_empty(), "{errors:?}");
}

/// A meeting that cannot be kept any more (its window closes too early) is
/// dropped as a goal once the repair and the full replan fail (section 5.5);
/// the observations stay.
#[test]
fn a_meeting_that_cannot_be_kept_is_dropped() {
    let dir = "tests/repair/dropped-meeting";
    let domain = read(&format!("{dir}/domain.pddl"));
    let options = RepairOptions {
        execution: hipop_analyzer::repair::Execution { unreachable: vec!["r2".into()], ..Default::default() },
        ..RepairOptions::default()
    };
    let (old, result, errors) = plan_then_repair(
        &domain,
        &read(&format!("{dir}/problem.pddl")),
        Some(&read(&format!("{dir}/new-problem.pddl"))),
        &options,
    );
    assert_eq!(result.status, Status::Solved, "{:?}", result.stages);
    assert_eq!(
        result.dropped,
        [hipop_analyzer::repair::DroppedGoal { goal: "(met r1 r2)".into(), unreachable: true }]
    );
    // The first attempt (stage 1 and the replan) had the meeting; the second not.
    assert!(result.stages.iter().any(|s| s.stage == Stage::Replan && s.status == Status::NoPlan));
    assert_eq!(result.stages.last().map(|s| s.goals), Some(2));
    let repaired = primitive(&result);
    assert!(!repaired.iter().any(|s| s.starts_with("(communicate")), "{repaired:?}");
    assert!(
        repaired.iter().any(|s| s == "(observe r1 a p1)")
            && repaired.iter().any(|s| s == "(observe r2 d p2)")
    );
    assert!(old.iter().any(|s| s.starts_with("(communicate")));
    // The repaired plan reaches the goals that are left; the new problem
    // still asks for the meeting, so its validation reports that goal only.
    assert!(errors.iter().all(|e| e.contains("met")), "{errors:?}");
}

/// A step executed at time 0 happens after the initial state, as VAL has
/// it: what it deletes there no longer holds for the goal. Fixing it at 0
/// put it at or before the origin, where its deletion threatened nothing,
/// and the repair returned the old plan, which misses a goal (found by
/// `repair_props`).
#[test]
fn a_step_executed_at_time_zero_comes_after_the_initial_state() {
    let text = "(define (domain d) (:requirements :strips :negative-preconditions :durative-actions)
           (:predicates (p1))
           (:action a0 :parameters () :precondition (and) :effect (not (p1)))
           (:durative-action a1 :parameters () :duration (= ?duration 1)
             :condition (and) :effect (at start (p1))))
         (define (problem pr) (:domain d) (:init (p1)) (:goal (and (not (p1)) (p1))))";
    let mut host = AnalysisHost::new();
    let p = host.set_file_text("problem.pddl", text.to_string());
    let old = host.set_file_text("old.plan", "0: (a0)\n".to_string());
    let limits = PlannerLimits { time: Some(std::time::Duration::from_secs(30)), ..PlannerLimits::default() };
    let options = RepairOptions {
        execution: hipop_analyzer::repair::Execution { now: Some(0.0), ..Default::default() },
        ..RepairOptions::default()
    };
    let result = host
        .analysis()
        .run_repair(p, old, None, &Config::default(), &limits, &options, &|| false, &mut |_| {})
        .unwrap()
        .unwrap();
    assert_eq!(result.status, Status::NoPlan, "{:?}", result.plan.map(|p| p.to_val("")));
}

/// The lost-robot fixture: r1 moves to b and patrols; its sensor fails at
/// 5 s, during its move (`new-problem.pddl`: its `visible` facts end then).
fn lost_robot(
    problem_edit: &dyn Fn(&str) -> String,
    options: &RepairOptions,
) -> (Vec<String>, RepairResult, Vec<String>) {
    let dir = "tests/repair/lost-robot";
    plan_then_repair(
        &read(&format!("{dir}/domain.pddl")),
        &problem_edit(&read(&format!("{dir}/problem.pddl"))),
        Some(&problem_edit(&read(&format!("{dir}/new-problem.pddl")))),
        options,
    )
}

fn at(now: f64, unreachable: &[&str]) -> RepairOptions {
    RepairOptions {
        execution: hipop_analyzer::repair::Execution {
            now: Some(now),
            unreachable: unreachable.iter().map(|s| s.to_string()).collect(),
            ..Default::default()
        },
        ..RepairOptions::default()
    }
}

/// A step whose condition only the initial state and timed literals give,
/// and which no longer holds from now on (r1's sensor is out of service),
/// is obsolete: stage 1 removes it and repairs from the rest. Before, the
/// start plan with it was inconsistent, no step was removed, and the repair
/// went to the full replan.
#[test]
fn a_step_whose_condition_never_holds_again_is_obsolete() {
    // Without the patrol: r1 moves to c and observes p2 itself.
    let flat = |t: &str| t.replace("(:allowed-actions move patrol)", "(:allowed-actions move observe)");
    let (old, result, errors) = lost_robot(&flat, &at(5.0, &[]));
    assert!(old.contains(&"(observe r1 c p2)".to_string()), "{old:?}");
    assert_eq!(result.status, Status::Solved, "{:?}", result.stages);
    assert_eq!(result.stage, Some(Stage::Obsolete), "{:?}", result.stages);
    let gone: Vec<&str> = result
        .removed
        .iter()
        .filter(|r| r.why == Why::ConditionGone)
        .map(|r| result.old[r.step].call.as_str())
        .collect();
    assert_eq!(gone, ["(observe r1 c p2)"]);
    assert!(
        primitive(&result)
            .iter()
            .any(|s| s.starts_with("(observe r2 c p2)") || s.starts_with("(observe r3 c p2)"))
    );
    assert!(errors.is_empty(), "{errors:?}");
}

/// The patrol whose observation is obsolete is un-refined (5.1.1); it cannot
/// be refined again for r1, so the next ring removes it (its effects came
/// from the subtasks removed) and another robot patrols. Before, the rings
/// never removed an un-refined abstract step and the repair went to the
/// full replan.
#[test]
fn an_abstract_step_that_lost_its_subtasks_is_removed_by_the_next_ring() {
    let (_, result, errors) = lost_robot(&|t: &str| t.to_string(), &at(5.0, &[]));
    assert_eq!(result.status, Status::Solved, "{:?}", result.stages);
    assert_eq!(result.stage, Some(Stage::Ring(1)), "{:?}", result.stages);
    let patrol =
        result.removed.iter().find(|r| result.old[r.step].call == "(patrol r1)").expect("the patrol goes");
    assert_eq!(patrol.why, Why::Ring(1));
    assert!(primitive(&result).iter().any(|s| s == "(observe r2 c p2)"), "{:?}", primitive(&result));
    assert!(errors.is_empty(), "{errors:?}");
}

/// A patrol half executed when r1's sensor fails at 17 s, during its move
/// from b to c: it observed p1, its observation of p2 can no longer
/// happen. Section 5.3: the patrol goes, what ran stays, and every action
/// may finish its work (𝒜 = A, where `observe` is not allowed): another
/// robot goes to c and observes p2, not an unreachable one. Before, the
/// patrol stayed (it is being executed), could not be refined again, and
/// there was no plan, even after the full replan.
#[test]
fn a_half_executed_patrol_is_finished_by_any_action() {
    let mid = |t: &str| {
        t.replace(
            "(at 5 (not (visible r1 b p1))) (at 5 (not (visible r1 c p2)))",
            "(at 17 (not (visible r1 c p2)))",
        )
    };
    assert!(mid(&read("tests/repair/lost-robot/new-problem.pddl")).contains("(at 17 "));
    for (unreachable, finisher) in [(&[][..], "(observe r2 c p2)"), (&["r2"][..], "(observe r3 c p2)")] {
        let (old, result, errors) = lost_robot(&mid, &at(17.0, unreachable));
        assert_eq!(result.status, Status::Solved, "{:?}", result.stages);
        assert_eq!(result.stage, Some(Stage::Obsolete), "{:?}", result.stages);
        let why: Vec<(&str, Why)> =
            result.removed.iter().map(|r| (result.old[r.step].call.as_str(), r.why)).collect();
        assert!(why.contains(&("(patrol r1)", Why::HalfExecuted)), "{why:?}");
        assert!(why.contains(&("(observe r1 c p2)", Why::ConditionGone)), "{why:?}");
        let steps = primitive(&result);
        for ran in ["(move r1 a b)", "(observe r1 b p1)", "(move r1 b c)"] {
            assert!(old.contains(&ran.to_string()) && steps.contains(&ran.to_string()), "{ran}: {steps:?}");
        }
        assert!(steps.contains(&finisher.to_string()), "{steps:?}");
        assert!(errors.is_empty(), "{errors:?}");
    }
}

/// Nothing new starts before now (5.3: the past is executed). Before, r2's
/// moves to b were scheduled from 0, in the past of a plan executed up to
/// 5 s; steps that started before now stay where they were.
#[test]
fn nothing_new_starts_before_now() {
    let (_, result, errors) = lost_robot(&|t: &str| t.to_string(), &at(5.0, &[]));
    assert_eq!(result.status, Status::Solved, "{:?}", result.stages);
    assert!(errors.is_empty(), "{errors:?}");
    let plan = result.plan.as_ref().unwrap();
    assert!(
        plan.steps.iter().any(|s| s.name == "move" && s.args[0] == "r1" && s.start < 5.0),
        "r1's move ran"
    );
    let new: Vec<String> = plan
        .steps
        .iter()
        .filter(|s| s.args.first().is_some_and(|a| a != "r1"))
        .map(|s| format!("{} {} at {}", s.name, s.args.join(" "), s.start))
        .collect();
    assert!(!new.is_empty());
    for s in plan.steps.iter().filter(|s| s.args.first().is_some_and(|a| a != "r1")) {
        assert!(s.start >= 5.0, "a step added before now: {new:?}");
    }
}

/// An unreachable agent's plan does not change (5.4): no step of r2 is
/// added, r3 patrols instead. Before, r2 (the first idle robot) was given
/// the patrol.
#[test]
fn no_step_is_added_to_an_unreachable_agent() {
    let (_, free, _) = lost_robot(&|t: &str| t.to_string(), &at(5.0, &[]));
    assert!(primitive(&free).iter().any(|s| s.contains(" r2 ")), "r2 is the robot chosen when reachable");
    let (_, result, errors) = lost_robot(&|t: &str| t.to_string(), &at(5.0, &["r2"]));
    assert_eq!(result.status, Status::Solved, "{:?}", result.stages);
    let steps = primitive(&result);
    assert!(!steps.iter().any(|s| s.contains(" r2 ")), "{steps:?}");
    assert!(steps.iter().any(|s| s == "(observe r3 c p2)"), "{steps:?}");
    assert!(errors.is_empty(), "{errors:?}");
}

/// The relay (section 5.2's survivorPos at a small scale): r1 lifted the
/// crate where it was reported and r2 hauled it on. The crate is found one
/// place further: the lift is obsolete, and r2's haul, which the lift
/// supported (the crate held), is in the first ring: another robot's step,
/// linked to the obsolete one by the links rebuilt by name.
#[test]
fn the_first_ring_holds_another_robots_step_that_an_obsolete_step_supported() {
    let dir = "tests/repair/relay";
    let (old, result, errors) = plan_then_repair(
        &read(&format!("{dir}/domain.pddl")),
        &read(&format!("{dir}/problem.pddl")),
        Some(&read(&format!("{dir}/new-problem.pddl"))),
        &RepairOptions::default(),
    );
    assert!(
        old.contains(&"(lift r1 k b c)".to_string()) && old.contains(&"(haul r2 k c d)".to_string()),
        "{old:?}"
    );
    assert_eq!(result.status, Status::Solved, "{:?}", result.stages);
    assert_eq!(result.stage, Some(Stage::Ring(1)), "{:?}", result.stages);
    let haul =
        result.removed.iter().find(|r| result.old[r.step].call == "(haul r2 k c d)").expect("the haul goes");
    assert_eq!(haul.why, Why::Ring(1));
    assert!(primitive(&result).contains(&"(lift r1 k c d)".to_string()), "{:?}", primitive(&result));
    assert!(errors.is_empty(), "{errors:?}");
}

/// A start plan links a condition to the producer the old schedule had
/// only when nothing undid it in between: with the old plan's second move
/// to b removed, the move from b to c is not linked to the first one (the
/// robot left b in between), its position stays open, and the start plan
/// is consistent. Before, the link to the first move was threatened by the
/// move back to a, both ways, and no start plan was built (the repair then
/// learnt nothing of the old plan's order).
#[test]
fn a_start_plan_does_not_link_across_a_step_that_undid_the_condition() {
    use hipop_analyzer::planner::search::{Search, Seed, SeedStep};
    use hipop_analyzer::planner::{Motion, prepare};
    let domain = "(define (domain shuttle)
      (:requirements :typing :durative-actions)
      (:types robot place)
      (:predicates (at-r ?r - robot ?p - place) (adjacent ?a ?b - place) (scanned ?p - place))
      (:durative-action move
        :parameters (?r - robot ?from ?to - place)
        :duration (= ?duration 10)
        :condition (and (at start (at-r ?r ?from)) (over all (adjacent ?from ?to)))
        :effect (and (at start (not (at-r ?r ?from))) (at end (at-r ?r ?to))))
      (:durative-action scan
        :parameters (?r - robot ?p - place)
        :duration (= ?duration 5)
        :condition (and (at start (at-r ?r ?p)) (over all (at-r ?r ?p)))
        :effect (at end (scanned ?p))))";
    let problem = "(define (problem shuttle-1) (:domain shuttle)
      (:objects r - robot a b c - place)
      (:init (at-r r a) (adjacent a b) (adjacent b a) (adjacent b c) (adjacent c b))
      (:goal (and (scanned b) (scanned c))))";
    let mut host = AnalysisHost::new();
    host.set_file_text("shuttle-domain.pddl", domain.to_string());
    let pf = host.set_file_text("shuttle.pddl", problem.to_string());
    let db = host.db();
    let unit = hipop_analyzer::db::file_units(db, pf)[0];
    let config = Config { motion: Motion::Off, ..Config::default() };
    let prepared = prepare(db, unit, &config, &PlannerLimits::default()).ok().expect("a task");
    let task = &prepared.task;
    let op = |call: &str| -> u32 {
        let words: Vec<&str> = call.split_whitespace().collect();
        (0..task.ops.len() as u32)
            .find(|&i| {
                let o = &task.ops[i as usize];
                o.name.as_str() == words[0]
                    && o.args.iter().map(|&a| task.g.objects.name(a)).eq(words[1..].iter().copied())
            })
            .unwrap_or_else(|| panic!("{call}"))
    };
    // The old plan: a→b, scan b, b→a, [a→b, removed], b→c, scan c.
    let step = |call: &str, start: f64, end: f64| SeedStep {
        op: op(call),
        parent: None,
        method: None,
        start,
        end,
        fixed: false,
        done: false,
    };
    let seed = Seed {
        steps: vec![
            step("move r a b", 0.0, 10.0),
            step("scan r b", 10.01, 15.01),
            step("move r b a", 15.02, 25.02),
            step("move r b c", 35.04, 45.04),
            step("scan r c", 45.05, 50.05),
        ],
        ..Seed::default()
    };
    let search = Search::new(task, &prepared.h, &config);
    let plans = search.seeded(&seed).expect("a consistent start plan");
    let (plan, of_seed) = &plans[0];
    let plan_step = |k: usize| of_seed.iter().position(|&s| s == Some(k)).expect("in the plan") as u32;
    let (first, to_c) = (plan_step(0), plan_step(3));
    assert!(
        !plan.links.iter().any(|l| l.from == first && l.to == to_c),
        "the move from b to c is linked to the first move to b"
    );
    assert!(plan.open.iter().any(|o| o.step == to_c), "its position stays open");
    // What nothing undid is linked as before: the scan of b to the first move.
    assert!(plan.links.iter().any(|l| l.from == first && l.to == plan_step(1)));
}

/// Repairs the plan text `old` for `new_problem`: the repair and the
/// repaired plan's validation errors.
fn repair_text(domain: &str, new_problem: &str, old: &str) -> (RepairResult, Vec<String>) {
    let mut host = AnalysisHost::new();
    host.set_file_text("domain.pddl", domain.to_string());
    let np = host.set_file_text("new-problem.pddl", new_problem.to_string());
    let f = host.set_file_text("old.plan", old.to_string());
    let limits = PlannerLimits { time: Some(std::time::Duration::from_secs(30)), ..PlannerLimits::default() };
    let options = RepairOptions::default();
    let result = host.analysis().run_repair(
        np,
        f,
        None,
        &Config::default(),
        &limits,
        &options,
        &|| false,
        &mut |_| {},
    );
    let result = result.unwrap().unwrap();
    let plan = result.plan.as_ref().expect("a plan");
    let r = host.set_file_text("repaired.plan", plan.to_val(""));
    let v = host.analysis().validate_plan(r, None, np, &Default::default()).unwrap().unwrap();
    let errors = v
        .diagnostics
        .iter()
        .filter(|d| d.severity == hipop_analyzer::Severity::Error)
        .map(|d| format!("{} {}", d.code.id, d.message))
        .collect();
    (result, errors)
}

/// What stays of the old plan keeps its old times where that delays the
/// end no further than the old steps ended: the photograph of z1 is no
/// longer needed, and the earliest schedule would drill and photograph z3
/// 3.01 s earlier than the team expects. Under a deadline (quiet ends at
/// 10 s, and the photograph needs it all along) the old times cannot be
/// kept, and both steps come as early as they can.
#[test]
fn the_steps_kept_keep_their_old_times_unless_a_deadline_forbids_it() {
    let dir = "tests/repair/phantom-link-keeps-order";
    let domain = read(&format!("{dir}/domain.pddl"));
    let problem = read(&format!("{dir}/new-problem.pddl"));
    let old = read(&format!("{dir}/old.plan"));
    let (result, errors) = repair_text(&domain, &problem, &old);
    assert!(errors.is_empty(), "{errors:?}");
    let plan = result.plan.as_ref().unwrap();
    assert_eq!(timed(plan), ["0.000 (set-up c1)", "5.020 (drill z2)", "9.030 (photograph c1 z3)"]);
    let deadline = problem.replace("(:init (quiet))", "(:init (quiet) (at 10 (not (quiet))))");
    assert!(deadline.contains("(at 10 "));
    let (result, errors) = repair_text(&domain, &deadline, &old);
    assert!(errors.is_empty(), "{errors:?}");
    let plan = result.plan.as_ref().unwrap();
    assert_eq!(timed(plan), ["0.000 (set-up c1)", "2.010 (drill z2)", "6.020 (photograph c1 z3)"]);
}

/// An executed step the goal does not need stays: the planner grounds only
/// what the goal may need, but a repair grounds every reachable instance,
/// so the old plan's steps keep theirs. With goal relevance, `(wander a)`
/// had no instance and was removed as obsolete, executed or not.
#[test]
fn an_executed_step_the_goal_does_not_need_stays() {
    let text = "(define (domain d) (:requirements :strips)
           (:predicates (walked ?x) (done))
           (:action wander :parameters (?x) :precondition (and) :effect (walked ?x))
           (:action finish :parameters () :precondition (and) :effect (done)))
         (define (problem pr) (:domain d) (:objects a) (:init) (:goal (done)))";
    let mut host = AnalysisHost::new();
    let p = host.set_file_text("problem.pddl", text.to_string());
    let old = host.set_file_text("old.plan", "0: (wander a)\n0.5: (finish)\n".to_string());
    let limits = PlannerLimits { time: Some(std::time::Duration::from_secs(30)), ..PlannerLimits::default() };
    let options = RepairOptions {
        execution: hipop_analyzer::repair::Execution { now: Some(0.2), ..Default::default() },
        ..RepairOptions::default()
    };
    let result = host
        .analysis()
        .run_repair(p, old, None, &Config::default(), &limits, &options, &|| false, &mut |_| {})
        .unwrap()
        .unwrap();
    assert_eq!(result.status, Status::Solved, "{:?}", result.stages);
    assert!(result.removed.iter().all(|r| r.why != Why::NoOperator), "{:?}", result.removed);
    assert!(primitive(&result).contains(&"(wander a)".to_string()), "{:?}", primitive(&result));
}
