//! Numeric fluents (PDDL 2.1) in the planner: the fragment the IPC 2002
//! temporal domains use.
//!
//! A ground fluent that a condition or a duration reads, or that an effect
//! assigns or scales, is a *resource* the search follows; one that effects
//! only increase or decrease and nothing reads (a metric's
//! `total-fuel-used`) is left to the validator: VAL lets such additive
//! updates happen together. A resource has a value only along an order of
//! the happenings that touch it, so every two steps that touch the same
//! resource, one of them writing it, are ordered ([`super::search`]'s
//! numeric orderings); once they are, its value at each happening is
//! computed from `:init` along that order ([`simulate`]), conditions are
//! checked, and durations that read it become fixed.
//!
//! Expressions are evaluated by the validator's evaluator
//! ([`crate::validate`]): the same arithmetic in the same order, so a
//! value the planner computes is the one the validator (and VAL) reads.

use std::cell::RefCell;
use std::rc::Rc;

use rustc_hash::FxHashMap;

use super::plan::{Kind, Plan};
use super::stn::Tp;
use super::task::{End, Task};
use crate::eval::{Binding, Eval, FluentId, NumOp, State, World};
use crate::model::{CmpOp, Gd, NumExpr, Str};
use crate::semantics::symbols::Loc;
use crate::verify::state::ObjId;

/// The values of an operator's parameters (and quantified variables).
pub type Vars = Rc<[(Str, ObjId)]>;

/// A numeric condition on one resource, compared with what is fixed for
/// the whole problem: `(>= (fuel a1) (* (distance c1 c2) (slow-burn a1)))`.
#[derive(Debug, Clone)]
pub struct NumCond<'db> {
    pub res: u32,
    pub at: End,
    pub gd: &'db Gd,
    pub vars: Vars,
    pub loc: Loc<'db>,
}

/// A numeric effect on a resource: `(decrease (energy r1) 8)`,
/// `(increase (energy r1) (* ?duration (recharge-rate r1)))`.
#[derive(Debug, Clone)]
pub struct NumEff<'db> {
    pub res: u32,
    pub at: End,
    pub(crate) op: NumOp,
    pub value: &'db NumExpr,
    pub vars: Vars,
}

/// A duration that reads a resource at the step's start:
/// `(/ (- (capacity a1) (fuel a1)) (refuel-rate a1))`.
#[derive(Debug, Clone)]
pub struct NumDuration<'db> {
    pub res: u32,
    pub expr: &'db NumExpr,
    pub vars: Vars,
}

/// The resources of a task and what evaluates expressions over them.
#[derive(Debug, Clone, Default)]
pub struct Numeric {
    /// Each resource's ground fluent, `[func, args…]`.
    pub keys: Vec<Vec<u32>>,
    /// Its value in `:init` (`None`: undefined).
    pub init: Vec<Option<f64>>,
    /// Per resource: the operators in 𝒜 with an effect on it, by index.
    pub writers: Vec<Vec<u32>>,
    /// Per resource: followed by the search (read by a condition or a
    /// duration, or written other than by `increase`/`decrease`).
    pub followed: Vec<bool>,
    /// Each resource's id in `state`.
    ids: Vec<FluentId>,
    /// Resources by ground fluent.
    index: FxHashMap<Vec<u32>, u32>,
    /// The initial state's fluents; the resource an expression reads is
    /// set before each evaluation.
    state: RefCell<State>,
}

impl Numeric {
    /// Whether the search follows no fluent.
    pub fn is_empty(&self) -> bool {
        !self.followed.iter().any(|&f| f)
    }

    pub(crate) fn new(init: &crate::verify::state::InitialState<'_>) -> Numeric {
        let mut state = State::default();
        let mut fluents: Vec<(&[u32], f64)> = init.fluents.iter().map(|(k, (v, _))| (k, *v)).collect();
        fluents.sort_by(|a, b| a.0.cmp(b.0));
        for (key, v) in fluents {
            let id = state.fluent(key);
            state.set_value(id, Some(v));
        }
        Numeric { state: RefCell::new(state), ..Numeric::default() }
    }

    /// The resource of a ground fluent, added if new.
    pub(crate) fn resource(&mut self, key: &[u32]) -> u32 {
        if let Some(&r) = self.index.get(key) {
            return r;
        }
        self.index.insert(key.to_vec(), self.keys.len() as u32);
        let mut state = self.state.borrow_mut();
        let id = state.fluent(key);
        self.init.push(state.value(id));
        self.ids.push(id);
        self.keys.push(key.to_vec());
        self.writers.push(Vec::new());
        (self.keys.len() - 1) as u32
    }

    /// Evaluates with resource `res` at `value` (and `?duration`).
    fn with<T>(
        &self,
        task: &Task<'_>,
        res: u32,
        value: Option<f64>,
        duration: Option<f64>,
        f: impl FnOnce(&Eval<'_, '_, '_>) -> T,
    ) -> T {
        let mut state = self.state.borrow_mut();
        if let Some(&id) = self.ids.get(res as usize) {
            state.set_value(id, value);
        }
        let world = World { objects: &task.g.objects, preds: &task.g.predicates, funcs: &task.g.functions };
        let eval = Eval { world: &world, state: &state, duration, total_time: None };
        f(&eval)
    }

    /// Whether a condition that reads no resource holds in `:init`.
    pub(crate) fn holds_static(
        &self,
        task_g: &crate::verify::ground::Ground<'_>,
        gd: &Gd,
        vars: &[(Str, ObjId)],
    ) -> bool {
        let state = self.state.borrow();
        let world = World { objects: &task_g.objects, preds: &task_g.predicates, funcs: &task_g.functions };
        let eval = Eval { world: &world, state: &state, duration: None, total_time: None };
        eval.holds(gd, &mut binding(vars)).unwrap_or(false)
    }

    /// The value of an expression that reads no resource and no
    /// `?duration`, if it has one.
    fn static_value(
        &self,
        g: &crate::verify::ground::Ground<'_>,
        e: &NumExpr,
        vars: &[(Str, ObjId)],
    ) -> Option<f64> {
        let state = self.state.borrow();
        let world = World { objects: &g.objects, preds: &g.predicates, funcs: &g.functions };
        let eval = Eval { world: &world, state: &state, duration: None, total_time: None };
        eval.num(e, &binding(vars)).ok()
    }

    /// Marks dead the operators with a numeric condition that no value
    /// the resource can take satisfies: a `zoom` that burns more fuel than
    /// the tank holds, when only a refuel to capacity adds fuel. The values
    /// a resource can take lie between the least and the greatest of its
    /// initial value and of what effects assign it, or beyond on the side
    /// increases (decreases) go; an effect whose value reads `?duration` or
    /// cannot be evaluated counts as going either way. Only a condition
    /// that compares the fluent itself with a static expression is judged
    /// (it is monotone in the fluent); the others are kept.
    pub(crate) fn prune(&self, g: &crate::verify::ground::Ground<'_>, ops: &mut [super::task::Op<'_>]) {
        let n = self.keys.len();
        let mut lo: Vec<f64> = self.init.iter().map(|v| v.unwrap_or(f64::NAN)).collect();
        let mut hi = lo.clone();
        for op in ops.iter().filter(|o| !o.dead) {
            for e in &op.num_effs {
                let r = e.res as usize;
                let v = self.static_value(g, e.value, &e.vars);
                match (e.op, v) {
                    (NumOp::Assign, Some(v)) => {
                        lo[r] = lo[r].min(v);
                        hi[r] = hi[r].max(v);
                    }
                    (NumOp::Increase, Some(v)) | (NumOp::Decrease, Some(v)) => {
                        let up = (e.op == NumOp::Increase) == (v > 0.0);
                        if v != 0.0 && up {
                            hi[r] = f64::INFINITY;
                        } else if v != 0.0 {
                            lo[r] = f64::NEG_INFINITY;
                        }
                    }
                    _ => {
                        lo[r] = f64::NEG_INFINITY;
                        hi[r] = f64::INFINITY;
                    }
                }
            }
        }
        for op in ops.iter_mut() {
            let impossible = op.num_conds.iter().any(|c| {
                let r = c.res as usize;
                if r >= n || lo[r].is_nan() || hi[r].is_nan() {
                    return false;
                }
                let Gd::Compare(cmp, l, rhs, _) = c.gd else { return false };
                let is_fluent = |e: &NumExpr| match e {
                    NumExpr::Fluent(f) => {
                        let key: Option<Vec<u32>> = g.functions.get(f.func.key()).and_then(|func| {
                            std::iter::once(Some(func))
                                .chain(f.args.iter().map(|t| match t {
                                    crate::model::Term::Var(v) => {
                                        c.vars.iter().rev().find(|(k, _)| *k == v.key()).map(|(_, o)| *o)
                                    }
                                    crate::model::Term::Const(o) => g.objects.id(o.key()),
                                    _ => None,
                                }))
                                .collect()
                        });
                        key.as_deref() == Some(self.keys[r].as_slice())
                    }
                    _ => false,
                };
                // `fluent cmp x`, the fluent on the left.
                let (cmp, other) = if is_fluent(l) {
                    (*cmp, rhs)
                } else if is_fluent(rhs) {
                    let flipped = match cmp {
                        CmpOp::Lt => CmpOp::Gt,
                        CmpOp::Le => CmpOp::Ge,
                        CmpOp::Gt => CmpOp::Lt,
                        CmpOp::Ge => CmpOp::Le,
                        CmpOp::Eq => CmpOp::Eq,
                    };
                    (flipped, l)
                } else {
                    return false;
                };
                let Some(x) = self.static_value(g, other, &c.vars) else { return false };
                let (lo, hi) = (lo[r], hi[r]);
                !match cmp {
                    CmpOp::Ge => hi >= x,
                    CmpOp::Gt => hi > x,
                    CmpOp::Le => lo <= x,
                    CmpOp::Lt => lo < x,
                    CmpOp::Eq => lo <= x && x <= hi,
                }
            });
            if impossible {
                op.dead = true;
            }
        }
    }

    /// Whether a condition holds with its resource at `value`.
    pub fn holds(&self, task: &Task<'_>, c: &NumCond<'_>, value: Option<f64>) -> bool {
        self.with(task, c.res, value, None, |e| e.holds(c.gd, &mut binding(&c.vars)).unwrap_or(false))
    }

    /// The duration with its resource at `value`: `None` when undefined,
    /// negative or not a finite number.
    pub fn duration(&self, task: &Task<'_>, d: &NumDuration<'_>, value: Option<f64>) -> Option<f64> {
        self.with(task, d.res, value, None, |e| e.num(d.expr, &binding(&d.vars)).ok())
            .filter(|v| v.is_finite() && *v >= 0.0)
    }

    /// The resource's value after effect `e`, from `old` (`?duration`:
    /// the step's duration).
    pub fn apply(
        &self,
        task: &Task<'_>,
        e: &NumEff<'_>,
        old: Option<f64>,
        duration: Option<f64>,
    ) -> Option<f64> {
        let v = self.with(task, e.res, old, duration, |ev| ev.num(e.value, &binding(&e.vars)).ok())?;
        e.op.apply(old, v)
    }
}

fn binding(vars: &[(Str, ObjId)]) -> Binding<'_> {
    let mut b = Binding::default();
    for (k, o) in vars {
        b.push(k, *o);
    }
    b
}

/// A happening of a step that touches a resource.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Event {
    pub step: u32,
    pub tp: Tp,
    pub end: End,
    pub writes: bool,
}

/// The happenings of a plan's steps that touch each resource, by resource.
pub fn events(task: &Task<'_>, p: &Plan) -> FxHashMap<u32, Vec<Event>> {
    let mut out: FxHashMap<u32, Vec<Event>> = FxHashMap::default();
    for (s, step) in p.steps.iter().enumerate() {
        let Kind::Op(o) = step.kind else { continue };
        let op = &task.ops[o as usize];
        if op.num_conds.is_empty() && op.num_effs.is_empty() && op.num_duration.is_none() {
            continue;
        }
        let mut add = |res: u32, at: End, writes: bool| {
            let tp = step.tp(at);
            let list = out.entry(res).or_default();
            match list.iter_mut().find(|e| e.step == s as u32 && e.tp == tp) {
                Some(e) => e.writes |= writes,
                None => list.push(Event { step: s as u32, tp, end: at, writes }),
            }
        };
        for c in &op.num_conds {
            add(c.res, c.at, false);
        }
        if let Some(d) = &op.num_duration {
            add(d.res, End::Start, false);
        }
        for e in &op.num_effs {
            add(e.res, e.at, true);
        }
    }
    out
}

/// What a plan's resources are once their happenings are ordered.
#[derive(Debug, Default)]
pub struct Values {
    /// Per step with a duration that reads a resource and that is not
    /// fixed yet: its duration, when its start's value is known and gives
    /// one. `None`: it gives none, or a duration fixed before is no longer
    /// what its start reads (a step that changes the fluent was inserted
    /// before it since): the plan is dead.
    pub durations: Vec<(u32, Option<f64>)>,
    /// A condition that does not hold: step, time point, resource, which of
    /// its operator's numeric conditions, and the value it read.
    pub failed: Option<Failed>,
    /// A resource whose values could not be followed (an effect needs a
    /// duration that is not known).
    pub blocked: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Failed {
    pub step: u32,
    pub tp: Tp,
    pub res: u32,
    pub cond: u32,
    pub value: Option<f64>,
}

/// The values of every resource along the plan's order of its happenings,
/// which must be total for each resource between writers and between a
/// writer and any other happening (the caller orders them first). The
/// durations of the steps that read a resource at their start are computed
/// on the way (`known`: those fixed already), and the first condition that
/// does not hold, in the order of the earliest schedule, is reported.
pub fn simulate(
    task: &Task<'_>,
    p: &Plan,
    events: &FxHashMap<u32, Vec<Event>>,
    known: &[(u32, f64)],
) -> Values {
    let num = &task.numeric;
    let mut out = Values::default();
    let mut durations: FxHashMap<u32, f64> = known.iter().copied().collect();
    let mut failed: Vec<Failed> = Vec::new();
    let mut resources: Vec<u32> = events.keys().copied().collect();
    resources.sort_unstable();
    // Rounds: a resource whose effects need a duration that another
    // resource decides waits for it.
    let mut done = vec![false; resources.len()];
    loop {
        let mut progress = false;
        for (k, &res) in resources.iter().enumerate() {
            if done[k] {
                continue;
            }
            let evs = &events[&res];
            // Writers are totally ordered with each other (by the network;
            // at the same earliest time only while their mutex is not
            // solved, and the plan is simulated again once it is).
            let mut writers: Vec<Event> = evs.iter().copied().filter(|e| e.writes).collect();
            writers.sort_by(|a, b| p.stn.est(a.tp).total_cmp(&p.stn.est(b.tp)).then(a.tp.cmp(&b.tp)));
            // The other happenings read the value after the writers before
            // them (a prefix of the writers' order).
            let mut readers: Vec<(usize, Event)> = evs
                .iter()
                .filter(|e| !e.writes)
                .map(|e| (writers.iter().filter(|w| p.stn.before(w.tp, e.tp) && w.tp != e.tp).count(), *e))
                .collect();
            readers.sort_by_key(|(i, e)| (*i, e.tp));
            let mut v = num.init.get(res as usize).copied().flatten();
            let mut blocked = false;
            let mut found: Vec<(u32, Option<f64>)> = Vec::new();
            let mut failures: Vec<Failed> = Vec::new();
            // What a happening reads: its conditions, and its duration at a start.
            let mut read = |e: &Event, value: Option<f64>, durations: &mut FxHashMap<u32, f64>| {
                let Some(o) = p.op_of(e.step) else { return };
                let op = &task.ops[o as usize];
                let step = p.steps[e.step as usize];
                if e.tp == step.start
                    && let Some(d) = op.num_duration.as_ref().filter(|d| d.res == res)
                {
                    let x = num.duration(task, d, value);
                    match (x, durations.get(&e.step)) {
                        // Fixed before, and still what its start reads.
                        (Some(x), Some(&fixed)) if x == fixed => {}
                        (_, Some(_)) => found.push((e.step, None)),
                        (Some(x), None) => {
                            durations.insert(e.step, x);
                            found.push((e.step, Some(x)));
                        }
                        (None, None) => found.push((e.step, None)),
                    }
                }
                for (ci, c) in op.num_conds.iter().enumerate() {
                    if c.res == res && step.tp(c.at) == e.tp && !num.holds(task, c, value) {
                        failures.push(Failed { step: e.step, tp: e.tp, res, cond: ci as u32, value });
                    }
                }
            };
            let mut r = 0;
            for i in 0..=writers.len() {
                while r < readers.len() && readers[r].0 == i {
                    read(&readers[r].1, v, &mut durations);
                    r += 1;
                }
                let Some(w) = writers.get(i) else { break };
                read(w, v, &mut durations);
                let Some(o) = p.op_of(w.step) else { continue };
                let op = &task.ops[o as usize];
                let step_duration = op.duration.or_else(|| durations.get(&w.step).copied());
                let step = p.steps[w.step as usize];
                for e in op.num_effs.iter().filter(|e| e.res == res && step.tp(e.at) == w.tp) {
                    if step_duration.is_none() && reads_duration(e.value) {
                        blocked = true;
                        break;
                    }
                    v = num.apply(task, e, v, step_duration);
                }
                if blocked {
                    break;
                }
            }
            if blocked {
                // Again next round, from scratch.
                for (s, _) in &found {
                    if !known.iter().any(|(k, _)| k == s) {
                        durations.remove(s);
                    }
                }
                continue;
            }
            failed.extend(failures);
            out.durations.extend(found);
            done[k] = true;
            progress = true;
        }
        if done.iter().all(|&d| d) {
            break;
        }
        if !progress {
            out.blocked = true;
            break;
        }
    }
    out.durations.sort_by_key(|(s, d)| (*s, d.is_some()));
    out.durations.dedup_by_key(|(s, _)| *s);
    out.failed =
        failed.into_iter().min_by(|a, b| p.stn.est(a.tp).total_cmp(&p.stn.est(b.tp)).then(a.tp.cmp(&b.tp)));
    out
}

/// Whether an expression reads `?duration`.
pub fn reads_duration(e: &NumExpr) -> bool {
    match e {
        NumExpr::Duration(_) => true,
        NumExpr::Op(_, xs, _) => xs.iter().any(reads_duration),
        _ => false,
    }
}

/// Whether inserting operator `h` before a happening that reads `value`
/// of resource `res` makes its failed condition `c` hold: `h`'s own
/// conditions on the resource at its start hold at `value`, and its
/// effects (with the duration `value` gives it) bring the resource to a
/// value where `c` holds.
pub fn helps(task: &Task<'_>, h: u32, res: u32, value: Option<f64>, c: &NumCond<'_>) -> bool {
    let num = &task.numeric;
    let op = &task.ops[h as usize];
    if !op.num_conds.iter().filter(|x| x.res == res && x.at == End::Start).all(|x| num.holds(task, x, value))
    {
        return false;
    }
    let duration = match &op.num_duration {
        Some(d) if d.res == res => match num.duration(task, d, value) {
            Some(d) => Some(d),
            None => return false,
        },
        Some(_) => None,
        None => op.duration,
    };
    let mut v = value;
    for at in [End::Start, End::End] {
        for e in op.num_effs.iter().filter(|e| e.res == res && e.at == at) {
            if duration.is_none() && reads_duration(e.value) {
                return false;
            }
            v = num.apply(task, e, v, duration);
        }
    }
    v != value && num.holds(task, c, v)
}
