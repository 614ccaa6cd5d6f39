//! Allowed-action lints (section 4.2.2 of the HiPOP paper): the set 𝒜 of
//! `(:allowed-actions …)` is what the planner may insert to close an open link;
//! everything else enters a plan only through the methods of the tasks it
//! refines.
//!
//! These lints read names and methods only; they run for problems that declare
//! `(:allowed-actions …)`. Without it every action is allowed (or, with an
//! `:htn`, none: pure HTN planning), and an action a given problem does not
//! need is not a mistake of the model.

use rustc_hash::{FxHashMap, FxHashSet};

use crate::db::{Db, Item, Section, Unit};
use crate::diagnostic::codes;
use crate::model::{ItemData, Name, Str};
use crate::semantics::symbols::Loc;

use super::Lint;
use super::lifted::{OperatorKind, method_schema, operator};

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
}

fn domain<'db>(db: &'db dyn Db, unit: Unit<'db>) -> Domain<'db> {
    let mut d = Domain { ops: FxHashMap::default(), methods: FxHashMap::default(), order: Vec::new() };
    for &item in unit.items(db) {
        if let Some(op) = operator(db, item) {
            if d.ops.insert(op.name.clone(), (item, op.name_span, op.kind)).is_none() {
                d.order.push(op.name.clone());
            }
        } else if let Some(m) = method_schema(db, item)
            && let Some((task, _, _)) = &m.task
        {
            let subtasks = m.subtasks.iter().map(|s| (s.name.clone(), s.span)).collect();
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
    let keyword = match item.syntax(db) {
        crate::db::ItemSyntax::List(g) => crate::syntax::GList::root(&g.0, 0.into()).and_then(|l| l.head()),
        crate::db::ItemSyntax::Chunk { .. } => None,
    };
    let keyword = keyword.map_or(rowan::TextRange::at(0.into(), 1.into()), |h| h.range());
    Some((item, keyword, names.clone()))
}

/// The task names of the problem's `:htn`.
fn htn_tasks(db: &dyn Db, problem: Unit<'_>) -> Vec<Str> {
    let mut out = Vec::new();
    for &item in problem.items(db) {
        if item.section(db) == Section::Htn
            && let ItemData::Htn(h) = &crate::db::lower_item(db, item).data
        {
            out.extend(h.network.subtasks.iter().map(|s| s.call.name.key.clone()));
        }
    }
    out
}

/// Dead actions and tasks (W0311) and allowed actions the planner could also
/// insert through an allowed task's method (W0312). `is_family_move` tells the
/// move actions of confirmed position families, which the paper allows on
/// purpose (a robot must reach the start of its next patrol).
pub(super) fn lints<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    domain_unit: Unit<'db>,
    is_family_move: &dyn Fn(&str) -> bool,
    out: &mut Vec<Lint<'db>>,
) {
    let Some((allowed_item, keyword, allowed)) = allowed_actions(db, problem) else { return };
    let d = domain(db, domain_unit);
    let allowed_keys: FxHashSet<&str> = allowed.iter().map(|n| &*n.key).collect();

    // Tasks reachable from the allowed tasks, then from the `:htn`, through
    // methods; the first method subtask that uses each action or task.
    let mut used: FxHashMap<Str, Loc<'db>> = FxHashMap::default();
    let mut from_allowed: FxHashMap<Str, Loc<'db>> = FxHashMap::default();
    let is_task = |n: &str| d.ops.get(n).is_some_and(|o| o.2 == OperatorKind::Task);
    let allowed_tasks: Vec<Str> = allowed.iter().map(|n| n.key.clone()).filter(|n| is_task(n)).collect();
    let htn = htn_tasks(db, problem);
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

    for name in &d.order {
        let (item, span, kind) = d.ops[name];
        if allowed_keys.contains(&**name) || used.contains_key(name) || htn.contains(name) {
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

    for n in &allowed {
        let Some(&(_, _, kind)) = d.ops.get(&n.key) else { continue };
        if kind == OperatorKind::Task || is_family_move(&n.key) {
            continue;
        }
        if let Some(&loc) = from_allowed.get(&n.key) {
            out.push(
                Lint::new(
                    codes::DOUBLE_INSERTION,
                    Loc { item: allowed_item, span: n.span },
                    format!(
                        "`{}` is allowed and is also a subtask of a method of an allowed task: the planner can \
                         build the same plan both ways",
                        n.text
                    ),
                )
                .related(loc, "a method of an allowed task uses it here"),
            );
        }
    }

    let usable: FxHashSet<&str> = allowed_keys.iter().copied().chain(used.keys().map(|k| &**k)).collect();
    unreachable_goals(db, problem, &d, &usable, out);
}

/// E0313: goal atoms that relaxed reachability from the initial state cannot
/// reach with the usable operators (the allowed ones and those the methods of
/// allowed tasks and of `:htn` use), naming the producers that are not usable.
fn unreachable_goals<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    d: &Domain<'db>,
    usable: &FxHashSet<&str>,
    out: &mut Vec<Lint<'db>>,
) {
    let g = super::ground::ground(db, problem);
    if g.truncated {
        // Instances are missing: an atom out of reach may only be out of the limit.
        return;
    }
    let schema_usable: Vec<bool> = g.schemas.iter().map(|s| usable.contains(&*s.name)).collect();
    let reach = super::reach::reachable(g, |op| schema_usable[op.schema as usize]);
    for &item in problem.items(db) {
        if item.section(db) != Section::Goal {
            continue;
        }
        let ItemData::Goal(goal) = &crate::db::lower_item(db, item).data else { continue };
        let mut atoms = Vec::new();
        positive_atoms(goal, &mut atoms);
        for atom in atoms {
            let Some(pred) = g.predicates.get(&atom.pred.key) else { continue };
            if g.untracked_preds.get(pred as usize).copied().unwrap_or(true) {
                continue;
            }
            let args: Option<Vec<u32>> = atom
                .args
                .iter()
                .map(|t| match t {
                    crate::model::Term::Const(n) => g.objects.id(&n.key),
                    _ => None,
                })
                .collect();
            let Some(args) = args else { continue };
            let id = g.atoms.find(pred, &args);
            if id.is_some_and(|a| reach.atom(a)) {
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
            let why = match producers.as_slice() {
                [] => "no action or task can add it from the initial state".to_string(),
                names => format!(
                    "{} could add it but {} not allowed, and no method of an allowed task uses {}",
                    names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", "),
                    if names.len() == 1 { "is" } else { "are" },
                    if names.len() == 1 { "it" } else { "them" },
                ),
            };
            let mut lint = Lint::new(
                codes::UNREACHABLE_GOAL,
                Loc { item, span: atom.span },
                format!(
                    "the goal `{}` cannot be achieved with the allowed actions and their methods, even \
                     ignoring deletions: {why}",
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
