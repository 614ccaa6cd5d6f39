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
}
