//! Effects: the changes they make in a state, by phase of a durative action.

use std::ops::ControlFlow;

use rowan::TextRange;

use super::{Binding, ErrorKind, Eval, EvalError, Key, NumOp, Res, for_each_binding, split_timed};
use crate::model::{Effect, Gd, NumExpr, TimeSpec};
use crate::semantics::check::gd_span;

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

/// Whether an effect has parts at the given time (`at start` or `at end`).
pub(crate) fn has_timed(e: &Effect, spec: TimeSpec) -> bool {
    match e {
        Effect::Timed(s, _, _) => *s == spec,
        Effect::And(es, _) => es.iter().any(|x| has_timed(x, spec)),
        Effect::Forall(_, body, _) | Effect::When(_, body, _) => has_timed(body, spec),
        Effect::Add(_) | Effect::Del(..) | Effect::Numeric(..) => false,
    }
}

impl<'m> Eval<'_, '_, '_> {
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
}
