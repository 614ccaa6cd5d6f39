//! The ground vocabulary of a problem and its initial state: objects, predicate
//! and function names, ground atoms, and what `:init` says about them.
//!
//! Everything is interned to `u32` ids so that the lints built on grounding
//! (position families over thousands of facts, the triangle inequality over
//! every triple of waypoints) compare integers, not strings. Locations are
//! item-relative ([`Loc`]), never absolute, so that typing elsewhere in a file
//! leaves these values equal.

use rustc_hash::FxHashMap;

use crate::db::{Db, Item, Section, Unit, lower_item};
use crate::model::{Fluent, InitElement, ItemData, NumExpr, Str, Term};
use crate::semantics::symbols::{DomainSymbols, Loc, ProblemSymbols};

/// An object: a problem object or a domain constant.
pub type ObjId = u32;
/// A predicate name.
pub type PredId = u32;
/// A function (numeric or object fluent) name.
pub type FuncId = u32;
/// A ground atom `(pred obj…)`.
pub type AtomId = u32;

/// Names interned to dense ids, in order of first appearance.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Interner {
    names: Vec<Str>,
    index: FxHashMap<Str, u32>,
}

impl Interner {
    pub fn intern(&mut self, name: &str) -> u32 {
        if let Some(&id) = self.index.get(name) {
            return id;
        }
        let id = self.names.len() as u32;
        self.names.push(name.into());
        self.index.insert(name.into(), id);
        id
    }

    pub fn get(&self, name: &str) -> Option<u32> {
        self.index.get(name).copied()
    }

    pub fn name(&self, id: u32) -> &str {
        self.names.get(id as usize).map_or("?", |n| n.as_str())
    }

    pub fn len(&self) -> usize {
        self.names.len()
    }

    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}

/// The objects a problem can ground with: the domain's constants, then the
/// problem's objects (a name declared as both keeps the constant).
#[derive(Debug, Clone, PartialEq, Eq, Default, salsa::SalsaValue)]
pub struct Objects<'db> {
    names: Interner,
    /// Each object's name as declared (`names` has the lower-cased keys).
    declared: Vec<Str>,
    locs: Vec<Loc<'db>>,
    /// Each object's types: its declared alternatives (`either`) and all their
    /// ancestors, `object` included.
    types: Vec<Vec<Str>>,
    /// The objects of each type (subtypes included), sorted.
    members: FxHashMap<Str, Vec<ObjId>>,
}

impl<'db> Objects<'db> {
    pub(crate) fn new(dom: &DomainSymbols<'db>, prob: &ProblemSymbols<'db>) -> Self {
        let mut objects = Objects::default();
        // Hash maps have no order: sort by name so that ids do not depend on hashing.
        let mut decls: Vec<_> = dom.constants.iter().collect();
        decls.sort_by(|a, b| a.0.cmp(b.0));
        let mut problem: Vec<_> = prob.objects.iter().collect();
        problem.sort_by(|a, b| a.0.cmp(b.0));
        decls.extend(problem);
        for (name, decl) in decls {
            if objects.names.get(name).is_some() {
                continue;
            }
            let id = objects.names.intern(name);
            let mut types: Vec<Str> = Vec::new();
            for t in &decl.ty {
                match dom.ancestors.get(t) {
                    Some(anc) => types.extend(anc.iter().cloned()),
                    // `object`, or a type the checks already reported as undeclared.
                    None => types.push(t.clone()),
                }
            }
            types.push("object".into());
            types.sort();
            types.dedup();
            for t in &types {
                objects.members.entry(t.clone()).or_default().push(id);
            }
            objects.declared.push(decl.name.clone());
            objects.locs.push(decl.loc);
            objects.types.push(types);
        }
        objects
    }

    pub fn len(&self) -> usize {
        self.names.len()
    }

    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// The object of that (lower-case) name.
    pub fn id(&self, name: &str) -> Option<ObjId> {
        self.names.get(name)
    }

    /// The lower-case name of an object.
    pub fn name(&self, id: ObjId) -> &str {
        self.names.name(id)
    }

    /// The name of an object as declared: what a plan writes (PDDL names
    /// match case-insensitively, but other tools may not).
    pub fn declared(&self, id: ObjId) -> &str {
        self.declared.get(id as usize).map_or_else(|| self.name(id), |n| n.as_str())
    }

    /// Where the object is declared.
    pub fn loc(&self, id: ObjId) -> Option<Loc<'db>> {
        self.locs.get(id as usize).copied()
    }

    /// The object's types, ancestors included (sorted).
    pub fn types(&self, id: ObjId) -> &[Str] {
        self.types.get(id as usize).map_or(&[], |t| t.as_slice())
    }

    pub fn has_type(&self, id: ObjId, ty: &str) -> bool {
        self.types(id).iter().any(|t| t == ty)
    }

    /// The objects of a type, subtypes included (sorted).
    pub fn of_type(&self, ty: &str) -> &[ObjId] {
        self.members.get(ty).map_or(&[], |m| m.as_slice())
    }

    /// The objects of any of the alternatives (a parameter's `either`), sorted.
    pub fn of_types(&self, types: &[Str]) -> Vec<ObjId> {
        match types {
            [t] => self.of_type(t).to_vec(),
            _ => {
                let mut all: Vec<ObjId> = types.iter().flat_map(|t| self.of_type(t)).copied().collect();
                all.sort_unstable();
                all.dedup();
                all
            }
        }
    }
}

/// The ground atoms met so far: those of `:init`, then those of the ground
/// operators. An atom is its predicate followed by its arguments. They are
/// stored back to back and found by the hash of that key (no allocation per
/// atom: grounding looks atoms up millions of times).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Atoms {
    /// `[pred, args…]` of every atom, back to back.
    data: Vec<u32>,
    /// Where each atom starts in `data`; one more entry for the end.
    starts: Vec<u32>,
    /// Atoms by the hash of their key: ids only, the keys are in `data`.
    index: AtomIndex,
}

/// The ids of [`Atoms`] in a hash table (4 bytes an atom).
#[derive(Debug, Clone, Default)]
struct AtomIndex(hashbrown::HashTable<AtomId>);

/// The index follows from `data` and `starts`: equal atoms, equal indices.
impl PartialEq for AtomIndex {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}
impl Eq for AtomIndex {}

/// Slice equality without a call to `memcmp`: keys have a handful of elements.
pub(crate) fn same(a: &[u32], b: &[u32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x == y)
}

fn hash_key(key: &[u32]) -> u64 {
    use std::hash::Hasher;
    let mut h = rustc_hash::FxHasher::default();
    for &k in key {
        h.write_u32(k);
    }
    h.finish()
}

impl Atoms {
    /// Room for `atoms` atoms of `key_len` numbers in all (predicates included).
    fn with_capacity(atoms: usize, key_len: usize) -> Atoms {
        Atoms {
            data: Vec::with_capacity(key_len),
            starts: Vec::with_capacity(atoms + 1),
            index: AtomIndex(hashbrown::HashTable::with_capacity(atoms)),
        }
    }

    fn key(&self, atom: AtomId) -> &[u32] {
        let i = atom as usize;
        match (self.starts.get(i), self.starts.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.data[a as usize..b as usize],
            _ => &[],
        }
    }

    fn lookup(&self, key: &[u32], h: u64) -> Option<AtomId> {
        self.index.0.find(h, |&a| same(self.key(a), key)).copied()
    }

    /// `key` is `[pred, args…]`.
    pub(crate) fn intern(&mut self, key: &[u32]) -> AtomId {
        let h = hash_key(key);
        if let Some(id) = self.lookup(key, h) {
            return id;
        }
        if self.starts.is_empty() {
            self.starts.push(0);
        }
        let id = (self.starts.len() - 1) as AtomId;
        self.data.extend_from_slice(key);
        self.starts.push(self.data.len() as u32);
        let Atoms { data, starts, index } = self;
        index.0.insert_unique(h, id, |&a| {
            let i = a as usize;
            hash_key(&data[starts[i] as usize..starts[i + 1] as usize])
        });
        id
    }

    /// The atom `[pred, args…]`, if it was met.
    pub fn get(&self, key: &[u32]) -> Option<AtomId> {
        self.lookup(key, hash_key(key))
    }

    /// The atom `(pred args…)`, if it was met.
    pub fn find(&self, pred: PredId, args: &[ObjId]) -> Option<AtomId> {
        let mut key: smallvec::SmallVec<[u32; 8]> = smallvec::SmallVec::with_capacity(args.len() + 1);
        key.push(pred);
        key.extend_from_slice(args);
        self.get(&key)
    }

    pub fn pred(&self, atom: AtomId) -> PredId {
        self.key(atom).first().copied().unwrap_or(u32::MAX)
    }

    pub fn args(&self, atom: AtomId) -> &[ObjId] {
        self.key(atom).get(1..).unwrap_or(&[])
    }

    pub fn len(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A timed initial literal: `(at time (p …))` or `(at time (not (p …)))`.
#[derive(Debug, Clone, PartialEq, salsa::SalsaValue)]
pub struct TimedLiteral<'db> {
    pub time: f64,
    pub atom: AtomId,
    pub positive: bool,
    pub loc: Loc<'db>,
}

/// What a problem's `:init` says, over all its chunks (a long `:init` is split
/// into several items).
#[derive(Debug, Clone, PartialEq, Default, salsa::SalsaValue)]
pub struct InitialState<'db> {
    /// The true atoms, in the order written, with the fact's location.
    pub facts: Vec<(AtomId, Loc<'db>)>,
    /// `(not (p …))` facts (closed world: they only repeat that `p` is false).
    pub negated: Vec<(AtomId, Loc<'db>)>,
    /// Timed initial literals: they become true (or false) later, not at the start.
    pub timed: Vec<TimedLiteral<'db>>,
    /// `(= (f objs…) v)`: the value and the location of the `=` fact, by
    /// `[func, args…]`. A fluent set twice keeps its first value.
    pub fluents: FluentValues<'db>,
    /// `(= (f objs…) obj)` (object fluents), by `[func, args…]`.
    pub object_fluents: FxHashMap<Box<[u32]>, (ObjId, Loc<'db>)>,
    /// Whether an atom is true at the start, by id (atoms met after `:init` are false).
    truth: Vec<bool>,
    /// The values of `fluents` again, in arrays for the functions whose
    /// argument tuples are few enough: durations read them once per ground
    /// instance (200,000 `slew_time` lookups for a Satellite problem), and a
    /// hash table of 77,562 boxed keys costs a cache miss or two each.
    dense: DenseFluents,
    /// The first `:init` item, to point at the initial state as a whole.
    pub first_item: Option<Item<'db>>,
}

/// The values `:init` gives numeric fluents, by `[func, args…]`, in the
/// order written. The keys are stored back to back as [`Atoms`] stores
/// atoms (4 bytes of table an entry), not as a hash map of boxed keys: a
/// Satellite problem sets 77,562 `slew_time` values, which took 82 bytes
/// each and an allocation, and take about 45.
#[derive(Debug, Clone, PartialEq, Default, salsa::SalsaValue)]
pub struct FluentValues<'db> {
    keys: Atoms,
    /// The value of each key, by its id in `keys`, and the `=` fact.
    values: Vec<(f64, Loc<'db>)>,
}

impl<'db> FluentValues<'db> {
    /// Room for `values` keys of `key_len` numbers in all.
    fn with_capacity(values: usize, key_len: usize) -> Self {
        FluentValues { keys: Atoms::with_capacity(values, key_len), values: Vec::with_capacity(values) }
    }

    /// Sets `key` to `value`, unless it has a value already (the first is kept).
    pub fn insert_first(&mut self, key: &[u32], value: (f64, Loc<'db>)) {
        if self.keys.intern(key) as usize == self.values.len() {
            self.values.push(value);
        }
    }

    /// The value of `key` (`[func, args…]`) and where it is set.
    pub fn get(&self, key: &[u32]) -> Option<&(f64, Loc<'db>)> {
        self.keys.get(key).map(|id| &self.values[id as usize])
    }

    /// Every key and its value, in the order written.
    pub fn iter(&self) -> impl Iterator<Item = (&[u32], &(f64, Loc<'db>))> + '_ {
        self.values.iter().enumerate().map(|(id, v)| (self.keys.key(id as AtomId), v))
    }

    pub fn len(&self) -> usize {
        self.values.len()
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}

/// Per function (by id), its arity and its values by argument tuple,
/// `args[0] * n^(k-1) + … + args[k-1]` over the `n` objects, NaN where
/// `:init` gives none (a value of `:init` is never NaN: [`constant`]); no
/// array for a function left to the hash table.
#[derive(Debug, Clone, Default)]
struct DenseFluents {
    objects: usize,
    values: Vec<(usize, Vec<f64>)>,
}

/// The arrays follow from `fluents`, compared on their own: equal states,
/// equal arrays (and NaN, which is not equal to itself, would make a state
/// unequal to itself).
impl PartialEq for DenseFluents {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl DenseFluents {
    /// At most this many entries per function, and at most four per value
    /// `:init` gives it: sparse functions keep the hash table alone.
    const MAX_ENTRIES: usize = 1 << 22;

    fn new(fluents: &FluentValues<'_>, objects: usize) -> DenseFluents {
        // Per function: its arity (None when two values disagree on it) and count.
        let mut shape: Vec<(Option<usize>, usize)> = Vec::new();
        for (key, _) in fluents.iter() {
            let (f, arity) = (key[0] as usize, key.len() - 1);
            if shape.len() <= f {
                shape.resize(f + 1, (None, 0));
            }
            let s = &mut shape[f];
            s.0 = if s.1 == 0 || s.0 == Some(arity) { Some(arity) } else { None };
            s.1 += 1;
        }
        let values = shape
            .iter()
            .map(|&(arity, count)| {
                let Some(arity) = arity else { return (0, Vec::new()) };
                match objects.checked_pow(arity as u32) {
                    Some(n) if n <= Self::MAX_ENTRIES && n <= count.saturating_mul(4).max(64) => {
                        (arity, vec![f64::NAN; n])
                    }
                    _ => (0, Vec::new()),
                }
            })
            .collect();
        let mut out = DenseFluents { objects, values };
        for (key, &(v, _)) in fluents.iter() {
            if let Some(i) = out.slot(key[0], &key[1..]) {
                out.values[key[0] as usize].1[i] = v;
            }
        }
        out
    }

    /// Where `(func args…)` is in its function's array, if it has one.
    fn slot(&self, func: FuncId, args: &[ObjId]) -> Option<usize> {
        let (arity, values) = self.values.get(func as usize).filter(|(_, v)| !v.is_empty())?;
        if args.len() != *arity {
            return None;
        }
        let mut at = 0usize;
        for &a in args {
            if a as usize >= self.objects {
                return None;
            }
            at = at * self.objects + a as usize;
        }
        (at < values.len()).then_some(at)
    }

    /// `Some(value or None)` when the function has an array, `None` when the
    /// hash table must tell.
    fn get(&self, func: FuncId, args: &[ObjId]) -> Option<Option<f64>> {
        let (arity, values) = self.values.get(func as usize).filter(|(_, v)| !v.is_empty())?;
        if args.len() != *arity {
            return None;
        }
        Some(self.slot(func, args).map(|i| values[i]).filter(|v| !v.is_nan()))
    }
}

impl<'db> InitialState<'db> {
    /// The value of a numeric fluent `(func args…)`, without its location:
    /// what evaluating a duration reads.
    pub fn fluent_value(&self, func: FuncId, args: &[ObjId]) -> Option<f64> {
        match self.dense.get(func, args) {
            Some(v) => v,
            None => self.fluent(func, args).map(|(v, _)| v),
        }
    }

    /// Whether the atom is true in the initial state.
    pub fn holds(&self, atom: AtomId) -> bool {
        self.truth.get(atom as usize).copied().unwrap_or(false)
    }

    /// Whether each atom is true at the start, by id.
    pub(crate) fn truth(&self) -> &[bool] {
        &self.truth
    }

    /// The value of a numeric fluent `(func args…)` and where it is set.
    pub fn fluent(&self, func: FuncId, args: &[ObjId]) -> Option<(f64, Loc<'db>)> {
        let mut key: smallvec::SmallVec<[u32; 8]> = smallvec::SmallVec::with_capacity(args.len() + 1);
        key.push(func);
        key.extend_from_slice(args);
        self.fluents.get(key.as_slice()).copied()
    }

    /// The value of an object fluent `(func args…)` and where it is set.
    pub fn object_fluent(&self, func: FuncId, args: &[ObjId]) -> Option<(ObjId, Loc<'db>)> {
        let mut key: smallvec::SmallVec<[u32; 8]> = smallvec::SmallVec::with_capacity(args.len() + 1);
        key.push(func);
        key.extend_from_slice(args);
        self.object_fluents.get(key.as_slice()).copied()
    }

    /// The span of the `(:init` keyword in [`first_item`](Self::first_item).
    pub fn keyword_loc(&self, db: &'db dyn Db) -> Option<Loc<'db>> {
        let item = self.first_item?;
        // Recorded when the items were made: the lints do not read the syntax.
        if item.section(db) != Section::Init {
            return None;
        }
        item.head(db).map(|span| Loc { item, span })
    }
}

/// Reads a problem's `:init` items into `atoms` and an [`InitialState`].
/// Facts naming an unknown object or predicate are skipped: the checks report them.
pub(crate) fn initial_state<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    objects: &Objects<'db>,
    preds: &mut Interner,
    funcs: &mut Interner,
    atoms: &mut Atoms,
) -> InitialState<'db> {
    let mut init = InitialState::default();
    let init_items = || problem.items(db).iter().filter(|i| i.section(db) == Section::Init);
    // The room the values take, reserved at once: a table grown by
    // doubling holds up to twice what it needs when the ground operators
    // are built next to it.
    let (mut values, mut key_len) = (0, 0);
    for &item in init_items() {
        let ItemData::Init(elements) = &lower_item(db, item).data else { continue };
        for e in elements {
            if let InitElement::Assign(f, ..) = e {
                values += 1;
                key_len += 1 + f.args.len();
            }
        }
    }
    init.fluents = FluentValues::with_capacity(values, key_len);
    let mut key: Vec<u32> = Vec::new();
    for &item in init_items() {
        init.first_item.get_or_insert(item);
        let ItemData::Init(elements) = &lower_item(db, item).data else { continue };
        let loc = |span| Loc { item, span };
        for e in elements {
            match e {
                InitElement::Fact(a) => {
                    if let Some(id) = ground_key(preds, a.pred.key(), &a.args, objects, &mut key)
                        .then(|| atoms.intern(&key))
                    {
                        init.facts.push((id, loc(a.span)));
                    }
                }
                InitElement::NotFact(a, span) => {
                    if ground_key(preds, a.pred.key(), &a.args, objects, &mut key) {
                        init.negated.push((atoms.intern(&key), loc(*span)));
                    }
                }
                InitElement::Assign(f, v, span) => {
                    if let (true, Some(v)) = (fluent_key(funcs, f, objects, &mut key), constant(v)) {
                        init.fluents.insert_first(&key, (v, loc(*span)));
                    }
                }
                InitElement::AssignObject(f, o, span) => {
                    if let (true, Some(o)) = (fluent_key(funcs, f, objects, &mut key), objects.id(o.key())) {
                        init.object_fluents.entry(key.as_slice().into()).or_insert((o, loc(*span)));
                    }
                }
                InitElement::Timed(time, inner, span) => {
                    let (a, positive) = match &**inner {
                        InitElement::Fact(a) => (a, true),
                        InitElement::NotFact(a, _) => (a, false),
                        // Timed numeric assignments do not change what holds at the start.
                        _ => continue,
                    };
                    if ground_key(preds, a.pred.key(), &a.args, objects, &mut key) {
                        let atom = atoms.intern(&key);
                        init.timed.push(TimedLiteral { time: time.value(), atom, positive, loc: loc(*span) });
                    }
                }
            }
        }
    }
    init.dense = DenseFluents::new(&init.fluents, objects.len());
    init.truth = vec![false; atoms.len()];
    for &(a, _) in &init.facts {
        init.truth[a as usize] = true;
    }
    init
}

/// Fills `key` with `[pred, args…]`; false if an argument is not an object.
fn ground_key(
    preds: &mut Interner,
    pred: &str,
    args: &[Term],
    objects: &Objects<'_>,
    key: &mut Vec<u32>,
) -> bool {
    key.clear();
    key.push(preds.intern(pred));
    args_key(args, objects, key)
}

fn fluent_key(funcs: &mut Interner, f: &Fluent, objects: &Objects<'_>, key: &mut Vec<u32>) -> bool {
    key.clear();
    key.push(funcs.intern(f.func.key()));
    args_key(&f.args, objects, key)
}

fn args_key(args: &[Term], objects: &Objects<'_>, key: &mut Vec<u32>) -> bool {
    for t in args {
        match t {
            Term::Const(n) => match objects.id(n.key()) {
                Some(o) => key.push(o),
                None => return false,
            },
            Term::Var(_) | Term::Func(_) => return false,
        }
    }
    true
}

/// The value of a constant numeric expression (an `:init` value: `30.98`,
/// `(- 2)`); `None` if it names a fluent or a variable, divides by zero or overflows.
pub(crate) fn constant(e: &NumExpr) -> Option<f64> {
    match e {
        NumExpr::Number(n) => Some(n.value()).filter(|v| !v.is_nan()),
        NumExpr::Op(op, args, _) => {
            let vals: Option<Vec<f64>> = args.iter().map(constant).collect();
            let vals = vals?;
            let (first, rest) = vals.split_first()?;
            let v = match (&**op, rest) {
                ("-", []) => -first,
                ("+", _) => rest.iter().fold(*first, |a, b| a + b),
                ("-", _) => rest.iter().fold(*first, |a, b| a - b),
                ("*", _) => rest.iter().fold(*first, |a, b| a * b),
                ("/", _) if rest.iter().all(|b| *b != 0.0) => rest.iter().fold(*first, |a, b| a / b),
                _ => return None,
            };
            Some(v).filter(|v| v.is_finite())
        }
        _ => None,
    }
}
