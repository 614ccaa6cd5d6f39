//! The checks that are not conditions of a happening: duration constraints,
//! the goal at the end of the plan, the plan's value.

use super::{Event, Run, plan_start};
use crate::diagnostic::codes;
use crate::eval::{Binding, ErrorKind, Eval, fmt_exact, fmt_num, fmt_operands};
use crate::model::{CmpOp, Gd, NumExpr};
use crate::semantics::check::gd_span;
use crate::semantics::symbols::Loc;
use crate::validate::Failure;

impl<'a, 'db> Run<'a, 'db> {
    /// Checks a duration constraint of a step; `None` when it holds.
    pub(super) fn check_duration(
        &self,
        e: Event,
        i: usize,
        g: &'db Gd,
        eval: &Eval<'_, '_, 'db>,
        b: &mut Binding<'db>,
    ) -> Option<Failure<'db>> {
        let step = &self.steps[i];
        let d = step.duration.unwrap_or(0.0);
        let tol = self.options.tolerance;
        let flip = |op| match op {
            CmpOp::Lt => CmpOp::Gt,
            CmpOp::Le => CmpOp::Ge,
            CmpOp::Ge => CmpOp::Le,
            CmpOp::Gt => CmpOp::Lt,
            CmpOp::Eq => CmpOp::Eq,
        };
        let (op, bound) = match g {
            Gd::Compare(op, l, r, _) if matches!(**l, NumExpr::Duration(_)) => (*op, &**r),
            Gd::Compare(op, l, r, _) if matches!(**r, NumExpr::Duration(_)) => (flip(*op), &**l),
            _ => {
                return match eval.holds(g, b) {
                    Ok(true) => None,
                    Ok(false) => Some(
                        Failure::new(
                            codes::DURATION_VIOLATED,
                            self.plan[i].span,
                            format!(
                                "{} lasts {}, which does not satisfy its duration constraint `{}`",
                                self.step_text(i),
                                fmt_num(d),
                                eval.show_gd(g, b)
                            ),
                        )
                        .at_step(i)
                        .model(step.loc(gd_span(g)), "the duration constraint"),
                    ),
                    Err(err) => Some(self.eval_failure(e.actor, e.time, "its duration constraint", err)),
                };
            }
        };
        let v = match eval.num(bound, b) {
            Ok(v) => v,
            Err(err) => return Some(self.eval_failure(e.actor, e.time, "its duration constraint", err)),
        };
        // VAL's tests (DurativeActionElement::confirmPrecondition).
        let ok = match op {
            CmpOp::Gt => d > v,
            CmpOp::Lt => d < v,
            CmpOp::Ge => v - d <= tol,
            CmpOp::Le => d - v <= tol,
            CmpOp::Eq => (d - v).abs() < tol,
        };
        if ok {
            return None;
        }
        // The duration and the bound, exactly when rounding shows them alike.
        let (ds, vs, exact) = fmt_operands(d, v);
        let by = |x: f64| if exact { fmt_exact(x) } else { fmt_num(x) };
        let need = match op {
            CmpOp::Eq => format!("{vs} (within the tolerance {tol})"),
            CmpOp::Ge => format!("at least {vs}"),
            CmpOp::Le => format!("at most {vs}"),
            CmpOp::Gt => format!("more than {vs}"),
            CmpOp::Lt => format!("less than {vs}"),
        };
        let (hint, target) = match op {
            CmpOp::Eq => (format!("set the duration to {vs}"), Some(v)),
            CmpOp::Ge => (format!("increase the duration by at least {}, to {vs}", by(v - d)), Some(v)),
            CmpOp::Le => (format!("decrease the duration by at least {}, to {vs}", by(d - v)), Some(v)),
            CmpOp::Gt => (format!("make the duration more than {vs}"), None),
            CmpOp::Lt => (format!("make the duration less than {vs}"), None),
        };
        let shown = eval.show_gd(g, b);
        let mut f = Failure::new(
            codes::DURATION_VIOLATED,
            self.plan[i].duration_span.unwrap_or(self.plan[i].span),
            format!(
                "{} lasts {ds}, but its duration constraint `{shown}` requires {need}",
                self.step_text(i)
            ),
        )
        .at_step(i)
        .model(step.loc(gd_span(g)), "the duration constraint")
        .hint(hint);
        if let (Some(v), Some(span)) = (target, self.plan[i].duration_span) {
            f = f.edit(span, format!("[{}]", self.edit_time(v)));
        }
        Some(f)
    }

    pub(super) fn check_goal(&mut self, makespan: f64) {
        let Some((item, goal)) = self.model.goal else { return };
        let world = self.world();
        let eval = Eval { world: &world, state: &self.state, duration: None, total_time: Some(makespan) };
        let mut b = Binding::default();
        let last = self.plan.last().map_or_else(|| plan_start(self.plan), |s| s.span);
        let whys = match eval.why_false(goal, &mut b, false) {
            Ok(w) => w,
            Err(err) => {
                let code = match err.kind {
                    ErrorKind::Undefined | ErrorKind::Arithmetic => codes::NUMERIC_ERROR,
                    _ => codes::UNSUPPORTED_IN_PLAN,
                };
                let f = Failure::new(code, last, format!("the goal cannot be evaluated: {}", err.message))
                    .model(Loc { item, span: err.span }, "here");
                self.failures.push(f);
                return;
            }
        };
        let mut out = Vec::new();
        for why in whys {
            let c = self.culprit(&why, makespan);
            let culprit_step = why
                .literal
                .as_ref()
                .and_then(|(key, _)| self.state.atoms.get(key))
                .and_then(|a| self.atom_last.get(&a))
                .and_then(|ch| ch.actor.step());
            let span = culprit_step.map_or(last, |i| self.plan[i].span);
            let mut f = Failure::new(
                codes::GOAL_NOT_REACHED,
                span,
                format!(
                    "the goal is not reached at the end of the plan ({}): {}{}",
                    fmt_num(makespan),
                    why.text,
                    c.text
                ),
            )
            .model(Loc { item, span: why.span }, "the goal");
            if let Some(i) = culprit_step {
                f = f.at_step(i);
            }
            f.plan_related = c.plan.into_iter().filter(|(s, _)| *s != span).collect();
            f.model_related.extend(c.model);
            f.hint = c.hint.or(Some(match &why.literal {
                Some((key, true)) => format!(
                    "add steps that make `{}` true by the end of the plan (and keep it true)",
                    world.show_atom(key)
                ),
                Some((key, false)) => {
                    format!("add steps that make `{}` false by the end of the plan", world.show_atom(key))
                }
                None => "change the plan so that the goal holds at its end".into(),
            }));
            out.push(f);
        }
        self.failures.extend(out);
    }

    /// The plan's value: the metric, or the makespan without one.
    pub(super) fn value(&mut self, makespan: f64) -> Option<f64> {
        let Some((item, _, expr)) = self.model.metric else { return Some(makespan) };
        let world = self.world();
        let eval = Eval { world: &world, state: &self.state, duration: None, total_time: Some(makespan) };
        match eval.num(expr, &Binding::default()) {
            Ok(v) => Some(v),
            Err(err) => {
                let last = self.plan.last().map_or_else(|| plan_start(self.plan), |s| s.span);
                let f = Failure::new(
                    codes::VALUE_NOT_EVALUABLE,
                    last,
                    format!("the plan's value cannot be computed: {}", err.message),
                )
                .model(Loc { item, span: err.span }, "in the metric");
                self.failures.push(f);
                None
            }
        }
    }
}
