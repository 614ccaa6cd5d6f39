//! The orders in which a hierarchical plan can run from the initial
//! state. In a problem where no step is ever inserted, every step a plan
//! will ever have is one of its steps or comes from refining one of its
//! unrefined abstract steps, between that step's start and end. So every
//! run of a plan it leads to goes through the plan's own elementary steps
//! in an order its network allows, with the steps that refinements bring
//! in somewhere between the start and the end of their abstract step.
//!
//! [`Search::unrunnable`] goes through those orders, depth first, over a
//! state of three values (true, false, unknown) that starts as the initial
//! state: the next point is one of those left that nothing left must
//! precede, an elementary step (run when its conditions are not known
//! false: its effects become known, unless an abstract step that may
//! change the atom is open), or the start of an unrefined abstract step
//! (from it on, what its refinements may change is unknown) or its end.
//! Every known value is the one any run of a later plan has at that point,
//! so a run of a later plan is one of the orders walked. An order where no
//! point can come next is a dead end; when every order is a dead end, so
//! is the plan, whatever the links, orderings and refinements chosen
//! later. The relaxed checks of [`super::tokens`] (deletions ignored, or
//! one literal at a time) cannot see this: an IPC 2020 Transport truck
//! refined to drive from a city it is not in at that point of its tour,
//! where it is at another point, is reached in the relaxation, and the
//! search found the tour wrong only once every way to link and order the
//! truck's stops around it had been tried. A progression planner sees it
//! in the state it reaches.
//!
//! Opening an abstract step, or running a step without effects, as soon
//! as it may come next loses no order (less is known after it, or nothing
//! changes). The orders are many when few steps are ordered: the walk
//! gives up after [`BUDGET_BASE`] plus [`BUDGET_PER_STEP`] prefixes per
//! point (the plan is kept), and a prefix seen with the same state is not
//! walked again.

use rustc_hash::FxHashSet;

use super::super::plan::{Kind, Plan};
use super::super::stn::{ORIGIN, Tp};
use super::super::task::{atom_of, is_neg, lit};
use super::Search;
use super::front::View;

/// Prefixes visited per step of the plan, beyond [`BUDGET_BASE`], before
/// the walk gives up and keeps the plan.
const BUDGET_PER_STEP: usize = 2;
const BUDGET_BASE: usize = 16;

/// Walks before the walk is judged: from then on it runs only while it
/// drops at least one plan in [`TRIAL_RATE`]. On IPC 2020 Rover, whose
/// plans have many steps and few orderings, most walks gave up and the
/// search expanded a third as many plans per second.
const TRIAL: u64 = 2000;
const TRIAL_RATE: u64 = 50;

/// What a point of the walk is.
#[derive(Clone, Copy, PartialEq, Eq)]
enum What {
    /// An elementary step.
    Step,
    /// The start of an unrefined abstract step: from it on, what its
    /// refinements may change is unknown.
    Opens,
    /// Its end: nothing it brings in comes after.
    Closes,
}

/// A time point the walk orders, with the conditions and effects of an
/// elementary step over the atoms the walk follows, or the atoms the
/// refinements of an unrefined abstract step may change.
struct Point {
    tp: Tp,
    what: What,
    /// Conditions: atom (the walk's index) and the value it must have.
    conds: Vec<(usize, bool)>,
    /// Effects: deletions first, then additions (PDDL's order); for an
    /// abstract step, the atoms its refinements may change.
    effs: Vec<(usize, bool)>,
    /// An abstract step's start: the index of its end.
    end: usize,
}

/// Bit sets over the walk's atoms and points (and the closure's rows read
/// by [`super::flaws`]).
pub(super) fn get(bits: &[u64], i: usize) -> bool {
    bits[i / 64] >> (i % 64) & 1 == 1
}

fn set(bits: &mut [u64], i: usize, v: bool) {
    if v {
        bits[i / 64] |= 1 << (i % 64);
    } else {
        bits[i / 64] &= !(1 << (i % 64));
    }
}

/// The state of a prefix: which atoms are known, and their values.
#[derive(Clone, PartialEq, Eq, Hash)]
struct State {
    known: Vec<u64>,
    value: Vec<u64>,
    /// How many open abstract steps may change each atom.
    open: Vec<u32>,
}

impl State {
    /// A condition fails only where the atom is known otherwise.
    fn allows(&self, conds: &[(usize, bool)]) -> bool {
        conds.iter().all(|&(a, v)| !get(&self.known, a) || get(&self.value, a) == v)
    }

    fn run(&mut self, p: &Point) {
        match p.what {
            What::Step => {
                for &(a, v) in &p.effs {
                    // An open abstract step may change it before or after.
                    set(&mut self.known, a, self.open[a] == 0);
                    set(&mut self.value, a, v);
                }
            }
            What::Opens => {
                for &(a, _) in &p.effs {
                    self.open[a] += 1;
                    set(&mut self.known, a, false);
                }
            }
            What::Closes => {
                for &(a, _) in &p.effs {
                    self.open[a] -= 1;
                }
            }
        }
    }
}

impl Search<'_, '_> {
    /// Whether no order of the plan's steps that its network allows can run
    /// from the initial state, as the module says. Only in a problem where
    /// no step is ever inserted, with instantaneous actions and no timed
    /// literals, and not in a repair (whose old steps ran from another
    /// state). `false` when the walk gives up.
    pub(super) fn unrunnable(&self, p: &Plan, view: Option<&View>) -> bool {
        let task = self.task;
        if self.tokens.is_none() || self.from_seeds.get() || !task.tils.is_empty() {
            return false;
        }
        let (walks, dropped) = self.walks.get();
        if walks >= TRIAL && dropped * TRIAL_RATE < walks {
            return false;
        }
        let dead = self.walk(p, view);
        self.walks.set((walks + 1, dropped + dead as u64));
        dead
    }

    /// [`Search::unrunnable`]'s walk; `view`, the front of a plan grown
    /// from its front.
    fn walk(&self, p: &Plan, view: Option<&View>) -> bool {
        let task = self.task;
        // Grown from its front, the committed steps run first, in their
        // order, before every step left: the walk starts after them, from
        // the state they leave.
        let front = view.filter(|_| p.front != ORIGIN);
        let mut left = vec![front.is_none(); p.steps.len()];
        for &s in front.iter().flat_map(|v| &v.rest) {
            left[s as usize] = true;
        }
        let walked = |s: usize| left[s];
        // The atoms the elementary steps read or write, numbered.
        let mut atoms: Vec<u32> = Vec::new();
        let mut elementary = 0usize;
        for (s, step) in p.steps.iter().enumerate() {
            let Kind::Op(o) = step.kind else { continue };
            let op = &task.ops[o as usize];
            if !op.is_abstract && !walked(s) {
                continue;
            }
            if op.is_abstract {
                // A refined abstract action's own effects: not followed.
                if !op.effs.is_empty() && !p.abstracts.contains(&(s as u32)) {
                    return false;
                }
                continue;
            }
            if !op.instant {
                return false;
            }
            elementary += 1;
            atoms.extend(op.conds.iter().map(|c| atom_of(c.lit)));
            atoms.extend(op.effs.iter().map(|e| atom_of(e.lit)));
        }
        if elementary == 0 {
            return false;
        }
        atoms.sort_unstable();
        atoms.dedup();
        let index = |a: u32| atoms.binary_search(&a).expect("an atom of the plan");
        let mut points: Vec<Point> = Vec::new();
        for (s, step) in p.steps.iter().enumerate() {
            let Kind::Op(o) = step.kind else { continue };
            let op = &task.ops[o as usize];
            if op.is_abstract || !walked(s) {
                continue;
            }
            let conds = op.conds.iter().map(|c| (index(atom_of(c.lit)), !is_neg(c.lit))).collect();
            let mut effs: Vec<(usize, bool)> =
                op.effs.iter().map(|e| (index(atom_of(e.lit)), !is_neg(e.lit))).collect();
            effs.sort_by_key(|&(_, v)| v);
            points.push(Point { tp: step.start, what: What::Step, conds, effs, end: 0 });
        }
        for &a in p.abstracts.iter() {
            let step = p.steps[a as usize];
            let Kind::Op(o) = step.kind else { continue };
            let op = &task.ops[o as usize];
            let changes: Vec<(usize, bool)> = atoms
                .iter()
                .enumerate()
                .filter(|&(_, &x)| {
                    [false, true].into_iter().any(|neg| {
                        let l = lit(x, neg);
                        self.h.may_add(o, l) || op.effs.iter().any(|e| e.lit == l)
                    })
                })
                .map(|(i, _)| (i, true))
                .collect();
            let end = points.len() + 1;
            points.push(Point {
                tp: step.start,
                what: What::Opens,
                conds: Vec::new(),
                effs: changes.clone(),
                end,
            });
            points.push(Point { tp: step.end, what: What::Closes, conds: Vec::new(), effs: changes, end: 0 });
        }
        let n = points.len();
        // What must come before what (strictly: not forced to the same
        // time); an abstract step's end after its start.
        // The closure's row of each point, read once ([`Stn::preceding`]:
        // `before(x, y)` is bit `x` of `y`'s row): one call of
        // [`Stn::before`] per pair, each through the orderings that wait,
        // was most of the walk on plans of hundreds of steps.
        let mut rows: Vec<u64> = Vec::new();
        let width = p.stn.len().div_ceil(64);
        let mut row = Vec::new();
        for pt in &points {
            p.stn.preceding(pt.tp, &mut row);
            rows.extend_from_slice(&row);
        }
        let before = |x: &Point, y: usize| get(&rows[y * width..(y + 1) * width], x.tp as usize);
        let mut waits = vec![0u32; n];
        let mut blocks: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (x, px) in points.iter().enumerate() {
            for (y, py) in points.iter().enumerate() {
                let own = px.what == What::Opens && px.end == y;
                if x != y && (own || before(px, y) && !before(py, x)) {
                    blocks[x].push(y as u32);
                    waits[y] += 1;
                }
            }
        }
        let words = atoms.len().div_ceil(64);
        let mut state =
            State { known: vec![u64::MAX; words], value: vec![0; words], open: vec![0; atoms.len()] };
        for (i, &a) in atoms.iter().enumerate() {
            let holds = match front {
                Some(view) => view.prefix.holds(task, lit(a, false)),
                None => task.init.get(a as usize).copied().unwrap_or(false),
            };
            set(&mut state.value, i, holds);
        }
        let mut done = vec![0u64; n.div_ceil(64)];
        // The points not run that wait for nothing left (kept as points
        // run and are undone: a scan of every point at each prefix cost
        // the walk a time quadratic in the plan's size).
        let mut free = vec![0u64; n.div_ceil(64)];
        for (i, &w) in waits.iter().enumerate() {
            set(&mut free, i, w == 0);
        }
        let mut run_count = 0usize;
        // The prefixes seen: the points run and the state's known atoms and
        // values (how many open abstract steps may change each atom follows
        // from the points run).
        let mut seen: FxHashSet<Vec<u64>> = FxHashSet::default();
        // The committed steps count as they did when the walk went through
        // them, one prefix each.
        let committed = front.map_or(0, |v| v.committed);
        let mut budget = BUDGET_BASE + BUDGET_PER_STEP * n + committed;
        // A level of the walk: the points that may come next, the next to
        // try, the one run from it (to undo) and the state before it.
        struct Level {
            next: Vec<u32>,
            at: usize,
            ran: Option<u32>,
            before: State,
        }
        let mut stack: Vec<Level> = Vec::new();
        // The prefix at hand: `Err(true)` when it may lead to a plan (or
        // the walk gives up), `Err(false)` when it was seen already, else
        // the points that may come next (none: a dead end).
        let mut visit = |state: &State, done: &[u64], free: &[u64], run_count: usize, budget: &mut usize| {
            if *budget == 0 {
                return Err(true);
            }
            *budget -= 1;
            let mut key = Vec::with_capacity(done.len() + 2 * state.known.len());
            key.extend_from_slice(done);
            key.extend_from_slice(&state.known);
            key.extend_from_slice(&state.value);
            if !seen.insert(key) {
                return Err(false);
            }
            if run_count == n || free.iter().all(|&w| w == 0) {
                // Every point run, or points forced to the same time only.
                return Err(true);
            }
            let mut next = Vec::new();
            for (k, &word) in free.iter().enumerate() {
                let mut bits = word;
                while bits != 0 {
                    let i = k * 64 + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let pt = &points[i];
                    match pt.what {
                        // Opening an abstract step early only makes less
                        // known, and what waits for it free sooner: at once.
                        What::Opens => return Ok(vec![i as u32]),
                        // A step without effects that can run changes
                        // nothing and only frees what waits for it: at once.
                        What::Step if pt.effs.is_empty() && state.allows(&pt.conds) => {
                            return Ok(vec![i as u32]);
                        }
                        What::Step if !state.allows(&pt.conds) => {}
                        _ => next.push(i as u32),
                    }
                }
            }
            Ok(next)
        };
        match visit(&state, &done, &free, run_count, &mut budget) {
            Err(alive) => return !alive,
            Ok(next) => stack.push(Level { next, at: 0, ran: None, before: state.clone() }),
        }
        loop {
            let Some(top) = stack.last_mut() else { return true };
            if let Some(r) = top.ran.take() {
                set(&mut done, r as usize, false);
                run_count -= 1;
                for &y in &blocks[r as usize] {
                    waits[y as usize] += 1;
                    set(&mut free, y as usize, false);
                }
                set(&mut free, r as usize, waits[r as usize] == 0);
                state.clone_from(&top.before);
            }
            if top.at == top.next.len() {
                stack.pop();
                continue;
            }
            let r = top.next[top.at];
            top.at += 1;
            top.ran = Some(r);
            set(&mut done, r as usize, true);
            run_count += 1;
            set(&mut free, r as usize, false);
            for &y in &blocks[r as usize] {
                waits[y as usize] -= 1;
                set(&mut free, y as usize, waits[y as usize] == 0 && !get(&done, y as usize));
            }
            state.run(&points[r as usize]);
            match visit(&state, &done, &free, run_count, &mut budget) {
                Err(true) => return false,
                Err(false) => {}
                Ok(next) => stack.push(Level { next, at: 0, ran: None, before: state.clone() }),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    /// `leave` takes the truck from `a` to `b`, `look` needs it at `a`,
    /// `both` at `a` and at `b` at once; `more` may bring it back.
    const DOMAIN: &str = "(define (domain d) (:requirements :hierarchy :negative-preconditions)
      (:predicates (at-a) (at-b))
      (:task job :parameters ())
      (:task more :parameters ())
      (:method bad :parameters () :task (job) :ordered-subtasks (and (leave) (look)))
      (:method good :parameters () :task (job) :ordered-subtasks (and (look) (leave)))
      (:method back :parameters () :task (job) :ordered-subtasks (and (leave) (more) (look)))
      (:method apart :parameters () :task (job) :subtasks (and (leave) (both)))
      (:method come-back :parameters () :task (more) :subtasks (and (come)))
      (:action leave :parameters () :precondition (at-a) :effect (and (not (at-a)) (at-b)))
      (:action come :parameters () :precondition (at-b) :effect (and (not (at-b)) (at-a)))
      (:action look :parameters () :precondition (at-a) :effect ())
      (:action both :parameters () :precondition (and (at-a) (at-b)) :effect ()))";

    /// A plan whose steps each have a supporter in the relaxation (the
    /// initial state, or `leave`) and use up nothing twice, but that no
    /// order of its steps runs from the initial state: `look` after
    /// `leave` (`bad`), or `both`, which no state before or after `leave`
    /// satisfies (`apart`, unordered). `good` runs; in `back`, the
    /// unrefined `more` before `look` may bring the truck back.
    #[test]
    fn a_plan_no_order_of_which_runs_from_the_initial_state_is_dropped() {
        let problem = "(define (problem p) (:domain d) (:htn :subtasks (and (job))) (:init (at-a)))";
        for (method, dead) in [("bad", true), ("apart", true), ("good", false), ("back", false)] {
            super::super::test_support::with_search(
                ("domain.hddl", "problem.hddl"),
                DOMAIN,
                problem,
                move |prepared, search| {
                    let mut plan = super::super::test_support::refined_by(prepared, search, method);
                    // The relaxed checks see nothing wrong.
                    assert!(search.stuck(&plan).is_none(), "{method}");
                    assert!(search.starved(&plan).is_none(), "{method}");
                    assert_eq!(search.unrunnable(&plan, None), dead, "{method}");
                    assert_eq!(search.score(&mut plan).is_none(), dead, "{method}");
                },
            );
        }
    }
}
