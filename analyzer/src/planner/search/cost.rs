//! What a partial plan costs: `g` beyond the makespan (the delay its open
//! threats must cause, the busiest agent's work) and `h`, the estimates of
//! its open links (h_add and its `reuse`, `advance-reuse`, `motion` and
//! `ncm` variants, Equations 1–3 of the HiPOP paper) and of its abstract
//! flaws.

use super::super::plan::{INIT, Kind, Open, Plan};
use super::super::stn::{EPS, ORIGIN, Slacks, Tp};
use super::super::task::{Lit, Task};
use super::super::{Motion, PlanHeuristic};
use super::Search;

impl Search<'_, '_> {
    /// h of a plan, and the effort.
    pub(super) fn estimate(&self, p: &Plan) -> (f64, f64) {
        self.estimate_in(p, None)
    }

    /// [`Search::estimate`], with the front of a plan grown from its front.
    pub(super) fn estimate_in(&self, p: &Plan, view: Option<&super::front::View>) -> (f64, f64) {
        if let Some(view) = view {
            return self.front_estimate(p, view);
        }
        if self.at_front() {
            return self.front_estimate(p, &self.view(p));
        }
        let (mut h, mut effort) = (0.0, 0.0);
        let wanted = p.open.iter().filter(|o| !self.is_visit(o)).flat_map(|o| [o.lit, o.lit ^ 1]);
        let index = EffectIndex::new(self.task, p, wanted);
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

    pub(super) fn open_cost(&self, p: &Plan, o: &Open, index: &EffectIndex) -> (f64, f64) {
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
                // And none of them surely deleting it between the producer
                // and the need (the paper's words: "no other step removes
                // this literal after its creation"): a fuel level that a
                // flight leaves does not serve the flight after the next.
                // The deletions that are not at or after the need, each with
                // whether it is surely before the need, are read from the
                // network once per link, not once per producer (an
                // aircraft's fuel level has as many producers and deleters
                // as the aircraft has flights in the plan).
                let strict = self.task.g.tdg_methods.is_none();
                let producers = index.of(o.lit);
                let initially = self.task.holds_initially(o.lit) && o.step != INIT;
                if !initially && producers.is_empty() {
                    return base;
                }
                let deleters: smallvec::SmallVec<[(Tp, bool); 16]> = index
                    .of(o.lit ^ 1)
                    .iter()
                    .filter(|&&d| d != o.need && !p.stn.before(o.need, d))
                    .map(|&d| (d, p.stn.before(d, o.need)))
                    .collect();
                // On purely hierarchical problems, Equation 1 as it is: their
                // steps come from methods, and the weighted search follows
                // the decomposition's estimate (IPC 2020 Rover problem 6
                // went from 65,617 plans to no plan in 355,136 with the rule).
                // `d` surely deletes the literal between `e` and the need.
                let between = |e: Tp, d: Tp, before_need: bool| {
                    strict && before_need && d != e && (e == ORIGIN || p.stn.before(e, d))
                };
                // Every deleter ordered with `e`, none surely between.
                let ordered = |e: Tp| {
                    deleters.iter().all(|&(d, before_need)| {
                        if e == ORIGIN || d == e {
                            return !between(e, d, before_need);
                        }
                        if p.stn.before(e, d) { !(strict && before_need) } else { p.stn.before(d, e) }
                    })
                };
                let can_be_before = |e: Tp| e != o.need && !p.stn.before(o.need, e);
                if initially && ordered(ORIGIN) {
                    return (0.0, 0.0);
                }
                if producers.iter().any(|&e| can_be_before(e) && ordered(e)) {
                    return (0.0, 0.0);
                }
                if initially {
                    // A step surely uses up the initial value before the
                    // need (one fuel level of the initial state does not
                    // serve two flights in a row): free only if a step of
                    // the plan may still give it back in time, else it
                    // must be made true again.
                    if producers
                        .iter()
                        .any(|&e| can_be_before(e) && deleters.iter().all(|&(d, b)| !between(e, d, b)))
                    {
                        return (0.0, 0.0);
                    }
                    let l = o.lit as usize;
                    return (self.h.again_cost[l].min(1e6), self.h.again_effort[l].min(1e6));
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
    pub(super) fn settle(&self, p: &mut Plan) -> Option<f64> {
        if !self.force_threats(p, false) {
            return None;
        }
        if p.threats.is_empty() {
            return Some(0.0);
        }
        // Ordering `a` before `b` delays the goal by `d − slack(b)`, with
        // `d = est(a) + ε − est(b)`: a threat adds the lesser of its two
        // orderings' delays, and the penalty is the greatest. A threat with
        // an ordering that delays nothing (`d ≤ 0`) adds nothing, and a
        // slack is only needed below `d` less the penalty found so far:
        // the threats that may add most come first.
        let mut threats: Vec<([f64; 2], [Tp; 2])> = Vec::new();
        for t in p.threats.iter() {
            let [(a1, b1), (a2, b2)] = self.threat_orders(p, t);
            let d1 = p.stn.est(a1) + EPS - p.stn.est(b1);
            let d2 = p.stn.est(a2) + EPS - p.stn.est(b2);
            if d1 > 0.0 && d2 > 0.0 {
                threats.push(([d1, d2], [b1, b2]));
            }
        }
        threats.sort_by(|x, y| y.0[0].min(y.0[1]).total_cmp(&x.0[0].min(x.0[1])));
        let mut penalty: f64 = 0.0;
        let mut slacks = Slacks::new(&p.stn, p.goal_tp);
        for (d, b) in threats {
            if d[0].min(d[1]) <= penalty {
                break;
            }
            // The cheaper ordering first: the other is only needed if it
            // could delay more than the penalty.
            let (i, j) = if d[0] <= d[1] { (0, 1) } else { (1, 0) };
            let vi = d[i] - slacks.slack(b[i], d[i] - penalty);
            if vi <= penalty {
                continue;
            }
            let vj = d[j] - slacks.slack(b[j], d[j] - penalty);
            penalty = penalty.max(vi.min(vj));
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
    pub(super) fn work(&self, p: &Plan) -> (f64, f64) {
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
}

/// The effects of a plan's steps on the literals its estimate asks about:
/// built once per plan. (Every literal's would cost a child of a plan of
/// 600 steps thousands of entries for the few its open links need.)
pub(super) struct EffectIndex {
    by_lit: rustc_hash::FxHashMap<Lit, Vec<Tp>>,
}

impl EffectIndex {
    pub(super) fn new(task: &Task<'_>, p: &Plan, wanted: impl Iterator<Item = Lit>) -> EffectIndex {
        let mut by_lit: rustc_hash::FxHashMap<Lit, Vec<Tp>> = wanted.map(|l| (l, Vec::new())).collect();
        if by_lit.is_empty() {
            return EffectIndex { by_lit };
        }
        for s in 0..p.steps.len() as u32 {
            for (l, tp) in p.effects(task, s) {
                if let Some(v) = by_lit.get_mut(&l) {
                    v.push(tp);
                }
            }
        }
        EffectIndex { by_lit }
    }

    pub(super) fn of(&self, l: Lit) -> &[Tp] {
        self.by_lit.get(&l).map_or(&[], |v| v.as_slice())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One token: `spend-a` and `spend-b` each need it at their start and
    /// use it up at their end; `mint` makes one (5 time units).
    const DOMAIN: &str = "(define (domain token)
  (:requirements :durative-actions)
  (:predicates (token) (a) (b))
  (:durative-action spend-a :parameters () :duration (= ?duration 1)
    :condition (at start (token)) :effect (and (at end (not (token))) (at end (a))))
  (:durative-action spend-b :parameters () :duration (= ?duration 1)
    :condition (at start (token)) :effect (and (at end (not (token))) (at end (b))))
  (:durative-action mint :parameters () :duration (= ?duration 5)
    :effect (at end (token))))";

    /// The estimate of `spend-b`'s open link on `(token)` in a plan where
    /// `spend-a` is ordered before it, and in one where `spend-b` is first.
    fn token_costs() -> (f64, f64, f64) {
        let problem = "(define (problem p) (:domain token) (:init (token)) (:goal (and (a) (b))))";
        super::super::test_support::with_search(
            ("domain.pddl", "problem.pddl"),
            DOMAIN,
            problem,
            |prepared, search| {
                let (task, h) = (&prepared.task, &prepared.h);
                let op = |name: &str| task.ops.iter().position(|o| &*o.name == name).expect("an op") as u32;
                let token = task.ops[op("mint") as usize].effs[0].lit;
                let cost_of_b = |a_first: bool| {
                    let mut p = Plan::initial(task).expect("a plan");
                    let a = p.add_step(task, h, op("spend-a"), None).expect("added");
                    let b = p.add_step(task, h, op("spend-b"), None).expect("added");
                    let (a, b) = (p.steps[a as usize], p.steps[b as usize]);
                    let ordered =
                        if a_first { p.stn.add(a.end, b.start, EPS) } else { p.stn.add(b.end, a.start, EPS) };
                    assert!(ordered);
                    let o = *p.open.iter().find(|o| o.need == b.start && o.lit == token).expect("b's link");
                    let index = EffectIndex::new(task, &p, [token, token ^ 1].into_iter());
                    search.open_cost(&p, &o, &index).0
                };
                (cost_of_b(true), cost_of_b(false), h.again_cost[token as usize])
            },
        )
    }

    /// Advance reuse (Equation 1) counts a link free when a producer can
    /// come before it and no step removes the literal after its creation:
    /// the initial token serves `spend-b` when `spend-b` comes first, not
    /// when `spend-a` has used it up before; then it must be minted again.
    #[test]
    fn a_literal_deleted_between_its_producer_and_the_need_is_not_reused() {
        let (after_a, before_a, again) = token_costs();
        assert_eq!(before_a, 0.0);
        assert!((again - (5.0 + EPS)).abs() < 1e-9, "{again}");
        assert_eq!(after_a, again);
    }
}
