//! The forward phase: a progression (state-space) search for problems
//! without a hierarchy, whose plan the partial-order planner then takes
//! over.
//!
//! The partial-order search makes a child per way to support an open link
//! (a hundred new steps for a ZenoTravel fuel level) and expands a few
//! thousand plans a second: on the larger IPC 2002 problems it never gets
//! near a plan. A greedy best-first search over states with FF's relaxed
//! plan heuristic and its helpful actions (Hoffmann and Nebel 2001; lazy
//! evaluation with a second open list of preferred operators, as Fast
//! Downward's lazy greedy search) finds plans there in seconds.
//!
//! - **States**: the atoms that hold and the values of the numeric fluents
//!   the planner follows ([`super::numeric`]); a state met before is not
//!   searched again (the map is by the state's hash, states compared in
//!   full).
//! - **Actions run one after another.** A durative action's `at start`
//!   conditions are checked in the state, its duration computed there (a
//!   duration that reads a fluent, at the start), its start effects
//!   applied (deletions first, then additions, as PDDL 2.1 says), its
//!   `over all` and `at end` conditions checked in the state they leave,
//!   and its end effects applied. Numeric effects are exact (the
//!   validator's evaluator). This is valid for every domain where no
//!   action needs another to run while it does; where one does, this
//!   phase finds no plan and the partial-order search goes on.
//! - **Heuristic**: the relaxed plan of FF (from h_add's best
//!   supporters), over literals (a negative condition is a fact the
//!   initial state or a deletion makes true), with unit costs. A numeric condition that does not hold in the state is a
//!   fact that the actions whose effect on its fluent may make it hold
//!   achieve: an increase for `(>= (fuel a) x)`, an assignment of a value
//!   where it holds (`refuel` to capacity), any effect the analysis cannot
//!   place (`helpers`). Where the relaxed plan uses up more of such a
//!   resource than the state holds (every `navigate` of a relaxed plan
//!   reads the same energy), a producer joins it (`recharge`, with what it
//!   needs). Helpful actions: the relaxed plan's actions applicable in the
//!   state.
//! - **The plan** is turned into a partial-order plan by
//!   `Prepared::forward`: the sequence, with its sequential
//!   times, is the start plan of the partial-order search
//!   ([`super::search::Seed`]): each condition linked to the last step
//!   before it that made it true, threats ordered as in the sequence, the
//!   happenings that touch the same numeric fluent in the sequence's
//!   order. The temporal network then schedules the steps with overlaps,
//!   and the redundant steps go as from any plan.

mod lookahead;

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::hash::Hasher;
use std::time::Instant;

use rustc_hash::FxHashMap;

use super::numeric::{NumCond, NumEff};
use super::output;
use super::search::{End2, Search, Seed, SeedOrder, SeedStep};
use super::stn::EPS;
use super::task::{End, Lit, Task, atom_of, is_neg, negate};
use super::{
    Config, FORWARD_AFTER, FORWARD_ALONE, FORWARD_FIRST, LimitKind, Outcome, PlannerLimits, Prepared,
    Progress, Quality, Stats, Status,
};
use crate::db::Db;
use lookahead::{Ahead, Lookahead};

/// A step of the sequence found: its operator and its times when the
/// actions run one after another, [`EPS`] apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    pub op: u32,
    pub start: f64,
    pub end: f64,
}

/// How the forward search ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Found {
    /// A sequence that reaches the goal.
    Plan(Vec<Step>),
    /// Every state reachable by running actions one after another was
    /// searched (or judged a dead end by the relaxation): no such
    /// sequence. A plan whose actions must overlap may still exist.
    Exhausted,
    Limit(LimitKind),
}

/// Whether the forward search can plan this task: no `:htn`, no abstract
/// action it may insert, no timed initial literals.
pub fn applies(task: &Task<'_>) -> bool {
    task.htn.is_none()
        && task.tils.is_empty()
        && !task.ops.iter().any(|o| o.is_abstract && o.allowed && !o.dead && !o.choice)
}

/// The value stored for an undefined fluent.
const UNDEFINED: u64 = u64::MAX;

/// Not reached, in the relaxation.
const FAR: u32 = u32::MAX;

/// What the forward search expands between two looks at the memory.
const MEMORY_EVERY: u64 = 256;

/// A state: the atoms that hold (a bit each) and every resource's value
/// (its bits, [`UNDEFINED`] when it has none).
#[derive(Clone, PartialEq, Eq, Hash)]
struct State {
    atoms: Box<[u64]>,
    vals: Box<[u64]>,
}

impl State {
    fn has(&self, atom: u32) -> bool {
        self.atoms[(atom / 64) as usize] >> (atom % 64) & 1 == 1
    }

    fn holds(&self, l: Lit) -> bool {
        self.has(atom_of(l)) != is_neg(l)
    }

    fn set(&mut self, l: Lit) {
        let a = atom_of(l);
        let (w, b) = ((a / 64) as usize, a % 64);
        if is_neg(l) {
            self.atoms[w] &= !(1u64 << b);
        } else {
            self.atoms[w] |= 1u64 << b;
        }
    }

    fn value(&self, res: u32) -> Option<f64> {
        match self.vals[res as usize] {
            UNDEFINED => None,
            bits => Some(f64::from_bits(bits)),
        }
    }

    fn set_value(&mut self, res: u32, v: Option<f64>) {
        self.vals[res as usize] = match v {
            // -0.0 and 0.0 are one value.
            Some(x) if !x.is_nan() => (x + 0.0).to_bits(),
            _ => UNDEFINED,
        };
    }

    fn bytes(&self) -> usize {
        8 * (self.atoms.len() + self.vals.len()) + 64
    }
}

/// The ground operators the forward search runs, and its relaxation.
struct Forward<'a, 'db> {
    task: &'a Task<'db>,
    /// The operators it runs (elementary, allowed, not dead), by local id.
    ops: Vec<u32>,
    /// The successor index. By atom: the local operators keyed by that
    /// atom, the one of their positive `at start` conditions that the
    /// fewest operators share (the rarest to hold: on DriverLog's hand-coded
    /// problems the first one, `(at ?truck ?from)`, keyed up to 296 drives,
    /// Depots' `(at ?hoist ?place)` up to 5,000 lifts); `unkeyed`: those
    /// without one.
    keyed: Lists,
    unkeyed: Vec<u32>,
    /// Per local operator: its literal conditions `at start` and
    /// `over all` (checked as it starts), in one array; whether it has
    /// numeric ones `at start`.
    start_lits: Lists,
    num_start: Vec<bool>,
    /// Facts of the relaxation: the literals some condition or goal
    /// needs, then one per group of numeric conditions ([`helpers`]).
    fact_lit: Vec<Lit>,
    n_facts: usize,
    /// By atom: the fact of its positive literal (`FAR`: none); the facts
    /// of negative literals (a state's facts found from its atoms, not by
    /// testing every fact).
    pos_fact: Vec<u32>,
    neg_facts: Vec<u32>,
    /// The relaxation's operators ([`Relaxed`]): local operators, the
    /// stand-ins of groups of them ([`Group`]) and the links of the facts
    /// that hold when any of a set does. Per relaxed operator: the facts
    /// it needs, the numeric conditions it needs at its start (index in
    /// its local operator's `num_conds`, and their fact), the facts it
    /// adds.
    pre: Lists,
    num_pre: Vec<Vec<(u32, u32)>>,
    /// Per relaxed operator: it has numeric conditions.
    numeric: Vec<bool>,
    add: Lists,
    /// Per relaxed operator: what it uses up of the resources that
    /// conditions want high (`(decrease (energy ?r) 8)` where a condition
    /// reads `(>= (energy ?r) 8)`), as (resource, amount).
    uses: Vec<Vec<(u32, f64)>>,
    /// Per resource: the numeric fact of a condition that wants it high
    /// (made by its producers, `recharge`); `FAR`: none.
    producer: Vec<u32>,
    /// Per relaxed operator: what it stands for.
    relaxed_of: Vec<Relaxed>,
    groups: Vec<Group>,
    /// The numeric facts (after the literal ones; the facts "any of a
    /// set" come after them).
    num_facts: std::ops::Range<u32>,
    /// Per fact: the relaxed operators that need it; `no_pre`: the
    /// relaxed operators that need none.
    consumers: Lists,
    no_pre: Vec<u32>,
    goals: Vec<u32>,
    goal_lits: Vec<Lit>,
    /// Per goal (in `goal_lits`' order): the relaxed operators that
    /// undo it; per relaxed operator: the goals it undoes (a group: those
    /// all its members undo).
    goal_deleters: Lists,
    op_del_goals: Lists,
    /// What undoing a goal that holds adds to an operator's cost in the
    /// relaxation: [`UNDO_GOAL`] on a model of [`UNDO_FROM`] operators or
    /// more, else 0.
    undo_cost: u32,
}

/// What an action that undoes a goal holding in the state costs the
/// relaxation beyond its own 1, and the relaxed plan counts one action
/// more for each goal its actions undo. Deletions are what the relaxation
/// drops, and a goal that holds is where that loses most: on IPC 2002
/// DriverLog a truck parked at its goal place with a driver aboard whose
/// goal is elsewhere is driven off by the relaxed plan, which then leaves
/// the driver at once where it wants him (two actions), not counting the
/// truck's way back; getting out and walking (three actions) is what
/// solves the problem. Every such state is a plateau the hill-climbing
/// crosses breadth-first; on the hand-coded problems dozens of them in a
/// row (`time-simple` 2 stalled at an estimate of 26 for 60 s). A goal
/// undone must be made again, at least the way back: `time-simple` and
/// `time` hand-coded 1-10 are all solved with 4 (0.3-7.5 s); of the ten
/// `time-simple` ones, 9 with 3, 5 with 2, 1 without.
const UNDO_GOAL: u32 = 4;

/// The ground operators from which a goal undone costs the relaxation
/// ([`UNDO_GOAL`]): where the lookahead runs too. A goal that holds may
/// have to be undone: ten blocks whose goal towers need a block moved
/// from under a goal already stacked (`towers-hill-climbing-runs-out.pddl`)
/// are then out of the best-first search's reach in 10,000 states, where
/// without it they take 1,736. Below 50,000 operators the forward phase
/// estimates as before (every IPC 2002 problem it solved there is solved).
const UNDO_FROM: usize = GROUP_FROM;

/// Lists of numbers by index, in one array (the relaxation goes through
/// those of a hundred thousand operators per state: one array each, not a
/// vector each, keeps them near in memory).
struct Lists {
    starts: Vec<u32>,
    items: Vec<u32>,
}

impl Lists {
    fn new(lists: Vec<Vec<u32>>) -> Lists {
        let mut starts = Vec::with_capacity(lists.len() + 1);
        let mut items = Vec::with_capacity(lists.iter().map(Vec::len).sum());
        starts.push(0);
        for l in lists {
            items.extend(l);
            starts.push(items.len() as u32);
        }
        Lists { starts, items }
    }

    fn get(&self, i: usize) -> &[u32] {
        &self.items[self.starts[i] as usize..self.starts[i + 1] as usize]
    }

    fn len_of(&self, i: usize) -> u32 {
        self.starts[i + 1] - self.starts[i]
    }
}

/// What an operator of the relaxation stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Relaxed {
    /// A local operator.
    Op(u32),
    /// The operators of a [`Group`], by index: it needs their common
    /// facts and the group's fact "any of", adds what they add, and is
    /// one action of a relaxed plan, the one whose own fact is the
    /// cheapest.
    Group(u32),
    /// A link: it needs one fact of a set and adds the fact "any of" the
    /// set, at no cost (no action of a relaxed plan).
    Any,
}

/// Local operators that need the same facts but one each and add the same
/// facts (DriverLog's `drive-truck` of a truck between two places, one
/// per driver: 20 where the condition that differs is `(driving ?d
/// ?truck)`): to the relaxation they are one operator that needs "any of"
/// their own facts (shared by the groups of every pair of places), which
/// costs the cheapest of them. The estimates and relaxed plans are those
/// of the operators one by one (up to ties), through a twentieth of them.
struct Group {
    /// The fact "any of" the members' facts.
    any: u32,
    /// The members: their own fact and local operator, by fact.
    members: Vec<(u32, u32)>,
}

/// The ground operators from which the relaxation groups operators
/// ([`Group`]): where its cost per state is what the search spends
/// (DriverLog's hand-coded problems, 100,000 and more). Below, the ties
/// of the relaxed plans stay those of the operators one by one: on Rovers
/// `time-simple` hand-coded 10 (4,261 operators, its communications
/// grouped by the rover's place) the hill-climbing, whose relaxed plans
/// then break ties otherwise, needed more than 1,000 states (818).
const GROUP_FROM: usize = 50_000;

/// The smallest group worth its links: a set "any of" is kept when the
/// operators of its groups outnumber its links and the groups' stand-ins.
const MIN_GROUP: usize = 2;

/// The relaxation's operators: the local operators' facts needed
/// (`pre`), added (`add`) and numeric conditions (`num_pre`), with groups
/// of them made one ([`Group`]). Returns the relaxed operators' lists,
/// what each stands for, the groups, and the number of facts with the
/// facts "any of" (from `n_facts`).
#[allow(clippy::type_complexity)]
fn group_operators(
    pre: Vec<Vec<u32>>,
    add: Vec<Vec<u32>>,
    num_pre: Vec<Vec<(u32, u32)>>,
    n_facts: usize,
    grouping: bool,
) -> (Vec<Vec<u32>>, Vec<Vec<u32>>, Vec<Vec<(u32, u32)>>, Vec<Relaxed>, Vec<Group>, usize) {
    let n = pre.len();
    // Candidate groups: by the facts added and the facts needed but one,
    // sorted by the hash of these (a vector of them per operator and
    // condition held 90 MB more on Depots `time-simple` hand-coded 2), the
    // operators of one hash then compared.
    let key_of = |k: usize, own: u32| -> Vec<u32> {
        let mut key = add[k].clone();
        key.push(FAR);
        key.extend(pre[k].iter().copied().filter(|&f| f != own));
        key
    };
    let mut by_hash: Vec<(u64, u32, u32)> = Vec::new();
    for k in 0..n {
        if !grouping || !num_pre[k].is_empty() || pre[k].is_empty() {
            continue;
        }
        for &own in &pre[k] {
            let mut h = rustc_hash::FxHasher::default();
            for &f in add[k].iter().chain([FAR].iter()).chain(pre[k].iter().filter(|&&f| f != own)) {
                h.write_u32(f);
            }
            by_hash.push((h.finish(), own, k as u32));
        }
    }
    by_hash.sort_unstable();
    let mut cands: Vec<(Vec<u32>, Vec<(u32, u32)>)> = Vec::new();
    for run in by_hash.chunk_by(|a, b| a.0 == b.0).filter(|r| r.len() >= MIN_GROUP) {
        let mut left: Vec<(u32, u32)> = run.iter().map(|e| (e.1, e.2)).collect();
        while left.len() >= MIN_GROUP {
            let key = key_of(left[0].1 as usize, left[0].0);
            let (mut m, rest): (Vec<_>, Vec<_>) =
                left.into_iter().partition(|e| key_of(e.1 as usize, e.0) == key);
            left = rest;
            // Operators that need and add the same facts are one to the
            // relaxation: the first (the others stay as they are).
            m.dedup_by_key(|e| e.0);
            if m.len() >= MIN_GROUP {
                cands.push((key, m));
            }
        }
    }
    // What each set "any of" would save: the operators of its groups, less
    // its links and the stand-ins.
    let set_of = |m: &[(u32, u32)]| -> Vec<u32> { m.iter().map(|e| e.0).collect() };
    let mut gain: FxHashMap<Vec<u32>, i64> = FxHashMap::default();
    for (_, m) in &cands {
        let g = gain.entry(set_of(m)).or_insert(-(m.len() as i64));
        *g += m.len() as i64 - 1;
    }
    cands.sort_by_cached_key(|(key, m)| (Reverse(gain[&set_of(m)]), Reverse(m.len()), key.clone()));
    let mut taken = vec![false; n];
    let mut chosen: Vec<(Vec<u32>, Vec<(u32, u32)>)> = Vec::new();
    for (key, m) in cands {
        if gain[&set_of(&m)] <= 0 || m.iter().any(|e| taken[e.1 as usize]) {
            continue;
        }
        for e in &m {
            taken[e.1 as usize] = true;
        }
        chosen.push((key, m));
    }
    let mut r_pre = Vec::with_capacity(n);
    let mut r_add = Vec::with_capacity(n);
    let mut r_num = Vec::with_capacity(n);
    let mut relaxed_of = Vec::with_capacity(n);
    let mut in_group = vec![false; n];
    for (_, m) in &chosen {
        for e in m {
            in_group[e.1 as usize] = true;
        }
    }
    // Operators not in a group, as they are (a duplicate of a member,
    // left out of its group, stays).
    for (k, ((p, a), np)) in pre.into_iter().zip(add).zip(num_pre).enumerate() {
        if in_group[k] {
            continue;
        }
        r_pre.push(p);
        r_add.push(a);
        r_num.push(np);
        relaxed_of.push(Relaxed::Op(k as u32));
    }
    let mut any_of: FxHashMap<Vec<u32>, u32> = FxHashMap::default();
    let mut n_facts = n_facts;
    let mut groups = Vec::with_capacity(chosen.len());
    for (key, m) in chosen {
        let set = set_of(&m);
        let any = match any_of.get(&set) {
            Some(&f) => f,
            None => {
                let f = n_facts as u32;
                n_facts += 1;
                for &member in &set {
                    r_pre.push(vec![member]);
                    r_add.push(vec![f]);
                    r_num.push(Vec::new());
                    relaxed_of.push(Relaxed::Any);
                }
                any_of.insert(set, f);
                f
            }
        };
        let split = key.iter().position(|&f| f == FAR).unwrap_or(key.len());
        let mut p: Vec<u32> = key[split + 1..].to_vec();
        p.push(any);
        p.sort_unstable();
        r_pre.push(p);
        r_add.push(key[..split].to_vec());
        r_num.push(Vec::new());
        relaxed_of.push(Relaxed::Group(groups.len() as u32));
        groups.push(Group { any, members: m });
    }
    (r_pre, r_add, r_num, relaxed_of, groups, n_facts)
}

/// The work arrays of the relaxed plans: a fact's cost and achiever, an
/// operator's conditions left and cost, valid when their stamp is the
/// call's.
struct Scratch {
    stamp: u32,
    fact_stamp: Vec<u32>,
    /// Per operator: what the relaxation reads and writes of it, side by
    /// side ([`OpWork`]).
    work: Vec<OpWork>,
    cost: Vec<u32>,
    achiever: Vec<u32>,
    waiting: Vec<u32>,
    /// Per operator: its numeric facts that did not hold in the state
    /// (`touched`: the operators with some).
    unmet: Vec<Vec<u32>>,
    touched: Vec<u32>,
    /// Per numeric fact: the operators waiting for it (`waited`: the
    /// facts with some).
    waiters: Vec<Vec<u32>>,
    waited: Vec<u32>,
    /// h_add: a fact's cost is final (popped), per stamp.
    done_stamp: Vec<u32>,
    /// Marked in the relaxed plan: the complement of the call's stamp.
    marked_op: Vec<u32>,
    marked_fact: Vec<u32>,
    /// The queue of facts by cost, the operators whose conditions are all
    /// reached, the relaxed plan's stack: kept from call to call (their
    /// memory allocated once, not per state).
    heap: BinaryHeap<Reverse<(u32, u32)>>,
    ready: Vec<(u32, u32)>,
    stack: Vec<u32>,
    /// Per resource: what the relaxed plan uses up of it (`used_res`: the
    /// resources with some), zero between calls.
    used: Vec<f64>,
    used_res: Vec<u32>,
    /// The last relaxed plan: its actions (relaxed operators, not the
    /// free links) with each fact the plan needs from them, in the order
    /// of the extraction ([`lookahead`]).
    plan: Vec<(u32, u32)>,
    /// Per relaxed operator: what undoing goals that hold in the state
    /// adds to its cost ([`UNDO_GOAL`] each; valid when `undo_stamp` is
    /// the call's); per goal: counted in the relaxed plan (the call's
    /// stamp).
    undo_stamp: Vec<u32>,
    undo: Vec<u32>,
    goal_mark: Vec<u32>,
}

impl Scratch {
    /// What undoing goals adds to operator `k`'s cost in the call of `stamp`.
    #[inline]
    fn undo_of(&self, k: u32, stamp: u32) -> u32 {
        if self.undo_stamp[k as usize] == stamp { self.undo[k as usize] } else { 0 }
    }
}

/// An operator in the relaxation: its work, valid when `stamp` is the
/// call's (its conditions left, the sum of their costs so far, its cost),
/// and what it needs and adds, in 32 bytes. The relaxation reaches a
/// hundred thousand operators per state in no order: one cache line each,
/// not one per array (on Depots `time-simple` hand-coded problem 2 the
/// loads of the separate arrays were most of its time).
#[derive(Clone, Copy, Default)]
struct OpWork {
    stamp: u32,
    counter: u32,
    sum: u32,
    cost: u32,
    /// Its literal facts needed.
    npre: u32,
    /// The number of facts it adds, and [`NUMERIC`].
    info: u32,
    /// The facts it adds when they are at most two (else in `add`).
    add: [u32; 2],
}

/// In [`OpWork::info`]: the operator has numeric conditions.
const NUMERIC: u32 = 1 << 31;

/// In [`OpWork::info`]: the operator costs nothing ([`Relaxed::Any`]).
const FREE: u32 = 1 << 30;

impl<'a, 'db> Forward<'a, 'db> {
    fn new(task: &'a Task<'db>) -> Forward<'a, 'db> {
        Forward::build(task, task.ops.len() >= GROUP_FROM)
    }

    /// The forward search's model of `task`, its relaxation with groups
    /// of operators made one ([`Group`]) or not.
    fn build(task: &'a Task<'db>, grouping: bool) -> Forward<'a, 'db> {
        let ops: Vec<u32> = (0..task.ops.len() as u32)
            .filter(|&o| {
                let op = &task.ops[o as usize];
                !op.is_abstract && op.allowed && !op.dead
            })
            .collect();
        let n_atoms = task.init.len();
        let mut start_lits = Vec::with_capacity(ops.len());
        let mut shared = vec![0u32; n_atoms];
        for &o in &ops {
            let op = &task.ops[o as usize];
            let mut l: Vec<u32> = op.conds.iter().filter(|c| c.at == End::Start).map(|c| c.lit).collect();
            l.sort_unstable();
            l.dedup();
            for &c in l.iter().filter(|&&c| !is_neg(c)) {
                shared[atom_of(c) as usize] += 1;
            }
            start_lits.push(l);
        }
        let mut keyed = vec![Vec::new(); n_atoms];
        let mut unkeyed = Vec::new();
        for (k, l) in start_lits.iter().enumerate() {
            // The first of the rarest, for a deterministic choice.
            match l
                .iter()
                .filter(|&&c| !is_neg(c))
                .map(|&c| atom_of(c))
                .min_by_key(|&a| (shared[a as usize], a))
            {
                Some(a) => keyed[a as usize].push(k as u32),
                None => unkeyed.push(k as u32),
            }
        }
        let num_start =
            ops.iter().map(|&o| task.ops[o as usize].num_conds.iter().any(|c| c.at == End::Start)).collect();
        let (keyed, start_lits) = (Lists::new(keyed), Lists::new(start_lits));
        // The literal facts.
        let mut fact_of: FxHashMap<Lit, u32> = FxHashMap::default();
        let mut fact_lit = Vec::new();
        let mut fact = |l: Lit, fact_lit: &mut Vec<Lit>| -> u32 {
            *fact_of.entry(l).or_insert_with(|| {
                fact_lit.push(l);
                (fact_lit.len() - 1) as u32
            })
        };
        let mut pre = Vec::with_capacity(ops.len());
        for &o in &ops {
            let op = &task.ops[o as usize];
            let mut p: Vec<u32> = Vec::new();
            for c in &op.conds {
                // A condition at the end that the action's own start makes
                // true is no precondition of the relaxed action.
                let own = c.at == End::End && op.effs.iter().any(|e| e.at == End::Start && e.lit == c.lit);
                if !own {
                    p.push(fact(c.lit, &mut fact_lit));
                }
            }
            p.sort_unstable();
            p.dedup();
            pre.push(p);
        }
        let goal_lits: Vec<Lit> = task.goals.iter().map(|g| g.0).collect();
        let mut goals: Vec<u32> = goal_lits.iter().map(|&l| fact(l, &mut fact_lit)).collect();
        goals.sort_unstable();
        goals.dedup();
        let n_lits = fact_lit.len();
        let mut add: Vec<Vec<u32>> = ops
            .iter()
            .map(|&o| {
                let mut a: Vec<u32> =
                    task.ops[o as usize].effs.iter().filter_map(|e| fact_of.get(&e.lit).copied()).collect();
                a.sort_unstable();
                a.dedup();
                a
            })
            .collect();
        // The numeric facts: one per resource and set of operators that
        // may make a condition on it hold.
        let local: FxHashMap<u32, u32> = ops.iter().enumerate().map(|(k, &o)| (o, k as u32)).collect();
        let mut groups: FxHashMap<(u32, Vec<u32>), u32> = FxHashMap::default();
        let mut n_facts = n_lits;
        let mut num_pre = Vec::with_capacity(ops.len());
        for &o in &ops {
            let op = &task.ops[o as usize];
            let mut np = Vec::new();
            for (ci, c) in op.num_conds.iter().enumerate() {
                // At the end, after a start effect on the same fluent: left
                // to the search's own check.
                if c.at == End::End && op.num_effs.iter().any(|e| e.at == End::Start && e.res == c.res) {
                    continue;
                }
                let mut hs: Vec<u32> =
                    helpers(task, c).into_iter().filter_map(|h| local.get(&h).copied()).collect();
                hs.sort_unstable();
                hs.dedup();
                let id = *groups.entry((c.res, hs)).or_insert_with(|| {
                    n_facts += 1;
                    (n_facts - 1) as u32
                });
                np.push((ci as u32, id));
            }
            num_pre.push(np);
        }
        for ((_, hs), id) in &groups {
            for &h in hs {
                add[h as usize].push(*id);
            }
        }
        let (uses, producer) = uses_and_producers(task, &ops, &num_pre);
        let num_facts = n_lits as u32..n_facts as u32;
        let (pre, add, num_pre, relaxed_of, groups, n_facts) =
            group_operators(pre, add, num_pre, n_facts, grouping);
        // What a relaxed operator uses up: its local operator's; a group's,
        // its first member's (the members differ by a condition only).
        let uses = relaxed_of
            .iter()
            .map(|r| match *r {
                Relaxed::Op(k) => uses[k as usize].clone(),
                Relaxed::Group(g) => uses[groups[g as usize].members[0].1 as usize].clone(),
                Relaxed::Any => Vec::new(),
            })
            .collect();
        let mut consumers = vec![Vec::new(); n_facts];
        for (k, p) in pre.iter().enumerate() {
            for &f in p {
                consumers[f as usize].push(k as u32);
            }
        }
        let no_pre = (0..pre.len() as u32).filter(|&k| pre[k as usize].is_empty()).collect();
        let mut pos_fact = vec![FAR; n_atoms];
        let mut neg_facts = Vec::new();
        for (f, &l) in fact_lit.iter().enumerate() {
            if is_neg(l) {
                neg_facts.push(f as u32);
            } else {
                pos_fact[atom_of(l) as usize] = f as u32;
            }
        }
        let numeric = num_pre.iter().map(|n| !n.is_empty()).collect();
        let (pre, add, consumers) = (Lists::new(pre), Lists::new(add), Lists::new(consumers));
        // The goals each local operator undoes.
        let mut goals_of_lit: FxHashMap<Lit, Vec<u32>> = FxHashMap::default();
        for (i, &l) in goal_lits.iter().enumerate() {
            goals_of_lit.entry(l).or_default().push(i as u32);
        }
        let local_del: Vec<Vec<u32>> = ops
            .iter()
            .map(|&o| {
                let mut d: Vec<u32> = task.ops[o as usize]
                    .effs
                    .iter()
                    .filter_map(|e| goals_of_lit.get(&negate(e.lit)))
                    .flatten()
                    .copied()
                    .collect();
                d.sort_unstable();
                d.dedup();
                d
            })
            .collect();
        let op_del_goals: Vec<Vec<u32>> = relaxed_of
            .iter()
            .map(|r| match *r {
                Relaxed::Op(k) => local_del[k as usize].clone(),
                Relaxed::Group(g) => {
                    let m = &groups[g as usize].members;
                    let first = &local_del[m[0].1 as usize];
                    first
                        .iter()
                        .copied()
                        .filter(|i| m.iter().all(|x| local_del[x.1 as usize].contains(i)))
                        .collect()
                }
                Relaxed::Any => Vec::new(),
            })
            .collect();
        let mut goal_deleters = vec![Vec::new(); goal_lits.len()];
        for (k, d) in op_del_goals.iter().enumerate() {
            for &i in d {
                goal_deleters[i as usize].push(k as u32);
            }
        }
        let (goal_deleters, op_del_goals) = (Lists::new(goal_deleters), Lists::new(op_del_goals));
        Forward {
            goal_deleters,
            op_del_goals,
            undo_cost: if ops.len() >= UNDO_FROM { UNDO_GOAL } else { 0 },
            task,
            no_pre,
            numeric,
            ops,
            keyed,
            unkeyed,
            start_lits,
            num_start,
            fact_lit,
            n_facts,
            pos_fact,
            neg_facts,
            pre,
            num_pre,
            add,
            uses,
            producer,
            relaxed_of,
            groups,
            num_facts,
            consumers,
            goals,
            goal_lits,
        }
    }

    fn scratch(&self) -> Scratch {
        Scratch {
            stamp: 0,
            fact_stamp: vec![0; self.n_facts],
            work: (0..self.relaxed_of.len())
                .map(|k| {
                    let add = self.add.get(k);
                    let mut inline = [FAR; 2];
                    if add.len() <= 2 {
                        inline[..add.len()].copy_from_slice(add);
                    }
                    let flags = if self.numeric[k] { NUMERIC } else { 0 }
                        | if self.relaxed_of[k] == Relaxed::Any { FREE } else { 0 };
                    OpWork {
                        npre: self.pre.len_of(k),
                        info: add.len() as u32 | flags,
                        add: inline,
                        ..OpWork::default()
                    }
                })
                .collect(),
            cost: vec![FAR; self.n_facts],
            achiever: vec![FAR; self.n_facts],
            waiting: vec![0; self.relaxed_of.len()],
            unmet: vec![Vec::new(); self.relaxed_of.len()],
            touched: Vec::new(),
            waiters: vec![Vec::new(); self.n_facts],
            waited: Vec::new(),
            marked_op: vec![0; self.relaxed_of.len()],
            marked_fact: vec![0; self.n_facts],
            done_stamp: vec![0; self.n_facts],
            heap: BinaryHeap::new(),
            ready: Vec::new(),
            stack: Vec::new(),
            used: vec![0.0; self.task.numeric.keys.len()],
            used_res: Vec::new(),
            plan: Vec::new(),
            undo_stamp: vec![0; self.relaxed_of.len()],
            undo: vec![0; self.relaxed_of.len()],
            goal_mark: vec![0; self.goal_lits.len()],
        }
    }

    fn initial(&self) -> State {
        let task = self.task;
        let mut s = State {
            atoms: vec![0u64; task.init.len().div_ceil(64)].into_boxed_slice(),
            vals: vec![UNDEFINED; task.numeric.keys.len()].into_boxed_slice(),
        };
        for (a, &holds) in task.init.iter().enumerate() {
            if holds {
                s.set(super::task::lit(a as u32, false));
            }
        }
        for (r, v) in task.numeric.init.iter().enumerate() {
            s.set_value(r as u32, *v);
        }
        s
    }

    fn is_goal(&self, s: &State) -> bool {
        self.goal_lits.iter().all(|&l| s.holds(l))
    }

    fn num_holds(&self, s: &State, c: &NumCond<'_>) -> bool {
        self.task.numeric.holds(self.task, c, s.value(c.res))
    }

    /// Whether local operator `k` may start in `s`: its `at start`
    /// conditions hold there (the rest is checked by [`Forward::apply`]).
    fn may_start(&self, s: &State, k: u32) -> bool {
        self.start_lits.get(k as usize).iter().all(|&l| s.holds(l))
            && (!self.num_start[k as usize] || {
                let op = &self.task.ops[self.ops[k as usize] as usize];
                op.num_conds.iter().all(|c| c.at == End::End || self.num_holds(s, c))
            })
    }

    /// The state after local operator `k` runs alone from `s`, and its
    /// duration; `None` when it cannot run there.
    #[inline(never)]
    fn apply(&self, s: &State, k: u32) -> Option<(State, f64)> {
        let task = self.task;
        let num = &task.numeric;
        let op = &task.ops[self.ops[k as usize] as usize];
        if !self.may_start(s, k) {
            return None;
        }
        let duration = match &op.num_duration {
            Some(d) => num.duration(task, d, s.value(d.res))?,
            None => op.duration?,
        };
        let mut t = s.clone();
        for at in [End::Start, End::End] {
            if at == End::End {
                // `over all` and `at end` conditions, after the start.
                let end_ok =
                    op.conds.iter().all(|c| (c.at == End::Start && c.until == End::Start) || t.holds(c.lit))
                        && op.num_conds.iter().all(|c| c.at == End::Start || self.num_holds(&t, c));
                if !end_ok {
                    return None;
                }
            }
            for e in op.num_effs.iter().filter(|e| e.at == at) {
                let v = num.apply(task, e, t.value(e.res), Some(duration))?;
                t.set_value(e.res, Some(v));
            }
            for e in op.effs.iter().filter(|e| e.at == at && is_neg(e.lit)) {
                t.set(e.lit);
            }
            for e in op.effs.iter().filter(|e| e.at == at && !is_neg(e.lit)) {
                t.set(e.lit);
            }
        }
        Some((t, duration))
    }

    /// The local operators that may start in `s`, by number (the order
    /// of the search's ties, whatever the index).
    #[inline(never)]
    fn successors(&self, s: &State, out: &mut Vec<u32>) {
        out.clear();
        for (w, &word) in s.atoms.iter().enumerate() {
            let mut bits = word;
            while bits != 0 {
                let b = bits.trailing_zeros();
                bits &= bits - 1;
                let atom = w * 64 + b as usize;
                out.extend(self.keyed.get(atom).iter().copied().filter(|&k| self.may_start(s, k)));
            }
        }
        out.extend(self.unkeyed.iter().copied().filter(|&k| self.may_start(s, k)));
        out.sort_unstable();
    }

    /// How many operators [`Forward::successors`] tests in `s`.
    #[cfg(test)]
    fn tested(&self, s: &State) -> usize {
        (0..self.task.init.len()).filter(|&a| s.has(a as u32)).map(|a| self.keyed.get(a).len()).sum::<usize>()
            + self.unkeyed.len()
    }

    /// FF's estimate of `s`: the actions of a relaxed plan to the goal,
    /// and those of them that may start in `s` (helpful); `None` when the
    /// relaxation reaches no goal (a dead end). Facts are reached in the
    /// order of their h_add cost (unit action costs) and each one's
    /// achiever is its cheapest (h_add's best supporters, as Fast
    /// Downward's FF heuristic): with the first achiever of a layered
    /// graph instead, Depots `time-simple` automatic problem 8 took 4,867
    /// states (215 now), hand-coded problem 1 more than 7,000 (1,605).
    /// The work arrays are stamped per call: a call touches what it
    /// reaches, not every operator of the task.
    #[inline(never)]
    fn relaxed(&self, s: &State, x: &mut Scratch, helpful: &mut Vec<u32>) -> Option<u32> {
        helpful.clear();
        x.stamp = x.stamp.wrapping_add(1);
        if x.stamp == 0 {
            x.fact_stamp.fill(0);
            for w in &mut x.work {
                w.stamp = 0;
            }
            x.done_stamp.fill(0);
            x.undo_stamp.fill(0);
            x.goal_mark.fill(0);
            x.stamp = 1;
        }
        let stamp = x.stamp;
        for &o in &x.touched {
            x.unmet[o as usize].clear();
        }
        x.touched.clear();
        for &f in &x.waited {
            x.waiters[f as usize].clear();
        }
        x.waited.clear();
        // A fact's cost, an operator's cost (its conditions' and 1).
        let mut heap = std::mem::take(&mut x.heap);
        heap.clear();
        // The facts of the state (the order of the pushes does not
        // matter: facts of one cost leave the queue by number).
        let mut hold = |f: u32| {
            x.fact_stamp[f as usize] = stamp;
            x.cost[f as usize] = 0;
            heap.push(Reverse((0, f)));
        };
        for (w, &word) in s.atoms.iter().enumerate() {
            let mut bits = word;
            while bits != 0 {
                let b = bits.trailing_zeros();
                bits &= bits - 1;
                let f = self.pos_fact[w * 64 + b as usize];
                if f != FAR {
                    hold(f);
                }
            }
        }
        for &f in &self.neg_facts {
            if s.holds(self.fact_lit[f as usize]) {
                hold(f);
            }
        }
        if self.undo_cost > 0 {
            for (i, &l) in self.goal_lits.iter().enumerate() {
                if s.holds(l) {
                    for &k in self.goal_deleters.get(i) {
                        if x.undo_stamp[k as usize] != stamp {
                            x.undo_stamp[k as usize] = stamp;
                            x.undo[k as usize] = 0;
                        }
                        x.undo[k as usize] += self.undo_cost;
                    }
                }
            }
        }
        let mut goals_left = self.goals.len();
        let mut ready = std::mem::take(&mut x.ready);
        ready.clear();
        ready.extend(self.no_pre.iter().map(|&k| (k, 0)));
        let reached = loop {
            // Operators whose conditions are all reached: their numeric
            // conditions, then their effects.
            while let Some((k, base)) = ready.pop() {
                let mut extra = 0u32;
                let w = x.work[k as usize];
                if w.info & NUMERIC != 0 {
                    let Relaxed::Op(local) = self.relaxed_of[k as usize] else {
                        unreachable!("grouped numeric")
                    };
                    let op = &self.task.ops[self.ops[local as usize] as usize];
                    let mut unmet = std::mem::take(&mut x.unmet[k as usize]);
                    let mut waiting = Vec::new();
                    for &(ci, f) in &self.num_pre[k as usize] {
                        if self.num_holds(s, &op.num_conds[ci as usize]) {
                            continue;
                        }
                        unmet.push(f);
                        if x.done_stamp[f as usize] == stamp {
                            extra += x.cost[f as usize];
                        } else {
                            waiting.push(f);
                        }
                    }
                    unmet.sort_unstable();
                    unmet.dedup();
                    waiting.sort_unstable();
                    waiting.dedup();
                    if !unmet.is_empty() {
                        x.touched.push(k);
                    }
                    x.unmet[k as usize] = unmet;
                    if !waiting.is_empty() {
                        x.waiting[k as usize] = waiting.len() as u32;
                        x.work[k as usize].sum = base + extra;
                        for &f in &waiting {
                            if x.waiters[f as usize].is_empty() {
                                x.waited.push(f);
                            }
                            x.waiters[f as usize].push(k);
                        }
                        continue;
                    }
                }
                let undo = x.undo_of(k, stamp);
                let c = base + extra + u32::from(w.info & FREE == 0) + undo;
                x.work[k as usize].cost = c;
                let n_add = (w.info & !(NUMERIC | FREE)) as usize;
                let adds = if n_add <= 2 { &w.add[..n_add] } else { self.add.get(k as usize) };
                for &f in adds {
                    if x.fact_stamp[f as usize] != stamp || c < x.cost[f as usize] {
                        x.fact_stamp[f as usize] = stamp;
                        x.cost[f as usize] = c;
                        x.achiever[f as usize] = k;
                        heap.push(Reverse((c, f)));
                    }
                }
            }
            let Some(Reverse((c, f))) = heap.pop() else { break false };
            if x.done_stamp[f as usize] == stamp || c > x.cost[f as usize] {
                continue;
            }
            x.done_stamp[f as usize] = stamp;
            if self.goals.binary_search(&f).is_ok() {
                goals_left -= 1;
                if goals_left == 0 {
                    break true;
                }
            }
            if !self.num_facts.contains(&f) {
                for &k in self.consumers.get(f as usize) {
                    let w = &mut x.work[k as usize];
                    if w.stamp != stamp {
                        w.stamp = stamp;
                        w.counter = w.npre;
                        w.sum = 0;
                    }
                    w.counter -= 1;
                    w.sum += c;
                    if w.counter == 0 {
                        ready.push((k, w.sum));
                    }
                }
            } else {
                let waiters = std::mem::take(&mut x.waiters[f as usize]);
                for &k in &waiters {
                    x.waiting[k as usize] -= 1;
                    x.work[k as usize].sum += c;
                    if x.waiting[k as usize] == 0 {
                        let undo = x.undo_of(k, stamp);
                        let c = x.work[k as usize].sum + 1 + undo;
                        x.work[k as usize].cost = c;
                        for &g in self.add.get(k as usize) {
                            if x.fact_stamp[g as usize] != stamp || c < x.cost[g as usize] {
                                x.fact_stamp[g as usize] = stamp;
                                x.cost[g as usize] = c;
                                x.achiever[g as usize] = k;
                                heap.push(Reverse((c, g)));
                            }
                        }
                    }
                }
                x.waiters[f as usize] = waiters;
            }
        };
        x.heap = heap;
        x.ready = ready;
        if !reached {
            return None;
        }
        let mark = !stamp;
        let mut stack = std::mem::take(&mut x.stack);
        stack.clear();
        stack.extend(self.goals.iter().copied().filter(|&g| x.cost[g as usize] > 0));
        let mut h = 0;
        let mut used_res = std::mem::take(&mut x.used_res);
        used_res.clear();
        let mut adjusted = false;
        x.plan.clear();
        loop {
            while let Some(f) = stack.pop() {
                if std::mem::replace(&mut x.marked_fact[f as usize], mark) == mark {
                    continue;
                }
                let k = x.achiever[f as usize];
                let w = x.work[k as usize];
                if w.info & FREE == 0 {
                    x.plan.push((k, f));
                }
                if std::mem::replace(&mut x.marked_op[k as usize], mark) == mark {
                    continue;
                }
                if w.info & FREE == 0 {
                    h += 1;
                    let undo = x.undo_of(k, stamp);
                    if undo > 0 {
                        for &i in self.op_del_goals.get(k as usize) {
                            if s.holds(self.goal_lits[i as usize])
                                && std::mem::replace(&mut x.goal_mark[i as usize], stamp) != stamp
                            {
                                h += 1;
                            }
                        }
                    }
                    if w.cost == 1 + undo {
                        helpful.push(match self.relaxed_of[k as usize] {
                            Relaxed::Op(local) => local,
                            // The member whose own fact holds.
                            Relaxed::Group(g) => {
                                let group = &self.groups[g as usize];
                                let link = x.achiever[group.any as usize];
                                let own = self.pre.get(link as usize)[0];
                                let i = group.members.partition_point(|m| m.0 < own);
                                group.members[i].1
                            }
                            Relaxed::Any => unreachable!(),
                        });
                    }
                }
                stack.extend(self.pre.get(k as usize).iter().copied().filter(|&p| x.cost[p as usize] > 0));
                if self.numeric[k as usize] {
                    stack.extend(x.unmet[k as usize].iter().copied());
                }
                for &(res, amount) in &self.uses[k as usize] {
                    if x.used[res as usize] == 0.0 {
                        used_res.push(res);
                    }
                    x.used[res as usize] += amount;
                }
            }
            if adjusted || used_res.is_empty() {
                break;
            }
            // The resources the relaxed plan uses up beyond what the state
            // holds: their producer (`recharge`, and what it needs) joins
            // the plan, once (the relaxation alone lets every `navigate` read
            // the same energy; Sapa's resource adjustment, Do and
            // Kambhampati 2003). A producer the relaxation did not reach
            // counts one action.
            adjusted = true;
            for &res in &used_res {
                let f = self.producer[res as usize];
                let have = s.value(res).unwrap_or(0.0);
                if x.used[res as usize] <= have + 1e-9 || f == FAR || x.marked_fact[f as usize] == mark {
                    continue;
                }
                if x.fact_stamp[f as usize] == stamp {
                    stack.push(f);
                } else {
                    h += 1;
                }
            }
        }
        for &res in &used_res {
            x.used[res as usize] = 0.0;
        }
        x.used_res = used_res;
        x.stack = stack;
        Some(h)
    }
}

/// Values far from any a condition compares with, and a probe value: a
/// condition that holds far above and not far below wants its fluent high;
/// an effect is additive when it moves 0 and the probe by the same amount.
const FAR_VALUE: f64 = 1e12;
const PROBE: f64 = 1000.0;

/// Whether condition `c` holds with its fluent far above, and far below.
fn holds_far(task: &Task<'_>, c: &NumCond<'_>) -> (bool, bool) {
    let num = &task.numeric;
    (num.holds(task, c, Some(FAR_VALUE)), num.holds(task, c, Some(-FAR_VALUE)))
}

/// Effect `e`'s value from 0 and from [`PROBE`], for a step of `duration`.
fn probe(task: &Task<'_>, e: &NumEff<'_>, duration: Option<f64>) -> (Option<f64>, Option<f64>) {
    let num = &task.numeric;
    (num.apply(task, e, Some(0.0), duration), num.apply(task, e, Some(PROBE), duration))
}

/// Whether an effect that leaves `a` from 0 and `b` from [`PROBE`] adds
/// the same amount to both (`a`).
fn additive(a: f64, b: f64) -> bool {
    ((b - PROBE) - a).abs() <= 1e-9 * (1.0 + a.abs())
}

/// What each local operator uses up of the resources that some condition
/// wants high (a constant `decrease`, or one read from fluents no action
/// writes: `(decrease (fuel ?a) (* (distance ?c1 ?c2) (slow-burn ?a)))`),
/// and per resource the numeric fact of such a condition (`FAR`: none).
fn uses_and_producers(
    task: &Task<'_>,
    ops: &[u32],
    num_pre: &[Vec<(u32, u32)>],
) -> (Vec<Vec<(u32, f64)>>, Vec<u32>) {
    let num = &task.numeric;
    let mut producer = vec![FAR; num.keys.len()];
    for (k, np) in num_pre.iter().enumerate() {
        let op = &task.ops[ops[k] as usize];
        for &(ci, f) in np {
            let c = &op.num_conds[ci as usize];
            let (up, down) = holds_far(task, c);
            if up && !down && producer[c.res as usize] == FAR {
                producer[c.res as usize] = f;
            }
        }
    }
    let uses = ops
        .iter()
        .map(|&o| {
            let op = &task.ops[o as usize];
            op.num_effs
                .iter()
                .filter(|e| producer[e.res as usize] != FAR)
                .filter_map(|e| match probe(task, e, op.duration) {
                    (Some(a), Some(b)) if additive(a, b) && a < 0.0 => Some((e.res, -a)),
                    _ => None,
                })
                .collect()
        })
        .collect();
    (uses, producer)
}

/// The operators that may make numeric condition `c` hold where it does
/// not: those with an effect on its fluent that goes the way the
/// condition wants (an increase for `(>= (fuel a) x)`), that assigns a
/// value where it holds, or that the analysis cannot place (an effect
/// neither additive nor an assignment of a constant, or one it cannot
/// evaluate). A condition that holds neither far above nor far below
/// (an equality) takes every writer.
fn helpers(task: &Task<'_>, c: &NumCond<'_>) -> Vec<u32> {
    let num = &task.numeric;
    let (up, down) = holds_far(task, c);
    let monotone = up != down;
    let mut out = Vec::new();
    let Some(writers) = num.writers.get(c.res as usize) else { return out };
    for &w in writers {
        let helps = task.ops[w as usize].num_effs.iter().filter(|e| e.res == c.res).any(|e| {
            if !monotone {
                return true;
            }
            match probe(task, e, Some(1.0)) {
                (Some(a), Some(b)) if additive(a, b) => (a > 0.0 && up) || (a < 0.0 && down),
                (Some(a), Some(b)) if (a - b).abs() <= 1e-9 * (1.0 + a.abs()) => num.holds(task, c, Some(a)),
                _ => true,
            }
        });
        if helps {
            out.push(w);
        }
    }
    out
}

/// A state the search met: where it came from.
struct Node {
    parent: u32,
    /// The local operator that led here (`u32::MAX` for the initial state)
    /// and its duration.
    op: u32,
    duration: f64,
}

/// The states a search met and how it reached them, each state once
/// among those it indexes: by hash, `same` chaining the states of one
/// hash, compared in full.
#[derive(Default)]
struct Table {
    states: Vec<State>,
    nodes: Vec<Node>,
    by_hash: FxHashMap<u64, u32>,
    same: Vec<u32>,
    /// The bytes it holds, estimated.
    bytes: usize,
}

impl Table {
    fn hash_of(s: &State) -> u64 {
        use std::hash::BuildHasher;
        rustc_hash::FxBuildHasher.hash_one(s)
    }

    /// Whether `s` (of hash `hash`) is indexed.
    fn has(&self, s: &State, hash: u64) -> bool {
        let mut seen = self.by_hash.get(&hash).copied();
        while let Some(i) = seen {
            if self.states[i as usize] == *s {
                return true;
            }
            seen = (self.same[i as usize] != u32::MAX).then_some(self.same[i as usize]);
        }
        false
    }

    /// Keeps and indexes `s`, reached by `node`: its id.
    fn insert(&mut self, s: State, hash: u64, node: Node) -> u32 {
        let id = self.states.len() as u32;
        self.bytes += s.bytes() + 40;
        self.same.push(self.by_hash.insert(hash, id).unwrap_or(u32::MAX));
        self.nodes.push(node);
        self.states.push(s);
        id
    }

    /// Keeps the steps of a lookahead from state `from`: the states on the
    /// way as empty placeholders, unindexed (their nodes make the path;
    /// met again, they are searched as any state), the last one kept and
    /// indexed. The id of the last one.
    fn insert_path(&mut self, from: u32, steps: Vec<Ahead>) -> u32 {
        let mut parent = from;
        let n = steps.len();
        for (i, a) in steps.into_iter().enumerate() {
            let node = Node { parent, op: a.op, duration: a.duration };
            parent = if i + 1 == n {
                let hash = Table::hash_of(&a.state);
                self.insert(a.state, hash, node)
            } else {
                self.bytes += 40;
                self.same.push(u32::MAX);
                self.nodes.push(node);
                self.states.push(State { atoms: Box::new([]), vals: Box::new([]) });
                (self.states.len() - 1) as u32
            };
        }
        parent
    }

    /// Forgets the index but for state `id` (of hash `hash`): the states
    /// and their nodes stay, and those met from now on may be met again.
    fn forget_all_but(&mut self, id: u32, hash: u64) {
        self.by_hash.clear();
        self.by_hash.insert(hash, id);
        self.same[id as usize] = u32::MAX;
    }
}

/// The limits of a forward search, checked at each state it expands,
/// and its progress reports.
struct Budget<'l> {
    started: Instant,
    limits: &'l PlannerLimits,
    cancel: &'l dyn Fn() -> bool,
    last_report: Instant,
    last_in_use: usize,
    expanded: u64,
}

impl<'l> Budget<'l> {
    fn new(limits: &'l PlannerLimits, cancel: &'l dyn Fn() -> bool, started: Instant) -> Budget<'l> {
        Budget {
            started,
            limits,
            cancel,
            last_report: Instant::now(),
            last_in_use: limits.memory_in_use.map_or(0, |f| f()),
            expanded: 0,
        }
    }

    /// Counts an expansion: the limit reached, if one is; a progress
    /// report every 100 ms (`open`: the states waiting, `best_h`: the
    /// best estimate so far).
    fn expand(
        &mut self,
        stats: &mut Stats,
        bytes: usize,
        open: usize,
        best_h: u32,
        progress: &mut dyn FnMut(&Progress),
    ) -> Option<LimitKind> {
        let limits = self.limits;
        self.expanded += 1;
        stats.expanded += 1;
        if (self.cancel)() {
            return Some(LimitKind::Cancelled);
        }
        if limits.time.is_some_and(|t| limits.time_spent_since(self.started) >= t) {
            return Some(LimitKind::Time);
        }
        if limits.nodes.is_some_and(|n| stats.expanded > n) {
            return Some(LimitKind::Nodes);
        }
        if self.expanded.is_multiple_of(MEMORY_EVERY) {
            let over = match (limits.memory, limits.memory_in_use) {
                (Some(m), Some(in_use)) => {
                    let now = in_use();
                    let next = now.saturating_add(now.saturating_sub(self.last_in_use));
                    self.last_in_use = now;
                    next > m
                }
                (Some(m), None) => bytes > m,
                (None, _) => false,
            };
            if over {
                return Some(LimitKind::Memory);
            }
        }
        if self.last_report.elapsed().as_millis() >= 100 {
            self.last_report = Instant::now();
            progress(&Progress {
                expanded: stats.expanded,
                open,
                best_f: f64::from(best_h),
                elapsed: limits.time_spent_since(self.started),
                makespan: None,
                improved: false,
            });
        }
        None
    }
}

/// The ground operators from which the forward searches take YAHSP's
/// lookahead ([`lookahead`]): the IPC 2002 hand-coded DriverLog and Depots
/// problems (52,540 to 456,360), where it solves DriverLog 1 and Depots
/// `time` 2 and 7 in 60 s. Below, on Depots `time-simple` and `time`
/// automatic 6 (1,728), the hill-climbing took its lookaheads' states into
/// a region it did not leave in 20 s (135,830 states; 28,173 to the goal
/// without them), and the IPC 2002 automatic sets went from 110/110 to
/// 108/110.
const LOOKAHEAD_FROM: usize = GROUP_FROM;

/// The forward search: FF's enforced hill-climbing
/// ([`hill_climb`]), and where it gets stuck, the greedy best-first
/// search ([`best_first`]) from the start, as FF does; both with YAHSP's
/// lookahead ([`lookahead`]) on a ground model of [`LOOKAHEAD_FROM`]
/// operators or more.
pub fn search(
    task: &Task<'_>,
    limits: &PlannerLimits,
    cancel: &dyn Fn() -> bool,
    progress: &mut dyn FnMut(&Progress),
    stats: &mut Stats,
) -> Found {
    let started = Instant::now();
    let fw = Forward::new(task);
    let look = (task.ops.len() >= LOOKAHEAD_FROM).then(|| Lookahead::new(&fw));
    let mut x = fw.scratch();
    let mut budget = Budget::new(limits, cancel, started);
    let found = match hill_climb(&fw, look.as_ref(), &mut x, &mut budget, progress, stats) {
        Some(found) => found,
        None => best_first(&fw, look.as_ref(), &mut x, &mut budget, progress, stats),
    };
    if limits.exits_after && matches!(found, Found::Limit(_)) {
        // The run ends here and the process exits: the relaxation's tables
        // are left to the exit to free.
        std::mem::forget((fw, x, look));
    }
    found
}

/// FF's enforced hill-climbing (Hoffmann and Nebel 2001): from the
/// current state, a breadth-first search through the helpful actions of
/// each state it reaches, every state estimated when it is reached,
/// until one estimated strictly better than the current one, which
/// becomes the current state. A state is not searched twice in one
/// breadth-first search (it may be in the next). `None` when a
/// breadth-first search runs out of states (or the initial state is a
/// dead end to the relaxation): the greedy best-first search takes over.
/// With the lookahead, every state reached tries its lookahead
/// ([`climb_ahead`]) before its helpful actions: on DriverLog
/// `time-simple` hand-coded 1 the run with the forward phase alone finds
/// its plan in 6,372 expansions in all, where with the lookahead of the
/// better states only it took 36,734 (and none in 60 s without).
///
/// On transport-like problems the relaxed plan's helpful actions lead
/// nearly straight to the goal, and a plateau (a driver walking to a
/// truck, the estimate unchanged) is crossed breadth-first in a few
/// states, where the best-first search, taking the oldest of the
/// thousands of states of the plateau's estimate, widens without end:
/// DriverLog `time-simple` hand-coded problem 1 (133,360 ground
/// operators) took 11,000 expansions without a plan, the estimate stuck
/// at 72.
fn hill_climb(
    fw: &Forward<'_, '_>,
    look: Option<&Lookahead>,
    x: &mut Scratch,
    budget: &mut Budget<'_>,
    progress: &mut dyn FnMut(&Progress),
    stats: &mut Stats,
) -> Option<Found> {
    let mut table = Table::default();
    let mut helpful = Vec::new();
    let init = fw.initial();
    let hash = Table::hash_of(&init);
    let mut cur = table.insert(init, hash, Node { parent: u32::MAX, op: u32::MAX, duration: 0.0 });
    if let Some(l) = budget.expand(stats, table.bytes, 0, u32::MAX, progress) {
        return Some(Found::Limit(l));
    }
    if fw.is_goal(&table.states[cur as usize]) {
        return Some(Found::Plan(sequence(fw, &table.nodes, cur)));
    }
    let mut cur_h = fw.relaxed(&table.states[cur as usize], x, &mut helpful)?;
    if let Some(found) =
        climb_ahead(fw, look, x, &mut table, budget, progress, stats, &mut cur, &mut cur_h, &mut helpful)
    {
        return Some(found);
    }
    // The states to reach: the state it comes from and the action.
    let mut queue: std::collections::VecDeque<(u32, u32)> = helpful.iter().map(|&k| (cur, k)).collect();
    while let Some((parent, k)) = queue.pop_front() {
        let Some((state, duration)) = fw.apply(&table.states[parent as usize], k) else { continue };
        let hash = Table::hash_of(&state);
        if table.has(&state, hash) {
            continue;
        }
        let mut id = table.insert(state, hash, Node { parent, op: k, duration });
        if let Some(l) = budget.expand(stats, table.bytes + 8 * queue.len(), queue.len(), cur_h, progress) {
            stats.open = queue.len();
            return Some(Found::Limit(l));
        }
        let s = &table.states[id as usize];
        if fw.is_goal(s) {
            return Some(Found::Plan(sequence(fw, &table.nodes, id)));
        }
        let Some(h) = fw.relaxed(s, x, &mut helpful) else { continue };
        stats.generated += helpful.len() as u64;
        if h < cur_h {
            // Better: the breadth-first search starts again from here.
            cur_h = h;
            queue.clear();
            table.forget_all_but(id, hash);
        }
        // The lookahead of every state reached, not only of the better
        // ones: its state, when better, ends the breadth-first search too.
        let reached = id;
        if let Some(found) =
            climb_ahead(fw, look, x, &mut table, budget, progress, stats, &mut id, &mut cur_h, &mut helpful)
        {
            return Some(found);
        }
        if id != reached {
            queue.clear();
        }
        queue.extend(helpful.iter().map(|&k| (id, k)));
        stats.peak_open = stats.peak_open.max(queue.len());
    }
    None
}

/// The hill-climbing's lookahead from the current state `cur`, estimated
/// `cur_h`, whose relaxed plan `x` holds and whose helpful actions are
/// `helpful`: while the state a lookahead reaches is new and estimated
/// better than the current one, it becomes the current state (the
/// lookahead's steps its path, the index forgotten but for it), with its
/// helpful actions, and its own lookahead is tried. The goal or a limit
/// when one is reached.
#[allow(clippy::too_many_arguments)]
fn climb_ahead(
    fw: &Forward<'_, '_>,
    look: Option<&Lookahead>,
    x: &mut Scratch,
    table: &mut Table,
    budget: &mut Budget<'_>,
    progress: &mut dyn FnMut(&Progress),
    stats: &mut Stats,
    cur: &mut u32,
    cur_h: &mut u32,
    helpful: &mut Vec<u32>,
) -> Option<Found> {
    let look = look?;
    let mut ahead_helpful = Vec::new();
    loop {
        let steps = look.run(fw, x, &table.states[*cur as usize]);
        let end = &steps.last()?.state;
        let hash = Table::hash_of(end);
        if table.has(end, hash) {
            return None;
        }
        if let Some(l) = budget.expand(stats, table.bytes, 0, *cur_h, progress) {
            return Some(Found::Limit(l));
        }
        stats.lookahead_steps += steps.len() as u64;
        if fw.is_goal(end) {
            let id = table.insert_path(*cur, steps);
            return Some(Found::Plan(sequence(fw, &table.nodes, id)));
        }
        let h = fw.relaxed(end, x, &mut ahead_helpful)?;
        stats.generated += ahead_helpful.len() as u64;
        if h >= *cur_h {
            return None;
        }
        stats.lookahead_taken += 1;
        let id = table.insert_path(*cur, steps);
        table.forget_all_but(id, hash);
        *cur = id;
        *cur_h = h;
        std::mem::swap(helpful, &mut ahead_helpful);
    }
}

/// The lazy greedy best-first search: a state is made and estimated when
/// it is taken from an open list, its successors enter with its estimate.
/// Two open lists (every successor; the helpful ones), taken in turn, the
/// helpful one `BOOST` more times after each better estimate. With the
/// lookahead, as YAHSP: after each state expanded, the state its
/// lookahead reaches, when new, is estimated and expanded at once (its
/// successors enter the lists), and so on from it.
fn best_first(
    fw: &Forward<'_, '_>,
    look: Option<&Lookahead>,
    x: &mut Scratch,
    budget: &mut Budget<'_>,
    progress: &mut dyn FnMut(&Progress),
    stats: &mut Stats,
) -> Found {
    let mut table = Table::default();
    // Entries: estimate of the parent, then first in first out.
    type Entry = Reverse<(u32, u64, u32, u32)>;
    let mut open: [BinaryHeap<Entry>; 2] = [BinaryHeap::new(), BinaryHeap::new()];
    let mut priority = [0i64; 2];
    let mut seq = 0u64;
    open[0].push(Reverse((0, 0, u32::MAX, u32::MAX)));
    let mut best_h = u32::MAX;
    let mut open_bytes = 0usize;
    let mut helpful = Vec::new();
    let mut succ = Vec::new();
    let mut is_helpful = vec![false; fw.ops.len()];
    let end = 'search: loop {
        // The list whose turn it is: the lower priority, a non-empty one.
        let lane = match (open[0].is_empty(), open[1].is_empty()) {
            (true, true) => break Found::Exhausted,
            (false, true) => 0,
            (true, false) => 1,
            (false, false) => usize::from(priority[1] < priority[0]),
        };
        priority[lane] += 1;
        let Some(Reverse((_, _, parent, k))) = open[lane].pop() else { continue };
        let made = if parent == u32::MAX {
            Some((fw.initial(), 0.0))
        } else {
            fw.apply(&table.states[parent as usize], k)
        };
        let Some((state, duration)) = made else { continue };
        let hash = Table::hash_of(&state);
        if table.has(&state, hash) {
            continue;
        }
        let n_open = open[0].len() + open[1].len();
        if let Some(l) = budget.expand(stats, table.bytes + open_bytes, n_open, best_h, progress) {
            break Found::Limit(l);
        }
        let mut id = table.insert(state, hash, Node { parent, op: k, duration });
        let s = &table.states[id as usize];
        if fw.is_goal(s) {
            break Found::Plan(sequence(fw, &table.nodes, id));
        }
        let Some(mut h) = fw.relaxed(s, x, &mut helpful) else { continue };
        loop {
            if h < best_h {
                best_h = h;
                // Progress: the helpful list gets the next turns.
                priority[1] -= BOOST;
            }
            fw.successors(&table.states[id as usize], &mut succ);
            for &k in &helpful {
                is_helpful[k as usize] = true;
            }
            for &k in &succ {
                seq += 1;
                open[0].push(Reverse((h, seq, id, k)));
                if is_helpful[k as usize] {
                    open[1].push(Reverse((h, seq, id, k)));
                }
            }
            for &k in &helpful {
                is_helpful[k as usize] = false;
            }
            open_bytes += 24 * succ.len();
            stats.generated += succ.len() as u64;
            stats.peak_open = stats.peak_open.max(open[0].len() + open[1].len());
            // The lookahead's state, expanded now when it is new.
            let Some(look) = look else { break };
            let steps = look.run(fw, x, &table.states[id as usize]);
            let Some(last) = steps.last() else { break };
            let hash = Table::hash_of(&last.state);
            if table.has(&last.state, hash) {
                break;
            }
            let n_open = open[0].len() + open[1].len();
            if let Some(l) = budget.expand(stats, table.bytes + open_bytes, n_open, best_h, progress) {
                break 'search Found::Limit(l);
            }
            stats.lookahead_steps += steps.len() as u64;
            stats.lookahead_taken += 1;
            id = table.insert_path(id, steps);
            let s = &table.states[id as usize];
            if fw.is_goal(s) {
                break 'search Found::Plan(sequence(fw, &table.nodes, id));
            }
            match fw.relaxed(s, x, &mut helpful) {
                Some(next) => h = next,
                None => break,
            }
        }
    };
    stats.open = open[0].len() + open[1].len();
    end
}

/// Turns taken by the helpful list after each better estimate.
const BOOST: i64 = 1000;

/// The sequence that leads to node `last`, with sequential times.
fn sequence(fw: &Forward<'_, '_>, nodes: &[Node], last: u32) -> Vec<Step> {
    let mut ops = Vec::new();
    let mut i = last;
    while nodes[i as usize].op != u32::MAX {
        let n = &nodes[i as usize];
        ops.push((fw.ops[n.op as usize], n.duration));
        i = n.parent;
    }
    ops.reverse();
    let mut t = 0.0;
    ops.into_iter()
        .map(|(op, d)| {
            let step = Step { op, start: t, end: t + d };
            t += d + EPS;
            step
        })
        .collect()
}

/// The orderings that keep the happenings touching each numeric fluent
/// in the sequence's order: a happening after the last writer before it,
/// a writer after the readers since the last writer. Between happenings
/// of different steps (a step's start is before its end anyway).
fn numeric_orders(task: &Task<'_>, steps: &[Step]) -> Vec<SeedOrder> {
    let mut out = Vec::new();
    for res in 0..task.numeric.keys.len() as u32 {
        let mut last_writer: Option<(usize, End)> = None;
        let mut readers: Vec<(usize, End)> = Vec::new();
        for (i, st) in steps.iter().enumerate() {
            let op = &task.ops[st.op as usize];
            for at in [End::Start, End::End] {
                let reads = op.num_conds.iter().any(|c| c.res == res && c.at == at)
                    || (at == End::Start && op.num_duration.as_ref().is_some_and(|d| d.res == res));
                let writes = op.num_effs.iter().any(|e| e.res == res && e.at == at);
                if !reads && !writes {
                    continue;
                }
                let here = (i, at);
                if let Some(w) = last_writer.filter(|w| w.0 != i) {
                    out.push(SeedOrder { from: w, to: here });
                }
                if writes {
                    out.extend(readers.iter().filter(|r| r.0 != i).map(|&r| SeedOrder { from: r, to: here }));
                    readers.clear();
                    last_writer = Some(here);
                } else {
                    readers.push(here);
                }
            }
        }
    }
    out
}

/// The partial-order search's effort to finish the plan of a sequence
/// (the flaws its start plan leaves: interfering happenings to order,
/// links the old times did not decide): expansions at most.
const FINISH_NODES: u64 = 20_000;

impl<'db> Prepared<'db> {
    /// The forward phase: the forward search within `limits`, then its
    /// sequence made a partial-order plan: the start plan of the
    /// partial-order search ([`Search::seeded`], with the sequential times
    /// as the old schedule, then forgotten: the plan is scheduled at its
    /// earliest), which solves what is left (at most [`FINISH_NODES`]
    /// expansions), then without its redundant steps. `NoPlan` when the
    /// forward search was exhausted, or its sequence could not be made a
    /// plan: not a verdict on the problem, the caller goes on.
    pub(super) fn forward(
        &self,
        db: &'db dyn Db,
        config: &Config,
        limits: &PlannerLimits,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&Progress),
    ) -> Outcome<'db> {
        let started = Instant::now();
        let task = &self.task;
        let mut stats = Stats { operators: task.ops.len(), methods: task.methods.len(), ..Stats::default() };
        let none = |status, stats| Outcome { status, plan: None, stats, lints: Vec::new() };
        let steps = match search(task, limits, cancel, progress, &mut stats) {
            Found::Plan(steps) => steps,
            Found::Exhausted => {
                stats.elapsed = started.elapsed();
                return none(Status::NoPlan, stats);
            }
            Found::Limit(kind) => {
                stats.elapsed = started.elapsed();
                return none(Status::Limit(kind), stats);
            }
        };
        let seed = Seed {
            steps: steps
                .iter()
                .map(|s| SeedStep {
                    op: s.op,
                    parent: None,
                    method: None,
                    start: s.start,
                    end: s.end,
                    fixed: false,
                    done: false,
                })
                .collect(),
            orders: numeric_orders(task, &steps),
            now: None,
        };
        let search = Search::new(task, &self.h, config);
        let roots: Vec<_> = match search.seeded(&seed) {
            Ok(v) => v
                .into_iter()
                .map(|(mut p, _)| {
                    // The earliest schedule, not the sequential one.
                    p.old_times = Default::default();
                    p
                })
                .collect(),
            Err(_) => Vec::new(),
        };
        let spent = limits.time_spent_since(started);
        let nodes = Some(stats.expanded + FINISH_NODES);
        let finish = PlannerLimits {
            time_spent: spent,
            nodes: limits.nodes.map_or(nodes, |n| nodes.map(|m| m.min(n))),
            first: true,
            better_than: None,
            exits_after: false,
            ..limits.clone()
        };
        let mut best = None;
        let end = search.run(roots, &finish, cancel, &mut |_| {}, &mut stats, &mut best);
        let End2::Solved(p) = end else {
            stats.elapsed = started.elapsed();
            return none(Status::NoPlan, stats);
        };
        let removing = Instant::now();
        let left = limits.time.map(|t| t.saturating_sub(limits.time_spent_since(started)));
        let stop = || cancel() || left.is_some_and(|l| removing.elapsed() >= l);
        let (p, removed) = search.without_redundant_steps(*p, &stop);
        stats.redundant_removed = removed.steps;
        stats.redundant_time = removing.elapsed();
        stats.best = Some(Quality { makespan: p.makespan(), cost: stats.best.map_or(0.0, |q| q.cost) });
        stats.elapsed = started.elapsed();
        stats.first_found = Some(stats.elapsed);
        stats.plans_found = 1;
        let plan = output::solved(db, task, &p);
        Outcome { status: Status::Solved, plan: Some(plan), stats, lints: Vec::new() }
    }
}

/// Whether the default sequence gives the partial-order search its whole
/// share of the time on this task: fewer than [`FORWARD_FIRST`] ground
/// operators. On a larger one it stops at [`LARGE_FIRST_NODES`]
/// expansions.
/// What the default sequence gives the partial-order search before the
/// forward phase, by the size of the ground model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum First {
    /// Its share of the time ([`FORWARD_AFTER`]).
    Share,
    /// Its share, and [`LARGE_FIRST_NODES`] expansions at most
    /// ([`FORWARD_FIRST`] operators or more).
    Nodes,
    /// Nothing: the forward phase starts ([`FORWARD_ALONE`] operators or
    /// more).
    Nothing,
}

fn first_search(task: &Task<'_>) -> First {
    match task.ops.len() {
        n if n >= FORWARD_ALONE => First::Nothing,
        n if n >= FORWARD_FIRST => First::Nodes,
        _ => First::Share,
    }
}

/// The partial-order search's expansions at most before the forward phase
/// on a ground model of [`FORWARD_FIRST`] operators or more: it solves
/// Satellite `time-simple` automatic 20 (4,037 ground operators) in 1,651
/// (0.8 s), where the forward phase took 60,065 states (4.2 s); on the
/// IPC 2002 hand-coded problems it solved none in a quarter of the time.
const LARGE_FIRST_NODES: u64 = 2_500;

impl<'db> Prepared<'db> {
    /// The first plan of a problem without a hierarchy: the partial-order
    /// search alone when the forward phase does not apply
    /// ([`applies`]) or the configuration says `noforward`; with
    /// `forward`, the forward phase first; by default the partial-order
    /// search for [`FORWARD_AFTER`] of the time left (or until the memory
    /// limit: its open list is freed; on a ground model of
    /// [`FORWARD_FIRST`] operators or more, [`LARGE_FIRST_NODES`]
    /// expansions at most; from [`FORWARD_ALONE`] operators, not at all),
    /// then the forward phase (without a time limit, the partial-order search
    /// alone). When the forward phase finds no sequence, the partial-order
    /// search runs for what is left. The statistics add up the phases'.
    pub(super) fn first_plan(
        &self,
        db: &'db dyn Db,
        config: &Config,
        limits: &PlannerLimits,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&Progress),
    ) -> Outcome<'db> {
        if config.noforward || !applies(&self.task) {
            return self.search(db, config, limits, None, cancel, progress);
        }
        let started = Instant::now();
        let mut before = Stats::default();
        // Adds the statistics of the phases before to an outcome's.
        let total = |mut o: Outcome<'db>, before: &Stats| {
            let b = &mut o.stats;
            b.expanded += before.expanded;
            b.generated += before.generated;
            b.peak_open = b.peak_open.max(before.peak_open);
            b.largest = b.largest.max(before.largest);
            b.first_found = b.first_found.map(|f| f + before.elapsed);
            b.elapsed += before.elapsed;
            o
        };
        // A phase's limits: the run's, less the expansions before, and
        // the time up to `until` (`None`: the run's limit).
        let phase = |until: Option<std::time::Duration>, before: &Stats, exits_after: bool| {
            let spent = limits.time_spent_since(started);
            PlannerLimits {
                time_spent: spent,
                time: match (limits.time, until) {
                    (Some(t), Some(u)) => Some(u.min(t)),
                    (t, _) => t,
                },
                nodes: limits.nodes.map(|n| n.saturating_sub(before.expanded)),
                exits_after,
                ..limits.clone()
            }
        };
        let first_search = first_search(&self.task);
        if !config.forward && first_search != First::Nothing {
            let share = limits.time.map(|t| {
                let spent = limits.time_spent_since(started);
                spent + t.saturating_sub(spent).mul_f64(FORWARD_AFTER)
            });
            let large = first_search == First::Nodes;
            let mut first_limits = phase(share, &before, false);
            if large {
                first_limits.nodes =
                    Some(first_limits.nodes.map_or(LARGE_FIRST_NODES, |n| n.min(LARGE_FIRST_NODES)));
            }
            // Its open list is freed: the forward phase comes next.
            let first = self.search(db, config, &first_limits, None, cancel, progress);
            // At its share of the time, or at the memory limit: its open
            // list, freed, was what filled the memory.
            let at_share = match first.status {
                Status::Limit(LimitKind::Time) => {
                    limits.time.is_none_or(|t| limits.time_spent_since(started) < t)
                }
                Status::Limit(LimitKind::Memory) => true,
                // At its expansions on a large model, not the run's.
                Status::Limit(LimitKind::Nodes) => {
                    large && limits.nodes.is_none_or(|n| first.stats.expanded < n)
                }
                _ => false,
            };
            if !at_share {
                return first;
            }
            before = first.stats;
        }
        let done = before.expanded;
        let mut counted = |p: &Progress| progress(&Progress { expanded: done + p.expanded, ..*p });
        // At a limit the forward phase's answer is the run's (its tables
        // left to the exit, when the process exits after).
        let fwd = self.forward(db, config, &phase(None, &before, limits.exits_after), cancel, &mut counted);
        if fwd.status != Status::NoPlan {
            return total(fwd, &before);
        }
        let fwd_stats = fwd.stats;
        before.expanded += fwd_stats.expanded;
        before.generated += fwd_stats.generated;
        before.peak_open = before.peak_open.max(fwd_stats.peak_open);
        before.elapsed += fwd_stats.elapsed;
        let done = before.expanded;
        let mut counted = |p: &Progress| progress(&Progress { expanded: done + p.expanded, ..*p });
        let rest =
            self.search(db, config, &phase(None, &before, limits.exits_after), None, cancel, &mut counted);
        total(rest, &before)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::prepare;

    /// The forward search's end on a fixture of `tests/planner`, and the
    /// names of the operators of the sequence it found.
    fn forward_on(file: &str) -> (Found, Vec<String>) {
        forward_on_text(file, fixture(file))
    }

    /// A fixture of `tests/planner`.
    fn fixture(file: &str) -> String {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/planner").join(file);
        std::fs::read_to_string(&path).expect("the fixture")
    }

    /// IPC 2002 Rovers time-simple, hand-coded problem 10 (4,261 ground
    /// operators), its domain and problem in one text; `None`, saying so,
    /// without the corpora.
    fn rovers_hand_coded_10() -> Option<String> {
        let dir = std::env::var_os("HIPOP_CORPORA")
            .map(std::path::PathBuf::from)
            .unwrap_or_else(|| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora"));
        let set = dir.join("ipc2002-temporal/rovers-time-simple-hand-coded");
        let read = |p: &str| std::fs::read_to_string(set.join(p)).ok();
        match (read("domain.pddl"), read("instances/instance-10.pddl")) {
            (Some(d), Some(p)) => Some(format!("{d}\n{p}")),
            _ => {
                eprintln!("skipped: the corpora are not in ../shared/corpora (set HIPOP_CORPORA)");
                None
            }
        }
    }

    /// Runs `f` on the prepared task of a text holding a domain and a
    /// problem, planned with a node limit of `nodes`.
    fn with_prepared<T>(
        file: &str,
        text: String,
        nodes: u64,
        f: impl FnOnce(&Prepared<'_>, &PlannerLimits) -> T + std::panic::UnwindSafe,
    ) -> T {
        let mut host = crate::AnalysisHost::new();
        let pf = host.set_file_text(file, text);
        host.analysis()
            .with_db(|db| {
                let unit = crate::host::first_problem(db, pf).expect("a problem");
                let limits = PlannerLimits { nodes: Some(nodes), ..PlannerLimits::default() };
                let prepared = prepare(db, unit, &Config::default(), &limits).ok().expect("prepared");
                f(&prepared, &limits)
            })
            .expect("not cancelled")
    }

    fn forward_on_text(file: &str, text: String) -> (Found, Vec<String>) {
        with_prepared(file, text, 10_000, |prepared, limits| {
            assert!(applies(&prepared.task));
            let mut stats = Stats::default();
            let found = search(&prepared.task, limits, &|| false, &mut |_| {}, &mut stats);
            let names = match &found {
                Found::Plan(steps) => steps.iter().map(|s| prepared.task.show_op(s.op)).collect(),
                _ => Vec::new(),
            };
            (found, names)
        })
    }

    /// Runs `f` on the forward search's model of a fixture of
    /// `tests/planner`.
    fn with_forward(file: &str, f: impl FnOnce(&Forward<'_, '_>) + std::panic::UnwindSafe) {
        with_prepared(file, fixture(file), 10_000, |prepared, _| f(&Forward::new(&prepared.task)));
    }

    /// The successor index keys each operator by the positive `at start`
    /// condition the fewest operators share: DriverLog's `board-truck`
    /// by `(empty ?truck)`, not by `(at ?truck ?loc)`, which every load,
    /// unload, boarding and disembarking there shares. In the initial
    /// state it tests fewer operators than keyed by the first condition.
    #[test]
    fn operators_are_keyed_by_their_rarest_condition() {
        with_forward("drivers-share-trucks.pddl", |fw| {
            let task = fw.task;
            let starts = |k: usize| -> Vec<u32> {
                let op = &task.ops[fw.ops[k] as usize];
                op.conds
                    .iter()
                    .filter(|c| c.at == End::Start && !is_neg(c.lit))
                    .map(|c| atom_of(c.lit))
                    .collect()
            };
            let mut shared = vec![0usize; task.init.len()];
            for k in 0..fw.ops.len() {
                let mut a = starts(k);
                a.sort_unstable();
                a.dedup();
                for a in a {
                    shared[a as usize] += 1;
                }
            }
            let mut first_keyed = vec![0usize; task.init.len()];
            let mut differs = 0;
            for a in 0..task.init.len() {
                for &k in fw.keyed.get(a) {
                    let conds = starts(k as usize);
                    assert!(
                        conds.iter().all(|&c| shared[a] <= shared[c as usize]),
                        "{}",
                        task.show_op(fw.ops[k as usize])
                    );
                    first_keyed[conds[0] as usize] += 1;
                    differs += usize::from(conds[0] != a as u32);
                }
            }
            assert!(differs > 0);
            let s = fw.initial();
            let by_first: usize =
                (0..task.init.len()).filter(|&a| s.has(a as u32)).map(|a| first_keyed[a]).sum();
            assert!(
                fw.tested(&s) < by_first,
                "{} tested, {by_first} keyed by the first condition",
                fw.tested(&s)
            );
        });
    }

    /// The successors from the index are the operators whose `at start`
    /// conditions hold, tested one by one, along a walk of 30 states.
    /// DriverLog's drives of a truck between two places, one per driver,
    /// are one operator to the relaxation, which needs "any of" the
    /// truck's drivers: fewer operators, and along a walk through the
    /// helpful actions the same estimates as the operators one by one,
    /// every helpful action one that may start.
    #[test]
    fn drives_that_differ_by_their_driver_are_one_to_the_relaxation() {
        with_prepared("drivers-share-trucks.pddl", fixture("drivers-share-trucks.pddl"), 10_000, |p, _| {
            let (grouped, alone) = (Forward::build(&p.task, true), Forward::build(&p.task, false));
            assert!(alone.groups.is_empty());
            assert_eq!(alone.relaxed_of.len(), alone.ops.len());
            assert!(!grouped.groups.is_empty());
            assert!(grouped.relaxed_of.len() < alone.relaxed_of.len());
            for g in &grouped.groups {
                for &(_, k) in &g.members {
                    assert_eq!(p.task.ops[grouped.ops[k as usize] as usize].name.as_str(), "drive-truck");
                }
            }
            let (mut xg, mut xa) = (grouped.scratch(), alone.scratch());
            let (mut hg, mut ha) = (Vec::new(), Vec::new());
            let mut s = grouped.initial();
            let mut steps = 0;
            while !grouped.is_goal(&s) && steps < 40 {
                let h = grouped.relaxed(&s, &mut xg, &mut hg);
                assert_eq!(h, alone.relaxed(&s, &mut xa, &mut ha), "the estimate after {steps} steps");
                assert!(!hg.is_empty());
                for &k in &hg {
                    assert!(
                        grouped.may_start(&s, k),
                        "{} may not start",
                        p.task.show_op(grouped.ops[k as usize])
                    );
                }
                // The helpful action whose state is estimated best.
                let next = hg
                    .iter()
                    .filter_map(|&k| grouped.apply(&s, k))
                    .map(|(t, _)| (alone.relaxed(&t, &mut xa, &mut ha).unwrap_or(u32::MAX), t))
                    .min_by_key(|(h, _)| *h)
                    .expect("a helpful action runs");
                s = next.1;
                steps += 1;
            }
            assert!(steps > 5);
        });
    }

    /// A graph of `n` places, a move between any two: `n * n` ground
    /// moves, every one reachable and relevant to reaching the last place.
    fn complete_graph(n: usize) -> String {
        let places: Vec<String> = (0..n).map(|i| format!("p{i}")).collect();
        format!(
            "(define (domain graph) (:requirements :strips :typing :durative-actions)
               (:types place)
               (:predicates (at ?p - place))
               (:durative-action move :parameters (?a ?b - place) :duration (= ?duration 1)
                 :condition (at start (at ?a))
                 :effect (and (at start (not (at ?a))) (at end (at ?b)))))
             (define (problem walk) (:domain graph)
               (:objects {} - place)
               (:init (at p0))
               (:goal (at p{})))",
            places.join(" "),
            n - 1
        )
    }

    /// The partial-order search runs before the forward phase for its share
    /// of the time on a small ground model, for a few thousand expansions
    /// from 3,000 operators, and not at all from 20,000.
    #[test]
    fn the_largest_models_start_with_the_forward_phase() {
        for (n, first) in [(10, First::Share), (60, First::Nodes), (150, First::Nothing)] {
            with_prepared("graph.pddl", complete_graph(n), 1, |prepared, _| {
                assert!(applies(&prepared.task));
                assert_eq!(prepared.task.ops.len(), n * n, "{n} places");
                assert_eq!(first_search(&prepared.task), first, "{n} places");
            });
        }
    }

    #[test]
    fn successors_are_the_operators_that_may_start() {
        with_forward("drivers-share-trucks.pddl", |fw| {
            let mut s = fw.initial();
            let mut succ = Vec::new();
            for step in 0..30 {
                fw.successors(&s, &mut succ);
                let all: Vec<u32> = (0..fw.ops.len() as u32)
                    .filter(|&k| {
                        let op = &fw.task.ops[fw.ops[k as usize] as usize];
                        op.conds.iter().all(|c| c.at == End::End || s.holds(c.lit))
                    })
                    .collect();
                assert_eq!(succ, all, "state {step}");
                let Some(next) = succ.iter().rev().find_map(|&k| fw.apply(&s, k)) else { break };
                s = next.0;
            }
        });
    }

    /// The rover has energy for one move and its goal is two moves away:
    /// the relaxation lets both moves read the same 10 units, so its plan
    /// uses up 16 and the recharge in the sun where the rover stands joins
    /// it (3 actions, not 2), a helpful action of the initial state.
    #[test]
    fn a_relaxed_plan_that_uses_up_more_energy_than_the_rover_has_recharges() {
        with_forward("recharge-duration-from-energy.pddl", |fw| {
            let mut x = fw.scratch();
            let mut helpful = Vec::new();
            let h = fw.relaxed(&fw.initial(), &mut x, &mut helpful);
            assert_eq!(h, Some(3));
            let names: Vec<String> = helpful.iter().map(|&k| fw.task.show_op(fw.ops[k as usize])).collect();
            assert!(names.iter().any(|n| n.contains("recharge")), "helpful: {names:?}");
            // The work arrays are left as they were found: the same again.
            assert_eq!(fw.relaxed(&fw.initial(), &mut x, &mut helpful), Some(3));
        });
    }

    /// The expansions of the enforced hill-climbing and of the greedy
    /// best-first search alone on a fixture, up to `nodes` each: whether
    /// each found a sequence, and its expansions.
    fn both_on(file: &str, text: String, nodes: u64) -> [(bool, u64); 2] {
        both_on_paying(file, text, nodes, None)
    }

    /// [`both_on`], with `undo` as the cost of undoing a goal when given.
    fn both_on_paying(file: &str, text: String, nodes: u64, undo: Option<u32>) -> [(bool, u64); 2] {
        with_prepared(file, text, nodes, |prepared, limits| {
            let mut fw = Forward::new(&prepared.task);
            if let Some(u) = undo {
                fw.undo_cost = u;
            }
            let mut x = fw.scratch();
            let mut run = |ehc: bool| {
                let mut stats = Stats::default();
                let mut budget = Budget::new(limits, &|| false, Instant::now());
                let found = if ehc {
                    hill_climb(&fw, None, &mut x, &mut budget, &mut |_| {}, &mut stats)
                } else {
                    Some(best_first(&fw, None, &mut x, &mut budget, &mut |_| {}, &mut stats))
                };
                (matches!(found, Some(Found::Plan(_))), stats.expanded)
            };
            [run(true), run(false)]
        })
    }

    /// The expansions of the enforced hill-climbing, then of the greedy
    /// best-first search alone, each without and with the lookahead, up to
    /// `nodes` each, on a fixture of `tests/planner`: whether each found a
    /// sequence (checked by replaying it from the initial state), and its
    /// expansions.
    fn with_and_without_lookahead(file: &str, nodes: u64) -> [[(bool, u64); 2]; 2] {
        with_prepared(file, fixture(file), nodes, |prepared, limits| {
            let fw = Forward::new(&prepared.task);
            let look = Lookahead::new(&fw);
            let mut x = fw.scratch();
            let mut run = |ehc: bool, look: Option<&Lookahead>| {
                let mut stats = Stats::default();
                let mut budget = Budget::new(limits, &|| false, Instant::now());
                let found = if ehc {
                    hill_climb(&fw, look, &mut x, &mut budget, &mut |_| {}, &mut stats)
                } else {
                    Some(best_first(&fw, look, &mut x, &mut budget, &mut |_| {}, &mut stats))
                };
                let solved = match found {
                    Some(Found::Plan(steps)) => {
                        let local: FxHashMap<u32, u32> =
                            fw.ops.iter().enumerate().map(|(k, &o)| (o, k as u32)).collect();
                        let mut s = fw.initial();
                        for step in &steps {
                            let (t, d) = fw.apply(&s, local[&step.op]).expect("each step runs");
                            assert!((step.end - step.start - d).abs() < 1e-9);
                            s = t;
                        }
                        assert!(fw.is_goal(&s), "the sequence reaches the goal");
                        true
                    }
                    _ => false,
                };
                (solved, stats.expanded)
            };
            [[run(true, None), run(true, Some(&look))], [run(false, None), run(false, Some(&look))]]
        })
    }

    /// A truck at its goal place with its driver aboard, whose goal is the
    /// next place: undoing the truck's goal costs the relaxation
    /// [`UNDO_GOAL`] more, so the relaxed plan gets the driver out and
    /// walks (three actions, the helpful one the disembarking), where
    /// without it the relaxed plan drives the truck away and lets the
    /// driver out there (two actions, the helpful one the drive). The
    /// search then finds those three actions.
    #[test]
    fn a_relaxed_plan_that_undoes_a_goal_pays_for_it() {
        let file = "driver-parked-at-the-trucks-goal.pddl";
        with_prepared(file, fixture(file), 100, |prepared, limits| {
            let task = &prepared.task;
            let mut fw = Forward::new(task);
            assert_eq!(fw.undo_cost, 0, "a model this small pays nothing");
            fw.undo_cost = UNDO_GOAL;
            let mut x = fw.scratch();
            let mut helpful = Vec::new();
            let s = fw.initial();
            let name = |fw: &Forward<'_, '_>, k: u32| task.show_op(fw.ops[k as usize]);
            assert_eq!(fw.relaxed(&s, &mut x, &mut helpful), Some(3));
            let names: Vec<String> = helpful.iter().map(|&k| name(&fw, k)).collect();
            assert_eq!(names, ["(disembark-truck driver1 truck1 s0)"]);
            let mut stats = Stats::default();
            let mut budget = Budget::new(limits, &|| false, Instant::now());
            let found = hill_climb(&fw, None, &mut x, &mut budget, &mut |_| {}, &mut stats);
            let Some(Found::Plan(steps)) = found else { panic!("no plan: {found:?}") };
            let names: Vec<String> = steps.iter().map(|s| task.show_op(s.op)).collect();
            assert_eq!(
                names,
                ["(disembark-truck driver1 truck1 s0)", "(walk driver1 s0 p0-1)", "(walk driver1 p0-1 s1)"]
            );
            fw.undo_cost = 0;
            assert_eq!(fw.relaxed(&s, &mut x, &mut helpful), Some(2));
            let names: Vec<String> = helpful.iter().map(|&k| name(&fw, k)).collect();
            assert_eq!(names, ["(drive-truck truck1 s0 s1 driver1)"]);
        });
    }

    /// Two trucks, three packages, drivers who walk: the relaxed plan
    /// drives a truck from where it is to every place it needs, and the
    /// lookahead runs it, a drive repaired to start where the truck
    /// arrived. With the lookahead both searches reach the goal in fewer
    /// expansions, their sequences valid.
    #[test]
    fn the_lookahead_reaches_a_drivers_goal_in_fewer_expansions() {
        let [[ehc, ehc_look], [gbfs, gbfs_look]] =
            with_and_without_lookahead("drivers-share-trucks.pddl", 10_000);
        assert!(ehc.0 && ehc_look.0 && gbfs.0 && gbfs_look.0, "{ehc:?} {ehc_look:?} {gbfs:?} {gbfs_look:?}");
        assert!(ehc_look.1 < ehc.1, "hill-climbing: {} with the lookahead, {} without", ehc_look.1, ehc.1);
        assert!(gbfs_look.1 < gbfs.1, "best-first: {} with the lookahead, {} without", gbfs_look.1, gbfs.1);
    }

    /// Along a walk through lookahead states: each lookahead's steps replay
    /// from the state it started in through [`Forward::apply`] (conditions,
    /// durations, effects) to the state it reports, and some step of some
    /// lookahead is a repair, an operator of no relaxed plan's action.
    #[test]
    fn a_repaired_lookahead_sequence_is_valid() {
        with_forward("drivers-share-trucks.pddl", |fw| {
            let look = Lookahead::new(fw);
            let mut x = fw.scratch();
            let mut helpful = Vec::new();
            let mut s = fw.initial();
            let mut repairs = 0;
            for _ in 0..20 {
                if fw.is_goal(&s) || fw.relaxed(&s, &mut x, &mut helpful).is_none() {
                    break;
                }
                let planned: Vec<u32> = x
                    .plan
                    .iter()
                    .flat_map(|&(k, _)| lookahead::members_of(fw, k).collect::<Vec<_>>())
                    .collect();
                let steps = look.run(fw, &x, &s);
                if steps.is_empty() {
                    break;
                }
                let mut t = s.clone();
                for a in &steps {
                    let (next, d) = fw.apply(&t, a.op).expect("a lookahead step runs where it is");
                    assert_eq!(d, a.duration);
                    assert!(next == a.state, "{}", fw.task.show_op(fw.ops[a.op as usize]));
                    repairs += usize::from(!planned.contains(&a.op));
                    t = next;
                }
                s = t;
            }
            assert!(repairs > 0, "no repaired step");
            assert!(fw.is_goal(&s), "the lookaheads reach the goal");
        });
    }

    /// On a Rovers problem of 4,261 ground operators the enforced
    /// hill-climbing finds a sequence within 1,000 expansions (818), where
    /// the greedy best-first search alone does not (1,783).
    #[test]
    fn hill_climbing_finds_a_rovers_sequence_in_fewer_expansions() {
        let Some(text) = rovers_hand_coded_10() else { return };
        let [ehc, gbfs] = both_on("rovers.pddl", text.clone(), 1_000);
        assert!(ehc.0, "enforced hill-climbing: {ehc:?}");
        assert!(!gbfs.0, "best-first: {gbfs:?}");
        let (found, _) = forward_on_text("rovers.pddl", text);
        assert!(matches!(found, Found::Plan(_)), "{found:?}");
    }

    /// Where the helpful actions lead only back to states already met, the
    /// enforced hill-climbing gives up at once and the greedy best-first
    /// search finds the sequence.
    #[test]
    fn the_best_first_search_takes_over_when_hill_climbing_runs_out() {
        let file = "towers-hill-climbing-runs-out.pddl";
        let [ehc, gbfs] = both_on(file, fixture(file), 10_000);
        assert!(!ehc.0 && ehc.1 < 10, "enforced hill-climbing: {ehc:?}");
        assert!(gbfs.0, "best-first: {gbfs:?}");
        // A goal stacked early must be undone here: paying for it, as the
        // largest models do ([`UNDO_FROM`]), the best-first search does
        // not find the sequence.
        let [_, paying] = both_on_paying(file, fixture(file), 10_000, Some(UNDO_GOAL));
        assert!(!paying.0, "best-first paying for undone goals: {paying:?}");
        let (found, names) = forward_on("towers-hill-climbing-runs-out.pddl");
        assert!(matches!(found, Found::Plan(_)), "{found:?}");
        assert!(names.iter().any(|n| n.starts_with("(stack")), "{names:?}");
    }

    /// `fix` needs the light on over all of it, and `light` turns it off at
    /// its end: no sequence reaches the goal, and the search says so.
    #[test]
    fn a_plan_that_needs_overlapping_actions_has_no_sequence() {
        assert_eq!(forward_on("light-while-fixing.pddl").0, Found::Exhausted);
    }

    /// The numeric conditions are checked in the state and the refuels
    /// come before the flights that need them, in sequence: times one
    /// after another, ε apart.
    #[test]
    fn a_sequence_refuels_before_the_flights_that_need_it() {
        let (found, names) = forward_on("passengers-need-the-forward-phase.pddl");
        let Found::Plan(steps) = found else { panic!("a sequence: {found:?}") };
        assert!(names.iter().any(|n| n.starts_with("(refuel")), "{names:?}");
        for w in steps.windows(2) {
            assert!((w[1].start - (w[0].end + EPS)).abs() < 1e-9, "{w:?}");
        }
    }
}
