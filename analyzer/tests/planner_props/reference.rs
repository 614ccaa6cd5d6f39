//! The reference the planner is held against: its own grounding of a
//! random problem and a breadth-first search over sequential executions.

use std::collections::{HashSet, VecDeque};
use std::fmt::Write as _;

use super::problem::*;

pub(crate) type State = u128;

#[derive(Debug, Clone)]
pub(crate) struct GroundOp {
    pub(crate) action: usize,
    pub(crate) args: Vec<usize>,
    /// Positive and negative conditions at the start, over all, at the end.
    pub(crate) pre: [(State, State); 3],
    /// Additions and deletions at the start and at the end.
    pub(crate) eff: [(State, State); 2],
}

pub(crate) struct Reference {
    pub(crate) ops: Vec<GroundOp>,
    pub(crate) init: State,
    pub(crate) goal: (State, State),
}

pub(crate) fn atom_index(p: &Problem, pred: usize, args: &[usize]) -> usize {
    let n = p.objects.len();
    let offset: usize = p.preds[..pred].iter().map(|a| n.pow(a.len() as u32)).sum();
    offset + args.iter().fold(0, |acc, &o| acc * n + o)
}

pub(crate) fn bit(p: &Problem, pred: usize, args: &[usize]) -> State {
    let i = atom_index(p, pred, args);
    assert!(i < 128);
    1u128 << i
}

/// The ground actions (those of 𝒜 when `allowed`).
pub(crate) fn ground_ops(p: &Problem, allowed: bool) -> Vec<GroundOp> {
    let mut ops = Vec::new();
    for (i, a) in p.actions.iter().enumerate() {
        if allowed && p.allowed.as_ref().is_some_and(|al| !al.contains(&i)) {
            continue;
        }
        for args in tuples(p, &a.params) {
            let mut op = GroundOp { action: i, args: args.clone(), pre: [(0, 0); 3], eff: [(0, 0); 2] };
            for l in &a.conds {
                let b = bit(p, l.pred, &l.args.iter().map(|&k| args[k]).collect::<Vec<_>>());
                let slot = &mut op.pre[l.at as usize];
                if l.neg {
                    slot.1 |= b;
                } else {
                    slot.0 |= b;
                }
            }
            for l in &a.effs {
                let b = bit(p, l.pred, &l.args.iter().map(|&k| args[k]).collect::<Vec<_>>());
                let slot = &mut op.eff[if l.at == When::Start { 0 } else { 1 }];
                if l.neg {
                    slot.1 |= b;
                } else {
                    slot.0 |= b;
                }
            }
            ops.push(op);
        }
    }
    ops
}

pub(crate) fn reference(p: &Problem) -> Reference {
    let ops = ground_ops(p, true);
    let init = p.init.iter().fold(0, |s, (pr, args)| s | bit(p, *pr, args));
    let mut goal = (0, 0);
    for (neg, pr, args) in &p.goal {
        if *neg {
            goal.1 |= bit(p, *pr, args);
        } else {
            goal.0 |= bit(p, *pr, args);
        }
    }
    Reference { ops, init, goal }
}

pub(crate) fn holds(s: State, (pos, neg): (State, State)) -> bool {
    s & pos == pos && s & neg == 0
}

/// Deletions before additions (VAL's).
pub(crate) fn apply(s: State, (add, del): (State, State)) -> State {
    (s & !del) | add
}

/// One action executed alone from `s`.
pub(crate) fn execute(op: &GroundOp, s: State) -> Option<State> {
    if !holds(s, op.pre[0]) {
        return None;
    }
    let mid = apply(s, op.eff[0]);
    if !holds(mid, op.pre[1]) || !holds(mid, op.pre[2]) {
        return None;
    }
    Some(apply(mid, op.eff[1]))
}

/// What the breadth-first search found.
pub(crate) struct Bfs {
    pub(crate) plan: Option<Vec<usize>>,
    /// Every reachable state was explored (not only to the depth bound).
    pub(crate) complete: bool,
}

pub(crate) const DEPTH: usize = 6;
pub(crate) const MAX_STATES: usize = 200_000;

pub(crate) fn bfs(r: &Reference) -> Bfs {
    let mut seen: HashSet<State> = HashSet::new();
    let mut parent: Vec<(usize, usize)> = Vec::new(); // (parent node, op)
    let mut nodes: Vec<State> = Vec::new();
    let mut queue = VecDeque::new();
    seen.insert(r.init);
    nodes.push(r.init);
    parent.push((usize::MAX, usize::MAX));
    queue.push_back((0usize, 0usize));
    let mut complete = true;
    while let Some((n, depth)) = queue.pop_front() {
        let s = nodes[n];
        if holds(s, r.goal) {
            let mut plan = Vec::new();
            let mut at = n;
            while parent[at].0 != usize::MAX {
                plan.push(parent[at].1);
                at = parent[at].0;
            }
            plan.reverse();
            return Bfs { plan: Some(plan), complete };
        }
        for (i, op) in r.ops.iter().enumerate() {
            let Some(next) = execute(op, s) else { continue };
            if seen.contains(&next) {
                continue;
            }
            if depth == DEPTH || seen.len() >= MAX_STATES {
                complete = false;
                continue;
            }
            seen.insert(next);
            nodes.push(next);
            parent.push((n, i));
            queue.push_back((nodes.len() - 1, depth + 1));
        }
    }
    Bfs { plan: None, complete }
}

/// Whether the positive goal atoms are reachable ignoring deletions (a
/// negative condition holds if its atom is false initially or something
/// deletes it): when not, no plan exists.
pub(crate) fn relaxed_reachable(r: &Reference) -> bool {
    let can_be_false = !r.init | r.ops.iter().fold(0, |d, op| d | op.eff[0].1 | op.eff[1].1);
    let mut s = r.init;
    loop {
        let mut next = s;
        for op in &r.ops {
            let pos = op.pre[0].0 | op.pre[1].0 | op.pre[2].0;
            let neg = op.pre[0].1 | op.pre[1].1 | op.pre[2].1;
            if s & pos == pos && neg & can_be_false == neg {
                next |= op.eff[0].0 | op.eff[1].0;
            }
        }
        if next == s {
            return s & r.goal.0 == r.goal.0;
        }
        s = next;
    }
}

/// A sequential plan in VAL's format: each step 0.01 after the previous one ends.
pub(crate) fn sequential_val(p: &Problem, r: &Reference, plan: &[usize]) -> String {
    let mut out = String::new();
    let mut t = 0u32; // hundredths
    for &i in plan {
        let op = &r.ops[i];
        let a = &p.actions[op.action];
        let _ = write!(out, "{}.{:02}: (a{}", t / 100, t % 100, op.action);
        for o in &op.args {
            let _ = write!(out, " o{o}");
        }
        out.push(')');
        if a.durative {
            let _ = write!(out, " [{}]", a.duration);
            t += a.duration * 100;
        }
        out.push('\n');
        t += 1;
    }
    out
}
