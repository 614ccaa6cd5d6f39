//! YAHSP's lookahead (Vidal, "A Lookahead Strategy for Heuristic Search
//! Planning", ICAPS 2004): from a state's relaxed plan, a sequence of
//! actions that runs as much of that plan as the real state allows.
//!
//! The relaxed plan's actions are taken in the order of their cost (h_add:
//! the layer where the relaxation reaches them, a drive before the load it
//! makes possible). Repeatedly, the first of them that can run in the
//! lookahead's state runs there and leaves the list; when none can, one
//! is repaired: an action that can run and adds a fact the relaxed plan
//! needed from an action that cannot (DriverLog: a `drive-truck` from
//! where the truck is, for one from where the relaxation left it) runs
//! in its place. An action whose facts all hold already leaves the list
//! unrun. The lookahead stops when nothing runs, or at the goal.
//!
//! Every action runs through [`Forward::apply`], as a successor in the
//! search does (its conditions, duration and numeric effects): the
//! sequence is valid from the state it starts in, and the searches keep
//! it as the path to the state it reaches.

use super::{Forward, Lists, Relaxed, Scratch, State};
use crate::planner::task::Lit;

/// A step of a lookahead: the local operator, its duration and the state
/// it leaves.
pub(super) struct Ahead {
    pub op: u32,
    pub duration: f64,
    pub state: State,
}

/// The index the lookahead's repairs need: the local operators by the
/// literals their effects make true.
pub(super) struct Lookahead {
    achievers: Lists,
}

impl Lookahead {
    pub(super) fn new(fw: &Forward<'_, '_>) -> Lookahead {
        let task = fw.task;
        let mut by_lit = vec![Vec::new(); 2 * task.init.len()];
        for (k, &o) in fw.ops.iter().enumerate() {
            let mut lits: Vec<Lit> = task.ops[o as usize].effs.iter().map(|e| e.lit).collect();
            lits.sort_unstable();
            lits.dedup();
            for l in lits {
                by_lit[l as usize].push(k as u32);
            }
        }
        Lookahead { achievers: Lists::new(by_lit) }
    }

    /// The lookahead from `s`, whose relaxed plan is the last one `x`
    /// extracted ([`Forward::relaxed`] on `s`): its steps, empty when no
    /// action of that plan, nor a repair, can run in `s`.
    pub(super) fn run(&self, fw: &Forward<'_, '_>, x: &Scratch, s: &State) -> Vec<Ahead> {
        let mut items = plan_items(fw, x);
        let mut steps: Vec<Ahead> = Vec::new();
        loop {
            let cur = steps.last().map_or(s, |a| &a.state);
            if fw.is_goal(cur) {
                break;
            }
            items.retain(|(_, lits)| !lits.iter().all(|&l| cur.holds(l)));
            let found = items
                .iter()
                .enumerate()
                .find_map(|(i, &(k, _))| {
                    members_of(fw, k).find_map(|local| fw.apply(cur, local).map(|(t, d)| (i, local, t, d)))
                })
                .or_else(|| self.repair(fw, cur, &items));
            let Some((i, op, state, duration)) = found else { break };
            items.remove(i);
            steps.push(Ahead { op, duration, state });
        }
        steps
    }

    /// A repair in `s`: the first action of the list (by its place, then
    /// its facts) with a fact that does not hold and an operator that can
    /// run in `s` and makes it hold. The item's index, the operator, the
    /// state it leaves and its duration.
    fn repair(
        &self,
        fw: &Forward<'_, '_>,
        s: &State,
        items: &[(u32, Vec<Lit>)],
    ) -> Option<(usize, u32, State, f64)> {
        items.iter().enumerate().find_map(|(i, (_, lits))| {
            lits.iter().filter(|&&l| !s.holds(l)).find_map(|&l| {
                self.achievers
                    .get(l as usize)
                    .iter()
                    .filter_map(|&b| fw.apply(s, b).map(|(t, d)| (b, t, d)))
                    .find(|(_, t, _)| t.holds(l))
                    .map(|(b, t, d)| (i, b, t, d))
            })
        })
    }
}

/// The local operators a relaxed operator stands for: itself, or a
/// group's members.
pub(super) fn members_of<'f>(fw: &'f Forward<'_, '_>, k: u32) -> impl Iterator<Item = u32> + 'f {
    let (one, group): (Option<u32>, &[(u32, u32)]) = match fw.relaxed_of[k as usize] {
        Relaxed::Op(local) => (Some(local), &[]),
        Relaxed::Group(g) => (None, &fw.groups[g as usize].members),
        Relaxed::Any => (None, &[]),
    };
    one.into_iter().chain(group.iter().map(|m| m.1))
}

/// The actions of the last relaxed plan `x` extracted, by their cost
/// (then their number), each with the literals the plan needs from it
/// (its numeric facts are left to the conditions of the actions that
/// read them).
fn plan_items(fw: &Forward<'_, '_>, x: &Scratch) -> Vec<(u32, Vec<Lit>)> {
    let mut pairs: Vec<(u32, u32, Lit)> = x
        .plan
        .iter()
        .filter(|&&(_, f)| f < fw.num_facts.start)
        .map(|&(k, f)| (x.work[k as usize].cost, k, fw.fact_lit[f as usize]))
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    let mut items: Vec<(u32, Vec<Lit>)> = Vec::new();
    for (_, k, l) in pairs {
        match items.last_mut() {
            Some((last, lits)) if *last == k => lits.push(l),
            _ => items.push((k, vec![l])),
        }
    }
    items
}
