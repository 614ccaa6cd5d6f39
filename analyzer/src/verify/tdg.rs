//! Top-down grounding of hierarchical problems through the task
//! decomposition graph (TDG), for the planner: the ground actions, tasks and
//! methods that the initial task network can decompose into, intersected
//! with relaxed reachability from `:init`, the way pandaPIgrounder grounds
//! (Behnke et al., "On Succinct Groundings of HTN Planning Problems", 2020).
//!
//! Grounding each method over the cross product of its parameters' types
//! is hopeless when methods have free variables (Woodworking's have up to
//! twelve; a parameter that only a subtask names is one), and so is grounding
//! every task over its types (`grindNplane`'s seven parameters). Here the
//! methods are rules evaluated by the instantiation engine of
//! [`super::instantiate`], over the reachable atoms plus two kinds of facts
//! about tasks:
//!
//! - `req T(args)`: the ground task `T(args)` may occur in a decomposition
//!   of the initial task network. The network's tasks are requested; a
//!   method of a requested task requests each of its abstract subtasks, its
//!   parameters bound from the task's arguments and, for those the subtask
//!   names, from the method's preconditions and primitive subtasks that
//!   mention no other variable (a static precondition such as
//!   `(road ?l1 ?l2)` binds `?l2` from `?l1`).
//! - `ok T(args)`: `T(args)` can be decomposed into reachable actions. A
//!   reachable action instance is `ok`; a method instance of a requested task
//!   whose preconditions are reachable and whose subtasks are all `ok` makes
//!   its task `ok`. Its parameters are bound by joining the subtasks' `ok`
//!   facts, never by enumerating their types.
//!
//! The method instances found that way are then pruned at the ground level
//! until nothing changes: only what the initial network reaches top-down
//! through methods whose subtasks are all still usable is kept, relaxed
//! reachability is computed again from `:init` with only the actions kept
//! (a package that only deliveries move can only be where it starts and
//! where a delivery takes it), which makes more method instances unusable,
//! and so on.

use rustc_hash::FxHashMap;

use super::ground::UNBOUND;
use super::instantiate::{Arg, CAtom, Compiler, OpInput, Preds, fixpoint, value};
use super::lifted::{Conditions, LAtom, LTerm, MethodSchema, Operator, OperatorKind, Param};
use super::state::{AtomId, Atoms, Interner, ObjId, Objects};
use crate::db::Item;
use crate::model::Str;

/// The problem's initial task network, lifted over its parameters.
pub(crate) struct LiftedHtn {
    pub params: Vec<Param>,
    pub subtasks: Vec<(Str, Vec<LTerm>)>,
}

/// What the top-down grounding reads.
pub(crate) struct Input<'a, 'db> {
    pub objects: &'a Objects<'db>,
    pub predicates: &'a Interner,
    pub static_preds: &'a [bool],
    pub untracked: &'a [bool],
    /// The atoms after the reachability of every action.
    pub atoms: &'a Atoms,
    /// The atoms that reachability reached, and where it started.
    pub reached: &'a [bool],
    pub start: &'a [AtomId],
    pub initial: &'a [bool],
    /// The domain's actions and tasks, with their compiled ground
    /// preconditions (not static) and add effects.
    pub ops: &'a [(Item<'db>, &'a Operator)],
    pub pre: Vec<&'a [CAtom]>,
    pub add: Vec<&'a [CAtom]>,
    /// The reachable instances of each action (none for tasks).
    pub instances: Vec<Vec<&'a [ObjId]>>,
    pub methods: &'a [(Item<'db>, &'a MethodSchema)],
    pub htn: &'a LiftedHtn,
    /// Parameter values the rules may try, and instances they may find.
    pub budget: u64,
    pub max_instances: usize,
}

/// The ground hierarchical model.
pub(crate) struct Output<'db> {
    /// The instances kept, per operator (`Input::ops`), each once.
    pub per_op: Vec<Vec<Box<[ObjId]>>>,
    /// The atoms reachable with the actions kept.
    pub reached: Vec<bool>,
    /// The method instances kept, by method, in `Input::methods`' order.
    pub methods: Vec<(Item<'db>, Vec<Box<[ObjId]>>)>,
    /// Per task of the network, the arguments of its ground instances that
    /// can be decomposed (one for a task without parameters, if any).
    pub htn_choices: Vec<Vec<Box<[ObjId]>>>,
    /// The subtasks split off their methods ([`split`]): per method (index
    /// in `Input::methods`), subtask (index in the method) and arguments of
    /// the subtask as the method's instances name them (its own variables
    /// [`UNBOUND`]), the ground instances of the subtask that can be chosen.
    pub splits: Vec<Split>,
    /// A limit was reached: the model is incomplete.
    pub truncated: bool,
    /// Then the method with the most instances found, and how many (none
    /// when it stopped before any: at the tasks the methods request).
    pub dominant: Option<(Str, usize)>,
    /// Parameter values tried.
    pub tried: u64,
}

/// A subtask split off its method, with the ground instances it may be.
pub(crate) struct Split {
    pub method: usize,
    pub subtask: usize,
    pub args: Box<[ObjId]>,
    pub choices: Vec<Box<[ObjId]>>,
}

/// The subtasks of a method grounded apart from it (method splitting,
/// Behnke et al. 2020), and the parameters its instances bind.
///
/// A method's parameter that is not an argument of its task, appears in no
/// precondition or constraint and is named by one subtask only is that
/// subtask's own: its value changes nothing else in the method. A subtask
/// with such parameters is split off when another subtask also has
/// parameters the task does not bind, or the task has arguments the
/// subtask does not name: the method's instances would otherwise be the
/// product of the subtasks' instances (Woodworking's `method16` colours any
/// part with any machine, whatever the part it grinds, and had millions),
/// or of the task's instances and the subtask's (`method0` varnishes with
/// any varnisher, whatever the machine its task names). The method's
/// instances then bind the other parameters only, and each split subtask is
/// a choice among its ground instances that agree with them.
pub(crate) fn split(m: &MethodSchema) -> (Vec<bool>, Vec<u32>) {
    let n = m.params.len() as u32;
    let mut split = vec![false; m.subtasks.len()];
    let all: Vec<u32> = (0..n).collect();
    if !m.unsupported.is_empty() || !m.pre.numeric.is_empty() {
        return (split, all);
    }
    let mut bound = Vec::new();
    if let Some((_, head, _)) = &m.task {
        vars(head, &mut bound);
    }
    for a in m.pre.pos.iter().chain(&m.pre.neg) {
        vars(&a.args, &mut bound);
    }
    for (x, y) in m.pre.eq.iter().chain(&m.pre.neq) {
        vars(std::slice::from_ref(x), &mut bound);
        vars(std::slice::from_ref(y), &mut bound);
    }
    let subtask_vars: Vec<Vec<u32>> = m
        .subtasks
        .iter()
        .map(|s| {
            let mut v = Vec::new();
            vars(&s.args, &mut v);
            v
        })
        .collect();
    let own = |q: u32, i: usize| {
        !bound.contains(&q) && subtask_vars.iter().enumerate().all(|(j, v)| j == i || !v.contains(&q))
    };
    let has_own: Vec<bool> =
        subtask_vars.iter().enumerate().map(|(i, v)| v.iter().any(|&q| own(q, i))).collect();
    let unbound_by_task: Vec<bool> =
        subtask_vars.iter().map(|v| v.iter().any(|q| !bound.contains(q))).collect();
    let mut head = Vec::new();
    if let Some((_, args, _)) = &m.task {
        vars(args, &mut head);
    }
    for i in 0..m.subtasks.len() {
        split[i] = has_own[i]
            && ((0..m.subtasks.len()).any(|j| j != i && unbound_by_task[j])
                || head.iter().any(|q| !subtask_vars[i].contains(q)));
    }
    let core = all
        .into_iter()
        .filter(|&q| !(0..m.subtasks.len()).any(|i| split[i] && subtask_vars[i].contains(&q) && own(q, i)))
        .collect();
    (split, core)
}

/// What a rule of the fixpoint derives.
enum Rule {
    /// Requests a method's subtask (or a network task).
    Request,
    /// A task's instance whose own conditions hold (the task's index in `Input::ops`).
    Task(usize),
    /// A method instance (index in `Input::methods`).
    Method(usize),
    /// A ground instance of the network's task (its index) that can be decomposed.
    Root(usize),
    /// A projection: a fact over some of another fact's arguments.
    Aux,
    /// A ground instance of a split subtask (index in `splits`).
    Part(usize),
}

fn vars(terms: &[LTerm], out: &mut Vec<u32>) {
    for t in terms {
        if let LTerm::Param(i) = t
            && !out.contains(i)
        {
            out.push(*i);
        }
    }
}

fn within(terms: &[LTerm], keep: &[u32]) -> bool {
    terms.iter().all(|t| !matches!(t, LTerm::Param(i) if !keep.contains(i)))
}

/// The terms with parameter `i` renumbered as its position in `keep`.
fn remap(terms: &[LTerm], keep: &[u32]) -> Vec<LTerm> {
    terms
        .iter()
        .map(|t| match t {
            LTerm::Param(i) => LTerm::Param(keep.iter().position(|k| k == i).unwrap_or(0) as u32),
            other => other.clone(),
        })
        .collect()
}

fn latom(pred: &str, args: Vec<LTerm>) -> LAtom {
    LAtom { pred: pred.into(), args: args.into(), span: Default::default() }
}

fn req(name: &str) -> String {
    format!("req {name}")
}

fn ok(name: &str) -> String {
    format!("ok {name}")
}

fn tok(name: &str) -> String {
    format!("task {name}")
}

/// The conditions of `pre` over the parameters in `keep`, renumbered; the
/// others are left out (an over-approximation).
fn restrict(pre: &Conditions, keep: &[u32], pos: &mut Vec<LAtom>) -> Conditions {
    for a in pre.pos.iter().filter(|a| within(&a.args, keep)) {
        pos.push(latom(&a.pred, remap(&a.args, keep)));
    }
    let pair = |(x, y): &(LTerm, LTerm)| {
        within(std::slice::from_ref(x), keep) && within(std::slice::from_ref(y), keep)
    };
    let remap_pair = |(x, y): &(LTerm, LTerm)| {
        (remap(std::slice::from_ref(x), keep).remove(0), remap(std::slice::from_ref(y), keep).remove(0))
    };
    Conditions {
        pos: std::mem::take(pos),
        neg: pre
            .neg
            .iter()
            .filter(|a| within(&a.args, keep))
            .map(|a| latom(&a.pred, remap(&a.args, keep)))
            .collect(),
        eq: pre.eq.iter().filter(|p| pair(p)).map(remap_pair).collect(),
        neq: pre.neq.iter().filter(|p| pair(p)).map(remap_pair).collect(),
        numeric: Vec::new(),
    }
}

/// Grounds the hierarchy. `None` when a method's task or a subtask is not
/// an operator of the domain (reported elsewhere; the caller grounds as
/// before).
pub(crate) fn ground<'db>(input: &Input<'_, 'db>) -> Option<Output<'db>> {
    let by_name: FxHashMap<&str, usize> =
        input.ops.iter().enumerate().map(|(i, (_, op))| (op.name.as_str(), i)).collect();
    let is_task = |i: usize| input.ops[i].1.kind == OperatorKind::Task;
    for (_, m) in input.methods {
        let (task, _, _) = m.task.as_ref()?;
        if !by_name.get(task.as_str()).is_some_and(|&i| is_task(i)) {
            return None;
        }
        if m.subtasks.iter().any(|s| !by_name.contains_key(s.name.as_str())) {
            return None;
        }
    }
    if input.htn.subtasks.iter().any(|(n, _)| !by_name.contains_key(n.as_str())) {
        return None;
    }

    // The rules, over the predicates and the pseudo-predicates of tasks.
    let mut preds = input.predicates.clone();
    let mut atoms = input.atoms.clone();
    let mut cx = Compiler {
        objects: input.objects,
        preds: Preds::Intern(&mut preds),
        static_preds: input.static_preds,
        untracked: input.untracked,
        derived: &[],
        unsupported: false,
    };
    let mut rules: Vec<(Rule, OpInput)> = Vec::new();
    let mut rule =
        |cx: &mut Compiler<'_, '_>, kind: Rule, params: Vec<Param>, pre: Conditions, add: LAtom| {
            let spec = cx.spec(&params, &pre);
            let add = cx.atom(&add).into_iter().collect();
            rules.push((kind, OpInput { spec, add }));
        };
    // A task's own conditions.
    for (t, (_, op)) in input.ops.iter().enumerate().filter(|(_, (_, op))| op.kind == OperatorKind::Task) {
        let all: Vec<u32> = (0..op.params.len() as u32).collect();
        let args: Vec<LTerm> = all.iter().map(|&i| LTerm::Param(i)).collect();
        let mut pos = vec![latom(&req(&op.name), args.clone())];
        let pre = restrict(&op.pre, &all, &mut pos);
        rule(&mut cx, Rule::Task(t), op.params.clone(), pre, latom(&tok(&op.name), args));
    }
    // Projections of a task's requests onto some of its arguments, by task
    // and arguments kept.
    let mut projections: FxHashMap<(String, Vec<bool>), String> = FxHashMap::default();
    // The split subtasks: (method, subtask, its arguments over `vars`, the
    // method's parameters it names).
    let mut splits: Vec<(usize, usize, Vec<LTerm>, Vec<u32>)> = Vec::new();
    for (k, (_, m)) in input.methods.iter().enumerate() {
        let Some((task, head, _)) = &m.task else { continue };
        let mut head_vars = Vec::new();
        vars(head, &mut head_vars);
        // Requests: one rule per abstract subtask.
        for (i, s) in m.subtasks.iter().enumerate() {
            if !is_task(by_name[s.name.as_str()]) {
                continue;
            }
            let mut keep = head_vars.clone();
            vars(&s.args, &mut keep);
            // The parameters the rule needs: the subtask's, and those of the
            // conditions over `keep` (the task's other arguments only
            // multiply the rule's instances: the request is the same).
            let mut used = Vec::new();
            vars(&s.args, &mut used);
            let mut body: Vec<LAtom> = Vec::new();
            for (j, t) in m.subtasks.iter().enumerate() {
                if j != i && !is_task(by_name[t.name.as_str()]) && within(&t.args, &keep) {
                    body.push(latom(&ok(&t.name), t.args.clone()));
                }
            }
            for a in body.iter().chain(&m.pre.pos).chain(&m.pre.neg) {
                if within(&a.args, &keep) {
                    vars(&a.args, &mut used);
                }
            }
            for (x, y) in m.pre.eq.iter().chain(&m.pre.neq) {
                let pair = [x.clone(), y.clone()];
                if within(&pair, &keep) {
                    vars(&pair, &mut used);
                }
            }
            used.sort_unstable();
            let mask: Vec<bool> =
                head.iter().map(|t| !matches!(t, LTerm::Param(q) if !used.contains(q))).collect();
            let req_atom = if mask.iter().all(|&b| b) {
                latom(&req(task), remap(head, &used))
            } else {
                let n = projections.len();
                let name = projections
                    .entry((task.to_string(), mask.clone()))
                    .or_insert_with(|| {
                        let op = input.ops[by_name[task.as_str()]].1;
                        let all: Vec<LTerm> = (0..op.params.len() as u32).map(LTerm::Param).collect();
                        let kept: Vec<LTerm> =
                            all.iter().zip(&mask).filter(|(_, b)| **b).map(|(t, _)| t.clone()).collect();
                        let name = format!("req {n} {task}");
                        let pre = restrict(&Conditions::default(), &[], &mut vec![latom(&req(task), all)]);
                        rule(&mut cx, Rule::Aux, op.params.clone(), pre, latom(&name, kept));
                        name
                    })
                    .clone();
                let kept: Vec<LTerm> =
                    head.iter().zip(&mask).filter(|(_, b)| **b).map(|(t, _)| t.clone()).collect();
                latom(&name, remap(&kept, &used))
            };
            let mut pos = vec![req_atom];
            pos.extend(body.iter().map(|a| latom(&a.pred, remap(&a.args, &used))));
            let pre = restrict(&m.pre, &used, &mut pos);
            let params = used.iter().map(|&q| m.params[q as usize].clone()).collect();
            rule(&mut cx, Rule::Request, params, pre, latom(&req(&s.name), remap(&s.args, &used)));
        }
        // Its instances, over the parameters the split subtasks leave.
        let (split_mask, core) = split(m);
        let mut pos = vec![latom(&tok(task), remap(head, &core))];
        for (i, s) in m.subtasks.iter().enumerate() {
            if !split_mask[i] {
                pos.push(latom(&ok(&s.name), remap(&s.args, &core)));
                continue;
            }
            // A split subtask: its instances (over the method's types), and
            // the method's condition that one agrees with the others.
            let mut own = Vec::new();
            vars(&s.args, &mut own);
            own.sort_unstable();
            let shared: Vec<LTerm> = s
                .args
                .iter()
                .filter(|t| !matches!(t, LTerm::Param(q) if !core.contains(q)))
                .cloned()
                .collect();
            let name = format!("part {k} {i}");
            let params = own.iter().map(|&q| m.params[q as usize].clone()).collect();
            let pre =
                restrict(&Conditions::default(), &[], &mut vec![latom(&ok(&s.name), remap(&s.args, &own))]);
            rule(&mut cx, Rule::Part(splits.len()), params, pre, latom(&name, remap(&shared, &own)));
            splits.push((k, i, remap(&s.args, &own), own));
            pos.push(latom(&name, remap(&shared, &core)));
        }
        let pre = restrict(&m.pre, &core, &mut pos);
        let params = core.iter().map(|&q| m.params[q as usize].clone()).collect();
        rule(&mut cx, Rule::Method(k), params, pre, latom(&ok(task), remap(head, &core)));
    }
    // The initial network: its tasks are requested, and each of their
    // instances that can be decomposed is a choice for the network's
    // parameters (never their cross product: Woodworking's networks have
    // up to 2,000,000 bindings, each task's parameters its own).
    let htn = input.htn;
    for (i, (name, args)) in htn.subtasks.iter().enumerate() {
        let mut keep = Vec::new();
        vars(args, &mut keep);
        keep.sort_unstable();
        let params: Vec<Param> = keep.iter().map(|&q| htn.params[q as usize].clone()).collect();
        let pre = restrict(&Conditions::default(), &keep, &mut Vec::new());
        rule(&mut cx, Rule::Request, params.clone(), pre, latom(&req(name), remap(args, &keep)));
        let mut pos = vec![latom(&ok(name), remap(args, &keep))];
        let pre = restrict(&Conditions::default(), &keep, &mut pos);
        rule(&mut cx, Rule::Root(i), params, pre, latom(&format!(" root {i}"), Vec::new()));
    }
    // Method subtasks and network tasks as compiled terms.
    let compile =
        |cx: &Compiler<'_, '_>, ts: &[LTerm]| ts.iter().map(|t| cx.arg(t)).collect::<Option<Vec<Arg>>>();
    // Per method: its task, its arguments, its subtasks and its
    // preconditions that are not static.
    type Terms = (usize, Vec<Arg>, Vec<(usize, Vec<Arg>)>, Vec<CAtom>);
    let mut method_terms: Vec<Terms> = Vec::new();
    for (_, m) in input.methods {
        let Some((task, head, _)) = &m.task else { return None };
        let head = compile(&cx, head)?;
        let subs = m
            .subtasks
            .iter()
            .map(|s| Some((by_name[s.name.as_str()], compile(&cx, &s.args)?)))
            .collect::<Option<Vec<_>>>()?;
        let mut pre = Vec::new();
        for a in &m.pre.pos {
            let c = cx.atom(a)?;
            if !cx.is_static(c.pred) {
                pre.push(c);
            }
        }
        method_terms.push((by_name[task.as_str()], head, subs, pre));
    }
    // A network task's arguments over the parameters its rule binds.
    let htn_terms: Vec<(usize, Vec<Arg>)> = htn
        .subtasks
        .iter()
        .map(|(n, ts)| {
            let mut keep = Vec::new();
            vars(ts, &mut keep);
            keep.sort_unstable();
            Some((by_name[n.as_str()], compile(&cx, &remap(ts, &keep))?))
        })
        .collect::<Option<Vec<_>>>()?;

    // A split subtask's instances, and which of their arguments the
    // method's instances leave `UNBOUND`.
    let split_terms: Vec<(usize, Vec<Arg>, Vec<bool>)> = splits
        .iter()
        .map(|(k, i, args, _)| {
            let m = input.methods[*k].1;
            let (_, core) = split(m);
            let s = &m.subtasks[*i];
            let masked = s.args.iter().map(|t| matches!(t, LTerm::Param(q) if !core.contains(q))).collect();
            Some((by_name[s.name.as_str()], compile(&cx, args)?, masked))
        })
        .collect::<Option<Vec<_>>>()?;
    // The facts: the reachable atoms, and each reachable action instance `ok`.
    let mut start: Vec<AtomId> =
        (0..input.reached.len() as AtomId).filter(|&a| input.reached[a as usize]).collect();
    let mut key = Vec::new();
    for (i, list) in input.instances.iter().enumerate() {
        if list.is_empty() {
            continue;
        }
        let pred = preds.intern(&ok(&input.ops[i].1.name));
        for args in list {
            key.clear();
            key.push(pred);
            key.extend_from_slice(args);
            start.push(atoms.intern(&key));
        }
    }
    let inputs: Vec<&OpInput> = rules.iter().map(|(_, r)| r).collect();
    let mut budget = input.budget;
    let fix = fixpoint(&inputs, &mut atoms, &start, input.initial.to_vec(), &mut budget, input.max_instances);
    let tried = input.budget - budget;
    drop(start);

    // The ground graph: nodes are ground actions and tasks.
    let mut graph = Graph::default();
    for (i, list) in input.instances.iter().enumerate() {
        for args in list {
            graph.node(i, args);
        }
    }
    let mut methods: Vec<MethodInst> = Vec::new();
    // The network's choices: (its task, the ground task).
    let mut roots: Vec<(usize, u32)> = Vec::new();
    // Per split subtask, its ground instances by the arguments the method
    // names (its own parameters `UNBOUND`).
    let mut parts: Vec<FxHashMap<Box<[ObjId]>, Vec<u32>>> = vec![FxHashMap::default(); splits.len()];
    // Task instances become nodes when a method refines them.
    for k in 0..fix.instances.len() {
        let (r, binding) = fix.instances.get(k);
        if let Rule::Task(t) = rules[r].0 {
            graph.node(t, binding);
        }
    }
    for k in 0..fix.instances.len() {
        let (r, binding) = fix.instances.get(k);
        if let Rule::Part(x) = rules[r].0 {
            let (op, ts, masked) = &split_terms[x];
            let args: Vec<ObjId> = ts.iter().map(|a| value(*a, binding)).collect();
            if let Some(node) = graph.find(*op, &args) {
                let key: Box<[ObjId]> =
                    args.iter().zip(masked).map(|(&o, &m)| if m { UNBOUND } else { o }).collect();
                parts[x].entry(key).or_default().push(node);
            }
        }
    }
    // Per method, its split subtasks (index in `splits`) and the
    // parameters its instances bind.
    let mut method_splits: Vec<(Vec<Option<usize>>, Vec<u32>)> =
        input.methods.iter().map(|(_, m)| (vec![None; m.subtasks.len()], split(m).1)).collect();
    for (x, (k, i, _, _)) in splits.iter().enumerate() {
        method_splits[*k].0[*i] = Some(x);
    }
    // The choice nodes made so far.
    let mut choices: FxHashMap<(usize, Box<[ObjId]>), u32> = FxHashMap::default();
    let mut full: Vec<ObjId> = Vec::new();
    for k in 0..fix.instances.len() {
        let (r, binding) = fix.instances.get(k);
        match rules[r].0 {
            Rule::Method(m) => {
                let (task, head, subs, pre) = &method_terms[m];
                let (split_of, core) = &method_splits[m];
                full.clear();
                full.resize(input.methods[m].1.params.len(), UNBOUND);
                for (&q, &o) in core.iter().zip(binding) {
                    full[q as usize] = o;
                }
                let binding = &full[..];
                let eval = |ts: &[Arg]| ts.iter().map(|a| value(*a, binding)).collect::<Vec<ObjId>>();
                let Some(task) = graph.find(*task, &eval(head)) else { continue };
                let mut sub_nodes = Vec::with_capacity(subs.len());
                for ((op, ts), split_of) in subs.iter().zip(split_of) {
                    let args = eval(ts);
                    match split_of {
                        None => match graph.find(*op, &args) {
                            Some(node) => sub_nodes.push(node),
                            None => break,
                        },
                        Some(x) => {
                            let Some(found) = parts[*x].get(&args[..]) else { break };
                            let key = (*x, Box::<[ObjId]>::from(&args[..]));
                            let node = match choices.get(&key) {
                                Some(&node) => node,
                                None => {
                                    let node = graph.node(input.ops.len() + *x, &args);
                                    for &c in found {
                                        methods.push(MethodInst {
                                            method: usize::MAX,
                                            binding: Box::default(),
                                            task: node,
                                            subs: vec![c],
                                            pre: Vec::new(),
                                        });
                                    }
                                    choices.insert(key, node);
                                    node
                                }
                            };
                            sub_nodes.push(node);
                        }
                    }
                }
                if sub_nodes.len() < subs.len() {
                    continue;
                }
                let mut pre_atoms = Vec::new();
                let mut dead = false;
                for c in pre {
                    c.key(binding, &mut key);
                    match input.atoms.get(&key) {
                        Some(a) => pre_atoms.push(a),
                        None => dead = true,
                    }
                }
                if !dead {
                    methods.push(MethodInst {
                        method: m,
                        binding: binding.into(),
                        task,
                        subs: sub_nodes,
                        pre: pre_atoms,
                    });
                }
            }
            Rule::Root(i) => {
                let (op, ts) = &htn_terms[i];
                let args: Vec<ObjId> = ts.iter().map(|a| value(*a, binding)).collect();
                if let Some(node) = graph.find(*op, &args) {
                    roots.push((i, node));
                }
            }
            Rule::Task(_) | Rule::Request | Rule::Aux | Rule::Part(_) => {}
        }
    }
    let truncated = fix.truncated;
    let mut dominant = None;
    if truncated {
        let mut count = vec![0usize; input.methods.len()];
        for k in 0..fix.instances.len() {
            if let Rule::Method(m) = rules[fix.instances.get(k).0].0 {
                count[m] += 1;
            }
        }
        dominant = (0..count.len())
            .max_by_key(|&m| count[m])
            .filter(|&m| count[m] > 0)
            .map(|m| (input.methods[m].1.name.clone(), count[m]));
    }
    drop(fix);
    drop(atoms);

    let pruned = prune(input, &graph, &methods, &roots, &mut key);
    let mut per_op: Vec<Vec<Box<[ObjId]>>> = vec![Vec::new(); input.ops.len()];
    let mut split_at: FxHashMap<u32, usize> = FxHashMap::default();
    let mut split_out: Vec<Split> = Vec::new();
    for (n, (op, args)) in graph.nodes.iter().enumerate() {
        if !pruned.nodes[n] {
            continue;
        }
        match op.checked_sub(input.ops.len()) {
            None => per_op[*op].push(args.clone()),
            Some(x) => {
                split_at.insert(n as u32, split_out.len());
                let (method, subtask, _, _) = splits[x];
                split_out.push(Split { method, subtask, args: args.clone(), choices: Vec::new() });
            }
        }
    }
    let mut by_method: Vec<Vec<Box<[ObjId]>>> = vec![Vec::new(); input.methods.len()];
    for (m, inst) in methods.into_iter().enumerate() {
        if !pruned.methods[m] {
            continue;
        }
        if inst.method == usize::MAX {
            if let Some(&s) = split_at.get(&inst.task) {
                split_out[s].choices.push(graph.nodes[inst.subs[0] as usize].1.clone());
            }
        } else {
            by_method[inst.method].push(inst.binding);
        }
    }
    let methods = input.methods.iter().zip(by_method).map(|((item, _), b)| (*item, b)).collect();
    let mut htn_choices: Vec<Vec<Box<[ObjId]>>> = vec![Vec::new(); htn.subtasks.len()];
    for ((i, node), keep) in roots.into_iter().zip(&pruned.roots) {
        if *keep {
            htn_choices[i].push(graph.nodes[node as usize].1.clone());
        }
    }
    for c in &mut htn_choices {
        c.sort_unstable();
        c.dedup();
    }
    // A network task without parameters that cannot be decomposed is kept,
    // without methods: the search then says there is no plan, at that task.
    for (i, (op, ts)) in htn_terms.iter().enumerate() {
        if htn_choices[i].is_empty() && htn.subtasks[i].1.iter().all(|t| !matches!(t, LTerm::Param(_))) {
            let args: Box<[ObjId]> = ts.iter().map(|a| value(*a, &[])).collect();
            if !per_op[*op].contains(&args) {
                per_op[*op].push(args.clone());
            }
            htn_choices[i].push(args);
        }
    }
    Some(Output {
        per_op,
        reached: pruned.reached,
        methods,
        htn_choices,
        splits: split_out,
        truncated,
        dominant,
        tried,
    })
}

struct MethodInst {
    method: usize,
    binding: Box<[ObjId]>,
    task: u32,
    subs: Vec<u32>,
    /// Its preconditions that are not static.
    pre: Vec<AtomId>,
}

#[derive(Default)]
struct Graph {
    nodes: Vec<(usize, Box<[ObjId]>)>,
    index: FxHashMap<(usize, Box<[ObjId]>), u32>,
}

impl Graph {
    fn node(&mut self, op: usize, args: &[ObjId]) -> u32 {
        let key = (op, Box::<[ObjId]>::from(args));
        if let Some(&n) = self.index.get(&key) {
            return n;
        }
        let n = self.nodes.len() as u32;
        self.nodes.push(key.clone());
        self.index.insert(key, n);
        n
    }

    fn find(&self, op: usize, args: &[ObjId]) -> Option<u32> {
        self.index.get(&(op, Box::<[ObjId]>::from(args))).copied()
    }
}

struct Pruned {
    nodes: Vec<bool>,
    methods: Vec<bool>,
    roots: Vec<bool>,
    reached: Vec<bool>,
}

/// Alternates top-down reachability from the network, relaxed reachability
/// of the actions it reaches, and bottom-up decomposability, until the
/// nodes reached stop changing.
fn prune(
    input: &Input<'_, '_>,
    graph: &Graph,
    methods: &[MethodInst],
    roots: &[(usize, u32)],
    key: &mut Vec<u32>,
) -> Pruned {
    let n = graph.nodes.len();
    // Split subtasks' choices are tasks without conditions or effects.
    let n_ops = input.ops.len();
    let is_task = |node: u32| {
        let op = graph.nodes[node as usize].0;
        op >= n_ops || input.ops[op].1.kind == OperatorKind::Task
    };
    let mut by_task: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (m, inst) in methods.iter().enumerate() {
        by_task[inst.task as usize].push(m as u32);
    }
    // Each node's own preconditions and add effects, as atoms.
    let atoms_of = |node: usize, lists: &[&[CAtom]], key: &mut Vec<u32>| -> Option<Vec<AtomId>> {
        let (op, args) = &graph.nodes[node];
        let mut out = Vec::new();
        for c in lists.get(*op).copied().unwrap_or_default() {
            c.key(args, key);
            out.push(input.atoms.get(key)?);
        }
        Some(out)
    };
    // `None`: a precondition no atom stands for (never reachable).
    let pre: Vec<Option<Vec<AtomId>>> = (0..n).map(|i| atoms_of(i, &input.pre, key)).collect();
    let add: Vec<Vec<AtomId>> = (0..n)
        .map(|i| {
            let (op, args) = &graph.nodes[i];
            input
                .add
                .get(*op)
                .copied()
                .unwrap_or_default()
                .iter()
                .filter_map(|c| {
                    c.key(args, key);
                    input.atoms.get(key)
                })
                .collect()
        })
        .collect();
    let n_atoms = input.atoms.len();
    let mut alive_m = vec![true; methods.len()];
    let mut alive_r = vec![true; roots.len()];
    let mut prev: Option<(Vec<bool>, Vec<bool>, Vec<bool>)> = None;
    loop {
        // Top-down from the network.
        let mut nodes = vec![false; n];
        let mut used_m = vec![false; methods.len()];
        let mut stack: Vec<u32> = Vec::new();
        for (r, &(_, node)) in roots.iter().enumerate() {
            if alive_r[r] {
                stack.push(node);
            }
        }
        while let Some(x) = stack.pop() {
            if std::mem::replace(&mut nodes[x as usize], true) {
                continue;
            }
            for &m in &by_task[x as usize] {
                if alive_m[m as usize] {
                    used_m[m as usize] = true;
                    stack.extend(&methods[m as usize].subs);
                }
            }
        }
        // Relaxed reachability with the nodes reached.
        let mut atom_reached = vec![false; n_atoms];
        let mut queue: Vec<AtomId> = Vec::new();
        for &a in input.start {
            if (a as usize) < n_atoms && !std::mem::replace(&mut atom_reached[a as usize], true) {
                queue.push(a);
            }
        }
        let mut missing: Vec<u32> = vec![u32::MAX; n];
        let mut waiting: FxHashMap<AtomId, Vec<u32>> = FxHashMap::default();
        let mut applicable = vec![false; n];
        let mut fire: Vec<u32> = Vec::new();
        for x in (0..n).filter(|&x| nodes[x]) {
            let Some(p) = &pre[x] else { continue };
            missing[x] = p.len() as u32;
            for &a in p {
                waiting.entry(a).or_default().push(x as u32);
            }
            if p.is_empty() {
                fire.push(x as u32);
            }
        }
        loop {
            while let Some(x) = fire.pop() {
                if std::mem::replace(&mut applicable[x as usize], true) {
                    continue;
                }
                for &a in &add[x as usize] {
                    if !std::mem::replace(&mut atom_reached[a as usize], true) {
                        queue.push(a);
                    }
                }
            }
            let Some(a) = queue.pop() else { break };
            if let Some(ws) = waiting.get(&a) {
                for &x in ws {
                    missing[x as usize] -= 1;
                    if missing[x as usize] == 0 {
                        fire.push(x);
                    }
                }
            }
        }
        // Bottom-up: which tasks can still be decomposed.
        let mut ok = vec![false; n];
        let mut left: Vec<u32> = vec![0; methods.len()];
        let mut users: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut done: Vec<u32> = Vec::new();
        for x in 0..n {
            if applicable[x] && !is_task(x as u32) {
                ok[x] = true;
            }
        }
        for (m, inst) in methods.iter().enumerate() {
            if !used_m[m] || !inst.pre.iter().all(|&a| atom_reached[a as usize]) {
                continue;
            }
            let mut l = 0;
            for &s in &inst.subs {
                if !ok[s as usize] {
                    l += 1;
                    users[s as usize].push(m as u32);
                }
            }
            left[m] = l;
            if l == 0 {
                done.push(m as u32);
            }
        }
        while let Some(m) = done.pop() {
            let t = methods[m as usize].task as usize;
            if ok[t] || !applicable[t] {
                continue;
            }
            ok[t] = true;
            for &u in &users[t] {
                left[u as usize] -= 1;
                if left[u as usize] == 0 {
                    done.push(u);
                }
            }
        }
        for (m, inst) in methods.iter().enumerate() {
            alive_m[m] = used_m[m]
                && inst.pre.iter().all(|&a| atom_reached[a as usize])
                && ok[inst.task as usize]
                && inst.subs.iter().all(|&s| ok[s as usize]);
        }
        for (r, &(_, node)) in roots.iter().enumerate() {
            alive_r[r] = alive_r[r] && ok[node as usize];
        }
        let nodes_ok: Vec<bool> = (0..n).map(|x| nodes[x] && ok[x]).collect();
        let now = (nodes_ok, alive_m.clone(), alive_r.clone());
        if prev.as_ref() == Some(&now) {
            return Pruned { nodes: now.0, methods: alive_m, roots: alive_r, reached: atom_reached };
        }
        prev = Some(now);
    }
}
