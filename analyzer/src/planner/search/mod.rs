//! Algorithm 1 of the HiPOP paper: A* over partial plans, with HiPOP's plan
//! and flaw selection (section 4.2.3) and geometric reasoning (4.3).
//!
//! - Plan selection (here): `f = g + h`, `g` the makespan of the plan's
//!   earliest schedule (or the busiest agent's work, when larger) plus what
//!   its threats must cost and a step cost, `h` the estimates of its open
//!   links and abstract flaws ([`cost`]), weighted by 2 on purely
//!   hierarchical problems ([`HTN_WEIGHT`]); ties broken on the remaining
//!   effort, the smaller plan, then last in, first out. A second open list
//!   ranks the same plans by size (steps plus the estimate in actions,
//!   VHPOP's `ADDR`), and the two are expanded in turn ([`Open`]). A plan
//!   entering its completion gets a greedy depth-first descent first
//!   ([`Search::probe`]).
//! - Flaw selection ([`flaws`]): which flaw of a plan is solved next.
//! - Resolvers ([`resolvers`]): the children that solve it, and the initial
//!   plans.

mod cost;
mod flaws;
mod front;
mod progression;
mod redundant;
mod resolvers;
mod seed;
mod tokens;

pub use redundant::Removed;
use resolvers::Made;
pub use seed::{Seed, SeedError, SeedOrder, SeedStep, Seeded};

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::rc::Rc;
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

/// The weight of `h` on purely hierarchical problems ([`Search::weight`]).
const HTN_WEIGHT: f64 = 2.0;

/// Expansions (greedy completions included) by the makespan's open list
/// alone before the one ranked by plan size takes turns with it: a problem
/// the makespan's solves at once keeps its plan (the plan size's may find
/// a smaller plan of a longer makespan first: a far robot's trip of as
/// many steps as a near one's), and its size list only costs its nodes.
const SIZE_LANE_AFTER: u64 = 1000;

/// What a threat left in a plan counts in the rank of the open list by
/// plan size ([`Search::size_rank`]): half a step. Ordering a threat adds
/// no step, and one that both orderings still solve is most often ordered
/// by later links; counted as a whole step, every step that may overlap a
/// link (a truck driven while a link needs another of its places, an
/// aircraft's flights around a boarding) put its plan a step behind the
/// plans whose steps were ordered already, and the list went through
/// those first: DriverLog `time` problem 8 took more than 231,000 plans
/// and 4 GiB, ZenoTravel time-simple problem 8 more than 22,000. Not
/// counted at all, Rovers `time` problem 1 (2,030 plans) and Depots `time`
/// problem 7 (15,024) were no longer solved in 30,000 (docs/benchmarks.md,
/// 2026-11-27).
const SIZE_THREAT_WEIGHT: f64 = 0.5;

/// Steps a greedy descent may add beyond twice the remaining effort of the
/// plan it starts from ([`Search::probe_steps`]).
const PROBE_SPARE_STEPS: usize = 16;

/// The open lists, left unfreed at their end when the process exits next
/// ([`PlannerLimits::exits_after`]): one ranked by `f` (the makespan and
/// the estimates in time), and, unless the configuration says `nosteps`,
/// one ranked by plan size (the steps and the estimates in actions),
/// expanded in turn. A plan is in both; the first to reach it expands it,
/// and the other drops it when it comes to it.
struct Open {
    lanes: Vec<BinaryHeap<Node>>,
    /// The lanes that expand: the makespan's alone for the first
    /// [`SIZE_LANE_AFTER`] expansions, then all.
    active: usize,
    /// Plans not expanded yet.
    live: usize,
    /// The lane that expands next.
    turn: usize,
    free: bool,
}

impl Open {
    fn new(lanes: usize, free: bool) -> Open {
        Open {
            lanes: (0..lanes.max(1)).map(|_| BinaryHeap::new()).collect(),
            active: 1,
            live: 0,
            turn: 0,
            free,
        }
    }

    fn len(&self) -> usize {
        self.live
    }

    /// Adds a plan, ranked in each lane by its key there (`f`, effort).
    fn push(&mut self, entry: Entry, keys: [(f64, f64); 2], size: usize, id: u64) {
        let entry = Rc::new(entry);
        for (lane, &(f, effort)) in self.lanes.iter_mut().zip(&keys) {
            lane.push(Node { f, effort, size, id, entry: Rc::clone(&entry) });
        }
        self.live += 1;
    }

    /// Keeps the makespan's lane alone (a plan is known: the search now
    /// looks for a shorter one).
    fn makespan_only(&mut self) {
        if self.lanes.len() > 1 {
            self.active = 1;
            let rest = self.lanes.split_off(1);
            if self.free {
                drop(rest);
            } else {
                std::mem::forget(rest);
            }
            self.turn = 0;
        }
    }

    /// The next plan to expand: the best of the active lane whose turn it
    /// is (or of another, when that one is empty), with its entry.
    fn pop(&mut self) -> Option<(Rc<Entry>, Child)> {
        let n = self.active;
        for k in 0..n {
            let lane = (self.turn + k) % n;
            while let Some(node) = self.lanes[lane].pop() {
                let taken = node.entry.plan.borrow_mut().take();
                if let Some(plan) = taken {
                    self.turn = (lane + 1) % n;
                    self.live -= 1;
                    return Some((node.entry, plan));
                }
            }
        }
        None
    }
}

impl Drop for Open {
    fn drop(&mut self) {
        if !self.free {
            std::mem::forget(std::mem::take(&mut self.lanes));
        }
    }
}

/// A plan in the open lists.
struct Entry {
    /// Its `f` (the makespan's lane), for progress reports.
    f: f64,
    /// The makespan of its earliest schedule, which no completion of the
    /// plan shortens: the bound of a search that goes on after a plan.
    span: f64,
    /// Its lineage had a greedy completion already.
    probed: bool,
    /// Taken by the lane that expands it.
    plan: std::cell::RefCell<Option<Child>>,
}

/// A plan of the open lists: the plan itself, or how to make it again
/// from its parent. A child of an open link is kept as its parent (shared
/// by its siblings) and what supports the link ([`Made`]): an expansion of
/// a plan of a hundred steps makes a hundred such children, a few
/// kilobytes each as plans (the chunks of its steps, links and network
/// that it wrote), of which one in a hundred is ever expanded. A child of
/// an abstract flaw likewise, as its parent, the abstract step and the
/// method instance that refines it: a refinement writes the most (its
/// subtasks' steps and time points, their orderings, the method's
/// preconditions and the step's effects as open links). The one popped is
/// made again and settled (its threats with one ordering left ordered, as
/// when it was scored): the same plan.
enum Child {
    /// Boxed: a plan is a few hundred bytes of spines and counters, ten
    /// times the rest of an entry.
    Plan(Box<Plan>),
    Made(Rc<Plan>, Made),
}

/// A plan's place in one lane.
struct Node {
    /// `f` in the makespan's lane; the steps and the estimate in actions
    /// in the plan size's.
    f: f64,
    effort: f64,
    /// Steps: a smaller plan first among equals (a chain of steps that
    /// cost nothing, parallel in the makespan and free in h by reuse,
    /// must not hide the sibling that links to a step already there).
    size: usize,
    id: u64,
    entry: Rc<Entry>,
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
    /// The front of a plan grown from its start ([`front`]): its
    /// elementary steps that can run next, and the refinements of the
    /// abstract step of the front at this index of `Plan::abstracts`.
    Front(Option<usize>),
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
    /// When the time limit falls, while [`Search::run`] runs: an expansion
    /// stops making children past it ([`Search::past_limit`]).
    until: std::cell::Cell<Option<Instant>>,
    /// What each operator uses up, in a problem where no step is ever
    /// inserted ([`tokens`]).
    tokens: Option<tokens::Tokens>,
    /// The search starts from a repair's start plans ([`Search::seeded`]):
    /// their old steps ran, or run, from another state than the problem's
    /// initial one, and [`Search::doomed`] does not apply.
    from_seeds: std::cell::Cell<bool>,
    /// The walks of [`Search::unrunnable`] so far, and the plans they
    /// dropped: the walk stops when it seldom drops one.
    walks: std::cell::Cell<(u64, u64)>,
    /// Plans grow from their front ([`front`]): the relaxed composition
    /// of the task, for their estimate.
    composition: Option<front::Composition>,
    /// Plans grown from their front that entered the open lists, by what
    /// they have left to do ([`Search::front_key`]).
    front_seen: std::cell::RefCell<front::Seen>,
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
        let tokens = task.achievers.is_empty().then(|| tokens::Tokens::new(task));
        let composition =
            Search::front_applies(task, config, geo.is_some()).then(|| front::Composition::new(task));
        Search {
            task,
            h,
            config,
            geo,
            loops: Default::default(),
            until: Default::default(),
            tokens,
            from_seeds: Default::default(),
            walks: Default::default(),
            composition,
            front_seen: Default::default(),
        }
    }

    /// Whether the time limit of the running search has passed. One
    /// expansion of a plan of a hundred steps on a large task makes
    /// hundreds of children, each with its own temporal network and
    /// estimate (a tenth of a second and more, longer on a loaded
    /// machine): past the limit, it stops making them, and the search
    /// stops at its next look at the clock.
    pub(super) fn past_limit(&self) -> bool {
        self.until.get().is_some_and(|t| Instant::now() >= t)
    }

    /// `g`, `h` and the effort of a plan about to enter the open list,
    /// after its threats with one ordering left are solved; `None` when a
    /// threat has none (the plan is dead).
    /// Also the makespan of its earliest schedule, which no completion of
    /// the plan shortens (steps and orderings are only added).
    fn score(&self, plan: &mut Plan) -> Option<(f64, f64, f64, f64)> {
        self.score_as(plan, true, &mut None)
    }

    /// [`Search::score`]; `steps_changed` when the plan may have steps its
    /// parent did not have (not a causal link's child): only then are its
    /// steps checked for ones that can never run ([`Search::doomed`]),
    /// which a causal link's ordering seldom brings about and which costs
    /// about as much as the rest of the score on the plans of IPC 2020 PCP.
    /// A plan grown from its front gets its key ([`Search::front_key`]) in
    /// `key`, for the search to record it when it enters the open lists.
    fn score_as(
        &self,
        plan: &mut Plan,
        steps_changed: bool,
        key: &mut Option<Box<[u32]>>,
    ) -> Option<(f64, f64, f64, f64)> {
        let penalty = self.settle(plan)?;
        let span = plan.makespan();
        // The front, read once for the key, the walk and the estimate.
        let view = self.at_front().then(|| self.view(plan));
        if let Some(view) = &view {
            *key = self.front_key_in(plan, view);
            if key.as_deref().is_some_and(|k| self.front_known_key(k, span)) {
                // Grown from its front, with what is left to do as a plan
                // met before: the same completions, none shorter. (Before
                // the walk of its orders, which costs more.)
                return None;
            }
        }
        if self.task.achievers.is_empty() {
            // No step is ever inserted: a link no step can support is dead.
            let ready = self.ready_links(plan);
            if self.dead_link(plan, &ready).is_some()
                || steps_changed && self.doomed(plan)
                || self.unrunnable(plan, view.as_ref())
            {
                return None;
            }
        }
        let (busiest, total) = self.work(plan);
        let (h, effort) = self.estimate_in(plan, view.as_ref());
        if !h.is_finite() {
            // Grown from its front: what is left cannot run from there.
            return None;
        }
        Some((span.max(busiest) + penalty + STEP_COST * total, h, effort, span))
    }

    /// The weight of `h` in `f`: 2 (weighted A*) on a purely hierarchical
    /// problem, grounded top-down, where the decomposition's estimate
    /// tells refinements apart that the makespan so far does not
    /// ([`front::FRONT_WEIGHT`] for plans grown from their front,
    /// [`front::FRONT_GREEDY_WEIGHT`] with `greedy`); 1 (A*) otherwise.
    fn weight(&self) -> f64 {
        if self.at_front() {
            return if self.config.greedy { front::FRONT_GREEDY_WEIGHT } else { front::FRONT_WEIGHT };
        }
        if self.task.g.tdg_methods.is_some() { HTN_WEIGHT } else { 1.0 }
    }

    /// A plan's rank in the lane of plan size: its steps plus the estimate
    /// of its open links and abstract flaws in actions (VHPOP's `ADDR` with
    /// unit action costs), plus [`SIZE_THREAT_WEIGHT`] per threat left.
    fn size_rank(&self, plan: &Plan, effort: f64) -> f64 {
        let steps = (plan.steps.len() - 2 - self.task.tils.len()) as f64;
        // The effort counts each threat as one.
        steps + effort - (1.0 - SIZE_THREAT_WEIGHT) * plan.threats.len() as f64
    }

    /// The open lists of a search: with the lane of plan size while it
    /// looks for a first plan, unless the configuration says `nosteps` or
    /// the problem has an `:htn`. A search bounded by a known plan looks for
    /// a shorter makespan, which plan size does not lead to.
    fn lanes(&self, limits: &PlannerLimits) -> usize {
        if self.config.steps && self.task.htn.is_none() && limits.better_than.is_none() { 2 } else { 1 }
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
        let mut made = Vec::new();
        match flaw {
            Flaw::Open(i) => self.open_resolvers_made(p, i, &mut children, &mut made),
            Flaw::Abstract(i) => self.refinements_made(p, i, &mut children, &mut |m| made.push(m)),
            flaw => self.resolvers(p, flaw, &mut children),
        }
        self.scored_made(p, children, made, linking, stats, dead)
    }

    /// The child of an open link or of an abstract flaw `made` from
    /// `parent`, made again and settled like [`Search::scored`] scored it:
    /// `None` if it does not come out the same way (it always does: making
    /// and settling a plan only read the parent and the task).
    fn remade(&self, parent: &Plan, made: Made) -> Option<Plan> {
        let mut c = self.remake(parent, made)?;
        self.settle(&mut c)?;
        Some(c)
    }

    /// [`Search::expand`] of `children`, the resolvers of an open link of
    /// `p` when `linking` (their steps added count in the descent's order).
    fn scored(
        &self,
        p: &Plan,
        children: Vec<Plan>,
        linking: bool,
        stats: &mut Stats,
        dead: &mut dyn FnMut(&Plan),
    ) -> Vec<Scored> {
        self.scored_made(p, children, Vec::new(), linking, stats, dead)
    }

    /// [`Search::scored`], with how each child was made when `made` is
    /// not empty (one per child, in order).
    fn scored_made(
        &self,
        p: &Plan,
        children: Vec<Plan>,
        made: Vec<Made>,
        linking: bool,
        stats: &mut Stats,
        dead: &mut dyn FnMut(&Plan),
    ) -> Vec<Scored> {
        let mut out = Vec::with_capacity(children.len());
        let mut made = made.into_iter();
        for mut c in children {
            if self.past_limit() {
                break;
            }
            let how = made.next();
            let added = if linking { c.steps.len() - p.steps.len() } else { 0 };
            let mut key = None;
            match self.score_as(&mut c, !linking, &mut key) {
                Some((g, h, effort, span)) => out.push(Scored {
                    f: g + self.weight() * h,
                    span,
                    effort,
                    added,
                    made: how,
                    key,
                    plan: c,
                }),
                None => dead(&c),
            }
        }
        stats.generated += out.len() as u64;
        out
    }

    /// Greedy completion: a depth-first descent from a plan's children (in
    /// [`Scored::probe_order`]) that backtracks, within `budget` expansions
    /// and through plans of at most `max_steps` steps.
    /// A plan it finds has no flaw, like one A* would return.
    /// Stopped by `deadline` when the process exits next (`free` off), the
    /// plans still waiting at every depth are left unfreed, like the open
    /// lists: freeing thousands of plans of a hundred steps took longer
    /// than the margin of the time limit.
    #[allow(clippy::too_many_arguments)]
    fn probe(
        &self,
        first: Vec<Plan>,
        budget: u64,
        max_steps: usize,
        admits: &dyn Fn(f64) -> bool,
        stats: &mut Stats,
        deadline: &dyn Fn() -> bool,
        free: bool,
    ) -> Option<Plan> {
        let mut stack: Vec<Level> = vec![Level { next: first.into_iter(), steps_for: None }];
        let mut spent = 0u64;
        // The children of a level, in the order the descent tries them.
        let order = |mut scored: Vec<Scored>| {
            scored.retain(|c| admits(c.span) && c.plan.steps.len() <= max_steps);
            scored.sort_by(Scored::probe_order);
            scored.into_iter().map(|x| x.plan).collect::<Vec<_>>().into_iter()
        };
        loop {
            let mut p = loop {
                let top = stack.last_mut()?;
                if let Some(n) = top.next.next() {
                    break n;
                }
                // Back at an open link whose causal links all failed: its
                // new steps now (they come after every link in the order).
                if let Some((parent, i)) = top.steps_for.take() {
                    let mut children = Vec::new();
                    self.open_steps(&parent, i, &mut children);
                    top.next = order(self.scored(&parent, children, true, stats, &mut |_| {}));
                    continue;
                }
                stack.pop();
            };
            p.stn.flush();
            p.stn.defer();
            spent += 1;
            stats.expanded += 1;
            stats.largest = stats.largest.max(p.steps.len());
            if spent > budget {
                return None;
            }
            if deadline() {
                if !free {
                    std::mem::forget(stack);
                }
                return None;
            }
            let Some(flaw) = self.select(&mut p) else {
                p.stn.flush();
                return Some(p);
            };
            let level = if let Flaw::Open(i) = flaw {
                let mut children = Vec::new();
                self.open_links(&p, i, &mut children);
                let next = order(self.scored(&p, children, true, stats, &mut |_| {}));
                Level { next, steps_for: Some((p, i)) }
            } else {
                Level { next: order(self.expand(&p, flaw, stats, &mut |_| {})), steps_for: None }
            };
            stack.push(level);
        }
    }

    /// The most steps a greedy descent from a plan may reach: its steps,
    /// plus twice its remaining effort (the estimate of its flaws in
    /// actions, and its threats) and [`PROBE_SPARE_STEPS`]. A descent
    /// always takes the cheapest child first, and when no step already
    /// there can support a link, a new step that needs the same literal
    /// again is often the cheapest (ZenoTravel's `zoom` from a city to
    /// itself: it needs the aircraft there, and its own supporter is one
    /// more such `zoom`): unbounded, the descent went hundreds of steps
    /// down that chain, each expansion slower than the last (hundreds of
    /// threats), and one descent outlasted a 10 s limit.
    fn probe_steps(&self, plan: &Plan) -> usize {
        let (_, effort) = self.estimate(plan);
        plan.steps.len() + 2 * effort.min(1e6) as usize + PROBE_SPARE_STEPS
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
        // Expansions stop making children at the limit only while the
        // search runs: the report of the best partial plan after it, which
        // asks for resolvers too, gets them all, whichever way this returns.
        struct Until<'s>(&'s std::cell::Cell<Option<Instant>>);
        impl Drop for Until<'_> {
            fn drop(&mut self) {
                self.0.set(None);
            }
        }
        self.until.set(limits.time.map(|t| started + t.saturating_sub(limits.time_spent)));
        let _until = Until(&self.until);
        let mut heap = Open::new(self.lanes(limits), !limits.exits_after);
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
                    let f = g + self.weight() * h;
                    let keys = [(f, effort), (self.size_rank(&root, effort), effort)];
                    let entry =
                        Entry { f, span, probed: false, plan: Some(Child::Plan(Box::new(root))).into() };
                    heap.push(entry, keys, size, id);
                }
                None => keep_best(&root, best, &mut best_effort),
            }
        }
        let out_of_time =
            |elapsed: std::time::Duration| limits.time.is_some_and(|t| elapsed + limits.time_spent >= t);
        let time_up = || out_of_time(started.elapsed()) || cancel();
        let mut last_report = Instant::now();
        // The memory is read every 32 expansions (a plan is a few kilobytes
        // to a few hundred), and the search stops when the next 32,
        // growing it as much as the last 32 did, would go over: it ends
        // under the limit, not a few megabytes past it.
        let last_in_use = std::cell::Cell::new(limits.memory_in_use.map_or(0, |f| f()));
        let memory_over = || match (limits.memory, limits.memory_in_use) {
            (Some(m), Some(in_use)) => {
                let now = in_use();
                let next = now.saturating_add(now.saturating_sub(last_in_use.get()));
                last_in_use.set(now);
                next > m
            }
            _ => false,
        };
        // A greedy descent looks at both limits too, at each of its
        // expansions; which one stopped it, for the search to end by it.
        let descended = std::cell::Cell::new(0u64);
        let stopped_descent = std::cell::Cell::new(None);
        let descent_stops = || {
            descended.set(descended.get() + 1);
            if time_up() {
                stopped_descent.set(Some(LimitKind::Time));
            } else if descended.get().is_multiple_of(32) && memory_over() {
                stopped_descent.set(Some(LimitKind::Memory));
            }
            stopped_descent.get().is_some()
        };
        let mut next_milestone: u64 = 1024;
        // The best plan found and its cost, when the search goes on.
        let mut incumbent: Option<(Plan, Quality)> = None;
        // A plan found: returned when it is the first and `first` is set;
        // else kept when better than the best, and `None` asks to go on.
        let found = |plan: Plan,
                     stats: &mut Stats,
                     incumbent: &mut Option<(Plan, Quality)>,
                     heap: &mut Open,
                     progress: &mut dyn FnMut(&Progress)|
         -> Option<End2> {
            let open = heap.len();
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
            heap.makespan_only();
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
            if heap.active < heap.lanes.len() && stats.expanded >= SIZE_LANE_AFTER {
                heap.active = heap.lanes.len();
            }
            let Some((node, child)) = heap.pop() else { break End2::Exhausted };
            let known = incumbent.as_ref().map(|(_, q)| *q).or(limits.better_than);
            let admits = |makespan: f64| known.is_none_or(|k| k.admits(makespan));
            if !admits(node.span) {
                // Found since it entered the open list: cannot do better.
                continue;
            }
            let mut plan = match child {
                Child::Plan(plan) => *plan,
                Child::Made(parent, made) => match self.remade(&parent, made) {
                    Some(plan) => plan,
                    None => continue,
                },
            };
            plan.stn.flush();
            plan.stn.defer();
            stats.expanded += 1;
            stats.open = heap.len();
            stats.peak_open = stats.peak_open.max(heap.len());
            stats.largest = stats.largest.max(plan.steps.len());
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
                (Some(_), Some(_)) => stats.expanded.is_multiple_of(32) && memory_over(),
                (Some(m), None) => heap.len().saturating_mul(approx_plan_bytes(&plan)) > m,
                (None, _) => false,
            };
            if over {
                stats.elapsed = started.elapsed();
                break End2::Limit(LimitKind::Memory);
            }
            let Some(flaw) = self.select(&mut plan) else {
                plan.stn.flush();
                match found(plan, stats, &mut incumbent, &mut heap, progress) {
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
                let max_steps = self.probe_steps(&plan);
                let mut first: Vec<&Scored> = scored.iter().collect();
                first.sort_by(|a, b| Scored::probe_order(a, b));
                let first = first.into_iter().map(|s| s.plan.clone()).collect();
                let descent =
                    self.probe(first, budget, max_steps, &admits, stats, &descent_stops, !limits.exits_after);
                if let Some(plan) = descent
                    && let Some(end) = found(plan, stats, &mut incumbent, &mut heap, progress)
                {
                    return end;
                }
                if stopped_descent.get() == Some(LimitKind::Memory) {
                    stats.elapsed = started.elapsed();
                    break End2::Limit(LimitKind::Memory);
                }
            }
            // The children of an open link or an abstract flaw are kept as
            // their parent and how each was made ([`Child`]).
            let parent = scored.iter().any(|c| c.made.is_some()).then(|| Rc::new(plan));
            for c in scored {
                if let Some(key) = c.key
                    && !self.front_record_key(key, c.span)
                {
                    continue;
                }
                id += 1;
                let size = c.plan.steps.len();
                let keys = [(c.f, c.effort), (self.size_rank(&c.plan, c.effort), c.effort)];
                let child = match (&parent, c.made) {
                    (Some(parent), Some(made)) => Child::Made(Rc::clone(parent), made),
                    _ => Child::Plan(Box::new(c.plan)),
                };
                let entry = Entry { f: c.f, span: c.span, probed, plan: Some(child).into() };
                heap.push(entry, keys, size, id);
            }
        };
        stats.elapsed = started.elapsed();
        if matches!(end, End2::Exhausted) && incumbent.is_none() {
            stats.loops_skipped = self.loops.get();
        }
        settle_end(end, incumbent, stats)
    }
}

/// A level of a greedy descent ([`Search::probe`]): the children left to
/// try, in order, and, for an open link, the plan and the link whose new
/// steps come after them. The descent tries causal links to the steps
/// already there first and mostly goes down one of them: the new steps
/// (a ZenoTravel fuel level has a hundred achievers, a flight between
/// every two cities) are only made and scored when it comes back to the
/// level, in the same order as before.
struct Level {
    next: std::vec::IntoIter<Plan>,
    steps_for: Option<(Plan, usize)>,
}

/// A child plan with its score.
struct Scored {
    f: f64,
    span: f64,
    effort: f64,
    /// Steps it added for an open link.
    added: usize,
    /// How it was made, for an open link or an abstract flaw
    /// ([`Child::Made`]).
    made: Option<Made>,
    /// Grown from its front: its key ([`Search::front_key`]).
    key: Option<Box<[u32]>>,
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

/// Test support for the unit tests of this module's files.
#[cfg(test)]
mod test_support {
    use super::super::plan::Plan;
    use super::super::{Prepared, prepare};
    use super::{Config, Flaw, PlannerLimits, Search};

    /// The child of the first plan whose first abstract step (the problem's
    /// one `:htn` task) is refined by the method named `method`.
    pub(super) fn refined_by(prepared: &Prepared<'_>, search: &Search<'_, '_>, method: &str) -> Plan {
        let task = &prepared.task;
        let roots = search.initial();
        assert_eq!(roots.len(), 1);
        let mut children = Vec::new();
        search.resolvers(&roots[0], Flaw::Abstract(0), &mut children);
        let name = |p: &Plan| {
            p.steps.iter().find_map(|s| s.method).map(|m| task.methods[m as usize].name.to_string())
        };
        children.into_iter().find(|c| name(c).as_deref() == Some(method)).expect("refined")
    }

    /// Prepares the problem `problem` of the domain `domain`
    /// (files named by `names`) and runs `f` on it with a search of it under
    /// the default configuration.
    pub(super) fn with_search<T>(
        names: (&str, &str),
        domain: &str,
        problem: &str,
        f: impl FnOnce(&Prepared<'_>, &Search<'_, '_>) -> T + std::panic::UnwindSafe,
    ) -> T {
        with_search_as(Config::default(), names, domain, problem, f)
    }

    /// [`with_search`] under configuration `config`.
    pub(super) fn with_search_as<T>(
        config: Config,
        names: (&str, &str),
        domain: &str,
        problem: &str,
        f: impl FnOnce(&Prepared<'_>, &Search<'_, '_>) -> T + std::panic::UnwindSafe,
    ) -> T {
        let mut host = crate::AnalysisHost::new();
        host.set_file_text(names.0, domain);
        let pf = host.set_file_text(names.1, problem);
        host.analysis()
            .with_db(|db| {
                let unit = crate::host::first_problem(db, pf).expect("a problem");
                let prepared = prepare(db, unit, &config, &PlannerLimits::default()).ok().expect("prepared");
                let search = Search::new(&prepared.task, &prepared.h, &config);
                f(&prepared, &search)
            })
            .expect("not cancelled")
    }
}
