//! A plan that solves a Survivors problem, built by construction: each team
//! patrols a run of zones (moving between them along shortest paths), then
//! the survivors are carried, one after the other, by the team that is free
//! first, to their nearest hospital.
//!
//! Written in VAL's format (the primitive steps) and in hipop's timed IPC
//! 2020 hierarchical format (the same steps, the patrols with their methods,
//! and `;@` timing annotations), see docs/plan-formats.md. Dependent
//! happenings are [`GAP_CS`] (0.01 s) apart.

use std::fmt::Write;

use super::{
    CARRY_FACTOR, EXPLORE_CS, GAP_CS, Leg, Map, RESCUE_CS, Split, ZONES_PER_ROW, patrol_name, team_robots,
    walks, zone_name,
};

/// A primitive step.
#[derive(Debug, Clone, PartialEq)]
struct Action {
    name: &'static str,
    args: Vec<String>,
    start: u64,
    duration: u64,
}

/// A patrol, with the method that refines it and its subtasks (indices of
/// [`Witness::actions`], in the method's order).
#[derive(Debug, Clone, PartialEq)]
struct Patrol {
    task: String,
    args: Vec<String>,
    method: String,
    subtasks: Vec<usize>,
    start: u64,
    duration: u64,
}

/// A witness plan.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Witness {
    actions: Vec<Action>,
    patrols: Vec<Patrol>,
}

/// `1234` cs → `12.340`.
fn time(cs: u64) -> String {
    format!("{}.{:02}0", cs / 100, cs % 100)
}

impl Witness {
    /// The plan of the problem of `map`.
    pub fn new(map: &Map) -> Witness {
        let mut w = Witness::default();
        let p = map.params;
        let mut free = vec![0u64; p.teams];
        let mut at = vec![map.base; p.teams];
        // Zones in a serpentine order (row by row, alternating directions),
        // cut into one run per team.
        let order: Vec<usize> = (0..p.rows)
            .flat_map(|r| {
                let row = [r * ZONES_PER_ROW, r * ZONES_PER_ROW + 1];
                if r.is_multiple_of(2) { row } else { [row[1], row[0]] }
            })
            .collect();
        let mut next = 0;
        for t in 0..p.teams {
            let n = order.len() / p.teams + usize::from(t < order.len() % p.teams);
            for &z in &order[next..next + n] {
                let start = map.cell(z, (1, 1));
                free[t] = w.travel(map, t, at[t], start, free[t]);
                free[t] = w.patrol(map, t, z, free[t]);
                at[t] = map.cell(z, (p.side, p.side));
            }
            next += n;
        }
        // Survivors, by the team free first, to the nearest hospital.
        for (s, &loc) in map.survivors.iter().enumerate() {
            let t = (0..p.teams).min_by_key(|&t| (free[t], t)).unwrap();
            let mut now = w.travel(map, t, at[t], loc, free[t]);
            let (path, _) =
                map.hospitals.iter().map(|&h| map.path(loc, h)).min_by_key(|(_, d)| *d).expect("a hospital");
            let [r1, r2] = team_robots(t);
            let survivor = format!("s{}", s + 1);
            let mut from = loc;
            for to in path {
                let d = CARRY_FACTOR * map.dist(from, to);
                let args =
                    vec![survivor.clone(), r1.clone(), r2.clone(), map.loc_name(from), map.loc_name(to)];
                w.push("carry", args, now, d);
                now += d + GAP_CS;
                from = to;
            }
            w.push("rescue", vec![survivor, r1, r2, map.loc_name(from)], now, RESCUE_CS);
            free[t] = now + RESCUE_CS + GAP_CS;
            at[t] = from;
        }
        w
    }

    fn push(&mut self, name: &'static str, args: Vec<String>, start: u64, duration: u64) -> usize {
        self.actions.push(Action { name, args, start, duration });
        self.actions.len() - 1
    }

    /// Both robots of team `t` go from `from` to `to` side by side, from
    /// `now`; returns when they can start their next step.
    fn travel(&mut self, map: &Map, t: usize, from: usize, to: usize, mut now: u64) -> u64 {
        let mut a = from;
        for b in map.path(from, to).0 {
            let d = map.dist(a, b);
            for r in team_robots(t) {
                self.push("move", vec![r, map.loc_name(a), map.loc_name(b)], now, d);
            }
            now += d + GAP_CS;
            a = b;
        }
        now
    }

    /// Team `t` patrols zone `z` from `now`, with the method whose walks end
    /// first; returns when the patrol is over.
    fn patrol(&mut self, map: &Map, t: usize, z: usize, now: u64) -> u64 {
        let side = map.params.side;
        let split = *Split::ALL.iter().min_by_key(|&&s| map.walk_spans(z, s).into_iter().max()).unwrap();
        let duration = map.patrol_cs(z);
        let robots = team_robots(t);
        let mut subtasks = Vec::new();
        for (legs, r) in walks(side, split).iter().zip(&robots) {
            let mut clock = now;
            for leg in legs {
                let (id, d) = match *leg {
                    Leg::Explore(c) => (
                        self.push(
                            "explore",
                            vec![r.clone(), map.loc_name(map.cell(z, c))],
                            clock,
                            EXPLORE_CS,
                        ),
                        EXPLORE_CS,
                    ),
                    Leg::Move(a, b) => {
                        let (a, b) = (map.cell(z, a), map.cell(z, b));
                        let d = map.dist(a, b);
                        (self.push("move", vec![r.clone(), map.loc_name(a), map.loc_name(b)], clock, d), d)
                    }
                };
                subtasks.push(id);
                clock += d + GAP_CS;
            }
            assert!(clock - GAP_CS <= now + duration, "a walk of {} outlasts its patrol", zone_name(z));
        }
        let mut args = robots.to_vec();
        args.push(zone_name(z));
        for i in 1..=side {
            for j in 1..=side {
                args.push(map.loc_name(map.cell(z, (i, j))));
            }
        }
        let task = patrol_name(side);
        let method = format!("{task}-{}", split.suffix());
        self.patrols.push(Patrol { task, args, method, subtasks, start: now, duration });
        now + duration + GAP_CS
    }

    /// The primitive steps in the order of their start times (then of creation).
    fn order(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.actions.len()).collect();
        order.sort_by_key(|&i| (self.actions[i].start, i));
        order
    }

    /// When the last step ends, in cs.
    pub fn makespan(&self) -> u64 {
        self.actions.iter().map(|a| a.start + a.duration).max().unwrap_or(0)
    }

    fn header(&self, out: &mut String, stem: &str, format: &str) {
        writeln!(
            out,
            "; Witness plan of {stem} (Survivors benchmark), {format}, written by hipop-samplegen (survivors --witness)."
        )
        .unwrap();
        writeln!(
            out,
            "; {} actions, {} patrols, makespan {}. Each team patrols a run of zones, then the survivors",
            self.actions.len(),
            self.patrols.len(),
            time(self.makespan())
        )
        .unwrap();
        writeln!(out, "; are carried, each by the team free first, to their nearest hospital.").unwrap();
    }

    /// The plan in VAL's format.
    pub fn val(&self, stem: &str) -> String {
        let mut out = String::new();
        self.header(&mut out, stem, "VAL format");
        for i in self.order() {
            let a = &self.actions[i];
            writeln!(out, "{}: ({} {}) [{}]", time(a.start), a.name, a.args.join(" "), time(a.duration))
                .unwrap();
        }
        out
    }

    /// The plan in hipop's timed IPC 2020 hierarchical format.
    pub fn hierarchical(&self, stem: &str) -> String {
        let mut out = String::new();
        self.header(&mut out, stem, "timed IPC 2020 hierarchical format");
        let order = self.order();
        let mut id = vec![0usize; self.actions.len()];
        for (k, &i) in order.iter().enumerate() {
            id[i] = k;
        }
        let n = self.actions.len();
        writeln!(out, "==>").unwrap();
        for (k, &i) in order.iter().enumerate() {
            let a = &self.actions[i];
            writeln!(out, "{k} {} {}", a.name, a.args.join(" ")).unwrap();
        }
        // The roots: the patrols and the actions that no patrol contains, by start time.
        let mut inside = vec![false; n];
        for p in &self.patrols {
            for &s in &p.subtasks {
                inside[s] = true;
            }
        }
        let mut roots: Vec<(u64, usize, usize)> =
            self.patrols.iter().enumerate().map(|(k, p)| (p.start, 0, n + k)).collect();
        roots.extend(order.iter().filter(|&&i| !inside[i]).map(|&i| (self.actions[i].start, 1, id[i])));
        roots.sort();
        let roots: Vec<String> = roots.iter().map(|r| r.2.to_string()).collect();
        writeln!(out, "root {}", roots.join(" ")).unwrap();
        for (k, p) in self.patrols.iter().enumerate() {
            let subtasks: Vec<String> = p.subtasks.iter().map(|&s| id[s].to_string()).collect();
            writeln!(out, "{} {} {} -> {} {}", n + k, p.task, p.args.join(" "), p.method, subtasks.join(" "))
                .unwrap();
        }
        writeln!(out, "<==").unwrap();
        for (k, &i) in order.iter().enumerate() {
            let a = &self.actions[i];
            writeln!(out, ";@ {k} {} [{}]", time(a.start), time(a.duration)).unwrap();
        }
        for (k, p) in self.patrols.iter().enumerate() {
            writeln!(out, ";@ {} {} [{}]", n + k, time(p.start), time(p.duration)).unwrap();
        }
        out
    }
}
