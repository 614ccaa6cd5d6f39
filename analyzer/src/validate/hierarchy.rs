//! Hierarchical plan validation: does the decomposition a plan gives (the
//! IPC 2020 hierarchical format, hipop's timed extension of it, or a JSON
//! plan with methods) refine the problem's tasks with the domain's methods?
//! The checks of pandaPIparser's verifier, plus HiPOP's:
//!
//! - every step names a declared task (decompositions) or action (primitive
//!   steps, unless [`HierarchyOptions::check_primitive_steps`] is off because
//!   the temporal validator checks them), with the right arguments;
//! - the method of a decomposition exists, is a method of the step's task,
//!   and its parameters bind consistently: the task's arguments unify with
//!   the method's `:task`, each listed subtask with one of the method's
//!   subtasks, one to one, under one binding (`matching.rs`), in an order
//!   the method's ordering allows (pandaPIparser matches subtasks in the
//!   listed order), and the method's constraints hold under it;
//! - every step is reached from the roots exactly once, without cycles;
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
mod timeline;

use rowan::TextRange;
use rustc_hash::FxHashMap;

use crate::db::{Db, Section, SourceFile, Unit, UnitKind, lower_item};
use crate::diagnostic::{Code, Diagnostic, Fix, Related, Severity, codes};
use crate::model::{Action, Htn, ItemData, Method, Str, Task};
use crate::plan::{NameMatching, Plan, StepId, normalise_name};
use crate::semantics::check::{domain_for, suggest};
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

    /// Resolves step `i` to its action or task and objects, reporting what
    /// does not resolve.
    fn resolve(&mut self, i: usize) {
        let s = &self.plan.steps[i];
        let m = self.opts.matching;
        if self.artificial_top() == Some(i) {
            // pandaPIparser's artificial root: its subtasks are the top level.
            return;
        }
        let check = s.is_abstract() || self.opts.check_primitive_steps;
        let (key, params, loc) = if s.is_abstract() {
            match self.tasks.get(&s.name.text, m).cloned() {
                Some(k) => {
                    let d = &self.dom.tasks[&k];
                    (k, d.params.clone(), d.loc)
                }
                None => {
                    self.unknown_callable(i, true);
                    return;
                }
            }
        } else {
            match self.actions.get(&s.name.text, m).cloned() {
                Some(k) => {
                    let d = &self.dom.actions[&k];
                    (k, d.params.clone(), d.loc)
                }
                None => {
                    if check {
                        self.unknown_callable(i, false);
                    }
                    self.unresolved_primitives = true;
                    return;
                }
            }
        };
        let what = if s.is_abstract() { "task" } else { "action" };
        if s.args.len() != params.len() {
            if check {
                let code = if s.is_abstract() { codes::TASK_STEP_ARITY } else { codes::STEP_ARITY };
                let names = self.param_names(&key, s.is_abstract());
                let n = s.args.len();
                let mut d = self.diag(
                    code,
                    s.range,
                    format!(
                        "{} gives `{key}` {n} argument{}, but the {what} takes {} ({})",
                        self.step_text(i),
                        if n == 1 { "" } else { "s" },
                        params.len(),
                        names.join(" ")
                    ),
                );
                self.related_loc(&mut d, loc, format!("the {what} is declared here"));
                self.push(d);
            }
            self.unresolved_primitives |= !s.is_abstract();
            return;
        }
        let mut args = Vec::with_capacity(s.args.len());
        let mut ok = true;
        for (k, a) in s.args.iter().enumerate() {
            match self.object_names.get(&a.text, m).cloned() {
                Some(o) if self.fits(&o, &params[k]) => args.push(o),
                Some(o) => {
                    ok = false;
                    if check {
                        self.type_mismatch(i, k, &key, &o, &params[k], loc);
                    }
                }
                None => {
                    ok = false;
                    if check {
                        self.unknown_object(i, k, &params[k]);
                    }
                }
            }
        }
        if !ok {
            self.unresolved_primitives |= !s.is_abstract();
            return;
        }
        self.resolved[i] = Some(Resolved { key, args });
    }

    fn param_names(&self, key: &str, task: bool) -> Vec<String> {
        let d = if task { self.dom.tasks.get(key) } else { self.dom.actions.get(key) };
        d.map(|d| d.param_names.iter().map(|p| p.to_string()).collect()).unwrap_or_default()
    }

    fn unknown_callable(&mut self, i: usize, is_abstract: bool) {
        let s = &self.plan.steps[i];
        let m = self.opts.matching;
        let name = &s.name.text;
        let (code, what, other, other_what) = if is_abstract {
            (codes::UNKNOWN_TASK_IN_PLAN, "task", self.actions.get(name, m).cloned(), "action")
        } else {
            (codes::UNKNOWN_ACTION_IN_PLAN, "action", self.tasks.get(name, m).cloned(), "task")
        };
        let mut d = self.diag(
            code,
            s.name.range,
            format!("{}: the domain has no {what} `{name}`", self.step_text(i)),
        );
        if let Some(other) = other {
            let loc = if is_abstract { self.dom.actions[&other].loc } else { self.dom.tasks[&other].loc };
            d.message = format!(
                "{}: `{name}` is {} {other_what}, not {} {what}",
                self.step_text(i),
                a(other_what),
                a(what)
            );
            self.related_loc(&mut d, loc, format!("the {other_what} is declared here"));
            let hint = if is_abstract {
                "an action is a primitive step: list it before `root`, as `ID action args…`, without `->`"
            } else {
                "a task is an abstract step: write it after `root`, as `ID task args… -> method subtask-ids…`"
            };
            self.hint(&mut d, hint, Vec::new());
        } else if is_abstract && normalise_name(name, NameMatching::Lenient) == "--top" {
            self.hint(
                &mut d,
                "pandaPIparser's artificial root `__top` stands for the problem's `:htn` only as the one id of the `root` line",
                Vec::new(),
            );
        } else {
            let keys: Vec<&str> = if is_abstract {
                self.dom.tasks.keys().map(|k| k.as_str()).collect()
            } else {
                self.dom.actions.keys().map(|k| k.as_str()).collect()
            };
            if let Some(best) = suggest(&name.to_ascii_lowercase(), keys.into_iter()) {
                let best = best.to_string();
                self.hint(&mut d, format!("did you mean `{best}`?"), vec![(s.name.range, best)]);
            }
        }
        self.push(d);
    }

    fn unknown_object(&mut self, i: usize, k: usize, wanted: &[Str]) {
        let s = &self.plan.steps[i];
        let arg = &s.args[k];
        let mut d = self.diag(
            codes::UNKNOWN_OBJECT_IN_PLAN,
            arg.range,
            format!(
                "{}: `{}` is not an object of the problem or a constant of the domain",
                self.step_text(i),
                arg.text
            ),
        );
        let candidates = self.objects.of_types(wanted);
        let names: Vec<&str> = candidates.iter().map(|&o| self.objects.name(o)).collect();
        if let Some(best) = suggest(&arg.text.to_ascii_lowercase(), names.into_iter()) {
            let best = best.to_string();
            self.hint(&mut d, format!("did you mean `{best}`?"), vec![(arg.range, best)]);
        }
        self.push(d);
    }

    fn type_mismatch(&mut self, i: usize, k: usize, key: &str, object: &str, wanted: &[Str], decl: Loc<'db>) {
        let s = &self.plan.steps[i];
        let arg = &s.args[k];
        let param = self.param_names(key, s.is_abstract()).get(k).cloned().unwrap_or_default();
        let mut d = self.diag(
            codes::STEP_TYPE_MISMATCH,
            arg.range,
            format!(
                "{}: `{}` is of type `{}`, but parameter `{param}` of `{key}` has type `{}`",
                self.step_text(i),
                arg.text,
                self.type_of(object),
                wanted.join(" or ")
            ),
        );
        self.related_loc(&mut d, decl, "declared here");
        if let Some(loc) = self.objects.id(object).and_then(|o| self.objects.loc(o)) {
            self.related_loc(&mut d, loc, format!("`{}` is declared here", arg.text));
        }
        self.push(d);
    }

    // ---- structure ---------------------------------------------------------

    /// Parents, the top level, what the roots reach: shared steps, cycles,
    /// orphans, duplicate subtasks.
    fn structure(&mut self) {
        let n = self.plan.steps.len();
        for i in 0..n {
            let s = &self.plan.steps[i];
            let Some(dec) = &s.decomposition else { continue };
            let mut seen: Vec<u32> = Vec::with_capacity(dec.subtasks.len());
            for sub in &dec.subtasks {
                let Some(j) = self.plan.index_of(sub.value) else { continue };
                if seen.contains(&sub.value) {
                    let first =
                        dec.subtasks.iter().find(|x| x.value == sub.value).map_or(sub.range, |x| x.range);
                    let mut d = self.diag(
                        codes::DUPLICATE_SUBTASK,
                        sub.range,
                        format!("{} lists its subtask {} twice", self.step_text(i), sub.value),
                    );
                    self.related_plan(&mut d, first, "listed here first");
                    self.hint(
                        &mut d,
                        "a step refines one subtask: remove the second id",
                        vec![(sub.range, String::new())],
                    );
                    self.push(d);
                    self.bad_list[i] = true;
                    continue;
                }
                seen.push(sub.value);
                if j == i {
                    let mut d = self.diag(
                        codes::DECOMPOSITION_CYCLE,
                        sub.range,
                        format!("{} lists itself as its own subtask", self.step_text(i)),
                    );
                    self.hint(&mut d, "a step's subtasks are other steps: give the id of the step that refines this subtask", Vec::new());
                    self.push(d);
                    self.bad_list[i] = true;
                    continue;
                }
                match self.parent[j] {
                    Some(p) if p != i => {
                        let mut d = self.diag(
                            codes::SHARED_STEP,
                            sub.range,
                            format!(
                                "{} is a subtask of {} and of {}: a step refines one task only",
                                self.step_text(j),
                                self.step_text(p),
                                self.step_text(i)
                            ),
                        );
                        let other = self.subtask_range(p, sub.value);
                        self.related_plan(
                            &mut d,
                            other,
                            format!("listed as a subtask of step {} here", self.id_value(p)),
                        );
                        self.hint(
                            &mut d,
                            "give each decomposition its own steps: add a step for this subtask with a new id",
                            Vec::new(),
                        );
                        self.push(d);
                        self.bad_list[i] = true;
                    }
                    _ => self.parent[j] = Some(i),
                }
            }
        }
        self.find_top();
        // What the top level reaches, depth first.
        let mut stack: Vec<usize> = Vec::new();
        let top: Vec<usize> = if self.top.implicit {
            (0..n).filter(|&i| self.parent[i].is_none()).collect()
        } else {
            let mut v = Vec::new();
            if let Some(a) = self.top.artificial {
                v.push(a);
            }
            v.extend(self.top.ids.iter().filter_map(|id| self.plan.index_of(id.value)));
            v
        };
        stack.extend(top.iter().rev());
        while let Some(i) = stack.pop() {
            if self.reached[i] {
                continue;
            }
            self.reached[i] = true;
            self.order.push(i);
            if let Some(dec) = &self.plan.steps[i].decomposition {
                for sub in dec.subtasks.iter().rev() {
                    if let Some(j) = self.plan.index_of(sub.value)
                        && self.parent[j] == Some(i)
                    {
                        stack.push(j);
                    }
                }
            }
        }
        if !self.top.implicit {
            self.unreached();
        }
    }

    /// The range of `id` in the subtask list of step `p`.
    fn subtask_range(&self, p: usize, id: u32) -> TextRange {
        let s = &self.plan.steps[p];
        s.decomposition
            .as_ref()
            .and_then(|d| d.subtasks.iter().find(|x| x.value == id))
            .map_or(s.range, |x| x.range)
    }

    /// The `root` line, or the `__top` step, and what is wrong with them.
    fn find_top(&mut self) {
        let Some(root) = &self.plan.root else {
            self.top = Top {
                ids: Vec::new(),
                artificial: None,
                range: self.plan.begin.unwrap_or_default(),
                implicit: true,
            };
            return;
        };
        let mut top = Top { ids: root.ids.clone(), artificial: None, range: root.range, implicit: false };
        if let Some(i) = self.artificial_top() {
            // `root 8` and `8 __top -> __top_method 13 16`.
            let dec = self.plan.steps[i].decomposition.as_ref();
            top = Top {
                ids: dec.map(|d| d.subtasks.clone()).unwrap_or_default(),
                artificial: Some(i),
                range: self.plan.steps[i].range,
                implicit: false,
            };
            if let Some(method) = dec.map(|d| &d.method)
                && normalise_name(&method.text, NameMatching::Lenient) != "--top-method"
            {
                self.top_method(i, method.range, &method.text);
            }
        }
        let mut seen: Vec<u32> = Vec::new();
        for id in &root.ids {
            let Some(j) = self.plan.index_of(id.value) else { continue };
            if seen.contains(&id.value) {
                let mut d = self.diag(
                    codes::DUPLICATE_SUBTASK,
                    id.range,
                    format!("the `root` line lists step {} twice", id.value),
                );
                self.hint(&mut d, "remove the second id", vec![(id.range, String::new())]);
                self.push(d);
                continue;
            }
            seen.push(id.value);
            if let Some(p) = self.parent[j] {
                let mut d = self.diag(
                    codes::SHARED_STEP,
                    id.range,
                    format!("{} is a root and a subtask of {}", self.step_text(j), self.step_text(p)),
                );
                let other = self.subtask_range(p, id.value);
                self.related_plan(&mut d, other, "listed as a subtask here");
                self.hint(
                    &mut d,
                    "a root is a task of the problem, not a subtask of another step: remove it from one of the lists",
                    Vec::new(),
                );
                self.push(d);
            }
        }
        self.top = top;
    }

    /// pandaPIparser's artificial root: the only id of the `root` line, a
    /// step of the task `__top` (which no domain declares).
    fn artificial_top(&self) -> Option<usize> {
        let [only] = self.plan.root.as_ref()?.ids.as_slice() else { return None };
        let i = self.plan.index_of(only.value)?;
        let s = &self.plan.steps[i];
        (s.is_abstract() && normalise_name(&s.name.text, NameMatching::Lenient) == "--top").then_some(i)
    }

    /// The artificial root refined by another method than `__top_method`
    /// (pandaPIparser's method of the problem's `:htn`).
    fn top_method(&mut self, i: usize, range: TextRange, name: &str) {
        let (code, message) = match self.methods.get(name, self.opts.matching) {
            Some(key) => {
                let task = self.dom.methods.get(key).and_then(|d| d.task.clone()).unwrap_or_default();
                (
                    codes::WRONG_METHOD,
                    format!(
                        "{} is refined by `{name}`, but `{key}` is a method of `{task}`, not of the artificial root `__top`",
                        self.step_text(i)
                    ),
                )
            }
            None => (
                codes::UNKNOWN_METHOD,
                format!(
                    "{} is refined by `{name}`, but the artificial root `__top` has one method, `__top_method`",
                    self.step_text(i)
                ),
            ),
        };
        let mut d = self.diag(code, range, message);
        self.hint(
            &mut d,
            "pandaPIparser's artificial root is refined by `__top_method` into the tasks of the problem's `:htn`",
            vec![(range, "__top_method".to_string())],
        );
        self.push(d);
    }

    /// Cycles and orphans: steps the top level does not reach.
    fn unreached(&mut self) {
        let n = self.plan.steps.len();
        // A step the roots do not reach is on a cycle of parents, below one,
        // or below a step without parent (an orphan).
        let mut cycle_of: Vec<bool> = vec![false; n];
        for i in 0..n {
            if self.reached[i] || cycle_of[i] {
                continue;
            }
            let mut path = vec![i];
            let mut at = i;
            while let Some(p) = self.parent[at] {
                if self.reached[p] || cycle_of[p] {
                    break;
                }
                if let Some(k) = path.iter().position(|&x| x == p) {
                    let cycle: Vec<usize> = path[k..].to_vec();
                    cycle.iter().for_each(|&c| cycle_of[c] = true);
                    self.report_cycle(&cycle);
                    break;
                }
                path.push(p);
                at = p;
            }
        }
        for i in 0..n {
            if self.reached[i] || cycle_of[i] || Some(i) == self.top.artificial {
                continue;
            }
            // Report the top of each orphan subtree only.
            let mut up = self.parent[i];
            let mut below_other = false;
            while let Some(p) = up {
                if cycle_of[p] || !self.reached[p] {
                    below_other = true;
                    break;
                }
                up = self.parent[p];
            }
            if below_other {
                continue;
            }
            let below = self.count_below(i);
            let what = if self.plan.steps[i].is_abstract() { "abstract step" } else { "primitive step" };
            let mut message = format!(
                "{} is not a root and no decomposition lists it: every {what} must be reached from the `root` line",
                self.step_text(i)
            );
            if below > 0 {
                message.push_str(&format!(" (nor are the {below} steps below it)"));
            }
            let mut d = self.diag(codes::ORPHAN_STEP, self.id_range(i), message);
            match (&self.htn, &self.plan.root) {
                (None, Some(r)) => {
                    let edit = (TextRange::empty(r.range.end()), format!(" {}", self.id_value(i)));
                    self.hint(
                        &mut d,
                        "add it to the `root` line, or list it as a subtask of the step it refines",
                        vec![edit],
                    );
                }
                _ => {
                    self.hint(&mut d, "list it as a subtask of the step it refines, or remove it", Vec::new())
                }
            }
            self.push(d);
        }
    }

    fn count_below(&self, i: usize) -> usize {
        let mut count = 0;
        let mut stack = vec![i];
        let mut seen = vec![false; self.plan.steps.len()];
        while let Some(x) = stack.pop() {
            if std::mem::replace(&mut seen[x], true) {
                continue;
            }
            if let Some(dec) = &self.plan.steps[x].decomposition {
                for sub in &dec.subtasks {
                    if let Some(j) = self.plan.index_of(sub.value)
                        && self.parent[j] == Some(x)
                        && !seen[j]
                    {
                        count += 1;
                        stack.push(j);
                    }
                }
            }
        }
        count
    }

    fn report_cycle(&mut self, cycle: &[usize]) {
        // Report at the step listed first in the file.
        let Some(&first) = cycle.iter().min_by_key(|&&c| self.plan.steps[c].range.start()) else { return };
        let names: Vec<String> = cycle.iter().map(|&c| self.id_value(c).to_string()).collect();
        let mut d = self.diag(
            codes::DECOMPOSITION_CYCLE,
            self.id_range(first),
            format!(
                "the steps {} are subtasks of each other in a cycle: no root reaches them, and none can be refined into actions",
                names.join(" → ")
            ),
        );
        for &c in cycle {
            if c != first {
                self.related_plan(&mut d, self.id_range(c), "on the cycle");
            }
        }
        self.hint(
            &mut d,
            "a decomposition lists the steps that refine its task: break the cycle",
            Vec::new(),
        );
        self.push(d);
        cycle.iter().for_each(|&c| self.bad_list[c] = true);
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
