//! Relaxed reachability: which ground atoms and operators can be reached from
//! the initial state when deletes and negative preconditions are ignored.
//!
//! It over-approximates what a plan can do: an atom it does not reach is false
//! in every state any plan visits, an operator it does not reach is in no plan.
//! Timed initial literals that make an atom true count as reaching it.
//!
//! The fixpoint is the usual counter-based one: each operator counts its
//! preconditions not reached yet; reaching an atom decrements the counters of
//! the operators that need it, and an operator whose counter drops to zero
//! reaches its add effects. Linear in the size of the ground problem.

use super::ground::{Ground, GroundOperator};
use super::state::AtomId;

/// What relaxed reachability found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reach {
    /// By atom id.
    pub atoms: Vec<bool>,
    /// By index in [`Ground::operators`].
    pub operators: Vec<bool>,
}

impl Reach {
    pub fn atom(&self, a: AtomId) -> bool {
        self.atoms.get(a as usize).copied().unwrap_or(false)
    }

    pub fn operator(&self, index: usize) -> bool {
        self.operators.get(index).copied().unwrap_or(false)
    }
}

/// Relaxed reachability from the initial state, using only the operators
/// `usable` accepts (a lint about allowed actions restricts them).
pub fn reachable(g: &Ground<'_>, usable: impl Fn(&GroundOperator<'_>) -> bool) -> Reach {
    let n_atoms = g.atoms.len();
    let n_ops = g.operators.len();
    let mut reached = vec![false; n_atoms];
    let mut fired = vec![false; n_ops];
    let usable: Vec<bool> = g.operators.iter().map(&usable).collect();

    // Which operators wait for each atom (compressed rows).
    let mut start = vec![0u32; n_atoms + 1];
    for (o, op) in g.operators.iter().enumerate() {
        if usable[o] {
            for &a in g.pre(op) {
                start[a as usize + 1] += 1;
            }
        }
    }
    for i in 0..n_atoms {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut waiting = vec![0u32; start[n_atoms] as usize];
    for (o, op) in g.operators.iter().enumerate() {
        if usable[o] {
            for &a in g.pre(op) {
                waiting[fill[a as usize] as usize] = o as u32;
                fill[a as usize] += 1;
            }
        }
    }
    // `pre` has no duplicates: its length is the number of atoms to wait for.
    let mut missing: Vec<u32> = g.operators.iter().map(|op| g.pre(op).len() as u32).collect();

    // Atoms of each predicate, for operators that add atoms grounding cannot name.
    let mut by_pred: Option<Vec<Vec<AtomId>>> = None;
    let mut wild_done = vec![false; g.predicates.len()];

    let mut queue: Vec<AtomId> = Vec::new();
    let reach = |a: AtomId, reached: &mut Vec<bool>, queue: &mut Vec<AtomId>| {
        if let Some(r) = reached.get_mut(a as usize)
            && !*r
        {
            *r = true;
            queue.push(a);
        }
    };
    for &(a, _) in &g.init.facts {
        reach(a, &mut reached, &mut queue);
    }
    for t in g.init.timed.iter().filter(|t| t.positive) {
        reach(t.atom, &mut reached, &mut queue);
    }
    let mut ready: Vec<usize> = (0..n_ops).filter(|&o| usable[o] && missing[o] == 0).collect();
    loop {
        while let Some(o) = ready.pop() {
            if fired[o] {
                continue;
            }
            fired[o] = true;
            let op = &g.operators[o];
            for &a in g.add(op) {
                reach(a, &mut reached, &mut queue);
            }
            let wild = g.schemas.get(op.schema as usize).map_or(&[][..], |s| s.wild_add.as_slice());
            for &p in wild {
                if wild_done.get(p as usize).copied().unwrap_or(true) {
                    continue;
                }
                wild_done[p as usize] = true;
                let by_pred = by_pred.get_or_insert_with(|| {
                    let mut v = vec![Vec::new(); g.predicates.len()];
                    for a in 0..n_atoms as AtomId {
                        if let Some(list) = v.get_mut(g.atoms.pred(a) as usize) {
                            list.push(a);
                        }
                    }
                    v
                });
                for &a in &by_pred[p as usize] {
                    reach(a, &mut reached, &mut queue);
                }
            }
        }
        let Some(a) = queue.pop() else { break };
        let (s, e) = (start[a as usize] as usize, start[a as usize + 1] as usize);
        for &o in &waiting[s..e] {
            let m = &mut missing[o as usize];
            *m -= 1;
            if *m == 0 {
                ready.push(o as usize);
            }
        }
    }
    Reach { atoms: reached, operators: fired }
}
