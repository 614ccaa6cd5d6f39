//! The ground vocabulary of a problem and the states of a plan's execution.

use super::FluentId;
use crate::verify::state::{AtomId, Atoms, InitialState, Interner, Objects, initial_state};

/// The ground vocabulary of a problem and its initial state, as both
/// validators start from: predicate and function names interned in sorted
/// order (hash maps have no order, so ids do not depend on hashing).
pub(crate) struct GroundWorld<'db> {
    pub preds: Interner,
    pub funcs: Interner,
    pub atoms: Atoms,
    pub init: InitialState<'db>,
}

impl<'db> GroundWorld<'db> {
    pub fn new(
        db: &'db dyn crate::db::Db,
        domain: crate::db::Unit<'db>,
        problem: crate::db::Unit<'db>,
        objects: &Objects<'db>,
    ) -> Self {
        let dom = crate::semantics::symbols::domain_symbols(db, domain);
        let sorted = |keys: &mut dyn Iterator<Item = &str>| {
            let mut names: Vec<&str> = keys.collect();
            names.sort_unstable();
            let mut interner = Interner::default();
            names.iter().for_each(|n| {
                interner.intern(n);
            });
            interner
        };
        let mut preds = sorted(&mut dom.predicates.keys().map(|k| k.as_str()));
        let mut funcs = sorted(&mut dom.functions.keys().map(|k| k.as_str()));
        let mut atoms = Atoms::default();
        let init = initial_state(db, problem, objects, &mut preds, &mut funcs, &mut atoms);
        GroundWorld { preds, funcs, atoms, init }
    }
}

/// A ground state: which atoms are true, the values of numeric fluents.
/// Atoms and fluents are interned as they are met.
#[derive(Debug, Clone, Default)]
pub(crate) struct State {
    pub atoms: Atoms,
    truth: Vec<bool>,
    pub fluents: Atoms,
    values: Vec<Option<f64>>,
}

impl State {
    pub fn new(atoms: Atoms, fluents: Atoms) -> State {
        let (na, nf) = (atoms.len(), fluents.len());
        State { atoms, truth: vec![false; na], fluents, values: vec![None; nf] }
    }

    pub fn is_true(&self, atom: AtomId) -> bool {
        self.truth.get(atom as usize).copied().unwrap_or(false)
    }

    pub fn set(&mut self, atom: AtomId, value: bool) {
        let i = atom as usize;
        if i >= self.truth.len() {
            self.truth.resize(i + 1, false);
        }
        self.truth[i] = value;
    }

    pub fn value(&self, fluent: FluentId) -> Option<f64> {
        self.values.get(fluent as usize).copied().flatten()
    }

    pub fn set_value(&mut self, fluent: FluentId, value: Option<f64>) {
        let i = fluent as usize;
        if i >= self.values.len() {
            self.values.resize(i + 1, None);
        }
        self.values[i] = value;
    }

    /// The id of a ground atom, interned if new.
    pub fn atom(&mut self, key: &[u32]) -> AtomId {
        self.atoms.intern(key)
    }

    /// The id of a ground fluent, interned if new.
    pub fn fluent(&mut self, key: &[u32]) -> FluentId {
        self.fluents.intern(key)
    }

    /// Whether the ground atom holds.
    pub fn holds(&self, key: &[u32]) -> bool {
        self.atoms.get(key).is_some_and(|a| self.is_true(a))
    }

    /// The value of the ground fluent, if it has one.
    pub fn value_of(&self, key: &[u32]) -> Option<f64> {
        self.fluents.get(key).and_then(|f| self.value(f))
    }
}
