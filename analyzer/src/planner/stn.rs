//! The simple temporal network of a partial plan (Dechter et al.), kept as
//! the least solution of its constraints plus a qualitative closure.
//!
//! - Constraints are `t_b ≥ t_a + w` (an edge `a → b` of weight `w`): an
//!   ordering with a separation (`w = ε`), a duration (`t_end ≥ t_start + d`
//!   and `t_start ≥ t_end − d`), a release date (`t_a ≥ t_0 + r`), a deadline
//!   (`t_0 ≥ t_a − d`).
//! - `est` is the earliest-start schedule: the least solution with every time
//!   point at or after the origin. Adding an edge raises `est` along the
//!   edges out of its head (a queue-based Bellman–Ford restricted to what
//!   changes). The network was consistent before, so a new inconsistency is a
//!   positive cycle through the new edge: the propagation comes back to raise
//!   its tail, or raises the origin (a deadline missed). Either refuses the
//!   edge. The makespan of a plan is the latest `est` of its steps.
//! - `pred` is the transitive closure of the edges of positive weight, one
//!   bit row per time point: `a ∈ pred[b]` means `t_b > t_a` in every
//!   solution. It answers "can this step come between these two?" (threats,
//!   Definitions 8, 11, 13) in one bit test. It misses orderings that only
//!   durations or deadlines imply, which can only make the planner see a
//!   threat that is not one: both resolvers are tried, and the STN keeps the
//!   one that holds.
//!
//! Every row and every adjacency list is shared with the parent plan until
//! written ([`PVec`] and `Rc`).

use std::cmp::Reverse;
use std::collections::VecDeque;
use std::rc::Rc;

use super::pvec::PVec;

/// The separation of dependent happenings, as VAL's default tolerance asks.
pub const EPS: f64 = 0.01;
/// Below this, a change of an earliest time is rounding noise.
const NOISE: f64 = 1e-9;

pub type Tp = u32;
pub const ORIGIN: Tp = 0;

/// The slacks of many points towards one target ([`Stn::slack_to`]), for
/// a caller that asks for several: each answer is kept (a slack found, or
/// a bound it is not below), and the searches share their arrays.
pub struct Slacks<'a> {
    stn: &'a Stn,
    target: Tp,
    /// Per point asked: the slack, or `INFINITY` with the bound it is at
    /// least.
    known: rustc_hash::FxHashMap<Tp, (f64, f64)>,
    dist: Vec<f64>,
    /// The search that last set `dist` (and `done`) of each point.
    seen: Vec<u32>,
    done: Vec<u32>,
    search: u32,
    heap: std::collections::BinaryHeap<Reverse<Key>>,
    /// Points settled by the searches so far; past twice the network's
    /// size, [`Slacks::all`] replaces them.
    settled: usize,
    /// Every point's slack, from one search backwards from the target.
    all: Option<Vec<f64>>,
}

impl<'a> Slacks<'a> {
    pub fn new(stn: &'a Stn, target: Tp) -> Slacks<'a> {
        Slacks {
            stn,
            target,
            known: rustc_hash::FxHashMap::default(),
            dist: Vec::new(),
            seen: Vec::new(),
            done: Vec::new(),
            search: 0,
            heap: std::collections::BinaryHeap::new(),
            settled: 0,
            all: None,
        }
    }

    /// [`Stn::slack_to`] of `from` towards the target, below `bound`.
    pub fn slack(&mut self, from: Tp, bound: f64) -> f64 {
        let n = self.stn.len();
        if from as usize >= n || self.target as usize >= n || bound <= 0.0 {
            return f64::INFINITY;
        }
        let below = |slack: f64| if slack < bound { slack } else { f64::INFINITY };
        if let Some(all) = &self.all {
            return below(all[from as usize]);
        }
        match self.known.get(&from) {
            Some(&(slack, _)) if slack.is_finite() => return below(slack),
            Some(&(_, at_least)) if bound <= at_least => return f64::INFINITY,
            _ => {}
        }
        if self.settled > 2 * n {
            let all = self.backwards();
            let slack = all[from as usize];
            self.all = Some(all);
            return below(slack);
        }
        let slack = self.search(from, bound);
        self.known.insert(from, (slack, bound));
        slack
    }

    fn search(&mut self, from: Tp, bound: f64) -> f64 {
        self.search += 1;
        let (stn, target, search) = (self.stn, self.target, self.search);
        if self.dist.is_empty() {
            let n = stn.len();
            (self.dist, self.seen, self.done) = (vec![0.0; n], vec![0; n], vec![0; n]);
        }
        self.heap.clear();
        self.dist[from as usize] = 0.0;
        self.seen[from as usize] = search;
        self.heap.push(Reverse(Key(0.0, from)));
        while let Some(Reverse(Key(d, x))) = self.heap.pop() {
            if d >= bound {
                return f64::INFINITY;
            }
            if x == target {
                return d;
            }
            if self.done[x as usize] == search {
                continue;
            }
            self.done[x as usize] = search;
            self.settled += 1;
            let ex = stn.est(x);
            for e in stn.edges(x) {
                let y = e.to as usize;
                if self.done[y] == search {
                    continue;
                }
                let nd = d + (stn.est(e.to) - ex - e.w).max(0.0);
                if self.seen[y] != search || nd < self.dist[y] {
                    self.seen[y] = search;
                    self.dist[y] = nd;
                    self.heap.push(Reverse(Key(nd, e.to)));
                }
            }
        }
        f64::INFINITY
    }

    /// Every point's slack towards the target: Dijkstra's search from the
    /// target along the edges backwards (the slacks of edges are never
    /// negative). `INFINITY` for a point that does not precede it.
    fn backwards(&mut self) -> Vec<f64> {
        let stn = self.stn;
        let n = stn.len();
        let mut into: Vec<Vec<(Tp, f64)>> = vec![Vec::new(); n];
        for x in 0..n as Tp {
            let ex = stn.est(x);
            for e in stn.edges(x) {
                into[e.to as usize].push((x, (stn.est(e.to) - ex - e.w).max(0.0)));
            }
        }
        let mut slack = vec![f64::INFINITY; n];
        let mut done = vec![false; n];
        slack[self.target as usize] = 0.0;
        self.heap.clear();
        self.heap.push(Reverse(Key(0.0, self.target)));
        while let Some(Reverse(Key(d, y))) = self.heap.pop() {
            if std::mem::replace(&mut done[y as usize], true) {
                continue;
            }
            for &(x, w) in &into[y as usize] {
                let nd = w + d;
                if !done[x as usize] && nd < slack[x as usize] {
                    slack[x as usize] = nd;
                    self.heap.push(Reverse(Key(nd, x)));
                }
            }
        }
        slack
    }
}

/// A slack and its point, ordered by slack (a total order on floats), for
/// the heap of [`Stn::slack_to`].
#[derive(Clone, Copy, PartialEq)]
struct Key(f64, Tp);

impl Eq for Key {}

impl PartialOrd for Key {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Key {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0).then(self.1.cmp(&other.1))
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    pub to: Tp,
    pub w: f64,
}

#[derive(Clone, Debug)]
pub struct Stn {
    est: PVec<f64>,
    out: PVec<Rc<Vec<Edge>>>,
    pred: PVec<Rc<Vec<u64>>>,
    /// Orderings of the closure not yet in its rows, in the order they
    /// came ([`Stn::flush`]); [`Stn::before`] takes them into account.
    pending: Vec<(Tp, Tp)>,
    /// Whether new orderings wait ([`Stn::defer`]).
    deferring: bool,
}

/// At most this many orderings wait for the closure's rows
/// ([`Stn::before`] takes a time quadratic in their number).
const PENDING: usize = 8;

impl Default for Stn {
    fn default() -> Self {
        Stn::new()
    }
}

impl Stn {
    /// A network with the origin only.
    pub fn new() -> Stn {
        let mut s = Stn {
            est: PVec::new(),
            out: PVec::new(),
            pred: PVec::new(),
            pending: Vec::new(),
            deferring: false,
        };
        s.add_point();
        s
    }

    pub fn len(&self) -> usize {
        self.est.len()
    }

    pub fn is_empty(&self) -> bool {
        self.est.is_empty()
    }

    /// A new time point, at or after the origin.
    pub fn add_point(&mut self) -> Tp {
        let t = self.est.len() as Tp;
        self.est.push(0.0);
        self.out.push(Rc::new(Vec::new()));
        self.pred.push(Rc::new(Vec::new()));
        t
    }

    pub fn est(&self, t: Tp) -> f64 {
        self.est.get(t as usize).copied().unwrap_or(0.0)
    }

    /// The edges out of a time point.
    pub fn edges(&self, t: Tp) -> &[Edge] {
        self.out.get(t as usize).map_or(&[], |v| v.as_slice())
    }

    /// Whether `b` is at or after `a` in every solution (by the closure):
    /// by the rows, or by a path through the orderings not in them yet.
    #[inline]
    pub fn before(&self, a: Tp, b: Tp) -> bool {
        self.in_row(a, b) || (!self.pending.is_empty() && self.before_by_pending(a, b))
    }

    /// [`Stn::before`] by a path through the orderings that wait (at most
    /// [`PENDING`]: the orderings reached are a bit set, no allocation).
    #[inline(never)]
    fn before_by_pending(&self, a: Tp, b: Tp) -> bool {
        let p = &self.pending;
        // `x` at or before `y` by the rows.
        let upto = |x: Tp, y: Tp| x == y || self.in_row(x, y);
        let mut seen = 0u32;
        for (i, &(from, _)) in p.iter().enumerate() {
            if upto(a, from) {
                seen |= 1 << i;
            }
        }
        let mut todo = seen;
        while todo != 0 {
            let i = todo.trailing_zeros() as usize;
            todo &= todo - 1;
            let to = p[i].1;
            if upto(to, b) {
                return true;
            }
            for (j, &(from, _)) in p.iter().enumerate() {
                if seen >> j & 1 == 0 && upto(to, from) {
                    seen |= 1 << j;
                    todo |= 1 << j;
                }
            }
        }
        false
    }

    /// The closure's row of `b`: bit `a` is set when `b` is after `a` in
    /// every solution ([`Stn::before`] of a whole row, for a caller that
    /// asks about many points before `b`). No ordering may wait
    /// ([`Stn::flush`]).
    pub fn predecessors(&self, b: Tp) -> &[u64] {
        debug_assert!(self.pending.is_empty(), "orderings wait for the closure's rows");
        self.pred.get(b as usize).map_or(&[], |r| r.as_slice())
    }

    /// The points before `b` in every solution, the orderings that wait
    /// included: bit `a` of `out` is set when [`Stn::before`]`(a, b)` (a
    /// whole row at once, for a caller that asks about many points).
    pub fn preceding(&self, b: Tp, out: &mut Vec<u64>) {
        out.clear();
        out.resize(self.len().div_ceil(64), 0);
        let add_row = |out: &mut Vec<u64>, x: Tp| {
            if let Some(row) = self.pred.get(x as usize) {
                for (o, w) in out.iter_mut().zip(row.iter()) {
                    *o |= w;
                }
            }
        };
        add_row(out, b);
        let p = &self.pending;
        if p.is_empty() {
            return;
        }
        // The orderings that wait on a path to `b`: backwards from `b`, as
        // [`Stn::before_by_pending`] goes forwards.
        let upto = |x: Tp, y: Tp| x == y || self.in_row(x, y);
        let mut reached = 0u32;
        for (i, &(_, to)) in p.iter().enumerate() {
            if upto(to, b) {
                reached |= 1 << i;
            }
        }
        let mut todo = reached;
        while todo != 0 {
            let i = todo.trailing_zeros() as usize;
            todo &= todo - 1;
            let from = p[i].0;
            for (j, &(_, to)) in p.iter().enumerate() {
                if reached >> j & 1 == 0 && upto(to, from) {
                    reached |= 1 << j;
                    todo |= 1 << j;
                }
            }
        }
        while reached != 0 {
            let i = reached.trailing_zeros() as usize;
            reached &= reached - 1;
            let from = p[i].0;
            add_row(out, from);
            if let Some(w) = out.get_mut(from as usize / 64) {
                *w |= 1 << (from % 64);
            }
        }
    }

    /// Whether the closure's row of `b` holds `a`.
    #[inline]
    fn in_row(&self, a: Tp, b: Tp) -> bool {
        self.pred
            .get(b as usize)
            .and_then(|row| row.get(a as usize / 64))
            .is_some_and(|w| w >> (a % 64) & 1 == 1)
    }

    /// From now on, and in the clones made from now on, an ordering into
    /// points with successors waits apart from the closure's rows until
    /// [`Stn::flush`]. The search defers the orderings of the children of
    /// a plan it expands, and writes them when it expands a child: most
    /// children are never expanded, and in a plan holding every step of an
    /// old plan (a repair), the rows an ordering changes are those of
    /// every point after it. (Elsewhere, as when a start plan is built,
    /// [`Stn::before`] would pay for the orderings that wait.)
    pub fn defer(&mut self) {
        self.deferring = true;
    }

    /// Writes the orderings that wait into the closure's rows, and stops
    /// deferring.
    pub fn flush(&mut self) {
        self.deferring = false;
        for (a, b) in std::mem::take(&mut self.pending) {
            self.close_rows(a, b);
        }
    }

    /// Whether `t_b ≥ t_a + w` already holds in the closure's sense: `b` is
    /// after `a` (only meaningful for `w ≤ ε`).
    pub fn implied(&self, a: Tp, b: Tp, w: f64) -> bool {
        w <= EPS && self.before(a, b) && self.est(b) >= self.est(a) + w - NOISE
    }

    /// Adds `t_b ≥ t_a + w`. `false` when the network becomes inconsistent
    /// (the caller drops it).
    pub fn add(&mut self, a: Tp, b: Tp, w: f64) -> bool {
        if a as usize >= self.len() || b as usize >= self.len() || !w.is_finite() {
            return false;
        }
        if a == b {
            return w <= 0.0;
        }
        {
            let out = Rc::make_mut(self.out.get_mut(a as usize).expect("in bounds"));
            match out.iter_mut().find(|e| e.to == b) {
                Some(e) if e.w >= w => {}
                Some(e) => e.w = w,
                None => out.push(Edge { to: b, w }),
            }
        }
        // The earliest times first: an ordering that makes the network
        // inconsistent is found there, and its plan dropped, before the
        // closure's rows are updated (in a repair, a third of the time
        // that updates took went to such orderings). Propagation needs no
        // closure that holds the new ordering: it takes the raised points
        // by their number of predecessors, and among points after `b` the
        // ordering changes neither which precedes which nor that order.
        if !self.propagate(a, b, w) {
            return false;
        }
        if w >= 0.0 {
            self.close(a, b);
        }
        true
    }

    /// Whether `t_b ≥ t_a + w` can be added and keep the network
    /// consistent: [`Stn::add`]'s propagation as a dry run, which changes
    /// nothing (no copy of the network, no closure update).
    pub fn allows(&self, a: Tp, b: Tp, w: f64) -> bool {
        if a as usize >= self.len() || b as usize >= self.len() || !w.is_finite() {
            return false;
        }
        if a == b {
            return w <= 0.0;
        }
        let start = self.est(a) + w;
        if start <= self.est(b) + NOISE {
            return true;
        }
        if b == ORIGIN {
            return false;
        }
        let mut raised: rustc_hash::FxHashMap<Tp, f64> = rustc_hash::FxHashMap::default();
        raised.insert(b, start);
        let mut queue = VecDeque::from([b]);
        let mut budget = 64 * (self.len() + 16) * (self.len() + 16);
        while let Some(x) = queue.pop_front() {
            let tx = raised[&x];
            for e in self.edges(x) {
                let t = tx + e.w;
                let cur = raised.get(&e.to).copied().unwrap_or_else(|| self.est(e.to));
                if t > cur + NOISE {
                    if e.to == a || e.to == ORIGIN {
                        return false;
                    }
                    raised.insert(e.to, t);
                    queue.push_back(e.to);
                }
                budget = budget.saturating_sub(1);
                if budget == 0 {
                    return false;
                }
            }
        }
        true
    }

    fn propagate(&mut self, a: Tp, b: Tp, w: f64) -> bool {
        let start = self.est(a) + w;
        if start <= self.est(b) + NOISE {
            return true;
        }
        if b == ORIGIN {
            return false;
        }
        self.est.set(b as usize, start);
        // In the closure's order: a point has more predecessors than any
        // point before it, so taking the raised points by their number of
        // predecessors takes a point after every raised point before it,
        // and raises it once (in first-in-first-out order, a repair that
        // inserts a step early in a plan of 1,200 points processed 17.9
        // million points to raise 1.2 million).
        // `b` first (every raised point is after it); the heap and the set
        // of points in it are only allocated when `b` raises another.
        let rank = |s: &Stn, x: Tp| -> u32 { s.pred[x as usize].iter().map(|w| w.count_ones()).sum() };
        let mut heap = std::collections::BinaryHeap::new();
        let mut queued = rustc_hash::FxHashSet::default();
        let mut budget = 64 * (self.len() + 16) * (self.len() + 16);
        let mut first = Some(b);
        while let Some(x) = first.take().or_else(|| heap.pop().map(|Reverse((_, x))| x)) {
            queued.remove(&x);
            let tx = self.est(x);
            let out = Rc::clone(&self.out[x as usize]);
            for e in out.iter() {
                let t = tx + e.w;
                if t > self.est(e.to) + NOISE {
                    if e.to == a || e.to == ORIGIN {
                        return false;
                    }
                    self.est.set(e.to as usize, t);
                    if queued.insert(e.to) {
                        heap.push(Reverse((rank(self, e.to), e.to)));
                    }
                }
                budget = budget.saturating_sub(1);
                if budget == 0 {
                    return false;
                }
            }
        }
        true
    }

    /// The slack of `from` towards `target`: how much later than its
    /// earliest time `from` can be without delaying `target`; `INFINITY`
    /// when it is `bound` or more, or `from` does not precede `target`.
    /// Adding `t_b ≥ t_a + w` delays `target` by at least
    /// `est(a) + w − est(b) − slack(b)` (exactly, when only lower bounds lie
    /// between `b` and `target`). With the earliest times as potentials,
    /// the slack of an edge `x → y`, `est(y) − est(x) − w`, is never
    /// negative (up to rounding), and `slack(from)` is the least total
    /// slack of a path to `target`: a Dijkstra search forwards, which
    /// reaches only the points after `from` whose detour is below the
    /// bound (few, for a point late in the plan, where new steps go).
    pub fn slack_to(&self, from: Tp, target: Tp, bound: f64) -> f64 {
        Slacks::new(self, target).slack(from, bound)
    }

    /// Every point's slack towards `target` ([`Stn::slack_to`] of each, with
    /// no bound), from one search backwards from it.
    pub fn slacks_to(&self, target: Tp) -> Vec<f64> {
        if target as usize >= self.len() {
            return vec![f64::INFINITY; self.len()];
        }
        Slacks::new(self, target).backwards()
    }

    /// Adds `a < b` to the closure: every point at or after `b` gets `a`
    /// and what precedes `a`. (Rows of predecessors: new steps mostly come
    /// after the plan's others, and a point late in the plan has few
    /// successors to update, where it has many predecessors.)
    fn close(&mut self, a: Tp, b: Tp) {
        if self.before(a, b) {
            return;
        }
        // Nothing after `b` yet (a new step's own points): its row alone
        // changes, and it is the child's.
        if !self.deferring || self.edges(b).iter().all(|e| e.w < 0.0) {
            self.close_rows(a, b);
            return;
        }
        self.pending.push((a, b));
        if self.pending.len() >= PENDING {
            self.flush();
        }
    }

    /// [`Stn::close`] in the rows (no ordering waits).
    fn close_rows(&mut self, a: Tp, b: Tp) {
        if self.in_row(a, b) {
            return;
        }
        let mut add: Vec<u64> = self.pred[a as usize].as_ref().clone();
        let (word, bit) = (a as usize / 64, a % 64);
        if add.len() <= word {
            add.resize(word + 1, 0);
        }
        add[word] |= 1 << bit;
        // `b` and the points after it that do not follow `a` yet: a walk
        // along the edges of non-negative weight (the closure is theirs)
        // from `b`, which stops at a point after `a` (the points after it
        // are too, with what precedes `a`). Few points for an ordering late
        // in the plan, where a scan of every point would cost the network;
        // a point updated is after `a`, so none is updated twice.
        let mut stack = vec![b];
        while let Some(y) = stack.pop() {
            if self.in_row(a, y) {
                continue;
            }
            let row = Rc::make_mut(self.pred.get_mut(y as usize).expect("in bounds"));
            if row.len() < add.len() {
                row.resize(add.len(), 0);
            }
            for (r, w) in row.iter_mut().zip(&add) {
                *r |= w;
            }
            stack.extend(self.edges(y).iter().filter(|e| e.w >= 0.0).map(|e| e.to));
        }
    }

    /// The latest times within `horizon` (every point at or before it): the
    /// greatest solution, `None` where the network does not bound a point
    /// below the horizon... never: every point is bounded by the horizon.
    pub fn latest(&self, horizon: f64) -> Vec<f64> {
        let n = self.len();
        let mut lst = vec![horizon; n];
        lst[ORIGIN as usize] = 0.0;
        // t_b ≥ t_a + w  ⇒  t_a ≤ t_b − w.
        let mut changed = true;
        let mut rounds = 0;
        while changed && rounds <= n + 1 {
            changed = false;
            rounds += 1;
            for a in 0..n {
                for e in self.edges(a as Tp) {
                    let t = lst[e.to as usize] - e.w;
                    if t < lst[a] - NOISE && a != ORIGIN as usize {
                        lst[a] = t;
                        changed = true;
                    }
                }
            }
        }
        lst
    }

    /// Words of closure rows and adjacency entries that this network owns
    /// alone (not shared with another plan): for memory measurements.
    pub fn footprint(&self) -> usize {
        self.len() * 3
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orderings_raise_earliest_times_and_cycles_are_refused() {
        let mut s = Stn::new();
        let (a, b, c) = (s.add_point(), s.add_point(), s.add_point());
        assert!(s.add(a, b, 5.0));
        assert!(s.add(b, c, 1.0));
        assert_eq!(s.est(c), 6.0);
        assert!(s.before(a, c));
        assert!(!s.before(c, a));
        // c ≤ a + 3 contradicts c ≥ a + 6.
        let mut t = s.clone();
        assert!(!t.add(c, a, -3.0));
        // c ≤ a + 7 is fine; the parent is untouched by the child's edges.
        assert!(s.clone().add(c, a, -7.0));
        assert_eq!(s.edges(c).len(), 0);
    }

    #[test]
    fn deadlines_are_checked_against_the_origin() {
        let mut s = Stn::new();
        let a = s.add_point();
        let b = s.add_point();
        assert!(s.add(a, b, 10.0));
        // b ≤ 8 is impossible.
        assert!(!s.clone().add(b, ORIGIN, -8.0));
        assert!(s.add(b, ORIGIN, -12.0));
        // a released at 3 makes b 13 > 12.
        assert!(!s.clone().add(ORIGIN, a, 3.0));
        assert!(s.add(ORIGIN, a, 1.5));
        assert_eq!(s.est(b), 11.5);
        // b must stay at 11.5 for itself: a may not slip; a point after a
        // by 1 with nothing after it may slip to the horizon.
        let slack = |s: &Stn, t: Tp, target: Tp| s.slack_to(t, target, f64::INFINITY);
        assert_eq!(slack(&s, a, b), 0.0);
        assert_eq!(slack(&s, b, b), 0.0);
        let c = s.add_point();
        assert!(s.add(a, c, 1.0));
        assert_eq!(slack(&s, c, b), f64::INFINITY);
        let d = s.add_point();
        assert!(s.add(d, b, 4.0));
        assert!(s.add(ORIGIN, d, 1.0));
        assert_eq!(s.est(d), 1.0);
        assert_eq!(slack(&s, d, b), 6.5);
        // Below a bound only.
        assert_eq!(s.slack_to(d, b, 6.5), f64::INFINITY);
        assert_eq!(s.slack_to(d, b, 7.0), 6.5);
        let lst = s.latest(20.0);
        assert_eq!(lst[b as usize], 12.0);
        assert_eq!(lst[a as usize], 2.0);
    }

    /// A small deterministic generator: `next(m)` is below `m`.
    fn below(mut seed: u64) -> impl FnMut(u64) -> u64 {
        move |m: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % m
        }
    }

    /// The closure is reachability along the edges of non-negative
    /// weight, after every change of random networks (constraints that
    /// fail leave the network as it was: the clone is dropped), with
    /// orderings waiting for the rows and written at random times.
    #[test]
    fn the_closure_is_reachability_along_non_negative_edges() {
        let mut next = below(0x2545_f491_4f6c_dd1d);
        for _ in 0..300 {
            let mut s = Stn::new();
            if next(4) != 0 {
                s.defer();
            }
            let n = 2 + next(25) as usize;
            let pts: Vec<Tp> = (0..n).map(|_| s.add_point()).collect();
            for _ in 0..next(50) {
                let (a, b) = (pts[next(n as u64) as usize], pts[next(n as u64) as usize]);
                let w = match next(3) {
                    0 => EPS,
                    1 => next(20) as f64,
                    _ => -(next(20) as f64),
                };
                let mut t = s.clone();
                if t.add(a, b, w) {
                    s = t;
                }
                // The search writes a plan's waiting orderings when it
                // expands it: at any time, and a network is cloned after.
                if next(4) == 0 {
                    s.flush();
                }
                for x in 0..s.len() as Tp {
                    let mut reach = vec![false; s.len()];
                    let mut stack = vec![x];
                    while let Some(y) = stack.pop() {
                        for e in s.edges(y) {
                            if e.w >= 0.0 && !std::mem::replace(&mut reach[e.to as usize], true) {
                                stack.push(e.to);
                            }
                        }
                    }
                    for y in 0..s.len() as Tp {
                        if y != x {
                            assert_eq!(s.before(x, y), reach[y as usize], "{x} before {y}");
                            if s.pending.is_empty() {
                                assert_eq!(s.in_row(x, y), reach[y as usize], "{x} before {y} in the rows");
                            }
                        }
                    }
                }
            }
        }
    }

    /// `slack_to` against the definition, by rounds of relaxation over
    /// every edge, on random consistent networks (orderings, durations both
    /// ways, release dates and deadlines).
    #[test]
    fn slacks_agree_with_relaxation_to_a_fixpoint() {
        let mut backwards = 0;
        let mut next = below(0x9e37_79b9_7f4a_7c15);
        for _ in 0..400 {
            let mut s = Stn::new();
            let n = 2 + next(30) as usize;
            let pts: Vec<Tp> = (0..n).map(|_| s.add_point()).collect();
            let sink = pts[next(n as u64) as usize];
            for _ in 0..next(60) {
                let (a, b) = (pts[next(n as u64) as usize], pts[next(n as u64) as usize]);
                let w = match next(4) {
                    0 => EPS,
                    1 => next(50) as f64,
                    2 => -(next(50) as f64),
                    _ => 0.0,
                };
                let mut t = s.clone();
                if t.add(a, b, w) {
                    s = t;
                }
                if next(8) == 0 {
                    let d = next(200) as f64;
                    let mut t = s.clone();
                    if t.add(a, ORIGIN, -d) {
                        s = t;
                    }
                }
            }
            let mut want = vec![f64::INFINITY; s.len()];
            want[sink as usize] = s.est(sink);
            for _ in 0..=s.len() {
                for a in 0..s.len() {
                    for e in s.edges(a as Tp) {
                        let t = want[e.to as usize] - e.w;
                        if t < want[a] {
                            want[a] = t;
                        }
                    }
                }
            }
            let got: Vec<f64> = (0..s.len() as Tp).map(|t| s.slack_to(t, sink, f64::INFINITY)).collect();
            for (t, w) in want.iter().enumerate() {
                let slack = w - s.est(t as Tp);
                assert!(
                    got[t] == slack || (got[t] - slack).abs() < 1e-6,
                    "slack of {t} = {} but relaxation gives {slack} (target {sink})",
                    got[t]
                );
            }
            // An answer below `bound` for point `t`: its slack if less
            // than the bound, else infinity (either, at the bound itself).
            let agrees = |t: Tp, bound: f64, answer: f64| {
                let slack = got[t as usize];
                let expected = if slack < bound { slack } else { f64::INFINITY };
                (slack - bound).abs() < 1e-6 || answer == expected || (answer - expected).abs() < 1e-6
            };
            // Forwards, below a bound.
            for t in 0..s.len() as Tp {
                let bound = if next(4) == 0 { f64::INFINITY } else { next(40) as f64 };
                let fwd = s.slack_to(t, sink, bound);
                assert!(
                    agrees(t, bound, fwd),
                    "slack_to({t}, {sink}, {bound}) = {fwd}, slack {}",
                    got[t as usize]
                );
            }
            // Many questions to one `Slacks`: answers kept, then every
            // slack at once backwards once the searches settled enough.
            let mut shared = Slacks::new(&s, sink);
            for round in 0..4 {
                for t in 0..s.len() as Tp {
                    let bound = if next(4) == 0 { f64::INFINITY } else { next(40) as f64 };
                    let answer = shared.slack(t, bound);
                    assert!(
                        agrees(t, bound, answer),
                        "round {round}: Slacks::slack({t}, {bound}) = {answer}, slack {} (target {sink})",
                        got[t as usize]
                    );
                }
            }
            backwards += usize::from(shared.all.is_some());
        }
        assert!(backwards > 0, "no network asked enough for every slack at once");
    }
}
