//! Formulas and numbers as messages show them.

use super::{Binding, Eval};
use crate::model::{CmpOp, Gd, NumExpr, Term, TimeSpec};
use crate::semantics::symbols::type_set;

impl<'m> Eval<'_, '_, '_> {
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
            Term::Var(n) => match b.get(n.key()) {
                Some(o) => s.push_str(self.world.objects.name(o)),
                None => s.push_str(n.text()),
            },
            Term::Const(n) => s.push_str(n.key()),
            Term::Func(f) => self.write_app(f.func.key(), &f.args, b, s),
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
            NumExpr::Fluent(f) => self.write_app(f.func.key(), &f.args, b, s),
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
                s.push_str(id.text());
                s.push(')');
            }
            NumExpr::Special(x, _) => s.push_str(x),
            NumExpr::Var(n) => s.push_str(n.text()),
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
            Gd::Atom(a) => self.write_app(a.pred.key(), &a.args, b, s),
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
                    s.push_str(v.name.text());
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
/// `130` (times and values, not counts). Times are sums of times and
/// durations: rounding hides their float noise (`4.11`, not
/// `4.109999999999999`). Where it could hide why a comparison fails,
/// [`fmt_operands`] shows more.
pub(crate) fn fmt_num(v: f64) -> String {
    if !v.is_finite() || v.abs() >= 1e15 {
        return fmt_exact(v);
    }
    fmt_exact((v * 1e6).round() / 1e6)
}

/// The shortest text that reads back as exactly `v` (`7.999999999995`,
/// `8.0`): Rust's shortest round-trip representation, with `.0` on whole
/// numbers.
pub(crate) fn fmt_exact(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 { format!("{v:.1}") } else { format!("{v}") }
}

/// The two sides of a comparison, as [`fmt_num`] shows them, unless that
/// shows two different numbers alike (`8.0 >= 8.0 fails` for
/// 7.999999999995 >= 8): then both exactly, and `true`.
pub(crate) fn fmt_operands(l: f64, r: f64) -> (String, String, bool) {
    let (a, b) = (fmt_num(l), fmt_num(r));
    if a == b && l != r { (fmt_exact(l), fmt_exact(r), true) } else { (a, b, false) }
}
