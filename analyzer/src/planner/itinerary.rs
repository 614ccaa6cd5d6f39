//! Geometric reasoning as itineraries (section 4.3 of the HiPOP paper).
//!
//! A member of a position family with move actions (`at r1 *`, Definitions
//! 12 and 14) is in one place at a time. Every step that needs it somewhere
//! (a *visit*: an open link to one of its positions) or moves it is
//! therefore in one sequence, its *itinerary*, and move actions can always
//! be added between two consecutive visits. The planner builds each
//! itinerary from its start, one visit at a time:
//!
//! - the *tail* of an itinerary is where the member is once the visits
//!   sequenced so far are done: the step and time point that put it there
//!   (its last known position, 4.3.1) and the time point until which the
//!   last visit holds it (its *release*);
//! - extending an itinerary chooses which pending visit comes next (one
//!   child per candidate), supports it from the tail (a causal link when the
//!   member is already there, else the shortest chain of moves, 4.3.2), and
//!   puts every other pending visit after it, at least the shortest travel
//!   time later ("adding temporal constraints", 4.3.2, from the last known
//!   position each time it changes). The order of the visits is then in
//!   the network, and its travel in the makespan, before any other choice:
//!   two orders of the same visits have different costs, so A* does not
//!   enumerate them as a plateau, and no position threat (Definition 13) is
//!   left to order one by one;
//! - an abstract step that needs the member and may move it (its
//!   `:conflicts` name the member's position, or its methods move it)
//!   *holds* it: the steps of its methods have an itinerary of their own
//!   (its *scope*), from where the member is at the abstract step's start,
//!   without new moves (its methods say how it moves). When the abstract
//!   step declares where it leaves the member, the itinerary goes on from
//!   that effect at once; when it does not (a round trip), the itinerary
//!   waits (is *blocked*) until the step is refined and its own itinerary
//!   is done, and goes on from where that one ends.
//!
//! A visit that enters the plan after its itinerary went past it (a step
//! inserted later, under a refinement) can only go at the end: visits are
//! sequenced once the open links that insert steps are solved (positions
//! last, 4.3.2), so this only restricts steps that methods add around a
//! member without holding it.

use std::rc::Rc;

use super::heuristic::Heuristic;
use super::plan::{Kind, Open, OpenOrigin, Plan};
use super::stn::{EPS, Tp};
use super::task::{Lit, Task, atom_of, is_neg, lit};

/// No step / no scope / unknown position.
pub const NONE: u32 = u32::MAX;

/// Where an itinerary stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tail {
    /// The motion group (the member).
    pub group: u32,
    /// The abstract step holding this itinerary, or [`NONE`] (the plan's).
    pub scope: u32,
    /// The step and time point whose effect put the member at `pos`.
    pub producer: u32,
    pub producer_tp: Tp,
    /// The member's local position, [`NONE`] while blocked.
    pub pos: u32,
    /// The last visit holds the member until this time point.
    pub release: Tp,
    /// The abstract step whose refinement tells where the member is, or [`NONE`].
    pub blocked_by: u32,
}

/// The pending visits of one itinerary: open links, by index.
#[derive(Debug, Clone, PartialEq)]
pub struct Pending {
    pub group: u32,
    pub scope: u32,
    pub visits: Vec<usize>,
}

/// What the search knows about positions: which abstract operators hold
/// which members.
pub struct Geo {
    /// Per operator: the motion groups it holds (sorted).
    held: Vec<Vec<u32>>,
    /// Per abstract operator: the motion groups its refinements may move (sorted).
    moves: Vec<Vec<u32>>,
}

impl Geo {
    pub fn new(task: &Task<'_>, h: &Heuristic) -> Geo {
        let moves: Vec<Vec<u32>> = task
            .ops
            .iter()
            .enumerate()
            .map(|(op, o)| {
                if !o.is_abstract {
                    return Vec::new();
                }
                (0..task.motion.len() as u32)
                    .filter(|&g| {
                        task.motion[g as usize]
                            .as_ref()
                            .is_some_and(|m| m.positions.iter().any(|&a| h.may_add(op as u32, lit(a, false))))
                    })
                    .collect()
            })
            .collect();
        let held = task
            .ops
            .iter()
            .enumerate()
            .map(|(op, o)| {
                if !o.is_abstract {
                    return Vec::new();
                }
                let mut v: Vec<u32> = o
                    .conds
                    .iter()
                    .filter(|c| !is_neg(c.lit))
                    .filter_map(|c| {
                        let (_, g, _) = task.motion_of(atom_of(c.lit))?;
                        let holds =
                            o.conflicts_with(task.g, atom_of(c.lit)) || moves[op].binary_search(&g).is_ok();
                        holds.then_some(g)
                    })
                    .collect();
                v.sort_unstable();
                v.dedup();
                v
            })
            .collect();
        Geo { held, moves }
    }

    /// The tails the plan starts with: every member where the initial state puts it.
    pub fn initial_tails(&self, task: &Task<'_>) -> Vec<Tail> {
        let mut out = Vec::new();
        for (g, m) in task.motion.iter().enumerate() {
            let Some(m) = m else { continue };
            if let Some(pos) = m.positions.iter().position(|&a| task.init[a as usize]) {
                out.push(Tail {
                    group: g as u32,
                    scope: NONE,
                    producer: super::plan::INIT,
                    producer_tp: super::stn::ORIGIN,
                    pos: pos as u32,
                    release: super::stn::ORIGIN,
                    blocked_by: NONE,
                });
            }
        }
        out
    }

    /// The motion group and local position of a literal, when it is a
    /// position of a member with move actions.
    pub fn position(task: &Task<'_>, l: Lit) -> Option<(u32, u32)> {
        if is_neg(l) {
            return None;
        }
        task.motion_of(atom_of(l)).map(|(_, g, pos)| (g, pos))
    }

    /// Whether step `s` holds member `group` (an abstract step that needs it
    /// and may move it).
    pub fn holds(&self, p: &Plan, s: u32, group: u32) -> bool {
        p.op_of(s).is_some_and(|o| self.held[o as usize].binary_search(&group).is_ok())
    }

    /// Whether step `s` (abstract) may move member `group` once refined.
    fn may_move(&self, p: &Plan, s: u32, group: u32) -> bool {
        p.op_of(s).is_some_and(|o| {
            self.held[o as usize].binary_search(&group).is_ok()
                || self.moves[o as usize].binary_search(&group).is_ok()
        })
    }

    /// The itinerary a visit belongs to: the nearest abstract step above it
    /// that holds its member (an abstract step's own effect is its own
    /// methods' to achieve), else the plan's.
    pub fn scope(&self, p: &Plan, o: &Open, group: u32) -> u32 {
        if o.origin == OpenOrigin::AbstractEffect && self.holds(p, o.step, group) {
            return o.step;
        }
        let mut up = p.steps[o.step as usize].parent;
        while let Some(a) = up {
            if self.holds(p, a, group) {
                return a;
            }
            up = p.steps[a as usize].parent;
        }
        NONE
    }

    /// The pending visits of every itinerary.
    pub fn pending(&self, task: &Task<'_>, p: &Plan) -> Vec<Pending> {
        let mut out: Vec<Pending> = Vec::new();
        for (i, o) in p.open.iter().enumerate() {
            let Some((g, _)) = Geo::position(task, o.lit) else { continue };
            let scope = self.scope(p, o, g);
            match out.iter_mut().find(|b| b.group == g && b.scope == scope) {
                Some(b) => b.visits.push(i),
                None => out.push(Pending { group: g, scope, visits: vec![i] }),
            }
        }
        out
    }

    /// [`Geo::pending`] of `after`, a plan made from `before` (with
    /// `pending`) by removing its open links `removed` (ascending) and
    /// appending others, as [`Geo::visit`] makes one: the indices moved,
    /// and only the appended open links read. An itinerary's scope does not
    /// change (it is the steps' hierarchy), and the itineraries stay in the
    /// order of their first visit.
    pub fn pending_after(
        &self,
        task: &Task<'_>,
        before: usize,
        after: &Plan,
        pending: &[Pending],
        removed: &[usize],
    ) -> Vec<Pending> {
        let moved = |i: usize| i - removed.partition_point(|&r| r < i);
        let mut out: Vec<Pending> = pending
            .iter()
            .map(|b| Pending {
                group: b.group,
                scope: b.scope,
                visits: b
                    .visits
                    .iter()
                    .filter(|&i| removed.binary_search(i).is_err())
                    .map(|&i| moved(i))
                    .collect(),
            })
            .filter(|b| !b.visits.is_empty())
            .collect();
        for (i, o) in after.open.iter().enumerate().skip(before - removed.len()) {
            let Some((g, _)) = Geo::position(task, o.lit) else { continue };
            let scope = self.scope(after, o, g);
            match out.iter_mut().find(|b| b.group == g && b.scope == scope) {
                Some(b) => b.visits.push(i),
                None => out.push(Pending { group: g, scope, visits: vec![i] }),
            }
        }
        out.sort_by_key(|b| b.visits[0]);
        out
    }

    /// Bounds the pending visits of the itineraries `extended` (with the
    /// step of the last visit of each) after their tails, at least the
    /// travel time later, as [`Geo::visit`] does after each visit: for a
    /// caller that made several visits without (the bounds from the tails
    /// it passed are implied by the moves and visits since, whose durations
    /// are at least the travel times). `false` when the plan cannot take
    /// them.
    pub fn bound_pending(
        &self,
        task: &Task<'_>,
        p: &mut Plan,
        pending: &[Pending],
        extended: &[((u32, u32), u32)],
    ) -> bool {
        for b in pending {
            let Some(&(_, last)) = extended.iter().find(|(k, _)| *k == (b.group, b.scope)) else { continue };
            let (Some(t), Some(m)) = (tail(p, b.group, b.scope), task.motion[b.group as usize].as_ref())
            else {
                continue;
            };
            let others: Vec<Open> = b.visits.iter().map(|&j| p.open[j]).filter(|q| q.step != last).collect();
            if !bound_after(task, m, &mut p.stn, &t, others.into_iter()) {
                return false;
            }
        }
        true
    }

    /// A new visit starts after its itinerary's tail, at least the shortest
    /// travel time later (4.3.2). `false` when it cannot (the plan is dead).
    pub fn bound(&self, task: &Task<'_>, p: &mut Plan, o: &Open) -> bool {
        let Some((g, pos)) = Geo::position(task, o.lit) else { return true };
        let scope = self.scope(p, o, g);
        let Some(t) = tail(p, g, scope) else { return true };
        if t.blocked_by != NONE {
            return p.stn.add(t.release, o.need, sep(o));
        }
        let d = dist(task, g, t.pos, pos);
        d.is_finite() && p.stn.add(t.release, o.need, d + sep(o))
    }

    /// Unblocks the itineraries waiting for an abstract step that is now
    /// refined and whose own itinerary is done: they go on from where that
    /// one ends, and their pending visits are put after it. `false` when
    /// that cannot be (the plan is dead).
    pub fn unblock(&self, task: &Task<'_>, p: &mut Plan, pending: &[Pending]) -> bool {
        for k in 0..p.tails.len() {
            let t = p.tails[k];
            let s = t.blocked_by;
            if s == NONE || p.steps[s as usize].method.is_none() {
                continue;
            }
            if pending.iter().any(|b| b.group == t.group && b.scope == s && !b.visits.is_empty()) {
                continue;
            }
            if p.abstracts.iter().any(|&a| a != s && p.descends(a, s) && self.may_move(p, a, t.group)) {
                continue;
            }
            let Some(inner) = tail(p, t.group, s) else { return false };
            if inner.blocked_by != NONE {
                continue;
            }
            let release = p.steps[s as usize].end;
            let new = Tail {
                producer: inner.producer,
                producer_tp: inner.producer_tp,
                pos: inner.pos,
                release,
                blocked_by: NONE,
                ..t
            };
            Rc::make_mut(&mut p.tails)[k] = new;
            if let Some(b) = pending.iter().find(|b| b.group == t.group && b.scope == t.scope) {
                for &i in &b.visits {
                    let o = p.open[i];
                    let Some((_, pos)) = Geo::position(task, o.lit) else { continue };
                    let d = dist(task, t.group, new.pos, pos);
                    if !(d.is_finite() && p.stn.add(release, o.need, d + sep(&o))) {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// The itinerary to extend next, among those with pending visits and a
    /// known tail: the inner ones (an abstract step's) first, then the one
    /// whose member is free first.
    pub fn choose(&self, p: &Plan, pending: &[Pending]) -> Option<usize> {
        let mut best: Option<(usize, bool, f64, u32)> = None;
        for (k, b) in pending.iter().enumerate() {
            let Some(t) = tail(p, b.group, b.scope) else { continue };
            if t.blocked_by != NONE || b.visits.is_empty() {
                continue;
            }
            let (top, free) = (b.scope == NONE, p.stn.est(t.release));
            let better = best.as_ref().is_none_or(|&(_, t0, f0, g0)| {
                top.cmp(&t0).then(free.total_cmp(&f0)).then(b.group.cmp(&g0)).is_lt()
            });
            if better {
                best = Some((k, top, free, b.group));
            }
        }
        best.map(|(k, ..)| k)
    }

    /// The children that extend itinerary `b` by each visit that can come
    /// next.
    pub fn extend(&self, task: &Task<'_>, h: &Heuristic, p: &Plan, b: &Pending, out: &mut Vec<Plan>) {
        let Some(ti) = tail_index(p, b.group, b.scope) else { return };
        let t = p.tails[ti];
        let Some(m) = task.motion[b.group as usize].as_ref() else { return };
        for &i in &b.visits {
            let o = p.open[i];
            let Some((_, pos)) = Geo::position(task, o.lit) else { continue };
            // A visit that another one must precede cannot come next; the
            // goal's visits come last.
            let preceded = b.visits.iter().any(|&j| {
                let q = p.open[j];
                q.step != o.step && (p.stn.before(q.need, o.need) && q.need != o.need)
            });
            let last_only =
                o.step == super::plan::GOAL && b.visits.iter().any(|&j| p.open[j].step != super::plan::GOAL);
            if preceded || last_only {
                continue;
            }
            let d = m.dist(t.pos as usize, pos as usize);
            if !d.is_finite() || (d > 0.0 && b.scope != NONE) {
                continue;
            }
            if let Some(c) = self.visit(task, h, p, b, ti, i, true) {
                out.push(c);
            }
        }
    }

    /// `p` with visit `i` next in itinerary `b` (tail `ti`); with `bound`,
    /// every other pending visit of `b` after the new tail, at least the
    /// travel time later (without, the caller bounds them later:
    /// [`Geo::bound_pending`]).
    #[allow(clippy::too_many_arguments)]
    pub fn visit(
        &self,
        task: &Task<'_>,
        h: &Heuristic,
        p: &Plan,
        b: &Pending,
        ti: usize,
        i: usize,
        bound: bool,
    ) -> Option<Plan> {
        let t = p.tails[ti];
        let m = task.motion[b.group as usize].as_ref()?;
        let o = p.open[i];
        let (_, pos) = Geo::position(task, o.lit)?;
        let mut c = p.clone();
        // The visit, and the other open links of its step to the same
        // position, linked together.
        let mut same: Vec<usize> = b
            .visits
            .iter()
            .copied()
            .filter(|&j| p.open[j].step == o.step && p.open[j].lit == o.lit)
            .collect();
        same.sort_unstable();
        let opens: Vec<Open> = same.iter().map(|&j| p.open[j]).collect();
        for &j in same.iter().rev() {
            c.remove_open(j);
        }
        // From the tail: a causal link, or a chain of moves first.
        let (mut prod, mut prod_tp) = (t.producer, t.producer_tp);
        if t.pos != pos {
            let path = m.path(t.pos, pos, |mv| task.moves[&mv].2)?;
            for (k, &mv) in path.iter().enumerate() {
                let ns = c.add_step(task, h, mv, None)?;
                let from_lit = lit(m.positions[task.moves[&mv].1 as usize], false);
                let idx =
                    (0..c.open.len()).rev().find(|&j| c.open[j].step == ns && c.open[j].lit == from_lit)?;
                let open = c.remove_open(idx);
                if k == 0 && t.release != t.producer_tp && !c.stn.add(t.release, open.need, EPS) {
                    return None;
                }
                if !c.add_link(task, prod, prod_tp, &open) {
                    return None;
                }
                (prod, prod_tp) = (ns, c.steps[ns as usize].end);
            }
        }
        for q in &opens {
            if t.release != t.producer_tp && prod == t.producer && !c.stn.add(t.release, q.need, sep(q)) {
                return None;
            }
            if !c.add_link(task, prod, prod_tp, q) {
                return None;
            }
        }
        // The new tail: where the visit's step leaves the member.
        let step = c.steps[o.step as usize];
        let moved = c.effects(task, o.step).find_map(|(l, tp)| {
            let (g, to) = Geo::position(task, l)?;
            (g == b.group && (to != pos || tp != o.need)).then_some((to, tp))
        });
        let release =
            opens.iter().map(|q| q.until).fold(o.until, |a, u| if c.stn.before(a, u) { u } else { a });
        let held = self.may_move(&c, o.step, b.group) && matches!(step.kind, Kind::Op(_));
        let new = match moved {
            Some((to, tp)) => {
                Tail { producer: o.step, producer_tp: tp, pos: to, release: tp, blocked_by: NONE, ..t }
            }
            None if held => Tail {
                producer: NONE,
                producer_tp: step.end,
                pos: NONE,
                release: step.end,
                blocked_by: o.step,
                ..t
            },
            None => Tail { producer: prod, producer_tp: prod_tp, pos, release, blocked_by: NONE, ..t },
        };
        // Every other pending visit comes after it.
        if bound {
            let others = b.visits.iter().map(|&j| p.open[j]).filter(|q| q.step != o.step);
            if !bound_after(task, m, &mut c.stn, &new, others) {
                return None;
            }
        }
        let tails = Rc::make_mut(&mut c.tails);
        tails[ti] = new;
        // An abstract step holding the member: its methods' itinerary starts here.
        if held && tails.iter().all(|x| !(x.group == b.group && x.scope == o.step)) {
            tails.push(Tail {
                group: b.group,
                scope: o.step,
                producer: prod,
                producer_tp: prod_tp,
                pos,
                // Its steps are inside the abstract step, which starts
                // after this producer: no separation of their own.
                release: prod_tp,
                blocked_by: NONE,
            });
        }
        Some(c)
    }

    /// Equation 2 with the itineraries: each pending visit costs the
    /// shortest travel to it from its tail or from another pending visit of
    /// its itinerary that may come before it (its possible last known
    /// positions).
    pub fn travel(&self, task: &Task<'_>, p: &Plan, pending: &[Pending]) -> f64 {
        let mut total = 0.0;
        for b in pending {
            let Some(m) = task.motion[b.group as usize].as_ref() else { continue };
            let t = tail(p, b.group, b.scope).filter(|t| t.blocked_by == NONE);
            for &i in &b.visits {
                let o = p.open[i];
                let Some((_, pos)) = Geo::position(task, o.lit) else { continue };
                let mut best = t.map_or(f64::INFINITY, |t| m.dist(t.pos as usize, pos as usize));
                for &j in &b.visits {
                    let q = p.open[j];
                    if q.step == o.step || p.stn.before(o.need, q.need) {
                        continue;
                    }
                    if let Some((_, qpos)) = Geo::position(task, q.lit) {
                        best = best.min(m.dist(qpos as usize, pos as usize));
                    }
                }
                if best.is_finite() {
                    total += best;
                }
            }
        }
        total
    }
}

/// The separation between a member's last visit and the next: none before
/// an abstract step's own effect, which holds as soon as the subtask that
/// makes it ends (the same happening as the step's end).
/// Bounds `visits` (open links of positions of `m`'s member) after tail
/// `t`: each at least the travel time from the tail's position later (no
/// time while the tail's position is not known). `false` when the network
/// cannot take one.
fn bound_after(
    task: &Task<'_>,
    m: &super::task::MotionGroup,
    stn: &mut super::stn::Stn,
    t: &Tail,
    visits: impl Iterator<Item = Open>,
) -> bool {
    for q in visits {
        let Some((_, qpos)) = Geo::position(task, q.lit) else { return false };
        let d = if t.pos == NONE { 0.0 } else { m.dist(t.pos as usize, qpos as usize) };
        if !(d.is_finite() && stn.add(t.release, q.need, d + sep(&q))) {
            return false;
        }
    }
    true
}

fn sep(o: &Open) -> f64 {
    if o.origin == OpenOrigin::AbstractEffect { 0.0 } else { EPS }
}

/// Where the tail of an itinerary is in [`Plan::tails`], if it has started.
pub fn tail_index(p: &Plan, group: u32, scope: u32) -> Option<usize> {
    p.tails.iter().position(|t| t.group == group && t.scope == scope)
}

/// The tail of an itinerary, if it has started.
pub fn tail(p: &Plan, group: u32, scope: u32) -> Option<Tail> {
    tail_index(p, group, scope).map(|k| p.tails[k])
}

fn dist(task: &Task<'_>, group: u32, from: u32, to: u32) -> f64 {
    match task.motion[group as usize].as_ref() {
        Some(m) if from != NONE => m.dist(from as usize, to as usize),
        _ => 0.0,
    }
}
