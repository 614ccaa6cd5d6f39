//! The old plan's order (phantom links, section 5.1.2 of the HiPOP paper):
//! the orderings between the time points of the old plan's steps, kept
//! through the steps removed since. Stored as the covering relation of the
//! order (its transitive reduction): the order between the steps still in
//! is reachability through it, whatever was removed. Keeping every ordered
//! pair instead takes the square of the plan's size (400,000 pairs for a
//! plan of 640 steps).

use crate::planner::search::SeedOrder;
use crate::planner::task::End;

/// The covering relation of the old plan's order.
#[derive(Debug, Clone, Default)]
pub struct OldOrder {
    /// Each time point: its old step and which end.
    points: Vec<(usize, End)>,
    /// The time points just after each one (no other point in between).
    next: Vec<Vec<u32>>,
}

impl OldOrder {
    /// The order of `points`: `before(j)` gives the points `i` that point
    /// `j` is at or after in every schedule (`i != j`); `time(i)` a time
    /// that puts them in an order compatible with it (the earliest
    /// schedule's).
    pub fn new(
        points: Vec<(usize, End)>,
        before: impl Fn(usize) -> Vec<usize>,
        time: impl Fn(usize) -> f64,
    ) -> OldOrder {
        let n = points.len();
        let words = n.div_ceil(64);
        // Rows and sets by rank in time order: the successors of a point,
        // in that order, are its set bits from the lowest.
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| time(a).total_cmp(&time(b)).then(a.cmp(&b)));
        let mut rank = vec![0; n];
        for (r, &i) in order.iter().enumerate() {
            rank[i] = r;
        }
        let mut rows = vec![0u64; n * words];
        for (rj, &j) in order.iter().enumerate() {
            for i in before(j) {
                if i != j {
                    rows[rank[i] * words + rj / 64] |= 1 << (rj % 64);
                }
            }
        }
        let mut next: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut covered = vec![0u64; words];
        for (ri, &i) in order.iter().enumerate() {
            covered.fill(0);
            // The successors in time order: one not after an earlier one
            // taken is just after `i`.
            for w in 0..words {
                let mut from = 0u64;
                loop {
                    let bits = rows[ri * words + w] & !covered[w] & !from;
                    if bits == 0 {
                        break;
                    }
                    let b = bits.trailing_zeros();
                    let rj = w * 64 + b as usize;
                    next[i].push(order[rj] as u32);
                    for (c, r) in covered.iter_mut().zip(&rows[rj * words..(rj + 1) * words]) {
                        *c |= r;
                    }
                    // This bit and those below it are done.
                    from = if b == 63 { u64::MAX } else { (2u64 << b) - 1 };
                }
            }
        }
        OldOrder { points, next }
    }

    /// The orderings to keep between the seed's steps: `index[step]` is the
    /// seed step of an old step (`usize::MAX`: not in the seed). From each
    /// point of a seed step, to the first points of other seed steps that
    /// follow it, through points of steps not in the seed: their transitive
    /// closure is the old order between the seed's steps.
    pub fn orders(&self, index: &[usize]) -> Vec<SeedOrder> {
        let n = self.points.len();
        let mut seen = vec![usize::MAX; n];
        let mut stack: Vec<u32> = Vec::new();
        let mut out = Vec::new();
        for u in 0..n {
            let (a, ea) = self.points[u];
            if index[a] == usize::MAX {
                continue;
            }
            stack.clear();
            stack.extend(&self.next[u]);
            while let Some(v) = stack.pop() {
                let v = v as usize;
                if seen[v] == u {
                    continue;
                }
                seen[v] = u;
                let (b, eb) = self.points[v];
                if index[b] == usize::MAX {
                    stack.extend(&self.next[v]);
                } else if b != a {
                    out.push(SeedOrder { from: (index[a], ea), to: (index[b], eb) });
                }
                // A point of the same step: its own orderings follow it.
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (tests only).
    struct Lcg(u64);
    impl Lcg {
        fn below(&mut self, n: u64) -> u64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 33) % n
        }
    }

    /// The closure of the orders between steps still in equals the old
    /// order between them, whatever steps are removed: random plans
    /// (two points per step, start before end), random orders between
    /// points, random steps removed.
    #[test]
    fn the_orders_kept_are_the_old_order_between_the_steps_left() {
        let mut rng = Lcg(7);
        for round in 0..200 {
            let steps = 2 + rng.below(14) as usize;
            let points: Vec<(usize, End)> =
                (0..steps).flat_map(|s| [(s, End::Start), (s, End::End)]).collect();
            let n = points.len();
            // Random edges forward in a random linear order of the points
            // that keeps each start before its end, then their closure.
            let mut rank: Vec<usize> = (0..n).collect();
            for i in (1..n).rev() {
                rank.swap(i, rng.below(i as u64 + 1) as usize);
            }
            for s in 0..steps {
                let (a, b) = (2 * s, 2 * s + 1);
                if rank[a] > rank[b] {
                    rank.swap(a, b);
                }
            }
            let mut before = vec![vec![false; n]; n];
            for s in 0..steps {
                before[2 * s][2 * s + 1] = true;
            }
            for _ in 0..rng.below(3 * n as u64) {
                let (i, j) = (rng.below(n as u64) as usize, rng.below(n as u64) as usize);
                if rank[i] < rank[j] {
                    before[i][j] = true;
                }
            }
            for k in 0..n {
                for i in 0..n {
                    for j in 0..n {
                        if before[i][k] && before[k][j] {
                            before[i][j] = true;
                        }
                    }
                }
            }
            let order = OldOrder::new(
                points.clone(),
                |j| (0..n).filter(|&i| before[i][j]).collect(),
                |i| rank[i] as f64,
            );
            let removed: Vec<bool> = (0..steps).map(|_| rng.below(3) == 0).collect();
            let mut index = vec![usize::MAX; steps];
            let mut k = 0;
            for s in 0..steps {
                if !removed[s] {
                    index[s] = k;
                    k += 1;
                }
            }
            // The closure of what is kept, with each step's start before its end.
            let mut kept = vec![vec![false; 2 * k]; 2 * k];
            let at = |(s, e): (usize, End)| 2 * s + usize::from(e == End::End);
            for o in order.orders(&index) {
                kept[at(o.from)][at(o.to)] = true;
            }
            for s in 0..k {
                kept[2 * s][2 * s + 1] = true;
            }
            for m in 0..2 * k {
                for i in 0..2 * k {
                    for j in 0..2 * k {
                        if kept[i][m] && kept[m][j] {
                            kept[i][j] = true;
                        }
                    }
                }
            }
            for i in 0..n {
                for j in 0..n {
                    let ((a, ea), (b, eb)) = (points[i], points[j]);
                    if removed[a] || removed[b] || a == b {
                        continue;
                    }
                    let (x, y) = (at((index[a], ea)), at((index[b], eb)));
                    assert_eq!(kept[x][y], before[i][j], "round {round}: {:?} → {:?}", points[i], points[j]);
                }
            }
        }
    }
}
