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

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::{Read, Write as _};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant, SystemTime};

use hipop_analyzer::planner::{Config, PlannerLimits, Status};
use hipop_analyzer::validate::Options;
use hipop_analyzer::{AnalysisHost, Diagnostic, Severity};
use serde_json::{Value, json};

/// The allocator of the `hipop` binary: what it measures is what users get.
#[global_allocator]
static GLOBAL: hipop_analyzer::alloc::Counting<mimalloc::MiMalloc> =
    hipop_analyzer::alloc::Counting::new(mimalloc::MiMalloc);

const SUITES: [&str; 6] =
    ["survivors", "satellite", "satellite-time", "satellite-abstract", "surveillance", "hddl"];
const SATELLITE: &str = "ipc2002-temporal/satellite-time-simple-automatic";
const SATELLITE_TIME: &str = "ipc2002-temporal/satellite-time-automatic";
/// Every plan must be valid from VAL's default tolerance down to this one.
const TOLERANCES: [f64; 2] = [Options::DEFAULT_TOLERANCE, 0.0001];
const HDDL: &str = "ipc2020-hddl/partial-order";

/// The shared corpora: `HIPOP_CORPORA`, or `../shared/corpora` beside the repository.
fn corpora() -> PathBuf {
    std::env::var_os("HIPOP_CORPORA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora"))
}

const HELP: &str = "\
cargo bench -p hipop-analyzer --bench plan -- [SUITE…] [OPTIONS]

SUITES: survivors satellite satellite-time satellite-abstract surveillance hddl (default: all)

OPTIONS:
    --configs A,B       configurations (default: Config::MAIN; the default one for hddl)
    --time-limit S      search time limit per problem, seconds (default 60)
    --jobs N            problems planned at once, each in its own process (default 1)
    --out FILE.md       the report (default target/plan-bench.md); the CSV is FILE.csv
    --per-domain N      hddl: only the first N problems of each domain
    --filter TEXT       only the problems whose DOMAIN/NAME contains TEXT
    --satellite DIR     the Satellite corpus folder (default: $HIPOP_CORPORA or ../shared/corpora)
    --hddl DIR          the IPC 2020 partial-order folder (default: $HIPOP_CORPORA or ../shared/corpora)
";

// ---------------------------------------------------------------- arguments

#[derive(Debug, Clone)]
struct Args {
    suites: Vec<String>,
    configs: Option<Vec<String>>,
    time_limit: f64,
    jobs: usize,
    out: PathBuf,
    per_domain: Option<usize>,
    filter: Option<String>,
    satellite: PathBuf,
    hddl: PathBuf,
}

/// The workspace root: relative paths given to the bench are taken from it
/// (cargo runs benches in the package's folder).
fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("the analyzer is in the workspace").to_path_buf()
}

/// The target folder: this binary is `target/release/deps/plan-…`.
fn target_dir() -> PathBuf {
    std::env::current_exe()
        .ok()
        .and_then(|e| e.ancestors().nth(3).map(Path::to_path_buf))
        .filter(|t| t.join("release").is_dir())
        .unwrap_or_else(|| workspace().join("target"))
}

fn from_workspace(p: &str) -> PathBuf {
    let p = PathBuf::from(p);
    if p.is_absolute() { p } else { workspace().join(p) }
}

fn parse_args(raw: &[String]) -> Result<Args, String> {
    let mut a = Args {
        suites: Vec::new(),
        configs: None,
        time_limit: 60.0,
        jobs: 1,
        out: target_dir().join("plan-bench.md"),
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
                for n in &names {
                    Config::parse(n)?;
                }
                a.configs = Some(names);
            }
            "--time-limit" => {
                let v = value("--time-limit")?;
                a.time_limit = v.parse().map_err(|_| format!("invalid time limit `{v}`"))?;
            }
            "--jobs" => {
                let v = value("--jobs")?;
                a.jobs = v.parse().ok().filter(|&n| n > 0).ok_or(format!("invalid job count `{v}`"))?;
            }
            "--out" => a.out = from_workspace(&value("--out")?),
            "--per-domain" => {
                let v = value("--per-domain")?;
                a.per_domain = Some(v.parse().map_err(|_| format!("invalid count `{v}`"))?);
            }
            "--filter" => a.filter = Some(value("--filter")?),
            "--satellite" => a.satellite = from_workspace(&value("--satellite")?),
            "--hddl" => a.hddl = from_workspace(&value("--hddl")?),
            s if SUITES.contains(&s) => a.suites.push(s.to_string()),
            other => return Err(format!("unexpected argument `{other}`")),
        }
    }
    if a.suites.is_empty() {
        a.suites = SUITES.iter().map(|s| s.to_string()).collect();
    }
    Ok(a)
}

// ---------------------------------------------------------------- the child: one problem

/// Peak resident memory of this process, in KiB.
fn vm_hwm(pid: Option<u32>) -> Option<u64> {
    let path = match pid {
        Some(p) => format!("/proc/{p}/status"),
        None => "/proc/self/status".to_string(),
    };
    let status = std::fs::read_to_string(path).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The first error of a validation, located in the plan when it is there.
fn first_error(
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

/// `--one DOMAIN PROBLEM CONFIG TIME_LIMIT PLAN_PREFIX`: plans, validates,
/// writes the plans beside PLAN_PREFIX and prints one JSON line.
fn one(raw: &[String]) -> ExitCode {
    let [domain, problem, config, limit, prefix] = raw else {
        eprintln!("--one DOMAIN PROBLEM CONFIG TIME_LIMIT PLAN_PREFIX");
        return ExitCode::from(2);
    };
    let config = Config::parse(config).expect("the parent checked the configuration");
    let limit: f64 = limit.parse().expect("the parent checked the limit");
    let limits = PlannerLimits {
        time: Some(Duration::from_secs_f64(limit)),
        memory_in_use: Some(hipop_analyzer::alloc::in_use),
        ..PlannerLimits::default()
    };
    let read = |p: &str| std::fs::read_to_string(p).unwrap_or_else(|e| panic!("cannot read {p}: {e}"));
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
        let mut texts = vec![("val", "plan", plan.to_val(&header))];
        if plan.is_hierarchical() {
            texts.push(("hier", "hier.plan", plan.to_hierarchical(&header)));
        }
        let start = Instant::now();
        for (key, ext, text) in texts {
            let _ = std::fs::write(format!("{prefix}.{ext}"), &text);
            let f = host.set_file_text(&format!("bench.{ext}"), text.as_str());
            // The first tolerance at which the plan is not valid decides.
            let checks = TOLERANCES.map(|tolerance| {
                let v =
                    host.analysis().validate_plan(f, None, pf, &Options { tolerance, ..Options::default() });
                (tolerance, v)
            });
            let failed = checks.iter().position(|(_, v)| {
                !matches!(v, Ok(Some(v)) if v.valid && v.checked && v.diagnostics.iter().all(|d| d.code.id != "W0411"))
            });
            let (tolerance, v) = match failed {
                Some(i) => checks[i].clone(),
                None => checks[0].clone(),
            };
            let check = match v {
                Ok(Some(v)) => {
                    // The plans are written with every dependent happening
                    // ε apart: one closer (W0411) is a planner bug too.
                    let close = v.diagnostics.iter().find(|d| d.code.id == "W0411");
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
        }
        out["validate"] = json!(start.elapsed().as_secs_f64());
    }
    out["rss_kb"] = json!(vm_hwm(None));
    println!("{out}");
    ExitCode::SUCCESS
}

// ---------------------------------------------------------------- the jobs

#[derive(Debug, Clone)]
struct Job {
    suite: &'static str,
    /// The domain folder for hddl, else the suite.
    group: String,
    problem: String,
    domain_path: PathBuf,
    problem_path: PathBuf,
    config: String,
}

/// What one run gave.
#[derive(Debug, Clone, Default)]
struct Run {
    status: String,
    detail: String,
    wall: f64,
    search: f64,
    expanded: u64,
    generated: u64,
    operators: u64,
    methods: u64,
    makespan: Option<f64>,
    length: Option<u64>,
    abstract_steps: Option<u64>,
    /// VAL text's validation: (valid, first error).
    val: Option<(bool, Option<String>)>,
    /// Hierarchical text's, when the plan has abstract steps.
    hier: Option<(bool, Option<String>)>,
    rss_kb: Option<u64>,
    /// The first flaw of the best partial plan when unsolved.
    flaw: Option<String>,
}

impl Run {
    fn solved(&self) -> bool {
        self.status == "solved"
    }

    fn invalid(&self) -> bool {
        self.solved() && (self.val.as_ref().is_none_or(|v| !v.0) || self.hier.as_ref().is_some_and(|h| !h.0))
    }

    fn nodes_per_s(&self) -> Option<f64> {
        (self.search > 0.0).then(|| self.expanded as f64 / self.search)
    }

    fn validated(&self) -> String {
        if !self.solved() {
            return "–".into();
        }
        let part = |name: &str, v: &Option<(bool, Option<String>)>| match v {
            Some((true, _)) => format!("{name} ok"),
            Some((false, e)) => format!("**{name} INVALID**: {}", e.as_deref().unwrap_or("?")),
            None => format!("**{name} not validated**"),
        };
        let mut s = part("VAL", &self.val);
        if self.hier.is_some() {
            s += ", ";
            s += &part("hier", &self.hier);
        }
        s
    }
}

fn check_of(v: &Value) -> Option<(bool, Option<String>)> {
    if v.is_null() {
        return None;
    }
    Some((v["valid"].as_bool().unwrap_or(false), v["error"].as_str().map(String::from)))
}

fn parse_run(line: &str) -> Option<Run> {
    let v: Value = serde_json::from_str(line).ok()?;
    Some(Run {
        status: v["status"].as_str()?.to_string(),
        detail: v["detail"].as_str().unwrap_or("").to_string(),
        wall: v["wall"].as_f64()?,
        search: v["search"].as_f64()?,
        expanded: v["expanded"].as_u64()?,
        generated: v["generated"].as_u64()?,
        operators: v["operators"].as_u64().unwrap_or(0),
        methods: v["methods"].as_u64().unwrap_or(0),
        makespan: v["makespan"].as_f64(),
        length: v["length"].as_u64(),
        abstract_steps: v["abstract"].as_u64(),
        val: check_of(&v["val"]),
        hier: check_of(&v["hier"]),
        rss_kb: v["rss_kb"].as_u64(),
        flaw: v["flaw"].as_str().map(String::from),
    })
}

/// Plans one job in a child process; kills it well after its time limit
/// (grounding is not under the search's limit, but must end too).
fn run_child(job: &Job, limit: f64, plans: &Path) -> Run {
    // By domain too: HDDL domains share problem names (`pfile01`).
    let prefix = plans.join(job.suite).join(&job.group).join(format!("{}.{}", job.problem, job.config));
    let _ = std::fs::create_dir_all(prefix.parent().expect("a plan folder"));
    let exe = std::env::current_exe().expect("the bench binary");
    let child = Command::new(exe)
        .arg("--one")
        .arg(&job.domain_path)
        .arg(&job.problem_path)
        .arg(&job.config)
        .arg(limit.to_string())
        .arg(&prefix)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            return Run { status: "crash".into(), detail: format!("cannot start: {e}"), ..Run::default() };
        }
    };
    let pid = child.id();
    let reader = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = r.read_to_string(&mut s);
            s
        })
    };
    let out = reader(Box::new(child.stdout.take().expect("piped")));
    let err = reader(Box::new(child.stderr.take().expect("piped")));
    let start = Instant::now();
    let deadline = Duration::from_secs_f64(limit * 2.0 + 60.0);
    let mut hwm = None;
    let mut killed = false;
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break Some(s),
            Ok(None) => {}
            Err(_) => break None,
        }
        hwm = vm_hwm(Some(pid)).or(hwm);
        if start.elapsed() > deadline && !killed {
            let _ = child.kill();
            killed = true;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let wall = start.elapsed().as_secs_f64();
    let out = out.join().unwrap_or_default();
    let err = err.join().unwrap_or_default();
    let last_err = err.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("").to_string();
    match out.lines().rev().find_map(parse_run) {
        Some(run) if status.is_some_and(|s| s.success()) => run,
        _ if killed => Run {
            status: "limit".into(),
            detail: format!("killed by the harness after {wall:.0} s"),
            wall,
            rss_kb: hwm,
            ..Run::default()
        },
        _ => Run {
            status: "crash".into(),
            detail: format!(
                "{}: {}",
                status.map(|s| s.to_string()).unwrap_or_else(|| "no status".into()),
                if last_err.is_empty() { "(no message)" } else { &last_err }
            ),
            wall,
            rss_kb: hwm,
            ..Run::default()
        },
    }
}

/// Problems of the suites, as (suite, group, problem name, domain, problem) — generated
/// inputs are written under `inputs`. Skipped suites are reported in `notes`.
fn problems(
    a: &Args,
    inputs: &Path,
    notes: &mut Vec<String>,
) -> Vec<(&'static str, String, String, PathBuf, PathBuf)> {
    let mut out = Vec::new();
    let write = |dir: &Path, files: &[(String, String)]| -> Vec<PathBuf> {
        std::fs::create_dir_all(dir).expect("the inputs folder");
        files
            .iter()
            .map(|(name, text)| {
                let p = dir.join(name);
                std::fs::write(&p, text).expect("an input file");
                p
            })
            .collect()
    };
    let stem = |p: &Path| p.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
    for suite in SUITES {
        if !a.suites.iter().any(|s| s == suite) {
            continue;
        }
        match suite {
            "survivors" => {
                let files = hipop_samplegen::survivors(hipop_samplegen::DEFAULT_SEED, false);
                let paths = write(&inputs.join("survivors"), &files);
                for p in &paths[1..] {
                    out.push((suite, suite.to_string(), stem(p), paths[0].clone(), p.clone()));
                }
            }
            "satellite" | "satellite-time" | "satellite-abstract" => {
                let corpus = if suite == "satellite-time" {
                    corpora().join(SATELLITE_TIME)
                } else {
                    a.satellite.clone()
                };
                if !corpus.join("domain.pddl").is_file() {
                    let note = format!("{suite}: skipped, no corpus at {}", corpus.display());
                    eprintln!("{note}");
                    notes.push(note);
                    continue;
                }
                if suite == "satellite-abstract" {
                    match hipop_samplegen::satellite::satellite_abstract(&a.satellite) {
                        Ok(files) => {
                            let paths = write(&inputs.join(suite), &files);
                            for p in &paths[1..] {
                                out.push((suite, suite.to_string(), stem(p), paths[0].clone(), p.clone()));
                            }
                        }
                        Err(e) => {
                            let note = format!("{suite}: skipped, {e}");
                            eprintln!("{note}");
                            notes.push(note);
                        }
                    }
                } else {
                    let dir = corpus.join("instances");
                    let mut ps: Vec<PathBuf> = std::fs::read_dir(&dir)
                        .map(|d| {
                            d.flatten()
                                .map(|e| e.path())
                                .filter(|p| p.extension().is_some_and(|e| e == "pddl"))
                                .collect()
                        })
                        .unwrap_or_default();
                    ps.sort_by_key(|p| {
                        let digits: String = stem(p).chars().filter(char::is_ascii_digit).collect();
                        (digits.parse::<u64>().unwrap_or(u64::MAX), stem(p))
                    });
                    for p in ps {
                        out.push((suite, suite.to_string(), stem(&p), corpus.join("domain.pddl"), p));
                    }
                }
            }
            "surveillance" => {
                let dir = workspace().join("samples/surveillance");
                out.push((
                    suite,
                    suite.to_string(),
                    "problem".into(),
                    dir.join("domain.pddl"),
                    dir.join("problem.pddl"),
                ));
            }
            "hddl" => {
                let Ok(entries) = std::fs::read_dir(&a.hddl) else {
                    let note = format!("hddl: skipped, no corpus at {}", a.hddl.display());
                    eprintln!("{note}");
                    notes.push(note);
                    continue;
                };
                let mut dirs: Vec<PathBuf> =
                    entries.flatten().map(|e| e.path()).filter(|p| p.is_dir()).collect();
                dirs.sort();
                for dir in dirs {
                    let group = dir.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
                    let mut ps: Vec<PathBuf> = std::fs::read_dir(&dir)
                        .map(|d| {
                            d.flatten()
                                .map(|e| e.path())
                                .filter(|p| {
                                    let name = p
                                        .file_name()
                                        .map(|n| n.to_string_lossy().to_string())
                                        .unwrap_or_default();
                                    name.ends_with(".hddl")
                                        && name != "domain.hddl"
                                        && !name.ends_with("-domain.hddl")
                                })
                                .collect()
                        })
                        .unwrap_or_default();
                    ps.sort();
                    let shared = dir.join("domain.hddl");
                    let mut taken = 0;
                    for p in ps {
                        let domain = if shared.is_file() {
                            shared.clone()
                        } else {
                            dir.join(format!("{}-domain.hddl", stem(&p)))
                        };
                        if !domain.is_file() {
                            notes.push(format!("hddl: {group}/{}: no domain file, skipped", stem(&p)));
                            continue;
                        }
                        if a.per_domain.is_some_and(|n| taken >= n) {
                            break;
                        }
                        taken += 1;
                        out.push((suite, group.clone(), stem(&p), domain, p));
                    }
                }
            }
            _ => unreachable!(),
        }
    }
    if let Some(f) = &a.filter {
        out.retain(|(_, domain, name, _, _)| format!("{domain}/{name}").contains(f.as_str()));
    }
    out
}

// ---------------------------------------------------------------- the report

fn median(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return None;
    }
    let n = v.len();
    Some(if n % 2 == 1 { v[n / 2] } else { (v[n / 2 - 1] + v[n / 2]) / 2.0 })
}

fn secs(x: Option<f64>) -> String {
    match x {
        None => "–".into(),
        Some(x) if x < 10.0 => format!("{x:.3} s"),
        Some(x) => format!("{x:.1} s"),
    }
}

fn mb(kb: Option<u64>) -> String {
    kb.map(|k| format!("{:.0} MB", k as f64 / 1024.0)).unwrap_or("–".into())
}

fn rate(x: Option<f64>) -> String {
    x.map(|r| format!("{r:.0}")).unwrap_or("–".into())
}

/// Civil date of the Unix day `days` (Howard Hinnant's algorithm).
fn civil(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

fn now_utc() -> String {
    let s = SystemTime::now().duration_since(SystemTime::UNIX_EPOCH).map(|d| d.as_secs() as i64).unwrap_or(0);
    let (y, m, d) = civil(s.div_euclid(86_400));
    let t = s.rem_euclid(86_400);
    format!("{y}-{m:02}-{d:02} {:02}:{:02} UTC", t / 3600, t / 60 % 60)
}

fn machine() -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model = cpuinfo
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map(|s| s.trim().to_string())
        .unwrap_or("unknown CPU".into());
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    let mem = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| m.lines().find(|l| l.starts_with("MemTotal:")).map(String::from))
        .and_then(|l| l.split_whitespace().nth(1).and_then(|k| k.parse::<f64>().ok()))
        .map(|k| format!(", {:.0} GiB RAM", k / 1048576.0))
        .unwrap_or_default();
    format!("{model}, {cores} core{}{mem}", if cores == 1 { "" } else { "s" })
}

fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or("?".into())
}

/// The commit measured, `+dirty` when the worktree has changes.
fn commit() -> String {
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .current_dir(workspace())
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["log", "-1", "--format=%h %s"]) {
        Some(c) => {
            let dirty =
                git(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
            let main = git(&["log", "-1", "--format=%h", "main"])
                .map(|m| format!(", branch main at `{m}`"))
                .unwrap_or_default();
            format!("`{c}`{}{main}", if dirty { " (+ uncommitted changes)" } else { "" })
        }
        None => "unknown (no git)".into(),
    }
}

fn status_cell(r: &Run) -> String {
    match r.status.as_str() {
        "solved" if r.invalid() => "**solved, INVALID**".into(),
        "solved" => "solved".into(),
        "limit" => format!("limit ({})", r.detail),
        "crash" => "**crash**".into(),
        s => s.into(),
    }
}

/// Summary rows of `runs` per configuration.
fn summary(out: &mut String, label: &str, configs: &[String], runs: &[(&Job, &Run)]) {
    for c in configs {
        let rs: Vec<&Run> = runs.iter().filter(|(j, _)| &j.config == c).map(|(_, r)| *r).collect();
        if rs.is_empty() {
            continue;
        }
        let count = |s: &str| rs.iter().filter(|r| r.status == s).count();
        let solved: Vec<f64> = rs.iter().filter(|r| r.solved()).map(|r| r.wall).collect();
        let expanded: u64 = rs.iter().map(|r| r.expanded).sum();
        let search: f64 = rs.iter().map(|r| r.search).sum();
        let rss: Vec<f64> = rs.iter().filter_map(|r| r.rss_kb).map(|k| k as f64).collect();
        let invalid = rs.iter().filter(|r| r.invalid()).count();
        let _ = writeln!(
            out,
            "| {label} | {c} | {}/{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            solved.len(),
            rs.len(),
            count("no-plan"),
            count("limit"),
            count("refused"),
            count("crash"),
            if invalid > 0 { format!("**{invalid}**") } else { "0".into() },
            secs(median(solved.clone())),
            secs(solved.iter().copied().reduce(f64::max)),
            rate((search > 0.0).then(|| expanded as f64 / search)),
            mb(median(rss.clone()).map(|k| k as u64)),
            mb(rss.iter().copied().reduce(f64::max).map(|k| k as u64)),
        );
    }
}

const SUMMARY_HEAD: &str = "| suite | configuration | solved | no plan | limit | refused | crash | invalid | median time (solved) | max time (solved) | nodes/s (all runs) | median peak RSS | max peak RSS |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";

/// `p-t2-r3-z9-s4` → (teams, rows, zone size, survivors).
fn survivors_params(stem: &str) -> Option<[u64; 4]> {
    let mut v = [0; 4];
    let parts: Vec<&str> = stem.split('-').skip(1).collect();
    for (i, (part, prefix)) in parts.iter().zip(["t", "r", "z", "s"]).enumerate() {
        v[i] = part.strip_prefix(prefix)?.parse().ok()?;
    }
    (parts.len() == 4).then_some(v)
}

fn growth(out: &mut String, configs: &[String], runs: &[(&Job, &Run)]) {
    let _ = writeln!(
        out,
        "\nHow time grows with the problem's size: per value of one parameter (the others vary over the whole grid), solved runs / runs and the median planning time **over all runs** (an unsolved run counts at the time it stopped, about the limit: a median at the limit means most runs were not solved).\n"
    );
    for (i, name) in ["teams", "rows", "locations per zone", "survivors"].iter().enumerate() {
        let mut head = format!("| {name} |");
        let mut rule = "|---|".to_string();
        for c in configs {
            head += &format!(" {c} |");
            rule += "---|";
        }
        let _ = writeln!(out, "{head}\n{rule}");
        let mut values: Vec<u64> =
            runs.iter().filter_map(|(j, _)| survivors_params(&j.problem)).map(|p| p[i]).collect();
        values.sort();
        values.dedup();
        for v in values {
            let mut row = format!("| {v} |");
            for c in configs {
                let rs: Vec<&Run> = runs
                    .iter()
                    .filter(|(j, _)| {
                        &j.config == c && survivors_params(&j.problem).is_some_and(|p| p[i] == v)
                    })
                    .map(|(_, r)| *r)
                    .collect();
                let solved = rs.iter().filter(|r| r.solved()).count();
                row += &format!(
                    " {solved}/{}, {} |",
                    rs.len(),
                    secs(median(rs.iter().map(|r| r.wall).collect()))
                );
            }
            let _ = writeln!(out, "{row}");
        }
        out.push('\n');
    }
}

fn report(
    a: &Args,
    raw: &[String],
    notes: &[String],
    jobs: &[Job],
    runs: &[Run],
    // (date, load average, commit) when the bench started.
    started: (&str, &str, &str),
    took: f64,
) -> String {
    let mut out = String::new();
    let pairs: Vec<(&Job, &Run)> = jobs.iter().zip(runs).collect();
    let invalid: Vec<&(&Job, &Run)> = pairs.iter().filter(|(_, r)| r.invalid()).collect();
    let crashes = pairs.iter().filter(|(_, r)| r.status == "crash").count();
    let _ = writeln!(out, "# Planner benchmark\n");
    let _ = writeln!(out, "- machine: {}", machine());
    let _ = writeln!(out, "- date: {} (finished {}, {:.0} min)", started.0, now_utc(), took / 60.0);
    let _ = writeln!(out, "- commit: {}", started.2);
    let _ = writeln!(out, "- load average: {} at the start, {} at the end", started.1, load());
    let _ = writeln!(
        out,
        "- command: `cargo bench -p hipop-analyzer --bench plan --{}`",
        raw.iter().filter(|s| *s != "--bench").map(|s| format!(" {s}")).collect::<String>()
    );
    let _ = writeln!(
        out,
        "- search time limit {} s per problem and configuration; {} job{} at once, each problem in its own process (peak RSS = its VmHWM)",
        a.time_limit,
        a.jobs,
        if a.jobs == 1 { "" } else { "s" }
    );
    let _ = writeln!(
        out,
        "- time = planning wall time in the child (grounding, task compilation, heuristic, search); nodes/s = plans expanded / search time; length = primitive actions; every plan found is validated (its VAL text, and its hierarchical text when it has abstract steps)"
    );
    for n in notes {
        let _ = writeln!(out, "- {n}");
    }
    out.push('\n');
    if invalid.is_empty() {
        let _ = writeln!(out, "**Every plan found is valid.**\n");
    } else {
        let _ = writeln!(
            out,
            "## **{} INVALID PLAN{}**\n",
            invalid.len(),
            if invalid.len() == 1 { "" } else { "S" }
        );
        let _ = writeln!(out, "| suite | problem | configuration | validation |\n|---|---|---|---|");
        for (j, r) in &invalid {
            let _ = writeln!(
                out,
                "| {} | {}/{} | {} | {} |",
                j.suite,
                j.group,
                j.problem,
                j.config,
                r.validated()
            );
        }
        out.push('\n');
    }
    if crashes > 0 {
        let _ = writeln!(
            out,
            "**{crashes} run{} crashed** (see the tables).\n",
            if crashes == 1 { "" } else { "s" }
        );
    }
    let _ = writeln!(out, "## Summary\n\n{SUMMARY_HEAD}");
    out.pop();
    let mut suites: Vec<&str> = jobs.iter().map(|j| j.suite).collect();
    suites.dedup();
    let configs_of = |s: &str| {
        let mut cs: Vec<String> = Vec::new();
        for j in jobs.iter().filter(|j| j.suite == s) {
            if !cs.contains(&j.config) {
                cs.push(j.config.clone());
            }
        }
        cs
    };
    for s in &suites {
        let rs: Vec<(&Job, &Run)> = pairs.iter().filter(|(j, _)| j.suite == *s).copied().collect();
        summary(&mut out, s, &configs_of(s), &rs);
    }
    for s in &suites {
        let configs = configs_of(s);
        let rs: Vec<(&Job, &Run)> = pairs.iter().filter(|(j, _)| j.suite == *s).copied().collect();
        let _ = writeln!(out, "\n## {s}");
        let mut groups: Vec<&str> = rs.iter().map(|(j, _)| j.group.as_str()).collect();
        groups.dedup();
        if groups.len() > 1 {
            let _ = write!(out, "\n{}", SUMMARY_HEAD.replacen("| suite |", "| domain |", 1));
            for g in &groups {
                let gs: Vec<(&Job, &Run)> = rs.iter().filter(|(j, _)| j.group == *g).copied().collect();
                summary(&mut out, g, &configs, &gs);
            }
        }
        if *s == "survivors" {
            growth(&mut out, &configs, &rs);
        }
        let name =
            |j: &Job| if groups.len() > 1 { format!("{}/{}", j.group, j.problem) } else { j.problem.clone() };
        let unsolved: Vec<&(&Job, &Run)> = rs.iter().filter(|(_, r)| !r.solved()).collect();
        if !unsolved.is_empty() {
            // reason → configuration → problems
            let mut why: BTreeMap<String, BTreeMap<&str, Vec<String>>> = BTreeMap::new();
            for (j, r) in &unsolved {
                let reason = match r.status.as_str() {
                    "limit" => format!("limit: {}", r.detail),
                    "no-plan" => "no plan: the search space within the allowed actions and the methods is exhausted (E0502)".into(),
                    _ => format!("{}: {}", r.status, r.detail),
                };
                why.entry(reason).or_default().entry(j.config.as_str()).or_default().push(name(j));
            }
            let _ = writeln!(out, "\nNot solved, by reason:\n");
            for (reason, by_config) in why {
                let _ = writeln!(out, "- {reason}");
                for (config, problems) in by_config {
                    let list = if problems.len() <= 12 {
                        problems.join(", ")
                    } else {
                        format!("{}, … {}", problems[..6].join(", "), problems[problems.len() - 1])
                    };
                    let _ = writeln!(out, "  - {config}: {} ({list})", problems.len());
                }
            }
        }
        let _ = writeln!(
            out,
            "\n| problem | configuration | status | time | search | expanded | nodes/s | makespan | length | abstract | validated | peak RSS |\n|---|---|---|---|---|---|---|---|---|---|---|---|"
        );
        for (j, r) in &rs {
            let name = name(j);
            let _ = writeln!(
                out,
                "| {name} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                j.config,
                status_cell(r),
                secs(Some(r.wall)),
                secs(Some(r.search)),
                r.expanded,
                rate(r.nodes_per_s()),
                r.makespan.map(|m| format!("{m:.2}")).unwrap_or("–".into()),
                r.length.map(|l| l.to_string()).unwrap_or("–".into()),
                r.abstract_steps.map(|l| l.to_string()).unwrap_or("–".into()),
                r.validated(),
                mb(r.rss_kb),
            );
        }
    }
    out
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

const CSV_HEAD: &str = "suite,domain,problem,config,status,detail,time_s,search_s,expanded,generated,nodes_per_s,operators,method_instances,makespan,length,abstract_steps,val_valid,hier_valid,validation_error,peak_rss_kb,best_plan_first_flaw";

fn csv_line(j: &Job, r: &Run) -> String {
    let opt = |x: Option<String>| x.unwrap_or_default();
    let valid = |v: &Option<(bool, Option<String>)>| opt(v.as_ref().map(|v| v.0.to_string()));
    let error = r.val.iter().chain(r.hier.iter()).find_map(|v| v.1.clone()).unwrap_or_default();
    [
        j.suite.to_string(),
        j.group.clone(),
        j.problem.clone(),
        j.config.clone(),
        r.status.clone(),
        r.detail.clone(),
        format!("{:.4}", r.wall),
        format!("{:.4}", r.search),
        r.expanded.to_string(),
        r.generated.to_string(),
        opt(r.nodes_per_s().map(|x| format!("{x:.0}"))),
        r.operators.to_string(),
        r.methods.to_string(),
        opt(r.makespan.map(|m| format!("{m:.3}"))),
        opt(r.length.map(|l| l.to_string())),
        opt(r.abstract_steps.map(|l| l.to_string())),
        valid(&r.val),
        valid(&r.hier),
        error,
        opt(r.rss_kb.map(|k| k.to_string())),
        opt(r.flaw.clone()),
    ]
    .iter()
    .map(|f| csv_field(f))
    .collect::<Vec<_>>()
    .join(",")
}

// ---------------------------------------------------------------- main

fn main() -> ExitCode {
    let raw: Vec<String> = std::env::args().skip(1).collect();
    if raw.first().is_some_and(|a| a == "--one") {
        return one(&raw[1..]);
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
    let base = target_dir().join("plan-bench");
    let mut notes = Vec::new();
    let problems = problems(&a, &base.join("inputs"), &mut notes);
    if let Some(n) = a.per_domain {
        notes.push(format!("hddl: only the first {n} problems (by file name) of each domain"));
    }
    if let Some(f) = &a.filter {
        notes.push(format!("only the problems whose name contains `{f}`"));
    }
    let mut jobs = Vec::new();
    for (suite, group, problem, domain_path, problem_path) in problems {
        let configs: Vec<String> = match (&a.configs, suite) {
            (Some(c), _) => c.clone(),
            (None, "hddl") => vec![Config::DEFAULT.to_string()],
            (None, _) => Config::MAIN.iter().map(|s| s.to_string()).collect(),
        };
        for config in configs {
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
    let csv_path = a.out.with_extension("csv");
    if let Some(dir) = a.out.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    eprintln!(
        "{} runs ({} s limit, {} job{}); report {}",
        jobs.len(),
        a.time_limit,
        a.jobs,
        if a.jobs == 1 { "" } else { "s" },
        a.out.display()
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
                    let run = run_child(job, a.time_limit, &plans);
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
    if let Err(e) = std::fs::write(&a.out, &md) {
        eprintln!("error: cannot write {}: {e}", a.out.display());
    }
    let invalid = runs.iter().filter(|r| r.invalid()).count();
    let crashes = runs.iter().filter(|r| r.status == "crash").count();
    eprintln!("report: {}\ncsv: {}", a.out.display(), csv_path.display());
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

fn r_status(r: &Run) -> String {
    match r.status.as_str() {
        "solved" if r.invalid() => "SOLVED, INVALID PLAN".into(),
        "limit" => format!("limit ({})", r.detail),
        "crash" => format!("CRASH ({})", r.detail),
        "refused" | "no-plan" => format!("{} ({})", r.status, r.detail),
        s => s.into(),
    }
}
