//! Hierarchical plan validation: does the decomposition a plan gives (the
//! IPC 2020 hierarchical format, hipop's timed extension of it, or a JSON
//! plan with methods) refine the problem's tasks with the domain's methods?
//! The checks of pandaPIparser's verifier, plus HiPOP's:
//!
//! - every step names a declared task (decompositions) or action (primitive
//!   steps, unless [`HierarchyOptions::check_primitive_steps`] is off because
//!   the temporal validator checks them), with the right arguments
//!   (`resolve.rs`);
//! - the method of a decomposition exists, is a method of the step's task,
//!   and its parameters bind consistently: the task's arguments unify with
//!   the method's `:task`, each listed subtask with one of the method's
//!   subtasks, one to one, under one binding (`matching.rs`), in an order
//!   the method's ordering allows (pandaPIparser matches subtasks in the
//!   listed order), and the method's constraints hold under it;
//! - every step is reached from the roots exactly once, without cycles
//!   (`structure.rs`);
//! - the roots are the tasks of the problem's `:htn` (any roots when the
//!   problem has a `:goal` instead), pandaPIparser's `__top` root included;
//! - the orderings of methods and of the `:htn` (HDDL 2.1 timed orderings
//!   too) hold in the plan's order, or in its times (`timeline.rs`), and a
//!   timed abstract step contains its subtasks (HiPOP);
//! - method preconditions hold (`conditions.rs`), and HiPOP abstract
//!   actions' preconditions and effects, in the states the primitive steps
//!   lead to; on a timed plan, the duration constraints of durative methods
//!   (HDDL 2.1) and of abstract actions hold on the steps' times.
//!
//! Unknown step ids, duplicate ids and unreadable lines are the reader's
//! (E0401–E0406): a step involved in one is not checked again. Executing the
//! primitive steps (their preconditions, effects, durations, the goal) is
//! the temporal validator's ([`super::validate_temporal`]).
//!
//! Pure: a function of the database and the plan, like the temporal
//! validator; diagnostics are in the plan file, with related locations in
//! the domain and the problem.

mod conditions;
mod decompose;
mod matching;
mod resolve;
mod structure;
mod timeline;

use rowan::TextRange;
use rustc_hash::FxHashMap;

use crate::db::{Db, Section, SourceFile, Unit, UnitKind, lower_item};
use crate::diagnostic::{Code, Diagnostic, Fix, Related, Severity, codes};
use crate::model::{Action, Htn, ItemData, Method, Str, Task};
use crate::plan::{NameMatching, Plan, StepId, normalise_name};
use crate::semantics::check::domain_for;
use crate::semantics::symbols::{DomainSymbols, Loc, domain_symbols, problem_symbols};
use crate::verify::state::{ObjId, Objects};

/// How to validate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HierarchyOptions {
    /// How names of the plan are compared with the domain's and problem's:
    /// `Lenient` is pandaPIparser's `-l`.
    pub matching: NameMatching,
    /// Whether primitive steps are checked to name an action with objects of
    /// the right types (E0410–E0413). Off when the temporal validator runs on
    /// the same steps, since it reports these.
    pub check_primitive_steps: bool,
    /// Whether the subtasks of a decomposition must be listed in an order
    /// the method's ordering allows, as pandaPIparser requires unless told
    /// to ignore the given order.
    pub listed_order: bool,
    /// VAL's tolerance: times closer than `tolerance / 10` are the same
    /// instant when orderings are checked on a timed plan.
    pub tolerance: f64,
}

impl Default for HierarchyOptions {
    fn default() -> Self {
        HierarchyOptions {
            matching: NameMatching::default(),
            check_primitive_steps: true,
            listed_order: true,
            tolerance: 0.01,
        }
    }
}

/// How an abstract step was found to be refined.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AppliedMethod {
    /// The abstract step (an index into [`Plan::steps`]).
    pub step: usize,
    /// The method's name, as the domain declares it (lower case).
    pub method: String,
    /// The values of the method's variables, by lower-case name.
    pub binding: Vec<(String, String)>,
    /// For each subtask of the decomposition, in the listed order, the
    /// index of the method subtask it is.
    pub subtasks: Vec<usize>,
}

/// The verdict on a plan's hierarchy.
#[derive(Debug, Clone, PartialEq)]
pub struct HierarchyReport {
    /// The plan was read without error and no check of its hierarchy failed
    /// (executing its primitive steps is the temporal validator's verdict).
    pub valid: bool,
    /// What failed (errors) and what could not be checked (warnings), in
    /// the plan file. The reader's own diagnostics are not repeated.
    pub diagnostics: Vec<Diagnostic>,
    /// Whether method preconditions (and abstract actions' conditions) were
    /// evaluated: not when a primitive step cannot be resolved or executed.
    pub preconditions_checked: bool,
    /// The methods of the abstract steps whose decomposition matched.
    pub methods: Vec<AppliedMethod>,
}

/// Validates the hierarchy of `plan` (read from `plan_file`) for `problem`.
pub fn validate_hierarchy(
    db: &dyn Db,
    problem: Unit<'_>,
    plan: &Plan,
    plan_file: SourceFile,
    options: &HierarchyOptions,
) -> HierarchyReport {
    let at = plan.begin.or_else(|| plan.steps.first().map(|s| s.range)).unwrap_or_default();
    let not_validated = |message: String, hint: &str| {
        let d = Diagnostic {
            code: codes::MODEL_NOT_VALIDATABLE,
            severity: Severity::Error,
            file: plan_file,
            range: at,
            message,
            related: Vec::new(),
            fix: Some(Fix { message: hint.to_string(), edits: Vec::new() }),
        };
        HierarchyReport {
            valid: false,
            diagnostics: vec![d],
            preconditions_checked: false,
            methods: Vec::new(),
        }
    };
    if problem.kind(db) != UnitKind::Problem {
        return not_validated(
            "the plan is not validated: its problem is not a `(define (problem …) …)`".into(),
            "give the problem file the plan solves",
        );
    }
    let Some(domain) = domain_for(db, problem) else {
        let name = problem.domain_ref(db).clone().unwrap_or_default();
        return not_validated(
            format!("the plan is not validated: the domain `{name}` of its problem is not among the files"),
            "give the domain file with the problem",
        );
    };
    if let Some((message, hint)) = super::model_errors(db, domain, problem) {
        return not_validated(message, &hint);
    }
    let mut cx = Cx::new(db, domain, problem, plan, plan_file, options);
    cx.run();
    let valid = !plan.has_errors() && cx.out.iter().all(|d| d.severity != Severity::Error);
    cx.out.sort_by_key(|d| (d.range.start(), d.range.end(), d.code.id));
    let methods = cx.applied_methods();
    HierarchyReport { valid, diagnostics: cx.out, preconditions_checked: cx.preconditions_checked, methods }
}

/// A step resolved to its action or task and its objects.
#[derive(Debug, Clone)]
struct Resolved {
    /// The action's or task's lower-case name.
    key: Str,
    /// Its arguments, as objects (lower-case names).
    args: Vec<Str>,
}

/// How an abstract step is refined, once its decomposition matched.
#[derive(Debug, Clone)]
struct Applied<'db> {
    method_key: Str,
    method: &'db Method,
    method_loc: Loc<'db>,
    /// The values of the method's variables.
    binding: Vec<matching::Bound>,
    /// For each listed subtask, the method subtask it is.
    assign: Vec<usize>,
    /// The method's constraints hold on the binding (when not, that was
    /// reported, and its precondition is not evaluated again).
    static_ok: bool,
    /// Too many matchings to find one under which the orderings hold (said
    /// by W0430): the orderings are not checked.
    orderings_undecided: bool,
}

/// Names of the domain and the problem, by their key under the name matching.
struct Lookup {
    map: FxHashMap<String, Vec<Str>>,
}

impl Lookup {
    fn new<'k>(keys: impl Iterator<Item = (&'k Str, Option<String>)>, matching: NameMatching) -> Lookup {
        let mut map: FxHashMap<String, Vec<Str>> = FxHashMap::default();
        for (key, text) in keys {
            let shown = text.as_deref().unwrap_or(key.as_str());
            map.entry(normalise_name(shown, matching).into_owned()).or_default().push(key.clone());
        }
        for v in map.values_mut() {
            v.sort();
        }
        Lookup { map }
    }

    /// The declaration a name of the plan means: under lenient matching,
    /// two declarations may have the same key; the one spelt as the plan
    /// does (ignoring case) wins.
    fn get(&self, name: &str, matching: NameMatching) -> Option<&Str> {
        let found = self.map.get(normalise_name(name, matching).as_ref())?;
        let lower = name.to_ascii_lowercase();
        found.iter().find(|k| k.as_str() == lower).or_else(|| found.first())
    }
}

/// Where the plan's top level is: the `root` line, or pandaPIparser's
/// artificial `__top` step.
#[derive(Debug, Clone)]
struct Top {
    /// The ids of the top-level steps, as listed.
    ids: Vec<StepId>,
    /// The `__top` step, when the plan has one.
    artificial: Option<usize>,
    /// Where the list is: the `root` line or the `__top` decomposition.
    range: TextRange,
    /// The plan has no `root` line: every step without a parent is a root.
    implicit: bool,
}

pub(super) struct Cx<'a, 'db> {
    db: &'db dyn Db,
    domain: Unit<'db>,
    problem: Unit<'db>,
    plan: &'a Plan,
    file: SourceFile,
    opts: &'a HierarchyOptions,
    dom: &'db DomainSymbols<'db>,
    objects: Objects<'db>,
    actions: Lookup,
    tasks: Lookup,
    methods: Lookup,
    object_names: Lookup,
    resolved: Vec<Option<Resolved>>,
    /// Abstract steps whose subtask list is wrong (a subtask twice, itself,
    /// another step's subtask, on a cycle): their method is not matched.
    bad_list: Vec<bool>,
    /// Primitive steps that could not be resolved (preconditions are then not evaluated).
    unresolved_primitives: bool,
    parent: Vec<Option<usize>>,
    /// Steps reached from the top level, in depth-first order.
    reached: Vec<bool>,
    order: Vec<usize>,
    top: Top,
    applied: Vec<Option<Applied<'db>>>,
    htn: Option<(Loc<'db>, &'db Htn)>,
    /// The top level matched the `:htn`: for each top-level step, its `:htn` subtask.
    htn_assign: Option<Vec<usize>>,
    /// Too many matchings of the top level to decide its orderings (W0430).
    htn_orderings_undecided: bool,
    /// Steps whose whole subtree checked out (names, methods, subtasks): only
    /// those take part in the checks of orderings and the windows of
    /// preconditions, so that one mistake is reported once.
    sound: Vec<bool>,
    preconditions_checked: bool,
    out: Vec<Diagnostic>,
}

impl<'a, 'db> Cx<'a, 'db> {
    fn new(
        db: &'db dyn Db,
        domain: Unit<'db>,
        problem: Unit<'db>,
        plan: &'a Plan,
        file: SourceFile,
        opts: &'a HierarchyOptions,
    ) -> Self {
        let dom = domain_symbols(db, domain);
        let prob = problem_symbols(db, problem);
        let objects = Objects::new(dom, prob);
        let m = opts.matching;
        // Under exact matching, names compare as the domain spells them.
        let text = |loc: Loc<'db>| (m == NameMatching::Exact).then(|| loc_text(db, loc));
        let actions = Lookup::new(dom.actions.iter().map(|(k, d)| (k, text(d.loc))), m);
        let tasks = Lookup::new(dom.tasks.iter().map(|(k, d)| (k, text(d.loc))), m);
        let methods = Lookup::new(dom.methods.iter().map(|(k, d)| (k, text(d.loc))), m);
        let object_keys: Vec<(Str, Option<String>)> = (0..objects.len() as ObjId)
            .map(|o| (Str::from(objects.name(o)), objects.loc(o).and_then(text)))
            .collect();
        let object_names = Lookup::new(object_keys.iter().map(|(k, t)| (k, t.clone())), m);
        let htn =
            problem.items(db).iter().find_map(|&item| match (&lower_item(db, item).data, item.section(db)) {
                (ItemData::Htn(h), Section::Htn) => Some((Loc { item, span: h.span }, h)),
                _ => None,
            });
        let n = plan.steps.len();
        Cx {
            db,
            domain,
            problem,
            plan,
            file,
            opts,
            dom,
            objects,
            actions,
            tasks,
            methods,
            object_names,
            resolved: vec![None; n],
            bad_list: vec![false; n],
            unresolved_primitives: false,
            parent: vec![None; n],
            reached: vec![false; n],
            order: Vec::new(),
            top: Top { ids: Vec::new(), artificial: None, range: TextRange::default(), implicit: true },
            applied: vec![None; n],
            htn,
            htn_assign: None,
            htn_orderings_undecided: false,
            sound: vec![false; n],
            preconditions_checked: false,
            out: Vec::new(),
        }
    }

    fn run(&mut self) {
        for i in 0..self.plan.steps.len() {
            self.resolve(i);
        }
        self.structure();
        // The steps' spans depend on the tree only: matchings are chosen so
        // that the orderings hold on them, when some do.
        let tl = timeline::Timeline::new(self);
        for k in 0..self.order.len() {
            let i = self.order[k];
            if self.plan.steps[i].is_abstract() && Some(i) != self.top.artificial {
                self.decompose(i, &tl);
            }
        }
        self.roots(&tl);
        self.soundness();
        tl.check_orderings(self);
        tl.check_abstract_times(self);
        conditions::check(self, &tl);
    }

    /// Which subtrees checked out, children before parents.
    fn soundness(&mut self) {
        let plan = self.plan;
        for k in (0..self.order.len()).rev() {
            let i = self.order[k];
            let s = &plan.steps[i];
            self.sound[i] = match &s.decomposition {
                None => self.resolved[i].is_some(),
                Some(dec) => {
                    (self.applied[i].as_ref().is_some_and(|a| a.static_ok) || Some(i) == self.top.artificial)
                        && !self.bad_list[i]
                        && dec.subtasks.iter().all(|id| {
                            plan.index_of(id.value)
                                .is_some_and(|j| self.parent[j] == Some(i) && self.sound[j])
                        })
                }
            };
        }
    }

    fn applied_methods(&self) -> Vec<AppliedMethod> {
        self.applied
            .iter()
            .enumerate()
            .filter_map(|(step, a)| {
                let a = a.as_ref()?;
                Some(AppliedMethod {
                    step,
                    method: a.method_key.to_string(),
                    binding: a.binding.iter().map(|b| (b.var.to_string(), b.value.to_string())).collect(),
                    subtasks: a.assign.clone(),
                })
            })
            .collect()
    }

    // ---- diagnostics -------------------------------------------------------

    fn diag(&self, code: &'static Code, range: TextRange, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            code,
            severity: code.severity,
            file: self.file,
            range,
            message: message.into(),
            related: Vec::new(),
            fix: None,
        }
    }

    fn related_plan(&self, d: &mut Diagnostic, range: TextRange, message: impl Into<String>) {
        d.related.push(Related { file: self.file, range, message: message.into() });
    }

    fn related_loc(&self, d: &mut Diagnostic, loc: Loc<'db>, message: impl Into<String>) {
        d.related.push(Related {
            file: loc.item.file(self.db),
            range: loc.span + loc.item.offset(self.db),
            message: message.into(),
        });
    }

    fn hint(&self, d: &mut Diagnostic, message: impl Into<String>, edits: Vec<(TextRange, String)>) {
        d.fix = Some(Fix {
            message: message.into(),
            edits: edits.into_iter().map(|(r, t)| (self.file, r, t)).collect(),
        });
    }

    fn push(&mut self, d: Diagnostic) {
        self.out.push(d);
    }

    // ---- steps -------------------------------------------------------------

    /// `step 8 `(deliver package-0 city-loc-0)``: by its id in the file,
    /// else by its line ([`crate::plan::step_label`]).
    fn step_text(&self, i: usize) -> String {
        let s = &self.plan.steps[i];
        let line = match s.id {
            Some(_) => 0,
            None => crate::plan::line_of(self.file.text(self.db), s.range.start()),
        };
        format!("{} `{}`", crate::plan::step_label(s.id.map(|id| id.value), line), s.call())
    }

    /// The step's id as written, or its line.
    fn id_range(&self, i: usize) -> TextRange {
        let s = &self.plan.steps[i];
        s.id.map_or(s.range, |id| id.range)
    }

    fn id_value(&self, i: usize) -> u32 {
        self.plan.steps[i].id.map_or(i as u32, |id| id.value)
    }

    fn action_model(&self, key: &str) -> Option<(Loc<'db>, &'db Action)> {
        let decl = self.dom.actions.get(key)?;
        match &lower_item(self.db, decl.loc.item).data {
            ItemData::Action(a) => Some((decl.loc, &**a)),
            _ => None,
        }
    }

    fn task_model(&self, key: &str) -> Option<(Loc<'db>, &'db Task)> {
        let decl = self.dom.tasks.get(key)?;
        match &lower_item(self.db, decl.loc.item).data {
            ItemData::Task(t) => Some((decl.loc, &**t)),
            _ => None,
        }
    }

    fn method_model(&self, key: &str) -> Option<(Loc<'db>, &'db Method)> {
        let decl = self.dom.methods.get(key)?;
        match &lower_item(self.db, decl.loc.item).data {
            ItemData::Method(m) => Some((decl.loc, &**m)),
            _ => None,
        }
    }

    /// Whether the object fits a parameter's types (a type the checks
    /// reported as undeclared fits anything).
    fn fits(&self, object: &str, types: &[Str]) -> bool {
        match self.objects.id(object) {
            Some(o) => types.iter().any(|t| self.objects.has_type(o, t) || !self.dom.is_type(t)),
            None => false,
        }
    }

    /// The type an object is declared with, for messages.
    fn type_of(&self, object: &str) -> String {
        let Some(o) = self.objects.id(object) else { return "object".into() };
        let decl =
            self.problem_objects_ty(object).or_else(|| self.dom.constants.get(object).map(|c| c.ty.clone()));
        match decl {
            Some(ty) if !ty.is_empty() => ty.join(" or "),
            _ => self.objects.types(o).first().map_or("object".into(), |t| t.to_string()),
        }
    }

    fn problem_objects_ty(&self, object: &str) -> Option<Vec<Str>> {
        problem_symbols(self.db, self.problem).objects.get(object).map(|d| d.ty.clone())
    }
}

/// `a` or `an`.
fn a(word: &str) -> &'static str {
    if word.starts_with(['a', 'e', 'i', 'o', 'u']) { "an" } else { "a" }
}

/// The text of a declaration, as the file spells it.
fn loc_text(db: &dyn Db, loc: Loc<'_>) -> String {
    let text = loc.item.file(db).text(db);
    let range = loc.span + loc.item.offset(db);
    text.get(usize::from(range.start())..usize::from(range.end())).unwrap_or_default().to_string()
}
