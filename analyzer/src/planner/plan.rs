//! Partial plans (Definition 6 of the HiPOP paper) and their flaws
//! (Definitions 7–13): steps, causal links, the temporal network, the
//! hierarchy, and the open links, threats and abstract flaws still to solve.
//!
//! A plan is cheap to copy: its steps and links are [`PVec`]s, its network a
//! [`Stn`] of shared rows, its open links a [`PList`] of shared chunks,
//! its other flaw lists small `Rc` vectors. Every
//! operation that can fail (a constraint that makes the network
//! inconsistent) returns `false`, and the caller drops the plan.

use std::rc::Rc;

use super::heuristic::Heuristic;
use super::itinerary::Tail;
use super::pvec::{PList, PVec};
use super::stn::{EPS, ORIGIN, Stn, Tp};
use super::task::{End, Lit, Task, atom_of, is_neg, negate};

/// What a step is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// The initial state (time point: the origin).
    Init,
    /// The goal: after every step.
    Goal,
    /// A timed initial literal, by index in [`Task::tils`].
    Til(u32),
    /// An operator, by index in [`Task::ops`].
    Op(u32),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    pub kind: Kind,
    pub start: Tp,
    pub end: Tp,
    /// The abstract step whose method introduced it (hierarchical relation).
    pub parent: Option<u32>,
    /// The method instance refining it (an abstract step), once refined.
    pub method: Option<u32>,
    /// When it entered the plan (flaw selection `local`).
    pub born: u32,
}

impl Step {
    pub fn tp(&self, e: End) -> Tp {
        match e {
            End::Start => self.start,
            End::End => self.end,
        }
    }
}

/// `from —lit→ to`: `lit` holds from `from_tp` until `until`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Link {
    pub from: u32,
    pub from_tp: Tp,
    pub to: u32,
    pub need: Tp,
    pub until: Tp,
    pub lit: Lit,
}

/// A condition of a step without a causal link (Definition 7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Open {
    pub step: u32,
    pub lit: Lit,
    pub need: Tp,
    pub until: Tp,
    /// Which condition of the step's operator (for locating it), or
    /// `u32::MAX` for a goal, a method precondition or an abstract effect.
    pub cond: u32,
    /// Where it comes from, for reports: a goal index, a method, an abstract effect.
    pub origin: OpenOrigin,
    /// Only an `over all` condition: needed in the open interval after the
    /// step's start, so the step's own start effect may support it.
    pub after_start: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OpenOrigin {
    Cond(u32),
    Goal(u32),
    MethodPre(u32, u32),
    /// An effect of an abstract step that its subtasks must achieve.
    AbstractEffect,
}

/// How a step threatens a link.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ThreatKind {
    /// It deletes the literal (negates it) at `tp`.
    Delete(Tp),
    /// It puts the family member elsewhere at `tp` (Definition 13).
    Position(Tp),
    /// An abstract step whose conflicts include the literal (Definition 11).
    Conflict,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Threat {
    pub link: u32,
    pub step: u32,
    pub kind: ThreatKind,
}

#[derive(Clone)]
pub struct Plan {
    pub steps: PVec<Step>,
    pub links: PVec<Link>,
    pub stn: Stn,
    pub open: PList<Open>,
    pub threats: Rc<Vec<Threat>>,
    /// Abstract steps not refined yet (Definition 9).
    pub abstracts: Rc<Vec<u32>>,
    pub goal_tp: Tp,
    /// Counter for [`Step::born`].
    pub clock: u32,
    /// Where each itinerary stands (geometric reasoning, [`super::itinerary`]).
    pub tails: Rc<Vec<Tail>>,
    /// The earliest start of a step added from now on: a repair of a
    /// partially executed plan cannot start anything in the past (0: none).
    pub not_before: f64,
    /// A repair's old schedule ([`Plan::keep_old_times`]).
    pub old_times: Rc<OldSchedule>,
    /// The durations fixed so far of the steps whose duration reads a
    /// numeric fluent that effects change (`refuel`), by step.
    pub durations: Rc<Vec<(u32, f64)>>,
    /// The start of the last elementary step committed to the plan's front
    /// (configuration part `front`, `super::search::front`): the steps at
    /// or before it run in that order, before every other step (the
    /// origin: none yet).
    pub front: Tp,
}

/// The old schedule of a repair's start plan: the start point of each old
/// step still in (primitive and not fixed) with its old start, and the
/// latest old end of the old steps still in.
#[derive(Debug, Clone, Default)]
pub struct OldSchedule {
    pub starts: Vec<(Tp, f64)>,
    pub makespan: f64,
}

/// Appends to a flaw list that the plan may share with others: a list of
/// its own takes the items in place; a shared one is copied once, at its
/// new length. (`Rc::make_mut` copies at the old length, and the append
/// then doubles the copy's capacity: up to twice the list for each child
/// plan that adds a step or a link, most of them never expanded.)
fn extend_shared<T: Clone>(list: &mut Rc<Vec<T>>, items: impl IntoIterator<Item = T>) {
    if let Some(own) = Rc::get_mut(list) {
        own.extend(items);
        return;
    }
    let items: Vec<T> = items.into_iter().collect();
    let mut copy = Vec::with_capacity(list.len() + items.len());
    copy.extend_from_slice(list);
    copy.extend(items);
    *list = Rc::new(copy);
}

pub const INIT: u32 = 0;
pub const GOAL: u32 = 1;

impl Plan {
    /// The plan with the initial step, the goal step and the timed literals.
    pub fn initial(task: &Task<'_>) -> Option<Plan> {
        let mut stn = Stn::new();
        let goal_tp = stn.add_point();
        let mut p = Plan {
            steps: PVec::new(),
            links: PVec::new(),
            stn,
            open: PList::new(),
            threats: Rc::new(Vec::new()),
            abstracts: Rc::new(Vec::new()),
            goal_tp,
            clock: 0,
            tails: Rc::new(Vec::new()),
            not_before: 0.0,
            old_times: Rc::new(OldSchedule::default()),
            durations: Rc::new(Vec::new()),
            front: ORIGIN,
        };
        p.steps.push(Step {
            kind: Kind::Init,
            start: ORIGIN,
            end: ORIGIN,
            parent: None,
            method: None,
            born: 0,
        });
        p.steps.push(Step {
            kind: Kind::Goal,
            start: goal_tp,
            end: goal_tp,
            parent: None,
            method: None,
            born: 0,
        });
        for (i, t) in task.tils.iter().enumerate() {
            let tp = p.stn.add_point();
            if !(p.stn.add(ORIGIN, tp, t.time) && p.stn.add(tp, ORIGIN, -t.time)) {
                return None;
            }
            p.steps.push(Step {
                kind: Kind::Til(i as u32),
                start: tp,
                end: tp,
                parent: None,
                method: None,
                born: 0,
            });
        }
        Some(p)
    }

    /// The duration of step `s` when its operator's reads a numeric
    /// fluent and it is fixed.
    pub fn fixed_duration(&self, s: u32) -> Option<f64> {
        self.durations.iter().find(|(k, _)| *k == s).map(|(_, d)| *d)
    }

    pub fn op_of(&self, s: u32) -> Option<u32> {
        match self.steps[s as usize].kind {
            Kind::Op(o) => Some(o),
            _ => None,
        }
    }

    /// The makespan: the latest earliest end of a step (g of section 4.2.3).
    pub fn makespan(&self) -> f64 {
        self.steps
            .iter()
            .filter(|s| matches!(s.kind, Kind::Op(_)))
            .map(|s| self.stn.est(s.end))
            .fold(0.0, f64::max)
    }

    /// Schedules a repaired plan's old steps no earlier than the old plan
    /// did, as far as the old steps' end allows. The written times are the
    /// earliest schedule, in which an old step moves earlier as soon as
    /// something before it was removed or shortened, and every step that
    /// moves is an action retimed for the team that executes the plan.
    ///
    /// An old step keeps its old start when, on its own, that start delays
    /// the plan's end to no later than the old steps ended (or than the
    /// earliest schedule ends, if later) and breaks no deadline: its delay
    /// is within its slack towards the goal, plus what the end may give,
    /// and within its slack towards the origin (through the deadlines).
    /// Those starts are added together: the least schedule with all of them
    /// is the latest of the least schedules with each (the schedules of a
    /// temporal network are closed under pointwise maximum), which keeps
    /// every deadline and ends no later than any of them.
    pub fn keep_old_times(&mut self) {
        let old = Rc::clone(&self.old_times);
        let late = |p: &Plan, tp: Tp, t: f64| t - p.stn.est(tp);
        let mut starts: Vec<(Tp, f64)> =
            old.starts.iter().copied().filter(|&(tp, t)| late(self, tp, t) > 0.0).collect();
        if starts.is_empty() {
            return;
        }
        let to_goal = self.stn.slacks_to(self.goal_tp);
        let to_deadlines = self.stn.slacks_to(ORIGIN);
        // How much later the goal may be: up to the old steps' end.
        let budget = (old.makespan + EPS - self.stn.est(self.goal_tp)).max(0.0);
        starts.retain(|&(tp, t)| {
            let late = late(self, tp, t);
            late <= to_goal[tp as usize] + budget && late < to_deadlines[tp as usize]
        });
        starts.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        for (tp, t) in starts {
            let kept = self.stn.add(ORIGIN, tp, t);
            debug_assert!(kept, "a start within its slacks is consistent");
        }
    }

    /// Whether `a` is (a descendant of) `ancestor`.
    pub fn descends(&self, mut a: u32, ancestor: u32) -> bool {
        loop {
            if a == ancestor {
                return true;
            }
            match self.steps[a as usize].parent {
                Some(p) => a = p,
                None => return false,
            }
        }
    }

    /// The effects of a step, at its time points: literal and time point.
    pub fn effects<'a>(&'a self, task: &'a Task<'_>, s: u32) -> impl Iterator<Item = (Lit, Tp)> + 'a {
        let step = self.steps[s as usize];
        let (op_effs, til, init): (&[super::task::Eff], Option<Lit>, bool) = match step.kind {
            Kind::Op(o) => (&task.ops[o as usize].effs, None, false),
            Kind::Til(t) => (&[], Some(task.tils[t as usize].lit), false),
            Kind::Init => (&[], None, true),
            Kind::Goal => (&[], None, false),
        };
        let _ = init;
        op_effs.iter().map(move |e| (e.lit, step.tp(e.at))).chain(til.map(|l| (l, step.start)))
    }

    /// Whether a happening at `d` can fall inside the protection of `link`
    /// (strictly after its producer, up to the end of its protection).
    pub fn can_be_inside(&self, link: &Link, d: Tp) -> bool {
        if d == link.from_tp || d == link.until {
            return false;
        }
        !self.stn.before(d, link.from_tp) && !self.stn.before(link.until, d)
    }

    /// Whether an interval `[s, e]` can overlap the protection of `link`.
    pub fn can_overlap(&self, link: &Link, s: Tp, e: Tp) -> bool {
        !self.stn.before(e, link.from_tp) && !self.stn.before(link.until, s)
    }

    /// [`Task::touches`] of step `k`'s effects (all bits when unknown):
    /// `k` can threaten a link only if they share a bit with the link's.
    pub fn touches(&self, task: &Task<'_>, k: u32) -> u64 {
        match self.steps[k as usize].kind {
            Kind::Op(o) => task.op_touches.get(o as usize).copied().unwrap_or(u64::MAX),
            Kind::Til(t) => task.touches(task.tils[t as usize].lit),
            Kind::Init | Kind::Goal => 0,
        }
    }

    /// The ways step `k` threatens `link` (Definitions 8, 11 and 13).
    pub fn threat_of(&self, task: &Task<'_>, k: u32, link: &Link, out: &mut Vec<ThreatKind>) {
        let step = self.steps[k as usize];
        let threatened = negate(link.lit);
        let family = if is_neg(link.lit) { None } else { task.family[atom_of(link.lit) as usize] };
        for (l, tp) in self.effects(task, k) {
            if (k == link.to && tp == link.until) || (k == link.from && tp == link.from_tp) {
                continue;
            }
            if l == threatened {
                if self.can_be_inside(link, tp) {
                    out.push(ThreatKind::Delete(tp));
                }
            } else if let Some((g, _)) = family
                && !is_neg(l)
                && l != link.lit
                && task.family[atom_of(l) as usize].is_some_and(|(g2, _)| g2 == g)
                && self.can_be_inside(link, tp)
            {
                out.push(ThreatKind::Position(tp));
            }
        }
        if let Kind::Op(o) = step.kind {
            let op = &task.ops[o as usize];
            if !op.conflicts.is_empty()
                && op.conflicts_with(task.g, atom_of(link.lit))
                && !self.descends(link.from, k)
                && !self.descends(link.to, k)
                && self.can_overlap(link, step.start, step.end)
            {
                out.push(ThreatKind::Conflict);
            }
        }
    }

    /// Whether a recorded threat still is one.
    pub fn still_threat(&self, task: &Task<'_>, t: &Threat) -> bool {
        let link = self.links[t.link as usize];
        let step = self.steps[t.step as usize];
        match t.kind {
            ThreatKind::Delete(tp) | ThreatKind::Position(tp) => self.can_be_inside(&link, tp),
            ThreatKind::Conflict => {
                let _ = task;
                self.can_overlap(&link, step.start, step.end)
            }
        }
    }

    /// Records the threats of step `k` on every link.
    pub fn threats_of_step(&mut self, task: &Task<'_>, k: u32) {
        let mut found = Vec::new();
        let mut kinds = Vec::new();
        let touches = self.touches(task, k);
        for (i, link) in self.links.iter().enumerate() {
            if touches & task.touches(link.lit) == 0 {
                continue;
            }
            kinds.clear();
            self.threat_of(task, k, link, &mut kinds);
            found.extend(kinds.iter().map(|&kind| Threat { link: i as u32, step: k, kind }));
        }
        if !found.is_empty() {
            extend_shared(&mut self.threats, found);
        }
    }

    /// Records the threats of every step on link `i`.
    pub fn threats_of_link(&mut self, task: &Task<'_>, i: u32) {
        let link = self.links[i as usize];
        let mut found = Vec::new();
        let mut kinds = Vec::new();
        let touches = task.touches(link.lit);
        for k in 0..self.steps.len() as u32 {
            if self.touches(task, k) & touches == 0 {
                continue;
            }
            kinds.clear();
            self.threat_of(task, k, &link, &mut kinds);
            found.extend(kinds.iter().map(|&kind| Threat { link: i, step: k, kind }));
        }
        if !found.is_empty() {
            extend_shared(&mut self.threats, found);
        }
    }

    /// Records the threats of every step on the links from `first` on:
    /// [`Plan::threats_of_link`] for many links at once, the candidate
    /// steps of each found in an index of the steps by effect (a step that
    /// deletes the link's literal, sets another position of its family, or
    /// may conflict with it) instead of every step for every link.
    pub fn threats_of_links(&mut self, task: &Task<'_>, first: u32) {
        if first as usize >= self.links.len() {
            return;
        }
        let mut by_lit: rustc_hash::FxHashMap<Lit, Vec<u32>> = rustc_hash::FxHashMap::default();
        let mut by_group: rustc_hash::FxHashMap<u32, Vec<u32>> = rustc_hash::FxHashMap::default();
        let mut conflicting = Vec::new();
        for k in 0..self.steps.len() as u32 {
            for (l, _) in self.effects(task, k) {
                by_lit.entry(l).or_default().push(k);
                if !is_neg(l)
                    && let Some((g, _)) = task.family[atom_of(l) as usize]
                {
                    by_group.entry(g).or_default().push(k);
                }
            }
            if let Kind::Op(o) = self.steps[k as usize].kind
                && !task.ops[o as usize].conflicts.is_empty()
            {
                conflicting.push(k);
            }
        }
        let mut found = Vec::new();
        let mut kinds = Vec::new();
        let mut candidates = Vec::new();
        for i in first..self.links.len() as u32 {
            let link = self.links[i as usize];
            candidates.clear();
            candidates.extend(by_lit.get(&negate(link.lit)).into_iter().flatten());
            if !is_neg(link.lit)
                && let Some((g, _)) = task.family[atom_of(link.lit) as usize]
            {
                candidates.extend(by_group.get(&g).into_iter().flatten());
            }
            candidates.extend(&conflicting);
            candidates.sort_unstable();
            candidates.dedup();
            for &k in &candidates {
                kinds.clear();
                self.threat_of(task, k, &link, &mut kinds);
                found.extend(kinds.iter().map(|&kind| Threat { link: i, step: k, kind }));
            }
        }
        if !found.is_empty() {
            extend_shared(&mut self.threats, found);
        }
    }

    /// Adds a step for operator `o` (under `parent`, if a method introduces
    /// it) with its open links and threats. `None` if the network rejects it.
    pub fn add_step(&mut self, task: &Task<'_>, h: &Heuristic, o: u32, parent: Option<u32>) -> Option<u32> {
        let op = &task.ops[o as usize];
        let start = self.stn.add_point();
        let end = if op.instant { start } else { self.stn.add_point() };
        if !op.instant {
            match op.duration {
                Some(d) => {
                    if !(self.stn.add(start, end, d) && self.stn.add(end, start, -d)) {
                        return None;
                    }
                }
                // Fixed once the fluent it reads is known at its start
                // (`super::numeric`): meanwhile at least ε, the start and
                // the end being two happenings.
                None if op.num_duration.is_some() => {
                    if !self.stn.add(start, end, EPS) {
                        return None;
                    }
                }
                None => {
                    if !self.stn.add(start, end, 0.0) {
                        return None;
                    }
                }
            }
        }
        if !self.stn.add(end, self.goal_tp, EPS) {
            return None;
        }
        if self.not_before > 0.0 && !self.stn.add(ORIGIN, start, self.not_before) {
            return None;
        }
        if let Some(p) = parent {
            let ps = self.steps[p as usize];
            if !(self.stn.add(ps.start, start, 0.0) && self.stn.add(end, ps.end, 0.0)) {
                return None;
            }
        }
        self.clock += 1;
        let s = self.steps.len() as u32;
        self.steps.push(Step { kind: Kind::Op(o), start, end, parent, method: None, born: self.clock });
        // Open links, one per literal (its widest protection).
        let mut opens: Vec<Open> = Vec::with_capacity(op.conds.len());
        for (ci, c) in op.conds.iter().enumerate() {
            let need = if c.at == End::Start { start } else { end };
            let until = if c.until == End::Start { start } else { end };
            let over_all = c.at == End::Start && c.until == End::End && !op.instant;
            if let Some(o) = opens.iter_mut().find(|o| o.lit == c.lit) {
                // Needed just after the start (what the start makes true
                // supports it) unless one of them is needed at the start
                // itself; an `at end` one adds nothing to an `over all`.
                if over_all {
                    o.after_start |= o.need != start;
                } else if need == start {
                    o.after_start = false;
                }
                if need == start {
                    o.need = start;
                }
                if until == end {
                    o.until = end;
                }
                continue;
            }
            if !h.reachable(c.lit) && !task.holds_initially(c.lit) {
                return None;
            }
            opens.push(Open {
                step: s,
                lit: c.lit,
                need,
                until,
                cond: ci as u32,
                origin: OpenOrigin::Cond(ci as u32),
                after_start: over_all,
            });
        }
        if !opens.is_empty() {
            self.open.extend(opens);
        }
        if op.is_abstract {
            Rc::make_mut(&mut self.abstracts).push(s);
        }
        self.threats_of_step(task, s);
        Some(s)
    }

    /// Adds an open link of another origin (goal, method precondition, abstract effect).
    pub fn add_open(&mut self, o: Open) {
        self.open.push(o);
    }

    /// Adds the causal link `from —lit→ open` and its threats.
    pub fn add_link(&mut self, task: &Task<'_>, from: u32, from_tp: Tp, o: &Open) -> bool {
        // The step's own start supporting its `over all` condition needs no
        // ordering (no edge is added for a need at the producer's own point).
        self.add_link_after(task, from, from_tp, o, Plan::link_separation(o))
    }

    /// The least separation of a need from its producer: ε, none for the
    /// effect of an abstract step, which holds once the subtask that makes
    /// it has ended (the same happening as the step's end).
    pub fn link_separation(o: &Open) -> f64 {
        if o.origin == OpenOrigin::AbstractEffect { 0.0 } else { EPS }
    }

    /// [`Plan::add_link`], the need at least `sep` after the producer.
    pub fn add_link_after(&mut self, task: &Task<'_>, from: u32, from_tp: Tp, o: &Open, sep: f64) -> bool {
        let i = self.links.len() as u32;
        if !self.add_link_without_threats(from, from_tp, o, sep) {
            return false;
        }
        self.threats_of_link(task, i);
        true
    }

    /// [`Plan::add_link_after`] without looking for the link's threats: the
    /// caller records them later ([`Plan::threats_of_links`]).
    pub fn add_link_without_threats(&mut self, from: u32, from_tp: Tp, o: &Open, sep: f64) -> bool {
        if from_tp != o.need && !self.stn.add(from_tp, o.need, sep) {
            return false;
        }
        self.links.push(Link { from, from_tp, to: o.step, need: o.need, until: o.until, lit: o.lit });
        true
    }

    pub fn remove_open(&mut self, i: usize) -> Open {
        self.open.remove(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A child that adds to a flaw list it shares copies it once, at its
    /// new length; a list of its own grows in place.
    #[test]
    fn shared_flaw_lists_are_copied_at_their_new_length() {
        let parent: Rc<Vec<u32>> = Rc::new((0..20).collect());
        let mut child = Rc::clone(&parent);
        extend_shared(&mut child, [20, 21, 22]);
        assert_eq!(child.len(), 23);
        assert_eq!(child.capacity(), 23);
        assert_eq!(parent.len(), 20);
        let before = Rc::as_ptr(&child);
        extend_shared(&mut child, [23]);
        assert_eq!(Rc::as_ptr(&child), before);
        assert_eq!(child[23], 23);
    }
}
