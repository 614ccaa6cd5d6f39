//! The model a plan is validated against, prepared once, and the plan's
//! steps grounded in it; what the validator does not support.

use rowan::TextRange;
use rustc_hash::FxHashMap;

use super::{Model, Step, Til, TilChange};
use crate::db::{Db, Section, Unit, lower_item};
use crate::diagnostic::codes;
use crate::eval::{GroundWorld, Key, fmt_num};
use crate::model::{Action, ActionKind, Gd, InitElement, ItemData, Name, NumExpr, Term};
use crate::semantics::check::{gd_span, suggest};
use crate::semantics::symbols::{Loc, domain_symbols, problem_symbols, type_set};
use crate::validate::{Failure, Options, TimedStep};
use crate::verify::state::{Interner, ObjId, Objects, constant};

/// PDDL+, derived predicates, PDDL 3 constraints: what this validator does not check.
pub(super) fn unsupported_model<'db>(
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
                            a.name.text()
                        ),
                        a.name.span,
                    ))
                }
                ItemData::Action(a) if continuous(a).is_some() => Some((
                    format!(
                        "the action `{}` has continuous effects (`#t`): change over time is not simulated",
                        a.name.text()
                    ),
                    continuous(a).unwrap_or(a.name.span),
                )),
                ItemData::Derived(atom, _, _) => Some((
                    format!(
                        "the domain has the derived predicate `{}`: derived predicates are not evaluated",
                        atom.pred.text()
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
pub(super) fn continuous(a: &Action) -> Option<TextRange> {
    pub(super) fn expr(e: &NumExpr) -> Option<TextRange> {
        match e {
            NumExpr::Special(s, span) if &**s == "#t" => Some(*span),
            NumExpr::Op(_, args, _) => args.iter().find_map(expr),
            _ => None,
        }
    }
    pub(super) fn gd(g: &Gd) -> Option<TextRange> {
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
    pub(super) fn effect(e: &crate::model::Effect) -> Option<TextRange> {
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
pub(super) fn prepare<'db>(db: &'db dyn Db, domain: Unit<'db>, problem: Unit<'db>) -> Model<'db> {
    let dom = domain_symbols(db, domain);
    let prob = problem_symbols(db, problem);
    let objects = Objects::new(dom, prob);
    let GroundWorld { preds, funcs, atoms, init } = GroundWorld::new(db, domain, problem, &objects);
    let mut actions = FxHashMap::default();
    for &item in domain.items(db) {
        if let ItemData::Action(a) = &lower_item(db, item).data {
            actions.entry(a.name.key().to_string()).or_insert((item, &**a));
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

pub(in crate::validate) fn til_change(
    e: &InitElement,
    objects: &Objects<'_>,
    preds: &Interner,
    funcs: &Interner,
) -> Option<TilChange> {
    let key = |names: &Interner, name: &Name, args: &[Term]| -> Option<Key> {
        let mut k = Key::new();
        k.push(names.get(name.key())?);
        for t in args {
            match t {
                Term::Const(n) => k.push(objects.id(n.key())?),
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
pub(super) fn normalize(s: &str, lenient: bool) -> String {
    let k = s.to_ascii_lowercase();
    if lenient { k.replace('_', "-") } else { k }
}

/// Resolves a step to its action and objects, reporting what does not resolve.
pub(super) fn ground_step<'db>(
    db: &'db dyn Db,
    model: &Model<'db>,
    i: usize,
    s: &TimedStep,
    time: f64,
    options: &Options,
    out: &mut Vec<Failure<'db>>,
) -> Option<Step<'db>> {
    let step = s.described();
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
            format!("{step}: the domain has no action `{}`", s.name),
        )
        .at_step(i);
        if let Some(task) = dom.tasks.get(key.as_str()) {
            f.message =
                format!("{step}: `{}` is a task, not an action; a temporal plan lists actions only", s.name);
            f = f.model(task.loc, "the task is declared here");
        } else if let Some(best) = suggest(&key, model.actions.keys().map(String::as_str)) {
            f = f.hint(format!("did you mean `{best}`?")).edit(s.name_span, best);
        }
        out.push(f);
        return None;
    };
    let decl = Loc { item, span: action.name.span };
    if s.args.len() != action.params.len() {
        let params: Vec<String> = action.params.iter().map(|p| p.name.text().to_string()).collect();
        out.push(
            Failure::new(
                codes::STEP_ARITY,
                s.span,
                format!(
                    "{step} gives `{}` {} argument{}, but it takes {} ({})",
                    action.name.text(),
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
                format!("{step}: `{arg}` is not an object of the problem or a constant of the domain"),
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
                    "{step}: `{arg}` is of type `{declared}`, but parameter `{}` of `{}` has type `{}`",
                    param.name.text(),
                    action.name.text(),
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
        out.push(timing(format!("{step} starts at {time}: a time is a number, 0 or more")));
        ok = false;
    }
    let duration = match (action.kind, s.duration) {
        (ActionKind::Durative, None) => {
            out.push(
                timing(format!("{step} is a durative action without a duration"))
                    .model(decl, "a durative action")
                    .hint(format!("give its duration after it: `{time:.3}: {} [d]`", s.text())),
            );
            ok = false;
            None
        }
        (ActionKind::Durative, Some(d)) if !d.is_finite() || d < 0.0 => {
            out.push(timing(format!("{step} has the duration {d}: a duration is a number, 0 or more")));
            ok = false;
            None
        }
        (ActionKind::Durative, Some(d)) => Some(d),
        (_, Some(d)) => {
            let mut f = Failure::new(
                codes::DURATION_IGNORED,
                s.duration_span.unwrap_or(s.span),
                format!("{step} is an instantaneous action: its duration {} is ignored", fmt_num(d)),
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
pub(super) fn declared_type(db: &dyn Db, model: &Model<'_>, id: ObjId) -> Option<String> {
    let name = model.objects.name(id);
    let dom = domain_symbols(db, model.domain);
    let decl = dom.constants.get(name).map(|d| d.ty.join(" or "));
    decl.or_else(|| {
        let loc = model.objects.loc(id)?;
        let unit = crate::semantics::check::unit_of(db, loc.item)?;
        problem_symbols(db, unit).objects.get(name).map(|d| d.ty.join(" or "))
    })
}
