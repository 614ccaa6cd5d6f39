//! The `survivors-repair` suite: the repair benchmark of the HiPOP paper
//! (section 5.2, Figures 12 and 13) on the generator's survivors-repair set.
//!
//! For each of the 72 problems: its initial problem is planned (a child
//! process, as any problem of the plan bench; the plan validated), then,
//! for each event (`startingPos`, `newSurvivor`, `survivorPos`), that plan
//! is repaired for the event's problem with `repair`
//! (`RepairOptions::default()`), with `repairFlat` (the old plan's
//! hierarchy discarded) and the event's problem is planned from scratch
//! (`replan`), each in its own child process with the time limit. Each plan
//! found is validated like the plan bench's, and compared with the old plan
//! as `hipop diff` does (instability, distance).
//!
//! The `surveillance-repair` suite (`surveillance.rs`): the case study with a
//! robot out of service mid-mission, repaired with `--now`.

mod child;
mod report;
mod surveillance;

use std::ffi::OsString;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Mutex;
use std::time::Instant;

use serde_json::Value;

use super::*;
pub(crate) use child::repair_one;

/// The survivors suite's name on the command line.
pub(crate) const SUITE: &str = "survivors-repair";
/// The repair suites: the survivors-repair set, the surveillance mission.
pub(crate) const SUITES: [&str; 2] = [SUITE, "surveillance-repair"];
/// Its default time limit per run, seconds.
pub(crate) const DEFAULT_LIMIT: f64 = 10.0;

/// How an event's problem is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    Repair,
    RepairFlat,
    Replan,
}

impl Mode {
    pub(crate) const ALL: [Mode; 3] = [Mode::Repair, Mode::RepairFlat, Mode::Replan];

    pub(crate) fn name(self) -> &'static str {
        match self {
            Mode::Repair => "repair",
            Mode::RepairFlat => "repairFlat",
            Mode::Replan => "replan",
        }
    }

    pub(crate) fn parse(s: &str) -> Option<Mode> {
        Mode::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// One repair run: an event of a problem, solved one way.
#[derive(Debug, Clone)]
pub(crate) struct RJob {
    pub(crate) problem: String,
    pub(crate) event: &'static str,
    pub(crate) mode: Mode,
    pub(crate) domain: PathBuf,
    pub(crate) event_problem: PathBuf,
    pub(crate) old_plan: PathBuf,
}

/// What one repair run gave.
#[derive(Debug, Clone, Default)]
pub(crate) struct RRun {
    pub(crate) status: String,
    pub(crate) detail: String,
    pub(crate) wall: f64,
    pub(crate) search: f64,
    pub(crate) expanded: u64,
    /// The stage that found the plan (`stage1`, `ringN`, `replan`); repairs only.
    pub(crate) stage: Option<String>,
    pub(crate) stages: Option<u64>,
    /// Steps of the old plan in the first start plan, and removed in all.
    pub(crate) kept: Option<u64>,
    pub(crate) removed_steps: Option<u64>,
    pub(crate) old_length: Option<u64>,
    pub(crate) length: Option<u64>,
    pub(crate) abstract_steps: Option<u64>,
    pub(crate) makespan: Option<f64>,
    pub(crate) instability: Option<u64>,
    pub(crate) distance: Option<u64>,
    pub(crate) removed: Option<u64>,
    pub(crate) added: Option<u64>,
    pub(crate) retimed: Option<u64>,
    pub(crate) val: Option<(bool, Option<String>)>,
    pub(crate) hier: Option<(bool, Option<String>)>,
    pub(crate) rss_kb: Option<u64>,
}

impl RRun {
    pub(crate) fn solved(&self) -> bool {
        self.status == "solved"
    }

    pub(crate) fn invalid(&self) -> bool {
        self.solved() && (self.val.as_ref().is_none_or(|v| !v.0) || self.hier.as_ref().is_some_and(|h| !h.0))
    }

    fn parse(line: &str) -> Option<RRun> {
        let v: Value = serde_json::from_str(line).ok()?;
        let u = |k: &str| v[k].as_u64();
        Some(RRun {
            status: v["status"].as_str()?.to_string(),
            detail: v["detail"].as_str().unwrap_or("").to_string(),
            wall: v["wall"].as_f64()?,
            search: v["search"].as_f64().unwrap_or(0.0),
            expanded: u("expanded").unwrap_or(0),
            stage: v["stage"].as_str().map(String::from),
            stages: u("stages"),
            kept: u("kept"),
            removed_steps: u("removed_steps"),
            old_length: u("old_length"),
            length: u("length"),
            abstract_steps: u("abstract"),
            makespan: v["makespan"].as_f64(),
            instability: u("instability"),
            distance: u("distance"),
            removed: u("removed"),
            added: u("added"),
            retimed: u("retimed"),
            val: check_of(&v["val"]),
            hier: check_of(&v["hier"]),
            rss_kb: u("rss_kb"),
        })
    }
}

/// Runs `f` on every item, `jobs` at a time, in order of the items; `done`
/// sees each result as it comes.
fn parallel<T: Sync, R: Clone + Send + Default>(
    jobs: usize,
    items: &[T],
    f: impl Fn(&T) -> R + Sync,
    done: impl Fn(usize, &T, &R) + Sync,
) -> Vec<R> {
    let next = Mutex::new(0usize);
    let results: Mutex<Vec<Option<R>>> = Mutex::new(vec![None; items.len()]);
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                loop {
                    let i = {
                        let mut n = next.lock().unwrap();
                        let i = *n;
                        *n += 1;
                        i
                    };
                    let Some(item) = items.get(i) else { break };
                    let r = f(item);
                    done(i, item, &r);
                    results.lock().unwrap()[i] = Some(r);
                }
            });
        }
    });
    results.into_inner().unwrap().into_iter().map(|r| r.unwrap_or_default()).collect()
}

/// The runs of one event's jobs (repair, repairFlat, replan), `repeat`
/// rounds of one run of each, each in a child process, and for each job
/// the run of median time (the plans found are the same; a run that does
/// not solve is reported as it is, and that job runs no more). The ways
/// take turns so that a slow spell of the machine falls on all of them
/// alike: run one after the other, five runs of one way could fall in a
/// spell the next way's missed, and their ratio was off by half.
fn run_event_median(group: &[RJob], config: &str, limit: f64, plans: &Path, repeat: usize) -> Vec<RRun> {
    let mut runs: Vec<Vec<RRun>> = vec![Vec::new(); group.len()];
    let mut last: Vec<Option<RRun>> = vec![None; group.len()];
    for _ in 0..repeat {
        for (k, job) in group.iter().enumerate() {
            if last[k].is_some() {
                continue;
            }
            let r = run_repair_child(job, config, limit, plans);
            if !r.solved() || r.invalid() {
                last[k] = Some(r);
            } else {
                runs[k].push(r);
            }
        }
    }
    runs.into_iter()
        .zip(last)
        .map(|(mut rs, last)| {
            last.unwrap_or_else(|| {
                rs.sort_by(|a, b| a.wall.total_cmp(&b.wall));
                rs.swap_remove(rs.len() / 2)
            })
        })
        .collect()
}

/// The repair run of `job` in a child process.
fn run_repair_child(job: &RJob, config: &str, limit: f64, plans: &Path) -> RRun {
    let prefix = plans.join(job.event).join(format!("{}.{}", job.problem, job.mode.name()));
    let _ = std::fs::create_dir_all(prefix.parent().expect("a plan folder"));
    let args: Vec<OsString> = vec![
        "--repair".into(),
        job.mode.name().into(),
        job.domain.clone().into(),
        job.event_problem.clone().into(),
        job.old_plan.clone().into(),
        config.into(),
        limit.to_string().into(),
        prefix.into(),
    ];
    let c = spawn_child(&args, limit);
    match c.line.as_deref().and_then(RRun::parse) {
        Some(run) if c.success => run,
        _ => RRun { status: c.status(), detail: c.detail(), wall: c.wall, rss_kb: c.hwm, ..RRun::default() },
    }
}

/// The suite: plans the initial problems, runs every event's repairs and
/// replans, writes the report and the CSV. Exit status 1 on an invalid plan
/// or a crash.
pub(crate) fn run(a: &Args, raw: &[String]) -> ExitCode {
    let config = match &a.configs {
        Some(c) if c.len() == 1 => c[0].clone(),
        Some(_) => {
            eprintln!("error: the repair suites run one configuration (--configs NAME)");
            return ExitCode::from(2);
        }
        None => Config::DEFAULT.to_string(),
    };
    let limit = a.time_limit.unwrap_or(DEFAULT_LIMIT);
    let base = target_dir().join("plan-bench");
    let inputs = base.join("inputs").join(SUITE);
    let plans = base.join("plans").join(SUITE);
    std::fs::create_dir_all(&inputs).expect("the inputs folder");
    for (name, text) in hipop_samplegen::survivors_repair(hipop_samplegen::DEFAULT_SEED) {
        std::fs::write(inputs.join(&name), text).expect("an input file");
    }
    let domain = inputs.join("domain.pddl");
    let mut stems: Vec<String> = if a.suites.iter().any(|s| s == SUITE) {
        hipop_samplegen::survivors::Params::grid().into_iter().map(|p| p.stem()).collect()
    } else {
        Vec::new()
    };
    let mut notes = Vec::new();
    if let Some(f) = &a.filter {
        stems.retain(|s| s.contains(f.as_str()));
        notes.push(format!("only the problems whose name contains `{f}`"));
    }
    let out_md = a.out_or("repair-bench.md");
    let csv_path = out_md.with_extension("csv");
    if let Some(dir) = out_md.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    let started = (now_utc(), load(), commit());
    let clock = Instant::now();
    // The initial plans.
    let initial: Vec<Job> = stems
        .iter()
        .map(|s| Job {
            suite: SUITE,
            group: "initial".into(),
            problem: s.clone(),
            domain_path: domain.clone(),
            problem_path: inputs.join(format!("{s}.pddl")),
            config: config.clone(),
        })
        .collect();
    if !stems.is_empty() {
        eprintln!(
            "{SUITE}: {} initial problems, then 3 events x 3 ways each ({limit} s limit, {} job{}); report {}",
            initial.len(),
            a.jobs,
            if a.jobs == 1 { "" } else { "s" },
            out_md.display()
        );
    }
    let plans_dir = target_dir().join("plan-bench").join("plans");
    let old: Vec<Run> = parallel(
        a.jobs,
        &initial,
        |j| run_child(j, limit, &plans_dir),
        |i, j, r| {
            eprintln!(
                "[{:>3}/{}] initial {}: {} in {}, {} actions",
                i + 1,
                initial.len(),
                j.problem,
                r_status(r),
                secs(Some(r.wall)),
                r.length.map_or("–".into(), |l| l.to_string())
            )
        },
    );
    // Each event, three ways, from the plans found.
    let mut jobs = Vec::new();
    for (j, r) in initial.iter().zip(&old) {
        if !r.solved() || r.invalid() {
            continue;
        }
        let prefix = plans_dir.join(SUITE).join("initial").join(format!("{}.{config}", j.problem));
        let hier = PathBuf::from(format!("{}.hier.plan", prefix.display()));
        let val = PathBuf::from(format!("{}.plan", prefix.display()));
        let old_plan = if hier.is_file() { hier } else { val };
        for event in hipop_samplegen::survivors::repair::Event::ALL {
            for mode in Mode::ALL {
                jobs.push(RJob {
                    problem: j.problem.clone(),
                    event: event.name(),
                    mode,
                    domain: domain.clone(),
                    event_problem: inputs.join(format!("{}-{}.pddl", j.problem, event.name())),
                    old_plan: old_plan.clone(),
                });
            }
        }
    }
    let csv = Mutex::new(std::fs::File::create(&csv_path).ok());
    if let Some(f) = csv.lock().unwrap().as_mut() {
        let _ = writeln!(f, "{}", report::CSV_HEAD);
        for (j, r) in initial.iter().zip(&old) {
            let _ = writeln!(f, "{}", report::csv_initial(j, r));
        }
    }
    // The jobs of one event are consecutive (its three ways): they run
    // together, in turns.
    let groups: Vec<&[RJob]> = jobs.chunk_by(|x, y| x.problem == y.problem && x.event == y.event).collect();
    let total = jobs.len();
    let first_of: Vec<usize> = groups
        .iter()
        .scan(0, |n, g| {
            let i = *n;
            *n += g.len();
            Some(i)
        })
        .collect();
    let runs: Vec<RRun> = parallel(
        a.jobs,
        &groups,
        |g| run_event_median(g, &config, limit, &plans, a.repeat),
        |gi, g, rs| {
            for (k, (j, r)) in g.iter().zip(rs).enumerate() {
                eprintln!(
                    "[{:>3}/{}] {} {} {}: {} in {}{}{}",
                    first_of[gi] + k + 1,
                    total,
                    j.problem,
                    j.event,
                    j.mode.name(),
                    if r.invalid() { "SOLVED, INVALID PLAN".to_string() } else { r.status.clone() },
                    secs(Some(r.wall)),
                    r.stage.as_ref().map(|s| format!(" ({s})")).unwrap_or_default(),
                    r.instability.map(|i| format!(", instability {i}")).unwrap_or_default(),
                );
                if let Some(f) = csv.lock().unwrap().as_mut() {
                    let _ = writeln!(f, "{}", report::csv_line(j, r));
                }
            }
        },
    )
    .into_iter()
    .flatten()
    .collect();
    let watched = a.suites.iter().any(|s| s == SUITES[1]).then(|| surveillance::run(&config, limit));
    // The CSV again, in order.
    let mut text = format!("{}\n", report::CSV_HEAD);
    for (j, r) in initial.iter().zip(&old) {
        text += &report::csv_initial(j, r);
        text.push('\n');
    }
    for (j, r) in jobs.iter().zip(&runs) {
        text += &report::csv_line(j, r);
        text.push('\n');
    }
    for (case, rs) in watched.iter().flat_map(|w| w.cases.iter()) {
        for r in rs {
            let j = RJob {
                problem: "surveillance".into(),
                event: "mona2-lost",
                mode: case.mode,
                domain: PathBuf::new(),
                event_problem: PathBuf::new(),
                old_plan: PathBuf::new(),
            };
            let line = report::csv_line(&j, r);
            text += &line.replacen(case.mode.name(), &report::csv_field_text(&case.label), 1);
            text.push('\n');
        }
    }
    let _ = std::fs::write(&csv_path, text);
    let md = report::report(&report::Context {
        args: a,
        raw,
        notes: &notes,
        config: &config,
        limit,
        started: (&started.0, &started.1, &started.2),
        took: clock.elapsed().as_secs_f64(),
        initial: &initial,
        old: &old,
        jobs: &jobs,
        runs: &runs,
        surveillance: watched.as_ref(),
    });
    if let Err(e) = std::fs::write(&out_md, &md) {
        eprintln!("error: cannot write {}: {e}", out_md.display());
    }
    eprintln!("report: {}\ncsv: {}", out_md.display(), csv_path.display());
    let watched_runs: Vec<&RRun> =
        watched.iter().flat_map(|w| w.cases.iter().flat_map(|c| c.1.iter())).collect();
    let invalid = old.iter().filter(|r| r.invalid()).count()
        + runs.iter().filter(|r| r.invalid()).count()
        + watched_runs.iter().filter(|r| r.invalid()).count()
        + watched.iter().filter(|w| w.initial.invalid()).count();
    let crashes = old.iter().filter(|r| r.status == "crash").count()
        + runs.iter().filter(|r| r.status == "crash").count()
        + watched_runs.iter().filter(|r| r.status == "crash").count();
    if invalid > 0 || crashes > 0 {
        eprintln!("FAILED: {invalid} invalid plan(s), {crashes} crash(es)");
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}
