//! Numeric expressions, their values in a state, and the operators of numeric effects.

use super::{Binding, ErrorKind, Eval, EvalError, Key, Res};
use crate::model::NumExpr;

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

impl<'m> Eval<'_, '_, '_> {
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
                format!("`{}` is an object, not a number", n.text()),
            )),
        }
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
}
