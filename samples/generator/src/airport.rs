//! Airport-style inputs for the throughput benchmarks of `hipop check`: the
//! shape of the IPC 2004 Airport domains (temporal variant), where every
//! problem comes with its own large domain. The airport's segments, the
//! airplanes and their types are constants of the domain, and the actions are
//! nearly ground: one `move` per pair of adjacent segments, direction of
//! travel and airplane type, each listing every airplane by name in its
//! condition and the segments it blocks and frees in its effect; `pushback`,
//! `startup`, `park` and `takeoff` per segment and type. Only the airplane
//! that acts is a parameter. The problem lists the airport's state (which
//! segments are occupied, blocked by whom, where each airplane stands and
//! faces) and asks outbound airplanes to take off and inbound ones to park.
//!
//! The layout: `runways` runways of `length` segments each, a taxiway beside
//! each, parallel to it and joined to it at both ends, the taxiways joined
//! end to end, and a parking position behind a door segment at every other
//! taxiway segment. Segment lengths are drawn from the seed; a move lasts
//! the length of the segment entered divided by the speed of the type.

use std::fmt::Write;

use crate::rng::Rng;

const TYPES: [(&str, u64); 3] = [("light", 30), ("medium", 20), ("heavy", 15)];
const MIB: f64 = 1_048_576.0;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Runway,
    Taxiway,
    Door,
    Parking,
}

struct Segment {
    name: String,
    kind: Kind,
    /// In metres.
    length: u64,
}

/// A move from one segment to the next, facing `dir` on both.
struct Move {
    from: usize,
    to: usize,
    dir: &'static str,
}

struct Airport {
    segments: Vec<Segment>,
    /// Undirected adjacency.
    next: Vec<Vec<usize>>,
    moves: Vec<Move>,
    /// `(door, parking)` pairs.
    gates: Vec<(usize, usize)>,
    /// The first segment of each runway (take-off facing north).
    runway_starts: Vec<usize>,
    planes: Vec<Plane>,
}

struct Plane {
    name: String,
    ty: usize,
    /// Where it stands, and whether it is parked there (outbound) or moving
    /// along a taxiway (inbound).
    at: usize,
    parked: bool,
    facing: &'static str,
    /// Inbound: the parking position to reach; outbound: the runway.
    goal: usize,
}

fn build(runways: usize, length: usize, seed: u64) -> Airport {
    let mut rng = Rng::new(seed);
    let mut segments = Vec::new();
    let seg = |segments: &mut Vec<Segment>, name: String, kind: Kind, rng: &mut Rng| {
        let length = match kind {
            Kind::Runway => rng.range(300, 900),
            Kind::Taxiway => rng.range(40, 300),
            Kind::Door | Kind::Parking => rng.range(20, 60),
        } as u64;
        segments.push(Segment { name, kind, length });
        segments.len() - 1
    };
    let mut edges = Vec::new();
    let mut chains = Vec::new();
    let mut gates = Vec::new();
    for r in 0..runways {
        let rw: Vec<usize> = (0..length)
            .map(|k| seg(&mut segments, format!("seg_rw_{r}_{k}"), Kind::Runway, &mut rng))
            .collect();
        let tw: Vec<usize> = (0..length)
            .map(|k| seg(&mut segments, format!("seg_tw_{r}_{k}"), Kind::Taxiway, &mut rng))
            .collect();
        for k in 1..length {
            edges.push((rw[k - 1], rw[k]));
            edges.push((tw[k - 1], tw[k]));
        }
        edges.push((tw[0], rw[0]));
        edges.push((tw[length - 1], rw[length - 1]));
        for k in (0..length).step_by(2) {
            let door = seg(&mut segments, format!("seg_ppdoor_{r}_{k}"), Kind::Door, &mut rng);
            let pp = seg(&mut segments, format!("seg_pp_{r}_{k}"), Kind::Parking, &mut rng);
            edges.push((tw[k], door));
            edges.push((door, pp));
            gates.push((door, pp));
        }
        chains.push((rw, tw));
    }
    for r in 1..runways {
        edges.push((chains[r - 1].1[length - 1], chains[r].1[0]));
    }
    let mut next = vec![Vec::new(); segments.len()];
    let mut moves = Vec::new();
    for &(a, b) in &edges {
        next[a].push(b);
        next[b].push(a);
        moves.push(Move { from: a, to: b, dir: "north" });
        moves.push(Move { from: b, to: a, dir: "south" });
    }
    // About one airplane for every 40 segments, at most 15 (the IPC's largest).
    let count = (segments.len() / 40).clamp(2, 15);
    let mut free: Vec<usize> = (0..gates.len()).collect();
    rng.shuffle(&mut free);
    let mut taxi: Vec<usize> = chains.iter().flat_map(|(_, tw)| tw.iter().copied()).collect();
    rng.shuffle(&mut taxi);
    let mut planes = Vec::new();
    for i in 0..count {
        let ty = rng.below(TYPES.len() as u64) as usize;
        let name = format!("airplane_{}{:02}", ["a", "b", "c", "d"][i % 4], i);
        let (at, parked, goal) = if i % 2 == 0 {
            let (_, pp) = gates[free.pop().unwrap_or(0)];
            (pp, true, chains[rng.below(runways as u64) as usize].0[0])
        } else {
            let (_, pp) = gates[free.pop().unwrap_or(0)];
            (taxi.pop().unwrap_or(0), false, pp)
        };
        planes.push(Plane { name, ty, at, parked, facing: if parked { "south" } else { "north" }, goal });
    }
    let runway_starts = chains.iter().map(|(rw, _)| rw[0]).collect();
    Airport { segments, next, moves, gates, runway_starts, planes }
}

/// `l / v` with four decimals.
fn duration(length: u64, speed: u64) -> String {
    let ten_thousandths = length * 10_000 / speed;
    format!("{}.{:04}", ten_thousandths / 10_000, ten_thousandths % 10_000)
}

fn header(out: &mut String, what: &str, command: &str) {
    writeln!(out, "; An airport in the shape of the IPC 2004 Airport domains (temporal): {what}.").unwrap();
    writeln!(out, "; Generated by hipop-samplegen. Do not edit by hand; regenerate with:").unwrap();
    writeln!(out, ";   {command}").unwrap();
}

fn domain(a: &Airport, name: &str, command: &str) -> String {
    let mut out = String::new();
    header(&mut out, "the domain", command);
    writeln!(out, "(define (domain {name})").unwrap();
    writeln!(out, "(:requirements :typing :durative-actions)").unwrap();
    writeln!(out, "(:types airplane segment direction airplanetype)").unwrap();
    writeln!(out, "(:constants").unwrap();
    writeln!(out, "             north south - direction").unwrap();
    writeln!(out, "             light medium heavy - airplanetype").unwrap();
    for p in &a.planes {
        writeln!(out, "             {} - airplane", p.name).unwrap();
    }
    for s in &a.segments {
        writeln!(out, "             {} - segment", s.name).unwrap();
    }
    writeln!(out, ")").unwrap();
    out.push_str(
        "(:predicates
                (has-type ?a - airplane ?t - airplanetype)
                ;; airplane ?a is at segment ?s
                (at-segment ?a - airplane ?s - segment)
                (facing ?a - airplane ?d - direction)
                (occupied ?s - segment)
                (not_occupied ?s - segment)
                (blocked ?s - segment ?a - airplane)
                (not_blocked ?s - segment ?a - airplane)
                (is-start-runway ?s - segment ?d - direction)
                (airborne ?a - airplane ?s - segment)
                (is-moving ?a - airplane)
                (is-pushing ?a - airplane)
                (is-parked ?a - airplane ?s - segment)
)
",
    );
    let seg = |i: usize| a.segments[i].name.as_str();
    for m in &a.moves {
        for (ti, &(ty, speed)) in TYPES.iter().enumerate() {
            // Behind the airplane: the segment it leaves, and for a heavy one
            // the segment before that on its way.
            let mut behind = vec![m.from];
            if ti == 2
                && let Some(&b) = a.next[m.from].iter().find(|&&n| n != m.to)
            {
                behind.push(b);
            }
            let freed: Vec<usize> =
                a.next[m.from].iter().copied().filter(|n| *n != m.to && !behind.contains(n)).collect();
            writeln!(out, "\n(:durative-action move_{}_{}_{}_{}_{ty}", seg(m.from), seg(m.to), m.dir, m.dir)
                .unwrap();
            writeln!(out, " :parameters (?a - airplane)").unwrap();
            writeln!(out, " :duration (= ?duration {})", duration(a.segments[m.to].length, speed)).unwrap();
            writeln!(out, " :condition (and").unwrap();
            writeln!(out, "                (over all (has-type ?a {ty}))").unwrap();
            writeln!(out, "                (over all (is-moving ?a))").unwrap();
            writeln!(out, "                (at start (facing ?a {}))", m.dir).unwrap();
            writeln!(out, "                (at start (at-segment ?a {}))", seg(m.from)).unwrap();
            writeln!(out, "                (at start (not_occupied {}))", seg(m.to)).unwrap();
            for p in &a.planes {
                writeln!(out, "                (at start (not_blocked {} {}))", seg(m.to), p.name).unwrap();
            }
            writeln!(out, "               )").unwrap();
            writeln!(out, " :effect (and").unwrap();
            writeln!(out, "                (at start (occupied {}))", seg(m.to)).unwrap();
            writeln!(out, "                (at start (not (not_occupied {})))", seg(m.to)).unwrap();
            writeln!(out, "                (at end (not (occupied {})))", seg(m.from)).unwrap();
            writeln!(out, "                (at end (not_occupied {}))", seg(m.from)).unwrap();
            writeln!(out, "                (at end (not (at-segment ?a {})))", seg(m.from)).unwrap();
            writeln!(out, "                (at end (at-segment ?a {}))", seg(m.to)).unwrap();
            for &b in &behind {
                writeln!(out, "                (at end (blocked {} ?a))", seg(b)).unwrap();
                writeln!(out, "                (at end (not (not_blocked {} ?a)))", seg(b)).unwrap();
            }
            for &f in &freed {
                writeln!(out, "                (at end (not (blocked {} ?a)))", seg(f)).unwrap();
                writeln!(out, "                (at end (not_blocked {} ?a))", seg(f)).unwrap();
            }
            writeln!(out, "               )\n)").unwrap();
        }
    }
    for &(door, pp) in &a.gates {
        for (ty, speed) in TYPES {
            writeln!(out, "\n(:durative-action pushback_{}_{}_{ty}", seg(pp), seg(door)).unwrap();
            writeln!(out, " :parameters (?a - airplane)").unwrap();
            writeln!(out, " :duration (= ?duration {})", duration(a.segments[door].length, speed / 3))
                .unwrap();
            writeln!(out, " :condition (and").unwrap();
            writeln!(out, "                (over all (has-type ?a {ty}))").unwrap();
            writeln!(out, "                (over all (is-pushing ?a))").unwrap();
            writeln!(out, "                (at start (facing ?a south))").unwrap();
            writeln!(out, "                (at start (at-segment ?a {}))", seg(pp)).unwrap();
            writeln!(out, "                (at start (not_occupied {}))", seg(door)).unwrap();
            for p in &a.planes {
                writeln!(out, "                (at start (not_blocked {} {}))", seg(door), p.name).unwrap();
            }
            writeln!(out, "               )").unwrap();
            writeln!(out, " :effect (and").unwrap();
            writeln!(out, "                (at start (occupied {}))", seg(door)).unwrap();
            writeln!(out, "                (at start (not (not_occupied {})))", seg(door)).unwrap();
            writeln!(out, "                (at end (not (occupied {})))", seg(pp)).unwrap();
            writeln!(out, "                (at end (not_occupied {}))", seg(pp)).unwrap();
            writeln!(out, "                (at end (not (at-segment ?a {})))", seg(pp)).unwrap();
            writeln!(out, "                (at end (at-segment ?a {}))", seg(door)).unwrap();
            writeln!(out, "                (at end (blocked {} ?a))", seg(pp)).unwrap();
            writeln!(out, "                (at end (not (not_blocked {} ?a)))", seg(pp)).unwrap();
            writeln!(out, "               )\n)").unwrap();
        }
        writeln!(out, "\n(:durative-action startup_{}", seg(door)).unwrap();
        writeln!(out, " :parameters (?a - airplane)").unwrap();
        writeln!(out, " :duration (= ?duration 60)").unwrap();
        writeln!(out, " :condition (and").unwrap();
        writeln!(out, "                (at start (is-pushing ?a))").unwrap();
        writeln!(out, "                (over all (at-segment ?a {}))", seg(door)).unwrap();
        writeln!(out, "               )").unwrap();
        writeln!(out, " :effect (and").unwrap();
        writeln!(out, "                (at end (not (is-pushing ?a)))").unwrap();
        writeln!(out, "                (at end (is-moving ?a))").unwrap();
        writeln!(out, "                (at end (not (facing ?a south)))").unwrap();
        writeln!(out, "                (at end (facing ?a north))").unwrap();
        writeln!(out, "                (at end (not (blocked {} ?a)))", seg(pp)).unwrap();
        writeln!(out, "                (at end (not_blocked {} ?a))", seg(pp)).unwrap();
        writeln!(out, "               )\n)").unwrap();
        writeln!(out, "\n(:durative-action park_{}", seg(pp)).unwrap();
        writeln!(out, " :parameters (?a - airplane)").unwrap();
        writeln!(out, " :duration (= ?duration 40)").unwrap();
        writeln!(out, " :condition (and").unwrap();
        writeln!(out, "                (at start (at-segment ?a {}))", seg(pp)).unwrap();
        writeln!(out, "                (at start (is-moving ?a))").unwrap();
        writeln!(out, "               )").unwrap();
        writeln!(out, " :effect (and").unwrap();
        writeln!(out, "                (at end (is-parked ?a {}))", seg(pp)).unwrap();
        writeln!(out, "                (at end (not (is-moving ?a)))").unwrap();
        writeln!(out, "                (at end (not (blocked {} ?a)))", seg(door)).unwrap();
        writeln!(out, "                (at end (not_blocked {} ?a))", seg(door)).unwrap();
        writeln!(out, "               )\n)").unwrap();
    }
    for &s in &a.runway_starts {
        writeln!(out, "\n(:durative-action takeoff_{}_north", seg(s)).unwrap();
        writeln!(out, " :parameters (?a - airplane)").unwrap();
        writeln!(out, " :duration (= ?duration 30)").unwrap();
        writeln!(out, " :condition (and").unwrap();
        writeln!(out, "                (at start (at-segment ?a {}))", seg(s)).unwrap();
        writeln!(out, "                (at start (facing ?a north))").unwrap();
        writeln!(out, "                (at start (is-start-runway {} north))", seg(s)).unwrap();
        writeln!(out, "                (at start (is-moving ?a))").unwrap();
        writeln!(out, "               )").unwrap();
        writeln!(out, " :effect (and").unwrap();
        writeln!(out, "                (at end (not (occupied {})))", seg(s)).unwrap();
        writeln!(out, "                (at end (not_occupied {}))", seg(s)).unwrap();
        writeln!(out, "                (at end (not (at-segment ?a {})))", seg(s)).unwrap();
        writeln!(out, "                (at end (airborne ?a {}))", seg(s)).unwrap();
        writeln!(out, "                (at end (not (is-moving ?a)))").unwrap();
        for &n in &a.next[s] {
            writeln!(out, "                (at end (not (blocked {} ?a)))", seg(n)).unwrap();
            writeln!(out, "                (at end (not_blocked {} ?a))", seg(n)).unwrap();
        }
        writeln!(out, "               )\n)").unwrap();
    }
    writeln!(out, ")").unwrap();
    out
}

fn problem(a: &Airport, name: &str, domain: &str, command: &str) -> String {
    let mut out = String::new();
    header(&mut out, "the problem", command);
    writeln!(out, "(define (problem {name})").unwrap();
    writeln!(out, "(:domain {domain})").unwrap();
    writeln!(out, "(:init").unwrap();
    for p in &a.planes {
        writeln!(out, "      (has-type {} {})", p.name, TYPES[p.ty].0).unwrap();
    }
    for &s in &a.runway_starts {
        writeln!(out, "      (is-start-runway {} north)", a.segments[s].name).unwrap();
    }
    for (i, s) in a.segments.iter().enumerate() {
        if a.planes.iter().any(|p| p.at == i) {
            writeln!(out, "      (occupied {})", s.name).unwrap();
        } else {
            writeln!(out, "      (not_occupied {})", s.name).unwrap();
        }
        for p in &a.planes {
            writeln!(out, "      (not_blocked {} {})", s.name, p.name).unwrap();
        }
    }
    for p in &a.planes {
        let at = &a.segments[p.at].name;
        writeln!(out, "      (at-segment {} {at})", p.name).unwrap();
        writeln!(out, "      (facing {} {})", p.name, p.facing).unwrap();
        if p.parked {
            writeln!(out, "      (is-pushing {})", p.name).unwrap();
        } else {
            writeln!(out, "      (is-moving {})", p.name).unwrap();
        }
    }
    writeln!(out, ")").unwrap();
    writeln!(out, "(:goal (and").unwrap();
    for p in &a.planes {
        let goal = &a.segments[p.goal].name;
        if a.segments[p.goal].kind == Kind::Parking {
            writeln!(out, "      (is-parked {} {goal})", p.name).unwrap();
        } else {
            writeln!(out, "      (airborne {} {goal})", p.name).unwrap();
        }
    }
    writeln!(out, "))").unwrap();
    writeln!(out, "(:metric minimize (total-time))").unwrap();
    writeln!(out, ")").unwrap();
    out
}

/// One domain and problem pair whose two files together are about `size_mb`
/// MiB, named `name` (the domain is `name-domain`).
pub fn pair(size_mb: f64, seed: u64, name: &str, command: &str) -> (String, String) {
    let target = size_mb * MIB;
    let render = |length: usize| {
        let runways = if length < 8 { 1 } else { 2 };
        let a = build(runways, length, seed);
        let d = domain(&a, &format!("{name}-domain"), command);
        let p = problem(&a, name, &format!("{name}-domain"), command);
        (d, p)
    };
    // The size grows with the runways' length: find the length whose size is closest, by bisection.
    let size = |f: &(String, String)| (f.0.len() + f.1.len()) as f64;
    let (mut lo, mut hi) = (2usize, 4usize);
    let mut files = render(hi);
    while size(&files) < target {
        lo = hi;
        hi *= 2;
        files = render(hi);
    }
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        let f = render(mid);
        if size(&f) < target {
            lo = mid;
        } else {
            (hi, files) = (mid, f);
        }
    }
    let below = render(lo);
    if target - size(&below) < size(&files) - target { below } else { files }
}

/// The domain and problem of one airport of about `size_mb` MiB.
pub fn airport(size_mb: f64, seed: u64) -> (String, String) {
    let command = format!(
        "cargo run --release -p hipop-samplegen -- airport --size-mb {size_mb} --seed {seed} --out DIR"
    );
    pair(size_mb, seed, "airport", &command)
}

/// A folder of `pairs` airports in the manner of the IPC 2004 Airport set
/// (`pNN-domain.pddl` beside `pNN-airport.pddl`), their sizes growing
/// linearly up to `size_mb` MiB per pair, as `(file name, text)`.
pub fn airport_set(pairs: usize, size_mb: f64, seed: u64) -> Vec<(String, String)> {
    let command = format!(
        "cargo run --release -p hipop-samplegen -- airport-set --pairs {pairs} --size-mb {size_mb} --seed {seed} --out DIR"
    );
    let mut files = Vec::new();
    for i in 1..=pairs {
        let size = size_mb * i as f64 / pairs as f64;
        let stem = format!("p{i:02}");
        let (d, p) = pair(size, seed.wrapping_add(i as u64), &format!("{stem}-airport"), &command);
        files.push((format!("{stem}-domain.pddl"), d));
        files.push((format!("{stem}-airport.pddl"), p));
    }
    files
}
