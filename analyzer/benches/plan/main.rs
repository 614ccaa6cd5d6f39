//! `cargo bench -p hipop-analyzer --bench plan -- [SUITE…] [OPTIONS]`: the
//! HiPOP planner on the benchmark suites, every plan validated.
//!
//! Suites: `survivors` (the 72 generated problems), `satellite` (the IPC 2002
//! temporal Satellite corpus, constant durations), `satellite-time` (its
//! variant whose durations come from numeric fluents: 0.5146, not 5),
//! `satellite-abstract` (the same problems as `satellite` with
//! abstract actions and `:allowed-actions`), `surveillance` (the case-study
//! sample), `hddl` (the IPC 2020 partial-order HDDL domains). Default: all of
//! them; every configuration of `Config::MAIN`, the default one only for hddl.
//! `survivors-repair` and `surveillance-repair` (without the plan suites,
//! never by default) are the repair benchmarks of section 5 of the HiPOP
//! paper: the `repair` module.
//!
//! Each (problem, configuration) runs in a child process (this binary again,
//! in the hidden `--one` mode): a crash stays one failed row, the peak memory
//! (VmHWM) is the problem's own, and `--jobs 2` runs two at once. The child
//! plans, then validates the plan it found with hipop's validator, at VAL's
//! default tolerance (0.01) and at 0.0001: the VAL text always, the
//! hierarchical text too when the plan has abstract steps.
//! An invalid plan is a loud failure: listed first in the report, and the
//! bench exits with status 1.
//!
//! Output: a Markdown report (`--out`, default `target/plan-bench.md`), a CSV
//! beside it (one line per problem and configuration), the plans found under
//! `target/plan-bench/plans/SUITE/DOMAIN/`, the generated inputs under
//! `target/plan-bench/inputs/`. Results are recorded in docs/benchmarks.md.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Mutex;
use std::time::Instant;

use hipop_analyzer::planner::Config;
use hipop_analyzer::validate::Options;

/// The allocator of the `hipop` binary: what it measures is what users get.
#[global_allocator]
static GLOBAL: hipop_analyzer::alloc::Counting<mimalloc::MiMalloc> =
    hipop_analyzer::alloc::Counting::new(mimalloc::MiMalloc);

const SUITES: [&str; 7] =
    ["survivors", "satellite", "satellite-time", "satellite-abstract", "surveillance", "hddl", "ipc2002"];
const SATELLITE: &str = "ipc2002-temporal/satellite-time-simple-automatic";
const SATELLITE_TIME: &str = "ipc2002-temporal/satellite-time-automatic";
/// Every plan must be valid from VAL's default tolerance down to this one.
const TOLERANCES: [f64; 2] = [Options::DEFAULT_TOLERANCE, 0.0001];
const HDDL: &str = "ipc2020-hddl/partial-order";
const IPC2002: &str = "ipc2002-temporal";

/// The shared corpora: `HIPOP_CORPORA`, or `../shared/corpora` beside the repository.
fn corpora() -> PathBuf {
    std::env::var_os("HIPOP_CORPORA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora"))
}

const HELP: &str = "\
cargo bench -p hipop-analyzer --bench plan -- [SUITE…] [OPTIONS]

SUITES: survivors satellite satellite-time satellite-abstract surveillance hddl ipc2002
        (default: all but ipc2002)
        ipc2002: the first 10 problems (--per-domain) of every set of the IPC 2002
        temporal corpus (Depots, DriverLog, Rovers, Satellite, ZenoTravel; time,
        time-simple and complex; automatic and hand-coded)
        survivors-repair (plan each initial problem of the survivors-repair set, then
        repair that plan for each of its 3 events with repair and repairFlat, and
        replan; report Figures 12-13 of the HiPOP paper and the issue's targets)
        surveillance-repair (plan the case study, then repair the plan after mona2 goes
        out of service at 3000 s, with --now 3000; the target: under 1 s)
        The repair suites run without the plan suites, never by default.

OPTIONS:
    --configs A,B       configurations (default: Config::MAIN; the default one for hddl;
                        survivors-repair: one, the default configuration by default);
                        NAME+anytime: the search goes on after its first plan until the
                        time limit and the best plan is kept (`hipop plan` without
                        --first); the others stop at the first plan.
                        Peers, run side by side under the same limit and validated by
                        hipop's validator (skipped, saying so, when not given):
                        vhpop: VHPOP with its 2002 competition options ($HIPOP_VHPOP:
                        the vhpop binary); pandapi: pandaPI's parser, grounder and engine
                        in PANDApro's 2023 partial-order agile configuration
                        ($HIPOP_PANDAPI: the folder holding pandaPIparser,
                        pandaPIgrounder and pandaPIengine). Their limit counts the
                        whole run, parsing and grounding included
    --time-limit S      search time limit per problem, seconds (default 60; per run, 10
                        for survivors-repair)
    --jobs N            problems planned at once, each in its own process (default 1)
    --repeat N          survivors-repair: runs of each repair, repairFlat and replan,
                        each in its own process, the three of an event taking turns;
                        the run of median time is reported (default 5)
    --out FILE.md       the report (default target/plan-bench.md; the repair suites:
                        target/repair-bench.md); the CSV is FILE.csv
    --per-domain N      hddl: only the first N problems of each domain; ipc2002: of
                        each set (default 10)
    --filter TEXT       only the problems whose DOMAIN/NAME contains TEXT
    --satellite DIR     the Satellite corpus folder (default: $HIPOP_CORPORA or ../shared/corpora)
    --hddl DIR          the IPC 2020 partial-order folder (default: $HIPOP_CORPORA or ../shared/corpora)
";

mod child;
mod jobs;
mod peers;
mod repair;
mod report;

use child::*;
use jobs::*;
use report::*;

// ---------------------------------------------------------------- arguments

#[derive(Debug, Clone)]
pub(crate) struct Args {
    pub(crate) suites: Vec<String>,
    pub(crate) configs: Option<Vec<String>>,
    /// `None`: the suite's default.
    pub(crate) time_limit: Option<f64>,
    pub(crate) jobs: usize,
    /// Runs of each survivors-repair job (the median is reported).
    pub(crate) repeat: usize,
    /// `None`: the suite's default, in the target folder.
    pub(crate) out: Option<PathBuf>,
    pub(crate) per_domain: Option<usize>,
    pub(crate) filter: Option<String>,
    pub(crate) satellite: PathBuf,
    pub(crate) hddl: PathBuf,
}

/// The workspace root: relative paths given to the bench are taken from it
/// (cargo runs benches in the package's folder).
pub(crate) fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("the analyzer is in the workspace").to_path_buf()
}

/// The target folder: this binary is `target/release/deps/plan-…`.
pub(crate) fn target_dir() -> PathBuf {
    std::env::current_exe()
        .ok()
        .and_then(|e| e.ancestors().nth(3).map(Path::to_path_buf))
        .filter(|t| t.join("release").is_dir())
        .unwrap_or_else(|| workspace().join("target"))
}

impl Args {
    /// The plan suites' time limit.
    pub(crate) fn limit(&self) -> f64 {
        self.time_limit.unwrap_or(60.0)
    }

    /// The report: `--out`, else `name` in the target folder.
    pub(crate) fn out_or(&self, name: &str) -> PathBuf {
        self.out.clone().unwrap_or_else(|| target_dir().join(name))
    }
}

pub(crate) fn from_workspace(p: &str) -> PathBuf {
    let p = PathBuf::from(p);
    if p.is_absolute() { p } else { workspace().join(p) }
}

pub(crate) fn parse_args(raw: &[String]) -> Result<Args, String> {
    let mut a = Args {
        suites: Vec::new(),
        configs: None,
        time_limit: None,
        jobs: 1,
        repeat: 5,
        out: None,
        per_domain: None,
        filter: None,
        satellite: corpora().join(SATELLITE),
        hddl: corpora().join(HDDL),
    };
    let mut it = raw.iter();
    while let Some(arg) = it.next() {
        let mut value = |name: &str| it.next().cloned().ok_or_else(|| format!("{name} needs a value"));
        match arg.as_str() {
            // cargo bench passes it to every harness = false bench.
            "--bench" => {}
            "-h" | "--help" => return Err(String::new()),
            "--configs" => {
                let v = value("--configs")?;
                let names: Vec<String> = v.split(',').filter(|s| !s.is_empty()).map(String::from).collect();
                for n in names.iter().filter(|n| !peers::PEERS.contains(&n.as_str())) {
                    Config::parse(n.strip_suffix(ANYTIME).unwrap_or(n))?;
                }
                a.configs = Some(names);
            }
            "--time-limit" => {
                let v = value("--time-limit")?;
                a.time_limit = Some(
                    v.parse().ok().filter(|&t: &f64| t > 0.0).ok_or(format!("invalid time limit `{v}`"))?,
                );
            }
            "--jobs" => {
                let v = value("--jobs")?;
                a.jobs = v.parse().ok().filter(|&n| n > 0).ok_or(format!("invalid job count `{v}`"))?;
            }
            "--repeat" => {
                let v = value("--repeat")?;
                a.repeat = v.parse().ok().filter(|&n| n > 0).ok_or(format!("invalid repeat count `{v}`"))?;
            }
            "--out" => a.out = Some(from_workspace(&value("--out")?)),
            "--per-domain" => {
                let v = value("--per-domain")?;
                a.per_domain = Some(v.parse().map_err(|_| format!("invalid count `{v}`"))?);
            }
            "--filter" => a.filter = Some(value("--filter")?),
            "--satellite" => a.satellite = from_workspace(&value("--satellite")?),
            "--hddl" => a.hddl = from_workspace(&value("--hddl")?),
            s if SUITES.contains(&s) || repair::SUITES.contains(&s) => a.suites.push(s.to_string()),
            other => return Err(format!("unexpected argument `{other}`")),
        }
    }
    if a.suites.is_empty() {
        a.suites = SUITES.iter().filter(|s| **s != "ipc2002").map(|s| s.to_string()).collect();
    }
    let repairs = a.suites.iter().filter(|s| repair::SUITES.contains(&s.as_str())).count();
    if repairs > 0 && repairs < a.suites.len() {
        return Err(format!("{} run without the plan suites", repair::SUITES.join(" and ")));
    }
    Ok(a)
}

// ---------------------------------------------------------------- main

pub(crate) fn main() -> ExitCode {
    let raw: Vec<String> = std::env::args().skip(1).collect();
    if raw.first().is_some_and(|a| a == "--one") {
        return one(&raw[1..]);
    }
    if raw.first().is_some_and(|a| a == "--repair") {
        return repair::repair_one(&raw[1..]);
    }
    let a = match parse_args(&raw) {
        Ok(a) => a,
        Err(e) => {
            if !e.is_empty() {
                eprintln!("error: {e}\n");
            }
            eprint!("{HELP}");
            return ExitCode::from(if e.is_empty() { 0 } else { 2 });
        }
    };
    if a.suites.iter().any(|s| repair::SUITES.contains(&s.as_str())) {
        return repair::run(&a, &raw);
    }
    let base = target_dir().join("plan-bench");
    let mut notes = Vec::new();
    let problems = problems(&a, &base.join("inputs"), &mut notes);
    if let Some(n) = a.per_domain.filter(|_| a.suites.iter().any(|s| s == "hddl")) {
        notes.push(format!("hddl: only the first {n} problems (by file name) of each domain"));
    }
    if a.suites.iter().any(|s| s == "ipc2002") {
        let n = a.per_domain.unwrap_or(10);
        notes.push(format!("ipc2002: the first {n} problems (by number) of each set"));
    }
    if let Some(f) = &a.filter {
        notes.push(format!("only the problems whose name contains `{f}`"));
    }
    let mut jobs = Vec::new();
    for (suite, group, problem, domain_path, problem_path) in problems {
        let configs: Vec<String> = match (&a.configs, suite) {
            (Some(c), _) => c.clone(),
            (None, "hddl" | "ipc2002") => vec![Config::DEFAULT.to_string()],
            (None, _) => Config::MAIN.iter().map(|s| s.to_string()).collect(),
        };
        for config in configs {
            if peers::PEERS.contains(&config.as_str())
                && let Some(why) = peers::missing(&config)
            {
                if !notes.contains(&why) {
                    eprintln!("{why}");
                    notes.push(why);
                }
                continue;
            }
            jobs.push(Job {
                suite,
                group: group.clone(),
                problem: problem.clone(),
                domain_path: domain_path.clone(),
                problem_path: problem_path.clone(),
                config,
            });
        }
    }
    let out = a.out_or("plan-bench.md");
    let csv_path = out.with_extension("csv");
    if let Some(dir) = out.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    eprintln!(
        "{} runs ({} s limit, {} job{}); report {}",
        jobs.len(),
        a.limit(),
        a.jobs,
        if a.jobs == 1 { "" } else { "s" },
        out.display()
    );
    let started = (now_utc(), load(), commit());
    let clock = Instant::now();
    // Rows are appended as runs finish, so an interrupted bench keeps what it measured.
    let csv = Mutex::new(std::fs::File::create(&csv_path).ok());
    if let Some(f) = csv.lock().unwrap().as_mut() {
        let _ = writeln!(f, "{CSV_HEAD}");
    }
    let next = Mutex::new(0usize);
    let results: Mutex<Vec<Option<Run>>> = Mutex::new(vec![None; jobs.len()]);
    let plans = base.join("plans");
    std::thread::scope(|scope| {
        for _ in 0..a.jobs {
            scope.spawn(|| {
                loop {
                    let i = {
                        let mut n = next.lock().unwrap();
                        let i = *n;
                        *n += 1;
                        i
                    };
                    let Some(job) = jobs.get(i) else { break };
                    let run = run_child(job, a.limit(), &plans);
                    eprintln!(
                        "[{:>4}/{}] {} {}/{} {}: {} in {}, {} expanded{}{}",
                        i + 1,
                        jobs.len(),
                        job.suite,
                        job.group,
                        job.problem,
                        job.config,
                        r_status(&run),
                        secs(Some(run.wall)),
                        run.expanded,
                        run.makespan.map(|m| format!(", makespan {m:.2}")).unwrap_or_default(),
                        if run.solved() { format!(", {}", run.validated()) } else { String::new() },
                    );
                    if let Some(f) = csv.lock().unwrap().as_mut() {
                        let _ = writeln!(f, "{}", csv_line(job, &run));
                    }
                    results.lock().unwrap()[i] = Some(run);
                }
            });
        }
    });
    let runs: Vec<Run> = results.into_inner().unwrap().into_iter().map(|r| r.unwrap_or_default()).collect();
    let md = report(
        &a,
        &raw,
        &notes,
        &jobs,
        &runs,
        (&started.0, &started.1, &started.2),
        clock.elapsed().as_secs_f64(),
    );
    let mut text = format!("{CSV_HEAD}\n");
    for (j, r) in jobs.iter().zip(&runs) {
        text += &csv_line(j, r);
        text.push('\n');
    }
    let _ = std::fs::write(&csv_path, text);
    if let Err(e) = std::fs::write(&out, &md) {
        eprintln!("error: cannot write {}: {e}", out.display());
    }
    let invalid = runs.iter().filter(|r| r.invalid()).count();
    // A peer that cannot read a domain (VHPOP and numeric effects) is its
    // limit, not a failure of the bench.
    let crashes = jobs
        .iter()
        .zip(&runs)
        .filter(|(j, r)| r.status == "crash" && !peers::PEERS.contains(&j.config.as_str()))
        .count();
    eprintln!("report: {}\ncsv: {}", out.display(), csv_path.display());
    for s in SUITES {
        let n = jobs.iter().filter(|j| j.suite == s).count();
        if n > 0 {
            let solved = jobs.iter().zip(&runs).filter(|(j, r)| j.suite == s && r.solved()).count();
            eprintln!("{s}: {solved}/{n} solved");
        }
    }
    if invalid > 0 || crashes > 0 {
        eprintln!("FAILED: {invalid} invalid plan(s), {crashes} crash(es)");
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

pub(crate) fn r_status(r: &Run) -> String {
    match r.status.as_str() {
        "solved" if r.invalid() => "SOLVED, INVALID PLAN".into(),
        "limit" => format!("limit ({})", r.detail),
        "crash" => format!("CRASH ({})", r.detail),
        "refused" | "no-plan" => format!("{} ({})", r.status, r.detail),
        s => s.into(),
    }
}
