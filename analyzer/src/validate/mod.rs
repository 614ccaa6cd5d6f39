//! Plan validation: does a plan solve a problem? This module checks PDDL 2.1
//! temporal plans (and sequential ones) with the semantics of VAL, the
//! reference validator, and reports each failure like a compiler error: the
//! step, what failed, why, where in the domain and problem, and how to repair.
//!
//! - `crate::eval`: ground states; conditions, numeric expressions and
//!   effects evaluated in them (shared with the planner's numeric fluents).
//! - `temporal/`: the happenings of a timed plan and the checks at each.
//! - [`file`]: a plan file read and validated; the one entry point of the
//!   CLI and the editor.
//!
//! The input is a list of [`TimedStep`]s that a plan reader produces (the
//! reader is not here: any format that gives steps, times and durations with
//! their locations can be validated). Pure functions: no salsa query here,
//! a caller that wants one wraps [`validate_temporal`].
//!
//! # Semantics (VAL's)
//!
//! - A step happens at its time; a plan without times is sequential: its
//!   untimed steps happen at 1, 2, 3… in order.
//! - A durative action is two events, its start at `time` and its end at
//!   `time + duration`; an `:action` is one event at `time`.
//! - Events are grouped into *happenings* as VAL groups them: a happening
//!   takes every event no later than `tolerance / 10` after its first event.
//! - At each happening, in time order: every condition (`at start` and
//!   duration constraints at a start, `at end` at an end, the precondition
//!   of an `:action`) is checked in the state before the happening; effects
//!   are computed in that state and applied together, deletions before
//!   additions, then numeric updates. Two events of one happening that
//!   interfere (one changes what the other reads, one adds what the other
//!   deletes, both change a fluent other than by `increase`/`decrease`) are
//!   a mutex violation.
//! - `over all` conditions hold in every state strictly between a step's
//!   start and its end: after each happening from its start's to the one
//!   before its end's.
//! - Duration constraints are evaluated in the state at the start, with the
//!   tolerance: `(= ?duration e)` accepts `|d - e| < tolerance`, `<=` and
//!   `>=` accept an error up to the tolerance, `<` and `>` none.
//! - Timed initial literals happen at their times, as events of the
//!   happenings; those after the plan's last event are not applied.
//! - The goal must hold after the last happening.
//!
//! Interfering events of different happenings that are closer than the
//! tolerance are accepted, as VAL accepts them, with the warning W0411.

pub mod file;
pub mod hierarchy;
mod temporal;

pub use crate::input::ValidationOptions as Options;
pub use file::{Validation, plan_file_diagnostics, timed_steps, validate_plan};

use rowan::TextRange;

use crate::db::{Db, SourceFile, Unit};
use crate::diagnostic::{Code, Diagnostic, Fix, Related, codes};
use crate::semantics::symbols::Loc;

/// One step of a plan, as a plan reader gives it. Names are as written
/// (matched case-insensitively, as PDDL names are); spans are byte ranges in
/// the plan file.
#[derive(Debug, Clone, PartialEq)]
pub struct TimedStep {
    /// The action's name: `move` in `12.5: (move r1 w5 w7) [3.0]`.
    pub name: String,
    /// The arguments: objects of the problem or constants of the domain.
    pub args: Vec<String>,
    /// The start time; `None` in a sequential plan (VAL then gives the
    /// untimed steps the times 1, 2, 3… in order).
    pub time: Option<f64>,
    /// The duration, required for a durative action.
    pub duration: Option<f64>,
    /// The whole step (the line without its comment): where failures point.
    pub span: TextRange,
    /// The action's name.
    pub name_span: TextRange,
    /// Each argument, in order (as many as `args`).
    pub arg_spans: Vec<TextRange>,
    /// The time's number (`12.5`, without the colon), when written.
    pub time_span: Option<TextRange>,
    /// The duration with its brackets (`[3.0]`), when written.
    pub duration_span: Option<TextRange>,
    /// The step's id in the plan file (hierarchical and JSON plans); VAL
    /// plans have none.
    pub id: Option<u32>,
    /// The line of the plan file the step is on, from 1 (0: unknown).
    pub line: usize,
}

impl TimedStep {
    /// A step without spans (tests, generated plans): everything at `span`.
    pub fn new(name: &str, args: &[&str], time: Option<f64>, duration: Option<f64>, span: TextRange) -> Self {
        TimedStep {
            name: name.to_string(),
            args: args.iter().map(|a| a.to_string()).collect(),
            time,
            duration,
            span,
            name_span: span,
            arg_spans: vec![span; args.len()],
            time_span: None,
            duration_span: None,
            id: None,
            line: 0,
        }
    }

    /// How messages name the step: `step 8` (its id in the file), or `the
    /// step on line 12` in a VAL plan ([`crate::plan::step_label`]).
    pub fn label(&self) -> String {
        crate::plan::step_label(self.id, self.line)
    }

    /// `step 8 `(drive t a b)``, `the step on line 12 `(drive t a b)``.
    pub fn described(&self) -> String {
        format!("{} `{}`", self.label(), self.text())
    }

    /// `(name args…)` as written.
    pub fn text(&self) -> String {
        let mut s = format!("({}", self.name);
        for a in &self.args {
            s.push(' ');
            s.push_str(a);
        }
        s.push(')');
        s
    }
}

/// One reason a plan is invalid (or a warning about it), located in the plan.
#[derive(Debug, Clone, PartialEq, salsa::SalsaValue)]
pub struct Failure<'db> {
    pub code: &'static Code,
    /// The step it is about (an index into the input), if one.
    pub step: Option<usize>,
    /// The primary location, in the plan file.
    pub span: TextRange,
    pub message: String,
    /// Other places in the plan: the other steps involved.
    pub plan_related: Vec<(TextRange, String)>,
    /// Places in the domain or the problem: the condition, the effect, the
    /// declaration involved.
    pub model_related: Vec<(Loc<'db>, String)>,
    /// How to repair, in the spirit of VAL's advice: which fact to make true,
    /// which steps to separate, how to change a duration.
    pub hint: Option<String>,
    /// Edits of the plan file that carry out the hint, when it is mechanical
    /// (a new duration, a new time, a name).
    pub edits: Vec<(TextRange, String)>,
}

impl<'db> Failure<'db> {
    pub(crate) fn new(code: &'static Code, span: TextRange, message: impl Into<String>) -> Self {
        Failure {
            code,
            step: None,
            span,
            message: message.into(),
            plan_related: Vec::new(),
            model_related: Vec::new(),
            hint: None,
            edits: Vec::new(),
        }
    }

    pub(crate) fn at_step(mut self, step: usize) -> Self {
        self.step = Some(step);
        self
    }

    pub(crate) fn plan(mut self, span: TextRange, message: impl Into<String>) -> Self {
        self.plan_related.push((span, message.into()));
        self
    }

    pub(crate) fn model(mut self, loc: Loc<'db>, message: impl Into<String>) -> Self {
        self.model_related.push((loc, message.into()));
        self
    }

    pub(crate) fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    pub(crate) fn edit(mut self, span: TextRange, text: impl Into<String>) -> Self {
        self.edits.push((span, text.into()));
        self
    }

    /// The diagnostic, in `plan`. The hint becomes the fix's message; a
    /// hint without edits is advice only (a fix with no edit).
    pub fn to_diagnostic(&self, db: &'db dyn Db, plan: SourceFile) -> Diagnostic {
        let mut related: Vec<Related> = self
            .plan_related
            .iter()
            .map(|(range, message)| Related { file: plan, range: *range, message: message.clone() })
            .collect();
        related.extend(self.model_related.iter().map(|(loc, message)| Related {
            file: loc.item.file(db),
            range: loc.span + loc.item.offset(db),
            message: message.clone(),
        }));
        Diagnostic {
            code: self.code,
            severity: self.code.severity,
            file: plan,
            range: self.span,
            message: self.message.clone(),
            related,
            fix: self.hint.as_ref().map(|h| Fix {
                message: h.clone(),
                edits: self.edits.iter().map(|(r, t)| (plan, *r, t.clone())).collect(),
            }),
        }
    }
}

/// The verdict on a plan.
#[derive(Debug, Clone, PartialEq, salsa::SalsaValue)]
pub struct Report<'db> {
    /// No failure of error severity.
    pub valid: bool,
    /// Errors and warnings, in the order execution met them.
    pub failures: Vec<Failure<'db>>,
    /// The time of the last event (a durative step's end), 0 for an empty plan.
    pub makespan: f64,
    /// The plan's value: the problem's metric evaluated in the final state
    /// (with `total-time` the makespan), or the makespan when the problem
    /// has no metric, like VAL's "Final value". `None` when the plan is
    /// invalid or the metric cannot be evaluated.
    pub value: Option<f64>,
    /// How many happenings were executed.
    pub happenings: usize,
}

impl<'db> Report<'db> {
    /// Why the plan has no verdict: the first error execution met stopped it
    /// before it could judge the plan, E0421 (a feature the validator does
    /// not check) or E0422 (a model it cannot validate against). An error
    /// met before is a verdict: the plan is invalid.
    pub fn not_judged(&self) -> Option<&'static Code> {
        self.failures
            .iter()
            .find(|f| f.code.severity == crate::diagnostic::Severity::Error)
            .map(|f| f.code)
            .filter(|&c| c == codes::UNSUPPORTED_IN_PLAN || c == codes::MODEL_NOT_VALIDATABLE)
    }

    /// Every failure as a diagnostic in the plan file.
    pub fn to_diagnostics(&self, db: &'db dyn Db, plan: SourceFile) -> Vec<Diagnostic> {
        self.failures.iter().map(|f| f.to_diagnostic(db, plan)).collect()
    }
}

/// Why a domain or problem with errors cannot be validated against: the
/// message and hint of E0422, or `None` when both are free of errors (a plan
/// is only validated against a model that means what it says).
pub(crate) fn model_errors(db: &dyn Db, domain: Unit<'_>, problem: Unit<'_>) -> Option<(String, String)> {
    [(domain, "domain"), (problem, "problem")].into_iter().find_map(|(unit, what)| {
        let errors = crate::semantics::unit_diagnostics(db, unit)
            .iter()
            .filter(|d| d.severity == crate::diagnostic::Severity::Error)
            .count();
        (errors > 0).then(|| {
            let name = unit.name(db).clone().unwrap_or_default();
            let s = if errors == 1 { "" } else { "s" };
            (
                format!(
                    "the plan is not validated: the {what} `{name}` has {errors} error{s}, so it may not mean what it says"
                ),
                format!("fix the {what} first (`hipop check` lists its errors)"),
            )
        })
    })
}

/// Validates a temporal (or sequential) plan for a problem, against the
/// problem's domain.
pub fn validate_temporal<'db>(
    db: &'db dyn Db,
    problem: Unit<'db>,
    steps: &[TimedStep],
    options: &Options,
) -> Report<'db> {
    temporal::validate(db, problem, steps, options)
}
