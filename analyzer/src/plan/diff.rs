//! Comparing two plans of the same mission (`hipop diff`): which steps were
//! removed, added or retimed, per agent; which abstract steps were refined
//! by another method; and the two stability figures.
//!
//! Matching, in this order:
//! 1. primitive steps (actions) by name and arguments, the k-th occurrence in
//!    one plan with the k-th in the other, occurrences ordered by start time
//!    (then by place in the file), or by place in the file in untimed plans;
//! 2. abstract steps along the decomposition trees: the roots by task and
//!    arguments in order, then, below two matched steps, their abstract
//!    subtasks likewise; abstract steps left over (their parent changed) are
//!    then matched by task and arguments in depth-first order.
//!
//! A matched action is *retimed* when both plans give it a start time and its
//! start or duration differ by more than the tolerance. The *instability* of
//! the HiPOP paper (section 5.2: the number of actions that changed between
//! the two plans) counts the actions removed, added and retimed; Fox et
//! al.'s *distance* |A∖B| + |B∖A| (multisets of ground actions) counts the
//! actions removed and added, ignoring time. Abstract steps count in neither:
//! they are reported apart.

use rustc_hash::FxHashMap;

use super::agents::AgentTable;
use super::{NameMatching, Plan, Step, normalise_name};

/// How two plans are compared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiffOptions {
    /// How far apart two start times (or durations) may be and still count as equal.
    pub tolerance: f64,
    pub matching: NameMatching,
}

impl Default for DiffOptions {
    fn default() -> Self {
        DiffOptions { tolerance: DiffOptions::DEFAULT_TOLERANCE, matching: NameMatching::CaseInsensitive }
    }
}

impl DiffOptions {
    /// Times are printed with three decimals: a smaller change is not a change.
    pub const DEFAULT_TOLERANCE: f64 = 0.001;
}

/// The changes of one agent (`None`: the steps whose agent is unknown).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AgentChanges {
    pub agent: Option<String>,
    pub unchanged: usize,
    pub removed: usize,
    pub added: usize,
    pub retimed: usize,
    pub method_changes: usize,
}

impl AgentChanges {
    pub fn changed(&self) -> bool {
        self.removed + self.added + self.retimed + self.method_changes > 0
    }
}

/// The difference between plan A and plan B. Steps are indices in
/// [`Plan::steps`] of A (`a`) and of B (`b`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct PlanDiff {
    /// Actions of A matched with actions of B, in B's order of occurrence.
    pub matched: Vec<(usize, usize)>,
    /// Actions of A that B does not have, in A's order of occurrence.
    pub removed: Vec<usize>,
    /// Actions of B that A does not have, in B's order of occurrence.
    pub added: Vec<usize>,
    /// The matched actions whose start or duration changed.
    pub retimed: Vec<(usize, usize)>,
    /// Abstract steps matched, in B's depth-first order.
    pub abstract_matched: Vec<(usize, usize)>,
    pub abstract_removed: Vec<usize>,
    pub abstract_added: Vec<usize>,
    /// Matched abstract steps refined by different methods.
    pub method_changes: Vec<(usize, usize)>,
    /// The agents of each step of A and of B (empty: unknown).
    pub agents_a: Vec<Vec<String>>,
    pub agents_b: Vec<Vec<String>>,
    /// Per agent, by name, the unknown agent last. A step with several agents
    /// counts for each of them.
    pub per_agent: Vec<AgentChanges>,
    /// The HiPOP paper's instability: actions removed, added and retimed.
    pub instability: usize,
    /// Fox et al.'s distance: actions removed and added.
    pub distance: usize,
}

impl PlanDiff {
    /// Whether the plans are the same: no action removed, added or retimed,
    /// no abstract step removed or added, no method changed.
    pub fn is_empty(&self) -> bool {
        self.removed.is_empty()
            && self.added.is_empty()
            && self.retimed.is_empty()
            && self.abstract_removed.is_empty()
            && self.abstract_added.is_empty()
            && self.method_changes.is_empty()
    }
}

/// What a step is matched by: its name and arguments, normalised.
fn key(step: &Step, matching: NameMatching) -> String {
    let mut k = normalise_name(&step.name.text, matching).into_owned();
    for a in &step.args {
        k.push(' ');
        k.push_str(&normalise_name(&a.text, matching));
    }
    k
}

/// The primitive steps of a plan in order of occurrence: by start time,
/// then by place in the file.
pub fn occurrences(plan: &Plan) -> Vec<usize> {
    let mut order: Vec<usize> = plan.primitive_steps().map(|(i, _)| i).collect();
    // A stable sort: steps at the same time keep the file's order; steps
    // without a time come after those with one.
    order.sort_by(|&x, &y| {
        let t = |i: usize| plan.steps[i].start.as_ref().map(|n| n.value);
        match (t(x), t(y)) {
            (Some(a), Some(b)) => a.total_cmp(&b),
            (Some(_), None) => std::cmp::Ordering::Less,
            (None, Some(_)) => std::cmp::Ordering::Greater,
            (None, None) => std::cmp::Ordering::Equal,
        }
    });
    order
}

/// Pairs the steps of `xs` and `ys` with equal keys, the k-th with the k-th.
/// Returns the pairs (in `ys`'s order) and the unpaired steps of each side.
fn pair_in_order(
    xs: &[usize],
    ys: &[usize],
    key_x: impl Fn(usize) -> String,
    key_y: impl Fn(usize) -> String,
) -> (Vec<(usize, usize)>, Vec<usize>, Vec<usize>) {
    let mut queues: FxHashMap<String, std::collections::VecDeque<usize>> = FxHashMap::default();
    for &x in xs {
        queues.entry(key_x(x)).or_default().push_back(x);
    }
    let mut pairs = Vec::new();
    let mut only_y = Vec::new();
    for &y in ys {
        match queues.get_mut(&key_y(y)).and_then(|q| q.pop_front()) {
            Some(x) => pairs.push((x, y)),
            None => only_y.push(y),
        }
    }
    let paired: rustc_hash::FxHashSet<usize> = pairs.iter().map(|&(x, _)| x).collect();
    let only_x = xs.iter().copied().filter(|x| !paired.contains(x)).collect();
    (pairs, only_x, only_y)
}

/// The abstract subtasks of an abstract step, in the order written.
fn abstract_children(plan: &Plan, i: usize) -> Vec<usize> {
    plan.steps[i].decomposition.as_ref().map_or_else(Vec::new, |d| {
        d.subtasks
            .iter()
            .filter_map(|id| plan.index_of(id.value))
            .filter(|&c| plan.steps[c].is_abstract())
            .collect()
    })
}

/// The abstract roots: the `root` line's, or the abstract steps that are no
/// step's subtask.
fn abstract_roots(plan: &Plan) -> Vec<usize> {
    if let Some(root) = &plan.root {
        return root
            .ids
            .iter()
            .filter_map(|id| plan.index_of(id.value))
            .filter(|&i| plan.steps[i].is_abstract())
            .collect();
    }
    let children: rustc_hash::FxHashSet<usize> =
        plan.abstract_steps().flat_map(|(i, _)| abstract_children(plan, i)).collect();
    plan.abstract_steps().map(|(i, _)| i).filter(|i| !children.contains(i)).collect()
}

/// The abstract steps in depth-first order from the roots, then those no
/// root reaches, in the file's order. Each once, whatever cycles a
/// malformed plan has.
fn depth_first(plan: &Plan) -> Vec<usize> {
    let mut seen = vec![false; plan.steps.len()];
    let mut out = Vec::new();
    let mut stack: Vec<usize> = abstract_roots(plan).into_iter().rev().collect();
    let rest: Vec<usize> = plan.abstract_steps().map(|(i, _)| i).collect();
    let mut rest = rest.into_iter();
    loop {
        let i = match stack.pop() {
            Some(i) => i,
            None => match rest.next() {
                Some(i) => i,
                None => break,
            },
        };
        if std::mem::replace(&mut seen[i], true) {
            continue;
        }
        out.push(i);
        stack.extend(abstract_children(plan, i).into_iter().rev());
    }
    out
}

/// Compares plan `a` with plan `b`.
pub fn diff(a: &Plan, b: &Plan, agents: &AgentTable, options: &DiffOptions) -> PlanDiff {
    let m = options.matching;
    let (matched, removed, added) =
        pair_in_order(&occurrences(a), &occurrences(b), |i| key(&a.steps[i], m), |i| key(&b.steps[i], m));
    let tol = options.tolerance;
    let retimed: Vec<(usize, usize)> = matched
        .iter()
        .copied()
        .filter(|&(x, y)| {
            let (sa, sb) = (&a.steps[x], &b.steps[y]);
            let (Some(ta), Some(tb)) = (&sa.start, &sb.start) else { return false };
            let d = |s: &Step| s.duration.as_ref().map_or(0.0, |d| d.value);
            (ta.value - tb.value).abs() > tol || (d(sa) - d(sb)).abs() > tol
        })
        .collect();

    // Abstract steps: along the trees first.
    let mut abstract_matched = Vec::new();
    let mut used_a = vec![false; a.steps.len()];
    let mut used_b = vec![false; b.steps.len()];
    let mut work = vec![(abstract_roots(a), abstract_roots(b))];
    while let Some((xs, ys)) = work.pop() {
        let xs: Vec<usize> = xs.into_iter().filter(|&x| !used_a[x]).collect();
        let ys: Vec<usize> = ys.into_iter().filter(|&y| !used_b[y]).collect();
        let (pairs, _, _) = pair_in_order(&xs, &ys, |i| key(&a.steps[i], m), |i| key(&b.steps[i], m));
        for &(x, y) in pairs.iter().rev() {
            if used_a[x] || used_b[y] {
                continue;
            }
            used_a[x] = true;
            used_b[y] = true;
            abstract_matched.push((x, y));
            work.push((abstract_children(a, x), abstract_children(b, y)));
        }
    }
    // Then what is left, in depth-first order.
    let left_a: Vec<usize> = depth_first(a).into_iter().filter(|&x| !used_a[x]).collect();
    let left_b: Vec<usize> = depth_first(b).into_iter().filter(|&y| !used_b[y]).collect();
    let (late, abstract_removed, abstract_added) =
        pair_in_order(&left_a, &left_b, |i| key(&a.steps[i], m), |i| key(&b.steps[i], m));
    abstract_matched.extend(late);
    let order_b: FxHashMap<usize, usize> =
        depth_first(b).into_iter().enumerate().map(|(k, i)| (i, k)).collect();
    abstract_matched.sort_by_key(|&(_, y)| order_b.get(&y).copied().unwrap_or(usize::MAX));
    let method = |s: &Step| s.decomposition.as_ref().map(|d| normalise_name(&d.method.text, m).into_owned());
    let method_changes: Vec<(usize, usize)> = abstract_matched
        .iter()
        .copied()
        .filter(|&(x, y)| method(&a.steps[x]) != method(&b.steps[y]))
        .collect();

    let agents_a: Vec<Vec<String>> = a.steps.iter().map(|s| agents.agents_of(s)).collect();
    let agents_b: Vec<Vec<String>> = b.steps.iter().map(|s| agents.agents_of(s)).collect();
    let per_agent = per_agent(&agents_a, &agents_b, &matched, &removed, &added, &retimed, &method_changes, m);
    let instability = removed.len() + added.len() + retimed.len();
    let distance = removed.len() + added.len();
    PlanDiff {
        matched,
        removed,
        added,
        retimed,
        abstract_matched,
        abstract_removed,
        abstract_added,
        method_changes,
        agents_a,
        agents_b,
        per_agent,
        instability,
        distance,
    }
}

#[expect(clippy::too_many_arguments, reason = "the parts of a diff, each counted per agent")]
fn per_agent(
    agents_a: &[Vec<String>],
    agents_b: &[Vec<String>],
    matched: &[(usize, usize)],
    removed: &[usize],
    added: &[usize],
    retimed: &[(usize, usize)],
    method_changes: &[(usize, usize)],
    matching: NameMatching,
) -> Vec<AgentChanges> {
    // Grouped by normalised name; shown as first written.
    let mut rows: FxHashMap<Option<String>, AgentChanges> = FxHashMap::default();
    let mut count = |agents: &[String], f: &dyn Fn(&mut AgentChanges)| {
        let keys: Vec<(Option<String>, Option<String>)> = if agents.is_empty() {
            vec![(None, None)]
        } else {
            agents.iter().map(|a| (Some(normalise_name(a, matching).into_owned()), Some(a.clone()))).collect()
        };
        for (k, shown) in keys {
            let row = rows.entry(k).or_insert_with(|| AgentChanges {
                agent: shown,
                unchanged: 0,
                removed: 0,
                added: 0,
                retimed: 0,
                method_changes: 0,
            });
            f(row);
        }
    };
    // A matched step counts for B's agents, or A's when only A's plan gives them.
    let both = |x: usize, y: usize| if agents_b[y].is_empty() { &agents_a[x] } else { &agents_b[y] };
    let retimed_b: rustc_hash::FxHashSet<usize> = retimed.iter().map(|&(_, y)| y).collect();
    for &(x, y) in matched {
        if !retimed_b.contains(&y) {
            count(both(x, y), &|r| r.unchanged += 1);
        }
    }
    for &x in removed {
        count(&agents_a[x], &|r| r.removed += 1);
    }
    for &y in added {
        count(&agents_b[y], &|r| r.added += 1);
    }
    for &(x, y) in retimed {
        count(both(x, y), &|r| r.retimed += 1);
    }
    for &(x, y) in method_changes {
        count(both(x, y), &|r| r.method_changes += 1);
    }
    let mut out: Vec<(Option<String>, AgentChanges)> = rows.into_iter().collect();
    out.sort_by(|(x, _), (y, _)| match (x, y) {
        (Some(x), Some(y)) => x.cmp(y),
        (Some(_), None) => std::cmp::Ordering::Less,
        (None, Some(_)) => std::cmp::Ordering::Greater,
        (None, None) => std::cmp::Ordering::Equal,
    });
    out.into_iter().map(|(_, r)| r).collect()
}
