//! Allowed-action lints (section 4.2.2 of the HiPOP paper): the set 𝒜 of
//! `(:allowed-actions …)` is what the planner may insert to close an open link;
//! everything else enters a plan only through the methods of the tasks it
//! refines.
//!
//! W0311 and W0312 read names and methods only; they run for problems that
//! declare `(:allowed-actions …)`. Without it every action is allowed (or,
//! with an `:htn`, none: pure HTN planning), and an action a given problem
//! does not need is not a mistake of the model.
//!
//! E0313 runs for those problems and for pure HTN ones (an `:htn`, no
//! `(:allowed-actions …)`): with relaxed reachability restricted to the
//! *usable* operators (the allowed ones, the `:htn` tasks, and what methods of
//! allowed and `:htn` tasks use), a goal atom out of reach, or an `:htn` task
//! that no method instance refines into achievable steps (the fixpoint of
//! [`Index::achievable`], computed in `decompose.rs`, whose query calls
//! [`htn_lints`]).

use rustc_hash::{FxHashMap, FxHashSet};

use crate::db::{Db, Item, Section, Unit};
use crate::diagnostic::codes;
use crate::model::{ItemData, Name, Str, Subtask, Term};
use crate::semantics::symbols::Loc;

use super::Lint;
use super::decompose::Index;
use super::ground::Ground;
use super::lifted::{OperatorKind, method_schema, operator};
use super::reach::Reach;
use super::state::ObjId;

/// A method, and the name and span of each of its subtasks.
type MethodUses<'db> = (Item<'db>, Vec<(Str, rowan::TextRange)>);

/// What a domain declares, by name.
struct Domain<'db> {
    /// Actions and tasks: item, name span, kind.
    ops: FxHashMap<Str, (Item<'db>, rowan::TextRange, OperatorKind)>,
    /// The methods of each task: item, and each subtask's name and span.
    methods: FxHashMap<Str, Vec<MethodUses<'db>>>,
    /// Declaration order, for stable output.
    order: Vec<Str>,
    /// Some method has an `:effect` (a PANDA extension): grounding does not
    /// apply those, so relaxed reachability may miss atoms.
    method_effects: bool,
}

fn domain<'db>(db: &'db dyn Db, unit: Unit<'db>) -> Domain<'db> {
    let mut d = Domain {
        ops: FxHashMap::default(),
        methods: FxHashMap::default(),
        order: Vec::new(),
        method_effects: false,
    };
    for &item in unit.items(db) {
        if let Some(op) = operator(db, item) {
            if d.ops.insert(op.name.clone(), (item, op.name_span, op.kind)).is_none() {
                d.order.push(op.name.clone());
            }
        } else if let Some(m) = method_schema(db, item)
            && let Some((task, _, _)) = &m.task
        {
            let subtasks = m.subtasks.iter().map(|s| (s.name.clone(), s.span)).collect();
            d.method_effects |= super::decompose::has_effect(db, item);
            d.methods.entry(task.clone()).or_default().push((item, subtasks));
        }
    }
    d
}

/// The problem's `(:allowed-actions …)`: its item, the span of its keyword and the names.
fn allowed_actions<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
) -> Option<(Item<'db>, rowan::TextRange, Vec<Name>)> {
    let item = problem.items(db).iter().copied().find(|i| i.section(db) == Section::AllowedActions)?;
    let ItemData::AllowedActions(names) = &crate::db::lower_item(db, item).data else { return None };
    let keyword = item.head(db).unwrap_or(rowan::TextRange::at(0.into(), 1.into()));
    Some((item, keyword, names.clone()))
}

/// The task names of the problem's `:htn`.
fn htn_tasks(db: &dyn Db, problem: Unit<'_>) -> Vec<Str> {
    let mut out = Vec::new();
    for &item in problem.items(db) {
        if item.section(db) == Section::Htn
            && let ItemData::Htn(h) = &crate::db::lower_item(db, item).data
        {
            out.extend(h.network.subtasks.iter().map(|s| s.call.name.key_str()));
        }
    }
    out
}

/// What the planner of a problem may use: the allowed set, and the actions
/// and tasks that methods reachable from the allowed tasks and from `:htn` use.
struct Usage<'db> {
    allowed: Option<(Item<'db>, rowan::TextRange, Vec<Name>)>,
    /// The task names of `:htn`.
    htn: Vec<Str>,
    /// Each action or task a method of an allowed or `:htn` task uses (directly
    /// or through other tasks), with the first subtask that does.
    used: FxHashMap<Str, Loc<'db>>,
    /// The same, from the allowed tasks only.
    from_allowed: FxHashMap<Str, Loc<'db>>,
}

impl Usage<'_> {
    /// No `(:allowed-actions …)`, an `:htn`: the planner inserts nothing on its own.
    fn pure_htn(&self) -> bool {
        self.allowed.is_none()
    }

    /// Whether the planner may use an action or task of that name.
    fn usable(&self, name: &str) -> bool {
        self.allowed.as_ref().is_some_and(|a| a.2.iter().any(|n| n.key() == name))
            || self.used.contains_key(name)
            || self.htn.iter().any(|h| h == name)
    }
}

/// `None` when the problem restricts nothing: no `(:allowed-actions …)` and
/// no `:htn` (every action is allowed).
fn usage<'db>(db: &'db dyn Db, problem: Unit<'db>, d: &Domain<'db>) -> Option<Usage<'db>> {
    let allowed = allowed_actions(db, problem);
    let htn = htn_tasks(db, problem);
    if allowed.is_none() && htn.is_empty() {
        return None;
    }
    let mut used: FxHashMap<Str, Loc<'db>> = FxHashMap::default();
    let mut from_allowed: FxHashMap<Str, Loc<'db>> = FxHashMap::default();
    let is_task = |n: &str| d.ops.get(n).is_some_and(|o| o.2 == OperatorKind::Task);
    let allowed_tasks: Vec<Str> =
        allowed.iter().flat_map(|a| &a.2).map(|n| n.key_str()).filter(|n| is_task(n)).collect();
    // Tasks reachable from the allowed tasks, then from the `:htn`, through
    // methods; the first method subtask that uses each action or task.
    for (roots, record) in [(allowed_tasks, &mut from_allowed), (htn.clone(), &mut used)] {
        let mut queue: Vec<Str> = roots;
        let mut seen: FxHashSet<Str> = queue.iter().cloned().collect();
        while let Some(task) = queue.pop() {
            for (method, subtasks) in d.methods.get(&task).into_iter().flatten() {
                for (name, span) in subtasks {
                    record.entry(name.clone()).or_insert(Loc { item: *method, span: *span });
                    if is_task(name) && seen.insert(name.clone()) {
                        queue.push(name.clone());
                    }
                }
            }
        }
    }
    for (name, loc) in &from_allowed {
        used.entry(name.clone()).or_insert(*loc);
    }
    Some(Usage { allowed, htn, used, from_allowed })
}

/// Relaxed reachability with the usable operators; `None` when grounding
/// stopped at a limit (what is out of reach may only be out of the limit).
fn usable_reach(g: &Ground<'_>, u: &Usage<'_>) -> Option<(Vec<bool>, Reach)> {
    if g.truncated {
        return None;
    }
    let schema_usable: Vec<bool> = g.schemas.iter().map(|s| u.usable(&s.name)).collect();
    let reach = super::reach::reachable(g, |op| schema_usable[op.schema as usize]);
    Some((schema_usable, reach))
}

/// The lints of the allowed set and of the goals: dead actions and tasks
/// (W0311) and allowed actions the planner could also insert through an
/// allowed task's method (W0312), for problems with `(:allowed-actions …)`;
/// goals out of reach (E0313), for those problems and for pure HTN ones (an
/// `:htn` without `(:allowed-actions …)`). `is_family_move` tells the move
/// actions of confirmed position families, which the paper allows on purpose
/// (a robot must reach the start of its next patrol). The `:htn` tasks out of
/// reach are [`htn_lints`], which needs the ground methods.
pub(super) fn lints<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    domain_unit: Unit<'db>,
    is_family_move: &dyn Fn(&str) -> bool,
    out: &mut Vec<Lint<'db>>,
) {
    let d = domain(db, domain_unit);
    let Some(u) = usage(db, problem, &d) else { return };
    if let Some((allowed_item, keyword, allowed)) = &u.allowed {
        dead_and_double(&d, *allowed_item, *keyword, allowed, &u, is_family_move, out);
    }
    if d.method_effects {
        // Grounding does not apply method effects: atoms they add are out of its reach.
        return;
    }
    if !problem.items(db).iter().any(|i| i.section(db) == Section::Goal) {
        return;
    }
    let g = super::ground::ground(db, problem);
    let Some((_, reach)) = usable_reach(g, &u) else { return };
    unreachable_goals(db, problem, &d, g, &reach, u.pure_htn(), out);
}

/// E0313 on the `:htn` tasks of a problem that no method instance refines
/// into achievable steps with the usable operators (see [`usage`]). Silent
/// when an instance may be missing: grounding stopped at a limit, or a usable
/// action or task is outside the STRIPS view; a task with a method whose
/// instances were cut counts as achievable.
pub(super) fn htn_lints<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    domain_unit: Unit<'db>,
    idx: &Index<'_, 'db>,
    out: &mut Vec<Lint<'db>>,
) {
    let d = domain(db, domain_unit);
    let Some(u) = usage(db, problem, &d) else { return };
    if u.htn.is_empty() || d.method_effects {
        return;
    }
    let Some((schema_usable, reach)) = usable_reach(idx.g, &u) else { return };
    let unsupported = idx.g.schemas.iter().zip(&schema_usable).any(|(s, &u)| u && s.unsupported);
    if unsupported {
        // Its lists may miss atoms, and its instances be pruned too much.
        return;
    }
    unreachable_htn(db, problem, &d, idx, &reach, u.pure_htn(), out);
}

/// W0311 and W0312.
fn dead_and_double<'db>(
    d: &Domain<'db>,
    allowed_item: Item<'db>,
    keyword: rowan::TextRange,
    allowed: &[Name],
    u: &Usage<'db>,
    is_family_move: &dyn Fn(&str) -> bool,
    out: &mut Vec<Lint<'db>>,
) {
    let allowed_keys: FxHashSet<&str> = allowed.iter().map(|n| n.key()).collect();
    for name in &d.order {
        let (item, span, kind) = d.ops[name];
        if allowed_keys.contains(&**name) || u.used.contains_key(name) || u.htn.contains(name) {
            continue;
        }
        let what = if kind == OperatorKind::Task { "task" } else { "action" };
        out.push(
            Lint::new(
                codes::DEAD_ACTION,
                Loc { item: allowed_item, span: keyword },
                format!(
                    "{what} `{name}` can never be in a plan of this problem: it is not allowed, and no method \
                     of an allowed task or of `:htn` uses it"
                ),
            )
            .related(Loc { item, span }, format!("`{name}` is declared here")),
        );
    }

    for n in allowed {
        let Some(&(_, _, kind)) = d.ops.get(n.key()) else { continue };
        if kind == OperatorKind::Task || is_family_move(n.key()) {
            continue;
        }
        if let Some(&loc) = u.from_allowed.get(n.key()) {
            out.push(
                Lint::new(
                    codes::DOUBLE_INSERTION,
                    Loc { item: allowed_item, span: n.span },
                    format!(
                        "`{}` is allowed and is also a subtask of a method of an allowed task: the planner can \
                         build the same plan both ways",
                        n.text()
                    ),
                )
                .related(loc, "a method of an allowed task uses it here"),
            );
        }
    }
}

/// E0313 on goals: goal atoms that relaxed reachability from the initial
/// state cannot reach with the usable operators (the allowed ones and those
/// the methods of allowed tasks and of `:htn` use), naming the producers that
/// are not usable.
fn unreachable_goals<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    d: &Domain<'db>,
    g: &Ground<'db>,
    reach: &Reach,
    pure_htn: bool,
    out: &mut Vec<Lint<'db>>,
) {
    for &item in problem.items(db) {
        if item.section(db) != Section::Goal {
            continue;
        }
        let ItemData::Goal(goal) = &crate::db::lower_item(db, item).data else { continue };
        let mut atoms = Vec::new();
        positive_atoms(goal, &mut atoms);
        for atom in atoms {
            let Some(pred) = g.predicates.get(atom.pred.key()) else { continue };
            if g.untracked_preds.get(pred as usize).copied().unwrap_or(true) {
                continue;
            }
            let args: Option<Vec<u32>> = atom
                .args
                .iter()
                .map(|t| match t {
                    crate::model::Term::Const(n) => g.objects.id(n.key()),
                    _ => None,
                })
                .collect();
            let Some(args) = args else { continue };
            let id = g.atoms.find(pred, &args);
            if id.is_some_and(|a| reach.atom(a)) {
                continue;
            }
            if pure_htn && !id.is_some_and(|a| g.is_reachable(a)) {
                // Out of reach of every action: a plain unreachable goal, which
                // hipop does not report for problems without restrictions
                // either (nor for a problem checked against another domain of
                // the same name). E0313 is about what the hierarchy removes.
                continue;
            }
            // Producers: the schemas of reachable instances that add it.
            let mut producers: Vec<&str> = Vec::new();
            if let Some(a) = id {
                for op in &g.operators {
                    let name = &*g.schemas[op.schema as usize].name;
                    if !producers.contains(&name) && g.add(op).contains(&a) {
                        producers.push(name);
                    }
                }
            }
            let (them, with) = if pure_htn {
                (
                    "no method of the `:htn` tasks (or of the tasks they use) uses",
                    "by refining the `:htn` tasks",
                )
            } else {
                (
                    "not allowed, and no method of an allowed task uses",
                    "with the allowed actions and their methods",
                )
            };
            let why = match producers.as_slice() {
                [] => "no action or task can add it from the initial state".to_string(),
                names if pure_htn => format!(
                    "{} could add it but {them} {}",
                    names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "),
                    if names.len() == 1 { "it" } else { "them" },
                ),
                names => format!(
                    "{} could add it but {} {them} {}",
                    names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "),
                    if names.len() == 1 { "is" } else { "are" },
                    if names.len() == 1 { "it" } else { "them" },
                ),
            };
            let mut lint = Lint::new(
                codes::UNREACHABLE_GOAL,
                Loc { item, span: atom.span },
                format!(
                    "the goal `{}` cannot be achieved {with}, even ignoring deletions: {why}",
                    g.show_atom_parts(pred, &args)
                ),
            );
            for name in producers {
                if let Some(&(op_item, span, _)) = d.ops.get(name) {
                    lint = lint.related(Loc { item: op_item, span }, format!("`{name}` adds it"));
                }
            }
            out.push(lint);
        }
    }
}

/// The subtasks of the problem's `:htn`, with their item.
fn htn_subtasks<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Vec<(Item<'db>, &'db Subtask)> {
    let mut out = Vec::new();
    for &item in problem.items(db) {
        if item.section(db) == Section::Htn
            && let ItemData::Htn(h) = &crate::db::lower_item(db, item).data
        {
            out.extend(h.network.subtasks.iter().map(|s| (item, s)));
        }
    }
    out
}

/// E0313 on `:htn` tasks: those that no method instance refines into steps
/// that are achievable with the usable operators (the relaxed decomposition
/// fixpoint of [`Index::achievable`]). A subtask with variables (`:htn
/// :parameters`) is out of reach when no achievable instance of its task
/// matches its constants.
fn unreachable_htn<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    d: &Domain<'db>,
    idx: &Index<'_, 'db>,
    reach: &Reach,
    pure_htn: bool,
    out: &mut Vec<Lint<'db>>,
) {
    let g = idx.g;
    let done = idx.achievable(reach);
    let with =
        if pure_htn { "with the domain's methods" } else { "with the allowed actions and the methods" };
    for (item, sub) in htn_subtasks(db, problem) {
        let name = sub.call.name.key();
        if idx.schema(name).is_none() || idx.incomplete_tasks.contains(name) {
            continue;
        }
        // Each argument: an object, or a variable (`None`).
        let mut pattern: Vec<Option<ObjId>> = Vec::new();
        let mut known = true;
        for t in &sub.call.args {
            match t {
                Term::Const(n) => match g.objects.id(n.key()) {
                    Some(o) => pattern.push(Some(o)),
                    None => known = false,
                },
                Term::Var(_) => pattern.push(None),
                Term::Func(_) => known = false,
            }
        }
        if !known {
            continue;
        }
        let ok = if idx.is_task(name) {
            idx.calls_matching(name, &pattern).iter().any(|&c| done[c as usize])
        } else {
            let s = &g.schemas[idx.schema(name).unwrap_or_default() as usize];
            let matches = |args: &[ObjId]| {
                args.len() == pattern.len()
                    && args.iter().zip(&pattern).all(|(a, p)| p.is_none_or(|p| p == *a))
            };
            s.unsupported
                || (s.start as usize..s.end as usize)
                    .any(|i| reach.operator(i) && matches(g.args(&g.operators[i])))
        };
        if ok {
            continue;
        }
        let shown = show_call(name, &sub.call.args);
        let instances: Vec<u32> = if idx.is_task(name) {
            idx.calls_matching(name, &pattern).iter().flat_map(|&c| idx.refiners(c).iter().copied()).collect()
        } else {
            Vec::new()
        };
        let why = why_not(db, idx, &done, name, &pattern, &instances);
        let mut lint = Lint::new(
            codes::UNREACHABLE_GOAL,
            Loc { item, span: sub.call.span },
            format!("the `:htn` task `{shown}` cannot be refined {with}, even ignoring deletions: {why}"),
        );
        if let Some(&(op_item, span, _)) = d.ops.get(name) {
            lint = lint.related(Loc { item: op_item, span }, format!("`{name}` is declared here"));
        }
        let method = match instances.iter().min() {
            Some(&k) => Some(idx.method_of(k)),
            None => d.methods.get(name).and_then(|ms| ms.first()).map(|m| m.0),
        };
        if let Some(m) = method
            && let Some(schema) = method_schema(db, m)
        {
            lint = lint.related(Loc { item: m, span: schema.name_span }, format!("method `{}`", schema.name));
        }
        out.push(lint);
    }
}

/// A call as written, with lower-case names: `(patrol ?r w1)`.
fn show_call(name: &str, args: &[Term]) -> String {
    let mut s = format!("({name}");
    for t in args {
        s.push(' ');
        match t {
            Term::Var(n) | Term::Const(n) => s.push_str(n.key()),
            Term::Func(f) => s.push_str(&format!("({} …)", f.func.key())),
        }
    }
    s.push(')');
    s
}

/// Why a `:htn` task (or action) matching `pattern` cannot be achieved;
/// `instances` are the method instances that refine it.
fn why_not(
    db: &dyn Db,
    idx: &Index<'_, '_>,
    done: &[bool],
    name: &str,
    pattern: &[Option<ObjId>],
    instances: &[u32],
) -> String {
    let ground = pattern.iter().all(Option::is_some);
    if !idx.is_task(name) {
        let any = if ground {
            let args: Vec<ObjId> = pattern.iter().flatten().copied().collect();
            idx.operator(name, &args).is_some()
        } else {
            idx.schema(name).is_some_and(|s| {
                let s = &idx.g.schemas[s as usize];
                s.end > s.start
            })
        };
        return if any {
            "its preconditions cannot be reached with the usable actions".to_string()
        } else {
            "the action is never applicable for these arguments, even ignoring deletions".to_string()
        };
    }
    let Some(&first) = instances.iter().min() else {
        let these = if ground { "these arguments" } else { "any arguments that match" };
        return format!(
            "no method of `{name}` has an instance for {these} (types, static preconditions or \
             preconditions out of reach rule them out)"
        );
    };
    let method = method_schema(db, idx.method_of(first)).as_ref().map_or("?".into(), |s| s.name.clone());
    // The first step of that instance that cannot be achieved, and why.
    let failing = idx.steps(first).iter().copied().find(|&c| !done[c as usize]);
    let Some(c) = failing else {
        return format!("no instance of `{name}` is refined into achievable steps");
    };
    let reason = if idx.is_task_call(c) {
        "cannot be refined either"
    } else if idx.call_operator(c).is_none() {
        "is never applicable, even ignoring deletions"
    } else {
        "needs preconditions that the usable actions cannot reach"
    };
    let needs = format!("`{}`, which {reason}", idx.show_call(c));
    match instances.len() {
        1 => format!("its only method instance, of `{method}`, needs {needs}"),
        k => format!(
            "each of its {k} method instances needs a step that cannot be achieved; the first, of \
             `{method}`, needs {needs}"
        ),
    }
}

/// The atoms a goal requires to be true (under `and` and timing only).
fn positive_atoms<'a>(gd: &'a crate::model::Gd, out: &mut Vec<&'a crate::model::Atom>) {
    use crate::model::Gd;
    match gd {
        Gd::Atom(a) => out.push(a),
        Gd::And(gs, _) => gs.iter().for_each(|g| positive_atoms(g, out)),
        Gd::Timed(_, g, _) => positive_atoms(g, out),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use crate::AnalysisHost;

    /// The E0313 diagnostics of a domain and a problem checked together, as
    /// `CODE message`.
    fn check(domain: &str, problem: &str) -> Vec<String> {
        let mut host = AnalysisHost::new();
        let d = host.set_file_text("m/domain.hddl", domain);
        let p = host.set_file_text("m/problem.hddl", problem);
        let analysis = host.analysis();
        [p, d]
            .iter()
            .flat_map(|&f| analysis.diagnostics(f).expect("not cancelled"))
            .filter(|d| d.code.id == "E0313")
            .map(|d| format!("{} {}", d.code.id, d.message))
            .collect()
    }

    const DOMAIN: &str = "(define (domain d) (:requirements :typing :hierarchy :negative-preconditions)
      (:types robot place)
      (:predicates (at ?r - robot ?p - place) (road ?a ?b - place) (seen ?p - place) (charged ?r - robot))
      (:task visit :parameters (?r - robot ?p - place))
      (:task loop :parameters (?r - robot))
      (:action move :parameters (?r - robot ?a ?b - place) :precondition (and (at ?r ?a) (road ?a ?b))
        :effect (and (not (at ?r ?a)) (at ?r ?b)))
      (:action look :parameters (?r - robot ?p - place) :precondition (at ?r ?p) :effect (seen ?p))
      (:action charge :parameters (?r - robot) :effect (charged ?r))
      (:method m-visit :parameters (?r - robot ?a ?p - place) :task (visit ?r ?p)
        :subtasks (and (t1 (move ?r ?a ?p)) (t2 (look ?r ?p))) :ordering (< t1 t2))
      (:method m-loop :parameters (?r - robot) :task (loop ?r) :subtasks (loop ?r))
      @BASE@)";

    fn domain(base_case: bool) -> String {
        let base = if base_case {
            "(:method m-done :parameters (?r - robot) :task (loop ?r) :subtasks ())"
        } else {
            ""
        };
        DOMAIN.replace("@BASE@", base)
    }

    fn problem(htn: &str, goal: &str) -> String {
        format!(
            "(define (problem p) (:domain d) (:objects r - robot a b c - place)
              (:htn :parameters (?x - place) :subtasks (and {htn}))
              (:init (at r a) (road a b))
              {goal})"
        )
    }

    #[test]
    fn a_task_whose_only_method_calls_itself_cannot_be_refined() {
        let got = check(&domain(false), &problem("(loop r)", ""));
        assert_eq!(got.len(), 1, "{got:?}");
        assert!(got[0].starts_with("E0313 the `:htn` task `(loop r)` cannot be refined"), "{got:?}");
        assert!(got[0].contains("`(loop r)`, which cannot be refined either"), "{got:?}");
        // A base case makes the recursion terminate.
        assert_eq!(check(&domain(true), &problem("(loop r)", "")), Vec::<String>::new());
    }

    #[test]
    fn a_task_refined_into_unreachable_steps() {
        // `b` is reachable, `c` is not: no road leads there.
        assert_eq!(check(&domain(true), &problem("(visit r b)", "")), Vec::<String>::new());
        let got = check(&domain(true), &problem("(visit r c)", ""));
        assert_eq!(got.len(), 1, "{got:?}");
        assert!(
            got[0].starts_with(
                "E0313 the `:htn` task `(visit r c)` cannot be refined with the domain's methods, even \
                 ignoring deletions: "
            ),
            "{got:?}"
        );
    }

    #[test]
    fn htn_variables_need_one_achievable_instance() {
        // `?x` can be `b`: fine. With no road at all, no instance of `visit r ?x` works.
        assert_eq!(check(&domain(true), &problem("(visit r ?x)", "")), Vec::<String>::new());
        let no_road = problem("(visit r ?x)", "").replace("(road a b)", "");
        let got = check(&domain(true), &no_road);
        assert_eq!(got.len(), 1, "{got:?}");
        assert!(got[0].starts_with("E0313 the `:htn` task `(visit r ?x)` cannot be refined"), "{got:?}");
    }

    #[test]
    fn pure_htn_goals_use_the_actions_of_the_methods_only() {
        // `look` is in a method of `visit`: `(seen b)` is reachable.
        let p = problem("(visit r b)", "(:goal (seen b))");
        assert_eq!(check(&domain(true), &p), Vec::<String>::new());
        // `charge` is in no method: with a pure HTN problem, nothing inserts it.
        let got = check(&domain(true), &problem("(visit r b)", "(:goal (charged r))"));
        assert_eq!(
            got,
            ["E0313 the goal `(charged r)` cannot be achieved by refining the `:htn` tasks, even ignoring \
                 deletions: `charge` could add it but no method of the `:htn` tasks (or of the tasks they use) \
                 uses it"]
        );
        // With `charge` allowed, it can.
        let allowed = problem("(visit r b)", "(:goal (charged r)) (:allowed-actions charge)");
        assert!(!check(&domain(true), &allowed).iter().any(|d| d.starts_with("E0313")));
        // Out of reach of every action (no road to `c`): not the hierarchy's doing, not reported.
        assert_eq!(check(&domain(true), &problem("(visit r b)", "(:goal (seen c))")), Vec::<String>::new());
    }

    #[test]
    fn problems_without_htn_or_allowed_actions_are_not_checked() {
        let p = "(define (problem p) (:domain d) (:objects r - robot a b c - place)
          (:init (at r a)) (:goal (seen c)))";
        assert_eq!(check(&domain(true), p), Vec::<String>::new());
    }
}
