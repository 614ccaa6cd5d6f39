//! Conditions: whether they hold in a state, why they do not, what they read.

use std::ops::ControlFlow;

use rowan::TextRange;

use super::{Binding, ErrorKind, Eval, EvalError, Key, Reads, Res, fmt_operands, op_text};
use crate::model::{CmpOp, Gd, TimeSpec, Typed};
use crate::semantics::check::gd_span;
use crate::semantics::symbols::type_set;
use crate::verify::state::{ObjId, Objects};

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

/// Calls `f` with each binding of `vars` to objects of their types, in
/// order (the last variable changing fastest), until it breaks. Without
/// recursion: a quantifier may bind thousands of variables.
pub(crate) fn for_each_binding<'m>(
    objects: &Objects<'_>,
    vars: &'m [Typed],
    b: &mut Binding<'m>,
    f: &mut dyn FnMut(&mut Binding<'m>) -> Res<ControlFlow<()>>,
) -> Res<ControlFlow<()>> {
    let domains: Vec<Vec<ObjId>> = vars.iter().map(|v| objects.of_types(&type_set(&v.ty))).collect();
    if domains.iter().any(Vec::is_empty) {
        return Ok(ControlFlow::Continue(()));
    }
    // An odometer: `at[k]` is the object of variable `k`, all of them pushed.
    let mut at = vec![0usize; vars.len()];
    for (v, d) in vars.iter().zip(&domains) {
        b.push(v.name.key(), d[0]);
    }
    let pop_all = |b: &mut Binding<'m>| (0..vars.len()).for_each(|_| b.pop());
    loop {
        match f(b) {
            Ok(ControlFlow::Continue(())) => {}
            done => {
                pop_all(b);
                return done;
            }
        }
        // The last variable that has an object left takes the next one; those
        // after it start again from their first.
        let Some(k) = (0..vars.len()).rev().find(|&k| at[k] + 1 < domains[k].len()) else {
            pop_all(b);
            return Ok(ControlFlow::Continue(()));
        };
        (k..vars.len()).for_each(|_| b.pop());
        at[k] += 1;
        b.push(vars[k].name.key(), domains[k][at[k]]);
        for j in k + 1..vars.len() {
            at[j] = 0;
            b.push(vars[j].name.key(), domains[j][0]);
        }
    }
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
    /// The comparison's numbers are shown exactly, because rounded they
    /// would look alike: show its fluents' values exactly too.
    pub exact: bool,
}

impl<'m> Eval<'_, '_, '_> {
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
                vec![Why {
                    text,
                    span: a.span,
                    literal: Some((key, !negated)),
                    fluents: Vec::new(),
                    exact: false,
                }]
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
                let (ls, rs, exact) = fmt_operands(lv, rv);
                let text = format!(
                    "`{}` is {is} ({ls} {} {rs} {})",
                    self.show_gd(g, b),
                    op_text(*op),
                    if negated { "holds" } else { "fails" }
                );
                vec![Why { text, span: *span, literal: None, fluents, exact }]
            }
            Gd::Timed(_, x, _) | Gd::Preference(_, x, _) => self.why_false(x, b, negated)?,
            _ => vec![Why {
                text: format!("`{}` is {is}", self.show_gd(g, b)),
                span: gd_span(g),
                literal: None,
                fluents: Vec::new(),
                exact: false,
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
                    let o = b.get(v.name.key()).map_or("?", |o| self.world.objects.name(o));
                    format!("{} = {o}", v.name.text())
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
                exact: false,
            });
        }
        Ok(found)
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
