//! Grounding: the instances of the actions and tasks of a problem's domain
//! over the problem's objects and the domain's constants that types, equality
//! constraints, static predicates and relaxed reachability allow; and the
//! instances of the methods (a separate query, [`ground_methods`], computed
//! only when a lint asks for it).
//!
//! A predicate is *static* when no action or task adds or deletes it and no
//! timed initial literal sets it: its atoms are true exactly when `:init` says
//! so, for the whole plan. Static preconditions do not appear in the ground
//! operators; a negative static precondition must be false in `:init`.
//!
//! Only instances whose positive preconditions are all reachable from the
//! initial state (ignoring deletes and negative preconditions) are kept: the
//! others are in no plan. They are found together, by the semi-naive
//! fixpoint of [`super::instantiate`]; static predicates alone would keep 2.4
//! times as many instances on the IPC 2002 temporal problems (6 to 10 times
//! on Depots). Relaxed reachability restricted to some operators (allowed
//! actions) is [`super::reach::reachable`].
//!
//! Numeric conditions are ignored (they only restrict, so the result is an
//! over-approximation). What the STRIPS view cannot express (see
//! [`super::lifted`]) is left out of the ground operator and flagged with
//! [`GroundOperator::unsupported`], so that lints can stay conservative.
//!
//! Grounding is bounded ([`Limits`]): past the limits it stops and says so
//! ([`Ground::truncated`]) rather than hang or exhaust memory.

use std::ops::ControlFlow;

use super::duration::{Compiler as DurationCompiler, DurationIssue, Env, Failure, IssueKind, Tally, Val};
use super::instantiate::{
    Arg, CAtom, Compiler, Facts, Instances, OpInput, Preds, Stop, fixpoint, instances_over, value,
};
use super::lifted::{Duration, LTerm, OperatorKind, method_schema, operator};
use super::relevance::{Goal as RelGoal, GoalAtom, RelOp};
use super::state::{AtomId, Atoms, FuncId, InitialState, Interner, ObjId, Objects, PredId, initial_state};
use crate::db::{Db, Item, Section, Unit, UnitKind, lower_item};
use crate::model::{ActionKind, Effect, Gd, ItemData, NumExpr, Str, Term};
use crate::semantics::check::domain_for;
use crate::semantics::symbols::{Loc, domain_symbols, problem_symbols};

/// Bounds on the work of grounding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Parameter values tried, over all operators (or all methods).
    pub candidates: u64,
    /// Ground operators kept.
    pub operators: usize,
    /// Ground instances kept per method.
    pub method_instances: usize,
    /// Whether a grounding stopped at a limit keeps the instances it found
    /// ([`Ground::operators`]). The planner's does: its refusal (E0501)
    /// says which action dominates and how many of its instances were
    /// found. The lints' does not: every lint but the durations' is silent
    /// on an incomplete grounding (it cannot confirm anything), and the
    /// durations are evaluated instance by instance all the same. At the
    /// lints' limit, that is 200,000 operators and their lists not held
    /// (15 MB of a 3.4 MB Satellite problem's check).
    pub keep_past_limit: bool,
}

impl Limits {
    /// The lints': they run on every edit, so grounding stays well under a
    /// second.
    pub const DEFAULT: Limits = Limits {
        candidates: 2_000_000,
        operators: 200_000,
        method_instances: 10_000,
        keep_past_limit: false,
    };
    /// The planner's ([`ground_relevant`]): a run is given seconds, and the
    /// model it grounds is what it searches, so only a model too large to
    /// search stops it (the candidates tried are work, not the model's size:
    /// Depots hand-coded instance 2 has 150,440 reachable instances found
    /// in 2.3 million candidates). 2,000,000 operators fit in the planner's
    /// default memory limit (4 GiB) with room for the search: Depots
    /// hand-coded 6's 1,547,850 take 1.3 GB.
    pub const PLANNER: Limits = Limits {
        candidates: 100_000_000,
        operators: 2_000_000,
        method_instances: 10_000,
        keep_past_limit: true,
    };
}

impl Default for Limits {
    fn default() -> Limits {
        Limits::DEFAULT
    }
}

/// One instance of an action or a task. Its lists (arguments, preconditions,
/// effects) live in one array of the [`Ground`], read with [`Ground::args`],
/// [`Ground::pre`], [`Ground::neg_pre`], [`Ground::add`] and [`Ground::del`]:
/// a large problem has hundreds of thousands of instances, and five
/// allocations each would dominate grounding.
#[derive(Debug, Clone, PartialEq, salsa::SalsaValue)]
pub struct GroundOperator<'db> {
    /// The action or task item.
    pub op: Item<'db>,
    /// Index of its [`Schema`] in [`Ground::schemas`].
    pub schema: u32,
    /// The duration ([`GroundOperator::duration`]), NaN for none: a
    /// duration is finite, and an `Option<f64>` would take 16 bytes.
    duration: Duration64,
    /// Its duration is undefined in the problem (a fluent without value), or
    /// negative, or not a finite number: PDDL 2.1 never applies the instance.
    pub no_duration: bool,
    /// The operator has constructs outside the STRIPS view: the lists may
    /// miss atoms (see [`super::lifted::Operator::unsupported`]).
    pub unsupported: bool,
    /// Where its lists start in [`Ground::lists`], and where each ends
    /// (relative): pre, neg_pre, add, del. Its arguments are just before,
    /// as many as the schema has parameters ([`Schema::arity`]).
    at: u32,
    ends: [u32; 4],
}

impl GroundOperator<'_> {
    /// The duration: 0 for an `:action`; `None` when it has no single value (a
    /// task without duration, bounds only, a fluent that effects change, or
    /// not evaluable, which is in [`Ground::duration_issues`]).
    pub fn duration(&self) -> Option<f64> {
        let d = self.duration.0;
        (!d.is_nan()).then_some(d)
    }
}

/// A duration or NaN, equal by its bits (so that a ground problem with
/// operators without duration still equals itself, for backdating).
#[derive(Debug, Clone, Copy)]
struct Duration64(f64);

impl PartialEq for Duration64 {
    fn eq(&self, other: &Self) -> bool {
        self.0.to_bits() == other.0.to_bits()
    }
}

/// An action or task of the domain and where its instances are.
#[derive(Debug, Clone, PartialEq, Eq, salsa::SalsaValue)]
pub struct Schema<'db> {
    pub item: Item<'db>,
    pub name: Str,
    pub kind: OperatorKind,
    /// How many parameters it has: the arguments of each of its instances.
    pub arity: u32,
    /// Its instances: `Ground::operators[start..end]`, sorted by arguments.
    pub start: u32,
    pub end: u32,
    /// Predicates it adds with an argument grounding cannot name (a `forall`
    /// variable, an object fluent): any atom of them may become true.
    pub wild_add: Vec<PredId>,
    pub unsupported: bool,
    /// How many objects each parameter may take: its types', less what
    /// goal relevance rules out (when the grounding applies it).
    pub candidates: Vec<u32>,
}

impl Schema<'_> {
    /// The product of [`Schema::candidates`]: how many instances grounding
    /// could find at most.
    pub fn candidate_instances(&self) -> f64 {
        self.candidates.iter().map(|&c| f64::from(c)).product()
    }
}

/// A method and the parameters' values of its instances.
pub type MethodBindings<'db> = (Item<'db>, Vec<Box<[ObjId]>>);

/// The value of a method parameter that only a split subtask names, in the
/// method's instances ([`Ground::tdg_splits`]): the subtask's instance is
/// chosen apart.
pub const UNBOUND: ObjId = ObjId::MAX;

/// A subtask split off its method: the method, the subtask's index in it,
/// its arguments as the method's instances name them, and the arguments of
/// the ground instances it may be.
#[derive(Debug, Clone, PartialEq, Eq, salsa::SalsaValue)]
pub struct SplitChoice<'db> {
    pub method: Item<'db>,
    pub subtask: usize,
    pub args: Box<[ObjId]>,
    pub choices: Vec<Box<[ObjId]>>,
}

/// The ground problem.
#[derive(Debug, Clone, PartialEq, Default, salsa::SalsaValue)]
pub struct Ground<'db> {
    pub objects: Objects<'db>,
    pub predicates: Interner,
    pub functions: Interner,
    /// Every atom met: in `:init`, then in the ground operators.
    pub atoms: Atoms,
    pub init: InitialState<'db>,
    /// Whether each predicate is static, by id.
    pub static_preds: Vec<bool>,
    /// Predicates whose atoms grounding cannot follow, by id: derived ones
    /// (hipop runs no axioms) and those some operator adds with a term it
    /// cannot name. Preconditions on them are assumed reachable.
    pub untracked_preds: Vec<bool>,
    /// Whether each function is changed by some effect, by id.
    pub dynamic_funcs: Vec<bool>,
    /// The domain's actions and tasks, in the order written.
    pub schemas: Vec<Schema<'db>>,
    /// The reachable instances, grouped by schema; none when grounding
    /// stopped at a limit that keeps nothing ([`Limits::keep_past_limit`]).
    pub operators: Vec<GroundOperator<'db>>,
    /// The lists of the ground operators, back to back.
    lists: Vec<u32>,
    /// Whether each atom is reachable with every operator, by id.
    pub reachable: Vec<bool>,
    /// Durations that cannot be evaluated, at most two per operator.
    pub duration_issues: Vec<DurationIssue<'db>>,
    /// Grounding stopped at a limit: `operators` is incomplete.
    pub truncated: bool,
    /// The limits it ran with, and how many parameter values it tried.
    pub limits: Limits,
    pub tried: u64,
    /// Only the instances relevant to the goal were kept ([`ground_relevant`]).
    pub relevance: bool,
    /// A hierarchical problem grounded top-down ([`super::tdg`]): its
    /// method instances, by method, in the domain's order
    /// ([`visit_methods`] reads them).
    pub tdg_methods: Option<Vec<MethodBindings<'db>>>,
    /// With [`Ground::tdg_methods`]: per task of the `:htn`, the arguments
    /// of its ground instances that can be decomposed.
    pub htn_choices: Option<Vec<Vec<Box<[ObjId]>>>>,
    /// With [`Ground::tdg_methods`]: the subtasks split off their methods
    /// ([`super::tdg::split`]). A method instance names such a subtask with
    /// its own parameters [`UNBOUND`]; the search chooses among
    /// the ground instances given here.
    pub tdg_splits: Vec<SplitChoice<'db>>,
    /// Top-down grounding stopped at a limit: the method with the most
    /// instances found then, and how many (none found: an empty name and 0).
    pub tdg_dominant: Option<(Str, usize)>,
}

impl<'db> Ground<'db> {
    /// The instances of an action or task item.
    pub fn operators_of(&self, item: Item<'db>) -> &[GroundOperator<'db>] {
        self.schemas
            .iter()
            .find(|s| s.item == item)
            .map_or(&[], |s| &self.operators[s.start as usize..s.end as usize])
    }

    /// List `k` of an instance: pre, neg_pre, add, del.
    fn list(&self, o: &GroundOperator<'db>, k: usize) -> &[u32] {
        let start = if k == 0 { 0 } else { o.ends[k - 1] };
        let (a, b) = (o.at as usize + start as usize, o.at as usize + o.ends[k] as usize);
        self.lists.get(a..b).unwrap_or(&[])
    }

    /// The parameters' values of an instance, in declaration order.
    pub fn args(&self, o: &GroundOperator<'db>) -> &[ObjId] {
        let arity = self.schemas.get(o.schema as usize).map_or(0, |s| s.arity as usize);
        let at = o.at as usize;
        self.lists.get(at.saturating_sub(arity)..at).unwrap_or(&[])
    }

    /// Positive preconditions on predicates that are not static (sorted, no duplicates).
    pub fn pre(&self, o: &GroundOperator<'db>) -> &[AtomId] {
        self.list(o, 0)
    }

    /// Negative preconditions on predicates that are not static (sorted).
    pub fn neg_pre(&self, o: &GroundOperator<'db>) -> &[AtomId] {
        self.list(o, 1)
    }

    /// Add effects (sorted).
    pub fn add(&self, o: &GroundOperator<'db>) -> &[AtomId] {
        self.list(o, 2)
    }

    /// Delete effects (sorted).
    pub fn del(&self, o: &GroundOperator<'db>) -> &[AtomId] {
        self.list(o, 3)
    }

    pub fn is_static(&self, pred: PredId) -> bool {
        self.static_preds.get(pred as usize).copied().unwrap_or(false)
    }

    pub fn is_reachable(&self, atom: AtomId) -> bool {
        self.reachable.get(atom as usize).copied().unwrap_or(false)
    }

    /// An atom as text: `(at r1 a)`.
    pub fn show_atom(&self, atom: AtomId) -> String {
        show(self.predicates.name(self.atoms.pred(atom)), self.atoms.args(atom), &self.objects)
    }

    /// An atom given by its parts as text, whether or not it was met.
    pub fn show_atom_parts(&self, pred: PredId, args: &[ObjId]) -> String {
        show(self.predicates.name(pred), args, &self.objects)
    }

    /// An operator instance as text: `(move r1 a b)`.
    pub fn show_operator(&self, op: &GroundOperator<'db>) -> String {
        let name = self.schemas.get(op.schema as usize).map_or("?", |s| s.name.as_str());
        show(name, self.args(op), &self.objects)
    }
}

pub(crate) fn show(name: &str, args: &[ObjId], objects: &Objects<'_>) -> String {
    let mut s = format!("({name}");
    for &a in args {
        s.push(' ');
        s.push_str(objects.name(a));
    }
    s.push(')');
    s
}

/// Grounds a problem with the default [`Limits`].
#[salsa::tracked(returns(ref))]
pub fn ground<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Ground<'db> {
    ground_with(db, problem, Limits::DEFAULT)
}

/// Grounds a problem for the planner: the instances that are reachable and
/// relevant to the goal ([`super::relevance`]), within [`Limits::PLANNER`].
/// The lints keep [`ground`]: an instance irrelevant to this goal is still
/// one the domain allows.
#[salsa::tracked(returns(ref))]
pub fn ground_relevant<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Ground<'db> {
    ground_with_relevance(db, problem, Limits::PLANNER, true)
}

/// Grounds a problem for the planner without goal relevance: every
/// reachable instance, within [`Limits::PLANNER`] (a plan repair reads the
/// old plan's steps against it).
#[salsa::tracked(returns(ref))]
pub fn ground_planner<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Ground<'db> {
    ground_with_relevance(db, problem, Limits::PLANNER, false)
}

/// Grounds a problem within `limits`. An empty result for what is not a
/// problem with a known domain.
pub fn ground_with<'db>(db: &'db dyn Db, problem: Unit<'db>, limits: Limits) -> Ground<'db> {
    ground_with_relevance(db, problem, limits, false)
}

/// Grounds a problem within `limits`, keeping only the instances relevant to
/// its goal when `relevance` is set and the problem allows it (no task
/// network, methods, derived predicates or constraints, and no construct the
/// STRIPS view leaves out but numeric effects: see [`relevance_goal`]).
pub fn ground_with_relevance<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    limits: Limits,
    relevance: bool,
) -> Ground<'db> {
    ground_with_mode(db, problem, limits, relevance, relevance)
}

/// [`ground_with_relevance`]; with `hierarchy`, a pure hierarchical problem
/// (an `:htn` and no allowed actions) is grounded top-down through its task
/// decomposition graph ([`super::tdg`]).
fn ground_with_mode<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    limits: Limits,
    relevance: bool,
    hierarchy: bool,
) -> Ground<'db> {
    let mut g = Ground { limits, ..Ground::default() };
    if problem.kind(db) != UnitKind::Problem {
        return g;
    }
    let Some(domain) = domain_for(db, problem) else { return g };
    let dom = domain_symbols(db, domain);
    g.objects = Objects::new(dom, problem_symbols(db, problem));
    // Stable ids: the domain's names sorted, then whatever `:init` adds.
    let mut names: Vec<&Str> = dom.predicates.keys().collect();
    names.sort();
    for n in names {
        g.predicates.intern(n);
    }
    let mut names: Vec<&Str> = dom.functions.keys().collect();
    names.sort();
    for n in names {
        g.functions.intern(n);
    }
    g.init = initial_state(db, problem, &g.objects, &mut g.predicates, &mut g.functions, &mut g.atoms);

    let ops: Vec<(Item<'db>, &super::lifted::Operator)> = domain
        .items(db)
        .iter()
        .filter(|i| matches!(i.section(db), Section::Action | Section::Task))
        .filter_map(|&i| operator(db, i).as_ref().map(|op| (i, op)))
        .collect();

    // Static predicates: no effect and no timed literal touches them.
    let mut touched: Vec<PredId> = Vec::new();
    let mut wild: Vec<PredId> = Vec::new();
    for (_, op) in &ops {
        for a in op.add.iter().chain(&op.del) {
            touched.push(g.predicates.intern(&a.pred));
        }
        for a in op.add.iter().filter(|a| a.args.iter().any(|t| matches!(t, LTerm::Free(_)))) {
            wild.push(g.predicates.intern(&a.pred));
        }
    }
    touched.extend(g.init.timed.iter().map(|t| g.atoms.pred(t.atom)));
    // Derived predicates, from their `(:derived …)` items: the symbol table
    // records the `:predicates` declaration when there is one.
    let derived: Vec<PredId> = domain
        .items(db)
        .iter()
        .filter(|i| i.section(db) == Section::Derived)
        .filter_map(|&i| match &lower_item(db, i).data {
            ItemData::Derived(atom, _, _) => Some(g.predicates.intern(atom.pred.key())),
            _ => None,
        })
        .collect();
    let n_preds = g.predicates.len();
    g.static_preds = vec![true; n_preds];
    g.untracked_preds = vec![false; n_preds];
    let mut is_derived = vec![false; n_preds];
    for &p in touched.iter().chain(&derived) {
        g.static_preds[p as usize] = false;
    }
    for &p in wild.iter().chain(&derived) {
        g.untracked_preds[p as usize] = true;
    }
    for &p in &derived {
        is_derived[p as usize] = true;
    }

    // Functions some effect changes: their values in `:init` hold only at the start.
    let mut changed: Vec<FuncId> = Vec::new();
    for &(item, _) in &ops {
        let effect = match &lower_item(db, item).data {
            ItemData::Action(a) => a.effect.as_ref(),
            ItemData::Task(t) => t.effect.as_ref(),
            _ => None,
        };
        numeric_targets(effect, &mut g.functions, &mut changed);
    }
    g.dynamic_funcs = vec![false; g.functions.len()];
    for f in changed {
        g.dynamic_funcs[f as usize] = true;
    }

    // Compile every operator.
    struct Compiled {
        spec_add: OpInput,
        pre: Vec<CAtom>,
        neg: Vec<CAtom>,
        del: Vec<CAtom>,
        wild_add: Vec<PredId>,
        unsupported: bool,
        duration: Option<super::duration::CExpr>,
        /// For relevance: the conditions `pre` and `neg` leave out because
        /// the operator's own start may make them true.
        own_pos: Vec<CAtom>,
        own_neg: Vec<CAtom>,
    }
    let mut compiled = Vec::with_capacity(ops.len());
    for (_, op) in &ops {
        let mut cx = Compiler {
            objects: &g.objects,
            preds: Preds::Intern(&mut g.predicates),
            static_preds: &g.static_preds,
            untracked: &g.untracked_preds,
            derived: &is_derived,
            unsupported: !op.unsupported.is_empty(),
        };
        let spec = cx.spec(&op.params, &op.pre);
        let pre = cx.atoms(&op.pre.pos, false);
        let neg = cx.atoms(&op.pre.neg, false);
        let add = cx.atoms(&op.add, true);
        let del = cx.atoms(&op.del, true);
        let wild_add = op
            .add
            .iter()
            .filter(|a| a.args.iter().any(|t| matches!(t, LTerm::Free(_))))
            .filter_map(|a| cx.pred(&a.pred))
            .collect();
        let unsupported = cx.unsupported;
        let (mut own_pos, mut own_neg) = (Vec::new(), Vec::new());
        if relevance {
            for (from, to) in [(&op.own_start.pos, &mut own_pos), (&op.own_start.neg, &mut own_neg)] {
                for a in from {
                    if let Some(c) = cx.atom(a).filter(|c| !cx.is_static(c.pred)) {
                        to.push(c);
                    }
                }
            }
        }
        let duration = DurationCompiler {
            params: &op.params,
            objects: &g.objects,
            funcs: &mut g.functions,
            dynamic: &g.dynamic_funcs,
        }
        .duration(&op.duration);
        compiled.push(Compiled {
            spec_add: OpInput { spec, add },
            pre,
            neg,
            del,
            wild_add,
            unsupported,
            duration,
            own_pos,
            own_neg,
        });
    }
    g.static_preds.resize(g.predicates.len(), true);
    g.untracked_preds.resize(g.predicates.len(), false);

    // A pure hierarchical problem: tasks are grounded top-down from its
    // network, not over their types.
    let methods: Vec<(Item<'db>, &super::lifted::MethodSchema)> = domain
        .items(db)
        .iter()
        .filter(|i| i.section(db) == Section::Method)
        .filter_map(|&i| method_schema(db, i).as_ref().map(|m| (i, m)))
        .collect();
    let htn = if hierarchy { lifted_htn(db, problem, domain, &ops, &methods) } else { None };
    if htn.is_some() {
        for ((_, op), c) in ops.iter().zip(&mut compiled) {
            if op.kind == OperatorKind::Task {
                c.spec_add.spec.restrict(None);
            }
        }
    }

    // Goal relevance: restrict each parameter to the objects a relevant
    // instance may give it; an operator without any relevant instance is
    // not instantiated at all.
    if relevance
        && htn.is_none()
        && let Some(goal) = relevance_goal(db, problem, domain, &ops, &g)
    {
        let rel_ops: Vec<RelOp> = ops
            .iter()
            .zip(&compiled)
            .map(|((item, op), c)| RelOp {
                domains: c.spec_add.spec.domains(),
                pos: c.pre.iter().chain(&c.own_pos).collect(),
                neg: c.neg.iter().chain(&c.own_neg).collect(),
                add: &c.spec_add.add,
                del: &c.del,
                wild_add: &c.wild_add,
                numeric_effect: op.unsupported.iter().any(|u| u.what == "a numeric effect"),
                numeric_read: !op.pre.numeric.is_empty() || reads_changing_fluent(db, *item, &g),
            })
            .collect();
        let found = super::relevance::relevant(&rel_ops, &goal, g.objects.len());
        drop(rel_ops);
        for (c, r) in compiled.iter_mut().zip(found) {
            c.spec_add.spec.restrict(r.as_deref());
        }
        g.relevance = true;
    }

    // Instantiate them with relaxed reachability.
    let inputs: Vec<&OpInput> = compiled.iter().map(|c| &c.spec_add).collect();
    let mut start: Vec<AtomId> = g.init.facts.iter().map(|(a, _)| *a).collect();
    start.extend(g.init.timed.iter().filter(|t| t.positive).map(|t| t.atom));
    let mut budget = limits.candidates;
    // Top-down grounding prunes the reachable actions afterwards: they may
    // be more than the limit before.
    let max_ops = if htn.is_some() { limits.operators.saturating_mul(4) } else { limits.operators };
    let mut fix = fixpoint(&inputs, &mut g.atoms, &start, g.init.truth().to_vec(), &mut budget, max_ops);
    g.truncated = fix.truncated;
    g.tried = limits.candidates - budget;

    // The instances found, by operator: indices into `fix.instances` (4
    // bytes each; a truncated grounding has 200,000 of them).
    let mut by_op = InstancesByOp::new(&fix.instances, ops.len());
    let mut reached = None;
    let tdg_out = match &htn {
        Some((htn, methods)) if !fix.truncated => {
            let input = super::tdg::Input {
                objects: &g.objects,
                predicates: &g.predicates,
                static_preds: &g.static_preds,
                untracked: &g.untracked_preds,
                atoms: &g.atoms,
                reached: &fix.reached,
                start: &start,
                initial: g.init.truth(),
                ops: &ops,
                pre: compiled.iter().map(|c| c.pre.as_slice()).collect(),
                add: compiled.iter().map(|c| c.spec_add.add.as_slice()).collect(),
                instances: by_op.slices(&fix.instances),
                methods,
                htn,
                budget: limits.candidates.saturating_sub(g.tried),
                // Tasks requested, decomposable, and method instances,
                // together: three times as many as one method may have.
                max_instances: limits.method_instances.max(limits.operators).saturating_mul(3),
            };
            match super::tdg::ground(&input) {
                Some(out) => Some(out),
                None => return ground_with_mode(db, problem, limits, relevance, false),
            }
        }
        _ => None,
    };
    // With top-down grounding, the instances it kept instead.
    let mut kept_by_op: Option<Vec<Vec<&[ObjId]>>> = None;
    if let Some(out) = &tdg_out {
        let lists: Vec<Vec<&[ObjId]>> =
            out.per_op.iter().map(|l| l.iter().map(|a| &a[..]).collect()).collect();
        let kept: usize = lists.iter().map(Vec::len).sum();
        kept_by_op = Some(lists);
        g.truncated = out.truncated || kept > limits.operators;
        g.tried += out.tried;
        g.relevance = true;
        reached = Some(out.reached.clone());
        g.tdg_methods = Some(out.methods.clone());
        g.htn_choices = Some(out.htn_choices.clone());
        g.tdg_splits = out
            .splits
            .iter()
            .map(|x| SplitChoice {
                method: methods[x.method].0,
                subtask: x.subtask,
                args: x.args.clone(),
                choices: x.choices.clone(),
            })
            .collect();
        g.tdg_dominant = out.truncated.then(|| out.dominant.clone().unwrap_or_default());
    }

    // Their exact number, and at most this much for their lists: no
    // doubling past what is needed (a truncated grounding has 200,000).
    let count = |schema: usize| match &kept_by_op {
        Some(lists) => lists[schema].len(),
        None => by_op.of(schema).len(),
    };
    let lists_len: usize = compiled
        .iter()
        .enumerate()
        .map(|(schema, c)| {
            let per = c.spec_add.spec.domains().len()
                + c.pre.len()
                + c.neg.len()
                + c.spec_add.add.len()
                + c.del.len();
            count(schema) * per
        })
        .sum();
    let total: usize = (0..ops.len()).map(count).sum();
    // The fixpoint's deduplication table and spare room are no longer
    // needed: freed before the ground operators are built, the largest part
    // of the peak.
    fix.instances.forget_index();
    // A grounding past its limit that keeps nothing only evaluates the
    // durations of the instances found ([`Limits::keep_past_limit`]).
    let keep = !g.truncated || limits.keep_past_limit;
    if keep {
        g.operators.reserve_exact(total);
        g.lists.reserve_exact(lists_len);
    }
    // Build the ground operators, schema by schema, instances sorted by arguments.
    let mut key = Vec::new();
    let by_args = |a: &[ObjId], b: &[ObjId]| {
        a.iter().zip(b.iter()).map(|(p, q)| p.cmp(q)).find(|o| o.is_ne()).unwrap_or(a.len().cmp(&b.len()))
    };
    for (schema, ((item, op), c)) in ops.iter().zip(&compiled).enumerate() {
        let arity = c.spec_add.spec.domains().len();
        let instances = &fix.instances;
        let found: Box<dyn Iterator<Item = &[ObjId]>> = match &mut kept_by_op {
            Some(lists) => {
                let mut found = std::mem::take(&mut lists[schema]);
                found.sort_unstable_by(|a, b| by_args(a, b));
                Box::new(found.into_iter())
            }
            None => {
                let indices = by_op.of_mut(schema);
                let args = move |k: u32| instances.args_of(k as usize, arity);
                indices.sort_unstable_by(|&a, &b| by_args(args(a), args(b)));
                Box::new(indices.iter().map(move |&k| args(k)))
            }
        };
        let start = g.operators.len() as u32;
        let fixed = match (&op.duration, op.kind) {
            (Duration::None, OperatorKind::Action) => Some(0.0),
            _ => None,
        };
        let mut tally = Tally::default();
        let Ground { atoms, init, objects, functions, operators, lists, .. } = &mut g;
        let env = Env { init, objects, funcs: functions };
        for args in found {
            // Every instance has one argument per parameter (the lists are
            // read by the schema's arity).
            debug_assert_eq!(args.len(), arity);
            if args.len() != arity {
                continue;
            }
            let (duration, no_duration) = match &c.duration {
                None => (fixed, false),
                Some(e) => {
                    let evaluated = env.duration(e, args, op.name_span);
                    let issue = |f: Failure<'db>| DurationIssue {
                        kind: IssueKind::NoInstance,
                        loc: Loc { item: *item, span: f.span },
                        operator: op.name.to_string(),
                        instance: show(&op.name, args, objects),
                        why: f.why,
                        fact: f.fact,
                        count: 1,
                        total: 0,
                    };
                    match evaluated {
                        Ok(Val::Known(v)) => {
                            tally.instance(None);
                            (Some(v), false)
                        }
                        Ok(Val::Dynamic) => {
                            tally.instance(None);
                            (None, false)
                        }
                        Err(f) => {
                            tally.instance(Some((f, &issue)));
                            (None, true)
                        }
                    }
                }
            };
            if !keep {
                continue;
            }
            lists.extend_from_slice(args);
            let at = lists.len();
            let mut ends = [0u32; 4];
            for (n, l) in [&c.pre, &c.neg, &c.spec_add.add, &c.del].into_iter().enumerate() {
                let from = lists.len();
                for a in l {
                    a.key(args, &mut key);
                    lists.push(atoms.intern(&key));
                }
                lists[from..].sort_unstable();
                let mut kept = from;
                for i in from..lists.len() {
                    if kept == from || lists[i] != lists[kept - 1] {
                        lists[kept] = lists[i];
                        kept += 1;
                    }
                }
                lists.truncate(kept);
                ends[n] = (lists.len() - at) as u32;
            }
            operators.push(GroundOperator {
                op: *item,
                schema: schema as u32,
                duration: Duration64(duration.unwrap_or(f64::NAN)),
                no_duration,
                unsupported: c.unsupported,
                at: at as u32,
                ends,
            });
        }
        g.duration_issues.extend(tally.issues());
        g.schemas.push(Schema {
            item: *item,
            name: op.name.clone(),
            kind: op.kind,
            arity: arity as u32,
            start,
            end: g.operators.len() as u32,
            wild_add: c.wild_add.clone(),
            unsupported: c.unsupported,
            candidates: c.spec_add.spec.candidates(),
        });
    }
    g.reachable = reached.unwrap_or(fix.reached);
    g.reachable.resize(g.atoms.len(), false);
    g
}

/// The instances of a fixpoint grouped by operator, each group in the order
/// found: their indices in [`Instances`], one array for all.
struct InstancesByOp {
    /// Where each operator's group starts in `indices`, and where the last ends.
    starts: Vec<usize>,
    indices: Vec<u32>,
}

impl InstancesByOp {
    fn new(instances: &Instances, ops: usize) -> InstancesByOp {
        let mut starts = vec![0usize; ops + 1];
        for k in 0..instances.len() {
            let op = instances.get(k).0;
            if op < ops {
                starts[op + 1] += 1;
            }
        }
        for i in 0..ops {
            starts[i + 1] += starts[i];
        }
        let mut next = starts.clone();
        let mut indices = vec![0u32; starts[ops]];
        for k in 0..instances.len() {
            let op = instances.get(k).0;
            if op < ops {
                indices[next[op]] = k as u32;
                next[op] += 1;
            }
        }
        InstancesByOp { starts, indices }
    }

    fn of(&self, op: usize) -> &[u32] {
        &self.indices[self.starts[op]..self.starts[op + 1]]
    }

    fn of_mut(&mut self, op: usize) -> &mut [u32] {
        &mut self.indices[self.starts[op]..self.starts[op + 1]]
    }

    /// Each operator's instances as their arguments.
    fn slices<'a>(&self, instances: &'a Instances) -> Vec<Vec<&'a [ObjId]>> {
        (0..self.starts.len() - 1)
            .map(|op| self.of(op).iter().map(|&k| instances.get(k as usize).1).collect())
            .collect()
    }
}

/// The problem's `:htn` lifted, with the domain's methods, when the problem
/// is purely hierarchical (an `:htn`, no allowed actions) and every method's
/// task and subtasks are operators of the domain with terms grounding can
/// name: then the planner grounds it top-down ([`super::tdg`]).
fn lifted_htn<'a, 'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    domain: Unit<'db>,
    ops: &[(Item<'db>, &super::lifted::Operator)],
    methods: &'a [(Item<'db>, &'a super::lifted::MethodSchema)],
) -> Option<(super::tdg::LiftedHtn, &'a [(Item<'db>, &'a super::lifted::MethodSchema)])> {
    let mut htn = None;
    for &item in problem.items(db) {
        match &lower_item(db, item).data {
            ItemData::AllowedActions(_) => return None,
            ItemData::Htn(h) => htn = Some(h),
            _ => {}
        }
    }
    let h = htn?;
    let n_methods = domain.items(db).iter().filter(|i| i.section(db) == Section::Method).count();
    if n_methods != methods.len() {
        return None;
    }
    let kind = |name: &str| ops.iter().find(|(_, op)| op.name == name).map(|(_, op)| op.kind);
    let named = |ts: &[LTerm]| ts.iter().all(|t| !matches!(t, LTerm::Free(_)));
    for (_, m) in methods {
        let (task, args, _) = m.task.as_ref()?;
        if kind(task) != Some(OperatorKind::Task) || !named(args) {
            return None;
        }
        if m.subtasks.iter().any(|s| kind(&s.name).is_none() || !named(&s.args)) {
            return None;
        }
    }
    let params: Vec<super::lifted::Param> = h
        .params
        .iter()
        .map(|t| super::lifted::Param {
            name: t.name.key_str(),
            types: crate::semantics::symbols::type_set(&t.ty),
            span: t.name.span,
        })
        .collect();
    let mut subtasks = Vec::new();
    for st in &h.network.subtasks {
        kind(st.call.name.key())?;
        let args = st
            .call
            .args
            .iter()
            .map(|t| match t {
                Term::Var(n) => params.iter().position(|p| p.name == n.key()).map(|i| LTerm::Param(i as u32)),
                Term::Const(n) => Some(LTerm::Const(n.key_sym())),
                Term::Func(_) => None,
            })
            .collect::<Option<Vec<LTerm>>>()?;
        subtasks.push((st.call.name.key_str(), args));
    }
    Some((super::tdg::LiftedHtn { params, subtasks }, methods))
}

/// The goal as [`super::relevance`] reads it, or `None` when relevance
/// cannot be applied soundly: a task network or methods (decomposition
/// needs what methods give, not what the goal needs), timed initial
/// literals (a step may be needed only to last past one), derived predicates,
/// PDDL 3 constraints or preferences, processes and events, or an operator
/// with a construct the STRIPS view leaves out (a disjunctive or quantified
/// condition, a conditional or quantified effect, an object fluent) other
/// than a numeric effect.
fn relevance_goal<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    domain: Unit<'db>,
    ops: &[(Item<'db>, &super::lifted::Operator)],
    g: &Ground<'db>,
) -> Option<RelGoal> {
    let blocked = |u: Unit<'db>| {
        u.items(db).iter().any(|i| {
            matches!(i.section(db), Section::Method | Section::Derived | Section::Htn | Section::Constraints)
        })
    };
    // Timed initial literals: VAL applies none after a plan's last
    // happening, so a goal a literal makes true needs some step, any step,
    // that ends after it (tests/planner/props/goal-made-by-a-late-timed-literal.pddl).
    if blocked(domain) || blocked(problem) || !g.init.timed.is_empty() {
        return None;
    }
    for (item, op) in ops {
        if op.unsupported.iter().any(|u| u.what != "a numeric effect") {
            return None;
        }
        if let ItemData::Action(a) = &lower_item(db, *item).data
            && matches!(a.kind, ActionKind::Process | ActionKind::Event)
        {
            return None;
        }
    }
    let mut goal = RelGoal::default();
    for &item in problem.items(db) {
        if let ItemData::Goal(gd) = &lower_item(db, item).data {
            goal_atoms(gd, Some(true), g, &mut goal)?;
        }
    }
    Some(goal)
}

/// Adds the atoms of a goal formula under `polarity` (`None`: both, inside a
/// disjunction) to `out`; `None` for what relevance cannot read.
fn goal_atoms(gd: &Gd, polarity: Option<bool>, g: &Ground<'_>, out: &mut RelGoal) -> Option<()> {
    match gd {
        Gd::Atom(a) => {
            let Some(pred) = g.predicates.get(a.pred.key()) else { return Some(()) };
            if g.is_static(pred) {
                return Some(());
            }
            // A variable (quantified) or a term that is no object: any object.
            let args: Vec<Option<ObjId>> = a
                .args
                .iter()
                .map(|t| match t {
                    Term::Const(c) => g.objects.id(c.key()),
                    _ => None,
                })
                .collect();
            if polarity != Some(false) {
                out.pos.push(GoalAtom { pred, args: args.clone() });
            }
            if polarity != Some(true) {
                out.neg.push(GoalAtom { pred, args });
            }
        }
        Gd::Equal(..) => {}
        Gd::Compare(..) => out.numeric = true,
        Gd::Not(inner, _) => goal_atoms(inner, polarity.map(|p| !p), g, out)?,
        Gd::And(gs, _) => gs.iter().try_for_each(|x| goal_atoms(x, polarity, g, out))?,
        Gd::Or(gs, _) => gs.iter().try_for_each(|x| goal_atoms(x, None, g, out))?,
        Gd::Imply(a, b, _) => {
            goal_atoms(a, None, g, out)?;
            goal_atoms(b, None, g, out)?;
        }
        Gd::Forall(_, inner, _) | Gd::Exists(_, inner, _) | Gd::Timed(_, inner, _) => {
            goal_atoms(inner, polarity, g, out)?
        }
        Gd::Preference(..) | Gd::Modal(..) | Gd::Order(_) | Gd::Sortof(..) => return None,
    }
    Some(())
}

/// Whether an operator's duration may read a fluent that effects change (a
/// bound only, or an expression over such a fluent): then the effects that
/// change it matter to whoever needs the operator.
fn reads_changing_fluent(db: &dyn Db, item: Item<'_>, g: &Ground<'_>) -> bool {
    fn reads(e: &NumExpr, g: &Ground<'_>) -> bool {
        match e {
            NumExpr::Fluent(f) => g
                .functions
                .get(f.func.key())
                .is_none_or(|id| g.dynamic_funcs.get(id as usize) != Some(&false)),
            NumExpr::Op(_, es, _) => es.iter().any(|e| reads(e, g)),
            NumExpr::Number(_) | NumExpr::Duration(_) | NumExpr::TaskDuration(..) | NumExpr::Var(_) => false,
            NumExpr::Special(..) => true,
        }
    }
    fn gd_reads(d: &Gd, g: &Ground<'_>) -> bool {
        match d {
            Gd::Compare(_, a, b, _) => reads(a, g) || reads(b, g),
            Gd::And(gs, _) => gs.iter().any(|x| gd_reads(x, g)),
            _ => true,
        }
    }
    let duration = match &lower_item(db, item).data {
        ItemData::Action(a) => a.duration.as_ref(),
        ItemData::Task(t) => t.duration.as_ref(),
        _ => None,
    };
    duration.is_some_and(|d| gd_reads(d, g))
}

/// The functions an effect changes.
fn numeric_targets(e: Option<&Effect>, funcs: &mut Interner, out: &mut Vec<FuncId>) {
    let Some(e) = e else { return };
    match e {
        Effect::Numeric(_, f, _, _) => out.push(funcs.intern(f.func.key())),
        Effect::And(es, _) => es.iter().for_each(|e| numeric_targets(Some(e), funcs, out)),
        Effect::Forall(_, e, _) | Effect::When(_, e, _) | Effect::Timed(_, e, _) => {
            numeric_targets(Some(e), funcs, out)
        }
        Effect::Add(_) | Effect::Del(..) => {}
    }
}

/// One instance of a method.
#[derive(Debug, Clone, PartialEq, Eq, salsa::SalsaValue)]
pub struct GroundMethod<'db> {
    pub method: Item<'db>,
    /// The method's parameters' values, in declaration order.
    pub args: Box<[ObjId]>,
    /// The task it refines, with its arguments.
    pub task: (Str, Box<[ObjId]>),
    /// Its subtasks (actions or tasks) in the order written.
    pub subtasks: Vec<(Str, Box<[ObjId]>)>,
}

/// The instances of a problem's methods.
#[derive(Debug, Clone, PartialEq, Eq, Default, salsa::SalsaValue)]
pub struct GroundMethods<'db> {
    pub methods: Vec<GroundMethod<'db>>,
    /// Methods whose instances were cut at [`Limits::method_instances`], or
    /// where the candidate budget ran out (every later method is then skipped too).
    pub truncated: Vec<Item<'db>>,
    /// Methods whose task or subtasks have terms grounding cannot name (an
    /// object fluent): not grounded.
    pub skipped: Vec<Item<'db>>,
}

/// Grounds a problem's methods with the default [`Limits`]: separate from
/// [`ground`] because methods with many free parameters are costly, and only
/// some lints need them.
#[salsa::tracked(returns(ref))]
pub fn ground_methods<'db>(db: &'db dyn Db, problem: Unit<'db>) -> GroundMethods<'db> {
    ground_methods_with(db, problem, ground(db, problem), Limits::DEFAULT)
}

/// Grounds a problem's methods over `g` within `limits`: the instances whose
/// types fit, whose (in)equalities and static preconditions hold and whose
/// other positive preconditions are relaxed-reachable. Which subtasks can be
/// decomposed is not considered.
pub fn ground_methods_with<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    g: &Ground<'db>,
    limits: Limits,
) -> GroundMethods<'db> {
    let mut out = GroundMethods::default();
    visit_methods(db, problem, g, limits, &mut |event| match event {
        MethodEvent::Instance(m) => out.methods.push(GroundMethod {
            method: m.method,
            args: m.binding.into(),
            task: (m.task.into(), m.task_args.into()),
            subtasks: m.subtasks().map(|(n, a)| (n.into(), a.into())).collect(),
        }),
        MethodEvent::Done(_) => {}
        MethodEvent::Truncated(item) => out.truncated.push(item),
        MethodEvent::Skipped(item) => out.skipped.push(item),
    });
    out
}

/// One instance of a method, borrowed from [`visit_methods`]' buffers.
pub struct MethodVisit<'a, 'db> {
    pub method: Item<'db>,
    /// The method's parameters' values, in declaration order.
    pub binding: &'a [ObjId],
    /// The task it refines, with its arguments.
    pub task: &'a str,
    pub task_args: &'a [ObjId],
    names: &'a [Str],
    args: &'a [ObjId],
    ends: &'a [usize],
}

impl<'a> MethodVisit<'a, '_> {
    /// Its subtasks (actions or tasks) in the order written, with their arguments.
    pub fn subtasks(&self) -> impl Iterator<Item = (&'a str, &'a [ObjId])> + '_ {
        self.names.iter().enumerate().map(|(j, n)| {
            let start = if j == 0 { 0 } else { self.ends[j - 1] };
            (n.as_str(), &self.args[start..self.ends[j]])
        })
    }
}

/// What [`visit_methods`] reports, method by method.
pub enum MethodEvent<'a, 'db> {
    /// An instance of the current method.
    Instance(&'a MethodVisit<'a, 'db>),
    /// The method's instances are complete (there may be none).
    Done(Item<'db>),
    /// The method's instances were cut at a limit (those reported are a part).
    Truncated(Item<'db>),
    /// The method has terms grounding cannot name: no instance.
    Skipped(Item<'db>),
}

/// Calls `f` on each instance of a problem's methods over `g` within
/// `limits` (see [`ground_methods_with`]), without keeping them (a large HTN
/// problem has millions), then says whether that method's instances are
/// complete.
pub fn visit_methods<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    g: &Ground<'db>,
    limits: Limits,
    f: &mut dyn FnMut(MethodEvent<'_, 'db>),
) {
    let Some(domain) = domain_for(db, problem).filter(|_| problem.kind(db) == UnitKind::Problem) else {
        return;
    };
    let facts = Facts::from_reached(&g.reachable, g.init.truth().to_vec(), &g.atoms);
    let mut budget = limits.candidates;
    let mut exhausted = false;
    let (mut task_buf, mut args_buf, mut ends): (Vec<ObjId>, Vec<ObjId>, Vec<usize>) = Default::default();
    for &item in domain.items(db).iter().filter(|i| i.section(db) == Section::Method) {
        let Some(m) = method_schema(db, item) else { continue };
        let Some((task, task_args, _)) = &m.task else { continue };
        if exhausted {
            f(MethodEvent::Truncated(item));
            continue;
        }
        let mut cx = Compiler {
            objects: &g.objects,
            preds: Preds::Get(&g.predicates),
            static_preds: &g.static_preds,
            untracked: &g.untracked_preds,
            derived: &[],
            unsupported: false,
        };
        let spec = cx.spec(&m.params, &m.pre);
        let args = |ts: &[LTerm]| ts.iter().map(|t| cx.arg(t)).collect::<Option<Vec<Arg>>>();
        let task_args = args(task_args);
        let subtasks: Option<Vec<Vec<Arg>>> = m.subtasks.iter().map(|s| args(&s.args)).collect();
        let (Some(task_args), Some(subtasks)) = (task_args, subtasks) else {
            f(MethodEvent::Skipped(item));
            continue;
        };
        let names: Vec<Str> = m.subtasks.iter().map(|s| s.name.clone()).collect();
        let mut count = 0;
        let mut emit = |binding: &[ObjId]| {
            if count >= limits.method_instances {
                return ControlFlow::Break(());
            }
            count += 1;
            task_buf.clear();
            task_buf.extend(task_args.iter().map(|x| value(*x, binding)));
            args_buf.clear();
            ends.clear();
            for a in &subtasks {
                args_buf.extend(a.iter().map(|x| value(*x, binding)));
                ends.push(args_buf.len());
            }
            f(MethodEvent::Instance(&MethodVisit {
                method: item,
                binding,
                task,
                task_args: &task_buf,
                names: &names,
                args: &args_buf,
                ends: &ends,
            }));
            ControlFlow::Continue(())
        };
        let flow = match &g.tdg_methods {
            // Grounded top-down: the instances found then.
            Some(found) => {
                let bindings = found.iter().find(|(i, _)| *i == item).map_or(&[][..], |(_, b)| b.as_slice());
                match bindings.iter().try_for_each(|b| emit(b)) {
                    ControlFlow::Continue(()) => ControlFlow::Continue(()),
                    ControlFlow::Break(()) => ControlFlow::Break(Stop::Caller),
                }
            }
            None => instances_over(&spec, &g.atoms, &facts, &mut budget, &mut emit),
        };
        match flow {
            ControlFlow::Continue(()) => f(MethodEvent::Done(item)),
            ControlFlow::Break(stop) => {
                f(MethodEvent::Truncated(item));
                exhausted = stop == Stop::Budget;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AnalysisHost;
    use crate::db::file_units;
    use crate::verify::reach::reachable;

    /// A truncated grounding holds 200,000 instances: each is 48 bytes
    /// (56 with an `Option<f64>` duration and the arity in every instance).
    #[test]
    fn ground_operators_stay_small() {
        assert!(size_of::<GroundOperator<'_>>() <= 48, "{}", size_of::<GroundOperator<'_>>());
    }

    /// An operator without duration equals itself (NaN inside), so that a
    /// ground problem compares equal to its copy.
    #[test]
    fn an_operator_without_duration_equals_itself() {
        let dom = "(define (domain d) (:requirements :durative-actions)
            (:predicates (p ?x) (q ?x))
            (:durative-action a :parameters (?x) :duration (>= ?duration 1)
              :condition (at start (p ?x)) :effect (at end (q ?x))))";
        let prob = "(define (problem p) (:domain d) (:objects o1 o2) (:init (p o1) (p o2)) (:goal (q o1)))";
        with_problem(dom, prob, |db, unit| {
            let g = ground(db, unit);
            assert_eq!(g.operators.len(), 2);
            assert!(g.operators.iter().all(|o| o.duration().is_none()));
            assert_eq!(g.args(&g.operators[1]).len(), 1);
            assert!(g == &g.clone());
        });
    }

    /// The values `:init` gives numeric fluents: the first of a fluent set
    /// twice, found by function and arguments, listed in the order written.
    #[test]
    fn initial_fluent_values_keep_the_first_in_the_order_written() {
        let dom = "(define (domain d) (:requirements :fluents)
            (:functions (dist ?a ?b) (fuel))
            (:action go :parameters (?a ?b) :precondition (> (dist ?a ?b) 0) :effect (decrease (fuel) 1)))";
        let prob = "(define (problem p) (:domain d) (:objects x y)
            (:init (= (dist y x) 4) (= (fuel) 10) (= (dist x y) 2) (= (dist y x) 5)) (:goal (and)))";
        with_problem(dom, prob, |db, unit| {
            let g = ground(db, unit);
            let f = |name: &str| g.functions.get(name).unwrap();
            let o = |name: &str| g.objects.id(name).unwrap();
            let value = |func: &str, args: &[&str]| {
                let args: Vec<ObjId> = args.iter().map(|a| o(a)).collect();
                g.init.fluent(f(func), &args).map(|(v, _)| v)
            };
            assert_eq!(value("dist", &["y", "x"]), Some(4.0));
            assert_eq!(value("dist", &["x", "y"]), Some(2.0));
            assert_eq!(value("fuel", &[]), Some(10.0));
            assert_eq!(value("dist", &["x", "x"]), None);
            let written: Vec<(Vec<u32>, f64)> =
                g.init.fluents.iter().map(|(k, &(v, _))| (k.to_vec(), v)).collect();
            let (dist, fuel, x, y) = (f("dist"), f("fuel"), o("x"), o("y"));
            assert_eq!(written, [(vec![dist, y, x], 4.0), (vec![fuel], 10.0), (vec![dist, x, y], 2.0)]);
            assert_eq!(g.init.fluents.len(), 3);
        });
    }

    /// A host with a domain and a problem; `f` gets the problem's unit.
    fn with_problem<T>(domain: &str, problem: &str, f: impl FnOnce(&dyn Db, Unit<'_>) -> T) -> T {
        let mut host = AnalysisHost::new();
        host.set_file_text("d/domain.pddl", domain);
        let p = host.set_file_text("d/problem.pddl", problem);
        let db = host.db();
        let unit = file_units(db, p)[0];
        f(db, unit)
    }

    /// The instances of every operator, as text, sorted.
    fn instances(g: &Ground<'_>) -> Vec<String> {
        let mut v: Vec<String> = g.operators.iter().map(|o| g.show_operator(o)).collect();
        v.sort();
        v
    }

    fn ground_texts(domain: &str, problem: &str) -> Vec<String> {
        with_problem(domain, problem, |db, p| instances(ground(db, p)))
    }

    const TYPES: &str = "(define (domain t) (:requirements :typing :equality)
      (:types vehicle place - object truck car - vehicle tank - truck)
      (:constants depot - place)
      (:predicates (at ?v - vehicle ?p - place) (ok ?x - (either truck place)) (done))
      (:action park :parameters (?v - truck ?p - place) :precondition (at ?v ?p) :effect (done))
      (:action mark :parameters (?x - (either truck place)) :effect (ok ?x))
      (:action home :parameters (?v - vehicle) :precondition (at ?v depot) :effect (done)))";

    #[test]
    fn types_either_subtypes_and_constants() {
        let got = ground_texts(
            TYPES,
            "(define (problem p) (:domain t) (:objects t1 - truck k1 - tank c1 - car a - place)
              (:init (at t1 a) (at k1 depot) (at c1 depot)))",
        );
        assert_eq!(
            got,
            [
                "(home c1)",
                "(home k1)",
                "(mark a)",
                "(mark depot)",
                "(mark k1)",
                "(mark t1)",
                // `at` is static here: parking needs the truck where it is.
                "(park k1 depot)",
                "(park t1 a)",
            ]
        );
    }

    #[test]
    fn equality_constraints() {
        let d = "(define (domain e) (:requirements :equality)
          (:predicates (p ?a ?b))
          (:action diff :parameters (?a ?b) :precondition (not (= ?a ?b)) :effect (p ?a ?b))
          (:action same :parameters (?a ?b) :precondition (= ?a ?b) :effect (p ?a ?b)))";
        let got = ground_texts(d, "(define (problem p) (:domain e) (:objects x y) (:init))");
        assert_eq!(got, ["(diff x y)", "(diff y x)", "(same x x)", "(same y y)"]);
    }

    #[test]
    fn static_predicates_prune_and_are_left_out() {
        let d = "(define (domain s) (:requirements :negative-preconditions)
          (:predicates (at ?w) (adjacent ?a ?b) (blocked ?w))
          (:action move :parameters (?a ?b)
            :precondition (and (at ?a) (adjacent ?a ?b) (not (blocked ?b)))
            :effect (and (not (at ?a)) (at ?b))))";
        let p = "(define (problem p) (:domain s) (:objects a b c d)
          (:init (at a) (adjacent a b) (adjacent b c) (adjacent a d) (adjacent c a) (blocked d)))";
        with_problem(d, p, |db, unit| {
            let g = ground(db, unit);
            assert_eq!(instances(g), ["(move a b)", "(move b c)", "(move c a)"]);
            let adjacent = g.predicates.get("adjacent").unwrap();
            let blocked = g.predicates.get("blocked").unwrap();
            let at = g.predicates.get("at").unwrap();
            assert!(g.is_static(adjacent) && g.is_static(blocked) && !g.is_static(at));
            // Only `at` remains in the ground lists.
            let o = &g.operators[0];
            let shown = |l: &[AtomId]| l.iter().map(|&a| g.show_atom(a)).collect::<Vec<_>>();
            assert_eq!(shown(g.pre(o)), ["(at a)"]);
            assert_eq!(shown(g.add(o)), ["(at b)"]);
            assert_eq!(shown(g.del(o)), ["(at a)"]);
            assert!(g.neg_pre(o).is_empty());
        });
    }

    #[test]
    fn only_reachable_instances_are_kept() {
        let d = "(define (domain r)
          (:predicates (at ?w) (road ?a ?b) (visited ?w))
          (:action go :parameters (?a ?b) :precondition (and (at ?a) (road ?a ?b))
            :effect (and (not (at ?a)) (at ?b) (visited ?b))))";
        // `d` is on a road, but nothing reaches `c`.
        let p = "(define (problem p) (:domain r) (:objects a b c d)
          (:init (at a) (road a b) (road b a) (road c d)))";
        with_problem(d, p, |db, unit| {
            let g = ground(db, unit);
            assert_eq!(instances(g), ["(go a b)", "(go b a)"]);
            let visited = |w: &str| {
                let id = g.atoms.find(g.predicates.get("visited").unwrap(), &[g.objects.id(w).unwrap()]);
                id.is_some_and(|a| g.is_reachable(a))
            };
            assert!(visited("a") && visited("b") && !visited("d"));
        });
    }

    #[test]
    fn four_parameters_drawn_from_facts() {
        // The naive product is 3 × 3 × 4 × 4; only the facts' tuples are tried.
        let d = "(define (domain c) (:types robot wp)
          (:predicates (at ?r - robot ?w - wp) (visible-com ?r1 ?r2 - robot ?w1 ?w2 - wp) (met ?r1 ?r2 - robot))
          (:action talk :parameters (?r1 ?r2 - robot ?w1 ?w2 - wp)
            :precondition (and (at ?r1 ?w1) (at ?r2 ?w2) (visible-com ?r1 ?r2 ?w1 ?w2)) :effect (met ?r1 ?r2)))";
        let p = "(define (problem p) (:domain c) (:objects r1 r2 r3 - robot a b c d - wp)
          (:init (at r1 a) (at r2 b) (at r3 c)
            (visible-com r1 r2 a b) (visible-com r2 r1 b a) (visible-com r1 r3 a d) (visible-com r3 r3 c c)))";
        let got = ground_texts(d, p);
        assert_eq!(got, ["(talk r1 r2 a b)", "(talk r2 r1 b a)", "(talk r3 r3 c c)"]);
    }

    #[test]
    fn timed_literals_are_not_static_and_count_as_reached() {
        let d = "(define (domain w) (:requirements :timed-initial-literals)
          (:predicates (window) (done))
          (:action act :parameters () :precondition (window) :effect (done)))";
        let p = "(define (problem p) (:domain w) (:init (at 10 (window)) (at 20 (not (window)))))";
        with_problem(d, p, |db, unit| {
            let g = ground(db, unit);
            assert!(!g.is_static(g.predicates.get("window").unwrap()));
            assert_eq!(instances(g), ["(act)"]);
            assert_eq!(g.init.timed.len(), 2);
            assert!(!g.init.holds(g.init.timed[0].atom));
        });
    }

    const DURATIONS: &str = "(define (domain m) (:requirements :typing :durative-actions :numeric-fluents)
      (:types robot wp)
      (:predicates (at ?r - robot ?w - wp) (adjacent ?a ?b - wp))
      (:functions (distance ?a ?b - wp) (speed ?r - robot) (battery ?r - robot))
      (:durative-action move :parameters (?r - robot ?a ?b - wp)
        :duration (= ?duration (/ (distance ?a ?b) (speed ?r)))
        :condition (and (at start (at ?r ?a)) (over all (adjacent ?a ?b)))
        :effect (and (at start (not (at ?r ?a))) (at end (at ?r ?b)))))";

    fn duration_problem(init: &str) -> String {
        format!("(define (problem p) (:domain m) (:objects r1 r2 - robot a b c - wp) (:init {init}))")
    }

    #[test]
    fn durations_are_evaluated_from_fluents() {
        let p = duration_problem(
            "(at r1 a) (at r2 a) (adjacent a b) (adjacent b c) (= (speed r1) 2) (= (speed r2) 0.5)
             (= (distance a b) 30) (= (distance b c) (- 12 2))",
        );
        with_problem(DURATIONS, &p, |db, unit| {
            let g = ground(db, unit);
            let durations: Vec<(String, Option<f64>)> =
                g.operators.iter().map(|o| (g.show_operator(o), o.duration())).collect();
            let expected = [
                ("(move r1 a b)", 15.0),
                ("(move r1 b c)", 5.0),
                ("(move r2 a b)", 60.0),
                ("(move r2 b c)", 20.0),
            ];
            assert_eq!(durations, expected.map(|(s, d)| (s.to_string(), Some(d))));
            assert!(g.duration_issues.is_empty());
            // The value's location is the `=` fact.
            let speed = g.functions.get("speed").unwrap();
            let (v, loc) = g.init.fluent(speed, &[g.objects.id("r1").unwrap()]).unwrap();
            assert_eq!(v, 2.0);
            assert_eq!(loc.item.section(db), Section::Init);
        });
    }

    #[test]
    fn a_missing_fluent_is_reported_once_per_operator() {
        let p = duration_problem(
            "(at r1 a) (at r2 a) (adjacent a b) (adjacent b c) (= (speed r1) 2) (= (speed r2) 1) (= (distance a b) 30)",
        );
        with_problem(DURATIONS, &p, |db, unit| {
            let g = ground(db, unit);
            assert_eq!(g.duration_issues.len(), 1);
            let issue = &g.duration_issues[0];
            assert_eq!(issue.instance, "(move r1 b c)");
            assert_eq!(issue.why, "`(distance b c)` has no value in `:init`");
            assert_eq!(issue.count, 2);
            assert_eq!(issue.fact, None);
            let none: Vec<bool> = g.operators.iter().map(|o| o.duration().is_none()).collect();
            assert_eq!(none, [false, true, false, true]);
        });
    }

    #[test]
    fn division_by_zero_is_reported_with_the_fact() {
        let p = duration_problem("(at r1 a) (adjacent a b) (= (speed r1) 0) (= (distance a b) 30)");
        with_problem(DURATIONS, &p, |db, unit| {
            let g = ground(db, unit);
            let issue = &g.duration_issues[0];
            assert_eq!(issue.why, "`(/ (distance a b) (speed r1))` divides by zero (`(speed r1)` is 0)");
            assert!(issue.fact.is_some_and(|f| f.item.section(db) == Section::Init));
            assert_eq!(g.operators[0].duration(), None);
        });
    }

    #[test]
    fn durations_without_a_single_value() {
        let d = "(define (domain n) (:requirements :durative-actions :numeric-fluents)
          (:predicates (p) (q))
          (:functions (fuel) (rate))
          (:action inst :parameters () :effect (p))
          (:durative-action bounded :parameters () :duration (<= ?duration (rate)) :condition () :effect (at end (q)))
          (:durative-action refuel :parameters () :duration (= ?duration (/ (- 10 (fuel)) (rate)))
            :condition () :effect (at end (increase (fuel) 1))))";
        // `fuel` changes: its value (even absent) gives no single duration, and no issue.
        let p = "(define (problem p) (:domain n) (:init (= (rate) 2)))";
        with_problem(d, p, |db, unit| {
            let g = ground(db, unit);
            let durations: Vec<Option<f64>> = g.operators.iter().map(|o| o.duration()).collect();
            assert_eq!(durations, [Some(0.0), None, None]);
            assert!(g.duration_issues.is_empty());
            assert!(g.dynamic_funcs[g.functions.get("fuel").unwrap() as usize]);
        });
    }

    #[test]
    fn reachability_with_a_filter() {
        let d = "(define (domain f)
          (:predicates (a) (b) (c) (d))
          (:action ab :parameters () :precondition (a) :effect (b))
          (:action bc :parameters () :precondition (b) :effect (c))
          (:action cd :parameters () :precondition (and (b) (c)) :effect (d)))";
        let p = "(define (problem p) (:domain f) (:init (a)))";
        with_problem(d, p, |db, unit| {
            let g = ground(db, unit);
            assert_eq!(g.operators.len(), 3);
            let atom = |n: &str| g.atoms.find(g.predicates.get(n).unwrap(), &[]).unwrap();
            let all = reachable(g, |_| true);
            assert!(["a", "b", "c", "d"].iter().all(|n| all.atom(atom(n))));
            assert!((0..3).all(|i| all.operator(i)));
            let bc = g.schemas[1].item;
            let some = reachable(g, |o| o.op != bc);
            assert!(some.atom(atom("b")) && !some.atom(atom("c")) && !some.atom(atom("d")));
            assert_eq!(some.operators, [true, false, false]);
        });
    }

    #[test]
    fn limits_truncate_instead_of_hanging() {
        let d = "(define (domain big) (:predicates (p ?a ?b ?c ?d))
          (:action make :parameters (?a ?b ?c ?d) :effect (p ?a ?b ?c ?d))
          (:task t :parameters (?a ?b))
          (:method m :parameters (?a ?b ?c ?d) :task (t ?a ?b) :subtasks (make ?a ?b ?c ?d)))";
        let objects: Vec<String> = (0..40).map(|i| format!("o{i}")).collect();
        let p = format!("(define (problem p) (:domain big) (:objects {}) (:init))", objects.join(" "));
        with_problem(d, &p, |db, unit| {
            // 40⁴ = 2,560,000 candidate instances of `make`.
            let limits = Limits {
                candidates: 100_000,
                operators: 1_000_000,
                method_instances: 10,
                keep_past_limit: true,
            };
            let g = ground_with(db, unit, limits);
            assert!(g.truncated);
            assert!(g.operators.len() < 100_000);
            let limits = Limits {
                candidates: 10_000_000,
                operators: 5_000,
                method_instances: 10,
                keep_past_limit: true,
            };
            let g = ground_with(db, unit, limits);
            assert!(g.truncated);
            assert_eq!(g.operators_of(g.schemas[0].item).len(), 5_000);
            let m = ground_methods_with(db, unit, &g, limits);
            assert_eq!(m.methods.len(), 10);
            assert_eq!(m.truncated.len(), 1);
        });
    }

    #[test]
    fn a_grounding_past_the_lints_limit_keeps_no_operator_but_evaluates_every_duration() {
        let d = "(define (domain trips) (:requirements :durative-actions :fluents)
          (:predicates (at ?p) (seen ?p))
          (:functions (distance ?a ?b))
          (:durative-action go :parameters (?a ?b)
            :duration (= ?duration (distance ?a ?b))
            :condition (at start (at ?a))
            :effect (and (at start (not (at ?a))) (at end (at ?b)) (at end (seen ?b)))))";
        let objects: Vec<String> = (0..40).map(|i| format!("o{i}")).collect();
        // Distances for the trips out of o0 only: the other 1,560 instances
        // of `go` have no duration.
        let distances: Vec<String> = (1..40).map(|i| format!("(= (distance o0 o{i}) {i})")).collect();
        let p = format!(
            "(define (problem p) (:domain trips) (:objects {}) (:init (at o0) {}))",
            objects.join(" "),
            distances.join(" ")
        );
        with_problem(d, &p, |db, unit| {
            let kept = Limits { operators: 500, keep_past_limit: true, ..Limits::DEFAULT };
            let kept = ground_with(db, unit, kept);
            let not_kept = ground_with(db, unit, Limits { operators: 500, ..Limits::DEFAULT });
            assert!(kept.truncated && not_kept.truncated);
            assert_eq!(kept.operators.len(), 500);
            assert!(not_kept.operators.is_empty());
            assert!(!kept.duration_issues.is_empty());
            assert_eq!(kept.duration_issues, not_kept.duration_issues);
        });
    }

    #[test]
    fn methods_are_grounded_with_their_task_and_subtasks() {
        let d = "(define (domain h) (:requirements :typing :hierarchy)
          (:types robot wp)
          (:predicates (at ?r - robot ?w - wp) (road ?a ?b - wp))
          (:task goto :parameters (?r - robot ?w - wp))
          (:action move :parameters (?r - robot ?a ?b - wp) :precondition (and (at ?r ?a) (road ?a ?b))
            :effect (and (not (at ?r ?a)) (at ?r ?b)))
          (:method direct :parameters (?r - robot ?a ?b - wp) :task (goto ?r ?b)
            :precondition (road ?a ?b) :subtasks (move ?r ?a ?b)))";
        let p = "(define (problem p) (:domain h) (:objects r - robot a b c - wp)
          (:init (at r a) (road a b) (road b c)))";
        with_problem(d, p, |db, unit| {
            let g = ground(db, unit);
            let m = ground_methods(db, unit);
            let shown: Vec<String> = m
                .methods
                .iter()
                .map(|gm| {
                    let names = |args: &[ObjId]| {
                        args.iter().map(|&o| g.objects.name(o)).collect::<Vec<_>>().join(" ")
                    };
                    format!(
                        "{} {} -> {}",
                        gm.task.0,
                        names(&gm.task.1),
                        gm.subtasks[0].0.clone() + " " + &names(&gm.subtasks[0].1)
                    )
                })
                .collect();
            assert_eq!(shown, ["goto r b -> move r a b", "goto r c -> move r b c"]);
            assert!(m.truncated.is_empty());
        });
    }

    #[test]
    fn derived_preconditions_are_assumed_reachable() {
        let d = "(define (domain x) (:requirements :derived-predicates)
          (:predicates (p ?a) (q ?a) (ready ?a))
          (:derived (ready ?a) (p ?a))
          (:action go :parameters (?a) :precondition (ready ?a) :effect (q ?a)))";
        let p = "(define (problem p) (:domain x) (:objects a b) (:init (p a)))";
        with_problem(d, p, |db, unit| {
            let g = ground(db, unit);
            // Without axioms, `(ready b)` may hold as well as `(ready a)`.
            assert_eq!(instances(g), ["(go a)", "(go b)"]);
            assert!(g.operators.iter().all(|o| o.unsupported && g.pre(o).is_empty()));
            assert!(g.untracked_preds[g.predicates.get("ready").unwrap() as usize]);
        });
    }

    #[test]
    fn the_planner_grounds_only_what_the_goal_may_need() {
        // `hold`'s `over all (p ?y)` is left out of its lifted preconditions
        // (its start may add it, when `?x` is `?y`); relevance still needs
        // `(p b)` for `(hold a b)`, hence `(make b)`.
        let d = "(define (domain g) (:requirements :durative-actions :typing)
          (:types s t)
          (:predicates (p ?a) (q ?a) (done ?a ?b))
          (:durative-action hold :parameters (?x - s ?y - t) :duration (= ?duration 1)
            :condition (over all (p ?y)) :effect (and (at start (p ?x)) (at end (done ?x ?y))))
          (:action make :parameters (?z) :effect (p ?z))
          (:action noise :parameters (?z) :effect (q ?z)))";
        let p = "(define (problem p) (:domain g) (:objects a - s b - t) (:init) (:goal (done a b)))";
        with_problem(d, p, |db, unit| {
            assert_eq!(instances(ground(db, unit)).len(), 5);
            let g = ground_relevant(db, unit);
            assert!(g.relevance && !g.truncated);
            assert_eq!(instances(g), ["(hold a b)", "(make b)"]);
            assert_eq!(g.schemas[2].candidates, [0]);
        });
        // A goal on the negation, in a disjunction: the deleters matter too.
        let d = "(define (domain h) (:requirements :negative-preconditions :disjunctive-preconditions)
          (:predicates (p ?a) (q ?a))
          (:action set :parameters (?z) :effect (p ?z))
          (:action unset :parameters (?z) :effect (not (p ?z)))
          (:action noise :parameters (?z) :effect (q ?z)))";
        let p = "(define (problem p) (:domain h) (:objects a b) (:init (p a))
          (:goal (or (not (p a)) (q b))))";
        with_problem(d, p, |db, unit| {
            assert_eq!(instances(ground_relevant(db, unit)), ["(noise b)", "(set a)", "(unset a)"]);
        });
    }

    #[test]
    fn hierarchical_problems_are_grounded_top_down() {
        // `four-hops` has five free variables only its subtasks name: their
        // types allow 30⁵ bindings, the task and the `hop` instances one.
        let d = "(define (domain routes) (:requirements :hierarchy :typing)
          (:types vehicle place)
          (:predicates (at ?v - vehicle ?p - place) (link ?a ?b - place))
          (:task go :parameters (?v - vehicle ?to - place))
          (:task idle :parameters (?v - vehicle ?p - place))
          (:method four-hops :parameters (?v - vehicle ?a ?b ?c ?d ?e - place) :task (go ?v ?e)
            :ordered-subtasks (and (hop ?v ?a ?b) (hop ?v ?b ?c) (hop ?v ?c ?d) (hop ?v ?d ?e)))
          (:method wait :parameters (?v - vehicle ?p - place) :task (idle ?v ?p) :subtasks (stay ?v ?p))
          (:action stay :parameters (?v - vehicle ?p - place) :precondition (at ?v ?p) :effect ())
          (:action hop :parameters (?v - vehicle ?from ?to - place)
            :precondition (and (at ?v ?from) (link ?from ?to))
            :effect (and (not (at ?v ?from)) (at ?v ?to))))";
        let places: Vec<String> = (0..30).map(|i| format!("p{i}")).collect();
        let links: Vec<String> = (0..29).map(|i| format!("(link p{i} p{})", i + 1)).collect();
        let p = format!(
            "(define (problem p) (:domain routes) (:objects truck - vehicle {} - place)
              (:htn :subtasks (and (go truck p4))) (:init (at truck p0) {}))",
            places.join(" "),
            links.join(" ")
        );
        with_problem(d, &p, |db, unit| {
            let g = ground_relevant(db, unit);
            assert!(!g.truncated && g.relevance);
            // The actions and tasks the network decomposes into: `idle`,
            // `stay`, and the hops past p4 are in no decomposition.
            assert_eq!(
                instances(g),
                [
                    "(go truck p4)",
                    "(hop truck p0 p1)",
                    "(hop truck p1 p2)",
                    "(hop truck p2 p3)",
                    "(hop truck p3 p4)"
                ]
            );
            let mut found = Vec::new();
            visit_methods(db, unit, g, Limits::PLANNER, &mut |e| {
                if let MethodEvent::Instance(m) = e {
                    found.push(m.binding.iter().map(|&o| g.objects.name(o)).collect::<Vec<_>>().join(" "));
                }
            });
            // `?a` is the first hop's own: that hop is split off the
            // method, a choice among its instances from p1's predecessors.
            assert_eq!(found, ["truck ? p1 p2 p3 p4"]);
            let splits: Vec<(usize, String, usize)> = g
                .tdg_splits
                .iter()
                .map(|s| {
                    let args = s.args.iter().map(|&o| g.objects.name(o)).collect::<Vec<_>>().join(" ");
                    (s.subtask, args, s.choices.len())
                })
                .collect();
            assert_eq!(splits, [(0, "truck ? p1".to_string(), 1)]);
            assert_eq!(
                g.tdg_splits[0].choices[0].iter().map(|&o| g.objects.name(o)).collect::<Vec<_>>(),
                ["truck", "p0", "p1"]
            );
            assert_eq!(g.htn_choices.as_deref().map(<[_]>::len), Some(1));
            // The lints' grounding is every reachable instance, as before.
            let all = ground(db, unit);
            assert!(all.tdg_methods.is_none() && instances(all).len() > 29);
        });
    }

    #[test]
    fn not_a_problem_grounds_to_nothing() {
        let mut host = AnalysisHost::new();
        let f = host.set_file_text("d.pddl", TYPES);
        let db = host.db();
        let unit = file_units(db, f)[0];
        assert_eq!(ground(db, unit), &Ground::default());
    }
}
