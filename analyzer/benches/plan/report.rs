//! The Markdown report and the CSV.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::process::Command;
use std::time::SystemTime;

use super::*;

pub(crate) fn median(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return None;
    }
    let n = v.len();
    Some(if n % 2 == 1 { v[n / 2] } else { (v[n / 2 - 1] + v[n / 2]) / 2.0 })
}

pub(crate) fn secs(x: Option<f64>) -> String {
    match x {
        None => "–".into(),
        Some(x) if x < 10.0 => format!("{x:.3} s"),
        Some(x) => format!("{x:.1} s"),
    }
}

pub(crate) fn mb(kb: Option<u64>) -> String {
    kb.map(|k| format!("{:.0} MB", k as f64 / 1024.0)).unwrap_or("–".into())
}

pub(crate) fn rate(x: Option<f64>) -> String {
    x.map(|r| format!("{r:.0}")).unwrap_or("–".into())
}

/// Civil date of the Unix day `days` (Howard Hinnant's algorithm).
pub(crate) fn civil(days: i64) -> (i64, u32, u32) {
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

pub(crate) fn now_utc() -> String {
    let s = SystemTime::now().duration_since(SystemTime::UNIX_EPOCH).map(|d| d.as_secs() as i64).unwrap_or(0);
    let (y, m, d) = civil(s.div_euclid(86_400));
    let t = s.rem_euclid(86_400);
    format!("{y}-{m:02}-{d:02} {:02}:{:02} UTC", t / 3600, t / 60 % 60)
}

pub(crate) fn machine() -> String {
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

pub(crate) fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or("?".into())
}

/// The commit measured, `+dirty` when the worktree has changes.
pub(crate) fn commit() -> String {
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

pub(crate) fn status_cell(r: &Run) -> String {
    match r.status.as_str() {
        "solved" if r.invalid() => "**solved, INVALID**".into(),
        "solved" => "solved".into(),
        "limit" => format!("limit ({})", r.detail),
        "crash" => "**crash**".into(),
        s => s.into(),
    }
}

/// Summary rows of `runs` per configuration.
pub(crate) fn summary(out: &mut String, label: &str, configs: &[String], runs: &[(&Job, &Run)]) {
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

pub(crate) const SUMMARY_HEAD: &str = "| suite | configuration | solved | no plan | limit | refused | crash | invalid | median time (solved) | max time (solved) | nodes/s (all runs) | median peak RSS | max peak RSS |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";

/// `p-t2-r3-z9-s4` → (teams, rows, zone size, survivors).
pub(crate) fn survivors_params(stem: &str) -> Option<[u64; 4]> {
    let mut v = [0; 4];
    let parts: Vec<&str> = stem.split('-').skip(1).collect();
    for (i, (part, prefix)) in parts.iter().zip(["t", "r", "z", "s"]).enumerate() {
        v[i] = part.strip_prefix(prefix)?.parse().ok()?;
    }
    (parts.len() == 4).then_some(v)
}

pub(crate) fn growth(out: &mut String, configs: &[String], runs: &[(&Job, &Run)]) {
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

pub(crate) fn report(
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
        a.limit(),
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
    // Steps that can go, in the plans without abstract steps.
    let checked: Vec<u64> = runs.iter().filter_map(|r| r.redundant).collect();
    if !checked.is_empty() {
        let with = checked.iter().filter(|&&k| k > 0).count();
        let _ = writeln!(
            out,
            "**Redundant steps:** {} step{} can be removed (with the steps that only served them, the plan stays valid) in {with} of the {} plans without abstract steps (target: none).\n",
            checked.iter().sum::<u64>(),
            if checked.iter().sum::<u64>() == 1 { "" } else { "s" },
            checked.len(),
        );
    }
    // What the planner removed before returning its plans.
    // hipop's own runs: a peer's plans are not reduced, and a peer stopped
    // by the time limit is killed by the harness, which says nothing of
    // how hipop honours its limit.
    let own: Vec<&Run> = pairs
        .iter()
        .filter(|(j, _)| !crate::peers::PEERS.contains(&j.config.as_str()))
        .map(|(_, r)| *r)
        .collect();
    let solved: Vec<&Run> = own.iter().copied().filter(|r| r.solved()).collect();
    if let Some(slowest) = solved.iter().max_by(|a, b| a.removal.total_cmp(&b.removal)) {
        let _ = writeln!(
            out,
            "**Removed by the planner:** {} redundant step{} in {} of the {} plans; the removal took at most {:.4} s (a plan of {} steps).\n",
            solved.iter().map(|r| r.removed).sum::<u64>(),
            if solved.iter().map(|r| r.removed).sum::<u64>() == 1 { "" } else { "s" },
            solved.iter().filter(|r| r.removed > 0).count(),
            solved.len(),
            slowest.removal,
            slowest.length.unwrap_or(0),
        );
    }
    // The time limit is honoured when a run stopped by it ends soon after.
    let over: Vec<f64> = own
        .iter()
        .filter(|r| r.status == "limit" && r.detail == "time")
        .map(|r| r.wall - a.limit())
        .collect();
    if let Some(worst) = over.iter().copied().reduce(f64::max) {
        let _ = writeln!(
            out,
            "**Time limit:** {} of hipop's runs stopped at the time limit ({} s); the longest ended {:.3} s after it (wall time in the child, grounding included).\n",
            over.len(),
            a.limit(),
            worst
        );
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
        side_by_side(&mut out, &configs, &rs);
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

/// hipop's configurations against each peer run in the same suite: the
/// problems both solve, hipop's median time and makespan as ratios of the
/// peer's, and the problems only one of them solves.
pub(crate) fn side_by_side(out: &mut String, configs: &[String], runs: &[(&Job, &Run)]) {
    let peers: Vec<&String> = configs.iter().filter(|c| super::peers::PEERS.contains(&c.as_str())).collect();
    if peers.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\nSide by side (same problems, same limit, same run; a peer's time is its whole run, \
         parsing and grounding included; ratios are hipop's over the peer's, on the problems both solve):\n\n\
         | hipop | peer | both solve | only hipop | only the peer | median time ratio | median makespan ratio (pandapi: length) |\n\
         |---|---|---|---|---|---|---|"
    );
    let find = |config: &str, j: &Job| {
        runs.iter()
            .find(|(k, _)| k.config == config && k.group == j.group && k.problem == j.problem)
            .map(|(_, r)| *r)
    };
    for peer in &peers {
        for config in configs.iter().filter(|c| !peers.contains(c)) {
            let (mut both, mut only_hipop, mut only_peer) = (0, 0, 0);
            let (mut times, mut spans) = (Vec::new(), Vec::new());
            for (j, r) in runs.iter().filter(|(j, _)| &j.config == config) {
                let Some(p) = find(peer, j) else { continue };
                match (r.solved() && !r.invalid(), p.solved() && !p.invalid()) {
                    (true, true) => {
                        both += 1;
                        if p.wall > 0.0 {
                            times.push(r.wall / p.wall);
                        }
                        // A hierarchical plan's quality is its length: pandaPI's
                        // plans are sequences.
                        let quality = |r: &Run| {
                            if peer.as_str() == "pandapi" { r.length.map(|l| l as f64) } else { r.makespan }
                        };
                        if let (Some(a), Some(b)) = (quality(r), quality(p))
                            && b > 0.0
                        {
                            spans.push(a / b);
                        }
                    }
                    (true, false) => only_hipop += 1,
                    (false, true) => only_peer += 1,
                    (false, false) => {}
                }
            }
            let ratio = |v: Vec<f64>| median(v).map(|m| format!("{m:.2}")).unwrap_or("–".into());
            let _ = writeln!(
                out,
                "| {config} | {peer} | {both} | {only_hipop} | {only_peer} | {} | {} |",
                ratio(times),
                ratio(spans)
            );
        }
    }
}

pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

pub(crate) const CSV_HEAD: &str = "suite,domain,problem,config,status,detail,time_s,search_s,expanded,generated,nodes_per_s,operators,method_instances,makespan,length,abstract_steps,val_valid,hier_valid,validation_error,peak_rss_kb,best_plan_first_flaw,redundant_steps,removed_steps,removal_s";

pub(crate) fn csv_line(j: &Job, r: &Run) -> String {
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
        opt(r.redundant.map(|k| k.to_string())),
        r.removed.to_string(),
        format!("{:.4}", r.removal),
    ]
    .iter()
    .map(|f| csv_field(f))
    .collect::<Vec<_>>()
    .join(",")
}
