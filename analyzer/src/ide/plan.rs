//! Hover and go to definition in plan files (VAL, IPC 2020 hierarchical,
//! JSON): a step is explained with its action's (or task's) signature from
//! the domain, its time window and the validator's verdict on it; its names
//! lead to the declarations of the domain and the problem.
//!
//! The plan is resolved to its problem, and the problem to its domain, the
//! way the validator does ([`plan_problem`], [`domain_for`]), so that hover
//! and the diagnostics always speak of the same model.

use rowan::{TextRange, TextSize};
use rustc_hash::FxHashMap;

use crate::db::{Db, SourceFile, Unit};
use crate::diagnostic::{Diagnostic, codes};
use crate::model::Str;
use crate::plan::plan_problem;
use crate::plan::{NameMatching, Plan, Step, normalise_name, parse_plan};
use crate::semantics::check::domain_for;
use crate::semantics::symbols::{DeclKind, DomainSymbols, domain_symbols, problem_symbols};

use super::{HoverResult, NavTarget, abs, sig_text};

/// The model a plan file is validated against.
struct Model<'db> {
    problem: Unit<'db>,
    domain: Option<Unit<'db>>,
    matching: NameMatching,
}

fn model(db: &dyn Db, file: SourceFile) -> Option<Model<'_>> {
    let problem = plan_problem(db, file)?;
    let lenient = crate::db::plan_options(db).lenient;
    Some(Model {
        problem,
        domain: domain_for(db, problem),
        matching: if lenient { NameMatching::Lenient } else { NameMatching::CaseInsensitive },
    })
}

/// The entry of `map` a plan's `name` means: its lower-cased key, else (under
/// lenient matching) the key equal to it up to `-` and `_`.
fn lookup<'m, V>(map: &'m FxHashMap<Str, V>, name: &str, matching: NameMatching) -> Option<(&'m Str, &'m V)> {
    let lower = name.to_ascii_lowercase();
    if let Some(found) = map.get_key_value(lower.as_str()) {
        return Some(found);
    }
    let wanted = normalise_name(name, matching);
    let mut candidates: Vec<_> = map.iter().filter(|(k, _)| normalise_name(k, matching) == wanted).collect();
    candidates.sort_by(|a, b| a.0.cmp(b.0));
    candidates.into_iter().next()
}

/// The step at `offset`: the innermost, so that a JSON step's own range wins.
fn step_at(plan: &Plan, offset: TextSize) -> Option<&Step> {
    plan.steps.iter().filter(|s| s.range.contains_inclusive(offset)).min_by_key(|s| s.range.len())
}

fn time(v: f64) -> String {
    format!("{v:.3}")
}

/// `1st`, `2nd`, `3rd`, `4th`, …, `11th`, `21st`.
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (1, r) if r != 11 => "st",
        (2, r) if r != 12 => "nd",
        (3, r) if r != 13 => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// When the step happens, in words.
fn time_window(step: &Step, index: usize) -> String {
    let Some(start) = &step.start else {
        return match step.id {
            Some(id) => format!("untimed (step {})", id.value),
            None => format!("untimed (sequential: {} in the plan's order)", ordinal(index + 1)),
        };
    };
    let mut out = match &step.duration {
        Some(d) => format!(
            "from {} to {} (duration {})",
            time(start.value),
            time(start.value + d.value),
            time(d.value)
        ),
        None => format!("at {}", time(start.value)),
    };
    if let Some(b) = &step.bounds
        && let (Some(lo), Some(hi)) = (b.start.lo, b.start.hi)
        && hi > lo
    {
        out.push_str(&format!("; may start from {} to {}", time(lo), time(hi)));
    }
    out
}

/// Whether two ranges share a byte, or an empty `a` lies in `b`.
fn touches(a: TextRange, b: TextRange) -> bool {
    if a.is_empty() { b.contains_inclusive(a.start()) } else { a.start() < b.end() && b.start() < a.end() }
}

/// The validator's verdict on a step: the diagnostics at it, or why the plan
/// was not validated, or "valid".
fn verdict(db: &dyn Db, file: SourceFile, plan: &Plan, model: Option<&Model<'_>>, step: &Step) -> String {
    // What the editor shows for the plan file (suppressions applied).
    let diagnostics: &[Diagnostic] = super::diagnostics::file_check_diagnostics(db, file);
    let here: Vec<&Diagnostic> =
        diagnostics.iter().filter(|d| d.file == file && touches(d.range, step.range)).collect();
    if !here.is_empty() {
        let lines: Vec<String> = here.iter().map(|d| format!("- `{}` {}", d.code.id, d.message)).collect();
        let status = if here.iter().any(|d| d.severity == crate::diagnostic::Severity::Error) {
            "**invalid**"
        } else {
            "**valid**, with warnings"
        };
        return format!("{status}:\n{}", lines.join("\n"));
    }
    if plan.has_errors() {
        return "**not validated**: the plan could not be read".to_string();
    }
    if model.is_none() {
        return "**not validated**: no problem found for this plan".to_string();
    }
    let blocked = [codes::MODEL_NOT_VALIDATABLE.id, codes::UNSUPPORTED_IN_PLAN.id];
    if diagnostics.iter().any(|d| blocked.contains(&d.code.id)) {
        return "**not validated**: see the plan's diagnostics".to_string();
    }
    "**valid**".to_string()
}

/// The signature of the step's action or task in the domain, with the
/// arguments it binds.
fn signature(dom: &DomainSymbols<'_>, step: &Step, matching: NameMatching) -> Option<String> {
    let map = if step.is_abstract() { &dom.tasks } else { &dom.actions };
    let (key, decl) =
        lookup(map, &step.name.text, matching).or_else(|| lookup(&dom.tasks, &step.name.text, matching))?;
    let what = match decl.kind {
        DeclKind::Action(crate::model::ActionKind::Durative) => "durative action",
        DeclKind::Task => "task",
        _ => "action",
    };
    let mut out = format!("```pddl\n{what} {}\n```", sig_text(key, decl));
    let bound: Vec<String> =
        decl.param_names.iter().zip(&step.args).map(|(p, a)| format!("`{p}` = `{}`", a.text)).collect();
    if !bound.is_empty() {
        out.push_str(&format!("\n\n{}", bound.join(", ")));
    }
    Some(out)
}

/// Hover on a step of a plan file: what it executes, when, and whether it is valid.
pub(super) fn hover(db: &dyn Db, file: SourceFile, offset: TextSize) -> Option<HoverResult> {
    let plan = parse_plan(db, file);
    let step = step_at(plan, offset)?;
    let index = plan.steps.iter().position(|s| std::ptr::eq(s, step)).unwrap_or(0);
    let model = model(db, file);
    let mut parts = Vec::new();
    let dom = model.as_ref().and_then(|m| Some((domain_symbols(db, m.domain?), m.matching)));
    match dom.and_then(|(d, matching)| signature(d, step, matching)) {
        Some(sig) => parts.push(sig),
        None => parts.push(format!("```pddl\n{}\n```", step.call())),
    }
    if let Some(d) = &step.decomposition {
        let ids: Vec<String> = d.subtasks.iter().map(|id| id.value.to_string()).collect();
        let into =
            if ids.is_empty() { "no subtask".to_string() } else { format!("steps {}", ids.join(", ")) };
        parts.push(format!("refined by method `{}` into {into}", d.method.text));
    }
    parts.push(time_window(step, index));
    parts.push(verdict(db, file, plan, model.as_ref(), step));
    Some(HoverResult { range: step.range, markdown: parts.join("\n\n") })
}

/// Go to definition from a plan: a step's action or task, a decomposition's
/// method, an argument's object or constant, a step id's step.
pub(super) fn definition(db: &dyn Db, file: SourceFile, offset: TextSize) -> Option<NavTarget> {
    let plan = parse_plan(db, file);
    // A step id named by a decomposition or the root line: that step.
    let listed = plan.steps.iter().filter_map(|s| s.decomposition.as_ref()).flat_map(|d| d.subtasks.iter());
    let roots = plan.root.iter().flat_map(|r| r.ids.iter());
    if let Some(id) = listed.chain(roots).find(|id| id.range.contains_inclusive(offset)) {
        let step = plan.step_by_id(id.value)?;
        return Some(NavTarget { file, range: step.id.map_or(step.range, |i| i.range) });
    }
    let step = step_at(plan, offset)?;
    let model = model(db, file)?;
    let nav = |(file, range)| NavTarget { file, range };
    let dom = model.domain.map(|d| domain_symbols(db, d));
    if step.name.range.contains_inclusive(offset) {
        let dom = dom?;
        let map = if step.is_abstract() { &dom.tasks } else { &dom.actions };
        let (_, decl) = lookup(map, &step.name.text, model.matching)
            .or_else(|| lookup(&dom.tasks, &step.name.text, model.matching))?;
        return Some(nav(abs(db, decl.loc)));
    }
    if let Some(d) = &step.decomposition
        && d.method.range.contains_inclusive(offset)
    {
        let (_, m) = lookup(&dom?.methods, &d.method.text, model.matching)?;
        return Some(nav(abs(db, m.loc)));
    }
    let arg = step.args.iter().find(|a| a.range.contains_inclusive(offset))?;
    if let Some((_, o)) = lookup(&problem_symbols(db, model.problem).objects, &arg.text, model.matching) {
        return Some(nav(abs(db, o.loc)));
    }
    let (_, c) = lookup(&dom?.constants, &arg.text, model.matching)?;
    Some(nav(abs(db, c.loc)))
}
