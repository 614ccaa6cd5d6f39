//! Ground states and what the model's formulas mean in them: conditions
//! ([`Gd`]) are true or false, numeric expressions ([`NumExpr`]) have values,
//! effects ([`Effect`]) are the changes they would make. Pure: nothing here
//! knows about plans or time, except which part of a durative action's
//! effects to collect ([`Phase`]).
//!
//! The semantics are PDDL 2.1's, as VAL implements them:
//! - closed world: an atom that was never added is false;
//! - a numeric fluent without a value is an error when read (VAL stops with
//!   "Attempt to access undefined expression"), not a false comparison;
//! - comparisons are exact (VAL compares doubles with `<`, `>=`, `==`);
//! - `forall` and `exists` range over the objects of the variable's types
//!   (subtypes included, the domain's constants too); `=` compares objects;
//! - effects are collected against the state before they apply: the
//!   conditions of conditional effects and the right-hand sides of numeric
//!   effects are evaluated in the state in which the happening starts.

use std::ops::ControlFlow;

use rowan::TextRange;

use crate::model::{Atom, CmpOp, Effect, Fluent, Gd, Name, NumExpr, Term, TimeSpec, Typed};
use crate::semantics::check::gd_span;
use crate::semantics::symbols::type_set;
use crate::verify::state::{AtomId, Atoms, InitialState, Interner, ObjId, Objects, initial_state};

/// A ground atom `[pred, args…]` or a ground fluent `[func, args…]`, before
/// it is interned: most have at most three arguments and stay inline.
pub(crate) type Key = smallvec::SmallVec<[u32; 4]>;

/// A ground numeric fluent, interned in [`State::fluents`].
pub(crate) type FluentId = u32;

/// The values of the variables in scope: an action's parameters, then
/// quantified variables. The innermost binding of a name wins.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Binding<'m> {
    vars: Vec<(&'m str, ObjId)>,
}

impl<'m> Binding<'m> {
    pub fn push(&mut self, var: &'m str, obj: ObjId) {
        self.vars.push((var, obj));
    }

    pub fn pop(&mut self) {
        self.vars.pop();
    }

    /// The value of a variable, by its lower-case key (`?x`).
    pub fn get(&self, var: &str) -> Option<ObjId> {
        self.vars.iter().rev().find(|(v, _)| *v == var).map(|&(_, o)| o)
    }
}

/// What does not change while a plan runs: objects and names.
pub(crate) struct World<'w, 'db> {
    pub objects: &'w Objects<'db>,
    pub preds: &'w Interner,
    pub funcs: &'w Interner,
}

impl World<'_, '_> {
    fn show(&self, names: &Interner, key: &[u32]) -> String {
        let mut s = String::from("(");
        s.push_str(key.first().map_or("?", |&p| names.name(p)));
        for &o in key.get(1..).unwrap_or(&[]) {
            s.push(' ');
            s.push_str(self.objects.name(o));
        }
        s.push(')');
        s
    }

    /// A ground atom as text: `(at r1 w5)`.
    pub fn show_atom(&self, key: &[u32]) -> String {
        self.show(self.preds, key)
    }

    /// A ground fluent as text: `(fuel plane1)`.
    pub fn show_fluent(&self, key: &[u32]) -> String {
        self.show(self.funcs, key)
    }
}

/// The ground vocabulary of a problem and its initial state, as both
/// validators start from: predicate and function names interned in sorted
/// order (hash maps have no order, so ids do not depend on hashing).
pub(crate) struct GroundWorld<'db> {
    pub preds: Interner,
    pub funcs: Interner,
    pub atoms: Atoms,
    pub init: InitialState<'db>,
}

impl<'db> GroundWorld<'db> {
    pub fn new(
        db: &'db dyn crate::db::Db,
        domain: crate::db::Unit<'db>,
        problem: crate::db::Unit<'db>,
        objects: &Objects<'db>,
    ) -> Self {
        let dom = crate::semantics::symbols::domain_symbols(db, domain);
        let sorted = |keys: &mut dyn Iterator<Item = &str>| {
            let mut names: Vec<&str> = keys.collect();
            names.sort_unstable();
            let mut interner = Interner::default();
            names.iter().for_each(|n| {
                interner.intern(n);
            });
            interner
        };
        let mut preds = sorted(&mut dom.predicates.keys().map(|k| k.as_str()));
        let mut funcs = sorted(&mut dom.functions.keys().map(|k| k.as_str()));
        let mut atoms = Atoms::default();
        let init = initial_state(db, problem, objects, &mut preds, &mut funcs, &mut atoms);
        GroundWorld { preds, funcs, atoms, init }
    }
}

/// A ground state: which atoms are true, the values of numeric fluents.
/// Atoms and fluents are interned as they are met.
#[derive(Debug, Clone, Default)]
pub(crate) struct State {
    pub atoms: Atoms,
    truth: Vec<bool>,
    pub fluents: Atoms,
    values: Vec<Option<f64>>,
}

impl State {
    pub fn new(atoms: Atoms, fluents: Atoms) -> State {
        let (na, nf) = (atoms.len(), fluents.len());
        State { atoms, truth: vec![false; na], fluents, values: vec![None; nf] }
    }

    pub fn is_true(&self, atom: AtomId) -> bool {
        self.truth.get(atom as usize).copied().unwrap_or(false)
    }

    pub fn set(&mut self, atom: AtomId, value: bool) {
        let i = atom as usize;
        if i >= self.truth.len() {
            self.truth.resize(i + 1, false);
        }
        self.truth[i] = value;
    }

    pub fn value(&self, fluent: FluentId) -> Option<f64> {
        self.values.get(fluent as usize).copied().flatten()
    }

    pub fn set_value(&mut self, fluent: FluentId, value: Option<f64>) {
        let i = fluent as usize;
        if i >= self.values.len() {
            self.values.resize(i + 1, None);
        }
        self.values[i] = value;
    }

    /// The id of a ground atom, interned if new.
    pub fn atom(&mut self, key: &[u32]) -> AtomId {
        self.atoms.intern(key)
    }

    /// The id of a ground fluent, interned if new.
    pub fn fluent(&mut self, key: &[u32]) -> FluentId {
        self.fluents.intern(key)
    }

    /// Whether the ground atom holds.
    pub fn holds(&self, key: &[u32]) -> bool {
        self.atoms.get(key).is_some_and(|a| self.is_true(a))
    }

    /// The value of the ground fluent, if it has one.
    pub fn value_of(&self, key: &[u32]) -> Option<f64> {
        self.fluents.get(key).and_then(|f| self.value(f))
    }
}

/// Why a formula cannot be evaluated.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct EvalError {
    pub kind: ErrorKind,
    pub message: String,
    /// Where in the formula's item.
    pub span: TextRange,
    /// The fluent without a value, for [`ErrorKind::Undefined`].
    pub fluent: Option<Key>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ErrorKind {
    /// A fluent without a value.
    Undefined,
    /// A division by zero, or a value that is not a finite number.
    Arithmetic,
    /// A construct the validator does not evaluate (object fluents,
    /// continuous change, PDDL 3 preferences and constraints).
    Unsupported,
    /// A name that does not resolve (the model's checks report it).
    Unresolved,
}

impl EvalError {
    fn new(kind: ErrorKind, span: TextRange, message: impl Into<String>) -> EvalError {
        EvalError { kind, message: message.into(), span, fluent: None }
    }
}

pub(crate) type Res<T> = Result<T, EvalError>;

/// A numeric effect's operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum NumOp {
    Assign,
    Increase,
    Decrease,
    ScaleUp,
    ScaleDown,
}

impl NumOp {
    pub fn parse(s: &str) -> Option<NumOp> {
        Some(match s {
            "assign" => NumOp::Assign,
            "increase" => NumOp::Increase,
            "decrease" => NumOp::Decrease,
            "scale-up" => NumOp::ScaleUp,
            "scale-down" => NumOp::ScaleDown,
            _ => return None,
        })
    }

    /// Additive updates commute with each other: VAL lets simultaneous
    /// steps increase and decrease the same fluent, nothing else.
    pub fn is_additive(self) -> bool {
        matches!(self, NumOp::Increase | NumOp::Decrease)
    }

    pub fn name(self) -> &'static str {
        match self {
            NumOp::Assign => "assign",
            NumOp::Increase => "increase",
            NumOp::Decrease => "decrease",
            NumOp::ScaleUp => "scale-up",
            NumOp::ScaleDown => "scale-down",
        }
    }

    /// The new value; `None` when the old value is needed but missing, or
    /// when the result is not a finite number (a scale-down by zero).
    pub fn apply(self, old: Option<f64>, v: f64) -> Option<f64> {
        let new = match self {
            NumOp::Assign => v,
            NumOp::Increase => old? + v,
            NumOp::Decrease => old? - v,
            NumOp::ScaleUp => old? * v,
            NumOp::ScaleDown => old? / v,
        };
        new.is_finite().then_some(new)
    }
}

/// The atoms and fluents something reads: conditions, durations, the
/// right-hand sides of numeric effects. Two simultaneous steps interfere
/// when one changes what the other reads.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Reads {
    pub atoms: Vec<Key>,
    pub fluents: Vec<Key>,
}

/// A numeric effect, evaluated.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Update {
    pub fluent: Key,
    pub op: NumOp,
    pub value: f64,
    pub span: TextRange,
}

/// The changes that effects make, with the effect in its item, and what
/// they read (the conditions of the conditional effects that fire, the
/// right-hand sides of numeric effects).
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Changes {
    pub adds: Vec<(Key, TextRange)>,
    pub dels: Vec<(Key, TextRange)>,
    pub updates: Vec<Update>,
    pub reads: Reads,
}

/// Which effects of an action to collect.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Phase {
    /// An `:action`: its effects, none of them timed.
    Instant,
    /// The `at start` effects of a durative action.
    Start,
    /// The `at end` effects of a durative action.
    End,
}

/// A conditional effect of a durative action whose condition spans the
/// action, `(when (and (at start c) (over all i) (at end e)) (at end …))`:
/// the `at start` part is evaluated at the start, the `over all` part while
/// the action runs, and the `at end` effects apply only if both held and the
/// `at end` part holds (VAL's semantics; it never makes a plan invalid).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Spanning<'m> {
    /// The `when` in the action's item.
    pub span: TextRange,
    /// The parameters and the values of the enclosing `forall` variables.
    pub binding: Binding<'m>,
    pub invariant: Vec<&'m Gd>,
    /// The start condition held, and the invariant has held so far.
    pub alive: bool,
}

/// The conditions of a durative action, or of one of its conditional
/// effects, by time.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct TimedParts<'m> {
    pub start: Vec<&'m Gd>,
    pub over_all: Vec<&'m Gd>,
    pub end: Vec<&'m Gd>,
    /// Conditions without `at start`, `over all` or `at end`.
    pub untimed: Vec<&'m Gd>,
}

/// Splits a conjunction of timed conditions by time.
pub(crate) fn split_timed(g: &Gd) -> TimedParts<'_> {
    fn walk<'m>(g: &'m Gd, out: &mut TimedParts<'m>) {
        match g {
            Gd::And(gs, _) => gs.iter().for_each(|x| walk(x, out)),
            Gd::Timed(TimeSpec::AtStart, x, _) => out.start.push(x),
            Gd::Timed(TimeSpec::OverAll, x, _) => out.over_all.push(x),
            Gd::Timed(TimeSpec::AtEnd, x, _) => out.end.push(x),
            other => out.untimed.push(other),
        }
    }
    let mut out = TimedParts::default();
    walk(g, &mut out);
    out
}

/// Whether an effect has parts at the given time (`at start` or `at end`).
pub(crate) fn has_timed(e: &Effect, spec: TimeSpec) -> bool {
    match e {
        Effect::Timed(s, _, _) => *s == spec,
        Effect::And(es, _) => es.iter().any(|x| has_timed(x, spec)),
        Effect::Forall(_, body, _) | Effect::When(_, body, _) => has_timed(body, spec),
        Effect::Add(_) | Effect::Del(..) | Effect::Numeric(..) => false,
    }
}

/// Calls `f` with each binding of `vars` to objects of their types, in
/// order, until it breaks.
pub(crate) fn for_each_binding<'m>(
    objects: &Objects<'_>,
    vars: &'m [Typed],
    b: &mut Binding<'m>,
    f: &mut dyn FnMut(&mut Binding<'m>) -> Res<ControlFlow<()>>,
) -> Res<ControlFlow<()>> {
    let Some((first, rest)) = vars.split_first() else { return f(b) };
    for o in objects.of_types(&type_set(&first.ty)) {
        b.push(&first.name.key, o);
        let flow = for_each_binding(objects, rest, b, f);
        b.pop();
        if flow? == ControlFlow::Break(()) {
            return Ok(ControlFlow::Break(()));
        }
    }
    Ok(ControlFlow::Continue(()))
}

/// A reason why a condition is false: a literal, a comparison, a quantifier.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Why {
    /// "`(at r1 w5)` is false", "`(>= (fuel p1) 30)` is false (12.0 >= 30.0 fails)".
    pub text: String,
    /// The sub-formula, in the condition's item.
    pub span: TextRange,
    /// The ground atom whose truth value is wrong, and the value the condition needs.
    pub literal: Option<(Key, bool)>,
    /// The fluents a failed comparison reads.
    pub fluents: Vec<Key>,
}

/// Formulas evaluated in a state.
pub(crate) struct Eval<'e, 'w, 'db> {
    pub world: &'e World<'w, 'db>,
    pub state: &'e State,
    /// The value of `?duration`, inside a durative action.
    pub duration: Option<f64>,
    /// The value of `total-time`, in the metric.
    pub total_time: Option<f64>,
}

impl<'m> Eval<'_, '_, '_> {
    pub fn term(&self, t: &Term, b: &Binding<'m>) -> Res<ObjId> {
        match t {
            Term::Var(n) => b.get(&n.key).ok_or_else(|| {
                EvalError::new(ErrorKind::Unresolved, n.span, format!("`{}` is not bound", n.text))
            }),
            Term::Const(n) => self.world.objects.id(&n.key).ok_or_else(|| {
                EvalError::new(ErrorKind::Unresolved, n.span, format!("`{}` is not an object", n.text))
            }),
            Term::Func(f) => Err(EvalError::new(
                ErrorKind::Unsupported,
                f.span,
                format!("object fluents (`({} …)` as a term) are not supported", f.func.text),
            )),
        }
    }

    fn key(&self, names: &Interner, what: &str, name: &Name, args: &[Term], b: &Binding<'m>) -> Res<Key> {
        let id = names.get(&name.key).ok_or_else(|| {
            EvalError::new(
                ErrorKind::Unresolved,
                name.span,
                format!("`{}` is not a declared {what}", name.text),
            )
        })?;
        let mut key = Key::with_capacity(args.len() + 1);
        key.push(id);
        for t in args {
            key.push(self.term(t, b)?);
        }
        Ok(key)
    }

    pub fn atom_key(&self, a: &Atom, b: &Binding<'m>) -> Res<Key> {
        self.key(self.world.preds, "predicate", &a.pred, &a.args, b)
    }

    pub fn fluent_key(&self, f: &Fluent, b: &Binding<'m>) -> Res<Key> {
        self.key(self.world.funcs, "function", &f.func, &f.args, b)
    }

    /// Whether a condition holds.
    pub fn holds(&self, g: &'m Gd, b: &mut Binding<'m>) -> Res<bool> {
        Ok(match g {
            Gd::Atom(a) => self.state.holds(&self.atom_key(a, b)?),
            Gd::Equal(x, y, _) => self.term(x, b)? == self.term(y, b)?,
            Gd::Compare(op, l, r, _) => compare(*op, self.num(l, b)?, self.num(r, b)?),
            Gd::Not(x, _) => !self.holds(x, b)?,
            Gd::And(xs, _) => {
                for x in xs {
                    if !self.holds(x, b)? {
                        return Ok(false);
                    }
                }
                true
            }
            Gd::Or(xs, _) => {
                for x in xs {
                    if self.holds(x, b)? {
                        return Ok(true);
                    }
                }
                false
            }
            Gd::Imply(x, y, _) => !self.holds(x, b)? || self.holds(y, b)?,
            Gd::Forall(vars, body, _) => {
                let flow = for_each_binding(self.world.objects, vars, b, &mut |b| {
                    Ok(if self.holds(body, b)? { ControlFlow::Continue(()) } else { ControlFlow::Break(()) })
                })?;
                flow == ControlFlow::Continue(())
            }
            Gd::Exists(vars, body, _) => {
                let flow = for_each_binding(self.world.objects, vars, b, &mut |b| {
                    Ok(if self.holds(body, b)? { ControlFlow::Break(()) } else { ControlFlow::Continue(()) })
                })?;
                flow == ControlFlow::Break(())
            }
            Gd::Sortof(t, ty, _) => {
                let o = self.term(t, b)?;
                type_set(ty).iter().any(|t| self.world.objects.has_type(o, t))
            }
            Gd::Timed(_, _, span) => {
                return Err(EvalError::new(
                    ErrorKind::Unsupported,
                    *span,
                    "a timed condition (`at start`, `over all`, `at end`) nested inside another condition",
                ));
            }
            Gd::Preference(_, _, span) => {
                return Err(EvalError::new(
                    ErrorKind::Unsupported,
                    *span,
                    "PDDL 3 preferences are not supported",
                ));
            }
            Gd::Modal(name, _, _, span) => {
                return Err(EvalError::new(
                    ErrorKind::Unsupported,
                    *span,
                    format!("the constraint `{name}` is not supported in plan validation"),
                ));
            }
            Gd::Order(o) => {
                return Err(EvalError::new(
                    ErrorKind::Unsupported,
                    o.span,
                    "an ordering of subtasks is not a condition on a state",
                ));
            }
        })
    }

    /// The value of a numeric expression.
    pub fn num(&self, e: &'m NumExpr, b: &Binding<'m>) -> Res<f64> {
        match e {
            NumExpr::Number(n) => {
                let v = n.value();
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(EvalError::new(
                        ErrorKind::Arithmetic,
                        n.span,
                        format!("`{}` is not a number", n.text),
                    ))
                }
            }
            NumExpr::Fluent(f) => {
                let key = self.fluent_key(f, b)?;
                self.state.value_of(&key).ok_or_else(|| EvalError {
                    kind: ErrorKind::Undefined,
                    message: format!("`{}` has no value", self.world.show_fluent(&key)),
                    span: f.span,
                    fluent: Some(key),
                })
            }
            NumExpr::Op(op, args, span) => {
                let mut vals = Vec::with_capacity(args.len());
                for a in args {
                    vals.push(self.num(a, b)?);
                }
                let arithmetic = |m: String| EvalError::new(ErrorKind::Arithmetic, *span, m);
                let Some((first, rest)) = vals.split_first() else {
                    return Err(arithmetic("an operation without operands".into()));
                };
                let v = match (&**op, rest) {
                    ("-", []) => -first,
                    ("+", _) => rest.iter().fold(*first, |a, x| a + x),
                    ("-", _) => rest.iter().fold(*first, |a, x| a - x),
                    ("*", _) => rest.iter().fold(*first, |a, x| a * x),
                    ("/", _) if rest.contains(&0.0) => {
                        return Err(arithmetic(format!("division by zero in `{}`", self.show_expr(e, b))));
                    }
                    ("/", _) => rest.iter().fold(*first, |a, x| a / x),
                    _ => return Err(arithmetic(format!("`{op}` is not an arithmetic operation"))),
                };
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(arithmetic(format!("`{}` is not a finite number", self.show_expr(e, b))))
                }
            }
            NumExpr::Duration(span) => self.duration.ok_or_else(|| {
                EvalError::new(
                    ErrorKind::Unresolved,
                    *span,
                    "`?duration` has no value outside a durative action",
                )
            }),
            NumExpr::Special(s, span) if &**s == "total-time" => self.total_time.ok_or_else(|| {
                EvalError::new(
                    ErrorKind::Unsupported,
                    *span,
                    "`total-time` has no value before the plan ends",
                )
            }),
            NumExpr::Special(s, span) if &**s == "#t" => Err(EvalError::new(
                ErrorKind::Unsupported,
                *span,
                "continuous change (`#t`) is not supported in plan validation",
            )),
            NumExpr::Special(s, span) => {
                Err(EvalError::new(ErrorKind::Unsupported, *span, format!("`{s}` has no numeric value")))
            }
            NumExpr::TaskDuration(_, span) => Err(EvalError::new(
                ErrorKind::Unsupported,
                *span,
                "a subtask's duration has no value in a temporal plan",
            )),
            NumExpr::Var(n) => Err(EvalError::new(
                ErrorKind::Unsupported,
                n.span,
                format!("`{}` is an object, not a number", n.text),
            )),
        }
    }

    /// Why a condition that should hold is false (with `negated`: why a
    /// condition that should be false holds): the literals, comparisons and
    /// quantifiers responsible. Empty when the condition is as it should be.
    pub fn why_false(&self, g: &'m Gd, b: &mut Binding<'m>, negated: bool) -> Res<Vec<Why>> {
        if self.holds(g, b)? != negated {
            return Ok(Vec::new());
        }
        let is = if negated { "true" } else { "false" };
        Ok(match g {
            Gd::Atom(a) => {
                let key = self.atom_key(a, b)?;
                let text = format!("`{}` is {is}", self.world.show_atom(&key));
                vec![Why { text, span: a.span, literal: Some((key, !negated)), fluents: Vec::new() }]
            }
            Gd::Not(x, _) => self.why_false(x, b, !negated)?,
            // A false conjunction: its false parts; a true disjunction that
            // should be false: its true parts. And the reverse: every part.
            Gd::And(xs, _) | Gd::Or(xs, _) => {
                let mut out = Vec::new();
                for x in xs {
                    out.extend(self.why_false(x, b, negated)?);
                }
                out
            }
            Gd::Imply(_, y, _) if !negated => self.why_false(y, b, false)?,
            Gd::Forall(vars, body, _) if !negated => self.first_instance(g, vars, body, b, false)?,
            Gd::Exists(vars, body, _) if negated => self.first_instance(g, vars, body, b, true)?,
            Gd::Compare(op, l, r, span) => {
                let (lv, rv) = (self.num(l, b)?, self.num(r, b)?);
                let mut fluents = Vec::new();
                self.expr_fluents(l, b, &mut fluents);
                self.expr_fluents(r, b, &mut fluents);
                let text = format!(
                    "`{}` is {is} ({} {} {} {})",
                    self.show_gd(g, b),
                    fmt_num(lv),
                    op_text(*op),
                    fmt_num(rv),
                    if negated { "holds" } else { "fails" }
                );
                vec![Why { text, span: *span, literal: None, fluents }]
            }
            Gd::Timed(_, x, _) | Gd::Preference(_, x, _) => self.why_false(x, b, negated)?,
            _ => vec![Why {
                text: format!("`{}` is {is}", self.show_gd(g, b)),
                span: gd_span(g),
                literal: None,
                fluents: Vec::new(),
            }],
        })
    }

    /// The reasons of the first instance of a quantifier's body that is
    /// false (with `negated`: true), followed by the instance's values.
    fn first_instance(
        &self,
        g: &'m Gd,
        vars: &'m [Typed],
        body: &'m Gd,
        b: &mut Binding<'m>,
        negated: bool,
    ) -> Res<Vec<Why>> {
        let mut found = Vec::new();
        let _ = for_each_binding(self.world.objects, vars, b, &mut |b| {
            let why = self.why_false(body, b, negated)?;
            if why.is_empty() {
                return Ok(ControlFlow::Continue(()));
            }
            let values: Vec<String> = vars
                .iter()
                .map(|v| {
                    let o = b.get(&v.name.key).map_or("?", |o| self.world.objects.name(o));
                    format!("{} = {o}", v.name.text)
                })
                .collect();
            found = why
                .into_iter()
                .map(|mut w| {
                    w.text = format!("{} (for {})", w.text, values.join(", "));
                    w
                })
                .collect();
            Ok(ControlFlow::Break(()))
        })?;
        if found.is_empty() {
            found.push(Why {
                text: format!("`{}` is {}", self.show_gd(g, b), if negated { "true" } else { "false" }),
                span: gd_span(g),
                literal: None,
                fluents: Vec::new(),
            });
        }
        Ok(found)
    }

    /// The ground fluents an expression reads (those that resolve), once each.
    pub fn expr_fluents(&self, e: &'m NumExpr, b: &Binding<'m>, out: &mut Vec<Key>) {
        match e {
            NumExpr::Fluent(f) => {
                if let Ok(k) = self.fluent_key(f, b)
                    && !out.contains(&k)
                {
                    out.push(k);
                }
            }
            NumExpr::Op(_, args, _) => args.iter().for_each(|a| self.expr_fluents(a, b, out)),
            _ => {}
        }
    }

    /// What a condition reads: every atom and fluent it mentions, over every
    /// instance of its quantifiers (VAL marks all of them, whichever decide
    /// the truth value).
    pub fn reads(&self, g: &'m Gd, b: &mut Binding<'m>, out: &mut Reads) -> Res<()> {
        match g {
            Gd::Atom(a) => out.atoms.push(self.atom_key(a, b)?),
            Gd::Compare(_, l, r, _) => {
                self.expr_fluents(l, b, &mut out.fluents);
                self.expr_fluents(r, b, &mut out.fluents);
            }
            Gd::Not(x, _) | Gd::Timed(_, x, _) | Gd::Preference(_, x, _) => self.reads(x, b, out)?,
            Gd::And(xs, _) | Gd::Or(xs, _) => {
                for x in xs {
                    self.reads(x, b, out)?;
                }
            }
            Gd::Imply(x, y, _) => {
                self.reads(x, b, out)?;
                self.reads(y, b, out)?;
            }
            Gd::Forall(vars, body, _) | Gd::Exists(vars, body, _) => {
                let _ = for_each_binding(self.world.objects, vars, b, &mut |b| {
                    self.reads(body, b, out)?;
                    Ok(ControlFlow::Continue(()))
                })?;
            }
            Gd::Equal(..) | Gd::Sortof(..) | Gd::Modal(..) | Gd::Order(_) => {}
        }
        Ok(())
    }

    /// Collects the changes an effect makes in a phase. `spanning` holds the
    /// conditional effects whose condition spans a durative action: they are
    /// added at its start and read at its end.
    pub fn effects(
        &self,
        e: &'m Effect,
        b: &mut Binding<'m>,
        phase: Phase,
        spanning: &mut Vec<Spanning<'m>>,
        out: &mut Changes,
    ) -> Res<()> {
        self.effects_in(e, b, phase, phase == Phase::Instant, spanning, out)
    }

    /// `timed`: inside an `at start`/`at end` of the phase (or an instantaneous action).
    fn effects_in(
        &self,
        e: &'m Effect,
        b: &mut Binding<'m>,
        phase: Phase,
        timed: bool,
        spanning: &mut Vec<Spanning<'m>>,
        out: &mut Changes,
    ) -> Res<()> {
        let untimed = |span| {
            EvalError::new(
                ErrorKind::Unsupported,
                span,
                "an effect of a durative action without `at start` or `at end`",
            )
        };
        match e {
            Effect::And(es, _) => {
                for x in es {
                    self.effects_in(x, b, phase, timed, spanning, out)?;
                }
            }
            Effect::Timed(spec, x, span) => match (phase, spec) {
                (Phase::Instant, _) => {
                    return Err(EvalError::new(
                        ErrorKind::Unsupported,
                        *span,
                        "a timed effect in an instantaneous action",
                    ));
                }
                (_, TimeSpec::OverAll) => {
                    return Err(EvalError::new(
                        ErrorKind::Unsupported,
                        *span,
                        "an `over all` effect (continuous change) is not supported",
                    ));
                }
                (Phase::Start, TimeSpec::AtStart) | (Phase::End, TimeSpec::AtEnd) => {
                    self.effects_in(x, b, phase, true, spanning, out)?;
                }
                _ => {}
            },
            Effect::Forall(vars, body, _) => {
                let _ = for_each_binding(self.world.objects, vars, b, &mut |b| {
                    self.effects_in(body, b, phase, timed, spanning, out)?;
                    Ok(ControlFlow::Continue(()))
                })?;
            }
            Effect::When(cond, body, span) => {
                self.when(cond, body, *span, b, (phase, timed), spanning, out)?;
            }
            Effect::Add(a) => {
                if !timed {
                    return Err(untimed(a.span));
                }
                out.adds.push((self.atom_key(a, b)?, a.span));
            }
            Effect::Del(a, span) => {
                if !timed {
                    return Err(untimed(*span));
                }
                out.dels.push((self.atom_key(a, b)?, *span));
            }
            Effect::Numeric(op, f, v, span) => {
                if !timed {
                    return Err(untimed(*span));
                }
                let Some(op) = NumOp::parse(op) else {
                    return Err(EvalError::new(
                        ErrorKind::Unsupported,
                        *span,
                        format!("`{op}` is not a numeric effect"),
                    ));
                };
                if matches!(v, NumExpr::Special(s, _) if &**s == "undefined") {
                    return Err(EvalError::new(
                        ErrorKind::Unsupported,
                        *span,
                        "assigning `undefined` to a fluent is not supported",
                    ));
                }
                let fluent = self.fluent_key(f, b)?;
                let value = self.num(v, b)?;
                self.expr_fluents(v, b, &mut out.reads.fluents);
                out.updates.push(Update { fluent, op, value, span: *span });
            }
        }
        Ok(())
    }

    /// A conditional effect. In an instantaneous action, or inside an
    /// `at start`/`at end` (`timed`), an ordinary one; directly in a durative
    /// action, its condition and effects are split by time as VAL does.
    #[allow(clippy::too_many_arguments)]
    fn when(
        &self,
        cond: &'m Gd,
        body: &'m Effect,
        span: TextRange,
        b: &mut Binding<'m>,
        (phase, timed): (Phase, bool),
        spanning: &mut Vec<Spanning<'m>>,
        out: &mut Changes,
    ) -> Res<()> {
        // Whether conditions hold; if so, they count as read.
        let fire = |b: &mut Binding<'m>, conds: &[&'m Gd], out: &mut Changes| -> Res<bool> {
            for c in conds {
                if !self.holds(c, b)? {
                    return Ok(false);
                }
            }
            for c in conds {
                self.reads(c, b, &mut out.reads)?;
            }
            Ok(true)
        };
        if phase == Phase::Instant || timed {
            if fire(b, &[cond], out)? {
                self.effects_in(body, b, phase, timed, spanning, out)?;
            }
            return Ok(());
        }
        let parts = split_timed(cond);
        if let Some(u) = parts.untimed.first() {
            return Err(EvalError::new(
                ErrorKind::Unsupported,
                gd_span(u),
                "a condition of a durative action's conditional effect without `at start`, `over all` or `at end`",
            ));
        }
        let spans_action = !parts.start.is_empty() || !parts.over_all.is_empty();
        match phase {
            Phase::Start => {
                if has_timed(body, TimeSpec::AtStart) {
                    if !parts.over_all.is_empty() || !parts.end.is_empty() {
                        return Err(EvalError::new(
                            ErrorKind::Unsupported,
                            span,
                            "an `at start` effect that depends on `over all` or `at end` conditions",
                        ));
                    }
                    if fire(b, &parts.start, out)? {
                        self.effects_in(body, b, phase, false, spanning, out)?;
                    }
                }
                if has_timed(body, TimeSpec::AtEnd) && spans_action {
                    let alive = fire(b, &parts.start, out)?;
                    spanning.push(Spanning { span, binding: b.clone(), invariant: parts.over_all, alive });
                }
            }
            Phase::End => {
                if !has_timed(body, TimeSpec::AtEnd) {
                    return Ok(());
                }
                if spans_action && !spanning.iter().any(|s| s.span == span && s.binding == *b && s.alive) {
                    return Ok(());
                }
                if fire(b, &parts.end, out)? {
                    self.effects_in(body, b, phase, false, spanning, out)?;
                }
            }
            Phase::Instant => {}
        }
        Ok(())
    }

    /// A condition with its variables replaced by their values.
    pub fn show_gd(&self, g: &Gd, b: &Binding<'m>) -> String {
        let mut s = String::new();
        self.write_gd(g, b, &mut s);
        s
    }

    /// A numeric expression with its variables replaced by their values.
    pub fn show_expr(&self, e: &NumExpr, b: &Binding<'m>) -> String {
        let mut s = String::new();
        self.write_expr(e, b, &mut s);
        s
    }

    fn write_term(&self, t: &Term, b: &Binding<'m>, s: &mut String) {
        match t {
            Term::Var(n) => match b.get(&n.key) {
                Some(o) => s.push_str(self.world.objects.name(o)),
                None => s.push_str(&n.text),
            },
            Term::Const(n) => s.push_str(&n.key),
            Term::Func(f) => self.write_app(&f.func.key, &f.args, b, s),
        }
    }

    fn write_app(&self, head: &str, args: &[Term], b: &Binding<'m>, s: &mut String) {
        s.push('(');
        s.push_str(head);
        for t in args {
            s.push(' ');
            self.write_term(t, b, s);
        }
        s.push(')');
    }

    fn write_expr(&self, e: &NumExpr, b: &Binding<'m>, s: &mut String) {
        match e {
            NumExpr::Number(n) => s.push_str(&n.text),
            NumExpr::Fluent(f) => self.write_app(&f.func.key, &f.args, b, s),
            NumExpr::Op(op, args, _) => {
                s.push('(');
                s.push_str(op);
                for a in args {
                    s.push(' ');
                    self.write_expr(a, b, s);
                }
                s.push(')');
            }
            NumExpr::Duration(_) => s.push_str("?duration"),
            NumExpr::TaskDuration(id, _) => {
                s.push_str("(duration ");
                s.push_str(&id.text);
                s.push(')');
            }
            NumExpr::Special(x, _) => s.push_str(x),
            NumExpr::Var(n) => s.push_str(&n.text),
        }
    }

    fn write_gd(&self, g: &Gd, b: &Binding<'m>, s: &mut String) {
        let list = |head: &str, xs: &[Gd], s: &mut String| {
            s.push('(');
            s.push_str(head);
            for x in xs {
                s.push(' ');
                self.write_gd(x, b, s);
            }
            s.push(')');
        };
        match g {
            Gd::Atom(a) => self.write_app(&a.pred.key, &a.args, b, s),
            Gd::Equal(x, y, _) => {
                s.push_str("(= ");
                self.write_term(x, b, s);
                s.push(' ');
                self.write_term(y, b, s);
                s.push(')');
            }
            Gd::Compare(op, l, r, _) => {
                s.push('(');
                s.push_str(op_text(*op));
                s.push(' ');
                self.write_expr(l, b, s);
                s.push(' ');
                self.write_expr(r, b, s);
                s.push(')');
            }
            Gd::Not(x, _) => {
                s.push_str("(not ");
                self.write_gd(x, b, s);
                s.push(')');
            }
            Gd::And(xs, _) => list("and", xs, s),
            Gd::Or(xs, _) => list("or", xs, s),
            Gd::Imply(x, y, _) => {
                s.push_str("(imply ");
                self.write_gd(x, b, s);
                s.push(' ');
                self.write_gd(y, b, s);
                s.push(')');
            }
            Gd::Forall(vars, body, _) | Gd::Exists(vars, body, _) => {
                s.push_str(if matches!(g, Gd::Forall(..)) { "(forall (" } else { "(exists (" });
                for (i, v) in vars.iter().enumerate() {
                    if i > 0 {
                        s.push(' ');
                    }
                    s.push_str(&v.name.text);
                    let types = type_set(&v.ty);
                    if types.as_slice() != ["object"] {
                        s.push_str(" - ");
                        s.push_str(&types.join(" "));
                    }
                }
                s.push_str(") ");
                self.write_gd(body, b, s);
                s.push(')');
            }
            Gd::Timed(spec, x, _) => {
                s.push_str(match spec {
                    TimeSpec::AtStart => "(at start ",
                    TimeSpec::AtEnd => "(at end ",
                    TimeSpec::OverAll => "(over all ",
                });
                self.write_gd(x, b, s);
                s.push(')');
            }
            Gd::Preference(_, x, _) => {
                s.push_str("(preference ");
                self.write_gd(x, b, s);
                s.push(')');
            }
            Gd::Modal(name, xs, _, _) => list(name, xs, s),
            Gd::Order(_) => s.push_str("(ordering)"),
            Gd::Sortof(t, ty, _) => {
                s.push_str("(sortof ");
                self.write_term(t, b, s);
                s.push_str(" - ");
                s.push_str(&type_set(ty).join(" "));
                s.push(')');
            }
        }
    }
}

pub(crate) fn compare(op: CmpOp, l: f64, r: f64) -> bool {
    match op {
        CmpOp::Lt => l < r,
        CmpOp::Le => l <= r,
        CmpOp::Eq => l == r,
        CmpOp::Ge => l >= r,
        CmpOp::Gt => l > r,
    }
}

pub(crate) fn op_text(op: CmpOp) -> &'static str {
    match op {
        CmpOp::Lt => "<",
        CmpOp::Le => "<=",
        CmpOp::Eq => "=",
        CmpOp::Ge => ">=",
        CmpOp::Gt => ">",
    }
}

/// A number for messages: rounded to six decimals, `130.0` rather than
/// `130` (times and values, not counts).
pub(crate) fn fmt_num(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    if r.fract() == 0.0 && r.abs() < 1e15 { format!("{r:.1}") } else { format!("{r}") }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AnalysisHost;
    use crate::db::{Db, Unit, file_units, lower_item};
    use crate::model::{Action, ItemData};
    use crate::semantics::check::domain_for;
    use crate::semantics::symbols::{domain_symbols, problem_symbols};
    use crate::verify::state::initial_state;

    const DOMAIN: &str = "(define (domain d) (:requirements :adl :fluents :durative-actions)
      (:types block - object small - block)
      (:constants table - object)
      (:predicates (on ?x ?y) (clear ?x) (red ?x))
      (:functions (weight ?x) (total))
      (:action paint :parameters (?x - object)
        :effect (and (forall (?y - block) (when (on ?y ?x) (red ?y)))
                     (when (red ?x) (not (clear ?x)))))
      (:action pour :parameters (?x - block)
        :effect (and (increase (weight ?x) 2) (decrease (total) (* 2 (weight ?x)))
                     (scale-up (weight ?x) 3) (assign (total) (+ (total) 1))))
      (:action spill :parameters (?x - block) :effect (assign (total) (/ (total) (- (weight ?x) (weight ?x)))))
      (:durative-action hold :parameters (?x - block) :duration (= ?duration 2)
        :condition (at start (clear ?x))
        :effect (and (at start (not (clear ?x))) (at end (clear ?x))
                     (at end (increase (total) (* ?duration 2)))
                     (when (and (at start (red ?x)) (over all (clear table))) (at end (on ?x table))))))";

    const PROBLEM: &str = "(define (problem p) (:domain d)
      (:objects b1 b2 - block s1 - small)
      (:init (clear b1) (clear b2) (clear s1) (red s1) (on b1 table) (clear table)
             (= (weight b1) 5) (= (total) 10))
      (:goal (and)))";

    /// Runs `f` with the world and initial state of `problem` (its `:goal`
    /// replaced by `goal`), the goal and the domain's actions by name.
    fn with(goal: &str, f: impl FnOnce(&World<'_, '_>, &State, &Gd, &[&Action])) {
        let mut host = AnalysisHost::new();
        host.set_file_text("m/domain.pddl", DOMAIN);
        let p = host
            .set_file_text("m/problem.pddl", PROBLEM.replace("(:goal (and))", &format!("(:goal {goal})")));
        let db: &dyn Db = host.db();
        let problem: Unit<'_> = file_units(db, p)[0];
        let domain = domain_for(db, problem).expect("the domain");
        let objects = Objects::new(domain_symbols(db, domain), problem_symbols(db, problem));
        let (mut preds, mut funcs, mut atoms) = (Interner::default(), Interner::default(), Atoms::default());
        for n in ["on", "clear", "red"] {
            preds.intern(n);
        }
        for n in ["weight", "total"] {
            funcs.intern(n);
        }
        let init = initial_state(db, problem, &objects, &mut preds, &mut funcs, &mut atoms);
        let mut state = State::new(atoms, Atoms::default());
        for &(a, _) in &init.facts {
            state.set(a, true);
        }
        for (key, (v, _)) in &init.fluents {
            let f = state.fluent(key);
            state.set_value(f, Some(*v));
        }
        let world = World { objects: &objects, preds: &preds, funcs: &funcs };
        let goal = problem
            .items(db)
            .iter()
            .find_map(|&i| match &lower_item(db, i).data {
                ItemData::Goal(g) => Some(g),
                _ => None,
            })
            .expect("a goal");
        let actions: Vec<&Action> = domain
            .items(db)
            .iter()
            .filter_map(|&i| match &lower_item(db, i).data {
                ItemData::Action(a) => Some(&**a),
                _ => None,
            })
            .collect();
        f(&world, &state, goal, &actions);
    }

    fn holds(goal: &str) -> bool {
        let mut out = false;
        with(goal, |world, state, g, _| {
            let eval = Eval { world, state, duration: None, total_time: None };
            out = eval.holds(g, &mut Binding::default()).expect("evaluates");
        });
        out
    }

    fn why(goal: &str) -> Vec<String> {
        let mut out = Vec::new();
        with(goal, |world, state, g, _| {
            let eval = Eval { world, state, duration: None, total_time: None };
            out = eval
                .why_false(g, &mut Binding::default(), false)
                .expect("evaluates")
                .into_iter()
                .map(|w| w.text)
                .collect();
        });
        out
    }

    #[test]
    fn quantifiers_range_over_subtypes_and_constants() {
        // `small` is a `block`: s1 is among the blocks.
        assert!(holds("(forall (?x - block) (clear ?x))"));
        assert!(!holds("(forall (?x - block) (red ?x))"));
        assert!(holds("(exists (?x - block) (red ?x))"));
        assert!(!holds("(exists (?x - small) (on ?x table))"));
        // `object` includes the domain's constant `table`.
        assert!(holds("(forall (?x) (clear ?x))"));
        assert!(!holds("(forall (?x - object) (or (= ?x table) (red ?x)))"));
        assert!(holds("(forall (?x - block) (imply (on ?x table) (clear ?x)))"));
        assert!(holds("(exists (?x ?y) (and (on ?x ?y) (not (= ?x ?y))))"));
        assert!(holds("(not (exists (?x - block) (on table ?x)))"));
        assert!(holds("(sortof s1 - block)"));
    }

    #[test]
    fn why_names_the_false_literals_and_instances() {
        assert_eq!(
            why("(and (clear b1) (red b1) (not (clear b2)))"),
            ["`(red b1)` is false", "`(clear b2)` is true"]
        );
        assert_eq!(why("(forall (?x - block) (red ?x))"), ["`(red b1)` is false (for ?x = b1)"]);
        assert_eq!(why("(exists (?x - block) (on ?x b2))"), ["`(exists (?x - block) (on ?x b2))` is false"]);
        assert_eq!(why("(or (red b1) (red b2))"), ["`(red b1)` is false", "`(red b2)` is false"]);
        assert_eq!(why("(imply (red s1) (on s1 table))"), ["`(on s1 table)` is false"]);
        assert_eq!(why("(> (weight b1) (total))"), ["`(> (weight b1) (total))` is false (5.0 > 10.0 fails)"]);
        assert!(why("(clear b1)").is_empty());
    }

    #[test]
    fn a_fluent_without_value_is_an_error_not_false() {
        with("(< (weight b2) 3)", |world, state, g, _| {
            let eval = Eval { world, state, duration: None, total_time: None };
            let err = eval.holds(g, &mut Binding::default()).unwrap_err();
            assert_eq!(err.kind, ErrorKind::Undefined);
            assert_eq!(err.message, "`(weight b2)` has no value");
            assert_eq!(world.show_fluent(&err.fluent.expect("the fluent")), "(weight b2)");
        });
    }

    fn find<'m>(actions: &[&'m Action], name: &str) -> &'m Action {
        actions.iter().find(|a| a.name.key == name).expect("the action")
    }

    fn bind<'m>(a: &'m Action, world: &World<'_, '_>, args: &[&str]) -> Binding<'m> {
        let mut b = Binding::default();
        for (p, o) in a.params.iter().zip(args) {
            b.push(&p.name.key, world.objects.id(o).expect("an object"));
        }
        b
    }

    fn shown(world: &World<'_, '_>, keys: &[(Key, TextRange)]) -> Vec<String> {
        keys.iter().map(|(k, _)| world.show_atom(k)).collect()
    }

    #[test]
    fn conditional_effects_read_the_state_before() {
        with("(and)", |world, state, _, actions| {
            let eval = Eval { world, state, duration: None, total_time: None };
            let paint = find(actions, "paint");
            let mut out = Changes::default();
            eval.effects(
                &paint.effect.clone().unwrap(),
                &mut bind(paint, world, &["table"]),
                Phase::Instant,
                &mut Vec::new(),
                &mut out,
            )
            .unwrap();
            // b1 is on the table: it is painted; the table is not red: still clear.
            assert_eq!(shown(world, &out.adds), ["(red b1)"]);
            assert!(out.dels.is_empty());
            // The conditions that fired are read: (on b1 table); those that did not are not.
            let reads: Vec<String> = out.reads.atoms.iter().map(|k| world.show_atom(k)).collect();
            assert_eq!(reads, ["(on b1 table)"]);
            let mut out = Changes::default();
            eval.effects(
                paint.effect.as_ref().unwrap(),
                &mut bind(paint, world, &["s1"]),
                Phase::Instant,
                &mut Vec::new(),
                &mut out,
            )
            .unwrap();
            assert!(out.adds.is_empty());
            assert_eq!(shown(world, &out.dels), ["(clear s1)"]);
        });
    }

    #[test]
    fn numeric_effects_evaluate_right_hand_sides_before() {
        with("(and)", |world, state, _, actions| {
            let eval = Eval { world, state, duration: None, total_time: None };
            let pour = find(actions, "pour");
            let mut out = Changes::default();
            eval.effects(
                pour.effect.as_ref().unwrap(),
                &mut bind(pour, world, &["b1"]),
                Phase::Instant,
                &mut Vec::new(),
                &mut out,
            )
            .unwrap();
            let got: Vec<(String, &str, f64)> =
                out.updates.iter().map(|u| (world.show_fluent(&u.fluent), u.op.name(), u.value)).collect();
            assert_eq!(
                got,
                [
                    ("(weight b1)".to_string(), "increase", 2.0),
                    ("(total)".to_string(), "decrease", 10.0),
                    ("(weight b1)".to_string(), "scale-up", 3.0),
                    ("(total)".to_string(), "assign", 11.0),
                ]
            );
            let fluents: Vec<String> = out.reads.fluents.iter().map(|k| world.show_fluent(k)).collect();
            assert_eq!(fluents, ["(weight b1)", "(total)"]);
            // Applied in order, as a happening applies them.
            let mut v = Some(5.0);
            for u in out.updates.iter().filter(|u| world.show_fluent(&u.fluent) == "(weight b1)") {
                v = u.op.apply(v, u.value);
            }
            assert_eq!(v, Some(21.0));
            assert_eq!(NumOp::Increase.apply(None, 1.0), None);
            assert_eq!(NumOp::Assign.apply(None, 1.0), Some(1.0));
            assert_eq!(NumOp::ScaleDown.apply(Some(1.0), 0.0), None);

            let spill = find(actions, "spill");
            let err = eval
                .effects(
                    spill.effect.as_ref().unwrap(),
                    &mut bind(spill, world, &["b1"]),
                    Phase::Instant,
                    &mut Vec::new(),
                    &mut Changes::default(),
                )
                .unwrap_err();
            assert_eq!(err.kind, ErrorKind::Arithmetic);
            assert_eq!(err.message, "division by zero in `(/ (total) (- (weight b1) (weight b1)))`");
        });
    }

    #[test]
    fn durative_effects_by_phase_with_duration_and_spanning_conditions() {
        with("(and)", |world, state, _, actions| {
            let hold = find(actions, "hold");
            let effect = hold.effect.as_ref().unwrap();
            let eval = Eval { world, state, duration: Some(2.0), total_time: None };
            let mut spanning = Vec::new();
            let mut start = Changes::default();
            eval.effects(effect, &mut bind(hold, world, &["s1"]), Phase::Start, &mut spanning, &mut start)
                .unwrap();
            assert_eq!(shown(world, &start.dels), ["(clear s1)"]);
            assert!(start.adds.is_empty() && start.updates.is_empty());
            // (red s1) held at the start: the conditional end effect is alive.
            assert_eq!(spanning.len(), 1);
            assert!(spanning[0].alive);
            let mut end = Changes::default();
            eval.effects(effect, &mut bind(hold, world, &["s1"]), Phase::End, &mut spanning, &mut end)
                .unwrap();
            assert_eq!(shown(world, &end.adds), ["(clear s1)", "(on s1 table)"]);
            assert_eq!(end.updates[0].value, 4.0, "`?duration` in an effect");
            // Once the `over all` part fails, the end effect does not happen.
            spanning[0].alive = false;
            let mut end = Changes::default();
            eval.effects(effect, &mut bind(hold, world, &["s1"]), Phase::End, &mut spanning, &mut end)
                .unwrap();
            assert_eq!(shown(world, &end.adds), ["(clear s1)"]);
            // b1 is not red: no spanning effect is alive for it.
            let mut spanning = Vec::new();
            eval.effects(
                effect,
                &mut bind(hold, world, &["b1"]),
                Phase::Start,
                &mut spanning,
                &mut Changes::default(),
            )
            .unwrap();
            assert!(!spanning[0].alive);
            // The conditions split by time.
            let parts = split_timed(hold.precondition.as_ref().unwrap());
            assert_eq!((parts.start.len(), parts.over_all.len(), parts.end.len()), (1, 0, 0));
        });
    }

    #[test]
    fn numbers_in_messages() {
        assert_eq!(fmt_num(130.0), "130.0");
        assert_eq!(fmt_num(0.1 + 0.2), "0.3");
        assert_eq!(fmt_num(16.1), "16.1");
        assert_eq!(fmt_num(-2.5), "-2.5");
    }
}
