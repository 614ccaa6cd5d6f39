//! Conflicts of HiPOP abstract actions (section 4.2.1 and Definitions 3 and 11
//! of the HiPOP paper), and tasks that no method refines.
//!
//! The planner decides that an abstract step threatens a causal link on `l`
//! when `l ∈ Del(τ)` or `l ∈ 𝒞(τ)` (Definition 11), *before* the step is
//! refined. Its `:conflicts` must therefore cover every literal that a step of
//! any of its methods may delete, or a plan that looks valid at the abstract
//! level breaks once the step is refined (the patrol example of 4.2.1).
//!
//! - `E0301 uncovered-conflict`: a literal a method may delete is covered
//!   neither by the task's `:conflicts` nor by its own `Del`.
//! - `W0302 unused-conflict`: a conflict atom that no method can delete.
//! - `E0303 task-without-methods` / `W0304 unused-task`: a task without
//!   method, used by some method of the domain (an error: it can never be
//!   refined) or by none (a leftover).
//!
//! Only tasks that declare `:conflicts` (even `()`) are checked: a plain HDDL
//! task is not a HiPOP abstract action, and the planners that read it do not
//! use conflicts.
//!
//! Literals are seen from the checked task: each argument is one of its
//! parameters, a constant, or a wildcard (a variable that no parameter binds:
//! a method-local variable, a conflict's wildcard, a quantified variable). A
//! deleted literal is covered by an atom whose arguments are, position by
//! position, a wildcard or the same parameter or constant; a wildcard is only
//! covered by a wildcard, because a method-local variable may take any value.
//!
//! What a subtask may delete is what its operator may delete, substituted with
//! the subtask's arguments: an action's `Del`; a task with `:conflicts`, its
//! `Del ∪ 𝒞` (what the planner reasons with, and what E0301 checks on that
//! task itself); a plain task, its `Del` and what its methods may delete,
//! computed as a fixpoint because recursive methods are common in HDDL.
//!
//! Everything is computed from the lifted operators and methods of each item
//! (`operator`, `method_schema`), never from text offsets, so that editing one
//! item re-runs only what depends on it.

use rowan::{TextRange, TextSize};
use rustc_hash::FxHashMap;

use super::Lint;
use super::LintFix;
use super::lifted::{LAtom, LSubtask, LTerm, MethodSchema, Operator, OperatorKind, method_schema, operator};
use crate::db::{Db, Item, Section, Unit};
use crate::diagnostic::codes;
use crate::model::{ConflictsForm, Str, Symbol};
use crate::semantics::symbols::Loc;

/// A term of a literal seen from one task.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum PTerm {
    /// The task's parameter at this index.
    Param(u32),
    /// A constant, by key.
    Const(Symbol),
    /// Any object: a variable that no parameter of the task binds, with the
    /// name it is shown with.
    Wild(Symbol),
}

/// `(pred args…)` over [`PTerm`]s.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct PAtom {
    pred: Symbol,
    args: Vec<PTerm>,
}

impl PAtom {
    fn of(a: &LAtom) -> PAtom {
        let args = a
            .args
            .iter()
            .map(|t| match t {
                LTerm::Param(i) => PTerm::Param(*i),
                LTerm::Const(c) => PTerm::Const(*c),
                LTerm::Free(n) => PTerm::Wild(*n),
            })
            .collect();
        PAtom { pred: a.pred, args }
    }
}

/// The same literal pattern (wildcard names do not matter).
fn same(a: &PAtom, b: &PAtom) -> bool {
    a.pred == b.pred
        && a.args.len() == b.args.len()
        && a.args.iter().zip(&b.args).all(|(x, y)| match (x, y) {
            (PTerm::Wild(_), PTerm::Wild(_)) => true,
            _ => x == y,
        })
}

/// Whether `c` covers every instance of `d`: position by position, `c` has a
/// wildcard, or the same parameter or constant as `d`.
fn covers(c: &PAtom, d: &PAtom) -> bool {
    c.pred == d.pred
        && c.args.len() == d.args.len()
        && c.args.iter().zip(&d.args).all(|(x, y)| match (x, y) {
            (PTerm::Wild(_), _) => true,
            (_, PTerm::Wild(_)) => false,
            _ => x == y,
        })
}

/// Whether some instance of `c` may be an instance of `d`: only two different
/// constants at the same position tell them apart (two parameters may be bound
/// to the same object).
fn unifies(c: &PAtom, d: &PAtom) -> bool {
    c.pred == d.pred
        && c.args.len() == d.args.len()
        && c.args.iter().zip(&d.args).all(|(x, y)| match (x, y) {
            (PTerm::Const(a), PTerm::Const(b)) => a == b,
            _ => true,
        })
}

/// Where a literal that may be deleted comes from: an effect of an action or
/// task, or a conflict atom of a task, with what to say about it.
#[derive(Debug, Clone)]
struct Origin<'db> {
    loc: Loc<'db>,
    what: String,
}

/// A literal an operator may delete, over that operator's parameters.
#[derive(Debug, Clone)]
struct Deleted<'db> {
    atom: PAtom,
    origin: Origin<'db>,
}

/// The operators and methods of a domain, by name.
struct Index<'db> {
    /// Actions and tasks, the first declaration of each name.
    ops: FxHashMap<Str, (Item<'db>, &'db Operator)>,
    /// Tasks in source order (first declarations).
    tasks: Vec<(Item<'db>, &'db Operator)>,
    /// The methods of each task, in source order.
    methods: FxHashMap<Str, Vec<(Item<'db>, &'db MethodSchema)>>,
}

impl<'db> Index<'db> {
    fn new(db: &'db dyn Db, unit: Unit<'db>) -> Index<'db> {
        let mut index = Index { ops: FxHashMap::default(), tasks: Vec::new(), methods: FxHashMap::default() };
        for &item in unit.items(db) {
            match item.section(db) {
                Section::Action | Section::Task => {
                    let Some(op) = operator(db, item).as_ref() else { continue };
                    if index.ops.contains_key(&op.name) {
                        continue; // A duplicate (E0109): the first declaration counts.
                    }
                    index.ops.insert(op.name.clone(), (item, op));
                    if op.kind == OperatorKind::Task {
                        index.tasks.push((item, op));
                    }
                }
                Section::Method => {
                    if let Some(m) = method_schema(db, item).as_ref()
                        && let Some((task, _, _)) = &m.task
                    {
                        index.methods.entry(task.clone()).or_default().push((item, m));
                    }
                }
                _ => {}
            }
        }
        index
    }
}

/// The lints of the conflicts of every task that declares `:conflicts`.
pub(super) fn conflict_lints<'db>(db: &'db dyn Db, unit: Unit<'db>, out: &mut Vec<Lint<'db>>) {
    let index = Index::new(db, unit);
    let checked: Vec<(Item<'db>, &Operator)> =
        index.tasks.iter().copied().filter(|(_, t)| t.conflicts.is_some()).collect();
    // Plain HDDL domains (all of the IPC corpus) stop here, before any fixpoint.
    if checked.is_empty() {
        return;
    }
    let sums = summaries(&index);
    for (item, task) in checked {
        check_task(&index, &sums, item, task, out);
    }
}

/// What an operator's `Del` may delete, with its origins.
fn own_deletions<'db>(item: Item<'db>, op: &Operator) -> Vec<Deleted<'db>> {
    op.del
        .iter()
        .map(|a| Deleted {
            atom: PAtom::of(a),
            origin: Origin {
                loc: Loc { item, span: a.span },
                what: format!("`{}` deletes `{}` here", op.name, show_latom(a, &op.params)),
            },
        })
        .collect()
}

/// What each action and task may delete (Definition 11's `Del ∪ 𝒞` of a task
/// with conflicts; `Del` and its methods' deletions for a plain task), over
/// its own parameters.
fn summaries<'db>(index: &Index<'db>) -> FxHashMap<Str, Vec<Deleted<'db>>> {
    let mut sums: FxHashMap<Str, Vec<Deleted<'db>>> = FxHashMap::default();
    for (name, &(item, op)) in &index.ops {
        let mut d = own_deletions(item, op);
        if let Some(c) = &op.conflicts {
            d.extend(c.atoms.iter().map(|a| Deleted {
                atom: PAtom::of(a),
                origin: Origin {
                    loc: Loc { item, span: a.span },
                    what: format!("`{}` declares the conflict `{}` here", op.name, show_latom(a, &op.params)),
                },
            }));
        }
        sums.insert(name.clone(), d);
    }
    // Plain tasks grow with what their methods may delete until nothing
    // changes. Every literal added is over the task's parameters, the
    // domain's constants and wildcards, and is not covered by one already
    // there: finitely many, so this ends, whatever the recursion.
    let plain: Vec<&Operator> =
        index.tasks.iter().map(|&(_, t)| t).filter(|t| t.conflicts.is_none()).collect();
    loop {
        let mut changed = false;
        for task in &plain {
            let Some(methods) = index.methods.get(&task.name) else { continue };
            let new: Vec<Deleted<'db>> = methods
                .iter()
                .flat_map(|(_, m)| method_deletions(index, &sums, task, m))
                .map(|(_, d)| d)
                .collect();
            let Some(entry) = sums.get_mut(&task.name) else { continue };
            for d in new {
                if !entry.iter().any(|e| covers(&e.atom, &d.atom)) {
                    entry.push(d);
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    sums
}

/// A term of a method (over its parameters) seen from the task it refines:
/// a method parameter at position `i` of the method's `:task (t …)` is the
/// task's parameter `i`; any other method variable is a wildcard.
fn lift(t: &LTerm, task: &Operator, m: &MethodSchema) -> PTerm {
    match t {
        LTerm::Param(j) => {
            let call = m.task.as_ref().map_or(&[][..], |(_, args, _)| &args[..]);
            match call.iter().position(|a| a == t) {
                Some(i) if i < task.params.len() => PTerm::Param(i as u32),
                _ => PTerm::Wild(
                    m.params.get(*j as usize).map_or_else(|| "?x".into(), |p| Symbol::new(&p.name)),
                ),
            }
        }
        LTerm::Const(c) => PTerm::Const(*c),
        LTerm::Free(n) => PTerm::Wild(*n),
    }
}

/// What the subtasks of method `m` of `task` may delete, over the task's
/// parameters, with the index of the subtask each comes from. Subtasks that
/// name nothing or have the wrong arity are skipped: E0104 and E0110 report
/// them, and a guess here would only add noise.
fn method_deletions<'db>(
    index: &Index<'db>,
    sums: &FxHashMap<Str, Vec<Deleted<'db>>>,
    task: &Operator,
    m: &MethodSchema,
) -> Vec<(usize, Deleted<'db>)> {
    let mut out = Vec::new();
    for (si, s) in m.subtasks.iter().enumerate() {
        let (Some((_, callee)), Some(sum)) = (index.ops.get(&s.name), sums.get(&s.name)) else { continue };
        if s.args.len() != callee.params.len() {
            continue;
        }
        for d in sum {
            let args = d
                .atom
                .args
                .iter()
                .map(|a| match a {
                    PTerm::Param(i) => {
                        s.args.get(*i as usize).map_or_else(|| PTerm::Wild("?x".into()), |a| lift(a, task, m))
                    }
                    other => other.clone(),
                })
                .collect();
            out.push((si, Deleted { atom: PAtom { pred: d.atom.pred, args }, origin: d.origin.clone() }));
        }
    }
    out
}

/// An uncovered literal and where it is first deleted.
struct Uncovered<'db> {
    atom: PAtom,
    method: (Item<'db>, &'db MethodSchema),
    subtask: usize,
    origin: Origin<'db>,
    /// Other places (subtasks, methods) that delete it.
    others: usize,
}

fn check_task<'db>(
    index: &Index<'db>,
    sums: &FxHashMap<Str, Vec<Deleted<'db>>>,
    item: Item<'db>,
    task: &Operator,
    out: &mut Vec<Lint<'db>>,
) {
    let Some(conflicts) = &task.conflicts else { return };
    // A task without methods is E0303 or W0304: nothing to check here.
    let Some(methods) = index.methods.get(&task.name) else { return };
    // Definition 11 counts `Del(τ)` as well as `𝒞(τ)`: the task's own
    // deletions need not be repeated in its conflicts.
    let covering: Vec<PAtom> = task.del.iter().chain(&conflicts.atoms).map(PAtom::of).collect();
    let mut deleted: Vec<PAtom> = Vec::new();
    let mut uncovered: Vec<Uncovered<'db>> = Vec::new();
    for &(mitem, m) in methods {
        for (si, d) in method_deletions(index, sums, task, m) {
            if !covering.iter().any(|c| covers(c, &d.atom)) {
                match uncovered.iter_mut().find(|u| same(&u.atom, &d.atom)) {
                    Some(u) => u.others += 1,
                    None => uncovered.push(Uncovered {
                        atom: d.atom.clone(),
                        method: (mitem, m),
                        subtask: si,
                        origin: d.origin,
                        others: 0,
                    }),
                }
            }
            deleted.push(d.atom);
        }
    }
    for u in fold_subsumed(uncovered) {
        out.push(uncovered_lint(item, task, u));
    }
    // The task's own `Del` does not make a conflict useful: Definition 11
    // already counts it, so such a conflict adds nothing.
    for c in &conflicts.atoms {
        let atom = PAtom::of(c);
        if !deleted.iter().any(|d| unifies(&atom, d)) {
            let message = format!(
                "no method of `{}` can delete `{}`: this conflict never applies",
                task.name,
                show(&atom, &task.params)
            );
            out.push(Lint::new(codes::UNUSED_CONFLICT, Loc { item, span: c.span }, message));
        }
    }
}

/// One diagnostic per literal to add: a literal that another uncovered one
/// covers (`(at ?r ?a)` beside `(at ?r ?w)` with `?w` a wildcard) is fixed by
/// the same atom, so it is counted with it rather than reported apart.
fn fold_subsumed(mut all: Vec<Uncovered<'_>>) -> Vec<Uncovered<'_>> {
    let general = |u: &Uncovered<'_>, all: &[Uncovered<'_>]| {
        !all.iter().any(|v| !same(&v.atom, &u.atom) && covers(&v.atom, &u.atom))
    };
    let keep: Vec<bool> = all.iter().map(|u| general(u, &all)).collect();
    let mut kept: Vec<Uncovered<'_>> = Vec::new();
    let mut folded: Vec<Uncovered<'_>> = Vec::new();
    for (u, k) in all.drain(..).zip(keep) {
        if k { kept.push(u) } else { folded.push(u) }
    }
    for f in folded {
        // `covers` is transitive: some kept literal covers every folded one.
        if let Some(k) = kept.iter_mut().find(|k| covers(&k.atom, &f.atom)) {
            k.others += f.others + 1;
        }
    }
    kept
}

fn uncovered_lint<'db>(item: Item<'db>, task: &Operator, u: Uncovered<'db>) -> Lint<'db> {
    let (mitem, m) = u.method;
    let literal = show(&u.atom, &task.params);
    let subtask = &m.subtasks[u.subtask];
    let id = subtask.id.as_ref().map(|i| format!("`{i}` ")).unwrap_or_default();
    let others = match u.others {
        0 => String::new(),
        1 => " (and 1 other place)".to_string(),
        n => format!(" (and {n} other places)"),
    };
    let message = format!(
        "conflicts of `{}` do not cover `{literal}`, deleted by subtask {id}`{}` in method `{}`{others}",
        task.name,
        show_subtask(subtask, m),
        m.name
    );
    // The task is `Some` here: only tasks with `:conflicts` are checked.
    let conflicts = task.conflicts.as_ref();
    let primary = conflicts.map_or(task.name_span, |c| c.keyword);
    let mut lint = Lint::new(codes::UNCOVERED_CONFLICT, Loc { item, span: primary }, message)
        .related(
            Loc { item: mitem, span: subtask.span },
            format!("this subtask of `{}` may delete it", m.name),
        )
        .related(u.origin.loc, u.origin.what);
    if let Some(c) = conflicts {
        let edits = add_conflict_edits(&c.form, c.span, &literal);
        if !edits.is_empty() {
            lint.fix = Some(LintFix {
                message: format!("add `{literal}` to the conflicts of `{}`", task.name),
                edits: edits.into_iter().map(|(span, text)| (Loc { item, span }, text)).collect(),
            });
        }
    }
    lint
}

/// The edits (item-relative) that add `atom` to a `:conflicts` formula
/// written as `form` at `span`, keeping the rest of the text as it is.
fn add_conflict_edits(form: &ConflictsForm, span: TextRange, atom: &str) -> Vec<(TextRange, String)> {
    match form {
        ConflictsForm::And { at, sep } => vec![(TextRange::empty(*at), format!("{sep}{atom}"))],
        // `(p …)` → `(and (p …) atom)`: the `)` is replaced rather than
        // followed, so that two such fixes overlap and only one is applied.
        ConflictsForm::Atom => {
            let close = TextRange::at(span.end() - TextSize::from(1), TextSize::from(1));
            vec![(TextRange::empty(span.start()), "(and ".to_string()), (close, format!(") {atom})"))]
        }
        ConflictsForm::Empty => vec![(span, format!("(and {atom})"))],
        ConflictsForm::Other => Vec::new(),
    }
}

/// A literal in the task's parameter names; wildcards keep their variable's
/// name unless it is a parameter's (or another wildcard's) name, so that the
/// atom means the same when pasted into `:conflicts`.
fn show(atom: &PAtom, params: &[super::lifted::Param]) -> String {
    let mut wild: Vec<(&str, String)> = Vec::new();
    let mut out = format!("({}", atom.pred);
    for a in &atom.args {
        out.push(' ');
        match a {
            PTerm::Param(i) => out.push_str(params.get(*i as usize).map_or("?", |p| &p.name)),
            PTerm::Const(c) => out.push_str(c),
            PTerm::Wild(n) => {
                let name = match wild.iter().find(|(orig, _)| orig == &&**n) {
                    Some((_, name)) => name.clone(),
                    None => {
                        // An object-fluent placeholder is not a variable name.
                        let base =
                            if n.starts_with('?') && n.len() > 1 { n.to_string() } else { "?x".into() };
                        let taken = |c: &str| {
                            params.iter().any(|p| &*p.name == c) || wild.iter().any(|(_, w)| w == c)
                        };
                        let mut name = base.clone();
                        let mut k = 2;
                        while taken(&name) {
                            name = format!("{base}{k}");
                            k += 1;
                        }
                        wild.push((n, name.clone()));
                        name
                    }
                };
                out.push_str(&name);
            }
        }
    }
    out.push(')');
    out
}

fn show_lterm(t: &LTerm, params: &[super::lifted::Param]) -> String {
    match t {
        LTerm::Param(i) => params.get(*i as usize).map_or_else(|| "?".into(), |p| p.name.to_string()),
        LTerm::Const(c) | LTerm::Free(c) => c.to_string(),
    }
}

fn show_latom(a: &LAtom, params: &[super::lifted::Param]) -> String {
    let args: String = a.args.iter().map(|t| format!(" {}", show_lterm(t, params))).collect();
    format!("({}{args})", a.pred)
}

fn show_subtask(s: &LSubtask, m: &MethodSchema) -> String {
    let args: String = s.args.iter().map(|t| format!(" {}", show_lterm(t, &m.params))).collect();
    format!("({}{args})", s.name)
}

/// E0303 and W0304: tasks that no method refines.
pub(super) fn method_less_tasks<'db>(db: &'db dyn Db, unit: Unit<'db>, out: &mut Vec<Lint<'db>>) {
    let index = Index::new(db, unit);
    // A method whose `:task` names no task (E0105, often a typo) may be meant
    // for any task of that arity: those are not reported until it is fixed.
    let orphan_arities: Vec<usize> = index
        .methods
        .iter()
        .filter(|(name, _)| !index.ops.contains_key(*name))
        .flat_map(|(_, ms)| ms.iter().filter_map(|(_, m)| m.task.as_ref().map(|(_, args, _)| args.len())))
        .collect();
    // Uses in methods of the domain, by task, in source order. A problem's
    // `:htn` or `:allowed-actions` is not seen here (this is a domain lint).
    let mut uses: FxHashMap<&Str, Vec<(Loc<'db>, &Str)>> = FxHashMap::default();
    for &m_item in unit.items(db) {
        let Some(m) = method_schema(db, m_item).as_ref() else { continue };
        for s in &m.subtasks {
            uses.entry(&s.name).or_default().push((Loc { item: m_item, span: s.span }, &m.name));
        }
    }
    for &(item, task) in &index.tasks {
        if index.methods.contains_key(&task.name) || orphan_arities.contains(&task.params.len()) {
            continue;
        }
        let loc = Loc { item, span: task.name_span };
        let uses = uses.get(&task.name).map_or(&[][..], |u| &u[..]);
        let Some(&(first, method)) = uses.first() else {
            let message = format!("task `{}` has no method, and no method uses it", task.name);
            out.push(Lint::new(codes::UNUSED_TASK, loc, message));
            continue;
        };
        let others = match uses.len() - 1 {
            0 => String::new(),
            1 => " (and 1 other subtask)".to_string(),
            n => format!(" (and {n} other subtasks)"),
        };
        let message = format!(
            "task `{}` has no method: it can never be refined, but method `{method}` uses it{others}",
            task.name
        );
        out.push(Lint::new(codes::TASK_WITHOUT_METHODS, loc, message).related(first, "used here"));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AnalysisHost, Diagnostic};

    fn p(pred: &str, args: &[PTerm]) -> PAtom {
        PAtom { pred: pred.into(), args: args.to_vec() }
    }
    fn param(i: u32) -> PTerm {
        PTerm::Param(i)
    }
    fn c(s: &str) -> PTerm {
        PTerm::Const(s.into())
    }
    fn w(s: &str) -> PTerm {
        PTerm::Wild(s.into())
    }

    #[test]
    fn coverage_by_position() {
        let del = p("at", &[param(0), param(1)]);
        assert!(covers(&p("at", &[param(0), param(1)]), &del));
        assert!(covers(&p("at", &[param(0), w("?w")]), &del));
        assert!(covers(&p("at", &[w("?a"), w("?b")]), &del));
        assert!(!covers(&p("at", &[param(0), param(0)]), &del), "another parameter");
        assert!(!covers(&p("at", &[param(0), c("base")]), &del), "a constant");
        assert!(!covers(&p("at", &[param(0)]), &del), "another arity");
        assert!(!covers(&p("on", &[param(0), param(1)]), &del), "another predicate");
        // A method-local variable (a wildcard) is covered by a wildcard only.
        let local = p("at", &[param(0), w("?b")]);
        assert!(covers(&p("at", &[param(0), w("?w")]), &local));
        assert!(!covers(&p("at", &[param(0), param(1)]), &local));
        // A constant by the same constant or a wildcard.
        let constant = p("at", &[param(0), c("base")]);
        assert!(covers(&p("at", &[param(0), c("base")]), &constant));
        assert!(covers(&p("at", &[param(0), w("?w")]), &constant));
        assert!(!covers(&p("at", &[param(0), c("dock")]), &constant));
    }

    #[test]
    fn unification_tells_apart_only_constants() {
        let del = p("at", &[param(0), c("base")]);
        assert!(unifies(&p("at", &[param(1), param(2)]), &del));
        assert!(unifies(&p("at", &[w("?r"), c("base")]), &del));
        assert!(!unifies(&p("at", &[param(0), c("dock")]), &del));
        assert!(!unifies(&p("at", &[param(0)]), &del));
        assert!(same(&p("at", &[w("?a")]), &p("at", &[w("?b")])));
        assert!(!same(&p("at", &[w("?a")]), &p("at", &[param(0)])));
    }

    #[test]
    fn wildcard_names_avoid_parameters() {
        let params: Vec<super::super::lifted::Param> = ["?r", "?w"]
            .iter()
            .map(|n| super::super::lifted::Param {
                name: (*n).into(),
                types: vec![],
                span: TextRange::default(),
            })
            .collect();
        assert_eq!(show(&p("at", &[param(0), w("?w")]), &params), "(at ?r ?w2)");
        assert_eq!(show(&p("link", &[w("?a"), w("?a"), w("?b")]), &params), "(link ?a ?a ?b)");
        assert_eq!(show(&p("f", &[w("(fuel)")]), &params), "(f ?x)");
    }

    const MOVE: &str = "(:predicates (at ?r ?w) (seen ?w) (busy ?r))
        (:action move :parameters (?r ?a ?b)
          :precondition (at ?r ?a) :effect (and (not (at ?r ?a)) (at ?r ?b)))";

    fn lints(tasks: &str) -> Vec<Diagnostic> {
        let mut host = AnalysisHost::new();
        let text = format!("(define (domain d) (:requirements :hierarchy) {MOVE}\n{tasks})");
        let f = host.set_file_text("d.hddl", text);
        host.analysis()
            .diagnostics(f)
            .expect("not cancelled")
            .into_iter()
            .filter(|d| d.code.id.starts_with("E03") || d.code.id.starts_with("W03"))
            .collect()
    }

    fn messages(ds: &[Diagnostic]) -> Vec<String> {
        ds.iter().map(|d| format!("{} {}", d.code.id, d.message)).collect()
    }

    #[test]
    fn wildcard_covers_local_variables_and_constants() {
        let ds = lints(
            "(:task patrol :parameters (?r) :conflicts (and (at ?r ?w)))
             (:method loop :parameters (?r ?a ?b) :task (patrol ?r)
               :ordered-subtasks (and (t1 (move ?r ?a ?b)) (t2 (move ?r ?b base)) (t3 (patrol ?r))))",
        );
        assert_eq!(messages(&ds), Vec::<String>::new());
    }

    #[test]
    fn parameter_does_not_cover_local_variable() {
        let ds = lints(
            "(:task goto :parameters (?r ?to) :conflicts (and (at ?r ?to)))
             (:method direct :parameters (?r ?from ?to) :task (goto ?r ?to)
               :subtasks (and (t1 (move ?r ?from ?to))))",
        );
        assert_eq!(
            messages(&ds),
            [
                "E0301 conflicts of `goto` do not cover `(at ?r ?from)`, deleted by subtask `t1` `(move ?r ?from ?to)` in method `direct`",
            ],
            "`(at ?r ?from)` may be `(at ?r ?to)`: the conflict is not unused"
        );
        // The method's variables are renamed to the task's: `?x` is bound to `?to`.
        let ds = lints(
            "(:task goto :parameters (?r ?to) :conflicts (and (at ?r ?to)))
             (:method back :parameters (?x ?y) :task (goto ?x ?y)
               :subtasks (and (t1 (move ?x ?y ?y))))",
        );
        assert_eq!(messages(&ds), Vec::<String>::new());
    }

    #[test]
    fn nested_tasks_count_their_deletions_and_conflicts() {
        // `tour` calls `goto` (with conflicts: they count) and `wander` (plain,
        // recursive: its methods' deletions count, through the recursion).
        let ds = lints(
            "(:task tour :parameters (?r) :conflicts (and (busy ?r)))
             (:method tour-m :parameters (?r ?w) :task (tour ?r)
               :subtasks (and (t1 (goto ?r ?w)) (t2 (wander ?r))))
             (:task goto :parameters (?r ?to) :conflicts (and (at ?r ?any)))
             (:method goto-m :parameters (?r ?from ?to) :task (goto ?r ?to)
               :subtasks (and (move ?r ?from ?to)))
             (:task wander :parameters (?r))
             (:method wander-step :parameters (?r ?a ?b) :task (wander ?r)
               :subtasks (and (wander ?r) (wander-from ?r ?a)))
             (:task wander-from :parameters (?r ?a) :effect (not (seen ?a)))
             (:method wander-from-m :parameters (?r ?a ?b) :task (wander-from ?r ?a)
               :subtasks (and (move ?r ?a ?b)))",
        );
        let m = messages(&ds);
        assert_eq!(m.len(), 3, "{m:#?}");
        assert!(m[0].starts_with("E0301 conflicts of `tour` do not cover `(at ?r ?any)`, deleted by subtask `t1` `(goto ?r ?w)` in method `tour-m` (and 1 other place)"), "{m:#?}");
        assert!(
            m[1].starts_with(
                "E0301 conflicts of `tour` do not cover `(seen ?a)`, deleted by subtask `t2` `(wander ?r)`"
            ),
            "{m:#?}"
        );
        assert_eq!(m[2], "W0302 no method of `tour` can delete `(busy ?r)`: this conflict never applies");
    }

    #[test]
    fn own_deletions_need_no_conflict_but_make_none_useful() {
        let ds = lints(
            "(:task rest :parameters (?r ?w) :effect (not (at ?r ?w)) :conflicts (and (at ?r ?w)))
             (:method rest-m :parameters (?r ?w) :task (rest ?r ?w)
               :subtasks (and (move ?r ?w ?w)))",
        );
        // `(at ?r ?w)` is deleted by the method (covered by `Del`): the conflict is used.
        assert_eq!(messages(&ds), Vec::<String>::new());
        let ds = lints(
            "(:task rest :parameters (?r ?w) :effect (not (busy ?r)) :conflicts (and (busy ?r)))
             (:method rest-m :parameters (?r ?w) :task (rest ?r ?w) :subtasks (and (move ?r ?w ?w)))",
        );
        assert_eq!(
            messages(&ds),
            [
                "E0301 conflicts of `rest` do not cover `(at ?r ?w)`, deleted by subtask `(move ?r ?w ?w)` in method `rest-m`",
                "W0302 no method of `rest` can delete `(busy ?r)`: this conflict never applies",
            ]
        );
    }

    #[test]
    fn plain_tasks_are_not_checked_but_empty_conflicts_are() {
        let plain = "(:task goto :parameters (?r ?to))
             (:method m :parameters (?r ?from ?to) :task (goto ?r ?to) :subtasks (and (move ?r ?from ?to)))";
        assert_eq!(messages(&lints(plain)), Vec::<String>::new());
        let ds = lints(&plain.replace("(?r ?to))", "(?r ?to) :conflicts ())"));
        assert_eq!(messages(&ds).len(), 1);
        assert_eq!(ds[0].code.id, "E0301");
    }

    #[test]
    fn identical_and_subsumed_literals_are_grouped() {
        let ds = lints(
            "(:task patrol :parameters (?r ?home) :conflicts (and (busy ?r)))
             (:method one :parameters (?r ?home ?b) :task (patrol ?r ?home)
               :subtasks (and (t1 (move ?r ?home ?b)) (t2 (move ?r ?b ?home)) (t3 (busy-move ?r))))
             (:method two :parameters (?r ?home ?c) :task (patrol ?r ?home)
               :subtasks (and (t1 (move ?r ?c ?home))))
             (:task busy-move :parameters (?r) :conflicts (and (busy ?r)))
             (:method bm :parameters (?r) :task (busy-move ?r) :subtasks (and))",
        );
        assert_eq!(
            messages(&ds),
            [
                "E0301 conflicts of `patrol` do not cover `(at ?r ?b)`, deleted by subtask `t2` `(move ?r ?b ?home)` in method `one` (and 2 other places)",
                // Its only method deletes nothing: its conflict is declared in vain
                // (and still counts for `patrol`, which calls it).
                "W0302 no method of `busy-move` can delete `(busy ?r)`: this conflict never applies",
            ]
        );
    }

    #[test]
    fn a_method_of_an_undeclared_task_may_be_meant_for_a_task_without_methods() {
        let ds = lints(
            "(:task goto :parameters (?r ?to))
             (:task park :parameters (?r))
             (:method m :parameters (?r ?to) :task (go-to ?r ?to) :subtasks (and))",
        );
        assert_eq!(messages(&ds), ["W0304 task `park` has no method, and no method uses it"]);
    }

    #[test]
    fn tasks_without_methods() {
        let ds = lints(
            "(:task used :parameters (?r))
             (:task unused :parameters (?r))
             (:task top :parameters (?r))
             (:method top-m :parameters (?r) :task (top ?r) :subtasks (and (used ?r) (used ?r)))",
        );
        assert_eq!(
            messages(&ds),
            [
                "E0303 task `used` has no method: it can never be refined, but method `top-m` uses it (and 1 other subtask)",
                "W0304 task `unused` has no method, and no method uses it",
            ]
        );
    }

    /// The text with the fix of a diagnostic applied.
    fn fixed(text: &str, d: &Diagnostic) -> String {
        let fix = d.fix.as_ref().expect("a fix");
        let edits: Vec<(TextRange, &str)> = fix.edits.iter().map(|(_, r, t)| (*r, t.as_str())).collect();
        crate::fix::apply_edits(text, &edits).expect("valid edits")
    }

    fn fix_of(conflicts: &str) -> String {
        let text = format!(
            "(define (domain d) (:requirements :hierarchy) {MOVE}
  (:task goto :parameters (?r ?to) :conflicts {conflicts})
  (:method m :parameters (?r ?from ?to) :task (goto ?r ?to) :subtasks (and (move ?r ?from ?to))))"
        );
        let mut host = AnalysisHost::new();
        let f = host.set_file_text("d.hddl", text.as_str());
        let ds = host.analysis().diagnostics(f).expect("not cancelled");
        let d = ds.iter().find(|d| d.code.id == "E0301").expect("E0301");
        let after = fixed(&text, d);
        let start = after.find(":conflicts ").expect("conflicts") + ":conflicts ".len();
        let end = after.find("\n  (:method").expect("method");
        after[start..end].strip_suffix(')').expect("the task's `)`").to_string()
    }

    #[test]
    fn fixes_keep_layout_and_comments() {
        assert_eq!(fix_of("(and (busy ?r))"), "(and (busy ?r) (at ?r ?from))");
        assert_eq!(fix_of("(and)"), "(and (at ?r ?from))");
        assert_eq!(fix_of("()"), "(and (at ?r ?from))");
        assert_eq!(fix_of("(busy ?r)"), "(and (busy ?r) (at ?r ?from))");
        assert_eq!(
            fix_of("(and\n    (busy ?r) ; why\n    (seen ?to))"),
            "(and\n    (busy ?r) ; why\n    (seen ?to)\n    (at ?r ?from))"
        );
    }
}
