//! The Markdown report and the CSV of the survivors-repair suite: the rows
//! of Figures 12 and 13 of the HiPOP paper per event (time, plan length,
//! instability), how instability grows with the old plan's length, and the
//! targets of the benchmark.

use std::fmt::Write as _;

use super::super::report::{csv_field, machine, mb, median, secs};
use super::super::*;
use super::{Mode, RJob, RRun, SUITE};

pub(crate) struct Context<'a> {
    pub(crate) args: &'a Args,
    pub(crate) raw: &'a [String],
    pub(crate) notes: &'a [String],
    pub(crate) config: &'a str,
    pub(crate) limit: f64,
    /// (date, load average, commit) when the bench started.
    pub(crate) started: (&'a str, &'a str, &'a str),
    pub(crate) took: f64,
    pub(crate) initial: &'a [Job],
    pub(crate) old: &'a [Run],
    pub(crate) jobs: &'a [RJob],
    pub(crate) runs: &'a [RRun],
    pub(crate) surveillance: Option<&'a super::surveillance::Results>,
}

const EVENTS: [&str; 3] = ["startingPos", "newSurvivor", "survivorPos"];

/// Least squares `y = a + b x`: the slope `b`, its standard error, and `n`.
pub(crate) fn slope(points: &[(f64, f64)]) -> Option<(f64, f64, usize)> {
    let n = points.len();
    if n < 3 {
        return None;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n as f64;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n as f64;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx == 0.0 {
        return None;
    }
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let b = sxy / sxx;
    let a = my - b * mx;
    let rss: f64 = points.iter().map(|p| (p.1 - a - b * p.0).powi(2)).sum();
    let se = (rss / (n as f64 - 2.0) / sxx).sqrt();
    Some((b, se, n))
}

fn fmt_slope(s: Option<(f64, f64, usize)>) -> String {
    match s {
        Some((b, se, _)) => format!("{b:.3} ± {se:.3}"),
        None => "–".into(),
    }
}

fn num(x: Option<f64>) -> String {
    match x {
        Some(x) if x.fract() == 0.0 => format!("{x:.0}"),
        Some(x) => format!("{x:.1}"),
        None => "–".into(),
    }
}

fn pct(k: usize, n: usize) -> String {
    if n == 0 { "–".into() } else { format!("{k}/{n} ({:.0} %)", 100.0 * k as f64 / n as f64) }
}

/// The runs of one problem and event, by mode.
struct Triple<'a> {
    problem: &'a str,
    event: &'a str,
    old_length: Option<u64>,
    by: [Option<&'a RRun>; 3],
}

impl<'a> Triple<'a> {
    fn get(&self, m: Mode) -> Option<&'a RRun> {
        self.by[Mode::ALL.iter().position(|&x| x == m).unwrap()]
    }
}

fn triples<'a>(ctx: &Context<'a>) -> Vec<Triple<'a>> {
    let mut out: Vec<Triple<'a>> = Vec::new();
    for (j, r) in ctx.jobs.iter().zip(ctx.runs) {
        let k = Mode::ALL.iter().position(|&m| m == j.mode).unwrap();
        match out.iter_mut().find(|t| t.problem == j.problem && t.event == j.event) {
            Some(t) => t.by[k] = Some(r),
            None => {
                let mut by = [None; 3];
                by[k] = Some(r);
                out.push(Triple { problem: &j.problem, event: j.event, old_length: None, by });
            }
        }
    }
    for t in &mut out {
        t.old_length = ctx
            .initial
            .iter()
            .zip(ctx.old)
            .find(|(j, _)| j.problem == t.problem)
            .and_then(|(_, r)| r.length)
            .or_else(|| t.by.iter().flatten().find_map(|r| r.old_length));
    }
    out
}

/// The rows of Figures 12 and 13 for one event.
fn figure_rows(out: &mut String, ts: &[&Triple], limit: f64) {
    let _ = writeln!(
        out,
        "| | solved | ≤ 0.1 s | ≤ 1 s | ≤ {limit} s | median time | max time | median length | length / replan's (median, both solved) | median instability | mean instability | max instability | median distance | instability vs old length: slope ± s.e. | distance: slope ± s.e. | stage that found the plan |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for m in Mode::ALL {
        let rs: Vec<(&Triple, &RRun)> = ts.iter().filter_map(|t| t.get(m).map(|r| (*t, r))).collect();
        let solved: Vec<(&Triple, &RRun)> = rs.iter().filter(|(_, r)| r.solved()).copied().collect();
        let within = |t: f64| solved.iter().filter(|(_, r)| r.wall <= t).count();
        let times: Vec<f64> = solved.iter().map(|(_, r)| r.wall).collect();
        let lengths: Vec<f64> = solved.iter().filter_map(|(_, r)| r.length).map(|l| l as f64).collect();
        let ratio: Vec<f64> = solved
            .iter()
            .filter_map(|(t, r)| {
                let re = t.get(Mode::Replan).filter(|x| x.solved())?;
                Some(r.length? as f64 / re.length? as f64)
            })
            .collect();
        let inst: Vec<f64> = solved.iter().filter_map(|(_, r)| r.instability).map(|x| x as f64).collect();
        let dist: Vec<f64> = solved.iter().filter_map(|(_, r)| r.distance).map(|x| x as f64).collect();
        let pts = |f: fn(&RRun) -> Option<u64>| -> Vec<(f64, f64)> {
            solved.iter().filter_map(|(t, r)| Some((t.old_length? as f64, f(r)? as f64))).collect()
        };
        let mut stages: Vec<(String, usize)> = Vec::new();
        for (_, r) in &solved {
            let s = r.stage.clone().unwrap_or_else(|| "–".into());
            match stages.iter_mut().find(|(x, _)| *x == s) {
                Some(e) => e.1 += 1,
                None => stages.push((s, 1)),
            }
        }
        stages.sort();
        let stages = if m == Mode::Replan {
            "–".to_string()
        } else {
            stages.iter().map(|(s, n)| format!("{s} {n}")).collect::<Vec<_>>().join(", ")
        };
        let _ = writeln!(
            out,
            "| **{}** | {}/{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            m.name(),
            solved.len(),
            rs.len(),
            within(0.1),
            within(1.0),
            within(limit),
            secs(median(times.clone())),
            secs(times.iter().copied().reduce(f64::max)),
            num(median(lengths)),
            median(ratio).map_or("–".into(), |x| format!("{x:.2}")),
            num(median(inst.clone())),
            if inst.is_empty() {
                "–".into()
            } else {
                format!("{:.1}", inst.iter().sum::<f64>() / inst.len() as f64)
            },
            num(inst.iter().copied().reduce(f64::max)),
            num(median(dist)),
            fmt_slope(slope(&pts(|r| r.instability))),
            fmt_slope(slope(&pts(|r| r.distance))),
            stages,
        );
    }
}

/// The targets of the benchmark, over `ts`: (text, met).
fn targets(ts: &[&Triple], invalid: usize, repaired: usize) -> Vec<(String, bool)> {
    let mut out = Vec::new();
    let replan_solved: Vec<&&Triple> =
        ts.iter().filter(|t| t.get(Mode::Replan).is_some_and(|r| r.solved())).collect();
    let missed: Vec<String> = replan_solved
        .iter()
        .filter(|t| !t.get(Mode::Repair).is_some_and(|r| r.solved()))
        .map(|t| format!("{} {}", t.problem, t.event))
        .collect();
    let repair_only = ts
        .iter()
        .filter(|t| {
            t.get(Mode::Repair).is_some_and(|r| r.solved())
                && !t.get(Mode::Replan).is_some_and(|r| r.solved())
        })
        .count();
    out.push((
        format!(
            "repair solves every problem that replan solves: {} of the {} replan solves{}{}",
            replan_solved.len() - missed.len(),
            replan_solved.len(),
            if missed.is_empty() { String::new() } else { format!(" (not: {})", missed.join(", ")) },
            if repair_only > 0 {
                format!("; and {repair_only} that replan does not solve")
            } else {
                String::new()
            }
        ),
        missed.is_empty(),
    ));
    let faster = replan_solved
        .iter()
        .filter(|t| {
            let (Some(a), Some(b)) = (t.get(Mode::Repair), t.get(Mode::Replan)) else { return false };
            a.solved() && a.wall < b.wall
        })
        .count();
    let share = if replan_solved.is_empty() { 0.0 } else { faster as f64 / replan_solved.len() as f64 };
    out.push((
        format!(
            "repair faster than replan on at least 90 %: {} of the problems replan solves",
            pct(faster, replan_solved.len())
        ),
        share >= 0.9,
    ));
    let both: Vec<(f64, f64)> = ts
        .iter()
        .filter_map(|t| {
            let a = t.get(Mode::Repair).filter(|r| r.solved())?.instability? as f64;
            let b = t.get(Mode::Replan).filter(|r| r.solved())?.instability? as f64;
            Some((a, b))
        })
        .collect();
    let (ma, mb_) = (median(both.iter().map(|p| p.0).collect()), median(both.iter().map(|p| p.1).collect()));
    out.push((
        format!(
            "median instability of repair at most a third of replan's: {} against {} ({} problems both solve{})",
            num(ma),
            num(mb_),
            both.len(),
            match (ma, mb_) {
                (Some(a), Some(b)) if b > 0.0 => format!(", ratio {:.2}", a / b),
                _ => String::new(),
            }
        ),
        matches!((ma, mb_), (Some(a), Some(b)) if a * 3.0 <= b),
    ));
    let pts: Vec<(f64, f64)> = ts
        .iter()
        .filter_map(|t| {
            Some((t.old_length? as f64, t.get(Mode::Repair).filter(|r| r.solved())?.instability? as f64))
        })
        .collect();
    let s = slope(&pts);
    let replan_pts: Vec<(f64, f64)> = ts
        .iter()
        .filter_map(|t| {
            Some((t.old_length? as f64, t.get(Mode::Replan).filter(|r| r.solved())?.instability? as f64))
        })
        .collect();
    // Not growing: the slope is within two standard errors of 0.
    let flat = s.is_some_and(|(b, se, _)| b <= 2.0 * se);
    out.push((
        format!(
            "instability of repair not growing with the old plan's length: slope {} actions per action of the old plan (replan: {}); not growing = at most 2 standard errors above 0",
            fmt_slope(s),
            fmt_slope(slope(&replan_pts))
        ),
        flat,
    ));
    out.push((
        format!("every repaired plan valid: {} of {} repaired plans", repaired - invalid, repaired),
        invalid == 0,
    ));
    out
}

pub(crate) fn report(ctx: &Context) -> String {
    let mut out = String::new();
    let a = ctx.args;
    let _ = writeln!(out, "# Repair benchmark (HiPOP paper, section 5)\n");
    let _ = writeln!(out, "- machine: {}", machine());
    let _ = writeln!(out, "- date: {} (finished {}, {:.0} min)", ctx.started.0, now_utc(), ctx.took / 60.0);
    let _ = writeln!(out, "- commit: {}", ctx.started.2);
    let _ = writeln!(out, "- load average: {} at the start, {} at the end", ctx.started.1, load());
    let _ = writeln!(
        out,
        "- command: `cargo bench -p hipop-analyzer --bench plan --{}`",
        ctx.raw.iter().filter(|s| *s != "--bench").map(|s| format!(" {s}")).collect::<String>()
    );
    let _ = writeln!(
        out,
        "- configuration {}; time limit {} s per run (the repair's stages share it: each search gets at most a quarter of it, the full replan what is left); {} job{} at once, each run in its own process; each repair, repairFlat and replan of an event runs {} time{}, the three taking turns (a slow spell of the machine falls on all three alike), and the run of median time is reported (the plans are the same)",
        ctx.config,
        ctx.limit,
        a.jobs,
        if a.jobs == 1 { "" } else { "s" },
        a.repeat,
        if a.repeat == 1 { "" } else { "s" }
    );
    if !ctx.initial.is_empty() {
        let _ = writeln!(
            out,
            "- each initial problem of `{SUITE}` is planned, its plan validated and written in the timed hierarchical format; for each event, that plan is repaired with `repair` (`RepairOptions::default()`) and `repairFlat` (`flat: true`), and the event's problem is planned from scratch (`replan`)"
        );
    }
    let _ = writeln!(
        out,
        "- time = wall time of `run_repair` or `run_planner` in the child (grounding, the stages' searches), the files already read; length = actions (primitive steps); instability and distance = `hipop diff` of the old plan and the plan found (instability: actions removed, added and retimed by more than 0.001 s; distance: actions removed and added); every plan found is validated (its VAL text, and its hierarchical text) at tolerances 0.01 and 0.0001"
    );
    for n in ctx.notes {
        let _ = writeln!(out, "- {n}");
    }
    out.push('\n');
    if let Some(w) = ctx.surveillance {
        super::surveillance::section(&mut out, w, ctx.limit);
    }
    if ctx.initial.is_empty() {
        return out;
    }
    let _ = writeln!(out, "## survivors-repair (section 5.2, Figures 12 and 13)\n");
    // The initial plans.
    let solved: Vec<&Run> = ctx.old.iter().filter(|r| r.solved()).collect();
    let lengths: Vec<f64> = solved.iter().filter_map(|r| r.length).map(|l| l as f64).collect();
    let _ = writeln!(
        out,
        "**Initial plans**: {}/{} solved ({} invalid), median {} (max {}), {} to {} actions (median {}), peak RSS median {}.\n",
        solved.len(),
        ctx.old.len(),
        ctx.old.iter().filter(|r| r.invalid()).count(),
        secs(median(solved.iter().map(|r| r.wall).collect())),
        secs(solved.iter().map(|r| r.wall).reduce(f64::max)),
        num(lengths.iter().copied().reduce(f64::min)),
        num(lengths.iter().copied().reduce(f64::max)),
        num(median(lengths.clone())),
        mb(median(solved.iter().filter_map(|r| r.rss_kb).map(|k| k as f64).collect()).map(|k| k as u64)),
    );
    for (j, r) in ctx.initial.iter().zip(ctx.old).filter(|(_, r)| !r.solved() || r.invalid()) {
        let _ = writeln!(out, "- initial {}: {} {} {}", j.problem, r_status(r), r.detail, r.validated());
    }
    let ts = triples(ctx);
    let all: Vec<&Triple> = ts.iter().collect();
    let invalid: Vec<(&RJob, &RRun)> = ctx.jobs.iter().zip(ctx.runs).filter(|(_, r)| r.invalid()).collect();
    let repaired =
        ctx.jobs.iter().zip(ctx.runs).filter(|(j, r)| j.mode != Mode::Replan && r.solved()).count();
    let repaired_invalid = invalid.iter().filter(|(j, _)| j.mode != Mode::Replan).count();
    if invalid.is_empty() {
        let _ = writeln!(out, "**Every plan found is valid.**\n");
    } else {
        let _ = writeln!(out, "### **{} INVALID PLANS**\n", invalid.len());
        let _ = writeln!(out, "| problem | event | way | validation |\n|---|---|---|---|");
        for (j, r) in &invalid {
            let err = r.val.iter().chain(r.hier.iter()).find_map(|v| v.1.clone()).unwrap_or_default();
            let _ = writeln!(out, "| {} | {} | {} | {} |", j.problem, j.event, j.mode.name(), err);
        }
        out.push('\n');
    }
    let crashes: Vec<(&RJob, &RRun)> =
        ctx.jobs.iter().zip(ctx.runs).filter(|(_, r)| r.status == "crash").collect();
    for (j, r) in &crashes {
        let _ = writeln!(out, "- **crash**: {} {} {}: {}", j.problem, j.event, j.mode.name(), r.detail);
    }
    let _ = writeln!(out, "### Targets\n");
    let _ = writeln!(out, "All events together:\n\n| target | met |\n|---|---|");
    for (text, met) in targets(&all, repaired_invalid, repaired) {
        let _ = writeln!(out, "| {text} | {} |", if met { "yes" } else { "**no**" });
    }
    let _ = writeln!(out, "\nPer event:\n");
    for e in EVENTS {
        let es: Vec<&Triple> = ts.iter().filter(|t| t.event == e).collect();
        let inv = invalid.iter().filter(|(j, _)| j.event == e && j.mode != Mode::Replan).count();
        let rep = ctx
            .jobs
            .iter()
            .zip(ctx.runs)
            .filter(|(j, r)| j.event == e && j.mode != Mode::Replan && r.solved())
            .count();
        let _ = writeln!(out, "- **{e}**:");
        for (text, met) in targets(&es, inv, rep) {
            let _ = writeln!(out, "  - {}{text}", if met { "" } else { "**not met**: " });
        }
    }
    let _ = writeln!(
        out,
        "\n### Figures 12 and 13, per event\n\nThe paper's three rows: time (problems solved within a time), plan length, instability; and how instability grows with the old plan's length (least squares over the solved problems). The stage that found the plan: `stage1` the search from the old plan without its obsolete steps, `ringN` after removing N rings of steps around them, `replan` the full replan that ends a repair.\n"
    );
    for e in EVENTS {
        let es: Vec<&Triple> = ts.iter().filter(|t| t.event == e).collect();
        let _ = writeln!(out, "#### {e}\n");
        figure_rows(&mut out, &es, ctx.limit);
        out.push('\n');
    }
    // Instability by the old plan's length, in bands.
    let _ = writeln!(
        out,
        "### Instability by the old plan's length\n\nMedian instability of the solved runs, per band of old plan length (actions).\n"
    );
    let mut bands: Vec<u64> = ts.iter().filter_map(|t| t.old_length).collect();
    bands.sort_unstable();
    // Quartiles of the old plans' lengths, each band at least one length.
    let mut edges: Vec<u64> = if bands.is_empty() {
        Vec::new()
    } else {
        (1..4).map(|q| bands[bands.len() * q / 4]).filter(|&e| e > bands[0]).collect()
    };
    edges.dedup();
    let band = |l: u64| edges.iter().filter(|&&e| l >= e).count();
    let mut head = "| event | way |".to_string();
    let mut rule = "|---|---|".to_string();
    for b in 0..=edges.len() {
        let lo = if b == 0 { bands.first().copied().unwrap_or(0) } else { edges[b - 1] };
        let hi = if b == edges.len() { bands.last().copied().unwrap_or(0) } else { edges[b] - 1 };
        head += &format!(" {lo}–{hi} |");
        rule += "---|";
    }
    let _ = writeln!(out, "{head}\n{rule}");
    for e in EVENTS {
        for m in Mode::ALL {
            let mut row = format!("| {e} | {} |", m.name());
            for b in 0..=edges.len() {
                let v: Vec<f64> = ts
                    .iter()
                    .filter(|t| t.event == e && t.old_length.is_some_and(|l| band(l) == b))
                    .filter_map(|t| t.get(m).filter(|r| r.solved())?.instability)
                    .map(|x| x as f64)
                    .collect();
                row += &format!(" {} ({}) |", num(median(v.clone())), v.len());
            }
            let _ = writeln!(out, "{row}");
        }
    }
    // Every run.
    let _ = writeln!(
        out,
        "\n### Every problem and event\n\nPer way: status, time, length, instability / distance, and for the repairs the stage that found the plan and the steps of the old plan removed.\n"
    );
    let _ = writeln!(
        out,
        "| problem | old plan | event | repair | repairFlat | replan |\n|---|---|---|---|---|---|"
    );
    for t in &ts {
        let cell = |m: Mode| match t.get(m) {
            None => "–".to_string(),
            Some(r) if r.solved() => format!(
                "{}{}, {} actions, {} / {}{}",
                if r.invalid() { "**INVALID** " } else { "" },
                secs(Some(r.wall)),
                r.length.map_or("–".into(), |l| l.to_string()),
                r.instability.map_or("–".into(), |l| l.to_string()),
                r.distance.map_or("–".into(), |l| l.to_string()),
                match (&r.stage, r.removed_steps) {
                    (Some(s), Some(n)) => format!(", {s}, {n} removed"),
                    (Some(s), None) => format!(", {s}"),
                    _ => String::new(),
                }
            ),
            Some(r) => format!("{} ({}) after {}", r.status, r.detail, secs(Some(r.wall))),
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} |",
            t.problem,
            t.old_length.map_or("–".into(), |l| format!("{l} actions")),
            t.event,
            cell(Mode::Repair),
            cell(Mode::RepairFlat),
            cell(Mode::Replan)
        );
    }
    out
}

pub(crate) const CSV_HEAD: &str = "problem,event,way,status,detail,time_s,search_s,expanded,stage,stages,old_steps_kept_stage1,old_steps_removed,old_length,length,abstract_steps,makespan,instability,distance,actions_removed,actions_added,actions_retimed,val_valid,hier_valid,validation_error,peak_rss_kb";

/// A CSV field.
pub(crate) fn csv_field_text(s: &str) -> String {
    csv_field(s)
}

fn opt<T: ToString>(x: Option<T>) -> String {
    x.map(|v| v.to_string()).unwrap_or_default()
}

fn valid(v: &Option<(bool, Option<String>)>) -> String {
    opt(v.as_ref().map(|v| v.0))
}

/// The line of an initial plan (event `initial`, way: the configuration).
pub(crate) fn csv_initial(j: &Job, r: &Run) -> String {
    let error = r.val.iter().chain(r.hier.iter()).find_map(|v| v.1.clone()).unwrap_or_default();
    [
        j.problem.clone(),
        "initial".into(),
        j.config.clone(),
        r.status.clone(),
        r.detail.clone(),
        format!("{:.4}", r.wall),
        format!("{:.4}", r.search),
        r.expanded.to_string(),
        String::new(),
        String::new(),
        String::new(),
        String::new(),
        String::new(),
        opt(r.length),
        opt(r.abstract_steps),
        opt(r.makespan.map(|m| format!("{m:.3}"))),
        String::new(),
        String::new(),
        String::new(),
        String::new(),
        String::new(),
        valid(&r.val),
        valid(&r.hier),
        error,
        opt(r.rss_kb),
    ]
    .iter()
    .map(|f| csv_field(f))
    .collect::<Vec<_>>()
    .join(",")
}

pub(crate) fn csv_line(j: &RJob, r: &RRun) -> String {
    let error = r.val.iter().chain(r.hier.iter()).find_map(|v| v.1.clone()).unwrap_or_default();
    [
        j.problem.clone(),
        j.event.to_string(),
        j.mode.name().to_string(),
        r.status.clone(),
        r.detail.clone(),
        format!("{:.4}", r.wall),
        format!("{:.4}", r.search),
        r.expanded.to_string(),
        r.stage.clone().unwrap_or_default(),
        opt(r.stages),
        opt(r.kept),
        opt(r.removed_steps),
        opt(r.old_length),
        opt(r.length),
        opt(r.abstract_steps),
        opt(r.makespan.map(|m| format!("{m:.3}"))),
        opt(r.instability),
        opt(r.distance),
        opt(r.removed),
        opt(r.added),
        opt(r.retimed),
        valid(&r.val),
        valid(&r.hier),
        error,
        opt(r.rss_kb),
    ]
    .iter()
    .map(|f| csv_field(f))
    .collect::<Vec<_>>()
    .join(",")
}
