//! The child process: plans one problem with one configuration, validates
//! the plan, and prints the run as one JSON line.

use std::process::ExitCode;
use std::time::{Duration, Instant};

use hipop_analyzer::planner::{Config, PlannerLimits, Status};
use hipop_analyzer::validate::Options;
use hipop_analyzer::{AnalysisHost, Diagnostic, Severity};
use serde_json::json;

use super::*;

/// Peak resident memory of this process, in KiB.
pub(crate) fn vm_hwm(pid: Option<u32>) -> Option<u64> {
    vm_status(pid, "VmHWM:")
}

/// A memory line of a process's status (`VmHWM:`, `VmRSS:`), in KiB.
fn vm_status(pid: Option<u32>, field: &str) -> Option<u64> {
    let path = match pid {
        Some(p) => format!("/proc/{p}/status"),
        None => "/proc/self/status".to_string(),
    };
    let status = std::fs::read_to_string(path).ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// What the memory limit counts, as `hipop plan` does: the larger of the
/// heap and the resident set.
fn memory_in_use() -> usize {
    let rss = vm_status(None, "VmRSS:").map_or(0, |k| k.saturating_mul(1024) as usize);
    hipop_analyzer::alloc::in_use().max(rss)
}

/// The first error of a validation, located in the plan when it is there.
pub(crate) fn first_error(
    diagnostics: &[Diagnostic],
    plan_file: hipop_analyzer::SourceFile,
    text: &str,
) -> Option<String> {
    let d = diagnostics.iter().find(|d| d.severity == Severity::Error)?;
    let at = if d.file == plan_file {
        let offset = usize::from(d.range.start()).min(text.len());
        format!(" (plan line {})", text[..offset].matches('\n').count() + 1)
    } else {
        String::new()
    };
    Some(format!("{} {}{at}", d.code.id, d.message))
}

/// Writes the plan's texts beside `prefix` (`PREFIX.plan`, and
/// `PREFIX.hier.plan` when it has abstract steps) and validates each against
/// `problem` at every tolerance of [`TOLERANCES`]: `out["val"]`,
/// `out["hier"]` (`{valid, error, makespan}`) and `out["validate"]` (the
/// seconds it took). Returns the texts written, VAL's first.
pub(crate) fn validate_into(
    out: &mut serde_json::Value,
    host: &mut AnalysisHost,
    problem: hipop_analyzer::SourceFile,
    plan: &hipop_analyzer::planner::output::SolvedPlan,
    header: &str,
    prefix: &str,
) -> Vec<String> {
    let mut texts = vec![("val", "plan", plan.to_val(header))];
    if plan.is_hierarchical() {
        texts.push(("hier", "hier.plan", plan.to_hierarchical(header)));
    }
    validate_texts(out, host, problem, texts, prefix, true)
}

/// Writes each `(key, extension, text)` beside `prefix` and validates it
/// against `problem` into `out[key]`; `out["validate"]`: the seconds it
/// took. Returns the texts. `strict` (hipop's own plans): valid at every
/// tolerance of [`TOLERANCES`], with no dependent happenings closer than
/// the tolerance (W0411). Otherwise (a peer's plans) as VAL judges them: at
/// its default tolerance, W0411 being VAL's own leniency.
pub(crate) fn validate_texts(
    out: &mut serde_json::Value,
    host: &mut AnalysisHost,
    problem: hipop_analyzer::SourceFile,
    texts: Vec<(&str, &str, String)>,
    prefix: &str,
    strict: bool,
) -> Vec<String> {
    let tolerances: &[f64] = if strict { &TOLERANCES } else { &TOLERANCES[..1] };
    let start = Instant::now();
    let mut written = Vec::new();
    for (key, ext, text) in texts {
        let _ = std::fs::write(format!("{prefix}.{ext}"), &text);
        let f = host.set_file_text(&format!("bench.{ext}"), text.as_str());
        // The first tolerance at which the plan is not valid decides.
        let checks: Vec<_> = tolerances
            .iter()
            .map(|&tolerance| {
                let v = host.analysis().validate_plan(
                    f,
                    None,
                    problem,
                    &Options { tolerance, ..Options::default() },
                );
                (tolerance, v)
            })
            .collect();
        let close_fails = |v: &hipop_analyzer::validate::Validation| {
            strict && v.diagnostics.iter().any(|d| d.code.id == "W0411")
        };
        let failed = checks
            .iter()
            .position(|(_, v)| !matches!(v, Ok(Some(v)) if v.valid && v.checked && !close_fails(v)));
        let (tolerance, v) = match failed {
            Some(i) => checks[i].clone(),
            None => checks[0].clone(),
        };
        let check = match v {
            Ok(Some(v)) => {
                // hipop writes its plans with every dependent happening
                // ε apart: one closer (W0411) is a planner bug too.
                let close = v.diagnostics.iter().find(|d| d.code.id == "W0411").filter(|_| strict);
                let ok = v.valid && v.checked && close.is_none();
                json!({
                    "valid": ok,
                    "error": if ok {
                        None
                    } else if let Some(d) = close.filter(|_| v.valid && v.checked) {
                        Some(format!("-t {tolerance}: W0411 {}", d.message))
                    } else {
                        let e = first_error(&v.diagnostics, f, &text).unwrap_or_else(|| "not checked".into());
                        Some(format!("-t {tolerance}: {e}"))
                    },
                    "makespan": v.makespan,
                })
            }
            _ => json!({"valid": false, "error": "the validator did not run"}),
        };
        out[key] = check;
        written.push(text);
    }
    out["validate"] = json!(start.elapsed().as_secs_f64());
    written
}

/// The limits of a child's search: the time limit the parent gives (its
/// text, checked by the parent), and the memory the process holds.
/// The suffix of a configuration run without `first` (`hipop plan`'s default).
pub(crate) const ANYTIME: &str = "+anytime";

pub(crate) fn child_limits(limit: &str) -> PlannerLimits {
    let limit: f64 = limit.parse().expect("the parent checked the limit");
    PlannerLimits {
        time: Some(Duration::from_secs_f64(limit)),
        memory_in_use: Some(memory_in_use),
        // As `hipop plan`: the child exits once it has reported.
        exits_after: true,
        ..PlannerLimits::default()
    }
}

/// A file the parent wrote or found.
pub(crate) fn read(path: &str) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {path}: {e}"))
}

/// The primitive steps of a plan without abstract steps that can go: the
/// plan left when one is removed, with the steps whose every causal link
/// served only removed steps, is still valid (at VAL's default tolerance,
/// with the same times). Issue 19's target is none.
pub(crate) fn redundant_steps(
    host: &mut AnalysisHost,
    problem: hipop_analyzer::SourceFile,
    plan: &hipop_analyzer::planner::output::SolvedPlan,
) -> usize {
    let mut count = 0;
    for (_, rest) in plan.without_each_step() {
        let f = host.set_file_text("bench.redundant.plan", rest.to_val(""));
        let valid = host.analysis().validate_plan(f, None, problem, &Options::default());
        if matches!(valid, Ok(Some(v)) if v.valid && v.checked) {
            count += 1;
        }
    }
    count
}

/// `--one DOMAIN PROBLEM CONFIG TIME_LIMIT PLAN_PREFIX`: plans, validates,
/// writes the plans beside PLAN_PREFIX and prints one JSON line.
pub(crate) fn one(raw: &[String]) -> ExitCode {
    let [domain, problem, config, limit, prefix] = raw else {
        eprintln!("--one DOMAIN PROBLEM CONFIG TIME_LIMIT PLAN_PREFIX");
        return ExitCode::from(2);
    };
    if peers::PEERS.contains(&config.as_str()) {
        return peers::peer_one(domain, problem, config, limit, prefix);
    }
    let anytime = config.ends_with(ANYTIME);
    let config = Config::parse(config.strip_suffix(ANYTIME).unwrap_or(config))
        .expect("the parent checked the configuration");
    let limits = PlannerLimits { first: !anytime, ..child_limits(limit) };
    let mut host = AnalysisHost::new();
    host.set_file_text(domain, read(domain));
    let pf = host.set_file_text(problem, read(problem));
    let start = Instant::now();
    let result = host
        .analysis()
        .run_planner(pf, &config, &limits, &|| false, &mut |_| {})
        .expect("nothing cancels the planner here")
        .expect("the problem file has a problem");
    let wall = start.elapsed().as_secs_f64();
    let s = &result.stats;
    let mut out = json!({
        "wall": wall,
        "search": s.elapsed.as_secs_f64(),
        "expanded": s.expanded,
        "generated": s.generated,
        "peak_open": s.peak_open,
        "operators": s.operators,
        "methods": s.methods,
        "removed": s.redundant_removed,
        "removal": s.redundant_time.as_secs_f64(),
    });
    let first_diag = |code: &str| {
        result
            .diagnostics
            .iter()
            .find(|d| d.code.id == code)
            .or(result.diagnostics.first())
            .map(|d| format!("{} {}", d.code.id, d.message))
            .unwrap_or_default()
    };
    let (status, detail) = match &result.status {
        Status::Solved => ("solved", String::new()),
        Status::NoPlan => ("no-plan", first_diag("E0502")),
        Status::Limit(k) => ("limit", k.as_str().to_string()),
        Status::Refused => ("refused", first_diag("E0501")),
    };
    out["status"] = json!(status);
    out["detail"] = json!(detail);
    // Why the search stopped where it did: the first flaw of its best partial plan.
    let flaw = result.diagnostics.iter().find(|d| matches!(d.code.id, "I0504" | "I0505" | "I0506"));
    out["flaw"] = json!(flaw.map(|d| format!("{} {}", d.code.id, d.message)));
    if let Some(plan) = &result.plan {
        let header = format!("hipop plan bench: {} of {}, {}", plan.problem, plan.domain, config.name());
        out["makespan"] = json!(plan.makespan);
        out["length"] = json!(plan.primitive().count());
        out["abstract"] = json!(plan.steps.len() - plan.primitive().count());
        validate_into(&mut out, &mut host, pf, plan, &header, prefix);
        if !plan.is_hierarchical() {
            out["redundant"] = json!(redundant_steps(&mut host, pf, plan));
        }
    }
    out["rss_kb"] = json!(vm_hwm(None));
    println!("{out}");
    ExitCode::SUCCESS
}
