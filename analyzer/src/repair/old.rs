//! The plan being executed, read for a repair: each step of the plan file
//! matched with a ground operator of the new problem's task (by name and
//! arguments), its place in the hierarchy (the decomposition lines), its
//! times in the old schedule and whether it is frozen (executed, running,
//! or an unreachable agent's).

use rustc_hash::{FxHashMap, FxHashSet};

use crate::db::{Db, Item, Unit};
use crate::model::Str;
use crate::plan::Plan as PlanFile;
use crate::planner::task::{Task, atom_of};
use crate::semantics::check::domain_for;
use crate::semantics::symbols::domain_symbols;
use crate::verify::lifted::{LAtom, LTerm, operator};
use crate::verify::state::{AtomId, ObjId};

/// Why a step of the old plan has no operator in the new problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Missing {
    /// No action or task of that name and those arguments (the action was
    /// removed, an object is unknown, the arguments do not fit).
    NoOperator,
    /// The domain has no action or task of that name.
    UnknownAction,
    /// This argument (its index) is not an object of the problem.
    UnknownObject(u32),
    /// Another number of arguments, or arguments of other types.
    Arguments,
    /// The action exists for these objects, but can never be executed in
    /// the new problem: grounding leaves it out (a condition can never hold).
    Unusable,
}

impl Missing {
    /// Why, for a step written `call` (`(name arg…)`).
    pub fn describe(self, call: &str) -> String {
        match self {
            Missing::NoOperator => "obsolete: no action or task of that name for these arguments".into(),
            Missing::UnknownAction => "obsolete: the domain has no action or task of that name".into(),
            Missing::UnknownObject(i) => {
                let arg = call.trim_matches(|c| c == '(' || c == ')').split_whitespace().nth(i as usize + 1);
                format!("obsolete: `{}` is not an object of the problem", arg.unwrap_or("?"))
            }
            Missing::Arguments => "obsolete: the arguments do not fit the action's parameters".into(),
            Missing::Unusable => {
                "obsolete: it can never be executed in the new problem (a condition of it can never hold)"
                    .into()
            }
        }
    }
}

/// One step of the old plan.
#[derive(Debug, Clone, PartialEq)]
pub struct OldStep {
    /// `(name arg…)` as the plan file writes it.
    pub call: String,
    /// The step's id in the file, else its index.
    pub id: u32,
    /// The ground operator of the new task, or why there is none.
    pub op: Result<u32, Missing>,
    pub is_abstract: bool,
    /// The method instance its decomposition names, when the new task has
    /// one of that name for this operator whose subtasks are the step's.
    pub method: Option<u32>,
    /// The decomposition's method name, as written.
    pub method_name: Option<String>,
    /// The abstract step whose decomposition lists it.
    pub parent: Option<usize>,
    pub children: Vec<usize>,
    pub start: f64,
    pub end: f64,
    /// Never removed: executed, running, or an unreachable agent's.
    pub frozen: bool,
    /// Started before `now` (or listed as executed): its start is fixed.
    pub fixed: bool,
    /// Ended before `now` (or listed as executed): its end is fixed too.
    pub done: bool,
    /// The agents of its operator.
    pub agents: Vec<String>,
}

/// What freezes steps of the old plan.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Execution {
    /// Steps that started before this time are executed or running.
    pub now: Option<f64>,
    /// Steps executed, by id (or index in a plan without ids).
    pub executed: Vec<u32>,
    /// Agents out of communication: their steps are frozen (5.4).
    pub unreachable: Vec<String>,
}

/// Reads the old plan against the new task.
pub fn read(task: &Task<'_>, plan: &PlanFile, execution: &Execution) -> Vec<OldStep> {
    // The operators by lower-case name and arguments (each name lowered once).
    let mut lower: FxHashMap<&str, Str> = FxHashMap::default();
    let mut ops: FxHashMap<(Str, &[ObjId]), u32> = FxHashMap::default();
    for (i, o) in task.ops.iter().enumerate() {
        let name = lower.entry(o.name.as_str()).or_insert_with(|| Str::from(o.name.to_lowercase())).clone();
        ops.entry((name, o.args.as_slice())).or_insert(i as u32);
    }
    let find = |s: &crate::plan::Step| -> Option<u32> {
        let args: Vec<ObjId> =
            s.args.iter().map(|a| task.g.objects.id(&a.text.to_lowercase())).collect::<Option<_>>()?;
        ops.get(&(Str::from(s.name.text.to_lowercase()), args.as_slice())).copied()
    };
    let mut by_id: FxHashMap<u32, usize> = FxHashMap::default();
    let mut steps: Vec<OldStep> = plan
        .steps
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let id = s.id.as_ref().map_or(i as u32, |d| d.value);
            by_id.entry(id).or_insert(i);
            let op = find(s).ok_or(Missing::NoOperator);
            let start = s.start.as_ref().map(|n| n.value);
            OldStep {
                call: s.call(),
                id,
                op,
                is_abstract: s.is_abstract(),
                method: None,
                method_name: s.decomposition.as_ref().map(|d| d.method.text.to_string()),
                parent: None,
                children: Vec::new(),
                start: start.unwrap_or(f64::NAN),
                end: s.end().unwrap_or(f64::NAN),
                frozen: false,
                fixed: false,
                done: false,
                agents: match op {
                    Ok(o) => task.ops[o as usize]
                        .agents
                        .iter()
                        .map(|&a| task.g.objects.name(a).to_string())
                        .collect(),
                    Err(_) => s.agents.iter().map(|a| a.text.to_string()).collect(),
                },
            }
        })
        .collect();
    // The hierarchy.
    for (i, s) in plan.steps.iter().enumerate() {
        let Some(d) = &s.decomposition else { continue };
        for sub in &d.subtasks {
            if let Some(&c) = by_id.get(&sub.value)
                && c != i
                && steps[c].parent.is_none()
            {
                steps[c].parent = Some(i);
                steps[i].children.push(c);
            }
        }
    }
    // Sequential plans: the order is the time.
    for (i, s) in steps.iter_mut().enumerate() {
        if !s.is_abstract && s.start.is_nan() {
            s.start = i as f64;
            s.end = i as f64;
        }
    }
    // Abstract steps without times span their subtasks (deepest first).
    let mut order: Vec<usize> = (0..steps.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(depth(&steps, i)));
    for i in order {
        if !steps[i].is_abstract || !steps[i].start.is_nan() {
            continue;
        }
        let (lo, hi) = steps[i]
            .children
            .iter()
            .map(|&c| (steps[c].start, steps[c].end))
            .filter(|(a, b)| !a.is_nan() && !b.is_nan())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| (lo.min(a), hi.max(b)));
        if lo <= hi {
            steps[i].start = lo;
            steps[i].end = hi;
        } else {
            steps[i].start = 0.0;
            steps[i].end = 0.0;
        }
    }
    // Methods: the instance of that name whose subtasks are the children's
    // operators. From every instance of the task, also those the search
    // may no longer use (a subtask of an unreachable agent's).
    let mut instances: FxHashMap<u32, Vec<u32>> = FxHashMap::default();
    for s in &steps {
        if let (Ok(op), Some(_)) = (s.op, &s.method_name) {
            instances.entry(op).or_default();
        }
    }
    for (m, mi) in task.methods.iter().enumerate() {
        if let Some(v) = instances.get_mut(&mi.task) {
            v.push(m as u32);
        }
    }
    for i in 0..steps.len() {
        let (Ok(op), Some(name)) = (&steps[i].op, &steps[i].method_name) else { continue };
        let mut children: Vec<u32> = Vec::new();
        let mut complete = true;
        for &c in &steps[i].children {
            match steps[c].op {
                Ok(o) => children.push(o),
                Err(_) => complete = false,
            }
        }
        if !complete {
            continue;
        }
        children.sort_unstable();
        steps[i].method = instances.get(op).into_iter().flatten().copied().find(|&m| {
            let mi = &task.methods[m as usize];
            let mut subs: Vec<u32> = mi.subtasks.iter().map(|&(_, o)| o).collect();
            subs.sort_unstable();
            mi.name.eq_ignore_ascii_case(name) && subs == children
        });
    }
    // Execution.
    for s in &mut steps {
        let listed = execution.executed.contains(&s.id);
        let started = execution.now.is_some_and(|now| s.start < now);
        let ended = execution.now.is_some_and(|now| s.end <= now);
        s.fixed = listed || started;
        s.done = listed || ended;
        let unreachable =
            s.agents.iter().any(|a| execution.unreachable.iter().any(|u| u.eq_ignore_ascii_case(a)));
        s.frozen = s.fixed || unreachable;
    }
    // An abstract step with a frozen subtask is frozen: it is being executed.
    let mut order: Vec<usize> = (0..steps.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(depth(&steps, i)));
    for i in order {
        if let Some(p) = steps[i].parent
            && steps[i].frozen
        {
            steps[p].frozen = true;
        }
    }
    steps
}

/// The conditions that only the initial state and the timed literals
/// decide: atoms that no operator changes.
pub struct Rigid {
    changed: FxHashSet<AtomId>,
}

impl Rigid {
    pub fn new(task: &Task<'_>) -> Self {
        let changed = task.ops.iter().flat_map(|o| o.effs.iter().map(|e| atom_of(e.lit))).collect();
        Rigid { changed }
    }

    /// Whether a condition of operator `op` can never hold from `now` on:
    /// no operator changes its atom, which has the wrong value at `now`
    /// (the initial state and the timed literals up to then) and no timed
    /// literal after `now` gives it the right one. A step that has not
    /// started by `now` cannot happen any more.
    pub fn never_again(&self, task: &Task<'_>, op: u32, now: f64) -> bool {
        task.ops[op as usize].conds.iter().any(|c| {
            let atom = atom_of(c.lit);
            if self.changed.contains(&atom) {
                return false;
            }
            let wanted = c.lit % 2 == 0;
            let mut tils: Vec<(f64, bool)> = task
                .tils
                .iter()
                .filter(|t| atom_of(t.lit) == atom)
                .map(|t| (t.time, t.lit % 2 == 0))
                .collect();
            tils.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut value = task.init.get(atom as usize).copied().unwrap_or(false);
            for &(t, v) in &tils {
                if t <= now {
                    value = v;
                } else if v == wanted {
                    return false;
                }
            }
            value != wanted
        })
    }
}

/// How many abstract steps are above step `i`.
fn depth(steps: &[OldStep], mut i: usize) -> usize {
    let mut d = 0;
    while let Some(p) = steps[i].parent {
        d += 1;
        i = p;
        if d > steps.len() {
            break;
        }
    }
    d
}

/// The action or task a step names in the problem's domain, if any.
fn schema<'db>(db: &'db dyn Db, domain: Option<Unit<'db>>, name: &str) -> Option<Item<'db>> {
    let symbols = domain_symbols(db, domain?);
    let key = name.to_lowercase();
    symbols.actions.get(key.as_str()).or_else(|| symbols.tasks.get(key.as_str())).map(|d| d.loc.item)
}

/// Says why each step of the old plan without an operator has none: an
/// unknown action or object, arguments that do not fit, or an instance
/// that can never be executed.
pub fn explain(db: &dyn Db, task: &Task<'_>, plan: &PlanFile, steps: &mut [OldStep]) {
    let domain = domain_for(db, task.problem);
    let symbols = domain.map(|d| domain_symbols(db, d));
    for (s, old) in plan.steps.iter().zip(steps.iter_mut()) {
        if old.op.is_ok() {
            continue;
        }
        let key = s.name.text.to_lowercase();
        let Some(decl) =
            symbols.and_then(|t| t.actions.get(key.as_str()).or_else(|| t.tasks.get(key.as_str())))
        else {
            old.op = Err(Missing::UnknownAction);
            continue;
        };
        let objects = &task.g.objects;
        let ids: Vec<Option<ObjId>> = s.args.iter().map(|a| objects.id(&a.text.to_lowercase())).collect();
        old.op = Err(if let Some(i) = ids.iter().position(Option::is_none) {
            Missing::UnknownObject(i as u32)
        } else if ids.len() != decl.params.len()
            || ids.iter().zip(&decl.params).any(|(&o, param)| {
                let o = o.unwrap_or_default();
                !param.iter().any(|t| t.as_str() == "object" || objects.has_type(o, t))
            })
        {
            Missing::Arguments
        } else {
            Missing::Unusable
        });
    }
}

/// The causal links of the old plan rebuilt by name from the domain's
/// actions and tasks (their conditions and effects, either end), as
/// `(producer, consumer)`: each condition of a step is supported by the
/// step that made it last before it in the old schedule. They tell what
/// the steps the new task cannot ground (an object gone, an action no
/// longer allowed) supported and needed.
pub fn links_by_name(
    db: &dyn Db,
    task: &Task<'_>,
    plan: &PlanFile,
    steps: &[OldStep],
) -> Vec<(usize, usize)> {
    let domain = domain_for(db, task.problem);
    type Atoms = Vec<(bool, String)>;
    let ground = |s: &crate::plan::Step| -> Option<(Atoms, Atoms)> {
        let op = operator(db, schema(db, domain, &s.name.text)?).as_ref()?;
        let args: Vec<String> = s.args.iter().map(|a| a.text.to_lowercase().to_string()).collect();
        let atom = |a: &LAtom| -> Option<String> {
            let mut k = a.pred.to_string();
            for t in &a.args {
                k.push(' ');
                match t {
                    LTerm::Param(i) => k.push_str(args.get(*i as usize)?),
                    LTerm::Const(c) => k.push_str(c),
                    LTerm::Free(_) => return None,
                }
            }
            Some(k)
        };
        let signed = |atoms: &[LAtom], sign: bool| {
            atoms.iter().filter_map(|a| Some((sign, atom(a)?))).collect::<Atoms>()
        };
        let mut needs = signed(&op.pre.pos, true);
        needs.extend(signed(&op.pre.neg, false));
        let mut makes = signed(&op.add, true);
        makes.extend(signed(&op.del, false));
        Some((needs, makes))
    };
    let grounded: Vec<Option<(Atoms, Atoms)>> = plan.steps.iter().map(ground).collect();
    let above = |mut c: usize, a: usize| {
        for _ in 0..steps.len() {
            match steps[c].parent {
                Some(p) if p == a => return true,
                Some(p) => c = p,
                None => return false,
            }
        }
        false
    };
    // The steps that make each literal.
    let mut makers: FxHashMap<&(bool, String), Vec<usize>> = FxHashMap::default();
    for (p, g) in grounded.iter().enumerate() {
        for m in g.iter().flat_map(|(_, makes)| makes) {
            let v = makers.entry(m).or_default();
            if v.last() != Some(&p) {
                v.push(p);
            }
        }
    }
    const SLACK: f64 = 1e-6;
    let mut links = Vec::new();
    for (c, g) in grounded.iter().enumerate() {
        let Some((needs, _)) = g else { continue };
        let (start, end) = (steps[c].start, steps[c].end);
        for need in needs {
            // The last producer ended before it started, else the last one
            // that started before it (an effect at the start, or a
            // condition at the end).
            let producers =
                makers.get(need).into_iter().flatten().copied().filter(|&p| p != c && !above(c, p));
            let best = producers
                .clone()
                .filter(|&p| steps[p].end <= start + SLACK)
                .max_by(|&a, &b| steps[a].end.total_cmp(&steps[b].end))
                .or_else(|| {
                    producers
                        .filter(|&p| steps[p].start <= start + SLACK && steps[p].end <= end + SLACK)
                        .max_by(|&a, &b| steps[a].start.total_cmp(&steps[b].start))
                });
            if let Some(p) = best {
                links.push((p, c));
            }
        }
    }
    links.sort_unstable();
    links.dedup();
    links
}
