//! `hipop repair DOMAIN PROBLEM OLD_PLAN`: repairs the plan being executed
//! for the problem after an event (`hipop_analyzer::repair`, section 5 of
//! the HiPOP paper), writes the repaired plan and reports what changed.

use std::path::{Path, PathBuf};

use hipop_analyzer::diagnostic::SHOWN_PER_FILE;
use hipop_analyzer::plan::NameMatching;
use hipop_analyzer::plan::diff::{DiffOptions, diff};
use hipop_analyzer::planner::output::SolvedPlan;
use hipop_analyzer::planner::{Config, PlannerLimits, Status};
use hipop_analyzer::repair::{Execution, RepairOptions, Stage};
use hipop_analyzer::{AnalysisHost, Severity};

use crate::ColorWhen;
use crate::plan::PlanOutput;
use crate::render::{Rendered, Sources, print_stdout};

pub struct Options {
    pub output: Option<PathBuf>,
    pub format: PlanOutput,
    pub config: Config,
    pub limits: PlannerLimits,
    pub repair: RepairOptions,
    pub color: ColorWhen,
    pub quiet: bool,
    pub stats: bool,
    /// Also plan from scratch and compare.
    pub compare_replan: bool,
}

/// Exit status: 0 repaired, 1 no plan even after the full replan, 3 a limit
/// reached, 2 usage or input error.
pub fn run(domain: &Path, problem: &Path, old: &Path, options: &Options) -> u8 {
    let mut host = AnalysisHost::new();
    let mut load = |path: &Path, what: &str| match crate::diff::read(path, what) {
        Ok(text) => Ok(host.set_file_text(&crate::inputs::key(path), text)),
        Err(m) => Err(m),
    };
    let files =
        match (load(domain, "a domain file"), load(problem, "a problem file"), load(old, "a plan file")) {
            (Ok(d), Ok(p), Ok(o)) => [d, p, o],
            (Err(m), _, _) | (_, Err(m), _) | (_, _, Err(m)) => {
                eprintln!("error: {m}");
                return 2;
            }
        };
    let [_, fp, fo] = files;
    let analysis = host.analysis();
    let interrupted = || {
        eprintln!("error: the analysis was interrupted; this is a bug in hipop, please report it");
        2u8
    };
    let mut errors = Vec::new();
    for f in [files[0], fp] {
        match analysis.check_diagnostics(f) {
            Ok(d) => errors.extend(d.into_iter().filter(|d| d.severity == Severity::Error)),
            Err(_) => return interrupted(),
        }
    }
    let model_errors = !errors.is_empty();
    match analysis.plan_diagnostics(fo, None) {
        Ok(d) => errors.extend(d.into_iter().filter(|d| d.severity == Severity::Error)),
        Err(_) => return interrupted(),
    }
    // The diagnostics of the three files, compiler-style, on standard error.
    let emit = |analysis: &hipop_analyzer::Analysis, diagnostics: &[hipop_analyzer::Diagnostic]| {
        let sources = Sources::new(analysis, &files);
        let rendered = Rendered {
            sources: &sources,
            diagnostics,
            io_errors: &[],
            files: 3,
            max_per_file: SHOWN_PER_FILE,
        };
        let mut stream = crate::render::stderr(options.color);
        rendered.emit_human(&mut stream);
        let _ = std::io::Write::flush(&mut stream);
    };
    if !errors.is_empty() {
        emit(&analysis, &errors);
        eprintln!(
            "error: {}",
            if model_errors {
                "the domain or the problem has errors: fix them before repairing"
            } else {
                "the old plan cannot be read: fix it before repairing"
            }
        );
        return 2;
    }
    let result = match analysis.run_repair(
        fp,
        fo,
        None,
        &options.config,
        &options.limits,
        &options.repair,
        &|| false,
        &mut |_| {},
    ) {
        Ok(Some(r)) => r,
        Ok(None) => {
            eprintln!("error: {}: no `(define (problem …) …)` in this file", problem.display());
            return 2;
        }
        Err(_) => return interrupted(),
    };
    // The report: the stages, the steps removed and why.
    if !options.quiet {
        for s in &result.stages {
            eprintln!(
                "{}: {} step{} of the old plan kept, {} goal{}, {}, {} plan{} expanded in {:.3} s",
                s.stage.describe(),
                s.kept,
                if s.kept == 1 { "" } else { "s" },
                s.goals,
                if s.goals == 1 { "" } else { "s" },
                status_text(&s.status),
                s.expanded,
                if s.expanded == 1 { "" } else { "s" },
                s.elapsed.as_secs_f64()
            );
        }
        for r in &result.removed {
            if r.stage == Stage::Replan {
                continue;
            }
            let step = &result.old[r.step];
            eprintln!("  removed {} (step {}): {}", step.call, step.id, r.describe(&result.old));
        }
        for d in &result.dropped {
            eprintln!(
                "  dropped the goal {}: a meeting{} that no plan keeps",
                d.goal,
                if d.unreachable { " with an unreachable agent" } else { "" }
            );
        }
    }
    if options.stats {
        let s = &result.stats;
        eprintln!(
            "search: {} plans expanded, {} generated in {:.3} s; {} ground operators, {} method instances",
            s.expanded,
            s.generated,
            s.elapsed.as_secs_f64(),
            s.operators,
            s.methods
        );
    }
    let Some(plan) = &result.plan else {
        let (code, what) = match result.status {
            Status::NoPlan => (1, "no plan, even after the full replan"),
            Status::Limit(_) => (3, "no plan before the limit"),
            _ => (2, "not repaired: the planner cannot plan this problem"),
        };
        emit(&analysis, &result.diagnostics);
        eprintln!("error: {what}");
        return code;
    };
    let format = match options.format {
        PlanOutput::Auto if plan.is_hierarchical() => PlanOutput::Hierarchical,
        PlanOutput::Auto => PlanOutput::Val,
        f => f,
    };
    let header = format!(
        "hipop repair of {} for problem {} of domain {}\nmakespan {:.3}, {} actions\nfound by {}, configuration {}",
        old.display(),
        plan.problem,
        plan.domain,
        plan.makespan,
        plan.primitive().count(),
        result.stage.map_or_else(|| "the full replan".to_string(), |s| s.describe()),
        options.config.name()
    );
    let text = match format {
        PlanOutput::Json => plan.to_json(),
        PlanOutput::Hierarchical => plan.to_hierarchical(&header),
        _ => plan.to_val(&header),
    };
    match &options.output {
        Some(path) => {
            if let Err(e) = std::fs::write(path, &text) {
                eprintln!("error: {}: cannot write: {e}", path.display());
                return 2;
            }
        }
        None => print_stdout(&text),
    }
    // The stability figures against the old plan, as `hipop diff` gives them.
    let repair_time: f64 = result.stages.iter().map(|s| s.elapsed.as_secs_f64()).sum();
    let repaired = plan.clone();
    let stage = result.stage;
    drop(analysis);
    let figures = |host: &mut AnalysisHost, name: &str, plan: &SolvedPlan| {
        let written = if plan.is_hierarchical() { plan.to_hierarchical("") } else { plan.to_val("") };
        let fr = host.set_file_text(name, written);
        let analysis = host.analysis();
        let a = analysis.plan(fo, None).ok()?;
        let b = analysis.plan(fr, None).ok()?;
        let agents = analysis.plan_agents(files[0], NameMatching::CaseInsensitive).ok()?;
        Some(diff(&a, &b, &agents, &DiffOptions::default()))
    };
    let mine = figures(&mut host, "<repaired plan>.plan", &repaired);
    if !options.quiet
        && let Some(d) = &mine
    {
        eprintln!(
            "repaired: {} action{} kept, {} removed, {} added, {} retimed; instability {}, distance {}",
            d.matched.len(),
            if d.matched.len() == 1 { "" } else { "s" },
            d.removed.len(),
            d.added.len(),
            d.retimed.len(),
            d.instability,
            d.distance
        );
    }
    if options.compare_replan {
        let replan =
            match host.analysis().run_planner(fp, &options.config, &options.limits, &|| false, &mut |_| {}) {
                Ok(Some(r)) => r,
                Ok(None) => return 2,
                Err(_) => return interrupted(),
            };
        let theirs = replan.plan.as_ref().and_then(|p| figures(&mut host, "<replanned plan>.plan", p));
        let cell = |x: Option<String>| x.unwrap_or_else(|| "–".into());
        let rows = [
            (
                "found",
                stage.map_or_else(|| "by the full replan".into(), |s| s.describe()),
                status_text(&replan.status).replace("repaired", "found"),
            ),
            ("time (s)", format!("{repair_time:.3}"), format!("{:.3}", replan.stats.elapsed.as_secs_f64())),
            (
                "actions",
                repaired.primitive().count().to_string(),
                cell(replan.plan.as_ref().map(|p| p.primitive().count().to_string())),
            ),
            (
                "makespan",
                format!("{:.3}", repaired.makespan),
                cell(replan.plan.as_ref().map(|p| format!("{:.3}", p.makespan))),
            ),
            (
                "instability",
                cell(mine.as_ref().map(|d| d.instability.to_string())),
                cell(theirs.as_ref().map(|d| d.instability.to_string())),
            ),
            (
                "distance",
                cell(mine.as_ref().map(|d| d.distance.to_string())),
                cell(theirs.as_ref().map(|d| d.distance.to_string())),
            ),
        ];
        eprintln!("{:<12} {:<40} replan", "", "repair");
        for (name, a, b) in rows {
            eprintln!("{name:<12} {a:<40} {b}");
        }
    }
    0
}

fn status_text(s: &Status) -> String {
    match s {
        Status::Solved => "repaired".into(),
        Status::NoPlan => "no plan from there".into(),
        Status::Limit(k) => format!("stopped by the {} limit", k.as_str()),
        Status::Refused => "refused".into(),
    }
}

/// What freezes steps of the old plan.
pub fn execution(now: Option<f64>, executed: Vec<u32>, unreachable: Vec<String>) -> Execution {
    Execution { now, executed, unreachable }
}
