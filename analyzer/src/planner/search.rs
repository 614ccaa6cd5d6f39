//! Algorithm 1 of the HiPOP paper: A* over partial plans, with HiPOP's plan
//! and flaw selection (section 4.2.3) and geometric reasoning (4.3).
//!
//! - Plan selection: `f = g + h`, `g` the makespan of the plan's earliest
//!   schedule (or the busiest agent's work, when larger: [`Search::load`])
//!   plus what its threats must cost (the least delay of the worse of its
//!   two orderings, for the worst threat: [`Search::settle`]), `h` the sum of the estimates of its open links (h_add, or its
//!   `reuse`, `advance-reuse`, `motion` and `ncm` variants, Equations 1–3)
//!   plus the refinement estimates of its abstract flaws; ties broken on the
//!   remaining effort, then last in, first out.
//! - Flaw selection: threats first (last found first), then open links
//!   (`local`: those of the step most recently added that still has some;
//!   `sorted`: all of them; the costliest first; `threatFirst`: last in,
//!   first out), open links to positions last when move actions exist, then
//!   abstract flaws in chronological order. A plan without those is checked
//!   for interfering happenings at the same time (VAL's mutex), which are
//!   ordered one way or the other.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::time::Instant;

use super::heuristic::Heuristic;
use super::itinerary::{Geo, Pending};
use super::plan::{GOAL, INIT, Kind, Open, OpenOrigin, Plan, Threat, ThreatKind};
use super::stn::{EPS, ORIGIN, Tp};
use super::task::{Lit, Task, atom_of, is_neg};
use super::{Config, FlawOrder, LimitKind, Motion, PlanHeuristic, PlannerLimits, Progress, Stats};

/// What a unit of work costs in `g` beyond the makespan: every step costs
/// something, so that no chain of steps is free (a step that fits in
/// parallel does not lengthen the makespan, and reuse makes its conditions
/// free in `h`): A* needs positive costs to leave an endless subtree of
/// such plans (`tests/planner/props/step-cost.pddl`). Small, so that the
/// makespan decides: measured neutral on the benchmarks' makespans.
const STEP_COST: f64 = 0.02;

/// A plan in the open list.
struct Node {
    f: f64,
    /// Its lineage had a greedy completion already.
    probed: bool,
    effort: f64,
    /// Steps: a smaller plan first among equals (a chain of steps that
    /// cost nothing, parallel in the makespan and free in h by reuse,
    /// must not hide the sibling that links to a step already there).
    size: usize,
    id: u64,
    plan: Plan,
}

impl PartialEq for Node {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Node {
    /// The best node is the greatest (BinaryHeap is a max-heap).
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .f
            .total_cmp(&self.f)
            .then(other.effort.total_cmp(&self.effort))
            .then(other.size.cmp(&self.size))
            .then(self.id.cmp(&other.id))
    }
}

/// The flaw chosen in a plan.
enum Flaw {
    Threat(usize),
    Open(usize),
    Abstract(usize),
    Mutex(Tp, Tp),
    /// A goal that a timed initial literal makes true, at this time point,
    /// after the plan's last event: VAL does not apply it.
    Late(Tp),
    /// The next visit of an itinerary (geometric reasoning).
    Visit(Pending),
    /// A flaw no resolver can solve (a threat with no ordering left, an
    /// itinerary that cannot go on): the plan has no child.
    Dead,
}

pub struct Search<'a, 'db> {
    pub task: &'a Task<'db>,
    pub h: &'a Heuristic,
    pub config: &'a Config,
    /// Geometric reasoning: the itineraries of the members of position
    /// families with move actions in 𝒜 (`motion`, `ncm`).
    geo: Option<Geo>,
    /// Method instances not tried because they only go round a loop.
    loops: std::cell::Cell<u64>,
}

/// How a search ended.
pub enum End2 {
    Solved(Plan),
    Exhausted,
    Limit(LimitKind),
}

impl<'a, 'db> Search<'a, 'db> {
    pub fn new(task: &'a Task<'db>, h: &'a Heuristic, config: &'a Config) -> Self {
        let has_motion = config.motion != Motion::Off && task.motion.iter().any(|m| m.is_some());
        let geo = has_motion.then(|| Geo::new(task, h));
        Search { task, h, config, geo, loops: Default::default() }
    }

    /// Adds a step (its open links bounded by their itineraries).
    fn add_step(&self, p: &mut Plan, op: u32, parent: Option<u32>) -> Option<u32> {
        let before = p.open.len();
        let s = p.add_step(self.task, self.h, op, parent)?;
        if let Some(geo) = &self.geo {
            for k in before..p.open.len() {
                let o = p.open[k];
                if !geo.bound(self.task, p, &o) {
                    return None;
                }
            }
        }
        Some(s)
    }

    /// Adds an open link of another origin (bounded by its itinerary).
    fn add_open(&self, p: &mut Plan, o: Open) -> bool {
        if let Some(geo) = &self.geo
            && !geo.bound(self.task, p, &o)
        {
            return false;
        }
        p.add_open(o);
        true
    }

    /// Whether an open link is a visit of an itinerary.
    fn is_visit(&self, o: &Open) -> bool {
        self.geo.is_some() && Geo::position(self.task, o.lit).is_some()
    }

    /// The initial plans: init, goal, timed literals, the goal's open links,
    /// and the `:htn` tasks with their orderings, one plan per ground
    /// initial task network (the bindings of the `:htn` parameters).
    pub fn initial(&self) -> Vec<Plan> {
        let Some(mut p) = Plan::initial(self.task) else { return Vec::new() };
        if let Some(geo) = &self.geo {
            p.tails = std::rc::Rc::new(geo.initial_tails(self.task));
        }
        for (i, &(l, _)) in self.task.goals.iter().enumerate() {
            let o = Open {
                step: GOAL,
                lit: l,
                need: p.goal_tp,
                until: p.goal_tp,
                cond: u32::MAX,
                origin: OpenOrigin::Goal(i as u32),
                after_start: false,
            };
            if !self.add_open(&mut p, o) {
                return Vec::new();
            }
        }
        let Some(nets) = &self.task.htn else { return vec![p] };
        nets.iter()
            .filter_map(|net| {
                let mut p = p.clone();
                let mut ids = Vec::new();
                for &(op, _) in &net.tasks {
                    ids.push(self.add_step(&mut p, op, None)?);
                }
                for o in &net.orders {
                    let a = p.steps[ids[o.from.0] as usize].tp(o.from.1);
                    let b = p.steps[ids[o.to.0] as usize].tp(o.to.1);
                    if !p.stn.add(a, b, if o.strict { EPS } else { 0.0 }) {
                        return None;
                    }
                }
                Some(p)
            })
            .collect()
    }

    /// Producers of a literal that could come before `need` and that are
    /// the last of their family before it (4.3.1): `(step, time point)`.
    fn producers(&self, p: &Plan, o: &Open, out: &mut Vec<(u32, Tp)>) {
        out.clear();
        if self.task.holds_initially(o.lit) && o.step != INIT {
            out.push((INIT, ORIGIN));
        }
        for s in 0..p.steps.len() as u32 {
            for (l, tp) in p.effects(self.task, s) {
                let own_start = s == o.step && o.after_start && tp == o.need;
                if l == o.lit
                    && (tp != o.need || own_start)
                    && (own_start || !p.stn.before(o.need, tp))
                    && !(s == o.step && tp == o.until)
                {
                    out.push((s, tp));
                }
            }
        }
        // The last known position: drop producers that another position
        // change of the same member necessarily follows before the need.
        if !is_neg(o.lit)
            && let Some((group, _)) = self.task.family[atom_of(o.lit) as usize]
            && !out.is_empty()
        {
            let mut changes: Vec<Tp> = Vec::new();
            for s in 0..p.steps.len() as u32 {
                for (l, tp) in p.effects(self.task, s) {
                    if !is_neg(l)
                        && l != o.lit
                        && self.task.family[atom_of(l) as usize].is_some_and(|(g, _)| g == group)
                        && p.stn.before(tp, o.need)
                    {
                        changes.push(tp);
                    }
                }
            }
            out.retain(|&(_, e)| !changes.iter().any(|&c| (e == ORIGIN || p.stn.before(e, c)) && c != e));
        }
    }

    /// h of a plan, and the effort.
    fn estimate(&self, p: &Plan) -> (f64, f64) {
        let (mut h, mut effort) = (0.0, 0.0);
        let index = EffectIndex::new(self.task, p);
        for o in p.open.iter() {
            if self.is_visit(o) {
                effort += 1.0;
                continue;
            }
            let (c, e) = self.open_cost(p, o, &index);
            h += c;
            effort += e;
        }
        if let Some(geo) = &self.geo
            && self.config.motion == Motion::Motion
        {
            // Equation 2: each visit costs the travel from its possible
            // last known positions (Equation 3, `ncm`: nothing).
            h += geo.travel(self.task, p, &geo.pending(self.task, p)).min(1e9);
        }
        for &a in p.abstracts.iter() {
            if let Kind::Op(op) = p.steps[a as usize].kind {
                // An abstract action with its own duration already counts in
                // the makespan: its subtasks fit in it.
                if self.task.ops[op as usize].duration.is_none() {
                    h += self.h.refine_cost[op as usize].min(1e6);
                }
                effort += self.h.refine_effort[op as usize].min(1e6);
            }
        }
        effort += p.threats.len() as f64;
        (h, effort)
    }

    fn open_cost(&self, p: &Plan, o: &Open, index: &EffectIndex) -> (f64, f64) {
        let base = (self.h.lit_cost(o.lit).min(1e6), self.h.lit_effort(o.lit).min(1e6));
        match self.config.plan_h {
            PlanHeuristic::Add => base,
            PlanHeuristic::Reuse => {
                if self.task.holds_initially(o.lit)
                    || index.of(o.lit).iter().any(|&tp| tp != o.need && !p.stn.before(o.need, tp))
                {
                    (0.0, 0.0)
                } else {
                    base
                }
            }
            PlanHeuristic::AdvanceReuse => {
                // Equation 1: a producer that can be before, and every step
                // deleting the literal ordered with it.
                // (A deletion at or after the need, the consumer's own
                // included, cannot come between the producer and the need.)
                let deleters = index.of(o.lit ^ 1);
                let ordered = |e: Tp| {
                    e == ORIGIN
                        || deleters.iter().all(|&d| {
                            d == o.need || p.stn.before(o.need, d) || p.stn.before(d, e) || p.stn.before(e, d)
                        })
                };
                if self.task.holds_initially(o.lit) && o.step != INIT && ordered(ORIGIN) {
                    return (0.0, 0.0);
                }
                for &e in index.of(o.lit) {
                    if e != o.need && !p.stn.before(o.need, e) && ordered(e) {
                        return (0.0, 0.0);
                    }
                }
                base
            }
        }
    }

    /// Drops the threats that are no longer threats and orders in place,
    /// until none is left, those that one ordering only still solves: false
    /// when one has none (the plan is dead). `exact` asks the network
    /// whether each ordering can be added (a dry run of its propagation);
    /// else only the closure is read (an ordering it does not contradict).
    fn force_threats(&self, p: &mut Plan, exact: bool) -> bool {
        loop {
            let mut forced = false;
            let mut i = p.threats.len();
            while i > 0 {
                i -= 1;
                let t = p.threats[i];
                if !p.still_threat(self.task, &t) {
                    std::rc::Rc::make_mut(&mut p.threats).remove(i);
                    continue;
                }
                let ok = |p: &Plan, a: Tp, b: Tp| {
                    if exact { p.stn.allows(a, b, EPS) } else { !p.stn.before(b, a) && b != a }
                };
                let [(a1, b1), (a2, b2)] = self.threat_orders(p, &t);
                let (a, b) = match (ok(p, a1, b1), ok(p, a2, b2)) {
                    (false, false) => return false,
                    (true, true) => continue,
                    (true, false) => (a1, b1),
                    (false, true) => (a2, b2),
                };
                if !p.stn.add(a, b, EPS) {
                    return false;
                }
                std::rc::Rc::make_mut(&mut p.threats).remove(i);
                forced = true;
            }
            if !forced {
                return true;
            }
        }
    }

    /// Solves in place the threats left with one consistent resolver, and
    /// looks ahead at the others: `None` when a threat has no resolver left
    /// (the plan is dead), else the least increase of the makespan that the
    /// worst of the remaining threats forces (both of its orderings are
    /// probed on the network).
    fn settle(&self, p: &mut Plan) -> Option<f64> {
        if !self.force_threats(p, false) {
            return None;
        }
        if p.threats.is_empty() {
            return Some(0.0);
        }
        let lst = p.stn.latest_for(p.goal_tp);
        let mut penalty: f64 = 0.0;
        for t in p.threats.iter() {
            let [(a1, b1), (a2, b2)] = self.threat_orders(p, t);
            let d1 = p.stn.est(a1) + EPS - lst[b1 as usize];
            let d2 = p.stn.est(a2) + EPS - lst[b2 as usize];
            penalty = penalty.max(d1.min(d2));
        }
        Some(penalty.max(0.0))
    }

    /// The busiest agent's work, and the whole plan's. An agent's work is
    /// the sum of the durations of the steps it takes part in (`:agent`), an
    /// abstract step with a duration counting for the subtasks it holds. A
    /// robot of a mission does one thing at a time, so the plan cannot be
    /// shorter; it is what makes the search share the work among the robots
    /// instead of piling it on one while the makespan of the partial plan
    /// does not show it yet. The whole plan's work is the same sum over
    /// every primitive step (or abstract step with a duration), agents or
    /// not, each step counting ε more.
    fn work(&self, p: &Plan) -> (f64, f64) {
        let mut load: rustc_hash::FxHashMap<u32, f64> = rustc_hash::FxHashMap::default();
        let mut total = 0.0;
        for s in p.steps.iter() {
            let Kind::Op(o) = s.kind else { continue };
            let op = &self.task.ops[o as usize];
            if op.is_abstract && op.duration.is_none() {
                continue;
            }
            let mut up = s.parent;
            let mut held = false;
            while let Some(a) = up {
                if p.op_of(a).is_some_and(|ao| self.task.ops[ao as usize].duration.is_some()) {
                    held = true;
                    break;
                }
                up = p.steps[a as usize].parent;
            }
            if held {
                continue;
            }
            let d = op.duration.unwrap_or(0.0) + EPS;
            total += d;
            for &a in &op.agents {
                *load.entry(a).or_insert(0.0) += d;
            }
        }
        (load.values().copied().fold(0.0, f64::max), total)
    }

    /// Picks the flaw to solve (section 4.2.3): threats that have one
    /// ordering left are solved in place (and one with none ends the plan);
    /// then open links (positions last: the itineraries), then the threats
    /// that both orderings still solve (delayed: later choices often order
    /// them, or leave one way only), then abstract flaws in chronological
    /// order, then interfering happenings.
    fn select(&self, p: &mut Plan) -> Option<Flaw> {
        let task = self.task;
        if p.threats.iter().any(|t| !p.still_threat(task, t)) {
            let keep: Vec<Threat> = p.threats.iter().copied().filter(|t| p.still_threat(task, t)).collect();
            p.threats = std::rc::Rc::new(keep);
        }
        if self.config.eager && !p.threats.is_empty() {
            return self.threat_flaw(p);
        }
        let pending = match &self.geo {
            Some(geo) => {
                let pending = geo.pending(task, p);
                if !geo.unblock(task, p, &pending) {
                    return Some(Flaw::Dead);
                }
                pending
            }
            None => Vec::new(),
        };
        // Open links that are not visits and that no unrefined abstract
        // step may still support.
        let ready: Vec<usize> = (0..p.open.len())
            .filter(|&i| !self.is_visit(&p.open[i]) && !self.deferred(p, &p.open[i]))
            .collect();
        if !ready.is_empty() {
            let pick = match self.config.flaws {
                FlawOrder::ThreatFirst => *ready.last().expect("non-empty"),
                FlawOrder::Sorted => self.costliest(p, ready.iter().copied()),
                FlawOrder::Local => {
                    let newest = ready
                        .iter()
                        .map(|&i| p.steps[p.open[i].step as usize].born)
                        .max()
                        .expect("non-empty");
                    self.costliest(
                        p,
                        ready.iter().copied().filter(|&i| p.steps[p.open[i].step as usize].born == newest),
                    )
                }
            };
            return Some(Flaw::Open(pick));
        }
        // Positions: the next visit of an itinerary.
        if let Some(geo) = &self.geo
            && let Some(k) = geo.choose(p, &pending)
        {
            let mut pending = pending;
            return Some(Flaw::Visit(pending.swap_remove(k)));
        }
        // Open links left wait for abstract steps.
        if !p.open.is_empty() && !p.abstracts.is_empty() {
            return Some(self.abstract_flaw(p));
        }
        if !p.threats.is_empty() {
            return self.threat_flaw(p);
        }
        if !p.abstracts.is_empty() {
            return Some(self.abstract_flaw(p));
        }
        if !p.open.is_empty() {
            // Nothing left can support them: their resolvers say so.
            return Some(Flaw::Open(0));
        }
        self.late_til(p).or_else(|| self.mutex(p))
    }

    /// Whether a step is of an elementary action.
    fn elementary(&self, k: Kind) -> bool {
        matches!(k, Kind::Op(o) if !self.task.ops[o as usize].is_abstract)
    }

    /// A goal supported by a timed initial literal later than every event
    /// of the plan: VAL applies no timed literal after the plan's last
    /// event, so some step must end after it.
    fn late_til(&self, p: &Plan) -> Option<Flaw> {
        let last =
            p.steps.iter().filter(|s| self.elementary(s.kind)).map(|s| p.stn.est(s.end)).fold(0.0, f64::max);
        p.links
            .iter()
            .filter(|l| {
                matches!(p.steps[l.from as usize].kind, Kind::Til(_))
                    && p.steps[l.to as usize].kind == Kind::Goal
                    && p.stn.est(l.from_tp) > last + 1e-9
            })
            .map(|l| Flaw::Late(l.from_tp))
            .next()
    }

    /// The earliest unrefined abstract step (chronological order, 4.2.3).
    fn abstract_flaw(&self, p: &Plan) -> Flaw {
        let (i, _) = p
            .abstracts
            .iter()
            .enumerate()
            .map(|(i, &s)| (i, p.stn.est(p.steps[s as usize].start)))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            .expect("non-empty");
        Flaw::Abstract(i)
    }

    /// A threat to solve: those the network allows one way only are ordered
    /// in place, one it allows neither way ends the plan; else the last found.
    fn threat_flaw(&self, p: &mut Plan) -> Option<Flaw> {
        if !self.force_threats(p, true) {
            return Some(Flaw::Dead);
        }
        if p.threats.is_empty() {
            return self.select(p);
        }
        Some(Flaw::Threat(p.threats.len() - 1))
    }

    /// Whether an open link must wait: an unrefined abstract step that can
    /// come before it may make its literal true once refined (its subtasks
    /// are not in the plan yet, and linking to another producer now could
    /// lose the plan). Section 4.2.3: abstract steps hide the literals their
    /// methods create, hence abstract flaws in chronological order first.
    fn deferred(&self, p: &Plan, o: &Open) -> bool {
        if p.abstracts.is_empty() {
            return false;
        }
        let pred = self.task.g.atoms.pred(atom_of(o.lit));
        p.abstracts.iter().any(|&a| {
            let st = p.steps[a as usize];
            let Kind::Op(op) = st.kind else { return false };
            // A HiPOP abstract action is used through what it declares, like
            // an elementary action (section 4.1): a predicate its effects
            // name is not waited for. What it does not declare (everything
            // for an HDDL task) only its methods tell.
            if self.task.ops[op as usize].effs.iter().any(|e| self.task.g.atoms.pred(atom_of(e.lit)) == pred)
            {
                return false;
            }
            a != o.step
                && !p.descends(o.step, a)
                && !p.stn.before(o.need, st.start)
                && self.h.may_add(op, o.lit)
        })
    }

    /// Whether refining step `s` with method `m` only goes round a loop: a
    /// subtask of `m` is the ground task of `s` or of one of its ancestors
    /// (same task, same arguments), and no method on the way from that task
    /// down (`m` included) adds an action that changes the state (a pure
    /// loop), or the
    /// repeat goes through other tasks and has arguments (a cycle:
    /// `get-to truck1 city2` again below `get-to truck1 city1` below itself
    /// means driving back to where the truck was). A task that recurses
    /// into itself directly through actions (`S → t S y`, PCP's;
    /// `remove-all r → remove t r, remove-all r`, any "repeat until done"
    /// task) makes progress and is kept.
    fn only_loops(&self, p: &Plan, s: u32, m: u32) -> bool {
        // A method makes progress when one of its actions changes the state:
        // deletes something or adds what it does not need (`drive l l` on a
        // road from a place to itself does not).
        let changes = |op: &super::task::Op<'_>| {
            op.effs.iter().any(|e| is_neg(e.lit) || !op.conds.iter().any(|c| c.lit == e.lit))
        };
        let primitive = |m: u32| {
            self.task.methods[m as usize].subtasks.iter().any(|&(_, op)| {
                let op = &self.task.ops[op as usize];
                !op.is_abstract && changes(op)
            })
        };
        // `s` and its ancestors, each with whether an action that changes
        // the state was added on the way down from it to `m`'s subtasks.
        let mut above = vec![(s, primitive(m))];
        while let Some(parent) = p.steps[above[above.len() - 1].0 as usize].parent {
            let progress = above[above.len() - 1].1 || p.steps[parent as usize].method.is_some_and(primitive);
            above.push((parent, progress));
        }
        self.task.methods[m as usize].subtasks.iter().any(|&(_, sub)| {
            // The nearest step above (or `s` itself) with the same ground task decides.
            above.iter().find(|&&(cur, _)| p.op_of(cur) == Some(sub)).is_some_and(|&(cur, progress)| {
                let through_others = cur != s && !self.task.ops[sub as usize].args.is_empty();
                !progress || through_others
            })
        })
    }

    fn costliest(&self, p: &Plan, it: impl Iterator<Item = usize>) -> usize {
        let mut best: Option<(usize, f64)> = None;
        for i in it {
            let c = self.h.lit_cost(p.open[i].lit);
            if best.is_none_or(|(_, b)| c > b) {
                best = Some((i, c));
            }
        }
        best.map_or(0, |(i, _)| i)
    }

    /// Two interfering happenings at the same time in the earliest
    /// schedule: VAL groups them into one happening and rejects the plan.
    fn mutex(&self, p: &Plan) -> Option<Flaw> {
        // (time, time point, step) of every happening of a primitive step or timed literal.
        let mut events: Vec<(f64, Tp, u32)> = Vec::new();
        for (s, step) in p.steps.iter().enumerate() {
            let prim = match step.kind {
                Kind::Til(_) => true,
                k => self.elementary(k),
            };
            if !prim {
                continue;
            }
            events.push((p.stn.est(step.start), step.start, s as u32));
            if step.end != step.start {
                events.push((p.stn.est(step.end), step.end, s as u32));
            }
        }
        events.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (i, a) in events.iter().enumerate() {
            for b in &events[i + 1..] {
                if b.0 - a.0 > EPS * 0.5 {
                    break;
                }
                if a.2 == b.2 || p.stn.before(a.1, b.1) && b.0 - a.0 >= EPS - 1e-9 {
                    continue;
                }
                if self.interfere(p, a.1, a.2, b.1, b.2) {
                    return Some(Flaw::Mutex(a.1, b.1));
                }
            }
        }
        None
    }

    /// What a happening reads and writes, by atom.
    fn touched(&self, p: &Plan, tp: Tp, s: u32) -> (Vec<u32>, Vec<u32>) {
        let (mut reads, mut writes) = (Vec::new(), Vec::new());
        let step = p.steps[s as usize];
        for (l, t) in p.effects(self.task, s) {
            if t == tp {
                writes.push(atom_of(l));
            }
        }
        if let Kind::Op(o) = step.kind {
            for c in &self.task.ops[o as usize].conds {
                if step.tp(c.at) == tp || step.tp(c.until) == tp {
                    reads.push(atom_of(c.lit));
                }
            }
        }
        (reads, writes)
    }

    fn interfere(&self, p: &Plan, a: Tp, sa: u32, b: Tp, sb: u32) -> bool {
        let (ra, wa) = self.touched(p, a, sa);
        let (rb, wb) = self.touched(p, b, sb);
        wa.iter().any(|x| rb.contains(x) || wb.contains(x)) || wb.iter().any(|x| ra.contains(x))
    }

    /// The two ways to solve a threat: the threatening happening (or
    /// abstract step) before the producer, or after the link's protection.
    fn threat_orders(&self, p: &Plan, t: &Threat) -> [(Tp, Tp); 2] {
        let link = p.links[t.link as usize];
        let step = p.steps[t.step as usize];
        match t.kind {
            ThreatKind::Delete(tp) | ThreatKind::Position(tp) => [(tp, link.from_tp), (link.until, tp)],
            ThreatKind::Conflict => [(step.end, link.from_tp), (link.until, step.start)],
        }
    }

    /// The children of a plan for its chosen flaw.
    fn resolvers(&self, p: &Plan, flaw: Flaw, out: &mut Vec<Plan>) {
        match flaw {
            Flaw::Threat(i) => {
                let t: Threat = p.threats[i];
                for (a, b) in self.threat_orders(p, &t) {
                    let mut c = p.clone();
                    std::rc::Rc::make_mut(&mut c.threats).remove(i);
                    if c.stn.add(a, b, EPS) {
                        out.push(c);
                    }
                }
            }
            Flaw::Open(i) => self.open_resolvers(p, i, out),
            Flaw::Abstract(i) => {
                let s = p.abstracts[i];
                let Kind::Op(op) = p.steps[s as usize].kind else { return };
                for &m in &self.task.ops[op as usize].methods {
                    if self.only_loops(p, s, m) {
                        self.loops.set(self.loops.get() + 1);
                        continue;
                    }
                    let mut c = p.clone();
                    std::rc::Rc::make_mut(&mut c.abstracts).remove(i);
                    if self.refine(&mut c, s, m) {
                        out.push(c);
                    }
                }
            }
            Flaw::Visit(b) => {
                if let Some(geo) = &self.geo {
                    geo.extend(self.task, self.h, p, &b, out);
                }
            }
            Flaw::Late(til) => {
                for step in p.steps.iter() {
                    if self.elementary(step.kind) {
                        let mut c = p.clone();
                        if c.stn.add(til, step.end, EPS) {
                            out.push(c);
                        }
                    }
                }
                // Or a new step of 𝒜 after it (an elementary one; a move
                // only through an itinerary).
                for (op, o) in self.task.ops.iter().enumerate() {
                    let op = op as u32;
                    if !o.allowed
                        || o.dead
                        || o.is_abstract
                        || self.geo.is_some() && self.task.moves.contains_key(&op)
                    {
                        continue;
                    }
                    let mut c = p.clone();
                    let Some(s) = self.add_step(&mut c, op, None) else { continue };
                    let end = c.steps[s as usize].end;
                    if c.stn.add(til, end, EPS) {
                        out.push(c);
                    }
                }
            }
            Flaw::Mutex(a, b) => {
                for (x, y) in [(a, b), (b, a)] {
                    let mut c = p.clone();
                    if c.stn.add(x, y, EPS) {
                        out.push(c);
                    }
                }
            }
            Flaw::Dead => {}
        }
    }

    fn open_resolvers(&self, p: &Plan, i: usize, out: &mut Vec<Plan>) {
        let o = p.open[i];
        let mut base = p.clone();
        base.remove_open(i);
        // Causal links to existing steps. An abstract step's own effect is
        // its method's to achieve: only the steps it holds support it.
        // Another step would make a method that does not do what its
        // abstract action says; a new one, a second patrol inserted for
        // the first one's observations, at no cost in makespan when its
        // robot is idle (an endless plateau of equal f).
        let mut prod = Vec::new();
        self.producers(p, &o, &mut prod);
        if o.origin == OpenOrigin::AbstractEffect {
            prod.retain(|&(s, _)| s != o.step && p.descends(s, o.step));
        }
        for &(s, tp) in &prod {
            let mut c = base.clone();
            if c.add_link(self.task, s, tp, &o) {
                out.push(c);
            }
        }
        if o.origin == OpenOrigin::AbstractEffect {
            return;
        }
        // New steps from 𝒜 (a visit gets its moves from its itinerary).
        let position = self.is_visit(&o);
        if let Some(achievers) = self.task.achievers.get(&o.lit) {
            for &(op, at) in achievers {
                if position && self.task.moves.contains_key(&op) {
                    continue;
                }
                if self.config.bare && self.task.ops[op as usize].is_abstract {
                    continue;
                }
                let mut c = base.clone();
                let Some(s) = self.add_step(&mut c, op, None) else { continue };
                let tp = c.steps[s as usize].tp(at);
                if c.add_link(self.task, s, tp, &o) {
                    out.push(c);
                }
            }
        }
    }

    /// Refines abstract step `s` with method instance `m`: its subtasks as
    /// children within the step, the method's orderings, its precondition,
    /// and the step's own effects as open links its subtasks must achieve.
    fn refine(&self, p: &mut Plan, s: u32, m: u32) -> bool {
        let method = &self.task.methods[m as usize];
        if let Some(st) = p.steps.get_mut(s as usize) {
            st.method = Some(m);
        }
        let mut ids = Vec::with_capacity(method.subtasks.len());
        for &(_, op) in &method.subtasks {
            match self.add_step(p, op, Some(s)) {
                Some(id) => ids.push(id),
                None => return false,
            }
        }
        for o in &method.orders {
            let a = p.steps[ids[o.from.0] as usize].tp(o.from.1);
            let b = p.steps[ids[o.to.0] as usize].tp(o.to.1);
            if !p.stn.add(a, b, if o.strict { EPS } else { 0.0 }) {
                return false;
            }
        }
        let step = p.steps[s as usize];
        for (ci, c) in method.pre.iter().enumerate() {
            let o = Open {
                step: s,
                lit: c.lit,
                need: step.start,
                until: step.start,
                cond: u32::MAX,
                origin: OpenOrigin::MethodPre(m, ci as u32),
                after_start: false,
            };
            // A position the step's itinerary already brought its member
            // to: the same causal link, or the method does not apply.
            let linked = match self.geo.as_ref().and_then(|_| Geo::position(self.task, c.lit)) {
                Some((g, _)) => p.links.iter().copied().find(|l| {
                    l.to == s
                        && l.need == step.start
                        && Geo::position(self.task, l.lit).is_some_and(|(g2, _)| g2 == g)
                }),
                None => None,
            };
            if let Some(l) = linked {
                if !(l.lit == c.lit && p.add_link(self.task, l.from, l.from_tp, &o)) {
                    return false;
                }
                continue;
            }
            if !self.add_open(p, o) {
                return false;
            }
        }
        let Kind::Op(op) = step.kind else { return true };
        for e in &self.task.ops[op as usize].effs {
            let tp = step.tp(e.at);
            let o = Open {
                step: s,
                lit: e.lit,
                need: tp,
                until: tp,
                cond: u32::MAX,
                origin: OpenOrigin::AbstractEffect,
                after_start: false,
            };
            if !self.add_open(p, o) {
                return false;
            }
        }
        true
    }

    /// `g`, `h` and the effort of a plan about to enter the open list,
    /// after its threats with one ordering left are solved; `None` when a
    /// threat has none (the plan is dead).
    fn score(&self, plan: &mut Plan) -> Option<(f64, f64, f64)> {
        let penalty = self.settle(plan)?;
        let (h, effort) = self.estimate(plan);
        let (busiest, total) = self.work(plan);
        let g = plan.makespan().max(busiest) + penalty + STEP_COST * total;
        Some((g, h, effort))
    }

    /// Whether a flaw belongs to the completion of a plan: what is left
    /// once every step that supports a goal or a condition is chosen
    /// (itineraries, refinements, the delayed threats).
    fn completes(flaw: &Flaw) -> bool {
        !matches!(flaw, Flaw::Open(_))
    }

    /// The children of a plan for a flaw, scored: those a threat left
    /// without ordering are dropped (`dead` gets them, for reports).
    fn expand(&self, p: &Plan, flaw: Flaw, stats: &mut Stats, dead: &mut dyn FnMut(&Plan)) -> Vec<Scored> {
        let linking = matches!(flaw, Flaw::Open(_));
        let mut children = Vec::new();
        self.resolvers(p, flaw, &mut children);
        let mut out = Vec::with_capacity(children.len());
        for mut c in children {
            let added = if linking { c.steps.len() - p.steps.len() } else { 0 };
            match self.score(&mut c) {
                Some((g, h, effort)) => out.push(Scored { f: g + h, effort, added, plan: c }),
                None => dead(&c),
            }
        }
        stats.generated += out.len() as u64;
        out
    }

    /// Greedy completion: a depth-first descent from a plan's children (in
    /// [`Scored::probe_order`]) that backtracks, within `budget` expansions.
    /// A plan it finds has no flaw, like one A* would return.
    fn probe(
        &self,
        first: Vec<Plan>,
        budget: u64,
        stats: &mut Stats,
        deadline: &dyn Fn() -> bool,
    ) -> Option<Plan> {
        let mut stack: Vec<std::vec::IntoIter<Plan>> = vec![first.into_iter()];
        let mut spent = 0u64;
        loop {
            let mut p = loop {
                let top = stack.last_mut()?;
                if let Some(n) = top.next() {
                    break n;
                }
                stack.pop();
            };
            spent += 1;
            stats.expanded += 1;
            if spent > budget || (spent.is_multiple_of(32) && deadline()) {
                return None;
            }
            let Some(flaw) = self.select(&mut p) else { return Some(p) };
            let mut scored = self.expand(&p, flaw, stats, &mut |_| {});
            scored.sort_by(Scored::probe_order);
            stack.push(scored.into_iter().map(|x| x.plan).collect::<Vec<_>>().into_iter());
        }
    }

    /// Runs the search.
    pub fn run(
        &self,
        limits: &PlannerLimits,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&Progress),
        stats: &mut Stats,
        best: &mut Option<Plan>,
    ) -> End2 {
        let started = Instant::now();
        let roots = self.initial();
        let mut heap = BinaryHeap::new();
        let mut id = 0u64;
        // The most advanced plan: the fewest open links and abstract flaws
        // (its threats are what stopped it, if anything).
        let mut best_effort = usize::MAX;
        let keep_best = |plan: &Plan, best: &mut Option<Plan>, best_effort: &mut usize| {
            let advance = plan.open.len() + plan.abstracts.len();
            if advance <= *best_effort {
                *best_effort = advance;
                *best = Some(plan.clone());
            }
        };
        let probing = self.config.lookahead;
        for mut root in roots {
            match self.score(&mut root) {
                Some((g, h, effort)) => {
                    id += 1;
                    stats.generated += 1;
                    let size = root.steps.len();
                    heap.push(Node { f: g + h, effort, size, id, probed: false, plan: root });
                }
                None => keep_best(&root, best, &mut best_effort),
            }
        }
        let time_up = || limits.time.is_some_and(|t| started.elapsed() >= t) || cancel();
        let mut last_report = Instant::now();
        let mut next_milestone: u64 = 1024;
        while let Some(node) = heap.pop() {
            let mut plan = node.plan;
            stats.expanded += 1;
            stats.open = heap.len();
            stats.peak_open = stats.peak_open.max(heap.len());
            keep_best(&plan, best, &mut best_effort);
            if stats.expanded.is_multiple_of(32) {
                let elapsed = started.elapsed();
                stats.elapsed = elapsed;
                if cancel() {
                    return End2::Limit(LimitKind::Cancelled);
                }
                if limits.time.is_some_and(|t| elapsed >= t) {
                    return End2::Limit(LimitKind::Time);
                }
                if last_report.elapsed().as_millis() >= 100 {
                    last_report = Instant::now();
                    progress(&Progress {
                        expanded: stats.expanded,
                        open: heap.len(),
                        best_f: node.f,
                        elapsed,
                    });
                }
            }
            if limits.nodes.is_some_and(|n| stats.expanded > n) {
                stats.elapsed = started.elapsed();
                return End2::Limit(LimitKind::Nodes);
            }
            let over = match (limits.memory, limits.memory_in_use) {
                // Measured: often enough (a plan is a few kilobytes to a few
                // hundred; 32 expansions cannot overshoot by much).
                (Some(m), Some(in_use)) => stats.expanded.is_multiple_of(32) && in_use() > m,
                (Some(m), None) => heap.len().saturating_mul(approx_plan_bytes(&plan)) > m,
                (None, _) => false,
            };
            if over {
                stats.elapsed = started.elapsed();
                return End2::Limit(LimitKind::Memory);
            }
            let Some(flaw) = self.select(&mut plan) else {
                stats.elapsed = started.elapsed();
                return End2::Solved(plan);
            };
            let completes = Self::completes(&flaw);
            let scored = self.expand(&plan, flaw, stats, &mut |c| keep_best(c, best, &mut best_effort));
            // A plan entering its completion: first a greedy descent from
            // its children. And when A* has spent 1024, 2048, 4096…
            // expansions, the plan it is at gets one too, whatever is left.
            let mut probed = node.probed;
            let milestone = stats.expanded >= next_milestone;
            if milestone {
                next_milestone *= 2;
            }
            if probing && (!probed && completes || milestone) {
                probed |= completes;
                let remaining = plan.open.len() as u64
                    + plan.threats.len() as u64
                    + plan
                        .abstracts
                        .iter()
                        .filter_map(|&a| plan.op_of(a))
                        .map(|o| self.h.refine_effort[o as usize].min(1e6) as u64)
                        .sum::<u64>();
                let budget = 256 + 4 * remaining;
                let mut first: Vec<&Scored> = scored.iter().collect();
                first.sort_by(|a, b| Scored::probe_order(a, b));
                let first = first.into_iter().map(|s| s.plan.clone()).collect();
                if let Some(found) = self.probe(first, budget, stats, &time_up) {
                    stats.elapsed = started.elapsed();
                    return End2::Solved(found);
                }
            }
            for c in scored {
                id += 1;
                let size = c.plan.steps.len();
                heap.push(Node { f: c.f, effort: c.effort, size, id, probed, plan: c.plan });
            }
        }
        stats.elapsed = started.elapsed();
        stats.loops_skipped = self.loops.get();
        End2::Exhausted
    }
}

/// A child plan with its score.
struct Scored {
    f: f64,
    effort: f64,
    /// Steps it added for an open link.
    added: usize,
    plan: Plan,
}

impl Scored {
    /// The order a greedy descent tries children in: for an open link, a
    /// causal link to a step already there before a new step (reuse keeps
    /// a new step's conditions free in h, so a descent could otherwise add
    /// steps that need steps without end); then the lowest f, the effort.
    fn probe_order(a: &Scored, b: &Scored) -> Ordering {
        a.added.cmp(&b.added).then(a.f.total_cmp(&b.f)).then(a.effort.total_cmp(&b.effort))
    }
}

/// The effects of a plan's steps, by literal: built once per plan for its estimate.
struct EffectIndex {
    by_lit: rustc_hash::FxHashMap<Lit, Vec<Tp>>,
}

impl EffectIndex {
    fn new(task: &Task<'_>, p: &Plan) -> EffectIndex {
        let mut by_lit: rustc_hash::FxHashMap<Lit, Vec<Tp>> = rustc_hash::FxHashMap::default();
        for s in 0..p.steps.len() as u32 {
            for (l, tp) in p.effects(task, s) {
                by_lit.entry(l).or_default().push(tp);
            }
        }
        EffectIndex { by_lit }
    }

    fn of(&self, l: Lit) -> &[Tp] {
        self.by_lit.get(&l).map_or(&[], |v| v.as_slice())
    }
}

/// What a plan in the open list costs on its own beyond what it shares:
/// the chunks a child copies (steps, links, time points) and its flaw lists.
fn approx_plan_bytes(p: &Plan) -> usize {
    let spine = (p.steps.len() + p.links.len() + 3 * p.stn.len()) / super::pvec::CHUNK * 8;
    spine + 4 * 1024 + (p.open.len() + p.threats.len()) * 32
}
