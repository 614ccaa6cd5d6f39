//! The decomposition of an abstract step (its method, the binding of the
//! method's variables, its subtasks) and the top level of the plan (the
//! problem's `:htn`).

use rowan::TextRange;
use rustc_hash::FxHashMap;

use super::matching::{
    self, ArgMisfit, Bound, Instance, Misfit, Outcome, PTerm, Pattern, Problem, Source, lookup,
};
use super::timeline::{NetOrder, Timeline};
use super::{Applied, Cx};
use crate::diagnostic::{Code, codes};
use crate::model::{CmpOp, Endpoint, Gd, Method, Str, Subtask, TaskNetwork, Term, Typed};
use crate::plan::StepId;
use crate::semantics::check::{gd_span, suggest};
use crate::semantics::symbols::{Loc, type_set};

/// What a network belongs to: a method (of an abstract step) or the problem's `:htn`.
#[derive(Clone)]
pub(super) enum Owner<'db> {
    Method { step: usize, key: Str, loc: Loc<'db> },
    Htn { loc: Loc<'db> },
}

/// A task network with what is needed to match it and to report on it.
pub(super) struct Net<'db> {
    pub owner: Owner<'db>,
    /// The item the network's spans are relative to.
    pub item: crate::db::Item<'db>,
    pub network: &'db TaskNetwork,
    pub params: &'db [Typed],
    /// Conditions checked on the binding alone (`=`, `sortof`): the
    /// method's precondition and constraints.
    pub statics: Vec<&'db Gd>,
}

/// The patterns of a network's subtasks.
pub(super) fn patterns(net: &TaskNetwork) -> Vec<Pattern> {
    net.subtasks
        .iter()
        .map(|s| Pattern {
            name: s.call.name.key_str(),
            args: s
                .call
                .args
                .iter()
                .map(|t| match t {
                    Term::Var(n) => PTerm::Var(n.key_str()),
                    Term::Const(n) => PTerm::Const(n.key_str()),
                    Term::Func(_) => PTerm::Any,
                })
                .collect(),
        })
        .collect()
}

/// The index of a subtask of a network by its id.
pub(super) fn subtask_index(net: &TaskNetwork, id: &str) -> Option<usize> {
    net.subtasks.iter().position(|s| s.id.as_ref().is_some_and(|n| n.key() == id))
}

/// For each subtask, the subtasks a network orders before it as a whole:
/// `:ordered-subtasks`, `(< a b)`, `(<= (end a) (start b))`, … (an ordering
/// that relates other points, or is negated, does not order whole tasks).
pub(super) fn precedences(net: &TaskNetwork) -> Vec<Vec<usize>> {
    let n = net.subtasks.len();
    let mut preds: Vec<Vec<usize>> = vec![Vec::new(); n];
    if net.ordered {
        for (j, p) in preds.iter_mut().enumerate().skip(1) {
            p.push(j - 1);
        }
    }
    for o in &net.ordering {
        if o.negated {
            continue;
        }
        let (before, after) = match o.op {
            CmpOp::Lt | CmpOp::Le => (&o.left, &o.right),
            CmpOp::Gt | CmpOp::Ge => (&o.right, &o.left),
            CmpOp::Eq => continue,
        };
        let whole_end = matches!(before.endpoint, Endpoint::Whole | Endpoint::End);
        let whole_start = matches!(after.endpoint, Endpoint::Whole | Endpoint::Start);
        if !(whole_end && whole_start) {
            continue;
        }
        if let (Some(a), Some(b)) = (subtask_index(net, before.id.key()), subtask_index(net, after.id.key()))
            && a != b
            && !preds[b].contains(&a)
        {
            preds[b].push(a);
        }
    }
    preds
}

/// The transitive closure of [`precedences`]: for each subtask, every
/// subtask ordered before it, directly or through others.
pub(super) fn transitive(preds: &[Vec<usize>]) -> Vec<Vec<usize>> {
    (0..preds.len())
        .map(|j| {
            let mut seen = vec![false; preds.len()];
            let mut stack: Vec<usize> = preds[j].clone();
            let mut out = Vec::new();
            while let Some(q) = stack.pop() {
                if q == j || std::mem::replace(&mut seen[q], true) {
                    continue;
                }
                out.push(q);
                stack.extend(&preds[q]);
            }
            out.sort_unstable();
            out
        })
        .collect()
}

/// A subtask's name in messages: its id, or its place.
pub(super) fn subtask_label(net: &TaskNetwork, j: usize) -> String {
    match net.subtasks.get(j).and_then(|s| s.id.as_ref()) {
        Some(id) => id.text().to_string(),
        None => format!("subtask {}", j + 1),
    }
}

/// `(name arg…)` of a subtask, with the variables the binding knows replaced.
pub(super) fn instantiate(s: &Subtask, binding: &[Bound]) -> String {
    let mut out = format!("({}", s.call.name.text());
    for t in &s.call.args {
        out.push(' ');
        match t {
            Term::Var(n) => match lookup(binding, n.key()) {
                Some(b) => out.push_str(&b.value),
                None => out.push_str(n.text()),
            },
            Term::Const(n) => out.push_str(n.text()),
            Term::Func(f) => out.push_str(&format!("({} …)", f.func.text())),
        }
    }
    out.push(')');
    out
}

/// `(name arg…)` of a subtask as written.
pub(super) fn written(s: &Subtask) -> String {
    instantiate(s, &[])
}

impl<'db> Cx<'_, 'db> {
    /// Whether a condition holds on a binding alone, ignoring the state:
    /// `Some` when equalities and types decide it, `None` when it depends
    /// on the state (atoms, comparisons, quantifiers) or on unbound variables.
    pub(super) fn static_holds(&self, g: &Gd, binding: &[Bound]) -> Option<bool> {
        let value = |t: &Term| -> Option<Str> {
            match t {
                Term::Var(n) => lookup(binding, n.key()).map(|b| b.value.clone()),
                Term::Const(n) => Some(n.key_str()),
                Term::Func(_) => None,
            }
        };
        match g {
            Gd::Equal(a, b, _) => Some(value(a)? == value(b)?),
            Gd::Sortof(t, ty, _) => Some(self.fits(&value(t)?, &type_set(ty))),
            Gd::Not(x, _) => self.static_holds(x, binding).map(|v| !v),
            Gd::And(xs, _) => {
                let vs: Vec<Option<bool>> = xs.iter().map(|x| self.static_holds(x, binding)).collect();
                if vs.contains(&Some(false)) {
                    Some(false)
                } else if vs.iter().all(|v| *v == Some(true)) {
                    Some(true)
                } else {
                    None
                }
            }
            Gd::Or(xs, _) => {
                let vs: Vec<Option<bool>> = xs.iter().map(|x| self.static_holds(x, binding)).collect();
                if vs.contains(&Some(true)) {
                    Some(true)
                } else if vs.iter().all(|v| *v == Some(false)) {
                    Some(false)
                } else {
                    None
                }
            }
            Gd::Imply(a, b, _) => match (self.static_holds(a, binding), self.static_holds(b, binding)) {
                (Some(false), _) | (_, Some(true)) => Some(true),
                (Some(true), Some(false)) => Some(false),
                _ => None,
            },
            _ => None,
        }
    }

    /// The part of a condition that is false on the binding alone.
    fn static_culprit<'g>(&self, g: &'g Gd, binding: &[Bound]) -> &'g Gd {
        match g {
            Gd::And(xs, _) => xs
                .iter()
                .find(|x| self.static_holds(x, binding) == Some(false))
                .map_or(g, |x| self.static_culprit(x, binding)),
            _ => g,
        }
    }

    /// Checks the decomposition of abstract step `i`.
    pub(super) fn decompose(&mut self, i: usize, tl: &Timeline) {
        let plan = self.plan;
        let s = &plan.steps[i];
        let (Some(res), Some(dec)) = (self.resolved[i].clone(), &s.decomposition) else { return };
        let m = self.opts.matching;
        let Some(mkey) = self.methods.get(&dec.method.text, m).cloned() else {
            self.unknown_method(i, &res.key);
            return;
        };
        let decl_task = self.dom.methods.get(&mkey).and_then(|d| d.task.clone());
        if decl_task.as_deref() != Some(res.key.as_str()) {
            self.wrong_method(i, &res.key, &mkey, decl_task.as_deref());
            return;
        }
        let Some((mloc, method)) = self.method_model(&mkey) else { return };
        let Some(head) = &method.task else { return };
        if head.args.len() != res.args.len() {
            // The method's `:task` has the wrong arity: the checks reported it.
            return;
        }
        let types: FxHashMap<Str, Vec<Str>> =
            method.params.iter().map(|p| (p.name.key_str(), type_set(&p.ty))).collect();
        let mut binding: Vec<Bound> = Vec::new();
        for (k, (t, v)) in head.args.iter().zip(&res.args).enumerate() {
            let problem = match t {
                Term::Var(x) => match lookup(&binding, x.key()) {
                    Some(b) if b.value != *v => {
                        let Source::Head(first) = b.source else { continue };
                        Some(format!(
                            "`{}` is both argument {} (`{}`) and argument {} (`{v}`) of the task, but the method's `:task` `{}` gives them the same variable `{}`",
                            s.call(),
                            first + 1,
                            b.value,
                            k + 1,
                            head_text(method),
                            x.text()
                        ))
                    }
                    Some(_) => None,
                    None => match types.get(x.key()) {
                        Some(ty) if !self.fits(v, ty) => Some(format!(
                            "argument {} of `{}` is `{v}`, of type `{}`, but the method's parameter `{}` has type `{}`",
                            k + 1,
                            s.call(),
                            self.type_of(v),
                            x.text(),
                            ty.join(" or ")
                        )),
                        _ => {
                            binding.push(Bound {
                                var: x.key_str(),
                                value: v.clone(),
                                source: Source::Head(k),
                            });
                            None
                        }
                    },
                },
                Term::Const(c) if c.key() != *v => Some(format!(
                    "argument {} of `{}` is `{v}`, but the method's `:task` `{}` has the constant `{}` there",
                    k + 1,
                    s.call(),
                    head_text(method),
                    c.text()
                )),
                _ => None,
            };
            if let Some(why) = problem {
                let arg = s.args.get(k).map_or(s.range, |a| a.range);
                let mut d = self.diag(
                    codes::METHOD_HEAD_MISMATCH,
                    arg,
                    format!("method `{mkey}` cannot refine {}: {why}", self.step_text(i)),
                );
                self.related_loc(&mut d, Loc { item: mloc.item, span: head.span }, "the method's `:task`");
                let others = self.methods_of(&res.key, Some(&mkey));
                let hint = if others.is_empty() {
                    format!("no other method refines `{}`: the step's arguments are wrong", res.key)
                } else {
                    format!("use a method whose `:task` fits: {}", others.join(", "))
                };
                self.hint(&mut d, hint, Vec::new());
                self.push(d);
                return;
            }
        }
        if self.bad_list[i] {
            return;
        }
        let mut statics = Vec::new();
        statics.extend(method.precondition.as_ref());
        statics.extend(method.network.constraints.as_ref());
        let net = Net {
            owner: Owner::Method { step: i, key: mkey.clone(), loc: mloc },
            item: mloc.item,
            network: &method.network,
            params: &method.params,
            statics,
        };
        let ids = dec.subtasks.clone();
        let list = list_range(&ids, dec.method.range);
        if let Some(m) = self.match_network(&net, &ids, list, binding, tl) {
            self.applied[i] = Some(Applied {
                method_key: mkey,
                method,
                method_loc: mloc,
                binding: m.binding,
                assign: m.assign,
                static_ok: m.static_ok,
                orderings_undecided: m.orderings_undecided,
            });
        }
    }

    /// The names of the methods of a task, but `except`.
    fn methods_of(&self, task: &str, except: Option<&str>) -> Vec<String> {
        let mut v: Vec<&str> = self
            .dom
            .methods
            .iter()
            .filter(|(k, d)| d.task.as_deref() == Some(task) && Some(k.as_str()) != except)
            .map(|(k, _)| k.as_str())
            .collect();
        v.sort_unstable();
        v.into_iter().map(|k| format!("`{k}`")).collect()
    }

    fn unknown_method(&mut self, i: usize, task: &str) {
        let dec = self.plan.steps[i].decomposition.as_ref().map(|d| d.method.clone());
        let Some(method) = dec else { return };
        let mut d = self.diag(
            codes::UNKNOWN_METHOD,
            method.range,
            format!(
                "{} is refined by `{}`, but the domain has no method of that name",
                self.step_text(i),
                method.text
            ),
        );
        let own = self.methods_of(task, None);
        let keys: Vec<&str> = self
            .dom
            .methods
            .iter()
            .filter(|(_, m)| m.task.as_deref() == Some(task))
            .map(|(k, _)| k.as_str())
            .collect();
        if let Some(best) = suggest(&method.text.to_ascii_lowercase(), keys.into_iter()) {
            let best = best.to_string();
            self.hint(&mut d, format!("did you mean `{best}`?"), vec![(method.range, best)]);
        } else if own.is_empty() {
            self.hint(&mut d, format!("the task `{task}` has no method"), Vec::new());
        } else {
            self.hint(&mut d, format!("the methods of `{task}` are {}", own.join(", ")), Vec::new());
        }
        if let Some(t) = self.dom.tasks.get(task) {
            let loc = t.loc;
            self.related_loc(&mut d, loc, "the task is declared here");
        }
        self.push(d);
    }

    fn wrong_method(&mut self, i: usize, task: &str, method: &str, its_task: Option<&str>) {
        let Some(sym) = self.plan.steps[i].decomposition.as_ref().map(|d| d.method.clone()) else { return };
        let its = its_task.map_or("another task".to_string(), |t| format!("`{t}`"));
        let mut d = self.diag(
            codes::WRONG_METHOD,
            sym.range,
            format!(
                "{} is refined by `{method}`, but `{method}` is a method of {its}, not of `{task}`",
                self.step_text(i)
            ),
        );
        if let Some(decl) = self.dom.methods.get(method) {
            let loc = decl.loc;
            self.related_loc(&mut d, loc, format!("`{method}` is declared here"));
        }
        let own = self.methods_of(task, None);
        let hint = if own.is_empty() {
            format!("the task `{task}` has no method")
        } else {
            format!("the methods of `{task}` are {}", own.join(", "))
        };
        self.hint(&mut d, hint, Vec::new());
        self.push(d);
    }

    /// Matches the listed steps `ids` with the network, reporting what does
    /// not match; of several matchings, one under which the orderings hold
    /// on the timeline. Returns the matching when the steps match the
    /// subtasks one to one.
    pub(super) fn match_network(
        &mut self,
        net: &Net<'db>,
        ids: &[StepId],
        list: TextRange,
        initial: Vec<Bound>,
        tl: &Timeline,
    ) -> Option<NetMatch> {
        let plan = self.plan;
        let steps: Vec<usize> = ids.iter().filter_map(|id| plan.index_of(id.value)).collect();
        if steps.len() != ids.len() {
            // An id names no step: the reader reported it.
            return None;
        }
        let mut instances = Vec::with_capacity(steps.len());
        for &j in &steps {
            let res = self.resolved[j].as_ref()?;
            instances.push(Instance { name: res.key.as_str(), args: res.args.as_slice() });
        }
        let pats = patterns(net.network);
        let preds = precedences(net.network);
        let types: FxHashMap<Str, Vec<Str>> =
            net.params.iter().map(|p| (p.name.key_str(), type_set(&p.ty))).collect();
        let type_ok = |var: &str, obj: &str| types.get(var).is_none_or(|ty| self.fits(obj, ty));
        let accept = |b: &[Bound]| net.statics.iter().all(|g| self.static_holds(g, b) != Some(false));
        let orderings = NetOrder::new(tl, net.network, plan, ids);
        let problem = Problem {
            patterns: &pats,
            preds: &preds,
            instances: &instances,
            initial: &initial,
            type_ok: &type_ok,
            accept: &accept,
            use_order: self.opts.listed_order,
            orderings: Some(&orderings),
        };
        let outcome = matching::matching(&problem);
        let report = match outcome {
            Outcome::Matched { assign, binding, undecided } => {
                if undecided {
                    self.report_undecided(net, ids, list);
                }
                return Some(NetMatch { assign, binding, static_ok: true, orderings_undecided: undecided });
            }
            Outcome::Unordered { assign, binding, undecided } => {
                self.report_listing_order(net, ids, list, &preds, &assign);
                if undecided {
                    self.report_undecided(net, ids, list);
                }
                return Some(NetMatch { assign, binding, static_ok: true, orderings_undecided: undecided });
            }
            Outcome::Rejected { assign, binding } => {
                self.report_rejected(net, list, &binding);
                return Some(NetMatch { assign, binding, static_ok: false, orderings_undecided: false });
            }
            Outcome::TooComplex => Report::TooComplex,
            Outcome::Partial { assign, binding } => {
                let misfits: Vec<(usize, Misfit)> = (0..steps.len())
                    .filter(|&pos| assign[pos].is_none())
                    .map(|pos| (pos, matching::explain(&problem, &assign, &binding, pos)))
                    .collect();
                Report::Partial { assign, binding, misfits }
            }
        };
        match report {
            Report::TooComplex => {
                let mut d = self.diag(
                    codes::HIERARCHY_NOT_CHECKED,
                    list,
                    format!(
                        "{}: too many ways to match the {} listed steps with the subtasks; the decomposition is not checked",
                        self.owner_text(net),
                        ids.len()
                    ),
                );
                self.related_owner(&mut d, net);
                self.push(d);
            }
            Report::Partial { assign, binding, misfits } => {
                self.report_partial(net, ids, &steps, list, &pats, &assign, &binding, &misfits);
            }
        }
        None
    }

    /// Too many matchings to find one under which the orderings hold.
    fn report_undecided(&mut self, net: &Net<'db>, ids: &[StepId], list: TextRange) {
        let mut d = self.diag(
            codes::HIERARCHY_NOT_CHECKED,
            list,
            format!(
                "{}: the orderings do not hold under the first matching of the {} listed steps with the subtasks, and there are too many others to try (more than {} search nodes); the orderings of the decomposition are not checked",
                self.owner_text(net),
                ids.len(),
                matching::BUDGET
            ),
        );
        self.related_owner(&mut d, net);
        self.hint(
            &mut d,
            "the method has many identical subtasks: the steps may match them in too many ways",
            Vec::new(),
        );
        self.push(d);
    }

    /// "method `m-deliver` of step 8 `(deliver p l)`", "the problem's `:htn`".
    pub(super) fn owner_text(&self, net: &Net<'db>) -> String {
        match &net.owner {
            Owner::Method { step, key, .. } => format!("method `{key}` of {}", self.step_text(*step)),
            Owner::Htn { .. } => "the problem's `:htn`".to_string(),
        }
    }

    fn owner_code(&self, net: &Net<'db>, method_code: &'static Code) -> &'static Code {
        match net.owner {
            Owner::Method { .. } => method_code,
            Owner::Htn { .. } => codes::HTN_MISMATCH,
        }
    }

    fn related_owner(&self, d: &mut crate::diagnostic::Diagnostic, net: &Net<'db>) {
        match &net.owner {
            Owner::Method { loc, key, .. } => self.related_loc(d, *loc, format!("`{key}` is declared here")),
            Owner::Htn { loc } => self.related_loc(d, *loc, "the problem's `:htn`"),
        }
    }

    fn subtask_loc(&self, net: &Net<'db>, j: usize) -> Loc<'db> {
        let span = net.network.subtasks.get(j).map_or(TextRange::default(), |s| s.call.span);
        Loc { item: net.item, span }
    }

    fn report_listing_order(
        &mut self,
        net: &Net<'db>,
        ids: &[StepId],
        list: TextRange,
        preds: &[Vec<usize>],
        assign: &[usize],
    ) {
        let Some((early, late)) = matching::first_inversion(preds, assign) else { return };
        let order = matching::allowed_order(preds, assign);
        let fixed: Vec<String> = order.iter().map(|&p| ids[p].value.to_string()).collect();
        let (je, jl) = (assign[early], assign[late]);
        let step =
            |pos: usize| self.plan.index_of(ids[pos].value).map_or(String::new(), |j| self.step_text(j));
        let short = if matches!(net.owner, Owner::Htn { .. }) { "`:htn`" } else { "method" };
        let (listed, whose) = match &net.owner {
            Owner::Method { step: i, key, .. } => {
                (format!("the subtasks of {}", self.step_text(*i)), format!("method `{key}`"))
            }
            Owner::Htn { .. } => ("the roots".to_string(), "the problem's `:htn`".to_string()),
        };
        let mut d = self.diag(
            codes::SUBTASK_LISTING_ORDER,
            ids[early].range,
            format!(
                "{listed} are listed in an order {whose} forbids: {} ({}) is listed before {} ({}), which the {short} orders before it",
                step(early),
                subtask_label(net.network, je),
                step(late),
                subtask_label(net.network, jl),
            ),
        );
        self.related_plan(&mut d, ids[late].range, format!("{} is listed here", ids[late].value));
        let ordering = net.network.ordering.iter().find(|o| {
            subtask_index(net.network, o.left.id.key()).is_some_and(|a| a == jl || a == je)
                && subtask_index(net.network, o.right.id.key()).is_some_and(|b| b == jl || b == je)
        });
        match ordering {
            Some(o) => self.related_loc(&mut d, Loc { item: net.item, span: o.span }, "the ordering"),
            None => self.related_loc(&mut d, self.subtask_loc(net, jl), "the subtask ordered first"),
        }
        self.hint(
            &mut d,
            format!(
                "pandaPIparser matches subtasks in the order they are listed: list them as `{}`",
                fixed.join(" ")
            ),
            vec![(list, fixed.join(" "))],
        );
        self.push(d);
    }

    fn report_rejected(&mut self, net: &Net<'db>, list: TextRange, binding: &[Bound]) {
        let Some(g) = net.statics.iter().find(|g| self.static_holds(g, binding) == Some(false)) else {
            return;
        };
        let culprit = self.static_culprit(g, binding);
        let shown: Vec<String> = binding.iter().map(|b| format!("{} = {}", b.var, b.value)).collect();
        let code = self.owner_code(net, codes::METHOD_PRECONDITION_FALSE);
        let mut d = self.diag(
            code,
            list,
            format!(
                "{}: the subtasks match, but under their binding ({}) a constraint of the method is false",
                self.owner_text(net),
                shown.join(", ")
            ),
        );
        self.related_loc(&mut d, Loc { item: net.item, span: gd_span(culprit) }, "this constraint is false");
        self.hint(
            &mut d,
            "the steps do not satisfy the method's constraints: use another method or other steps",
            Vec::new(),
        );
        self.push(d);
    }

    #[allow(clippy::too_many_arguments)]
    fn report_partial(
        &mut self,
        net: &Net<'db>,
        ids: &[StepId],
        steps: &[usize],
        list: TextRange,
        pats: &[Pattern],
        assign: &[Option<usize>],
        binding: &[Bound],
        misfits: &[(usize, Misfit)],
    ) {
        let free: Vec<usize> = (0..pats.len()).filter(|j| !assign.contains(&Some(*j))).collect();
        let labels: Vec<String> = (0..pats.len()).map(|j| subtask_label(net.network, j)).collect();
        let is_htn = matches!(net.owner, Owner::Htn { .. });
        // The listed steps that fit no subtask.
        for (pos, misfit) in misfits {
            let j = steps[*pos];
            let step = self.step_text(j);
            let code = self.owner_code(net, codes::UNEXPECTED_SUBTASK);
            let whose = match &net.owner {
                Owner::Method { key, .. } => format!("method `{key}`"),
                Owner::Htn { .. } => "the problem's `:htn`".to_string(),
            };
            let listed = match net.owner {
                Owner::Method { step: i, .. } => {
                    format!("{step} is listed as a subtask of step {}", self.id_value(i))
                }
                Owner::Htn { .. } => format!("{step} is a root"),
            };
            let (why, pattern) = match misfit {
                Misfit::NoSuchName => {
                    let name = self.resolved[j].as_ref().map_or("", |r| r.key.as_str()).to_string();
                    let mut all: Vec<String> = pats.iter().map(|p| format!("`{}`", p.name)).collect();
                    all.dedup();
                    let have = if all.is_empty() { "none".to_string() } else { all.join(", ") };
                    (format!("{whose} has no subtask `{name}` (it has {have})"), None)
                }
                Misfit::Taken(by) => {
                    let by: Vec<String> = by.iter().map(|&p| ids[p].value.to_string()).collect();
                    (
                        format!(
                            "every subtask of {whose} with this task is already the step {} listed with it",
                            by.join(" or ")
                        ),
                        None,
                    )
                }
                Misfit::Argument { pattern, arg, why } => {
                    let sub = &net.network.subtasks[*pattern];
                    let got =
                        self.resolved[j].as_ref().and_then(|r| r.args.get(*arg)).map_or("", |a| a.as_str());
                    let why = match why {
                        ArgMisfit::Constant(c) => {
                            format!("argument {} is `{got}`, but the subtask has `{c}` there", arg + 1)
                        }
                        ArgMisfit::Bound(b) => {
                            let from = match b.source {
                                Source::Head(k) => match net.owner {
                                    Owner::Method { step: i, .. } => {
                                        format!("argument {} of {}", k + 1, self.step_text(i))
                                    }
                                    Owner::Htn { .. } => "the `:htn`".to_string(),
                                },
                                Source::Subtask(p) => self.step_text(steps[p]),
                            };
                            format!(
                                "`{}` is `{}` (from {from}), but argument {} is `{got}`",
                                b.var,
                                b.value,
                                arg + 1
                            )
                        }
                        ArgMisfit::Type(v) => {
                            let ty = net
                                .params
                                .iter()
                                .find(|p| p.name.key() == *v)
                                .map_or("object".to_string(), |p| type_set(&p.ty).join(" or "));
                            format!(
                                "argument {} is `{got}`, of type `{}`, but `{v}` has type `{ty}`",
                                arg + 1,
                                self.type_of(got)
                            )
                        }
                        ArgMisfit::Arity(k) => format!("the subtask takes {k} arguments"),
                    };
                    (
                        format!(
                            "it does not fit {} `{}`: {why}",
                            labels[*pattern],
                            instantiate(sub, binding)
                        ),
                        Some(*pattern),
                    )
                }
                Misfit::Constraints { pattern } => (
                    format!(
                        "as {} `{}`, a constraint of the method would be false",
                        labels[*pattern],
                        written(&net.network.subtasks[*pattern])
                    ),
                    Some(*pattern),
                ),
            };
            let mut d = self.diag(code, ids[*pos].range, format!("{listed}, but {why}"));
            if let Some(p) = pattern {
                self.related_loc(&mut d, self.subtask_loc(net, p), format!("{} of {whose}", labels[p]));
            } else {
                self.related_owner(&mut d, net);
            }
            self.related_plan(&mut d, self.plan.steps[j].range, "the step");
            let hint = if free.is_empty() {
                format!("remove {} from the list", ids[*pos].value)
            } else {
                let wanted: Vec<String> = free
                    .iter()
                    .map(|&k| format!("{} `{}`", labels[k], instantiate(&net.network.subtasks[k], binding)))
                    .collect();
                format!("the subtasks without a step are {}", wanted.join(", "))
            };
            self.hint(&mut d, hint, Vec::new());
            self.push(d);
        }
        // The subtasks without a step, beyond those the misfits stand for.
        let missing = free.len().saturating_sub(misfits.len());
        if missing == 0 {
            return;
        }
        // Prefer, as missing, the subtasks no misfit step has the task of.
        let misfit_names: Vec<&str> = misfits
            .iter()
            .filter_map(|(pos, _)| self.resolved[steps[*pos]].as_ref().map(|r| r.key.as_str()))
            .collect();
        let mut order: Vec<usize> = free.clone();
        order.sort_by_key(|&k| (misfit_names.contains(&pats[k].name.as_str()), k));
        let shown: Vec<usize> = order.into_iter().take(missing).collect();
        let list_all = labels.join(" ");
        let n = pats.len();
        for &k in &shown {
            let sub = &net.network.subtasks[k];
            let inst = instantiate(sub, binding);
            let message = if is_htn {
                format!(
                    "the problem's `:htn` has {n} task{} ({list_all}); the roots give {}: no root is {} `{inst}`",
                    if n == 1 { "" } else { "s" },
                    ids.len(),
                    labels[k]
                )
            } else {
                format!(
                    "{} has {n} subtask{} ({list_all}); the plan gives {} id{}: no step is {} `{inst}`",
                    self.owner_text(net),
                    if n == 1 { "" } else { "s" },
                    ids.len(),
                    if ids.len() == 1 { "" } else { "s" },
                    labels[k]
                )
            };
            let code = self.owner_code(net, codes::MISSING_SUBTASK);
            let mut d = self.diag(code, list, message);
            self.related_loc(&mut d, self.subtask_loc(net, k), format!("{} is declared here", labels[k]));
            let how = if pats[k].name.is_empty() {
                String::new()
            } else if self.dom.tasks.contains_key(&pats[k].name) {
                format!(
                    "`ID {} -> METHOD SUBTASK-IDS…` after `root`",
                    inst.trim_start_matches('(').trim_end_matches(')')
                )
            } else {
                format!("`ID {}` before `root`", inst.trim_start_matches('(').trim_end_matches(')'))
            };
            let target = if is_htn { "the `root` line" } else { "the decomposition" };
            self.hint(
                &mut d,
                format!("add the step for {} {how} and its id to {target}", labels[k]),
                Vec::new(),
            );
            self.push(d);
        }
    }

    /// Matches the top level of the plan with the problem's `:htn`.
    pub(super) fn roots(&mut self, tl: &Timeline) {
        let Some((loc, htn)) = self.htn else { return };
        if self.top.implicit {
            let n = htn.network.subtasks.len();
            if n == 0 {
                return;
            }
            let at = self.plan.begin.or_else(|| self.plan.steps.first().map(|s| s.range)).unwrap_or_default();
            let mut d = self.diag(
                codes::HTN_MISMATCH,
                at,
                format!(
                    "the plan has no `root` line, but the problem's `:htn` has {n} task{} to refine",
                    if n == 1 { "" } else { "s" }
                ),
            );
            self.related_loc(&mut d, loc, "the problem's `:htn`");
            self.hint(
                &mut d,
                "list the steps of the `:htn`'s tasks on a `root` line after the primitive steps",
                Vec::new(),
            );
            self.push(d);
            return;
        }
        let mut statics = Vec::new();
        statics.extend(htn.network.constraints.as_ref());
        let net = Net {
            owner: Owner::Htn { loc },
            item: loc.item,
            network: &htn.network,
            params: &htn.params,
            statics,
        };
        let ids = self.top.ids.clone();
        let list = match self.top.artificial {
            Some(i) => self.plan.steps[i]
                .decomposition
                .as_ref()
                .map_or(self.top.range, |d| list_range(&d.subtasks, d.method.range)),
            None => self.plan.root.as_ref().map_or(self.top.range, |r| list_range(&r.ids, r.range)),
        };
        if let Some(m) = self.match_network(&net, &ids, list, Vec::new(), tl) {
            self.htn_assign = Some(m.assign);
            self.htn_orderings_undecided = m.orderings_undecided;
        }
    }
}

/// A matching of a network's subtasks with the listed steps.
pub(super) struct NetMatch {
    /// For each listed step, its subtask.
    pub assign: Vec<usize>,
    pub binding: Vec<Bound>,
    /// The static conditions hold on the binding.
    pub static_ok: bool,
    /// Too many matchings to find one under which the orderings hold.
    pub orderings_undecided: bool,
}

enum Report {
    TooComplex,
    Partial { assign: Vec<Option<usize>>, binding: Vec<Bound>, misfits: Vec<(usize, Misfit)> },
}

/// The range of a list of ids (empty, after `after`, when there are none).
pub(super) fn list_range(ids: &[StepId], after: TextRange) -> TextRange {
    match (ids.first(), ids.last()) {
        (Some(a), Some(b)) => TextRange::new(a.range.start(), b.range.end()),
        _ => TextRange::empty(after.end()),
    }
}

/// The method's `:task` as written.
pub(super) fn head_text(method: &Method) -> String {
    let Some(t) = &method.task else { return String::new() };
    let mut s = format!("({}", t.name.text());
    for a in &t.args {
        s.push(' ');
        match a {
            Term::Var(n) | Term::Const(n) => s.push_str(n.text()),
            Term::Func(f) => s.push_str(&format!("({} …)", f.func.text())),
        }
    }
    s.push(')');
    s
}
