//! Progression at the front of a hierarchical plan (configuration part
//! `front`): the plan grows from its start, as a progression planner over
//! the task network grows its prefix (pandaPI's search, Höller et al.,
//! 2020).
//!
//! In a problem where no step is ever inserted, the elementary steps
//! committed so far run first, in the order they were committed (each is
//! ordered after the one before, and before every step not committed yet),
//! so the state after them is known. The *front* is what may come next: the
//! unrefined abstract steps and the elementary steps not committed that
//! nothing left must precede. A plan's flaw is its front, and its children
//! are
//!
//! - for each elementary step of the front whose conditions hold in that
//!   state, the plan with it committed next: ordered after the last one
//!   and before every step left, its conditions linked to the last
//!   committed step (or the initial state) that made them true, so that no
//!   step can threaten those links;
//! - the refinements of one abstract step of the front (the newest): every
//!   abstract step is refined some time, and the order in which they are
//!   does not matter; its method's precondition is linked the same way,
//!   and a method whose precondition does not hold there is no child.
//!
//! While the refinement of a recursive task has steps left (a Transport
//! `get-to` refined into a route), the front is those steps only: the
//! route runs to its end before another task's steps come in
//! ([`Search::recursion_under_way`]).
//!
//! An elementary step of the front without effects whose conditions hold
//! is committed alone: it changes nothing, so committing it first loses
//! no plan. When nothing is left but the goal, the goal is committed.
//!
//! Other flaw orders choose a truck's route (which `get-to` drives from
//! where) long before they know where the truck is at that point: on IPC
//! 2020 Transport every `get-to` was refined before any of the truck's
//! stops was linked, and a wrong route was found dead late, under every
//! way to link and order the stops around it. At the front, the state
//! says where the truck is, and a drive from elsewhere does not run.

use rustc_hash::FxHashMap;

use super::super::plan::{GOAL, INIT, Kind, OpenOrigin, Plan};
use super::super::stn::{EPS, ORIGIN, Tp};
use super::super::task::{Lit, Task, atom_of, is_neg, lit};
use super::{Flaw, Search};

/// The most operators and method instances of a task whose plans the
/// default configuration grows from their front (between the search with
/// refinements first and the one with links first): the relaxed
/// composition is evaluated at every plan, and on IPC 2020 Monroe (74,349
/// operators, 61,947 methods) the search expanded 3 plans in 10 s.
pub const FRONT_MAX_ACTIONS: usize = 20_000;

/// The weight of `h` in `f` for plans grown from their front (2 in the
/// other searches of a purely hierarchical problem, `HTN_WEIGHT`): `g`
/// grows by a step's ε with each step committed, and `h` is the relaxed
/// composition's plan from the state they leave, which the search trusts
/// more. With duplicates dropped ([`Search::front_key`]), weight 2 lost
/// plans that the greedy descents had found (IPC 2020 Rover pfile08 in
/// 1,116 expansions before, none in 20,000; Barman-BDI pfile07, 4,177 and
/// none in 43,000); at 5 the default sequence solves 6 to 8 of the first
/// 10 of Barman-BDI (3 before; Rover pfile10 is lost), and Transport
/// pfile14 and 15 (not solved in 10 s at 2) take 1,121 and 1,681
/// expansions alone (docs/benchmarks.md, 2026-11-27).
pub(super) const FRONT_WEIGHT: f64 = 5.0;

/// The weight of `h` in `f` for plans grown from their front under the
/// configuration part `greedy`, which the default sequence runs after the
/// search at [`FRONT_WEIGHT`]. IPC 2020 Barman-BDI makes each cocktail by
/// a long run of steps that the relaxed composition's estimate barely
/// tells apart (which hand, which shot holds an ingredient), and at weight
/// 5 the search goes back to shallower plans through every such choice:
/// pfile03, 06 and 12 take 1,809, 1,952 and 5,816 expansions alone at 20,
/// none within 20,000 at 5 (06, 11) or 10,000. It loses elsewhere
/// (Transport pfile15: 1,681 expansions at 5, none in 10,000 at 10, 15 or
/// 20), hence both (docs/benchmarks.md, 2026-11-28).
pub(super) const FRONT_GREEDY_WEIGHT: f64 = 20.0;

/// The state after the committed steps: for each atom a committed step
/// writes, the last such step, its time point and the value it leaves.
pub(super) struct Prefix {
    last: FxHashMap<u32, (u32, Tp, bool)>,
}

impl Prefix {
    /// Whether `l` holds after the committed steps.
    pub(super) fn holds(&self, task: &Task<'_>, l: Lit) -> bool {
        match self.last.get(&atom_of(l)) {
            Some(&(_, _, v)) => v != is_neg(l),
            None => task.holds_initially(l),
        }
    }

    /// The step (and time point) that last made `l` true, when it holds.
    fn producer(&self, task: &Task<'_>, l: Lit) -> Option<(u32, Tp)> {
        match self.last.get(&atom_of(l)) {
            Some(&(s, tp, v)) => (v != is_neg(l)).then_some((s, tp)),
            None => task.holds_initially(l).then_some((INIT, ORIGIN)),
        }
    }
}

/// A plan's front: its prefix's state, the elementary steps not committed
/// yet, the unrefined abstract steps, and which of them nothing left
/// precedes.
pub(super) struct View {
    pub(super) prefix: Prefix,
    /// Elementary steps not committed.
    pub(super) rest: Vec<u32>,
    /// How many elementary steps are committed.
    pub(super) committed: usize,
    /// Elementary steps of the front.
    steps: Vec<u32>,
    /// Indices in `Plan::abstracts` of the abstract steps of the front.
    abstracts: Vec<usize>,
}

impl Search<'_, '_> {
    /// Whether the search grows plans from their front: configuration part
    /// `front`, in a problem where no step is ever inserted, with
    /// instantaneous actions, tasks without effects of their own, no timed
    /// literals, no numeric fluents and no itineraries, and not in a repair.
    pub(super) fn at_front(&self) -> bool {
        self.composition.is_some() && !self.from_seeds.get()
    }

    /// Whether a problem and configuration allow [`Search::at_front`].
    pub(super) fn front_applies(task: &Task<'_>, config: &super::Config, geo: bool) -> bool {
        config.front
            && task.htn.is_some()
            && task.achievers.is_empty()
            && task.tils.is_empty()
            && task.numeric.is_empty()
            && !geo
            && task.ops.iter().all(|o| if o.is_abstract { o.effs.is_empty() } else { o.instant })
    }

    /// Whether the search under `config` grows plans from their front, and
    /// the relaxed composition it evaluates at each plan is small enough
    /// ([`FRONT_MAX_ACTIONS`]).
    pub fn grows_from_front(task: &Task<'_>, config: &super::Config) -> bool {
        let motion = config.motion != super::super::Motion::Off && task.motion.iter().any(|m| m.is_some());
        Search::front_applies(task, config, motion)
            && task.ops.len() + task.methods.len() <= FRONT_MAX_ACTIONS
    }

    /// Whether step `s` is an elementary step committed to the front.
    fn committed(&self, p: &Plan, s: u32) -> bool {
        let step = p.steps[s as usize];
        p.front != ORIGIN
            && self.elementary(step.kind)
            && (step.start == p.front || p.stn.before(step.start, p.front))
    }

    pub(super) fn view(&self, p: &Plan) -> View {
        let task = self.task;
        let mut done: Vec<(f64, u32)> = Vec::new();
        let mut rest = Vec::new();
        for (s, step) in p.steps.iter().enumerate() {
            if !self.elementary(step.kind) {
                continue;
            }
            if self.committed(p, s as u32) {
                done.push((p.stn.est(step.start), s as u32));
            } else {
                rest.push(s as u32);
            }
        }
        done.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut last = FxHashMap::default();
        for &(_, s) in &done {
            let mut effs: Vec<(Lit, Tp)> = p.effects(task, s).collect();
            // Deletions first, then additions (PDDL's order).
            effs.sort_by_key(|&(l, _)| !is_neg(l));
            for (l, tp) in effs {
                last.insert(atom_of(l), (s, tp, !is_neg(l)));
            }
        }
        let unrefined: Vec<u32> = p.abstracts.iter().copied().collect();
        // The points of what is left: a step's start, an abstract step's
        // end; a step waits when one of them is before its start.
        let mut left = vec![0u64; p.stn.len().div_ceil(64)];
        let mut mark = |t: Tp| {
            if let Some(w) = left.get_mut(t as usize / 64) {
                *w |= 1 << (t % 64);
            }
        };
        rest.iter().for_each(|&z| mark(p.steps[z as usize].start));
        unrefined.iter().for_each(|&a| mark(p.steps[a as usize].end));
        let mut row = Vec::new();
        let mut free = |x: u32| {
            p.stn.preceding(p.steps[x as usize].start, &mut row);
            row.iter().zip(&left).all(|(r, l)| r & l == 0)
        };
        let mut steps: Vec<u32> = rest.iter().copied().filter(|&x| free(x)).collect();
        let mut abstracts: Vec<usize> =
            unrefined.iter().enumerate().filter(|&(_, &a)| free(a)).map(|(i, _)| i).collect();
        if let Some(a) = self.recursion_under_way(p, &rest, &unrefined) {
            steps.retain(|&x| descends(p, x, a));
            abstracts.retain(|&i| descends(p, unrefined[i], a));
        }
        View { prefix: Prefix { last }, rest, committed: done.len(), steps, abstracts }
    }

    /// The refined step of a recursive task (one of whose refinements may
    /// hold the task again: a Transport `get-to` by `m-drive-to-via`) that
    /// has steps left among `rest` and `unrefined`: the outermost such
    /// ancestor of a step left, the oldest when there are several. While
    /// there is one, the front is its steps only ([`Search::view`]): a
    /// recursion, once refined, runs to its end before anything else
    /// starts. A `get-to` refined fixes the truck's route from where the
    /// truck is; a step of another task that moves the truck in the middle
    /// of it (the next package's drive) leaves the rest of the route to run
    /// from a place the truck is no longer at, and only other routes of the
    /// same truck, still abstract, could bring it back there, which the
    /// relaxed composition takes for granted: on IPC 2020 Transport
    /// pfile16 the search reached plans of 41 committed steps with two such
    /// drives left, and went back through every shorter prefix. The plans
    /// lost are those that interleave another task with a recursion under
    /// way; the search with links first, last in the default sequence,
    /// still finds them.
    /// Whether plans grow from their front with a recursive task to run
    /// to its end ([`Search::recursion_under_way`]): the search is then
    /// not complete.
    pub fn runs_recursions_to_their_end(&self) -> bool {
        self.composition.as_ref().is_some_and(|c| c.recursive.iter().any(|&r| r))
    }

    fn recursion_under_way(&self, p: &Plan, rest: &[u32], unrefined: &[u32]) -> Option<u32> {
        let comp = self.composition.as_ref()?;
        let mut found: Option<u32> = None;
        for &s in rest.iter().chain(unrefined) {
            let mut outer = None;
            let mut up = p.steps[s as usize].parent;
            while let Some(u) = up {
                if p.op_of(u).is_some_and(|o| comp.recursive[o as usize]) {
                    outer = Some(u);
                }
                up = p.steps[u as usize].parent;
            }
            if let Some(u) = outer
                && found.is_none_or(|f| p.steps[u as usize].born < p.steps[f as usize].born)
            {
                found = Some(u);
            }
        }
        found
    }

    /// The flaw of a plan grown from its front: its front, with the
    /// abstract step whose refinements are among its children (the newest
    /// of the front); [`Flaw::Dead`] when nothing can come next; `None`
    /// when every step is committed and the goal holds.
    pub(super) fn front_flaw(&self, p: &Plan) -> Option<Flaw> {
        let view = self.view(p);
        let refine = view.abstracts.iter().copied().max_by_key(|&i| p.steps[p.abstracts[i] as usize].born);
        if refine.is_none() && view.rest.is_empty() {
            // Nothing but the goal left.
            if p.open.iter().any(|o| o.step == GOAL) {
                return Some(Flaw::Front(None));
            }
            return None;
        }
        let runs = view.steps.iter().any(|&x| self.applicable(p, &view.prefix, x));
        if refine.is_none() && !runs {
            return Some(Flaw::Dead);
        }
        Some(Flaw::Front(refine))
    }

    /// Whether the conditions of step `x` not linked yet hold after the prefix.
    fn applicable(&self, p: &Plan, prefix: &Prefix, x: u32) -> bool {
        p.open.iter().filter(|o| o.step == x).all(|o| prefix.holds(self.task, o.lit))
    }

    /// The children of a plan for its front ([`Flaw::Front`]): the steps
    /// of the front committed next, and the refinements of `refine`.
    pub(super) fn front_resolvers(&self, p: &Plan, refine: Option<usize>, out: &mut Vec<Plan>) {
        let view = self.view(p);
        if refine.is_none() && view.rest.is_empty() {
            out.extend(self.commit(p, &view, GOAL));
            return;
        }
        let runs: Vec<u32> =
            view.steps.iter().copied().filter(|&x| self.applicable(p, &view.prefix, x)).collect();
        // A step without effects changes nothing: first, and alone.
        if let Some(&x) =
            runs.iter().find(|&&x| p.op_of(x).is_some_and(|o| self.task.ops[o as usize].effs.is_empty()))
        {
            out.extend(self.commit(p, &view, x));
            return;
        }
        for &x in &runs {
            if self.past_limit() {
                return;
            }
            out.extend(self.commit(p, &view, x));
        }
        let Some(i) = refine else { return };
        let s = p.abstracts[i];
        let first_new = p.steps.len();
        let mut refined = Vec::new();
        self.resolvers(p, Flaw::Abstract(i), &mut refined);
        'child: for mut c in refined {
            if p.front != ORIGIN {
                for k in first_new..c.steps.len() {
                    let t = c.steps[k].start;
                    if !c.stn.before(p.front, t) && !c.stn.add(p.front, t, EPS) {
                        continue 'child;
                    }
                }
            }
            let mut k = c.open.len();
            while k > 0 {
                k -= 1;
                let o = c.open[k];
                if o.step != s || !matches!(o.origin, OpenOrigin::MethodPre(..)) {
                    continue;
                }
                let Some((from, tp)) = view.prefix.producer(self.task, o.lit) else { continue 'child };
                c.remove_open(k);
                if !c.add_link(self.task, from, tp, &o) {
                    continue 'child;
                }
            }
            out.push(c);
        }
    }

    /// Plan `p` with step `x` of its front committed next: after the last
    /// committed step, before every step and unrefined abstract step left,
    /// its conditions linked to the prefix. `None` when a condition does
    /// not hold or the network refuses an ordering.
    fn commit(&self, p: &Plan, view: &View, x: u32) -> Option<Plan> {
        let mut c = p.clone();
        let start = c.steps[x as usize].start;
        if x != GOAL {
            if p.front != ORIGIN && !c.stn.add(p.front, start, EPS) {
                return None;
            }
            let later = view
                .rest
                .iter()
                .copied()
                .filter(|&z| z != x)
                .chain(p.abstracts.iter().copied())
                .map(|z| p.steps[z as usize].start);
            for t in later {
                if !c.stn.before(start, t) && !c.stn.add(start, t, EPS) {
                    return None;
                }
            }
        }
        let mut k = c.open.len();
        while k > 0 {
            k -= 1;
            let o = c.open[k];
            if o.step != x {
                continue;
            }
            let (from, tp) = view.prefix.producer(self.task, o.lit)?;
            c.remove_open(k);
            if !c.add_link(self.task, from, tp, &o) {
                return None;
            }
        }
        if x != GOAL {
            c.front = start;
        }
        debug_assert!(x == GOAL || matches!(c.steps[x as usize].kind, Kind::Op(_)));
        Some(c)
    }
}

/// Whether step `s` of `p` is `a` or one of the steps its refinements brought in.
fn descends(p: &Plan, s: u32, a: u32) -> bool {
    let mut up = Some(s);
    while let Some(u) = up {
        if u == a {
            return true;
        }
        up = p.steps[u as usize].parent;
    }
    false
}

/// The plans grown from their front that the search has put in its open
/// lists, by their key ([`Search::front_key`]), each with the least
/// makespan of an earliest schedule met with it.
pub(super) type Seen = FxHashMap<Box<[u32]>, f64>;

impl Search<'_, '_> {
    /// What a plan grown from its front has left to do, as a key: the state
    /// after its committed steps (the atoms whose value differs from the
    /// initial one), the goal's conditions not linked yet, and what is left
    /// of its task network: the elementary steps not committed and the
    /// unrefined abstract steps, each with its operator or task and its
    /// conditions not linked yet, in a canonical order, and which of them
    /// must end before which starts. Two plans with the same key have the
    /// same completions: what is left runs from the same state, under the
    /// same orderings (every step not committed comes after the committed
    /// ones; a method precondition linked to a committed step no step left
    /// can threaten, as it can be ordered after it), and the methods that
    /// refine an abstract step put its subtasks where it stands. `None`
    /// when the plan has threats (not settled: no key).
    ///
    /// The order of the steps is by operator, conditions left, and those of
    /// the steps before and after it; steps alike on all of these are taken
    /// in the plan's order, so two plans whose networks are the same up to
    /// the names of their steps may still have different keys (a duplicate
    /// missed, never a plan lost).
    #[cfg(test)]
    pub(super) fn front_key(&self, p: &Plan) -> Option<Box<[u32]>> {
        self.front_key_in(p, &self.view(p))
    }

    /// [`Search::front_key`], with the plan's front.
    pub(super) fn front_key_in(&self, p: &Plan, view: &View) -> Option<Box<[u32]>> {
        if !p.threats.is_empty() {
            return None;
        }
        let task = self.task;
        let mut key = state_key(task, &view.prefix);
        key.push(u32::MAX);
        let mut goal_open = 0u32;
        let mut opens: FxHashMap<u32, u32> = FxHashMap::default();
        for o in p.open.iter() {
            if o.step == GOAL {
                goal_open += 1;
            } else {
                *opens.entry(o.step).or_insert(0) += 1;
            }
        }
        key.push(goal_open);
        let mut goal_lits: Vec<u32> = p.open.iter().filter(|o| o.step == GOAL).map(|o| o.lit).collect();
        goal_lits.sort_unstable();
        key.extend(goal_lits);
        let left: Vec<u32> = view.rest.iter().chain(p.abstracts.iter()).copied().collect();
        let n = left.len();
        // Each step's operator (or task) and its conditions left.
        let label =
            |s: u32| -> (u32, u32) { (p.op_of(s).unwrap_or(u32::MAX), opens.get(&s).copied().unwrap_or(0)) };
        let labels: Vec<(u32, u32)> = left.iter().map(|&s| label(s)).collect();
        let mut before = vec![false; n * n];
        let mut row = Vec::new();
        for j in 0..n {
            p.stn.preceding(p.steps[left[j] as usize].start, &mut row);
            for i in 0..n {
                let end = p.steps[left[i] as usize].end as usize;
                if i != j && row.get(end / 64).is_some_and(|w| w >> (end % 64) & 1 == 1) {
                    before[i * n + j] = true;
                }
            }
        }
        // The labels of the steps before and after each step, mixed into
        // its place in the order (any mix: the key holds the network).
        let mix = |h: u64, x: (u32, u32)| {
            let v = (u64::from(x.0) << 32) | u64::from(x.1);
            (h ^ v.wrapping_mul(0x9e37_79b9_7f4a_7c15)).rotate_left(5).wrapping_add(v)
        };
        let around: Vec<(u64, u64)> = (0..n)
            .map(|i| {
                let (mut pre, mut post) = (Vec::new(), Vec::new());
                for j in 0..n {
                    if before[j * n + i] {
                        pre.push(labels[j]);
                    }
                    if before[i * n + j] {
                        post.push(labels[j]);
                    }
                }
                pre.sort_unstable();
                post.sort_unstable();
                (pre.into_iter().fold(pre_seed(), mix), post.into_iter().fold(pre_seed() ^ 1, mix))
            })
            .collect();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&i| (labels[i], around[i], i));
        key.push(n as u32);
        for &i in &order {
            key.push(labels[i].0);
            key.push(labels[i].1);
        }
        let mut word = 0u32;
        let mut bits = 0;
        for &i in &order {
            for &j in &order {
                word = (word << 1) | before[i * n + j] as u32;
                bits += 1;
                if bits == 32 {
                    key.push(word);
                    (word, bits) = (0, 0);
                }
            }
        }
        if bits > 0 {
            key.push(word);
        }
        Some(key.into_boxed_slice())
    }

    /// Whether a plan grown from its front is already in the open lists,
    /// or was, with an earliest schedule no longer than `span`: its
    /// completions are that plan's, and none is shorter.
    #[cfg(test)]
    pub(super) fn front_known(&self, p: &Plan, span: f64) -> bool {
        self.front_key(p).is_some_and(|key| self.front_known_key(&key, span))
    }

    /// [`Search::front_known`] by the plan's key.
    pub(super) fn front_known_key(&self, key: &[u32], span: f64) -> bool {
        self.front_seen.borrow().get(key).is_some_and(|&s| s <= span)
    }

    /// Records a plan grown from its front that enters the open lists;
    /// `false` (not recorded) when [`Search::front_known`].
    #[cfg(test)]
    pub(super) fn front_record(&self, p: &Plan, span: f64) -> bool {
        self.front_key(p).is_none_or(|key| self.front_record_key(key, span))
    }

    /// [`Search::front_record`] by the plan's key.
    pub(super) fn front_record_key(&self, key: Box<[u32]>, span: f64) -> bool {
        let mut seen = self.front_seen.borrow_mut();
        match seen.get_mut(&key) {
            Some(s) if *s <= span => false,
            Some(s) => {
                *s = span;
                true
            }
            None => {
                seen.insert(key, span);
                true
            }
        }
    }
}

/// The start of the mix of the labels around a step ([`Search::front_key`]).
fn pre_seed() -> u64 {
    0x243f_6a88_85a3_08d3
}

/// The relaxed composition of the task (Höller et al., 2018), the model of
/// pandaPI's RC heuristics: deletions ignored, and each task a fact, made
/// true by any of its methods once the method's preconditions and the
/// facts of its subtasks are; an elementary operator makes its effects and
/// its own fact true. Facts: the literals (`2 × atoms`), then one per
/// operator.
pub(super) struct Composition {
    lits: usize,
    /// Per action (the elementary operators, then the methods): its
    /// preconditions, its effects and its own cost (an operator its
    /// duration and ε, a method nothing).
    pre: Vec<Vec<u32>>,
    eff: Vec<Vec<u32>>,
    own: Vec<f64>,
    /// Per fact, the actions that need it (once per occurrence).
    users: Vec<Vec<u32>>,
    /// Per operator, whether it is a task one of whose refinements may
    /// hold it again, directly or through other tasks (a cycle of the
    /// ground task decomposition graph).
    recursive: Vec<bool>,
    /// The costs from the last states evaluated, the most recent last.
    cache: std::cell::RefCell<Vec<Relaxed>>,
    /// The relaxed plan's marks, all `false` between evaluations.
    marked: std::cell::RefCell<Vec<bool>>,
    seen: std::cell::RefCell<Vec<bool>>,
}

impl Composition {
    pub(super) fn new(task: &Task<'_>) -> Composition {
        let lits = task.g.atoms.len() * 2;
        let facts = lits + task.ops.len();
        let (mut pre, mut eff, mut own) = (Vec::new(), Vec::new(), Vec::new());
        for (o, op) in task.ops.iter().enumerate() {
            if op.is_abstract || op.dead {
                continue;
            }
            pre.push(op.conds.iter().map(|c| c.lit).collect());
            eff.push(op.effs.iter().map(|e| e.lit).chain([(lits + o) as u32]).collect());
            own.push(op.duration.unwrap_or(0.0) + EPS);
        }
        for m in &task.methods {
            let p: Vec<u32> = m
                .pre
                .iter()
                .map(|c| c.lit)
                .chain(m.subtasks.iter().map(|&(_, s)| (lits as u32) + s))
                .collect();
            pre.push(p);
            eff.push(vec![(lits as u32) + m.task]);
            own.push(0.0);
        }
        let mut users = vec![Vec::new(); facts];
        for (a, p) in pre.iter().enumerate() {
            for &f in p {
                users[f as usize].push(a as u32);
            }
        }
        Composition {
            recursive: super::super::heuristic::recursive_tasks(task),
            lits,
            pre,
            eff,
            own,
            users,
            cache: Default::default(),
            marked: Default::default(),
            seen: Default::default(),
        }
    }
}

impl Search<'_, '_> {
    /// `h` and the effort of a plan grown from its front: pandaPI's RC2
    /// with FF, from the state after the committed steps. The relaxed plan
    /// (each fact's cheapest supporter, h_add's, from that state) that
    /// makes true the fact of every step not committed and every unrefined
    /// abstract step, and the goal; `h` the cost of its elementary
    /// operators, the effort its actions. A task several steps of the plan
    /// share counts once in it: each further step adds the task's h_add.
    /// `INFINITY` when one of them cannot be reached even so: no order of
    /// what is left runs from that state, and the plan is dead. A
    /// progression planner's heuristic reads the state it reached: the
    /// estimates from the initial state told a truck's `get-to` apart by
    /// where the truck starts, not where it is.
    ///
    /// The composition's costs from a state are kept for the last
    /// [`RELAXED_STATES`] states ([`Relaxed`]), and computed only as far as
    /// the goals asked so far: the refinements of a plan's abstract step
    /// leave its state as it was, and the costs from it serve them all.
    pub(super) fn front_estimate(&self, p: &Plan, view: &View) -> (f64, f64) {
        let Some(comp) = &self.composition else { return (0.0, 0.0) };
        let task = self.task;
        // The goals: the facts of what is left, and the goal's literals.
        let mut goals: Vec<u32> = view
            .rest
            .iter()
            .chain(p.abstracts.iter())
            .filter_map(|&s| p.op_of(s))
            .map(|o| (comp.lits as u32) + o)
            .collect();
        goals.extend(p.open.iter().filter(|o| o.step == GOAL).map(|o| o.lit));
        goals.sort_unstable();
        let state = state_key(task, &view.prefix);
        let mut cache = comp.cache.borrow_mut();
        let mut r = match cache.iter().position(|r| r.state == state) {
            Some(i) => cache.remove(i),
            None => {
                let mut r = if cache.len() < RELAXED_STATES { Relaxed::default() } else { cache.remove(0) };
                r.start(comp, task, &view.prefix, state);
                r
            }
        };
        r.reach(comp, &goals);
        let (cost, best) = (&r.cost, &r.best);
        let (mut h, mut effort) = (0.0, 0.0);
        for w in goals.windows(2) {
            if w[0] == w[1] {
                h += cost[w[0] as usize];
            }
        }
        goals.dedup();
        let mut marked = comp.marked.borrow_mut();
        let mut seen = comp.seen.borrow_mut();
        marked.resize(comp.pre.len(), false);
        seen.resize(comp.users.len(), false);
        let (mut marks, mut sights) = (Vec::new(), Vec::new());
        let mut stack = goals;
        let mut dead = false;
        while let Some(f) = stack.pop() {
            let f = f as usize;
            if seen[f] || cost[f] == 0.0 && best[f] == u32::MAX {
                continue;
            }
            seen[f] = true;
            sights.push(f);
            let a = best[f];
            if a == u32::MAX {
                dead = true;
                break;
            }
            let a = a as usize;
            if !marked[a] {
                marked[a] = true;
                marks.push(a);
                h += comp.own[a];
                effort += 1.0;
                stack.extend_from_slice(&comp.pre[a]);
            }
        }
        for f in sights {
            seen[f] = false;
        }
        for a in marks {
            marked[a] = false;
        }
        cache.push(r);
        if dead {
            return (f64::INFINITY, f64::INFINITY);
        }
        (h, effort + p.threats.len() as f64)
    }
}

/// The states whose relaxed composition's costs the search keeps
/// ([`Search::front_estimate`]).
const RELAXED_STATES: usize = 8;

/// The state after a prefix: the atoms whose value differs from the
/// initial one (`atom × 2 + value`), in order.
fn state_key(task: &Task<'_>, prefix: &Prefix) -> Vec<u32> {
    let mut key: Vec<u32> = prefix
        .last
        .iter()
        .filter(|&(&a, &(_, _, v))| task.holds_initially(lit(a, false)) != v)
        .map(|(&a, &(_, _, v))| (a << 1) | v as u32)
        .collect();
    key.sort_unstable();
    key
}

/// The relaxed composition evaluated from one state (h_add's costs, each
/// fact's cheapest supporter), as far as the goals asked so far need: a
/// Dijkstra search over the facts that stops once they are all settled
/// and goes on from there for further goals. The costs of the facts it
/// settled are those of a search run to its end.
#[derive(Default)]
struct Relaxed {
    state: Vec<u32>,
    cost: Vec<f64>,
    best: Vec<u32>,
    settled: Vec<bool>,
    /// Per action, the preconditions not settled yet, and the sum of the
    /// costs of those settled.
    left: Vec<u32>,
    sum: Vec<f64>,
    heap: std::collections::BinaryHeap<std::cmp::Reverse<(Cost, u32)>>,
}

impl Relaxed {
    /// Starts from `state` (the state after `prefix`), reusing the memory.
    fn start(&mut self, comp: &Composition, task: &Task<'_>, prefix: &Prefix, state: Vec<u32>) {
        let facts = comp.users.len();
        self.state = state;
        self.cost.clear();
        self.cost.resize(facts, f64::INFINITY);
        self.best.clear();
        self.best.resize(facts, u32::MAX);
        self.settled.clear();
        self.settled.resize(facts, false);
        self.left.clear();
        self.left.extend(comp.pre.iter().map(|p| p.len() as u32));
        self.sum.clear();
        self.sum.resize(comp.pre.len(), 0.0);
        let mut heap = std::mem::take(&mut self.heap).into_vec();
        heap.clear();
        for a in 0..(comp.lits / 2) as u32 {
            let l = lit(a, false);
            let l = if prefix.holds(task, l) { l } else { l ^ 1 };
            self.cost[l as usize] = 0.0;
            heap.push(std::cmp::Reverse((Cost(0.0), l)));
        }
        self.heap = heap.into();
        for a in 0..comp.pre.len() {
            if self.left[a] == 0 {
                self.fire(comp, a, 0.0);
            }
        }
    }

    /// Action `a` reached at cost `c` (its preconditions'): its effects.
    fn fire(&mut self, comp: &Composition, a: usize, c: f64) {
        let c = c + comp.own[a];
        for &e in &comp.eff[a] {
            if c < self.cost[e as usize] {
                self.cost[e as usize] = c;
                self.best[e as usize] = a as u32;
                self.heap.push(std::cmp::Reverse((Cost(c), e)));
            }
        }
    }

    /// Goes on until every fact of `goals` is settled, or none is left to
    /// settle (those not settled then cannot be reached).
    fn reach(&mut self, comp: &Composition, goals: &[u32]) {
        let mut waiting = goals.iter().filter(|&&g| !self.settled[g as usize]).count();
        while waiting > 0 {
            let Some(std::cmp::Reverse((Cost(c), f))) = self.heap.pop() else { return };
            if self.settled[f as usize] || c > self.cost[f as usize] {
                continue;
            }
            self.settled[f as usize] = true;
            for &a in &comp.users[f as usize] {
                let a = a as usize;
                self.left[a] -= 1;
                self.sum[a] += c;
                if self.left[a] == 0 {
                    let s = self.sum[a];
                    self.fire(comp, a, s);
                }
            }
            // A goal several steps share is counted as often (`goals` is
            // sorted).
            waiting -= goals.partition_point(|&g| g <= f) - goals.partition_point(|&g| g < f);
        }
    }
}

/// A cost ordered totally, for the heap.
#[derive(Clone, Copy)]
struct Cost(f64);

impl PartialEq for Cost {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}

impl Eq for Cost {}

impl PartialOrd for Cost {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Cost {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::Config;
    use super::super::super::plan::Plan;
    use super::super::Flaw;
    use super::super::test_support::{refined_by, with_search_as};
    use rustc_hash::FxHashMap;

    /// A truck at `a` goes to `b`, then to `c`. `here` needs the truck at
    /// the place already; `drive` needs it where it starts.
    const DOMAIN: &str = "(define (domain d) (:requirements :hierarchy :typing)
      (:types place)
      (:predicates (at ?p - place) (road ?a ?b - place))
      (:task tour :parameters ())
      (:task get-to :parameters (?p - place))
      (:method m-tour :parameters () :task (tour)
        :ordered-subtasks (and (get-to b) (get-to c)))
      (:method by-road :parameters (?a ?b - place) :task (get-to ?b) :subtasks (drive ?a ?b))
      (:method here :parameters (?p - place) :task (get-to ?p) :precondition (at ?p) :subtasks (noop ?p))
      (:action drive :parameters (?a ?b - place)
        :precondition (and (at ?a) (road ?a ?b)) :effect (and (not (at ?a)) (at ?b)))
      (:action noop :parameters (?p - place) :precondition (at ?p) :effect ()))";
    const PROBLEM: &str = "(define (problem p) (:domain d)
      (:objects a b c - place)
      (:htn :subtasks (and (tour)))
      (:init (at a) (road a b) (road b c) (road c b)))";

    /// The front of the tour is its first `get-to`: refined into a drive
    /// from `a` (the truck is there) or from `c` (where it is not yet),
    /// never into `here`, whose precondition does not hold at the front.
    /// The drive from `a` is committed next, its conditions linked to the
    /// initial state; the drive from `c` can run nowhere next, and the
    /// second `get-to` waits for the first: that plan is dead.
    #[test]
    fn a_plan_grows_from_its_front_with_the_steps_that_run_there() {
        let config = Config::parse("AR-time-local-motion-front").expect("a configuration");
        with_search_as(config, ("domain.hddl", "problem.hddl"), DOMAIN, PROBLEM, |prepared, search| {
            let task = &prepared.task;
            assert!(search.at_front());
            let mut tour = refined_by(prepared, search, "m-tour");
            let Some(Flaw::Front(Some(i))) = search.select(&mut tour) else { panic!("a get-to to refine") };
            let get_to = tour.abstracts[i];
            assert_eq!(task.show_op(tour.op_of(get_to).expect("an op")), "(get-to b)");
            let mut children = Vec::new();
            search.resolvers(&tour, Flaw::Front(Some(i)), &mut children);
            let drive_of = |p: &Plan| {
                (0..p.steps.len() as u32)
                    .filter_map(|s| p.op_of(s).map(|o| (s, task.show_op(o))))
                    .find(|(_, name)| name.starts_with("(drive"))
            };
            let mut names: Vec<String> = children.iter().filter_map(|c| drive_of(c).map(|d| d.1)).collect();
            names.sort();
            assert_eq!(names, ["(drive a b)", "(drive c b)"]);
            assert_eq!(children.len(), 2, "no `here`: the truck is not at b");
            for mut c in children {
                let (drive, name) = drive_of(&c).expect("a drive");
                let flaw = search.select(&mut c);
                if name == "(drive c b)" {
                    assert!(matches!(flaw, Some(Flaw::Dead)), "nothing can come next");
                    continue;
                }
                let Some(Flaw::Front(None)) = flaw else { panic!("the drive to commit") };
                let mut next = Vec::new();
                search.resolvers(&c, Flaw::Front(None), &mut next);
                assert_eq!(next.len(), 1);
                let done = &next[0];
                assert_eq!(done.front, done.steps[drive as usize].start);
                assert!(done.open.iter().all(|o| o.step != drive), "its conditions are linked");
                assert!(
                    done.links.iter().filter(|l| l.to == drive).all(|l| l.from == 0),
                    "to the initial state"
                );
            }
        });
    }

    /// The walk of a plan grown from its front starts after its committed
    /// steps, from the state they leave: on every plan of the search's
    /// tree, it says what the walk of all its steps from the initial state
    /// says.
    #[test]
    fn the_walk_from_the_front_agrees_with_the_walk_from_the_start() {
        let config = Config::parse("AR-time-local-motion-front").expect("a configuration");
        with_search_as(config, ("domain.hddl", "problem.hddl"), DOMAIN, PROBLEM, |prepared, search| {
            let mut todo = vec![refined_by(prepared, search, "m-tour")];
            let (mut checked, mut committed) = (0, 0);
            while let Some(mut p) = todo.pop() {
                let view = search.view(&p);
                assert_eq!(search.unrunnable(&p, Some(&view)), search.unrunnable(&p, None));
                checked += 1;
                committed += usize::from(view.committed > 0);
                let Some(flaw @ Flaw::Front(_)) = search.select(&mut p) else { continue };
                search.resolvers(&p, flaw, &mut todo);
            }
            assert!(checked >= 5 && committed >= 2, "{checked} plans, {committed} with committed steps");
        });
    }

    /// A truck at `a` goes to `c`, by a road through `b`, and a photo is
    /// taken at `a`, in either order: `get-to` is recursive (`via` holds
    /// another `get-to`).
    const ROUTE: &str = "(define (domain route) (:requirements :hierarchy :typing)
      (:types place)
      (:predicates (at ?p - place) (road ?a ?b - place) (seen ?p - place))
      (:task tour :parameters ())
      (:task get-to :parameters (?p - place))
      (:task look :parameters (?p - place))
      (:method m-tour :parameters () :task (tour) :subtasks (and (look a) (get-to c)))
      (:method direct :parameters (?a ?b - place) :task (get-to ?b) :subtasks (drive ?a ?b))
      (:method via :parameters (?a ?b - place) :task (get-to ?b)
        :ordered-subtasks (and (get-to ?a) (drive ?a ?b)))
      (:method m-look :parameters (?p - place) :task (look ?p) :subtasks (snap ?p))
      (:action drive :parameters (?a ?b - place)
        :precondition (and (at ?a) (road ?a ?b)) :effect (and (not (at ?a)) (at ?b)))
      (:action snap :parameters (?p - place) :precondition (at ?p) :effect (seen ?p)))";
    const ROUTE_PROBLEM: &str = "(define (problem p) (:domain route)
      (:objects a b c - place)
      (:htn :subtasks (and (tour)))
      (:init (at a) (road a b) (road b a) (road b c) (road c b)))";

    /// Once `get-to c` is refined into the route `a`, `b`, `c`, the route
    /// runs to its end before `look a` is refined: the front of the plan
    /// with the first drive to commit is that drive alone. Before the
    /// route is refined, both tasks are in the front.
    #[test]
    fn a_recursion_under_way_runs_to_its_end_before_other_tasks() {
        let config = Config::parse("AR-time-local-motion-front").expect("a configuration");
        with_search_as(config, ("domain.hddl", "problem.hddl"), ROUTE, ROUTE_PROBLEM, |prepared, search| {
            let task = &prepared.task;
            let names = |p: &Plan| -> Vec<String> {
                (0..p.steps.len() as u32).filter_map(|s| p.op_of(s).map(|o| task.show_op(o))).collect()
            };
            let method_of = |p: &Plan, name: &str| {
                (0..p.steps.len())
                    .find(|&s| p.op_of(s as u32).is_some_and(|o| task.show_op(o) == name))
                    .and_then(|s| p.steps[s].method)
                    .map(|m| task.methods[m as usize].name.to_string())
            };
            let tour = refined_by(prepared, search, "m-tour");
            let view = search.view(&tour);
            assert_eq!(view.abstracts.len(), 2, "get-to c and look a, before the route is chosen");
            // Every plan of the search's tree, until the one with the route
            // refined to its end (`via b`, then `direct` from `a`), its first
            // drive not committed, and `look a` not refined.
            let mut todo = vec![tour];
            let mut under_way = None;
            while let Some(mut p) = todo.pop() {
                let n = names(&p);
                let unrefined: Vec<String> =
                    p.abstracts.iter().map(|&a| task.show_op(p.op_of(a).expect("an op"))).collect();
                if method_of(&p, "(get-to c)").as_deref() == Some("via")
                    && method_of(&p, "(get-to b)").as_deref() == Some("direct")
                    && n.iter().any(|x| x == "(drive a b)")
                    && unrefined.iter().any(|x| x == "(look a)")
                    && search.view(&p).committed == 0
                {
                    under_way = Some(p);
                    break;
                }
                let Some(flaw @ Flaw::Front(_)) = search.select(&mut p) else { continue };
                search.resolvers(&p, flaw, &mut todo);
            }
            let mut p = under_way.expect("the route refined before anything is committed");
            let Some(flaw @ Flaw::Front(refine)) = search.select(&mut p) else { panic!("a front") };
            assert_eq!(refine, None, "look a waits for the route");
            let mut children = Vec::new();
            search.resolvers(&p, flaw, &mut children);
            assert_eq!(children.len(), 1, "the first drive only");
            let view = search.view(&children[0]);
            assert_eq!(view.committed, 1);
            assert!(
                children[0]
                    .abstracts
                    .iter()
                    .any(|&a| task.show_op(children[0].op_of(a).expect("op")) == "(look a)")
            );
        });
    }

    /// Two tasks that do not interfere, unordered: `a` and `b` each make
    /// their own fact.
    const TWO: &str = "(define (domain two) (:requirements :hierarchy)
      (:predicates (done-a) (done-b))
      (:task top :parameters ())
      (:task ta :parameters ())
      (:task tb :parameters ())
      (:method m-top :parameters () :task (top) :subtasks (and (ta) (tb)))
      (:method m-a :parameters () :task (ta) :subtasks (a))
      (:method m-b :parameters () :task (tb) :subtasks (b))
      (:action a :parameters () :effect (done-a))
      (:action b :parameters () :effect (done-b)))";
    const TWO_PROBLEM: &str = "(define (problem p) (:domain two)
      (:htn :subtasks (and (top)))
      (:init))";

    /// Every plan grown from the front of `top`'s refinement: refining `tb`
    /// then committing `b` then refining `ta` leaves what refining both
    /// then committing `b` leaves (the state `done-b`, the step `a` left),
    /// and both orders of the two steps end in the same state with nothing
    /// left: the same key. A plan with `a` committed and one with `b`
    /// committed have different keys; so have two plans with the same
    /// state and a task left unrefined in one, refined in the other.
    #[test]
    fn plans_with_the_same_state_and_network_left_have_the_same_key() {
        let config = Config::parse("AR-time-local-motion-front").expect("a configuration");
        with_search_as(config, ("domain.hddl", "problem.hddl"), TWO, TWO_PROBLEM, |prepared, search| {
            let task = &prepared.task;
            let top = refined_by(prepared, search, "m-top");
            // Each plan reached, with what it committed (in order) and what
            // it left.
            let committed = |p: &Plan| {
                let mut done: Vec<(f64, String)> = (0..p.steps.len() as u32)
                    .filter(|&s| search.committed(p, s))
                    .map(|s| (p.stn.est(p.steps[s as usize].start), task.show_op(p.op_of(s).expect("an op"))))
                    .collect();
                done.sort_by(|x, y| x.0.total_cmp(&y.0));
                done.into_iter().map(|(_, n)| n).collect::<Vec<_>>().join(" ")
            };
            let mut by_key: FxHashMap<Box<[u32]>, Vec<(String, usize)>> = FxHashMap::default();
            let mut todo = vec![top];
            let mut plans = Vec::new();
            while let Some(mut p) = todo.pop() {
                p.stn.flush();
                let key = search.front_key(&p).expect("no threats");
                by_key.entry(key).or_default().push((committed(&p), p.abstracts.len()));
                let Some(flaw) = search.select(&mut p) else { continue };
                let mut children = Vec::new();
                search.resolvers(&p, flaw, &mut children);
                todo.extend(children);
                plans.push((committed(&p), p.abstracts.len(), p));
            }
            let keys_of = |done: &str, unrefined: usize| -> Vec<&Box<[u32]>> {
                by_key
                    .iter()
                    .filter(|(_, plans)| plans.iter().any(|(d, u)| d == done && *u == unrefined))
                    .map(|(k, _)| k)
                    .collect()
            };
            // Both committed, in either order: one key for both.
            let both = keys_of("(a) (b)", 0);
            assert_eq!(both, keys_of("(b) (a)", 0));
            assert_eq!(both.len(), 1);
            // `b` committed, `a` left, reached two ways (`ta` refined
            // before or after `b` was committed): one key.
            let b_then = by_key.values().find(|plans| plans.iter().any(|(d, u)| d == "(b)" && *u == 0));
            assert!(b_then.is_some_and(|plans| plans.len() >= 2), "{by_key:?}");
            // Different states, or a task refined in one and not the other.
            assert_ne!(keys_of("(a)", 0), keys_of("(b)", 0));
            assert_ne!(keys_of("(b)", 0), keys_of("(b)", 1));
            // The search records a plan, and drops one with its key unless
            // its schedule is shorter.
            let mut plans = plans.into_iter();
            let (_, _, b_first) = plans.find(|(d, u, _)| d == "(b)" && *u == 0).expect("b committed");
            let (_, _, b_again) = {
                let key = search.front_key(&b_first);
                plans.find(|(d, u, p)| d == "(b)" && *u == 0 && search.front_key(p) == key).expect("again")
            };
            assert!(!search.front_known(&b_first, 1.0));
            assert!(search.front_record(&b_first, 1.0));
            assert!(search.front_known(&b_again, 1.0));
            assert!(!search.front_record(&b_again, 1.0));
            assert!(!search.front_known(&b_again, 0.5));
            assert!(search.front_record(&b_again, 0.5));
        });
    }
}
