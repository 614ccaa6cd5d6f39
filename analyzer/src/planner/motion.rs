//! Geometric reasoning (section 4.3 of the HiPOP paper): the position
//! families that model verification confirmed (Definition 12,
//! [`crate::verify::families`]), split into groups (one per key: `at r1 *`),
//! and, for the families with move actions (Definition 14), the shortest
//! chains of moves between the positions of each group.
//!
//! Real maps rarely have a move between every two positions (property 4):
//! the surveillance sample links adjacent waypoints only. The paper's answer
//! is to add the missing moves as abstract actions whose methods are shortest
//! paths; the planner does the equivalent directly: the minimum duration
//! between two positions is the shortest chain of moves (Floyd–Warshall over
//! the ground moves of the group), and supporting a position can insert that
//! chain. Property 6 (the triangle inequality) then holds by construction.

use crate::db::{Db, Unit};
use crate::verify::families::{is_member, planner_families, reachable_planner_families};

use super::task::{End, MotionGroup, Task, atom_of, is_neg};

/// Fills the family and motion tables of `task`.
/// With `types`, the families of one key type too (`at ?truck *`).
pub(super) fn families<'db>(db: &'db dyn Db, problem: Unit<'db>, task: &mut Task<'db>, types: bool) {
    let g = task.g;
    let fams = if task.goal_relevance {
        planner_families(db, problem)
    } else {
        reachable_planner_families(db, problem)
    };
    let mut group_keys: rustc_hash::FxHashMap<(u32, Vec<u32>), u32> = Default::default();
    let mut groups: Vec<(Vec<u32>, bool)> = Vec::new(); // positions, has moves
    let confirmed: Vec<_> =
        fams.confirmed.iter().filter(|f| types || f.candidate.key_type.is_none()).collect();
    for f in &confirmed {
        // A family of one key type is for threats and the last known
        // position only: no itineraries (Depots' trucks: their visits
        // sequenced one by one made the searches longer, docs/planner.md).
        let has_moves = !f.moves.is_empty() && f.candidate.key_type.is_none();
        for atom in 0..g.atoms.len() as u32 {
            if !is_member(g, atom, f.pred, &f.candidate) {
                continue;
            }
            let mut key = g.atoms.args(atom).to_vec();
            key.remove(f.candidate.pos as usize);
            let id = *group_keys.entry((f.pred, key)).or_insert_with(|| {
                groups.push((Vec::new(), has_moves));
                groups.len() as u32 - 1
            });
            let local = groups[id as usize].0.len() as u32;
            groups[id as usize].0.push(atom);
            task.family[atom as usize] = Some((id, local));
        }
    }
    task.groups = groups.len();
    // The move operators of each group: their only condition is the
    // from-position, their only effects the to-position and its deletion.
    // Only moves of 𝒜: the chains of moves are steps the planner inserts (in
    // a pure HTN problem, none: moves come from methods).
    let move_items: Vec<_> = confirmed.iter().flat_map(|f| f.moves.iter().map(|(item, _)| *item)).collect();
    let mut edges: Vec<Vec<(u32, u32, f64, u32)>> = vec![Vec::new(); groups.len()];
    for (i, op) in task.ops.iter().enumerate() {
        if !move_items.contains(&op.item) || op.dead || !op.allowed {
            continue;
        }
        let from =
            op.conds.iter().find(|c| !is_neg(c.lit)).and_then(|c| task.family[atom_of(c.lit) as usize]);
        let to = op
            .effs
            .iter()
            .find(|e| !is_neg(e.lit) && e.at == End::End || op.instant && !is_neg(e.lit))
            .and_then(|e| task.family[atom_of(e.lit) as usize]);
        let (Some((g1, f)), Some((g2, t)), Some(d)) = (from, to, op.duration) else { continue };
        if g1 != g2 || f == t {
            continue;
        }
        task.moves.insert(i as u32, (g1, f, t));
        edges[g1 as usize].push((f, t, d, i as u32));
    }
    task.motion = groups
        .iter()
        .zip(edges)
        .map(|((positions, has_moves), edges)| {
            if !has_moves || edges.is_empty() {
                return None;
            }
            let n = positions.len();
            let mut dist = vec![f64::INFINITY; n * n];
            let mut next_move = vec![u32::MAX; n * n];
            for i in 0..n {
                dist[i * n + i] = 0.0;
            }
            for (f, t, d, op) in edges {
                let k = f as usize * n + t as usize;
                if d < dist[k] {
                    dist[k] = d;
                    next_move[k] = op;
                }
            }
            for k in 0..n {
                for i in 0..n {
                    let dik = dist[i * n + k];
                    if !dik.is_finite() || i == k {
                        continue;
                    }
                    for j in 0..n {
                        let d = dik + dist[k * n + j];
                        if d < dist[i * n + j] - 1e-12 {
                            dist[i * n + j] = d;
                            next_move[i * n + j] = next_move[i * n + k];
                        }
                    }
                }
            }
            Some(MotionGroup { positions: positions.clone(), dist, next_move })
        })
        .collect();
}

impl MotionGroup {
    /// The moves of a shortest chain from `from` to `to` (local positions),
    /// given where each move leads.
    pub fn path(&self, from: u32, to: u32, leads_to: impl Fn(u32) -> u32) -> Option<Vec<u32>> {
        let n = self.n();
        let mut at = from;
        let mut out = Vec::new();
        while at != to {
            let m = self.next_move[at as usize * n + to as usize];
            if m == u32::MAX || out.len() > n {
                return None;
            }
            out.push(m);
            at = leads_to(m);
        }
        Some(out)
    }
}
