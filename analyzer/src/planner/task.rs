//! The planning task: the problem's ground model in the form the planner
//! searches (section 4.1 of the HiPOP paper), compiled from grounding
//! ([`crate::verify::ground`]) and the domain's model.
//!
//! Unlike the STRIPS view the lints use, the planner keeps *when* each
//! condition and effect applies: an operator has a start and an end time
//! point (one for an `:action`), a condition is needed at one of them and
//! protected until one of them (`at start`: start–start, `over all`:
//! start–end, `at end`: end–end), an effect happens at one of them. Literals
//! are signed atoms, so negative conditions are supported like positive ones
//! (supported by a deletion, or by the closed-world initial state).
//!
//! Numeric conditions, effects and durations on the fluents effects change
//! are compiled for [`super::numeric`]: conditions at the start or the end
//! on one such fluent, effects whose value reads no such fluent, durations
//! that read one at the start.
//!
//! What the planner cannot follow is reported here, located, before any
//! search ([`Unsupported`]): other numeric conditions (`over all`, or
//! comparing two fluents that effects change), disjunctions and quantifiers
//! in conditions, conditional and quantified effects, durations that are
//! not one number nor read one changing fluent, method effects, grounding
//! past its limits, `:htn` parameters with too many bindings.

use rustc_hash::FxHashMap;

use super::PlannerLimits;
use super::numeric::{NumCond, NumDuration, NumEff, Numeric};
use crate::db::{Db, Item, Section, Unit, UnitKind, lower_item};
use crate::eval::NumOp;
use crate::model::{
    ActionKind, CmpOp, Effect, Endpoint, Gd, ItemData, Method, NumExpr, Ordering, Str, TaskNetwork, Term,
    TimeSpec, Typed,
};
use crate::semantics::check::{domain_for, gd_span};
use crate::semantics::symbols::Loc;
use crate::verify::ground::{
    Ground, Limits, MethodEvent, UNBOUND, ground_planner, ground_relevant, visit_methods,
};
use crate::verify::lifted::{OperatorKind, method_schema};
use crate::verify::state::{AtomId, ObjId, PredId};

/// A signed atom: `atom * 2`, plus 1 when negated.
pub type Lit = u32;

pub fn lit(atom: AtomId, negated: bool) -> Lit {
    atom * 2 + negated as u32
}

pub fn atom_of(l: Lit) -> AtomId {
    l / 2
}

pub fn is_neg(l: Lit) -> bool {
    l & 1 == 1
}

pub fn negate(l: Lit) -> Lit {
    l ^ 1
}

/// One end of a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum End {
    Start,
    End,
}

/// A condition: the literal must hold at `at` and stay true until `until`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cond<'db> {
    pub lit: Lit,
    pub at: End,
    pub until: End,
    pub loc: Loc<'db>,
}

/// An effect: the literal becomes true (a negative one: the atom false) at `at`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Eff {
    pub lit: Lit,
    pub at: End,
}

impl<'db> Op<'db> {
    /// A choice among ground instances (an `:htn` task with free
    /// parameters, a split subtask): abstract, one method per instance.
    fn choice(item: Item<'db>, name: Str, methods: Vec<u32>) -> Op<'db> {
        Op {
            item,
            name,
            args: Vec::new(),
            is_abstract: true,
            instant: false,
            duration: None,
            conds: Vec::new(),
            effs: Vec::new(),
            conflicts: Vec::new(),
            agents: Vec::new(),
            allowed: false,
            methods,
            dead: false,
            choice: true,
            num_conds: Vec::new(),
            num_effs: Vec::new(),
            num_duration: None,
        }
    }
}

/// A ground action (elementary) or task (abstract), Definitions 2 and 3.
#[derive(Debug, Clone)]
pub struct Op<'db> {
    pub item: Item<'db>,
    pub name: Str,
    pub args: Vec<ObjId>,
    pub is_abstract: bool,
    /// An `:action`: one time point (start and end are the same happening).
    pub instant: bool,
    /// The duration; `None` for a task without one (its subtasks decide).
    pub duration: Option<f64>,
    pub conds: Vec<Cond<'db>>,
    pub effs: Vec<Eff>,
    /// `:conflicts` (Definition 11): predicate and arguments, `None` for a wildcard.
    pub conflicts: Vec<(PredId, Vec<Option<ObjId>>)>,
    pub agents: Vec<ObjId>,
    /// In 𝒜: the planner may insert it to support a condition (4.2.2).
    pub allowed: bool,
    /// Its method instances (abstract operators), indices in [`Task::methods`].
    pub methods: Vec<u32>,
    /// Some condition can never hold (an atom no operator adds): never usable.
    pub dead: bool,
    /// The choice of an `:htn` task's arguments, or of a split subtask's
    /// (its methods are the task's ground instances): not an operator of
    /// the domain, and not written in plans (its child is a root, or a
    /// subtask of the choice's parent).
    pub choice: bool,
    /// Numeric conditions, effects and a duration that read or write the
    /// resources the search follows ([`super::numeric`]).
    pub num_conds: Vec<NumCond<'db>>,
    pub num_effs: Vec<NumEff<'db>>,
    pub num_duration: Option<NumDuration<'db>>,
}

impl Op<'_> {
    pub fn conflicts_with(&self, g: &Ground<'_>, atom: AtomId) -> bool {
        self.conflicts.iter().any(|(p, args)| {
            *p == g.atoms.pred(atom)
                && args.len() == g.atoms.args(atom).len()
                && args.iter().zip(g.atoms.args(atom)).all(|(a, b)| a.is_none_or(|a| a == *b))
        })
    }
}

/// An ordering between two subtasks of a network: `to`'s point is at least
/// `ε` (`strict`) or `0` after `from`'s.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NetOrder {
    pub from: (usize, End),
    pub to: (usize, End),
    pub strict: bool,
}

/// An instance of a method (Definition 6: a partial plan refining a task).
#[derive(Debug, Clone)]
pub struct MethodInst<'db> {
    pub item: Item<'db>,
    pub name: Str,
    pub task: u32,
    /// The subtasks' operators, in the order written, with their ids.
    pub subtasks: Vec<(Option<Str>, u32)>,
    pub orders: Vec<NetOrder>,
    /// Conditions at the start of the refined step (HDDL method preconditions).
    pub pre: Vec<Cond<'db>>,
}

/// A timed initial literal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Til<'db> {
    pub time: f64,
    pub lit: Lit,
    pub loc: Loc<'db>,
}

/// The problem's initial task network (`:htn`).
#[derive(Debug, Clone, Default)]
pub struct Network<'db> {
    pub tasks: Vec<(u32, Loc<'db>)>,
    pub orders: Vec<NetOrder>,
}

/// A construct the planner does not support, where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Unsupported<'db> {
    pub loc: Loc<'db>,
    pub what: String,
}

/// A position family instance (`at r1 *`) whose positions have move actions
/// (Definition 14, section 4.3.2): the planner reasons on it geometrically.
#[derive(Debug, Clone)]
pub struct MotionGroup {
    /// Its atoms (positions), index = local position id.
    pub positions: Vec<AtomId>,
    /// Shortest move durations between positions (row-major, `INFINITY` when
    /// no chain of moves connects them), and the first move of such a chain.
    pub dist: Vec<f64>,
    pub next_move: Vec<u32>,
}

impl MotionGroup {
    pub fn n(&self) -> usize {
        self.positions.len()
    }

    pub fn dist(&self, from: usize, to: usize) -> f64 {
        self.dist[from * self.n() + to]
    }
}

/// The planning task.
#[derive(Clone)]
pub struct Task<'db> {
    pub g: &'db Ground<'db>,
    pub problem: Unit<'db>,
    pub ops: Vec<Op<'db>>,
    pub methods: Vec<MethodInst<'db>>,
    /// Operators in 𝒜 with an effect, by literal (insertion resolvers).
    pub achievers: FxHashMap<Lit, Vec<(u32, End)>>,
    pub init: Vec<bool>,
    pub tils: Vec<Til<'db>>,
    pub goals: Vec<(Lit, Loc<'db>)>,
    /// A goal that can never hold (an atom no action makes true, a static
    /// atom false in the initial state, or its negation true): no plan.
    pub impossible_goal: Option<Loc<'db>>,
    /// The ground initial task networks: one per binding of the `:htn`
    /// parameters that has ground tasks (one when it has none); the planner
    /// starts from each.
    pub htn: Option<Vec<Network<'db>>>,
    /// Pure HTN problem: an `:htn` and no `(:allowed-actions …)`.
    pub pure_htn: bool,
    /// Per atom: its position family group and local position, if any
    /// (families confirmed by model verification, Definition 12).
    pub family: Vec<Option<(u32, u32)>>,
    /// Per family group: its motion data, when it has move actions.
    pub motion: Vec<Option<MotionGroup>>,
    /// Number of family groups.
    pub groups: usize,
    /// Move operators (by op index): their group, from and to positions.
    pub moves: FxHashMap<u32, (u32, u32, u32)>,
    /// Per operator: the [`Task::touches`] bits of its effects, all bits
    /// for one with `:conflicts` (it may threaten any link). Empty until
    /// [`Task::index_effects`]; then a step whose bits share none with a
    /// link's cannot threaten it.
    pub op_touches: Vec<u64>,
    /// `g` is [`ground_relevant`]'s (else [`ground_planner`]'s).
    pub goal_relevance: bool,
    /// The numeric fluents the search follows.
    pub numeric: Numeric,
}

impl<'db> Task<'db> {
    pub fn holds_initially(&self, l: Lit) -> bool {
        self.init.get(atom_of(l) as usize).copied().unwrap_or(false) != is_neg(l)
    }

    pub fn show_lit(&self, l: Lit) -> String {
        let a = self.g.show_atom(atom_of(l));
        if is_neg(l) { format!("(not {a})") } else { a }
    }

    pub fn show_op(&self, op: u32) -> String {
        let o = &self.ops[op as usize];
        crate::verify::ground::show(&o.name, &o.args, &self.g.objects)
    }

    /// Recomputes [`Task::achievers`] after a change of 𝒜 or of the methods.
    pub fn rebuild_achievers(&mut self) {
        self.achievers.clear();
        for (i, op) in self.ops.iter().enumerate() {
            if !op.allowed || op.dead || (op.is_abstract && op.methods.is_empty()) {
                continue;
            }
            for e in &op.effs {
                // An operator's entries are pushed together: a literal it
                // adds at both ends is the last entry when seen again (a
                // search of the whole list was quadratic in the achievers
                // of a literal, 10 s on Depots hand-coded 5's 732,900).
                let v = self.achievers.entry(e.lit).or_default();
                if v.last().is_none_or(|&(o, _)| o != i as u32) {
                    v.push((i as u32, e.at));
                }
            }
        }
    }

    /// A 64-bit summary of what literal `l` is about: a bit for its atom
    /// and, for a position of a family (positive), a bit for its group. A
    /// step threatens a link only through an effect on the link's atom
    /// (Definition 8) or a position of the same group (Definition 13), so
    /// the bits of the two share one at least.
    pub fn touches(&self, l: Lit) -> u64 {
        const MIX: u64 = 0x9E37_79B9_7F4A_7C15;
        let bit = |x: u64| 1u64 << (x.wrapping_mul(MIX) >> 58);
        let atom = atom_of(l);
        let group = if is_neg(l) { None } else { self.family.get(atom as usize).copied().flatten() };
        bit(2 * u64::from(atom)) | group.map_or(0, |(g, _)| bit(2 * u64::from(g) + 1))
    }

    /// Computes [`Task::op_touches`]; again after a change of the effects,
    /// the families or the conflicts.
    pub fn index_effects(&mut self) {
        self.op_touches = self
            .ops
            .iter()
            .map(|o| {
                if o.conflicts.is_empty() {
                    o.effs.iter().fold(0, |acc, e| acc | self.touches(e.lit))
                } else {
                    u64::MAX
                }
            })
            .collect();
    }

    /// Whether an atom is a position of a group with move actions.
    pub fn motion_of(&self, atom: AtomId) -> Option<(&MotionGroup, u32, u32)> {
        let (group, pos) = self.family.get(atom as usize).copied().flatten()?;
        self.motion[group as usize].as_ref().map(|m| (m, group, pos))
    }
}

type Binding = Vec<(Str, ObjId)>;

/// The initial task networks a problem's `:htn` parameters may give.
const MAX_HTN_BINDINGS: usize = 10_000;

/// The instances a universally quantified condition may stand for.
const MAX_FORALL_INSTANCES: usize = 10_000;

struct Compiler<'a, 'db> {
    db: &'db dyn Db,
    g: &'a Ground<'db>,
    unsupported: Vec<Unsupported<'db>>,
    /// Compiling the goal: grounding checked the static conditions of the
    /// operators, not those of the goal, so a static goal atom is checked
    /// here against the initial state.
    goal: bool,
    /// The resources met so far, and the numeric conditions and effects of
    /// the operator being compiled.
    num: Numeric,
    num_conds: Vec<NumCond<'db>>,
    num_effs: Vec<NumEff<'db>>,
    /// Per resource: read by a condition or a duration, or written other
    /// than by `increase`/`decrease` (VAL's mutex then orders its writers).
    followed: Vec<bool>,
}

impl<'db> Compiler<'_, 'db> {
    fn term(&self, t: &Term, b: &Binding) -> Option<ObjId> {
        match t {
            Term::Var(n) => b.iter().rev().find(|(k, _)| *k == n.key()).map(|(_, o)| *o),
            Term::Const(n) => self.g.objects.id(n.key()),
            _ => None,
        }
    }

    fn unsupported(&mut self, item: Item<'db>, span: rowan::TextRange, what: &str) {
        let loc = Loc { item, span };
        if !self.unsupported.iter().any(|u| u.loc == loc) {
            self.unsupported.push(Unsupported { loc, what: what.to_string() });
        }
    }

    /// The literal of an atom under a binding: `Ok(None)` for a static atom
    /// (grounding checked it), `Err(())` when the atom occurs nowhere (a
    /// positive condition on it can never hold).
    fn atom(&mut self, item: Item<'db>, a: &crate::model::Atom, b: &Binding) -> Result<Option<AtomId>, ()> {
        let Some(pred) = self.g.predicates.get(a.pred.key()) else { return Err(()) };
        if self.g.is_static(pred) && !self.goal {
            return Ok(None);
        }
        let mut args = smallvec::SmallVec::<[ObjId; 4]>::new();
        for t in &a.args {
            match self.term(t, b) {
                Some(o) => args.push(o),
                None => {
                    self.unsupported(item, a.span, "a term the planner cannot name (an object fluent)");
                    return Ok(None);
                }
            }
        }
        let found = self.g.atoms.find(pred, &args);
        if self.g.is_static(pred) {
            // A goal on a static predicate: true or false for ever.
            return match found {
                Some(atom) if self.g.init.holds(atom) => Ok(None),
                _ => Err(()),
            };
        }
        found.map(Some).ok_or(())
    }

    /// Collects the conditions of `gd` at `time` (`None`: untimed).
    fn conds(
        &mut self,
        item: Item<'db>,
        gd: &'db Gd,
        b: &Binding,
        time: Option<TimeSpec>,
        out: &mut Vec<Cond<'db>>,
        dead: &mut bool,
    ) {
        let (at, until) = match time {
            None | Some(TimeSpec::AtStart) => (End::Start, End::Start),
            Some(TimeSpec::OverAll) => (End::Start, End::End),
            Some(TimeSpec::AtEnd) => (End::End, End::End),
        };
        match gd {
            Gd::And(gs, _) => gs.iter().for_each(|g| self.conds(item, g, b, time, out, dead)),
            Gd::Timed(spec, inner, _) => self.conds(item, inner, b, Some(*spec), out, dead),
            Gd::Atom(a) => match self.atom(item, a, b) {
                Ok(Some(atom)) => {
                    out.push(Cond { lit: lit(atom, false), at, until, loc: Loc { item, span: a.span } })
                }
                Ok(None) => {}
                Err(()) => *dead = true,
            },
            Gd::Not(inner, span) => match inner.as_ref() {
                Gd::Atom(a) => match self.atom(item, a, b) {
                    Ok(Some(atom)) => {
                        out.push(Cond { lit: lit(atom, true), at, until, loc: Loc { item, span: *span } })
                    }
                    // A static goal atom that holds: its negation never will.
                    Ok(None) if self.goal => *dead = true,
                    Ok(None) | Err(()) => {}
                },
                // Grounding enforced (in)equalities.
                Gd::Equal(..) => {}
                other => self.unsupported(item, gd_span(other), "a negated formula in a condition"),
            },
            Gd::Equal(..) => {}
            Gd::Compare(_, l, r, span) => self.numeric_cond(item, gd, [l, r], *span, b, time, dead),
            Gd::Or(_, s) => self.unsupported(item, *s, "a disjunctive condition"),
            Gd::Imply(_, _, s) => self.unsupported(item, *s, "an implication in a condition"),
            Gd::Forall(vars, inner, s) => {
                // Over finitely many objects: the conjunction of its instances.
                let (domains, count) = var_domains(self.g, vars);
                if count > MAX_FORALL_INSTANCES {
                    self.unsupported(
                        item,
                        *s,
                        &format!(
                            "a universally quantified condition over more than {MAX_FORALL_INSTANCES} objects ({count})"
                        ),
                    );
                    return;
                }
                each_binding(vars, &domains, |inst| {
                    let mut b2 = b.clone();
                    b2.extend(inst);
                    self.conds(item, inner, &b2, time, out, dead);
                });
            }
            Gd::Exists(_, _, s) => self.unsupported(item, *s, "an existentially quantified condition"),
            other => self.unsupported(item, gd_span(other), "a condition the planner cannot follow"),
        }
    }

    /// The ground fluents some effect changes that `e` reads, as resources;
    /// `Err` with where and what when it reads what the planner cannot
    /// follow.
    fn dynamic_reads(
        &mut self,
        e: &NumExpr,
        b: &Binding,
        duration_ok: bool,
        out: &mut Vec<u32>,
    ) -> Result<(), (rowan::TextRange, &'static str)> {
        match e {
            NumExpr::Number(_) => Ok(()),
            NumExpr::Fluent(f) => {
                let Some(func) = self.g.functions.get(f.func.key()) else { return Ok(()) };
                if !self.g.dynamic_funcs.get(func as usize).copied().unwrap_or(false) {
                    return Ok(());
                }
                let mut key = vec![func];
                for t in &f.args {
                    match self.term(t, b) {
                        Some(o) => key.push(o),
                        None => return Err((f.span, "a fluent with a term the planner cannot name")),
                    }
                }
                let r = self.num.resource(&key);
                if !out.contains(&r) {
                    out.push(r);
                }
                Ok(())
            }
            NumExpr::Op(_, xs, _) => xs.iter().try_for_each(|x| self.dynamic_reads(x, b, duration_ok, out)),
            NumExpr::Duration(span) if !duration_ok => Err((*span, "`?duration` in a condition")),
            NumExpr::Duration(_) => Ok(()),
            NumExpr::Special(_, span) => Err((*span, "`#t` or `total-time` in an action")),
            NumExpr::TaskDuration(_, span) => Err((*span, "a subtask's duration in an action")),
            NumExpr::Var(n) => Err((n.span, "an object used as a number")),
        }
    }

    /// A numeric condition: one that reads no changing fluent is checked
    /// against `:init` here; one that reads one is a [`NumCond`] at the
    /// start or the end; anything else is refused.
    #[allow(clippy::too_many_arguments)]
    fn numeric_cond(
        &mut self,
        item: Item<'db>,
        gd: &'db Gd,
        sides: [&NumExpr; 2],
        span: rowan::TextRange,
        b: &Binding,
        time: Option<TimeSpec>,
        dead: &mut bool,
    ) {
        let mut reads = Vec::new();
        for side in sides {
            if let Err((at, what)) = self.dynamic_reads(side, b, false, &mut reads) {
                self.unsupported(item, at, &format!("{what} (in a numeric condition)"));
                return;
            }
        }
        match reads.as_slice() {
            [] => {
                if !self.num.holds_static(self.g, gd, b) {
                    *dead = true;
                }
            }
            &[res] => {
                if self.goal {
                    self.unsupported(item, span, "a numeric goal on a fluent that effects change");
                    return;
                }
                let at = match time {
                    None | Some(TimeSpec::AtStart) => End::Start,
                    Some(TimeSpec::AtEnd) => End::End,
                    Some(TimeSpec::OverAll) => {
                        self.unsupported(
                            item,
                            span,
                            "a numeric condition `over all` on a fluent that effects change",
                        );
                        return;
                    }
                };
                self.followed.resize(self.num.keys.len(), false);
                self.followed[res as usize] = true;
                self.num_conds.push(NumCond { res, at, gd, vars: b.clone().into(), loc: Loc { item, span } });
            }
            _ => {
                self.unsupported(item, span, "a numeric condition comparing two fluents that effects change")
            }
        }
    }

    /// A numeric effect: on a fluent the search follows, a [`NumEff`];
    /// its value may read `?duration` and fluents nothing changes.
    #[allow(clippy::too_many_arguments)]
    fn numeric_eff(
        &mut self,
        item: Item<'db>,
        name: &str,
        f: &crate::model::Fluent,
        value: &'db NumExpr,
        span: rowan::TextRange,
        b: &Binding,
        time: Option<TimeSpec>,
    ) {
        let Some(op) = NumOp::parse(name) else {
            self.unsupported(item, span, &format!("the numeric effect `{name}`"));
            return;
        };
        let mut reads = Vec::new();
        if let Err((at, what)) = self.dynamic_reads(value, b, time.is_some(), &mut reads) {
            self.unsupported(item, at, &format!("{what} (in a numeric effect)"));
            return;
        }
        if !reads.is_empty() {
            self.unsupported(item, span, "a numeric effect whose value reads a fluent that effects change");
            return;
        }
        let mut target = Vec::new();
        if let Err((at, what)) =
            self.dynamic_reads(&NumExpr::Fluent(Box::new(f.clone())), b, false, &mut target)
        {
            self.unsupported(item, at, what);
            return;
        }
        let Some(&res) = target.first() else { return };
        self.followed.resize(self.num.keys.len(), false);
        if !op.is_additive() {
            self.followed[res as usize] = true;
        }
        let at = match time {
            Some(TimeSpec::AtStart) => End::Start,
            _ => End::End,
        };
        self.num_effs.push(NumEff { res, at, op, value, vars: b.clone().into() });
    }

    /// The duration of a durative action that reads a fluent effects
    /// change: `(= ?duration e)` with `e` reading one such fluent.
    fn numeric_duration(&mut self, d: &'db Gd, b: &Binding) -> Option<NumDuration<'db>> {
        let Gd::Compare(CmpOp::Eq, l, r, _) = d else { return None };
        let expr = match (&**l, &**r) {
            (NumExpr::Duration(_), e) | (e, NumExpr::Duration(_)) => e,
            _ => return None,
        };
        let mut reads = Vec::new();
        self.dynamic_reads(expr, b, false, &mut reads).ok()?;
        let &[res] = reads.as_slice() else { return None };
        self.followed.resize(self.num.keys.len(), false);
        self.followed[res as usize] = true;
        Some(NumDuration { res, expr, vars: b.clone().into() })
    }

    fn effs(
        &mut self,
        item: Item<'db>,
        e: &'db Effect,
        b: &Binding,
        time: Option<TimeSpec>,
        out: &mut Vec<Eff>,
    ) {
        // Untimed effects happen at the end (an `:action` has one time point;
        // an abstract action's effects hold once it is done).
        let at = match time {
            Some(TimeSpec::AtStart) => End::Start,
            _ => End::End,
        };
        match e {
            Effect::And(es, _) => es.iter().for_each(|e| self.effs(item, e, b, time, out)),
            // PDDL 2.1 has no `over all` effects; the validator refuses them too.
            Effect::Timed(TimeSpec::OverAll, _, s) => {
                self.unsupported(item, *s, "an `over all` effect (continuous change)")
            }
            Effect::Timed(spec, inner, _) => self.effs(item, inner, b, Some(*spec), out),
            Effect::Add(a) => {
                if let Ok(Some(atom)) = self.atom(item, a, b) {
                    out.push(Eff { lit: lit(atom, false), at });
                }
            }
            Effect::Del(a, _) => {
                if let Ok(Some(atom)) = self.atom(item, a, b) {
                    out.push(Eff { lit: lit(atom, true), at });
                }
            }
            Effect::Numeric(name, f, value, span) => self.numeric_eff(item, name, f, value, *span, b, time),
            Effect::Forall(_, _, s) => self.unsupported(item, *s, "a universally quantified effect"),
            Effect::When(_, _, s) => self.unsupported(item, *s, "a conditional effect"),
        }
    }
}

fn binding(params: &[Typed], args: &[ObjId]) -> Binding {
    params.iter().zip(args).map(|(p, &o)| (p.name.key_str(), o)).collect()
}

/// The objects of each variable's types, and how many bindings they make.
fn var_domains(g: &Ground<'_>, vars: &[Typed]) -> (Vec<Vec<ObjId>>, usize) {
    let domains: Vec<Vec<ObjId>> =
        vars.iter().map(|v| g.objects.of_types(&crate::semantics::symbols::type_set(&v.ty))).collect();
    let count = domains.iter().fold(1usize, |n, d| n.saturating_mul(d.len()));
    (domains, count)
}

/// Calls `f` with every binding of `vars` to objects of their `domains`
/// (none when a domain is empty), the last variable varying fastest.
fn each_binding(vars: &[Typed], domains: &[Vec<ObjId>], mut f: impl FnMut(Binding)) {
    if domains.iter().any(Vec::is_empty) {
        return;
    }
    let mut choice = vec![0usize; domains.len()];
    loop {
        f(vars.iter().zip(domains).zip(&choice).map(|((v, d), &k)| (v.name.key_str(), d[k])).collect());
        let Some(k) = (0..choice.len()).rev().find(|&k| choice[k] + 1 < domains[k].len()) else { return };
        choice[k] += 1;
        choice[k + 1..].fill(0);
    }
}

fn agents(params: &[Typed], agent: &[crate::model::Name], args: &[ObjId]) -> Vec<ObjId> {
    agent
        .iter()
        .filter_map(|a| {
            params.iter().position(|p| p.name.key() == a.key()).and_then(|i| args.get(i).copied())
        })
        .collect()
}

/// Compiles a problem into a planning task, or says what the planner does
/// not support in it. `types`: the position families of one key type too
/// (the configuration's `types`).
pub fn compile<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    limits: &PlannerLimits,
    types: bool,
) -> Result<Task<'db>, Vec<Unsupported<'db>>> {
    let none = |what: &str| {
        vec![Unsupported {
            loc: Loc { item: problem.items(db)[0], span: rowan::TextRange::default() },
            what: what.to_string(),
        }]
    };
    if problem.kind(db) != UnitKind::Problem || problem.items(db).is_empty() {
        return Err(Vec::new());
    }
    let Some(domain) = domain_for(db, problem) else { return Err(none("a problem without its domain")) };
    let g: &'db Ground<'db> =
        if limits.goal_relevance { ground_relevant(db, problem) } else { ground_planner(db, problem) };
    let mut c = Compiler {
        db,
        g,
        unsupported: Vec::new(),
        goal: false,
        num: Numeric::new(&g.init),
        num_conds: Vec::new(),
        num_effs: Vec::new(),
        followed: Vec::new(),
    };
    if g.truncated {
        return Err(none(&too_large(g)));
    }

    // Problem sections.
    let mut allowed_names: Option<Vec<Str>> = None;
    let mut goal: Vec<(Item<'db>, &'db Gd)> = Vec::new();
    let mut htn_item: Option<(Item<'db>, &'db crate::model::Htn)> = None;
    for &item in problem.items(db) {
        match (&lower_item(db, item).data, item.section(db)) {
            (ItemData::AllowedActions(names), _) => {
                allowed_names.get_or_insert_with(Vec::new).extend(names.iter().map(|n| n.key_str()))
            }
            (ItemData::Goal(gd), _) => goal.push((item, gd)),
            (ItemData::Htn(h), _) => htn_item = Some((item, h)),
            (ItemData::Constraints(gd), _) => c.unsupported(item, gd_span(gd), "PDDL 3 constraints"),
            _ => {}
        }
    }
    let pure_htn = htn_item.is_some() && allowed_names.is_none();
    for &item in domain.items(db) {
        match &lower_item(db, item).data {
            ItemData::Derived(a, _, _) => c.unsupported(item, a.span, "derived predicates"),
            ItemData::Constraints(gd) => c.unsupported(item, gd_span(gd), "PDDL 3 constraints"),
            _ => {}
        }
    }

    // Operators, in the order of `g.operators`.
    let mut ops: Vec<Op<'db>> = Vec::with_capacity(g.operators.len());
    let mut schema_used = vec![false; g.schemas.len()];
    for o in &g.operators {
        let schema = &g.schemas[o.schema as usize];
        let args = g.args(o).to_vec();
        let item = o.op;
        let mut op = Op {
            item,
            name: schema.name.clone(),
            args: args.clone(),
            is_abstract: schema.kind == OperatorKind::Task,
            instant: schema.kind == OperatorKind::Action,
            duration: None,
            conds: Vec::new(),
            effs: Vec::new(),
            conflicts: Vec::new(),
            agents: Vec::new(),
            allowed: match &allowed_names {
                Some(names) => names.contains(&schema.name),
                None => !pure_htn,
            },
            methods: Vec::new(),
            dead: false,
            choice: false,
            num_conds: Vec::new(),
            num_effs: Vec::new(),
            num_duration: None,
        };
        let report = !schema_used[o.schema as usize];
        schema_used[o.schema as usize] = true;
        let before = c.unsupported.len();
        match &lower_item(db, item).data {
            ItemData::Action(a) => {
                let b = binding(&a.params, &args);
                op.agents = agents(&a.params, &a.agent, &args);
                if matches!(a.kind, ActionKind::Process | ActionKind::Event) {
                    c.unsupported(item, a.name.span, "PDDL+ processes and events");
                }
                if let Some(pre) = &a.precondition {
                    let mut dead = false;
                    c.conds(item, pre, &b, None, &mut op.conds, &mut dead);
                    op.dead = dead;
                }
                if let Some(e) = &a.effect {
                    c.effs(item, e, &b, None, &mut op.effs);
                }
                op.duration = match a.kind {
                    ActionKind::Action => Some(0.0),
                    _ => o.duration(),
                };
                if o.no_duration {
                    // Undefined in this problem (a fluent without value): PDDL
                    // 2.1 never applies the instance.
                    op.dead = true;
                } else if op.duration.is_none() {
                    // A duration that reads a fluent effects change: fixed
                    // once the step's place among the steps that change
                    // that fluent is known.
                    match a.duration.as_ref().and_then(|d| c.numeric_duration(d, &b)) {
                        Some(d) => op.num_duration = Some(d),
                        None => {
                            let span = a.duration.as_ref().map_or(a.name.span, gd_span);
                            c.unsupported(
                                item,
                                span,
                                "a duration that is not one number (bounds, or an expression over several fluents that effects change)",
                            );
                        }
                    }
                }
            }
            ItemData::Task(t) => {
                let b = binding(&t.params, &args);
                op.agents = agents(&t.params, &t.agent, &args);
                if let Some(pre) = &t.precondition {
                    let mut dead = false;
                    c.conds(item, pre, &b, None, &mut op.conds, &mut dead);
                    op.dead = dead;
                }
                if let Some(e) = &t.effect {
                    c.effs(item, e, &b, None, &mut op.effs);
                }
                op.duration = o.duration();
                if o.no_duration {
                    op.dead = true;
                } else if op.duration.is_none()
                    && let Some(d) = &t.duration
                    && !matches!(d, Gd::Compare(CmpOp::Eq, ..))
                {
                    c.unsupported(item, gd_span(d), "a task duration that is not one number");
                }
                if let Some(conf) = &t.conflicts {
                    for a in &conf.atoms {
                        let Some(pred) = g.predicates.get(a.pred.key()) else { continue };
                        let args = a.args.iter().map(|t| c.term(t, &b)).collect();
                        op.conflicts.push((pred, args));
                    }
                }
            }
            _ => op.dead = true,
        }
        op.num_conds = std::mem::take(&mut c.num_conds);
        op.num_effs = std::mem::take(&mut c.num_effs);
        if op.is_abstract && !(op.num_conds.is_empty() && op.num_effs.is_empty()) {
            let loc = op.num_conds.first().map_or(Loc { item, span: rowan::TextRange::default() }, |n| n.loc);
            c.unsupported(loc.item, loc.span, "numeric conditions or effects of an abstract task");
        }
        if !report {
            c.unsupported.truncate(before);
        }
        // Deletions happen before additions: a deletion of an atom that the
        // same time point adds has no effect.
        let effs = op.effs.clone();
        op.effs.retain(|e| !(is_neg(e.lit) && effs.iter().any(|f| f.at == e.at && f.lit == negate(e.lit))));
        // A durative action of duration 0 is one happening: its start and
        // end must not interfere (VAL's mutex), or it is in no valid plan.
        if !op.instant && op.duration == Some(0.0) {
            let touched = |at: End| -> Vec<AtomId> {
                op.effs.iter().filter(|e| e.at == at).map(|e| atom_of(e.lit)).collect()
            };
            let (starts, ends) = (touched(End::Start), touched(End::End));
            let mut end_reads = op.conds.iter().filter(|c| c.at == End::End).map(|c| atom_of(c.lit));
            if starts.iter().any(|a| ends.contains(a)) || end_reads.any(|a| starts.contains(&a)) {
                op.dead = true;
            }
        }
        ops.push(op);
    }

    // Where each operator instance is, for method subtasks.
    let mut op_index: FxHashMap<(Str, &[ObjId]), u32> = FxHashMap::default();
    for (i, o) in g.operators.iter().enumerate() {
        op_index.insert((g.schemas[o.schema as usize].name.clone(), g.args(o)), i as u32);
    }

    // Methods.
    let mut methods: Vec<MethodInst<'db>> = Vec::new();
    let method_limits = Limits { method_instances: limits.method_instances, ..Limits::PLANNER };
    let mut truncated: Vec<(Item<'db>, usize)> = Vec::new();
    let mut cache: FxHashMap<Item<'db>, Option<&'db Method>> = FxHashMap::default();
    // Instances of the method being visited, to say why it was cut.
    let mut visited = 0usize;
    // The subtasks split off their methods: each is an abstract operator
    // (after the others) choosing among its ground instances.
    let split_base = ops.len() as u32;
    let split_index: FxHashMap<(Item<'db>, usize, &[ObjId]), u32> = g
        .tdg_splits
        .iter()
        .enumerate()
        .map(|(x, s)| ((s.method, s.subtask, &s.args[..]), split_base + x as u32))
        .collect();
    visit_methods(db, problem, g, method_limits, &mut |event| match event {
        MethodEvent::Instance(m) => {
            visited += 1;
            let method = *cache.entry(m.method).or_insert_with(|| match &lower_item(db, m.method).data {
                ItemData::Method(me) => Some(&**me),
                _ => None,
            });
            let Some(method) = method else { return };
            let Some(&task) = op_index.get(&(Str::from(m.task), m.task_args)) else { return };
            let mut subtasks = Vec::new();
            for (i, ((name, args), st)) in m.subtasks().zip(&method.network.subtasks).enumerate() {
                let op = if args.contains(&UNBOUND) {
                    split_index.get(&(m.method, i, args))
                } else {
                    op_index.get(&(Str::from(name), args))
                };
                let Some(&op) = op else { return };
                subtasks.push((st.id.as_ref().map(|n| n.key_str()), op));
            }
            let b = binding(&method.params, m.binding);
            let mut pre = Vec::new();
            let mut dead = false;
            if let Some(p) = &method.precondition {
                c.conds(m.method, p, &b, None, &mut pre, &mut dead);
            }
            // `:constraints`: grounding enforced their (in)equalities; an
            // atom there is a condition like the precondition's.
            if let Some(g) = &method.network.constraints {
                c.conds(m.method, g, &b, None, &mut pre, &mut dead);
            }
            if let Some(n) = c.num_conds.first() {
                let loc = n.loc;
                c.num_conds.clear();
                c.unsupported(
                    loc.item,
                    loc.span,
                    "a numeric method precondition on a fluent that effects change",
                );
            }
            if dead {
                return;
            }
            // Method preconditions are needed where the refined step starts.
            for p in &mut pre {
                p.at = End::Start;
                p.until = End::Start;
            }
            let orders = network_orders(&mut c, m.method, &method.network);
            methods.push(MethodInst {
                item: m.method,
                name: method.name.key_str(),
                task,
                subtasks,
                orders,
                pre,
            });
        }
        MethodEvent::Done(_) => visited = 0,
        MethodEvent::Truncated(item) => {
            truncated.push((item, visited));
            visited = 0;
        }
        MethodEvent::Skipped(item) => {
            visited = 0;
            c.unsupported(item, rowan::TextRange::default(), "method terms grounding cannot name")
        }
    });
    for (item, found) in truncated {
        if let ItemData::Method(m) = &lower_item(db, item).data {
            let what = if found >= method_limits.method_instances {
                format!(
                    "a method with more ground instances than hipop's limit of {}",
                    thousands(method_limits.method_instances as f64)
                )
            } else {
                format!(
                    "a method whose grounding ran past hipop's limit of {} parameter values tried ({} instances found)",
                    thousands(method_limits.candidates as f64),
                    thousands(found as f64)
                )
            };
            c.unsupported(item, m.name.span, &what);
        }
    }
    for &item in domain.items(db).iter().filter(|i| i.section(db) == Section::Method) {
        if let ItemData::Method(m) = &lower_item(db, item).data
            && let Some(e) = &m.effect
        {
            let span = match e {
                Effect::And(_, s) | Effect::Del(_, s) => *s,
                Effect::Add(a) => a.span,
                _ => m.name.span,
            };
            c.unsupported(item, span, "method effects");
        }
    }
    for split in &g.tdg_splits {
        let Some(name) =
            method_schema(db, split.method).as_ref().map(|m| m.subtasks[split.subtask].name.clone())
        else {
            continue;
        };
        let choice = ops.len() as u32;
        let mut item = None;
        for args in &split.choices {
            if let Some(&op) = op_index.get(&(name.clone(), &args[..])) {
                item.get_or_insert(ops[op as usize].item);
                methods.push(MethodInst {
                    item: split.method,
                    name: name.clone(),
                    task: choice,
                    subtasks: vec![(None, op)],
                    orders: Vec::new(),
                    pre: Vec::new(),
                });
            }
        }
        ops.push(Op::choice(item.unwrap_or(split.method), name, Vec::new()));
    }
    for (i, m) in methods.iter().enumerate() {
        ops[m.task as usize].methods.push(i as u32);
    }

    // Initial state, timed literals, goal.
    let init: Vec<bool> = (0..g.atoms.len() as AtomId).map(|a| g.init.holds(a)).collect();
    let tils = g
        .init
        .timed
        .iter()
        .map(|t| Til { time: t.time, lit: lit(t.atom, !t.positive), loc: t.loc })
        .collect();
    let mut goals = Vec::new();
    let mut impossible_goal = None;
    for (item, gd) in goal {
        let mut conds = Vec::new();
        let mut dead = false;
        c.goal = true;
        c.conds(item, gd, &Binding::new(), None, &mut conds, &mut dead);
        c.goal = false;
        if dead && impossible_goal.is_none() {
            impossible_goal = Some(Loc { item, span: gd_span(gd) });
        }
        goals.extend(conds.into_iter().map(|c| (c.lit, c.loc)));
    }

    // Initial task network.
    let htn = match htn_item {
        None => None,
        Some((item, h)) => {
            // `:htn :parameters`: every binding of them to objects of their
            // types is an initial task network to start from.
            let orders = network_orders(&mut c, item, &h.network);
            let mut nets = Vec::new();
            let mut missing = None;
            // Grounded top-down, with each parameter in one task at most:
            // one network, where a task with several ground instances is a
            // choice among them (a refinement, not one network per binding
            // of the parameters: Woodworking's have up to 2,000,000).
            let mut uses = vec![0usize; h.params.len()];
            for st in &h.network.subtasks {
                let mut seen = Vec::new();
                for t in st.call.args.iter() {
                    if let Term::Var(n) = t
                        && let Some(i) = h.params.iter().position(|p| p.name.key() == n.key())
                        && !seen.contains(&i)
                    {
                        seen.push(i);
                        uses[i] += 1;
                    }
                }
            }
            let choices = g.htn_choices.as_ref().filter(|_| uses.iter().all(|&u| u <= 1));
            if let Some(choices) = choices {
                let mut net = Network { tasks: Vec::new(), orders };
                for (st, found) in h.network.subtasks.iter().zip(choices) {
                    let loc = Loc { item, span: st.call.span };
                    let name = st.call.name.key_str();
                    let ground: Vec<u32> =
                        found.iter().filter_map(|a| op_index.get(&(name.clone(), &a[..])).copied()).collect();
                    match ground.as_slice() {
                        [] => {
                            missing.get_or_insert(st.call.span);
                        }
                        [one] => net.tasks.push((*one, loc)),
                        _ => {
                            let choice = ops.len() as u32;
                            for &op in &ground {
                                methods.push(MethodInst {
                                    item,
                                    name: name.clone(),
                                    task: choice,
                                    subtasks: vec![(None, op)],
                                    orders: Vec::new(),
                                    pre: Vec::new(),
                                });
                            }
                            let first = ground.len();
                            let between = ((methods.len() - first) as u32..methods.len() as u32).collect();
                            ops.push(Op::choice(ops[ground[0] as usize].item, name, between));
                            net.tasks.push((choice, loc));
                        }
                    }
                }
                if missing.is_none() {
                    nets.push(net);
                }
            } else {
                let (domains, count) = var_domains(g, &h.params);
                if count > MAX_HTN_BINDINGS {
                    c.unsupported(
                        item,
                        h.span,
                        &format!("`:htn` parameters with more than {MAX_HTN_BINDINGS} bindings ({count})"),
                    );
                } else {
                    each_binding(&h.params, &domains, |b| {
                        let mut net = Network { tasks: Vec::new(), orders: orders.clone() };
                        for st in &h.network.subtasks {
                            let args: Option<Vec<ObjId>> =
                                st.call.args.iter().map(|t| c.term(t, &b)).collect();
                            match args
                                .and_then(|a| op_index.get(&(st.call.name.key_str(), a.as_slice())).copied())
                            {
                                Some(op) => net.tasks.push((op, Loc { item, span: st.call.span })),
                                None => {
                                    missing.get_or_insert(st.call.span);
                                    return;
                                }
                            }
                        }
                        nets.push(net);
                    });
                }
            }
            if nets.is_empty() && c.unsupported.is_empty() {
                return Err(vec![Unsupported {
                    loc: Loc { item, span: missing.unwrap_or(h.span) },
                    what: "an `:htn` task with no ground instance (its arguments' types or static preconditions rule it out, or none can be decomposed into reachable actions)".into(),
                }]);
            }
            Some(nets)
        }
    };

    if !c.unsupported.is_empty() {
        return Err(c.unsupported);
    }

    // Numeric effects on fluents nothing reads and that only increase or
    // decrease are left to the validator (VAL lets such updates happen
    // together); the others' writers are the helpers of their conditions.
    let mut numeric = std::mem::take(&mut c.num);
    c.followed.resize(numeric.keys.len(), false);
    numeric.followed = c.followed.clone();
    for op in ops.iter_mut() {
        op.num_effs.retain(|e| c.followed[e.res as usize]);
    }
    numeric.prune(g, &mut ops);
    for (i, op) in ops.iter_mut().enumerate() {
        if op.allowed && !op.dead && !op.is_abstract {
            for e in &op.num_effs {
                let w = &mut numeric.writers[e.res as usize];
                if w.last() != Some(&(i as u32)) {
                    w.push(i as u32);
                }
            }
        }
    }

    let mut task = Task {
        g,
        goal_relevance: limits.goal_relevance,
        problem,
        ops,
        methods,
        achievers: FxHashMap::default(),
        init,
        tils,
        goals,
        impossible_goal,
        htn,
        pure_htn,
        family: vec![None; g.atoms.len()],
        motion: Vec::new(),
        groups: 0,
        moves: FxHashMap::default(),
        op_touches: Vec::new(),
        numeric,
    };
    super::motion::families(db, problem, &mut task, types);
    // The achievers in 𝒜; operators the numeric bounds ruled out support
    // nothing.
    task.rebuild_achievers();
    task.index_effects();
    Ok(task)
}

/// What a grounding past its limits says: how far it got, and the action or
/// task that dominates, with how many instances its parameters' candidate
/// objects allow.
fn too_large(g: &Ground<'_>) -> String {
    let relevant = if g.relevance { "reachable and relevant" } else { "reachable" };
    let stopped = if g.tried >= g.limits.candidates {
        format!(
            "grounding stopped at its limit of {} parameter values tried, with {} instances found",
            thousands(g.limits.candidates as f64),
            thousands(g.operators.len() as f64)
        )
    } else {
        format!("grounding stopped at its limit of {} ground instances", thousands(g.limits.operators as f64))
    };
    if let Some((method, found)) = &g.tdg_dominant {
        if *found == 0 {
            return format!(
                "a hierarchical problem whose ground model, grounded top-down from its `:htn`, exceeds hipop's limits: \
                 grounding stopped at {} tasks and method instances (or {} parameter values tried) while its methods \
                 requested their subtasks, before any method instance",
                thousands(g.limits.method_instances.max(g.limits.operators) as f64 * 3.0),
                thousands(g.limits.candidates as f64),
            );
        }
        return format!(
            "a hierarchical problem whose ground model, grounded top-down from its `:htn`, exceeds hipop's limits: \
             grounding stopped at {} tasks and method instances (or {} parameter values tried); `{method}` dominates, \
             with {} instances found",
            thousands(g.limits.method_instances.max(g.limits.operators) as f64 * 3.0),
            thousands(g.limits.candidates as f64),
            thousands(*found as f64)
        );
    }
    let mut text = format!("a problem whose {relevant} ground model exceeds hipop's limits: {stopped}");
    // The action or task with the most instances found; before any is
    // found, the one whose parameters allow the most.
    let dominant = g.schemas.iter().max_by(|a, b| {
        (a.end - a.start)
            .cmp(&(b.end - b.start))
            .then(a.candidate_instances().total_cmp(&b.candidate_instances()))
    });
    if let Some(s) = dominant.filter(|s| s.candidate_instances() > 0.0) {
        let factors: Vec<String> = s.candidates.iter().map(|c| c.to_string()).collect();
        text.push_str(&format!(
            "; `{}` dominates, with up to {} instances ({} objects for its parameters), {} of them found",
            s.name,
            approx(s.candidate_instances()),
            factors.join(" × "),
            thousands(f64::from(s.end - s.start)),
        ));
    }
    text
}

/// `1234567` as `1,234,567`.
fn thousands(x: f64) -> String {
    let digits = format!("{:.0}", x.max(0.0));
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A count that may be huge: exact up to a billion, then `8.1 × 10⁹`.
fn approx(x: f64) -> String {
    if x < 1e9 {
        return thousands(x);
    }
    let exp = x.log10().floor() as i32;
    let mantissa = x / 10f64.powi(exp);
    let sup: String = exp
        .to_string()
        .chars()
        .map(|c| match c {
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect();
    format!("{mantissa:.1} × 10{sup}")
}

/// The orderings of a task network over its subtasks' indices.
fn network_orders<'db>(c: &mut Compiler<'_, 'db>, item: Item<'db>, net: &TaskNetwork) -> Vec<NetOrder> {
    let mut out = Vec::new();
    let n = net.subtasks.len();
    if net.ordered {
        for i in 1..n {
            out.push(NetOrder { from: (i - 1, End::End), to: (i, End::Start), strict: true });
        }
        return out;
    }
    let index = |id: &str| net.subtasks.iter().position(|s| s.id.as_ref().is_some_and(|n| n.key() == id));
    for o in &net.ordering {
        let order: &Ordering = o;
        let (Some(l), Some(r)) = (index(order.left.id.key()), index(order.right.id.key())) else {
            continue;
        };
        if order.negated {
            c.unsupported(item, order.span, "a negated ordering");
            continue;
        }
        let point = |e: Endpoint, whole: End| match e {
            Endpoint::Whole => whole,
            Endpoint::Start => End::Start,
            Endpoint::End => End::End,
        };
        let lp = point(order.left.endpoint, End::End);
        let rp = point(order.right.endpoint, End::Start);
        match order.op {
            CmpOp::Lt => out.push(NetOrder { from: (l, lp), to: (r, rp), strict: true }),
            CmpOp::Le => out.push(NetOrder { from: (l, lp), to: (r, rp), strict: false }),
            CmpOp::Gt => {
                let lp = point(order.left.endpoint, End::Start);
                let rp = point(order.right.endpoint, End::End);
                out.push(NetOrder { from: (r, rp), to: (l, lp), strict: true })
            }
            CmpOp::Ge => {
                let lp = point(order.left.endpoint, End::Start);
                let rp = point(order.right.endpoint, End::End);
                out.push(NetOrder { from: (r, rp), to: (l, lp), strict: false })
            }
            CmpOp::Eq => c.unsupported(item, order.span, "an equality ordering"),
        }
    }
    let _ = c.db;
    out
}
