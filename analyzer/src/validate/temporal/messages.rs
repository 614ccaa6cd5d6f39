//! How failures name steps and events, and what they blame: the culprit
//! of a false condition, a violated invariant, a formula that cannot be
//! evaluated.

use rowan::TextRange;

use super::{Actor, Event, Run, plan_start};
use crate::diagnostic::{Code, codes};
use crate::eval::{ErrorKind, EvalError, Why, fmt_exact, fmt_num};
use crate::semantics::symbols::Loc;
use crate::validate::Failure;

/// A culprit for a false condition: what to add to the message, where.
#[derive(Default)]
pub(super) struct Culprit<'db> {
    pub(super) text: String,
    pub(super) plan: Vec<(TextRange, String)>,
    pub(super) model: Vec<(Loc<'db>, String)>,
    pub(super) hint: Option<String>,
}

impl<'a, 'db> Run<'a, 'db> {
    /// `step 3 `(drive t a b)`` (its id), `the step on line 7 `(drive t a b)``.
    pub(super) fn step_text(&self, i: usize) -> String {
        self.plan[i].described()
    }

    /// "the start of step 3 `(drive t a b)`", "the timed initial literal at 10.0".
    pub(super) fn actor_text(&self, a: Actor) -> String {
        match a {
            Actor::Start(i) => format!("the start of {}", self.step_text(i)),
            Actor::End(i) => format!("the end of {}", self.step_text(i)),
            Actor::Instant(i) => self.step_text(i),
            Actor::Til(j) => format!("the timed initial literal at {}", fmt_num(self.model.tils[j].time)),
        }
    }

    /// "the start of step 3", "the timed initial literal at 10.0".
    pub(super) fn actor_short(&self, a: Actor) -> String {
        match a {
            Actor::Start(i) => format!("the start of {}", self.plan[i].label()),
            Actor::End(i) => format!("the end of {}", self.plan[i].label()),
            Actor::Instant(i) => self.plan[i].label(),
            Actor::Til(_) => self.actor_text(a),
        }
    }

    /// "step 3 `(drive t a b)` at 3.0", "step 3 `(drive t a b)`, ending at 13.0".
    pub(super) fn event_head(&self, e: Event) -> String {
        match e.actor {
            Actor::End(i) => format!("{}, ending at {}", self.step_text(i), fmt_num(e.time)),
            Actor::Start(i) | Actor::Instant(i) => format!("{} at {}", self.step_text(i), fmt_num(e.time)),
            Actor::Til(_) => self.actor_text(e.actor),
        }
    }

    /// Where an event points in the plan: its step.
    pub(super) fn event_span(&self, a: Actor) -> TextRange {
        match a.step() {
            Some(i) => self.plan[i].span,
            None => plan_start(self.plan),
        }
    }

    /// A time for an edit of the plan: enough decimals for the tolerance.
    pub(super) fn edit_time(&self, t: f64) -> String {
        let decimals = (-self.options.tolerance.log10()).ceil().clamp(3.0, 9.0) as usize;
        format!("{t:.decimals$}")
    }

    /// The item of an event's action, or of the timed literal.
    pub(super) fn effect_loc(&self, a: Actor, span: TextRange) -> Loc<'db> {
        match a {
            Actor::Til(j) => self.model.tils[j].loc,
            Actor::Start(i) | Actor::End(i) | Actor::Instant(i) => self.steps[i].loc(span),
        }
    }

    pub(super) fn violated_invariant(&self, i: usize, time: f64, why: &Why) -> Failure<'db> {
        let step = &self.steps[i];
        let c = self.culprit(why, time);
        let mut f = Failure::new(
            codes::INVARIANT_VIOLATED,
            self.plan[i].span,
            format!(
                "{} runs from {} to {}, but its `over all` condition {} from {}{}",
                self.step_text(i),
                fmt_num(step.time),
                fmt_num(step.end()),
                why.text,
                fmt_num(time),
                c.text
            ),
        )
        .at_step(i)
        .model(step.loc(why.span), "the `over all` condition");
        f.plan_related = c.plan;
        f.model_related.extend(c.model);
        let what = match &why.literal {
            Some((key, true)) => format!("keep `{}` true", self.world().show_atom(key)),
            Some((key, false)) => format!("keep `{}` false", self.world().show_atom(key)),
            None => "keep the condition true".to_string(),
        };
        f.hint(format!(
            "{what} from {} to {}: move what changes it out of that interval, or make {} end before {}",
            fmt_num(step.time),
            fmt_num(step.end()),
            self.step_text(i),
            fmt_num(time)
        ))
    }

    /// Why a false condition is false: the last change of its atom or fluents.
    pub(super) fn culprit(&self, why: &Why, when: f64) -> Culprit<'db> {
        let world = self.world();
        let mut c = Culprit::default();
        if let Some((key, needed)) = &why.literal {
            let atom = world.show_atom(key);
            let id = self.state.atoms.get(key);
            match id.and_then(|a| self.atom_last.get(&a)) {
                Some(ch) => {
                    let verb = if ch.added { "added" } else { "deleted" };
                    c.text = format!(": {verb} at {} by {}", fmt_num(ch.time), self.actor_text(ch.actor));
                    if let Some(i) = ch.actor.step() {
                        c.plan.push((self.plan[i].span, format!("{verb} `{atom}` at {}", fmt_num(ch.time))));
                    }
                    if let Some(loc) = ch.effect {
                        c.model.push((loc, format!("{verb} here")));
                    }
                    let mover = match ch.actor.step() {
                        Some(i) => format!(
                            ", or move {} so that it does not {} it before {}",
                            self.plan[i].label(),
                            if ch.added { "add" } else { "delete" },
                            fmt_num(when)
                        ),
                        None => String::new(),
                    };
                    c.hint = Some(if *needed {
                        format!(
                            "`{atom}` must be true at {}: make it true again after {}{mover}",
                            fmt_num(when),
                            fmt_num(ch.time)
                        )
                    } else {
                        format!(
                            "`{atom}` must be false at {}: delete it again after {}{mover}",
                            fmt_num(when),
                            fmt_num(ch.time)
                        )
                    });
                }
                None if *needed => {
                    c.text = ": it is not in the initial state and nothing makes it true before".into();
                    c.hint = Some(format!(
                        "`{atom}` must be true at {}: add a step that makes it true before, or add it to `:init` if it holds from the start",
                        fmt_num(when)
                    ));
                }
                None => {
                    c.text = ": it is true in the initial state".into();
                    if let Some(loc) = id.and_then(|a| self.init_facts.get(&a)) {
                        c.model.push((*loc, "true in the initial state".into()));
                    }
                    c.hint = Some(format!(
                        "`{atom}` must be false at {}: add a step that deletes it before",
                        fmt_num(when)
                    ));
                }
            }
        } else if !why.fluents.is_empty() {
            let mut parts = Vec::new();
            for key in &why.fluents {
                let name = world.show_fluent(key);
                let f = self.state.fluents.get(key);
                let show = if why.exact { fmt_exact } else { fmt_num };
                let value = f.and_then(|f| self.state.value(f)).map_or("no value".to_string(), show);
                match f.and_then(|f| self.fluent_last.get(&f)) {
                    Some(ch) => {
                        parts.push(format!(
                            "`{name}` is {value}, set at {} by {}",
                            fmt_num(ch.time),
                            self.actor_text(ch.actor)
                        ));
                        if let Some(i) = ch.actor.step() {
                            c.plan.push((
                                self.plan[i].span,
                                format!("changes `{name}` at {}", fmt_num(ch.time)),
                            ));
                        }
                    }
                    None => {
                        parts.push(format!("`{name}` is {value} since the initial state"));
                        if let Some(loc) = f.and_then(|f| self.init_fluents.get(&f)) {
                            c.model.push((*loc, "the initial value".into()));
                        }
                    }
                }
            }
            c.text = format!(": {}", parts.join("; "));
            c.hint = Some(format!("change the plan so that the condition holds at {}", fmt_num(when)));
        }
        c
    }

    /// A condition of an event that is false.
    pub(super) fn false_condition(
        &self,
        e: Event,
        label: &str,
        why: &Why,
        code: &'static Code,
    ) -> Failure<'db> {
        let c = self.culprit(why, e.time);
        let mut f = Failure::new(
            code,
            self.event_span(e.actor),
            format!("{}: {label} {}{}", self.event_head(e), why.text, c.text),
        );
        if let Some(i) = e.actor.step() {
            f = f.at_step(i).model(self.steps[i].loc(why.span), format!("the {label}"));
        }
        f.plan_related = c.plan;
        f.model_related.extend(c.model);
        f.hint = c.hint;
        f
    }

    /// A formula of an event that cannot be evaluated.
    pub(super) fn eval_failure(&self, a: Actor, time: f64, what: &str, err: EvalError) -> Failure<'db> {
        let code = match err.kind {
            ErrorKind::Undefined | ErrorKind::Arithmetic => codes::NUMERIC_ERROR,
            ErrorKind::Unsupported | ErrorKind::Unresolved => codes::UNSUPPORTED_IN_PLAN,
        };
        let head = match a {
            Actor::Start(i) | Actor::Instant(i) => format!("{} at {}", self.step_text(i), fmt_num(time)),
            Actor::End(i) => format!("{}, ending at {}", self.step_text(i), fmt_num(time)),
            Actor::Til(_) => self.actor_text(a),
        };
        let mut f = Failure::new(
            code,
            self.event_span(a),
            format!("{head}: cannot evaluate {what}: {}", err.message),
        );
        if let Some(i) = a.step() {
            f = f.at_step(i).model(self.steps[i].loc(err.span), "here");
        }
        if let (ErrorKind::Undefined, Some(key)) = (err.kind, &err.fluent) {
            f = f.hint(format!(
                "give `{}` a value in `:init`, or assign it before {}",
                self.world().show_fluent(key),
                fmt_num(time)
            ));
        }
        f
    }
}
