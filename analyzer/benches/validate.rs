//! `cargo bench -p hipop-analyzer --bench validate`: the time to read and
//! validate long plans (issue 4: a plan of 10,000 steps validates in well
//! under a second). Results are recorded in docs/benchmarks.md.

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use hipop_analyzer::AnalysisHost;
use hipop_analyzer::validate::Options;

/// The allocator of the `hipop` binary: what it measures is what users get.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Robots shuttling parcels between depots: every step depends on the one
/// before it for the same robot, and the robots' steps interleave in time.
const DOMAIN: &str = "(define (domain shuttle)
  (:requirements :strips :typing :durative-actions :numeric-fluents)
  (:types robot place)
  (:predicates (at ?r - robot ?p - place) (road ?a ?b - place))
  (:functions (length ?a ?b - place) (driven ?r - robot))
  (:durative-action drive
    :parameters (?r - robot ?from ?to - place)
    :duration (= ?duration (length ?from ?to))
    :condition (and (at start (at ?r ?from)) (over all (road ?from ?to)))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to))
                 (at end (increase (driven ?r) (length ?from ?to))))))";

/// A problem with `robots` robots and `places` places on a ring, and a plan
/// of `steps` drives around the ring (valid, goal: every robot back home).
fn mission(robots: usize, places: usize, steps: usize) -> (String, String) {
    let mut p = String::from("(define (problem ring) (:domain shuttle) (:objects");
    for r in 0..robots {
        write!(p, " r{r}").unwrap();
    }
    p.push_str(" - robot");
    for i in 0..places {
        write!(p, " w{i}").unwrap();
    }
    p.push_str(" - place) (:init");
    for r in 0..robots {
        write!(p, " (at r{r} w0) (= (driven r{r}) 0)").unwrap();
    }
    for i in 0..places {
        let j = (i + 1) % places;
        write!(p, " (road w{i} w{j}) (= (length w{i} w{j}) {}.5)", 2 + i % 3).unwrap();
    }
    p.push_str(") (:goal (and");
    let per_robot = steps / robots;
    for r in 0..robots {
        write!(p, " (at r{r} w{})", per_robot % places).unwrap();
    }
    p.push_str(")))");
    let mut plan = String::new();
    for r in 0..robots {
        let mut t = r as f64 * 0.1;
        for k in 0..per_robot {
            let (i, j) = (k % places, (k + 1) % places);
            let d = 2.0 + (i % 3) as f64 + 0.5;
            writeln!(plan, "{t:.3}: (drive r{r} w{i} w{j}) [{d:.3}]").unwrap();
            t += d + 0.01;
        }
    }
    (p, plan)
}

fn main() {
    println!("| plan | steps | read + validate, median | fastest |");
    println!("|---|---|---|---|");
    for (robots, steps) in [(1, 1_000), (10, 10_000), (10, 50_000)] {
        let (problem, plan) = mission(robots, 50, steps);
        let mut host = AnalysisHost::new();
        host.set_file_text("domain.pddl", DOMAIN);
        let p = host.set_file_text("problem.pddl", problem);
        assert!(host.analysis().check_diagnostics(p).unwrap().is_empty());
        let mut times: Vec<Duration> = Vec::new();
        for run in 0..7 {
            // A new text each run: the plan is read again, not taken from salsa's memo.
            let text = format!("; run {run}\n{plan}");
            let start = Instant::now();
            let f = host.set_file_text("ring.plan", text);
            let v = host.analysis().validate_plan(f, None, p, &Options::default()).unwrap().unwrap();
            times.push(start.elapsed());
            assert!(v.valid, "{:?}", &v.diagnostics[..v.diagnostics.len().min(2)]);
        }
        times.sort();
        println!(
            "| {robots} robot{} on a ring of 50 places | {steps} | {:.1} ms | {:.1} ms |",
            if robots == 1 { "" } else { "s" },
            times[times.len() / 2].as_secs_f64() * 1e3,
            times[0].as_secs_f64() * 1e3
        );
    }
}
