//! Per-item checks: names, arities, types, variables, subtask ids, orderings.
//!
//! A check reads its item's model and the symbol tables only, so editing one
//! action re-runs the check of that action alone.

mod features;
mod names;
mod network;

use rowan::TextRange;
use rustc_hash::{FxHashMap, FxHashSet};

use super::resolve::resolve_domain;
use super::symbols::{
    DomainSymbols, Loc, ProblemSymbols, SigDecl, TypeSet, domain_symbols, problem_symbols, type_set,
};
use crate::db::{Db, Item, Unit, UnitKind, file_units, lower_item};
use crate::diagnostic::{Code, codes};
use crate::model::*;

pub use features::{Feature, KNOWN_REQUIREMENTS};
pub use names::suggest;

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
        last_predicate: None,
        last_function: None,
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
    /// The last predicate and function looked up: consecutive facts of a
    /// problem mostly share them, and a key comparison beats two hash lookups.
    last_predicate: Option<(Str, &'a SigDecl<'db>)>,
    last_function: Option<(Str, &'a SigDecl<'db>)>,
    out: ItemCheck<'db>,
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

    fn item_data(&mut self, data: &ItemData) {
        match data {
            ItemData::Header(_) | ItemData::DomainRef(_) | ItemData::Unknown => {}
            ItemData::Requirements(reqs) => self.requirements(reqs),
            ItemData::Types(types) => {
                if let Some(t) = types.first() {
                    self.feature(Feature::Typing, t.name.span);
                }
                for t in types {
                    if self.dom.cyclic_types.iter().any(|c| c == t.name.key()) && t.ty != TypeRef::Implicit {
                        let msg = format!("type `{}` is its own ancestor", t.name.text());
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
                        && n.key() != "number"
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
                    if self.known_domain && self.dom.callable(n.key()).is_none() {
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
            if !KNOWN_REQUIREMENTS.contains(&r.key()) {
                let s = suggest(r.key(), KNOWN_REQUIREMENTS.iter().copied()).map(str::to_string);
                let d = self.diag(
                    codes::UNKNOWN_REQUIREMENT,
                    r.span,
                    format!("unknown requirement `{}`", r.text()),
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
            self.out.uses.types.insert(n.key_str());
            if self.known_domain && !self.dom.is_type(n.key()) {
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
            if let Some(first) = seen.insert(p.name.key(), p.name.span) {
                let msg = format!("parameter `{}` is declared twice", p.name.text());
                let loc = self.loc(first);
                self.diag(codes::DUPLICATE, p.name.span, msg)
                    .related
                    .push((loc, "first declared here".into()));
            }
            if bind {
                self.scope.push((p.name.key_str(), type_set(&p.ty)));
            }
        }
    }

    fn agent(&mut self, agent: &[Name]) {
        for a in agent {
            if !self.scope.iter().any(|(v, _)| *v == a.key()) {
                let msg = format!("agent `{}` is not a parameter", a.text());
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
        let simple = matches!(d, Gd::Compare(CmpOp::Eq, l, _, _) if matches!(**l, NumExpr::Duration(_)))
            || matches!(d, Gd::And(v, _) if v.is_empty());
        if !simple {
            self.feature(Feature::DurationInequalities, gd_span(d));
        }
        self.gd(d, false);
        self.duration_values(d);
        self.durative = saved;
    }

    /// `E0115`: a constraint on `?duration` with a constant value that no
    /// duration satisfies, `(= ?duration -5)`, `(<= ?duration (- 2 5))`, or
    /// a value that is not a finite number, `(= ?duration (/ 1 0))`.
    fn duration_values(&mut self, d: &Gd) {
        match d {
            Gd::And(parts, _) => parts.iter().for_each(|p| self.duration_values(p)),
            Gd::Timed(_, inner, _) => self.duration_values(inner),
            Gd::Compare(op, a, b, span) => {
                let (op, value) = match (&**a, &**b) {
                    (NumExpr::Duration(_), e) => (*op, e),
                    // `(>= 5 ?duration)` is `(<= ?duration 5)`.
                    (e, NumExpr::Duration(_)) => match op {
                        CmpOp::Lt => (CmpOp::Gt, e),
                        CmpOp::Le => (CmpOp::Ge, e),
                        CmpOp::Ge => (CmpOp::Le, e),
                        CmpOp::Gt => (CmpOp::Lt, e),
                        CmpOp::Eq => (CmpOp::Eq, e),
                    },
                    _ => return,
                };
                let Some(v) = static_value(value) else { return };
                let why = if !v.is_finite() {
                    format!("the duration is `{v}`, not a finite number")
                } else {
                    match op {
                        CmpOp::Eq if v < 0.0 => format!("the duration is {v}: a duration cannot be negative"),
                        CmpOp::Le if v < 0.0 => {
                            format!("no duration is at most {v}: a duration cannot be negative")
                        }
                        CmpOp::Lt if v <= 0.0 => {
                            format!("no duration is below {v}: a duration cannot be negative")
                        }
                        _ => return,
                    }
                };
                self.diag(
                    codes::NEGATIVE_DURATION,
                    *span,
                    format!("{why}, so the action can never be applied"),
                );
            }
            _ => {}
        }
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
        for c in t.conflicts.iter().flat_map(|c| &c.atoms) {
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
            match dom.tasks.get(call.name.key()) {
                Some(decl) => self.call_args(call, decl, "task"),
                None if !self.known_domain => {}
                None => {
                    if let Some(action) = self.dom.actions.get(call.name.key()) {
                        let loc = action.loc;
                        let msg = format!("`{}` is an action: a method decomposes a task", call.name.text());
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

fn term_text(t: &Term) -> String {
    match t {
        Term::Var(n) | Term::Const(n) => n.text().to_string(),
        Term::Func(f) => format!("({} …)", f.func.text()),
    }
}

/// The value of a numeric expression without fluents, as arithmetic gives
/// it: a division by zero is infinite (or not a number), not refused.
fn static_value(e: &NumExpr) -> Option<f64> {
    match e {
        NumExpr::Number(n) => Some(n.value()),
        NumExpr::Op(op, args, _) => {
            let vals = args.iter().map(static_value).collect::<Option<Vec<f64>>>()?;
            let (first, rest) = vals.split_first()?;
            Some(match (&**op, rest) {
                ("-", []) => -first,
                ("+", _) => rest.iter().fold(*first, |a, b| a + b),
                ("-", _) => rest.iter().fold(*first, |a, b| a - b),
                ("*", _) => rest.iter().fold(*first, |a, b| a * b),
                ("/", _) => rest.iter().fold(*first, |a, b| a / b),
                _ => return None,
            })
        }
        _ => None,
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
