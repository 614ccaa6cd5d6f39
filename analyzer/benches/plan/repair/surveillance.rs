//! The `surveillance-repair` suite: the case study's mission with a robot
//! out of service mid-mission (section 5.5 of the HiPOP paper). The mission
//! is planned; then `mona2` goes out of service at 3000 s (the generator's
//! `surveillance-lost` problem: it can no longer observe or communicate), and
//! that plan is repaired with `--now 3000` (the steps started before are
//! executed): alone, with `mona3` out of communication too (`--unreachable
//! mona3`: its plan cannot change), and flat. A replan from scratch of the
//! same problem, which ignores what was executed, is timed for reference.
//! Each repair is repeated: the report gives the median and the longest time.

use std::ffi::OsString;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::super::report::{median, secs};
use super::super::*;
use super::{Mode, RRun};

/// How many times each case runs.
pub(crate) const REPEAT: usize = 5;

/// One way of repairing the mission.
#[derive(Debug, Clone)]
pub(crate) struct Case {
    pub(crate) label: String,
    pub(crate) mode: Mode,
    pub(crate) now: Option<f64>,
    pub(crate) unreachable: Vec<String>,
}

/// The cases, their runs, and the initial plan's run.
pub(crate) struct Results {
    pub(crate) initial: Run,
    pub(crate) cases: Vec<(Case, Vec<RRun>)>,
    pub(crate) event: String,
}

fn cases() -> Vec<Case> {
    let (robot, at) = hipop_samplegen::LOST_ROBOT;
    let now = Some(at as f64);
    vec![
        Case { label: format!("repair --now {at}"), mode: Mode::Repair, now, unreachable: Vec::new() },
        Case {
            label: format!("repair --now {at} --unreachable mona3"),
            mode: Mode::Repair,
            now,
            unreachable: vec!["mona3".into()],
        },
        Case {
            label: format!("repair --flat --now {at}"),
            mode: Mode::RepairFlat,
            now,
            unreachable: Vec::new(),
        },
        Case {
            label: format!("replan from scratch (ignores what {robot} and the others executed)"),
            mode: Mode::Replan,
            now: None,
            unreachable: Vec::new(),
        },
    ]
}

/// Plans the mission, then runs every case [`REPEAT`] times.
pub(crate) fn run(config: &str, limit: f64) -> Results {
    let (robot, at) = hipop_samplegen::LOST_ROBOT;
    let base = target_dir().join("plan-bench");
    let inputs = base.join("inputs").join("surveillance-repair");
    let plans = base.join("plans");
    std::fs::create_dir_all(&inputs).expect("the inputs folder");
    let (domain, problem) = hipop_samplegen::surveillance(hipop_samplegen::DEFAULT_SEED);
    let lost = hipop_samplegen::surveillance_lost(hipop_samplegen::DEFAULT_SEED, robot, at)
        .expect("the mission has the robot");
    let lost_name = format!("problem-lost-{robot}.pddl");
    for (name, text) in [("domain.pddl", &domain), ("problem.pddl", &problem), (lost_name.as_str(), &lost)] {
        std::fs::write(inputs.join(name), text).expect("an input file");
    }
    let job = Job {
        suite: "surveillance-repair",
        group: "initial".into(),
        problem: "problem".into(),
        domain_path: inputs.join("domain.pddl"),
        problem_path: inputs.join("problem.pddl"),
        config: config.to_string(),
    };
    let initial = run_child(&job, limit, &plans);
    eprintln!(
        "surveillance-repair: initial plan {} in {}, {} actions",
        r_status(&initial),
        secs(Some(initial.wall)),
        initial.length.map_or("–".into(), |l| l.to_string())
    );
    let event = format!("{robot} out of service from {at} s ({lost_name})");
    let mut out = Results { initial: initial.clone(), cases: Vec::new(), event };
    if !initial.solved() || initial.invalid() {
        return out;
    }
    let prefix = plans.join("surveillance-repair").join("initial").join(format!("problem.{config}"));
    let hier = PathBuf::from(format!("{}.hier.plan", prefix.display()));
    let old = if hier.is_file() { hier } else { PathBuf::from(format!("{}.plan", prefix.display())) };
    for case in cases() {
        let mut runs = Vec::new();
        // The replan is a reference: once is enough.
        let times = if case.mode == Mode::Replan { 1 } else { REPEAT };
        for k in 0..times {
            let r = run_case(&case, &inputs, &lost_name, &old, config, limit, &plans, k);
            eprintln!(
                "surveillance-repair {} [{}/{times}]: {} in {}{}{}",
                case.label,
                k + 1,
                if r.invalid() { "SOLVED, INVALID PLAN".to_string() } else { r.status.clone() },
                secs(Some(r.wall)),
                r.stage.as_ref().map(|s| format!(" ({s})")).unwrap_or_default(),
                r.instability.map(|i| format!(", instability {i}")).unwrap_or_default(),
            );
            runs.push(r);
        }
        out.cases.push((case, runs));
    }
    out
}

#[allow(clippy::too_many_arguments)]
fn run_case(
    case: &Case,
    inputs: &Path,
    lost: &str,
    old: &Path,
    config: &str,
    limit: f64,
    plans: &Path,
    k: usize,
) -> RRun {
    let name = case.label.split_whitespace().collect::<Vec<_>>().join("_").replace(['(', ')', ','], "");
    let prefix = plans.join("surveillance-repair").join("lost").join(format!("{name}.{k}"));
    let _ = std::fs::create_dir_all(prefix.parent().expect("a plan folder"));
    let mut args: Vec<OsString> = vec![
        "--repair".into(),
        case.mode.name().into(),
        inputs.join("domain.pddl").into(),
        inputs.join(lost).into(),
        old.into(),
        config.into(),
        limit.to_string().into(),
        prefix.into(),
    ];
    if let Some(now) = case.now {
        args.push("--now".into());
        args.push(now.to_string().into());
    }
    if !case.unreachable.is_empty() {
        args.push("--unreachable".into());
        args.push(case.unreachable.join(",").into());
    }
    let c = spawn_child(&args, limit);
    match c.line.as_deref().and_then(RRun::parse) {
        Some(run) if c.success => run,
        _ => RRun { status: c.status(), detail: c.detail(), wall: c.wall, rss_kb: c.hwm, ..RRun::default() },
    }
}

/// The report's section.
pub(crate) fn section(out: &mut String, r: &Results, limit: f64) {
    let _ = writeln!(out, "## Surveillance: a robot out of service mid-mission (section 5.5)\n");
    let i = &r.initial;
    let _ = writeln!(
        out,
        "The case study (`samples/surveillance`) planned: {} in {}, {} actions, {}. Event: {}. Each repair runs {REPEAT} times (the replan once), each in its own process, with the {limit} s limit; the time is `run_repair`'s (or `run_planner`'s) wall time in the process. Target: repaired in under 1 s.\n",
        r_status(i),
        secs(Some(i.wall)),
        i.length.map_or("–".into(), |l| l.to_string()),
        i.validated(),
        r.event
    );
    if r.cases.is_empty() {
        let _ = writeln!(out, "**Not run: the mission was not planned.**\n");
        return;
    }
    let _ = writeln!(
        out,
        "| case | solved | median time | max time | stage | old steps removed | length | instability / distance | valid | under 1 s |\n|---|---|---|---|---|---|---|---|---|---|"
    );
    for (case, runs) in &r.cases {
        let solved = runs.iter().filter(|x| x.solved()).count();
        let times: Vec<f64> = runs.iter().map(|x| x.wall).collect();
        let max = times.iter().copied().reduce(f64::max);
        let first = &runs[0];
        let valid = runs.iter().filter(|x| x.solved() && !x.invalid()).count();
        let _ = writeln!(
            out,
            "| `{}` | {solved}/{} | {} | {} | {} | {} | {} | {} / {} | {valid}/{solved} | {} |",
            case.label,
            runs.len(),
            secs(median(times.clone())),
            secs(max),
            first.stage.clone().unwrap_or_else(|| "–".into()),
            first.removed_steps.map_or("–".into(), |n| n.to_string()),
            first.length.map_or("–".into(), |n| n.to_string()),
            first.instability.map_or("–".into(), |n| n.to_string()),
            first.distance.map_or("–".into(), |n| n.to_string()),
            match (case.mode, max) {
                (Mode::Replan, _) => "–".to_string(),
                (_, Some(m)) if solved == runs.len() && m < 1.0 => "yes".to_string(),
                _ => "**no**".to_string(),
            }
        );
    }
    out.push('\n');
}
