//! Per-item checks: names, arities, types, variables, subtask ids, orderings.
//!
//! A check reads its item's model and the symbol tables only, so editing one
//! action re-runs the check of that action alone.

use crate::model::Str;
use std::borrow::Cow;

use rowan::TextRange;
use rustc_hash::{FxHashMap, FxHashSet};

use super::resolve::resolve_domain;
use super::symbols::{
    DeclKind, DomainSymbols, Loc, ProblemSymbols, SigDecl, TypeSet, domain_symbols, problem_symbols, type_set,
};
use crate::db::{Db, Item, Unit, UnitKind, file_units, lower_item};
use crate::diagnostic::{Code, codes};
use crate::model::*;

/// A diagnostic of one item: item-relative primary span, related spans anywhere.
#[derive(Debug, Clone, PartialEq, Eq, salsa::SalsaValue)]
pub struct ItemDiag<'db> {
    pub code: &'static Code,
    pub span: TextRange,
    pub message: String,
    pub related: Vec<(Loc<'db>, String)>,
    /// A replacement of a span of this item.
    pub fix: Option<(String, TextRange, String)>,
}

/// What an item uses: names (for unused-declaration warnings) and language
/// features (for missing-requirement warnings, with the first place each is used).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Uses {
    pub types: FxHashSet<Str>,
    pub predicates: FxHashSet<Str>,
    pub functions: FxHashSet<Str>,
    pub constants: FxHashSet<Str>,
    pub features: Vec<(Feature, TextRange)>,
}

/// A language feature that needs a requirement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Feature {
    Typing,
    NegativePreconditions,
    DisjunctivePreconditions,
    ExistentialPreconditions,
    UniversalPreconditions,
    ConditionalEffects,
    Equality,
    NumericFluents,
    DurativeActions,
    DurationInequalities,
    TimedInitialLiterals,
    DerivedPredicates,
    Preferences,
    Constraints,
    Hierarchy,
    MethodPreconditions,
}

impl Feature {
    /// The requirement to declare, and the requirements that also grant it.
    pub fn requirement(self) -> (&'static str, &'static [&'static str]) {
        match self {
            Feature::Typing => (":typing", &[":adl"]),
            Feature::NegativePreconditions => (":negative-preconditions", &[":adl"]),
            Feature::DisjunctivePreconditions => (":disjunctive-preconditions", &[":adl"]),
            Feature::ExistentialPreconditions => {
                (":existential-preconditions", &[":quantified-preconditions", ":adl"])
            }
            Feature::UniversalPreconditions => {
                (":universal-preconditions", &[":quantified-preconditions", ":adl"])
            }
            Feature::ConditionalEffects => (":conditional-effects", &[":adl"]),
            Feature::Equality => (":equality", &[":adl"]),
            Feature::NumericFluents => (":numeric-fluents", &[":fluents"]),
            Feature::DurativeActions => (":durative-actions", &[":time"]),
            Feature::DurationInequalities => (":duration-inequalities", &[]),
            Feature::TimedInitialLiterals => (":timed-initial-literals", &[]),
            Feature::DerivedPredicates => (":derived-predicates", &[]),
            Feature::Preferences => (":preferences", &[]),
            Feature::Constraints => (":constraints", &[":method-constraints"]),
            Feature::Hierarchy => (":hierarchy", &[":hierachie", ":htn"]),
            Feature::MethodPreconditions => (":method-preconditions", &[]),
        }
    }

    /// What the user wrote that needs it, for messages.
    pub fn what(self) -> &'static str {
        match self {
            Feature::Typing => "typed declarations",
            Feature::NegativePreconditions => "a negative condition `(not …)`",
            Feature::DisjunctivePreconditions => "a disjunctive condition (`or`, `imply`)",
            Feature::ExistentialPreconditions => "`exists`",
            Feature::UniversalPreconditions => "`forall` in a condition",
            Feature::ConditionalEffects => "a conditional effect (`when`, `forall`)",
            Feature::Equality => "`=` between objects",
            Feature::NumericFluents => "numeric fluents",
            Feature::DurativeActions => "durative actions",
            Feature::DurationInequalities => "a duration inequality",
            Feature::TimedInitialLiterals => "a timed initial literal `(at t …)`",
            Feature::DerivedPredicates => "`:derived`",
            Feature::Preferences => "`preference`",
            Feature::Constraints => "constraints",
            Feature::Hierarchy => "tasks and methods",
            Feature::MethodPreconditions => "a method precondition",
        }
    }
}

/// The result of checking one item.
#[derive(Debug, Clone, PartialEq, Eq, Default, salsa::SalsaValue)]
pub struct ItemCheck<'db> {
    pub diags: Vec<ItemDiag<'db>>,
    pub uses: Uses,
}

/// The unit an item belongs to.
pub fn unit_of<'db>(db: &'db dyn Db, item: Item<'db>) -> Option<Unit<'db>> {
    file_units(db, item.file(db)).get(item.unit(db) as usize).copied()
}

/// The domain symbols an item is checked against, if its domain is known.
pub fn domain_for<'db>(db: &'db dyn Db, unit: Unit<'db>) -> Option<Unit<'db>> {
    match unit.kind(db) {
        UnitKind::Domain => Some(unit),
        UnitKind::Problem => resolve_domain(db, unit).domain(),
        UnitKind::Unknown => None,
    }
}

/// Checks one item.
#[salsa::tracked(returns(ref))]
pub fn check_item<'db>(db: &'db dyn Db, item: Item<'db>) -> ItemCheck<'db> {
    let Some(unit) = unit_of(db, item) else { return ItemCheck::default() };
    let domain = domain_for(db, unit);
    let empty = DomainSymbols::default();
    let dom = domain.map_or(&empty, |d| domain_symbols(db, d));
    let prob = (unit.kind(db) == UnitKind::Problem).then(|| problem_symbols(db, unit));
    let mut cx = Checker {
        db,
        unit,
        item,
        dom,
        prob,
        known_domain: domain.is_some(),
        scope: Vec::new(),
        durative: false,
        ids: None,
        out: ItemCheck::default(),
    };
    cx.item_data(&lower_item(db, item).data);
    cx.out
}

struct Checker<'a, 'db> {
    db: &'db dyn Db,
    unit: Unit<'db>,
    item: Item<'db>,
    dom: &'a DomainSymbols<'db>,
    prob: Option<&'a ProblemSymbols<'db>>,
    /// Whether the domain is known: without it, names cannot be checked.
    known_domain: bool,
    scope: Vec<(Str, TypeSet)>,
    /// Whether `?duration` is defined here.
    durative: bool,
    /// Subtask ids of the task network being checked.
    ids: Option<FxHashSet<Str>>,
    out: ItemCheck<'db>,
}

/// Levenshtein distance, for "did you mean" suggestions.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur.push(sub.min(prev[j + 1] + 1).min(cur[j] + 1));
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The closest of `candidates` to `name`, if close enough to be a typo.
pub fn suggest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (name.len() / 3).clamp(1, 3);
    let mut scored: Vec<(usize, &str)> =
        candidates.map(|c| (distance(name, c), c)).filter(|(d, c)| *d <= limit && *c != name).collect();
    scored.sort_unstable();
    scored.dedup();
    match scored.as_slice() {
        // Two equally close names: a guess would be a coin toss.
        [(d1, _), (d2, _), ..] if d1 == d2 => None,
        [(_, c), ..] => Some(c),
        [] => None,
    }
}

fn describe(t: &[Str]) -> String {
    if t.len() == 1 { format!("`{}`", t[0]) } else { format!("`(either {})`", t.join(" ")) }
}

impl<'a, 'db> Checker<'a, 'db> {
    fn loc(&self, span: TextRange) -> Loc<'db> {
        Loc { item: self.item, span }
    }

    fn diag(&mut self, code: &'static Code, span: TextRange, message: String) -> &mut ItemDiag<'db> {
        self.out.diags.push(ItemDiag { code, span, message, related: Vec::new(), fix: None });
        self.out.diags.last_mut().expect("just pushed")
    }

    fn feature(&mut self, f: Feature, span: TextRange) {
        if !self.out.uses.features.iter().any(|(g, _)| *g == f) {
            self.out.uses.features.push((f, span));
        }
    }

    fn undefined(&mut self, code: &'static Code, what: &str, name: &Name, candidates: Vec<&str>) {
        let suggestion = suggest(&name.key, candidates.into_iter()).map(str::to_string);
        let d = self.diag(code, name.span, format!("undefined {what} `{}`", name.text));
        if let Some(s) = suggestion {
            d.message.push_str(&format!(" (did you mean `{s}`?)"));
            d.fix = Some((format!("replace with `{s}`"), name.span, s));
        }
    }

    fn item_data(&mut self, data: &ItemData) {
        match data {
            ItemData::Header(_) | ItemData::DomainRef(_) | ItemData::Unknown => {}
            ItemData::Requirements(reqs) => self.requirements(reqs),
            ItemData::Types(types) => {
                if let Some(t) = types.first() {
                    self.feature(Feature::Typing, t.name.span);
                }
                for t in types {
                    if self.dom.cyclic_types.contains(&t.name.key) && t.ty != TypeRef::Implicit {
                        let msg = format!("type `{}` is its own ancestor", t.name.text);
                        self.diag(codes::TYPE_CYCLE, t.name.span, msg);
                    }
                    self.type_ref(&t.ty);
                }
            }
            ItemData::Constants(cs) | ItemData::Objects(cs) => {
                for c in cs {
                    self.type_ref(&c.ty);
                }
            }
            ItemData::Predicates(sigs) | ItemData::Functions(sigs) => {
                for s in sigs {
                    self.params(&s.params, false);
                    if let TypeRef::Named(n) = &s.result
                        && n.key.as_str() != "number"
                    {
                        self.type_ref(&s.result);
                    }
                }
                if matches!(data, ItemData::Functions(_))
                    && let Some(s) = sigs.first()
                {
                    self.feature(Feature::NumericFluents, s.span);
                }
            }
            ItemData::Action(a) => self.action(a),
            ItemData::Task(t) => self.task(t),
            ItemData::Method(m) => self.method(m),
            ItemData::Derived(atom, params, body) => {
                self.feature(Feature::DerivedPredicates, atom.pred.span);
                self.params(params, true);
                self.gd(body, true);
                self.scope.clear();
            }
            ItemData::Init(elements) => {
                for e in elements {
                    self.init_element(e);
                }
            }
            ItemData::Goal(g) => self.gd(g, true),
            ItemData::Htn(h) => {
                self.feature(Feature::Hierarchy, h.span);
                self.params(&h.params, true);
                self.network(&h.network);
                self.scope.clear();
            }
            ItemData::AllowedActions(names) => {
                for n in names {
                    if self.known_domain && self.dom.callable(&n.key).is_none() {
                        let cands =
                            self.dom.actions.keys().chain(self.dom.tasks.keys()).map(|k| &**k).collect();
                        self.undefined(codes::UNDEFINED_ACTION, "action or task", n, cands);
                    }
                }
            }
            ItemData::Metric(_, e) => self.num_expr(e),
            ItemData::Constraints(g) => {
                self.feature(Feature::Constraints, gd_span(g));
                self.gd(g, false);
            }
        }
    }

    /// `at start`, `at end` and `over all` need a duration to refer to.
    fn untimed_context(&mut self, ts: TimeSpec, span: TextRange) {
        if !self.durative {
            let what = match ts {
                TimeSpec::AtStart => "at start",
                TimeSpec::AtEnd => "at end",
                TimeSpec::OverAll => "over all",
            };
            let msg = format!(
                "`{what}` needs a duration: use it in a durative action, a durative method or a task with a `:duration`"
            );
            self.diag(codes::MALFORMED, span, msg);
        }
    }

    fn requirements(&mut self, reqs: &[Name]) {
        for r in reqs {
            if !KNOWN_REQUIREMENTS.contains(&r.key.as_ref()) {
                let s = suggest(&r.key, KNOWN_REQUIREMENTS.iter().copied()).map(str::to_string);
                let d = self.diag(
                    codes::UNKNOWN_REQUIREMENT,
                    r.span,
                    format!("unknown requirement `{}`", r.text),
                );
                if let Some(s) = s {
                    d.message.push_str(&format!(" (did you mean `{s}`?)"));
                    d.fix = Some((format!("replace with `{s}`"), r.span, s));
                }
            }
        }
    }

    fn type_ref(&mut self, t: &TypeRef) {
        if *t != TypeRef::Implicit
            && let Some(n) = t.names().first()
        {
            self.feature(Feature::Typing, n.span);
        }
        for n in t.names() {
            self.out.uses.types.insert(n.key.clone());
            if self.known_domain && !self.dom.is_type(&n.key) {
                let cands = self.dom.types.keys().map(|k| &**k).collect();
                self.undefined(codes::UNDEFINED_TYPE, "type", n, cands);
            }
        }
    }

    /// Checks parameter declarations; pushes them in scope when `bind`.
    fn params(&mut self, params: &[Typed], bind: bool) {
        let mut seen: FxHashMap<&str, TextRange> = FxHashMap::default();
        for p in params {
            self.type_ref(&p.ty);
            if let Some(first) = seen.insert(&p.name.key, p.name.span) {
                let msg = format!("parameter `{}` is declared twice", p.name.text);
                let loc = self.loc(first);
                self.diag(codes::DUPLICATE, p.name.span, msg)
                    .related
                    .push((loc, "first declared here".into()));
            }
            if bind {
                self.scope.push((p.name.key.clone(), type_set(&p.ty)));
            }
        }
    }

    fn agent(&mut self, agent: &[Name]) {
        for a in agent {
            if !self.scope.iter().any(|(v, _)| *v == a.key) {
                let msg = format!("agent `{}` is not a parameter", a.text);
                self.diag(codes::UNDEFINED_VARIABLE, a.span, msg);
            }
        }
    }

    fn action(&mut self, a: &Action) {
        self.params(&a.params, true);
        self.agent(&a.agent);
        self.durative = a.kind == ActionKind::Durative;
        if a.kind == ActionKind::Durative {
            self.feature(Feature::DurativeActions, a.name.span);
        }
        if let Some(d) = &a.duration {
            self.duration(d);
        }
        if let Some(p) = &a.precondition {
            self.gd(p, true);
        }
        if let Some(e) = &a.effect {
            self.effect(e);
        }
        self.durative = false;
        self.scope.clear();
    }

    fn duration(&mut self, d: &Gd) {
        let saved = self.durative;
        self.durative = true;
        let simple = matches!(d, Gd::Compare(CmpOp::Eq, NumExpr::Duration(_), _, _))
            || matches!(d, Gd::And(v, _) if v.is_empty());
        if !simple {
            self.feature(Feature::DurationInequalities, gd_span(d));
        }
        self.gd(d, false);
        self.durative = saved;
    }

    fn task(&mut self, t: &Task) {
        self.feature(Feature::Hierarchy, t.name.span);
        self.params(&t.params, true);
        self.agent(&t.agent);
        self.durative = t.duration.is_some();
        if let Some(d) = &t.duration {
            self.duration(d);
        }
        if let Some(p) = &t.precondition {
            self.gd(p, true);
        }
        if let Some(e) = &t.effect {
            self.effect(e);
        }
        for c in &t.conflicts {
            self.atom(c, true);
        }
        self.durative = false;
        self.scope.clear();
    }

    fn method(&mut self, m: &Method) {
        self.feature(Feature::Hierarchy, m.name.span);
        self.durative = m.durative || m.duration.is_some();
        self.params(&m.params, true);
        if let Some(call) = &m.task {
            let dom = self.dom;
            match dom.tasks.get(&call.name.key) {
                Some(decl) => self.call_args(call, decl, "task"),
                None if !self.known_domain => {}
                None => {
                    if let Some(action) = self.dom.actions.get(&call.name.key) {
                        let loc = action.loc;
                        let msg = format!("`{}` is an action: a method decomposes a task", call.name.text);
                        self.diag(codes::UNDEFINED_TASK, call.name.span, msg)
                            .related
                            .push((loc, "declared as an action here".into()));
                    } else {
                        let cands = self.dom.tasks.keys().map(|k| &**k).collect();
                        self.undefined(codes::UNDEFINED_TASK, "task", &call.name, cands);
                    }
                }
            }
        }
        if let Some(p) = &m.precondition {
            self.feature(Feature::MethodPreconditions, gd_span(p));
            self.gd(p, true);
        }
        self.network(&m.network);
        if let Some(d) = &m.duration {
            self.duration(d);
        }
        if let Some(e) = &m.effect {
            self.effect(e);
        }
        self.ids = None;
        self.durative = false;
        self.scope.clear();
    }

    /// Checks a task network; leaves its ids in `self.ids` for duration constraints.
    fn network(&mut self, net: &TaskNetwork) {
        let mut ids: FxHashMap<Str, TextRange> = FxHashMap::default();
        for st in &net.subtasks {
            if let Some(id) = &st.id
                && let Some(first) = ids.insert(id.key.clone(), id.span)
            {
                let msg = format!("subtask id `{}` is used twice", id.text);
                let loc = self.loc(first);
                self.diag(codes::DUPLICATE, id.span, msg).related.push((loc, "first used here".into()));
            }
            let dom = self.dom;
            match dom.callable(&st.call.name.key) {
                Some(decl) => self.call_args(&st.call, decl, "subtask"),
                None if !self.known_domain => {}
                None => {
                    let cands = self.dom.actions.keys().chain(self.dom.tasks.keys()).map(|k| &**k).collect();
                    self.undefined(codes::UNDEFINED_ACTION, "action or task", &st.call.name, cands);
                }
            }
        }
        self.ids = Some(ids.keys().cloned().collect());
        for o in &net.ordering {
            for p in [&o.left, &o.right] {
                self.subtask_id(&p.id);
            }
        }
        self.ordering_cycles(&net.ordering);
        for cl in &net.causal_links {
            self.subtask_id(&cl.from);
            self.subtask_id(&cl.to);
            self.atom(&cl.atom, false);
        }
        if let Some(c) = &net.constraints {
            self.gd(c, false);
        }
    }

    fn subtask_id(&mut self, id: &Name) {
        let Some(ids) = &self.ids else { return };
        if !ids.contains(&id.key) {
            let cands: Vec<&str> = ids.iter().map(|k| &**k).collect();
            let suggestion = suggest(&id.key, cands.into_iter()).map(str::to_string);
            let d =
                self.diag(codes::UNDEFINED_SUBTASK, id.span, format!("no subtask has the id `{}`", id.text));
            if let Some(s) = suggestion {
                d.message.push_str(&format!(" (did you mean `{s}`?)"));
                d.fix = Some((format!("replace with `{s}`"), id.span, s));
            }
        }
    }

    /// Reports a cycle of strict orderings (`t1 < t2 < … < t1`): a strongly
    /// connected component of the time-point graph with a strict edge inside.
    fn ordering_cycles(&mut self, orderings: &[Ordering]) {
        // Nodes are time points (subtask id, start?); a whole subtask before another means its end.
        let mut index: FxHashMap<TimePoint, usize> = FxHashMap::default();
        let mut node = |p: &OrderPoint, left: bool| -> usize {
            let start = match p.endpoint {
                Endpoint::Start => true,
                Endpoint::End => false,
                Endpoint::Whole => !left,
            };
            let n = index.len();
            *index.entry((p.id.key.clone(), start)).or_insert(n)
        };
        // (from, to, strict, ordering index)
        let mut edges: Vec<(usize, usize, bool, usize)> = Vec::new();
        for (i, o) in orderings.iter().enumerate() {
            if o.negated {
                continue;
            }
            let (from, to, strict) = match o.op {
                CmpOp::Lt => (node(&o.left, true), node(&o.right, false), true),
                CmpOp::Le => (node(&o.left, true), node(&o.right, false), false),
                CmpOp::Gt => (node(&o.right, true), node(&o.left, false), true),
                CmpOp::Ge => (node(&o.right, true), node(&o.left, false), false),
                CmpOp::Eq => continue,
            };
            edges.push((from, to, strict, i));
        }
        // A subtask starts before it ends.
        let points: Vec<(TimePoint, usize)> = index.iter().map(|(k, v)| (k.clone(), *v)).collect();
        for ((id, start), n) in &points {
            if *start && let Some(&end) = index.get(&(id.clone(), false)) {
                edges.push((*n, end, false, usize::MAX));
            }
        }
        let comp = strongly_connected(index.len(), &edges);
        let Some(&(a, _, _, _)) = edges.iter().find(|(a, b, strict, _)| *strict && comp[*a] == comp[*b])
        else {
            return;
        };
        let mut involved: Vec<usize> = edges
            .iter()
            .filter(|(x, y, _, i)| comp[*x] == comp[a] && comp[*y] == comp[a] && *i != usize::MAX)
            .map(|e| e.3)
            .collect();
        involved.sort_unstable();
        involved.dedup();
        let related: Vec<_> = involved[1..]
            .iter()
            .map(|&i| (self.loc(orderings[i].span), "part of the cycle".to_string()))
            .collect();
        let msg = "these orderings form a cycle: no schedule can satisfy them".to_string();
        self.diag(codes::ORDERING_CYCLE, orderings[involved[0]].span, msg).related = related;
    }

    fn call_args(&mut self, call: &TaskCall, decl: &SigDecl<'db>, _what: &str) {
        self.args(&call.name, &call.args, call.span, decl, false);
    }

    /// Checks arity and argument types against a declaration.
    fn args(&mut self, name: &Name, args: &[Term], span: TextRange, decl: &SigDecl<'db>, wildcards: bool) {
        let kind = match decl.kind {
            DeclKind::Predicate | DeclKind::Derived => "predicate",
            DeclKind::Function => "function",
            DeclKind::Action(_) => "action",
            DeclKind::Task => "task",
        };
        if args.len() != decl.params.len() {
            for a in args {
                self.term(a, wildcards);
            }
            let msg = format!(
                "{kind} `{}` takes {} argument{}, but {} {} given",
                name.text,
                decl.params.len(),
                if decl.params.len() == 1 { "" } else { "s" },
                args.len(),
                if args.len() == 1 { "is" } else { "are" }
            );
            self.diag(codes::ARITY, span, msg).related.push((decl.loc, "declared here".into()));
            return;
        }
        for (arg, param) in args.iter().zip(&decl.params) {
            let Some(ty) = self.term(arg, wildcards) else { continue };
            // A variable of a supertype narrows to the parameter's type (HDDL's
            // "sortof" semantics); an object must fit.
            let ok = match arg {
                Term::Var(_) => self.dom.compatible(&ty, param),
                _ => self.dom.fits(&ty, param),
            };
            if !ok {
                let msg = format!(
                    "`{}` has type {}, but {kind} `{}` expects {} here",
                    term_text(arg),
                    describe(&ty),
                    name.text,
                    describe(param)
                );
                self.diag(codes::TYPE_MISMATCH, arg.span(), msg)
                    .related
                    .push((decl.loc, "declared here".into()));
            }
        }
    }

    /// The type of a term, reporting what is undefined.
    fn term(&mut self, t: &Term, wildcards: bool) -> Option<Cow<'a, [Str]>> {
        let dom = self.dom;
        match t {
            Term::Var(v) => {
                if let Some((_, ty)) = self.scope.iter().rev().find(|(n, _)| *n == v.key) {
                    return Some(Cow::Owned(ty.clone()));
                }
                if v.key.as_str() == "?duration" && self.durative {
                    return None;
                }
                if !wildcards {
                    let cands: Vec<String> = self.scope.iter().map(|(n, _)| n.to_string()).collect();
                    let suggestion = suggest(&v.key, cands.iter().map(String::as_str)).map(str::to_string);
                    let d = self.diag(
                        codes::UNDEFINED_VARIABLE,
                        v.span,
                        format!("variable `{}` is not bound by a parameter or quantifier", v.text),
                    );
                    if let Some(s) = suggestion {
                        d.message.push_str(&format!(" (did you mean `{s}`?)"));
                        d.fix = Some((format!("replace with `{s}`"), v.span, s));
                    }
                }
                None
            }
            Term::Const(c) => {
                if c.key.parse::<f64>().is_ok() {
                    return None;
                }
                self.out.uses.constants.insert(c.key.clone());
                if let Some(d) = dom.constants.get(&c.key) {
                    return Some(Cow::Borrowed(&d.ty));
                }
                if let Some(d) = self.prob.and_then(|p| p.objects.get(&c.key)) {
                    return Some(Cow::Borrowed(&d.ty));
                }
                if self.prob.is_none() && self.known_domain {
                    // pandaPIparser accepts a domain constant that its problems declare as an object.
                    let problems = super::resolve::problems_of(self.db, self.unit);
                    let declaring = problems.iter().find_map(|&p| {
                        problem_symbols(self.db, p).objects.get(&c.key).map(|o| (p, o.clone()))
                    });
                    if let Some((p, obj)) = declaring {
                        let pname = p.name(self.db).clone().unwrap_or_default();
                        let msg = format!(
                            "constant `{}` is not declared in the domain, only as an object of problem `{pname}`",
                            c.text
                        );
                        self.diag(codes::CONSTANT_FROM_PROBLEM, c.span, msg)
                            .related
                            .push((obj.loc, "declared here".into()));
                        return Some(Cow::Owned(obj.ty));
                    }
                    if problems.is_empty() {
                        let msg = format!(
                            "constant `{}` is not declared in the domain: its problems must declare it as an object",
                            c.text
                        );
                        self.diag(codes::CONSTANT_FROM_PROBLEM, c.span, msg);
                        return None;
                    }
                }
                if self.known_domain {
                    let mut cands: Vec<&str> = self.dom.constants.keys().map(|k| &**k).collect();
                    if let Some(p) = self.prob {
                        cands.extend(p.objects.keys().map(|k| &**k));
                    }
                    let what = if self.prob.is_some() { "object" } else { "constant" };
                    self.undefined(codes::UNDEFINED_OBJECT, what, c, cands);
                }
                None
            }
            Term::Func(f) => self.fluent(f),
        }
    }

    fn fluent(&mut self, f: &Fluent) -> Option<Cow<'a, [Str]>> {
        self.out.uses.functions.insert(f.func.key.clone());
        let dom = self.dom;
        match dom.functions.get(&f.func.key) {
            Some(decl) => {
                self.args(&f.func, &f.args, f.span, decl, false);
                decl.result.as_deref().map(Cow::Borrowed)
            }
            None => {
                for a in &f.args {
                    self.term(a, false);
                }
                if self.known_domain {
                    let cands = self.dom.functions.keys().map(|k| &**k).collect();
                    self.undefined(codes::UNDEFINED_FUNCTION, "function", &f.func, cands);
                }
                None
            }
        }
    }

    fn atom(&mut self, a: &Atom, wildcards: bool) {
        if !self.out.uses.predicates.contains(&a.pred.key) {
            self.out.uses.predicates.insert(a.pred.key.clone());
        }
        let dom = self.dom;
        match dom.predicates.get(&a.pred.key) {
            Some(decl) => self.args(&a.pred, &a.args, a.span, decl, wildcards),
            None => {
                for t in &a.args {
                    self.term(t, wildcards);
                }
                if self.known_domain {
                    let cands = self.dom.predicates.keys().map(|k| &**k).collect();
                    self.undefined(codes::UNDEFINED_PREDICATE, "predicate", &a.pred, cands);
                }
            }
        }
    }

    fn num_expr(&mut self, e: &NumExpr) {
        match e {
            NumExpr::Number(_) => {}
            NumExpr::Fluent(f) => {
                self.feature(Feature::NumericFluents, f.span);
                self.fluent(f);
            }
            NumExpr::Op(_, args, _) => {
                for a in args {
                    self.num_expr(a);
                }
            }
            NumExpr::Duration(span) => {
                if !self.durative {
                    self.diag(
                        codes::UNDEFINED_VARIABLE,
                        *span,
                        "`?duration` is only defined in durative actions and timed tasks".into(),
                    );
                }
            }
            NumExpr::TaskDuration(id, _) => self.subtask_id(id),
            NumExpr::Special(..) => {}
            NumExpr::Var(v) => {
                self.term(&Term::Var(v.clone()), false);
            }
        }
    }

    /// Checks a goal description. `precondition`: negations and quantifiers there need requirements.
    fn gd(&mut self, g: &Gd, precondition: bool) {
        match g {
            Gd::Atom(a) => self.atom(a, false),
            Gd::Equal(a, b, span) => {
                self.feature(Feature::Equality, *span);
                self.term(a, false);
                self.term(b, false);
            }
            Gd::Compare(_, a, b, _) => {
                self.num_expr(a);
                self.num_expr(b);
            }
            Gd::Not(inner, span) => {
                if precondition && !matches!(**inner, Gd::Equal(..)) {
                    self.feature(Feature::NegativePreconditions, *span);
                }
                self.gd(inner, precondition);
            }
            Gd::And(v, _) => {
                for x in v {
                    self.gd(x, precondition);
                }
            }
            Gd::Or(v, span) => {
                self.feature(Feature::DisjunctivePreconditions, *span);
                for x in v {
                    self.gd(x, precondition);
                }
            }
            Gd::Imply(a, b, span) => {
                self.feature(Feature::DisjunctivePreconditions, *span);
                self.gd(a, precondition);
                self.gd(b, precondition);
            }
            Gd::Forall(ps, body, span) | Gd::Exists(ps, body, span) => {
                let f = if matches!(g, Gd::Forall(..)) {
                    Feature::UniversalPreconditions
                } else {
                    Feature::ExistentialPreconditions
                };
                self.feature(f, *span);
                let depth = self.scope.len();
                self.params(ps, true);
                self.gd(body, precondition);
                self.scope.truncate(depth);
            }
            Gd::Timed(ts, inner, span) => {
                self.untimed_context(*ts, *span);
                self.gd(inner, precondition)
            }
            Gd::Preference(_, inner, span) => {
                self.feature(Feature::Preferences, *span);
                self.gd(inner, precondition);
            }
            Gd::Modal(_, gds, ids, _) => {
                for x in gds {
                    self.gd(x, precondition);
                }
                if self.ids.is_some() {
                    for id in ids {
                        self.subtask_id(id);
                    }
                }
            }
            Gd::Order(o) => {
                self.subtask_id(&o.left.id);
                self.subtask_id(&o.right.id);
            }
            Gd::Sortof(t, ty, _) => {
                self.term(t, false);
                self.type_ref(ty);
            }
        }
    }

    fn effect(&mut self, e: &Effect) {
        match e {
            Effect::Add(a) | Effect::Del(a, _) => self.atom(a, false),
            Effect::And(v, _) => {
                for x in v {
                    self.effect(x);
                }
            }
            Effect::Forall(ps, body, span) => {
                self.feature(Feature::ConditionalEffects, *span);
                let depth = self.scope.len();
                self.params(ps, true);
                self.effect(body);
                self.scope.truncate(depth);
            }
            Effect::When(c, body, span) => {
                self.feature(Feature::ConditionalEffects, *span);
                self.gd(c, false);
                self.effect(body);
            }
            Effect::Numeric(_, f, v, span) => {
                self.feature(Feature::NumericFluents, *span);
                self.fluent(f);
                self.num_expr(v);
            }
            Effect::Timed(ts, inner, span) => {
                self.untimed_context(*ts, *span);
                self.effect(inner)
            }
        }
    }

    fn init_element(&mut self, e: &InitElement) {
        match e {
            InitElement::Fact(a) | InitElement::NotFact(a, _) => self.atom(a, false),
            InitElement::Assign(f, v, span) => {
                self.feature(Feature::NumericFluents, *span);
                self.fluent(f);
                self.num_expr(v);
            }
            InitElement::AssignObject(f, o, _) => {
                self.fluent(f);
                self.term(&Term::Const(o.clone()), false);
            }
            InitElement::Timed(_, inner, span) => {
                self.feature(Feature::TimedInitialLiterals, *span);
                self.init_element(inner);
            }
        }
    }
}

/// A subtask's start (`true`) or end.
type TimePoint = (Str, bool);

/// The strongly connected component of each node (Kosaraju, iterative).
fn strongly_connected(n: usize, edges: &[(usize, usize, bool, usize)]) -> Vec<usize> {
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut rev: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(a, b, _, _) in edges {
        out[a].push(b);
        rev[b].push(a);
    }
    // First pass: finishing order.
    let mut order = Vec::with_capacity(n);
    let mut seen = vec![false; n];
    for s in 0..n {
        if seen[s] {
            continue;
        }
        seen[s] = true;
        let mut stack = vec![(s, 0usize)];
        while let Some((v, i)) = stack.pop() {
            if i < out[v].len() {
                stack.push((v, i + 1));
                let w = out[v][i];
                if !seen[w] {
                    seen[w] = true;
                    stack.push((w, 0));
                }
            } else {
                order.push(v);
            }
        }
    }
    // Second pass on the reversed graph, in reverse finishing order.
    let mut comp = vec![usize::MAX; n];
    let mut c = 0;
    for &s in order.iter().rev() {
        if comp[s] != usize::MAX {
            continue;
        }
        let mut stack = vec![s];
        comp[s] = c;
        while let Some(v) = stack.pop() {
            for &w in &rev[v] {
                if comp[w] == usize::MAX {
                    comp[w] = c;
                    stack.push(w);
                }
            }
        }
        c += 1;
    }
    comp
}

fn term_text(t: &Term) -> String {
    match t {
        Term::Var(n) | Term::Const(n) => n.text.to_string(),
        Term::Func(f) => format!("({} …)", f.func.text),
    }
}

pub fn gd_span(g: &Gd) -> TextRange {
    match g {
        Gd::Atom(a) => a.span,
        Gd::Order(o) => o.span,
        Gd::Equal(.., s)
        | Gd::Compare(.., s)
        | Gd::Not(_, s)
        | Gd::And(_, s)
        | Gd::Or(_, s)
        | Gd::Imply(_, _, s)
        | Gd::Forall(_, _, s)
        | Gd::Exists(_, _, s)
        | Gd::Timed(_, _, s)
        | Gd::Preference(_, _, s)
        | Gd::Modal(.., s)
        | Gd::Sortof(.., s) => *s,
    }
}

/// Requirements hipop knows (PDDL 1.2–3.1, PDDL+, HDDL 1.0 and 2.1).
pub const KNOWN_REQUIREMENTS: &[&str] = &[
    ":strips",
    ":typing",
    ":negative-preconditions",
    ":disjunctive-preconditions",
    ":equality",
    ":existential-preconditions",
    ":universal-preconditions",
    ":quantified-preconditions",
    ":conditional-effects",
    ":fluents",
    ":numeric-fluents",
    ":object-fluents",
    ":adl",
    ":durative-actions",
    ":duration-inequalities",
    ":continuous-effects",
    ":derived-predicates",
    ":timed-initial-literals",
    ":preferences",
    ":constraints",
    ":action-costs",
    ":time",
    ":hierarchy",
    ":method-preconditions",
    ":durative-methods",
    ":method-constraints",
];
