use std::path::Path;

use crate::AnalysisHost;
use crate::planner::{Config, PlannerLimits};

use super::*;

/// Loads a sample's domain and problem; returns the problem's file.
fn load(host: &mut AnalysisHost, dir: &str, domain: &str, problem: &str) -> (SourceFile, SourceFile) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(dir);
    let read = |name: &str| std::fs::read_to_string(root.join(name)).expect("a sample");
    let d = host.set_file_text(&format!("/{dir}/{domain}"), read(domain));
    let p = host.set_file_text(&format!("/{dir}/{problem}"), read(problem));
    (d, p)
}

fn run(host: &AnalysisHost, problem: SourceFile) -> PlanRun {
    let limits = PlannerLimits { time: Some(std::time::Duration::from_secs(60)), ..PlannerLimits::default() };
    let config = Config::parse(Config::DEFAULT).expect("the default configuration");
    let r = host.analysis().run_planner(problem, &config, &limits, &|| false, &mut |_| {}).unwrap().unwrap();
    r.into_run(limits.time).0
}

/// The hints as `line:col label`, the figures that vary (time) masked.
fn shown(host: &AnalysisHost, file: SourceFile, run: &PlanRun) -> String {
    let text = host.analysis().file_text(file).unwrap();
    let hints = host.analysis().plan_hints(file, run).unwrap();
    hints
        .iter()
        .map(|h| {
            let at = usize::from(h.offset);
            let line = text[..at].matches('\n').count() + 1;
            let col = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
            let label = match h.kind {
                PlanHintKind::Summary => {
                    h.label.rsplit_once(", ").map_or(h.label.clone(), |(a, _)| a.to_string())
                }
                _ => h.label.clone(),
            };
            format!("{line}:{col} {label}")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn a_plan_shows_a_summary_on_the_problem_line_and_the_achiever_of_each_goal() {
    let mut host = AnalysisHost::new();
    let (_, p) = load(&mut host, "samples/survivors", "domain.pddl", "p-t2-r2-z4-s2.pddl");
    let r = run(&host, p);
    assert_eq!(r.status, Status::Solved);
    let text = host.analysis().file_text(p).unwrap();
    let hints = host.analysis().plan_hints(p, &r).unwrap();
    // The summary ends the `(problem …)` line.
    let first = &hints[0];
    assert_eq!(first.kind, PlanHintKind::Summary);
    let line_start = text.find("(problem").unwrap();
    assert_eq!(usize::from(first.offset), line_start + text[line_start..].find('\n').unwrap());
    assert!(first.label.starts_with("plan: "), "{}", first.label);
    // One hint per goal literal, after its `)`.
    let goals = hints.iter().filter(|h| h.kind == PlanHintKind::Goal).count();
    assert!(goals > 0);
    for h in hints.iter().filter(|h| h.kind == PlanHintKind::Goal) {
        assert_eq!(&text[usize::from(h.offset) - 1..usize::from(h.offset)], ")");
        assert!(h.label.starts_with("← ("), "{}", h.label);
    }
    insta::assert_snapshot!(shown(&host, p, &r));
}

#[test]
fn the_tasks_of_htn_show_their_method_and_span() {
    let mut host = AnalysisHost::new();
    let (_, p) = load(&mut host, "samples/transport-htn", "domain.hddl", "problem.hddl");
    let r = run(&host, p);
    assert_eq!(r.status, Status::Solved);
    let hints = host.analysis().plan_hints(p, &r).unwrap();
    assert!(hints.iter().any(|h| h.kind == PlanHintKind::Task), "{hints:?}");
    insta::assert_snapshot!(shown(&host, p, &r));
}

#[test]
fn a_repair_says_what_each_goal_was_achieved_by_before() {
    let mut host = AnalysisHost::new();
    let (_, p) = load(&mut host, "samples/survivors", "domain.pddl", "p-t2-r2-z4-s2.pddl");
    let first = run(&host, p);
    let old = first.plan.clone().unwrap();
    // Another achiever for every goal: the same plan with every step one
    // unit later reads as a repair that retimed everything.
    let mut later = old.clone();
    for s in &mut later.steps {
        s.start += 1.0;
        s.end += 1.0;
    }
    let repaired = PlanRun {
        plan: Some(later),
        repair: Some(RepairSummary { old, instability: 7, distance: 2 }),
        ..first
    };
    let hints = host.analysis().plan_hints(p, &repaired).unwrap();
    assert!(hints[0].label.starts_with("repaired plan: "), "{}", hints[0].label);
    assert!(hints[0].label.ends_with("; instability 7, distance 2"), "{}", hints[0].label);
    let goals: Vec<&PlanHint> = hints.iter().filter(|h| h.kind == PlanHintKind::Goal).collect();
    assert!(!goals.is_empty());
    for g in goals {
        if !g.label.contains("initial state") {
            assert!(g.label.contains(" (was ("), "{}", g.label);
        }
    }
}

#[test]
fn no_plan_says_which_limit_stopped_the_search() {
    let run = PlanRun {
        status: Status::Limit(LimitKind::Time),
        plan: None,
        stats: Stats::default(),
        time_limit: Some(std::time::Duration::from_secs(5)),
        flaws: 3,
        repair: None,
    };
    assert_eq!(summary(&run), "no plan: time limit (5.00 s) reached, 3 flaws");
    let none = PlanRun { status: Status::NoPlan, flaws: 1, ..run };
    assert_eq!(summary(&none), "no plan exists: 1 flaw in the best partial plan");
}

#[test]
fn hover_tells_how_the_last_plan_uses_an_action_and_an_object() {
    let mut host = AnalysisHost::new();
    let (d, p) = load(&mut host, "samples/survivors", "domain.pddl", "p-t2-r2-z4-s2.pddl");
    let r = run(&host, p);
    let plan = r.plan.as_ref().unwrap();
    let plans = [("p".to_string(), plan)];
    let domain = host.analysis().file_text(d).unwrap();
    let action = plan.steps.iter().find(|s| !s.is_abstract).unwrap();
    let at = domain
        .find(&format!("(:durative-action {}", action.name))
        .or_else(|| domain.find(&format!("(:action {}", action.name)))
        .unwrap();
    let at = at + domain[at..].find(action.name.as_str()).unwrap();
    let said = host.analysis().plan_hover(d, TextSize::from(at as u32), &plans).unwrap().unwrap();
    let count = plan.steps.iter().filter(|s| s.name == action.name).count();
    assert!(said.starts_with(&format!("- {count} step")), "{said}");
    // An object of the problem, as an argument of actions.
    let problem = host.analysis().file_text(p).unwrap();
    let object = &action.args[0];
    let at =
        problem.find(&format!(" {object} ")).or_else(|| problem.find(&format!("{object} "))).unwrap() + 1;
    let said = host.analysis().plan_hover(p, TextSize::from(at as u32), &plans).unwrap().unwrap();
    assert!(said.contains("action") && said.contains("of the last plan of `p`"), "{said}");
    // Nothing on a keyword, nothing without plans.
    assert_eq!(host.analysis().plan_hover(d, TextSize::from(1), &plans).unwrap(), None);
    assert_eq!(host.analysis().plan_hover(d, TextSize::from(at as u32), &[]).unwrap(), None);
}
