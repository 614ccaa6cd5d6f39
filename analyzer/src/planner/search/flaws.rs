//! Flaw selection (section 4.2.3 of the HiPOP paper): which flaw of a
//! partial plan the search solves next. Threats that one ordering alone
//! still solves are ordered in place; then open links (in a purely
//! hierarchical problem, one that a single step can support first;
//! positions last: the itineraries), the abstract flaws that open links
//! wait for, the delayed threats, the other abstract flaws in
//! chronological order, and, in a plan without any of those, timed
//! literals after the plan's end and interfering happenings too close
//! together (VAL's mutex).

use super::super::FlawOrder;
use super::super::numeric;
use super::super::plan::{Kind, Open, OpenOrigin, Plan, Threat};
use super::super::stn::{EPS, Tp};
use super::super::task::atom_of;
use super::progression::get;
use super::{Flaw, Search};

impl Search<'_, '_> {
    /// Picks the flaw to solve (section 4.2.3): threats that have one
    /// ordering left are solved in place (and one with none ends the plan);
    /// then open links (one a single step can support first, in a purely
    /// hierarchical problem; positions last: the itineraries), then the
    /// threats that both orderings still solve (delayed: later choices
    /// often order them, or leave one way only), then abstract flaws in
    /// chronological order, then interfering happenings.
    pub(super) fn select(&self, p: &mut Plan) -> Option<Flaw> {
        let task = self.task;
        if p.threats.iter().any(|t| !p.still_threat(task, t)) {
            let keep: Vec<Threat> = p.threats.iter().copied().filter(|t| p.still_threat(task, t)).collect();
            p.threats = std::rc::Rc::new(keep);
        }
        if self.config.eager && !p.threats.is_empty() {
            return self.threat_flaw(p);
        }
        if self.at_front() {
            if !p.threats.is_empty() {
                return self.threat_flaw(p);
            }
            return self.front_flaw(p).or_else(|| self.late_til(p)).or_else(|| self.mutex(p));
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
        let ready = self.ready_links(p);
        if let Some(i) = self.forced_link(p, &ready) {
            return Some(Flaw::Open(i));
        }
        // `refine`, in a purely hierarchical problem: refinements first, a
        // wrong one found dead when generated ([`super::progression`]),
        // before its steps' links are chosen every way they can be.
        if self.config.refine && self.task.achievers.is_empty() && !p.abstracts.is_empty() {
            return Some(self.abstract_flaw(p));
        }
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
        if let Some(flaw) = self.numeric_flaw(p) {
            return Some(flaw);
        }
        self.late_til(p).or_else(|| self.mutex(p))
    }

    /// Numeric fluents, once nothing else is left but timed literals and
    /// mutexes: the happenings that touch the same resource, one of them
    /// writing it, ordered (in place when the network allows one way only;
    /// else a [`Flaw::NumOrder`]); then the resources' values along that
    /// order, the durations that read them fixed in the network, and the
    /// first condition that does not hold ([`Flaw::Numeric`]).
    pub(super) fn numeric_flaw(&self, p: &mut Plan) -> Option<Flaw> {
        let task = self.task;
        if task.numeric.is_empty() {
            return None;
        }
        let events = numeric::events(task, p);
        let mut resources: Vec<&u32> = events.keys().collect();
        resources.sort_unstable();
        for res in resources {
            let evs = &events[res];
            for (i, a) in evs.iter().enumerate() {
                for b in &evs[i + 1..] {
                    if !(a.writes || b.writes) || p.stn.before(a.tp, b.tp) || p.stn.before(b.tp, a.tp) {
                        continue;
                    }
                    match (p.stn.allows(a.tp, b.tp, EPS), p.stn.allows(b.tp, a.tp, EPS)) {
                        (false, false) => return Some(Flaw::Dead),
                        (true, true) => return Some(Flaw::NumOrder(a.tp, b.tp)),
                        (true, false) => {
                            if !p.stn.add(a.tp, b.tp, EPS) {
                                return Some(Flaw::Dead);
                            }
                        }
                        (false, true) => {
                            if !p.stn.add(b.tp, a.tp, EPS) {
                                return Some(Flaw::Dead);
                            }
                        }
                    }
                }
            }
        }
        let values = numeric::simulate(task, p, &events, &p.durations);
        if values.blocked {
            return Some(Flaw::Dead);
        }
        for (s, d) in values.durations {
            let Some(d) = d else { return Some(Flaw::Dead) };
            let step = p.steps[s as usize];
            if !(p.stn.add(step.start, step.end, d) && p.stn.add(step.end, step.start, -d)) {
                return Some(Flaw::Dead);
            }
            std::rc::Rc::make_mut(&mut p.durations).push((s, d));
        }
        values.failed.map(Flaw::Numeric)
    }

    /// Whether a step is of an elementary action.
    pub(super) fn elementary(&self, k: Kind) -> bool {
        matches!(k, Kind::Op(o) if !self.task.ops[o as usize].is_abstract)
    }

    /// A goal supported by a timed initial literal later than every event
    /// of the plan: VAL applies no timed literal after the plan's last
    /// event, so some step must end after it.
    pub(super) fn late_til(&self, p: &Plan) -> Option<Flaw> {
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
    pub(super) fn abstract_flaw(&self, p: &Plan) -> Flaw {
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
    pub(super) fn threat_flaw(&self, p: &mut Plan) -> Option<Flaw> {
        if !self.force_threats(p, true) {
            return Some(Flaw::Dead);
        }
        if p.threats.is_empty() {
            return self.select(p);
        }
        Some(Flaw::Threat(p.threats.len() - 1))
    }

    /// The open links that are not visits and that no unrefined abstract
    /// step may still support ([`Waiting::defers`]).
    pub(super) fn ready_links(&self, p: &Plan) -> Vec<usize> {
        let waiting = Waiting::of(p);
        p.open
            .iter()
            .enumerate()
            .filter(|&(_, o)| !self.is_visit(o) && !waiting.defers(self, p, o))
            .map(|(i, _)| i)
            .collect()
    }

    /// In a problem where no step is ever inserted (no action in 𝒜: a
    /// purely hierarchical one), a ready open link that no step of the plan
    /// can support: the plan is dead, and is dropped when generated
    /// ([`Search::score`]). Left in the open list, such a plan waited until
    /// `local` order chose that link, behind the links of newer steps with
    /// several producers each, and the search went through every way to
    /// link those first (a plan found dead at each leaf).
    pub(super) fn dead_link(&self, p: &Plan, ready: &[usize]) -> Option<usize> {
        self.link_with_at_most(p, ready, 0)
    }

    /// In a problem where no step is ever inserted, a ready open link that
    /// one step of the plan only can support: it is linked first, whatever
    /// `local` order would choose (one child, no choice). The links of the
    /// newest step with several producers each, chosen first, made the
    /// search go through every way to link them before finding that a
    /// forced link elsewhere cannot be made in any of them: IPC 2020
    /// Transport links a truck's position at each stop many ways, and the
    /// capacity level a `pick-up` needs, which one `drop` only makes, then
    /// fails under each (docs/planner.md).
    pub(super) fn forced_link(&self, p: &Plan, ready: &[usize]) -> Option<usize> {
        if ready.len() < 2 {
            return None;
        }
        self.link_with_at_most(p, ready, 1)
    }

    /// The first of the ready open links that at most `n` steps of the plan
    /// can support, in a problem where no step is ever inserted.
    fn link_with_at_most(&self, p: &Plan, ready: &[usize], n: usize) -> Option<usize> {
        if !self.task.achievers.is_empty() || ready.is_empty() {
            return None;
        }
        let index = super::resolvers::Effects::for_lits(self.task, p, ready.iter().map(|&i| p.open[i].lit));
        let mut prod = Vec::new();
        ready.iter().copied().find(|&i| {
            let o = p.open[i];
            self.producers_indexed(p, &o, &index, &mut prod);
            if o.origin == OpenOrigin::AbstractEffect {
                prod.retain(|&(s, _)| s != o.step && p.descends(s, o.step));
            }
            prod.len() <= n
        })
    }

    pub(super) fn costliest(&self, p: &Plan, it: impl Iterator<Item = usize>) -> usize {
        let mut best: Option<(usize, f64)> = None;
        for i in it {
            let c = self.h.lit_cost(p.open[i].lit);
            if best.is_none_or(|(_, b)| c > b) {
                best = Some((i, c));
            }
        }
        best.map_or(0, |(i, _)| i)
    }

    /// Two interfering happenings less than ε apart in the earliest
    /// schedule: at some tolerance up to ε, VAL groups them into one
    /// happening and rejects the plan (or the validator warns that they
    /// are closer than the tolerance, W0411). The schedule is no longer on
    /// a grid (durations are exact), so "the same time" is not enough.
    pub(super) fn mutex(&self, p: &Plan) -> Option<Flaw> {
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
                if b.0 - a.0 >= EPS - 1e-9 {
                    break;
                }
                if a.2 == b.2 {
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
    pub(super) fn touched(&self, p: &Plan, tp: Tp, s: u32) -> (Vec<u32>, Vec<u32>) {
        let (mut reads, mut writes) = (Vec::new(), Vec::new());
        let step = p.steps[s as usize];
        for (l, t) in p.effects(self.task, s) {
            if t == tp {
                writes.push(atom_of(l));
            }
        }
        if let Kind::Op(o) = step.kind {
            let op = &self.task.ops[o as usize];
            for c in &op.conds {
                if step.tp(c.at) == tp || step.tp(c.until) == tp {
                    reads.push(atom_of(c.lit));
                }
            }
            // Numeric fluents the search follows, as ids past the atoms'.
            let fluent = |res: u32| u32::MAX - res;
            reads.extend(op.num_conds.iter().filter(|c| step.tp(c.at) == tp).map(|c| fluent(c.res)));
            if step.start == tp {
                reads.extend(op.num_duration.iter().map(|d| fluent(d.res)));
            }
            writes.extend(op.num_effs.iter().filter(|e| step.tp(e.at) == tp).map(|e| fluent(e.res)));
        }
        (reads, writes)
    }

    pub(super) fn interfere(&self, p: &Plan, a: Tp, sa: u32, b: Tp, sb: u32) -> bool {
        let (ra, wa) = self.touched(p, a, sa);
        let (rb, wb) = self.touched(p, b, sb);
        wa.iter().any(|x| rb.contains(x) || wb.contains(x)) || wb.iter().any(|x| ra.contains(x))
    }
}

/// The unrefined abstract steps of a plan that open links may wait for,
/// read once for all its open links ([`Search::ready_links`]): each with
/// its operator and the closure's row of its start (asked once per open
/// link and abstract step before, each through the orderings that wait:
/// a fifth of the search on IPC 2020 Transport's larger problems, plans
/// of hundreds of steps).
struct Waiting {
    /// Step, operator, and the offset of its start's row in `rows`.
    steps: Vec<(u32, u32, usize)>,
    rows: Vec<u64>,
}

impl Waiting {
    fn of(p: &Plan) -> Waiting {
        let mut w = Waiting { steps: Vec::new(), rows: Vec::new() };
        if p.abstracts.is_empty() || p.open.is_empty() {
            return w;
        }
        let mut row = Vec::new();
        for &a in p.abstracts.iter() {
            let st = p.steps[a as usize];
            let Kind::Op(op) = st.kind else { continue };
            p.stn.preceding(st.start, &mut row);
            w.steps.push((a, op, w.rows.len()));
            w.rows.extend_from_slice(&row);
        }
        w
    }

    /// Whether an open link must wait: an unrefined abstract step that can
    /// come before it may make its literal true once refined (its subtasks
    /// are not in the plan yet, and linking to another producer now could
    /// lose the plan). Section 4.2.3: abstract steps hide the literals
    /// their methods create, hence abstract flaws in chronological order
    /// first.
    fn defers(&self, search: &Search<'_, '_>, p: &Plan, o: &Open) -> bool {
        if self.steps.is_empty() {
            return false;
        }
        let task = search.task;
        let pred = task.g.atoms.pred(atom_of(o.lit));
        let width = p.stn.len().div_ceil(64);
        let need = o.need as usize;
        self.steps.iter().any(|&(a, op, at)| {
            // A HiPOP abstract action is used through what it declares,
            // like an elementary action (section 4.1): a predicate its
            // effects name is not waited for. What it does not declare
            // (everything for an HDDL task) only its methods tell.
            if task.ops[op as usize].effs.iter().any(|e| task.g.atoms.pred(atom_of(e.lit)) == pred) {
                return false;
            }
            // Not `before(o.need, start)`: bit `need` of the start's row.
            a != o.step
                && !get(&self.rows[at..at + width], need)
                && search.h.may_add(op, o.lit)
                && !p.descends(o.step, a)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::Prepared;
    use super::*;

    /// Two actions on one tank: `burn` takes a unit of fuel at its start,
    /// `check` needs a unit at its start; nothing else orders them.
    const DOMAIN: &str = "(define (domain tank)
  (:requirements :durative-actions :numeric-fluents)
  (:predicates (burnt) (checked))
  (:functions (fuel))
  (:durative-action burn :parameters () :duration (= ?duration 1)
    :condition (at start (>= (fuel) 1))
    :effect (and (at start (decrease (fuel) 1)) (at end (burnt))))
  (:durative-action check :parameters () :duration (= ?duration 1)
    :condition (at start (>= (fuel) 1))
    :effect (at end (checked)))
  (:durative-action fill :parameters () :duration (= ?duration (- 5 (fuel)))
    :condition (at start (< (fuel) 5))
    :effect (at end (assign (fuel) 5)))
  (:durative-action guzzle :parameters () :duration (= ?duration 1)
    :condition (at start (<= 6 (fuel)))
    :effect (and (at start (decrease (fuel) 6)) (at end (burnt)))))";

    /// Runs `f` on the prepared problem with `fuel` in `:init`, and a search of it.
    fn with_task<T>(
        fuel: u32,
        f: impl FnOnce(&Prepared<'_>, &Search<'_, '_>) -> T + std::panic::UnwindSafe,
    ) -> T {
        let problem = format!(
            "(define (problem p) (:domain tank) (:init (= (fuel) {fuel})) (:goal (and (burnt) (checked))))"
        );
        super::super::test_support::with_search(("domain.pddl", "problem.pddl"), DOMAIN, &problem, f)
    }

    /// A duration that reads the fuel is fixed once the fuel at its start
    /// is known; a step that changes the fuel, ordered before it later,
    /// would change what it reads, and the plan is dead (its duration in
    /// the network is no longer the one the validator computes).
    #[test]
    fn a_duration_read_from_a_fluent_is_fixed_and_stays_what_its_start_reads() {
        with_task(2, |prepared, search| {
            let task = &prepared.task;
            let op = |name: &str| task.ops.iter().position(|o| &*o.name == name).expect("an op") as u32;
            let mut p = Plan::initial(task).expect("a plan");
            let fill = p.add_step(task, search.h, op("fill"), None).expect("added");
            let (fs, fe) = (p.steps[fill as usize].start, p.steps[fill as usize].end);
            assert!(search.numeric_flaw(&mut p).is_none());
            assert_eq!(p.fixed_duration(fill), Some(3.0));
            assert!((p.stn.est(fe) - p.stn.est(fs) - 3.0).abs() < 1e-9);
            let burn = p.add_step(task, search.h, op("burn"), None).expect("added");
            assert!(p.stn.add(p.steps[burn as usize].start, fs, EPS));
            assert!(matches!(search.numeric_flaw(&mut p), Some(Flaw::Dead)));
        });
    }

    /// The fuel is never above 5 (`:init` gives less, `fill` assigns 5,
    /// nothing increases it): `guzzle`, which needs 6, is never usable and
    /// supports nothing; `burn` is kept.
    #[test]
    fn an_action_needing_more_than_a_fluent_can_hold_is_never_used() {
        with_task(2, |prepared, _| {
            let task = &prepared.task;
            let dead = |name: &str| task.ops.iter().find(|o| &*o.name == name).expect("an op").dead;
            assert!(dead("guzzle"));
            assert!(!dead("burn") && !dead("check") && !dead("fill"));
            let burnt =
                task.achievers.iter().find(|(l, _)| task.show_lit(**l) == "(burnt)").expect("achieved");
            assert!(burnt.1.iter().all(|&(o, _)| &*task.ops[o as usize].name == "burn"));
        });
    }

    /// With `fuel` in `:init`: the plan with a `burn` and a `check` step
    /// and no ordering between them; for each of the orderings the numeric
    /// threat offers (which happening comes first), whether `check` comes
    /// first and what the numeric stage finds next.
    fn orderings(fuel: u32) -> Vec<(bool, Option<String>)> {
        with_task(fuel, |prepared, search| {
            let task = &prepared.task;
            let op = |name: &str| task.ops.iter().position(|o| &*o.name == name).expect("an op") as u32;
            let mut p = Plan::initial(task).expect("a plan");
            let burn = p.add_step(task, &prepared.h, op("burn"), None).expect("added");
            let check = p.add_step(task, &prepared.h, op("check"), None).expect("added");
            let (bs, cs) = (p.steps[burn as usize].start, p.steps[check as usize].start);
            let Some(Flaw::NumOrder(a, b)) = search.numeric_flaw(&mut p) else {
                panic!("the two starts touch the fuel, one writes it: a numeric threat")
            };
            assert_eq!([a.min(b), a.max(b)], [bs.min(cs), bs.max(cs)]);
            let mut children = Vec::new();
            search.resolvers(&p, Flaw::NumOrder(a, b), &mut children);
            children
                .into_iter()
                .map(|mut c| {
                    let check_first = c.stn.before(cs, bs);
                    assert!(check_first != c.stn.before(bs, cs), "ordered one way");
                    assert!(c.stn.est(cs).max(c.stn.est(bs)) >= EPS, "ε apart");
                    let next = match search.numeric_flaw(&mut c) {
                        None => None,
                        Some(Flaw::Numeric(f)) => Some(format!(
                            "{} reads {:?}",
                            task.show_op(c.op_of(f.step).expect("op")),
                            f.value
                        )),
                        Some(_) => Some("another flaw".to_string()),
                    };
                    (check_first, next)
                })
                .collect()
        })
    }

    /// A purely hierarchical problem: `lean` refines `job` into a `use-x`
    /// that nothing in its plan can support (only `full`'s `make-x` adds
    /// `x`, and no step is ever inserted), beside a `use-y` whose link has
    /// two producers and costs more. The plan is dropped when scored, not
    /// left to end after every way to link `use-y`.
    #[test]
    fn a_hierarchical_plan_with_a_link_nothing_can_support_is_dropped() {
        let domain = "(define (domain d) (:requirements :hierarchy)
          (:predicates (x) (y) (w))
          (:task job :parameters ())
          (:method lean :parameters () :task (job)
            :subtasks (and (use-x) (make-w) (make-y-a) (make-y-b) (use-y)))
          (:method full :parameters () :task (job)
            :ordered-subtasks (and (make-x) (use-x) (make-w) (make-y-a) (use-y)))
          (:action make-x :parameters () :effect (x))
          (:action make-w :parameters () :effect (w))
          (:action make-y-a :parameters () :precondition (w) :effect (y))
          (:action make-y-b :parameters () :precondition (w) :effect (y))
          (:action use-x :parameters () :precondition (x) :effect ())
          (:action use-y :parameters () :precondition (y) :effect ()))";
        let problem = "(define (problem p) (:domain d) (:htn :subtasks (and (job))) (:init))";
        super::super::test_support::with_search(
            ("domain.hddl", "problem.hddl"),
            domain,
            problem,
            |prepared, search| {
                let task = &prepared.task;
                let mut roots = search.initial();
                assert_eq!(roots.len(), 1);
                let flaw = search.select(&mut roots[0]).expect("a flaw");
                assert!(matches!(flaw, Flaw::Abstract(_)), "the job is refined first");
                let mut children = Vec::new();
                search.resolvers(&roots[0], flaw, &mut children);
                let method =
                    |p: &Plan| p.steps.iter().find_map(|s| s.method).map(|m| &*task.methods[m as usize].name);
                let mut lean =
                    children.into_iter().find(|c| method(c) == Some("lean")).expect("refined by lean");
                let ready = search.ready_links(&lean);
                let dead = search.dead_link(&lean, &ready).expect("a dead link");
                assert_eq!(task.show_lit(lean.open[dead].lit), "(x)");
                let mut none = Vec::new();
                search.resolvers(&lean, Flaw::Open(dead), &mut none);
                assert!(none.is_empty(), "no step of the plan adds (x)");
                // The plan never enters the open list: dead when scored.
                assert!(search.score(&mut lean).is_none());
                let mut full = search.initial().remove(0);
                let mut children = Vec::new();
                search.resolvers(&full, Flaw::Abstract(0), &mut children);
                full = children.into_iter().find(|c| method(c) == Some("full")).expect("refined by full");
                assert!(search.score(&mut full).is_some(), "full makes its own (x)");
            },
        );
    }

    #[test]
    fn steps_touching_a_fluent_are_ordered_both_ways_and_read_along_the_order() {
        // Two units: either order works.
        assert_eq!(orderings(2), [(false, None), (true, None)]);
        // One unit: `check` after `burn` reads 0.
        assert_eq!(orderings(1), [(false, Some("(check) reads Some(0.0)".to_string())), (true, None)]);
    }
}
