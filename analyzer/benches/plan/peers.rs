//! Peer planners run side by side with hipop, in the same bench run and
//! under the same limit: `vhpop` (the temporal partial-order planner of the
//! 2002 competition) and `pandapi` (pandaPI's parser, grounder and engine
//! in PANDApro's partial-order agile configuration of the 2023
//! competition). Neither is part of the project: a bench run takes their
//! binaries from the environment and skips them, saying so, without it.
//! Their plans are validated by hipop's validator like hipop's own.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::{Duration, Instant};

use hipop_analyzer::AnalysisHost;
use serde_json::json;

use super::*;

/// The peer configurations' names.
pub(crate) const PEERS: [&str; 2] = ["vhpop", "pandapi"];

/// The variable naming a peer's binary (`vhpop`) or folder (`pandapi`).
pub(crate) fn variable(peer: &str) -> &'static str {
    match peer {
        "vhpop" => "HIPOP_VHPOP",
        _ => "HIPOP_PANDAPI",
    }
}

/// Why a peer cannot run here, when it cannot.
pub(crate) fn missing(peer: &str) -> Option<String> {
    let var = variable(peer);
    let Some(path) = std::env::var_os(var).map(PathBuf::from) else {
        return Some(format!("{peer}: skipped, {var} is not set"));
    };
    let needed: Vec<PathBuf> = match peer {
        "vhpop" => vec![path],
        _ => ["pandaPIparser", "pandaPIgrounder", "pandaPIengine"].iter().map(|b| path.join(b)).collect(),
    };
    needed.iter().find(|p| !p.is_file()).map(|p| format!("{peer}: skipped, no {} ({var})", p.display()))
}

/// VHPOP's options at the 2002 competition, as its repository's
/// `ipc3-vhpop` script gives them: ground actions, the additive heuristic
/// with reuse, and four flaw selection strategies in turn with their plan
/// limits (larger ones for durative domains).
fn vhpop_args(domain_text: &str) -> Vec<String> {
    let temporal = domain_text.contains(":durative-actions");
    let limits = if temporal { ["12000", "100000", "240000"] } else { ["10000", "100000", "200000"] };
    let mut args: Vec<String> = vec!["-g".into(), "-h".into(), "ADDR/ADDR_WORK/BUC/LIFO".into()];
    let orders = [
        ("{n,s}LR/{l}MW_add", limits[0]),
        ("{n,s}LR/{u}MW_add/{l}MW_add", limits[1]),
        ("{n,s,l}LR", limits[2]),
        ("{n,s,u}LR/{l}LR", "unlimited"),
    ];
    for (f, l) in orders {
        args.extend(["-f".into(), f.into(), "-l".into(), l.into()]);
    }
    args
}

/// The steps of VHPOP's output (`0.01:(walk d1 s2 p1-2)[20]`), as VAL text.
pub(crate) fn vhpop_plan(stdout: &str) -> Option<String> {
    let steps: Vec<&str> = stdout
        .lines()
        .map(str::trim)
        .filter(|l| {
            l.split_once(':').is_some_and(|(t, rest)| t.parse::<f64>().is_ok() && rest.starts_with('('))
        })
        .collect();
    (!steps.is_empty() || stdout.contains("Makespan:")).then(|| steps.join("\n") + "\n")
}

/// What one peer run gave: the plan text when it found one.
struct PeerRun {
    plan: Option<String>,
    status: &'static str,
    detail: String,
    hwm: Option<u64>,
}

fn run_vhpop(domain: &Path, problem: &Path, limit: Duration) -> PeerRun {
    let exe = std::env::var_os(variable("vhpop")).expect("checked by the parent");
    let mut c = Command::new(exe);
    c.args(vhpop_args(&read(&domain.to_string_lossy()))).arg(domain).arg(problem);
    let end = spawn_until(c, limit);
    let plan = if end.success { vhpop_plan(&end.out) } else { None };
    let (status, detail) = match (&plan, end.killed) {
        (Some(_), _) => ("solved", String::new()),
        (None, true) => ("limit", "time".to_string()),
        (None, false) if end.success => ("no-plan", first_line(&end.out)),
        (None, false) => ("crash", end.detail()),
    };
    PeerRun { plan, status, detail, hwm: end.hwm }
}

/// pandaPI as PANDApro's partial-order agile entry ran it: parse, ground
/// (`-q -i`), weighted A* with weight 2 and the RC2 heuristic over FF, then
/// the plan written in the IPC 2020 hierarchical format. The limit counts
/// the three stages.
fn run_pandapi(domain: &Path, problem: &Path, limit: Duration, work: &Path) -> PeerRun {
    let dir = PathBuf::from(std::env::var_os(variable("pandapi")).expect("checked by the parent"));
    let start = Instant::now();
    let parsed = work.with_extension("parsed");
    let grounded = work.with_extension("psas");
    let log = work.with_extension("panda.log");
    let plan_file = work.with_extension("panda.plan");
    let mut hwm = None;
    let stages: [(&str, Vec<std::ffi::OsString>); 3] = [
        ("pandaPIparser", vec![domain.into(), problem.into(), parsed.clone().into()]),
        ("pandaPIgrounder", vec!["-q".into(), "-i".into(), parsed.clone().into(), grounded.clone().into()]),
        (
            "pandaPIengine",
            vec!["--astarweight=2".into(), "--heuristic=rc2(ff)".into(), grounded.clone().into()],
        ),
    ];
    for (binary, args) in stages {
        let left = limit.saturating_sub(start.elapsed());
        let mut c = Command::new(dir.join(binary));
        c.args(&args);
        let end = spawn_until(c, left);
        hwm = hwm.max(end.hwm);
        if end.killed {
            return PeerRun { plan: None, status: "limit", detail: format!("time, in {binary}"), hwm };
        }
        if !end.success {
            return PeerRun {
                plan: None,
                status: "crash",
                detail: format!("{binary}: {}", end.detail()),
                hwm,
            };
        }
        if binary == "pandaPIengine" {
            let _ = std::fs::write(&log, &end.out);
            if !end.out.contains("==>") {
                let status = if end.out.contains("Reached time limit") { "limit" } else { "no-plan" };
                return PeerRun { plan: None, status, detail: last_line(&end.out), hwm };
            }
        }
    }
    let mut c = Command::new(dir.join("pandaPIparser"));
    c.arg("-c").arg(&log).arg(&plan_file);
    let end = spawn_until(c, Duration::from_secs(60));
    let plan = std::fs::read_to_string(&plan_file).ok().filter(|p| end.success && p.contains("==>"));
    for f in [parsed, grounded, log] {
        let _ = std::fs::remove_file(f);
    }
    match plan {
        Some(p) => PeerRun { plan: Some(p), status: "solved", detail: String::new(), hwm },
        None => PeerRun {
            plan: None,
            status: "crash",
            detail: format!("pandaPIparser -c: {}", end.detail()),
            hwm,
        },
    }
}

fn first_line(s: &str) -> String {
    s.lines().map(str::trim).find(|l| !l.is_empty()).unwrap_or("").to_string()
}

fn last_line(s: &str) -> String {
    s.lines().rev().map(str::trim).find(|l| !l.is_empty()).unwrap_or("").to_string()
}

/// `--one DOMAIN PROBLEM PEER TIME_LIMIT PLAN_PREFIX` for a peer: runs it,
/// validates its plan with hipop's validator and prints one JSON line, as
/// hipop's runs do.
pub(crate) fn peer_one(domain: &str, problem: &str, peer: &str, limit: &str, prefix: &str) -> ExitCode {
    let limit = Duration::from_secs_f64(limit.parse().expect("the parent checked the limit"));
    let start = Instant::now();
    let run = if peer == "vhpop" {
        run_vhpop(Path::new(domain), Path::new(problem), limit)
    } else {
        run_pandapi(Path::new(domain), Path::new(problem), limit, Path::new(prefix))
    };
    let wall = start.elapsed().as_secs_f64();
    let mut out = json!({
        "wall": wall, "search": wall, "expanded": 0, "generated": 0,
        "status": run.status, "detail": run.detail, "rss_kb": run.hwm,
    });
    if let Some(text) = run.plan {
        let mut host = AnalysisHost::new();
        host.set_file_text(domain, read(domain));
        let pf = host.set_file_text(problem, read(problem));
        let hierarchical = text.contains("==>");
        let key = if hierarchical { "hier" } else { "val" };
        let ext = if hierarchical { "hier.plan" } else { "plan" };
        validate_texts(&mut out, &mut host, pf, vec![(key, ext, text.clone())], prefix, false);
        if hierarchical {
            // One validation checks both: the primitive plan runs, and the
            // hierarchy decomposes the task network into it.
            out["val"] = out["hier"].clone();
        }
        out["makespan"] = out[key]["makespan"].clone();
        let steps = if hierarchical {
            let body = text.split("==>").nth(1).unwrap_or("");
            body.lines()
                .take_while(|l| !l.trim_start().starts_with("root"))
                .filter(|l| !l.trim().is_empty())
                .count()
        } else {
            text.lines().filter(|l| !l.trim().is_empty()).count()
        };
        out["length"] = json!(steps);
    }
    println!("{out}");
    ExitCode::SUCCESS
}
