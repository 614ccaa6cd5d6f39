//! `hipop plan DOMAIN PROBLEM`: runs the HiPOP planner and writes the plan.
//! The planner is `hipop_analyzer::planner`; this module reads the files,
//! shows progress, writes the plan and computes the exit status.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

use hipop_analyzer::planner::{Config, PlannerLimits, Status};
use hipop_analyzer::{AnalysisHost, Severity};
use serde_json::json;

use crate::ColorWhen;
use crate::render::{Rendered, Sources, print_stdout};
use hipop_analyzer::diagnostic::SHOWN_PER_FILE;

/// How the plan is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PlanOutput {
    /// `hierarchical` when the plan has abstract steps, else `val`.
    Auto,
    /// VAL's temporal format: `0.000: (move r1 a b) [30.980]`.
    Val,
    /// IPC 2020 hierarchical format, with hipop's `;@ ID START [DURATION]` timing after `<==`.
    Hierarchical,
    /// hipop's JSON plan: the whole partial-order plan (schema in docs/plan-formats.md).
    Json,
}

pub struct Options {
    pub output: Option<PathBuf>,
    pub format: PlanOutput,
    pub config: Config,
    pub limits: PlannerLimits,
    pub color: ColorWhen,
    pub quiet: bool,
    pub progress: bool,
    pub stats: bool,
    pub timeline: crate::timeline::TimelineArgs,
}

/// Exit status: 0 plan found, 1 no plan, 3 limit reached, 2 usage or input error.
pub fn run(domain: &Path, problem: &Path, options: &Options) -> u8 {
    // The time limit is the whole run's: reading, parsing and checking the
    // files count too.
    let started = std::time::Instant::now();
    if let Err(m) = options.timeline.check(1, options.format != PlanOutput::Json) {
        eprintln!("error: {m}");
        return 2;
    }
    let mut host = AnalysisHost::new();
    let load = |host: &mut AnalysisHost, path: &Path, what: &str| match crate::diff::read(path, what) {
        Ok(text) => Ok(host.set_file_text(&crate::inputs::key(path), text)),
        Err(m) => Err(m),
    };
    let (fd, fp) =
        match (load(&mut host, domain, "a domain file"), load(&mut host, problem, "a problem file")) {
            (Ok(d), Ok(p)) => (d, p),
            (Err(m), _) | (_, Err(m)) => {
                eprintln!("error: {m}");
                return 2;
            }
        };
    let analysis = host.analysis();
    let interrupted = || {
        eprintln!("error: the analysis was interrupted; this is a bug in hipop, please report it");
        2u8
    };
    let files = [fd, fp];
    let mut model = Vec::new();
    for f in files {
        match analysis.check_diagnostics(f) {
            Ok(d) => model.extend(d.into_iter().filter(|d| d.severity == Severity::Error)),
            Err(_) => return interrupted(),
        }
    }
    let sources = Sources::new(&analysis, &files);
    let emit = |diagnostics: &[hipop_analyzer::Diagnostic]| {
        let rendered = Rendered {
            sources: &sources,
            diagnostics,
            io_errors: &[],
            files: 2,
            max_per_file: SHOWN_PER_FILE,
        };
        let mut stream = crate::render::stderr(options.color);
        rendered.emit_human(&mut stream);
        let _ = std::io::Write::flush(&mut stream);
    };
    if !model.is_empty() {
        emit(&model);
        eprintln!("error: the domain or the problem has errors: fix them before planning");
        return 2;
    }
    let show_progress = options.progress;
    let mut last_makespan = None;
    let limits = PlannerLimits { time_spent: started.elapsed(), ..options.limits.clone() };
    let watchdog = Watchdog::start(&limits, options.format == PlanOutput::Json);
    let searching = watchdog.searching.clone();
    let mut progress = |p: &hipop_analyzer::planner::Progress| {
        searching.store(true, std::sync::atomic::Ordering::Release);
        if show_progress && p.improved {
            let makespan = p.makespan.unwrap_or(p.best_f);
            // Same makespan, lower cost: fewer steps (or less work).
            let how = if last_makespan == Some(makespan) { ", fewer steps" } else { "" };
            last_makespan = Some(makespan);
            eprintln!(
                "  {:>8.1} s: plan with makespan {makespan:.3}{how} ({} plans expanded)",
                p.elapsed.as_secs_f64(),
                p.expanded
            );
        } else if show_progress {
            eprintln!(
                "  {:>8.1} s: {} plans expanded, {} open, best f {:.2}",
                p.elapsed.as_secs_f64(),
                p.expanded,
                p.open,
                p.best_f
            );
        }
    };
    let planned = analysis.run_planner(fp, &options.config, &limits, &|| false, &mut progress);
    drop(watchdog);
    let result = match planned {
        Ok(Some(r)) => r,
        Ok(None) => {
            eprintln!("error: {}: no `(define (problem …) …)` in this file", problem.display());
            return 2;
        }
        Err(_) => return interrupted(),
    };
    let stats = &result.stats;
    let plural = |n: u64| if n == 1 { "" } else { "s" };
    let mut search = format!(
        "{} plan{} expanded, configuration {}",
        stats.expanded,
        plural(stats.expanded),
        options.config.name()
    );
    if !options.limits.first
        && let Some(first) = stats.first_found
    {
        let n = stats.plans_found;
        let end = match stats.stopped_by {
            Some(kind) => format!("stopped by the {} limit", kind.as_str()),
            None => "no better plan left".to_string(),
        };
        search.push_str(&format!(
            "; best of {n} plan{} found (first at {:.2} s), {end}",
            plural(n.into()),
            first.as_secs_f64()
        ));
    }
    if options.stats {
        eprintln!(
            "search: {} plans expanded, {} generated in {:.3} s ({:.0} plans/s); {} ground operators, {} method instances; open list peak {}; largest plan expanded {} steps",
            stats.expanded,
            stats.generated,
            stats.elapsed.as_secs_f64(),
            stats.expanded as f64 / stats.elapsed.as_secs_f64().max(1e-9),
            stats.operators,
            stats.methods,
            stats.peak_open,
            stats.largest
        );
        if stats.lookahead_steps > 0 {
            eprintln!(
                "lookahead: {} taken, {} actions in those estimated",
                stats.lookahead_taken, stats.lookahead_steps
            );
        }
        if stats.redundant_removed > 0 {
            eprintln!(
                "redundant steps: {} removed in {:.3} s",
                stats.redundant_removed,
                stats.redundant_time.as_secs_f64()
            );
        }
    }
    match (&result.status, &result.plan) {
        (Status::Solved, Some(plan)) => {
            let count = |n: usize, one: &str| format!("{n} {one}{}", if n == 1 { "" } else { "s" });
            let actions = plan.primitive().count();
            let header = format!(
                "hipop plan for problem {} of domain {}\nmakespan {:.3}, {}, {}\n{search}",
                plan.problem,
                plan.domain,
                plan.makespan,
                count(actions, "action"),
                count(plan.steps.len() - actions, "abstract step"),
            );
            let format = match options.format {
                PlanOutput::Auto if plan.is_hierarchical() => PlanOutput::Hierarchical,
                PlanOutput::Auto => PlanOutput::Val,
                f => f,
            };
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
            if !options.quiet {
                eprintln!(
                    "plan found: {} actions, makespan {:.3}; {search}",
                    plan.primitive().count(),
                    plan.makespan
                );
            }
            if options.timeline.wanted() {
                // Drawn from the plan as written, read back like any plan file.
                let text = if plan.is_hierarchical() { plan.to_hierarchical("") } else { plan.to_val("") };
                let title = format!("plan of {} ({})", plan.problem, options.config.name());
                drop(analysis);
                let file = host.set_file_text("<hipop plan>.plan", text);
                let analysis = host.analysis();
                let drawn = match crate::timeline::layout(
                    &analysis,
                    file,
                    None,
                    fd,
                    hipop_analyzer::plan::NameMatching::CaseInsensitive,
                ) {
                    Ok(timeline) => crate::timeline::emit(&options.timeline, &timeline, &title),
                    Err(_) => return interrupted(),
                };
                if let Err(m) = drawn {
                    eprintln!("error: {m}");
                    return 2;
                }
            }
            0
        }
        (status, _) => {
            let (code, what) = match status {
                Status::Refused => (2, "not planned: the planner cannot plan this problem".to_string()),
                Status::NoPlan => (
                    1,
                    "no plan: every partial plan within the allowed actions and the methods was explored"
                        .into(),
                ),
                Status::Limit(k) => (3, format!("no plan found: the {} limit was reached", k.as_str())),
                Status::Solved => (1, "no plan".into()),
            };
            if options.format == PlanOutput::Json {
                let rendered = Rendered {
                    sources: &sources,
                    diagnostics: &result.diagnostics,
                    io_errors: &[],
                    files: 2,
                    max_per_file: SHOWN_PER_FILE,
                };
                let doc = json!({
                    "status": match status {
                        Status::Refused => "refused",
                        Status::NoPlan => "no-plan",
                        Status::Limit(_) => "limit",
                        Status::Solved => "solved",
                    },
                    "limit": match status { Status::Limit(k) => Some(k.as_str()), _ => None },
                    "expanded": stats.expanded,
                    "generated": stats.generated,
                    "seconds": stats.elapsed.as_secs_f64(),
                    "diagnostics": rendered.json_diagnostics(),
                });
                print_stdout(&serde_json::to_string_pretty(&doc).unwrap_or_default());
            } else {
                emit(&result.diagnostics);
            }
            eprintln!("{what}; {search}");
            let _ = std::io::stderr().flush();
            code
        }
    }
}

/// The time and memory limits, whatever the planner is doing: the search
/// looks at the clock at every plan it expands and at the memory every 32,
/// but grounding and compiling a large problem (hundreds of thousands of
/// instances, millions of method instances) look at neither. Past the time
/// limit by [`Watchdog::GRACE`], or over the memory limit, the process ends
/// with exit status 3, as for any limit, saying where it was.
struct Watchdog {
    done: std::sync::Arc<std::sync::atomic::AtomicBool>,
    /// Set once the search reports its progress: a limit reached after it
    /// was reached by the search between two of its looks at it.
    searching: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

impl Watchdog {
    /// After the time limit, what the search's own stop, its report and the
    /// plan written may take (the search stops within 0.09 s of it).
    const GRACE: Duration = Duration::from_millis(150);
    /// How often the memory is read.
    const EVERY: Duration = Duration::from_millis(20);

    fn start(limits: &PlannerLimits, json: bool) -> Watchdog {
        use std::sync::atomic::Ordering;
        let done = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let seen = done.clone();
        let searching = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let in_search = searching.clone();
        let time = limits.time;
        let deadline =
            time.map(|t| std::time::Instant::now() + t.saturating_sub(limits.time_spent) + Self::GRACE);
        let memory = limits.memory.zip(limits.memory_in_use);
        std::thread::spawn(move || {
            let mut last = memory.map_or(0, |(_, in_use)| in_use());
            let which = loop {
                if seen.load(Ordering::Acquire) {
                    return;
                }
                let now = std::time::Instant::now();
                if deadline.is_some_and(|d| now >= d) {
                    break "time";
                }
                // Before the next reading, the memory grows about as much
                // as since the last one: stop while it is still under.
                if let Some((m, in_use)) = memory {
                    let now = in_use();
                    if now.saturating_add(now.saturating_sub(last)) > m {
                        break "memory";
                    }
                    last = now;
                }
                let wait = deadline.map_or(Self::EVERY, |d| (d - now).min(Self::EVERY));
                std::thread::sleep(wait);
            };
            if seen.load(Ordering::Acquire) {
                return;
            }
            if json {
                let doc = json!({
                    "status": "limit",
                    "limit": which,
                    "expanded": 0,
                    "generated": 0,
                    "seconds": time.map(|t| t.as_secs_f64()),
                    "diagnostics": [],
                });
                print_stdout(&serde_json::to_string_pretty(&doc).unwrap_or_default());
            }
            let limit = match (which, time, memory) {
                ("time", Some(t), _) => format!("{:.1} s", t.as_secs_f64()),
                (_, _, Some((m, _))) => format!("{} MiB", m >> 20),
                _ => String::new(),
            };
            let where_ = if in_search.load(Ordering::Acquire) {
                "during the search, between two of its looks at it"
            } else {
                "where the planner does not look at it (grounding or compiling a large problem)"
            };
            eprintln!("no plan found: the {which} limit ({limit}) was reached {where_}");
            let _ = std::io::stderr().flush();
            std::process::exit(3);
        });
        Watchdog { done, searching }
    }
}

impl Drop for Watchdog {
    fn drop(&mut self) {
        self.done.store(true, std::sync::atomic::Ordering::Release);
    }
}

/// Parses a duration in seconds.
pub fn parse_seconds(s: &str) -> Result<Duration, String> {
    match s.parse::<f64>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(Duration::from_secs_f64(t)),
        _ => Err(format!("`{s}` is not a number of seconds (more than 0)")),
    }
}

/// Parses a planner configuration name.
pub fn parse_config(s: &str) -> Result<Config, String> {
    Config::parse(s)
}
