//! Plans the search starts from when it repairs (section 5.1 of the HiPOP
//! paper): a non-empty initial plan, built from the steps of a plan that
//! was being executed. Each step keeps what the old plan says of it: its
//! operator, its place in the hierarchy (an abstract step refined by its
//! method, with its subtasks as children), its times in the old schedule
//! (which choose causal links and threat orderings as the old plan had
//! them), whether it is fixed in time (executed or running), and the
//! orderings to keep (phantom links, 5.1.2).

use super::super::itinerary::{self, Geo};
use super::super::plan::{INIT, Kind, OpenOrigin, Plan};
use super::super::stn::{EPS, ORIGIN, Tp};
use rustc_hash::FxHashMap;

use super::super::task::{End, Lit, Task, atom_of, is_neg, negate};
use super::Search;

/// How far the old times of a producer and of its consumer may be out of
/// order and still be the old plan's link: times in plan files are rounded.
const OLD_TIME_SLACK: f64 = 1e-6;

/// A step of the old plan to put in the start plan.
#[derive(Debug, Clone, PartialEq)]
pub struct SeedStep {
    /// The ground operator, an index in [`super::super::task::Task::ops`].
    pub op: u32,
    /// The abstract seed step whose method introduced it, by index in
    /// [`Seed::steps`]: that step is refined (`method`), and its children
    /// are the method's subtasks, all of them.
    pub parent: Option<usize>,
    /// The method instance refining it (an abstract step), or `None`: the
    /// step enters the plan unrefined (an abstract flaw, 5.1.1).
    pub method: Option<u32>,
    /// Its start and end in the old schedule.
    pub start: f64,
    pub end: f64,
    /// Executed or running: its start is fixed at `start`; `done`: its end
    /// at `end` too.
    pub fixed: bool,
    pub done: bool,
}

/// An ordering to keep between two seed steps' time points: `to` at least
/// ε after `from`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SeedOrder {
    pub from: (usize, End),
    pub to: (usize, End),
}

/// The start plan of a repair.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Seed {
    pub steps: Vec<SeedStep>,
    pub orders: Vec<SeedOrder>,
    /// The time of the repair in a partially executed plan: every step but
    /// the fixed ones, and every step the search adds, starts at or after it.
    pub now: Option<f64>,
}

/// A start plan, with the seed step of each of its steps.
pub type Seeded = (Plan, Vec<Option<usize>>);

/// Why a seed gives no start plan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SeedError {
    /// A refined step's children are not its method's subtasks.
    Children(usize),
    /// The temporal network rejects the steps, their fixed times or the
    /// orderings kept.
    Inconsistent,
}

/// The time of each time point of the start plan in the old schedule,
/// where it has one (the initial state first of all, the goal last).
struct OldTimes(rustc_hash::FxHashMap<Tp, f64>);

impl OldTimes {
    fn at(&self, tp: Tp) -> Option<f64> {
        self.0.get(&tp).copied()
    }
}

/// Fixes time point `tp` at time `t`. At time 0, the bound above is a
/// hair over it: `t_0 ≥ t_tp − 0` would close `tp` before the origin,
/// where its effects would come before the initial state and threaten no
/// link from it (VAL applies them after it, at 0).
fn fix(p: &mut Plan, tp: Tp, t: f64) -> bool {
    let upper = if t > 0.0 { -t } else { -AT_ORIGIN };
    p.stn.add(ORIGIN, tp, t) && p.stn.add(tp, ORIGIN, upper)
}

/// How far after the origin a step fixed at time 0 may be.
const AT_ORIGIN: f64 = 1e-9;

impl Search<'_, '_> {
    /// The start plans for `seed`: the initial plans (goals, timed literals,
    /// `:htn`) with the seed's steps, each open link of theirs supported
    /// as in the old schedule (by the latest producer before it, else the
    /// initial state), threats ordered as there, and the orderings kept.
    /// What the old schedule does not decide is left to the search.
    /// Returns the plans and, per plan step, its seed step.
    pub fn seeded(&self, seed: &Seed) -> Result<Vec<Seeded>, SeedError> {
        self.from_seeds.set(true);
        let mut out = Vec::new();
        let mut last_error = SeedError::Inconsistent;
        for root in self.initial() {
            match self.seed_one(root, seed) {
                Ok(x) => out.push(x),
                Err(e) => last_error = e,
            }
        }
        if out.is_empty() { Err(last_error) } else { Ok(out) }
    }

    fn seed_one(&self, mut p: Plan, seed: &Seed) -> Result<Seeded, SeedError> {
        let n = seed.steps.len();
        let mut id: Vec<Option<u32>> = vec![None; n];
        // `:htn` tasks are in the plan already: the seed's top-level steps
        // of the same operators are them, in the order of the seed.
        let mut htn_steps: Vec<u32> = (0..p.steps.len() as u32)
            .filter(|&s| {
                matches!(p.steps[s as usize].kind, Kind::Op(_)) && p.steps[s as usize].parent.is_none()
            })
            .collect();
        let mut order: Vec<usize> = (0..n).filter(|&i| seed.steps[i].parent.is_none()).collect();
        order.sort_by(|&a, &b| seed.steps[a].start.total_cmp(&seed.steps[b].start));
        let mut k = 0;
        while k < order.len() {
            let i = order[k];
            k += 1;
            let st = &seed.steps[i];
            let s = match (id[i], htn_steps.iter().position(|&s| p.op_of(s) == Some(st.op))) {
                (Some(s), _) => s,
                (None, Some(j)) => htn_steps.remove(j),
                (None, None) => self.add_step(&mut p, st.op, None).ok_or(SeedError::Inconsistent)?,
            };
            id[i] = Some(s);
            // Its children, after it: refined with its method.
            if let Some(m) = st.method {
                if let Some(j) = p.abstracts.iter().position(|&a| a == s) {
                    std::rc::Rc::make_mut(&mut p.abstracts).remove(j);
                }
                let before = p.steps.len() as u32;
                if !self.refine(&mut p, s, m) {
                    return Err(SeedError::Inconsistent);
                }
                let mut children: Vec<usize> = (0..n).filter(|&c| seed.steps[c].parent == Some(i)).collect();
                children.sort_by(|&a, &b| seed.steps[a].start.total_cmp(&seed.steps[b].start));
                let created: Vec<u32> = (before..p.steps.len() as u32)
                    .filter(|&c| p.steps[c as usize].parent == Some(s))
                    .collect();
                if created.len() != children.len() {
                    return Err(SeedError::Children(i));
                }
                let mut free = created;
                for &c in &children {
                    let Some(j) = free.iter().position(|&x| p.op_of(x) == Some(seed.steps[c].op)) else {
                        return Err(SeedError::Children(i));
                    };
                    id[c] = Some(free.remove(j));
                    order.push(c);
                }
            }
        }
        if let Some(c) = (0..n).find(|&c| id[c].is_none()) {
            return Err(SeedError::Children(seed.steps[c].parent.unwrap_or(c)));
        }
        let id: Vec<u32> = id.into_iter().map(|s| s.unwrap_or(INIT)).collect();
        let mut of_seed: Vec<Option<usize>> = vec![None; p.steps.len()];
        let mut times = OldTimes(rustc_hash::FxHashMap::default());
        times.0.insert(ORIGIN, f64::NEG_INFINITY);
        times.0.insert(p.goal_tp, f64::INFINITY);
        for step in p.steps.iter() {
            if let Kind::Til(t) = step.kind {
                times.0.insert(step.start, self.task.tils[t as usize].time);
            }
        }
        let mut old = crate::planner::plan::OldSchedule::default();
        for (i, &s) in id.iter().enumerate() {
            of_seed[s as usize] = Some(i);
            let step = p.steps[s as usize];
            times.0.insert(step.start, seed.steps[i].start);
            times.0.insert(step.end, seed.steps[i].end);
            if !seed.steps[i].fixed && !self.task.ops[seed.steps[i].op as usize].is_abstract {
                old.starts.push((step.start, seed.steps[i].start));
            }
            old.makespan = old.makespan.max(seed.steps[i].end);
        }
        p.old_times = std::rc::Rc::new(old);
        // Fixed times, nothing else before now, then the orderings kept.
        if let Some(now) = seed.now.filter(|&t| t > 0.0) {
            p.not_before = now;
        }
        for (i, st) in seed.steps.iter().enumerate() {
            let step = p.steps[id[i] as usize];
            if !st.fixed && p.not_before > 0.0 && !p.stn.add(ORIGIN, step.start, p.not_before) {
                return Err(SeedError::Inconsistent);
            }
            if st.fixed && !fix(&mut p, step.start, st.start) {
                return Err(SeedError::Inconsistent);
            }
            if st.done && !fix(&mut p, step.end, st.end) {
                return Err(SeedError::Inconsistent);
            }
        }
        for o in &seed.orders {
            let a = p.steps[id[o.from.0] as usize].tp(o.from.1);
            let b = p.steps[id[o.to.0] as usize].tp(o.to.1);
            if !p.stn.before(a, b) && !p.stn.add(a, b, EPS) {
                return Err(SeedError::Inconsistent);
            }
        }
        self.link_as_before(&mut p, &times);
        self.replay_itineraries(&mut p, &times);
        self.order_threats_as_before(&mut p, &times);
        if !self.force_threats(&mut p, true) {
            return Err(SeedError::Inconsistent);
        }
        Ok((p, of_seed))
    }

    /// Supports each open link by the producer the old schedule had: the
    /// latest one before the need among the seed's steps, else the initial
    /// state. Visits of itineraries are left to them.
    fn link_as_before(&self, p: &mut Plan, times: &OldTimes) {
        let undone = Undone::new(self.task, p, times);
        let first_link = p.links.len() as u32;
        // Linking adds links and orderings, never steps: one index serves.
        let effects = super::resolvers::Effects::new(self.task, p);
        let mut i = 0;
        let mut producers = Vec::new();
        while i < p.open.len() {
            let o = p.open[i];
            if self.is_visit(&o) {
                i += 1;
                continue;
            }
            let Some(need) = times.at(o.need) else {
                i += 1;
                continue;
            };
            self.producers_indexed(p, &o, &effects, &mut producers);
            if o.origin == OpenOrigin::AbstractEffect {
                producers.retain(|&(s, _)| s != o.step && p.descends(s, o.step));
            }
            let best = producers
                .iter()
                .filter_map(|&(s, tp)| {
                    let t = times.at(tp)?;
                    // The old times are read from a plan file, rounded.
                    let before = t <= need + OLD_TIME_SLACK || o.origin == OpenOrigin::AbstractEffect;
                    before.then_some((t, s, tp))
                })
                .max_by(|a, b| a.0.total_cmp(&b.0));
            let Some((t, s, tp)) = best else {
                i += 1;
                continue;
            };
            // A step of the old plan undid the literal in between: the
            // step that made it true again for this need was removed, and
            // the link would not be the old one (the need stays open).
            if o.origin != OpenOrigin::AbstractEffect && undone.between(self.task, o.lit, t, need) {
                i += 1;
                continue;
            }
            // A step executed at time 0 (other planners start there) reads
            // the initial state in the same happening, no ε after it.
            let at_origin = s == INIT && need < EPS && !p.stn.allows(ORIGIN, o.need, EPS);
            let sep = if at_origin { 0.0 } else { Plan::link_separation(&o) };
            // A dry run first, then the plan changed in place (a copy per
            // link copied the threats each time); the threats of the links
            // are recorded at the end, all at once.
            if tp != o.need && !p.stn.allows(tp, o.need, sep) {
                i += 1;
                continue;
            }
            let open = p.remove_open(i);
            let linked = p.add_link_without_threats(s, tp, &open, sep);
            debug_assert!(linked, "the network allowed the link");
        }
        p.threats_of_links(self.task, first_link);
    }
}

impl Search<'_, '_> {
    /// Under geometric reasoning, the itineraries of the old plan, replayed:
    /// each itinerary goes on, in the old schedule's order, through the
    /// visits of the old steps that the member makes where it already is
    /// (a causal link from its tail, as the search links a visit; the moves
    /// of the old plan are steps of the seed, their own visits among
    /// those), until the next old visit is elsewhere (a move of the old
    /// plan is gone, or the member starts elsewhere). The visits left, and
    /// those of the steps the search adds, go after the tail as the search
    /// sequences them: new work comes after what the member already does,
    /// and an itinerary the event did not break costs no search at all.
    fn replay_itineraries(&self, p: &mut Plan, times: &OldTimes) {
        let Some(geo) = &self.geo else { return };
        // The visits do not bound the pending ones after each new tail
        // (a robot with a hundred old visits would get five thousand
        // orderings, most of the network's): the tails reached bound them
        // at the end, which implies the others.
        // Should the plan not take them, the replay starts again with the
        // bounds after each visit, as the search makes them, and the
        // itinerary that cannot take its bounds stops there.
        let start = p.clone();
        let mut extended: Vec<((u32, u32), u32)> = Vec::new();
        let mut pending = geo.pending(self.task, p);
        self.replay(geo, p, times, &mut pending, &mut extended, false);
        if !geo.bound_pending(self.task, p, &pending, &extended) {
            *p = start;
            let mut pending = geo.pending(self.task, p);
            self.replay(geo, p, times, &mut pending, &mut Vec::new(), true);
        }
    }

    /// The loop of [`Search::replay_itineraries`], which records the
    /// itineraries extended and their last visits' steps; `bound`: as
    /// [`Geo::visit`]'s.
    fn replay(
        &self,
        geo: &Geo,
        p: &mut Plan,
        times: &OldTimes,
        pending: &mut Vec<itinerary::Pending>,
        extended: &mut Vec<((u32, u32), u32)>,
        bound: bool,
    ) {
        let old = |p: &Plan, i: usize| times.at(p.open[i].need).filter(|t| t.is_finite());
        // Each itinerary is replayed until it breaks; a visit is linked at
        // most once, so this ends.
        let mut broken: Vec<(u32, u32)> = Vec::new();
        // The pending visits are kept up to date after each visit rather
        // than read again from every open link (a replay visits about as
        // many times as the plan has open links).
        loop {
            let mut c = p.clone();
            if !geo.unblock(self.task, &mut c, pending) {
                return;
            }
            *p = c;
            let mut next = None;
            for b in pending.iter() {
                if broken.contains(&(b.group, b.scope)) {
                    continue;
                }
                let Some(ti) = itinerary::tail_index(p, b.group, b.scope) else { continue };
                let t = p.tails[ti];
                if t.blocked_by != itinerary::NONE {
                    continue;
                }
                let first = b
                    .visits
                    .iter()
                    .filter_map(|&i| old(p, i).map(|t| (t, i)))
                    .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                let Some((_, i)) = first else { continue };
                let o = p.open[i];
                // Elsewhere: the plan's itinerary goes there by the
                // shortest route (a move of the old plan left from where the
                // member no longer is, and the repair removed it), an
                // abstract step's cannot (its methods say how it moves).
                let here = Geo::position(self.task, o.lit).is_some_and(|(_, pos)| pos == t.pos);
                let move_from_elsewhere =
                    !here && p.op_of(o.step).is_some_and(|op| self.task.moves.contains_key(&op));
                let preceded = b.visits.iter().any(|&j| {
                    let q = p.open[j];
                    q.step != o.step && q.need != o.need && p.stn.before(q.need, o.need)
                });
                if (!here && (b.scope != itinerary::NONE || move_from_elsewhere)) || preceded {
                    broken.push((b.group, b.scope));
                    continue;
                }
                next = Some((b.clone(), ti, i));
                break;
            }
            let Some((b, ti, i)) = next else { return };
            // The open links the visit links: those of its step to the same place.
            let o = p.open[i];
            let same: Vec<usize> = b
                .visits
                .iter()
                .copied()
                .filter(|&j| p.open[j].step == o.step && p.open[j].lit == o.lit)
                .collect();
            match geo.visit(self.task, self.h, p, &b, ti, i, bound) {
                Some(c) => {
                    *pending = geo.pending_after(self.task, p.open.len(), &c, pending, &same);
                    debug_assert_eq!(
                        *pending,
                        geo.pending(self.task, &c),
                        "the pending visits kept up to date"
                    );
                    *p = c;
                    let key = (b.group, b.scope);
                    match extended.iter_mut().find(|(k, _)| *k == key) {
                        Some(e) => e.1 = o.step,
                        None => extended.push((key, o.step)),
                    }
                }
                None => broken.push((b.group, b.scope)),
            }
        }
    }
}

/// When the start plan's steps undo literals in the old schedule: the old
/// times of their effects that delete a literal (by literal), and of those
/// that put a member of a position family somewhere (by family group).
struct Undone {
    deleted: FxHashMap<Lit, Vec<f64>>,
    placed: FxHashMap<u32, Vec<(f64, u32)>>,
}

impl Undone {
    fn new(task: &Task<'_>, p: &Plan, times: &OldTimes) -> Undone {
        let mut out = Undone { deleted: FxHashMap::default(), placed: FxHashMap::default() };
        for step in p.steps.iter() {
            let Kind::Op(op) = step.kind else { continue };
            for e in &task.ops[op as usize].effs {
                let Some(t) = times.at(step.tp(e.at)) else { continue };
                out.deleted.entry(negate(e.lit)).or_default().push(t);
                if !is_neg(e.lit)
                    && let Some((group, pos)) = task.family.get(atom_of(e.lit) as usize).copied().flatten()
                {
                    out.placed.entry(group).or_default().push((t, pos));
                }
            }
        }
        out
    }

    /// Whether literal `lit` was undone strictly between `from` and `to`
    /// in the old schedule: deleted, or its member put elsewhere.
    fn between(&self, task: &Task<'_>, lit: Lit, from: f64, to: f64) -> bool {
        let inside = |t: f64| t > from + OLD_TIME_SLACK && t < to - OLD_TIME_SLACK;
        if self.deleted.get(&lit).is_some_and(|v| v.iter().any(|&t| inside(t))) {
            return true;
        }
        !is_neg(lit)
            && task.family.get(atom_of(lit) as usize).copied().flatten().is_some_and(|(group, pos)| {
                self.placed.get(&group).is_some_and(|v| v.iter().any(|&(t, q)| q != pos && inside(t)))
            })
    }
}

impl Search<'_, '_> {
    /// Orders each threat the way the old schedule has it, when the network
    /// allows: the threat is then solved as it was.
    fn order_threats_as_before(&self, p: &mut Plan, times: &OldTimes) {
        let mut i = p.threats.len();
        while i > 0 {
            i -= 1;
            let t = p.threats[i];
            let orders = self.threat_orders(p, &t);
            for (a, b) in orders {
                let (Some(ta), Some(tb)) = (times.at(a), times.at(b)) else { continue };
                if ta < tb && p.stn.allows(a, b, EPS) && p.stn.add(a, b, EPS) {
                    std::rc::Rc::make_mut(&mut p.threats).remove(i);
                    break;
                }
            }
        }
    }
}
