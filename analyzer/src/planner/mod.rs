//! The HiPOP planner (section 4 of the HiPOP paper): hybrid partial-order
//! and hierarchical planning over a problem's ground model, with conflicts
//! of abstract actions, allowed actions and geometric reasoning.
//!
//! - [`task`]: the planning task compiled from the ground model (timed
//!   conditions and effects, method instances, 𝒜, timed literals, the
//!   `:htn`), and what the planner does not support, located.
//! - [`motion`]: position families and shortest chains of moves (4.3);
//!   [`itinerary`]: each member's visits in sequence, with the moves between.
//! - [`heuristic`]: h_add and refinement estimates (4.2.3).
//! - [`stn`], [`pvec`]: the temporal network and the persistent vectors that
//!   make child plans cheap.
//! - [`plan`]: partial plans and their flaws; [`search`]: Algorithm 1.
//! - [`output`]: the solved plan in VAL's format, the IPC 2020 hierarchical
//!   format with hipop's timing, and JSON.
//!
//! Pure: the caller gives the limits, a cancellation predicate and a
//! progress callback; nothing here does I/O.

pub mod forward;
pub mod heuristic;
pub mod itinerary;
pub mod motion;
pub mod numeric;
pub mod output;
pub mod plan;
pub mod pvec;
pub mod search;
pub mod stn;
pub mod task;

use std::time::Duration;

use crate::db::{Db, Unit};
use crate::diagnostic::codes;
use crate::semantics::symbols::Loc;
use crate::verify::Lint;

/// How `h` treats open links whose literal some step already produces (4.2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanHeuristic {
    /// Plain h_add.
    Add,
    /// `R`: VHPOP's reuse, 0 when a step producing the literal can be before.
    Reuse,
    /// `AR`: advance reuse (Equation 1).
    AdvanceReuse,
}

/// How open links are ordered (4.2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FlawOrder {
    /// The costliest open link of the most recently added step that has one.
    Local,
    /// The costliest open link.
    Sorted,
    /// Last in, first out.
    ThreatFirst,
}

/// Geometric reasoning (4.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// None: positions are literals like any other (threats of Definition 13
    /// and the last-known-position rule of 4.3.1 still apply to confirmed families).
    Off,
    /// `motion`: h_motion (Equation 2), open links to positions last,
    /// chains of moves, minimum durations.
    Motion,
    /// `ncm`: the same with no cost for positions (Equation 3).
    Ncm,
}

/// A planner configuration, named like the paper's (`AR-time-local-motion`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Config {
    pub plan_h: PlanHeuristic,
    pub flaws: FlawOrder,
    pub motion: Motion,
    /// `bare`: ignore abstract actions (POP planning).
    pub bare: bool,
    /// `eager`: solve every threat first, as soon as it appears (the
    /// paper's order). Without it, a threat that both orderings still solve
    /// waits until the open links are solved.
    pub eager: bool,
    /// The greedy completion (lookahead) of plans that reach their
    /// completion, and of the plan at hand after 1024, 2048… expansions;
    /// `nolookahead` turns it off (A* alone, as in the paper).
    pub lookahead: bool,
    /// A second open list ranked by plan size (VHPOP's plan ranking: the
    /// steps plus the unit-cost estimate of the open links), expanded in
    /// turn with the makespan's (`nosteps`: the makespan's alone). Problems
    /// with an `:htn` use the makespan's alone.
    pub steps: bool,
    /// `types`: a predicate that is no position family may be one for the
    /// keys of one type (the `at` of trucks, where drivers and packages
    /// have an `at` too), and the planner reasons on those families too.
    pub types: bool,
    /// `refine`: in a purely hierarchical problem (where plans that no
    /// order of their steps runs are dropped), abstract flaws before open
    /// links.
    pub refine: bool,
    /// `links`: in a purely hierarchical problem, open links before
    /// abstract flaws only. With neither `refine` nor `links`, the search
    /// with refinements first runs for a bounded effort, then the one with
    /// links first ([`REFINE_FIRST_NODES`]).
    pub links: bool,
    /// `front`: in a purely hierarchical problem, plans grow from their
    /// front, as in a progression planner (`search::front`).
    pub front: bool,
    /// `greedy`: plans grown from their front (it implies `front`), with
    /// `h` weighing 20 in `f` rather than 5 (`FRONT_GREEDY_WEIGHT` and
    /// `FRONT_WEIGHT` in `search/front.rs`). The default sequence runs the
    /// search from the front at both weights, one after the other.
    pub greedy: bool,
    /// `forward`: in a problem without a hierarchy, the forward phase
    /// ([`forward`]) first, for the whole time; the partial-order search
    /// after it only when it finds no sequence. By default the
    /// partial-order search runs first, for [`FORWARD_AFTER`] of the time
    /// (on a ground model of [`FORWARD_FIRST`] operators or more, a few
    /// thousand expansions at most).
    pub forward: bool,
    /// `noforward`: no forward phase.
    pub noforward: bool,
}

/// In a problem without a hierarchy (where [`forward::applies`]), the
/// default sequence: the partial-order search for this share of the time
/// left, then the forward phase for the rest (then, if that finds no
/// sequence, the partial-order search again). The partial-order search
/// solves the smaller problems in a fraction of a second, often with
/// shorter makespans; the forward phase solves the larger ones it never
/// gets near.
pub const FORWARD_AFTER: f64 = 0.25;

/// On a ground model of this many operators or more, the default sequence
/// gives the partial-order search at most a few thousand expansions
/// (`forward::LARGE_FIRST_NODES`) of its share before the forward phase. On
/// the IPC 2002 sets of 2026-11-27 (first 10 problems of each), every
/// problem of the automatic sets has fewer than 2,000 ground operators and
/// the partial-order search solves most of them within its quarter; every
/// problem of the hand-coded sets has more than 4,000, and each one solved
/// was solved by the forward phase, after a quarter of the time (15 s at
/// 60 s) spent in a partial-order search that never got near a plan.
pub const FORWARD_FIRST: usize = 3_000;

/// On a ground model of this many operators or more, the default sequence
/// starts with the forward phase: the partial-order search does not run
/// before it. On the IPC 2002 hand-coded DriverLog and Depots problems 1–10
/// (22,944 to 1,547,850 ground operators) its few thousand expansions took
/// 11 to 15 s of a 60 s run (a quarter, at 60 to 230 plans a second) and
/// got near no plan; no problem without a hierarchy that the benchmarks
/// solve has this many operators and was solved by it (2026-11-28).
pub const FORWARD_ALONE: usize = 20_000;

/// In a purely hierarchical problem, the search with refinements first
/// (`refine`) runs for at most this many expansions and a quarter of the
/// time, then the search with links first for the rest (unless the
/// configuration names one of them). Each finds plans the other does not:
/// on the first 10 problems of each IPC 2020 partial-order domain, `refine`
/// solves PCP p-pcp05, 06 and 09 within 6,630 expansions, where links
/// first stop at the 10 s limit, and links first solve Rover pfile06 in
/// 32,802, where `refine` does not in 165,000 (docs/benchmarks.md,
/// 2026-11-27).
pub const REFINE_FIRST_NODES: u64 = 8_192;

impl Default for Config {
    fn default() -> Self {
        Config::parse(Config::DEFAULT).expect("the default configuration parses")
    }
}

impl Config {
    /// The default configuration (the one the benchmarks show best).
    pub const DEFAULT: &'static str = "AR-time-local-motion";

    /// The configurations the benchmarks compare: the paper's, the default
    /// without hipop's additions to the search (`eager`, `nolookahead`),
    /// and `bare`.
    pub const MAIN: &'static [&'static str] = &[
        "AR-time-local-motion",
        "AR-time-local-ncm",
        "R-time-local",
        "time-threatFirst",
        "AR-time-local-motion-eager-nolookahead",
        "bare",
    ];

    /// Parses a name: dash-separated parts among `AR`/`R` (plan heuristic,
    /// h_add without), `time` (the objective, always the makespan),
    /// `local`/`sorted`/`threatFirst` (open links; `local` without),
    /// `motion`/`ncm` (geometric reasoning; none without), `eager` (every
    /// threat first), `nolookahead` (no greedy completion), `nosteps` (no
    /// open list ranked by plan size), `types` (position families of one
    /// key type), `refine` (refinements before links in purely
    /// hierarchical problems), `bare`. `bare` alone is the default configuration
    /// without abstract actions.
    pub fn parse(name: &str) -> Result<Config, String> {
        if name.eq_ignore_ascii_case("bare") {
            return Ok(Config { bare: true, ..Config::parse(Config::DEFAULT)? });
        }
        let mut c = Config {
            plan_h: PlanHeuristic::Add,
            flaws: FlawOrder::Local,
            motion: Motion::Off,
            bare: false,
            eager: false,
            lookahead: true,
            steps: true,
            types: false,
            refine: false,
            links: false,
            front: false,
            greedy: false,
            forward: false,
            noforward: false,
        };
        for part in name.split('-').filter(|p| !p.is_empty()) {
            match part.to_ascii_lowercase().as_str() {
                "hipop" => {}
                "ar" => c.plan_h = PlanHeuristic::AdvanceReuse,
                "r" => c.plan_h = PlanHeuristic::Reuse,
                "time" => {}
                "local" => c.flaws = FlawOrder::Local,
                "sorted" => c.flaws = FlawOrder::Sorted,
                "threatfirst" => c.flaws = FlawOrder::ThreatFirst,
                "motion" => c.motion = Motion::Motion,
                "ncm" => c.motion = Motion::Ncm,
                "bare" => c.bare = true,
                "eager" => c.eager = true,
                "nolookahead" => c.lookahead = false,
                "nosteps" => c.steps = false,
                "types" => c.types = true,
                "refine" => c.refine = true,
                "links" => c.links = true,
                "front" => c.front = true,
                "greedy" => {
                    c.front = true;
                    c.greedy = true;
                }
                "forward" => c.forward = true,
                "noforward" => c.noforward = true,
                other => {
                    return Err(format!(
                        "unknown part `{other}` in configuration `{name}` (expected AR, R, time, local, sorted, threatFirst, motion, ncm, eager, nolookahead, nosteps, types, refine, links, front, greedy, forward, noforward, bare)"
                    ));
                }
            }
        }
        Ok(c)
    }

    pub fn name(&self) -> String {
        let mut parts: Vec<&str> = Vec::new();
        if self.bare {
            parts.push("bare");
        }
        match self.plan_h {
            PlanHeuristic::AdvanceReuse => parts.push("AR"),
            PlanHeuristic::Reuse => parts.push("R"),
            PlanHeuristic::Add => {}
        }
        parts.push("time");
        parts.push(match self.flaws {
            FlawOrder::Local => "local",
            FlawOrder::Sorted => "sorted",
            FlawOrder::ThreatFirst => "threatFirst",
        });
        match self.motion {
            Motion::Motion => parts.push("motion"),
            Motion::Ncm => parts.push("ncm"),
            Motion::Off => {}
        }
        if self.eager {
            parts.push("eager");
        }
        if !self.lookahead {
            parts.push("nolookahead");
        }
        if !self.steps {
            parts.push("nosteps");
        }
        if self.types {
            parts.push("types");
        }
        if self.refine {
            parts.push("refine");
        }
        if self.links {
            parts.push("links");
        }
        if self.front {
            parts.push("front");
        }
        if self.greedy {
            parts.push("greedy");
        }
        if self.forward {
            parts.push("forward");
        }
        if self.noforward {
            parts.push("noforward");
        }
        parts.join("-")
    }
}

/// Where the planner stops.
#[derive(Debug, Clone)]
pub struct PlannerLimits {
    pub time: Option<Duration>,
    /// Plans expanded.
    pub nodes: Option<u64>,
    /// Heap bytes: measured by `memory_in_use` when the host gives it, else
    /// the open list's size, estimated.
    pub memory: Option<usize>,
    /// The heap bytes the process holds (`crate::alloc::in_use` in a binary
    /// whose global allocator is `crate::alloc::Counting`).
    pub memory_in_use: Option<fn() -> usize>,
    /// Ground instances per method.
    pub method_instances: usize,
    /// Time already spent on this run before the search (grounding, the
    /// heuristic's tables), counted against [`PlannerLimits::time`].
    pub time_spent: Duration,
    /// The caller's process exits right after the run (`hipop plan`): the
    /// search's open list is left to the exit to free. Freeing millions of
    /// plans one by one takes seconds (1.1 s for 234,000 plans, 2.3 GB),
    /// past the time limit; the exit returns the memory at once.
    pub exits_after: bool,
    /// Return the first plan found. Without it the search goes on within
    /// the limits for better plans ([`Quality`]: a shorter makespan, then
    /// fewer steps), with the best plan found as a bound, and returns the
    /// best; it ends early when the bound empties the open list.
    pub first: bool,
    /// Only plans better than this are returned (a plan this good is
    /// known): partial plans whose schedule is already as long are dropped.
    pub better_than: Option<Quality>,
    /// Ground only the instances relevant to the goal
    /// ([`crate::verify::ground::ground_relevant`]). A repair grounds every
    /// reachable one: the old plan's steps, executed ones included, keep
    /// their instances even when the new goal does not need them.
    pub goal_relevance: bool,
}

impl Default for PlannerLimits {
    fn default() -> Self {
        PlannerLimits {
            time: Some(Duration::from_secs(60)),
            nodes: None,
            memory: Some(4 << 30),
            memory_in_use: None,
            method_instances: 1_000_000,
            time_spent: Duration::ZERO,
            exits_after: false,
            first: true,
            better_than: None,
            goal_relevance: true,
        }
    }
}

impl PlannerLimits {
    /// These limits with the time since `started` counted as spent: what
    /// ran before (parsing, grounding) uses up the run's time limit.
    pub fn spent_since(&self, started: std::time::Instant) -> PlannerLimits {
        PlannerLimits { time_spent: self.time_spent_since(started), ..self.clone() }
    }

    /// The time spent before `started` and since: what counts against
    /// [`PlannerLimits::time`] at this point.
    pub fn time_spent_since(&self, started: std::time::Instant) -> std::time::Duration {
        self.time_spent + started.elapsed()
    }
}

/// Which limit stopped the search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LimitKind {
    Time,
    Nodes,
    Memory,
    Cancelled,
}

impl LimitKind {
    pub fn as_str(self) -> &'static str {
        match self {
            LimitKind::Time => "time",
            LimitKind::Nodes => "nodes",
            LimitKind::Memory => "memory",
            LimitKind::Cancelled => "cancelled",
        }
    }
}

/// A progress report, about every 100 ms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    pub expanded: u64,
    pub open: usize,
    pub best_f: f64,
    pub elapsed: Duration,
    /// The makespan of the best plan found so far, when searching on
    /// after the first ([`PlannerLimits::first`] off).
    pub makespan: Option<f64>,
    /// This report is for a better plan just found (sent at once, not on
    /// the 100 ms clock).
    pub improved: bool,
}

/// What the search did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stats {
    pub expanded: u64,
    pub generated: u64,
    pub open: usize,
    pub peak_open: usize,
    /// The most steps of a plan the search expanded, greedy descents
    /// included.
    pub largest: usize,
    pub elapsed: Duration,
    /// Ground operators and method instances of the task.
    pub operators: usize,
    pub methods: usize,
    /// Method instances not tried because they repeat a task below itself
    /// (set when the search space is exhausted).
    pub loops_skipped: u64,
    /// Steps of the plan found that it could do without, removed before it
    /// was returned, and the time that took.
    pub redundant_removed: usize,
    pub redundant_time: Duration,
    /// When the first plan was found (from the start of the search).
    pub first_found: Option<Duration>,
    /// Plans found, the first included, each better than the one before.
    pub plans_found: u32,
    /// The limit that ended a search that went on after its first plan;
    /// `None` when it ended because no plan left could do better.
    pub stopped_by: Option<LimitKind>,
    /// How good the plan returned is.
    pub best: Option<Quality>,
    /// The forward phase's lookaheads whose state it took (a better
    /// current state in the hill-climbing, a state expanded in the
    /// best-first search), and the actions of all it estimated.
    pub lookahead_taken: u64,
    pub lookahead_steps: u64,
}

/// How good a plan is: its makespan, then its cost (`g`: the makespan or
/// the busiest agent's work when larger, and a small cost per step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quality {
    pub makespan: f64,
    pub cost: f64,
}

impl Quality {
    /// Makespans closer than this are the same.
    const SAME: f64 = 1e-6;

    /// A shorter makespan, or the same at a lower cost (fewer steps).
    pub fn better_than(self, other: Quality) -> bool {
        self.makespan < other.makespan - Self::SAME
            || (self.makespan <= other.makespan + Self::SAME && self.cost < other.cost)
    }

    /// Whether a partial plan whose schedule is already `makespan` long
    /// (a lower bound of its completions') can still lead to a better plan.
    pub fn admits(self, makespan: f64) -> bool {
        makespan < self.makespan - Self::SAME
    }
}

/// How planning ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// A plan was found.
    Solved,
    /// The search space within 𝒜 and the methods is exhausted: no plan.
    NoPlan,
    /// A limit was reached first.
    Limit(LimitKind),
    /// The model has constructs the planner does not support, or errors.
    Refused,
}

/// The result of planning.
pub struct Outcome<'db> {
    pub status: Status,
    pub plan: Option<output::SolvedPlan>,
    pub stats: Stats,
    /// Why there is no plan: unsupported constructs, or the flaws of the
    /// best partial plan, located in the domain and the problem.
    pub lints: Vec<Lint<'db>>,
}

/// Plans a problem. `cancel` is polled at every expansion; `progress` is
/// called about every 100 ms, and at once for each better plan when the
/// search goes on after its first ([`PlannerLimits::first`] off).
pub fn plan<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    config: &Config,
    limits: &PlannerLimits,
    cancel: &dyn Fn() -> bool,
    progress: &mut dyn FnMut(&Progress),
) -> Outcome<'db> {
    let started = std::time::Instant::now();
    match prepare(db, problem, config, limits) {
        Ok(prepared) => {
            // The time limit is the run's, grounding included.
            let limits = limits.spent_since(started);
            let hierarchical = prepared.task.htn.is_some() && prepared.task.achievers.is_empty();
            let outcome = if hierarchical && !config.refine && !config.links && !config.front && !config.bare
            {
                prepared.refine_then_links(db, config, &limits, cancel, progress)
            } else if prepared.task.htn.is_some() {
                prepared.search(db, config, &limits, None, cancel, progress)
            } else if limits.first || config.bare {
                prepared.first_plan(db, config, &limits, cancel, progress)
            } else {
                prepared.improve(db, config, &limits, cancel, progress)
            };
            if limits.exits_after {
                // Left to the exit: freeing the ground operators one by one
                // took 0.1 to 0.15 s past the limit on IPC 2002 Depots
                // hand-coded 6 (1,547,850 operators).
                std::mem::forget(prepared);
            }
            outcome
        }
        Err(outcome) => *outcome,
    }
}

/// A problem ready to plan: its planning task and heuristic, for one search
/// or several (a repair searches from several start plans).
pub struct Prepared<'db> {
    pub task: task::Task<'db>,
    pub h: heuristic::Heuristic,
}

/// Compiles the planning task of a problem, or says why it cannot be
/// planned (errors, unsupported constructs, a goal that can never hold).
pub fn prepare<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    config: &Config,
    limits: &PlannerLimits,
) -> Result<Prepared<'db>, Box<Outcome<'db>>> {
    let refuse = |lints| Outcome { status: Status::Refused, plan: None, stats: Stats::default(), lints };
    if !crate::verify::model_is_clean(db, problem) {
        let loc = Loc { item: problem.items(db)[0], span: rowan::TextRange::default() };
        return Err(Box::new(refuse(vec![Lint::new(
            codes::PLANNER_UNSUPPORTED,
            loc,
            "the problem or its domain has errors: fix them before planning",
        )])));
    }
    let mut task = match task::compile(db, problem, limits, config.types) {
        Ok(t) => t,
        Err(unsupported) => {
            return Err(Box::new(refuse(
                unsupported
                    .into_iter()
                    .map(|u| {
                        Lint::new(
                            codes::PLANNER_UNSUPPORTED,
                            u.loc,
                            format!("the planner does not support {}", u.what),
                        )
                    })
                    .collect(),
            )));
        }
    };
    if config.bare {
        if task.htn.is_some() {
            let loc = Loc { item: problem.items(db)[0], span: rowan::TextRange::default() };
            return Err(Box::new(refuse(vec![Lint::new(
                codes::PLANNER_UNSUPPORTED,
                loc,
                "`bare` ignores abstract actions, which an `:htn` problem cannot do without",
            )])));
        }
        bare(&mut task);
    }
    if let Some(loc) = task.impossible_goal {
        let lints = vec![
            Lint::new(codes::NO_PLAN, loc, "no plan: a goal can never hold"),
            Lint::new(
                codes::PLAN_OPEN_LINK,
                loc,
                "open link: no action makes this goal true, and the initial state does not either",
            ),
        ];
        return Err(Box::new(Outcome { status: Status::NoPlan, plan: None, stats: Stats::default(), lints }));
    }
    let h = heuristic::Heuristic::new(&task);
    Ok(Prepared { task, h })
}

impl<'db> Prepared<'db> {
    /// Anytime planning of a problem whose abstract actions are optional
    /// (no `:htn` task network): the first plan of the configured search;
    /// then, with that plan as a bound, the first better plan of the search
    /// without abstract actions (`bare`, at most half the time left: plans
    /// of elementary actions alone are often shorter, a patrol keeps its
    /// order of visits); then the configured search again, branch and bound
    /// on the best plan's makespan ([`Quality`]), until the time limit or no
    /// partial plan can do better. Returns the best plan.
    fn improve(
        &self,
        db: &'db dyn Db,
        config: &Config,
        limits: &PlannerLimits,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&Progress),
    ) -> Outcome<'db> {
        let started = std::time::Instant::now();
        let spent = || limits.time_spent_since(started);
        let first = PlannerLimits { first: true, ..limits.clone() };
        let mut best = self.first_plan(db, config, &first, cancel, progress);
        if best.status != Status::Solved {
            return best;
        }
        let mut stats = best.stats.clone();
        // The bound for what follows is the plan as written: without its
        // redundant steps, its makespan may be shorter than as found.
        let written = |q: Option<Quality>, plan: Option<&output::SolvedPlan>| {
            q.zip(plan).map(|(q, p)| Quality { makespan: q.makespan.min(p.makespan), ..q })
        };
        stats.best = written(stats.best, best.plan.as_ref());
        let report = |plan: &output::SolvedPlan, stats: &Stats, progress: &mut dyn FnMut(&Progress)| {
            progress(&Progress {
                expanded: stats.expanded,
                open: 0,
                best_f: stats.best.map_or(plan.makespan, |q| q.cost),
                elapsed: limits.time_spent_since(started),
                makespan: Some(plan.makespan),
                improved: true,
            })
        };
        if let Some(plan) = &best.plan {
            report(plan, &stats, progress);
        }
        let merge = |stats: &mut Stats, run: &Stats| {
            stats.expanded += run.expanded;
            stats.generated += run.generated;
            stats.peak_open = stats.peak_open.max(run.peak_open);
            stats.largest = stats.largest.max(run.largest);
            stats.redundant_time += run.redundant_time;
        };
        // The search without abstract actions, for at most half the time left.
        let left = limits.time.map(|t| t.saturating_sub(spent()));
        if left.is_none_or(|l| !l.is_zero()) && !cancel() {
            let mut task = self.task.clone();
            bare(&mut task);
            let h = heuristic::Heuristic::new(&task);
            let bare_config = Config { bare: true, ..config.clone() };
            let half = left.map(|l| spent() + l / 2);
            let bare_limits = PlannerLimits {
                time: half,
                time_spent: spent(),
                first: true,
                better_than: stats.best,
                ..limits.clone()
            };
            let other = Prepared { task, h };
            let run = other.search(db, &bare_config, &bare_limits, None, cancel, &mut |_| {});
            merge(&mut stats, &run.stats);
            if run.status == Status::Solved && run.plan.is_some() {
                stats.best = written(run.stats.best, run.plan.as_ref());
                stats.redundant_removed = run.stats.redundant_removed;
                stats.plans_found += 1;
                if let Some(plan) = &run.plan {
                    report(plan, &stats, progress);
                }
                best.plan = run.plan;
            }
        }
        // The configured search again, bounded by the best plan.
        let bounded =
            PlannerLimits { time_spent: spent(), first: false, better_than: stats.best, ..limits.clone() };
        let run = self.search(db, config, &bounded, None, cancel, progress);
        merge(&mut stats, &run.stats);
        match (run.status, run.plan) {
            (Status::Solved, Some(plan)) => {
                stats.best = written(run.stats.best, Some(&plan));
                stats.redundant_removed = run.stats.redundant_removed;
                stats.plans_found += run.stats.plans_found;
                stats.stopped_by = run.stats.stopped_by;
                best.plan = Some(plan);
            }
            (Status::Limit(kind), _) if kind != LimitKind::Cancelled => stats.stopped_by = Some(kind),
            _ => {}
        }
        stats.elapsed = limits.time_spent_since(started);
        best.stats = stats;
        best
    }

    /// A purely hierarchical problem: the search with refinements first for
    /// at most [`REFINE_FIRST_NODES`] expansions and a quarter of the time,
    /// then, when the problem allows it ([`search::Search::grows_from_front`]),
    /// the search that grows plans from their front for another quarter,
    /// and again with `greedy` (a heavier `h`) for a third quarter, then the
    /// search with links first for what is left. Each search that
    /// stops at its own bound hands over to the next; one that ends
    /// otherwise (a plan, none at all, or the run's own limit) is the answer.
    fn refine_then_links(
        &self,
        db: &'db dyn Db,
        config: &Config,
        limits: &PlannerLimits,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&Progress),
    ) -> Outcome<'db> {
        let started = std::time::Instant::now();
        let front = Config { front: true, ..config.clone() };
        let mut phases = vec![(Config { refine: true, ..config.clone() }, Some(REFINE_FIRST_NODES))];
        if search::Search::grows_from_front(&self.task, &front) {
            let greedy = Config { greedy: true, ..front.clone() };
            phases.push((front, None));
            phases.push((greedy, None));
        }
        phases.push((Config { links: true, ..config.clone() }, None));
        let quarter = limits.time.map(|t| t.saturating_sub(limits.time_spent) / 4);
        // What the searches before the one at hand did.
        let mut before = Stats::default();
        let last = phases.len() - 1;
        for (k, (phase, bound)) in phases.into_iter().enumerate() {
            let spent = limits.time_spent_since(started);
            let nodes = limits.nodes.map(|n| n.saturating_sub(before.expanded));
            let phase_limits = if k == last {
                PlannerLimits { time_spent: spent, nodes, ..limits.clone() }
            } else {
                let nodes = match (nodes, bound) {
                    (Some(n), Some(b)) => Some(n.min(b)),
                    (n, b) => n.or(b),
                };
                let time = limits.time.zip(quarter).map(|(t, q)| (spent + q).min(t));
                // A search that hands over frees its open lists: the
                // process goes on (left to the exit, those of the first
                // three searches were all held by the last).
                PlannerLimits { time_spent: spent, nodes, time, exits_after: false, ..limits.clone() }
            };
            // The reports count the expansions of every search.
            let done = before.expanded;
            let mut counted = |p: &Progress| progress(&Progress { expanded: done + p.expanded, ..*p });
            let mut outcome = self.search(db, &phase, &phase_limits, None, cancel, &mut counted);
            let spent = limits.time_spent_since(started);
            let at_bound = k < last
                && match outcome.status {
                    Status::Limit(LimitKind::Nodes) => {
                        limits.nodes.is_none_or(|n| before.expanded + outcome.stats.expanded < n)
                    }
                    Status::Limit(LimitKind::Time) => limits.time.is_none_or(|t| spent < t),
                    // The search from the front runs a recursion to its end
                    // before other tasks: running out of plans proves
                    // nothing where a plan must interleave them (IPC 2020
                    // PCP p-pcp14, solved by links first).
                    Status::NoPlan => phase.front,
                    _ => false,
                };
            let b = &mut outcome.stats;
            b.expanded += before.expanded;
            b.generated += before.generated;
            b.peak_open = b.peak_open.max(before.peak_open);
            b.largest = b.largest.max(before.largest);
            b.elapsed += before.elapsed;
            b.first_found = b.first_found.map(|f| f + before.elapsed);
            if !at_bound {
                return outcome;
            }
            before = outcome.stats;
        }
        unreachable!("the last search is the answer")
    }

    /// Runs the search from the empty plan, or from the start plan `seed`
    /// (a repair, section 5.1 of the HiPOP paper: the search only adds to
    /// it). A seed the task cannot take gives no plan.
    pub fn search(
        &self,
        db: &'db dyn Db,
        config: &Config,
        limits: &PlannerLimits,
        seed: Option<&search::Seed>,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&Progress),
    ) -> Outcome<'db> {
        let task = &self.task;
        let h = &self.h;
        let mut stats = Stats { operators: task.ops.len(), methods: task.methods.len(), ..Stats::default() };
        // A repair adds to its start plan and wants the shortest schedule
        // near the old one: plan size would lead it to the fewest new steps
        // (a far robot's long trip rather than a near one's), not there.
        let repair = Config { steps: false, ..config.clone() };
        let config = if seed.is_some() { &repair } else { config };
        let search = search::Search::new(task, h, config);
        let roots = match seed {
            None => search.initial(),
            Some(seed) => {
                search.seeded(seed).map(|v| v.into_iter().map(|(p, _)| p).collect()).unwrap_or_default()
            }
        };
        let mut best = None;
        let end = search.run(roots, limits, cancel, progress, &mut stats, &mut best);
        match end {
            search::End2::Solved(p) => {
                let mut p = *p;
                // A repair keeps the old steps it started from: only a
                // plan of the search's own loses its redundant steps.
                if seed.is_none() {
                    let started = std::time::Instant::now();
                    // Within what is left of the time limit.
                    let left = limits.time.map(|t| t.saturating_sub(limits.time_spent + stats.elapsed));
                    let stop = || cancel() || left.is_some_and(|l| started.elapsed() >= l);
                    let (q, removed) = search.without_redundant_steps(p, &stop);
                    p = q;
                    stats.redundant_removed = removed.steps;
                    stats.redundant_time = started.elapsed();
                }
                p.keep_old_times();
                let plan = output::solved(db, task, &p);
                Outcome { status: Status::Solved, plan: Some(plan), stats, lints: Vec::new() }
            }
            search::End2::Exhausted => {
                let skipped = match stats.loops_skipped {
                    0 => String::new(),
                    n => format!(
                        ", except {n} refinement{} that repeat a task with the same arguments below itself",
                        if n == 1 { "" } else { "s" }
                    ),
                };
                let message = if search.runs_recursions_to_their_end() {
                    format!(
                        "no plan from the front: the search explored every partial plan that runs a recursion to its end before other tasks ({} expanded){skipped}; a plan that interleaves them may exist (the default configuration searches for it)",
                        stats.expanded
                    )
                } else {
                    format!(
                        "no plan with the allowed actions and the methods: the search explored every partial plan ({} expanded){skipped}",
                        stats.expanded
                    )
                };
                let mut lints = vec![Lint::new(codes::NO_PLAN, mission_loc(db, task), message)];
                lints.extend(output::flaws(db, task, best.as_ref(), h));
                Outcome { status: Status::NoPlan, plan: None, stats, lints }
            }
            search::End2::Limit(kind) => {
                let what = match kind {
                    LimitKind::Time => format!(
                        "the time limit ({:.1} s)",
                        limits.time.unwrap_or(stats.elapsed + limits.time_spent).as_secs_f64()
                    ),
                    LimitKind::Nodes => format!("the node limit ({} plans expanded)", stats.expanded),
                    LimitKind::Memory => "the memory limit".to_string(),
                    LimitKind::Cancelled => "a cancellation".to_string(),
                };
                let mut lints = vec![Lint::new(
                    codes::PLANNER_LIMIT,
                    mission_loc(db, task),
                    format!(
                        "no plan found before {what}; the flaws of the most advanced partial plan follow"
                    ),
                )];
                lints.extend(output::flaws(db, task, best.as_ref(), h));
                Outcome { status: Status::Limit(kind), plan: None, stats, lints }
            }
        }
    }
}

/// Where a verdict on the whole problem is reported: its first goal literal
/// or `:htn` task, else its first section.
fn mission_loc<'db>(db: &'db dyn Db, task: &task::Task<'db>) -> Loc<'db> {
    task.goals
        .first()
        .map(|g| g.1)
        .or_else(|| task.htn.iter().flatten().find_map(|n| n.tasks.first().map(|t| t.1)))
        .unwrap_or(Loc { item: task.problem.items(db)[0], span: rowan::TextRange::default() })
}

/// `bare`: every elementary action is allowed, no abstract one.
fn bare(task: &mut task::Task<'_>) {
    for op in &mut task.ops {
        op.allowed = !op.is_abstract;
    }
    task.achievers.clear();
    for (i, op) in task.ops.iter().enumerate() {
        if !op.allowed || op.dead {
            continue;
        }
        for e in &op.effs {
            let v = task.achievers.entry(e.lit).or_default();
            if !v.iter().any(|(o, _)| *o == i as u32) {
                v.push((i as u32, e.at));
            }
        }
    }
}
