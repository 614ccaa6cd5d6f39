//! Method preconditions, and the preconditions and effects of HiPOP's
//! abstract actions, in the states the primitive steps lead to.
//!
//! HDDL's semantics (and pandaPIparser's): a method's precondition is an
//! action without effect that comes after every step its task is ordered
//! after and before every step of the method. The primitive steps are
//! executed in the plan's order (a sequential plan) or at their times; the
//! precondition must hold in one of the states between the end of the last
//! step ordered before the task and the first action of the method. The
//! earliest such state is chosen, which leaves the subtasks' preconditions
//! the most room. An abstract action's effects must hold once its last
//! action has ended.
//!
//! Executing the primitive steps (their own preconditions, the goal) is the
//! temporal validator's: here only their effects are applied.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rowan::TextRange;

use super::super::temporal::TilChange;
use super::super::temporal::model::til_change;
use super::Cx;
use super::decompose::{precedences, transitive};
use super::timeline::{EventKind, Timeline};
use crate::db::{Section, lower_item};
use crate::diagnostic::codes;
use crate::eval::{
    Binding, Changes, Eval, EvalError, GroundWorld, Phase, Res, State, World, fmt_num, fmt_operands,
    for_each_binding, has_timed, op_text, split_timed,
};
use crate::model::{
    ActionKind, CmpOp, Effect, Gd, InitElement, ItemData, Method, NumExpr, Str, Term, TimeSpec, Typed,
};
use crate::semantics::symbols::Loc;
use crate::verify::state::{Atoms, ObjId};

/// Variables and their values.
type Values = Vec<(Str, ObjId)>;

/// A condition to check where an abstract step starts.
struct Condition<'db> {
    gd: &'db Gd,
    /// The values of the variables.
    binding: Vec<(Str, ObjId)>,
    /// Variables without value that occur in the condition: it holds if
    /// some values make it true.
    free: Vec<Typed>,
    /// A method's precondition (`false`: an abstract action's).
    method: bool,
    loc: Loc<'db>,
}

/// An abstract step, with what must hold where it starts and ends.
/// A duration constraint of a durative method or of a HiPOP abstract action,
/// checked on its step's times where the step starts.
struct DurationCheck<'db> {
    gd: &'db Gd,
    binding: Values,
    /// The step's duration, and the durations of the method's subtasks by id.
    duration: f64,
    subtasks: Vec<(Str, f64)>,
    /// A method's (`false`: an abstract action's).
    method: bool,
    loc: Loc<'db>,
}

struct Node<'db> {
    step: usize,
    conditions: Vec<Condition<'db>>,
    durations: Vec<DurationCheck<'db>>,
    effect: Option<(&'db Effect, Values, Loc<'db>)>,
    children: Vec<usize>,
    /// The first state its start may be in, from its siblings ordered before it.
    lo: usize,
    /// The last state its start may be in: before its first action, or
    /// before the first action of what is ordered after it.
    hi: usize,
}

pub(super) fn check(cx: &mut Cx<'_, '_>, tl: &Timeline) {
    if cx.unresolved_primitives {
        return;
    }
    let db = cx.db;
    warn_unchecked(cx, tl.timed);
    let mut nodes: Vec<Node<'_>> = Vec::new();
    let mut node_of: Vec<Option<usize>> = vec![None; cx.plan.steps.len()];
    for &i in &cx.order {
        if !cx.plan.steps[i].is_abstract() || Some(i) == cx.top.artificial {
            continue;
        }
        node_of[i] = Some(nodes.len());
        nodes.push(Node {
            step: i,
            conditions: Vec::new(),
            durations: Vec::new(),
            effect: None,
            children: Vec::new(),
            lo: 0,
            hi: 0,
        });
    }
    if nodes.is_empty() {
        cx.preconditions_checked = true;
        return;
    }
    let n_events = tl.events.len();
    // Conditions and effects.
    for node in nodes.iter_mut() {
        let i = node.step;
        let Some(res) = cx.resolved[i].clone() else { continue };
        if let Some(applied) = &cx.applied[i]
            && applied.static_ok
            && let Some(pre) = &applied.method.precondition
        {
            let binding: Vec<(Str, ObjId)> = applied
                .binding
                .iter()
                .filter_map(|b| Some((b.var.clone(), cx.objects.id(&b.value)?)))
                .collect();
            let loc = Loc { item: applied.method_loc.item, span: crate::semantics::check::gd_span(pre) };
            for g in at_start(pre) {
                let free = free_vars(applied.method, g, &binding);
                node.conditions.push(Condition { gd: g, binding: binding.clone(), free, method: true, loc });
            }
        }
        // The step's duration, and those of the listed subtasks, on a timed plan.
        let step_duration = |j: usize| -> Option<f64> {
            let s = &cx.plan.steps[j];
            match (&s.start, &s.duration) {
                (Some(_), Some(d)) if s.is_abstract() => Some(d.value),
                _ => tl.span[j].map(|sp| sp.end - sp.start),
            }
        };
        if tl.timed
            && let Some(applied) = &cx.applied[i]
            && let Some(g) = &applied.method.duration
            && let Some(d) = step_duration(i)
        {
            let ids =
                cx.plan.steps[i].decomposition.as_ref().map(|dec| dec.subtasks.clone()).unwrap_or_default();
            let subtasks: Vec<(Str, f64)> = applied
                .assign
                .iter()
                .zip(&ids)
                .filter_map(|(&j, id)| {
                    let sub = applied.method.network.subtasks.get(j)?.id.as_ref()?.key_str();
                    Some((sub, step_duration(cx.plan.index_of(id.value)?)?))
                })
                .collect();
            let binding: Values = applied
                .binding
                .iter()
                .filter_map(|b| Some((b.var.clone(), cx.objects.id(&b.value)?)))
                .collect();
            let loc = Loc { item: applied.method_loc.item, span: crate::semantics::check::gd_span(g) };
            node.durations.push(DurationCheck { gd: g, binding, duration: d, subtasks, method: true, loc });
        }
        if let Some((tloc, task)) = cx.task_model(&res.key) {
            let binding: Vec<(Str, ObjId)> = task
                .params
                .iter()
                .zip(&res.args)
                .filter_map(|(p, a)| Some((p.name.key_str(), cx.objects.id(a)?)))
                .collect();
            if let Some(pre) = &task.precondition {
                let loc = Loc { item: tloc.item, span: crate::semantics::check::gd_span(pre) };
                for g in at_start(pre) {
                    node.conditions.push(Condition {
                        gd: g,
                        binding: binding.clone(),
                        free: Vec::new(),
                        method: false,
                        loc,
                    });
                }
            }
            if tl.timed
                && let Some(g) = &task.duration
                && let Some(d) = step_duration(i)
            {
                let loc = Loc { item: tloc.item, span: crate::semantics::check::gd_span(g) };
                node.durations.push(DurationCheck {
                    gd: g,
                    binding: binding.clone(),
                    duration: d,
                    subtasks: Vec::new(),
                    method: false,
                    loc,
                });
            }
            if let Some(e) = &task.effect {
                node.effect = Some((e, binding, Loc { item: tloc.item, span: effect_span(e) }));
            }
        }
    }
    // The tree, and each node's window.
    let first = |j: usize| tl.event_range[j].map(|r| r.0);
    let last = |j: usize| tl.event_range[j].map(|r| r.1);
    // (children of a step with their predecessors and successors among siblings)
    let top_children = siblings(cx, None);
    // A step that is both a root and a subtask (E0440) may close a cycle of
    // subtasks: each node is placed once.
    let mut placed = vec![false; nodes.len()];
    let mut stack: Vec<(Option<usize>, usize)> = vec![(None, n_events)];
    while let Some((parent, hi_inherited)) = stack.pop() {
        let kids = match parent {
            None => top_children.clone(),
            Some(p) => siblings(cx, Some(nodes[p].step)),
        };
        for (j, preds, succs) in &kids {
            // Siblings with a mistake of their own have no reliable span.
            let lo = preds
                .iter()
                .filter(|&&s| cx.sound[s])
                .filter_map(|&s| last(s))
                .map(|e| e + 1)
                .max()
                .unwrap_or(0);
            let mut after = succs
                .iter()
                .filter(|&&s| cx.sound[s])
                .filter_map(|&s| first(s))
                .min()
                .unwrap_or(n_events)
                .min(hi_inherited);
            // A step's subtasks may take place while it runs, whatever its
            // siblings (when they overlap, an ordering error was reported).
            if let Some(l) = last(*j) {
                after = after.max(l + 1);
            }
            let hi = first(*j).unwrap_or(after);
            if let Some(nj) = node_of[*j]
                && !std::mem::replace(&mut placed[nj], true)
            {
                nodes[nj].lo = lo.min(hi);
                nodes[nj].hi = hi;
                if let Some(p) = parent {
                    nodes[p].children.push(nj);
                }
                stack.push((Some(nj), after));
            }
        }
    }
    // A step starts before its subtasks: no later than where they may start.
    for k in (0..cx.order.len()).rev() {
        let Some(n) = node_of[cx.order[k]] else { continue };
        let earliest = nodes[n].children.iter().map(|&c| nodes[c].hi).min();
        if let Some(e) = earliest {
            nodes[n].hi = nodes[n].hi.min(e);
            nodes[n].lo = nodes[n].lo.min(nodes[n].hi);
        }
    }
    // The roots of the node forest: nodes whose step's parent is no node.
    let roots: Vec<usize> =
        (0..nodes.len()).filter(|&n| cx.parent[nodes[n].step].is_none_or(|p| node_of[p].is_none())).collect();
    // The ground world.
    let GroundWorld { preds, funcs, atoms, init } = GroundWorld::new(db, cx.domain, cx.problem, &cx.objects);
    let mut state = State::new(atoms, Atoms::default());
    for &(a, _) in &init.facts {
        state.set(a, true);
    }
    let mut fluents: Vec<_> = init.fluents.iter().collect();
    fluents.sort_by(|a, b| a.0.cmp(b.0));
    for (key, &(v, _)) in fluents {
        let f = state.fluent(key);
        state.set_value(f, Some(v));
    }
    // The timed initial literals of a timed plan, by time: each changes the
    // states after it, as it does for the plan's own validation (a literal
    // at the time of an event comes with it, after its conditions).
    let mut tils: Vec<(f64, TilChange)> = Vec::new();
    if tl.timed {
        for &item in cx.problem.items(db) {
            if let (ItemData::Init(elements), Section::Init) = (&lower_item(db, item).data, item.section(db))
            {
                for e in elements {
                    if let InitElement::Timed(time, inner, _) = e
                        && let Some(change) = til_change(inner, &cx.objects, &preds, &funcs)
                    {
                        tils.push((time.value(), change));
                    }
                }
            }
        }
        tils.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let mut next_til = 0;
    let objects = &cx.objects;
    let world = World { objects, preds: &preds, funcs: &funcs };
    // The sweep: states 0..=n_events, state k before event k.
    // Nodes waiting for their first state, and effects waiting for the state
    // after their step: min-heaps by state, then node (a deterministic order).
    let mut pending: BinaryHeap<Reverse<(usize, usize)>> =
        roots.iter().map(|&n| Reverse((nodes[n].lo, n))).collect();
    let mut active: Vec<usize> = Vec::new();
    // The state from which each node was looked for.
    let mut from: Vec<usize> = vec![0; nodes.len()];
    // Effects to check once the state after an event is reached: (state, node).
    let mut effects_at: BinaryHeap<Reverse<(usize, usize)>> = BinaryHeap::new();
    let mut failures: Vec<Failure> = Vec::new();
    let mut unevaluable: Vec<(usize, EvalError)> = Vec::new();
    let mut stopped: Option<(usize, EvalError)> = None;
    for k in 0..=n_events {
        // The literals timed before event k (none after the last event, as
        // VAL applies none after the plan's last happening).
        if let Some(e) = tl.events.get(k) {
            while let Some((time, change)) = tils.get(next_til)
                && *time < e.time - tl.eps
            {
                match change {
                    TilChange::Atom(key, value) => {
                        let a = state.atom(key);
                        state.set(a, *value);
                    }
                    TilChange::Fluent(key, value) => {
                        let f = state.fluent(key);
                        state.set_value(f, Some(*value));
                    }
                }
                next_til += 1;
            }
        }
        loop {
            let mut progressed = false;
            while let Some(&Reverse((lo, n))) = pending.peek()
                && lo <= k
            {
                pending.pop();
                from[n] = k;
                active.push(n);
                progressed = true;
            }
            let mut a = 0;
            while a < active.len() {
                let n = active[a];
                let ev = Eval { world: &world, state: &state, duration: None, total_time: None };
                let mut failed: Vec<usize> = Vec::new();
                for (c, cond) in nodes[n].conditions.iter().enumerate() {
                    match holds(&ev, cond) {
                        Ok(true) => {}
                        Ok(false) => failed.push(c),
                        Err(e) => {
                            if !unevaluable.iter().any(|(m, _)| *m == n) {
                                unevaluable.push((n, e));
                            }
                        }
                    }
                }
                if failed.is_empty() || k >= nodes[n].hi {
                    for (c, check) in nodes[n].durations.iter().enumerate() {
                        match duration_holds(&ev, check, cx.opts.tolerance) {
                            Ok(None) => {}
                            Ok(Some(why)) => failures.push(Failure::Duration { node: n, check: c, why }),
                            Err(e) => unevaluable.push((n, e)),
                        }
                    }
                    if !failed.is_empty() {
                        let whys = failed.iter().map(|&c| (c, why(&ev, &nodes[n].conditions[c]))).collect();
                        failures.push(Failure::Condition { node: n, state: k, whys, lo: from[n] });
                    }
                    active.swap_remove(a);
                    for &c in &nodes[n].children {
                        pending.push(Reverse((nodes[c].lo.max(k).min(nodes[c].hi), c)));
                    }
                    if nodes[n].effect.is_some()
                        && let Some(l) = last(nodes[n].step)
                    {
                        effects_at.push(Reverse((l + 1, n)));
                    }
                    progressed = true;
                } else {
                    a += 1;
                }
            }
            if !progressed {
                break;
            }
        }
        // Effects of abstract actions that ended before state k.
        while let Some(&Reverse((at, n))) = effects_at.peek()
            && at <= k
        {
            effects_at.pop();
            let ev = Eval { world: &world, state: &state, duration: None, total_time: None };
            if let Some((eff, binding, _)) = &nodes[n].effect {
                match unmet_effects(&ev, eff, binding) {
                    Ok(unmet) if !unmet.is_empty() => {
                        failures.push(Failure::Effect { node: n, state: k, unmet })
                    }
                    Ok(_) => {}
                    Err(err) => unevaluable.push((n, err)),
                }
            }
        }
        if k == n_events {
            break;
        }
        if let Err(err) = apply(cx, &world, &mut state, tl, k) {
            stopped = Some((k, err));
            break;
        }
    }
    // Report.
    for f in failures {
        report(cx, tl, &nodes, f);
    }
    for (n, err) in unevaluable {
        let step = nodes[n].step;
        let mut d = cx.diag(
            codes::HIERARCHY_NOT_CHECKED,
            cx.id_range(step),
            format!(
                "{}: a condition of its method or task cannot be evaluated: {}",
                cx.step_text(step),
                err.message
            ),
        );
        if let Some(c) = nodes[n].conditions.first() {
            cx.related_loc(&mut d, Loc { item: c.loc.item, span: err.span }, "here");
        }
        cx.push(d);
    }
    match stopped {
        Some((k, err)) => {
            let step = tl.events[k].step;
            let mut d = cx.diag(
                codes::HIERARCHY_NOT_CHECKED,
                cx.plan.steps[step].range,
                format!(
                    "method preconditions are not checked from {} on: its effects cannot be applied ({})",
                    cx.step_text(step),
                    err.message
                ),
            );
            if let Some((loc, _)) = cx.resolved[step].as_ref().and_then(|r| cx.action_model(&r.key)) {
                cx.related_loc(&mut d, Loc { item: loc.item, span: err.span }, "this effect");
            }
            cx.push(d);
        }
        None => cx.preconditions_checked = true,
    }
}

/// What failed, found during the sweep and reported after it.
enum Failure {
    /// Conditions of a node false in every state from `lo` to `state`:
    /// which, and why (in the last state).
    Condition { node: usize, state: usize, whys: Vec<(usize, String)>, lo: usize },
    /// A duration constraint that the step's times do not satisfy, and why.
    Duration { node: usize, check: usize, why: String },
    /// Effects of an abstract action that do not hold after its last action
    /// (the event before `state`): the atoms, and whether they should be true.
    Effect { node: usize, state: usize, unmet: Vec<(String, bool)> },
}

/// "before step 4 `(drive t a b)`", "after the last step".
fn state_text(cx: &Cx<'_, '_>, tl: &Timeline, k: usize) -> String {
    match tl.events.get(k) {
        Some(e) => {
            let which = match e.kind {
                EventKind::Instant => "",
                EventKind::Start => "the start of ",
                EventKind::End => "the end of ",
            };
            format!("before {which}{}", cx.step_text(e.step))
        }
        None => "after the last step".to_string(),
    }
}

fn report(cx: &mut Cx<'_, '_>, tl: &Timeline, nodes: &[Node<'_>], f: Failure) {
    match f {
        Failure::Condition { node, state, whys, lo } => {
            let n = &nodes[node];
            let step = n.step;
            let dec_range = cx.plan.steps[step]
                .decomposition
                .as_ref()
                .map_or(cx.plan.steps[step].range, |d| d.method.range);
            for (c, why) in whys {
                let cond = &n.conditions[c];
                let (code, whose, at) = if cond.method {
                    let key = cx.applied[step].as_ref().map_or(String::new(), |a| a.method_key.to_string());
                    (
                        codes::METHOD_PRECONDITION_FALSE,
                        format!("the precondition of method `{key}`"),
                        dec_range,
                    )
                } else {
                    let key = cx.resolved[step].as_ref().map_or(String::new(), |r| r.key.to_string());
                    (
                        codes::ABSTRACT_ACTION_VIOLATED,
                        format!("the precondition of the abstract action `{key}`"),
                        cx.plan.steps[step].name.range,
                    )
                };
                let when = if lo < state {
                    format!("in every state from {} to {}", state_text(cx, tl, lo), state_text(cx, tl, state))
                } else {
                    state_text(cx, tl, state)
                };
                let mut d =
                    cx.diag(code, at, format!("{whose} is false for {}, {when}: {why}", cx.step_text(step)));
                cx.related_loc(&mut d, cond.loc, "the precondition");
                if let Some(e) = tl.events.get(state) {
                    cx.related_plan(&mut d, cx.plan.steps[e.step].range, "the first action of the step");
                }
                let hint = if cond.method {
                    "the method cannot be applied here: make the precondition true before its first action (reorder the steps, or add the actions that achieve it), or use another method"
                } else {
                    "make the abstract action's precondition true before its first action, or refine it later"
                };
                cx.hint(&mut d, hint, Vec::new());
                cx.push(d);
            }
        }
        Failure::Duration { node, check, why } => {
            let n = &nodes[node];
            let step = n.step;
            let c = &n.durations[check];
            let (whose, at) = if c.method {
                let key = cx.applied[step].as_ref().map_or(String::new(), |a| a.method_key.to_string());
                let at = cx.plan.steps[step]
                    .decomposition
                    .as_ref()
                    .map_or(cx.plan.steps[step].range, |d| d.method.range);
                (format!("method `{key}`"), at)
            } else {
                let key = cx.resolved[step].as_ref().map_or(String::new(), |r| r.key.to_string());
                (format!("the abstract action `{key}`"), cx.plan.steps[step].name.range)
            };
            let mut d = cx.diag(
                codes::METHOD_DURATION_VIOLATED,
                at,
                format!(
                    "{} lasts {}, which the duration constraint of {whose} rejects: {why}",
                    cx.step_text(step),
                    fmt_num(c.duration)
                ),
            );
            cx.related_loc(&mut d, c.loc, "the duration constraint");
            cx.hint(
                &mut d,
                "a step lasts from its first subtask's start to its last subtask's end: retime its actions so that the constraint holds, or use another method",
                Vec::new(),
            );
            cx.push(d);
        }
        Failure::Effect { node, state, unmet } => {
            let step = nodes[node].step;
            let key = cx.resolved[step].as_ref().map_or(String::new(), |r| r.key.to_string());
            let shown: Vec<String> = unmet
                .iter()
                .map(|(a, t)| format!("`{a}` is {}", if *t { "false" } else { "still true" }))
                .collect();
            let mut d = cx.diag(
                codes::ABSTRACT_ACTION_VIOLATED,
                cx.plan.steps[step].name.range,
                format!(
                    "the effect of the abstract action `{key}` does not hold when {} ends, after {}: {}",
                    cx.step_text(step),
                    state.checked_sub(1).and_then(|e| tl.events.get(e)).map_or(
                        "its last action".to_string(),
                        |e| {
                            let which = if e.kind == EventKind::End { "the end of " } else { "" };
                            format!("{which}{}", cx.step_text(e.step))
                        }
                    ),
                    shown.join(", ")
                ),
            );
            if let Some(loc) = nodes[node].effect.as_ref().map(|e| e.2) {
                cx.related_loc(&mut d, loc, "the effect");
            }
            cx.hint(
                &mut d,
                "an abstract action's method must achieve its effects: the method's actions do not, or a later action undoes them first",
                Vec::new(),
            );
            cx.push(d);
        }
    }
}

/// Why a condition is false, in words.
fn why(ev: &Eval<'_, '_, '_>, c: &Condition<'_>) -> String {
    if !c.free.is_empty() {
        let vars: Vec<&str> = c.free.iter().map(|t| t.name.text()).collect();
        return format!("no value of {} makes it true", vars.join(", "));
    }
    let mut b: Binding<'_> = Binding::default();
    for (var, obj) in &c.binding {
        b.push(var.as_str(), *obj);
    }
    match ev.why_false(c.gd, &mut b, false) {
        Ok(whys) if !whys.is_empty() => whys.iter().map(|w| w.text.clone()).collect::<Vec<_>>().join(", "),
        _ => format!("`{}` is false", ev.show_gd(c.gd, &b)),
    }
}

/// The parts of a precondition checked where the step starts: all but its
/// `over all` and `at end` parts (durative methods).
fn at_start(g: &Gd) -> Vec<&Gd> {
    let parts = split_timed(g);
    let mut v = parts.untimed;
    v.extend(parts.start);
    v
}

/// Whether a condition holds, for some values of its free variables.
fn holds<'m>(ev: &Eval<'_, '_, '_>, c: &'m Condition<'_>) -> Res<bool> {
    let mut b: Binding<'m> = Binding::default();
    for (var, obj) in &c.binding {
        b.push(var.as_str(), *obj);
    }
    if c.free.is_empty() {
        return ev.holds(c.gd, &mut b);
    }
    let mut found = false;
    let mut error: Option<EvalError> = None;
    let _ = for_each_binding(ev.world.objects, &c.free, &mut b, &mut |b| match ev.holds(c.gd, b) {
        Ok(true) => {
            found = true;
            Ok(std::ops::ControlFlow::Break(()))
        }
        Ok(false) => Ok(std::ops::ControlFlow::Continue(())),
        Err(e) => {
            error = Some(e);
            Ok(std::ops::ControlFlow::Break(()))
        }
    });
    match error {
        Some(e) if !found => Err(e),
        _ => Ok(found),
    }
}

/// Whether a duration constraint holds on a step's times: `None` when it
/// does, or why not. Comparisons accept the tolerance as VAL does for
/// durative actions: `=` within it, `<=` and `>=` up to it, `<` and `>` none.
fn duration_holds(ev: &Eval<'_, '_, '_>, c: &DurationCheck<'_>, tol: f64) -> Res<Option<String>> {
    let mut b: Binding<'_> = Binding::default();
    for (var, obj) in &c.binding {
        b.push(var.as_str(), *obj);
    }
    let mut parts: Vec<&Gd> = Vec::new();
    flatten_and(c.gd, &mut parts);
    for g in parts {
        let Gd::Compare(op, l, r, _) = g else {
            let timed =
                Eval { world: ev.world, state: ev.state, duration: Some(c.duration), total_time: None };
            if !timed.holds(g, &mut b)? {
                return Ok(Some(format!("`{}` is false", ev.show_gd(g, &b))));
            }
            continue;
        };
        let (lv, rv) = (duration_num(ev, l, &b, c)?, duration_num(ev, r, &b, c)?);
        let ok = match op {
            CmpOp::Gt => lv > rv,
            CmpOp::Lt => lv < rv,
            CmpOp::Ge => rv - lv <= tol,
            CmpOp::Le => lv - rv <= tol,
            CmpOp::Eq => (lv - rv).abs() < tol,
        };
        if !ok {
            let (ls, rs, _) = fmt_operands(lv, rv);
            return Ok(Some(format!("`{}` is false ({ls} {} {rs} fails)", ev.show_gd(g, &b), op_text(*op))));
        }
    }
    Ok(None)
}

fn flatten_and<'g>(g: &'g Gd, out: &mut Vec<&'g Gd>) {
    match g {
        Gd::And(xs, _) => xs.iter().for_each(|x| flatten_and(x, out)),
        other => out.push(other),
    }
}

/// A numeric expression of a duration constraint: `?duration` is the step's
/// duration, `(duration t1)` that of the subtask `t1`.
fn duration_num<'m>(
    ev: &Eval<'_, '_, '_>,
    e: &'m NumExpr,
    b: &Binding<'m>,
    c: &DurationCheck<'_>,
) -> Res<f64> {
    match e {
        NumExpr::Duration(_) => Ok(c.duration),
        NumExpr::TaskDuration(id, span) => {
            c.subtasks.iter().find(|(k, _)| *k == id.key()).map(|(_, d)| *d).ok_or_else(|| EvalError {
                kind: crate::eval::ErrorKind::Unresolved,
                message: format!("`{}` is not a subtask with times", id.text()),
                span: *span,
                fluent: None,
            })
        }
        NumExpr::Op(op, args, _) => {
            let vals = args.iter().map(|a| duration_num(ev, a, b, c)).collect::<Res<Vec<f64>>>()?;
            let Some((first, rest)) = vals.split_first() else { return ev.num(e, b) };
            Ok(match (&**op, rest) {
                ("-", []) => -first,
                ("+", _) => rest.iter().fold(*first, |a, x| a + x),
                ("-", _) => rest.iter().fold(*first, |a, x| a - x),
                ("*", _) => rest.iter().fold(*first, |a, x| a * x),
                ("/", _) if !rest.contains(&0.0) => rest.iter().fold(*first, |a, x| a / x),
                _ => return ev.num(e, b),
            })
        }
        _ => ev.num(e, b),
    }
}

/// The effects of an abstract action that do not hold: `(atom, should be true)`.
fn unmet_effects(ev: &Eval<'_, '_, '_>, e: &Effect, binding: &[(Str, ObjId)]) -> Res<Vec<(String, bool)>> {
    let mut b: Binding<'_> = Binding::default();
    for (var, obj) in binding {
        b.push(var.as_str(), *obj);
    }
    let phase = if has_timed(e, TimeSpec::AtStart) || has_timed(e, TimeSpec::AtEnd) {
        Phase::End
    } else {
        Phase::Instant
    };
    let mut ch = Changes::default();
    ev.effects(e, &mut b, phase, &mut Vec::new(), &mut ch)?;
    let mut unmet = Vec::new();
    for (key, _) in &ch.adds {
        if !ev.state.holds(key) {
            unmet.push((ev.world.show_atom(key), true));
        }
    }
    for (key, _) in &ch.dels {
        if ev.state.holds(key) && !ch.adds.iter().any(|(k, _)| k == key) {
            unmet.push((ev.world.show_atom(key), false));
        }
    }
    Ok(unmet)
}

/// Applies the effects of event `k`.
fn apply(cx: &Cx<'_, '_>, world: &World<'_, '_>, state: &mut State, tl: &Timeline, k: usize) -> Res<()> {
    let ev = tl.events[k];
    let Some(res) = cx.resolved[ev.step].as_ref() else { return Ok(()) };
    let Some((_, action)) = cx.action_model(&res.key) else { return Ok(()) };
    let Some(effect) = &action.effect else { return Ok(()) };
    let binding: Vec<(Str, ObjId)> = action
        .params
        .iter()
        .zip(&res.args)
        .filter_map(|(p, a)| Some((p.name.key_str(), cx.objects.id(a)?)))
        .collect();
    let phases: &[Phase] = match (action.kind, ev.kind) {
        (ActionKind::Durative, EventKind::Instant) => &[Phase::Start, Phase::End],
        (ActionKind::Durative, EventKind::Start) => &[Phase::Start],
        (ActionKind::Durative, EventKind::End) => &[Phase::End],
        _ => &[Phase::Instant],
    };
    for &phase in phases {
        let mut b: Binding<'_> = Binding::default();
        for (var, obj) in &binding {
            b.push(var.as_str(), *obj);
        }
        let mut ch = Changes::default();
        {
            let e = Eval {
                world,
                state,
                duration: cx.plan.steps[ev.step].duration.as_ref().map(|d| d.value),
                total_time: None,
            };
            e.effects(effect, &mut b, phase, &mut Vec::new(), &mut ch)?;
        }
        for (key, _) in &ch.dels {
            let a = state.atom(key);
            state.set(a, false);
        }
        for (key, _) in &ch.adds {
            let a = state.atom(key);
            state.set(a, true);
        }
        for u in &ch.updates {
            let f = state.fluent(&u.fluent);
            let old = state.value(f);
            state.set_value(f, u.op.apply(old, u.value));
        }
    }
    Ok(())
}

/// The children of a step (`None`: the top level), each with the siblings
/// its network orders before and after it.
fn siblings(cx: &Cx<'_, '_>, parent: Option<usize>) -> Vec<(usize, Vec<usize>, Vec<usize>)> {
    let plan = cx.plan;
    let (ids, network, assign) = match parent {
        Some(p) => {
            let Some(dec) = &plan.steps[p].decomposition else { return Vec::new() };
            let applied = cx.applied[p].as_ref();
            (dec.subtasks.clone(), applied.map(|a| &a.method.network), applied.map(|a| a.assign.clone()))
        }
        None => {
            let ids = if cx.top.implicit { Vec::new() } else { cx.top.ids.clone() };
            (ids, cx.htn.map(|(_, h)| &h.network), cx.htn_assign.clone())
        }
    };
    let steps: Vec<Option<usize>> = ids.iter().map(|id| plan.index_of(id.value)).collect();
    let mut out: Vec<(usize, Vec<usize>, Vec<usize>)> = Vec::new();
    if parent.is_none() && cx.top.implicit {
        for (i, _) in plan.steps.iter().enumerate() {
            if cx.parent[i].is_none() && cx.reached[i] {
                out.push((i, Vec::new(), Vec::new()));
            }
        }
        return out;
    }
    let order = match (network, &assign) {
        (Some(net), Some(assign)) if assign.len() == steps.len() => {
            // Transitively: a subtask ordered after one refined into nothing
            // is still after what that one is ordered after.
            let preds = transitive(&precedences(net));
            // preds over listed positions
            let pos_of = |j: usize| assign.iter().position(|&a| a == j);
            Some(
                assign
                    .iter()
                    .map(|&j| preds[j].iter().filter_map(|&q| pos_of(q)).collect::<Vec<usize>>())
                    .collect::<Vec<_>>(),
            )
        }
        _ => None,
    };
    for (pos, s) in steps.iter().enumerate() {
        let Some(j) = *s else { continue };
        if parent.is_some_and(|p| cx.parent[j] != Some(p)) {
            continue;
        }
        let (before, after) = match &order {
            Some(o) => (
                o[pos].iter().filter_map(|&q| steps[q]).collect(),
                (0..steps.len()).filter(|&q| o[q].contains(&pos)).filter_map(|q| steps[q]).collect(),
            ),
            None => (Vec::new(), Vec::new()),
        };
        out.push((j, before, after));
    }
    out
}

/// The method's parameters without value that occur in `g`.
fn free_vars(method: &Method, g: &Gd, binding: &[(Str, ObjId)]) -> Vec<Typed> {
    let mut used: Vec<Str> = Vec::new();
    gd_vars(g, &mut used);
    method
        .params
        .iter()
        .filter(|p| {
            used.iter().any(|u| u == p.name.key()) && !binding.iter().any(|(v, _)| *v == p.name.key())
        })
        .cloned()
        .collect()
}

fn term_vars(t: &Term, out: &mut Vec<Str>) {
    match t {
        Term::Var(n) => out.push(n.key_str()),
        Term::Const(_) => {}
        Term::Func(f) => f.args.iter().for_each(|a| term_vars(a, out)),
    }
}

fn expr_vars(e: &NumExpr, out: &mut Vec<Str>) {
    match e {
        NumExpr::Fluent(f) => f.args.iter().for_each(|a| term_vars(a, out)),
        NumExpr::Op(_, xs, _) => xs.iter().for_each(|x| expr_vars(x, out)),
        NumExpr::Var(n) => out.push(n.key_str()),
        _ => {}
    }
}

fn gd_vars(g: &Gd, out: &mut Vec<Str>) {
    match g {
        Gd::Atom(a) => a.args.iter().for_each(|t| term_vars(t, out)),
        Gd::Equal(a, b, _) => {
            term_vars(a, out);
            term_vars(b, out);
        }
        Gd::Compare(_, l, r, _) => {
            expr_vars(l, out);
            expr_vars(r, out);
        }
        Gd::Not(x, _)
        | Gd::Timed(_, x, _)
        | Gd::Preference(_, x, _)
        | Gd::Forall(_, x, _)
        | Gd::Exists(_, x, _) => gd_vars(x, out),
        Gd::And(xs, _) | Gd::Or(xs, _) => xs.iter().for_each(|x| gd_vars(x, out)),
        Gd::Imply(a, b, _) => {
            gd_vars(a, out);
            gd_vars(b, out);
        }
        Gd::Modal(_, xs, _, _) => xs.iter().for_each(|x| gd_vars(x, out)),
        Gd::Sortof(t, _, _) => term_vars(t, out),
        Gd::Order(_) => {}
    }
}

fn effect_span(e: &Effect) -> TextRange {
    match e {
        Effect::Add(a) => a.span,
        Effect::Del(_, s)
        | Effect::And(_, s)
        | Effect::Forall(_, _, s)
        | Effect::When(_, _, s)
        | Effect::Numeric(_, _, _, s)
        | Effect::Timed(_, _, s) => *s,
    }
}

/// Warns, once per method, about what is not checked: method effects,
/// durations of durative methods, HDDL 2.1 modal constraints.
fn warn_unchecked(cx: &mut Cx<'_, '_>, timed: bool) {
    let mut seen: Vec<Str> = Vec::new();
    for k in 0..cx.order.len() {
        let i = cx.order[k];
        let Some(applied) = cx.applied[i].clone() else { continue };
        if seen.contains(&applied.method_key) {
            continue;
        }
        seen.push(applied.method_key.clone());
        let m = applied.method;
        let by_hand = "the plan is validated without it: check this part by hand";
        let mut what: Vec<(&str, TextRange, &str)> = Vec::new();
        if let Some(e) = &m.effect {
            what.push((
                "its effect is not applied to the states method preconditions are checked in",
                effect_span(e),
                "the plan is validated without it: pandaPIparser applies method effects where a method starts",
            ));
        }
        if let Some(d) = &m.duration
            && !timed
        {
            what.push((
                "its duration constraint is not checked: the plan has no times",
                crate::semantics::check::gd_span(d),
                by_hand,
            ));
        }
        if let Some(pre) = &m.precondition {
            let parts = split_timed(pre);
            if let Some(g) = parts.over_all.first().or(parts.end.first()) {
                let span = crate::semantics::check::gd_span(g);
                what.push(("its `over all` and `at end` conditions are not checked", span, by_hand));
            }
        }
        if let Some(c) = &m.network.constraints
            && let Some(span) = modal_span(c)
        {
            what.push(("its HDDL 2.1 constraints are not checked", span, by_hand));
        }
        for (message, span, hint) in what {
            let dec =
                cx.plan.steps[i].decomposition.as_ref().map_or(cx.plan.steps[i].range, |d| d.method.range);
            let mut d = cx.diag(
                codes::HIERARCHY_NOT_CHECKED,
                dec,
                format!("method `{}` (first used by {}): {message}", applied.method_key, cx.step_text(i)),
            );
            cx.related_loc(&mut d, Loc { item: applied.method_loc.item, span }, "here");
            cx.hint(&mut d, hint, Vec::new());
            cx.push(d);
        }
    }
}

fn modal_span(g: &Gd) -> Option<TextRange> {
    match g {
        Gd::Modal(_, _, _, s) => Some(*s),
        Gd::And(xs, _) => xs.iter().find_map(modal_span),
        _ => None,
    }
}
