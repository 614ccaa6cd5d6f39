//! The jobs: the problems of each suite, and running each in a child process.

use std::ffi::OsString;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use super::*;

#[derive(Debug, Clone)]
pub(crate) struct Job {
    pub(crate) suite: &'static str,
    /// The domain folder for hddl, else the suite.
    pub(crate) group: String,
    pub(crate) problem: String,
    pub(crate) domain_path: PathBuf,
    pub(crate) problem_path: PathBuf,
    pub(crate) config: String,
}

/// What one run gave.
#[derive(Debug, Clone, Default)]
pub(crate) struct Run {
    pub(crate) status: String,
    pub(crate) detail: String,
    pub(crate) wall: f64,
    pub(crate) search: f64,
    pub(crate) expanded: u64,
    pub(crate) generated: u64,
    pub(crate) operators: u64,
    pub(crate) methods: u64,
    pub(crate) makespan: Option<f64>,
    pub(crate) length: Option<u64>,
    pub(crate) abstract_steps: Option<u64>,
    /// VAL text's validation: (valid, first error).
    pub(crate) val: Option<(bool, Option<String>)>,
    /// Hierarchical text's, when the plan has abstract steps.
    pub(crate) hier: Option<(bool, Option<String>)>,
    pub(crate) rss_kb: Option<u64>,
    /// Primitive steps that can be removed, for a plan without abstract steps.
    pub(crate) redundant: Option<u64>,
    /// Steps the planner removed as redundant before returning the plan,
    /// and the seconds that took.
    pub(crate) removed: u64,
    pub(crate) removal: f64,
    /// The first flaw of the best partial plan when unsolved.
    pub(crate) flaw: Option<String>,
}

impl Run {
    pub(crate) fn solved(&self) -> bool {
        self.status == "solved"
    }

    pub(crate) fn invalid(&self) -> bool {
        self.solved() && (self.val.as_ref().is_none_or(|v| !v.0) || self.hier.as_ref().is_some_and(|h| !h.0))
    }

    pub(crate) fn nodes_per_s(&self) -> Option<f64> {
        (self.search > 0.0).then(|| self.expanded as f64 / self.search)
    }

    pub(crate) fn validated(&self) -> String {
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

pub(crate) fn check_of(v: &Value) -> Option<(bool, Option<String>)> {
    if v.is_null() {
        return None;
    }
    Some((v["valid"].as_bool().unwrap_or(false), v["error"].as_str().map(String::from)))
}

pub(crate) fn parse_run(line: &str) -> Option<Run> {
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
        redundant: v["redundant"].as_u64(),
        removed: v["removed"].as_u64().unwrap_or(0),
        removal: v["removal"].as_f64().unwrap_or(0.0),
        flaw: v["flaw"].as_str().map(String::from),
    })
}

/// Plans one job in a child process; kills it well after its time limit
/// (grounding is not under the search's limit, but must end too).
pub(crate) fn run_child(job: &Job, limit: f64, plans: &Path) -> Run {
    // By domain too: HDDL domains share problem names (`pfile01`).
    let prefix = plans.join(job.suite).join(&job.group).join(format!("{}.{}", job.problem, job.config));
    let _ = std::fs::create_dir_all(prefix.parent().expect("a plan folder"));
    let args: Vec<OsString> = vec![
        "--one".into(),
        job.domain_path.clone().into(),
        job.problem_path.clone().into(),
        job.config.clone().into(),
        limit.to_string().into(),
        prefix.into(),
    ];
    let c = spawn_child(&args, limit);
    match c.line.as_deref().and_then(parse_run) {
        Some(run) if c.success => run,
        _ => Run { status: c.status(), detail: c.detail(), wall: c.wall, rss_kb: c.hwm, ..Run::default() },
    }
}

/// How a child process ended.
pub(crate) struct ChildEnd {
    /// Its last line of standard output that is a JSON object.
    pub(crate) line: Option<String>,
    /// Its whole standard output.
    pub(crate) out: String,
    pub(crate) success: bool,
    pub(crate) killed: bool,
    pub(crate) exit: Option<std::process::ExitStatus>,
    pub(crate) wall: f64,
    /// Its peak resident memory, as last seen (KiB).
    pub(crate) hwm: Option<u64>,
    pub(crate) last_err: String,
}

impl ChildEnd {
    /// `limit` when the harness killed it, else `crash`.
    pub(crate) fn status(&self) -> String {
        if self.killed { "limit".into() } else { "crash".into() }
    }

    pub(crate) fn detail(&self) -> String {
        if self.killed {
            format!("killed by the harness after {:.0} s", self.wall)
        } else {
            format!(
                "{}: {}",
                self.exit.map(|s| s.to_string()).unwrap_or_else(|| "no status".into()),
                if self.last_err.is_empty() { "(no message)" } else { &self.last_err }
            )
        }
    }
}

/// Runs this binary again with `args`, killing it `limit × 2 + 60` seconds
/// after it started.
pub(crate) fn spawn_child(args: &[OsString], limit: f64) -> ChildEnd {
    let exe = std::env::current_exe().expect("the bench binary");
    let mut command = Command::new(exe);
    command.args(args);
    spawn_until(command, Duration::from_secs_f64(limit * 2.0 + 60.0))
}

/// Runs `command`, killing it once `deadline` has passed since it started,
/// and watches its peak resident memory.
pub(crate) fn spawn_until(mut command: Command, deadline: Duration) -> ChildEnd {
    let child = command.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            return ChildEnd {
                line: None,
                out: String::new(),
                success: false,
                killed: false,
                exit: None,
                wall: 0.0,
                hwm: None,
                last_err: format!("cannot start: {e}"),
            };
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
        std::thread::sleep(Duration::from_millis(20));
    };
    let wall = start.elapsed().as_secs_f64();
    let out = out.join().unwrap_or_default();
    let err = err.join().unwrap_or_default();
    ChildEnd {
        line: out.lines().rev().find(|l| l.trim_start().starts_with('{')).map(String::from),
        out,
        success: status.is_some_and(|s| s.success()),
        killed,
        exit: status,
        wall,
        hwm,
        last_err: err.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("").to_string(),
    }
}

/// The `.pddl` files of a corpus set's `instances` folder, by the number in
/// their names (`instance-2` before `instance-10`).
fn instances(dir: &Path) -> Vec<PathBuf> {
    let stem = |p: &Path| p.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
    let mut ps: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| {
            d.flatten().map(|e| e.path()).filter(|p| p.extension().is_some_and(|e| e == "pddl")).collect()
        })
        .unwrap_or_default();
    ps.sort_by_key(|p| {
        let digits: String = stem(p).chars().filter(char::is_ascii_digit).collect();
        (digits.parse::<u64>().unwrap_or(u64::MAX), stem(p))
    });
    ps
}

/// Problems of the suites, as (suite, group, problem name, domain, problem) — generated
/// inputs are written under `inputs`. Skipped suites are reported in `notes`.
pub(crate) fn problems(
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
                    for p in instances(&corpus.join("instances")) {
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
            "ipc2002" => {
                let root = corpora().join(IPC2002);
                let Ok(entries) = std::fs::read_dir(&root) else {
                    let note = format!("ipc2002: skipped, no corpus at {}", root.display());
                    eprintln!("{note}");
                    notes.push(note);
                    continue;
                };
                let mut sets: Vec<PathBuf> = entries
                    .flatten()
                    .map(|e| e.path())
                    .filter(|p| p.join("domain.pddl").is_file() && p.join("instances").is_dir())
                    .collect();
                sets.sort();
                let per_set = a.per_domain.unwrap_or(10);
                for set in sets {
                    let group = set.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
                    for p in instances(&set.join("instances")).into_iter().take(per_set) {
                        out.push((suite, group.clone(), stem(&p), set.join("domain.pddl"), p));
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
