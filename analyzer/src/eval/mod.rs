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
//!
//! - `state.rs`: the ground vocabulary and states.
//! - `conditions.rs`: conditions, true or false, and why.
//! - `numeric.rs`: numeric expressions and numeric effects' operators.
//! - `effects.rs`: the changes effects make.
//! - `show.rs`: formulas and numbers as messages show them.

mod conditions;
mod effects;
mod numeric;
mod show;
mod state;
#[cfg(test)]
mod tests;

pub(crate) use conditions::{Why, for_each_binding, split_timed};
pub(crate) use effects::{Changes, Phase, Reads, Spanning, Update, has_timed};
pub(crate) use numeric::NumOp;
pub(crate) use show::{fmt_exact, fmt_num, fmt_operands, op_text};
pub(crate) use state::{GroundWorld, State};

use rowan::TextRange;

use crate::model::{Atom, Fluent, Name, Term};
use crate::verify::state::{Interner, ObjId, Objects};

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
            Term::Var(n) => b.get(n.key()).ok_or_else(|| {
                EvalError::new(ErrorKind::Unresolved, n.span, format!("`{}` is not bound", n.text()))
            }),
            Term::Const(n) => self.world.objects.id(n.key()).ok_or_else(|| {
                EvalError::new(ErrorKind::Unresolved, n.span, format!("`{}` is not an object", n.text()))
            }),
            Term::Func(f) => Err(EvalError::new(
                ErrorKind::Unsupported,
                f.span,
                format!("object fluents (`({} …)` as a term) are not supported", f.func.text()),
            )),
        }
    }

    fn key(&self, names: &Interner, what: &str, name: &Name, args: &[Term], b: &Binding<'m>) -> Res<Key> {
        let id = names.get(name.key()).ok_or_else(|| {
            EvalError::new(
                ErrorKind::Unresolved,
                name.span,
                format!("`{}` is not a declared {what}", name.text()),
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
}
