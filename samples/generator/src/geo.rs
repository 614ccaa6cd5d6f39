//! Geometry and graph helpers: distances, a spatial hash, shortest paths.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// Euclidean distance between two points given in decimetres, returned in
/// centimetres (hundredths of metres), rounded to the nearest unit.
///
/// `sqrt` is correctly rounded by IEEE 754, so this is the same on every platform.
pub fn dist_cm(ax: i64, ay: i64, bx: i64, by: i64) -> u64 {
    let dx = (ax - bx) as f64;
    let dy = (ay - by) as f64;
    ((dx * dx + dy * dy).sqrt() * 10.0).round() as u64
}

/// Squared Euclidean distance in square decimetres.
pub fn dist2(ax: i64, ay: i64, bx: i64, by: i64) -> i64 {
    let dx = ax - bx;
    let dy = ay - by;
    dx * dx + dy * dy
}

/// Squared distance (dm²) from point `p` to the segment `a`–`b`.
pub fn seg_dist2(p: (i64, i64), a: (i64, i64), b: (i64, i64)) -> f64 {
    let (px, py) = (p.0 as f64, p.1 as f64);
    let (ax, ay) = (a.0 as f64, a.1 as f64);
    let (bx, by) = (b.0 as f64, b.1 as f64);
    let (vx, vy) = (bx - ax, by - ay);
    let len2 = vx * vx + vy * vy;
    let t = if len2 == 0.0 { 0.0 } else { (((px - ax) * vx + (py - ay) * vy) / len2).clamp(0.0, 1.0) };
    let (cx, cy) = (ax + t * vx, ay + t * vy);
    (px - cx) * (px - cx) + (py - cy) * (py - cy)
}

/// A uniform grid of buckets over the plane, for radius queries.
///
/// Queries visit cells in a fixed order and return indices in increasing order,
/// so results never depend on hash-map iteration order.
#[derive(Debug, Clone)]
pub struct SpatialHash {
    cell: i64,
    buckets: HashMap<(i64, i64), Vec<usize>>,
}

impl SpatialHash {
    pub fn new(cell: i64) -> Self {
        assert!(cell > 0);
        SpatialHash { cell, buckets: HashMap::new() }
    }

    fn key(&self, x: i64, y: i64) -> (i64, i64) {
        (x.div_euclid(self.cell), y.div_euclid(self.cell))
    }

    pub fn insert(&mut self, id: usize, x: i64, y: i64) {
        let k = self.key(x, y);
        self.buckets.entry(k).or_default().push(id);
    }

    /// Ids whose point lies within `radius` (inclusive) of `(x, y)`, sorted.
    pub fn within(&self, x: i64, y: i64, radius: i64, pos: impl Fn(usize) -> (i64, i64)) -> Vec<usize> {
        let (kx0, ky0) = self.key(x - radius, y - radius);
        let (kx1, ky1) = self.key(x + radius, y + radius);
        let r2 = radius * radius;
        let mut out = Vec::new();
        for ky in ky0..=ky1 {
            for kx in kx0..=kx1 {
                if let Some(ids) = self.buckets.get(&(kx, ky)) {
                    for &id in ids {
                        let (px, py) = pos(id);
                        if dist2(x, y, px, py) <= r2 {
                            out.push(id);
                        }
                    }
                }
            }
        }
        out.sort_unstable();
        out
    }
}

/// An undirected weighted graph given as adjacency lists of `(neighbour, weight)`.
#[derive(Debug, Clone)]
pub struct Graph {
    pub adj: Vec<Vec<(usize, u64)>>,
}

impl Graph {
    pub fn new(n: usize, edges: &[(usize, usize, u64)]) -> Self {
        let mut adj = vec![Vec::new(); n];
        for &(u, v, w) in edges {
            adj[u].push((v, w));
            adj[v].push((u, w));
        }
        for list in &mut adj {
            list.sort_unstable();
        }
        Graph { adj }
    }

    /// Shortest distances from `src` to every node, using only nodes for which
    /// `allowed` holds (`u64::MAX` when unreachable); with the predecessor of
    /// each node on a shortest path. Stops early once every node of `targets`
    /// is settled (when `targets` is not empty).
    pub fn dijkstra(
        &self,
        src: usize,
        allowed: &dyn Fn(usize) -> bool,
        targets: &[usize],
    ) -> (Vec<u64>, Vec<usize>) {
        let n = self.adj.len();
        let mut dist = vec![u64::MAX; n];
        let mut pred = vec![usize::MAX; n];
        let mut done = vec![false; n];
        let mut remaining = targets.iter().filter(|&&t| t != src).count();
        let mut is_target = vec![false; if targets.is_empty() { 0 } else { n }];
        for &t in targets {
            is_target[t] = true;
        }
        let mut heap = BinaryHeap::new();
        dist[src] = 0;
        heap.push(Reverse((0u64, src)));
        while let Some(Reverse((d, u))) = heap.pop() {
            if done[u] {
                continue;
            }
            done[u] = true;
            if !targets.is_empty() && u != src && is_target[u] {
                remaining -= 1;
                if remaining == 0 {
                    break;
                }
            }
            for &(v, w) in &self.adj[u] {
                if !allowed(v) {
                    continue;
                }
                let nd = d + w;
                if nd < dist[v] || (nd == dist[v] && u < pred[v]) {
                    dist[v] = nd;
                    pred[v] = u;
                    heap.push(Reverse((nd, v)));
                }
            }
        }
        (dist, pred)
    }
}

/// Whether a path from `from` to `to` of length at most `limit` exists in the
/// graph given by `adj` (lists of `(neighbour, weight, edge id)`), ignoring the
/// edge `skip` and the edges that are not `alive`.
pub fn has_path_within(
    adj: &[Vec<(usize, u64, usize)>],
    alive: &[bool],
    from: usize,
    to: usize,
    skip: usize,
    limit: u64,
) -> bool {
    let mut dist: HashMap<usize, u64> = HashMap::new();
    let mut heap = BinaryHeap::new();
    dist.insert(from, 0);
    heap.push(Reverse((0u64, from)));
    while let Some(Reverse((d, u))) = heap.pop() {
        if u == to {
            return true;
        }
        if dist.get(&u).is_some_and(|&best| best < d) {
            continue;
        }
        for &(v, w, e) in &adj[u] {
            if e == skip || !alive[e] {
                continue;
            }
            let nd = d + w;
            if nd > limit {
                continue;
            }
            if dist.get(&v).is_none_or(|&best| nd < best) {
                dist.insert(v, nd);
                heap.push(Reverse((nd, v)));
            }
        }
    }
    false
}

/// Removes, longest first, every edge not kept by `protected` for which another
/// path at most `num/den` times as long exists. The remaining edges are then
/// strictly shorter than any detour through other edges when `num > den`, which
/// makes move durations satisfy the triangle inequality even after rounding.
/// Removing an edge only when a detour exists keeps the graph's connectivity.
pub fn prune_detours(
    n: usize,
    edges: &[(usize, usize, u64)],
    protected: &dyn Fn(usize) -> bool,
    num: u64,
    den: u64,
) -> Vec<(usize, usize, u64)> {
    let mut adj = vec![Vec::new(); n];
    for (id, &(u, v, w)) in edges.iter().enumerate() {
        adj[u].push((v, w, id));
        adj[v].push((u, w, id));
    }
    let mut order: Vec<usize> = (0..edges.len()).filter(|&e| !protected(e)).collect();
    order.sort_by_key(|&e| (Reverse(edges[e].2), edges[e].0, edges[e].1));
    let mut alive = vec![true; edges.len()];
    for e in order {
        let (u, v, w) = edges[e];
        if has_path_within(&adj, &alive, u, v, e, w * num / den) {
            alive[e] = false;
        }
    }
    edges.iter().zip(&alive).filter(|(_, a)| **a).map(|(e, _)| *e).collect()
}

/// Checks that no edge is longer than a detour through other edges (the
/// triangle inequality, generalised to paths). Returns the first offending
/// edge and the length of the shorter detour.
pub fn first_detour_violation(n: usize, edges: &[(usize, usize, u64)]) -> Option<((usize, usize, u64), u64)> {
    let mut adj = vec![Vec::new(); n];
    for (id, &(u, v, w)) in edges.iter().enumerate() {
        adj[u].push((v, w, id));
        adj[v].push((u, w, id));
    }
    let alive = vec![true; edges.len()];
    for (id, &(u, v, w)) in edges.iter().enumerate() {
        if w > 0 && has_path_within(&adj, &alive, u, v, id, w - 1) {
            // Find the detour length for the message.
            let mut lo = 0;
            let mut hi = w - 1;
            while lo < hi {
                let mid = (lo + hi) / 2;
                if has_path_within(&adj, &alive, u, v, id, mid) {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            return Some(((u, v, w), lo));
        }
    }
    None
}

/// Union–find over `0..n`.
#[derive(Debug, Clone)]
pub struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    pub fn new(n: usize) -> Self {
        UnionFind { parent: (0..n).collect() }
    }

    pub fn find(&mut self, x: usize) -> usize {
        let mut root = x;
        while self.parent[root] != root {
            root = self.parent[root];
        }
        let mut y = x;
        while self.parent[y] != root {
            let next = self.parent[y];
            self.parent[y] = root;
            y = next;
        }
        root
    }

    /// Joins the sets of `a` and `b`; the smaller root becomes the representative.
    pub fn union(&mut self, a: usize, b: usize) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        self.parent[hi] = lo;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_are_in_centimetres() {
        // 3-4-5 triangle in decimetres: 50 dm = 5 m = 500 cm.
        assert_eq!(dist_cm(0, 0, 30, 40), 500);
    }

    #[test]
    fn pruning_removes_collinear_shortcuts() {
        // a - b - c nearly collinear: the long edge a-c must go.
        let edges = vec![(0, 1, 1000), (1, 2, 1000), (0, 2, 1999)];
        let kept = prune_detours(3, &edges, &|_| false, 108, 100);
        assert_eq!(kept, vec![(0, 1, 1000), (1, 2, 1000)]);
        assert!(first_detour_violation(3, &edges).is_none());
        let bad = vec![(0, 1, 1000), (1, 2, 1000), (0, 2, 2001)];
        assert_eq!(first_detour_violation(3, &bad), Some(((0, 2, 2001), 2000)));
    }
}
