//! The happenings of a timed plan and what VAL checks at each (see the
//! module documentation of [`super`] for the semantics).
//!
//! Execution keeps, besides the state, where each atom and fluent last
//! changed (which step, at what time, by which effect), so that a false
//! condition names its culprit: "deleted at 120.0 by the start of step 9
//! `(move r1 w5 w7)`".
//!
//! - `mod.rs`: the plan's events and happenings, in time order, executed.
//! - `model.rs`: the model prepared once, the steps grounded in it, what
//!   is not supported.
//! - `happening.rs`: one happening: conditions, effects, `over all`.
//! - `mutex.rs`: interfering events, in a happening and across close ones.
//! - `checks.rs`: duration constraints, the goal, the plan's value.
//! - `messages.rs`: how failures name steps and events, and their culprits.

mod checks;
mod happening;
mod messages;
pub(super) mod model;
mod mutex;
#[cfg(test)]
mod tests;

use rowan::TextRange;
use rustc_hash::FxHashMap;

use super::{Failure, Options, Report, TimedStep};
use crate::db::{Db, Item, Unit, UnitKind};
use crate::diagnostic::{Severity, codes};
use crate::eval::{Binding, FluentId, Key, NumOp, Spanning, State, World, split_timed};
use crate::model::{Action, Gd, Name, NumExpr};
use crate::semantics::check::domain_for;
use crate::semantics::symbols::Loc;
use crate::verify::state::{AtomId, Atoms, InitialState, Interner, ObjId, Objects};

use model::{ground_step, prepare, unsupported_model};

/// A step, grounded: its action and arguments, its times.
struct Step<'db> {
    item: Item<'db>,
    action: &'db Action,
    args: Vec<ObjId>,
    time: f64,
    /// `Some` for a durative action.
    duration: Option<f64>,
}

impl<'db> Step<'db> {
    fn binding(&self) -> Binding<'db> {
        let mut b = Binding::default();
        for (p, &o) in self.action.params.iter().zip(&self.args) {
            b.push(p.name.key(), o);
        }
        b
    }

    fn end(&self) -> f64 {
        self.time + self.duration.unwrap_or(0.0)
    }

    fn loc(&self, span: TextRange) -> Loc<'db> {
        Loc { item: self.item, span }
    }
}

/// A timed initial literal or timed numeric assignment of `:init`.
struct Til<'db> {
    time: f64,
    change: TilChange,
    loc: Loc<'db>,
}

pub(in crate::validate) enum TilChange {
    Atom(Key, bool),
    Fluent(Key, f64),
}

/// What an event is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Actor {
    Start(usize),
    End(usize),
    Instant(usize),
    Til(usize),
}

impl Actor {
    fn step(self) -> Option<usize> {
        match self {
            Actor::Start(i) | Actor::End(i) | Actor::Instant(i) => Some(i),
            Actor::Til(_) => None,
        }
    }
}

#[derive(Debug, Clone, Copy)]
struct Event {
    time: f64,
    actor: Actor,
}

/// The last change of an atom or a fluent.
#[derive(Debug, Clone, Copy)]
struct Change<'db> {
    time: f64,
    actor: Actor,
    /// For an atom: whether it was added.
    added: bool,
    /// The effect, in its item.
    effect: Option<Loc<'db>>,
}

/// What an event reads and writes, interned: the base of mutual exclusion.
#[derive(Debug, Clone, Default)]
struct Touch {
    reads: Vec<AtomId>,
    adds: Vec<AtomId>,
    dels: Vec<AtomId>,
    fluent_reads: Vec<FluentId>,
    fluent_writes: Vec<(FluentId, NumOp)>,
}

/// Everything a validation reads: the model, prepared once.
struct Model<'db> {
    domain: Unit<'db>,
    objects: Objects<'db>,
    preds: Interner,
    funcs: Interner,
    /// Actions by lower-case name.
    actions: FxHashMap<String, (Item<'db>, &'db Action)>,
    init: InitialState<'db>,
    atoms: Atoms,
    tils: Vec<Til<'db>>,
    goal: Option<(Item<'db>, &'db Gd)>,
    metric: Option<(Item<'db>, &'db Name, &'db NumExpr)>,
}

/// Where failures about the plan as a whole point: its first step.
fn plan_start(steps: &[TimedStep]) -> TextRange {
    steps.first().map_or_else(|| TextRange::empty(0.into()), |s| s.span)
}

fn invalid<'db>(failures: Vec<Failure<'db>>) -> Report<'db> {
    Report { valid: false, failures, makespan: 0.0, value: None, happenings: 0 }
}

pub(crate) fn validate<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    steps: &[TimedStep],
    options: &Options,
) -> Report<'db> {
    let at = plan_start(steps);
    if problem.kind(db) != UnitKind::Problem {
        return invalid(vec![Failure::new(
            codes::MODEL_NOT_VALIDATABLE,
            at,
            "the plan is not validated: its problem is not a `(define (problem …) …)`",
        )]);
    }
    let Some(domain) = domain_for(db, problem) else {
        let name = problem.domain_ref(db).clone().unwrap_or_default();
        return invalid(vec![
            Failure::new(
                codes::MODEL_NOT_VALIDATABLE,
                at,
                format!(
                    "the plan is not validated: the domain `{name}` of its problem is not among the files"
                ),
            )
            .hint("give the domain file with the problem"),
        ]);
    };
    if let Some(f) = unsupported_model(db, domain, problem, at) {
        return invalid(vec![f]);
    }
    if let Some((message, hint)) = super::model_errors(db, domain, problem) {
        return invalid(vec![Failure::new(codes::MODEL_NOT_VALIDATABLE, at, message).hint(hint)]);
    }
    let model = prepare(db, domain, problem);
    let mut failures = Vec::new();
    let grounded: Vec<Option<Step<'db>>> = {
        let mut untimed = 0.0;
        steps
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let time = s.time.unwrap_or_else(|| {
                    untimed += 1.0;
                    untimed
                });
                ground_step(db, &model, i, s, time, options, &mut failures)
            })
            .collect()
    };
    if failures.iter().any(|f| f.code.severity == Severity::Error) {
        return Report { valid: false, failures, makespan: 0.0, value: None, happenings: 0 };
    }
    // Every step that does not ground has an error: all are grounded here.
    let grounded: Vec<Step<'db>> = grounded.into_iter().flatten().collect();
    if grounded.len() != steps.len() {
        return Report { valid: false, failures, makespan: 0.0, value: None, happenings: 0 };
    }
    Run::new(&model, steps, &grounded, options, failures).execute()
}

/// A condition checked at an event, and how to call it.
struct Condition<'db> {
    gd: &'db Gd,
    label: &'static str,
}

/// The execution of a plan.
struct Run<'a, 'db> {
    model: &'a Model<'db>,
    plan: &'a [TimedStep],
    steps: &'a [Step<'db>],
    options: &'a Options,
    failures: Vec<Failure<'db>>,
    state: State,
    atom_last: FxHashMap<AtomId, Change<'db>>,
    fluent_last: FxHashMap<FluentId, Change<'db>>,
    init_facts: FxHashMap<AtomId, Loc<'db>>,
    init_fluents: FxHashMap<FluentId, Loc<'db>>,
    /// Per step: its conditional effects that span it.
    spanning: Vec<Vec<Spanning<'db>>>,
    /// What each executed event touched, with its happening.
    touched: Vec<(Event, usize, Touch)>,
}

impl<'a, 'db> Run<'a, 'db> {
    fn new(
        model: &'a Model<'db>,
        plan: &'a [TimedStep],
        steps: &'a [Step<'db>],
        options: &'a Options,
        failures: Vec<Failure<'db>>,
    ) -> Self {
        let mut state = State::new(model.atoms.clone(), Atoms::default());
        let mut init_facts = FxHashMap::default();
        for &(a, loc) in &model.init.facts {
            state.set(a, true);
            init_facts.entry(a).or_insert(loc);
        }
        let mut init_fluents = FxHashMap::default();
        let mut fluents: Vec<_> = model.init.fluents.iter().collect();
        fluents.sort_by(|a, b| a.0.cmp(b.0));
        for (key, &(v, loc)) in fluents {
            let f = state.fluent(key);
            state.set_value(f, Some(v));
            init_fluents.insert(f, loc);
        }
        Run {
            model,
            plan,
            steps,
            options,
            failures,
            state,
            atom_last: FxHashMap::default(),
            fluent_last: FxHashMap::default(),
            init_facts,
            init_fluents,
            spanning: vec![Vec::new(); steps.len()],
            touched: Vec::new(),
        }
    }

    fn world(&self) -> World<'a, 'db> {
        World { objects: &self.model.objects, preds: &self.model.preds, funcs: &self.model.funcs }
    }

    fn has_errors(&self) -> usize {
        self.failures.iter().filter(|f| f.code.severity == Severity::Error).count()
    }

    /// Every event, in time order (plan order among equal times, timed
    /// initial literals last); literals after the plan's last event are left out.
    fn events(&self, makespan: f64) -> Vec<Event> {
        let mut events = Vec::with_capacity(self.steps.len() * 2 + self.model.tils.len());
        for (i, s) in self.steps.iter().enumerate() {
            if s.duration.is_some() {
                events.push(Event { time: s.time, actor: Actor::Start(i) });
                events.push(Event { time: s.end(), actor: Actor::End(i) });
            } else {
                events.push(Event { time: s.time, actor: Actor::Instant(i) });
            }
        }
        for (j, til) in self.model.tils.iter().enumerate() {
            if til.time.is_finite() && til.time <= makespan {
                events.push(Event { time: til.time, actor: Actor::Til(j) });
            }
        }
        events.sort_by(|a, b| a.time.total_cmp(&b.time));
        events
    }

    fn execute(mut self) -> Report<'db> {
        let makespan = self.steps.iter().map(Step::end).fold(0.0, f64::max);
        let events = self.events(makespan);
        // VAL's happenings: every event no later than tolerance/10 after the
        // happening's first event (`after` in VAL's Plan.h).
        let mut happenings: Vec<std::ops::Range<usize>> = Vec::new();
        let mut start = 0;
        for k in 1..=events.len() {
            if k == events.len() || events[k].time > events[start].time + self.options.tolerance / 10.0 {
                happenings.push(start..k);
                start = k;
            }
        }
        let mut active: Vec<usize> = Vec::new();
        let mut executed = 0;
        let mut stopped = false;
        for (h, range) in happenings.iter().enumerate() {
            let before = self.has_errors();
            self.happening(h, &events[range.clone()], &mut active);
            executed += 1;
            if self.has_errors() > before && !self.options.keep_going {
                stopped = true;
                break;
            }
        }
        if !stopped {
            self.check_goal(makespan);
        }
        self.close_happenings();
        let valid = self.has_errors() == 0;
        let value = if valid { self.value(makespan) } else { None };
        Report { valid, failures: self.failures, makespan, value, happenings: executed }
    }

    /// The conditions checked at an event.
    fn conditions(&self, a: Actor) -> Vec<Condition<'db>> {
        let Some(i) = a.step() else { return Vec::new() };
        let Some(pre) = &self.steps[i].action.precondition else { return Vec::new() };
        let parts = split_timed(pre);
        let (list, label) = match a {
            Actor::Start(_) => (parts.start, "`at start` condition"),
            Actor::End(_) => (parts.end, "`at end` condition"),
            Actor::Instant(_) => (vec![pre], "precondition"),
            Actor::Til(_) => (Vec::new(), ""),
        };
        list.into_iter().map(|gd| Condition { gd, label }).collect()
    }

    /// The duration constraints checked at an event: `(at end …)` ones at
    /// the end, the others at the start.
    fn duration_constraints(&self, a: Actor) -> Vec<&'db Gd> {
        let (i, at_end) = match a {
            Actor::Start(i) => (i, false),
            Actor::End(i) => (i, true),
            _ => return Vec::new(),
        };
        let Some(d) = &self.steps[i].action.duration else { return Vec::new() };
        let parts = split_timed(d);
        if at_end {
            parts.end
        } else {
            let mut v = parts.start;
            v.extend(parts.untimed);
            v
        }
    }
}
