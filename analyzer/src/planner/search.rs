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
use super::plan::{GOAL, INIT, Kind, Open, OpenOrigin, Plan, Threat, ThreatKind};
use super::stn::{EPS, ORIGIN, Tp};
use super::task::{End, Lit, Task, atom_of, is_neg};
use super::{Config, FlawOrder, LimitKind, Motion, PlanHeuristic, PlannerLimits, Progress, Stats};

/// A plan in the open list.
struct Node {
    f: f64,
    effort: f64,
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
        other.f.total_cmp(&self.f).then(other.effort.total_cmp(&self.effort)).then(self.id.cmp(&other.id))
    }
}

/// The flaw chosen in a plan.
enum Flaw {
    Threat(usize),
    Open(usize),
    Abstract(usize),
    Mutex(Tp, Tp),
    /// A position link waiting for an abstract step that may move its
    /// member and cannot overlap it: before it or after it.
    Order(usize, u32),
}

/// What the itinerary stage of flaw selection found.
enum OrderChoice {
    /// An ordering to choose, both ways consistent.
    Choose(Flaw),
    /// Orderings with one consistent way were added: select again.
    Forced,
    /// An ordering with no consistent way: the plan is dead.
    Dead(Flaw),
}

pub struct Search<'a, 'db> {
    pub task: &'a Task<'db>,
    pub h: &'a Heuristic,
    pub config: &'a Config,
    pub has_motion: bool,
    /// Whether some operator names its agents (the load estimate).
    pub has_agents: bool,
    /// Per abstract operator, the motion groups (members of a position
    /// family with move actions) its refinements may move (sorted).
    moves_groups: Vec<Vec<u32>>,
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
        let has_agents = task.ops.iter().any(|o| !o.agents.is_empty());
        let moves_groups = task
            .ops
            .iter()
            .enumerate()
            .map(|(op, o)| {
                if !has_motion || !o.is_abstract {
                    return Vec::new();
                }
                (0..task.motion.len() as u32)
                    .filter(|&g| {
                        task.motion[g as usize].as_ref().is_some_and(|m| {
                            m.positions.iter().any(|&a| h.may_add(op as u32, super::task::lit(a, false)))
                        })
                    })
                    .collect()
            })
            .collect();
        Search { task, h, config, has_motion, has_agents, moves_groups, loops: Default::default() }
    }

    /// The initial plans: init, goal, timed literals, the goal's open links,
    /// and the `:htn` tasks with their orderings, one plan per ground
    /// initial task network (the bindings of the `:htn` parameters).
    pub fn initial(&self) -> Vec<Plan> {
        let Some(mut p) = Plan::initial(self.task) else { return Vec::new() };
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
            if !p.add_open(self.task, o) {
                return Vec::new();
            }
        }
        let Some(nets) = &self.task.htn else { return vec![p] };
        nets.iter()
            .filter_map(|net| {
                let mut p = p.clone();
                let mut ids = Vec::new();
                for &(op, _) in &net.tasks {
                    ids.push(p.add_step(self.task, self.h, op, None)?);
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

    fn is_position_link(&self, l: Lit) -> bool {
        self.has_motion && !is_neg(l) && self.task.motion_of(atom_of(l)).is_some()
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
            let (c, e) = self.open_cost(p, o, &index);
            h += c;
            effort += e;
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
        if !is_neg(o.lit)
            && self.config.motion != Motion::Off
            && let Some((m, group, to)) = self.task.motion_of(atom_of(o.lit))
        {
            if self.config.motion == Motion::Ncm {
                return (0.0, 1.0);
            }
            // Equation 2: the shortest chain of moves from a last known position.
            let mut best = f64::INFINITY;
            let mut any = false;
            for &(from, tp) in index.positions(group) {
                if tp == o.need || p.stn.before(o.need, tp) {
                    continue;
                }
                any = true;
                best = best.min(m.dist(from as usize, to as usize));
            }
            if let Some(&a) = m.positions.iter().find(|&&a| self.task.init[a as usize])
                && let Some((_, from)) = self.task.family[a as usize]
            {
                any = true;
                best = best.min(m.dist(from as usize, to as usize));
            }
            if any {
                return (best.min(1e6), if best == 0.0 { 0.0 } else { 1.0 });
            }
            return base;
        }
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
                let deleters = index.of(o.lit ^ 1);
                let ordered =
                    |e: Tp| e == ORIGIN || deleters.iter().all(|&d| p.stn.before(d, e) || p.stn.before(e, d));
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

    /// Solves in place the threats left with one consistent resolver, and
    /// looks ahead at the others: `None` when a threat has no resolver left
    /// (the plan is dead), else the least increase of the makespan that the
    /// worst of the remaining threats forces (both of its orderings are
    /// probed on the network).
    fn settle(&self, p: &mut Plan) -> Option<f64> {
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
                let [(a1, b1), (a2, b2)] = self.threat_orders(p, &t);
                let ok1 = !p.stn.before(b1, a1) && b1 != a1;
                let ok2 = !p.stn.before(b2, a2) && b2 != a2;
                let (a, b) = match (ok1, ok2) {
                    (false, false) => return None,
                    (true, true) => continue,
                    (true, false) => (a1, b1),
                    (false, true) => (a2, b2),
                };
                if !p.stn.add(a, b, EPS) {
                    return None;
                }
                std::rc::Rc::make_mut(&mut p.threats).remove(i);
                forced = true;
            }
            if !forced {
                break;
            }
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

    /// The busiest agent's work: the sum of the durations of the steps it
    /// takes part in (`:agent`), an abstract step with a duration counting
    /// for the subtasks it holds. A robot of a mission does one thing at a
    /// time, so the plan cannot be shorter; it is what makes the search
    /// share the work among the robots instead of piling it on one while
    /// the makespan of the partial plan does not show it yet.
    fn load(&self, p: &Plan) -> f64 {
        if !self.has_agents {
            return 0.0;
        }
        let mut load: rustc_hash::FxHashMap<u32, f64> = rustc_hash::FxHashMap::default();
        for s in p.steps.iter() {
            let Kind::Op(o) = s.kind else { continue };
            let op = &self.task.ops[o as usize];
            if op.agents.is_empty() || op.is_abstract && op.duration.is_none() {
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
            for &a in &op.agents {
                *load.entry(a).or_insert(0.0) += d;
            }
        }
        load.values().copied().fold(0.0, f64::max)
    }

    /// Picks the flaw to solve, dropping threats that orderings solved since.
    fn select(&self, p: &mut Plan) -> Option<Flaw> {
        // Threats: those with one consistent resolver are solved in place
        // (no choice to make), one with none kills the plan, and among the
        // others the last found is chosen.
        let mut i = p.threats.len();
        let mut choice = None;
        while i > 0 {
            i -= 1;
            let t = p.threats[i];
            if !p.still_threat(self.task, &t) {
                std::rc::Rc::make_mut(&mut p.threats).remove(i);
                choice = choice.map(|c: usize| if c > i { c - 1 } else { c });
                continue;
            }
            let [(a1, b1), (a2, b2)] = self.threat_orders(p, &t);
            let mut first = p.stn.clone();
            let ok1 = first.add(a1, b1, EPS);
            let mut second = p.stn.clone();
            let ok2 = second.add(a2, b2, EPS);
            match (ok1, ok2) {
                (false, false) => return Some(Flaw::Threat(i)),
                (true, false) | (false, true) => {
                    p.stn = if ok1 { first } else { second };
                    std::rc::Rc::make_mut(&mut p.threats).remove(i);
                    choice = choice.map(|c: usize| if c > i { c - 1 } else { c });
                }
                (true, true) => {
                    if choice.is_none() {
                        choice = Some(i);
                    }
                }
            }
        }
        if let Some(c) = choice {
            // Orderings forced since may have solved it.
            if p.still_threat(self.task, &p.threats[c]) {
                return Some(Flaw::Threat(c));
            }
            std::rc::Rc::make_mut(&mut p.threats).remove(c);
            return self.select(p);
        }
        // Open links that nothing can support yet while an unrefined
        // abstract step that may come before them could (its subtasks are
        // not in the plan yet) wait for the abstract flaws.
        let ready: Vec<usize> = (0..p.open.len()).filter(|&i| !self.deferred(p, &p.open[i])).collect();
        // Then where each robot's itinerary goes: a position link waiting
        // for an abstract step it may come before or after (both are tried).
        if ready.iter().all(|&i| self.is_position_link(p.open[i].lit)) {
            match self.order_flaw(p, &ready) {
                Some(OrderChoice::Choose(f) | OrderChoice::Dead(f)) => return Some(f),
                // Orderings forced since may have made links ready.
                Some(OrderChoice::Forced) => return self.select(p),
                None => {}
            }
        }
        if !ready.is_empty() {
            let positions_last = self.has_motion;
            let candidates: Vec<usize> = {
                let non_pos: Vec<usize> = ready
                    .iter()
                    .copied()
                    .filter(|&i| !(positions_last && self.is_position_link(p.open[i].lit)))
                    .collect();
                if non_pos.is_empty() { ready } else { non_pos }
            };
            if positions_last && self.is_position_link(p.open[candidates[0]].lit) {
                // Positions in chronological order: a robot's itinerary is
                // built from its first destination on, each chain of moves
                // starting where the one before ended.
                let need = |i: usize| p.stn.est(p.open[i].need);
                let first = candidates.iter().map(|&i| need(i)).fold(f64::INFINITY, f64::min);
                return Some(Flaw::Open(
                    self.costliest(p, candidates.iter().copied().filter(|&i| need(i) <= first)),
                ));
            }
            let pick = match self.config.flaws {
                FlawOrder::ThreatFirst => *candidates.last().expect("non-empty"),
                FlawOrder::Sorted => self.costliest(p, candidates.iter().copied()),
                FlawOrder::Local => {
                    let newest = candidates
                        .iter()
                        .map(|&i| p.steps[p.open[i].step as usize].born)
                        .max()
                        .expect("non-empty");
                    self.costliest(
                        p,
                        candidates
                            .iter()
                            .copied()
                            .filter(|&i| p.steps[p.open[i].step as usize].born == newest),
                    )
                }
            };
            return Some(Flaw::Open(pick));
        }
        if p.abstracts.is_empty() && !p.open.is_empty() {
            // Every open link is unsupported and no abstract step is left.
            return Some(Flaw::Open(0));
        }
        if !p.abstracts.is_empty() {
            let (i, _) = p
                .abstracts
                .iter()
                .enumerate()
                .map(|(i, &s)| (i, p.stn.est(p.steps[s as usize].start)))
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
                .expect("non-empty");
            return Some(Flaw::Abstract(i));
        }
        self.mutex(p)
    }

    /// A position link that waits for an abstract step it is not ordered
    /// with, when that step cannot overlap the link (its conflicts name the
    /// position): whether the link comes before or after the step is a
    /// choice, made before any chain of moves is (a meeting in a window
    /// must get its place in the robot's itinerary before the patrol that
    /// the robot could do first takes its start from the initial position).
    fn order_flaw(&self, p: &mut Plan, ready: &[usize]) -> Option<OrderChoice> {
        if !self.has_motion || p.abstracts.is_empty() {
            return None;
        }
        let mut best: Option<(f64, Flaw)> = None;
        let mut forced = false;
        for i in 0..p.open.len() {
            let o = p.open[i];
            if !self.is_position_link(o.lit) || ready.contains(&i) {
                continue;
            }
            for k in 0..p.abstracts.len() {
                let a = p.abstracts[k];
                let st = p.steps[a as usize];
                let Kind::Op(op) = st.kind else { continue };
                let op = &self.task.ops[op as usize];
                if a == o.step
                    || p.descends(o.step, a)
                    || p.stn.before(o.need, st.start)
                    || p.stn.before(st.end, o.need)
                    || !op.conflicts_with(self.task.g, atom_of(o.lit))
                {
                    continue;
                }
                // One way only (a time window, say): taken in place, no choice.
                let mut first = p.stn.clone();
                let ok1 = first.add(o.until, st.start, EPS);
                let mut second = p.stn.clone();
                let ok2 = second.add(st.end, o.need, EPS);
                match (ok1, ok2) {
                    (false, false) => return Some(OrderChoice::Dead(Flaw::Order(i, a))),
                    (true, false) => (p.stn, forced) = (first, true),
                    (false, true) => (p.stn, forced) = (second, true),
                    (true, true) => {
                        let t = p.stn.est(o.need);
                        if best.as_ref().is_none_or(|(b, _)| t < *b) {
                            best = Some((t, Flaw::Order(i, a)));
                        }
                    }
                }
            }
        }
        if forced {
            return Some(OrderChoice::Forced);
        }
        best.map(|(_, f)| OrderChoice::Choose(f))
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
        // The link's member, when it is a position (see below).
        let group = if self.is_position_link(o.lit) {
            self.task.motion_of(atom_of(o.lit)).map(|(_, g, _)| g)
        } else {
            None
        };
        p.abstracts.iter().any(|&a| {
            let st = p.steps[a as usize];
            let Kind::Op(op) = st.kind else { return false };
            // A HiPOP abstract action is used through what it declares, like
            // an elementary action (section 4.1): a predicate its effects
            // name is not waited for. What it does not declare (a robot's
            // position along a round trip, everything for an HDDL task) only
            // its methods tell.
            if self.task.ops[op as usize].effs.iter().any(|e| self.task.g.atoms.pred(atom_of(e.lit)) == pred)
            {
                return false;
            }
            // A position also waits for an abstract step that may move its
            // member elsewhere: where that step leaves it is where the next
            // chain of moves starts (the last known position, 4.3.1).
            let may = self.h.may_add(op, o.lit)
                || group.is_some_and(|g| self.moves_groups[op as usize].binary_search(&g).is_ok());
            a != o.step && !p.descends(o.step, a) && !p.stn.before(o.need, st.start) && may
        })
    }

    /// Whether refining step `s` with method `m` only goes round a loop: a
    /// subtask of `m` is the ground task of `s` or of one of its ancestors
    /// (same task, same arguments), and either that task has arguments (a
    /// cycle: `get-to truck1 city2` again below itself means driving back to
    /// where the truck was), or no method on the way from that ancestor down
    /// (`m` included) adds a primitive step (a pure loop). A task without
    /// arguments that recurses through actions (`S → t S y`, PCP's, any
    /// "repeat until done" task) makes progress and is kept.
    fn only_loops(&self, p: &Plan, s: u32, m: u32) -> bool {
        let primitive = |m: u32| {
            self.task.methods[m as usize]
                .subtasks
                .iter()
                .any(|&(_, op)| !self.task.ops[op as usize].is_abstract)
        };
        let subtasks = &self.task.methods[m as usize].subtasks;
        let mut progress = primitive(m);
        let mut cur = s;
        loop {
            if let Some(op) = p.op_of(cur)
                && subtasks.iter().any(|&(_, sub)| sub == op)
                && (!progress || !self.task.ops[op as usize].args.is_empty())
            {
                return true;
            }
            match p.steps[cur as usize].parent {
                Some(parent) => {
                    progress |= p.steps[parent as usize].method.is_some_and(primitive);
                    cur = parent;
                }
                None => return false,
            }
        }
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
                Kind::Op(o) => !self.task.ops[o as usize].is_abstract,
                Kind::Til(_) => true,
                _ => false,
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
            Flaw::Order(i, a) => {
                let (o, st) = (p.open[i], p.steps[a as usize]);
                for (x, y) in [(o.until, st.start), (st.end, o.need)] {
                    let mut c = p.clone();
                    if c.stn.add(x, y, EPS) {
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
        // Chains of moves from the last known positions (4.3.2).
        let position = !is_neg(o.lit) && self.has_motion && self.task.motion_of(atom_of(o.lit)).is_some();
        if position {
            self.move_chains(&base, &o, out);
        }
        // New steps from 𝒜.
        if let Some(achievers) = self.task.achievers.get(&o.lit) {
            for &(op, at) in achievers {
                if position && self.task.moves.contains_key(&op) {
                    continue;
                }
                if self.config.bare && self.task.ops[op as usize].is_abstract {
                    continue;
                }
                let mut c = base.clone();
                let Some(s) = c.add_step(self.task, self.h, op, None) else { continue };
                let tp = c.steps[s as usize].tp(at);
                if c.add_link(self.task, s, tp, &o) {
                    out.push(c);
                }
            }
        }
    }

    /// Supports a position by the shortest chain of moves from each last
    /// known position of its member.
    fn move_chains(&self, base: &Plan, o: &Open, out: &mut Vec<Plan>) {
        let Some((m, group, to)) = self.task.motion_of(atom_of(o.lit)) else { return };
        // Last known positions: producers of another position of the group.
        let mut starts: Vec<(u32, Tp, u32)> = Vec::new();
        let mut prod = Vec::new();
        for (pos, &atom) in m.positions.iter().enumerate() {
            if pos as u32 == to {
                continue;
            }
            let probe = Open { lit: super::task::lit(atom, false), ..*o };
            self.producers(base, &probe, &mut prod);
            starts.extend(prod.iter().map(|&(s, tp)| (s, tp, pos as u32)));
        }
        let _ = group;
        for (s, tp, from) in starts {
            let Some(path) = m.path(from, to, |mv| self.task.moves[&mv].2) else { continue };
            let mut c = base.clone();
            let mut prev =
                (s, tp, self.task.motion_of(atom_of(probe_lit(m, from))).map(|_| probe_lit(m, from)));
            let mut ok = true;
            for (k, &mv) in path.iter().enumerate() {
                let Some(ns) = c.add_step(self.task, self.h, mv, None) else {
                    ok = false;
                    break;
                };
                // Link the move's from-position to the previous producer.
                let from_lit = probe_lit(m, self.task.moves[&mv].1);
                let Some(idx) = c.open.iter().rposition(|x| x.step == ns && x.lit == from_lit) else {
                    ok = false;
                    break;
                };
                let open = c.remove_open(idx);
                if !c.add_link(self.task, prev.0, prev.1, &open) {
                    ok = false;
                    break;
                }
                let end = c.steps[ns as usize].end;
                prev = (ns, end, None);
                if k + 1 == path.len() && !c.add_link(self.task, ns, end, o) {
                    ok = false;
                }
            }
            if ok && !path.is_empty() {
                out.push(c);
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
            match p.add_step(self.task, self.h, op, Some(s)) {
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
            if !p.add_open(self.task, o) {
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
            if !p.add_open(self.task, o) {
                return false;
            }
        }
        let _ = End::Start;
        true
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
        let mut best_effort = f64::INFINITY;
        let mut keep_best = |plan: &Plan, best: &mut Option<Plan>| {
            let advance = (plan.open.len() + plan.abstracts.len()) as f64;
            if advance <= best_effort {
                best_effort = advance;
                *best = Some(plan.clone());
            }
        };
        let push = |heap: &mut BinaryHeap<Node>,
                    mut plan: Plan,
                    id: &mut u64,
                    stats: &mut Stats,
                    best: &mut Option<Plan>,
                    keep_best: &mut dyn FnMut(&Plan, &mut Option<Plan>)| {
            // Threats with one resolver left are solved now; a plan with a
            // threat that has none is dropped before it costs anything (it
            // may still be the most advanced one, to report that threat).
            let Some(penalty) = self.settle(&mut plan) else {
                keep_best(&plan, best);
                return;
            };
            let (h, effort) = self.estimate(&plan);
            let f = plan.makespan().max(self.load(&plan)) + penalty + h;
            *id += 1;
            stats.generated += 1;
            heap.push(Node { f, effort, id: *id, plan });
        };
        for root in roots {
            push(&mut heap, root, &mut id, stats, best, &mut keep_best);
        }
        let mut last_report = Instant::now();
        let mut children = Vec::new();
        while let Some(node) = heap.pop() {
            let mut plan = node.plan;
            stats.expanded += 1;
            stats.open = heap.len();
            stats.peak_open = stats.peak_open.max(heap.len());
            keep_best(&plan, best);
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
            children.clear();
            self.resolvers(&plan, flaw, &mut children);
            for c in children.drain(..) {
                push(&mut heap, c, &mut id, stats, best, &mut keep_best);
            }
        }
        stats.elapsed = started.elapsed();
        stats.loops_skipped = self.loops.get();
        End2::Exhausted
    }
}

/// The effects of a plan's steps, by literal, and the positions its steps
/// reach, by family: built once per plan for its estimate.
struct EffectIndex {
    by_lit: rustc_hash::FxHashMap<Lit, Vec<Tp>>,
    /// Per motion group: (position, time point).
    positions: rustc_hash::FxHashMap<u32, Vec<(u32, Tp)>>,
}

impl EffectIndex {
    fn new(task: &Task<'_>, p: &Plan) -> EffectIndex {
        let mut by_lit: rustc_hash::FxHashMap<Lit, Vec<Tp>> = rustc_hash::FxHashMap::default();
        let mut positions: rustc_hash::FxHashMap<u32, Vec<(u32, Tp)>> = rustc_hash::FxHashMap::default();
        for s in 0..p.steps.len() as u32 {
            for (l, tp) in p.effects(task, s) {
                by_lit.entry(l).or_default().push(tp);
                if !is_neg(l)
                    && let Some((g, pos)) = task.family[atom_of(l) as usize]
                {
                    positions.entry(g).or_default().push((pos, tp));
                }
            }
        }
        EffectIndex { by_lit, positions }
    }

    fn of(&self, l: Lit) -> &[Tp] {
        self.by_lit.get(&l).map_or(&[], |v| v.as_slice())
    }

    fn positions(&self, group: u32) -> &[(u32, Tp)] {
        self.positions.get(&group).map_or(&[], |v| v.as_slice())
    }
}

fn probe_lit(m: &super::task::MotionGroup, pos: u32) -> Lit {
    super::task::lit(m.positions[pos as usize], false)
}

/// What a plan in the open list costs on its own beyond what it shares:
/// the chunks a child copies (steps, links, time points) and its flaw lists.
fn approx_plan_bytes(p: &Plan) -> usize {
    let spine = (p.steps.len() + p.links.len() + 3 * p.stn.len()) / super::pvec::CHUNK * 8;
    spine + 4 * 1024 + (p.open.len() + p.threats.len()) * 32
}
