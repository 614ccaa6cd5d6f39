//! Goal relevance, lifted: which instances of the operators a plan for this
//! problem's goal may need, computed backwards from the goal before any
//! instantiation (the relevance analysis of Fast Downward's translator,
//! over an abstraction that stays small).
//!
//! The relevant atoms are abstracted per predicate and argument position:
//! the objects that may stand there (a Cartesian over-approximation). An
//! operator is relevant when one of its add effects can be a relevant atom,
//! or one of its deletes can be an atom some condition needs false; its
//! parameters then take the values of the matching positions (the other
//! parameters any value of their types), the union over every effect that
//! matches. The conditions of a relevant operator, with those values, are
//! relevant in turn, up to a fixpoint.
//!
//! It is sound: an instance outside the result adds nothing any relevant
//! instance or the goal needs, and deletes nothing any of them needs false,
//! so removing it from a plan (with every other irrelevant step) leaves a
//! plan. Numeric fluents are handled conservatively: once a relevant
//! operator or the goal reads a fluent that effects change (a numeric
//! condition, a duration), every operator with a numeric effect is relevant
//! with all its instances.

use super::instantiate::{Arg, CAtom};
use super::state::{ObjId, PredId};

/// A set of objects, as bits.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ObjSet {
    words: Vec<u64>,
}

impl ObjSet {
    pub fn empty(n: usize) -> ObjSet {
        ObjSet { words: vec![0; n.div_ceil(64)] }
    }

    pub fn of(n: usize, objects: &[ObjId]) -> ObjSet {
        let mut s = ObjSet::empty(n);
        for &o in objects {
            s.insert(o);
        }
        s
    }

    pub fn contains(&self, o: ObjId) -> bool {
        self.words.get(o as usize / 64).is_some_and(|w| w >> (o % 64) & 1 == 1)
    }

    /// Adds an object; whether it was new.
    fn insert(&mut self, o: ObjId) -> bool {
        let i = o as usize / 64;
        if i >= self.words.len() {
            self.words.resize(i + 1, 0);
        }
        let bit = 1u64 << (o % 64);
        let new = self.words[i] & bit == 0;
        self.words[i] |= bit;
        new
    }

    /// Adds every object of `other`; whether one was new.
    fn union_with(&mut self, other: &ObjSet) -> bool {
        if self.words.len() < other.words.len() {
            self.words.resize(other.words.len(), 0);
        }
        let mut changed = false;
        for (w, &x) in self.words.iter_mut().zip(&other.words) {
            changed |= x & !*w != 0;
            *w |= x;
        }
        changed
    }

    fn intersect_with(&mut self, other: &ObjSet) {
        for (i, w) in self.words.iter_mut().enumerate() {
            *w &= other.words.get(i).copied().unwrap_or(0);
        }
    }

    fn is_empty(&self) -> bool {
        self.words.iter().all(|&w| w == 0)
    }
}

/// An operator as relevance sees it. Conditions and effects are on
/// predicates that are not static (no operator adds or deletes a static
/// one, so they never make anything relevant).
pub(crate) struct RelOp<'a> {
    /// Each parameter's objects (its types).
    pub domains: &'a [Vec<ObjId>],
    /// Every positive and negative atom condition, at any time point.
    pub pos: Vec<&'a CAtom>,
    pub neg: Vec<&'a CAtom>,
    pub add: &'a [CAtom],
    pub del: &'a [CAtom],
    /// Predicates it adds with a term grounding cannot name: any atom.
    pub wild_add: &'a [PredId],
    /// It changes a numeric fluent.
    pub numeric_effect: bool,
    /// It reads a fluent that may change (a numeric condition, a duration
    /// that is not fixed).
    pub numeric_read: bool,
}

/// A goal literal's atom: an object, or any object (a quantified variable).
pub(crate) struct GoalAtom {
    pub pred: PredId,
    pub args: Vec<Option<ObjId>>,
}

/// The goal: atoms needed true, atoms needed false, and whether it reads
/// numeric fluents.
#[derive(Default)]
pub(crate) struct Goal {
    pub pos: Vec<GoalAtom>,
    pub neg: Vec<GoalAtom>,
    pub numeric: bool,
}

/// Per predicate, per argument position, the objects of relevant atoms;
/// `None` when no atom of the predicate is relevant.
type Atoms = Vec<Option<Vec<ObjSet>>>;

/// Adds `(pred args)` to `rel`, with each argument's objects given; whether
/// something was new.
fn add_pattern(rel: &mut Atoms, pred: PredId, args: impl ExactSizeIterator<Item = ObjSet>, n: usize) -> bool {
    let p = pred as usize;
    if rel.len() <= p {
        rel.resize(p + 1, None);
    }
    let arity = args.len();
    let mut changed = false;
    let sets = rel[p].get_or_insert_with(|| {
        changed = true;
        Vec::new()
    });
    if sets.len() < arity {
        sets.resize(arity, ObjSet::empty(n));
        changed = true;
    }
    for (s, a) in sets.iter_mut().zip(args) {
        changed |= s.union_with(&a);
    }
    changed
}

/// The parameters' objects under which effect `a` may be an atom of `rel`,
/// starting from `params` (the parameters' current objects); `None` when it
/// cannot. A position `rel` does not know (an arity error) matches anything.
fn matching(a: &CAtom, rel: &Atoms, params: &[ObjSet]) -> Option<Vec<ObjSet>> {
    let sets = rel.get(a.pred as usize)?.as_ref()?;
    let mut bx = params.to_vec();
    for (i, arg) in a.args.iter().enumerate() {
        let Some(s) = sets.get(i) else { continue };
        match *arg {
            Arg::Obj(o) => {
                if !s.contains(o) {
                    return None;
                }
            }
            Arg::Param(q) => {
                if let Some(b) = bx.get_mut(q as usize) {
                    b.intersect_with(s);
                }
            }
        }
    }
    let used = |q: usize| a.args.contains(&Arg::Param(q as u32));
    if bx.iter().enumerate().any(|(q, b)| used(q) && b.is_empty()) {
        return None;
    }
    Some(bx)
}

/// For each operator, the objects each parameter may take in a relevant
/// instance; `None` for an operator with no relevant instance.
pub(crate) fn relevant(ops: &[RelOp], goal: &Goal, n_objects: usize) -> Vec<Option<Vec<ObjSet>>> {
    let n = n_objects;
    let mut pos: Atoms = Vec::new();
    let mut neg: Atoms = Vec::new();
    let goal_set = |o: Option<ObjId>| match o {
        Some(o) => ObjSet::of(n, &[o]),
        None => ObjSet::of(n, &(0..n as ObjId).collect::<Vec<_>>()),
    };
    for g in &goal.pos {
        add_pattern(&mut pos, g.pred, g.args.iter().map(|&o| goal_set(o)), n);
    }
    for g in &goal.neg {
        add_pattern(&mut neg, g.pred, g.args.iter().map(|&o| goal_set(o)), n);
    }
    let mut numeric = goal.numeric;
    let types: Vec<Vec<ObjSet>> =
        ops.iter().map(|op| op.domains.iter().map(|d| ObjSet::of(n, d)).collect()).collect();
    let mut out: Vec<Option<Vec<ObjSet>>> = vec![None; ops.len()];
    let mut changed = true;
    while changed {
        changed = false;
        for (i, op) in ops.iter().enumerate() {
            let full = &types[i];
            // Every way an effect of it may be relevant.
            let mut boxes: Vec<Vec<ObjSet>> = Vec::new();
            let whole = (numeric && op.numeric_effect)
                || op.wild_add.iter().any(|&p| pos.get(p as usize).is_some_and(Option::is_some));
            if whole {
                boxes.push(full.clone());
            } else {
                boxes.extend(op.add.iter().filter_map(|a| matching(a, &pos, full)));
                boxes.extend(op.del.iter().filter_map(|a| matching(a, &neg, full)));
            }
            if boxes.is_empty() {
                continue;
            }
            let mut grew = false;
            let dom = out[i].get_or_insert_with(|| {
                grew = true;
                vec![ObjSet::empty(n); full.len()]
            });
            for b in &boxes {
                for (d, s) in dom.iter_mut().zip(b) {
                    grew |= d.union_with(s);
                }
            }
            if !grew {
                continue;
            }
            changed = true;
            numeric |= op.numeric_read;
            // Its conditions are relevant, with these parameters.
            let dom = &out[i].as_ref().expect("just set");
            let arg_set = |a: &Arg| match *a {
                Arg::Obj(o) => ObjSet::of(n, &[o]),
                Arg::Param(q) => dom.get(q as usize).cloned().unwrap_or_else(|| ObjSet::empty(n)),
            };
            for a in &op.pos {
                add_pattern(&mut pos, a.pred, a.args.iter().map(arg_set), n);
            }
            for a in &op.neg {
                add_pattern(&mut neg, a.pred, a.args.iter().map(arg_set), n);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn atom(pred: PredId, args: &[Arg]) -> CAtom {
        CAtom { pred, args: args.to_vec() }
    }

    #[test]
    fn only_the_goal_instance_of_a_free_action() {
        // link ?a ?b over 10 objects, goal (linked 1 2).
        let domains = vec![(0..10).collect::<Vec<_>>(), (0..10).collect()];
        let add = [atom(0, &[Arg::Param(0), Arg::Param(1)])];
        let op = RelOp {
            domains: &domains,
            pos: vec![],
            neg: vec![],
            add: &add,
            del: &[],
            wild_add: &[],
            numeric_effect: false,
            numeric_read: false,
        };
        let goal = Goal { pos: vec![GoalAtom { pred: 0, args: vec![Some(1), Some(2)] }], ..Goal::default() };
        let r = relevant(&[op], &goal, 10);
        let d = r[0].as_ref().unwrap();
        let members = |s: &ObjSet| (0..10).filter(|&o| s.contains(o)).collect::<Vec<_>>();
        assert_eq!(members(&d[0]), [1]);
        assert_eq!(members(&d[1]), [2]);
    }

    #[test]
    fn conditions_chain_and_deletes_of_negative_conditions() {
        // go ?x: pre (ready ?x) (not (blocked ?x)), adds (done ?x);
        // prep ?x adds (ready ?x); unblock ?x deletes (blocked ?x);
        // noise ?x adds (other ?x).
        let d = vec![(0..4).collect::<Vec<_>>()];
        let (done, ready, blocked, other) = (0, 1, 2, 3);
        let p = [Arg::Param(0)];
        let go_pre = [atom(ready, &p)];
        let go_neg = [atom(blocked, &p)];
        let go_add = [atom(done, &p)];
        let prep_add = [atom(ready, &p)];
        let unblock_del = [atom(blocked, &p)];
        let noise_add = [atom(other, &p)];
        let ops = [
            RelOp {
                domains: &d,
                pos: go_pre.iter().collect(),
                neg: go_neg.iter().collect(),
                add: &go_add,
                del: &[],
                wild_add: &[],
                numeric_effect: false,
                numeric_read: false,
            },
            RelOp {
                domains: &d,
                pos: vec![],
                neg: vec![],
                add: &prep_add,
                del: &[],
                wild_add: &[],
                numeric_effect: false,
                numeric_read: false,
            },
            RelOp {
                domains: &d,
                pos: vec![],
                neg: vec![],
                add: &[],
                del: &unblock_del,
                wild_add: &[],
                numeric_effect: false,
                numeric_read: false,
            },
            RelOp {
                domains: &d,
                pos: vec![],
                neg: vec![],
                add: &noise_add,
                del: &[],
                wild_add: &[],
                numeric_effect: true,
                numeric_read: false,
            },
        ];
        let goal = Goal { pos: vec![GoalAtom { pred: done, args: vec![Some(3)] }], ..Goal::default() };
        let r = relevant(&ops, &goal, 4);
        let members =
            |i: usize| r[i].as_ref().map(|d| (0..4).filter(|&o| d[0].contains(o)).collect::<Vec<_>>());
        assert_eq!(members(0), Some(vec![3]));
        assert_eq!(members(1), Some(vec![3]));
        assert_eq!(members(2), Some(vec![3]));
        assert_eq!(members(3), None);
        // A numeric goal makes every operator with a numeric effect relevant.
        let goal = Goal { numeric: true, ..goal };
        let r = relevant(&ops, &goal, 4);
        assert_eq!(r[3].as_ref().map(|d| (0..4).filter(|&o| d[0].contains(o)).count()), Some(4));
    }
}
