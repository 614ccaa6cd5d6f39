//! What the last planner run on a problem shows in the editor: inlay hints
//! on the problem (a summary after its `(problem …)`, the achiever of each
//! goal literal, the refinement of each `:htn` task, and what a repair
//! changed), and how the plan uses a name, for hover.
//!
//! The run itself is plain data ([`PlanRun`]) kept by the shell; these
//! functions only read the problem's syntax to place the hints, so a run
//! can be shown on any later text of the file (the shell decides whether it
//! is still the text that was planned).

use rowan::{TextRange, TextSize};

use crate::db::{Db, SourceFile, UnitKind, file_units, parse};
use crate::planner::output::{SolvedPlan, SolvedStep};
use crate::planner::{LimitKind, Stats, Status};
use crate::syntax::{List, Sexp};
use crate::syntax::{SyntaxKind, SyntaxNode};

use super::refs::RefKind;

/// A planner run on one problem, as the shell keeps it.
#[derive(Debug, Clone)]
pub struct PlanRun {
    pub status: Status,
    pub plan: Option<SolvedPlan>,
    pub stats: Stats,
    /// The time limit the run had, to say which limit stopped it.
    pub time_limit: Option<std::time::Duration>,
    /// The flaws of the best partial plan, when there is no plan.
    pub flaws: usize,
    /// Set when the run repaired an earlier plan of the problem.
    pub repair: Option<RepairSummary>,
}

/// What a repair changed, against the plan it started from.
#[derive(Debug, Clone)]
pub struct RepairSummary {
    /// The plan repaired.
    pub old: SolvedPlan,
    /// Actions removed, added and retimed (the HiPOP paper's instability).
    pub instability: usize,
    /// Actions removed and added (Fox et al.'s distance).
    pub distance: usize,
}

/// An inlay hint: a label shown at `offset`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlanHint {
    pub offset: TextSize,
    pub label: String,
    /// More on hover: the plan's figures, the old achiever.
    pub tooltip: Option<String>,
    pub kind: PlanHintKind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanHintKind {
    /// After `(problem …)`: what the run found.
    Summary,
    /// After a goal literal: the step that achieves it.
    Goal,
    /// After a task of `:htn`: the step that refines it.
    Task,
}

/// `x` as the plan files write times.
fn time(x: f64) -> String {
    format!("{x:.2}")
}

fn seconds(d: std::time::Duration) -> String {
    let s = d.as_secs_f64();
    if s < 10.0 { format!("{s:.2} s") } else { format!("{s:.0} s") }
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The summary of a run: "plan: 242 actions, makespan 5528.04, 0.03 s".
pub fn summary(run: &PlanRun) -> String {
    let took = seconds(run.stats.elapsed);
    match (&run.status, &run.plan) {
        (Status::Solved, Some(plan)) => {
            let actions = plan.primitive().count();
            let head = if run.repair.is_some() { "repaired plan" } else { "plan" };
            let mut s = format!(
                "{head}: {}, makespan {}, {took}",
                plural(actions, "action", "actions"),
                time(plan.makespan)
            );
            if let Some(r) = &run.repair {
                s.push_str(&format!("; instability {}, distance {}", r.instability, r.distance));
            }
            s
        }
        (Status::Limit(kind), _) => {
            let limit = match kind {
                LimitKind::Time => match run.time_limit {
                    Some(t) => format!("time limit ({}) reached", seconds(t)),
                    None => "time limit reached".to_string(),
                },
                LimitKind::Nodes => "node limit reached".to_string(),
                LimitKind::Memory => "memory limit reached".to_string(),
                LimitKind::Cancelled => "cancelled".to_string(),
            };
            format!("no plan: {limit}, {}", plural(run.flaws, "flaw", "flaws"))
        }
        (Status::NoPlan, _) => {
            format!("no plan exists: {} in the best partial plan", plural(run.flaws, "flaw", "flaws"))
        }
        (Status::Refused, _) => "not planned: see the errors".to_string(),
        (Status::Solved, None) => format!("no plan: {}", plural(run.flaws, "flaw", "flaws")),
    }
}

/// A step as a plan writes it: `(observe ressac1 poi3)`.
pub fn step_text(step: &SolvedStep) -> String {
    let mut s = format!("({}", step.name);
    for a in &step.args {
        s.push(' ');
        s.push_str(a);
    }
    s.push(')');
    s
}

/// The `define` list of the first problem of a file.
fn problem_list(db: &dyn Db, file: SourceFile) -> Option<List> {
    let unit = file_units(db, file).iter().copied().find(|u| u.kind(db) == UnitKind::Problem)?;
    let range = unit.range(db);
    let root = parse(db, file).syntax();
    root.children().filter_map(List::cast).find(|l| l.range() == range)
}

/// The offset of the end of the line holding `at` (before its line break).
fn line_end(root: &SyntaxNode, at: TextSize) -> TextSize {
    let text = root.text().to_string();
    let from = usize::from(at).min(text.len());
    let end = text[from..].find(['\n', '\r']).map_or(text.len(), |i| from + i);
    TextSize::try_from(end).unwrap_or(at)
}

/// A ground literal of the goal, or a task of `:htn`, where it is written.
#[derive(Debug, Clone)]
struct Written {
    name: String,
    args: Vec<String>,
    negated: bool,
    range: TextRange,
}

fn ground(list: &List, negated: bool) -> Option<Written> {
    let mut elements = list.elements();
    let head = elements.next()?;
    let head = head.as_atom().filter(|t| t.kind() == SyntaxKind::Symbol)?;
    let mut args = Vec::new();
    for e in elements {
        let atom = e.as_atom()?;
        if !matches!(atom.kind(), SyntaxKind::Symbol | SyntaxKind::Number) {
            return None;
        }
        args.push(atom.text().to_ascii_lowercase());
    }
    Some(Written { name: head.text().to_ascii_lowercase(), args, negated, range: list.range() })
}

/// The ground literals of a goal formula, through `and`, `not` and the
/// time specifiers a temporal goal may carry; quantified and disjunctive
/// parts have no single achiever and are skipped.
fn goal_literals(formula: &List, negated: bool, out: &mut Vec<Written>) {
    let Some(head) = formula.head_text().map(|h| h.to_ascii_lowercase()) else { return };
    match head.as_str() {
        "and" => {
            for e in formula.elements().skip(1) {
                if let Some(l) = e.as_list() {
                    goal_literals(l, negated, out);
                }
            }
        }
        "not" => {
            if let Some(l) = formula.elements().nth(1).as_ref().and_then(Sexp::as_list) {
                goal_literals(l, !negated, out);
            }
        }
        "at" => {
            // `(at end φ)`: the literal is φ. `(at r w)` is a literal named `at`.
            let elements: Vec<Sexp> = formula.elements().collect();
            if elements.len() == 3
                && elements[1].atom_text().is_some_and(|t| t.eq_ignore_ascii_case("end"))
                && let Some(l) = elements[2].as_list()
            {
                goal_literals(l, negated, out);
            } else {
                out.extend(ground(formula, negated));
            }
        }
        "or" | "imply" | "forall" | "exists" | "when" | "preference" | "=" | "<" | ">" | "<=" | ">=" => {}
        _ => out.extend(ground(formula, negated)),
    }
}

/// The tasks of an `:htn` section, in the order written.
fn htn_tasks(htn: &List, out: &mut Vec<Written>) {
    let elements: Vec<Sexp> = htn.elements().collect();
    for (i, e) in elements.iter().enumerate() {
        let is_tasks = e.atom_text().is_some_and(|k| {
            matches!(
                k.to_ascii_lowercase().as_str(),
                ":subtasks" | ":ordered-subtasks" | ":tasks" | ":ordered-tasks"
            )
        });
        let Some(network) = elements.get(i + 1).and_then(Sexp::as_list).filter(|_| is_tasks) else {
            continue;
        };
        let entries: Vec<List> = if network.head_is("and") {
            network.elements().skip(1).filter_map(|e| e.as_list().cloned()).collect()
        } else {
            vec![network.clone()]
        };
        for entry in entries {
            // `(t1 (deliver p l))` or `(deliver p l)`.
            let labelled = {
                let parts: Vec<Sexp> = entry.elements().collect();
                (parts.len() == 2 && parts[0].as_atom().is_some())
                    .then(|| parts[1].as_list().cloned())
                    .flatten()
            };
            let task = labelled.unwrap_or(entry);
            out.extend(ground(&task, false));
        }
    }
}

fn sections(problem: &List) -> impl Iterator<Item = List> + '_ {
    problem.elements().filter_map(|e| e.as_list().cloned())
}

/// The achiever of a goal literal in `plan`: its label and its time.
fn achiever(plan: &SolvedPlan, goal: &Written) -> Option<(String, Option<f64>)> {
    let link = plan.causal_links.iter().find(|l| {
        l.to.is_none()
            && l.negated == goal.negated
            && l.predicate.eq_ignore_ascii_case(&goal.name)
            && l.args.len() == goal.args.len()
            && l.args.iter().zip(&goal.args).all(|(a, b)| a.eq_ignore_ascii_case(b))
    })?;
    Some(match link.from.and_then(|id| plan.steps.get(id)) {
        Some(step) => (step_text(step), Some(step.start)),
        None => ("the initial state".to_string(), None),
    })
}

fn achiever_text((label, at): &(String, Option<f64>)) -> String {
    match at {
        Some(t) => format!("{label} @ {}", time(*t)),
        None => label.clone(),
    }
}

/// The primitive steps below an abstract step.
fn actions_below(plan: &SolvedPlan, id: usize) -> usize {
    let mut count = 0;
    let mut stack = vec![id];
    while let Some(s) = stack.pop() {
        let Some(step) = plan.steps.get(s) else { continue };
        if step.is_abstract {
            stack.extend(&step.subtasks);
        } else {
            count += 1;
        }
    }
    count
}

/// The root steps refining the tasks of `:htn`, matched in order by task and arguments.
fn refinements(plan: &SolvedPlan, tasks: &[Written]) -> Vec<Option<usize>> {
    let mut used = vec![false; plan.root.len()];
    tasks
        .iter()
        .map(|t| {
            let i = plan.root.iter().enumerate().position(|(i, &id)| {
                !used[i]
                    && plan.steps.get(id).is_some_and(|s| {
                        s.name.eq_ignore_ascii_case(&t.name)
                            && s.args.len() == t.args.len()
                            && s.args.iter().zip(&t.args).all(|(a, b)| a.eq_ignore_ascii_case(b))
                    })
            })?;
            used[i] = true;
            Some(plan.root[i])
        })
        .collect()
}

fn refinement_text(plan: &SolvedPlan, id: usize) -> String {
    let step = &plan.steps[id];
    let by = step.method.as_deref().map(|m| format!("{m}: ")).unwrap_or_default();
    let n = actions_below(plan, id);
    format!("{by}{} @ {}–{}", plural(n, "action", "actions"), time(step.start), time(step.end))
}

/// The inlay hints of a run on the first problem of `file`.
pub fn plan_hints(db: &dyn Db, file: SourceFile, run: &PlanRun) -> Vec<PlanHint> {
    let Some(problem) = problem_list(db, file) else { return Vec::new() };
    let root = parse(db, file).syntax();
    let mut hints = Vec::new();
    let header = sections(&problem).find(|l| l.head_is("problem")).map_or(problem.range(), |l| l.range());
    let figures = format!("{} plans expanded in {}", run.stats.expanded, seconds(run.stats.elapsed));
    hints.push(PlanHint {
        offset: line_end(&root, header.end()),
        label: summary(run),
        tooltip: Some(figures),
        kind: PlanHintKind::Summary,
    });
    let Some(plan) = run.plan.as_ref().filter(|_| run.status == Status::Solved) else { return hints };
    let old = run.repair.as_ref().map(|r| &r.old);
    let mut goals = Vec::new();
    let mut tasks = Vec::new();
    for section in sections(&problem) {
        let head = section.head_text().map(|h| h.to_ascii_lowercase()).unwrap_or_default();
        match head.as_str() {
            ":goal" => {
                if let Some(formula) = section.elements().nth(1).as_ref().and_then(Sexp::as_list) {
                    goal_literals(formula, false, &mut goals);
                }
            }
            ":htn" | ":tihtn" | ":htnti" | ":tasks" => htn_tasks(&section, &mut tasks),
            _ => {}
        }
    }
    for goal in &goals {
        let Some(now) = achiever(plan, goal) else { continue };
        let mut label = format!("← {}", achiever_text(&now));
        let mut tooltip = None;
        if let Some(before) = old.and_then(|o| achiever(o, goal)) {
            let same = before.0 == now.0
                && match (before.1, now.1) {
                    (Some(a), Some(b)) => (a - b).abs() < 0.005,
                    (a, b) => a.is_none() && b.is_none(),
                };
            if !same {
                label.push_str(&format!(" (was {})", achiever_text(&before)));
                tooltip = Some(format!("before the repair: {}", achiever_text(&before)));
            }
        }
        hints.push(PlanHint { offset: goal.range.end(), label, tooltip, kind: PlanHintKind::Goal });
    }
    let now = refinements(plan, &tasks);
    let before = old.map(|o| refinements(o, &tasks));
    for (i, task) in tasks.iter().enumerate() {
        let Some(id) = now[i] else { continue };
        let text = refinement_text(plan, id);
        let mut label = format!("← {text}");
        let mut tooltip = None;
        if let (Some(o), Some(Some(old_id))) = (old, before.as_ref().map(|b| b[i])) {
            let was = refinement_text(o, old_id);
            if was != text {
                label.push_str(&format!(" (was {was})"));
                tooltip = Some(format!("before the repair: {was}"));
            }
        }
        hints.push(PlanHint { offset: task.range.end(), label, tooltip, kind: PlanHintKind::Task });
    }
    hints
}

/// How a plan uses a name: as an action or task, as an argument, as an agent.
#[derive(Debug, Default)]
struct Usage {
    count: usize,
    first: f64,
    last: f64,
    agents: Vec<String>,
}

impl Usage {
    fn add(&mut self, step: &SolvedStep) {
        if self.count == 0 {
            (self.first, self.last) = (step.start, step.end);
        } else {
            self.first = self.first.min(step.start);
            self.last = self.last.max(step.end);
        }
        self.count += 1;
        for a in &step.agents {
            if !self.agents.contains(a) {
                self.agents.push(a.clone());
            }
        }
    }
}

/// What the last plans say of the name at `offset` (an action, a task, an
/// object or a constant), in Markdown; `plans` are the last plans of the
/// problems `file` belongs to, with their problem's name.
pub fn plan_hover(
    db: &dyn Db,
    file: SourceFile,
    offset: TextSize,
    plans: &[(String, &SolvedPlan)],
) -> Option<String> {
    if plans.is_empty() {
        return None;
    }
    let (_, _, kind, key, _) = super::occurrence_at(db, file, offset)?;
    let mut lines = Vec::new();
    for (problem, plan) in plans {
        let mut usage = Usage::default();
        let what = match kind {
            RefKind::Callable | RefKind::Task => {
                plan.steps.iter().filter(|s| s.name.eq_ignore_ascii_case(&key)).for_each(|s| usage.add(s));
                "steps"
            }
            RefKind::Object => {
                plan.steps
                    .iter()
                    .filter(|s| !s.is_abstract && s.args.iter().any(|a| a.eq_ignore_ascii_case(&key)))
                    .for_each(|s| usage.add(s));
                "actions"
            }
            _ => return None,
        };
        let text = if usage.count == 0 {
            format!("not in the last plan of `{problem}`")
        } else {
            usage.agents.sort();
            let mut t = format!(
                "{} of the last plan of `{problem}`, {}–{}",
                plural(usage.count, &what[..what.len() - 1], what),
                time(usage.first),
                time(usage.last)
            );
            if !usage.agents.is_empty() {
                let shown: Vec<&str> = usage.agents.iter().take(8).map(String::as_str).collect();
                t.push_str(&format!("; agents {}", shown.join(", ")));
                if usage.agents.len() > 8 {
                    t.push_str(&format!(" and {} more", usage.agents.len() - 8));
                }
            }
            t
        };
        lines.push(format!("- {text}"));
    }
    Some(lines.join("\n"))
}

#[cfg(test)]
mod tests;
