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
//! longer hold, and when the goals still hold, they are all removed. A
//! try starts where the step starts, from the run of the plan as it is
//! up to there, and goes beside that run, happening by happening, only as
//! far as it must: it succeeds as soon as both states are the same again
//! and what it left out has no happening left, and fails as soon as a
//! goal is lost for good. A removal that matters locally costs a few
//! happenings, not the whole plan (the worst case, a removal felt to the
//! end of the plan, stays quadratic). The steps left are the start plan of a
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
use rustc_hash::{FxHashMap, FxHashSet};

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
        if self.task.htn.is_some() || p.steps.iter().any(|s| !self.elementary_or_fixed(s.kind)) {
            return (p, removed);
        }
        // Numeric fluents: the simulation follows literals only, so a
        // removal it finds can break a numeric condition (a `recharge` that
        // a later step's energy needs, a `refuel`); the rebuilt plan's
        // flaws say so (the search's own numeric check), and each removal
        // found is then tried alone, one a round.
        let numeric = !self.task.numeric.is_empty();
        let mut p = p;
        // Each round removes a step at least; a handful is plenty (the
        // rounds after the first only see what the new links show).
        for _ in 0..if numeric { 32 } else { 8 } {
            if stop() {
                break;
            }
            let (gone, groups) = self.eliminate(&p, stop);
            let n = gone.iter().filter(|&&g| g).count();
            if n == 0 {
                break;
            }
            match self.rebuild(&p, &gone) {
                Some(next) => {
                    removed.steps += n;
                    p = next;
                }
                None if numeric => {
                    let alone = groups.iter().find_map(|g| {
                        let mut one = vec![false; gone.len()];
                        for &s in g {
                            one[s as usize] = true;
                        }
                        Some((self.rebuild(&p, &one)?, g.len()))
                    });
                    let Some((next, k)) = alone else { break };
                    removed.steps += k;
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
    /// Also each removal found: the steps that went together.
    pub(super) fn eliminate(&self, p: &Plan, stop: &dyn Fn() -> bool) -> (Vec<bool>, Vec<Vec<u32>>) {
        let (gone, _, groups) = self.eliminate_counting(p, stop);
        (gone, groups)
    }

    /// [`Search::eliminate`], and how many groups of happenings it
    /// simulated in all (the measure of its work).
    fn eliminate_counting(&self, p: &Plan, stop: &dyn Fn() -> bool) -> (Vec<bool>, u64, Vec<Vec<u32>>) {
        let events = happenings(self, p);
        let n = p.steps.len();
        let mut gone = vec![false; n];
        let mut work = 0u64;
        let mut groups: Vec<Vec<u32>> = Vec::new();
        // The reference run: the plan as it is must be valid under these
        // rules, since every try is compared with it.
        if simulate(self, p, &events, &mut gone.clone(), false) != Run::Valid {
            return (gone, work, groups);
        }
        let goals = Goals::new(self, p, &events);
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
        let mut read = vec![false; self.task.init.len()];
        for &(l, _) in &self.task.goals {
            read[atom_of(l) as usize] = true;
        }
        for st in p.steps.iter() {
            if let Kind::Op(o) = st.kind {
                for c in &self.task.ops[o as usize].conds {
                    read[atom_of(c.lit) as usize] = true;
                }
            }
        }
        let cx = Tries { search: self, p, events: &events, goals: &goals, read: &read };
        // The reference run up to the start of the step tried: the steps
        // are tried in start order, so it only moves forward (and starts
        // again when a try is kept).
        let mut base = Sim::new(self, p, &events, &gone);
        let mut trial = gone.clone();
        for &s in &order {
            if stop() {
                break;
            }
            if gone[s as usize] {
                continue;
            }
            let t0 = p.stn.est(p.steps[s as usize].start);
            while !base.done(&events) && events[base.i].t < t0 {
                work += 1;
                if base.group(self, p, &events, &mut gone, false).is_some() {
                    // Not valid after all: keep what was found.
                    return (gone, work, groups);
                }
            }
            // The step alone (and what needed it), as action elimination
            // does.
            trial.copy_from_slice(&gone);
            trial[s as usize] = true;
            let mut extra = vec![s];
            if cx.attempt(&base, &mut gone, &mut trial, &mut extra, &mut work) {
                gone.copy_from_slice(&trial);
                groups.push(extra.clone());
                // What the trial did without starts at `t0` or later (unless
                // it went again from the start): the reference run up to
                // `t0` is the same, but for the timed literals when the
                // plan's last happening moved.
                let later = extra.iter().all(|&x| p.stn.est(p.steps[x as usize].start) >= t0);
                if !later || last_happening(p, &events, &gone) != base.last {
                    base = cx.replay(&mut gone, t0, &mut work);
                }
                continue;
            }
            // With the producers whose every link served removed steps
            // (a producer another step could replace stays).
            trial.copy_from_slice(&gone);
            trial[s as usize] = true;
            let mut extra = vec![s];
            let mut work_list = vec![s];
            while let Some(r) = work_list.pop() {
                for &q in &producers[r as usize] {
                    if p.op_of(q).is_some()
                        && !trial[q as usize]
                        && consumers[q as usize].iter().all(|&c| trial[c as usize])
                    {
                        trial[q as usize] = true;
                        extra.push(q);
                        work_list.push(q);
                    }
                }
            }
            // The producers started earlier: from the start of the plan.
            if extra.len() > 1
                && cx.attempt(
                    &Sim::new(self, p, &events, &gone),
                    &mut gone,
                    &mut trial,
                    &mut extra,
                    &mut work,
                )
            {
                gone.copy_from_slice(&trial);
                groups.push(extra);
                base = cx.replay(&mut gone, t0, &mut work);
            }
        }
        (gone, work, groups)
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
                let done =
                    self.probe(vec![c], 64 + 4 * size as u64, size, &|_| true, &mut stats, &|| false, true)?;
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

/// What a try needs: the plan, its happenings, and the goals' achievers.
struct Tries<'a, 's, 'db> {
    search: &'a Search<'s, 'db>,
    p: &'a Plan,
    events: &'a [Happening],
    goals: &'a Goals,
    /// The atoms a condition of the plan's steps or a goal reads.
    read: &'a [bool],
}

impl Tries<'_, '_, '_> {
    /// Whether the schedule runs without `trial` (the steps not `base`
    /// less `extra`, and the later steps that can no longer run, which
    /// join both): from `from`, where the reference run (the steps not
    /// `base`, valid) stands. A step that started and fails later: again
    /// without it, from the start of the plan. `base` is borrowed mutably
    /// for [`Sim::group`] only, which changes nothing without `drop`: no
    /// copy of it per try.
    fn attempt(
        &self,
        from: &Sim,
        base: &mut [bool],
        trial: &mut [bool],
        extra: &mut Vec<u32>,
        work: &mut u64,
    ) -> bool {
        let mut restart: Option<Sim> = None;
        for _ in 0..=self.p.steps.len() {
            let start = restart.as_ref().unwrap_or(from);
            match self.converge(start, base, trial, extra, true, work) {
                Run::Without(x) => {
                    trial[x as usize] = true;
                    extra.push(x);
                    restart = Some(Sim::new(self.search, self.p, self.events, base));
                }
                Run::Valid => return self.converge(start, base, trial, extra, false, work) == Run::Valid,
                Run::Invalid => return false,
            }
        }
        false
    }

    /// Runs `trial` from `from` beside the reference run from the same
    /// point, group of happenings by group. It ends as soon as both states
    /// are the same again and no step of `extra` (the steps the trial does
    /// without; those it drops join them) has a happening left: from there
    /// the two runs are one, and the reference is valid. It also ends when
    /// a goal no longer holds and no happening left can make it true
    /// again. A removal that only matters locally (a pair that undoes
    /// itself, a step whose first consumer is near) is so decided near
    /// where it is, not at the end of the plan.
    fn converge(
        &self,
        from: &Sim,
        base: &mut [bool],
        trial: &mut [bool],
        extra: &mut Vec<u32>,
        drop: bool,
        work: &mut u64,
    ) -> Run {
        let (search, p, events) = (self.search, self.p, self.events);
        let last_of = |s: u32| {
            let st = p.steps[s as usize];
            p.stn.est(st.start).max(p.stn.est(st.end))
        };
        let mut t = from.clone();
        if extra.iter().any(|&x| last_of(x) >= from.last - 1e-9) {
            t.last = last_happening(p, events, trial);
        }
        let mut r = from.clone();
        let mut diff: FxHashSet<u32> = FxHashSet::default();
        let mut pending = extra.iter().map(|&x| last_of(x)).fold(f64::NEG_INFINITY, f64::max);
        let mut beside = true;
        loop {
            if t.done(events) {
                return t.goals(search);
            }
            let (first, time) = (t.i, events[t.i].t);
            *work += 1;
            if let Some(run) = t.group(search, p, events, trial, drop) {
                return run;
            }
            for e in &events[first..t.i] {
                if trial[e.step as usize] && !base[e.step as usize] {
                    pending = pending.max(last_of(e.step));
                    if !extra.contains(&e.step) {
                        extra.push(e.step);
                    }
                }
            }
            if !beside {
                continue;
            }
            if r.group(search, p, events, base, false).is_some() {
                // The reference fails (it should not): the trial runs to
                // its end alone.
                beside = false;
                continue;
            }
            for &a in t.dels.iter().chain(&t.adds).chain(&r.dels).chain(&r.adds) {
                // An atom no condition and no goal reads makes no
                // difference.
                if t.state[a as usize] != r.state[a as usize] && self.read[a as usize] {
                    diff.insert(a);
                } else {
                    diff.remove(&a);
                }
            }
            // `pending` is the time of a happening, read from the same
            // schedule: compared exactly (a happening a rounding error
            // before it, 2.1199999999999997 against 2.12, is another
            // group, and the step's end is still to come).
            if diff.is_empty() && time >= pending {
                return Run::Valid;
            }
            if diff.iter().any(|&a| self.goals.lost(a, &t.state, t.i, events, trial)) {
                return Run::Invalid;
            }
        }
    }

    /// The reference run of the steps not `gone`, up to the happenings
    /// at `t0` (not run).
    fn replay(&self, gone: &mut [bool], t0: f64, work: &mut u64) -> Sim {
        let (search, p, events) = (self.search, self.p, self.events);
        let mut sim = Sim::new(search, p, events, gone);
        while !sim.done(events) && events[sim.i].t < t0 {
            *work += 1;
            if sim.group(search, p, events, gone, false).is_some() {
                break;
            }
        }
        sim
    }
}

/// The goals, and for each goal atom the happenings that can make it true
/// (or false, for a negative goal).
struct Goals {
    /// Goal atom → its literal and the indexes (in the happenings) of what
    /// makes the literal hold.
    by_atom: FxHashMap<u32, (Lit, Vec<u32>)>,
}

impl Goals {
    fn new(search: &Search<'_, '_>, p: &Plan, events: &[Happening]) -> Goals {
        let task = search.task;
        let mut by_atom: FxHashMap<u32, (Lit, Vec<u32>)> =
            task.goals.iter().map(|&(l, _)| (atom_of(l), (l, Vec::new()))).collect();
        for (i, e) in events.iter().enumerate() {
            let mut note = |l: Lit| {
                if let Some((g, at)) = by_atom.get_mut(&atom_of(l))
                    && is_neg(l) == is_neg(*g)
                {
                    at.push(i as u32);
                }
            };
            match p.steps[e.step as usize].kind {
                Kind::Op(o) => {
                    let op = &task.ops[o as usize];
                    for eff in &op.effs {
                        if op.instant || (eff.at == End::End) == e.end {
                            note(eff.lit);
                        }
                    }
                }
                // Whether it applies depends on the plan's last happening:
                // counted as if it did.
                Kind::Til(k) => note(task.tils[k as usize].lit),
                Kind::Init | Kind::Goal => {}
            }
        }
        Goals { by_atom }
    }

    /// Whether `a` is a goal atom whose goal does not hold in `state` and
    /// that no happening from `next` on, of a step not `gone`, can make
    /// hold: without steps added, the goal is lost.
    fn lost(&self, a: u32, state: &[bool], next: usize, events: &[Happening], gone: &[bool]) -> bool {
        let Some((l, at)) = self.by_atom.get(&a) else { return false };
        !holds(state, *l)
            && !at.iter().any(|&i| i as usize >= next && !gone[events[i as usize].step as usize])
    }
}

/// The time of the last happening of a step not `gone`.
fn last_happening(p: &Plan, events: &[Happening], gone: &[bool]) -> f64 {
    events
        .iter()
        .filter(|e| matches!(p.steps[e.step as usize].kind, Kind::Op(_)) && !gone[e.step as usize])
        .map(|e| e.t)
        .fold(0.0, f64::max)
}

/// Runs the schedule without the steps `gone`: `Valid` when every
/// condition of the steps run and every goal holds. With `drop`, a step
/// whose at-start conditions fail is not run (it is added to `gone`), and
/// one that started and fails later gives `Without` it.
fn simulate(search: &Search<'_, '_>, p: &Plan, events: &[Happening], gone: &mut [bool], drop: bool) -> Run {
    let mut sim = Sim::new(search, p, events, gone);
    while !sim.done(events) {
        if let Some(run) = sim.group(search, p, events, gone, drop) {
            return run;
        }
    }
    sim.goals(search)
}

/// A run of the schedule, between two groups of happenings.
#[derive(Debug, Clone)]
struct Sim {
    state: Vec<bool>,
    /// `over all` conditions running: (step, literal, end).
    invariants: Vec<(u32, Lit, f64)>,
    /// The first happening not run yet.
    i: usize,
    /// Timed literals apply up to the plan's last happening (VAL applies
    /// none after it).
    last: f64,
    /// The atoms the last group deleted, and those it added.
    dels: Vec<u32>,
    adds: Vec<u32>,
}

impl Sim {
    fn new(search: &Search<'_, '_>, p: &Plan, events: &[Happening], gone: &[bool]) -> Sim {
        Sim {
            state: search.task.init.clone(),
            invariants: Vec::new(),
            i: 0,
            last: last_happening(p, events, gone),
            dels: Vec::new(),
            adds: Vec::new(),
        }
    }

    fn done(&self, events: &[Happening]) -> bool {
        self.i >= events.len()
    }

    fn goals(&self, search: &Search<'_, '_>) -> Run {
        if search.task.goals.iter().all(|&(l, _)| holds(&self.state, l)) { Run::Valid } else { Run::Invalid }
    }

    /// Runs the happenings at the next time: `Some` when the run ends
    /// there (a condition fails).
    fn group(
        &mut self,
        search: &Search<'_, '_>,
        p: &Plan,
        events: &[Happening],
        gone: &mut [bool],
        drop: bool,
    ) -> Option<Run> {
        let task = search.task;
        let t = events[self.i].t;
        let mut j = self.i;
        while j < events.len() && events[j].t == t {
            j += 1;
        }
        let group = &events[self.i..j];
        self.i = j;
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
                !checked || holds(&self.state, c.lit)
            });
            if !ok {
                if !drop {
                    return Some(Run::Invalid);
                }
                if e.end {
                    return Some(Run::Without(e.step));
                }
                gone[e.step as usize] = true;
            }
        }
        // Effects: deletions, then additions.
        self.adds.clear();
        self.dels.clear();
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
                                self.dels.push(atom_of(eff.lit))
                            } else {
                                self.adds.push(atom_of(eff.lit))
                            }
                        }
                    }
                }
                Kind::Til(k) => {
                    if t <= self.last + 1e-9 {
                        let l = task.tils[k as usize].lit;
                        if is_neg(l) { self.dels.push(atom_of(l)) } else { self.adds.push(atom_of(l)) }
                    }
                }
                Kind::Init | Kind::Goal => {}
            }
        }
        for &a in &self.dels {
            self.state[a as usize] = false;
        }
        for &a in &self.adds {
            self.state[a as usize] = true;
        }
        // `over all`: from just after the start to the end (exclusive).
        self.invariants.retain(|&(s, _, end)| end > t && !gone[s as usize]);
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
                    self.invariants.push((e.step, c.lit, end));
                }
            }
        }
        if let Some(&(s, _, _)) = self.invariants.iter().find(|&&(_, l, _)| !holds(&self.state, l)) {
            return Some(if drop { Run::Without(s) } else { Run::Invalid });
        }
        None
    }
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
        let (mut host, pf, (text, removed)) = seeded(DOMAIN, &problem, steps, |db, task, search, p| {
            let (p, removed) = search.without_redundant_steps(p, &|| stop);
            (output::solved(db, task, &p).to_val(""), removed.steps)
        });
        let v = validated(&mut host, pf, &text);
        let valid = v.valid && v.checked && v.diagnostics.iter().all(|d| d.code.id != "W0411");
        (text, removed, valid)
    }

    /// `text`, as a plan of the problem in `pf`, validated.
    fn validated(host: &mut AnalysisHost, pf: crate::SourceFile, text: &str) -> crate::validate::Validation {
        let f = host.set_file_text("plan.plan", text);
        host.analysis()
            .validate_plan(f, None, pf, &Default::default())
            .expect("not cancelled")
            .expect("validated")
    }

    /// The plan of `steps` (an operator's name, or its instance as
    /// `(go a b)`, with its start) for `problem`, complete, given to `f`.
    fn seeded<R>(
        domain: &str,
        problem: &str,
        steps: &[(&str, f64)],
        f: impl FnOnce(&dyn crate::db::Db, &crate::planner::task::Task<'_>, &Search<'_, '_>, Plan) -> R
        + std::panic::UnwindSafe,
    ) -> (AnalysisHost, crate::SourceFile, R) {
        let mut host = AnalysisHost::new();
        host.set_file_text("domain.pddl", domain);
        let pf = host.set_file_text("problem.pddl", problem);
        let r = host
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
                            let op = (0..task.ops.len() as u32)
                                .find(|&o| &*task.ops[o as usize].name == name || task.show_op(o) == name)
                                .unwrap_or_else(|| panic!("no operator {name}"));
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
                // Complete but for orderings (numeric ones), as the pass
                // completes the plans it rebuilds.
                if search.select(&mut p).is_some() {
                    let size = p.steps.len();
                    let mut stats = crate::planner::Stats::default();
                    p = search
                        .probe(vec![p], 64, size, &|_| true, &mut stats, &|| false, true)
                        .expect("the plan given is complete");
                    assert_eq!(p.steps.len(), size, "the plan given is complete");
                }
                f(db, task, &search, p)
            })
            .expect("not cancelled");
        (host, pf, r)
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

    /// A walk along a chain of `n` nodes, each seen (a goal), with a
    /// blink at every fourth node that nothing reads: the blinks go, the
    /// walk stays. Each try is decided near the step tried (a goal lost
    /// as soon as its only achiever is dropped, the same state again once
    /// a blink is over), so the pass simulates a number of groups of
    /// happenings linear in the plan's size, not its square.
    #[test]
    fn a_long_walk_is_passed_in_linear_work() {
        const WALK: &str = "(define (domain walk)
  (:requirements :typing :durative-actions)
  (:types node)
  (:predicates (at ?n - node) (next ?a ?b - node) (seen ?n - node) (blinked ?n - node))
  (:durative-action go :parameters (?a ?b - node) :duration (= ?duration 1)
    :condition (and (at start (at ?a)) (over all (next ?a ?b)))
    :effect (and (at start (not (at ?a))) (at end (at ?b)) (at end (seen ?b))))
  (:durative-action blink :parameters (?a - node) :duration (= ?duration 0.5)
    :condition (over all (at ?a)) :effect (at end (blinked ?a))))";
        let n = 60;
        let nodes: Vec<String> = (0..=n).map(|i| format!("n{i}")).collect();
        let next: String = (0..n).map(|i| format!("(next n{i} n{})", i + 1)).collect();
        let seen: String = (1..=n).map(|i| format!("(seen n{i})")).collect();
        let problem = format!(
            "(define (problem p) (:domain walk) (:objects {} - node) (:init (at n0) {next}) (:goal (and {seen})))",
            nodes.join(" ")
        );
        let mut names = Vec::new();
        for i in 0..n {
            names.push((format!("(go n{i} n{})", i + 1), 2.0 * i as f64 + 0.01));
            if i % 4 == 0 {
                names.push((format!("(blink n{i})"), 2.0 * i as f64 - 0.99 + 1.0));
            }
        }
        let steps: Vec<(&str, f64)> = names.iter().map(|(s, t)| (s.as_str(), *t)).collect();
        let (_, _, (gone, work, walks)) = seeded(WALK, &problem, &steps, |_, task, search, p| {
            let (gone, work, _) = search.eliminate_counting(&p, &|| false);
            let walks = (0..p.steps.len() as u32)
                .filter(|&s| gone[s as usize])
                .filter(|&s| task.show_op(p.op_of(s).expect("a step")).starts_with("(go"))
                .count();
            (gone.iter().filter(|&&g| g).count(), work, walks)
        });
        assert_eq!((gone, walks), (n / 4, 0));
        // About 4 groups of happenings per step (the walk's starts and
        // ends, the blinks'): the reference run once, and a few groups per
        // try. Every try running the whole plan would be over 1,000 per
        // step.
        let steps = steps.len() as u64;
        assert!(work <= 20 * steps, "{work} groups simulated for {steps} steps");
    }

    /// Numeric fluents: the `beep` goes; the `recharge` stays, though the
    /// simulation of literals finds it removable, because the second
    /// `move`'s energy needs it (the rebuilt plan's numeric check says so,
    /// and the removals are then tried one by one).
    #[test]
    fn a_step_a_numeric_condition_needs_stays() {
        const ENERGY: &str = "(define (domain energy)
  (:requirements :typing :durative-actions :fluents)
  (:types place)
  (:predicates (at ?p - place) (beeped))
  (:functions (energy))
  (:durative-action move :parameters (?a ?b - place) :duration (= ?duration 2)
    :condition (and (at start (at ?a)) (at start (>= (energy) 5)))
    :effect (and (at start (not (at ?a))) (at end (at ?b)) (at start (decrease (energy) 5))))
  (:durative-action recharge :parameters () :duration (= ?duration 1)
    :condition (at start (<= (energy) 5)) :effect (at end (increase (energy) 10)))
  (:durative-action beep :parameters () :duration (= ?duration 1)
    :condition (at start (>= (energy) 0)) :effect (at end (beeped))))";
        let problem = "(define (problem p) (:domain energy) (:objects a b c - place)
  (:init (at a) (= (energy) 5)) (:goal (and (at c))))";
        let steps = [("(beep)", 0.0), ("(recharge)", 0.0), ("(move a b)", 1.01), ("(move b c)", 3.02)];
        let (mut host, pf, (text, removed)) = seeded(ENERGY, problem, &steps, |db, task, search, p| {
            let (p, removed) = search.without_redundant_steps(p, &|| false);
            (output::solved(db, task, &p).to_val(""), removed.steps)
        });
        assert_eq!(removed, 1, "{text}");
        let mut got = names(&text);
        got.sort();
        assert_eq!(got, ["move a b", "move b c", "recharge"], "{text}");
        let v = validated(&mut host, pf, &text);
        assert!(v.valid && v.checked, "{text}\n{:?}", v.diagnostics);
    }

    /// A happening a rounding error before a step's end is not its end:
    /// `b` ends at 0.1 + 0.01 + 5 = 5.11 and `d` at 5 + 0.01 + 0.1 =
    /// 5.109999999999999. Without `a` (and so
    /// `b`, which needs it), the try saw both runs alike after `d`'s end
    /// and took `b`'s end as done: `a` and `b` were found removable, the
    /// plan rebuilt without them was invalid, and the pass removed
    /// nothing, not even `noise`.
    #[test]
    fn a_happening_a_rounding_error_before_a_step_end_does_not_end_its_try() {
        const ROUNDING: &str = "(define (domain rounding)
  (:requirements :durative-actions)
  (:predicates (a-done) (b-done) (c-done) (d-done) (g-done) (noise))
  (:durative-action a :parameters () :duration (= ?duration 0.1) :condition (and) :effect (at end (a-done)))
  (:durative-action b :parameters () :duration (= ?duration 5)
    :condition (at start (a-done)) :effect (at end (b-done)))
  (:durative-action c :parameters () :duration (= ?duration 5) :condition (and) :effect (at end (c-done)))
  (:durative-action d :parameters () :duration (= ?duration 0.1)
    :condition (at start (c-done)) :effect (at end (d-done)))
  (:durative-action g :parameters () :duration (= ?duration 1)
    :condition (and (at start (b-done)) (at start (d-done))) :effect (at end (g-done)))
  (:durative-action r :parameters () :duration (= ?duration 1) :condition (and) :effect (at end (noise))))";
        let problem = "(define (problem p) (:domain rounding) (:init) (:goal (and (g-done))))";
        let steps = [("a", 0.0), ("c", 0.0), ("r", 0.0), ("b", 0.11), ("d", 5.01), ("g", 5.12)];
        let (mut host, pf, (times, found, text, removed)) =
            seeded(ROUNDING, problem, &steps, |db, task, search, p| {
                let times: Vec<f64> = happenings(search, &p).iter().map(|e| e.t).collect();
                let (gone, _) = search.eliminate(&p, &|| false);
                let found: Vec<String> = (0..p.steps.len() as u32)
                    .filter(|&s| gone[s as usize])
                    .filter_map(|s| p.op_of(s))
                    .map(|o| task.show_op(o))
                    .collect();
                let (p, removed) = search.without_redundant_steps(p, &|| false);
                (times, found, output::solved(db, task, &p).to_val(""), removed.steps)
            });
        // The schedule has the two times this test is about.
        assert!(times.contains(&5.11) && times.contains(&5.109999999999999), "{times:?}");
        assert_eq!(found, ["(r)"], "{text}");
        assert_eq!(removed, 1, "{text}");
        let v = validated(&mut host, pf, &text);
        assert!(v.valid && v.checked, "{text}\n{:?}", v.diagnostics);
    }
}
