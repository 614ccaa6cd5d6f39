//! The lifted STRIPS view of actions, tasks and methods that model verification
//! reasons on (Definitions 2, 3 and 6 of the HiPOP paper): preconditions, add and
//! delete lists, equality constraints, a duration, conflicts, and subtasks.
//!
//! Durative actions are flattened the way the paper's definitions read them:
//! `Pre` is every condition (`at start`, `over all`, `at end`) but those the
//! action's own start may make true in some instance (relaxed reachability
//! must not ask for them before it starts), `Add` and `Del` every effect of
//! either end. What does not fit that view (disjunctions,
//! quantifiers, conditional or numeric effects, object-fluent terms) is listed
//! in [`Operator::unsupported`], so that each check can decide whether its
//! conclusion still holds; numeric conditions are kept apart because grounding
//! can ignore them safely (they only restrict).
//!
//! Spans are relative to the item, like the model's.

use rowan::TextRange;

use crate::db::{Db, Item, Section, lower_item};
use crate::model::{
    Action, ActionKind, Atom, CmpOp, ConflictsForm, Effect, Gd, ItemData, Method, NumExpr, Str, Symbol, Task,
    Term, TimeSpec, Typed,
};
use crate::semantics::check::gd_span;
use crate::semantics::symbols::type_set;

/// A term of a lifted atom.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum LTerm {
    /// The operator's (or method's) parameter at this index.
    Param(u32),
    /// A constant, by key.
    Const(Symbol),
    /// A variable that is not a parameter: a wildcard in `:conflicts`, a
    /// quantified variable in a `forall` effect, or a placeholder for a term
    /// hipop cannot name (an object fluent).
    Free(Symbol),
}

/// The arguments of a lifted atom: most have at most three, kept inline.
pub type LArgs = smallvec::SmallVec<[LTerm; 3]>;

/// `(pred args…)` over [`LTerm`]s.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct LAtom {
    /// The predicate's key.
    pub pred: Symbol,
    pub args: LArgs,
    pub span: TextRange,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Param {
    pub name: Str,
    /// The alternatives of its type (`either`), `object` when untyped.
    pub types: Vec<Str>,
    pub span: TextRange,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OperatorKind {
    Action,
    Durative,
    /// A HiPOP abstract action (an HDDL task, possibly with its own condition,
    /// effect, duration and conflicts).
    Task,
}

/// How long an operator takes.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Duration {
    /// Instantaneous (`:action`) or not given (a task without `:duration`).
    None,
    /// `(= ?duration e)`.
    Exact(NumExpr),
    /// Only bounds (`(<= ?duration e)`, …): no single value.
    Bounded(TextRange),
}

/// A construct outside the STRIPS view, where it is.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Unsupported {
    pub span: TextRange,
    pub what: &'static str,
}

/// A conditions list: positive and negative atoms, (in)equalities.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct Conditions {
    pub pos: Vec<LAtom>,
    pub neg: Vec<LAtom>,
    pub eq: Vec<(LTerm, LTerm)>,
    pub neq: Vec<(LTerm, LTerm)>,
    /// Numeric comparisons (ignored by grounding: they only restrict).
    pub numeric: Vec<TextRange>,
}

/// An action or task as (name, Pre, Add, Del, dur, 𝒞).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Operator {
    pub kind: OperatorKind,
    pub name: Str,
    pub name_span: TextRange,
    pub params: Vec<Param>,
    pub pre: Conditions,
    /// The atom conditions left out of `pre` because the operator's own
    /// start may make them true: an instance where it does not still needs
    /// them (relevance analysis reads them; `eq`, `neq` and `numeric` stay
    /// empty).
    pub own_start: Conditions,
    pub add: Vec<LAtom>,
    pub del: Vec<LAtom>,
    pub duration: Duration,
    /// `:conflicts` of a task, `None` when it has none (an action, or a plain
    /// HDDL task, which is not a HiPOP abstract action).
    pub conflicts: Option<LConflicts>,
    pub unsupported: Vec<Unsupported>,
}

/// A task's `:conflicts`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct LConflicts {
    /// Variables that are not parameters are [`LTerm::Free`] (wildcards).
    pub atoms: Vec<LAtom>,
    /// The `:conflicts` keyword.
    pub keyword: TextRange,
    /// The formula after it.
    pub span: TextRange,
    pub form: ConflictsForm,
}

/// A subtask of a method, over the method's parameters.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct LSubtask {
    pub id: Option<Str>,
    pub name: Str,
    pub args: Vec<LTerm>,
    pub span: TextRange,
}

/// A method: the task it refines (over the method's parameters), its
/// precondition and its subtasks.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct MethodSchema {
    pub name: Str,
    pub name_span: TextRange,
    pub params: Vec<Param>,
    /// The task refined and its arguments.
    pub task: Option<(Str, Vec<LTerm>, TextRange)>,
    pub pre: Conditions,
    pub subtasks: Vec<LSubtask>,
    pub unsupported: Vec<Unsupported>,
}

/// The lifted operator of an action or task item.
#[salsa::tracked(returns(ref))]
pub fn operator<'db>(db: &'db dyn Db, item: Item<'db>) -> Option<Operator> {
    if !matches!(item.section(db), Section::Action | Section::Task) {
        return None;
    }
    match &lower_item(db, item).data {
        ItemData::Action(a) => Some(action_operator(a)),
        ItemData::Task(t) => Some(task_operator(t)),
        _ => None,
    }
}

/// The lifted schema of a method item.
#[salsa::tracked(returns(ref))]
pub fn method_schema<'db>(db: &'db dyn Db, item: Item<'db>) -> Option<MethodSchema> {
    if item.section(db) != Section::Method {
        return None;
    }
    match &lower_item(db, item).data {
        ItemData::Method(m) => Some(method(m)),
        _ => None,
    }
}

/// Translates terms and formulas against a parameter list.
struct Scope<'a> {
    params: &'a [Param],
    unsupported: Vec<Unsupported>,
}

impl Scope<'_> {
    fn term(&mut self, t: &Term) -> LTerm {
        match t {
            Term::Var(n) => match self.params.iter().position(|p| p.name == n.key()) {
                Some(i) => LTerm::Param(i as u32),
                None => LTerm::Free(n.key_sym()),
            },
            Term::Const(n) => LTerm::Const(n.key_sym()),
            Term::Func(f) => {
                self.unsupported.push(Unsupported { span: f.span, what: "an object-fluent term" });
                LTerm::Free(format!("({})", f.func.key()).into())
            }
        }
    }

    fn atom(&mut self, a: &Atom) -> LAtom {
        LAtom { pred: a.pred.key_sym(), args: a.args.iter().map(|t| self.term(t)).collect(), span: a.span }
    }

    fn unsupported(&mut self, span: TextRange, what: &'static str) {
        self.unsupported.push(Unsupported { span, what });
    }

    /// Adds a condition to `out`; `positive` is false under a `not`.
    fn condition(&mut self, gd: &Gd, positive: bool, out: &mut Conditions) {
        match gd {
            Gd::Atom(a) => {
                let a = self.atom(a);
                if positive { out.pos.push(a) } else { out.neg.push(a) }
            }
            Gd::Equal(x, y, _) => {
                let pair = (self.term(x), self.term(y));
                if positive { out.eq.push(pair) } else { out.neq.push(pair) }
            }
            Gd::Not(g, _) => self.condition(g, !positive, out),
            Gd::And(gs, span) => {
                if !positive && gs.len() > 1 {
                    self.unsupported(*span, "a negated conjunction (a disjunction)");
                }
                for g in gs {
                    self.condition(g, positive, out);
                }
            }
            Gd::Timed(_, g, _) => self.condition(g, positive, out),
            Gd::Compare(_, _, _, span) => out.numeric.push(*span),
            Gd::Or(_, span) | Gd::Imply(_, _, span) => self.unsupported(*span, "a disjunctive condition"),
            Gd::Forall(_, _, span) | Gd::Exists(_, _, span) => {
                self.unsupported(*span, "a quantified condition")
            }
            Gd::Preference(_, _, span) => self.unsupported(*span, "a preference"),
            Gd::Modal(_, _, _, span) => self.unsupported(*span, "a trajectory constraint"),
            Gd::Order(o) => self.unsupported(o.span, "an ordering constraint"),
            Gd::Sortof(_, _, span) => self.unsupported(*span, "a `sortof` constraint"),
        }
    }

    fn effect(&mut self, e: &Effect, add: &mut Vec<LAtom>, del: &mut Vec<LAtom>) {
        match e {
            Effect::Add(a) => add.push(self.atom(a)),
            Effect::Del(a, _) => del.push(self.atom(a)),
            Effect::And(es, _) => {
                for e in es {
                    self.effect(e, add, del);
                }
            }
            Effect::Timed(_, e, _) => self.effect(e, add, del),
            Effect::Forall(_, e, span) => {
                // Quantified variables are not parameters: they become free terms.
                self.unsupported(*span, "a universally quantified effect");
                self.effect(e, add, del);
            }
            Effect::When(_, e, span) => {
                // What it may add or delete still counts (conflicts, reachability).
                self.unsupported(*span, "a conditional effect");
                self.effect(e, add, del);
            }
            Effect::Numeric(_, _, _, span) => self.unsupported(*span, "a numeric effect"),
        }
    }
}

fn params(typed: &[Typed]) -> Vec<Param> {
    typed
        .iter()
        .map(|t| Param { name: t.name.key_str(), types: type_set(&t.ty), span: t.name.span })
        .collect()
}

fn duration(gd: Option<&Gd>) -> Duration {
    match gd {
        None => Duration::None,
        Some(Gd::Compare(CmpOp::Eq, l, r, _)) if matches!(**l, NumExpr::Duration(_)) => {
            Duration::Exact((**r).clone())
        }
        Some(Gd::Compare(CmpOp::Eq, l, r, _)) if matches!(**r, NumExpr::Duration(_)) => {
            Duration::Exact((**l).clone())
        }
        Some(Gd::And(gs, _)) if gs.len() == 1 => duration(gs.first()),
        Some(other) => Duration::Bounded(gd_span(other)),
    }
}

/// Leaves out of `pre` the conditions the operator's own start makes true:
/// an `over all` or `at end` condition on an atom its start adds (or, under
/// a `not`, deletes) needs nothing before the operator starts, and `Pre` is
/// what must hold for it to run (relaxed reachability, Definition 12).
fn drop_own_start_support(
    scope: &mut Scope,
    cond: Option<&Gd>,
    eff: Option<&Effect>,
    pre: &mut Conditions,
) -> Conditions {
    let mut dropped = Conditions::default();
    let (mut adds, mut dels) = (Vec::new(), Vec::new());
    if let Some(e) = eff {
        start_effects(scope, e, false, &mut adds, &mut dels);
    }
    if adds.is_empty() && dels.is_empty() {
        return dropped;
    }
    let mut at_start = Conditions::default();
    if let Some(g) = cond {
        start_conditions(scope, g, true, true, &mut at_start);
    }
    // A condition goes when some instance of the operator may make it true
    // at its start: an effect of the same predicate whose arguments can be
    // equal (`(p ?x1)` over all and `(p ?x0)` at start meet when `?x0` is
    // `?x1`). It stays when the start needs it too.
    let same = |a: &LAtom, b: &LAtom| a.pred == b.pred && a.args == b.args;
    let keep = |a: &LAtom, effs: &[LAtom], start: &[LAtom]| {
        !effs.iter().any(|x| may_meet(x, a)) || start.iter().any(|x| same(x, a))
    };
    let (pos, neg) = (std::mem::take(&mut pre.pos), std::mem::take(&mut pre.neg));
    for a in pos {
        if keep(&a, &adds, &at_start.pos) { pre.pos.push(a) } else { dropped.pos.push(a) }
    }
    for a in neg {
        if keep(&a, &dels, &at_start.neg) { pre.neg.push(a) } else { dropped.neg.push(a) }
    }
    dropped
}

/// Whether two atoms of an operator can be the same atom in some instance:
/// same predicate, and argument by argument two different constants never.
fn may_meet(a: &LAtom, b: &LAtom) -> bool {
    a.pred == b.pred
        && a.args.len() == b.args.len()
        && a.args.iter().zip(&b.args).all(|(x, y)| match (x, y) {
            (LTerm::Const(c), LTerm::Const(d)) => c == d,
            _ => true,
        })
}

/// The atoms an effect adds and deletes `at start`.
fn start_effects(
    scope: &mut Scope,
    e: &Effect,
    at_start: bool,
    adds: &mut Vec<LAtom>,
    dels: &mut Vec<LAtom>,
) {
    match e {
        Effect::And(es, _) => es.iter().for_each(|e| start_effects(scope, e, at_start, adds, dels)),
        Effect::Timed(spec, e, _) => start_effects(scope, e, *spec == TimeSpec::AtStart, adds, dels),
        Effect::Add(a) if at_start => adds.push(scope.atom(a)),
        Effect::Del(a, _) if at_start => dels.push(scope.atom(a)),
        _ => {}
    }
}

/// The conditions needed at the start (untimed ones count as such).
fn start_conditions(scope: &mut Scope, gd: &Gd, at_start: bool, positive: bool, out: &mut Conditions) {
    match gd {
        Gd::And(gs, _) if positive => gs.iter().for_each(|g| start_conditions(scope, g, at_start, true, out)),
        Gd::Timed(spec, g, _) => start_conditions(scope, g, *spec == TimeSpec::AtStart, positive, out),
        Gd::Not(g, _) => start_conditions(scope, g, at_start, !positive, out),
        Gd::Atom(a) if at_start => {
            let a = scope.atom(a);
            if positive { out.pos.push(a) } else { out.neg.push(a) }
        }
        _ => {}
    }
}

fn action_operator(a: &Action) -> Operator {
    let params = params(&a.params);
    let mut scope = Scope { params: &params, unsupported: Vec::new() };
    let mut pre = Conditions::default();
    if let Some(gd) = &a.precondition {
        scope.condition(gd, true, &mut pre);
    }
    let (mut add, mut del) = (Vec::new(), Vec::new());
    if let Some(e) = &a.effect {
        scope.effect(e, &mut add, &mut del);
    }
    let mut own_start = Conditions::default();
    if a.kind != ActionKind::Action {
        let unsupported = scope.unsupported.len();
        own_start = drop_own_start_support(&mut scope, a.precondition.as_ref(), a.effect.as_ref(), &mut pre);
        scope.unsupported.truncate(unsupported);
    }
    let unsupported = scope.unsupported;
    Operator {
        kind: if a.kind == ActionKind::Action { OperatorKind::Action } else { OperatorKind::Durative },
        name: a.name.key_str(),
        name_span: a.name.span,
        duration: duration(a.duration.as_ref()),
        params,
        pre,
        own_start,
        add,
        del,
        conflicts: None,
        unsupported,
    }
}

fn task_operator(t: &Task) -> Operator {
    let params = params(&t.params);
    let mut scope = Scope { params: &params, unsupported: Vec::new() };
    let mut pre = Conditions::default();
    if let Some(gd) = &t.precondition {
        scope.condition(gd, true, &mut pre);
    }
    let (mut add, mut del) = (Vec::new(), Vec::new());
    if let Some(e) = &t.effect {
        scope.effect(e, &mut add, &mut del);
    }
    let unsupported = scope.unsupported.len();
    let own_start = drop_own_start_support(&mut scope, t.precondition.as_ref(), t.effect.as_ref(), &mut pre);
    scope.unsupported.truncate(unsupported);
    let conflicts = t.conflicts.as_ref().map(|c| LConflicts {
        atoms: c.atoms.iter().map(|a| scope.atom(a)).collect(),
        keyword: c.keyword,
        span: c.span,
        form: c.form.clone(),
    });
    let unsupported = scope.unsupported;
    Operator {
        kind: OperatorKind::Task,
        name: t.name.key_str(),
        name_span: t.name.span,
        duration: duration(t.duration.as_ref()),
        params,
        pre,
        own_start,
        add,
        del,
        conflicts,
        unsupported,
    }
}

fn method(m: &Method) -> MethodSchema {
    let params = params(&m.params);
    let mut scope = Scope { params: &params, unsupported: Vec::new() };
    let mut pre = Conditions::default();
    if let Some(gd) = &m.precondition {
        scope.condition(gd, true, &mut pre);
    }
    // HDDL's `:constraints` constrain the parameters ((in)equalities): the
    // instances that violate them are not instances of the method.
    if let Some(gd) = &m.network.constraints {
        scope.condition(gd, true, &mut pre);
    }
    let task =
        m.task.as_ref().map(|c| (c.name.key_str(), c.args.iter().map(|a| scope.term(a)).collect(), c.span));
    let subtasks = m
        .network
        .subtasks
        .iter()
        .map(|s| LSubtask {
            id: s.id.as_ref().map(|i| i.key_str()),
            name: s.call.name.key_str(),
            args: s.call.args.iter().map(|a| scope.term(a)).collect(),
            span: s.call.span,
        })
        .collect();
    let unsupported = scope.unsupported;
    MethodSchema { name: m.name.key_str(), name_span: m.name.span, params, task, pre, subtasks, unsupported }
}

#[cfg(test)]
pub(crate) mod tests_support {
    use super::*;
    use crate::AnalysisHost;

    /// The operators of a domain text, in order.
    pub(crate) fn operators(text: &str) -> Vec<Operator> {
        let mut host = AnalysisHost::new();
        let f = host.set_file_text("d.pddl", text);
        let db = host.db();
        let units = crate::db::file_units(db, f);
        units.iter().flat_map(|u| u.items(db).iter().filter_map(|&i| operator(db, i).clone())).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::tests_support::operators;
    use super::*;

    #[test]
    fn durative_action_is_flattened() {
        let ops = operators(
            "(define (domain d) (:predicates (at ?r ?w) (adj ?a ?b))
              (:durative-action move :parameters (?r ?a ?b) :duration (= ?duration 3)
               :condition (and (at start (at ?r ?a)) (over all (adj ?a ?b)) (over all (not (= ?a ?b))))
               :effect (and (at start (not (at ?r ?a))) (at end (at ?r ?b)))))",
        );
        let m = &ops[0];
        assert_eq!(m.kind, OperatorKind::Durative);
        assert_eq!(m.pre.pos.len(), 2);
        assert_eq!(m.pre.neq, vec![(LTerm::Param(1), LTerm::Param(2))]);
        assert_eq!(m.add[0].args.as_slice(), [LTerm::Param(0), LTerm::Param(2)]);
        assert_eq!(m.del[0].args.as_slice(), [LTerm::Param(0), LTerm::Param(1)]);
        assert!(matches!(m.duration, Duration::Exact(_)));
        assert!(m.unsupported.is_empty());
    }

    #[test]
    fn conflict_wildcards_are_free() {
        let ops = operators(
            "(define (domain d) (:predicates (at ?r ?w))
              (:task patrol :parameters (?r) :conflicts (and (at ?r ?w))))",
        );
        let conflicts = ops[0].conflicts.as_ref().expect("declared");
        assert_eq!(conflicts.atoms[0].args.as_slice(), [LTerm::Param(0), LTerm::Free("?w".into())]);
    }

    #[test]
    fn absent_and_empty_conflicts_differ() {
        let ops = operators(
            "(define (domain d) (:predicates (at ?r ?w))
              (:task plain :parameters (?r))
              (:task none :parameters (?r) :conflicts ()))",
        );
        assert_eq!(ops[0].conflicts, None);
        let none = ops[1].conflicts.as_ref().expect("declared, empty");
        assert!(none.atoms.is_empty());
        assert_eq!(none.form, ConflictsForm::Empty);
    }

    #[test]
    fn conflicts_form_says_where_atoms_go() {
        let text = "(define (domain d) (:predicates (at ?r ?w) (p))
              (:task one :parameters (?r) :conflicts (at ?r ?w))
              (:task both :parameters (?r) :conflicts (and (p) (at ?r ?w)) )
              (:task lines :parameters (?r) :conflicts (and
                  (p) ; a comment
                  (at ?r ?w)
                ))
              (:task nothing :parameters (?r) :conflicts (and)))";
        let ops = operators(text);
        let forms: Vec<&ConflictsForm> = ops.iter().map(|o| &o.conflicts.as_ref().unwrap().form).collect();
        assert_eq!(forms[0], &ConflictsForm::Atom);
        let ConflictsForm::And { at, sep } = forms[1] else { panic!("{:?}", forms[1]) };
        assert_eq!(&**sep, " ");
        let span = ops[1].conflicts.as_ref().unwrap().span;
        // Offsets are item-relative: check the text right before the insertion point.
        assert_eq!(u32::from(*at) - u32::from(span.start()), "(and (p) (at ?r ?w)".len() as u32);
        let ConflictsForm::And { sep, .. } = forms[2] else { panic!("{:?}", forms[2]) };
        assert_eq!(&**sep, "\n                  ");
        let ConflictsForm::And { at, sep } = forms[3] else { panic!("{:?}", forms[3]) };
        let span = ops[3].conflicts.as_ref().unwrap().span;
        assert_eq!((u32::from(*at) - u32::from(span.start()), &**sep), (4, " "));
    }

    #[test]
    fn unsupported_constructs_are_listed() {
        let ops = operators(
            "(define (domain d) (:predicates (p ?x) (q))
              (:action a :parameters () :precondition (or (q) (q))
               :effect (forall (?x) (when (q) (not (p ?x))))))",
        );
        let what: Vec<&str> = ops[0].unsupported.iter().map(|u| u.what).collect();
        assert_eq!(
            what,
            ["a disjunctive condition", "a universally quantified effect", "a conditional effect"]
        );
        assert_eq!(ops[0].del[0].args.as_slice(), [LTerm::Free("?x".into())]);
    }
}
