//! Matching the subtask ids of a decomposition with the subtasks of its
//! method (or the root steps of a plan with the tasks of the problem's
//! `:htn`): a one-to-one assignment under which every step's task and
//! arguments are the method subtask's, with one binding of the method's
//! variables for all of them.
//!
//! As pandaPIparser's verifier, the steps are matched in the order the plan
//! lists them, and (unless told to ignore it) that order must be one the
//! method's ordering allows: a method subtask can take a position only once
//! every subtask ordered before it has one. When no matching exists, the
//! largest partial matching explains what is missing and what is wrong.
//!
//! A method may have the same subtask twice (`(task1 (y))` and `(task2
//! (y))`, ordered `task1 < task2`): the steps then match either way, and only
//! one way may respect the method's orderings in the plan. When the first
//! matching found does not ([`OrderingCheck`]), the others are searched for
//! one that does, as pandaPIparser tries all its matchings. Each search is
//! bounded ([`BUDGET`] nodes); when the search for a matching whose
//! orderings hold reaches it, the first matching is kept and the outcome says
//! the orderings are undecided.
//!
//! Pure: names are the domain's lower-case keys, objects their keys.

use crate::model::Str;

/// An argument of a method subtask (or of the method's task).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum PTerm {
    Var(Str),
    Const(Str),
    /// A term that is not an object (an object fluent): matches anything.
    Any,
}

/// A method subtask: the action or task, and its arguments.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Pattern {
    pub name: Str,
    pub args: Vec<PTerm>,
}

/// A plan step, resolved: its action or task, and its objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Instance<'a> {
    pub name: &'a str,
    pub args: &'a [Str],
}

/// Where a variable got its value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Source {
    /// The argument at this position of the decomposed task.
    Head(usize),
    /// The step at this position of the decomposition's subtask list.
    Subtask(usize),
}

/// A variable and its value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Bound {
    pub var: Str,
    pub value: Str,
    pub source: Source,
}

/// The value of a variable in a binding.
pub(crate) fn lookup<'b>(binding: &'b [Bound], var: &str) -> Option<&'b Bound> {
    binding.iter().find(|b| b.var == var)
}

/// Whether a matching's orderings hold in the plan: the method's orderings
/// on the steps matched with its subtasks.
pub(crate) trait OrderingCheck {
    /// No ordering between the step at `pos` and another step already
    /// matched is violated (`assign[pos]`: the pattern of the step at `pos`,
    /// when matched): a necessary condition for [`OrderingCheck::complete`],
    /// which prunes the search.
    fn partial(&self, assign: &[Option<usize>], pos: usize) -> bool;
    /// Every ordering holds under a complete matching.
    fn complete(&self, assign: &[usize]) -> bool;
}

/// A matching problem.
pub(crate) struct Problem<'a> {
    pub patterns: &'a [Pattern],
    /// For each pattern, the patterns the method orders strictly before it.
    pub preds: &'a [Vec<usize>],
    pub instances: &'a [Instance<'a>],
    /// The binding from the decomposed task.
    pub initial: &'a [Bound],
    /// Whether an object may be the value of a variable (its type).
    pub type_ok: &'a dyn Fn(&str, &str) -> bool,
    /// Whether a complete binding satisfies the method's static constraints.
    pub accept: &'a dyn Fn(&[Bound]) -> bool,
    /// Whether the listed order must be one the method's ordering allows.
    pub use_order: bool,
    /// The orderings in the plan: a matching under which they hold is
    /// preferred to one under which they do not.
    pub orderings: Option<&'a dyn OrderingCheck>,
}

/// What matching found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Outcome {
    /// `assign[pos]` is the pattern of the step at `pos`. When the orderings
    /// do not hold under it, they hold under no other matching, unless
    /// `undecided`: the search for one reached its budget.
    Matched { assign: Vec<usize>, binding: Vec<Bound>, undecided: bool },
    /// A matching exists, but not in the order the steps are listed.
    Unordered { assign: Vec<usize>, binding: Vec<Bound>, undecided: bool },
    /// Matchings exist, but each violates a static constraint (the first found).
    Rejected { assign: Vec<usize>, binding: Vec<Bound> },
    /// No one-to-one matching: the largest partial one (`None`: the step
    /// matches no pattern left).
    Partial { assign: Vec<Option<usize>>, binding: Vec<Bound> },
    /// Too many combinations to decide within the budget.
    TooComplex,
}

/// How many search nodes one search may cost: the search for a matching,
/// and the search for one whose orderings hold (a complete matching whose
/// orderings are checked costs one node per pattern more).
pub(crate) const BUDGET: usize = 200_000;

struct Search<'p, 'a> {
    p: &'p Problem<'a>,
    used: Vec<bool>,
    assign: Vec<Option<usize>>,
    binding: Vec<Bound>,
    budget: usize,
    ordered: bool,
    /// Whether only matchings whose orderings hold are complete.
    by_orderings: bool,
    rejected: Option<(Vec<usize>, Vec<Bound>)>,
    best: Option<(usize, Vec<Option<usize>>, Vec<Bound>)>,
}

/// The search ran out of budget.
struct Exhausted;

impl Search<'_, '_> {
    fn tick(&mut self) -> Result<(), Exhausted> {
        if self.budget == 0 {
            return Err(Exhausted);
        }
        self.budget -= 1;
        Ok(())
    }

    /// Extends the binding so that the step at `pos` is pattern `j`; on
    /// failure, the binding may have grown (the caller truncates it).
    fn unify(&mut self, j: usize, pos: usize) -> bool {
        let pat = &self.p.patterns[j];
        let inst = self.p.instances[pos];
        if pat.name != inst.name || pat.args.len() != inst.args.len() {
            return false;
        }
        for (t, v) in pat.args.iter().zip(inst.args) {
            match t {
                PTerm::Any => {}
                PTerm::Const(c) => {
                    if c != v {
                        return false;
                    }
                }
                PTerm::Var(x) => match lookup(&self.binding, x) {
                    Some(b) => {
                        if b.value != *v {
                            return false;
                        }
                    }
                    None => {
                        if !(self.p.type_ok)(x, v) {
                            return false;
                        }
                        self.binding.push(Bound {
                            var: x.clone(),
                            value: v.clone(),
                            source: Source::Subtask(pos),
                        });
                    }
                },
            }
        }
        true
    }

    fn available(&self, j: usize) -> bool {
        !self.used[j] && (!self.ordered || self.p.preds[j].iter().all(|&q| self.used[q]))
    }

    /// A complete matching, depth first without recursion (a decomposition
    /// may have thousands of subtasks): `levels[pos]` is the next pattern to
    /// try for the step at `pos` and the binding's length before it. With
    /// `by_orderings`, only a matching whose orderings hold, pruned by the
    /// orderings a partial matching already violates.
    fn full(&mut self) -> Result<bool, Exhausted> {
        let n = self.p.instances.len();
        let mut levels: Vec<(usize, usize)> = Vec::new();
        // Whether the search enters the position `levels.len()` (else it
        // comes back to the last level, whose choice is undone).
        let mut entering = true;
        loop {
            if entering {
                self.tick()?;
                if levels.len() == n {
                    if (self.p.accept)(&self.binding) {
                        let Some(check) = self.p.orderings.filter(|_| self.by_orderings) else {
                            return Ok(true);
                        };
                        self.budget = self.budget.saturating_sub(self.p.patterns.len());
                        let assign: Vec<usize> = self.assign.iter().map(|a| a.unwrap_or(0)).collect();
                        if check.complete(&assign) {
                            return Ok(true);
                        }
                    } else if self.rejected.is_none() && !self.by_orderings {
                        let assign = self.assign.iter().map(|a| a.unwrap_or(0)).collect();
                        self.rejected = Some((assign, self.binding.clone()));
                    }
                    entering = false;
                } else {
                    levels.push((0, self.binding.len()));
                }
            }
            let Some(&(start, mark)) = levels.last() else { return Ok(false) };
            let pos = levels.len() - 1;
            if !entering {
                if let Some(j) = self.assign[pos].take() {
                    self.used[j] = false;
                }
                self.binding.truncate(mark);
            }
            let mut chosen = None;
            for j in start..self.p.patterns.len() {
                if !self.available(j) {
                    continue;
                }
                if self.unify(j, pos) {
                    chosen = Some(j);
                    break;
                }
                self.binding.truncate(mark);
            }
            match chosen {
                Some(j) => {
                    self.used[j] = true;
                    self.assign[pos] = Some(j);
                    levels[pos].0 = j + 1;
                    let pruned = self.by_orderings
                        && self.p.orderings.is_some_and(|check| !check.partial(&self.assign, pos));
                    entering = !pruned;
                }
                None => {
                    levels.pop();
                    entering = false;
                }
            }
        }
    }

    /// The largest partial matching, depth first without recursion: each
    /// step is matched with each pattern left in turn, then left unmatched
    /// (the last branch: its level is done then).
    fn partial(&mut self) -> Result<(), Exhausted> {
        struct Level {
            pos: usize,
            matched: usize,
            /// The next pattern to try, and the binding's length before.
            next: usize,
            mark: usize,
        }
        let n = self.p.instances.len();
        let mut levels: Vec<Level> = Vec::new();
        // The position entered next, with how many steps before it are matched.
        let mut enter = (0, 0);
        loop {
            let (pos, matched) = enter;
            self.tick()?;
            let best = self.best.as_ref().map_or(0, |b| b.0);
            // Whether the search comes back at once (to the last level, whose
            // choice is undone): no better matching below, or a complete one.
            let back = if self.best.is_some() && matched + (n - pos) <= best {
                true
            } else if pos == n {
                self.best = Some((matched, self.assign.clone(), self.binding.clone()));
                true
            } else {
                levels.push(Level { pos, matched, next: 0, mark: self.binding.len() });
                false
            };
            let Some(level) = levels.last_mut() else { return Ok(()) };
            if back {
                if let Some(j) = self.assign[level.pos].take() {
                    self.used[j] = false;
                }
                self.binding.truncate(level.mark);
            }
            let mut chosen = None;
            for j in level.next..self.p.patterns.len() {
                if self.used[j] {
                    continue;
                }
                if self.unify(j, level.pos) {
                    chosen = Some(j);
                    break;
                }
                self.binding.truncate(level.mark);
            }
            match chosen {
                Some(j) => {
                    level.next = j + 1;
                    self.used[j] = true;
                    self.assign[level.pos] = Some(j);
                    enter = (level.pos + 1, level.matched + 1);
                }
                None => {
                    enter = (level.pos + 1, level.matched);
                    levels.pop();
                }
            }
        }
    }
}

/// Matches the steps with the patterns.
pub(crate) fn matching(p: &Problem<'_>) -> Outcome {
    matching_by(p, |s| s.full(), |s| s.partial())
}

/// [`matching`], with the searches for a complete and for the largest
/// partial matching given (the tests compare them with recursive ones).
fn matching_by(
    p: &Problem<'_>,
    full: fn(&mut Search<'_, '_>) -> Result<bool, Exhausted>,
    partial: fn(&mut Search<'_, '_>) -> Result<(), Exhausted>,
) -> Outcome {
    let (n, k) = (p.instances.len(), p.patterns.len());
    let mut s = Search {
        p,
        used: vec![false; k],
        assign: vec![None; n],
        binding: p.initial.to_vec(),
        budget: BUDGET,
        ordered: p.use_order,
        by_orderings: false,
        rejected: None,
        best: None,
    };
    let done = |s: &Search<'_, '_>| {
        let assign: Vec<usize> = s.assign.iter().map(|a| a.unwrap_or(0)).collect();
        (assign, s.binding.clone())
    };
    let reset = |s: &mut Search<'_, '_>| {
        s.used.iter_mut().for_each(|u| *u = false);
        s.assign.iter_mut().for_each(|a| *a = None);
        s.binding = p.initial.to_vec();
    };
    // A matching found: when its orderings do not hold, another whose do.
    let settle = |s: &mut Search<'_, '_>| -> (Vec<usize>, Vec<Bound>, bool) {
        let (assign, binding) = done(s);
        let Some(check) = p.orderings else { return (assign, binding, false) };
        if check.complete(&assign) {
            return (assign, binding, false);
        }
        reset(s);
        s.by_orderings = true;
        s.budget = BUDGET;
        let found = full(s);
        s.by_orderings = false;
        match found {
            Ok(true) => {
                let (assign, binding) = done(s);
                (assign, binding, false)
            }
            Ok(false) => (assign, binding, false),
            Err(Exhausted) => (assign, binding, true),
        }
    };
    if n == k {
        match full(&mut s) {
            Err(Exhausted) => return Outcome::TooComplex,
            Ok(true) => {
                let (assign, binding, undecided) = settle(&mut s);
                return Outcome::Matched { assign, binding, undecided };
            }
            Ok(false) => {}
        }
        if p.use_order {
            reset(&mut s);
            s.ordered = false;
            match full(&mut s) {
                Err(Exhausted) => return Outcome::TooComplex,
                Ok(true) => {
                    let (assign, binding, undecided) = settle(&mut s);
                    return Outcome::Unordered { assign, binding, undecided };
                }
                Ok(false) => {}
            }
        }
        if let Some((assign, binding)) = s.rejected.take() {
            return Outcome::Rejected { assign, binding };
        }
    }
    reset(&mut s);
    s.ordered = false;
    match partial(&mut s) {
        Err(Exhausted) => Outcome::TooComplex,
        Ok(()) => match s.best {
            Some((_, assign, binding)) => Outcome::Partial { assign, binding },
            None => Outcome::Partial { assign: vec![None; n], binding: p.initial.to_vec() },
        },
    }
}

/// Why a step matches no pattern left, under a binding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Misfit {
    /// No pattern has the step's action or task.
    NoSuchName,
    /// Every pattern with that name is taken, by the steps at these positions.
    Taken(Vec<usize>),
    /// A pattern with that name is left, but an argument disagrees.
    Argument { pattern: usize, arg: usize, why: ArgMisfit },
    /// Every argument agrees, but the method's constraints reject the binding.
    Constraints { pattern: usize },
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum ArgMisfit {
    /// The pattern has this constant there.
    Constant(Str),
    /// The variable already has another value.
    Bound(Bound),
    /// The object is not of the variable's type.
    Type(Str),
    /// The pattern has another number of arguments.
    Arity(usize),
}

/// Explains why the step at `pos` matches none of the free patterns.
pub(crate) fn explain(p: &Problem<'_>, assign: &[Option<usize>], binding: &[Bound], pos: usize) -> Misfit {
    let inst = p.instances[pos];
    let named: Vec<usize> = (0..p.patterns.len()).filter(|&j| p.patterns[j].name == inst.name).collect();
    if named.is_empty() {
        return Misfit::NoSuchName;
    }
    let taken_by = |j: usize| assign.iter().position(|a| *a == Some(j));
    let free: Vec<usize> = named.iter().copied().filter(|&j| taken_by(j).is_none()).collect();
    let Some(&j) = free.first() else {
        return Misfit::Taken(named.iter().filter_map(|&j| taken_by(j)).collect());
    };
    // Of the free patterns with the name, the one that disagrees latest.
    let mut worst: Option<(usize, usize, ArgMisfit)> = None;
    for &j in &free {
        let pat = &p.patterns[j];
        if pat.args.len() != inst.args.len() {
            let m = (j, 0, ArgMisfit::Arity(pat.args.len()));
            if worst.is_none() {
                worst = Some(m);
            }
            continue;
        }
        let mut local: Vec<Bound> = binding.to_vec();
        for (k, (t, v)) in pat.args.iter().zip(inst.args).enumerate() {
            let why = match t {
                PTerm::Any => None,
                PTerm::Const(c) => (c != v).then(|| ArgMisfit::Constant(c.clone())),
                PTerm::Var(x) => match lookup(&local, x) {
                    Some(b) if b.value != *v => Some(ArgMisfit::Bound(b.clone())),
                    Some(_) => None,
                    None if !(p.type_ok)(x, v) => Some(ArgMisfit::Type(x.clone())),
                    None => {
                        local.push(Bound { var: x.clone(), value: v.clone(), source: Source::Subtask(pos) });
                        None
                    }
                },
            };
            if let Some(why) = why {
                if worst.as_ref().is_none_or(|w| k > w.1 || matches!(w.2, ArgMisfit::Arity(_))) {
                    worst = Some((j, k, why));
                }
                break;
            }
        }
    }
    match worst {
        Some((pattern, arg, why)) => Misfit::Argument { pattern, arg, why },
        // Every argument agrees one by one: the static constraints reject it.
        None => Misfit::Constraints { pattern: j },
    }
}

/// An order of the listed steps that the method's ordering allows, as
/// close to the listed one as possible (positions into the list).
pub(crate) fn allowed_order(preds: &[Vec<usize>], assign: &[usize]) -> Vec<usize> {
    let n = assign.len();
    let pos_of = |j: usize| assign.iter().position(|&a| a == j);
    let mut placed = vec![false; n];
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let next = (0..n).find(|&pos| {
            !placed[pos] && preds[assign[pos]].iter().all(|&q| pos_of(q).is_none_or(|qp| placed[qp]))
        });
        // The method's ordering has no cycle (checked with the domain); were
        // it to have one, the rest keeps its listed order.
        let pos = next.unwrap_or_else(|| (0..n).find(|&pos| !placed[pos]).unwrap_or(0));
        placed[pos] = true;
        out.push(pos);
    }
    out
}

/// The first listed step that comes before a step the method orders
/// before it: `(early, late)` positions, `late` listed after `early` but
/// ordered first.
pub(crate) fn first_inversion(preds: &[Vec<usize>], assign: &[usize]) -> Option<(usize, usize)> {
    for (pos, &j) in assign.iter().enumerate() {
        for &q in &preds[j] {
            if let Some(qp) = assign.iter().position(|&a| a == q)
                && qp > pos
            {
                return Some((pos, qp));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pat(name: &str, args: &[&str]) -> Pattern {
        Pattern {
            name: name.into(),
            args: args
                .iter()
                .map(|a| {
                    if let Some(v) = a.strip_prefix('?') {
                        PTerm::Var(v.into())
                    } else {
                        PTerm::Const((*a).into())
                    }
                })
                .collect(),
        }
    }

    fn run(
        patterns: &[Pattern],
        preds: &[Vec<usize>],
        steps: &[(&str, &[&str])],
        use_order: bool,
    ) -> Outcome {
        let args: Vec<Vec<Str>> =
            steps.iter().map(|(_, a)| a.iter().map(|&x| Str::from(x)).collect()).collect();
        let instances: Vec<Instance<'_>> =
            steps.iter().zip(&args).map(|((n, _), a)| Instance { name: n, args: a }).collect();
        let p = Problem {
            patterns,
            preds,
            instances: &instances,
            initial: &[],
            type_ok: &|_, _| true,
            accept: &|_| true,
            use_order,
            orderings: None,
        };
        matching(&p)
    }

    #[test]
    fn repeated_tasks_are_told_apart_by_their_binding() {
        // (get-to ?v ?l1) (load ?v ?l1 ?p) (get-to ?v ?l2) (unload ?v ?l2 ?p), in order.
        let pats = [
            pat("get-to", &["?v", "?l1"]),
            pat("load", &["?v", "?l1", "?p"]),
            pat("get-to", &["?v", "?l2"]),
            pat("unload", &["?v", "?l2", "?p"]),
        ];
        let preds = vec![vec![], vec![0], vec![1], vec![2]];
        let steps: [(&str, &[&str]); 4] = [
            ("get-to", &["t", "a"]),
            ("load", &["t", "a", "p"]),
            ("get-to", &["t", "b"]),
            ("unload", &["t", "b", "p"]),
        ];
        match run(&pats, &preds, &steps, true) {
            Outcome::Matched { assign, .. } => assert_eq!(assign, vec![0, 1, 2, 3]),
            other => panic!("{other:?}"),
        }
        // Listed out of order: found without the order, and a fixed order proposed.
        let shuffled = [steps[3], steps[2], steps[0], steps[1]];
        match run(&pats, &preds, &shuffled, true) {
            Outcome::Unordered { assign, .. } => {
                assert_eq!(assign, vec![3, 2, 0, 1]);
                assert_eq!(allowed_order(&preds, &assign), vec![2, 3, 1, 0]);
                assert_eq!(first_inversion(&preds, &assign), Some((0, 1)));
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(run(&pats, &preds, &shuffled, false), Outcome::Matched { .. }));
    }

    /// The plan runs the step listed second before the step listed first:
    /// the orderings hold when the listed second is the subtask ordered first.
    struct SecondRunsFirst;

    impl OrderingCheck for SecondRunsFirst {
        fn partial(&self, assign: &[Option<usize>], _pos: usize) -> bool {
            assign.get(1).copied().flatten().is_none_or(|j| j == 0)
        }
        fn complete(&self, assign: &[usize]) -> bool {
            assign.get(1) == Some(&0)
        }
    }

    /// No matching's orderings hold.
    struct Never;

    impl OrderingCheck for Never {
        fn partial(&self, _: &[Option<usize>], _: usize) -> bool {
            true
        }
        fn complete(&self, _: &[usize]) -> bool {
            false
        }
    }

    fn run_with(
        patterns: &[Pattern],
        preds: &[Vec<usize>],
        steps: &[(&str, &[&str])],
        use_order: bool,
        orderings: &dyn OrderingCheck,
    ) -> Outcome {
        let args: Vec<Vec<Str>> =
            steps.iter().map(|(_, a)| a.iter().map(|&x| Str::from(x)).collect()).collect();
        let instances: Vec<Instance<'_>> =
            steps.iter().zip(&args).map(|((n, _), a)| Instance { name: n, args: a }).collect();
        let p = Problem {
            patterns,
            preds,
            instances: &instances,
            initial: &[],
            type_ok: &|_, _| true,
            accept: &|_| true,
            use_order,
            orderings: Some(orderings),
        };
        matching(&p)
    }

    #[test]
    fn identical_subtasks_are_matched_the_way_the_orderings_hold() {
        // (task1 (y)) (task2 (y)), task1 < task2: the steps match either way.
        let pats = [pat("y", &[]), pat("y", &[])];
        let preds = vec![vec![], vec![0]];
        let steps: [(&str, &[&str]); 2] = [("y", &[]), ("y", &[])];
        // The listed order ignored: the other way round, where the orderings hold.
        match run_with(&pats, &preds, &steps, false, &SecondRunsFirst) {
            Outcome::Matched { assign, undecided: false, .. } => assert_eq!(assign, vec![1, 0]),
            other => panic!("{other:?}"),
        }
        // In the listed order, the first listed is task1: the orderings fail.
        match run_with(&pats, &preds, &steps, true, &SecondRunsFirst) {
            Outcome::Matched { assign, undecided: false, .. } => assert_eq!(assign, vec![0, 1]),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn the_search_for_orderings_that_hold_is_bounded() {
        // Nine identical subtasks: 9! matchings, more than the budget allows
        // once each complete one is checked; the first matching is kept.
        let pats: Vec<Pattern> = (0..9).map(|_| pat("y", &[])).collect();
        let preds = vec![vec![]; 9];
        let steps: Vec<(&str, &[&str])> = (0..9).map(|_| ("y", &[][..])).collect();
        match run_with(&pats, &preds, &steps, false, &Never) {
            Outcome::Matched { assign, undecided: true, .. } => {
                assert_eq!(assign, (0..9).collect::<Vec<_>>())
            }
            other => panic!("{other:?}"),
        }
        // Three: every matching tried, none holds, decided.
        let steps3 = &steps[..3];
        match run_with(&pats[..3], &preds[..3], steps3, false, &Never) {
            Outcome::Matched { undecided: false, .. } => {}
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_missing_step_leaves_a_partial_matching() {
        let pats = [pat("a", &["?x"]), pat("b", &["?x"]), pat("c", &["?x"])];
        let preds = vec![vec![]; 3];
        let steps: [(&str, &[&str]); 2] = [("a", &["o"]), ("c", &["o"])];
        match run(&pats, &preds, &steps, true) {
            Outcome::Partial { assign, .. } => assert_eq!(assign, vec![Some(0), Some(2)]),
            other => panic!("{other:?}"),
        }
        // A wrong argument: the step is left out, and the misfit names the variable.
        let steps: [(&str, &[&str]); 3] = [("a", &["o"]), ("b", &["q"]), ("c", &["o"])];
        let args: Vec<Vec<Str>> =
            steps.iter().map(|(_, a)| a.iter().map(|&x| Str::from(x)).collect()).collect();
        let instances: Vec<Instance<'_>> =
            steps.iter().zip(&args).map(|((n, _), a)| Instance { name: n, args: a }).collect();
        let p = Problem {
            patterns: &pats,
            preds: &preds,
            instances: &instances,
            initial: &[],
            type_ok: &|_, _| true,
            accept: &|_| true,
            use_order: true,
            orderings: None,
        };
        let Outcome::Partial { assign, binding } = matching(&p) else { panic!() };
        assert_eq!(assign, vec![Some(0), None, Some(2)]);
        match explain(&p, &assign, &binding, 1) {
            Misfit::Argument { pattern: 1, arg: 0, why: ArgMisfit::Bound(b) } => {
                assert_eq!((b.var.as_str(), b.value.as_str(), b.source), ("x", "o", Source::Subtask(0)))
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn constraints_reject_matchings() {
        let pats = [pat("a", &["?x"]), pat("a", &["?y"])];
        let preds = vec![vec![]; 2];
        let steps: [(&str, &[&str]); 2] = [("a", &["o"]), ("a", &["o"])];
        let args: Vec<Vec<Str>> =
            steps.iter().map(|(_, a)| a.iter().map(|&x| Str::from(x)).collect()).collect();
        let instances: Vec<Instance<'_>> =
            steps.iter().zip(&args).map(|((n, _), a)| Instance { name: n, args: a }).collect();
        let distinct = |b: &[Bound]| lookup(b, "x").map(|b| &b.value) != lookup(b, "y").map(|b| &b.value);
        let p = Problem {
            patterns: &pats,
            preds: &preds,
            instances: &instances,
            initial: &[],
            type_ok: &|_, _| true,
            accept: &distinct,
            use_order: true,
            orderings: None,
        };
        assert!(matches!(matching(&p), Outcome::Rejected { .. }));
    }

    /// The recursive searches the iterative ones replaced, as a reference.
    impl Search<'_, '_> {
        fn full_rec(&mut self, pos: usize) -> Result<bool, Exhausted> {
            self.tick()?;
            if pos == self.p.instances.len() {
                if (self.p.accept)(&self.binding) {
                    let Some(check) = self.p.orderings.filter(|_| self.by_orderings) else { return Ok(true) };
                    self.budget = self.budget.saturating_sub(self.p.patterns.len());
                    let assign: Vec<usize> = self.assign.iter().map(|a| a.unwrap_or(0)).collect();
                    return Ok(check.complete(&assign));
                }
                if self.rejected.is_none() && !self.by_orderings {
                    let assign = self.assign.iter().map(|a| a.unwrap_or(0)).collect();
                    self.rejected = Some((assign, self.binding.clone()));
                }
                return Ok(false);
            }
            for j in 0..self.p.patterns.len() {
                if !self.available(j) {
                    continue;
                }
                let mark = self.binding.len();
                if self.unify(j, pos) {
                    self.used[j] = true;
                    self.assign[pos] = Some(j);
                    let pruned = self.by_orderings
                        && self.p.orderings.is_some_and(|check| !check.partial(&self.assign, pos));
                    if !pruned && self.full_rec(pos + 1)? {
                        return Ok(true);
                    }
                    self.used[j] = false;
                    self.assign[pos] = None;
                }
                self.binding.truncate(mark);
            }
            Ok(false)
        }

        fn partial_rec(&mut self, pos: usize, matched: usize) -> Result<(), Exhausted> {
            self.tick()?;
            let n = self.p.instances.len();
            let best = self.best.as_ref().map_or(0, |b| b.0);
            if self.best.is_some() && matched + (n - pos) <= best {
                return Ok(());
            }
            if pos == n {
                self.best = Some((matched, self.assign.clone(), self.binding.clone()));
                return Ok(());
            }
            for j in 0..self.p.patterns.len() {
                if self.used[j] {
                    continue;
                }
                let mark = self.binding.len();
                if self.unify(j, pos) {
                    self.used[j] = true;
                    self.assign[pos] = Some(j);
                    self.partial_rec(pos + 1, matched + 1)?;
                    self.used[j] = false;
                    self.assign[pos] = None;
                }
                self.binding.truncate(mark);
            }
            self.partial_rec(pos + 1, matched)
        }
    }

    /// What [`matching`] returns, with the recursive searches.
    fn reference_matching(p: &Problem<'_>) -> Outcome {
        matching_by(p, |s| s.full_rec(0), |s| s.partial_rec(0, 0))
    }

    /// Orderings given by a table: pattern `j` must not be matched by a step
    /// listed before the step of a pattern `i` with `after[j] & (1 << i)`.
    struct Table(Vec<u8>);

    impl OrderingCheck for Table {
        fn partial(&self, assign: &[Option<usize>], pos: usize) -> bool {
            let Some(j) = assign[pos] else { return true };
            assign[..pos].iter().flatten().all(|&i| self.0.get(i).is_none_or(|b| b & (1 << j) == 0))
        }
        fn complete(&self, assign: &[usize]) -> bool {
            let some: Vec<Option<usize>> = assign.iter().map(|&j| Some(j)).collect();
            (0..some.len()).all(|pos| self.partial(&some, pos))
        }
    }

    use proptest::prelude::*;

    fn terms(vars: bool) -> impl Strategy<Value = Vec<&'static str>> {
        let choices: &'static [&'static str] =
            if vars { &["?x", "?y", "o1", "o2"] } else { &["o1", "o2", "o3"] };
        proptest::collection::vec(proptest::sample::select(choices), 0..3)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// The searches without recursion find what the recursive ones found.
        #[test]
        fn the_searches_without_recursion_are_the_recursive_ones(
            patterns in proptest::collection::vec((proptest::sample::select(&["a", "b"][..]), terms(true)), 0..6),
            before in proptest::collection::vec(any::<u8>(), 6),
            steps in proptest::collection::vec((proptest::sample::select(&["a", "b", "c"][..]), terms(false)), 0..6),
            use_order in any::<bool>(),
            distinct in any::<bool>(),
            o3_not_y in any::<bool>(),
            table in proptest::option::of(proptest::collection::vec(any::<u8>(), 6)),
        ) {
            let table = table.map(Table);
            let pats: Vec<Pattern> = patterns.iter().map(|(n, a)| pat(n, a)).collect();
            // Pattern j is ordered after the patterns i < j whose bit is set.
            let preds: Vec<Vec<usize>> =
                (0..pats.len()).map(|j| (0..j).filter(|&i| before[j] & (1 << i) != 0).collect()).collect();
            let args: Vec<Vec<Str>> = steps.iter().map(|(_, a)| a.iter().map(|&x| Str::from(x)).collect()).collect();
            let instances: Vec<Instance<'_>> =
                steps.iter().zip(&args).map(|((n, _), a)| Instance { name: n, args: a }).collect();
            let accept = |b: &[Bound]| !distinct || lookup(b, "x").map(|b| &b.value) != lookup(b, "y").map(|b| &b.value);
            let type_ok = |x: &str, v: &str| !(o3_not_y && x == "y" && v == "o3");
            let p = Problem {
                patterns: &pats,
                preds: &preds,
                instances: &instances,
                initial: &[],
                type_ok: &type_ok,
                accept: &accept,
                use_order,
                orderings: table.as_ref().map(|t| t as &dyn OrderingCheck),
            };
            prop_assert_eq!(matching(&p), reference_matching(&p));
        }
    }

    /// A decomposition of 20,000 subtasks is matched on a small stack (the
    /// recursive search needed a frame per subtask).
    #[test]
    fn thousands_of_subtasks_are_matched_without_recursion() {
        let n = 20_000;
        let pats: Vec<Pattern> = (0..n).map(|_| pat("a", &["?x"])).collect();
        let preds = vec![Vec::new(); n];
        let args = vec![Str::from("o")];
        let instances: Vec<Instance<'_>> = (0..n).map(|_| Instance { name: "a", args: &args }).collect();
        let outcome = std::thread::scope(|scope| {
            std::thread::Builder::new()
                .stack_size(256 << 10)
                .spawn_scoped(scope, || {
                    let p = Problem {
                        patterns: &pats,
                        preds: &preds,
                        instances: &instances,
                        initial: &[],
                        type_ok: &|_, _| true,
                        accept: &|_| true,
                        use_order: true,
                        orderings: None,
                    };
                    matching(&p)
                })
                .expect("a thread")
                .join()
                .expect("no stack overflow")
        });
        let Outcome::Matched { assign, .. } = outcome else { panic!("{outcome:?}") };
        assert_eq!(assign, (0..n).collect::<Vec<_>>());
    }
}
