//! `cargo bench -p hipop-analyzer --bench check`: parse + full check throughput
//! and the latency of the incremental re-check after a one-character edit.
//! Results are recorded in docs/benchmarks.md.

use std::path::Path;
use std::time::{Duration, Instant};

use hipop_analyzer::{AnalysisHost, TextEdit, TextRange, TextSize};

/// The allocator of the `hipop` binary: what it measures is what users get.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn minimum(v: &[Duration]) -> Duration {
    v.iter().copied().min().unwrap_or_default()
}

/// Full check from scratch: a new database, parse, lower, check every item of
/// the domain and of the problem, collect every diagnostic of both files.
/// Returns the median and the fastest run (on a shared machine the fastest is
/// the best estimate of the work itself, the median of what a user sees).
fn full_check(domain: &str, problem: &str, runs: usize, lints: bool) -> (Duration, Duration) {
    let times: Vec<Duration> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            let mut host = AnalysisHost::new();
            let d_file = host.set_file_text("domain.pddl", domain);
            let p = host.set_file_text("problem.pddl", problem);
            let a = host.analysis();
            let diagnostics = |f| if lints { a.diagnostics(f) } else { a.check_diagnostics(f) };
            let mut d = diagnostics(p).unwrap();
            d.extend(diagnostics(d_file).unwrap());
            let elapsed = start.elapsed();
            assert!(
                d.iter().all(|d| d.severity != hipop_analyzer::Severity::Error),
                "{:?}",
                &d[..d.len().min(3)]
            );
            elapsed
        })
        .collect();
    (median(times.clone()), minimum(&times))
}

fn row(name: &str, bytes: usize, (median, min): (Duration, Duration)) {
    let mbps = |t: Duration| bytes as f64 / 1e6 / t.as_secs_f64();
    println!(
        "| {name} | {:.2} MB | {:.1} ms | {:.0} MB/s | {:.1} ms | {:.0} MB/s |",
        bytes as f64 / 1e6,
        median.as_secs_f64() * 1e3,
        mbps(median),
        min.as_secs_f64() * 1e3,
        mbps(min)
    );
}

/// A one-character edit inside one `:init` fact, and back, through the incremental path.
fn incremental(domain: &str, problem: &str, runs: usize, lints: bool) -> (Duration, Duration) {
    let mut host = AnalysisHost::new();
    host.set_file_text("domain.pddl", domain);
    let p = host.set_file_text("problem.pddl", problem);
    host.analysis().diagnostics(p).unwrap();
    // The middle `(= (distance a b) 12.34)` fact: edit the last digit of its value.
    let facts: Vec<usize> = problem.match_indices("(= (distance ").map(|(i, _)| i).collect();
    let fact = facts[facts.len() / 2];
    let inner_close = fact + problem[fact..].find(')').unwrap();
    let close = inner_close + 1 + problem[inner_close + 1..].find(')').unwrap();
    let digit = close - 1;
    assert!(problem.as_bytes()[digit].is_ascii_digit());
    let at = TextSize::from(digit as u32);
    let original = &problem[digit..digit + 1];
    let other = if original == "1" { "2" } else { "1" };
    let mut edit_times = Vec::new();
    let mut check_times = Vec::new();
    for i in 0..runs {
        let insert = if i % 2 == 0 { other } else { original };
        let start = Instant::now();
        host.apply_edits(
            "problem.pddl",
            vec![TextEdit { range: TextRange::at(at, 1.into()), insert: insert.into() }],
        );
        let edited = start.elapsed();
        let a = host.analysis();
        let d = if lints { a.diagnostics(p) } else { a.check_diagnostics(p) }.unwrap();
        check_times.push(start.elapsed());
        edit_times.push(edited);
        assert!(d.iter().all(|d| d.severity != hipop_analyzer::Severity::Error));
    }
    (median(edit_times), median(check_times))
}

fn main() {
    // `cargo bench` passes `--bench`; the harness takes no options.
    // What the language server publishes first (the syntax and semantic
    // checks), and everything with the model-verification lints (which
    // ground the problem).
    for (title, lints, runs) in [("checks", false, 40), ("checks + model-verification lints", true, 5)] {
        println!("\n{title}\n");
        println!("| input | size | full check, median | throughput | fastest run | throughput |");
        println!("|---|---|---|---|---|---|");
        let corpora = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora/ipc2002-temporal");
        let largest = corpora.join("driverlog-time-hand-coded/instances/instance-20.pddl");
        match (
            std::fs::read_to_string(corpora.join("driverlog-time-hand-coded/domain.pddl")),
            std::fs::read_to_string(&largest),
        ) {
            (Ok(d), Ok(p)) => row(
                "largest corpus file (DriverLog time hand-coded #20) + domain",
                d.len() + p.len(),
                full_check(&d, &p, runs, lints),
            ),
            _ => eprintln!("SKIP corpus file: ../shared/corpora is absent"),
        }
        let (sd, sp) = hipop_samplegen::surveillance(hipop_samplegen::DEFAULT_SEED);
        row("surveillance sample (domain + problem)", sd.len() + sp.len(), full_check(&sd, &sp, runs, lints));
        let (bd, bp) = hipop_samplegen::big(5.0, hipop_samplegen::DEFAULT_SEED);
        row(
            "generated 5 MB problem + its domain (hipop-samplegen big --size-mb 5)",
            bd.len() + bp.len(),
            full_check(&bd, &bp, runs.min(15), lints),
        );
        let (edit, total) = incremental(&bd, &bp, if lints { 10 } else { 50 }, lints);
        println!();
        println!("| incremental, one-character edit in one `:init` fact of the 5 MB problem | median |");
        println!("|---|---|");
        println!(
            "| apply the edit (text + incremental re-parse + salsa inputs) | {:.2} ms |",
            edit.as_secs_f64() * 1e3
        );
        println!(
            "| edit + every diagnostic ({title}) of the file up to date | {:.2} ms |",
            total.as_secs_f64() * 1e3
        );
    }
}
