//! Algorithm 1 of the HiPOP paper: A* over partial plans, with HiPOP's plan
//! and flaw selection (section 4.2.3) and geometric reasoning (4.3).
//!
//! - Plan selection (here): `f = g + h`, `g` the makespan of the plan's
//!   earliest schedule (or the busiest agent's work, when larger) plus what
//!   its threats must cost and a step cost, `h` the estimates of its open
//!   links and abstract flaws ([`cost`]); ties broken on the remaining
//!   effort, the smaller plan, then last in, first out. A plan entering its
//!   completion gets a greedy depth-first descent first ([`Search::probe`]).
//! - Flaw selection ([`flaws`]): which flaw of a plan is solved next.
//! - Resolvers ([`resolvers`]): the children that solve it, and the initial
//!   plans.

mod cost;
mod flaws;
mod redundant;
mod resolvers;
mod seed;

pub use redundant::Removed;
pub use seed::{Seed, SeedError, SeedOrder, SeedStep, Seeded};

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::time::Instant;

use super::heuristic::Heuristic;
use super::itinerary::{Geo, Pending};
use super::plan::Plan;
use super::stn::Tp;
use super::task::Task;
use super::{Config, LimitKind, Motion, PlannerLimits, Progress, Quality, Stats};

/// What a unit of work costs in `g` beyond the makespan: every step costs
/// something, so that no chain of steps is free (a step that fits in
/// parallel does not lengthen the makespan, and reuse makes its conditions
/// free in `h`): A* needs positive costs to leave an endless subtree of
/// such plans (`tests/planner/props/step-cost.pddl`). Small, so that the
/// makespan decides: measured neutral on the benchmarks' makespans.
const STEP_COST: f64 = 0.02;

/// A plan in the open list.
/// The open list, left unfreed at its end when the process exits next
/// ([`PlannerLimits::exits_after`]).
struct Open {
    heap: BinaryHeap<Node>,
    free: bool,
}

impl std::ops::Deref for Open {
    type Target = BinaryHeap<Node>;
    fn deref(&self) -> &BinaryHeap<Node> {
        &self.heap
    }
}

impl std::ops::DerefMut for Open {
    fn deref_mut(&mut self) -> &mut BinaryHeap<Node> {
        &mut self.heap
    }
}

impl Drop for Open {
    fn drop(&mut self) {
        if !self.free {
            std::mem::forget(std::mem::take(&mut self.heap));
        }
    }
}

struct Node {
    f: f64,
    /// The makespan of its earliest schedule, which no completion of the
    /// plan shortens: the bound of a search that goes on after a plan.
    span: f64,
    /// Its lineage had a greedy completion already.
    probed: bool,
    effort: f64,
    /// Steps: a smaller plan first among equals (a chain of steps that
    /// cost nothing, parallel in the makespan and free in h by reuse,
    /// must not hide the sibling that links to a step already there).
    size: usize,
    id: u64,
    plan: Plan,
}

impl PartialEq for Node {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Node {
    /// The best node is the greatest (BinaryHeap is a max-heap).
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .f
            .total_cmp(&self.f)
            .then(other.effort.total_cmp(&self.effort))
            .then(other.size.cmp(&self.size))
            .then(self.id.cmp(&other.id))
    }
}

/// The flaw chosen in a plan.
enum Flaw {
    Threat(usize),
    Open(usize),
    Abstract(usize),
    Mutex(Tp, Tp),
    /// A goal that a timed initial literal makes true, at this time point,
    /// after the plan's last event: VAL does not apply it.
    Late(Tp),
    /// The next visit of an itinerary (geometric reasoning).
    Visit(Pending),
    /// Two happenings that touch the same numeric fluent, one writing it,
    /// not ordered yet.
    NumOrder(Tp, Tp),
    /// A numeric condition that does not hold where its step reads it.
    Numeric(super::numeric::Failed),
    /// A flaw no resolver can solve (a threat with no ordering left, an
    /// itinerary that cannot go on): the plan has no child.
    Dead,
}

pub struct Search<'a, 'db> {
    pub task: &'a Task<'db>,
    pub h: &'a Heuristic,
    pub config: &'a Config,
    /// Geometric reasoning: the itineraries of the members of position
    /// families with move actions in 𝒜 (`motion`, `ncm`).
    geo: Option<Geo>,
    /// Method instances not tried because they only go round a loop.
    loops: std::cell::Cell<u64>,
}

/// How a search ended.
pub enum End2 {
    Solved(Box<Plan>),
    Exhausted,
    Limit(LimitKind),
}

impl<'a, 'db> Search<'a, 'db> {
    pub fn new(task: &'a Task<'db>, h: &'a Heuristic, config: &'a Config) -> Self {
        let has_motion = config.motion != Motion::Off && task.motion.iter().any(|m| m.is_some());
        let geo = has_motion.then(|| Geo::new(task, h));
        Search { task, h, config, geo, loops: Default::default() }
    }

    /// `g`, `h` and the effort of a plan about to enter the open list,
    /// after its threats with one ordering left are solved; `None` when a
    /// threat has none (the plan is dead).
    /// Also the makespan of its earliest schedule, which no completion of
    /// the plan shortens (steps and orderings are only added).
    fn score(&self, plan: &mut Plan) -> Option<(f64, f64, f64, f64)> {
        let penalty = self.settle(plan)?;
        let (h, effort) = self.estimate(plan);
        let (busiest, total) = self.work(plan);
        let span = plan.makespan();
        Some((span.max(busiest) + penalty + STEP_COST * total, h, effort, span))
    }

    /// Whether a flaw belongs to the completion of a plan: what is left
    /// once every step that supports a goal or a condition is chosen
    /// (itineraries, refinements, the delayed threats).
    fn completes(flaw: &Flaw) -> bool {
        !matches!(flaw, Flaw::Open(_))
    }

    /// The children of a plan for a flaw, scored: those a threat left
    /// without ordering are dropped (`dead` gets them, for reports).
    fn expand(&self, p: &Plan, flaw: Flaw, stats: &mut Stats, dead: &mut dyn FnMut(&Plan)) -> Vec<Scored> {
        let linking = matches!(flaw, Flaw::Open(_));
        let mut children = Vec::new();
        self.resolvers(p, flaw, &mut children);
        let mut out = Vec::with_capacity(children.len());
        for mut c in children {
            let added = if linking { c.steps.len() - p.steps.len() } else { 0 };
            match self.score(&mut c) {
                Some((g, h, effort, span)) => out.push(Scored { f: g + h, span, effort, added, plan: c }),
                None => dead(&c),
            }
        }
        stats.generated += out.len() as u64;
        out
    }

    /// Greedy completion: a depth-first descent from a plan's children (in
    /// [`Scored::probe_order`]) that backtracks, within `budget` expansions.
    /// A plan it finds has no flaw, like one A* would return.
    fn probe(
        &self,
        first: Vec<Plan>,
        budget: u64,
        admits: &dyn Fn(f64) -> bool,
        stats: &mut Stats,
        deadline: &dyn Fn() -> bool,
    ) -> Option<Plan> {
        let mut stack: Vec<std::vec::IntoIter<Plan>> = vec![first.into_iter()];
        let mut spent = 0u64;
        loop {
            let mut p = loop {
                let top = stack.last_mut()?;
                if let Some(n) = top.next() {
                    break n;
                }
                stack.pop();
            };
            p.stn.flush();
            p.stn.defer();
            spent += 1;
            stats.expanded += 1;
            if spent > budget || deadline() {
                return None;
            }
            let Some(flaw) = self.select(&mut p) else {
                p.stn.flush();
                return Some(p);
            };
            let mut scored = self.expand(&p, flaw, stats, &mut |_| {});
            scored.retain(|c| admits(c.span));
            scored.sort_by(Scored::probe_order);
            stack.push(scored.into_iter().map(|x| x.plan).collect::<Vec<_>>().into_iter());
        }
    }

    /// What a plan without flaws costs: its `g` (the makespan, or the
    /// busiest agent's work when larger, and the step cost).
    fn solution_cost(&self, plan: &Plan) -> f64 {
        let (busiest, total) = self.work(plan);
        plan.makespan().max(busiest) + STEP_COST * total
    }

    /// Runs the search from `roots` ([`Search::initial`], or a repair's
    /// start plans, [`Search::seeded`]). With [`PlannerLimits::first`] it
    /// returns the first plan found; otherwise it goes on with the best plan
    /// found as a bound on `f` (branch and bound: children that cannot do
    /// better are dropped), until no plan left in the open list can do
    /// better or a limit is reached, and returns the best.
    pub fn run(
        &self,
        roots: Vec<Plan>,
        limits: &PlannerLimits,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&Progress),
        stats: &mut Stats,
        best: &mut Option<Plan>,
    ) -> End2 {
        let started = Instant::now();
        let mut heap = Open { heap: BinaryHeap::new(), free: !limits.exits_after };
        let mut id = 0u64;
        // The most advanced plan: the fewest open links and abstract flaws
        // (its threats are what stopped it, if anything).
        let mut best_effort = usize::MAX;
        let keep_best = |plan: &Plan, best: &mut Option<Plan>, best_effort: &mut usize| {
            let advance = plan.open.len() + plan.abstracts.len();
            if advance <= *best_effort {
                *best_effort = advance;
                *best = Some(plan.clone());
            }
        };
        let probing = self.config.lookahead;
        for mut root in roots {
            match self.score(&mut root) {
                Some((g, h, effort, span)) => {
                    id += 1;
                    stats.generated += 1;
                    let size = root.steps.len();
                    heap.push(Node { f: g + h, span, effort, size, id, probed: false, plan: root });
                }
                None => keep_best(&root, best, &mut best_effort),
            }
        }
        let out_of_time =
            |elapsed: std::time::Duration| limits.time.is_some_and(|t| elapsed + limits.time_spent >= t);
        let time_up = || out_of_time(started.elapsed()) || cancel();
        let mut last_report = Instant::now();
        let mut last_in_use = limits.memory_in_use.map_or(0, |f| f());
        let mut next_milestone: u64 = 1024;
        // The best plan found and its cost, when the search goes on.
        let mut incumbent: Option<(Plan, Quality)> = None;
        // A plan found: returned when it is the first and `first` is set;
        // else kept when better than the best, and `None` asks to go on.
        let found = |plan: Plan,
                     stats: &mut Stats,
                     incumbent: &mut Option<(Plan, Quality)>,
                     open: usize,
                     progress: &mut dyn FnMut(&Progress)|
         -> Option<End2> {
            let elapsed = started.elapsed();
            let quality = Quality { makespan: plan.makespan(), cost: self.solution_cost(&plan) };
            let known = incumbent.as_ref().map(|(_, q)| *q).or(limits.better_than);
            if known.is_some_and(|k| !quality.better_than(k)) {
                return None;
            }
            stats.best = Some(quality);
            if limits.first {
                stats.elapsed = elapsed;
                stats.first_found = Some(elapsed);
                stats.plans_found = 1;
                return Some(End2::Solved(Box::new(plan)));
            }
            stats.first_found.get_or_insert(elapsed);
            stats.plans_found += 1;
            progress(&Progress {
                expanded: stats.expanded,
                open,
                best_f: quality.cost,
                elapsed: limits.time_spent + elapsed,
                makespan: Some(quality.makespan),
                improved: true,
            });
            *incumbent = Some((plan, quality));
            None
        };
        // How a search that goes on ends: with its best plan, if any.
        let settle_end =
            |end: End2, incumbent: Option<(Plan, Quality)>, stats: &mut Stats| match (end, incumbent) {
                (End2::Limit(kind), Some((plan, _))) if kind != LimitKind::Cancelled => {
                    stats.stopped_by = Some(kind);
                    End2::Solved(Box::new(plan))
                }
                (End2::Exhausted, Some((plan, _))) => End2::Solved(Box::new(plan)),
                (end, _) => end,
            };
        let end = loop {
            let Some(node) = heap.pop() else { break End2::Exhausted };
            let known = incumbent.as_ref().map(|(_, q)| *q).or(limits.better_than);
            let admits = |makespan: f64| known.is_none_or(|k| k.admits(makespan));
            if !admits(node.span) {
                // Found since it entered the open list: cannot do better.
                continue;
            }
            let mut plan = node.plan;
            plan.stn.flush();
            plan.stn.defer();
            stats.expanded += 1;
            stats.open = heap.len();
            stats.peak_open = stats.peak_open.max(heap.len());
            keep_best(&plan, best, &mut best_effort);
            // At every expansion: one can take a tenth of a second on a
            // large task (8,000 ground operators), and 32 of them would
            // overshoot the time limit by seconds.
            {
                let elapsed = started.elapsed();
                stats.elapsed = elapsed;
                if cancel() {
                    break End2::Limit(LimitKind::Cancelled);
                }
                if out_of_time(elapsed) {
                    break End2::Limit(LimitKind::Time);
                }
                if last_report.elapsed().as_millis() >= 100 {
                    last_report = Instant::now();
                    progress(&Progress {
                        expanded: stats.expanded,
                        open: heap.len(),
                        best_f: node.f,
                        elapsed: limits.time_spent + elapsed,
                        makespan: incumbent.as_ref().map(|(p, _)| p.makespan()),
                        improved: false,
                    });
                }
            }
            if limits.nodes.is_some_and(|n| stats.expanded > n) {
                stats.elapsed = started.elapsed();
                break End2::Limit(LimitKind::Nodes);
            }
            let over = match (limits.memory, limits.memory_in_use) {
                // Measured every 32 expansions (a plan is a few kilobytes to
                // a few hundred), and the search stops when the next 32,
                // growing the memory as much as the last 32 did, would go
                // over: it ends under the limit, not a few megabytes past it.
                (Some(m), Some(in_use)) if stats.expanded.is_multiple_of(32) => {
                    let now = in_use();
                    let next = now.saturating_add(now.saturating_sub(last_in_use));
                    last_in_use = now;
                    next > m
                }
                (Some(_), Some(_)) => false,
                (Some(m), None) => heap.len().saturating_mul(approx_plan_bytes(&plan)) > m,
                (None, _) => false,
            };
            if over {
                stats.elapsed = started.elapsed();
                break End2::Limit(LimitKind::Memory);
            }
            let Some(flaw) = self.select(&mut plan) else {
                plan.stn.flush();
                match found(plan, stats, &mut incumbent, heap.len(), progress) {
                    Some(end) => return end,
                    None => continue,
                }
            };
            let completes = Self::completes(&flaw);
            let mut scored = self.expand(&plan, flaw, stats, &mut |c| keep_best(c, best, &mut best_effort));
            scored.retain(|c| admits(c.span));
            // A plan entering its completion: first a greedy descent from
            // its children. And when A* has spent 1024, 2048, 4096…
            // expansions, the plan it is at gets one too, whatever is left.
            let mut probed = node.probed;
            let milestone = stats.expanded >= next_milestone;
            if milestone {
                next_milestone *= 2;
            }
            if probing && (!probed && completes || milestone) {
                probed |= completes;
                let remaining = plan.open.len() as u64
                    + plan.threats.len() as u64
                    + plan
                        .abstracts
                        .iter()
                        .filter_map(|&a| plan.op_of(a))
                        .map(|o| self.h.refine_effort[o as usize].min(1e6) as u64)
                        .sum::<u64>();
                let budget = 256 + 4 * remaining;
                let mut first: Vec<&Scored> = scored.iter().collect();
                first.sort_by(|a, b| Scored::probe_order(a, b));
                let first = first.into_iter().map(|s| s.plan.clone()).collect();
                if let Some(plan) = self.probe(first, budget, &admits, stats, &time_up)
                    && let Some(end) = found(plan, stats, &mut incumbent, heap.len(), progress)
                {
                    return end;
                }
            }
            for c in scored {
                id += 1;
                let size = c.plan.steps.len();
                heap.push(Node { f: c.f, span: c.span, effort: c.effort, size, id, probed, plan: c.plan });
            }
        };
        stats.elapsed = started.elapsed();
        if matches!(end, End2::Exhausted) && incumbent.is_none() {
            stats.loops_skipped = self.loops.get();
        }
        settle_end(end, incumbent, stats)
    }
}

/// A child plan with its score.
struct Scored {
    f: f64,
    span: f64,
    effort: f64,
    /// Steps it added for an open link.
    added: usize,
    plan: Plan,
}

impl Scored {
    /// The order a greedy descent tries children in: for an open link, a
    /// causal link to a step already there before a new step (reuse keeps
    /// a new step's conditions free in h, so a descent could otherwise add
    /// steps that need steps without end); then the lowest f, the effort.
    fn probe_order(a: &Scored, b: &Scored) -> Ordering {
        a.added.cmp(&b.added).then(a.f.total_cmp(&b.f)).then(a.effort.total_cmp(&b.effort))
    }
}

/// What a plan in the open list costs on its own beyond what it shares:
/// the chunks a child copies (steps, links, time points) and its flaw lists.
fn approx_plan_bytes(p: &Plan) -> usize {
    let spine = (p.steps.len() + p.links.len() + 3 * p.stn.len()) / super::pvec::CHUNK * 8;
    spine + 4 * 1024 + (p.open.len() + p.threats.len()) * 32
}
