//! Hierarchical plans that cannot run. In a problem where no step is ever
//! inserted (purely hierarchical: every step comes from a method), the
//! steps of a plan are in every plan it leads to, and only its unrefined
//! abstract steps may add more. Three ways such a plan is dead, whatever the
//! links and orderings chosen later ([`Search::doomed`]):
//!
//! - a step can never run: its conditions are not reached from the
//!   initial state through the plan's own steps ([`Search::stuck`]);
//! - a literal is used up faster than it is made ([`Search::starved`]). A
//!   step that needs a literal and deletes it at the same happening (a
//!   `pick-up` that needs the truck's capacity level and takes it, a
//!   `drive` from a place) *uses up* the literal: after it, the literal is
//!   false until a step makes it true again. So in any execution of the
//!   plan, each such step ends a stretch of time over which the literal
//!   holds, a stretch that the initial state or some step making the
//!   literal true began, before it; no two steps end the same stretch.
//!   When the plan's users of a literal cannot each be given a maker of
//!   their own that can come before them (a bipartite matching, Hall's
//!   condition) and no unrefined abstract step that can come before the
//!   one left over may make the literal, the plan is dead;
//! - an unrefined abstract step needs, however it is refined, a literal
//!   that nothing can make true before it ([`Search::unmet`]).
//!
//! Such a plan is dropped when generated ([`Search::score`]), instead of
//! when every way to link and order its steps has been tried.

use super::super::plan::{Kind, Plan};
use super::super::stn::{ORIGIN, Tp};
use super::super::task::{End, Lit, Op, Task, negate};
use super::Search;

/// What each operator uses up and makes, by literal and end: computed once
/// per search of a purely hierarchical problem.
pub(super) struct Tokens {
    /// The literals an elementary operator needs and deletes at the same
    /// happening, without adding them there.
    uses: Vec<Vec<(Lit, End)>>,
    /// The literals an operator makes true where it does not need them
    /// (else they held already: no new stretch begins there).
    makes: Vec<Vec<(Lit, End)>>,
}

impl Tokens {
    pub(super) fn new(task: &Task<'_>) -> Tokens {
        let same = |op: &Op<'_>, a: End, b: End| op.instant || a == b;
        let uses = task
            .ops
            .iter()
            .map(|op| {
                if op.is_abstract {
                    return Vec::new();
                }
                let mut v: Vec<(Lit, End)> = op
                    .conds
                    .iter()
                    .filter(|c| {
                        let del = negate(c.lit);
                        op.effs.iter().any(|e| e.lit == del && same(op, e.at, c.at))
                            && !op.effs.iter().any(|e| e.lit == c.lit && same(op, e.at, c.at))
                    })
                    .map(|c| (c.lit, c.at))
                    .collect();
                v.sort_unstable_by_key(|&(l, at)| (l, at == End::End));
                v.dedup();
                v
            })
            .collect();
        let makes = task
            .ops
            .iter()
            .map(|op| {
                op.effs
                    .iter()
                    .filter(|e| !op.conds.iter().any(|c| c.lit == e.lit && same(op, c.at, e.at)))
                    .map(|e| (e.lit, e.at))
                    .collect()
            })
            .collect();
        Tokens { uses, makes }
    }
}

impl Search<'_, '_> {
    /// Whether a plan of a problem where no step is ever inserted cannot
    /// lead to a plan: one of its steps can never run ([`Search::stuck`]),
    /// or a literal is used up more often than it is made
    /// ([`Search::starved`]). Not in a repair: the old steps of its start
    /// plans ran from another state than the initial one.
    pub(super) fn doomed(&self, p: &Plan) -> bool {
        self.tokens.is_some()
            && !self.from_seeds.get()
            && (self.stuck(p).is_some() || self.starved(p).is_some() || self.unmet(p).is_some())
    }

    /// An unrefined abstract step of the plan, and a literal that every
    /// refinement of it needs from outside it ([`Heuristic::needs`]) and
    /// that nothing can make true before it: the initial state does not,
    /// no step that can come before its end makes it, and no other
    /// unrefined abstract step that can start before its end may. The
    /// need falls inside the step, so its producer would have to. An
    /// IPC 2020 Woodworking `grindNplane` bound to grind a part that is
    /// not untreated, as untreated: each of its methods needs the part
    /// untreated, which nothing makes it; before, it was found dead only
    /// once it and the choice of its action's free parameters were
    /// refined, in every plan that had it.
    ///
    /// [`Heuristic::needs`]: super::super::heuristic::Heuristic::needs
    pub(super) fn unmet(&self, p: &Plan) -> Option<(u32, Lit)> {
        let task = self.task;
        if self.h.needs.is_none() || p.abstracts.is_empty() {
            return None;
        }
        let missing = |l: &Lit| !task.holds_initially(*l);
        let mut wanted: Vec<Lit> = p
            .abstracts
            .iter()
            .filter_map(|&a| p.op_of(a))
            .flat_map(|o| self.h.needs(o).iter().copied())
            .filter(missing)
            .collect();
        if wanted.is_empty() {
            return None;
        }
        wanted.sort_unstable();
        wanted.dedup();
        // The plan's effects on them: (literal, time point).
        let mut made: Vec<(Lit, Tp)> = Vec::new();
        for s in 0..p.steps.len() as u32 {
            made.extend(p.effects(task, s).filter(|(l, _)| wanted.binary_search(l).is_ok()));
        }
        made.sort_unstable();
        for &a in p.abstracts.iter() {
            let Some(op) = p.op_of(a) else { continue };
            let end = p.steps[a as usize].end;
            for &l in self.h.needs(op).iter().filter(|l| missing(l)) {
                let from = made.partition_point(|&(x, _)| x < l);
                if made[from..].iter().take_while(|&&(x, _)| x == l).any(|&(_, tp)| !p.stn.before(end, tp)) {
                    continue;
                }
                let may = p.abstracts.iter().any(|&b| {
                    let st = p.steps[b as usize];
                    b != a
                        && matches!(st.kind, Kind::Op(o) if self.h.may_add(o, l))
                        && !p.stn.before(end, st.start)
                });
                if !may {
                    return Some((a, l));
                }
            }
        }
        None
    }

    /// An elementary step of the plan whose conditions no run of the plan
    /// can make true: relaxed reachability (deletions ignored) from the
    /// initial state through the plan's own steps, in the plan's order (a
    /// condition counts as reached when a reached step that can come before
    /// it makes it, or an unrefined abstract step that can come before it
    /// may). Every step of the plan is in every plan it leads to, so the
    /// plan is dead: two `drive`s, from `a` to `b` and from `b` to `a`,
    /// where nothing else brings the truck to `a` or `b`, each wait for the
    /// other. Such a pair is found only once every way to link and order
    /// the rest of the plan has been tried, else.
    pub(super) fn stuck(&self, p: &Plan) -> Option<u32> {
        let task = self.task;
        let n = p.steps.len();
        // Steps that run whatever the others do: the initial state, the
        // goal, timed literals, abstract steps (what they declare, or what
        // their methods add, is counted as made).
        let mut reached: Vec<bool> = p
            .steps
            .iter()
            .map(|st| match st.kind {
                Kind::Op(o) => task.ops[o as usize].is_abstract || task.ops[o as usize].conds.is_empty(),
                _ => true,
            })
            .collect();
        let mut waiting: Vec<u32> = (0..n as u32).filter(|&s| !reached[s as usize]).collect();
        if waiting.is_empty() {
            return None;
        }
        waiting.sort_by(|&a, &b| {
            p.stn.est(p.steps[a as usize].start).total_cmp(&p.stn.est(p.steps[b as usize].start))
        });
        // Every effect, by literal: (literal, step, time point).
        let mut made: Vec<(Lit, u32, Tp)> = Vec::new();
        for s in 0..n as u32 {
            made.extend(p.effects(task, s).map(|(l, tp)| (l, s, tp)));
        }
        made.sort_unstable();
        let abstract_may = |l: Lit, need: Tp| {
            p.abstracts.iter().any(|&a| {
                let st = p.steps[a as usize];
                matches!(st.kind, Kind::Op(op) if self.h.may_add(op, l)) && !p.stn.before(need, st.start)
            })
        };
        loop {
            let mut progress = false;
            waiting.retain(|&s| {
                let step = p.steps[s as usize];
                let Kind::Op(o) = step.kind else { return false };
                let ok = task.ops[o as usize].conds.iter().all(|c| {
                    let need = step.tp(c.at);
                    if task.holds_initially(c.lit) {
                        return true;
                    }
                    let from = made.partition_point(|&(l, _, _)| l < c.lit);
                    made[from..]
                        .iter()
                        .take_while(|&&(l, _, _)| l == c.lit)
                        .any(|&(_, t, tp)| reached[t as usize] && tp != need && !p.stn.before(need, tp))
                        || abstract_may(c.lit, need)
                });
                if ok {
                    reached[s as usize] = true;
                    progress = true;
                }
                !ok
            });
            if waiting.is_empty() {
                return None;
            }
            if !progress {
                return waiting.first().copied();
            }
        }
    }

    /// A literal that the plan's steps use up more often than its steps
    /// (and the initial state) can make it, as the module says: `None` when
    /// each user can be given a maker of its own that can come before it,
    /// or an unrefined abstract step that may still make it.
    pub(super) fn starved(&self, p: &Plan) -> Option<Lit> {
        let tokens = self.tokens.as_ref()?;
        let task = self.task;
        // The users of each literal, by the time point that uses it up.
        let mut users: Vec<(Lit, Tp)> = Vec::new();
        for step in p.steps.iter() {
            let Kind::Op(o) = step.kind else { continue };
            users.extend(tokens.uses[o as usize].iter().map(|&(l, at)| (l, step.tp(at))));
        }
        if users.is_empty() {
            return None;
        }
        users.sort_unstable();
        let mut lits: Vec<Lit> = users.iter().map(|&(l, _)| l).collect();
        lits.dedup();
        let wanted = |l: Lit| lits.binary_search(&l).is_ok();
        // Their makers: the initial state, and the steps' effects on them.
        let mut makers: Vec<(Lit, Tp)> =
            lits.iter().filter(|&&l| task.holds_initially(l)).map(|&l| (l, ORIGIN)).collect();
        for step in p.steps.iter() {
            match step.kind {
                Kind::Op(o) => makers.extend(
                    tokens.makes[o as usize]
                        .iter()
                        .filter(|&&(l, _)| wanted(l))
                        .map(|&(l, at)| (l, step.tp(at))),
                ),
                Kind::Til(t) => {
                    let l = task.tils[t as usize].lit;
                    if wanted(l) {
                        makers.push((l, step.start));
                    }
                }
                Kind::Init | Kind::Goal => {}
            }
        }
        makers.sort_unstable();
        let group = |v: &[(Lit, Tp)], l: Lit| -> Vec<Tp> {
            let from = v.partition_point(|&(x, _)| x < l);
            let to = v.partition_point(|&(x, _)| x <= l);
            v[from..to].iter().map(|&(_, tp)| tp).collect()
        };
        for &l in &lits {
            let mut used = group(&users, l);
            let made = group(&makers, l);
            if used.len() <= made.len() && matched(p, &used, &made) {
                continue;
            }
            // A user that an unrefined abstract step that may make the
            // literal can come before is served by it.
            let may: Vec<Tp> = p
                .abstracts
                .iter()
                .map(|&a| p.steps[a as usize])
                .filter(|st| matches!(st.kind, Kind::Op(op) if self.h.may_add(op, l)))
                .map(|st| st.start)
                .collect();
            used.retain(|&u| !may.iter().any(|&a| !p.stn.before(u, a)));
            if used.len() > made.len() || !matched(p, &used, &made) {
                return Some(l);
            }
        }
        None
    }
}

/// Whether every user can be given a maker of its own that can come before
/// it (Kuhn's augmenting paths).
fn matched(p: &Plan, users: &[Tp], makers: &[Tp]) -> bool {
    let can = |u: Tp, m: Tp| u != m && !p.stn.before(u, m);
    const FREE: usize = usize::MAX;
    let mut owner = vec![FREE; makers.len()];
    for (i, &u) in users.iter().enumerate() {
        // A free maker at once, else an augmenting path.
        if let Some(j) = (0..makers.len()).find(|&j| owner[j] == FREE && can(u, makers[j])) {
            owner[j] = i;
            continue;
        }
        let mut seen = vec![false; makers.len()];
        if !augment(i, users, makers, &mut owner, &mut seen, &can) {
            return false;
        }
    }
    true
}

/// One augmenting path from user `i` (iterative: the depth is bounded by
/// the users, which the input decides).
fn augment(
    i: usize,
    users: &[Tp],
    makers: &[Tp],
    owner: &mut [usize],
    seen: &mut [bool],
    can: &dyn Fn(Tp, Tp) -> bool,
) -> bool {
    const FREE: usize = usize::MAX;
    // The path: (user, next maker to try), and the maker that led to it.
    let mut path: Vec<(usize, usize, usize)> = vec![(i, 0, FREE)];
    while let Some(&mut (u, ref mut next, _)) = path.last_mut() {
        let mut found = None;
        while *next < makers.len() {
            let j = *next;
            *next += 1;
            if !seen[j] && can(users[u], makers[j]) {
                seen[j] = true;
                found = Some(j);
                break;
            }
        }
        match found {
            None => {
                path.pop();
            }
            Some(j) if owner[j] == FREE => {
                // Flip the path: each user takes the maker that led on from it.
                let mut j = j;
                while let Some((u, _, via)) = path.pop() {
                    owner[j] = u;
                    j = via;
                }
                return true;
            }
            Some(j) => path.push((owner[j], 0, j)),
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::super::super::plan::Plan;
    use super::super::super::task::Task;
    use super::super::{Flaw, Search};

    /// The plan of `problem` whose only `:htn` task, `job`, is refined by
    /// the method named `method`, with `f` run on it.
    fn refined(
        domain: &str,
        method: &str,
        f: impl FnOnce(&Task<'_>, &Search<'_, '_>, Plan) + std::panic::UnwindSafe,
    ) {
        let problem = "(define (problem p) (:domain d) (:htn :subtasks (and (job))) (:init (token)))";
        let method = method.to_string();
        super::super::test_support::with_search(
            ("domain.hddl", "problem.hddl"),
            domain,
            problem,
            move |prepared, search| {
                let plan = super::super::test_support::refined_by(prepared, search, &method);
                f(&prepared.task, search, plan);
            },
        );
    }

    /// `use-a` and `use-b` each take the one `(token)`; `give` makes one.
    const TOKEN: &str = "(define (domain d) (:requirements :hierarchy :negative-preconditions)
      (:predicates (token) (a-done) (b-done))
      (:task job :parameters ())
      (:task more :parameters ())
      (:method both :parameters () :task (job) :subtasks (and (use-a) (use-b)))
      (:method refill :parameters () :task (job) :subtasks (and (use-a) (give) (use-b)))
      (:method late :parameters () :task (job)
        :ordered-subtasks (and (use-a) (use-b) (give)))
      (:method later :parameters () :task (job) :subtasks (and (use-a) (use-b) (more)))
      (:method give-it :parameters () :task (more) :subtasks (and (give)))
      (:action use-a :parameters () :precondition (token) :effect (and (not (token)) (a-done)))
      (:action use-b :parameters () :precondition (token) :effect (and (not (token)) (b-done)))
      (:action give :parameters () :effect (token)))";

    /// Two steps that use up the initial `(token)` and nothing that makes
    /// it again: each link alone has a producer (the initial state), and
    /// the plan used to be found dead only once both links and their
    /// threats were tried. It is dropped when scored.
    #[test]
    fn a_literal_used_up_twice_and_made_once_is_starved() {
        for (method, dead) in [("both", true), ("refill", false), ("late", true), ("later", false)] {
            refined(TOKEN, method, |task, search, mut plan| {
                let starved = search.starved(&plan).map(|l| task.show_lit(l));
                assert_eq!(starved.is_some(), dead, "{method}: {starved:?}");
                if dead {
                    assert_eq!(starved.as_deref(), Some("(token)"));
                    // Not a link nothing supports: the initial state does.
                    let ready = search.ready_links(&plan);
                    assert!(search.dead_link(&plan, &ready).is_none(), "{method}");
                }
                assert_eq!(search.score(&mut plan).is_none(), dead, "{method}");
            });
        }
    }

    /// `paint` needs `(blue)` however it is refined (both its methods'
    /// actions need it; only `paint-b`'s needs `(red)` too), and only
    /// `make-blue` makes it.
    const PAINT: &str = "(define (domain d) (:requirements :hierarchy)
      (:predicates (token) (red) (blue) (done))
      (:task job :parameters ())
      (:task paint :parameters ())
      (:method bare :parameters () :task (job) :subtasks (and (paint)))
      (:method made :parameters () :task (job) :subtasks (and (make-blue) (paint)))
      (:method late :parameters () :task (job) :ordered-subtasks (and (paint) (make-blue)))
      (:method paint-a :parameters () :task (paint) :subtasks (and (use-blue)))
      (:method paint-b :parameters () :task (paint) :subtasks (and (use-blue-red)))
      (:action use-blue :parameters () :precondition (blue) :effect (done))
      (:action use-blue-red :parameters () :precondition (and (blue) (red)) :effect (done))
      (:action make-blue :parameters () :effect (blue)))";

    /// An unrefined `paint` with nothing that makes `(blue)` before it is
    /// dead before either of its methods is tried; a `make-blue` that can
    /// come before it keeps it.
    #[test]
    fn an_abstract_step_that_needs_what_nothing_makes_before_it_is_unmet() {
        for (method, dead) in [("bare", true), ("made", false), ("late", true)] {
            refined(PAINT, method, |task, search, mut plan| {
                let paint = task.ops.iter().position(|o| &*o.name == "paint").expect("paint") as u32;
                let needs: Vec<String> = search.h.needs(paint).iter().map(|&l| task.show_lit(l)).collect();
                assert_eq!(needs, ["(blue)"], "what every refinement of paint needs");
                let unmet = search.unmet(&plan).map(|(s, l)| (plan.op_of(s), task.show_lit(l)));
                assert_eq!(unmet.is_some(), dead, "{method}: {unmet:?}");
                if dead {
                    assert_eq!(unmet, Some((Some(paint), "(blue)".to_string())));
                }
                assert_eq!(search.score(&mut plan).is_none(), dead, "{method}");
            });
        }
    }

    /// `a` needs what `b` makes and `b` what `a` makes: neither can ever
    /// run first, unless `c` starts the chain.
    const CYCLE: &str = "(define (domain d) (:requirements :hierarchy)
      (:predicates (token) (p) (q))
      (:task job :parameters ())
      (:method loop :parameters () :task (job) :subtasks (and (a) (b)))
      (:method seeded :parameters () :task (job) :subtasks (and (c) (a) (b)))
      (:action a :parameters () :precondition (p) :effect (q))
      (:action b :parameters () :precondition (q) :effect (p))
      (:action c :parameters () :effect (p)))";

    #[test]
    fn steps_that_wait_for_each_other_are_stuck() {
        for (method, dead) in [("loop", true), ("seeded", false)] {
            refined(CYCLE, method, |task, search, mut plan| {
                let stuck = search.stuck(&plan).map(|s| task.show_op(plan.op_of(s).expect("an op")));
                assert_eq!(stuck.is_some(), dead, "{method}: {stuck:?}");
                let ready = search.ready_links(&plan);
                assert!(search.dead_link(&plan, &ready).is_none(), "{method}: each link has a producer");
                assert_eq!(search.score(&mut plan).is_none(), dead, "{method}");
            });
        }
    }

    /// `use-x`'s `(x)` has one producer, `use-y`'s `(y)` two; `use-y` is
    /// the newest step, whose links `local` order takes first. The forced
    /// link goes first.
    #[test]
    fn a_link_with_one_producer_is_chosen_first() {
        let domain = "(define (domain d) (:requirements :hierarchy)
          (:predicates (token) (x) (y))
          (:task job :parameters ())
          (:method m :parameters () :task (job)
            :subtasks (and (make-x) (make-y-a) (make-y-b) (use-x) (use-y)))
          (:action make-x :parameters () :effect (x))
          (:action make-y-a :parameters () :effect (y))
          (:action make-y-b :parameters () :effect (y))
          (:action use-x :parameters () :precondition (x) :effect ())
          (:action use-y :parameters () :precondition (y) :effect ()))";
        refined(domain, "m", |task, search, mut plan| {
            let Some(Flaw::Open(i)) = search.select(&mut plan) else { panic!("an open link") };
            assert_eq!(task.show_lit(plan.open[i].lit), "(x)");
        });
    }
}
