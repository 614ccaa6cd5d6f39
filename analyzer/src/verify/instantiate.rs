//! The instantiation engine behind [`super::ground`]: parameters bound one at
//! a time, each drawn from the facts of a precondition whose other arguments
//! are bound, every constraint checked as soon as its arguments are.
//!
//! Operators are instantiated together with relaxed reachability, the way
//! Datalog engines evaluate rules (semi-naive evaluation): a first round
//! instantiates every operator over the initial state; each later round only
//! looks for instances that use an atom the previous round made reachable
//! (the "seed"), with the other preconditions drawn from every atom reached so
//! far. Each instance found adds its effects; the fixpoint is reached when a
//! round adds nothing. The result is the set of operators whose positive
//! preconditions are all relaxed-reachable: an operator outside it is in no
//! plan, and no lint should reason on it. Static predicates alone leave many:
//! on the 352 IPC 2002 temporal problems (of 388) that ground completely with
//! 20 million candidates, 43.6 million instances against 17.8 million
//! reachable ones (6 to 10 times more on Depots, whose `lift ?hoist ?crate
//! ?surface ?place` has no static precondition at all).

use std::ops::ControlFlow;

use rustc_hash::{FxHashMap, FxHashSet};

use super::lifted::{Conditions, LAtom, LTerm, Param};
use super::state::{AtomId, Atoms, Interner, ObjId, Objects, PredId};

/// A compiled term: a parameter or an object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Arg {
    Param(u32),
    Obj(ObjId),
}

/// An atom over parameters and objects.
#[derive(Debug, Clone)]
pub(crate) struct CAtom {
    pub pred: PredId,
    pub args: Vec<Arg>,
}

impl CAtom {
    /// `[pred, args…]` under a binding.
    pub fn key(&self, binding: &[ObjId], key: &mut Vec<u32>) {
        key.clear();
        key.push(self.pred);
        key.extend(self.args.iter().map(|a| value(*a, binding)));
    }

    fn params(&self) -> impl Iterator<Item = u32> + '_ {
        self.args.iter().filter_map(|a| match a {
            Arg::Param(p) => Some(*p),
            Arg::Obj(_) => None,
        })
    }

    fn has_param(&self, q: u32) -> bool {
        self.params().any(|p| p == q)
    }
}

pub(crate) fn value(a: Arg, binding: &[ObjId]) -> ObjId {
    match a {
        Arg::Param(p) => binding.get(p as usize).copied().unwrap_or(u32::MAX),
        Arg::Obj(o) => o,
    }
}

/// What constrains the parameters of an operator or a method.
pub(crate) struct Spec {
    /// Each parameter's objects (its type and subtypes, `either` alternatives).
    domains: Vec<Vec<ObjId>>,
    /// Whether each object fits each parameter: `fits[param][obj]`.
    fits: Vec<Vec<bool>>,
    /// Positive preconditions: true in the initial state (static predicates)
    /// or reachable (the others).
    pos: Vec<CAtom>,
    /// Negative preconditions on static predicates: false in the initial state.
    neg_static: Vec<CAtom>,
    eq: Vec<(Arg, Arg)>,
    neq: Vec<(Arg, Arg)>,
    /// No instance is wanted (goal relevance ruled them all out).
    disabled: bool,
}

impl Spec {
    pub fn domains(&self) -> &[Vec<ObjId>] {
        &self.domains
    }

    /// How many objects each parameter may take.
    pub fn candidates(&self) -> Vec<u32> {
        if self.disabled {
            return vec![0; self.domains.len()];
        }
        self.domains.iter().map(|d| d.len() as u32).collect()
    }

    /// Keeps each parameter's objects that `relevant` has (`None`: no instance).
    pub fn restrict(&mut self, relevant: Option<&[super::relevance::ObjSet]>) {
        let Some(sets) = relevant else {
            self.disabled = true;
            return;
        };
        for ((d, f), s) in self.domains.iter_mut().zip(&mut self.fits).zip(sets) {
            d.retain(|&o| s.contains(o));
            for (o, fit) in f.iter_mut().enumerate() {
                *fit &= s.contains(o as ObjId);
            }
        }
    }
}

/// Predicate names: interned while compiling operators, only looked up later.
pub(crate) enum Preds<'a> {
    Intern(&'a mut Interner),
    Get(&'a Interner),
}

/// Compiles lifted atoms and conditions against a problem's names.
pub(crate) struct Compiler<'a, 'db> {
    pub objects: &'a Objects<'db>,
    pub preds: Preds<'a>,
    /// By predicate id; a predicate met only now (undeclared, already
    /// reported) is in no effect, hence static.
    pub static_preds: &'a [bool],
    /// Predicates whose atoms grounding cannot follow: derived ones (axioms
    /// hipop does not run) and those added with a term it cannot name.
    pub untracked: &'a [bool],
    /// Derived predicates (no action adds them).
    pub derived: &'a [bool],
    /// Something was left out: the result over-approximates.
    pub unsupported: bool,
}

impl Compiler<'_, '_> {
    pub fn pred(&mut self, name: &str) -> Option<PredId> {
        match &mut self.preds {
            Preds::Intern(i) => Some(i.intern(name)),
            Preds::Get(i) => i.get(name),
        }
    }

    pub fn arg(&self, t: &LTerm) -> Option<Arg> {
        match t {
            LTerm::Param(i) => Some(Arg::Param(*i)),
            LTerm::Const(c) => self.objects.id(c).map(Arg::Obj),
            LTerm::Free(_) => None,
        }
    }

    fn flag(table: &[bool], pred: PredId) -> bool {
        table.get(pred as usize).copied().unwrap_or(false)
    }

    pub fn is_static(&self, pred: PredId) -> bool {
        self.static_preds.get(pred as usize).copied().unwrap_or(true)
    }

    /// An atom over parameters and objects; `None` when a term cannot be named.
    pub fn atom(&mut self, a: &LAtom) -> Option<CAtom> {
        let pred = self.pred(&a.pred)?;
        let args = a.args.iter().map(|t| self.arg(t)).collect::<Option<Vec<_>>>()?;
        Some(CAtom { pred, args })
    }

    /// The atoms of a ground operator's list: effects keep every atom,
    /// preconditions those on predicates that are not static (derived ones are
    /// dropped: nothing would ever reach them).
    pub fn atoms(&mut self, atoms: &[LAtom], effects: bool) -> Vec<CAtom> {
        let mut out = Vec::new();
        for a in atoms {
            let Some(c) = self.atom(a) else {
                // A term grounding cannot name: leave the atom out, and say so.
                self.unsupported = true;
                continue;
            };
            if effects {
                out.push(c);
            } else if Self::flag(self.derived, c.pred) {
                self.unsupported = true;
            } else if !self.is_static(c.pred) {
                out.push(c);
            }
        }
        out
    }

    /// The constraints on the parameters. Negative preconditions on
    /// predicates that are not static are relaxed away.
    pub fn spec(&mut self, params: &[Param], pre: &Conditions) -> Spec {
        let n = self.objects.len();
        let domains: Vec<Vec<ObjId>> = params.iter().map(|p| self.objects.of_types(&p.types)).collect();
        let fits = domains
            .iter()
            .map(|d| {
                let mut f = vec![false; n];
                for &o in d {
                    f[o as usize] = true;
                }
                f
            })
            .collect();
        let mut spec = Spec {
            domains,
            fits,
            pos: Vec::new(),
            neg_static: Vec::new(),
            eq: Vec::new(),
            neq: Vec::new(),
            disabled: false,
        };
        for a in &pre.pos {
            match self.atom(a) {
                Some(c) if !Self::flag(self.untracked, c.pred) => spec.pos.push(c),
                _ => self.unsupported = true,
            }
        }
        for a in &pre.neg {
            match self.atom(a) {
                Some(c) if self.is_static(c.pred) && !Self::flag(self.untracked, c.pred) => {
                    spec.neg_static.push(c)
                }
                Some(_) => {}
                None => self.unsupported = true,
            }
        }
        for (pairs, equal) in [(&pre.eq, true), (&pre.neq, false)] {
            for (x, y) in pairs {
                match (self.arg(x), self.arg(y)) {
                    (Some(x), Some(y)) if equal => spec.eq.push((x, y)),
                    (Some(x), Some(y)) => spec.neq.push((x, y)),
                    // A constant that is no object (already reported), an object fluent.
                    _ => self.unsupported = true,
                }
            }
        }
        spec
    }
}

/// The atoms reached so far.
pub(crate) struct Facts {
    reached: Vec<bool>,
    by_pred: FxHashMap<PredId, Vec<AtomId>>,
    /// The initial state, for negative static preconditions.
    initial: Vec<bool>,
}

impl Facts {
    pub fn new(initial: Vec<bool>) -> Facts {
        Facts { reached: Vec::new(), by_pred: FxHashMap::default(), initial }
    }

    pub fn holds(&self, atom: AtomId) -> bool {
        self.reached.get(atom as usize).copied().unwrap_or(false)
    }

    /// Adds an atom; false if it was reached already.
    pub fn add(&mut self, atom: AtomId, atoms: &Atoms) -> bool {
        let i = atom as usize;
        if self.reached.len() <= i {
            self.reached.resize(i + 1, false);
        }
        if self.reached[i] {
            return false;
        }
        self.reached[i] = true;
        self.by_pred.entry(atoms.pred(atom)).or_default().push(atom);
        true
    }

    /// The atoms `reached` marks, over the initial state `initial`.
    pub fn from_reached(reached: &[bool], initial: Vec<bool>, atoms: &Atoms) -> Facts {
        let mut facts = Facts::new(initial);
        for (a, _) in reached.iter().enumerate().filter(|(_, r)| **r) {
            facts.add(a as AtomId, atoms);
        }
        facts
    }

    pub fn into_reached(self) -> Vec<bool> {
        self.reached
    }
}

/// The values of parameter `q` in the reached atoms matching `pattern`, keyed
/// by the values of `key_params`. Atoms that disagree with the pattern's
/// objects or repeated parameters are left out.
struct Index {
    pred: PredId,
    pattern: Vec<Arg>,
    key_params: Vec<u32>,
    q: u32,
    values: FxHashMap<Box<[u32]>, Vec<ObjId>>,
    /// When the pattern has other parameters, two atoms can give the same
    /// key and value: this keeps each pair once.
    seen: Option<FxHashSet<Box<[u32]>>>,
}

impl Index {
    fn insert(&mut self, args: &[ObjId], scratch: &mut Vec<(u32, ObjId)>, key: &mut Vec<u32>) {
        if args.len() != self.pattern.len() {
            return;
        }
        scratch.clear();
        for (x, &v) in self.pattern.iter().zip(args) {
            match *x {
                Arg::Obj(o) if o != v => return,
                Arg::Obj(_) => {}
                Arg::Param(x) => match scratch.iter().find(|(y, _)| *y == x) {
                    Some(&(_, w)) if w != v => return,
                    Some(_) => {}
                    None => scratch.push((x, v)),
                },
            }
        }
        let find = |x: u32| scratch.iter().find(|(y, _)| *y == x).map_or(u32::MAX, |s| s.1);
        key.clear();
        key.extend(self.key_params.iter().map(|&x| find(x)));
        let v = find(self.q);
        if let Some(seen) = &mut self.seen {
            key.push(v);
            if !seen.insert(key.as_slice().into()) {
                return;
            }
            key.pop();
        }
        match self.values.get_mut(key.as_slice()) {
            Some(list) => list.push(v),
            None => {
                self.values.insert(key.as_slice().into(), vec![v]);
            }
        }
    }
}

/// Every index, kept up to date as atoms are reached.
#[derive(Default)]
pub(crate) struct Indexes {
    list: Vec<Index>,
    by_pred: FxHashMap<PredId, Vec<usize>>,
    /// Each index by the hash of (predicate, pattern, key parameters,
    /// parameter): plans ask for the same ones again and again, and a
    /// lookup allocates nothing.
    shared: hashbrown::HashTable<usize>,
}

fn index_hash(pred: PredId, pattern: &[Arg], key_params: &[u32], q: u32) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = rustc_hash::FxHasher::default();
    (pred, pattern, key_params, q).hash(&mut h);
    h.finish()
}

impl Indexes {
    fn get(&mut self, a: &CAtom, key_params: Vec<u32>, q: u32, facts: &Facts, atoms: &Atoms) -> usize {
        let h = index_hash(a.pred, &a.args, &key_params, q);
        let list = &self.list;
        let same = |&i: &usize| {
            let x = &list[i];
            x.pred == a.pred && x.q == q && x.pattern == a.args && x.key_params == key_params
        };
        if let Some(&i) = self.shared.find(h, same) {
            return i;
        }
        let others = a.params().any(|x| x != q && !key_params.contains(&x));
        let mut index = Index {
            pred: a.pred,
            pattern: a.args.clone(),
            key_params,
            q,
            values: FxHashMap::default(),
            seen: others.then(FxHashSet::default),
        };
        let (mut scratch, mut key) = (Vec::new(), Vec::new());
        for &f in facts.by_pred.get(&a.pred).map_or(&[][..], |v| v.as_slice()) {
            index.insert(atoms.args(f), &mut scratch, &mut key);
        }
        let i = self.list.len();
        self.list.push(index);
        self.by_pred.entry(a.pred).or_default().push(i);
        let list = &self.list;
        self.shared.insert_unique(h, i, |&j| {
            let x = &list[j];
            index_hash(x.pred, &x.pattern, &x.key_params, x.q)
        });
        i
    }

    /// Adds a newly reached atom to the indexes of its predicate.
    fn add(&mut self, atom: AtomId, atoms: &Atoms) {
        let Some(ids) = self.by_pred.get(&atoms.pred(atom)) else { return };
        let (mut scratch, mut key) = (Vec::new(), Vec::new());
        for &i in ids {
            self.list[i].insert(atoms.args(atom), &mut scratch, &mut key);
        }
    }
}

/// A check made once its arguments are bound.
#[derive(Debug, Clone, Copy)]
enum Check {
    Holds(usize),
    NotHolds(usize),
    Eq(Arg, Arg),
    Neq(Arg, Arg),
}

struct Step {
    param: u32,
    generator: Option<usize>,
    checks: Vec<Check>,
}

/// An order of the parameters, with what to check at each step. A seeded plan
/// binds the parameters of one positive precondition from a given atom first.
pub(crate) struct Plan {
    seed: Option<usize>,
    /// Parameters bound by the seed, then one step per other parameter.
    seeded: Vec<u32>,
    start: Vec<Check>,
    steps: Vec<Step>,
}

impl Plan {
    pub fn new(
        spec: &Spec,
        seed: Option<usize>,
        indexes: &mut Indexes,
        facts: &Facts,
        atoms: &Atoms,
    ) -> Plan {
        let n = spec.domains.len();
        let mut bound = vec![false; n];
        let mut order: Vec<u32> = Vec::with_capacity(n);
        if let Some(j) = seed {
            for q in spec.pos[j].params() {
                if !bound[q as usize] {
                    bound[q as usize] = true;
                    order.push(q);
                }
            }
        }
        let seeded = order.clone();
        let bound_count = |a: &CAtom, bound: &[bool]| {
            a.args
                .iter()
                .filter(|x| match x {
                    Arg::Obj(_) => true,
                    Arg::Param(x) => bound[*x as usize],
                })
                .count()
        };
        // Greedy: prefer a parameter some precondition generates with the most
        // arguments already bound, then the smallest domain.
        while order.len() < n {
            let best = (0..n as u32).filter(|&q| !bound[q as usize]).max_by_key(|&q| {
                let generated = spec
                    .pos
                    .iter()
                    .filter(|a| a.has_param(q))
                    .map(|a| 1 + bound_count(a, &bound))
                    .max()
                    .unwrap_or(0);
                (generated, std::cmp::Reverse(spec.domains[q as usize].len()), std::cmp::Reverse(q))
            });
            let Some(q) = best else { break };
            bound[q as usize] = true;
            order.push(q);
        }
        let mut rank = vec![0usize; n];
        for (k, &q) in order.iter().enumerate() {
            rank[q as usize] = k + 1;
        }
        // A check runs at the step that binds its last parameter; the seed's
        // parameters are bound at once, before the first step.
        let s0 = seeded.len();
        let at = |args: &[Arg]| {
            let r = args
                .iter()
                .map(|a| match a {
                    Arg::Param(q) => rank.get(*q as usize).copied().unwrap_or(0),
                    Arg::Obj(_) => 0,
                })
                .max()
                .unwrap_or(0);
            r.saturating_sub(s0)
        };
        let mut checks: Vec<Vec<Check>> = vec![Vec::new(); n - s0 + 1];
        for (i, a) in spec.pos.iter().enumerate() {
            if seed != Some(i) {
                checks[at(&a.args)].push(Check::Holds(i));
            }
        }
        for (i, a) in spec.neg_static.iter().enumerate() {
            checks[at(&a.args)].push(Check::NotHolds(i));
        }
        for &(x, y) in &spec.eq {
            checks[at(&[x, y])].push(Check::Eq(x, y));
        }
        for &(x, y) in &spec.neq {
            checks[at(&[x, y])].push(Check::Neq(x, y));
        }
        let mut bound = vec![false; n];
        for &q in &seeded {
            bound[q as usize] = true;
        }
        let mut steps = Vec::with_capacity(n - s0);
        for (k, &q) in order.iter().enumerate().skip(s0) {
            let generator =
                spec.pos.iter().filter(|a| a.has_param(q)).max_by_key(|a| bound_count(a, &bound)).map(|a| {
                    let mut key_params: Vec<u32> = Vec::new();
                    for x in a.params() {
                        if bound[x as usize] && !key_params.contains(&x) {
                            key_params.push(x);
                        }
                    }
                    indexes.get(a, key_params, q, facts, atoms)
                });
            bound[q as usize] = true;
            steps.push(Step { param: q, generator, checks: std::mem::take(&mut checks[k - s0 + 1]) });
        }
        Plan { seed, seeded, start: std::mem::take(&mut checks[0]), steps }
    }

    /// The positive precondition this plan is seeded by.
    pub fn seed_pred(&self, spec: &Spec) -> Option<PredId> {
        self.seed.map(|j| spec.pos[j].pred)
    }
}

/// What a search reads, and its budget.
pub(crate) struct Search<'a> {
    pub spec: &'a Spec,
    pub indexes: &'a Indexes,
    pub facts: &'a Facts,
    pub atoms: &'a Atoms,
    /// Parameter values left to try.
    pub budget: &'a mut u64,
}

/// Why a search stopped early.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stop {
    /// The candidate budget ran out.
    Budget,
    /// The caller asked to stop.
    Caller,
}

type Emit<'e> = dyn FnMut(&[ObjId]) -> ControlFlow<()> + 'e;

impl<'a> Search<'a> {
    fn check(&self, c: Check, binding: &[ObjId], key: &mut Vec<u32>) -> bool {
        match c {
            Check::Holds(i) => {
                self.spec.pos[i].key(binding, key);
                self.atoms.get(key).is_some_and(|id| self.facts.holds(id))
            }
            Check::NotHolds(i) => {
                self.spec.neg_static[i].key(binding, key);
                !self
                    .atoms
                    .get(key)
                    .is_some_and(|id| self.facts.initial.get(id as usize).copied().unwrap_or(false))
            }
            Check::Eq(x, y) => value(x, binding) == value(y, binding),
            Check::Neq(x, y) => value(x, binding) != value(y, binding),
        }
    }

    /// Every binding of an unseeded plan.
    pub fn run(&mut self, plan: &Plan, emit: &mut Emit<'_>) -> ControlFlow<Stop> {
        if self.spec.disabled || self.spec.domains.iter().any(|d| d.is_empty()) {
            return ControlFlow::Continue(());
        }
        let mut binding = vec![u32::MAX; self.spec.domains.len()];
        let mut key = Vec::new();
        if !plan.start.iter().all(|c| self.check(*c, &binding, &mut key)) {
            return ControlFlow::Continue(());
        }
        self.search(plan, &mut binding, &mut key, emit)
    }

    /// Every binding of a seeded plan that matches its seed to `seed_args`.
    pub fn run_seeded(&mut self, plan: &Plan, seed_args: &[ObjId], emit: &mut Emit<'_>) -> ControlFlow<Stop> {
        let Some(j) = plan.seed.filter(|_| !self.spec.disabled) else { return ControlFlow::Continue(()) };
        let pattern = &self.spec.pos[j].args;
        if pattern.len() != seed_args.len() {
            return ControlFlow::Continue(());
        }
        let mut binding = vec![u32::MAX; self.spec.domains.len()];
        for (x, &v) in pattern.iter().zip(seed_args) {
            let ok = match *x {
                Arg::Obj(o) => o == v,
                Arg::Param(q) => {
                    let b = &mut binding[q as usize];
                    let fits = self.spec.fits[q as usize].get(v as usize).copied().unwrap_or(false);
                    if *b == u32::MAX && fits {
                        *b = v;
                    }
                    *b == v
                }
            };
            if !ok {
                return ControlFlow::Continue(());
            }
        }
        debug_assert!(plan.seeded.iter().all(|&q| binding[q as usize] != u32::MAX));
        let mut key = Vec::new();
        if !plan.start.iter().all(|c| self.check(*c, &binding, &mut key)) {
            return ControlFlow::Continue(());
        }
        self.search(plan, &mut binding, &mut key, emit)
    }

    /// Every binding of the steps of `plan` from the one given, depth first
    /// with an explicit stack (an operator may have thousands of
    /// parameters): level `k` tries the candidates of step `k` in order.
    fn search(
        &mut self,
        plan: &Plan,
        binding: &mut [ObjId],
        key: &mut Vec<u32>,
        emit: &mut Emit<'_>,
    ) -> ControlFlow<Stop> {
        let (spec, indexes) = (self.spec, self.indexes);
        // The values step `k` may take, given the parameters bound before it.
        let candidates = |k: usize, binding: &[ObjId], key: &mut Vec<u32>| -> &'a [ObjId] {
            let step = &plan.steps[k];
            match step.generator {
                Some(i) => {
                    let index = &indexes.list[i];
                    key.clear();
                    key.extend(index.key_params.iter().map(|&q| binding[q as usize]));
                    index.values.get(key.as_slice()).map_or(&[], |v| v.as_slice())
                }
                None => &spec.domains[step.param as usize],
            }
        };
        if plan.steps.is_empty() {
            return match emit(binding) {
                ControlFlow::Continue(()) => ControlFlow::Continue(()),
                ControlFlow::Break(()) => ControlFlow::Break(Stop::Caller),
            };
        }
        // Per level: its candidates and the next one to try.
        let mut stack: Vec<(&[ObjId], usize)> = Vec::with_capacity(plan.steps.len());
        stack.push((candidates(0, binding, key), 0));
        while let Some(&(cands, mut next)) = stack.last() {
            let k = stack.len() - 1;
            let step = &plan.steps[k];
            let fits = &spec.fits[step.param as usize];
            let mut found = false;
            while next < cands.len() {
                let o = cands[next];
                next += 1;
                if *self.budget == 0 {
                    return ControlFlow::Break(Stop::Budget);
                }
                *self.budget -= 1;
                if !fits.get(o as usize).copied().unwrap_or(false) {
                    continue;
                }
                binding[step.param as usize] = o;
                if step.checks.iter().all(|c| self.check(*c, binding, key)) {
                    found = true;
                    break;
                }
            }
            stack[k].1 = next;
            if !found {
                binding[step.param as usize] = u32::MAX;
                stack.pop();
            } else if k + 1 == plan.steps.len() {
                if emit(binding).is_break() {
                    return ControlFlow::Break(Stop::Caller);
                }
            } else {
                stack.push((candidates(k + 1, binding, key), 0));
            }
        }
        ControlFlow::Continue(())
    }
}

/// An operator to instantiate: its constraints and its add effects.
pub(crate) struct OpInput {
    pub spec: Spec,
    pub add: Vec<CAtom>,
}

/// Instances of several operators, stored flat, each once.
#[derive(Default)]
pub(crate) struct Instances {
    /// Each instance's operator and the start of its arguments in `args`.
    found: Vec<(u32, u32)>,
    args: Vec<ObjId>,
    /// Each operator's arity.
    arity: Vec<u32>,
    /// Instances by the hash of (operator, arguments), for deduplication
    /// without a key allocation per instance: the table holds indices only
    /// (4 bytes an instance; a truncated grounding has 200,000 of them).
    by_hash: hashbrown::HashTable<u32>,
}

impl Instances {
    fn new(arity: Vec<u32>) -> Instances {
        Instances { arity, ..Instances::default() }
    }

    pub fn len(&self) -> usize {
        self.found.len()
    }

    /// Frees the deduplication table, and the spare room of the arrays
    /// (grown by doubling): no instance is added any more.
    pub fn forget_index(&mut self) {
        self.by_hash = hashbrown::HashTable::new();
        // Exact copies: the allocator may keep a block shrunk in place whole.
        self.found = self.found.as_slice().to_vec();
        self.args = self.args.as_slice().to_vec();
    }

    /// The arguments of instance `i`, whose operator has `arity` parameters.
    pub fn args_of(&self, i: usize, arity: usize) -> &[ObjId] {
        let at = self.found[i].1 as usize;
        &self.args[at..at + arity]
    }

    /// The operator and arguments of instance `i`.
    pub fn get(&self, i: usize) -> (usize, &[ObjId]) {
        let (op, at) = self.found[i];
        let n = self.arity[op as usize] as usize;
        (op as usize, &self.args[at as usize..at as usize + n])
    }

    fn hash(op: usize, args: &[ObjId]) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = rustc_hash::FxHasher::default();
        op.hash(&mut h);
        args.hash(&mut h);
        h.finish()
    }

    /// The hash of an instance, and whether it is known.
    fn find(&self, op: usize, args: &[ObjId]) -> (u64, bool) {
        let h = Self::hash(op, args);
        let known = self
            .by_hash
            .find(h, |&i| {
                let (o, a) = self.get(i as usize);
                o == op && super::state::same(a, args)
            })
            .is_some();
        (h, known)
    }

    /// Adds an instance that [`find`](Self::find) did not know; its index.
    fn push(&mut self, op: usize, args: &[ObjId], h: u64) -> u32 {
        let i = self.found.len() as u32;
        self.found.push((op as u32, self.args.len() as u32));
        self.args.extend_from_slice(args);
        let Instances { found, args: all, arity, by_hash } = self;
        by_hash.insert_unique(h, i, |&j| {
            let (o, at) = found[j as usize];
            let n = arity[o as usize] as usize;
            Self::hash(o as usize, &all[at as usize..at as usize + n])
        });
        i
    }
}

/// The reachable instances of a set of operators.
pub(crate) struct Fixpoint {
    pub instances: Instances,
    /// The reached atoms, by id.
    pub reached: Vec<bool>,
    /// Whether it stopped at a limit (the instances are then incomplete).
    pub truncated: bool,
}

/// The seeded plans of one predicate, in the order they were made (operator,
/// then precondition), and by the first object their seed's pattern names:
/// a nearly ground domain (the IPC Airport domains: a `move` per pair of
/// segments) has thousands of plans seeded on `(at-segment ?a seg_3)`, of
/// which a new atom can only match those naming its own segment.
#[derive(Default)]
struct SeededPlans {
    plans: Vec<(usize, Plan)>,
    /// The plans whose seed has no object.
    open: Vec<u32>,
    /// The others, by the position and object of the first object.
    by_object: FxHashMap<(u32, ObjId), Vec<u32>>,
}

impl SeededPlans {
    fn push(&mut self, op: usize, plan: Plan, pattern: &[Arg]) {
        let k = self.plans.len() as u32;
        let first = pattern.iter().enumerate().find_map(|(at, x)| match *x {
            Arg::Obj(o) => Some((at as u32, o)),
            Arg::Param(_) => None,
        });
        match first {
            Some(key) => self.by_object.entry(key).or_default().push(k),
            None => self.open.push(k),
        }
        self.plans.push((op, plan));
    }

    /// The plans an atom of these arguments may seed, in the order made; the
    /// others name another object where the atom has its own, and
    /// [`Search::run_seeded`] would reject them without a search.
    fn matching(&self, args: &[ObjId], out: &mut Vec<u32>) {
        out.clear();
        out.extend_from_slice(&self.open);
        if !self.by_object.is_empty() {
            for (at, &o) in args.iter().enumerate() {
                if let Some(ks) = self.by_object.get(&(at as u32, o)) {
                    out.extend_from_slice(ks);
                }
            }
            out.sort_unstable();
        }
    }
}

/// Instantiates `ops` together with relaxed reachability from `start` (the
/// initial facts and the atoms timed literals make true).
pub(crate) fn fixpoint(
    ops: &[&OpInput],
    atoms: &mut Atoms,
    start: &[AtomId],
    initial: Vec<bool>,
    budget: &mut u64,
    max_instances: usize,
) -> Fixpoint {
    let mut facts = Facts::new(initial);
    for &a in start {
        facts.add(a, atoms);
    }
    let mut indexes = Indexes::default();
    let first: Vec<Option<Plan>> = ops
        .iter()
        .map(|op| (!op.spec.disabled).then(|| Plan::new(&op.spec, None, &mut indexes, &facts, atoms)))
        .collect();
    let seeded = seeded_plans(ops, &mut indexes, &facts, atoms);
    let mut matching: Vec<u32> = Vec::new();

    let mut instances = Instances::new(ops.iter().map(|op| op.spec.domains.len() as u32).collect());
    // Instances found but whose effects are not reached yet.
    let mut pending: Vec<u32> = Vec::new();
    let record = |i: usize, args: &[ObjId], instances: &mut Instances, pending: &mut Vec<u32>| {
        let (h, known) = instances.find(i, args);
        if known {
            return ControlFlow::Continue(());
        }
        if instances.len() >= max_instances {
            return ControlFlow::Break(());
        }
        pending.push(instances.push(i, args, h));
        ControlFlow::Continue(())
    };

    let mut truncated = false;
    for (i, plan) in first.iter().enumerate() {
        let Some(plan) = plan else { continue };
        let mut search = Search {
            spec: &ops[i].spec,
            indexes: &indexes,
            facts: &facts,
            atoms: &*atoms,
            budget: &mut *budget,
        };
        if search.run(plan, &mut |args| record(i, args, &mut instances, &mut pending)).is_break() {
            truncated = true;
            break;
        }
    }
    let mut delta: Vec<AtomId> = Vec::new();
    let mut key = Vec::new();
    loop {
        for k in pending.drain(..) {
            let (i, args) = instances.get(k as usize);
            for a in &ops[i].add {
                a.key(args, &mut key);
                let id = atoms.intern(&key);
                if facts.add(id, atoms) {
                    delta.push(id);
                }
            }
        }
        if delta.is_empty() || truncated {
            break;
        }
        for &a in &delta {
            indexes.add(a, atoms);
        }
        'round: for a in delta.drain(..) {
            let Some(plans) = seeded.get(&atoms.pred(a)) else { continue };
            plans.matching(atoms.args(a), &mut matching);
            for &k in &matching {
                let (i, plan) = &plans.plans[k as usize];
                let i = *i;
                let mut search = Search {
                    spec: &ops[i].spec,
                    indexes: &indexes,
                    facts: &facts,
                    atoms: &*atoms,
                    budget: &mut *budget,
                };
                let args = atoms.args(a);
                if search
                    .run_seeded(plan, args, &mut |b| record(i, b, &mut instances, &mut pending))
                    .is_break()
                {
                    truncated = true;
                    break 'round;
                }
            }
        }
    }
    Fixpoint { instances, reached: facts.into_reached(), truncated }
}

/// The seeded plans of `ops`, by the predicate of their seed. A plan is
/// seeded by an atom newly reached, which some operator adds: none for a
/// precondition whose predicate no operator adds (`has-type` in the Airport
/// domains), nor for a ground one already reached (most of the Airport's
/// `not_blocked` conditions, true from the start).
fn seeded_plans(
    ops: &[&OpInput],
    indexes: &mut Indexes,
    facts: &Facts,
    atoms: &Atoms,
) -> FxHashMap<PredId, SeededPlans> {
    let added = added_preds(ops);
    let mut key = Vec::new();
    let mut may_seed = |a: &CAtom| {
        if !added.get(a.pred as usize).copied().unwrap_or(false) {
            return false;
        }
        if a.params().next().is_some() {
            return true;
        }
        a.key(&[], &mut key);
        atoms.get(&key).is_none_or(|id| !facts.holds(id))
    };
    let mut seeded: FxHashMap<PredId, SeededPlans> = FxHashMap::default();
    for (i, op) in ops.iter().enumerate().filter(|(_, op)| !op.spec.disabled) {
        for (j, a) in op.spec.pos.iter().enumerate() {
            if !may_seed(a) {
                continue;
            }
            let plan = Plan::new(&op.spec, Some(j), indexes, facts, atoms);
            if let Some(p) = plan.seed_pred(&op.spec) {
                seeded.entry(p).or_default().push(i, plan, &a.args);
            }
        }
    }
    seeded
}

/// Whether some operator of `ops` adds atoms of each predicate, by id.
fn added_preds(ops: &[&OpInput]) -> Vec<bool> {
    let mut added = Vec::new();
    for a in ops.iter().flat_map(|op| &op.add) {
        let p = a.pred as usize;
        if added.len() <= p {
            added.resize(p + 1, false);
        }
        added[p] = true;
    }
    added
}

/// Every binding of `spec` over the atoms `reached` (no fixpoint: methods).
pub(crate) fn instances_over(
    spec: &Spec,
    atoms: &Atoms,
    facts: &Facts,
    budget: &mut u64,
    emit: &mut Emit<'_>,
) -> ControlFlow<Stop> {
    let mut indexes = Indexes::default();
    let plan = Plan::new(spec, None, &mut indexes, facts, atoms);
    Search { spec, indexes: &indexes, facts, atoms, budget }.run(&plan, emit)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn atom(pred: PredId, args: &[Arg]) -> CAtom {
        CAtom { pred, args: args.to_vec() }
    }

    /// A plan is seeded only by what may be newly reached: not by a
    /// predicate no operator adds, nor by a ground atom true from the start.
    #[test]
    fn plans_are_seeded_only_by_atoms_that_may_be_reached() {
        // Predicates: 0 static, 1 and 2 added; objects 0 and 1.
        let (x, o0, o1) = (Arg::Param(0), Arg::Obj(0), Arg::Obj(1));
        let spec = Spec {
            domains: vec![vec![0, 1]],
            fits: vec![vec![true, true]],
            pos: vec![atom(0, &[x]), atom(1, &[o0]), atom(1, &[o1]), atom(2, &[x])],
            neg_static: Vec::new(),
            eq: Vec::new(),
            neq: Vec::new(),
            disabled: false,
        };
        let op = OpInput { spec, add: vec![atom(1, &[x]), atom(2, &[x])] };
        let mut atoms = Atoms::default();
        let start = [atoms.intern(&[0, 0]), atoms.intern(&[0, 1]), atoms.intern(&[1, 0])];
        let mut facts = Facts::new(Vec::new());
        for a in start {
            facts.add(a, &atoms);
        }
        let seeded = seeded_plans(&[&op], &mut Indexes::default(), &facts, &atoms);
        let seeds = |p: PredId| seeded.get(&p).map_or(0, |s| s.plans.len());
        assert_eq!((seeds(0), seeds(1), seeds(2)), (0, 1, 1));
        // The plan of predicate 1 is seeded by `(1 o1)`, not yet reached.
        assert_eq!(seeded[&1].by_object.keys().collect::<Vec<_>>(), [&(0, 1)]);

        // The reachable instances are those of every plan.
        let mut budget = u64::MAX;
        let fix = fixpoint(&[&op], &mut atoms, &start, Vec::new(), &mut budget, usize::MAX);
        assert!(fix.instances.len() == 0 && !fix.truncated);
    }
}
