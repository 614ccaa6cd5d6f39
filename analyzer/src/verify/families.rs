//! Position families and move actions (section 4.3 of the HiPOP paper,
//! Definitions 12 and 14), confirmed on a problem's ground model.
//!
//! A candidate family is lifted (`at-r ?r *`, see [`geometry::candidates`]);
//! an instance of it is the set of atoms `(at-r r1 *)` of one key `r1`. A
//! candidate is a family when, for every instance:
//!
//! 1. exactly one of its atoms holds initially;
//! 2. every ground operator that deletes one of its atoms requires it and adds
//!    another atom of the same instance;
//! 3. every ground operator that adds one of its atoms requires and deletes
//!    another one.
//!
//! Durative operators are read as the paper's definitions read them (Pre, Add
//! and Del over both ends), so a move that deletes at start and adds at end is
//! a move; an operator that deletes and adds the same atom leaves the position
//! unchanged and is not held against the family.
//!
//! For a family, the move actions (Definition 14) are the ground operators
//! whose only non-static precondition is the from-position, whose only
//! deletion is the from-position and whose only addition is the to-position.
//! Properties 4 (a move between every two positions), 5 (no operator changes
//! position faster than the move) and 6 (the triangle inequality of move
//! durations) are then checked.

use rustc_hash::FxHashMap;

use crate::db::{Db, Item, Unit};
use crate::diagnostic::codes;
use crate::model::{NumExpr, Str, Term};
use crate::semantics::symbols::Loc;

use super::Lint;
use super::geometry::{self, Candidate};
use super::ground::{Ground, GroundOperator, ground};
use super::lifted::{Duration, operator};
use super::state::{AtomId, ObjId, PredId};

/// A confirmed position family.
#[derive(Debug, Clone, PartialEq, salsa::SalsaValue)]
pub struct Family<'db> {
    pub candidate: Candidate,
    pub pred: PredId,
    /// The predicate's declaration.
    pub decl: Option<Loc<'db>>,
    /// The number of instances (keys: robots).
    pub instances: usize,
    /// The move actions, by schema item, and how many ground moves each has.
    pub moves: Vec<(Item<'db>, usize)>,
}

/// Why a candidate is not a family: the property that fails and a witness.
#[derive(Debug, Clone, PartialEq, salsa::SalsaValue)]
pub struct Rejected<'db> {
    pub candidate: Candidate,
    pub decl: Option<Loc<'db>>,
    /// 1, 2 or 3 (Definition 12).
    pub property: u8,
    pub why: String,
    /// Where the witness is: an `:init` fact, an object, an action.
    pub witness: Option<(Loc<'db>, String)>,
    /// Some ground operator moves along the candidate as a move action does
    /// (Definition 14): whoever wrote it likely meant a position family.
    pub has_move: bool,
}

/// What the families of a problem are.
#[derive(Debug, Clone, PartialEq, Default, salsa::SalsaValue)]
pub struct Families<'db> {
    pub confirmed: Vec<Family<'db>>,
    pub rejected: Vec<Rejected<'db>>,
    /// Lints of properties 4–6 for the confirmed families.
    pub lints: Vec<Lint<'db>>,
    /// The problem's `:init` keyword: where what concerns the problem as a
    /// whole is reported, so that a domain with many problems is not flooded.
    pub init: Option<Loc<'db>>,
    /// The domain or the problem uses the HiPOP extensions (abstract actions,
    /// `:agent`, `:allowed-actions`): it is written for HiPOP's planner, whose
    /// position reasoning the notes about families explain.
    pub hipop: bool,
}

impl Families<'_> {
    /// Whether an action is a move action of a confirmed family.
    pub fn is_move(&self, name: &str, db: &dyn Db) -> bool {
        self.confirmed.iter().any(|f| {
            f.moves
                .iter()
                .any(|(item, _)| item.name(db).as_deref().is_some_and(|n| n.eq_ignore_ascii_case(name)))
        })
    }
}

/// How many triangle-inequality violations of one family are reported one by
/// one; the others are related locations of one summary diagnostic.
const DETOURS_SHOWN: usize = 20;

/// The position families of a problem, with the lints of their move actions.
#[salsa::tracked(returns(ref))]
pub fn families<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Families<'db> {
    families_over(db, problem, ground(db, problem), false)
}

/// The position families over the planner's grounding
/// ([`super::ground::ground_relevant`]): confirmed on the operators the
/// planner has, with the same predicate ids; with the families of one key
/// type (`at ?truck *`) of the candidates that are not families, which the
/// planner uses when its configuration says `types`.
#[salsa::tracked(returns(ref))]
pub fn planner_families<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Families<'db> {
    families_over(db, problem, super::ground::ground_relevant(db, problem), true)
}

/// The position families over [`super::ground::ground_planner`] (a repair's).
#[salsa::tracked(returns(ref))]
pub fn reachable_planner_families<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Families<'db> {
    families_over(db, problem, super::ground::ground_planner(db, problem), true)
}

/// The families over `g`; with `typed`, also the families of one key type
/// of the candidates that are not families ([`key_types`]).
fn families_over<'db>(db: &'db dyn Db, problem: Unit<'db>, g: &Ground<'db>, typed: bool) -> Families<'db> {
    let mut out = Families::default();
    let Some(domain) = crate::semantics::check::domain_for(db, problem) else { return out };
    if g.truncated {
        // An incomplete set of ground operators cannot confirm anything.
        return out;
    }
    let operators: Vec<_> = domain.items(db).iter().filter_map(|&i| operator(db, i).as_ref()).collect();
    let symbols = crate::semantics::symbols::domain_symbols(db, domain);
    let tolerance = crate::db::triangle_tolerance(db);
    out.init = g.init.keyword_loc(db);
    out.hipop = uses_hipop_extensions(db, domain, problem);
    for candidate in geometry::candidates(operators.iter().copied()) {
        let Some(pred) = g.predicates.get(&candidate.pred) else { continue };
        let decl = symbols.predicates.get(&candidate.pred).map(|s| s.loc);
        match check(db, g, symbols, &candidate, pred, decl) {
            Ok(family) => {
                // A family without any move action says nothing about an
                // ordinary domain (I0308 on every pair): only for HiPOP.
                if out.hipop || !family.moves.is_empty() {
                    moves(db, g, &family, tolerance, out.init, &mut out.lints);
                }
                out.confirmed.push(family);
            }
            Err(mut rejected) => {
                rejected.has_move = g.operators.iter().any(|op| move_of(g, op, pred, &candidate).is_some());
                out.rejected.push(*rejected);
                // The same predicate for the keys of one type: the `at` of
                // trucks is a family when that of drivers is not.
                let mut split: Vec<Str> = Vec::new();
                let split_by_type = if typed { key_types(g, symbols, &candidate, pred) } else { Vec::new() };
                for typed in split_by_type {
                    let t = typed.key_type.clone().expect("a key type");
                    // A subtype of a type confirmed already: its keys are in that family.
                    let within = |done: &Str| symbols.ancestors.get(&t).is_some_and(|a| a.contains(done));
                    if split.iter().any(within) {
                        continue;
                    }
                    // Keys that nothing moves (Depots' pallets) are no family worth naming.
                    let moved =
                        g.operators.iter().any(|op| g.add(op).iter().any(|&a| is_member(g, a, pred, &typed)));
                    if !moved {
                        continue;
                    }
                    if let Ok(family) = check(db, g, symbols, &typed, pred, decl) {
                        split.push(t);
                        if out.hipop || !family.moves.is_empty() {
                            moves(db, g, &family, tolerance, out.init, &mut out.lints);
                        }
                        out.confirmed.push(family);
                    }
                }
            }
        }
    }
    out
}

/// The candidates of one key type each that a rejected candidate of two
/// arguments splits into: one per type that some of its keys have and not
/// all of them (the whole was rejected), the types with the most keys
/// first (a supertype before its subtypes).
fn key_types(
    g: &Ground<'_>,
    symbols: &crate::semantics::symbols::DomainSymbols<'_>,
    c: &Candidate,
    pred: PredId,
) -> Vec<Candidate> {
    if c.arity != 2 || c.key_type.is_some() {
        return Vec::new();
    }
    let key_param = if c.pos == 0 { 1 } else { 0 };
    let mut keys: Vec<ObjId> = symbols
        .predicates
        .get(&c.pred)
        .and_then(|sig| sig.params.get(key_param))
        .map(|types| g.objects.of_types(types))
        .unwrap_or_default();
    for atom in 0..g.atoms.len() as AtomId {
        if g.atoms.pred(atom) == pred && g.atoms.args(atom).len() == 2 {
            keys.push(g.atoms.args(atom)[key_param]);
        }
    }
    keys.sort_unstable();
    keys.dedup();
    let mut types: FxHashMap<&str, usize> = FxHashMap::default();
    for &k in &keys {
        for t in g.objects.types(k) {
            *types.entry(t.as_str()).or_default() += 1;
        }
    }
    let mut types: Vec<(&str, usize)> = types.into_iter().filter(|&(_, n)| n < keys.len()).collect();
    types.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    types.into_iter().map(|(t, _)| Candidate { key_type: Some(t.into()), ..c.clone() }).collect()
}

/// Whether a domain or its problem uses the HiPOP extensions (HiPOP paper,
/// section 4.2): abstract actions (tasks with their own `:duration`,
/// `:precondition`, `:effect` or `:conflicts`), `:agent`, `:allowed-actions`.
fn uses_hipop_extensions(db: &dyn Db, domain: Unit<'_>, problem: Unit<'_>) -> bool {
    use crate::model::ItemData;
    let in_domain = domain.items(db).iter().any(|&i| match &crate::db::lower_item(db, i).data {
        ItemData::Task(t) => {
            t.duration.is_some()
                || t.precondition.is_some()
                || t.effect.is_some()
                || t.conflicts.is_some()
                || !t.agent.is_empty()
        }
        ItemData::Action(a) => !a.agent.is_empty(),
        _ => false,
    });
    in_domain || problem.items(db).iter().any(|&i| i.section(db) == crate::db::Section::AllowedActions)
}

/// The key of a family atom (its arguments but the position) and its position.
fn split(g: &Ground<'_>, atom: AtomId, c: &Candidate) -> (Vec<ObjId>, ObjId) {
    let args = g.atoms.args(atom);
    let mut key = args.to_vec();
    let pos = key.remove(c.pos as usize);
    (key, pos)
}

/// Whether an atom is one of the candidate's: its predicate and arity, and
/// for a candidate of one key type, a key of that type.
pub fn is_member(g: &Ground<'_>, atom: AtomId, pred: PredId, c: &Candidate) -> bool {
    g.atoms.pred(atom) == pred
        && g.atoms.args(atom).len() == c.arity as usize
        && c.key_type.as_ref().is_none_or(|t| {
            let key = g.atoms.args(atom)[if c.pos == 0 { 1 } else { 0 }];
            g.objects.has_type(key, t)
        })
}

fn check<'db>(
    db: &'db dyn Db,
    g: &Ground<'db>,
    symbols: &crate::semantics::symbols::DomainSymbols<'db>,
    c: &Candidate,
    pred: PredId,
    decl: Option<Loc<'db>>,
) -> Result<Family<'db>, Box<Rejected<'db>>> {
    let family = format!("{}", Pattern(c));
    let reject = |property: u8, why: String, witness: Option<(Loc<'db>, String)>| {
        Box::new(Rejected { candidate: c.clone(), decl, property, why, witness, has_move: false })
    };
    // Property 1, over every key some atom of the family mentions, and every
    // object of the key's type when the key is one object.
    let mut initial: FxHashMap<Vec<ObjId>, Vec<(AtomId, Loc<'db>)>> = FxHashMap::default();
    for atom in 0..g.atoms.len() as AtomId {
        if is_member(g, atom, pred, c) {
            initial.entry(split(g, atom, c).0).or_default();
        }
    }
    if c.arity == 2 {
        let key_param = if c.pos == 0 { 1 } else { 0 };
        if let Some(types) = symbols.predicates.get(&c.pred).and_then(|sig| sig.params.get(key_param)) {
            for o in g.objects.of_types(types) {
                if c.key_type.as_ref().is_none_or(|t| g.objects.has_type(o, t)) {
                    initial.entry(vec![o]).or_default();
                }
            }
        }
    }
    for &(atom, loc) in &g.init.facts {
        if is_member(g, atom, pred, c) {
            initial.entry(split(g, atom, c).0).or_default().push((atom, loc));
        }
    }
    let mut keys: Vec<_> = initial.iter().collect();
    keys.sort_by(|a, b| a.0.cmp(b.0));
    for (key, facts) in &keys {
        // Whose position: the key's objects; a family of one argument
        // (`at-robby *`) has no key: the position is the initial state's.
        let who = key.iter().map(|&o| g.objects.name(o)).collect::<Vec<_>>().join(" ");
        match facts.as_slice() {
            [_] => {}
            [] => {
                let witness = key
                    .first()
                    .and_then(|&o| g.objects.loc(o))
                    .map(|l| (l, format!("`{who}` is declared here")));
                let why = if key.is_empty() {
                    "the initial state has no position".to_string()
                } else {
                    format!("`{who}` has no position in the initial state")
                };
                return Err(reject(1, why, witness));
            }
            [(a, _), (b, loc), ..] => {
                let n = facts.len();
                let positions = if key.is_empty() {
                    format!("the initial state has {n} positions")
                } else {
                    format!("`{who}` has {n} positions in the initial state")
                };
                let why = format!("{positions}: `{}` and `{}`", g.show_atom(*a), g.show_atom(*b));
                return Err(reject(1, why, Some((*loc, "a second position".to_string()))));
            }
        }
    }
    if let Some(t) = g.init.timed.iter().find(|t| is_member(g, t.atom, pred, c)) {
        let why = format!("a timed initial literal changes `{}` without an action", g.show_atom(t.atom));
        return Err(reject(1, why, Some((t.loc, "here".to_string()))));
    }
    // Properties 2 and 3, over the reachable ground operators.
    for schema in &g.schemas {
        if schema.wild_add.contains(&pred) {
            let why = format!("`{}` may add atoms of `{family}` that hipop cannot name", schema.name);
            return Err(reject(3, why, name_loc(db, schema.item)));
        }
    }
    // An instance whose duration is undefined is never applied (PDDL 2.1).
    for op in g.operators.iter().filter(|op| !op.no_duration) {
        let members = |atoms: &[AtomId]| -> Vec<AtomId> {
            atoms.iter().copied().filter(|&a| is_member(g, a, pred, c)).collect()
        };
        let (adds, dels) = (members(g.add(op)), members(g.del(op)));
        if (!adds.is_empty() || !dels.is_empty()) && op.unsupported {
            let why = format!(
                "the effects of `{}` are not all known (conditional or quantified effects)",
                g.show_operator(op)
            );
            return Err(reject(2, why, name_loc(db, op.op)));
        }
        for &f in dels.iter().filter(|f| !adds.contains(f)) {
            let key = split(g, f, c).0;
            let replaced = adds.iter().any(|&a| a != f && split(g, a, c).0 == key);
            if !g.pre(op).contains(&f) || !replaced {
                let why = if g.pre(op).contains(&f) {
                    format!(
                        "`{}` deletes `{}` without adding another position",
                        g.show_operator(op),
                        g.show_atom(f)
                    )
                } else {
                    format!("`{}` deletes `{}` without requiring it", g.show_operator(op), g.show_atom(f))
                };
                return Err(reject(2, why, name_loc(db, op.op)));
            }
        }
        for &a in adds.iter().filter(|a| !dels.contains(a)) {
            let key = split(g, a, c).0;
            let moved_from =
                dels.iter().any(|&f| f != a && split(g, f, c).0 == key && g.pre(op).contains(&f));
            if !moved_from {
                let why = format!(
                    "`{}` adds `{}` without requiring and deleting the previous position",
                    g.show_operator(op),
                    g.show_atom(a)
                );
                return Err(reject(3, why, name_loc(db, op.op)));
            }
        }
    }
    // The move actions (Definition 14).
    let mut moves: Vec<(Item<'db>, usize)> = Vec::new();
    for op in &g.operators {
        if move_of(g, op, pred, c).is_some() {
            match moves.iter_mut().find(|(i, _)| *i == op.op) {
                Some((_, n)) => *n += 1,
                None => moves.push((op.op, 1)),
            }
        }
    }
    Ok(Family { candidate: c.clone(), pred, decl, instances: keys.len(), moves })
}

/// `(from, to)` when the operator is a move action of the family.
fn move_of(g: &Ground<'_>, op: &GroundOperator<'_>, pred: PredId, c: &Candidate) -> Option<(AtomId, AtomId)> {
    match (g.pre(op), g.del(op), g.add(op)) {
        (&[p], &[f], &[t])
            if p == f
                && f != t
                && g.neg_pre(op).is_empty()
                && !op.unsupported
                && !op.no_duration
                && is_member(g, f, pred, c)
                && is_member(g, t, pred, c)
                && split(g, f, c).0 == split(g, t, c).0 =>
        {
            Some((f, t))
        }
        _ => None,
    }
}

/// Properties 4, 5 and 6 of Definition 14 for a confirmed family.
fn moves<'db>(
    db: &'db dyn Db,
    g: &Ground<'db>,
    f: &Family<'db>,
    tolerance: f64,
    init: Option<Loc<'db>>,
    out: &mut Vec<Lint<'db>>,
) {
    let c = &f.candidate;
    let pattern = Pattern(c).to_string();
    let Some(decl) = f.decl else { return };
    let here = init.unwrap_or(decl);
    // Per instance: its positions, and the fastest move between two of them.
    struct Instance {
        positions: Vec<ObjId>,
        moves: FxHashMap<(ObjId, ObjId), (f64, usize)>,
    }
    let mut instances: FxHashMap<Vec<ObjId>, Instance> = FxHashMap::default();
    for atom in 0..g.atoms.len() as AtomId {
        if is_member(g, atom, f.pred, c) {
            let (key, pos) = split(g, atom, c);
            instances
                .entry(key)
                .or_insert_with(|| Instance { positions: Vec::new(), moves: FxHashMap::default() })
                .positions
                .push(pos);
        }
    }
    for (index, op) in g.operators.iter().enumerate() {
        let (Some((from, to)), Some(d)) = (move_of(g, op, f.pred, c), op.duration()) else { continue };
        let (key, a) = split(g, from, c);
        let b = split(g, to, c).1;
        if let Some(inst) = instances.get_mut(&key) {
            let e = inst.moves.entry((a, b)).or_insert((d, index));
            if d < e.0 {
                *e = (d, index);
            }
        }
    }
    for inst in instances.values_mut() {
        inst.positions.sort_unstable();
        inst.positions.dedup();
    }
    let mut keys: Vec<Vec<ObjId>> = instances.keys().cloned().collect();
    keys.sort();
    let who = |key: &[ObjId]| key.iter().map(|&o| g.objects.name(o)).collect::<Vec<_>>().join(" ");

    // Property 4: pairs of positions without a move action. Counted from the
    // moves (a robot may have thousands of positions); the examples are the
    // first missing pairs found.
    let (mut pairs, mut missing, mut examples) = (0usize, 0usize, Vec::new());
    for key in &keys {
        let inst = &instances[key];
        let positions = &inst.positions;
        let n = positions.len();
        let here = inst.moves.keys().filter(|(a, b)| a != b).count();
        pairs += n * n.saturating_sub(1);
        missing += n * n.saturating_sub(1) - here.min(n * n.saturating_sub(1));
        'examples: for &a in positions {
            for &b in positions.iter().filter(|&&b| b != a) {
                if examples.len() == 3 {
                    break 'examples;
                }
                if !inst.moves.contains_key(&(a, b)) {
                    let k = who(key);
                    let k = if k.is_empty() { String::new() } else { format!("{k}: ") };
                    examples.push(format!("{k}{} → {}", g.objects.name(a), g.objects.name(b)));
                }
            }
        }
    }
    if missing > 0 {
        let lint = Lint::new(
            codes::MISSING_MOVE,
            here,
            format!(
                "position family `{pattern}`: {missing} of {pairs} ordered pairs of positions have no move action \
                 (e.g. {}); the planner plans those trips with several moves",
                examples.join(", ")
            ),
        );
        out.push(if here == decl {
            lint
        } else {
            lint.related(decl, format!("the predicate of `{pattern}`"))
        });
    }

    // Property 5: an operator that changes position faster than the move.
    let mut reported: Vec<Item<'db>> = Vec::new();
    for op in &g.operators {
        let Some(d) = op.duration() else { continue };
        if reported.contains(&op.op) || move_of(g, op, f.pred, c).is_some() {
            continue;
        }
        let found = g.pre(op).iter().filter(|&&a| is_member(g, a, f.pred, c)).find_map(|&from| {
            let (key, a) = split(g, from, c);
            g.add(op).iter().filter(|&&t| t != from && is_member(g, t, f.pred, c)).find_map(|&to| {
                let (k2, b) = split(g, to, c);
                let (m, index) = *instances.get(&key)?.moves.get(&(a, b))?;
                (k2 == key && d + tolerance < m).then_some((from, to, m, index))
            })
        });
        if let Some((from, to, m, index)) = found {
            reported.push(op.op);
            let mv = &g.operators[index];
            let mut lint = Lint::new(
                codes::FASTER_THAN_MOVE,
                name_loc(db, op.op).map_or(decl, |l| l.0),
                format!(
                    "`{}` goes from `{}` to `{}` in {d}, faster than the move action `{}` ({m}): move \
                     durations are no longer lower bounds (Definition 14, property 5)",
                    g.show_operator(op),
                    g.show_atom(from),
                    g.show_atom(to),
                    g.show_operator(mv)
                ),
            );
            if let Some((loc, _)) = name_loc(db, mv.op) {
                lint = lint.related(loc, "the move action");
            }
            out.push(lint);
        }
    }

    // Property 6: the triangle inequality, per instance; instances with the
    // same positions and durations (robots of one type) are checked once.
    let mut detours: Vec<Lint<'db>> = Vec::new();
    let mut seen: rustc_hash::FxHashSet<u64> = rustc_hash::FxHashSet::default();
    for key in &keys {
        let inst = &instances[key];
        let positions = &inst.positions;
        let n = positions.len();
        let index: FxHashMap<ObjId, usize> = positions.iter().enumerate().map(|(i, &p)| (p, i)).collect();
        let mut dur = vec![f64::INFINITY; n * n];
        for i in 0..n {
            dur[i * n + i] = 0.0;
        }
        let mut moves: Vec<(usize, usize, u64)> = Vec::with_capacity(inst.moves.len());
        for (&(a, b), &(d, _)) in &inst.moves {
            if let (Some(&i), Some(&j)) = (index.get(&a), index.get(&b))
                && i != j
            {
                dur[i * n + j] = d;
                moves.push((i, j, d.to_bits()));
            }
        }
        // Instances with the same positions and move durations give the same
        // detours: robots of one type are checked once.
        moves.sort_unstable();
        let signature = {
            use std::hash::{Hash, Hasher};
            let mut h = rustc_hash::FxHasher::default();
            positions.hash(&mut h);
            moves.hash(&mut h);
            h.finish()
        };
        if !seen.insert(signature) {
            continue;
        }
        for d in geometry::detours(n, &dur, tolerance) {
            let name = |i: u32| g.objects.name(positions[i as usize]);
            let (_, index) = inst.moves[&(positions[d.from as usize], positions[d.to as usize])];
            let mv = &g.operators[index];
            // On the value that makes the direct move slow, when a fluent gives it.
            let loc = duration_fact(db, g, mv).or_else(|| name_loc(db, mv.op).map(|l| l.0)).unwrap_or(decl);
            let k = who(key);
            let k = if k.is_empty() { String::new() } else { format!("`{k}` ") };
            let mut lint = Lint::new(
                codes::TRIANGLE_INEQUALITY,
                loc,
                format!(
                    "moving {k}from `{}` to `{}` takes {}, but through `{}` it takes {} + {} = {}: a direct move \
                     must not be slower than two (triangle inequality, Definition 14)",
                    name(d.from),
                    name(d.to),
                    d.direct,
                    name(d.via),
                    d.first,
                    d.second,
                    d.first + d.second
                ),
            );
            if loc != decl {
                lint = lint.related(decl, format!("position family `{pattern}`"));
            }
            detours.push(lint);
        }
    }
    if detours.len() > DETOURS_SHOWN {
        let rest = detours.split_off(DETOURS_SHOWN);
        let mut summary = Lint::new(
            codes::TRIANGLE_INEQUALITY,
            here,
            format!(
                "position family `{pattern}`: {} more moves break the triangle inequality (all of them are \
                 related locations of this diagnostic)",
                rest.len()
            ),
        );
        for l in rest {
            summary = summary.related(l.loc, l.message);
        }
        detours.push(summary);
    }
    out.extend(detours);
}

/// The `:init` fact that sets the fluent a move's duration reads (the first
/// fluent of `(= ?duration …)`), if any.
fn duration_fact<'db>(db: &'db dyn Db, g: &Ground<'db>, op: &GroundOperator<'db>) -> Option<Loc<'db>> {
    let lifted = operator(db, op.op).as_ref()?;
    let Duration::Exact(expr) = &lifted.duration else { return None };
    let fluent = first_fluent(expr)?;
    let func = g.functions.get(fluent.func.key())?;
    let args: Option<Vec<ObjId>> = fluent
        .args
        .iter()
        .map(|t| match t {
            Term::Var(n) => {
                lifted.params.iter().position(|p| p.name == n.key()).and_then(|i| g.args(op).get(i).copied())
            }
            Term::Const(n) => g.objects.id(n.key()),
            Term::Func(_) => None,
        })
        .collect();
    g.init.fluent(func, &args?).map(|(_, loc)| loc)
}

fn first_fluent(e: &NumExpr) -> Option<&crate::model::Fluent> {
    match e {
        NumExpr::Fluent(f) => Some(f),
        NumExpr::Op(_, es, _) => es.iter().find_map(first_fluent),
        _ => None,
    }
}

fn name_loc<'db>(db: &'db dyn Db, item: Item<'db>) -> Option<(Loc<'db>, String)> {
    operator(db, item).as_ref().map(|o| (Loc { item, span: o.name_span }, format!("`{}`", o.name)))
}

/// `at-r ? *`: a candidate as the paper writes families.
struct Pattern<'a>(&'a Candidate);

impl std::fmt::Display for Pattern<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.0.pred)?;
        for i in 0..self.0.arity {
            f.write_str(if i == self.0.pos { " *" } else { " ?" })?;
            if i != self.0.pos
                && let Some(t) = &self.0.key_type
            {
                f.write_str(t)?;
            }
        }
        Ok(())
    }
}

/// I0307 for each candidate that is not a family, on the problem's `:init`.
/// Only where someone likely meant a position family: the domain uses the
/// HiPOP extensions, or some action moves along the candidate as a move
/// action does. Elsewhere (blocksworld's `on`, airport's segments) the note
/// is noise; hover still says why a predicate is not a family.
pub fn rejected_lints<'db>(f: &Families<'db>) -> Vec<Lint<'db>> {
    f.rejected
        .iter()
        .filter(|r| f.hipop || r.has_move)
        .filter_map(|r| {
            let decl = r.decl?;
            let here = f.init.unwrap_or(decl);
            let mut lint = Lint::new(
                codes::NOT_A_POSITION_FAMILY,
                here,
                format!(
                    "`{}` is not a position family (Definition 12, property {}): {}; hipop does not use position \
                     reasoning for it",
                    Pattern(&r.candidate),
                    r.property,
                    r.why
                ),
            );
            if here != decl {
                lint = lint.related(decl, format!("the predicate of `{}`", Pattern(&r.candidate)));
            }
            if let Some((loc, message)) = &r.witness {
                lint = lint.related(*loc, message.clone());
            }
            Some(lint)
        })
        .collect()
}

/// What the position families of `problem` say about a predicate (hover):
/// whether it is a confirmed family, with its instances and move actions, or
/// a candidate that is not one, and why. `None` when it is not a candidate.
pub fn describe_predicate(db: &dyn Db, problem: Unit<'_>, pred: &str) -> Option<String> {
    let f = families(db, problem);
    let name = problem.name(db).clone().unwrap_or_else(|| "?".into());
    if let Some(fam) = f.confirmed.iter().find(|c| c.candidate.pred.eq_ignore_ascii_case(pred)) {
        return Some(format!(
            "position family `{}` in problem `{name}`: confirmed (Definition 12), {}; move actions: {}",
            Pattern(&fam.candidate),
            instances(fam.instances),
            move_list(db, fam)
        ));
    }
    let r = f.rejected.iter().find(|r| r.candidate.pred.eq_ignore_ascii_case(pred))?;
    Some(format!(
        "`{}` is not a position family in problem `{name}` (Definition 12, property {}): {}",
        Pattern(&r.candidate),
        r.property,
        r.why
    ))
}

/// Whether an action is a move action of a confirmed family of `problem`, as
/// a sentence for hover.
pub fn describe_action(db: &dyn Db, problem: Unit<'_>, action: &str) -> Option<String> {
    let f = families(db, problem);
    let name = problem.name(db).clone().unwrap_or_else(|| "?".into());
    f.confirmed.iter().find_map(|fam| {
        let (_, n) = fam
            .moves
            .iter()
            .find(|(item, _)| item.name(db).as_deref().is_some_and(|m| m.eq_ignore_ascii_case(action)))?;
        Some(format!(
            "move action of position family `{}` in problem `{name}` (Definition 14): {n} ground moves",
            Pattern(&fam.candidate)
        ))
    })
}

/// `1 instance`, `8 instances`.
fn instances(n: usize) -> String {
    format!("{n} instance{}", if n == 1 { "" } else { "s" })
}

/// The move actions of a family, with their numbers of ground moves.
fn move_list(db: &dyn Db, fam: &Family<'_>) -> String {
    let moves: Vec<String> = fam
        .moves
        .iter()
        .map(|(item, n)| format!("`{}` ({n} ground moves)", item.name(db).as_deref().unwrap_or("?")))
        .collect();
    if moves.is_empty() { "none".to_string() } else { moves.join(", ") }
}

/// The families of a problem as text: confirmed ones with their move actions,
/// then the candidates that are not families and why
/// (`hipop check --explain families`).
pub fn explain(db: &dyn Db, problem: Unit<'_>) -> String {
    use std::fmt::Write;
    let f = families(db, problem);
    let name = problem.name(db).clone().unwrap_or_else(|| "?".into());
    let mut out = format!("problem `{name}`:\n");
    if f.confirmed.is_empty() && f.rejected.is_empty() {
        out.push_str(
            "  no candidate position family (no action replaces an atom by another of the same predicate)\n",
        );
    }
    for fam in &f.confirmed {
        let _ = writeln!(
            out,
            "  position family `{}`: confirmed, {}; move actions: {}",
            Pattern(&fam.candidate),
            instances(fam.instances),
            move_list(db, fam)
        );
    }
    for r in &f.rejected {
        let _ = writeln!(
            out,
            "  `{}`: not a position family (Definition 12, property {}): {}",
            Pattern(&r.candidate),
            r.property,
            r.why
        );
    }
    out
}
