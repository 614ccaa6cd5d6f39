//! Redundant steps: before a plan without abstract steps is returned, the
//! steps it can do without are removed (action elimination, Nakhost and
//! Müller 2010, on the plan's schedule).
//!
//! The schedule is simulated forward, happening by happening, as the
//! validator reads it: at-start conditions before the start's effects,
//! `over all` ones after them and after every happening until the end,
//! at-end ones before the end's effects, deletions before additions in a
//! happening, timed literals up to the plan's last happening, the goals
//! after it. Each step in start order is tried alone, then with the steps
//! whose causal links only served it (and so on, as the plan bench counts
//! them); the simulation drops every later step whose conditions no
//! longer hold, and when the goals still hold, they are all removed. Each
//! try is one simulation (or a few, when a step that started fails
//! later): the pass takes a time quadratic in the plan's size at worst,
//! a few milliseconds for plans of a hundred steps. The steps left are the start plan of a
//! repair without anything to repair ([`Search::seeded`]: each condition
//! linked to its latest producer in the schedule, each threat ordered as
//! there), which the simulation checks again at its earliest schedule;
//! then again, until no step can go.
//!
//! Removing steps at the same times leaves every pair of interfering
//! happenings as far apart as it was; the start plan orders each threat
//! as the schedule had it, and its mutexes are the search's flaws
//! ([`Search::select`]): a start plan with flaws left is completed by a
//! short greedy descent that may not add a step, else the pass stops
//! where it is. Plans with abstract steps are left as they are: their
//! steps are their methods'.

use super::super::Stats;
use super::super::plan::{Kind, Plan};
use super::super::stn::Tp;
use super::super::task::{End, Lit, atom_of, is_neg};
use super::{Search, Seed, SeedStep};

/// A happening of the schedule: a step's start or end, or a timed literal.
#[derive(Debug, Clone, Copy)]
struct Happening {
    t: f64,
    step: u32,
    tp: Tp,
    end: bool,
}

/// How a simulation ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Run {
    Valid,
    Invalid,
    /// A step started whose `over all` or at-end condition fails later: the
    /// simulation goes again without it.
    Without(u32),
}

/// What the pass removed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Removed {
    pub steps: usize,
}

impl Search<'_, '_> {
    /// The plan without its redundant steps (a plan with abstract steps is
    /// returned as it is), and how many went. `stop` is polled at every
    /// step tried: when it says so, the steps found so far go, no more.
    pub fn without_redundant_steps(&self, p: Plan, stop: &dyn Fn() -> bool) -> (Plan, Removed) {
        let mut removed = Removed::default();
        // Numeric fluents: the simulation follows literals only, and
        // removing a step that changes a fluent (a `refuel`) changes what
        // later steps read; such plans are left as they are.
        if self.task.htn.is_some()
            || !self.task.numeric.is_empty()
            || p.steps.iter().any(|s| !self.elementary_or_fixed(s.kind))
        {
            return (p, removed);
        }
        let mut p = p;
        // Each round removes a step at least; a handful is plenty (the
        // rounds after the first only see what the new links show).
        for _ in 0..8 {
            if stop() {
                break;
            }
            let gone = self.eliminate(&p, stop);
            let n = gone.iter().filter(|&&g| g).count();
            if n == 0 {
                break;
            }
            match self.rebuild(&p, &gone) {
                Some(next) => {
                    removed.steps += n;
                    p = next;
                }
                None => break,
            }
        }
        (p, removed)
    }

    /// A step the pass understands: an elementary action, the initial
    /// state, the goal, a timed literal.
    fn elementary_or_fixed(&self, k: Kind) -> bool {
        match k {
            Kind::Op(o) => !self.task.ops[o as usize].is_abstract,
            _ => true,
        }
    }

    /// The steps that can go, by action elimination over the plan's
    /// earliest schedule.
    pub(super) fn eliminate(&self, p: &Plan, stop: &dyn Fn() -> bool) -> Vec<bool> {
        let events = happenings(self, p);
        let n = p.steps.len();
        let mut gone = vec![false; n];
        // The producers of each step's conditions, by causal link.
        let mut producers: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut consumers: Vec<Vec<u32>> = vec![Vec::new(); n];
        for l in p.links.iter() {
            producers[l.to as usize].push(l.from);
            consumers[l.from as usize].push(l.to);
        }
        let mut order: Vec<u32> = (0..n as u32).filter(|&s| p.op_of(s).is_some()).collect();
        order.sort_by(|&a, &b| {
            let (sa, sb) = (p.steps[a as usize], p.steps[b as usize]);
            p.stn.est(sa.start).total_cmp(&p.stn.est(sb.start)).then(a.cmp(&b))
        });
        // Runs the schedule without `trial`, dropping the later steps that
        // can no longer run (a step that started and fails later: again
        // without it); `true` when the goals still hold.
        let attempt = |trial: &mut Vec<bool>| {
            for _ in 0..=n {
                match simulate(self, p, &events, trial, true) {
                    Run::Without(x) => trial[x as usize] = true,
                    Run::Valid => return simulate(self, p, &events, trial, false) == Run::Valid,
                    Run::Invalid => return false,
                }
            }
            false
        };
        let mut trial = gone.clone();
        for &s in &order {
            if stop() {
                break;
            }
            if gone[s as usize] {
                continue;
            }
            // The step alone (and what needed it), as action elimination
            // does.
            trial.copy_from_slice(&gone);
            trial[s as usize] = true;
            if attempt(&mut trial) {
                gone.copy_from_slice(&trial);
                continue;
            }
            // With the producers whose every link served removed steps
            // (a producer another step could replace stays).
            trial.copy_from_slice(&gone);
            trial[s as usize] = true;
            let mut work = vec![s];
            let mut more = false;
            while let Some(r) = work.pop() {
                for &q in &producers[r as usize] {
                    if p.op_of(q).is_some()
                        && !trial[q as usize]
                        && consumers[q as usize].iter().all(|&c| trial[c as usize])
                    {
                        trial[q as usize] = true;
                        more = true;
                        work.push(q);
                    }
                }
            }
            if more && attempt(&mut trial) {
                gone.copy_from_slice(&trial);
            }
        }
        gone
    }

    /// The plan of the steps not `gone`: linked and ordered as the
    /// schedule has them, at its earliest schedule. `None` when it cannot be
    /// built without adding steps, or is not valid, or ends later.
    fn rebuild(&self, p: &Plan, gone: &[bool]) -> Option<Plan> {
        let mut steps = Vec::new();
        for (s, st) in p.steps.iter().enumerate() {
            let Kind::Op(op) = st.kind else { continue };
            if gone[s] {
                continue;
            }
            steps.push(SeedStep {
                op,
                parent: None,
                method: None,
                start: p.stn.est(st.start),
                end: p.stn.est(st.end),
                fixed: false,
                done: false,
            });
        }
        let seed = Seed { steps, orders: Vec::new(), now: None };
        let (mut c, _) = self.seeded(&seed).ok()?.into_iter().next()?;
        // The earliest schedule, not the old one.
        c.old_times = Default::default();
        c.stn.flush();
        let size = c.steps.len();
        let mut c = match self.select(&mut c) {
            None => c,
            Some(_) => {
                let mut stats = Stats::default();
                let done = self.probe(vec![c], 64 + 4 * size as u64, &|_| true, &mut stats, &|| false)?;
                if done.steps.len() != size {
                    return None;
                }
                done
            }
        };
        c.stn.flush();
        let events = happenings(self, &c);
        let mut none = vec![false; c.steps.len()];
        let valid = simulate(self, &c, &events, &mut none, false) == Run::Valid;
        let makespan = |p: &Plan| {
            p.steps
                .iter()
                .filter(|s| matches!(s.kind, Kind::Op(_)))
                .map(|s| p.stn.est(s.end))
                .fold(0.0, f64::max)
        };
        (valid && makespan(&c) <= makespan(p) + 1e-9).then_some(c)
    }
}

/// The happenings of a plan's primitive steps and timed literals, by time.
fn happenings(search: &Search<'_, '_>, p: &Plan) -> Vec<Happening> {
    let mut out = Vec::with_capacity(2 * p.steps.len());
    for (s, st) in p.steps.iter().enumerate() {
        let s = s as u32;
        match st.kind {
            Kind::Op(o) => {
                out.push(Happening { t: p.stn.est(st.start), step: s, tp: st.start, end: false });
                if !search.task.ops[o as usize].instant {
                    out.push(Happening { t: p.stn.est(st.end), step: s, tp: st.end, end: true });
                }
            }
            Kind::Til(_) => out.push(Happening { t: p.stn.est(st.start), step: s, tp: st.start, end: false }),
            Kind::Init | Kind::Goal => {}
        }
    }
    out.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.tp.cmp(&b.tp)));
    out
}

fn holds(state: &[bool], l: Lit) -> bool {
    state[atom_of(l) as usize] != is_neg(l)
}

/// Runs the schedule without the steps `gone`: `Valid` when every
/// condition of the steps run and every goal holds. With `drop`, a step
/// whose at-start conditions fail is not run (it is added to `gone`), and
/// one that started and fails later gives `Without` it.
fn simulate(search: &Search<'_, '_>, p: &Plan, events: &[Happening], gone: &mut [bool], drop: bool) -> Run {
    let task = search.task;
    let mut state = task.init.clone();
    // Timed literals apply up to the plan's last happening (VAL applies
    // none after it).
    let last = events
        .iter()
        .filter(|e| matches!(p.steps[e.step as usize].kind, Kind::Op(_)) && !gone[e.step as usize])
        .map(|e| e.t)
        .fold(0.0, f64::max);
    // `over all` conditions running: (step, literal, end).
    let mut invariants: Vec<(u32, Lit, f64)> = Vec::new();
    let mut adds: Vec<u32> = Vec::new();
    let mut dels: Vec<u32> = Vec::new();
    let mut i = 0;
    while i < events.len() {
        let t = events[i].t;
        let mut j = i;
        while j < events.len() && events[j].t == t {
            j += 1;
        }
        let group = &events[i..j];
        i = j;
        // Conditions, in the state before the happening.
        for e in group {
            let Kind::Op(o) = p.steps[e.step as usize].kind else { continue };
            if gone[e.step as usize] {
                continue;
            }
            let op = &task.ops[o as usize];
            let ok = op.conds.iter().all(|c| {
                let checked = if op.instant {
                    true
                } else if e.end {
                    c.at == End::End
                } else {
                    c.at == End::Start && c.until == End::Start
                };
                !checked || holds(&state, c.lit)
            });
            if !ok {
                if !drop {
                    return Run::Invalid;
                }
                if e.end {
                    return Run::Without(e.step);
                }
                gone[e.step as usize] = true;
            }
        }
        // Effects: deletions, then additions.
        adds.clear();
        dels.clear();
        for e in group {
            if gone[e.step as usize] {
                continue;
            }
            match p.steps[e.step as usize].kind {
                Kind::Op(o) => {
                    let op = &task.ops[o as usize];
                    for eff in &op.effs {
                        let here = op.instant || (eff.at == End::End) == e.end;
                        if here {
                            if is_neg(eff.lit) {
                                dels.push(atom_of(eff.lit))
                            } else {
                                adds.push(atom_of(eff.lit))
                            }
                        }
                    }
                }
                Kind::Til(k) => {
                    if t <= last + 1e-9 {
                        let l = task.tils[k as usize].lit;
                        if is_neg(l) { dels.push(atom_of(l)) } else { adds.push(atom_of(l)) }
                    }
                }
                Kind::Init | Kind::Goal => {}
            }
        }
        for &a in &dels {
            state[a as usize] = false;
        }
        for &a in &adds {
            state[a as usize] = true;
        }
        // `over all`: from just after the start to the end (exclusive).
        invariants.retain(|&(s, _, end)| end > t && !gone[s as usize]);
        for e in group {
            let Kind::Op(o) = p.steps[e.step as usize].kind else { continue };
            if e.end || gone[e.step as usize] {
                continue;
            }
            let op = &task.ops[o as usize];
            if op.instant {
                continue;
            }
            let end = p.stn.est(p.steps[e.step as usize].end);
            for c in &op.conds {
                if c.at == End::Start && c.until == End::End {
                    invariants.push((e.step, c.lit, end));
                }
            }
        }
        if let Some(&(s, _, _)) = invariants.iter().find(|&&(_, l, _)| !holds(&state, l)) {
            return if drop { Run::Without(s) } else { Run::Invalid };
        }
    }
    if task.goals.iter().all(|&(l, _)| holds(&state, l)) { Run::Valid } else { Run::Invalid }
}

#[cfg(test)]
mod tests {
    use super::super::super::{Config, PlannerLimits, output, prepare};
    use super::*;
    use crate::AnalysisHost;

    /// A small durative domain: a door to close before a launch (a
    /// negative condition), a lamp that two actions toggle (they
    /// interfere), and a beacon nothing needs.
    const DOMAIN: &str = "(define (domain pass)
  (:requirements :typing :durative-actions :negative-preconditions)
  (:predicates (door-open) (launched) (lamp) (lit-once) (dark-once) (beacon)
    (ready) (red) (done-red) (done-blue))
  (:durative-action close :parameters () :duration (= ?duration 1)
    :condition (at start (door-open)) :effect (at end (not (door-open))))
  (:durative-action launch :parameters () :duration (= ?duration 2)
    :condition (at start (not (door-open))) :effect (at end (launched)))
  (:durative-action light :parameters () :duration (= ?duration 1)
    :condition (at start (not (lamp))) :effect (and (at end (lamp)) (at end (lit-once))))
  (:durative-action darken :parameters () :duration (= ?duration 1)
    :condition (at start (lamp)) :effect (and (at end (not (lamp))) (at end (dark-once))))
  (:durative-action beep :parameters () :duration (= ?duration 5)
    :condition (at start (door-open)) :effect (at end (beacon)))
  (:durative-action wait :parameters () :duration (= ?duration 5)
    :condition (at start (door-open)) :effect (at end (ready)))
  (:durative-action paint-red :parameters () :duration (= ?duration 2)
    :condition (at start (ready)) :effect (and (at end (red)) (at end (done-red))))
  (:durative-action paint-blue :parameters () :duration (= ?duration 2)
    :condition (at start (ready)) :effect (and (at end (not (red))) (at end (done-blue)))))";

    /// Plans `steps` (operator name, start) for a problem with `init` and
    /// `goal`, passes them through [`Search::without_redundant_steps`], and
    /// returns the plan left in VAL's format, how many steps went, and
    /// whether the validator finds it valid.
    fn pass(init: &str, goal: &str, steps: &[(&str, f64)]) -> (String, usize, bool) {
        pass_until(init, goal, steps, false)
    }

    /// [`pass`], told to stop at once when `stop`.
    fn pass_until(init: &str, goal: &str, steps: &[(&str, f64)], stop: bool) -> (String, usize, bool) {
        let problem = format!("(define (problem p) (:domain pass) (:init {init}) (:goal (and {goal})))");
        let mut host = AnalysisHost::new();
        host.set_file_text("domain.pddl", DOMAIN);
        let pf = host.set_file_text("problem.pddl", problem.as_str());
        let (text, removed) = host
            .analysis()
            .with_db(|db| {
                let unit = crate::host::first_problem(db, pf).expect("a problem");
                let config = Config::default();
                // Every reachable instance: the steps given include some the
                // goal does not need, which is what the pass is about.
                let limits = PlannerLimits { goal_relevance: false, ..PlannerLimits::default() };
                let prepared = prepare(db, unit, &config, &limits).ok().expect("prepared");
                let task = &prepared.task;
                let search = Search::new(task, &prepared.h, &config);
                let seed = Seed {
                    steps: steps
                        .iter()
                        .map(|&(name, start)| {
                            let op = task
                                .ops
                                .iter()
                                .position(|o| &*o.name == name)
                                .unwrap_or_else(|| panic!("no operator {name}"))
                                as u32;
                            let d = task.ops[op as usize].duration.unwrap_or(0.0);
                            SeedStep {
                                op,
                                parent: None,
                                method: None,
                                start,
                                end: start + d,
                                fixed: false,
                                done: false,
                            }
                        })
                        .collect(),
                    orders: Vec::new(),
                    now: None,
                };
                let (mut p, _) = search.seeded(&seed).expect("seeded").into_iter().next().expect("a plan");
                p.old_times = Default::default();
                p.stn.flush();
                assert!(search.select(&mut p).is_none(), "the plan given is complete");
                let (p, removed) = search.without_redundant_steps(p, &|| stop);
                (output::solved(db, task, &p).to_val(""), removed.steps)
            })
            .expect("not cancelled");
        let f = host.set_file_text("plan.plan", text.as_str());
        let v = host
            .analysis()
            .validate_plan(f, None, pf, &Default::default())
            .expect("not cancelled")
            .expect("validated");
        let valid = v.valid && v.checked && v.diagnostics.iter().all(|d| d.code.id != "W0411");
        (text, removed, valid)
    }

    fn names(val: &str) -> Vec<&str> {
        val.lines().filter_map(|l| l.split('(').nth(1)?.split(')').next()).collect()
    }

    #[test]
    fn a_step_nothing_needs_is_removed() {
        let (val, removed, valid) =
            pass("(door-open)", "(launched)", &[("beep", 0.0), ("close", 0.01), ("launch", 1.02)]);
        assert_eq!(removed, 1, "{val}");
        assert_eq!(names(&val), ["close", "launch"], "{val}");
        assert!(valid, "{val}");
        // The schedule is the earliest without it.
        assert!(val.contains("\n0.01: (close)") || val.starts_with("0.01: (close)"), "{val}");
    }

    /// Out of time (or cancelled), the pass leaves the plan as it is.
    #[test]
    fn a_pass_told_to_stop_removes_nothing() {
        let (val, removed, valid) = pass_until(
            "(door-open)",
            "(launched)",
            &[("beep", 0.0), ("close", 0.01), ("launch", 1.02)],
            true,
        );
        assert_eq!((removed, names(&val)), (0, vec!["beep", "close", "launch"]), "{val}");
        assert!(valid, "{val}");
    }

    /// `close` makes nothing true: its only use is the negative condition
    /// of `launch`, which needs the door shut.
    #[test]
    fn a_step_that_only_deletes_what_a_negative_condition_needs_stays() {
        let (val, removed, valid) = pass("(door-open)", "(launched)", &[("close", 0.0), ("launch", 1.01)]);
        assert_eq!((removed, names(&val)), (0, vec!["close", "launch"]), "{val}");
        assert!(valid, "{val}");
    }

    /// A pair that undoes itself (`light` then `darken`) goes, and with it
    /// the wait it caused; the pair the goals need stays, its interfering
    /// happenings (both write the lamp) ε apart in the earlier schedule.
    #[test]
    fn a_pair_that_undoes_itself_goes_and_interfering_happenings_stay_apart() {
        let (val, removed, valid) = pass(
            "",
            "(lit-once) (dark-once) (launched)",
            &[("light", 0.0), ("darken", 1.01), ("light", 2.02), ("darken", 3.03), ("launch", 0.0)],
        );
        assert_eq!(removed, 2, "{val}");
        assert_eq!(names(&val), ["launch", "light", "darken"], "{val}");
        assert!(valid, "{val}");
        assert!(val.contains("\n1.02: (darken)"), "{val}");
    }

    /// `wait` makes `ready` true, which holds from the start: it goes, and
    /// `paint-blue`, which waited for it, moves to the start of the plan,
    /// where it would end with `paint-red`. Both write `red` there (a
    /// mutex, though no condition reads it): the earlier schedule keeps
    /// their ends ε apart, and the plan stays valid.
    #[test]
    fn interfering_happenings_a_removal_brings_together_stay_apart() {
        let (val, removed, valid) = pass(
            "(door-open) (ready)",
            "(done-red) (done-blue)",
            &[("wait", 0.0), ("paint-red", 0.01), ("paint-blue", 5.01)],
        );
        assert_eq!(removed, 1, "{val}");
        let mut got = names(&val);
        got.sort();
        assert_eq!(got, ["paint-blue", "paint-red"], "{val}");
        assert!(valid, "{val}");
        let ends: Vec<f64> = val
            .lines()
            .filter_map(|l| {
                let (start, rest) = l.split_once(": ")?;
                let d = rest.split('[').nth(1)?.trim_end_matches(']');
                Some(start.parse::<f64>().ok()? + d.parse::<f64>().ok()?)
            })
            .collect();
        assert_eq!(ends.len(), 2, "{val}");
        assert!((ends[0] - ends[1]).abs() >= 0.01 - 1e-9, "{val}");
        assert!(ends.iter().all(|&e| e < 5.0), "the wait is gone from the schedule: {val}");
    }
}
