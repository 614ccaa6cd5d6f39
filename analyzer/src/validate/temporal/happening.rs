//! A happening executed: its conditions checked in the state before it,
//! its effects applied together, then the `over all` conditions of the
//! running steps.

use super::mutex::{causal, interferences};
use super::{Actor, Change, Event, Run, TilChange, Touch};
use crate::diagnostic::{Severity, codes};
use crate::eval::{Changes, Eval, NumOp, Phase, Reads, Update, Why, fmt_num, split_timed};
use crate::semantics::check::gd_span;
use crate::validate::Failure;

impl<'a, 'db> Run<'a, 'db> {
    pub(super) fn happening(&mut self, h: usize, events: &[Event], active: &mut Vec<usize>) {
        let world = self.world();
        let n = events.len();
        let mut changes: Vec<Changes> = vec![Changes::default(); n];
        let mut reads: Vec<Reads> = vec![Reads::default(); n];
        let mut whys: Vec<(usize, &'static str, Why)> = Vec::new();
        let mut out: Vec<Failure<'db>> = Vec::new();
        for (k, e) in events.iter().enumerate() {
            let i = match e.actor {
                Actor::Til(j) => {
                    let til = &self.model.tils[j];
                    match &til.change {
                        TilChange::Atom(key, true) => changes[k].adds.push((key.clone(), til.loc.span)),
                        TilChange::Atom(key, false) => changes[k].dels.push((key.clone(), til.loc.span)),
                        TilChange::Fluent(key, v) => changes[k].updates.push(Update {
                            fluent: key.clone(),
                            op: NumOp::Assign,
                            value: *v,
                            span: til.loc.span,
                        }),
                    }
                    continue;
                }
                Actor::Start(i) | Actor::End(i) | Actor::Instant(i) => i,
            };
            let step = &self.steps[i];
            let mut b = step.binding();
            let eval = Eval { world: &world, state: &self.state, duration: step.duration, total_time: None };
            if let (Actor::Start(_), Some(pre)) = (e.actor, &step.action.precondition)
                && let Some(u) = split_timed(pre).untimed.first()
            {
                out.push(
                    Failure::new(
                        codes::UNSUPPORTED_IN_PLAN,
                        self.plan[i].span,
                        format!(
                            "{}: a condition of a durative action without `at start`, `over all` or `at end` cannot be checked",
                            self.event_head(*e)
                        ),
                    )
                    .at_step(i)
                    .model(step.loc(gd_span(u)), "this condition"),
                );
            }
            let failed_before = whys.len() + out.len();
            for c in self.conditions(e.actor) {
                let _ = eval.reads(c.gd, &mut b, &mut reads[k]);
                match eval.why_false(c.gd, &mut b, false) {
                    Ok(ws) => whys.extend(ws.into_iter().map(|w| (k, c.label, w))),
                    Err(err) => {
                        out.push(self.eval_failure(e.actor, e.time, &format!("its {}", c.label), err))
                    }
                }
            }
            for g in self.duration_constraints(e.actor) {
                let _ = eval.reads(g, &mut b, &mut reads[k]);
                if let Some(f) = self.check_duration(*e, i, g, &eval, &mut b) {
                    out.push(f);
                }
            }
            // Effects of an event whose conditions fail are not reported on:
            // VAL stops before them, and their errors would be consequences.
            let conditions_hold = whys.len() + out.len() == failed_before;
            if let Some(effect) = &step.action.effect {
                let phase = match e.actor {
                    Actor::Start(_) => Phase::Start,
                    Actor::End(_) => Phase::End,
                    _ => Phase::Instant,
                };
                let result = eval.effects(effect, &mut b, phase, &mut self.spanning[i], &mut changes[k]);
                if let (Err(err), true) = (result, conditions_hold) {
                    out.push(self.eval_failure(e.actor, e.time, "its effects", err));
                }
            }
        }
        // False conditions: made true too late in the same happening, or not at all.
        let mut reported: Vec<(usize, usize)> = Vec::new();
        for (k, label, why) in whys {
            let earlier = |o: usize| o != k && events[o].time <= events[k].time;
            // Another event of the happening makes the literal as needed, or
            // changes a fluent the comparison reads.
            let other = match &why.literal {
                Some((key, needed)) => (0..n).filter(|&o| earlier(o)).find_map(|o| {
                    let list = if *needed { &changes[o].adds } else { &changes[o].dels };
                    let (verb, value) =
                        if *needed { ("makes it true", "true") } else { ("makes it false", "false") };
                    let note = format!("makes `{}` {value}", world.show_atom(key));
                    list.iter().find(|(x, _)| x == key).map(|(_, span)| (o, *span, verb.to_string(), note))
                }),
                None => (0..n).filter(|&o| earlier(o)).find_map(|o| {
                    changes[o].updates.iter().find(|u| why.fluents.contains(&u.fluent)).map(|u| {
                        let verb = format!("changes `{}` (`{}`)", world.show_fluent(&u.fluent), u.op.name());
                        (o, u.span, verb.clone(), verb)
                    })
                }),
            };
            match other {
                Some((o, span, verb, note)) => {
                    reported.push((k.min(o), k.max(o)));
                    out.push(self.too_close(events[k], events[o], label, &why, span, (&verb, &note)));
                }
                None => out.push(self.false_condition(events[k], label, &why, codes::PRECONDITION_FALSE)),
            }
        }
        // Interference between the events of the happening (VAL's ownership).
        let touches: Vec<Touch> = (0..n).map(|k| self.touch(&reads[k], &changes[k])).collect();
        if n > 1 {
            let refs: Vec<&Touch> = touches.iter().collect();
            for reasons in interferences(&refs) {
                if !reported.contains(&reasons[0].events()) {
                    let inter = causal(&reasons, &|k| events[k]);
                    out.push(self.mutex(inter, &|k| events[k]));
                }
            }
        }
        let failed = out.iter().any(|f| f.code.severity == Severity::Error);
        self.failures.extend(out);
        self.touched.extend(events.iter().zip(touches).map(|(e, t)| (*e, h, t)));
        if failed && !self.options.keep_going {
            return;
        }
        self.apply(events, &changes);
        // `over all` conditions: those of the steps running after this happening.
        for e in events {
            match e.actor {
                Actor::Start(i) if !events.iter().any(|x| x.actor == Actor::End(i)) => active.push(i),
                Actor::End(i) => {
                    active.retain(|&x| x != i);
                    self.spanning[i].clear();
                }
                _ => {}
            }
        }
        self.check_invariants(events[0].time, active);
    }

    /// Applies the changes of a happening: deletions, additions, then
    /// numeric updates in order.
    pub(super) fn apply(&mut self, events: &[Event], changes: &[Changes]) {
        for (e, ch) in events.iter().zip(changes) {
            for (key, span) in &ch.dels {
                let a = self.state.atom(key);
                self.state.set(a, false);
                let effect = Some(self.effect_loc(e.actor, *span));
                self.atom_last.insert(a, Change { time: e.time, actor: e.actor, added: false, effect });
            }
        }
        for (e, ch) in events.iter().zip(changes) {
            for (key, span) in &ch.adds {
                let a = self.state.atom(key);
                self.state.set(a, true);
                let effect = Some(self.effect_loc(e.actor, *span));
                self.atom_last.insert(a, Change { time: e.time, actor: e.actor, added: true, effect });
            }
        }
        for (e, ch) in events.iter().zip(changes) {
            for u in &ch.updates {
                let f = self.state.fluent(&u.fluent);
                let old = self.state.value(f);
                let effect = self.effect_loc(e.actor, u.span);
                match u.op.apply(old, u.value) {
                    Some(v) => {
                        self.state.set_value(f, Some(v));
                        let change =
                            Change { time: e.time, actor: e.actor, added: true, effect: Some(effect) };
                        self.fluent_last.insert(f, change);
                    }
                    None => {
                        let fluent = self.world().show_fluent(&u.fluent);
                        let why = if old.is_none() {
                            format!("`{fluent}` has no value")
                        } else {
                            format!(
                                "the result is not a finite number (`{fluent}` is {})",
                                fmt_num(old.unwrap_or(0.0))
                            )
                        };
                        let mut f = Failure::new(
                            codes::NUMERIC_ERROR,
                            self.event_span(e.actor),
                            format!(
                                "{}: cannot `{}` `{fluent}` by {}: {why}",
                                self.event_head(*e),
                                u.op.name(),
                                fmt_num(u.value)
                            ),
                        )
                        .model(effect, "this effect");
                        if let Some(i) = e.actor.step() {
                            f = f.at_step(i);
                        }
                        if old.is_none() {
                            f = f.hint(format!("give `{fluent}` a value in `:init`"));
                        }
                        self.failures.push(f);
                    }
                }
            }
        }
    }

    /// Interns what an event reads and writes.
    pub(super) fn touch(&mut self, reads: &Reads, ch: &Changes) -> Touch {
        let mut t = Touch::default();
        for k in reads.atoms.iter().chain(ch.reads.atoms.iter()) {
            t.reads.push(self.state.atom(k));
        }
        for k in reads.fluents.iter().chain(ch.reads.fluents.iter()) {
            t.fluent_reads.push(self.state.fluent(k));
        }
        for (k, _) in &ch.adds {
            t.adds.push(self.state.atom(k));
        }
        for (k, _) in &ch.dels {
            t.dels.push(self.state.atom(k));
        }
        for u in &ch.updates {
            t.fluent_writes.push((self.state.fluent(&u.fluent), u.op));
        }
        t
    }

    /// Checks the `over all` conditions of the running steps in the state
    /// after the happening at `time`; a step is reported once.
    pub(super) fn check_invariants(&mut self, time: f64, active: &mut Vec<usize>) {
        let world = self.world();
        let eval = Eval { world: &world, state: &self.state, duration: None, total_time: None };
        let mut out = Vec::new();
        let mut violated = Vec::new();
        for &i in active.iter() {
            let step = &self.steps[i];
            let eval = Eval { duration: step.duration, ..eval };
            let mut b = step.binding();
            let Some(pre) = &step.action.precondition else { continue };
            let mut failed = false;
            for g in split_timed(pre).over_all {
                match eval.why_false(g, &mut b, false) {
                    Ok(whys) => {
                        for why in whys {
                            failed = true;
                            out.push(self.violated_invariant(i, time, &why));
                        }
                    }
                    Err(err) => {
                        failed = true;
                        out.push(self.eval_failure(Actor::Start(i), time, "its `over all` condition", err));
                    }
                }
            }
            if failed {
                violated.push(i);
            }
            for s in self.spanning[i].iter_mut().filter(|s| s.alive) {
                let mut b = s.binding.clone();
                s.alive = s.invariant.iter().all(|g| eval.holds(g, &mut b).unwrap_or(false));
            }
        }
        active.retain(|i| !violated.contains(i));
        self.failures.extend(out);
    }
}
