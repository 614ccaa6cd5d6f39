//! Plan repair after disruptive events (section 5 of the HiPOP paper,
//! Figure 10): "unrefine, then refine". The plan being executed is read
//! against the new problem; the planner searches again from what is left
//! of it, removing more of it each time the search fails, until a last
//! search from the empty plan (a full replan).
//!
//! - Stage 1 (obsolete elements): steps whose action or task no longer
//!   exists for those arguments, top-level steps no longer allowed (𝒜), the
//!   subtasks of a decomposition whose method is gone; then, until none is
//!   left, top-level steps that support nothing (no causal link leaves
//!   them). The search starts from the rest.
//! - Deadlines (Figure 14, stages 3–4): while the steps left cannot be
//!   scheduled (a step ran late, a window closes earlier), the steps
//!   between now and the next deadline (a timed initial literal) are
//!   removed, one deadline after the other.
//! - Rings: on failure, the steps next to those removed at the previous
//!   stage (a causal link of the old plan between them, or the same agent's
//!   step just before or after in the old schedule) are removed, and the
//!   search starts again.
//! - Hierarchy (5.1.1): a subtask removed un-refines its abstract step as a
//!   whole (every step its method added goes; the abstract step stays, to
//!   be refined again); an abstract step removed takes its subtasks with it.
//!   `flat` (the paper's repairFlat) discards the hierarchy first.
//! - Phantom links (5.1.2): the orderings of the old plan between the steps
//!   that stay, through the steps removed, are kept.
//! - Frozen steps (5.3, 5.4): executed and running steps (fixed at their
//!   old times) and the steps of unreachable agents are never removed.
//! - The last stage plans from scratch with the caller's configuration.
//! - Meetings (5.5): when even that fails, the goals only actions of two
//!   agents or more achieve are dropped (an unreachable agent's first) and
//!   the repair starts again.
//!
//! With geometric reasoning, the old plan's top-level moves are not put in
//! the start plan: the itineraries add moves again between the visits,
//! which the phantom links keep in their old order. Pure, like the planner:
//! limits, cancellation and progress come from the caller.

mod old;
mod order;

use std::time::{Duration, Instant};

use rustc_hash::FxHashSet;

use crate::db::{Db, Unit};
use crate::plan::Plan as PlanFile;
use crate::planner::output::SolvedPlan;
use crate::planner::search::{Search, Seed, SeedOrder, SeedStep};
use crate::planner::stn::{EPS, Tp};
use crate::planner::task::End;
use crate::planner::{Config, Motion, PlannerLimits, Prepared, Progress, Stats, Status, prepare};
use crate::verify::Lint;

pub use old::{Execution, Missing, OldStep};

/// How to repair.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RepairOptions {
    pub execution: Execution,
    /// repairFlat: the old plan's hierarchy discarded (its primitive steps kept).
    pub flat: bool,
}

/// A stage of the repair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// The search from the old plan without its obsolete steps.
    Obsolete,
    /// The search after removing the `n`-th ring of steps around those removed.
    Ring(u32),
    /// The search from the empty plan.
    Replan,
}

impl Stage {
    pub fn describe(self) -> String {
        match self {
            Stage::Obsolete => "stage 1 (obsolete steps removed)".into(),
            Stage::Ring(n) => format!("stage {} (ring {n} of steps around those removed)", n + 1),
            Stage::Replan => "the full replan".into(),
        }
    }
}

/// Why a step of the old plan was removed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Why {
    /// No action or task of that name for those arguments in the new problem.
    NoOperator,
    /// A top-level step whose action is no longer allowed (not in 𝒜).
    NotAllowed,
    /// Its abstract step's method no longer has these subtasks.
    MethodGone,
    /// It supported nothing any more.
    SupportsNothing,
    /// Its abstract step was un-refined (another of its subtasks was removed).
    Unrefined,
    /// A subtask of an abstract step removed.
    UnderRemoved,
    /// repairFlat: an abstract step, discarded with the hierarchy.
    Flat,
    /// In the `n`-th ring around the steps removed.
    Ring(u32),
    /// Between now and a deadline that the plan misses (Figure 14).
    Deadline(f64),
    /// A condition that only the initial state and the timed literals give
    /// no longer holds from now on (a robot out of service, a window closed).
    ConditionGone,
    /// An abstract step un-refined while some of its subtasks had run
    /// (5.3): it goes, the subtasks that ran stay on their own, and every
    /// action may be inserted to finish its work (𝒜 = A).
    HalfExecuted,
    /// A move of the old plan from where its robot no longer is (it starts
    /// elsewhere, or the moves before it were removed): its route is
    /// planned again from where the robot is.
    Rerouted,
    /// The full replan removed every step.
    Replan,
}

impl Why {
    pub fn describe(self) -> String {
        match self {
            Why::NoOperator => "obsolete: no action or task of that name for these arguments".into(),
            Why::NotAllowed => "obsolete: the action is no longer allowed".into(),
            Why::MethodGone => "obsolete: its method no longer exists with these subtasks".into(),
            Why::SupportsNothing => "it supported nothing any more".into(),
            Why::Unrefined => "its abstract step was un-refined".into(),
            Why::UnderRemoved => "its abstract step was removed".into(),
            Why::Flat => "the hierarchy is discarded (repairFlat)".into(),
            Why::Ring(n) => format!("ring {n}: next to a step removed"),
            Why::Deadline(t) => format!("it comes before the deadline at {t}, which the plan misses"),
            Why::ConditionGone => {
                "obsolete: a condition that only the initial state and timed literals give never holds again"
                    .into()
            }
            Why::HalfExecuted => {
                "it was half executed: the subtasks that ran stay, and every action may now finish its work (𝒜 = A)"
                    .into()
            }
            Why::Rerouted => {
                "its robot is no longer where it starts from: the route is planned again from where it is"
                    .into()
            }
            Why::Replan => "the full replan starts from nothing".into(),
        }
    }
}

/// A step of the old plan removed by the repair.
#[derive(Debug, Clone, PartialEq)]
pub struct Removed {
    /// Its index in the old plan's steps.
    pub step: usize,
    pub why: Why,
    pub stage: Stage,
}

impl Removed {
    /// Why it was removed, in words; for an obsolete step, what the new
    /// problem lacks (`old` are the old plan's steps).
    pub fn describe(&self, old: &[OldStep]) -> String {
        match (self.why, old.get(self.step).map(|s| (&s.op, &s.call))) {
            (Why::NoOperator, Some((Err(missing), call))) => missing.describe(call),
            (why, _) => why.describe(),
        }
    }
}

/// One search of the repair.
#[derive(Debug, Clone, PartialEq)]
pub struct StageRun {
    pub stage: Stage,
    /// Steps of the old plan in the start plan.
    pub kept: usize,
    /// Goals searched for (fewer once meetings are dropped).
    pub goals: usize,
    pub status: Status,
    pub expanded: u64,
    pub elapsed: Duration,
}

/// The result of a repair.
pub struct RepairOutcome<'db> {
    pub status: Status,
    /// The stage that found the plan.
    pub stage: Option<Stage>,
    pub plan: Option<SolvedPlan>,
    /// The old plan's steps, as read against the new problem.
    pub old: Vec<OldStep>,
    pub removed: Vec<Removed>,
    pub stages: Vec<StageRun>,
    /// The goals dropped (meetings that cannot be kept, 5.5).
    pub dropped: Vec<DroppedGoal>,
    /// Why there is no plan (the last search's flaws), or why the problem
    /// cannot be planned.
    pub lints: Vec<Lint<'db>>,
    pub stats: Stats,
}

/// A goal the repair dropped (section 5.5: a meeting that cannot be kept).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DroppedGoal {
    /// The goal, as `(met r1 r2)`.
    pub goal: String,
    /// Whether one of the agents that could meet is unreachable.
    pub unreachable: bool,
}

/// Repairs `old_plan` for `problem`. When no plan is found, even by the
/// full replan, the meetings are dropped (goals that only actions of two
/// agents or more achieve): first those with an unreachable agent, then
/// all of them, and the repair starts again each time (5.5).
#[allow(clippy::too_many_arguments)]
pub fn repair<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    old_plan: &PlanFile,
    config: &Config,
    limits: &PlannerLimits,
    options: &RepairOptions,
    cancel: &dyn Fn() -> bool,
    progress: &mut dyn FnMut(&Progress),
) -> RepairOutcome<'db> {
    let started = Instant::now();
    // Every reachable instance: the old plan's steps keep theirs.
    let limits = &PlannerLimits { goal_relevance: false, ..limits.clone() };
    let mut prepared = match prepare(db, problem, config, limits) {
        Ok(p) => p,
        Err(outcome) => {
            return RepairOutcome {
                status: outcome.status,
                stage: None,
                plan: outcome.plan,
                old: Vec::new(),
                removed: Vec::new(),
                stages: Vec::new(),
                dropped: Vec::new(),
                lints: outcome.lints,
                stats: outcome.stats,
            };
        }
    };
    out_of_reach(&mut prepared, &options.execution.unreachable);
    let rounds = meetings(&prepared.task, &options.execution.unreachable);
    let mut dropped: Vec<DroppedGoal> = Vec::new();
    let mut dropped_lits = Vec::new();
    let mut stages = Vec::new();
    let mut round = 0;
    loop {
        let mut out = attempt(
            db,
            &prepared,
            &dropped_lits,
            old_plan,
            config,
            limits,
            options,
            started,
            cancel,
            progress,
        );
        stages.append(&mut out.stages);
        out.stages = std::mem::take(&mut stages);
        let retry = out.status == Status::NoPlan && !cancel();
        let next = rounds.iter().skip(round).position(|r| !r.is_empty());
        let (true, Some(k)) = (retry, next) else {
            out.dropped = dropped;
            return out;
        };
        round += k + 1;
        let goals = &rounds[round - 1];
        let task = &mut prepared.task;
        for &(l, unreachable) in goals {
            if task.goals.iter().any(|g| g.0 == l) {
                dropped.push(DroppedGoal { goal: task.show_lit(l), unreachable });
            }
        }
        task.goals.retain(|g| !goals.iter().any(|&(l, _)| l == g.0));
        dropped_lits.extend(goals.iter().map(|&(l, _)| l));
        stages = out.stages;
    }
}

/// The meetings among the goals, in the order they are dropped: those an
/// unreachable agent takes part in, then the others. A meeting is a goal
/// that only actions of two agents or more achieve.
fn meetings(
    task: &crate::planner::task::Task<'_>,
    unreachable: &[String],
) -> [Vec<(crate::planner::task::Lit, bool)>; 2] {
    let mut out = [Vec::new(), Vec::new()];
    for &(l, _) in &task.goals {
        // Every operator that makes it true, allowed or not.
        let achievers: Vec<&crate::planner::task::Op<'_>> =
            task.ops.iter().filter(|o| o.effs.iter().any(|e| e.lit == l)).collect();
        if achievers.is_empty() || achievers.iter().any(|o| o.agents.len() < 2) {
            continue;
        }
        let with_unreachable = achievers.iter().any(|o| {
            o.agents
                .iter()
                .any(|&a| unreachable.iter().any(|u| u.eq_ignore_ascii_case(task.g.objects.name(a))))
        });
        out[usize::from(!with_unreachable)].push((l, with_unreachable));
    }
    // Dropping all of them includes those of the first round.
    let first = out[0].clone();
    out[1].extend(first);
    out
}

/// Whether operator `op` makes one of the `dropped` goals true.
fn achieves_dropped(prepared: &Prepared<'_>, dropped: &[crate::planner::task::Lit], op: u32) -> bool {
    prepared.task.ops[op as usize].effs.iter().any(|e| dropped.contains(&e.lit))
}

/// The plans a repair stage's search may expand: as many as the old steps
/// it keeps, and [`STAGE_NODES`] more. A stage that finds a plan needs far
/// fewer (on the survivors-repair benchmark, a median of 0.24 per step kept,
/// and at most one but for two runs); a search that needs more is working
/// around old steps that the next ring removes, and a failing search only
/// ends at a limit.
fn stage_nodes(kept: usize) -> u64 {
    kept as u64 + STAGE_NODES
}

const STAGE_NODES: u64 = 100;

/// One repair, stages and full replan, with the goals of `prepared`.
#[allow(clippy::too_many_arguments)]
fn attempt<'db>(
    db: &'db dyn Db,
    prepared: &Prepared<'db>,
    dropped: &[crate::planner::task::Lit],
    old_plan: &PlanFile,
    config: &Config,
    limits: &PlannerLimits,
    options: &RepairOptions,
    started: Instant,
    cancel: &dyn Fn() -> bool,
    progress: &mut dyn FnMut(&Progress),
) -> RepairOutcome<'db> {
    let mut steps = old::read(&prepared.task, old_plan, &options.execution);
    old::explain(db, &prepared.task, old_plan, &mut steps);
    // A step that achieves a dropped goal (a meeting) is no longer frozen by
    // its unreachable agent: the meeting is cancelled (5.5). Executed steps stay.
    for s in &mut steps {
        if s.frozen && !s.fixed && s.op.is_ok_and(|o| achieves_dropped(prepared, dropped, o)) {
            s.frozen = false;
        }
    }
    let by_name = old::links_by_name(db, &prepared.task, old_plan, &steps);
    let mut r = Repair::new(prepared, config, steps);
    r.by_name = by_name;
    r.obsolete(options.flat, options.execution.now.unwrap_or(0.0));
    let stage_time = limits.time.map(|t| t / 4);
    let mut stages = Vec::new();
    let mut stage = Stage::Obsolete;
    let mut last = None;
    // The task with every action allowed, once a half-executed abstract
    // step is removed.
    let mut every: Option<Prepared<'db>> = None;
    let goals = prepared.task.goals.len();
    loop {
        let remaining = limits.time.map(|t| t.saturating_sub(started.elapsed()));
        let stage_limits = PlannerLimits {
            time: match (stage_time, remaining) {
                (Some(s), Some(r)) => Some(s.min(r)),
                _ => None,
            },
            ..limits.clone()
        };
        let seed = Seed { now: options.execution.now, ..r.seed() };
        let kept = r.kept().count();
        let stage_limits = PlannerLimits {
            nodes: Some(stage_nodes(kept).min(limits.nodes.unwrap_or(u64::MAX))),
            ..stage_limits
        };
        let searcher = searcher(&mut every, r.every_action, prepared, &options.execution.unreachable);
        let outcome = searcher.search(db, config, &stage_limits, Some(&seed), cancel, progress);
        stages.push(StageRun {
            stage,
            kept,
            goals,
            status: outcome.status.clone(),
            expanded: outcome.stats.expanded,
            elapsed: outcome.stats.elapsed,
        });
        if outcome.status == Status::Solved {
            return RepairOutcome {
                status: Status::Solved,
                stage: Some(stage),
                plan: outcome.plan,
                old: r.old,
                removed: r.removed,
                stages,
                dropped: Vec::new(),
                lints: Vec::new(),
                stats: outcome.stats,
            };
        }
        if cancel() || remaining.is_some_and(|r| r.is_zero()) {
            last = Some(outcome);
            break;
        }
        let ring = match stage {
            Stage::Obsolete => 1,
            Stage::Ring(n) => n + 1,
            Stage::Replan => unreachable!("the replan is not a repair stage"),
        };
        if !r.next_ring(ring) {
            break;
        }
        stage = Stage::Ring(ring);
    }
    // The full replan.
    let remaining = limits.time.map(|t| t.saturating_sub(started.elapsed()));
    let replan = match last {
        Some(outcome) => outcome,
        None => {
            let replan_limits = PlannerLimits { time: remaining, ..limits.clone() };
            // Everything goes but the frozen steps: executed, running, or
            // an unreachable agent's (they stay in any plan).
            for i in 0..r.old.len() {
                if r.why[i].is_none() && !r.old[i].frozen {
                    r.remove(i, Why::Replan, Stage::Replan);
                }
            }
            // With --now, nothing new starts before now, also here.
            let frozen = r.kept().next().is_some();
            let seed = (frozen || options.execution.now.is_some())
                .then(|| Seed { now: options.execution.now, ..r.seed() });
            let searcher = searcher(&mut every, r.every_action, prepared, &options.execution.unreachable);
            let outcome = searcher.search(db, config, &replan_limits, seed.as_ref(), cancel, progress);
            stages.push(StageRun {
                stage: Stage::Replan,
                kept: r.kept().count(),
                goals,
                status: outcome.status.clone(),
                expanded: outcome.stats.expanded,
                elapsed: outcome.stats.elapsed,
            });
            outcome
        }
    };
    RepairOutcome {
        status: replan.status.clone(),
        stage: (replan.status == Status::Solved).then_some(Stage::Replan),
        plan: replan.plan,
        old: r.old,
        removed: r.removed,
        stages,
        dropped: Vec::new(),
        lints: replan.lints,
        stats: replan.stats,
    }
}

/// What the searches plan with: `prepared`, or, once a half-executed
/// abstract step is removed (`every_action`), its task with every action
/// allowed, made the first time and kept in `every`.
fn searcher<'a, 'db>(
    every: &'a mut Option<Prepared<'db>>,
    every_action: bool,
    prepared: &'a Prepared<'db>,
    unreachable: &[String],
) -> &'a Prepared<'db> {
    if !every_action {
        return prepared;
    }
    every.get_or_insert_with(|| with_every_action(prepared, unreachable))
}

/// Section 5.3: once a half-executed abstract step is removed, the
/// searches may insert every primitive action (𝒜 = A), but those of the
/// unreachable agents (5.4); the heuristic is computed for that set.
fn with_every_action<'db>(prepared: &Prepared<'db>, unreachable: &[String]) -> Prepared<'db> {
    let mut task = prepared.task.clone();
    for op in &mut task.ops {
        if !op.is_abstract {
            op.allowed = true;
        }
    }
    task.rebuild_achievers();
    let h = crate::planner::heuristic::Heuristic::new(&task);
    let mut every = Prepared { task, h };
    out_of_reach(&mut every, unreachable);
    every
}

/// Section 5.4: an agent out of communication cannot learn of a new step.
/// No step of an unreachable agent is inserted, neither to support a
/// condition nor by a method; those of the old plan are frozen (the seed
/// keeps them, with their refinements).
fn out_of_reach(prepared: &mut Prepared<'_>, unreachable: &[String]) {
    let task = &mut prepared.task;
    let out: Vec<bool> = task
        .ops
        .iter()
        .map(|o| {
            o.agents.iter().any(|&a| {
                let name = task.g.objects.name(a);
                unreachable.iter().any(|u| u.eq_ignore_ascii_case(name))
            })
        })
        .collect();
    if !out.contains(&true) {
        return;
    }
    let methods = &task.methods;
    for (op, &out_of_reach) in task.ops.iter_mut().zip(&out) {
        if out_of_reach {
            op.allowed = false;
        }
        op.methods.retain(|&m| !methods[m as usize].subtasks.iter().any(|&(_, s)| out[s as usize]));
    }
    task.rebuild_achievers();
    // The heuristic is kept: rebuilt without the agent's actions, it would
    // call the conditions of its own frozen steps unreachable (its
    // positions after the first), and no start plan would hold them.
}

/// A start plan, each plan step's seed step, and each seed step's old step.
type StartPlan = (crate::planner::plan::Plan, Vec<Option<usize>>, Vec<usize>);

/// The state of a repair: which steps of the old plan are still in.
struct Repair<'p, 'db> {
    prepared: &'p Prepared<'db>,
    config: &'p Config,
    old: Vec<OldStep>,
    /// Why each removed step was removed.
    why: Vec<Option<Why>>,
    removed: Vec<Removed>,
    /// The steps removed by the last stage (the next ring is around them).
    frontier: Vec<usize>,
    /// The orderings of the old plan between its steps (phantom links),
    /// and its causal links, as steps of the old plan.
    phantoms: order::OldOrder,
    /// The orderings of the old plan through the steps removed before the
    /// order was learnt, between steps of the old plan (phantom links too).
    through: Vec<SeedOrder>,
    links: Vec<(usize, usize)>,
    /// The old plan's causal links rebuilt by name (`old::links_by_name`).
    by_name: Vec<(usize, usize)>,
    stage: Stage,
    /// A half-executed abstract step was removed: the searches may insert
    /// every action (𝒜 = A, section 5.3).
    every_action: bool,
}

impl<'p, 'db> Repair<'p, 'db> {
    fn new(prepared: &'p Prepared<'db>, config: &'p Config, old: Vec<OldStep>) -> Self {
        let n = old.len();
        Repair {
            prepared,
            config,
            old,
            why: vec![None; n],
            removed: Vec::new(),
            frontier: Vec::new(),
            phantoms: order::OldOrder::default(),
            through: Vec::new(),
            links: Vec::new(),
            by_name: Vec::new(),
            stage: Stage::Obsolete,
            every_action: false,
        }
    }

    fn kept(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.old.len()).filter(|&i| self.why[i].is_none())
    }

    fn remove(&mut self, i: usize, why: Why, stage: Stage) {
        if self.why[i].is_none() {
            self.why[i] = Some(why);
            self.removed.push(Removed { step: i, why, stage });
            self.frontier.push(i);
        }
    }

    /// Removes step `i` with what the hierarchy takes with it: its
    /// subtasks, and its abstract step's refinement (un-refined as a whole).
    fn remove_with_hierarchy(&mut self, i: usize, why: Why) {
        let stage = self.stage;
        self.remove(i, why, stage);
        let mut stack = vec![i];
        while let Some(s) = stack.pop() {
            for c in self.old[s].children.clone() {
                self.remove(c, Why::UnderRemoved, stage);
                stack.push(c);
            }
        }
        if let Some(p) = self.old[i].parent
            && self.why[p].is_none()
        {
            self.unrefine(p);
        }
    }

    /// Un-refines abstract step `p`: every step its method added goes,
    /// except frozen ones, which stay on their own; `p` stays, unrefined.
    /// When some of those had run (executed or running), `p` was half
    /// executed: it goes too, with what is above it, and the searches may
    /// insert every action to finish its work (5.3: refined again, it
    /// would do again what ran). Not in a problem with an `:htn`, whose
    /// task network needs its tasks.
    fn unrefine(&mut self, p: usize) {
        let stage = self.stage;
        self.old[p].method = None;
        let mut ran = false;
        let mut stack = self.old[p].children.clone();
        while let Some(s) = stack.pop() {
            if self.old[s].frozen {
                ran |= self.old[s].fixed;
                self.old[s].parent = None;
                continue;
            }
            self.remove(s, Why::Unrefined, stage);
            stack.extend(self.old[s].children.clone());
        }
        let children: Vec<usize> = self.old[p]
            .children
            .iter()
            .copied()
            .filter(|&c| self.why[c].is_none() && self.old[c].parent == Some(p))
            .collect();
        self.old[p].children = children;
        if ran && self.prepared.task.htn.is_none() && self.why[p].is_none() {
            self.every_action = true;
            self.remove(p, Why::HalfExecuted, stage);
            if let Some(q) = self.old[p].parent
                && self.why[q].is_none()
            {
                self.unrefine(q);
            }
        }
    }

    /// Stage 1: the obsolete steps, then the steps that support nothing.
    fn obsolete(&mut self, flat: bool, now: f64) {
        let task = &self.prepared.task;
        let rigid = old::Rigid::new(task);
        // Only steps the planner inserted itself must be in 𝒜: the
        // subtasks of methods need not be, flattened or not.
        let top_level: Vec<bool> = self.old.iter().map(|s| s.parent.is_none()).collect();
        if flat {
            for i in 0..self.old.len() {
                if self.old[i].is_abstract {
                    self.remove(i, Why::Flat, Stage::Obsolete);
                }
                self.old[i].parent = None;
                self.old[i].children.clear();
                self.old[i].method = None;
            }
        }
        for (i, &top_level) in top_level.iter().enumerate() {
            if self.why[i].is_some() {
                continue;
            }
            let why = match self.old[i].op {
                Err(_) => Some(Why::NoOperator),
                Ok(op) => {
                    let o = &task.ops[op as usize];
                    let htn_root = o.is_abstract && task.htn.is_some();
                    let frozen = self.old[i].frozen;
                    if top_level && !o.allowed && !htn_root && !frozen {
                        Some(Why::NotAllowed)
                    } else if !frozen && rigid.never_again(task, op, now) {
                        Some(Why::ConditionGone)
                    } else {
                        None
                    }
                }
            };
            if let Some(why) = why {
                self.remove_with_hierarchy(i, why);
            }
        }
        // A decomposition whose method the new task does not have.
        for i in 0..self.old.len() {
            if self.why[i].is_none() && self.old[i].method.is_none() && !self.old[i].children.is_empty() {
                for c in self.old[i].children.clone() {
                    if self.why[c].is_none() {
                        self.remove_with_hierarchy(c, Why::MethodGone);
                    }
                }
                self.unrefine(i);
            }
        }
        // The old plan's orderings and causal links, from the most complete
        // start plan the new task allows.
        self.deadlines(now);
        let start = self.learn_old_order();
        self.through_removed();
        // Steps that support nothing, until none is left: removing one
        // takes the support of its own conditions away, on the same links
        // (a step that supports nothing is no producer of a step that stays,
        // so the links of those that stay do not change).
        let Some((plan, of_seed, seed_steps)) = start.or_else(|| self.start_plan()) else { return };
        let links: Vec<(usize, Option<usize>)> = plan
            .links
            .iter()
            .filter_map(|l| {
                let k = of_seed[l.from as usize]?;
                Some((seed_steps[k], of_seed[l.to as usize].map(|c| seed_steps[c])))
            })
            .collect();
        loop {
            // A link supports its producer and the abstract steps above it
            // that do not hold its consumer too.
            let mut supports = vec![false; self.old.len()];
            for &(producer, consumer) in &links {
                if self.why[producer].is_some() || consumer.is_some_and(|c| self.why[c].is_some()) {
                    continue;
                }
                let mut a = Some(producer);
                while let Some(i) = a {
                    if consumer.is_some_and(|c| self.holds(i, c)) {
                        break;
                    }
                    supports[i] = true;
                    a = self.old[i].parent;
                }
            }
            let idle: Vec<usize> = self
                .kept()
                .filter(|&i| !supports[i] && self.old[i].parent.is_none() && !self.old[i].frozen)
                .collect();
            if idle.is_empty() {
                break;
            }
            for i in idle {
                self.remove_with_hierarchy(i, Why::SupportsNothing);
            }
        }
        self.reroute();
    }

    /// Under geometric reasoning, the old moves that leave from where their
    /// robot no longer is are removed: each robot's position is followed
    /// through the old steps still in, in the old schedule's order, from
    /// where the new problem puts it, and a top-level move that does not
    /// start there goes (a robot that starts elsewhere, a detour removed).
    /// The search's replay of the itinerary then brings the robot to its
    /// next old visit by the shortest route, instead of back to where the
    /// removed moves went.
    fn reroute(&mut self) {
        if self.config.motion == Motion::Off {
            return;
        }
        let task = &self.prepared.task;
        let mut order: Vec<usize> = self.kept().filter(|&i| self.old[i].op.is_ok()).collect();
        order.sort_by(|&a, &b| self.old[a].start.total_cmp(&self.old[b].start).then(a.cmp(&b)));
        let mut pos: Vec<Option<u32>> = task
            .motion
            .iter()
            .map(|m| {
                m.as_ref()
                    .and_then(|m| m.positions.iter().position(|&a| task.init[a as usize]).map(|p| p as u32))
            })
            .collect();
        let mut stranded = Vec::new();
        for i in order {
            let Ok(op) = self.old[i].op else { continue };
            if let Some(&(group, from, to)) = task.moves.get(&op) {
                let g = group as usize;
                if pos[g] == Some(from) || self.old[i].frozen || self.old[i].parent.is_some() {
                    pos[g] = Some(to);
                } else if self.itinerary_move(i) {
                    stranded.push(i);
                }
                continue;
            }
            for e in &task.ops[op as usize].effs {
                if let Some((_, g, p)) = task.motion_of(crate::planner::task::atom_of(e.lit))
                    && !crate::planner::task::is_neg(e.lit)
                {
                    pos[g as usize] = Some(p);
                }
            }
        }
        for i in stranded {
            self.remove(i, Why::Rerouted, Stage::Obsolete);
        }
    }

    /// Figure 14, stages 3–4: while the steps still in cannot be scheduled
    /// (a deadline, the end of a timed initial literal's window, is missed,
    /// say after a step ran late), the steps between `now` and the next
    /// deadline are removed, one deadline after the other.
    fn deadlines(&mut self, now: f64) {
        let mut times: Vec<f64> =
            self.prepared.task.tils.iter().map(|t| t.time).filter(|&t| t > now).collect();
        times.sort_by(f64::total_cmp);
        times.dedup();
        for deadline in times {
            if self.start_plan().is_some() {
                return;
            }
            let between: Vec<usize> = self
                .kept()
                .filter(|&i| !self.old[i].frozen && self.old[i].start >= now && self.old[i].start < deadline)
                .collect();
            for i in between {
                if self.why[i].is_none() {
                    self.remove_with_hierarchy(i, Why::Deadline(deadline));
                }
            }
        }
    }

    /// Whether old step `i` is a top-level move of a member whose itinerary
    /// the search builds (geometric reasoning): such moves are not put in
    /// the start plan, the itineraries add them again between the visits,
    /// in the order the phantom links keep.
    fn itinerary_move(&self, i: usize) -> bool {
        let s = &self.old[i];
        self.config.motion != Motion::Off
            && s.parent.is_none()
            && !s.frozen
            && s.op.is_ok_and(|op| self.prepared.task.moves.contains_key(&op))
    }

    /// Whether old step `c` is `a` or below it.
    fn holds(&self, a: usize, mut c: usize) -> bool {
        for _ in 0..=self.old.len() {
            if c == a {
                return true;
            }
            match self.old[c].parent {
                Some(p) => c = p,
                None => return false,
            }
        }
        false
    }

    /// Removes the next ring: the steps next to those removed at the
    /// previous stage. False when there is none (the full replan is next).
    fn next_ring(&mut self, ring: u32) -> bool {
        self.stage = Stage::Ring(ring);
        let frontier: FxHashSet<usize> = std::mem::take(&mut self.frontier).into_iter().collect();
        let mut next: Vec<usize> = Vec::new();
        for &(a, b) in &self.links {
            if frontier.contains(&a) && self.why[b].is_none() {
                next.push(b);
            }
            if frontier.contains(&b) && self.why[a].is_none() {
                next.push(a);
            }
        }
        // The abstract step whose method added a step removed, un-refined
        // since: its effects came from its subtasks (5.1.1).
        for &f in &frontier {
            if let Some(p) = self.old[f].parent
                && self.why[p].is_none()
            {
                next.push(p);
            }
        }
        // The same agent's steps just before and after, in the old schedule.
        for &f in &frontier {
            for agent in self.old[f].agents.clone() {
                let same: Vec<usize> = self
                    .kept()
                    .filter(|&i| !self.old[i].is_abstract && self.old[i].agents.contains(&agent))
                    .collect();
                let before = same
                    .iter()
                    .copied()
                    .filter(|&i| self.old[i].start <= self.old[f].start)
                    .max_by(|&a, &b| self.old[a].start.total_cmp(&self.old[b].start));
                let after = same
                    .iter()
                    .copied()
                    .filter(|&i| self.old[i].start >= self.old[f].start)
                    .min_by(|&a, &b| self.old[a].start.total_cmp(&self.old[b].start));
                next.extend(before.into_iter().chain(after));
            }
        }
        next.retain(|&i| !self.old[i].frozen);
        next.sort_unstable();
        next.dedup();
        if next.is_empty() {
            return false;
        }
        for i in next {
            if self.why[i].is_none() {
                self.remove_with_hierarchy(i, Why::Ring(ring));
            }
        }
        true
    }

    /// The seed of the steps still in: each with its operator, parent and
    /// method (refined when all its subtasks are still in), old times, and
    /// the phantom orderings between them.
    fn seed(&self) -> Seed {
        self.seed_with(true, true).0
    }

    /// The seed, and the old step of each seed step. For the analysis
    /// (`all_moves`), the moves the itineraries would add again are in it.
    fn seed_with(&self, phantoms: bool, all_moves: bool) -> (Seed, Vec<usize>) {
        let kept: Vec<usize> = self
            .kept()
            .filter(|&i| self.old[i].op.is_ok() && (all_moves || !self.itinerary_move(i)))
            .collect();
        let mut index = vec![usize::MAX; self.old.len()];
        for (k, &i) in kept.iter().enumerate() {
            index[i] = k;
        }
        let steps = kept
            .iter()
            .map(|&i| {
                let s = &self.old[i];
                let parent = s.parent.filter(|&p| index[p] != usize::MAX && self.old[p].method.is_some());
                SeedStep {
                    op: s.op.unwrap_or_default(),
                    parent: parent.map(|p| index[p]),
                    method: s.method,
                    start: s.start,
                    end: s.end,
                    fixed: s.fixed,
                    done: s.done,
                }
            })
            .collect();
        let orders = if phantoms {
            let mut orders = self.phantoms.orders(&index);
            orders.extend(self.through.iter().filter_map(|o| {
                let (a, b) = (index[o.from.0], index[o.to.0]);
                (a != usize::MAX && b != usize::MAX)
                    .then_some(SeedOrder { from: (a, o.from.1), to: (b, o.to.1) })
            }));
            orders
        } else {
            Vec::new()
        };
        (Seed { steps, orders, now: None }, kept)
    }

    /// The start plan of the steps still in, without phantoms and without
    /// geometric reasoning (every condition linked, moves included), which
    /// tells what supports what: the plan, each plan step's seed step, and
    /// each seed step's old step.
    fn start_plan(&self) -> Option<StartPlan> {
        let (seed, kept) = self.seed_with(false, true);
        let analysis = Config { motion: Motion::Off, ..self.config.clone() };
        let search = Search::new(&self.prepared.task, &self.prepared.h, &analysis);
        let (plan, of_seed) = search.seeded(&seed).ok()?.into_iter().next()?;
        Some((plan, of_seed, kept))
    }

    /// The links and orderings of the old plan through the steps removed
    /// before [`Repair::learn_old_order`] (those the new task cannot ground
    /// or no longer allows, which its start plan cannot hold), from the
    /// links rebuilt by name: the next ring is around them, and the order
    /// of the steps that stay, through them, is kept (phantom links).
    fn through_removed(&mut self) {
        let gone: Vec<bool> = self.why.iter().map(Option::is_some).collect();
        let by_name = std::mem::take(&mut self.by_name);
        self.links.extend(by_name.iter().copied().filter(|&(a, b)| gone[a] || gone[b]));
        for a in (0..self.old.len()).filter(|&a| !gone[a]) {
            let mut seen = FxHashSet::default();
            let mut stack: Vec<usize> =
                by_name.iter().filter(|&&(x, y)| x == a && gone[y]).map(|&(_, y)| y).collect();
            let mut reached = Vec::new();
            while let Some(x) = stack.pop() {
                if !seen.insert(x) {
                    continue;
                }
                for &(_, y) in by_name.iter().filter(|&&(x2, _)| x2 == x) {
                    if gone[y] {
                        stack.push(y);
                    } else if y != a {
                        reached.push(y);
                    }
                }
            }
            reached.sort_unstable();
            reached.dedup();
            for b in reached {
                // In the old schedule's order, ε apart at least.
                let (sa, ea, sb) = (self.old[a].start, self.old[a].end, self.old[b].start);
                let from = if ea + EPS <= sb + 1e-6 {
                    (a, End::End)
                } else if sa + EPS <= sb + 1e-6 {
                    (a, End::Start)
                } else {
                    continue;
                };
                self.through.push(SeedOrder { from, to: (b, End::Start) });
            }
        }
        self.by_name = by_name;
    }

    /// Learns the old plan's order and causal links from the start plan of
    /// every step still in: the orderings its network implies between their
    /// time points are the phantom links of later stages. Returns that
    /// start plan.
    fn learn_old_order(&mut self) -> Option<StartPlan> {
        let (mut plan, of_seed, kept) = self.start_plan()?;
        plan.stn.flush();
        let mut tps: Vec<(usize, End, Tp)> = Vec::new();
        for (s, k) in of_seed.iter().enumerate() {
            let Some(k) = *k else { continue };
            let step = plan.steps[s];
            tps.push((kept[k], End::Start, step.start));
            if step.end != step.start {
                tps.push((kept[k], End::End, step.end));
            }
        }
        let points = tps.iter().map(|&(a, e, _)| (a, e)).collect();
        let mut of_tp = vec![usize::MAX; plan.stn.len()];
        for (k, t) in tps.iter().enumerate() {
            of_tp[t.2 as usize] = k;
        }
        self.phantoms = order::OldOrder::new(
            points,
            |j| {
                let row = plan.stn.predecessors(tps[j].2);
                let bits = row.iter().enumerate().flat_map(|(w, &word)| {
                    (0..64).filter(move |b| word >> b & 1 == 1).map(move |b| w * 64 + b)
                });
                bits.filter_map(|tp| of_tp.get(tp).copied().filter(|&k| k != usize::MAX)).collect()
            },
            |i| plan.stn.est(tps[i].2),
        );
        for l in plan.links.iter() {
            if let (Some(a), Some(b)) = (of_seed[l.from as usize], of_seed[l.to as usize]) {
                self.links.push((kept[a], kept[b]));
            }
        }
        Some((plan, of_seed, kept))
    }
}
