//! Validating a plan file: read it ([`crate::plan`]), find the steps the
//! validators take, run them (the temporal validator on the primitive steps,
//! and the hierarchy's on a plan with decompositions), and gather every
//! diagnostic of the file. The one path for `hipop validate` and for plan
//! files open in the editor.

use crate::db::{Db, SourceFile, Unit};
use crate::diagnostic::{Code, Diagnostic, Severity};
use crate::plan::{NameMatching, Plan, PlanFormat, Step};

use super::hierarchy::{HierarchyOptions, validate_hierarchy};
use super::{Options, TimedStep, validate_temporal};

/// What validating a plan file found.
#[derive(Debug, Clone, PartialEq)]
pub struct Validation {
    /// The plan could be read and every check passed (warnings allowed).
    pub valid: bool,
    /// The plan was read without errors and validated (not only read).
    pub checked: bool,
    /// Why a plan that was read has no verdict ([`super::Report::not_judged`]):
    /// E0421 (a feature the validator does not check: PDDL+, derived
    /// predicates…) or E0422 (a model it cannot validate against). `valid`
    /// is false then, but the plan is not known to be invalid.
    pub not_judged: Option<&'static Code>,
    /// The time of the last happening; `None` for a plan not read or not judged.
    pub makespan: Option<f64>,
    /// The problem's metric on the plan (VAL's "Final value"), or the makespan.
    pub value: Option<f64>,
    /// Reading and validation diagnostics, in the plan file and the model's files.
    pub diagnostics: Vec<Diagnostic>,
}

/// The primitive steps of a plan, as the temporal validator takes them, in
/// the order of the file: a VAL plan's steps, a hierarchical plan's
/// primitive steps (listed in execution order, the IPC 2020 convention;
/// timed by hipop's annotations when it has them).
/// `text` is the plan file's, for the steps' lines.
pub fn timed_steps(plan: &Plan, text: &str) -> Vec<TimedStep> {
    let mut lines = Lines::new(text);
    plan.primitive_steps().map(|(_, s)| timed_step(s, lines.line_of(s.range.start()))).collect()
}

/// Lines of offsets that mostly come in increasing order (steps in the
/// order of the file): counted on from the previous offset, not from the
/// start of the text.
struct Lines<'t> {
    text: &'t str,
    offset: usize,
    line: usize,
}

impl<'t> Lines<'t> {
    fn new(text: &'t str) -> Self {
        Lines { text, offset: 0, line: 1 }
    }

    fn line_of(&mut self, offset: rowan::TextSize) -> usize {
        let to = usize::from(offset).min(self.text.len());
        if to < self.offset {
            (self.offset, self.line) = (0, 1);
        }
        self.line += self.text.as_bytes()[self.offset..to].iter().filter(|&&b| b == b'\n').count();
        self.offset = to;
        self.line
    }
}

fn timed_step(s: &Step, line: usize) -> TimedStep {
    TimedStep {
        name: s.name.text.to_string(),
        args: s.args.iter().map(|a| a.text.to_string()).collect(),
        time: s.start.as_ref().map(|n| n.value),
        duration: s.duration.as_ref().map(|n| n.value),
        span: s.range,
        name_span: s.name.range,
        arg_spans: s.args.iter().map(|a| a.range).collect(),
        time_span: s.start.as_ref().map(|n| n.range),
        duration_span: s.duration.as_ref().map(|n| n.range),
        id: s.id.map(|id| id.value),
        line,
    }
}

/// Reads `file` as a plan (in `format`, or the format its content shows) and
/// validates it against `problem` and the problem's domain. A plan that
/// cannot be read is not validated: its reading errors are the diagnostics.
pub fn validate_plan<'db>(
    db: &'db dyn Db,
    file: SourceFile,
    format: Option<PlanFormat>,
    problem: Unit<'db>,
    options: &Options,
) -> Validation {
    let plan = match format {
        Some(f) => crate::plan::parse_plan_as(db, file, f),
        None => crate::plan::parse_plan(db, file),
    };
    let mut diagnostics = plan.file_diagnostics(file);
    if plan.has_errors() {
        return Validation {
            valid: false,
            checked: false,
            not_judged: None,
            makespan: None,
            value: None,
            diagnostics,
        };
    }
    // The primitive steps are executed (VAL's semantics) whatever the format;
    // a plan with a decomposition is also checked against the methods.
    let report = validate_temporal(db, problem, &timed_steps(plan, file.text(db)), options);
    let not_judged = report.not_judged();
    diagnostics.extend(report.to_diagnostics(db, file));
    let mut valid = report.valid;
    if plan.is_hierarchical() {
        let matching = if options.lenient { NameMatching::Lenient } else { NameMatching::CaseInsensitive };
        let h = validate_hierarchy(
            db,
            problem,
            plan,
            file,
            &HierarchyOptions {
                matching,
                // The temporal validator reports unknown actions and bad arguments.
                check_primitive_steps: false,
                listed_order: !options.ignore_listed_order,
                tolerance: options.tolerance,
            },
        );
        valid &= h.valid;
        // Both validators refuse a model with errors the same way (E0422): say it once.
        for d in h.diagnostics {
            if !diagnostics.contains(&d) {
                diagnostics.push(d);
            }
        }
    }
    diagnostics.sort_by_key(|d| (d.range.start(), d.range.end()));
    let valid = valid && diagnostics.iter().all(|d| d.severity != Severity::Error);
    Validation {
        valid,
        checked: true,
        not_judged,
        // Without a verdict, the plan was not executed to its end.
        makespan: not_judged.is_none().then_some(report.makespan),
        value: report.value,
        diagnostics,
    }
}

/// The diagnostics of a plan file of the workspace: reading it, and
/// validating it against its problem when one is found
/// ([`crate::plan::plan_problem`]) with the options of the
/// analysis's settings.
#[salsa::tracked(returns(ref))]
pub fn plan_file_diagnostics(db: &dyn Db, file: SourceFile) -> Vec<Diagnostic> {
    match crate::plan::plan_problem(db, file) {
        Some(problem) => validate_plan(db, file, None, problem, &crate::db::plan_options(db)).diagnostics,
        None => crate::plan::parse_plan(db, file).file_diagnostics(file),
    }
}
