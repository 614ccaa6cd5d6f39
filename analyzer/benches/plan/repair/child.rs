//! The child process of a repair run: repairs (or replans) one event's
//! problem from the initial problem's plan, validates the plan it finds,
//! compares it with the old plan as `hipop diff` does, and prints one JSON
//! line.

use std::process::ExitCode;
use std::time::Instant;

use hipop_analyzer::AnalysisHost;
use hipop_analyzer::plan::NameMatching;
use hipop_analyzer::plan::diff::{DiffOptions, diff};
use hipop_analyzer::planner::{Config, Status};
use hipop_analyzer::repair::{Execution, RepairOptions, Stage};
use serde_json::json;

use super::super::child::{validate_into, vm_hwm};
use super::Mode;

/// `--repair MODE DOMAIN PROBLEM OLD_PLAN CONFIG TIME_LIMIT PLAN_PREFIX
/// [--now T] [--unreachable A,B]`.
pub(crate) fn repair_one(raw: &[String]) -> ExitCode {
    let usage =
        "--repair MODE DOMAIN PROBLEM OLD_PLAN CONFIG TIME_LIMIT PLAN_PREFIX [--now T] [--unreachable A,B]";
    let (Some([mode, domain, problem, old, config, limit, prefix]), rest) =
        (raw.get(..7).and_then(|r| <&[String; 7]>::try_from(r).ok()), raw.get(7..).unwrap_or(&[]))
    else {
        eprintln!("{usage}");
        return ExitCode::from(2);
    };
    let mut execution = Execution::default();
    let mut flags = rest.iter();
    while let Some(flag) = flags.next() {
        match (flag.as_str(), flags.next()) {
            ("--now", Some(v)) => execution.now = Some(v.parse().expect("the parent wrote a time")),
            ("--unreachable", Some(v)) => execution.unreachable = v.split(',').map(String::from).collect(),
            _ => {
                eprintln!("{usage}");
                return ExitCode::from(2);
            }
        }
    }
    let mode = Mode::parse(mode).expect("the parent checked the mode");
    let config = Config::parse(config).expect("the parent checked the configuration");
    let limits = crate::child::child_limits(limit);
    let read = crate::child::read;
    let mut host = AnalysisHost::new();
    let df = host.set_file_text(domain, read(domain));
    let pf = host.set_file_text(problem, read(problem));
    let of = host.set_file_text(old, read(old));
    // The old plan is read before the clock starts, as `hipop repair` has
    // it before repairing.
    let old_plan = host.analysis().plan(of, None).expect("nothing cancels");
    let start = Instant::now();
    let mut out = json!({});
    let (status, plan, diagnostics, stats) = match mode {
        Mode::Replan => {
            let r = host
                .analysis()
                .run_planner(pf, &config, &limits, &|| false, &mut |_| {})
                .expect("nothing cancels the planner here")
                .expect("the problem file has a problem");
            (r.status, r.plan, r.diagnostics, r.stats)
        }
        Mode::Repair | Mode::RepairFlat => {
            let options = RepairOptions { flat: mode == Mode::RepairFlat, execution: execution.clone() };
            let r = host
                .analysis()
                .run_repair(pf, of, None, &config, &limits, &options, &|| false, &mut |_| {})
                .expect("nothing cancels the repair here")
                .expect("the problem file has a problem");
            out["stage"] = json!(r.stage.map(stage_name));
            out["stages"] = json!(r.stages.len());
            out["kept"] = json!(r.stages.first().map(|s| s.kept));
            out["removed_steps"] = json!(r.removed.iter().filter(|x| x.stage != Stage::Replan).count());
            out["old_steps"] = json!(r.old.len());
            (r.status, r.plan, r.diagnostics, r.stats)
        }
    };
    let wall = start.elapsed().as_secs_f64();
    out["wall"] = json!(wall);
    out["search"] = json!(stats.elapsed.as_secs_f64());
    out["expanded"] = json!(stats.expanded);
    out["generated"] = json!(stats.generated);
    let first = |code: &str| {
        diagnostics
            .iter()
            .find(|d| d.code.id == code)
            .or(diagnostics.first())
            .map(|d| format!("{} {}", d.code.id, d.message))
            .unwrap_or_default()
    };
    let (status, detail) = match &status {
        Status::Solved => ("solved", String::new()),
        Status::NoPlan => ("no-plan", first("E0502")),
        Status::Limit(k) => ("limit", k.as_str().to_string()),
        Status::Refused => ("refused", first("E0501")),
    };
    out["status"] = json!(status);
    out["detail"] = json!(detail);
    out["old_length"] = json!(old_plan.primitive_steps().count());
    if let Some(plan) = &plan {
        let header = format!("hipop plan bench: {} of {} for {}", mode.name(), old, plan.problem);
        out["makespan"] = json!(plan.makespan);
        out["length"] = json!(plan.primitive().count());
        out["abstract"] = json!(plan.steps.len() - plan.primitive().count());
        let texts = validate_into(&mut out, &mut host, pf, plan, &header, prefix);
        // The stability figures: the old plan against the plan found, read
        // back from the text that keeps the most (the hierarchical one),
        // as `hipop repair` and `hipop diff` compare them.
        let text = texts.last().expect("the VAL text at least").clone();
        let nf = host.set_file_text("new.plan", text);
        let analysis = host.analysis();
        let new_plan = analysis.plan(nf, None).expect("nothing cancels");
        let agents = analysis.plan_agents(df, NameMatching::CaseInsensitive).expect("nothing cancels");
        let d = diff(&old_plan, &new_plan, &agents, &DiffOptions::default());
        out["instability"] = json!(d.instability);
        out["distance"] = json!(d.distance);
        out["removed"] = json!(d.removed.len());
        out["added"] = json!(d.added.len());
        out["retimed"] = json!(d.retimed.len());
    }
    out["rss_kb"] = json!(vm_hwm(None));
    println!("{out}");
    ExitCode::SUCCESS
}

/// `stage1`, `ring2`, `replan`.
pub(crate) fn stage_name(s: Stage) -> String {
    match s {
        Stage::Obsolete => "stage1".into(),
        Stage::Ring(n) => format!("ring{n}"),
        Stage::Replan => "replan".into(),
    }
}
