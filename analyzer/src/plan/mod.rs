//! Plans: a located, error-recovering reader of the plan formats users have
//! (docs/plan-formats.md), and the comparison of two plans ([`diff`]).
//!
//! - VAL's format (PDDL 2.1 temporal and sequential plans): [`val`];
//! - the IPC 2020 hierarchical format, and hipop's timed extension of it
//!   (`;@ ID START [DURATION]` annotations after `<==`): [`hierarchical`];
//! - hipop's JSON form of a partial-order plan: [`json`].
//!
//! Every format is read into the same [`Plan`]: steps with their names,
//! arguments, ids, times and decompositions, each with the byte range it was
//! read from, and the diagnostics of what could not be read (codes
//! E0401–E0409, W0401–W0409). Reading never fails and never panics: a malformed
//! line is a diagnostic, and the lines around it are still read.
//!
//! Architecture invariant: like the rest of the analyzer, no I/O and no
//! printing; ranges are absolute byte offsets in the plan file.

pub mod agents;
pub mod diff;
pub mod hierarchical;
pub mod json;
mod lines;
mod problem;
pub mod timeline;
pub mod val;

pub use problem::plan_problem;

#[cfg(test)]
mod tests;

use std::borrow::Cow;

use rowan::TextRange;
use rustc_hash::FxHashMap;

use crate::db::{Db, SourceFile};
use crate::diagnostic::{Code, Diagnostic, LocalDiag, Related, Severity};
use crate::model::Str;

/// The formats a plan can be written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PlanFormat {
    /// VAL's format: `time: (action args…) [duration]`, time and duration
    /// optional (a sequential plan is one `(action args…)` per line).
    Val,
    /// The IPC 2020 hierarchical format (`==>` … `root` … `<==`), with or
    /// without hipop's timing annotations.
    Hierarchical,
    /// hipop's JSON form of a partial-order plan.
    Json,
}

impl PlanFormat {
    pub fn as_str(self) -> &'static str {
        match self {
            PlanFormat::Val => "val",
            PlanFormat::Hierarchical => "hierarchical",
            PlanFormat::Json => "json",
        }
    }
}

/// How messages name a step, in every validator and in `hipop diff`: by the
/// id the plan file gives it (hierarchical and JSON plans: `step 8`, the
/// step whose id is 8), else by its line (VAL plans number no steps: `the
/// step on line 12`). `line` counts from 1; 0 when unknown (`the step`).
pub fn step_label(id: Option<u32>, line: usize) -> String {
    match (id, line) {
        (Some(id), _) => format!("step {id}"),
        (None, 0) => "the step".to_string(),
        (None, line) => format!("the step on line {line}"),
    }
}

/// The line, from 1, of a byte offset of a text.
pub fn line_of(text: &str, offset: rowan::TextSize) -> usize {
    let end = usize::from(offset).min(text.len());
    text.as_bytes()[..end].iter().filter(|&&b| b == b'\n').count() + 1
}

/// A name (action, task, method, object, agent) as written, with its range.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Symbol {
    pub text: Str,
    pub range: TextRange,
}

/// A number as written (kept for messages: `30.980`, not `30.98`), with its value.
#[derive(Debug, Clone, PartialEq)]
pub struct Number {
    pub text: Str,
    /// Always finite.
    pub value: f64,
    pub range: TextRange,
}

/// A step id of a hierarchical or JSON plan (a non-negative integer), where it is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct StepId {
    pub value: u32,
    pub range: TextRange,
}

/// How an abstract step was refined: `-> method subtask-ids…`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decomposition {
    pub method: Symbol,
    /// The subtasks' ids, in the order written.
    pub subtasks: Vec<StepId>,
}

/// An interval of time; `None` bounds are unbounded.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Interval {
    pub lo: Option<f64>,
    pub hi: Option<f64>,
}

/// The earliest and latest times the temporal network of a partial-order plan
/// allows for a step's start and end (JSON plans).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Bounds {
    pub start: Interval,
    pub end: Interval,
}

/// One step of a plan: an action (primitive) or a task refined by a method (abstract).
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// The whole step: its line (without line break and comment) or its JSON object.
    pub range: TextRange,
    /// Hierarchical and JSON plans number their steps; VAL plans do not (a
    /// step is its index in [`Plan::steps`]).
    pub id: Option<StepId>,
    pub name: Symbol,
    pub args: Vec<Symbol>,
    /// When the step starts: VAL's `time:`, a `;@` timing annotation, JSON `start`.
    pub start: Option<Number>,
    /// How long it lasts: VAL's `[duration]`, an annotation's `[duration]`,
    /// JSON `duration` (or `end - start`).
    pub duration: Option<Number>,
    /// `Some` for an abstract step (a decomposition line, a JSON step with a `method`).
    pub decomposition: Option<Decomposition>,
    /// JSON plans: the agents the planner assigned to the step (empty elsewhere).
    pub agents: Vec<Symbol>,
    /// JSON plans: the flexibility of the step's times.
    pub bounds: Option<Bounds>,
}

impl Step {
    pub fn is_abstract(&self) -> bool {
        self.decomposition.is_some()
    }

    /// When the step ends, if it has a start (an instantaneous step ends when it starts).
    pub fn end(&self) -> Option<f64> {
        Some(self.start.as_ref()?.value + self.duration.as_ref().map_or(0.0, |d| d.value))
    }

    /// `(name arg…)`, as written.
    pub fn call(&self) -> String {
        let mut s = String::with_capacity(2 + self.name.text.len() + self.args.len() * 8);
        s.push('(');
        s.push_str(&self.name.text);
        for a in &self.args {
            s.push(' ');
            s.push_str(&a.text);
        }
        s.push(')');
        s
    }
}

/// The `root` line of a hierarchical plan (the JSON `root` array).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Root {
    pub range: TextRange,
    pub ids: Vec<StepId>,
}

/// One end of a causal link: a step, or the initial state / the goal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinkEnd {
    /// The initial state (as a source) or the goal (as a target).
    Problem,
    Step(StepId),
}

/// A literal of a causal link.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Literal {
    pub negated: bool,
    pub predicate: Symbol,
    pub args: Vec<Symbol>,
}

/// `from` achieves `literal` for `to` (JSON plans).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CausalLink {
    pub range: TextRange,
    pub from: LinkEnd,
    pub to: LinkEnd,
    pub literal: Literal,
}

/// The start or the end of a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Point {
    Start,
    End,
}

/// A time point of a plan: the plan's origin (time 0) or a step's start or end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimePoint {
    Origin,
    Step(StepId, Point),
}

/// `min <= to - from <= max` (JSON plans); `None` bounds are unbounded.
#[derive(Debug, Clone, PartialEq)]
pub struct TemporalLink {
    pub range: TextRange,
    pub from: TimePoint,
    pub to: TimePoint,
    pub min: Option<f64>,
    pub max: Option<f64>,
}

/// What a JSON plan says it solves.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ProblemRef {
    pub domain: Option<Symbol>,
    pub problem: Option<Symbol>,
    /// `fnv1a64:…` of the domain and problem ([`json::problem_hash`]).
    pub hash: Option<Symbol>,
}

/// A plan as read from a file, in any format.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub format: PlanFormat,
    /// Every step in the order of the file: in a hierarchical plan the
    /// primitive steps (in execution order) come first, then the abstract ones.
    pub steps: Vec<Step>,
    /// Hierarchical and JSON plans: the roots of the decomposition.
    pub root: Option<Root>,
    /// Hierarchical plans: the `==>` and `<==` lines.
    pub begin: Option<TextRange>,
    pub end: Option<TextRange>,
    pub causal_links: Vec<CausalLink>,
    pub temporal_links: Vec<TemporalLink>,
    pub problem: Option<ProblemRef>,
    /// What could not be read, in absolute ranges of the plan file.
    pub diagnostics: Vec<LocalDiag>,
    /// Step id → index in `steps` (the first step with that id).
    ids: FxHashMap<u32, usize>,
    /// The ids of steps that could not be read (already reported): naming
    /// them is not reported again.
    unreadable: Vec<u32>,
}

impl Plan {
    fn new(format: PlanFormat) -> Plan {
        Plan {
            format,
            steps: Vec::new(),
            root: None,
            begin: None,
            end: None,
            causal_links: Vec::new(),
            temporal_links: Vec::new(),
            problem: None,
            diagnostics: Vec::new(),
            ids: FxHashMap::default(),
            unreadable: Vec::new(),
        }
    }

    /// The index in [`Plan::steps`] of the step with this id.
    pub fn index_of(&self, id: u32) -> Option<usize> {
        self.ids.get(&id).copied()
    }

    pub fn step_by_id(&self, id: u32) -> Option<&Step> {
        self.index_of(id).map(|i| &self.steps[i])
    }

    /// The primitive steps (actions), in the order of the file.
    pub fn primitive_steps(&self) -> impl Iterator<Item = (usize, &Step)> {
        self.steps.iter().enumerate().filter(|(_, s)| !s.is_abstract())
    }

    /// The abstract steps (refined tasks), in the order of the file.
    pub fn abstract_steps(&self) -> impl Iterator<Item = (usize, &Step)> {
        self.steps.iter().enumerate().filter(|(_, s)| s.is_abstract())
    }

    /// Whether the plan has a decomposition (a `root` line or abstract steps).
    pub fn is_hierarchical(&self) -> bool {
        self.root.is_some() || self.steps.iter().any(Step::is_abstract)
    }

    /// Whether some step has a start time.
    pub fn is_timed(&self) -> bool {
        self.steps.iter().any(|s| s.start.is_some())
    }

    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(|d| d.code.severity == Severity::Error)
    }

    /// The plan's diagnostics as [`Diagnostic`]s of `file`.
    pub fn file_diagnostics(&self, file: SourceFile) -> Vec<Diagnostic> {
        self.diagnostics
            .iter()
            .map(|d| Diagnostic {
                code: d.code,
                severity: d.code.severity,
                file,
                range: d.span,
                message: d.message.clone(),
                related: d
                    .related
                    .iter()
                    .map(|(range, message)| Related { file, range: *range, message: message.clone() })
                    .collect(),
                fix: None,
            })
            .collect()
    }

    fn diag(&mut self, code: &'static Code, range: TextRange, message: impl Into<String>) {
        self.diagnostics.push(LocalDiag::new(code, range, message));
    }

    /// Indexes the ids and reports duplicates (E0402) and ids that name no
    /// step (E0403) in the root, the subtasks and the links.
    fn finish(&mut self) {
        use crate::diagnostic::codes::{DUPLICATE_STEP_ID, UNKNOWN_STEP_ID};
        let mut dups = Vec::new();
        for (i, s) in self.steps.iter().enumerate() {
            let Some(id) = s.id else { continue };
            if let Some(&first) = self.ids.get(&id.value) {
                let first = self.steps[first].id.map_or(self.steps[first].range, |f| f.range);
                dups.push(
                    LocalDiag::new(
                        DUPLICATE_STEP_ID,
                        id.range,
                        format!("a second step has the id {}", id.value),
                    )
                    .with_related(first, "the first step with this id"),
                );
            } else {
                self.ids.insert(id.value, i);
            }
        }
        self.diagnostics.extend(dups);
        let mut refs: Vec<(StepId, &'static str)> = Vec::new();
        if let Some(root) = &self.root {
            refs.extend(root.ids.iter().map(|&id| (id, "the root")));
        }
        for s in &self.steps {
            if let Some(d) = &s.decomposition {
                refs.extend(d.subtasks.iter().map(|&id| (id, "this subtask")));
            }
        }
        for l in &self.causal_links {
            for end in [l.from, l.to] {
                if let LinkEnd::Step(id) = end {
                    refs.push((id, "this causal link"));
                }
            }
        }
        for l in &self.temporal_links {
            for end in [l.from, l.to] {
                if let TimePoint::Step(id, _) = end {
                    refs.push((id, "this temporal link"));
                }
            }
        }
        let unknown: Vec<LocalDiag> = refs
            .into_iter()
            .filter(|(id, _)| !self.ids.contains_key(&id.value) && !self.unreadable.contains(&id.value))
            .map(|(id, what)| {
                LocalDiag::new(
                    UNKNOWN_STEP_ID,
                    id.range,
                    format!("{what} names the step {}, which the plan does not have", id.value),
                )
            })
            .collect();
        self.diagnostics.extend(unknown);
        self.diagnostics.sort_by_key(|d| (d.span.start(), d.span.end()));
    }
}

/// The format of a plan, from its content (never from the file's name):
/// JSON if it starts with `{`; hierarchical if a line starts with `==>`, or
/// if more lines look like IPC 2020 lines (`ID name…`, `root …`, `… -> …`,
/// `<==`) than like VAL steps (`time: (…)`, `(…)`); VAL otherwise (an empty
/// plan is an empty VAL plan).
pub fn detect_format(text: &str) -> PlanFormat {
    let first = text.trim_start_matches(['\u{feff}', ' ', '\t', '\r', '\n']);
    if first.starts_with('{') {
        return PlanFormat::Json;
    }
    let (mut val, mut hier) = (0usize, 0usize);
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("==>") {
            return PlanFormat::Hierarchical;
        }
        if t.starts_with(';') || t.is_empty() {
            continue;
        }
        let first_token = t.split_whitespace().next().unwrap_or("");
        if t.starts_with('(') || lines::looks_like_val_step(t) {
            val += 1;
        } else if first_token == "root"
            || first_token == "<=="
            || (first_token.bytes().all(|b| b.is_ascii_digit()) && t.len() > first_token.len())
        {
            hier += 1;
        }
    }
    if hier > val { PlanFormat::Hierarchical } else { PlanFormat::Val }
}

/// Reads a plan in `format`, or in the format its content shows ([`detect_format`]).
pub fn read_plan(text: &str, format: Option<PlanFormat>) -> Plan {
    let format = format.unwrap_or_else(|| detect_format(text));
    let mut plan = match format {
        PlanFormat::Val => val::read(text),
        PlanFormat::Hierarchical => hierarchical::read(text),
        PlanFormat::Json => json::read(text),
    };
    plan.finish();
    plan
}

/// The plan in a file, in the format its content shows.
#[salsa::tracked(returns(ref))]
pub fn parse_plan(db: &dyn Db, file: SourceFile) -> Plan {
    read_plan(file.text(db), None)
}

/// The plan in a file, read in the given format whatever its content.
#[salsa::tracked(returns(ref))]
pub fn parse_plan_as(db: &dyn Db, file: SourceFile, format: PlanFormat) -> Plan {
    read_plan(file.text(db), Some(format))
}

/// How names are compared between plans, and between a plan and a domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum NameMatching {
    /// Byte for byte.
    Exact,
    /// Ignoring ASCII case, as PDDL does.
    #[default]
    CaseInsensitive,
    /// pandaPIparser's `-l`: ignoring case, and `-` and `_` interchangeable
    /// (planners mangle names).
    Lenient,
}

/// The key a name is compared by under `matching`.
pub fn normalise_name(name: &str, matching: NameMatching) -> Cow<'_, str> {
    match matching {
        NameMatching::Exact => Cow::Borrowed(name),
        NameMatching::CaseInsensitive if !name.bytes().any(|b| b.is_ascii_uppercase()) => Cow::Borrowed(name),
        NameMatching::CaseInsensitive => Cow::Owned(name.to_ascii_lowercase()),
        NameMatching::Lenient if !name.bytes().any(|b| b.is_ascii_uppercase() || b == b'_') => {
            Cow::Borrowed(name)
        }
        NameMatching::Lenient => Cow::Owned(
            name.chars().map(|c| if c == '_' { '-' } else { c.to_ascii_lowercase() }).collect::<String>(),
        ),
    }
}
