//! The cost estimates HiPOP's plan selection uses (section 4.2.3):
//! h_add over the relaxed ground model (deletions ignored, sub-goals assumed
//! independent, as in VHPOP), in two units: time (an operator costs its
//! duration plus the separation ε, so that instantaneous actions cost
//! something) and effort (an operator costs 1: the tie-breaker, "the
//! approximate number of iterations to reach a solution").
//!
//! Abstract operators also get a refinement estimate, the task decomposition
//! graph's cost as hierarchical planners compute it: the cheapest method's
//! preconditions (their h_add) and subtasks, recursively (a fixpoint, since
//! methods may recurse); a method whose precondition is unreachable in the
//! relaxed model does not count.

use super::stn::EPS;
use super::task::{Eff, End, Lit, Op, Task, lit};

pub struct Heuristic {
    /// h_add of each literal in time, and in effort (`INFINITY` when unreachable).
    pub cost: Vec<f64>,
    pub effort: Vec<f64>,
    /// Estimated time and effort to refine each abstract operator.
    pub refine_cost: Vec<f64>,
    pub refine_effort: Vec<f64>,
    /// Per literal that holds initially: h_add in time and effort of making
    /// it true again with a step (its cheapest achiever's conditions and
    /// duration), for an open link that the initial state can no longer
    /// support (a step already deletes it before the need); `INFINITY`
    /// when nothing adds it. Other literals: their h_add.
    pub again_cost: Vec<f64>,
    pub again_effort: Vec<f64>,
    /// Per abstract operator: the literals its refinements may make true
    /// (sorted); `None` when the fixpoint was too large to compute, and any
    /// literal is assumed possible.
    pub may_add: Option<MayAdd>,
    /// Per operator, in a problem where no step is ever inserted: the
    /// literals that every refinement of it needs from outside
    /// ([`needs`]); `None` elsewhere, or when too large to compute.
    pub needs: Option<Vec<Vec<Lit>>>,
}

impl Heuristic {
    pub fn new(task: &Task<'_>) -> Heuristic {
        let n = task.g.atoms.len() * 2;
        let mut cost = vec![f64::INFINITY; n];
        let mut effort = vec![f64::INFINITY; n];
        for a in 0..task.g.atoms.len() as u32 {
            let l = if task.init[a as usize] { lit(a, false) } else { lit(a, true) };
            cost[l as usize] = 0.0;
            effort[l as usize] = 0.0;
        }
        for t in &task.tils {
            cost[t.lit as usize] = cost[t.lit as usize].min(t.time);
            effort[t.lit as usize] = 0.0;
        }
        // h_add: iterate to the fixpoint (Bellman–Ford style), over what the
        // planner may insert (𝒜) when it may insert anything, since that is
        // how open links get closed; over every operator in pure HTN.
        let restrict = task.ops.iter().any(|o| o.allowed);
        let mut changed = true;
        let mut rounds = 0;
        while changed && rounds < 256 {
            changed = false;
            rounds += 1;
            for op in task.ops.iter() {
                if op.dead || (restrict && !op.allowed) || (op.is_abstract && op.methods.is_empty()) {
                    continue;
                }
                let Some(ends) = effect_costs(op, &cost, &effort) else { continue };
                for e in &op.effs {
                    let (oc, oe) = ends[effect_end(op, e)];
                    if !oc.is_finite() {
                        continue;
                    }
                    let k = e.lit as usize;
                    if oc < cost[k] - 1e-9 {
                        cost[k] = oc;
                        changed = true;
                    }
                    if oe < effort[k] - 1e-9 {
                        effort[k] = oe;
                        changed = true;
                    }
                }
            }
        }
        // Making a literal true again: the cheapest achiever, with the
        // costs of the fixpoint (a literal that does not hold initially
        // keeps its own).
        let mut again_cost = cost.clone();
        let mut again_effort = effort.clone();
        for a in 0..task.g.atoms.len() as u32 {
            for l in [lit(a, false), lit(a, true)] {
                if task.holds_initially(l) {
                    again_cost[l as usize] = f64::INFINITY;
                    again_effort[l as usize] = f64::INFINITY;
                }
            }
        }
        for t in task.tils.iter().filter(|t| task.holds_initially(t.lit)) {
            again_cost[t.lit as usize] = again_cost[t.lit as usize].min(t.time);
            again_effort[t.lit as usize] = 0.0;
        }
        for op in task.ops.iter() {
            if op.dead || (restrict && !op.allowed) || (op.is_abstract && op.methods.is_empty()) {
                continue;
            }
            let Some(ends) = effect_costs(op, &cost, &effort) else { continue };
            for e in op.effs.iter().filter(|e| task.holds_initially(e.lit)) {
                let (oc, oe) = ends[effect_end(op, e)];
                let k = e.lit as usize;
                again_cost[k] = again_cost[k].min(oc);
                again_effort[k] = again_effort[k].min(oe);
            }
        }
        // Refinement estimates: a primitive subtask costs its duration and
        // the h_add of its conditions; a task, its cheapest method.
        let nops = task.ops.len();
        let mut refine_cost = vec![f64::INFINITY; nops];
        let mut refine_effort = vec![f64::INFINITY; nops];
        for (i, op) in task.ops.iter().enumerate() {
            if !op.is_abstract {
                let pc: f64 = op.conds.iter().map(|c| cost[c.lit as usize].min(1e6)).sum();
                let pe: f64 = op.conds.iter().map(|c| effort[c.lit as usize].min(1e6)).sum();
                refine_cost[i] = op.duration.unwrap_or(0.0) + EPS + pc;
                refine_effort[i] = 1.0 + pe;
            }
        }
        let mut changed = true;
        let mut rounds = 0;
        while changed && rounds < 64 {
            changed = false;
            rounds += 1;
            for m in &task.methods {
                // The method's preconditions (relaxed: their h_add; one
                // that cannot be reached rules the method out), then its
                // subtasks.
                // A choice (an `:htn` task's instance, a split subtask's)
                // is no method of the plan.
                let (mut c, mut e) = (0.0, if task.ops[m.task as usize].choice { 0.0 } else { 1.0 });
                for p in &m.pre {
                    c += cost[p.lit as usize];
                    e += effort[p.lit as usize];
                }
                for &(_, s) in &m.subtasks {
                    c += refine_cost[s as usize];
                    e += refine_effort[s as usize];
                }
                let t = m.task as usize;
                if c < refine_cost[t] - 1e-9 || e < refine_effort[t] - 1e-9 {
                    refine_cost[t] = refine_cost[t].min(c);
                    refine_effort[t] = refine_effort[t].min(e);
                    changed = true;
                }
            }
        }
        let graph = SubtaskGraph::of(task);
        let may_add = may_add(task, &graph);
        let needs = match &may_add {
            Some(may) if task.achievers.is_empty() && task.htn.is_some() => needs(task, &graph, may),
            _ => None,
        };
        Heuristic { cost, effort, refine_cost, refine_effort, again_cost, again_effort, may_add, needs }
    }

    pub fn lit_cost(&self, l: Lit) -> f64 {
        self.cost.get(l as usize).copied().unwrap_or(f64::INFINITY)
    }

    pub fn lit_effort(&self, l: Lit) -> f64 {
        self.effort.get(l as usize).copied().unwrap_or(f64::INFINITY)
    }

    /// Whether a literal is reachable at all in the relaxed model.
    pub fn reachable(&self, l: Lit) -> bool {
        self.lit_cost(l).is_finite()
    }

    /// The literals every refinement of operator `op` needs from outside
    /// it ([`needs`]); none when unknown.
    pub fn needs(&self, op: u32) -> &[Lit] {
        self.needs.as_ref().and_then(|n| n.get(op as usize)).map_or(&[], Vec::as_slice)
    }

    /// Whether refining abstract operator `op` may make `l` true.
    pub fn may_add(&self, op: u32, l: Lit) -> bool {
        match &self.may_add {
            Some(m) => m.contains(op, l),
            None => true,
        }
    }
}

/// What an operator's effects cost in time and effort, from the costs of
/// its conditions: `[0]` an effect at its start (what the start needs, ε,
/// one action), `[1]` one at its end (every condition but those its own
/// start makes true, the duration, ε, one action). `None` when its start
/// cannot be reached.
fn effect_costs(op: &Op<'_>, cost: &[f64], effort: &[f64]) -> Option<[(f64, f64); 2]> {
    // What the start needs; then what the rest needs, but what the
    // operator's own start provides (an `over all` or `at end` condition
    // its start makes true).
    let own = |l: Lit| op.effs.iter().any(|e| e.at == End::Start && e.lit == l);
    let (mut sc, mut se, mut ec, mut ee) = (0.0, 0.0, 0.0, 0.0);
    for c in &op.conds {
        let later = c.at == End::End || c.until == End::End;
        if !later || op.instant {
            sc += cost[c.lit as usize];
            se += effort[c.lit as usize];
        } else if !own(c.lit) {
            ec += cost[c.lit as usize];
            ee += effort[c.lit as usize];
        }
    }
    if !sc.is_finite() {
        return None;
    }
    Some([(sc + EPS, se + 1.0), (sc + ec + op.duration.unwrap_or(0.0) + EPS, se + ee + 1.0)])
}

/// Which of [`effect_costs`] an effect takes: `0` at the start of a
/// durative operator, else `1`.
fn effect_end(op: &Op<'_>, e: &Eff) -> usize {
    if e.at == End::Start && !op.instant { 0 } else { 1 }
}

/// What the refinements of each abstract operator may add: the effects of
/// the elementary operators its methods reach, directly or through other
/// tasks. Operators that reach each other (a strongly connected component
/// of the graph from a task to its methods' subtasks: a recursion) reach
/// the same operators, so each component's set is computed once, from
/// those of the components below it (Tarjan's algorithm gives them children
/// first). Bounded in size. A fixpoint over the methods went through every
/// method's subtasks' sets again each round: 40 % of the run on IPC 2020
/// Monroe (74,349 ground operators, 61,947 method instances), 8 s.
fn may_add(task: &Task<'_>, graph: &SubtaskGraph) -> Option<MayAdd> {
    const CAP: usize = 4_000_000;
    let SubtaskGraph { succ, comp, comps } = graph;
    let mut sets: Vec<Vec<Lit>> = Vec::with_capacity(comps.len());
    let mut total = 0usize;
    // `components` lists a component after every component it reaches.
    for members in comps {
        let c = sets.len() as u32;
        let mut v: Vec<Lit> = Vec::new();
        for &o in members {
            let op = &task.ops[o as usize];
            if !op.is_abstract {
                v.extend(op.effs.iter().map(|e| e.lit));
            }
            for &s in &succ[o as usize] {
                let d = comp[s as usize];
                if d != c {
                    v.extend_from_slice(&sets[d as usize]);
                }
            }
        }
        v.sort_unstable();
        v.dedup();
        total += v.len();
        if total > CAP {
            return None;
        }
        sets.push(v);
    }
    Some(MayAdd::new(comp.clone(), sets))
}

/// An operator to its methods' subtasks (each list sorted, no repeats),
/// and the graph's strongly connected components ([`components`]): what
/// [`may_add`] and [`needs`] go through, bottom up.
struct SubtaskGraph {
    succ: Vec<Vec<u32>>,
    comp: Vec<u32>,
    comps: Vec<Vec<u32>>,
}

impl SubtaskGraph {
    fn of(task: &Task<'_>) -> SubtaskGraph {
        let mut succ: Vec<Vec<u32>> = vec![Vec::new(); task.ops.len()];
        for m in &task.methods {
            for &(_, s) in &m.subtasks {
                succ[m.task as usize].push(s);
            }
        }
        for v in &mut succ {
            v.sort_unstable();
            v.dedup();
        }
        let (comp, comps) = components(&succ);
        SubtaskGraph { succ, comp, comps }
    }
}

/// Per operator of `task`, whether it is a task on a cycle of the ground
/// task decomposition graph (task to its methods' subtasks): in a strongly
/// connected component of more than one operator, or its own subtask.
pub(super) fn recursive_tasks(task: &Task<'_>) -> Vec<bool> {
    let SubtaskGraph { succ, comp, comps } = SubtaskGraph::of(task);
    (0..succ.len())
        .map(|v| comps[comp[v] as usize].len() > 1 || succ[v].binary_search(&(v as u32)).is_ok())
        .collect()
}

/// What every refinement of each operator needs from outside it: the
/// literals that some elementary step of any refinement needs and that no
/// other step of the refinement may make true (so the initial state, or a
/// step outside it, must). An elementary operator needs its conditions but
/// those it makes true itself before (at its start, for a later condition
/// of a durative one); a method, its preconditions and what each subtask
/// needs that no other subtask may add ([`Heuristic::may_add`]); a task,
/// what each of its methods needs. An operator in a recursion (a strongly
/// connected component of more than one operator, or one with itself as a
/// subtask) needs nothing known, nor does one that has no method: an
/// under-approximation, which a plan can rely on ([`super::search`] drops
/// a plan with an unrefined abstract step that needs a literal nothing can
/// make true before it). IPC 2020 Woodworking binds a part's old treatment
/// in a method's free parameter: the task that grinds it from there needs
/// the part in that treatment, however it is refined, and a binding it is
/// not in is dropped when chosen. Bounded in size like [`may_add`].
fn needs(task: &Task<'_>, graph: &SubtaskGraph, may: &MayAdd) -> Option<Vec<Vec<Lit>>> {
    const CAP: usize = 4_000_000;
    let n = task.ops.len();
    let SubtaskGraph { succ, comps, .. } = graph;
    let mut methods: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (i, m) in task.methods.iter().enumerate() {
        methods[m.task as usize].push(i as u32);
    }
    let mut needs: Vec<Vec<Lit>> = vec![Vec::new(); n];
    let mut total = 0usize;
    let may_add = |op: u32, l: Lit| may.contains(op, l);
    // `components` lists a component after every component it reaches.
    for members in comps {
        let &[o] = members.as_slice() else { continue };
        if succ[o as usize].contains(&o) {
            continue;
        }
        let op = &task.ops[o as usize];
        let mut v: Vec<Lit> = if !op.is_abstract {
            // A condition after its start that its own start makes true.
            let own = |c: &super::task::Cond<'_>| {
                !op.instant
                    && c.at != End::Start
                    && op.effs.iter().any(|e| e.lit == c.lit && e.at == End::Start)
            };
            op.conds.iter().filter(|c| !own(c)).map(|c| c.lit).collect()
        } else {
            let mut all: Option<Vec<Lit>> = None;
            for &m in &methods[o as usize] {
                let m = &task.methods[m as usize];
                let mut ext: Vec<Lit> = m.pre.iter().map(|c| c.lit).collect();
                for (i, &(_, s)) in m.subtasks.iter().enumerate() {
                    let others = || m.subtasks.iter().enumerate().filter(move |&(j, _)| j != i);
                    ext.extend(
                        needs[s as usize].iter().filter(|&&l| !others().any(|(_, &(_, t))| may_add(t, l))),
                    );
                }
                ext.sort_unstable();
                ext.dedup();
                all = Some(match all {
                    None => ext,
                    Some(a) => a.into_iter().filter(|l| ext.binary_search(l).is_ok()).collect(),
                });
                if all.as_ref().is_some_and(Vec::is_empty) {
                    break;
                }
            }
            all.unwrap_or_default()
        };
        v.sort_unstable();
        v.dedup();
        total += v.len();
        if total > CAP {
            return None;
        }
        needs[o as usize] = v;
    }
    Some(needs)
}

/// The strongly connected components of a graph (Tarjan's algorithm,
/// iterative): each node's component, and the components' nodes, every
/// component after the components it reaches.
fn components(succ: &[Vec<u32>]) -> (Vec<u32>, Vec<Vec<u32>>) {
    const NONE: u32 = u32::MAX;
    let n = succ.len();
    let mut index = vec![NONE; n];
    let mut low = vec![0u32; n];
    let mut on_stack = vec![false; n];
    let mut comp = vec![NONE; n];
    let mut comps: Vec<Vec<u32>> = Vec::new();
    let mut stack: Vec<u32> = Vec::new();
    let mut next = 0u32;
    // The depth-first path: a node and how many of its successors it has
    // gone through.
    let mut path: Vec<(u32, usize)> = Vec::new();
    for root in 0..n as u32 {
        if index[root as usize] != NONE {
            continue;
        }
        index[root as usize] = next;
        low[root as usize] = next;
        next += 1;
        stack.push(root);
        on_stack[root as usize] = true;
        path.push((root, 0));
        while let Some(top) = path.last_mut() {
            let (v, k) = *top;
            let vu = v as usize;
            if let Some(&w) = succ[vu].get(k) {
                top.1 += 1;
                let wu = w as usize;
                if index[wu] == NONE {
                    index[wu] = next;
                    low[wu] = next;
                    next += 1;
                    stack.push(w);
                    on_stack[wu] = true;
                    path.push((w, 0));
                } else if on_stack[wu] {
                    low[vu] = low[vu].min(index[wu]);
                }
                continue;
            }
            path.pop();
            if let Some(&(parent, _)) = path.last() {
                low[parent as usize] = low[parent as usize].min(low[vu]);
            }
            if low[vu] == index[vu] {
                let c = comps.len() as u32;
                let mut members = Vec::new();
                while let Some(w) = stack.pop() {
                    on_stack[w as usize] = false;
                    comp[w as usize] = c;
                    members.push(w);
                    if w == v {
                        break;
                    }
                }
                comps.push(members);
            }
        }
    }
    (comp, comps)
}

/// The literals the refinements of each operator may make true: the set of
/// its strongly connected component ([`may_add`]).
pub struct MayAdd {
    comp: Vec<u32>,
    sets: Vec<Vec<Lit>>,
    /// The larger sets again as bit sets over the literals, for
    /// [`MayAdd::contains`]: each set's words from its offset in `bits`,
    /// as many as its greatest literal needs (`NO_BITS`: none, the sorted
    /// set is searched). The search and the walk of the orders ask it for
    /// every open link and unrefined abstract step of every plan they
    /// score: a binary search in sets of hundreds of literals each time was
    /// a quarter of the search on IPC 2020 Barman-BDI's larger problems.
    bits: Vec<u64>,
    offsets: Vec<(u32, u32)>,
}

/// A set without a bit set ([`MayAdd::bits`]).
const NO_BITS: u32 = u32::MAX;

/// Sets of fewer literals are only searched ([`MayAdd::bits`]).
const BITS_FROM: usize = 16;

/// The most words of bit sets [`MayAdd`] keeps (32 MiB); the sets beyond
/// are only searched.
const BITS_CAP: usize = 4 << 20;

impl MayAdd {
    fn new(comp: Vec<u32>, sets: Vec<Vec<Lit>>) -> MayAdd {
        let mut bits = Vec::new();
        let mut offsets = Vec::with_capacity(sets.len());
        for set in &sets {
            let words = set.last().map_or(0, |&l| l as usize / 64 + 1);
            if set.len() < BITS_FROM || bits.len() + words > BITS_CAP {
                offsets.push((NO_BITS, 0));
                continue;
            }
            let at = bits.len();
            bits.resize(at + words, 0);
            for &l in set {
                bits[at + l as usize / 64] |= 1 << (l % 64);
            }
            offsets.push((at as u32, words as u32));
        }
        MayAdd { comp, sets, bits, offsets }
    }

    /// Whether `op`'s set holds `l`.
    fn contains(&self, op: u32, l: Lit) -> bool {
        let Some(&c) = self.comp.get(op as usize) else { return false };
        match self.offsets[c as usize] {
            (NO_BITS, _) => self.sets[c as usize].binary_search(&l).is_ok(),
            (at, words) => {
                let w = l as usize / 64;
                w < words as usize && self.bits[at as usize + w] >> (l % 64) & 1 == 1
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AnalysisHost;
    use crate::planner::PlannerLimits;

    /// Compiles the problem `problem` of the HDDL domain `domain` and runs
    /// `f` on its task and its heuristic.
    fn with_heuristic(
        domain: &str,
        problem: &str,
        f: impl FnOnce(&Task<'_>, &Heuristic) + std::panic::UnwindSafe,
    ) {
        let mut host = AnalysisHost::new();
        host.set_file_text("domain.hddl", domain);
        let pf = host.set_file_text("problem.hddl", problem);
        host.analysis()
            .with_db(|db| {
                let unit = crate::db::file_units(db, pf)[0];
                let task = match crate::planner::task::compile(db, unit, &PlannerLimits::default(), false) {
                    Ok(task) => task,
                    Err(_) => panic!("the problem does not compile"),
                };
                f(&task, &Heuristic::new(&task));
            })
            .expect("not cancelled");
    }

    /// `deliver` has two methods: `far` (three drives, no precondition) and
    /// `near` (one drive, needing `(ready)`, which only `prepare` makes).
    /// The refinement estimate is the cheapest method's preconditions and
    /// subtasks: `near` counts its precondition, and a method whose
    /// precondition cannot be reached (`never`) does not count.
    #[test]
    fn refinement_estimates_count_method_preconditions() {
        let domain = "(define (domain d) (:requirements :hierarchy)
          (:predicates (ready) (blocked) (done))
          (:task deliver :parameters ())
          (:task get-ready :parameters ())
          (:method far :parameters () :task (deliver) :ordered-subtasks (and (drive) (drive) (drive)))
          (:method near :parameters () :task (deliver) :precondition (ready) :ordered-subtasks (and (drive)))
          (:method never :parameters () :task (deliver) :precondition (blocked) :ordered-subtasks (and (finish)))
          (:method prepare-it :parameters () :task (get-ready) :ordered-subtasks (and (prepare)))
          (:action drive :parameters () :effect (done))
          (:action finish :parameters () :effect (done))
          (:action prepare :parameters () :effect (ready)))";
        let problem = "(define (problem p) (:domain d) (:htn :subtasks (and (get-ready) (deliver))) (:init))";
        with_heuristic(domain, problem, |task, h| {
            let op = |name: &str| task.ops.iter().position(|o| &*o.name == name).expect("an operator");
            let ready = task.ops[op("prepare")].effs[0].lit;
            // One step each: `drive` costs ε and one unit of effort.
            assert!((h.refine_cost[op("drive")] - EPS).abs() < 1e-9);
            assert_eq!(h.refine_effort[op("drive")], 1.0);
            // `near`: (ready) by `prepare`, then one drive; `far`: three
            // drives; `never`: unreachable.
            assert_eq!(h.lit_effort(ready), 1.0);
            assert_eq!(h.refine_effort[op("deliver")], 1.0 + 1.0 + 1.0);
            assert!((h.refine_cost[op("deliver")] - (h.lit_cost(ready) + EPS)).abs() < 1e-9);
        });
    }

    /// The bit sets of the larger sets answer as the sorted sets do: every
    /// literal of each set, and none other, below and past its greatest
    /// (operator 3 has no set; a set too small for bits is searched).
    #[test]
    fn may_add_bit_sets_hold_what_the_sets_hold() {
        let small: Vec<Lit> = vec![3, 70, 200];
        let large: Vec<Lit> = (0..40).map(|i| i * 7 + (i % 3)).collect();
        let m = MayAdd::new(vec![1, 0, 1], vec![small.clone(), large.clone()]);
        assert_eq!(m.offsets[0].0, NO_BITS);
        assert_ne!(m.offsets[1].0, NO_BITS);
        for l in 0..400 {
            assert_eq!(m.contains(1, l), small.contains(&l), "{l}");
            assert_eq!(m.contains(0, l), large.contains(&l), "{l}");
            assert_eq!(m.contains(2, l), large.contains(&l), "{l}");
            assert!(!m.contains(3, l));
        }
    }

    /// What a task's refinements may add is what the elementary actions
    /// below it add, however deep: `t0` reaches `act` through 80 tasks, and
    /// `loop-a` and `loop-b` refine into each other (one component) and
    /// reach `other`. The fixpoint over the methods before stopped after 64
    /// rounds, one level each, and `t0` to `t15` were missing `(p)`.
    #[test]
    fn may_add_reaches_every_level_and_goes_round_recursions() {
        const DEPTH: usize = 80;
        let mut domain = String::from(
            "(define (domain d) (:requirements :hierarchy) (:predicates (p) (q))
             (:task loop-a :parameters ()) (:task loop-b :parameters ())
             (:method a-b :parameters () :task (loop-a) :ordered-subtasks (and (loop-b)))
             (:method b-a :parameters () :task (loop-b) :ordered-subtasks (and (other) (loop-a)))
             (:method b-done :parameters () :task (loop-b) :ordered-subtasks (and (other)))
             (:action act :parameters () :effect (p))
             (:action other :parameters () :effect (q))",
        );
        for i in 0..DEPTH {
            domain.push_str(&format!(" (:task t{i} :parameters ())"));
        }
        // Declared from the top: each round of a fixpoint in this order
        // carries `(p)` up one level only.
        for i in 0..DEPTH {
            let sub = if i + 1 < DEPTH { format!("t{}", i + 1) } else { "act".to_owned() };
            domain.push_str(&format!(
                " (:method m{i} :parameters () :task (t{i}) :ordered-subtasks (and ({sub})))"
            ));
        }
        domain.push(')');
        let problem = "(define (problem p) (:domain d) (:htn :subtasks (and (t0) (loop-a))) (:init))";
        with_heuristic(&domain, problem, |task, h| {
            let op = |name: &str| task.ops.iter().position(|o| &*o.name == name).expect("an operator") as u32;
            let p = task.ops[op("act") as usize].effs[0].lit;
            let q = task.ops[op("other") as usize].effs[0].lit;
            for i in 0..DEPTH {
                let t = op(&format!("t{i}"));
                assert!(h.may_add(t, p), "t{i} may add (p)");
                assert!(!h.may_add(t, q), "t{i} may not add (q)");
            }
            for name in ["loop-a", "loop-b"] {
                assert!(h.may_add(op(name), q), "{name} may add (q)");
                assert!(!h.may_add(op(name), p), "{name} may not add (p)");
            }
        });
    }
}
