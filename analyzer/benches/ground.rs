//! `cargo bench -p hipop-analyzer --bench ground`: the time to ground a problem
//! (instantiate its actions and tasks with relaxed reachability, evaluate
//! their durations), once its files are parsed, lowered and checked.
//! Results are recorded in docs/benchmarks.md.

use std::path::Path;
use std::time::{Duration, Instant};

use hipop_analyzer::AnalysisHost;
use hipop_analyzer::db::{UnitKind, file_units};
use hipop_analyzer::verify::ground::{Limits, ground_methods_with, ground_with};

/// The allocator of the `hipop` binary: what it measures is what users get.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn ms(d: Duration) -> String {
    format!("{:.2} ms", d.as_secs_f64() * 1e3)
}

/// Grounds `problem` `runs` times (operators, then methods) on a database where
/// everything else is computed already; prints one table row.
fn bench(name: &str, domain: &str, problem: &str, runs: usize) {
    let mut host = AnalysisHost::new();
    let d = host.set_file_text("domain.pddl", domain);
    let p = host.set_file_text("problem.pddl", problem);
    let analysis = host.analysis();
    // Parse, lower and check both files first: what is timed is grounding alone.
    let diags = analysis.diagnostics(p).unwrap();
    analysis.diagnostics(d).unwrap();
    assert!(
        diags.iter().all(|d| d.severity != hipop_analyzer::Severity::Error),
        "{:?}",
        &diags[..diags.len().min(3)]
    );
    let db = host.db();
    let unit =
        file_units(db, p).iter().copied().find(|u| u.kind(db) == UnitKind::Problem).expect("a problem");
    let mut ops_times = Vec::new();
    let mut method_times = Vec::new();
    let mut last = None;
    for _ in 0..runs {
        let start = Instant::now();
        let g = ground_with(db, unit, Limits::DEFAULT);
        ops_times.push(start.elapsed());
        let start = Instant::now();
        let m = ground_methods_with(db, unit, &g, Limits::DEFAULT);
        method_times.push(start.elapsed());
        last = Some((
            g.objects.len(),
            g.init.facts.len(),
            g.init.fluents.len(),
            g.atoms.len(),
            g.operators.len(),
            g.truncated,
            m.methods.len(),
        ));
    }
    let (objects, facts, fluents, atoms, ops, truncated, methods) = last.expect("at least one run");
    println!(
        "| {name} | {objects} | {facts} + {fluents} | {ops}{} | {atoms} | {} | {methods} | {} |",
        if truncated { " (truncated)" } else { "" },
        ms(median(ops_times)),
        ms(median(method_times)),
    );
}

/// The surveillance problem at the paper's scale: every waypoint adjacent to
/// every other one, with its distance (the generator only links neighbours).
fn complete_surveillance(domain: &str, problem: &str) -> String {
    let mut waypoints: Vec<&str> = domain
        .split(|c: char| c.is_whitespace() || c == '(' || c == ')')
        .chain(problem.split(|c: char| c.is_whitespace() || c == '(' || c == ')'))
        .filter(|w| {
            let parts: Vec<&str> = w.split('_').collect();
            matches!(parts[0], "wpa" | "wpr" | "wpg")
                && parts.len() == 3
                && parts[1..].iter().all(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()))
        })
        .collect();
    waypoints.sort();
    waypoints.dedup();
    let coords = |w: &str| {
        let mut parts = w.split('_').skip(1).map(|n| n.parse::<f64>().unwrap_or(0.0) / 10.0);
        (parts.next().unwrap_or(0.0), parts.next().unwrap_or(0.0))
    };
    let mut facts = String::new();
    for a in &waypoints {
        for b in &waypoints {
            if a != b {
                let ((x1, y1), (x2, y2)) = (coords(a), coords(b));
                let d = ((x1 - x2).powi(2) + (y1 - y2).powi(2)).sqrt();
                facts.push_str(&format!("    (adjacent {a} {b}) (= (distance {a} {b}) {d:.2})\n"));
            }
        }
    }
    let kept: Vec<&str> =
        problem.lines().filter(|l| !l.contains("(adjacent ") && !l.contains("(= (distance ")).collect();
    kept.join("\n").replacen("(:init\n", &format!("(:init\n{facts}"), 1)
}

/// Position families and move actions (properties 4–6 of Definition 14, the
/// triangle inequality included) on an already grounded problem.
fn families_bench(name: &str, domain: &str, problem: &str, runs: usize) {
    let mut times = Vec::new();
    let mut summary = String::new();
    for _ in 0..runs {
        let mut host = AnalysisHost::new();
        host.set_file_text("domain.pddl", domain);
        let p = host.set_file_text("problem.pddl", problem);
        let db = host.db();
        let unit =
            file_units(db, p).iter().copied().find(|u| u.kind(db) == UnitKind::Problem).expect("a problem");
        hipop_analyzer::verify::ground::ground(db, unit);
        let start = Instant::now();
        let f = hipop_analyzer::verify::families::families(db, unit);
        times.push(start.elapsed());
        let moves: usize = f.confirmed.iter().flat_map(|c| c.moves.iter().map(|m| m.1)).sum();
        summary = format!("{} confirmed, {} ground moves, {} lints", f.confirmed.len(), moves, f.lints.len());
    }
    println!("| {name} | {summary} | {} |", ms(median(times)));
}

fn main() {
    // `cargo bench` passes `--bench`; the harness takes no options.
    println!(
        "| problem | objects | init facts + fluent values | ground operators | atoms | grounding, median | ground methods | methods, median |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let (sd, sp) = hipop_samplegen::surveillance(hipop_samplegen::DEFAULT_SEED);
    bench("surveillance sample (seed 42)", &sd, &sp, 30);
    let full = complete_surveillance(&sd, &sp);
    bench("surveillance sample, every pair of waypoints adjacent (6,162 distances)", &sd, &full, 20);
    let corpora = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora/ipc2002-temporal");
    let largest = corpora.join("driverlog-time-hand-coded/instances/instance-20.pddl");
    match (
        std::fs::read_to_string(corpora.join("driverlog-time-hand-coded/domain.pddl")),
        std::fs::read_to_string(&largest),
    ) {
        (Ok(d), Ok(p)) => bench("largest corpus file (DriverLog time hand-coded #20)", &d, &p, 10),
        _ => eprintln!("SKIP corpus file: ../shared/corpora is absent"),
    }
    let (bd, bp) = hipop_samplegen::big(5.0, hipop_samplegen::DEFAULT_SEED);
    bench("generated 5 MB problem (hipop-samplegen big --size-mb 5)", &bd, &bp, 5);
    println!();
    println!("| problem | families | families, moves, properties 4–6 (median) |");
    println!("|---|---|---|");
    families_bench("surveillance sample (seed 42)", &sd, &sp, 20);
    families_bench("surveillance, every pair of its 79 waypoints adjacent (3 robot types)", &sd, &full, 10);
    families_bench("generated 5 MB problem", &bd, &bp, 3);
}
