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
//!
//! With geometric reasoning, the old plan's top-level moves are not put in
//! the start plan: the itineraries add moves again between the visits,
//! which the phantom links keep in their old order. Pure, like the planner:
//! limits, cancellation and progress come from the caller.

mod old;

use std::time::{Duration, Instant};

use rustc_hash::FxHashSet;

use crate::db::{Db, Unit};
use crate::plan::Plan as PlanFile;
use crate::planner::output::SolvedPlan;
use crate::planner::search::{Search, Seed, SeedOrder, SeedStep};
use crate::planner::stn::Tp;
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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
            Why::Replan => "the full replan starts from nothing".into(),
        }
    }
}

/// A step of the old plan removed by the repair.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Removed {
    /// Its index in the old plan's steps.
    pub step: usize,
    pub why: Why,
    pub stage: Stage,
}

/// One search of the repair.
#[derive(Debug, Clone, PartialEq)]
pub struct StageRun {
    pub stage: Stage,
    /// Steps of the old plan in the start plan.
    pub kept: usize,
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
    /// Why there is no plan (the last search's flaws), or why the problem
    /// cannot be planned.
    pub lints: Vec<Lint<'db>>,
    pub stats: Stats,
}

/// Repairs `old_plan` for `problem`.
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
    let stage_config = config.clone();
    let empty = |outcome: crate::planner::Outcome<'db>| RepairOutcome {
        status: outcome.status,
        stage: None,
        plan: outcome.plan,
        old: Vec::new(),
        removed: Vec::new(),
        stages: Vec::new(),
        lints: outcome.lints,
        stats: outcome.stats,
    };
    let prepared = match prepare(db, problem, &stage_config, limits) {
        Ok(p) => p,
        Err(outcome) => return empty(*outcome),
    };
    let mut r =
        Repair::new(&prepared, &stage_config, old::read(&prepared.task, old_plan, &options.execution));
    r.obsolete(options.flat);
    let stage_time = limits.time.map(|t| t / 4);
    let mut stages = Vec::new();
    let mut stage = Stage::Obsolete;
    let mut last = None;
    loop {
        let remaining = limits.time.map(|t| t.saturating_sub(started.elapsed()));
        let stage_limits = PlannerLimits {
            time: match (stage_time, remaining) {
                (Some(s), Some(r)) => Some(s.min(r)),
                _ => None,
            },
            ..limits.clone()
        };
        let seed = r.seed();
        let kept = r.kept().count();
        let outcome = prepared.search(db, &stage_config, &stage_limits, Some(&seed), cancel, progress);
        stages.push(StageRun {
            stage,
            kept,
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
                lints: Vec::new(),
                stats: outcome.stats,
            };
        }
        if cancel() {
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
    // The full replan, with the configuration as given.
    let remaining = limits.time.map(|t| t.saturating_sub(started.elapsed()));
    let replan = match last {
        Some(outcome) => outcome,
        None => {
            let replan_limits = PlannerLimits { time: remaining, ..limits.clone() };
            let outcome = match prepare(db, problem, config, limits) {
                Ok(p) => p.search(db, config, &replan_limits, None, cancel, progress),
                Err(outcome) => *outcome,
            };
            stages.push(StageRun {
                stage: Stage::Replan,
                kept: 0,
                status: outcome.status.clone(),
                expanded: outcome.stats.expanded,
                elapsed: outcome.stats.elapsed,
            });
            for i in 0..r.old.len() {
                if r.why[i].is_none() {
                    r.remove(i, Why::Replan, Stage::Replan);
                }
            }
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
        lints: replan.lints,
        stats: replan.stats,
    }
}

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
    phantoms: Vec<SeedOrder>,
    links: Vec<(usize, usize)>,
    stage: Stage,
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
            phantoms: Vec::new(),
            links: Vec::new(),
            stage: Stage::Obsolete,
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
    fn unrefine(&mut self, p: usize) {
        let stage = self.stage;
        self.old[p].method = None;
        let mut stack = self.old[p].children.clone();
        while let Some(s) = stack.pop() {
            if self.old[s].frozen {
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
    }

    /// Stage 1: the obsolete steps, then the steps that support nothing.
    fn obsolete(&mut self, flat: bool) {
        let task = &self.prepared.task;
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
                Err(Missing::NoOperator) => Some(Why::NoOperator),
                Ok(op) => {
                    let o = &task.ops[op as usize];
                    let htn_root = o.is_abstract && task.htn.is_some();
                    (top_level && !o.allowed && !htn_root && !self.old[i].frozen).then_some(Why::NotAllowed)
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
        self.learn_old_order();
        // Steps that support nothing, until none is left.
        while let Some((plan, of_seed, seed_steps)) = self.start_plan() {
            // A link supports its producer and the abstract steps above it
            // that do not hold its consumer too.
            let mut supports = vec![false; self.old.len()];
            for l in plan.links.iter() {
                let Some(k) = of_seed[l.from as usize] else { continue };
                let consumer = of_seed[l.to as usize].map(|c| seed_steps[c]);
                let mut a = Some(seed_steps[k]);
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
        self.seed_with(true, false).0
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
            self.phantoms
                .iter()
                .filter_map(|o| {
                    let (a, b) = (index[o.from.0], index[o.to.0]);
                    (a != usize::MAX && b != usize::MAX)
                        .then_some(SeedOrder { from: (a, o.from.1), to: (b, o.to.1) })
                })
                .collect()
        } else {
            Vec::new()
        };
        (Seed { steps, orders }, kept)
    }

    /// The start plan of the steps still in, without phantoms and without
    /// geometric reasoning (every condition linked, moves included), which
    /// tells what supports what: the plan, each plan step's seed step, and
    /// each seed step's old step.
    fn start_plan(&self) -> Option<(crate::planner::plan::Plan, Vec<Option<usize>>, Vec<usize>)> {
        let (seed, kept) = self.seed_with(false, true);
        let analysis = Config { motion: Motion::Off, ..self.config.clone() };
        let search = Search::new(&self.prepared.task, &self.prepared.h, &analysis);
        let (plan, of_seed) = search.seeded(&seed).ok()?.into_iter().next()?;
        Some((plan, of_seed, kept))
    }

    /// Learns the old plan's order and causal links from the start plan of
    /// every step still in: the orderings its network implies between their
    /// time points are the phantom links of later stages.
    fn learn_old_order(&mut self) {
        let Some((plan, of_seed, kept)) = self.start_plan() else { return };
        let mut tps: Vec<(usize, End, Tp)> = Vec::new();
        for (s, k) in of_seed.iter().enumerate() {
            let Some(k) = *k else { continue };
            let step = plan.steps[s];
            tps.push((kept[k], End::Start, step.start));
            if step.end != step.start {
                tps.push((kept[k], End::End, step.end));
            }
        }
        for &(a, ea, ta) in &tps {
            for &(b, eb, tb) in &tps {
                if a != b && plan.stn.before(ta, tb) {
                    self.phantoms.push(SeedOrder { from: (a, ea), to: (b, eb) });
                }
            }
        }
        for l in plan.links.iter() {
            if let (Some(a), Some(b)) = (of_seed[l.from as usize], of_seed[l.to as usize]) {
                self.links.push((kept[a], kept[b]));
            }
        }
    }
}
