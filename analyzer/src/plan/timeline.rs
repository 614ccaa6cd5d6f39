//! Per-agent timelines of a plan, as in Figures 9 and 21 of the HiPOP paper:
//! one lane per agent, each step a bar from its start to its end. Built from
//! a [`Plan`] and the domain's [`AgentTable`]; drawn by [`gantt_text`] (a
//! terminal Gantt chart) and [`svg`] (a standalone picture).
//!
//! - **Lanes.** One per agent, in the order the agents first appear in the
//!   plan's steps (the order of the file), agents compared as the table
//!   compares names (case ignored). Steps whose agents are unknown are in a
//!   last lane, [`NO_AGENT`]. A step with several agents (`communicate r1
//!   r2`) is drawn in each of its agents' lanes.
//! - **Times.** A step's own start and duration when the plan gives them. In
//!   a plan without any time (a sequential or IPC 2020 plan), the k-th
//!   primitive step (0-based, in the order of the file) fills the slot from k
//!   to k + 1. In a timed plan, a primitive step without a time is where VAL
//!   executes it: the k-th such step (1-based) at time k.
//! - **Abstract steps** (with a decomposition) are bands above the actions of
//!   their lanes, outermost first: their own times when a timed plan gives
//!   them (HiPOP's abstract actions have their own), else from the first
//!   start to the last end of their subtasks; their lanes are their own
//!   agents (a task's `:agent`), else the lanes of their subtasks. An
//!   abstract step with neither times nor timed subtasks is not drawn
//!   ([`Timeline::undrawn`]).
//! - **Rows.** Steps of one lane that overlap in time are on separate rows
//!   (first fit, in order of start); an instantaneous step overlaps a step
//!   that starts at its time or runs through it.
//!
//! Architecture invariant: pure; the renderers build strings.

mod gantt;
mod svg;

#[cfg(test)]
mod tests;

use rustc_hash::FxHashMap;

pub use gantt::{GanttOptions, gantt_text};
pub use svg::svg;

use super::agents::AgentTable;
use super::{Plan, normalise_name};

/// The name of the lane of the steps whose agents are unknown.
pub const NO_AGENT: &str = "(no agent)";

/// Where a bar's times come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Timing {
    /// The plan gives the step's start (and duration).
    Given,
    /// The plan gives no time for the step: placed by its position (a slot
    /// in an untimed plan; VAL's time in a timed one).
    Position,
    /// An abstract step without times of its own: the span of its subtasks.
    Subtasks,
}

/// One step of the plan on the timeline.
#[derive(Debug, Clone, PartialEq)]
pub struct Bar {
    /// The step's index in [`Plan::steps`].
    pub step: usize,
    /// The number shown on the chart and in the legend: 1 for the first bar
    /// of [`Timeline::bars`], and so on.
    pub key: usize,
    /// The step's id (hierarchical and JSON plans).
    pub id: Option<u32>,
    /// The action or task, as written.
    pub name: String,
    /// `(name arg…)`, as written.
    pub call: String,
    /// `Some(method)` for an abstract step.
    pub method: Option<String>,
    pub start: f64,
    /// At least `start`.
    pub end: f64,
    pub timing: Timing,
    /// The lanes the bar is drawn in (indices in [`Timeline::lanes`]), at least one.
    pub lanes: Vec<usize>,
    /// Abstract steps: how deep in the decomposition (0 for a root).
    pub depth: usize,
}

impl Bar {
    pub fn is_abstract(&self) -> bool {
        self.method.is_some()
    }

    /// A step that ends when it starts.
    pub fn is_instant(&self) -> bool {
        self.end <= self.start
    }

    /// Whether `self` is over before `other` starts (and the two can share a
    /// row): an instantaneous step is not over at its own time.
    fn before(&self, other: &Bar) -> bool {
        self.end < other.start || (self.end == other.start && !self.is_instant())
    }
}

/// What a row of a lane holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    /// Abstract steps of this depth in the decomposition.
    Abstract {
        depth: usize,
    },
    Actions,
}

/// Bars of one lane that do not overlap, in order of start.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub kind: RowKind,
    /// Indices in [`Timeline::bars`].
    pub bars: Vec<usize>,
}

/// The steps of one agent.
#[derive(Debug, Clone, PartialEq)]
pub struct Lane {
    /// The agent as first written, or [`NO_AGENT`].
    pub name: String,
    /// Abstract rows (outermost first), then the rows of actions.
    pub rows: Vec<Row>,
}

/// A plan laid out per agent.
#[derive(Debug, Clone, PartialEq)]
pub struct Timeline {
    pub lanes: Vec<Lane>,
    /// Every drawn step once, in order of start (an abstract step before the
    /// steps it contains), then of the file.
    pub bars: Vec<Bar>,
    /// Whether the plan has times; `false`: the time unit is a step.
    pub timed: bool,
    /// Where the axis starts: 0, or the earliest start if one is negative.
    pub start: f64,
    /// Where the axis ends: the latest end (at least `start`).
    pub end: f64,
    /// The latest end of a primitive step (0 without any).
    pub makespan: f64,
    /// Abstract steps that are not drawn: neither times nor timed subtasks
    /// (indices in [`Plan::steps`]).
    pub undrawn: Vec<usize>,
}

impl Timeline {
    /// The number of primitive steps drawn.
    pub fn actions(&self) -> usize {
        self.bars.iter().filter(|b| !b.is_abstract()).count()
    }

    /// Where `t` is between [`Timeline::start`] (0) and [`Timeline::end`]
    /// (1); 0 when the timeline has no length. Never overflows.
    pub fn fraction(&self, t: f64) -> f64 {
        // Halves: the difference of two finite numbers may overflow, that of their halves does not.
        let span = self.end / 2.0 - self.start / 2.0;
        if span.is_nan() || span <= 0.0 {
            return 0.0;
        }
        ((t / 2.0 - self.start / 2.0) / span).clamp(0.0, 1.0)
    }
}

/// A finite number: infinities (a start plus a huge duration) become the largest finite ones.
fn finite(v: f64) -> f64 {
    if v.is_nan() { 0.0 } else { v.clamp(f64::MIN, f64::MAX) }
}

/// Lays `plan` out per agent, with the agents `agents` gives each step.
pub fn timeline(plan: &Plan, agents: &AgentTable) -> Timeline {
    let n = plan.steps.len();
    let prims: Vec<usize> = plan.primitive_steps().map(|(i, _)| i).collect();
    let timed = prims.iter().any(|&i| plan.steps[i].start.is_some());

    // Primitive steps' places.
    let mut place: Vec<Option<(f64, f64, Timing)>> = vec![None; n];
    let mut untimed = 0.0;
    for (k, &i) in prims.iter().enumerate() {
        let s = &plan.steps[i];
        let duration = s.duration.as_ref().map_or(0.0, |d| d.value);
        place[i] = Some(match (&s.start, timed) {
            (Some(start), true) => {
                let end = finite(start.value + duration);
                (start.value.min(end), start.value.max(end), Timing::Given)
            }
            (None, true) => {
                untimed += 1.0;
                let end = finite(untimed + duration);
                (untimed.min(end), untimed.max(end), Timing::Position)
            }
            (_, false) => (k as f64, k as f64 + 1.0, Timing::Position),
        });
    }

    // Lanes: keys are the names as the table compares them; `None` is the
    // lane of unknown agents, created last.
    let matching = agents.matching();
    let mut lane_names: Vec<String> = Vec::new();
    let mut lane_index: FxHashMap<String, usize> = FxHashMap::default();
    let mut own_lanes: Vec<Vec<usize>> = Vec::with_capacity(n);
    for s in &plan.steps {
        let mut lanes = Vec::new();
        for a in agents.agents_of(s) {
            let key = normalise_name(&a, matching).into_owned();
            let next = lane_names.len();
            let l = *lane_index.entry(key).or_insert(next);
            if l == next {
                lane_names.push(a);
            }
            if !lanes.contains(&l) {
                lanes.push(l);
            }
        }
        own_lanes.push(lanes);
    }
    let no_agent = lane_names.len();
    let mut lanes_of: Vec<Vec<usize>> = own_lanes
        .iter()
        .zip(&plan.steps)
        .map(|(l, s)| if l.is_empty() && !s.is_abstract() { vec![no_agent] } else { l.clone() })
        .collect();

    // Abstract steps, children before parents (iteratively: a malformed
    // plan may have long chains or cycles).
    let children = |i: usize| -> Vec<usize> {
        plan.steps[i]
            .decomposition
            .as_ref()
            .map_or_else(Vec::new, |d| d.subtasks.iter().filter_map(|id| plan.index_of(id.value)).collect())
    };
    let mut state = vec![0u8; n]; // 0 unseen, 1 on the stack, 2 done
    for (root, _) in plan.abstract_steps() {
        if state[root] != 0 {
            continue;
        }
        state[root] = 1;
        let mut stack: Vec<(usize, Vec<usize>, usize)> = vec![(root, children(root), 0)];
        while let Some(top) = stack.last_mut() {
            if let Some(&j) = top.1.get(top.2) {
                top.2 += 1;
                if plan.steps[j].is_abstract() && state[j] == 0 {
                    state[j] = 1;
                    stack.push((j, children(j), 0));
                }
                continue;
            }
            let (i, subs, _) = stack.pop().expect("the stack is not empty");
            state[i] = 2;
            let s = &plan.steps[i];
            let hull =
                subs.iter().filter_map(|&j| place[j]).fold(None, |h: Option<(f64, f64)>, (a, b, _)| {
                    Some(h.map_or((a, b), |(x, y)| (x.min(a), y.max(b))))
                });
            place[i] = match (&s.start, timed) {
                (Some(start), true) => {
                    let end = finite(start.value + s.duration.as_ref().map_or(0.0, |d| d.value));
                    Some((start.value.min(end), start.value.max(end), Timing::Given))
                }
                _ => hull.map(|(a, b)| (a, b, Timing::Subtasks)),
            };
            if lanes_of[i].is_empty() {
                let mut lanes: Vec<usize> = Vec::new();
                for &j in &subs {
                    for &l in &lanes_of[j] {
                        if !lanes.contains(&l) {
                            lanes.push(l);
                        }
                    }
                }
                lanes.sort_unstable();
                lanes_of[i] = if lanes.is_empty() { vec![no_agent] } else { lanes };
            }
        }
    }

    let depth = abstract_depths(plan);

    // The bars, in order of start, abstract steps (outermost first) before
    // actions at the same time, then the file's order.
    let mut order: Vec<usize> = (0..n).filter(|&i| place[i].is_some()).collect();
    order.sort_by(|&x, &y| {
        let (sx, sy) = (place[x].map_or(0.0, |p| p.0), place[y].map_or(0.0, |p| p.0));
        sx.total_cmp(&sy)
            .then(plan.steps[y].is_abstract().cmp(&plan.steps[x].is_abstract()))
            .then(depth[x].cmp(&depth[y]))
            .then(x.cmp(&y))
    });
    lane_names.push(NO_AGENT.to_string());
    // Only the lanes of drawn steps, in their order (an agent of an undrawn
    // abstract step only has no lane).
    let mut used = vec![false; lane_names.len()];
    order.iter().flat_map(|&i| &lanes_of[i]).for_each(|&l| used[l] = true);
    let mut renumber = vec![usize::MAX; lane_names.len()];
    let mut kept = Vec::new();
    for (l, name) in lane_names.into_iter().enumerate() {
        if used[l] {
            renumber[l] = kept.len();
            kept.push(name);
        }
    }
    for l in lanes_of.iter_mut().flatten() {
        *l = renumber[*l];
    }
    let bars: Vec<Bar> = order
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            let s = &plan.steps[i];
            let (start, end, timing) = place[i].expect("placed steps only");
            Bar {
                step: i,
                key: k + 1,
                id: s.id.map(|id| id.value),
                name: s.name.text.to_string(),
                call: s.call(),
                method: s.decomposition.as_ref().map(|d| d.method.text.to_string()),
                start,
                end,
                timing,
                lanes: lanes_of[i].clone(),
                depth: depth[i],
            }
        })
        .collect();
    let undrawn: Vec<usize> = plan.abstract_steps().map(|(i, _)| i).filter(|&i| place[i].is_none()).collect();

    // Rows: per lane, abstract steps by depth, then actions; first fit.
    let mut lanes: Vec<Lane> = kept.into_iter().map(|name| Lane { name, rows: Vec::new() }).collect();
    let mut per_lane: Vec<Vec<usize>> = vec![Vec::new(); lanes.len()];
    for (b, bar) in bars.iter().enumerate() {
        for &l in &bar.lanes {
            per_lane[l].push(b);
        }
    }
    for (lane, members) in lanes.iter_mut().zip(per_lane) {
        let mut depths: Vec<usize> =
            members.iter().filter(|&&b| bars[b].is_abstract()).map(|&b| bars[b].depth).collect();
        depths.sort_unstable();
        depths.dedup();
        for d in depths {
            let group = members.iter().copied().filter(|&b| bars[b].is_abstract() && bars[b].depth == d);
            lane.rows.extend(pack(&bars, group, RowKind::Abstract { depth: d }));
        }
        let actions = members.iter().copied().filter(|&b| !bars[b].is_abstract());
        lane.rows.extend(pack(&bars, actions, RowKind::Actions));
    }

    let start = bars.iter().map(|b| b.start).fold(0.0, f64::min);
    let end = bars.iter().map(|b| b.end).fold(start, f64::max);
    let makespan = bars.iter().filter(|b| !b.is_abstract()).map(|b| b.end).fold(0.0, f64::max);
    Timeline { lanes, bars, timed, start, end, makespan, undrawn }
}

/// Puts each bar (in order of start) in the first row it does not overlap.
fn pack(bars: &[Bar], members: impl Iterator<Item = usize>, kind: RowKind) -> Vec<Row> {
    let mut rows: Vec<Row> = Vec::new();
    for b in members {
        match rows.iter_mut().find(|r| r.bars.last().is_none_or(|&last| bars[last].before(&bars[b]))) {
            Some(r) => r.bars.push(b),
            None => rows.push(Row { kind, bars: vec![b] }),
        }
    }
    rows
}

/// How deep each abstract step is in the decomposition: 0 for the roots (the
/// `root` line's, or the abstract steps that are no step's subtask), and for
/// abstract steps no root reaches; 0 for primitive steps.
fn abstract_depths(plan: &Plan) -> Vec<usize> {
    let n = plan.steps.len();
    let mut depth = vec![0usize; n];
    let mut seen = vec![false; n];
    let subtasks = |i: usize| {
        plan.steps[i]
            .decomposition
            .iter()
            .flat_map(|d| d.subtasks.iter())
            .filter_map(|id| plan.index_of(id.value))
            .filter(|&j| plan.steps[j].is_abstract())
    };
    let roots: Vec<usize> = match &plan.root {
        Some(root) => root
            .ids
            .iter()
            .filter_map(|id| plan.index_of(id.value))
            .filter(|&i| plan.steps[i].is_abstract())
            .collect(),
        None => {
            let mut child = vec![false; n];
            for (i, _) in plan.abstract_steps() {
                subtasks(i).for_each(|j| child[j] = true);
            }
            plan.abstract_steps().map(|(i, _)| i).filter(|&i| !child[i]).collect()
        }
    };
    let mut queue: std::collections::VecDeque<usize> = roots.into_iter().collect();
    queue.iter().for_each(|&i| seen[i] = true);
    while let Some(i) = queue.pop_front() {
        for j in subtasks(i) {
            if !std::mem::replace(&mut seen[j], true) {
                depth[j] = depth[i] + 1;
                queue.push_back(j);
            }
        }
    }
    depth
}
