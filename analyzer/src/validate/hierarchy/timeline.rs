//! When the steps of a plan happen: the primitive steps in the plan's order
//! (a sequential plan) or at their times (a timed one), an abstract step from
//! its first action's start to its last action's end; the orderings of
//! methods and of the `:htn` checked on them; timed abstract steps (HiPOP's
//! abstract actions have their own times) checked to contain their subtasks.

use rowan::TextRange;

use super::Cx;
use super::decompose::{Net, Owner, subtask_index, subtask_label};
use super::matching::OrderingCheck;
use crate::diagnostic::codes;
use crate::eval::fmt_num;
use crate::model::{ActionKind, CmpOp, Endpoint, Ordering, TaskNetwork};
use crate::plan::{Plan, StepId};
use crate::semantics::symbols::Loc;

/// An event of the execution: a primitive step, or the start or end of a
/// durative one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Event {
    pub step: usize,
    pub kind: EventKind,
    pub time: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum EventKind {
    Instant,
    Start,
    End,
}

/// Where a step is in time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Span {
    pub start: f64,
    pub end: f64,
    /// The primitive steps that start first and end last (the step itself
    /// when it is primitive); `None` for an abstract step timed by its own
    /// annotation.
    pub first: Option<usize>,
    pub last: Option<usize>,
}

pub(super) struct Timeline {
    /// Whether the plan has times (every primitive step has a start).
    pub timed: bool,
    /// Times closer than this are the same instant.
    pub eps: f64,
    pub events: Vec<Event>,
    /// For each step: its span, when it has one (an abstract step without
    /// actions below it and without times has none).
    pub span: Vec<Option<Span>>,
    /// For each step: the indices of its first and last events.
    pub event_range: Vec<Option<(usize, usize)>>,
}

impl Timeline {
    pub(super) fn new(cx: &Cx<'_, '_>) -> Timeline {
        let plan = cx.plan;
        let n = plan.steps.len();
        let prims: Vec<usize> = plan.primitive_steps().map(|(i, _)| i).collect();
        let timed = !prims.is_empty() && prims.iter().all(|&i| plan.steps[i].start.is_some());
        let mut events = Vec::with_capacity(prims.len() * 2);
        let mut span: Vec<Option<Span>> = vec![None; n];
        for (k, &i) in prims.iter().enumerate() {
            let s = &plan.steps[i];
            let (start, end) = if timed {
                let start = s.start.as_ref().map_or(0.0, |t| t.value);
                (start, s.end().unwrap_or(start))
            } else {
                (k as f64, k as f64)
            };
            span[i] = Some(Span { start, end, first: Some(i), last: Some(i) });
            let durative = cx.resolved[i]
                .as_ref()
                .and_then(|r| cx.action_model(&r.key))
                .is_some_and(|(_, a)| a.kind == ActionKind::Durative);
            if timed && durative {
                events.push(Event { step: i, kind: EventKind::Start, time: start });
                events.push(Event { step: i, kind: EventKind::End, time: end });
            } else {
                events.push(Event { step: i, kind: EventKind::Instant, time: start });
            }
        }
        // Stable: the plan's order among equal times.
        events.sort_by(|a, b| a.time.total_cmp(&b.time));
        let mut event_range: Vec<Option<(usize, usize)>> = vec![None; n];
        for (e, ev) in events.iter().enumerate() {
            let r = event_range[ev.step].get_or_insert((e, e));
            r.0 = r.0.min(e);
            r.1 = r.1.max(e);
        }
        // Abstract steps, children before parents.
        for &i in cx.order.iter().rev() {
            let s = &plan.steps[i];
            let Some(dec) = &s.decomposition else { continue };
            let mut hull: Option<Span> = None;
            let mut range: Option<(usize, usize)> = None;
            for sub in &dec.subtasks {
                let Some(j) = plan.index_of(sub.value) else { continue };
                if cx.parent[j] != Some(i) {
                    continue;
                }
                if let Some(c) = span[j] {
                    hull = Some(match hull {
                        None => c,
                        Some(h) => Span {
                            start: h.start.min(c.start),
                            end: h.end.max(c.end),
                            first: if c.start < h.start { c.first } else { h.first },
                            last: if c.end > h.end { c.last } else { h.last },
                        },
                    });
                }
                if let Some((a, b)) = event_range[j] {
                    range = Some(range.map_or((a, b), |(x, y)| (x.min(a), y.max(b))));
                }
            }
            if hull.is_none()
                && timed
                && let Some(start) = &s.start
            {
                let end = s.end().unwrap_or(start.value);
                hull = Some(Span { start: start.value, end, first: None, last: None });
            }
            span[i] = hull;
            event_range[i] = range;
        }
        let eps = if timed { cx.opts.tolerance / 10.0 } else { 0.0 };
        Timeline { timed, eps, events, span, event_range }
    }

    /// Checks the orderings of every matched method, and of the `:htn`.
    pub(super) fn check_orderings(&self, cx: &mut Cx<'_, '_>) {
        for k in 0..cx.order.len() {
            let i = cx.order[k];
            let Some(applied) = cx.applied[i].clone() else { continue };
            if applied.orderings_undecided {
                continue;
            }
            let Some(dec) = &cx.plan.steps[i].decomposition else { continue };
            let net = Net {
                owner: Owner::Method { step: i, key: applied.method_key.clone(), loc: applied.method_loc },
                item: applied.method_loc.item,
                network: &applied.method.network,
                params: &applied.method.params,
                statics: Vec::new(),
            };
            self.check_network(cx, &net, &dec.subtasks, &applied.assign);
        }
        if let (Some((loc, htn)), Some(assign)) = (cx.htn, cx.htn_assign.clone())
            && !cx.htn_orderings_undecided
        {
            let net = Net {
                owner: Owner::Htn { loc },
                item: loc.item,
                network: &htn.network,
                params: &htn.params,
                statics: Vec::new(),
            };
            let ids = cx.top.ids.clone();
            self.check_network(cx, &net, &ids, &assign);
        }
    }

    fn check_network(&self, cx: &mut Cx<'_, '_>, net: &Net<'_>, ids: &[StepId], assign: &[usize]) {
        let order = NetOrder::new(self, net.network, cx.plan, ids);
        // A subtree with a mistake of its own (reported) has no reliable span.
        let found = order.violations(assign, Some(&cx.sound));
        for v in found {
            match v {
                Violation::Direct { a, b, pa, pb, o } => {
                    let (Some(sa), Some(sb)) = (order.steps[pa], order.steps[pb]) else { continue };
                    let (Some(spa), Some(spb)) = (self.span[sa], self.span[sb]) else { continue };
                    self.report_ordering(cx, net, (a, pa, sa, spa), (b, pb, sb, spb), ids, o);
                }
                Violation::Derived(d) => self.report_derived(cx, net, &order, ids, assign, &d),
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn report_ordering(
        &self,
        cx: &mut Cx<'_, '_>,
        net: &Net<'_>,
        (a, pa, sa, spa): (usize, usize, usize, Span),
        (b, pb, sb, spb): (usize, usize, usize, Span),
        ids: &[StepId],
        o: Option<&Ordering>,
    ) {
        let network = net.network;
        let (la, lb) = (subtask_label(network, a), subtask_label(network, b));
        let constraint = match o {
            Some(o) => ordering_text(o),
            None => format!("`:ordered-subtasks`: {la} before {lb}"),
        };
        let simple = o.is_none_or(|o| {
            !o.negated
                && o.op == CmpOp::Lt
                && o.left.endpoint == Endpoint::Whole
                && o.right.endpoint == Endpoint::Whole
        });
        let prim = |k: Option<usize>| k.map(|k| cx.step_text(k));
        let detail = if simple {
            let last = prim(spa.last);
            let first = prim(spb.first);
            match (self.timed, last, first) {
                (false, Some(l), Some(f)) => {
                    if spa.last == spb.first {
                        format!("both are refined into {l}")
                    } else {
                        format!("{l} (in {la}) comes after {f} (in {lb})")
                    }
                }
                (true, Some(l), Some(f)) => format!(
                    "{la} ends at {} ({l}), not before {lb} starts at {} ({f})",
                    fmt_num(spa.end),
                    fmt_num(spb.start)
                ),
                _ => format!("{la} and {lb} overlap"),
            }
        } else {
            let point = |sp: Span, e: Endpoint| match e {
                Endpoint::Start | Endpoint::Whole => sp.start,
                Endpoint::End => sp.end,
            };
            let (ea, eb) =
                o.map_or((Endpoint::Whole, Endpoint::Whole), |o| (o.left.endpoint, o.right.endpoint));
            if self.timed {
                format!(
                    "{la} is at {}–{} and {lb} at {}–{} (the points compared: {} and {})",
                    fmt_num(spa.start),
                    fmt_num(spa.end),
                    fmt_num(spb.start),
                    fmt_num(spb.end),
                    fmt_num(point(spa, ea)),
                    fmt_num(point(spb, eb))
                )
            } else {
                format!(
                    "{la} spans actions {}–{} and {lb} actions {}–{} of the plan",
                    spa.start as u64 + 1,
                    spa.end as u64 + 1,
                    spb.start as u64 + 1,
                    spb.end as u64 + 1
                )
            }
        };
        let mut d = cx.diag(
            codes::ORDERING_VIOLATED,
            ids[pb].range,
            format!(
                "{} orders {} ({la}) and {} ({lb}) by {constraint}, which the plan does not respect: {detail}",
                cx.owner_text(net),
                cx.step_text(sa),
                cx.step_text(sb),
            ),
        );
        cx.related_plan(&mut d, ids[pa].range, format!("{la} is step {}", ids[pa].value));
        if let Some(o) = o {
            cx.related_loc(&mut d, Loc { item: net.item, span: o.span }, "the ordering");
        } else if let Some(s) = network.subtasks.get(b) {
            cx.related_loc(&mut d, Loc { item: net.item, span: s.call.span }, format!("{lb}, after {la}"));
        }
        let hint = if simple && !self.timed {
            format!(
                "every action below step {} must come before every action below step {}: reorder the primitive steps, or refine the tasks differently",
                ids[pa].value, ids[pb].value
            )
        } else if simple {
            format!(
                "start the actions of {lb} (step {}) more than {} after {} (when {la} ends): times closer than tolerance/10 are the same instant",
                ids[pb].value,
                fmt_num(self.eps),
                fmt_num(spa.end)
            )
        } else {
            "move the steps so that the constraint holds, or refine the tasks differently".to_string()
        };
        cx.hint(&mut d, hint, Vec::new());
        cx.push(d);
    }

    /// An ordering that follows from two through subtasks refined into
    /// nothing (`a < t < b`, `t` without actions: `a < b`), violated.
    fn report_derived(
        &self,
        cx: &mut Cx<'_, '_>,
        net: &Net<'_>,
        order: &NetOrder<'_>,
        ids: &[StepId],
        assign: &[usize],
        d: &Derived<'_>,
    ) {
        let network = net.network;
        let (a, b) = (d.from.task, d.to.task);
        let (Some(sa), Some(sb)) = (order.steps[d.pa], order.steps[d.pb]) else { return };
        let (Some(spa), Some(spb)) = (self.span[sa], self.span[sb]) else { return };
        let (la, lb) = (subtask_label(network, a), subtask_label(network, b));
        let empties: Vec<usize> = d.path.iter().skip(1).map(|e| e.from.task).collect();
        let labels: Vec<String> = empties.iter().map(|&t| subtask_label(network, t)).collect();
        let mut by_order: Vec<String> = Vec::new();
        let mut constraints: Vec<String> = Vec::new();
        for e in &d.path {
            match e.origin {
                Some(o) => constraints.push(ordering_text(o)),
                None => by_order.push(format!(
                    "{} before {}",
                    subtask_label(network, e.from.task),
                    subtask_label(network, e.to.task)
                )),
            }
        }
        if !by_order.is_empty() {
            constraints.push(format!("`:ordered-subtasks`: {}", by_order.join(", ")));
        }
        let simple = d.from.end && !d.to.end && d.strict;
        let relation = if simple {
            format!("{} ({la}) before {} ({lb})", cx.step_text(sa), cx.step_text(sb))
        } else {
            let point = |p: Pt, l: &str| format!("the {} of {l}", if p.end { "end" } else { "start" });
            format!(
                "{} of {} {} {} of {}",
                point(d.from, &la),
                cx.step_text(sa),
                if d.strict { "before" } else { "no later than" },
                point(d.to, &lb),
                cx.step_text(sb)
            )
        };
        let value = |sp: Span, p: Pt| if p.end { sp.end } else { sp.start };
        let detail = match (simple, self.timed, spa.last, spb.first) {
            (true, false, Some(l), Some(f)) => {
                format!("{} (in {la}) comes after {} (in {lb})", cx.step_text(l), cx.step_text(f))
            }
            (true, true, Some(l), Some(f)) => format!(
                "{la} ends at {} ({}), not before {lb} starts at {} ({})",
                fmt_num(spa.end),
                cx.step_text(l),
                fmt_num(spb.start),
                cx.step_text(f)
            ),
            _ if self.timed => format!(
                "the points compared are at {} and {}",
                fmt_num(value(spa, d.from)),
                fmt_num(value(spb, d.to))
            ),
            _ => format!(
                "{la} spans actions {}–{} and {lb} actions {}–{} of the plan",
                spa.start as u64 + 1,
                spa.end as u64 + 1,
                spb.start as u64 + 1,
                spb.end as u64 + 1
            ),
        };
        let mut diag = cx.diag(
            codes::ORDERING_VIOLATED,
            ids[d.pb].range,
            format!(
                "{} orders {relation} through {} (refined into nothing) by {}, which the plan does not respect: {detail}",
                cx.owner_text(net),
                labels.join(" and "),
                constraints.join(" and ")
            ),
        );
        cx.related_plan(&mut diag, ids[d.pa].range, format!("{la} is step {}", ids[d.pa].value));
        for &t in &empties {
            if let Some(pt) = assign.iter().position(|&x| x == t) {
                cx.related_plan(
                    &mut diag,
                    ids[pt].range,
                    format!(
                        "{} is step {}, refined into no action: the orderings go through it",
                        subtask_label(network, t),
                        ids[pt].value
                    ),
                );
            }
        }
        for e in &d.path {
            match e.origin {
                Some(o) => cx.related_loc(&mut diag, Loc { item: net.item, span: o.span }, "the ordering"),
                None => {
                    if let Some(s) = network.subtasks.get(e.to.task) {
                        let l = subtask_label(network, e.from.task);
                        let msg = format!("{}, after {l}", subtask_label(network, e.to.task));
                        cx.related_loc(&mut diag, Loc { item: net.item, span: s.call.span }, msg);
                    }
                }
            }
        }
        let hint = if simple && !self.timed {
            format!(
                "orderings are transitive: every action below step {} must come before every action below step {}, even though {} between them has no action; reorder the primitive steps, or refine the tasks differently",
                ids[d.pa].value,
                ids[d.pb].value,
                labels.join(" and ")
            )
        } else {
            format!(
                "orderings are transitive, even through {} without actions: move the steps so that the constraint holds, or refine the tasks differently",
                labels.join(" and ")
            )
        };
        cx.hint(&mut diag, hint, Vec::new());
        cx.push(diag);
    }

    /// A timed abstract step must contain the times of its subtasks.
    pub(super) fn check_abstract_times(&self, cx: &mut Cx<'_, '_>) {
        if !self.timed {
            return;
        }
        for k in 0..cx.order.len() {
            let i = cx.order[k];
            let s = &cx.plan.steps[i];
            let (Some(start), Some(hull)) = (&s.start, self.span[i]) else { continue };
            if hull.first.is_none() {
                continue;
            }
            let end = s.end().unwrap_or(start.value);
            let early = hull.start < start.value - self.eps;
            let late = hull.end > end + self.eps;
            if !early && !late {
                continue;
            }
            let which = if early {
                hull.first.map(|f| format!("{} starts at {}", cx.step_text(f), fmt_num(hull.start)))
            } else {
                hull.last.map(|l| format!("{} ends at {}", cx.step_text(l), fmt_num(hull.end)))
            };
            let mut d = cx.diag(
                codes::ABSTRACT_STEP_TIMING,
                start.range,
                format!(
                    "{} is timed {}–{}, but its subtasks run {}–{}: {}",
                    cx.step_text(i),
                    fmt_num(start.value),
                    fmt_num(end),
                    fmt_num(hull.start),
                    fmt_num(hull.end),
                    which.unwrap_or_default()
                ),
            );
            if let Some(x) = if early { hull.first } else { hull.last } {
                cx.related_plan(&mut d, cx.plan.steps[x].range, "this action");
            }
            let dur = hull.end - hull.start;
            let mut edits: Vec<(TextRange, String)> = vec![(start.range, format!("{:.3}", hull.start))];
            if let Some(dn) = &s.duration {
                edits.push((dn.range, format!("{dur:.3}")));
            }
            cx.hint(
                &mut d,
                format!(
                    "an abstract step lasts while its subtasks run (HiPOP schedules a method's steps inside its abstract action): `;@ {} {:.3} [{dur:.3}]`",
                    cx.id_value(i),
                    hull.start,
                ),
                if s.duration.is_some() { edits } else { Vec::new() },
            );
            cx.push(d);
        }
    }
}

/// A point of a subtask: its start or its end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Pt {
    pub task: usize,
    pub end: bool,
}

/// `from` is before `to` (strictly, or at the same time at the latest), by
/// an ordering of the network (`None`: `:ordered-subtasks`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Edge<'t> {
    pub from: Pt,
    pub to: Pt,
    pub strict: bool,
    pub origin: Option<&'t Ordering>,
}

/// A violated ordering of a network.
pub(super) enum Violation<'t> {
    /// An ordering of the network between subtasks `a` and `b`, at the
    /// listed positions `pa` and `pb`.
    Direct { a: usize, b: usize, pa: usize, pb: usize, o: Option<&'t Ordering> },
    /// An ordering that follows through subtasks refined into nothing.
    Derived(Derived<'t>),
}

/// `from` before `to` through subtasks without actions: `path` goes from
/// `from` to `to`, each edge but the first leaving a subtask without actions.
pub(super) struct Derived<'t> {
    pub from: Pt,
    pub to: Pt,
    pub strict: bool,
    pub pa: usize,
    pub pb: usize,
    pub path: Vec<Edge<'t>>,
}

/// The orderings of a network, checked on the plan's spans under a matching
/// of its subtasks with the listed steps. A subtask refined into nothing (an
/// empty method, or methods down to one) has no span: its orderings hold on
/// their own, but it passes them on, as orderings are transitive: `a < t <
/// b` orders `a` before `b` even when `t` disappears.
pub(super) struct NetOrder<'t> {
    tl: &'t Timeline,
    network: &'t TaskNetwork,
    /// The plan step at each listed position.
    pub steps: Vec<Option<usize>>,
    /// The orderings: two subtasks and the constraint (`None`: `:ordered-subtasks`).
    orderings: Vec<(usize, usize, Option<&'t Ordering>)>,
    /// Their points, for orderings through subtasks refined into nothing.
    edges: Vec<Edge<'t>>,
}

impl<'t> NetOrder<'t> {
    pub(super) fn new(tl: &'t Timeline, network: &'t TaskNetwork, plan: &Plan, ids: &[StepId]) -> Self {
        let steps = ids.iter().map(|id| plan.index_of(id.value)).collect();
        let mut orderings: Vec<(usize, usize, Option<&Ordering>)> = Vec::new();
        if network.ordered {
            for j in 1..network.subtasks.len() {
                orderings.push((j - 1, j, None));
            }
        }
        for o in &network.ordering {
            if let (Some(a), Some(b)) =
                (subtask_index(network, o.left.id.key()), subtask_index(network, o.right.id.key()))
            {
                orderings.push((a, b, Some(o)));
            }
        }
        let edges = orderings.iter().flat_map(|&(a, b, o)| point_edges(a, b, o)).collect();
        NetOrder { tl, network, steps, orderings, edges }
    }

    fn holds_on(&self, spa: Span, spb: Span, o: Option<&Ordering>) -> bool {
        let (op, negated, ea, eb) = match o {
            Some(o) => (o.op, o.negated, o.left.endpoint, o.right.endpoint),
            None => (CmpOp::Lt, false, Endpoint::Whole, Endpoint::Whole),
        };
        holds(op, (spa, ea), (spb, eb), self.tl.eps) != negated
    }

    /// The orderings violated under `assign` (`assign[pos]`: the subtask of
    /// the step listed at `pos`); with `sound`, only between steps whose
    /// subtrees checked out.
    pub(super) fn violations(&self, assign: &[usize], sound: Option<&[bool]>) -> Vec<Violation<'t>> {
        let pos_of = |j: usize| assign.iter().position(|&a| a == j);
        let ok = |s: usize| sound.is_none_or(|so| so[s]);
        let mut out = Vec::new();
        // Pairs of subtasks reported, once each.
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        for &(a, b, o) in &self.orderings {
            let (Some(pa), Some(pb)) = (pos_of(a), pos_of(b)) else { continue };
            let (Some(sa), Some(sb)) = (self.steps[pa], self.steps[pb]) else { continue };
            if !(ok(sa) && ok(sb)) {
                continue;
            }
            let (Some(spa), Some(spb)) = (self.tl.span[sa], self.tl.span[sb]) else { continue };
            if self.holds_on(spa, spb, o) {
                continue;
            }
            pairs.push((a.min(b), a.max(b)));
            out.push(Violation::Direct { a, b, pa, pb, o });
        }
        // Through subtasks refined into nothing: `Some(true)` for those,
        // `Some(false)` for subtasks with a span, `None` for the others.
        let n = self.network.subtasks.len();
        let empty: Vec<Option<bool>> = (0..n)
            .map(|j| {
                let s = pos_of(j).and_then(|p| self.steps[p])?;
                ok(s).then(|| self.tl.span[s].is_none())
            })
            .collect();
        if !empty.contains(&Some(true)) {
            return out;
        }
        let is_empty = |t: usize| empty[t] == Some(true);
        let timed = |t: usize| empty[t] == Some(false);
        // A subtask without actions is one point: its start is its end.
        let same = |p: Pt, q: Pt| p.task == q.task && (p.end == q.end || is_empty(p.task));
        let mut sources: Vec<Pt> = Vec::new();
        for e in &self.edges {
            if timed(e.from.task) && is_empty(e.to.task) && !sources.contains(&e.from) {
                sources.push(e.from);
            }
        }
        let mut found: Vec<Derived<'t>> = Vec::new();
        for &u in &sources {
            // States: (a subtask without actions, strict so far), with the
            // path that reached it.
            let mut seen: Vec<(usize, bool)> = Vec::new();
            let mut queue: std::collections::VecDeque<(usize, bool, Vec<Edge<'t>>)> = Default::default();
            for e in self.edges.iter().filter(|e| same(e.from, u) && is_empty(e.to.task)) {
                if !seen.contains(&(e.to.task, e.strict)) {
                    seen.push((e.to.task, e.strict));
                    queue.push_back((e.to.task, e.strict, vec![*e]));
                }
            }
            while let Some((t, strict, path)) = queue.pop_front() {
                for e in self.edges.iter().filter(|e| e.from.task == t) {
                    let s = strict || e.strict;
                    let mut next = path.clone();
                    next.push(*e);
                    if is_empty(e.to.task) {
                        if !seen.contains(&(e.to.task, s)) {
                            seen.push((e.to.task, s));
                            queue.push_back((e.to.task, s, next));
                        }
                    } else if timed(e.to.task) && e.to.task != u.task {
                        let w = e.to;
                        match found.iter_mut().find(|d| d.from == u && d.to == w) {
                            Some(d) => {
                                if s && !d.strict {
                                    d.strict = true;
                                    d.path = next;
                                }
                            }
                            None => {
                                let (Some(pa), Some(pb)) = (pos_of(u.task), pos_of(w.task)) else { continue };
                                found.push(Derived { from: u, to: w, strict: s, pa, pb, path: next });
                            }
                        }
                    }
                }
            }
        }
        for d in found {
            let pair = (d.from.task.min(d.to.task), d.from.task.max(d.to.task));
            if pairs.contains(&pair) {
                continue;
            }
            let (Some(sa), Some(sb)) = (self.steps[d.pa], self.steps[d.pb]) else { continue };
            let (Some(spa), Some(spb)) = (self.tl.span[sa], self.tl.span[sb]) else { continue };
            let value = |sp: Span, p: Pt| if p.end { sp.end } else { sp.start };
            let (x, y) = (value(spa, d.from), value(spb, d.to));
            let holds = if d.strict { y - x > self.tl.eps } else { x <= y + self.tl.eps };
            if !holds {
                pairs.push(pair);
                out.push(Violation::Derived(d));
            }
        }
        out
    }
}

impl OrderingCheck for NetOrder<'_> {
    fn partial(&self, assign: &[Option<usize>], pos: usize) -> bool {
        let Some(j) = assign.get(pos).copied().flatten() else { return true };
        let span_of = |k: usize| {
            let p = assign.iter().position(|&x| x == Some(k))?;
            self.tl.span[self.steps[p]?]
        };
        self.orderings.iter().filter(|(a, b, _)| *a == j || *b == j).all(|&(a, b, o)| {
            match (span_of(a), span_of(b)) {
                (Some(spa), Some(spb)) => self.holds_on(spa, spb, o),
                _ => true,
            }
        })
    }

    fn complete(&self, assign: &[usize]) -> bool {
        self.violations(assign, None).is_empty()
    }
}

/// The points an ordering between subtasks `a` and `b` orders (none for a
/// negated equality, a disjunction): what [`holds`] compares.
fn point_edges(a: usize, b: usize, o: Option<&Ordering>) -> Vec<Edge<'_>> {
    let (op, negated, ea, eb) = match o {
        Some(o) => (o.op, o.negated, o.left.endpoint, o.right.endpoint),
        None => (CmpOp::Lt, false, Endpoint::Whole, Endpoint::Whole),
    };
    // The point of a subtask at an endpoint; a whole task stands for its end
    // or its start, as `holds` picks.
    let pt = |task: usize, e: Endpoint, whole_end: bool| Pt {
        task,
        end: match e {
            Endpoint::Start => false,
            Endpoint::End => true,
            Endpoint::Whole => whole_end,
        },
    };
    let edge = |from: Pt, to: Pt, strict: bool| Edge { from, to, strict, origin: o };
    let (a_end, b_start) = (pt(a, ea, true), pt(b, eb, false));
    let (a_start, b_end) = (pt(a, ea, false), pt(b, eb, true));
    match (op, negated) {
        (CmpOp::Lt, false) => vec![edge(a_end, b_start, true)],
        (CmpOp::Lt, true) => vec![edge(b_start, a_end, false)],
        (CmpOp::Le, false) => vec![edge(a_end, b_start, false)],
        (CmpOp::Le, true) => vec![edge(b_start, a_end, true)],
        (CmpOp::Gt, false) => vec![edge(b_end, a_start, true)],
        (CmpOp::Gt, true) => vec![edge(a_start, b_end, false)],
        (CmpOp::Ge, false) => vec![edge(b_end, a_start, false)],
        (CmpOp::Ge, true) => vec![edge(a_start, b_end, true)],
        (CmpOp::Eq, false) if ea == Endpoint::Whole && eb == Endpoint::Whole => {
            let (sa, sb) = (Pt { task: a, end: false }, Pt { task: b, end: false });
            let (fa, fb) = (Pt { task: a, end: true }, Pt { task: b, end: true });
            vec![edge(sa, sb, false), edge(sb, sa, false), edge(fa, fb, false), edge(fb, fa, false)]
        }
        (CmpOp::Eq, false) => vec![edge(a_start, b_start, false), edge(b_start, a_start, false)],
        (CmpOp::Eq, true) => Vec::new(),
    }
}

/// Whether `(op left right)` holds: a whole task on the left of `<` is its
/// end, on the right its start (the reverse for `>`); `=` of two whole tasks
/// is the same interval.
pub(super) fn holds(op: CmpOp, (a, ea): (Span, Endpoint), (b, eb): (Span, Endpoint), eps: f64) -> bool {
    let pick = |s: Span, e: Endpoint, whole_end: bool| match e {
        Endpoint::Start => s.start,
        Endpoint::End => s.end,
        Endpoint::Whole if whole_end => s.end,
        Endpoint::Whole => s.start,
    };
    match op {
        CmpOp::Lt => pick(b, eb, false) - pick(a, ea, true) > eps,
        CmpOp::Le => pick(a, ea, true) <= pick(b, eb, false) + eps,
        CmpOp::Gt => pick(a, ea, false) - pick(b, eb, true) > eps,
        CmpOp::Ge => pick(a, ea, false) + eps >= pick(b, eb, true),
        CmpOp::Eq if ea == Endpoint::Whole && eb == Endpoint::Whole => {
            (a.start - b.start).abs() <= eps && (a.end - b.end).abs() <= eps
        }
        CmpOp::Eq => (pick(a, ea, false) - pick(b, eb, false)).abs() <= eps,
    }
}

/// An ordering as the domain writes it, with its ids.
fn ordering_text(o: &Ordering) -> String {
    let point = |p: &crate::model::OrderPoint| match p.endpoint {
        Endpoint::Whole => p.id.text().to_string(),
        Endpoint::Start => format!("(start {})", p.id.text()),
        Endpoint::End => format!("(end {})", p.id.text()),
    };
    let op = match o.op {
        CmpOp::Lt => "<",
        CmpOp::Le => "<=",
        CmpOp::Eq => "=",
        CmpOp::Ge => ">=",
        CmpOp::Gt => ">",
    };
    let inner = format!("({op} {} {})", point(&o.left), point(&o.right));
    if o.negated { format!("`(not {inner})`") } else { format!("`{inner}`") }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(start: f64, end: f64) -> Span {
        Span { start, end, first: None, last: None }
    }

    #[test]
    fn orderings_compare_the_right_points() {
        let (a, b) = (span(0.0, 5.0), span(5.01, 8.0));
        let w = Endpoint::Whole;
        assert!(holds(CmpOp::Lt, (a, w), (b, w), 0.001));
        assert!(!holds(CmpOp::Lt, (a, w), (b, w), 0.1), "within the tolerance: the same instant");
        assert!(holds(CmpOp::Le, (a, w), (b, w), 0.1));
        assert!(holds(CmpOp::Gt, (b, w), (a, w), 0.001));
        assert!(holds(CmpOp::Lt, (a, Endpoint::Start), (b, Endpoint::Start), 0.0));
        assert!(!holds(CmpOp::Lt, (b, Endpoint::Start), (a, Endpoint::End), 0.0));
        assert!(holds(CmpOp::Eq, (a, w), (span(0.0, 5.0), w), 0.0));
        assert!(!holds(CmpOp::Eq, (a, w), (span(0.0, 6.0), w), 0.0));
        assert!(holds(CmpOp::Eq, (a, Endpoint::End), (span(5.0, 9.0), Endpoint::Start), 0.0));
        // Sequential plans: positions, no tolerance.
        assert!(holds(CmpOp::Lt, (span(0.0, 2.0), w), (span(3.0, 3.0), w), 0.0));
        assert!(!holds(CmpOp::Lt, (span(0.0, 3.0), w), (span(3.0, 3.0), w), 0.0));
    }
}
