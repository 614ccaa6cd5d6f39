//! The happenings of a timed plan and what VAL checks at each (see the
//! module documentation of [`super`] for the semantics).
//!
//! Execution keeps, besides the state, where each atom and fluent last
//! changed (which step, at what time, by which effect), so that a false
//! condition names its culprit: "deleted at 120.0 by the start of step 9
//! `(move r1 w5 w7)`".

use rowan::TextRange;
use rustc_hash::FxHashMap;

use super::eval::{
    Binding, Changes, ErrorKind, Eval, EvalError, FluentId, GroundWorld, Key, NumOp, Phase, Reads, Spanning,
    State, Why, World, fmt_num, split_timed,
};
use super::{Failure, Options, Report, TimedStep};
use crate::db::{Db, Item, Section, Unit, UnitKind, lower_item};
use crate::diagnostic::{Code, Severity, codes};
use crate::model::{Action, ActionKind, CmpOp, Gd, InitElement, ItemData, Name, NumExpr, Term};
use crate::semantics::check::{domain_for, gd_span, suggest};
use crate::semantics::symbols::{Loc, domain_symbols, problem_symbols, type_set};
use crate::verify::state::{AtomId, Atoms, InitialState, Interner, ObjId, Objects, constant};

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
            b.push(&p.name.key, o);
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

enum TilChange {
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

/// PDDL+, derived predicates, PDDL 3 constraints: what this validator does not check.
fn unsupported_model<'db>(
    db: &'db dyn Db,
    domain: Unit<'db>,
    problem: Unit<'db>,
    at: TextRange,
) -> Option<Failure<'db>> {
    for unit in [domain, problem] {
        for &item in unit.items(db) {
            let what = match &lower_item(db, item).data {
                ItemData::Action(a) if matches!(a.kind, ActionKind::Process | ActionKind::Event) => {
                    let kind = if a.kind == ActionKind::Process { "process" } else { "event" };
                    Some((
                        format!(
                            "the domain has the PDDL+ {kind} `{}`: what processes and events do over time is not checked",
                            a.name.text
                        ),
                        a.name.span,
                    ))
                }
                ItemData::Action(a) if continuous(a).is_some() => Some((
                    format!(
                        "the action `{}` has continuous effects (`#t`): change over time is not simulated",
                        a.name.text
                    ),
                    continuous(a).unwrap_or(a.name.span),
                )),
                ItemData::Derived(atom, _, _) => Some((
                    format!(
                        "the domain has the derived predicate `{}`: derived predicates are not evaluated",
                        atom.pred.text
                    ),
                    atom.pred.span,
                )),
                ItemData::Constraints(g) => {
                    Some(("PDDL 3 `:constraints` are not checked".to_string(), gd_span(g)))
                }
                _ => None,
            };
            if let Some((message, span)) = what {
                return Some(
                    Failure::new(
                        codes::UNSUPPORTED_IN_PLAN,
                        at,
                        format!("the plan cannot be validated: {message}"),
                    )
                    .model(Loc { item, span }, "not supported in plan validation")
                    .hint("validate this plan with VAL, which simulates PDDL+ and derived predicates"),
                );
            }
        }
    }
    None
}

/// Where an action uses `#t` (continuous change), if it does.
fn continuous(a: &Action) -> Option<TextRange> {
    fn expr(e: &NumExpr) -> Option<TextRange> {
        match e {
            NumExpr::Special(s, span) if &**s == "#t" => Some(*span),
            NumExpr::Op(_, args, _) => args.iter().find_map(expr),
            _ => None,
        }
    }
    fn gd(g: &Gd) -> Option<TextRange> {
        match g {
            Gd::Compare(_, l, r, _) => expr(l).or_else(|| expr(r)),
            Gd::Not(x, _)
            | Gd::Timed(_, x, _)
            | Gd::Preference(_, x, _)
            | Gd::Forall(_, x, _)
            | Gd::Exists(_, x, _) => gd(x),
            Gd::And(xs, _) | Gd::Or(xs, _) => xs.iter().find_map(gd),
            Gd::Imply(x, y, _) => gd(x).or_else(|| gd(y)),
            _ => None,
        }
    }
    fn effect(e: &crate::model::Effect) -> Option<TextRange> {
        use crate::model::Effect;
        match e {
            Effect::Numeric(_, _, v, _) => expr(v),
            Effect::And(es, _) => es.iter().find_map(effect),
            Effect::Forall(_, x, _) | Effect::Timed(_, x, _) => effect(x),
            Effect::When(c, x, _) => gd(c).or_else(|| effect(x)),
            Effect::Add(_) | Effect::Del(..) => None,
        }
    }
    a.effect.as_ref().and_then(effect).or_else(|| a.precondition.as_ref().and_then(gd))
}

/// Builds the ground vocabulary, the initial state and the actions.
fn prepare<'db>(db: &'db dyn Db, domain: Unit<'db>, problem: Unit<'db>) -> Model<'db> {
    let dom = domain_symbols(db, domain);
    let prob = problem_symbols(db, problem);
    let objects = Objects::new(dom, prob);
    let GroundWorld { preds, funcs, atoms, init } = GroundWorld::new(db, domain, problem, &objects);
    let mut actions = FxHashMap::default();
    for &item in domain.items(db) {
        if let ItemData::Action(a) = &lower_item(db, item).data {
            actions.entry(a.name.key.to_string()).or_insert((item, &**a));
        }
    }
    let mut tils = Vec::new();
    let mut goal = None;
    let mut metric = None;
    for &item in problem.items(db) {
        match (&lower_item(db, item).data, item.section(db)) {
            (ItemData::Init(elements), Section::Init) => {
                for e in elements {
                    if let InitElement::Timed(time, inner, span) = e
                        && let Some(change) = til_change(inner, &objects, &preds, &funcs)
                    {
                        tils.push(Til { time: time.value(), change, loc: Loc { item, span: *span } });
                    }
                }
            }
            (ItemData::Goal(g), _) => goal = Some((item, g)),
            (ItemData::Metric(dir, e), _) => metric = Some((item, dir, e)),
            _ => {}
        }
    }
    Model { domain, objects, preds, funcs, actions, init, atoms, tils, goal, metric }
}

fn til_change(
    e: &InitElement,
    objects: &Objects<'_>,
    preds: &Interner,
    funcs: &Interner,
) -> Option<TilChange> {
    let key = |names: &Interner, name: &Name, args: &[Term]| -> Option<Key> {
        let mut k = Key::new();
        k.push(names.get(&name.key)?);
        for t in args {
            match t {
                Term::Const(n) => k.push(objects.id(&n.key)?),
                _ => return None,
            }
        }
        Some(k)
    };
    match e {
        InitElement::Fact(a) => Some(TilChange::Atom(key(preds, &a.pred, &a.args)?, true)),
        InitElement::NotFact(a, _) => Some(TilChange::Atom(key(preds, &a.pred, &a.args)?, false)),
        InitElement::Assign(f, v, _) => Some(TilChange::Fluent(key(funcs, &f.func, &f.args)?, constant(v)?)),
        _ => None,
    }
}

/// Lower case; in lenient mode, `_` as `-`.
fn normalize(s: &str, lenient: bool) -> String {
    let k = s.to_ascii_lowercase();
    if lenient { k.replace('_', "-") } else { k }
}

/// Resolves a step to its action and objects, reporting what does not resolve.
fn ground_step<'db>(
    db: &'db dyn Db,
    model: &Model<'db>,
    i: usize,
    s: &TimedStep,
    time: f64,
    options: &Options,
    out: &mut Vec<Failure<'db>>,
) -> Option<Step<'db>> {
    let n = i + 1;
    let key = normalize(&s.name, options.lenient);
    let found = model.actions.get(&key).copied().or_else(|| {
        options
            .lenient
            .then(|| model.actions.iter().find(|(k, _)| normalize(k, true) == key).map(|(_, v)| *v))
            .flatten()
    });
    let Some((item, action)) = found else {
        let dom = domain_symbols(db, model.domain);
        let mut f = Failure::new(
            codes::UNKNOWN_ACTION_IN_PLAN,
            s.name_span,
            format!("step {n} `{}`: the domain has no action `{}`", s.text(), s.name),
        )
        .at_step(i);
        if let Some(task) = dom.tasks.get(key.as_str()) {
            f.message = format!(
                "step {n} `{}`: `{}` is a task, not an action; a temporal plan lists actions only",
                s.text(),
                s.name
            );
            f = f.model(task.loc, "the task is declared here");
        } else if let Some(best) = suggest(&key, model.actions.keys().map(String::as_str)) {
            f = f.hint(format!("did you mean `{best}`?")).edit(s.name_span, best);
        }
        out.push(f);
        return None;
    };
    let decl = Loc { item, span: action.name.span };
    if s.args.len() != action.params.len() {
        let params: Vec<String> = action.params.iter().map(|p| p.name.text.to_string()).collect();
        out.push(
            Failure::new(
                codes::STEP_ARITY,
                s.span,
                format!(
                    "step {n} `{}` gives `{}` {} argument{}, but it takes {} ({})",
                    s.text(),
                    action.name.text,
                    s.args.len(),
                    if s.args.len() == 1 { "" } else { "s" },
                    action.params.len(),
                    params.join(" ")
                ),
            )
            .at_step(i)
            .model(decl, "the action is declared here"),
        );
        return None;
    }
    let dom = domain_symbols(db, model.domain);
    let mut args = Vec::with_capacity(s.args.len());
    let mut ok = true;
    for (k, (arg, param)) in s.args.iter().zip(&action.params).enumerate() {
        let span = s.arg_spans.get(k).copied().unwrap_or(s.span);
        let akey = normalize(arg, options.lenient);
        let id = model.objects.id(&akey).or_else(|| {
            options
                .lenient
                .then(|| {
                    (0..model.objects.len() as ObjId)
                        .find(|&o| normalize(model.objects.name(o), true) == akey)
                })
                .flatten()
        });
        let wanted = type_set(&param.ty);
        let Some(id) = id else {
            let candidates = model.objects.of_types(&wanted);
            let names: Vec<&str> = candidates.iter().map(|&o| model.objects.name(o)).collect();
            let mut f = Failure::new(
                codes::UNKNOWN_OBJECT_IN_PLAN,
                span,
                format!(
                    "step {n} `{}`: `{arg}` is not an object of the problem or a constant of the domain",
                    s.text()
                ),
            )
            .at_step(i);
            if let Some(best) = suggest(&akey, names.into_iter()) {
                f = f.hint(format!("did you mean `{best}`?")).edit(span, best);
            }
            out.push(f);
            ok = false;
            continue;
        };
        // A parameter's type that is not declared was reported by the checks.
        let fits = wanted.iter().any(|t| model.objects.has_type(id, t) || !dom.is_type(t));
        if !fits {
            let declared = model.objects.types(id).first().map_or("object", |t| t.as_str());
            let declared = declared_type(db, model, id).unwrap_or_else(|| declared.to_string());
            let mut f = Failure::new(
                codes::STEP_TYPE_MISMATCH,
                span,
                format!(
                    "step {n} `{}`: `{arg}` is of type `{declared}`, but parameter `{}` of `{}` has type `{}`",
                    s.text(),
                    param.name.text,
                    action.name.text,
                    wanted.join(" or ")
                ),
            )
            .at_step(i)
            .model(Loc { item, span: param.name.span }, "the parameter is declared here");
            if let Some(loc) = model.objects.loc(id) {
                f = f.model(loc, format!("`{arg}` is declared here"));
            }
            out.push(f);
            ok = false;
            continue;
        }
        args.push(id);
    }
    let timing = |message: String| Failure::new(codes::INVALID_STEP_TIMING, s.span, message).at_step(i);
    if !time.is_finite() || time < 0.0 {
        out.push(timing(format!("step {n} `{}` starts at {time}: a time is a number, 0 or more", s.text())));
        ok = false;
    }
    let duration = match (action.kind, s.duration) {
        (ActionKind::Durative, None) => {
            out.push(
                timing(format!("step {n} `{}` is a durative action without a duration", s.text()))
                    .model(decl, "a durative action")
                    .hint(format!("give its duration after it: `{time:.3}: {} [d]`", s.text())),
            );
            ok = false;
            None
        }
        (ActionKind::Durative, Some(d)) if !d.is_finite() || d < 0.0 => {
            out.push(timing(format!(
                "step {n} `{}` has the duration {d}: a duration is a number, 0 or more",
                s.text()
            )));
            ok = false;
            None
        }
        (ActionKind::Durative, Some(d)) => Some(d),
        (_, Some(d)) => {
            let mut f = Failure::new(
                codes::DURATION_IGNORED,
                s.duration_span.unwrap_or(s.span),
                format!(
                    "step {n} `{}` is an instantaneous action: its duration {} is ignored",
                    s.text(),
                    fmt_num(d)
                ),
            )
            .at_step(i)
            .model(decl, "an `:action`, not a `:durative-action`")
            .hint("remove the duration");
            if let Some(span) = s.duration_span {
                f = f.edit(span, "");
            }
            out.push(f);
            None
        }
        (_, None) => None,
    };
    ok.then_some(Step { item, action, args, time, duration })
}

/// The type an object is declared with, as written in `:objects` or `:constants`.
fn declared_type(db: &dyn Db, model: &Model<'_>, id: ObjId) -> Option<String> {
    let name = model.objects.name(id);
    let dom = domain_symbols(db, model.domain);
    let decl = dom.constants.get(name).map(|d| d.ty.join(" or "));
    decl.or_else(|| {
        let loc = model.objects.loc(id)?;
        let unit = crate::semantics::check::unit_of(db, loc.item)?;
        problem_symbols(db, unit).objects.get(name).map(|d| d.ty.join(" or "))
    })
}

/// How two events of a happening interfere.
#[derive(Debug, Clone, Copy)]
enum Interference {
    /// `writer` adds (or deletes) an atom that `reader` reads.
    AtomRead {
        reader: usize,
        writer: usize,
        atom: AtomId,
        added: bool,
    },
    AtomAddDel {
        adder: usize,
        deleter: usize,
        atom: AtomId,
    },
    FluentRead {
        reader: usize,
        writer: usize,
        fluent: FluentId,
        op: NumOp,
    },
    FluentWrite {
        first: usize,
        second: usize,
        fluent: FluentId,
        ops: (NumOp, NumOp),
    },
}

impl Interference {
    fn events(self) -> (usize, usize) {
        let (a, b) = match self {
            Interference::AtomRead { reader, writer, .. }
            | Interference::FluentRead { reader, writer, .. } => (reader, writer),
            Interference::AtomAddDel { adder, deleter, .. } => (adder, deleter),
            Interference::FluentWrite { first, second, .. } => (first, second),
        };
        (a.min(b), a.max(b))
    }
}

/// The interfering pairs among events (by index into `touches`), each pair
/// once, with every reason found (VAL's rules of ownership).
fn interferences(touches: &[&Touch]) -> Vec<Vec<Interference>> {
    #[derive(Clone, Copy, PartialEq)]
    enum Use {
        Read,
        Add,
        Del,
    }
    let mut atoms: FxHashMap<AtomId, Vec<(usize, Use)>> = FxHashMap::default();
    let mut fluents: FxHashMap<FluentId, Vec<(usize, Option<NumOp>)>> = FxHashMap::default();
    for (e, t) in touches.iter().enumerate() {
        let mut note = |a: AtomId, u: Use| {
            let uses = atoms.entry(a).or_default();
            if !uses.contains(&(e, u)) {
                uses.push((e, u));
            }
        };
        t.reads.iter().for_each(|&a| note(a, Use::Read));
        t.adds.iter().for_each(|&a| note(a, Use::Add));
        t.dels.iter().for_each(|&a| note(a, Use::Del));
        for &f in &t.fluent_reads {
            fluents.entry(f).or_default().push((e, None));
        }
        for &(f, op) in &t.fluent_writes {
            fluents.entry(f).or_default().push((e, Some(op)));
        }
    }
    let mut found: Vec<Vec<Interference>> = Vec::new();
    let mut push = |i: Interference| match found.iter_mut().find(|x| x[0].events() == i.events()) {
        Some(reasons) => reasons.push(i),
        None => found.push(vec![i]),
    };
    let mut atom_ids: Vec<&AtomId> = atoms.keys().collect();
    atom_ids.sort_unstable();
    for atom in atom_ids {
        let uses = &atoms[atom];
        for &(x, ux) in uses {
            for &(y, uy) in uses {
                if x == y {
                    continue;
                }
                match (ux, uy) {
                    (Use::Read, Use::Add | Use::Del) => push(Interference::AtomRead {
                        reader: x,
                        writer: y,
                        atom: *atom,
                        added: uy == Use::Add,
                    }),
                    (Use::Add, Use::Del) => {
                        push(Interference::AtomAddDel { adder: x, deleter: y, atom: *atom })
                    }
                    _ => {}
                }
            }
        }
    }
    let mut fluent_ids: Vec<&FluentId> = fluents.keys().collect();
    fluent_ids.sort_unstable();
    for fluent in fluent_ids {
        let uses = &fluents[fluent];
        for (k, &(x, ox)) in uses.iter().enumerate() {
            for &(y, oy) in &uses[k + 1..] {
                if x == y {
                    continue;
                }
                match (ox, oy) {
                    (None, Some(op)) => {
                        push(Interference::FluentRead { reader: x, writer: y, fluent: *fluent, op })
                    }
                    (Some(op), None) => {
                        push(Interference::FluentRead { reader: y, writer: x, fluent: *fluent, op })
                    }
                    (Some(a), Some(b)) if !(a.is_additive() && b.is_additive()) => {
                        push(Interference::FluentWrite { first: x, second: y, fluent: *fluent, ops: (a, b) })
                    }
                    _ => {}
                }
            }
        }
    }
    found
}

/// The reason to tell of two events' interference: preferably the earlier
/// event changing what the later one reads (a cause and its effect).
fn causal(reasons: &[Interference], event: &dyn Fn(usize) -> Event) -> Interference {
    let earlier =
        |a: usize, b: usize| event(a).time < event(b).time || (event(a).time == event(b).time && a < b);
    reasons
        .iter()
        .copied()
        .find(|r| match *r {
            Interference::AtomRead { reader, writer, .. }
            | Interference::FluentRead { reader, writer, .. } => earlier(writer, reader),
            _ => false,
        })
        .unwrap_or(reasons[0])
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

    fn step_text(&self, i: usize) -> String {
        format!("step {} `{}`", i + 1, self.plan[i].text())
    }

    /// "the start of step 3 `(drive t a b)`", "the timed initial literal at 10.0".
    fn actor_text(&self, a: Actor) -> String {
        match a {
            Actor::Start(i) => format!("the start of {}", self.step_text(i)),
            Actor::End(i) => format!("the end of {}", self.step_text(i)),
            Actor::Instant(i) => self.step_text(i),
            Actor::Til(j) => format!("the timed initial literal at {}", fmt_num(self.model.tils[j].time)),
        }
    }

    /// "the start of step 3", "the timed initial literal at 10.0".
    fn actor_short(&self, a: Actor) -> String {
        match a {
            Actor::Start(i) => format!("the start of step {}", i + 1),
            Actor::End(i) => format!("the end of step {}", i + 1),
            Actor::Instant(i) => format!("step {}", i + 1),
            Actor::Til(_) => self.actor_text(a),
        }
    }

    /// "step 3 `(drive t a b)` at 3.0", "step 3 `(drive t a b)`, ending at 13.0".
    fn event_head(&self, e: Event) -> String {
        match e.actor {
            Actor::End(i) => format!("{}, ending at {}", self.step_text(i), fmt_num(e.time)),
            Actor::Start(i) | Actor::Instant(i) => format!("{} at {}", self.step_text(i), fmt_num(e.time)),
            Actor::Til(_) => self.actor_text(e.actor),
        }
    }

    /// Where an event points in the plan: its step.
    fn event_span(&self, a: Actor) -> TextRange {
        match a.step() {
            Some(i) => self.plan[i].span,
            None => plan_start(self.plan),
        }
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

/// A culprit for a false condition: what to add to the message, where.
#[derive(Default)]
struct Culprit<'db> {
    text: String,
    plan: Vec<(TextRange, String)>,
    model: Vec<(Loc<'db>, String)>,
    hint: Option<String>,
}

impl<'a, 'db> Run<'a, 'db> {
    /// A time for an edit of the plan: enough decimals for the tolerance.
    fn edit_time(&self, t: f64) -> String {
        let decimals = (-self.options.tolerance.log10()).ceil().clamp(3.0, 9.0) as usize;
        format!("{t:.decimals$}")
    }

    /// The item of an event's action, or of the timed literal.
    fn effect_loc(&self, a: Actor, span: TextRange) -> Loc<'db> {
        match a {
            Actor::Til(j) => self.model.tils[j].loc,
            Actor::Start(i) | Actor::End(i) | Actor::Instant(i) => self.steps[i].loc(span),
        }
    }

    fn happening(&mut self, h: usize, events: &[Event], active: &mut Vec<usize>) {
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
                        TilChange::Fluent(key, v) => changes[k].updates.push(super::eval::Update {
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
    fn apply(&mut self, events: &[Event], changes: &[Changes]) {
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
    fn touch(&mut self, reads: &Reads, ch: &Changes) -> Touch {
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
    fn check_invariants(&mut self, time: f64, active: &mut Vec<usize>) {
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

    fn violated_invariant(&self, i: usize, time: f64, why: &Why) -> Failure<'db> {
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
    fn culprit(&self, why: &Why, when: f64) -> Culprit<'db> {
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
                            ", or move step {} so that it does not {} it before {}",
                            i + 1,
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
                let value = f.and_then(|f| self.state.value(f)).map_or("no value".to_string(), fmt_num);
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
    fn false_condition(&self, e: Event, label: &str, why: &Why, code: &'static Code) -> Failure<'db> {
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

    /// Moves a step so that its event `m` happens the tolerance after `anchor`.
    fn separate(&self, f: Failure<'db>, m: Event, anchor: Event) -> Failure<'db> {
        let Some(i) = m.actor.step() else { return f };
        let tol = self.options.tolerance;
        let new_event = anchor.time + tol;
        let new_start = self.steps[i].time + (new_event - m.time);
        let whom = match anchor.actor {
            Actor::Til(_) => "the timed initial literal".to_string(),
            a => format!("step {}", a.step().map_or(0, |j| j + 1)),
        };
        let hint = match m.actor {
            Actor::End(_) => format!(
                "separate them by at least the tolerance ({tol}): step {} must end at {} or later, {} after {whom}; start it at {}",
                i + 1,
                fmt_num(new_event),
                tol,
                self.edit_time(new_start)
            ),
            _ => format!(
                "separate them by at least the tolerance ({tol}): start step {} at {} or later",
                i + 1,
                self.edit_time(new_start)
            ),
        };
        let f = f.hint(hint);
        match self.plan[i].time_span {
            Some(span) => f.edit(span, self.edit_time(new_start)),
            None => f,
        }
    }

    /// Why two events of one happening with different times are one happening.
    fn grouped(&self, early: Event, late: Event) -> String {
        if late.time > early.time {
            format!(
                ", only {} earlier: at tolerance {}, events no more than {} apart are one happening, whose conditions are checked before its effects",
                fmt_num(late.time - early.time),
                self.options.tolerance,
                fmt_num(self.options.tolerance / 10.0)
            )
        } else {
            ", in the same happening: its conditions are checked before its effects".into()
        }
    }

    /// A false condition that another event of the same happening (`o`, by
    /// the effect at `effect`) makes as needed: `verb`, "makes it true";
    /// `note`, the same for the other step, "makes `(p)` true".
    fn too_close(
        &self,
        e: Event,
        o: Event,
        label: &str,
        why: &Why,
        effect: TextRange,
        (verb, note): (&str, &str),
    ) -> Failure<'db> {
        let mut f = Failure::new(
            codes::MUTEX_HAPPENINGS,
            self.event_span(e.actor),
            format!(
                "{}: {label} {}: {} {verb} at {}{}",
                self.event_head(e),
                why.text,
                self.actor_text(o.actor),
                fmt_num(o.time),
                self.grouped(o, e)
            ),
        );
        if let Some(i) = e.actor.step() {
            f = f.at_step(i).model(self.steps[i].loc(why.span), format!("the {label}"));
        }
        if let Some(i) = o.actor.step() {
            f = f.plan(self.plan[i].span, format!("{note} at {}", fmt_num(o.time)));
        }
        f = f.model(self.effect_loc(o.actor, effect), "the effect");
        self.separate(f, e, o)
    }

    /// Two interfering events of one happening.
    fn mutex(&self, inter: Interference, event: &dyn Fn(usize) -> Event) -> Failure<'db> {
        let (a, b) = inter.events();
        let (early, late) = (event(a), event(b));
        // Move a step: the later event's, unless it is a timed literal.
        let (moved, anchor) = if late.actor.step().is_some() { (late, early) } else { (early, late) };
        let what = self.interference_text(inter, event);
        let same_step = early.actor.step().is_some() && early.actor.step() == late.actor.step();
        let message = format!(
            "{} interferes with {} at {}{}: {what}",
            self.event_head(moved),
            self.actor_text(anchor.actor),
            fmt_num(anchor.time),
            if late.time > early.time { self.grouped(early, late) } else { String::new() }
        );
        let mut f = Failure::new(codes::MUTEX_HAPPENINGS, self.event_span(moved.actor), message);
        if let Some(i) = moved.actor.step() {
            f = f.at_step(i);
        }
        if let Some(i) = anchor.actor.step().filter(|_| !same_step) {
            f = f.plan(self.plan[i].span, format!("interferes at {}", fmt_num(anchor.time)));
        }
        if same_step {
            let i = moved.actor.step().unwrap_or(0);
            let d = self.options.tolerance;
            let mut f = f
                .hint(format!("its start and end interfere: give step {} a duration of at least {d}", i + 1));
            if let Some(span) = self.plan[i].duration_span {
                f = f.edit(span, format!("[{}]", self.edit_time(d)));
            }
            return f;
        }
        self.separate(f, moved, anchor)
    }

    /// "the start of step 2 `(drive …)` deletes `(at t a)`, which step 5 `(load …)` reads".
    fn interference_text(&self, inter: Interference, event: &dyn Fn(usize) -> Event) -> String {
        let world = self.world();
        let who = |k: usize| self.actor_short(event(k).actor);
        let atom = |a: AtomId| world.show_atom(&self.atom_key(a));
        let fluent = |f: FluentId| world.show_fluent(&self.fluent_key(f));
        match inter {
            Interference::AtomRead { reader, writer, atom: a, added } => format!(
                "{} {} `{}`, which {} reads",
                who(writer),
                if added { "adds" } else { "deletes" },
                atom(a),
                who(reader)
            ),
            Interference::AtomAddDel { adder, deleter, atom: a } => {
                format!("{} adds `{}`, which {} deletes", who(adder), atom(a), who(deleter))
            }
            Interference::FluentRead { reader, writer, fluent: fl, op } => {
                format!(
                    "{} changes `{}` (`{}`), which {} reads",
                    who(writer),
                    fluent(fl),
                    op.name(),
                    who(reader)
                )
            }
            Interference::FluentWrite { first, second, fluent: fl, ops } => format!(
                "{} and {} both change `{}` (`{}` and `{}`), which do not commute",
                who(first),
                who(second),
                fluent(fl),
                ops.0.name(),
                ops.1.name()
            ),
        }
    }

    fn atom_key(&self, a: AtomId) -> Key {
        let mut k = Key::new();
        k.push(self.state.atoms.pred(a));
        k.extend_from_slice(self.state.atoms.args(a));
        k
    }

    fn fluent_key(&self, f: FluentId) -> Key {
        let mut k = Key::new();
        k.push(self.state.fluents.pred(f));
        k.extend_from_slice(self.state.fluents.args(f));
        k
    }

    /// A formula of an event that cannot be evaluated.
    fn eval_failure(&self, a: Actor, time: f64, what: &str, err: EvalError) -> Failure<'db> {
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

    /// Checks a duration constraint of a step; `None` when it holds.
    fn check_duration(
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
            Gd::Compare(op, NumExpr::Duration(_), r, _) => (*op, r),
            Gd::Compare(op, l, NumExpr::Duration(_), _) => (flip(*op), l),
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
        let need = match op {
            CmpOp::Eq => format!("{} (within the tolerance {tol})", fmt_num(v)),
            CmpOp::Ge => format!("at least {}", fmt_num(v)),
            CmpOp::Le => format!("at most {}", fmt_num(v)),
            CmpOp::Gt => format!("more than {}", fmt_num(v)),
            CmpOp::Lt => format!("less than {}", fmt_num(v)),
        };
        let (hint, target) = match op {
            CmpOp::Eq => (format!("set the duration to {}", fmt_num(v)), Some(v)),
            CmpOp::Ge => {
                (format!("increase the duration by at least {}, to {}", fmt_num(v - d), fmt_num(v)), Some(v))
            }
            CmpOp::Le => {
                (format!("decrease the duration by at least {}, to {}", fmt_num(d - v), fmt_num(v)), Some(v))
            }
            CmpOp::Gt => (format!("make the duration more than {}", fmt_num(v)), None),
            CmpOp::Lt => (format!("make the duration less than {}", fmt_num(v)), None),
        };
        let shown = eval.show_gd(g, b);
        let mut f = Failure::new(
            codes::DURATION_VIOLATED,
            self.plan[i].duration_span.unwrap_or(self.plan[i].span),
            format!(
                "{} lasts {}, but its duration constraint `{shown}` requires {need}",
                self.step_text(i),
                fmt_num(d)
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

    fn check_goal(&mut self, makespan: f64) {
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

    /// W0411: interfering events of different happenings closer than the
    /// tolerance (VAL accepts them; PDDL 2.1's ε-separation does not).
    fn close_happenings(&mut self) {
        let tol = self.options.tolerance;
        let touched = &self.touched;
        // The events of each happening.
        let mut ranges: Vec<std::ops::Range<usize>> = Vec::new();
        for (k, (_, h, _)) in touched.iter().enumerate() {
            match ranges.last_mut() {
                Some(r) if touched[r.start].1 == *h => r.end = k + 1,
                _ => ranges.push(k..k + 1),
            }
        }
        let mut warned: Vec<(usize, usize)> = Vec::new();
        let mut out = Vec::new();
        for (x, rx) in ranges.iter().enumerate() {
            let last = touched[rx.clone()].iter().map(|t| t.0.time).fold(f64::MIN, f64::max);
            for ry in &ranges[x + 1..] {
                if touched[ry.start].0.time - last >= tol {
                    break;
                }
                let idx: Vec<usize> = rx.clone().chain(ry.clone()).collect();
                let refs: Vec<&Touch> = idx.iter().map(|&k| &touched[k].2).collect();
                let event = |k: usize| touched[idx[k]].0;
                for reasons in interferences(&refs) {
                    let inter = causal(&reasons, &event);
                    let (a, b) = inter.events();
                    let (ea, eb) = (event(a), event(b));
                    let (Some(sa), Some(sb)) = (ea.actor.step(), eb.actor.step()) else { continue };
                    let cross = (idx[a] < ry.start) != (idx[b] < ry.start);
                    if !cross || sa == sb || (eb.time - ea.time).abs() >= tol - 1e-9 {
                        continue;
                    }
                    let pair = (sa.min(sb), sa.max(sb));
                    if warned.contains(&pair) {
                        continue;
                    }
                    warned.push(pair);
                    let (early, late) = if ea.time <= eb.time { (ea, eb) } else { (eb, ea) };
                    let what = self.interference_text(inter, &event);
                    let f = Failure::new(
                        codes::CLOSE_HAPPENINGS,
                        self.event_span(late.actor),
                        format!(
                            "{} interferes with {}, only {} earlier: {what}; VAL accepts it (more than tolerance/10 apart, two happenings), but PDDL 2.1 asks interfering happenings to be at least the tolerance ({tol}) apart",
                            self.event_head(late),
                            self.actor_text(early.actor),
                            fmt_num(late.time - early.time)
                        ),
                    )
                    .at_step(late.actor.step().unwrap_or(0))
                    .plan(self.event_span(early.actor), format!("interferes at {}", fmt_num(early.time)));
                    out.push(self.separate(f, late, early));
                }
            }
        }
        self.failures.extend(out);
    }

    /// The plan's value: the metric, or the makespan without one.
    fn value(&mut self, makespan: f64) -> Option<f64> {
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

#[cfg(test)]
mod tests {
    use super::super::{Options, TimedStep, validate_temporal};
    use crate::AnalysisHost;
    use crate::db::file_units;

    const DOMAIN: &str = "(define (domain lights)
      (:requirements :typing :durative-actions :fluents :timed-initial-literals :negative-preconditions)
      (:types room)
      (:predicates (lit ?r - room) (open ?r - room) (busy))
      (:functions (power) (uses ?r - room))
      (:durative-action light :parameters (?r - room) :duration (= ?duration 2)
        :condition (and (at start (not (lit ?r))) (over all (open ?r)))
        :effect (and (at end (lit ?r)) (at start (increase (power) 1))))
      (:durative-action work :parameters (?r - room) :duration (<= ?duration 5)
        :condition (and (at start (lit ?r)) (over all (lit ?r)) (at end (open ?r)))
        :effect (and (at start (busy)) (at end (not (busy))) (at end (increase (uses ?r) ?duration))))
      (:action close :parameters (?r - room) :precondition (open ?r) :effect (not (open ?r)))
      (:action all-off :parameters () :effect (and (assign (power) 0) (forall (?r - room) (not (lit ?r)))))
      (:action reset :parameters () :effect (assign (power) 0)))";

    const PROBLEM: &str = "(define (problem p) (:domain lights)
      (:objects r1 r2 - room)
      (:init (open r1) (open r2) (= (power) 0) (= (uses r1) 0) (at 10 (not (open r1))) (at 20 (open r1)))
      (:goal (lit r1))
      (:metric minimize (+ (total-time) (power))))";

    /// Steps from `[time:] (name args…) [[duration]]` lines, without spans.
    fn steps(plan: &str) -> Vec<TimedStep> {
        plan.lines()
            .filter(|l| l.contains('('))
            .map(|l| {
                let (head, rest) = l.split_once('(').expect("a step");
                let (call, tail) = rest.split_once(')').expect("a closed step");
                let words: Vec<&str> = call.split_whitespace().collect();
                let time = head.trim().trim_end_matches(':').trim().parse().ok();
                let duration = tail.trim().trim_start_matches('[').trim_end_matches(']').parse().ok();
                TimedStep::new(words[0], &words[1..], time, duration, Default::default())
            })
            .collect()
    }

    /// The verdict, the value and the failures (`CODE message`).
    fn run(plan: &str, options: Options) -> (bool, Option<f64>, Vec<String>) {
        let mut host = AnalysisHost::new();
        host.set_file_text("m/domain.pddl", DOMAIN);
        let p = host.set_file_text("m/problem.pddl", PROBLEM);
        let db = host.db();
        let report = validate_temporal(db, file_units(db, p)[0], &steps(plan), &options);
        let failures = report.failures.iter().map(|f| format!("{} {}", f.code.id, f.message)).collect();
        (report.valid, report.value, failures)
    }

    fn check(plan: &str) -> (bool, Option<f64>, Vec<String>) {
        run(plan, Options::default())
    }

    #[test]
    fn a_valid_plan_has_the_metric_as_value() {
        assert_eq!(check("0: (light r1) [2]"), (true, Some(3.0), vec![]));
        // Simultaneous increases commute.
        assert_eq!(check("0: (light r1) [2]\n0: (light r2) [2]"), (true, Some(4.0), vec![]));
        // Untimed steps happen at 1, 2, 3…: `light` ends at 3.
        assert_eq!(check("(light r1) [2]"), (true, Some(4.0), vec![]));
    }

    #[test]
    fn timed_initial_literals_happen_at_their_time_until_the_plan_ends() {
        let (valid, _, failures) = check("9: (light r1) [2]");
        assert!(!valid);
        assert_eq!(
            failures,
            [
                "E0416 step 1 `(light r1)` runs from 9.0 to 11.0, but its `over all` condition `(open r1)` is false from 10.0: deleted at 10.0 by the timed initial literal at 10.0"
            ]
        );
        // The literal at 20 opens r1 again.
        assert!(check("20: (light r1) [2]").0);
        // Literals after the last step are not applied: r1 stays open.
        assert!(check("0: (light r1) [2]\n3: (close r2)").0);
    }

    #[test]
    fn culprits_are_named() {
        let (_, _, failures) = check("(close r2)\n(close r2)\n0: (light r1) [2]");
        assert_eq!(
            failures,
            [
                "E0415 step 2 `(close r2)` at 2.0: precondition `(open r2)` is false: deleted at 1.0 by step 1 `(close r2)`"
            ]
        );
        let (_, _, failures) = check("");
        assert_eq!(
            failures,
            [
                "E0419 the goal is not reached at the end of the plan (0.0): `(lit r1)` is false: it is not in the initial state and nothing makes it true before"
            ]
        );
        let (_, _, failures) = check("0: (light r1) [2]\n3: (light r1) [2]");
        assert_eq!(
            failures,
            [
                "E0415 step 2 `(light r1)` at 3.0: `at start` condition `(lit r1)` is true: added at 2.0 by the end of step 1 `(light r1)`"
            ]
        );
    }

    #[test]
    fn over_all_holds_strictly_between_start_and_end() {
        // Closing r1 when `light` ends is fine: `over all` excludes the end.
        assert!(check("0: (light r1) [2]\n2: (close r1)").0);
        // Closing it when `light` starts is not: the state after the start
        // happening is inside the interval. No mutex: invariants are not
        // part of a happening.
        let (_, _, failures) = check("0: (light r1) [2]\n0: (close r1)");
        assert_eq!(failures.len(), 1);
        assert!(failures[0].starts_with("E0416"), "{failures:?}");
    }

    #[test]
    fn mutual_exclusion_within_a_happening() {
        let (valid, _, failures) = check("0: (light r1) [2]\n0: (reset)");
        assert!(!valid);
        assert_eq!(failures.len(), 1, "{failures:?}");
        assert!(failures[0].contains("both change `(power)` (`increase` and `assign`)"), "{failures:?}");
        let (_, _, failures) = check("0: (light r1) [2]\n0: (all-off)");
        assert_eq!(
            failures,
            [
                "E0418 step 2 `(all-off)` at 0.0 interferes with the start of step 1 `(light r1)` at 0.0: step 2 deletes `(lit r1)`, which the start of step 1 reads"
            ]
        );
        // A zero duration puts a step's start and end in one happening.
        let (_, _, failures) = check("0: (light r1) [2]\n2.01: (work r1) [0]");
        assert_eq!(failures.len(), 1, "{failures:?}");
        assert!(failures[0].starts_with("E0418"), "{failures:?}");
        assert!(
            failures[0].contains("the start of step 2 adds `(busy)`, which the end of step 2 deletes"),
            "{failures:?}"
        );
    }

    #[test]
    fn duration_inequalities_use_the_tolerance() {
        assert!(check("0: (light r1) [2]\n2.01: (work r1) [5.005]").0);
        let (_, _, failures) = check("0: (light r1) [2]\n2.01: (work r1) [6]");
        assert_eq!(
            failures,
            [
                "E0417 step 2 `(work r1)` lasts 6.0, but its duration constraint `(<= ?duration 5)` requires at most 5.0"
            ]
        );
        assert!(!check("0: (light r1) [2.02]").0);
        assert!(check("0: (light r1) [2.009]").0);
    }

    #[test]
    fn names_are_case_insensitive_and_lenient_with_underscores() {
        assert!(check("0: (LIGHT R1) [2]").0);
        let plan = "0: (light r1) [2]\n3: (all_off)\n4: (light r1) [2]";
        let (valid, _, failures) = check(plan);
        assert!(!valid && failures[0].starts_with("E0410"), "{failures:?}");
        let (valid, _, failures) = run(plan, Options { lenient: true, ..Options::default() });
        assert!(valid, "{failures:?}");
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig { cases: 200, ..Default::default() })]
        /// Any steps, however wrong (unknown names, wrong arities, times and
        /// durations that are negative, zero or not numbers, events at the
        /// same time), give a verdict without panicking, and the verdict is
        /// "valid" exactly when no failure is an error.
        #[test]
        fn any_steps_get_a_consistent_verdict(
            raw in proptest::collection::vec(
                (0..8usize, proptest::collection::vec(0..4usize, 0..3), 0..9usize, 0..9usize),
                0..12,
            ),
            keep_going in proptest::bool::ANY,
        ) {
            const NAMES: [&str; 8] = ["light", "work", "close", "all-off", "reset", "LIGHT", "nope", "all_off"];
            const ARGS: [&str; 4] = ["r1", "r2", "x", "R1"];
            const NUMBERS: [f64; 9] = [0.0, 0.0005, 0.005, 1.0, 2.0, 10.0, -1.0, f64::NAN, f64::INFINITY];
            let plan: Vec<TimedStep> = raw
                .iter()
                .map(|(n, args, t, d)| {
                    let args: Vec<&str> = args.iter().map(|&a| ARGS[a]).collect();
                    let time = (*t != 0).then(|| NUMBERS[*t - 1]);
                    let duration = (*d != 0).then(|| NUMBERS[*d - 1]);
                    TimedStep::new(NAMES[*n], &args, time, duration, Default::default())
                })
                .collect();
            let mut host = AnalysisHost::new();
            host.set_file_text("m/domain.pddl", DOMAIN);
            let p = host.set_file_text("m/problem.pddl", PROBLEM);
            let db = host.db();
            let options = Options { keep_going, ..Options::default() };
            let report = validate_temporal(db, file_units(db, p)[0], &plan, &options);
            let errors = report.failures.iter().filter(|f| f.code.severity == crate::Severity::Error).count();
            proptest::prop_assert_eq!(report.valid, errors == 0);
            proptest::prop_assert!(report.valid || report.value.is_none());
        }
    }

    #[test]
    fn keep_going_reports_later_failures() {
        let plan = "(close r2)\n(close r2)\n(close r2)\n0: (light r1) [2]";
        assert_eq!(check(plan).2.len(), 1);
        let (valid, _, failures) = run(plan, Options { keep_going: true, ..Options::default() });
        assert!(!valid);
        assert_eq!(failures.len(), 2, "{failures:?}");
    }
}
