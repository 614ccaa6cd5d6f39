//! Relaxed decomposition over the ground problem: which ground tasks the
//! methods can refine into steps that relaxed reachability allows (the `:htn`
//! part of E0313, see `allowed.rs`), and methods whose subtasks have no
//! instance at all in a problem (W0314 uninstantiable-method).
//!
//! Both reason on [`ground`] and the instances of the methods
//! ([`visit_methods`]), which over-approximate what a plan can contain: a task
//! instance that no method instance refines is in no plan. Both stay silent
//! where an instance may be missing: grounding stopped at a limit, a method
//! was cut or skipped, or a construct grounding cannot follow may have pruned
//! too much.
//!
//! A large HTN problem has millions of method instances (the IPC 2020
//! problems: 20 million over the corpus, without those whose grounding stops
//! at a limit). They are not kept: [`Index`] interns each subtask instance (a
//! *call*: an action or task and its arguments) once and keeps, per method
//! instance, the ids of its task and steps, in flat arrays.

use rustc_hash::{FxHashMap, FxHashSet};

use super::Lint;
use super::ground::{Ground, Limits, MethodEvent, ground, visit_methods};
use super::lifted::{LTerm, MethodSchema, Operator, OperatorKind, method_schema, operator};
use super::reach::Reach;
use super::state::ObjId;
use crate::db::{Db, Item, Section, Unit};
use crate::diagnostic::codes;
use crate::model::Str;
use crate::semantics::symbols::Loc;

/// What [`super::lifted`] says of a negated conjunction: its atoms are kept as
/// a conjunction of negations, stronger than the disjunction it means, so
/// that static ones can prune instances that exist.
const NEGATED_CONJUNCTION: &str = "a negated conjunction (a disjunction)";

/// The limits of the method instances these lints visit: 2,000 per method
/// rather than [`Limits::DEFAULT`]'s 10,000. A method cut at the limit is of no
/// use (its task counts as refinable), and over the IPC 2020 corpus 70 % of
/// the instances visited at 10,000 were those of methods cut anyway; the
/// methods of a HiPOP mission have far fewer (448 in all for the 5 MB
/// generated problem).
const LIMITS: Limits = Limits { method_instances: 2_000, ..Limits::DEFAULT };

/// No ground operator (an action call), or no schema (a name grounding does not know).
const NONE: u32 = u32::MAX;

/// Interned calls, each a key `[schema, args…]`, stored back to back.
#[derive(Default)]
struct Calls {
    data: Vec<u32>,
    /// Where each call's key ends in `data`.
    ends: Vec<u32>,
    /// The last call of each hash; earlier ones with the same hash are chained in `prev`.
    index: FxHashMap<u64, u32>,
    prev: Vec<u32>,
}

impl Calls {
    fn hash(key: &[u32]) -> u64 {
        use std::hash::Hasher;
        let mut h = rustc_hash::FxHasher::default();
        for &k in key {
            h.write_u32(k);
        }
        h.finish()
    }

    fn key(&self, c: u32) -> &[u32] {
        let c = c as usize;
        let start = if c == 0 { 0 } else { self.ends[c - 1] as usize };
        &self.data[start..self.ends[c] as usize]
    }

    fn find(&self, key: &[u32], h: u64) -> Option<u32> {
        let mut c = *self.index.get(&h)?;
        while c != NONE {
            if self.key(c) == key {
                return Some(c);
            }
            c = self.prev[c as usize];
        }
        None
    }

    fn get(&self, key: &[u32]) -> Option<u32> {
        self.find(key, Self::hash(key))
    }

    /// The call's id, and whether it is new.
    fn intern(&mut self, key: &[u32]) -> (u32, bool) {
        let h = Self::hash(key);
        if let Some(c) = self.find(key, h) {
            return (c, false);
        }
        let c = self.ends.len() as u32;
        self.data.extend_from_slice(key);
        self.ends.push(self.data.len() as u32);
        self.prev.push(self.index.insert(h, c).unwrap_or(NONE));
        (c, true)
    }

    fn len(&self) -> usize {
        self.ends.len()
    }

    fn schema(&self, c: u32) -> u32 {
        self.key(c).first().copied().unwrap_or(NONE)
    }

    fn args(&self, c: u32) -> &[ObjId] {
        self.key(c).get(1..).unwrap_or(&[])
    }
}

/// What a call names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Action,
    Task,
    /// Not an action or task of the domain (already reported): never a reason to conclude.
    Unknown,
}

/// The ground operators and method instances of a problem, indexed by call.
pub(super) struct Index<'a, 'db> {
    pub g: &'a Ground<'db>,
    /// Schema index of each action and task name.
    schema: FxHashMap<&'a str, u32>,
    /// The calls met in method instances (their tasks and subtasks).
    calls: Calls,
    /// Per call: what it names, and for an action its ground operator (or [`NONE`]).
    call_kind: Vec<Kind>,
    call_op: Vec<u32>,
    /// Per method instance: its method (index in `methods`), the call of its
    /// task, and where its steps end in `steps`.
    inst_method: Vec<u32>,
    inst_task: Vec<u32>,
    inst_end: Vec<u32>,
    /// The calls of the subtasks of every method instance, back to back.
    steps: Vec<u32>,
    /// The method items met, and the range of their instances (contiguous).
    methods: Vec<(Item<'db>, u32, u32)>,
    /// The method instances refining each call: `refiners[refiner_start[c]..refiner_start[c + 1]]`.
    refiner_start: Vec<u32>,
    refiners: Vec<u32>,
    /// Method items whose instances may be missing: cut at a limit, skipped,
    /// or with a negated conjunction in their precondition.
    pub incomplete: FxHashSet<Item<'db>>,
    /// Tasks with an incomplete method: any of their instances may be refinable.
    pub incomplete_tasks: FxHashSet<Str>,
}

/// Whether a lifted condition list may prune instances that exist.
fn prunes_too_much(unsupported: &[super::lifted::Unsupported]) -> bool {
    unsupported.iter().any(|u| u.what == NEGATED_CONJUNCTION)
}

impl<'a, 'db> Index<'a, 'db> {
    /// Grounds the methods of `problem` over `g` and indexes their instances.
    /// The instances of a method cut at a limit are dropped: its task counts
    /// as incomplete, which they could not change.
    pub fn new(db: &'db dyn Db, problem: Unit<'db>, domain: Unit<'db>, g: &'a Ground<'db>) -> Self {
        let schema: FxHashMap<&'a str, u32> =
            g.schemas.iter().enumerate().map(|(i, s)| (s.name.as_str(), i as u32)).collect();
        let mut idx = Index {
            g,
            schema,
            calls: Calls::default(),
            call_kind: Vec::new(),
            call_op: Vec::new(),
            inst_method: Vec::new(),
            inst_task: Vec::new(),
            inst_end: Vec::new(),
            steps: Vec::new(),
            methods: Vec::new(),
            refiner_start: Vec::new(),
            refiners: Vec::new(),
            incomplete: FxHashSet::default(),
            incomplete_tasks: FxHashSet::default(),
        };
        // The current method's instances: the schemas and arities of its task
        // and subtasks, and one row of arguments per instance.
        let mut shape: Vec<(u32, usize)> = Vec::new();
        let mut rows: Vec<u32> = Vec::new();
        let mut count = 0usize;
        let mut key: Vec<u32> = Vec::new();
        visit_methods(db, problem, g, LIMITS, &mut |event| match event {
            MethodEvent::Instance(m) => {
                if shape.is_empty() {
                    let schema = |n: &str| idx.schema.get(n).copied().unwrap_or(NONE);
                    shape.push((schema(m.task), m.task_args.len()));
                    shape.extend(m.subtasks().map(|(n, a)| (schema(n), a.len())));
                }
                rows.extend_from_slice(m.task_args);
                for (_, a) in m.subtasks() {
                    rows.extend_from_slice(a);
                }
                count += 1;
            }
            MethodEvent::Done(item) => {
                let stride: usize = shape.iter().map(|s| s.1).sum();
                let n = std::mem::take(&mut count);
                if n > 0 {
                    let first = idx.inst_method.len() as u32;
                    let method = idx.methods.len() as u32;
                    for r in 0..n {
                        let mut at = r * stride;
                        let mut row_calls = shape.iter().map(|&(schema, arity)| {
                            let args = &rows[at..at + arity];
                            at += arity;
                            (schema, args)
                        });
                        let (schema, args) = row_calls.next().unwrap_or((NONE, &[]));
                        let task = idx.intern(schema, args, &mut key);
                        for (schema, args) in row_calls {
                            let c = idx.intern(schema, args, &mut key);
                            idx.steps.push(c);
                        }
                        idx.inst_method.push(method);
                        idx.inst_task.push(task);
                        idx.inst_end.push(idx.steps.len() as u32);
                    }
                    idx.methods.push((item, first, idx.inst_method.len() as u32));
                }
                shape.clear();
                rows.clear();
            }
            MethodEvent::Truncated(item) | MethodEvent::Skipped(item) => {
                idx.incomplete.insert(item);
                shape.clear();
                rows.clear();
                count = 0;
            }
        });
        for &item in domain.items(db).iter().filter(|i| i.section(db) == Section::Method) {
            let Some(m) = method_schema(db, item) else { continue };
            if prunes_too_much(&m.unsupported) {
                idx.incomplete.insert(item);
            }
            if idx.incomplete.contains(&item)
                && let Some((task, _, _)) = &m.task
            {
                idx.incomplete_tasks.insert(task.clone());
            }
        }
        // The refiners of each call, in instance order (counting sort).
        let n = idx.calls.len();
        let mut start = vec![0u32; n + 1];
        for &t in &idx.inst_task {
            start[t as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        idx.refiners = vec![0; idx.inst_task.len()];
        for (k, &t) in idx.inst_task.iter().enumerate() {
            idx.refiners[fill[t as usize] as usize] = k as u32;
            fill[t as usize] += 1;
        }
        idx.refiner_start = start;
        idx
    }

    /// The id of a call, interned with what it names.
    fn intern(&mut self, schema: u32, args: &[ObjId], key: &mut Vec<u32>) -> u32 {
        key.clear();
        key.push(schema);
        key.extend_from_slice(args);
        let (c, new) = self.calls.intern(key);
        if new {
            let (kind, op) = match self.g.schemas.get(schema as usize) {
                None => (Kind::Unknown, NONE),
                Some(s) if s.kind == OperatorKind::Task => (Kind::Task, NONE),
                Some(_) => (Kind::Action, self.operator_in(schema, args).map_or(NONE, |i| i as u32)),
            };
            self.call_kind.push(kind);
            self.call_op.push(op);
        }
        c
    }

    /// The schema of an action or task name.
    pub fn schema(&self, name: &str) -> Option<u32> {
        self.schema.get(name).copied()
    }

    /// Whether a name is a task (compound), as opposed to an action.
    pub fn is_task(&self, name: &str) -> bool {
        self.schema(name).is_some_and(|s| self.g.schemas[s as usize].kind == OperatorKind::Task)
    }

    fn operator_in(&self, schema: u32, args: &[ObjId]) -> Option<usize> {
        let s = self.g.schemas.get(schema as usize)?;
        let (start, end) = (s.start as usize, s.end as usize);
        let ops = &self.g.operators[start..end];
        ops.binary_search_by(|o| self.g.args(o).cmp(args)).ok().map(|i| start + i)
    }

    /// The ground operator of an action or task instance, by index.
    pub fn operator(&self, name: &str, args: &[ObjId]) -> Option<usize> {
        self.operator_in(self.schema(name)?, args)
    }

    /// The call of a task or action with these arguments, if a method instance names it.
    pub fn call(&self, name: &str, args: &[ObjId]) -> Option<u32> {
        let mut key = Vec::with_capacity(args.len() + 1);
        key.push(self.schema(name)?);
        key.extend_from_slice(args);
        self.calls.get(&key)
    }

    /// The calls of a name whose arguments match `pattern` (`None`: any object).
    pub fn calls_matching(&self, name: &str, pattern: &[Option<ObjId>]) -> Vec<u32> {
        if let Some(args) = pattern.iter().copied().collect::<Option<Vec<ObjId>>>() {
            return self.call(name, &args).into_iter().collect();
        }
        let schema = self.schema(name).unwrap_or(NONE);
        (0..self.calls.len() as u32)
            .filter(|&c| {
                let args = self.calls.args(c);
                self.calls.schema(c) == schema
                    && args.len() == pattern.len()
                    && args.iter().zip(pattern).all(|(a, p)| p.is_none_or(|p| p == *a))
            })
            .collect()
    }

    /// A call as text: `(move r1 a b)`.
    pub fn show_call(&self, c: u32) -> String {
        let schema = self.calls.schema(c) as usize;
        let name = self.g.schemas.get(schema).map_or("?", |s| s.name.as_str());
        super::ground::show(name, self.calls.args(c), &self.g.objects)
    }

    /// The method instances that refine a call.
    pub fn refiners(&self, c: u32) -> &[u32] {
        let c = c as usize;
        match (self.refiner_start.get(c), self.refiner_start.get(c + 1)) {
            (Some(&a), Some(&b)) => &self.refiners[a as usize..b as usize],
            _ => &[],
        }
    }

    /// The method item of an instance.
    pub fn method_of(&self, k: u32) -> Item<'db> {
        self.methods[self.inst_method[k as usize] as usize].0
    }

    /// The calls of an instance's subtasks.
    pub fn steps(&self, k: u32) -> &[u32] {
        let k = k as usize;
        let start = if k == 0 { 0 } else { self.inst_end[k - 1] as usize };
        &self.steps[start..self.inst_end[k] as usize]
    }

    /// Whether a call names a task.
    pub fn is_task_call(&self, c: u32) -> bool {
        self.call_kind[c as usize] == Kind::Task
    }

    /// The ground operator of an action call.
    pub fn call_operator(&self, c: u32) -> Option<usize> {
        let op = self.call_op[c as usize];
        (op != NONE).then_some(op as usize)
    }

    /// Whether a task call's task has a method whose instances may be missing.
    pub fn call_incomplete(&self, c: u32) -> bool {
        let schema = self.calls.schema(c) as usize;
        self.g.schemas.get(schema).is_some_and(|s| self.incomplete_tasks.contains(&s.name))
    }

    /// The relaxed decomposition fixpoint: by call, whether it is achievable.
    /// An action call is when `reach` reaches its ground operator; a task
    /// call when some method instance refines it into achievable steps, or
    /// when its task has an incomplete method (an instance may be missing).
    /// A cycle of tasks without a base case stays out.
    pub fn achievable(&self, reach: &Reach) -> Vec<bool> {
        let n = self.calls.len();
        let mut done: Vec<bool> = (0..n as u32)
            .map(|c| match self.call_kind[c as usize] {
                Kind::Unknown => true,
                Kind::Action => self.call_operator(c).is_some_and(|i| reach.operator(i)),
                Kind::Task => self.call_incomplete(c),
            })
            .collect();
        // The instances waiting for each task call (with multiplicity).
        let mut start = vec![0u32; n + 1];
        for &c in &self.steps {
            if !done[c as usize] {
                start[c as usize + 1] += 1;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut waiting = vec![0u32; start[n] as usize];
        let n_inst = self.inst_task.len();
        let mut missing = vec![0u32; n_inst];
        let mut ready: Vec<u32> = Vec::new();
        for k in 0..n_inst as u32 {
            let mut count = 0;
            let mut dead = false;
            for &c in self.steps(k) {
                if done[c as usize] {
                    continue;
                }
                if self.is_task_call(c) {
                    waiting[fill[c as usize] as usize] = k;
                    fill[c as usize] += 1;
                    count += 1;
                } else {
                    dead = true;
                }
            }
            missing[k as usize] = if dead { NONE } else { count };
            if !dead && count == 0 {
                ready.push(k);
            }
        }
        while let Some(k) = ready.pop() {
            let t = self.inst_task[k as usize] as usize;
            if done[t] {
                continue;
            }
            done[t] = true;
            for &w in &waiting[start[t] as usize..start[t + 1] as usize] {
                let m = &mut missing[w as usize];
                if *m != NONE {
                    *m -= 1;
                    if *m == 0 {
                        ready.push(w);
                    }
                }
            }
        }
        done
    }

    /// Whether a call has an instance at all (one level: a task call needs a
    /// method instance that refines it, not a full decomposition). `true`
    /// when an instance may be missing.
    fn instantiable(&self, c: u32) -> bool {
        match self.call_kind[c as usize] {
            Kind::Unknown => true,
            Kind::Task => self.call_incomplete(c) || !self.refiners(c).is_empty(),
            Kind::Action => {
                self.call_op[c as usize] != NONE
                    || self.g.schemas.get(self.calls.schema(c) as usize).is_some_and(|s| s.unsupported)
            }
        }
    }
}

/// The lints that need the instances of a problem's methods: `:htn` tasks
/// out of reach (E0313) and methods that can never be used (W0314). A query
/// of its own, so that editing the goal does not ground the methods again;
/// the instances are not kept.
#[salsa::tracked(returns(ref))]
pub(super) fn decomposition_lints<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Vec<Lint<'db>> {
    let mut out = Vec::new();
    let Some(domain) = crate::semantics::check::domain_for(db, problem) else { return out };
    let g = ground(db, problem);
    let methods: Vec<Item<'db>> =
        domain.items(db).iter().copied().filter(|i| i.section(db) == Section::Method).collect();
    if g.truncated || methods.is_empty() || methods.iter().any(|&m| has_effect(db, m)) {
        // Instances are missing (grounding stopped at a limit, or method
        // effects it does not apply add atoms): neither lint could say "never".
        return out;
    }
    let idx = Index::new(db, problem, domain, g);
    super::allowed::htn_lints(db, problem, domain, &idx, &mut out);
    uninstantiable_methods(db, &idx, problem, &mut out);
    out
}

/// An action that changes nothing: a precondition test.
fn is_test(op: &Operator) -> bool {
    op.add.is_empty() && op.del.is_empty() && !op.unsupported.iter().any(|u| u.what.contains("effect"))
}

/// Whether a method item has an `:effect` (a PANDA extension).
pub(super) fn has_effect(db: &dyn Db, method: Item<'_>) -> bool {
    matches!(&crate::db::lower_item(db, method).data, crate::model::ItemData::Method(m) if m.effect.is_some())
}

/// A subtask of a lifted method as written: `(unload ?t ?p)`.
fn show_lifted(m: &MethodSchema, name: &str, args: &[LTerm]) -> String {
    let mut s = format!("({name}");
    for a in args {
        s.push(' ');
        match a {
            LTerm::Param(i) => s.push_str(m.params.get(*i as usize).map_or("?", |p| p.name.as_str())),
            LTerm::Const(c) | LTerm::Free(c) => s.push_str(c),
        }
    }
    s.push(')');
    s
}

/// W0314: methods that have instances in a problem, none of which has every
/// subtask instantiable (an action instance that grounding keeps, a task
/// instance that some method instance refines). Located on the method's name
/// in the domain. Not reported: methods without any instance of their own,
/// and instances where an action without effects has no instance (a
/// precondition compiled into a step, as SHOP translations do) or that call
/// a task no method instance refines for any arguments: the method does not
/// apply, which a problem that does not need it makes normal.
fn uninstantiable_methods<'db>(
    db: &'db dyn Db,
    idx: &Index<'_, 'db>,
    problem: Unit<'db>,
    out: &mut Vec<Lint<'db>>,
) {
    if idx.g.truncated {
        return;
    }
    let tests: Vec<bool> = idx
        .g
        .schemas
        .iter()
        .map(|s| s.kind != OperatorKind::Task && operator(db, s.item).as_ref().is_some_and(is_test))
        .collect();
    // Tasks that some method instance refines, whatever the arguments.
    let mut refined = vec![false; idx.g.schemas.len()];
    for &t in &idx.inst_task {
        if let Some(r) = refined.get_mut(idx.calls.schema(t) as usize) {
            *r = true;
        }
    }
    // A step that says the method does not apply rather than that it is
    // broken: a failed precondition test, or a task this problem never
    // refines at all (its methods have no instance: the problem does not need
    // it, and neither does it need a method that only leads to it).
    let not_applicable = |c: u32| {
        let schema = idx.calls.schema(c) as usize;
        match idx.call_kind[c as usize] {
            Kind::Action => tests.get(schema).copied().unwrap_or(false) && !idx.instantiable(c),
            Kind::Task => !refined.get(schema).copied().unwrap_or(true) && !idx.instantiable(c),
            Kind::Unknown => false,
        }
    };
    let problem_name = problem.name(db).as_deref().unwrap_or("?");
    for &(item, start, end) in &idx.methods {
        if idx.incomplete.contains(&item) {
            continue;
        }
        let Some(schema) = method_schema(db, item) else { continue };
        let instances: Vec<u32> =
            (start..end).filter(|&k| !idx.steps(k).iter().any(|&c| not_applicable(c))).collect();
        if instances.is_empty() {
            // No instance whose precondition holds: the problem does not need the method.
            continue;
        }
        // For each subtask, in how many instances it has an instance.
        let mut ok = vec![0usize; schema.subtasks.len()];
        let mut usable = false;
        for &k in &instances {
            let mut all = true;
            for (j, &c) in idx.steps(k).iter().enumerate() {
                if idx.instantiable(c) {
                    if let Some(n) = ok.get_mut(j) {
                        *n += 1;
                    }
                } else {
                    all = false;
                }
            }
            if all {
                usable = true;
                break;
            }
        }
        if usable {
            continue;
        }
        let n = instances.len();
        let count =
            if n == 1 { "its only instance".to_string() } else { format!("any of its {n} instances") };
        // The first subtask that fails everywhere, else the first failing one of the first instance.
        let first = idx.steps(instances[0]);
        let j = ok.iter().position(|&c| c == 0).or_else(|| first.iter().position(|&c| !idx.instantiable(c)));
        let (Some(j), Some(sub)) = (j, j.and_then(|j| schema.subtasks.get(j))) else { continue };
        let shown = show_lifted(schema, &sub.name, &sub.args);
        let id = sub.id.as_ref().map_or(String::new(), |i| format!("`{i}` "));
        let compound = idx.is_task(&sub.name);
        let why = match (ok[j] == 0, compound) {
            (true, false) => format!(
                "its subtask {id}`{shown}` has no action instance for {count} (types, static \
                 preconditions or preconditions out of reach rule them out)"
            ),
            (true, true) => format!(
                "no method of `{}` has an instance that refines its subtask {id}`{shown}`, for {count}",
                sub.name
            ),
            (false, _) => format!(
                "each of its {n} instances has a subtask without instance (the first one: `{}`)",
                first.get(j).map_or_else(|| shown.clone(), |&c| idx.show_call(c))
            ),
        };
        let mut lint = Lint::new(
            codes::UNINSTANTIABLE_METHOD,
            Loc { item, span: schema.name_span },
            format!("method `{}` can never be used in problem `{problem_name}`: {why}", schema.name),
        )
        .related(Loc { item, span: sub.span }, "this subtask");
        if let Some(s) = idx.schema(&sub.name)
            && let Some(op) = operator(db, idx.g.schemas[s as usize].item)
        {
            let what = if compound { "task" } else { "action" };
            lint = lint.related(
                Loc { item: idx.g.schemas[s as usize].item, span: op.name_span },
                format!("the {what} `{}` is declared here", op.name),
            );
        }
        out.push(lint);
    }
}

#[cfg(test)]
mod tests {
    use crate::AnalysisHost;

    /// The W0314 messages of a domain and a problem checked together.
    fn w0314(domain: &str, problem: &str) -> Vec<String> {
        let mut host = AnalysisHost::new();
        let d = host.set_file_text("m/domain.hddl", domain);
        host.set_file_text("m/problem.hddl", problem);
        let analysis = host.analysis();
        let diags = analysis.diagnostics(d).expect("not cancelled");
        diags.iter().filter(|d| d.code.id == "W0314").map(|d| d.message.clone()).collect()
    }

    const DOMAIN: &str = "(define (domain d) (:requirements :typing :hierarchy)
      (:types truck pkg place)
      (:predicates (at ?x - object ?p - place) (road ?a ?b - place) (ok ?p - place) (in ?k - pkg ?t - truck))
      (:task deliver :parameters (?k - pkg ?p - place))
      (:task drive :parameters (?t - truck ?p - place))
      (:action go :parameters (?t - truck ?a ?b - place) :precondition (and (at ?t ?a) (road ?a ?b))
        :effect (and (not (at ?t ?a)) (at ?t ?b)))
      (:action load :parameters (?k - pkg ?t - truck ?p - place) :precondition (and (at ?k ?p) (at ?t ?p))
        :effect (and (not (at ?k ?p)) (in ?k ?t)))
      (:action unload :parameters (?k - pkg ?t - truck ?p - place) :precondition (and (in ?k ?t) (at ?t ?p) (ok ?p))
        :effect (and (not (in ?k ?t)) (at ?k ?p)))
      (:action check-ok :parameters (?p - place) :precondition (ok ?p))
      (:method m-drive :parameters (?t - truck ?a ?b - place) :task (drive ?t ?b) :precondition (road ?a ?b)
        :subtasks (go ?t ?a ?b))
      (:method m-deliver :parameters (?k - pkg ?t - truck ?a ?p - place) :task (deliver ?k ?p)
        :subtasks (and (t1 (load ?k ?t ?a)) (t2 (unload ?k ?t ?p))))
      @EXTRA@)";

    const PROBLEM: &str = "(define (problem p) (:domain d) (:objects t - truck k - pkg a b - place)
      (:htn :subtasks (deliver k a)) (:init (at t a) (at k a) (road a b) @INIT@))";

    fn run(extra: &str, init: &str) -> Vec<String> {
        w0314(&DOMAIN.replace("@EXTRA@", extra), &PROBLEM.replace("@INIT@", init))
    }

    #[test]
    fn a_subtask_without_instance_makes_the_method_useless() {
        // No place is `ok`: `unload` has no instance, `m-deliver` has 4.
        assert_eq!(
            run("", ""),
            [
                "method `m-deliver` can never be used in problem `p`: its subtask `t2` `(unload ?k ?t ?p)` has \
                 no action instance for any of its 4 instances (types, static preconditions or preconditions out \
                 of reach rule them out)"
            ]
        );
        assert_eq!(run("", "(ok a)"), Vec::<String>::new());
    }

    #[test]
    fn methods_that_do_not_apply_are_not_reported() {
        // No instance of its own: a precondition that `:init` never satisfies.
        let guarded = "(:method m-guarded :parameters (?k - pkg ?p - place) :task (deliver ?k ?p)
            :precondition (ok ?p) :subtasks (check-ok ?p))";
        assert_eq!(run(guarded, "(ok a)"), Vec::<String>::new());
        // A precondition compiled into an action without effects, SHOP-style.
        let tested = "(:method m-tested :parameters (?k - pkg ?t - truck ?p - place) :task (deliver ?k ?p)
            :subtasks (and (check-ok ?p) (unload ?k ?t ?p)))";
        assert_eq!(run(tested, "(ok a)"), Vec::<String>::new());
    }

    #[test]
    fn a_compound_subtask_needs_a_method_instance_for_its_arguments() {
        // `drive` is refined towards `b` only (the only road): a method that drives to `a` is useless.
        let back = "(:method m-back :parameters (?k - pkg ?t - truck ?p - place) :task (deliver ?k ?p)
            :subtasks (and (drive ?t a) (unload ?k ?t ?p)))";
        let got = run(back, "(ok a) (ok b)");
        assert_eq!(got.len(), 1, "{got:?}");
        assert!(
            got[0].starts_with("method `m-back` can never be used in problem `p`: no method of `drive`"),
            "{got:?}"
        );
        // A task no method instance refines at all is not needed by the problem: not reported.
        let fly = "(:task fly :parameters (?t - truck ?p - place))
          (:method m-fly :parameters (?t - truck ?p - place) :task (fly ?t ?p) :precondition (ok ?p)
            :subtasks (go ?t ?p ?p))
          (:method m-via :parameters (?k - pkg ?t - truck ?p - place) :task (deliver ?k ?p)
            :subtasks (and (fly ?t ?p) (load ?k ?t ?p)))";
        let got = run(fly, "").into_iter().filter(|m| m.contains("m-via")).count();
        assert_eq!(got, 0);
    }
}
