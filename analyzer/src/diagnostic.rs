//! The one diagnostic type of hipop, and the registry of stable codes.
//!
//! Architecture invariant: no LSP or terminal types here. The CLI converts
//! to codespan-reporting, the server to LSP; both keep the code, the message,
//! the primary range, the related ranges and the fix.

use rowan::TextRange;

use crate::input::SourceFile;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Severity {
    Error,
    Warning,
    Info,
}

impl Severity {
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
            Severity::Info => "info",
        }
    }
}

/// A stable diagnostic code.
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct Code {
    /// `E0102`: never reused for another meaning.
    pub id: &'static str,
    /// `undefined-predicate`: the name used in docs and in `--format json`.
    pub name: &'static str,
    pub severity: Severity,
    /// One line for `hipop check --explain`-style listings.
    pub summary: &'static str,
}

macro_rules! codes {
    ($($konst:ident = $id:literal $name:literal $sev:ident $summary:literal;)*) => {
        $(pub const $konst: &Code = &Code { id: $id, name: $name, severity: Severity::$sev, summary: $summary };)*
        /// Every code, in order.
        pub const ALL: &[&Code] = &[$($konst),*];
    };
}

/// The registry. Documented with an example each in `docs/diagnostics.md`.
pub mod codes {
    use super::{Code, Severity};
    codes! {
        MISSING_PAREN = "E0001" "missing-paren" Error "a list is not closed";
        EXTRA_PAREN = "E0002" "extra-paren" Error "a `)` closes nothing or closes too early";
        MALFORMED = "E0003" "malformed" Error "an element does not have the expected shape";
        UNKNOWN_SECTION = "E0004" "unknown-section" Error "a section or field keyword is not part of the language";
        MISPLACED_SECTION = "E0006" "misplaced-section" Error "a problem section in a domain, or the reverse";
        NESTING_TOO_DEEP = "E0007" "nesting-too-deep" Error "lists nested more than 256 deep: the deeper list is kept as text, not read";
        DIAGNOSTICS_NOT_SHOWN = "I0008" "diagnostics-not-shown" Info "a file has more diagnostics than are shown (200 by default): how many more, of which severities";
        UNDEFINED_TYPE = "E0101" "undefined-type" Error "a type is used but not declared";
        UNDEFINED_PREDICATE = "E0102" "undefined-predicate" Error "a predicate is used but not declared";
        UNDEFINED_FUNCTION = "E0103" "undefined-function" Error "a function (numeric fluent) is used but not declared";
        UNDEFINED_ACTION = "E0104" "undefined-action" Error "a subtask or allowed action names no action or task";
        UNDEFINED_TASK = "E0105" "undefined-task" Error "a method decomposes a task that is not declared";
        UNDEFINED_OBJECT = "E0106" "undefined-object" Error "a constant or object is used but not declared";
        UNDEFINED_VARIABLE = "E0107" "undefined-variable" Error "a variable is not bound by a parameter or quantifier";
        UNDEFINED_SUBTASK = "E0108" "undefined-subtask" Error "an ordering or constraint names no subtask id of its network";
        DUPLICATE = "E0109" "duplicate-definition" Error "a name is declared twice";
        ARITY = "E0110" "wrong-arity" Error "a predicate, function, action or task gets the wrong number of arguments";
        TYPE_MISMATCH = "E0111" "type-mismatch" Error "an argument's type is not a subtype of the parameter's type";
        TYPE_CYCLE = "E0112" "type-cycle" Error "the type hierarchy has a cycle";
        ORDERING_CYCLE = "E0113" "ordering-cycle" Error "the ordering constraints of a task network have a cycle";
        MISSING_DOMAIN = "E0114" "missing-domain" Error "a problem's domain is not among the files";
        NEGATIVE_DURATION = "E0115" "negative-duration" Error "a duration constraint whose constant value is negative or not a finite number: the action can never be applied";

        UNUSED = "W0201" "unused-declaration" Warning "a type, predicate, function or constant is declared but never used";
        UNKNOWN_REQUIREMENT = "W0202" "unknown-requirement" Warning "a requirement is not one hipop knows";
        MISSING_REQUIREMENT = "W0203" "missing-requirement" Warning "a feature is used without its requirement";
        DUPLICATE_TYPE = "W0204" "duplicate-type" Warning "a type is declared twice";
        DOMAIN_MISMATCH = "W0205" "domain-mismatch" Warning "a problem names a domain other than the one beside it";
        CONSTANT_FROM_PROBLEM = "W0206" "constant-from-problem" Warning "a domain uses a constant that only its problems declare";
        // E0005 was this diagnostic as an error: retired, never to be reused.
        UNSUPPORTED = "W0207" "unsupported" Warning "a construct hipop reads but does not check, plan or validate with (PDDL+ processes and events)";

        UNCOVERED_CONFLICT = "E0301" "uncovered-conflict" Error "a literal that a method of a task may delete is not covered by the task's `:conflicts`";
        UNUSED_CONFLICT = "W0302" "unused-conflict" Warning "a conflict atom that no method of the task can delete";
        TASK_WITHOUT_METHODS = "E0303" "task-without-methods" Error "a task that the model uses has no method: it can never be refined";
        UNUSED_TASK = "W0304" "unused-task" Warning "a task without methods that nothing uses";
        DURATION_NOT_EVALUABLE = "E0305" "duration-not-evaluable" Error "no instance of an action has a duration in a problem: its duration cannot be evaluated from the problem's numeric fluents, or is negative";
        DURATION_UNDEFINED = "I0306" "duration-undefined" Info "some instances of an action have no duration in a problem (a fluent without value): PDDL 2.1 makes them not applicable";
        INVALID_DURATION_VALUE = "W0315" "invalid-duration-value" Warning "a duration computed from a problem's fluents is negative or not a finite number (a division by zero) for some instances of an action";
        NOT_A_POSITION_FAMILY = "I0307" "not-a-position-family" Info "a predicate that looks like a position fails a property of Definition 12 (with the witness)";
        MISSING_MOVE = "I0308" "missing-move" Info "pairs of positions of a family with no move action between them (Definition 14, property 4)";
        FASTER_THAN_MOVE = "W0309" "faster-than-move" Warning "an action changes position faster than the move action (Definition 14, property 5)";
        TRIANGLE_INEQUALITY = "W0310" "triangle-inequality" Warning "a direct move is slower than going through another position (Definition 14, property 6)";
        DEAD_ACTION = "W0311" "dead-action" Warning "an action or task that can never be in a plan with the problem's allowed actions";
        DOUBLE_INSERTION = "W0312" "double-insertion" Warning "an allowed action is also a subtask of an allowed task's method: the same plan can be built twice";
        UNREACHABLE_GOAL = "E0313" "unreachable-goal" Error "a goal or `:htn` task cannot be achieved with the allowed actions and the methods, even ignoring deletions";
        UNINSTANTIABLE_METHOD = "W0314" "uninstantiable-method" Warning "a method has instances in a problem, but none whose subtasks all have instances: it can never be used";

        MALFORMED_STEP = "E0401" "malformed-step" Error "a plan step (a VAL line, an IPC 2020 line or a JSON step) cannot be read";
        DUPLICATE_STEP_ID = "E0402" "duplicate-step-id" Error "two steps of a plan have the same id";
        UNKNOWN_STEP_ID = "E0403" "unknown-step-id" Error "a root, subtask, timing annotation or link names a step id the plan does not have";
        MISSING_PLAN_START = "E0404" "missing-plan-start" Error "a hierarchical plan has no `==>` line before its steps";
        MALFORMED_PLAN_LINE = "E0405" "malformed-plan-line" Error "a `root` line or timing annotation of a hierarchical plan is misplaced or cannot be read";
        MALFORMED_JSON_PLAN = "E0406" "malformed-json-plan" Error "a JSON plan is not JSON, or a part other than a step (header, problem, root, links) cannot be read";
        IGNORED_LINE = "W0401" "ignored-line" Warning "text in a plan that is neither a step nor a comment, and is ignored";
        UNPORTABLE_PLAN_LINE = "W0402" "unportable-plan-line" Warning "a comment or timing annotation inside `==>` … `<==`, which pandaPIparser rejects";
        MIXED_TIMING = "W0403" "mixed-timing" Warning "some steps of a plan have a start time and others do not";

        UNKNOWN_ACTION_IN_PLAN = "E0410" "unknown-action-in-plan" Error "a plan step names no action of the domain";
        STEP_ARITY = "E0411" "step-arity" Error "a plan step gives its action the wrong number of arguments";
        UNKNOWN_OBJECT_IN_PLAN = "E0412" "unknown-object-in-plan" Error "an argument of a plan step is not an object of the problem or a constant of the domain";
        STEP_TYPE_MISMATCH = "E0413" "step-type-mismatch" Error "an argument of a plan step is not of its parameter's type";
        INVALID_STEP_TIMING = "E0414" "invalid-step-timing" Error "a durative action without a duration, or a negative or non-finite time or duration";
        PRECONDITION_FALSE = "E0415" "precondition-false" Error "a condition of a step (`at start`, `at end`, a precondition) is false when the step happens";
        INVARIANT_VIOLATED = "E0416" "invariant-violated" Error "an `over all` condition is false while its step runs";
        DURATION_VIOLATED = "E0417" "duration-violated" Error "a step's duration does not satisfy its action's duration constraint";
        MUTEX_HAPPENINGS = "E0418" "mutex-happenings" Error "interfering steps happen at the same time (one happening for VAL)";
        GOAL_NOT_REACHED = "E0419" "goal-not-reached" Error "the goal is false after the last step";
        NUMERIC_ERROR = "E0420" "numeric-error" Error "a numeric value cannot be computed while executing the plan (a fluent without value, a division by zero)";
        UNSUPPORTED_IN_PLAN = "E0421" "unsupported-in-plan" Error "the plan needs a feature the validator cannot check (PDDL+, derived predicates, PDDL 3)";
        MODEL_NOT_VALIDATABLE = "E0422" "model-not-validatable" Error "the plan is not validated: the problem has no domain, or the domain or the problem has errors";
        DURATION_IGNORED = "W0410" "duration-ignored" Warning "an instantaneous action is given a duration, which is ignored";
        CLOSE_HAPPENINGS = "W0411" "close-happenings" Warning "interfering steps closer than the tolerance, which VAL accepts as separate happenings";
        VALUE_NOT_EVALUABLE = "W0412" "value-not-evaluable" Warning "the problem's metric cannot be evaluated on the plan";

        UNKNOWN_TASK_IN_PLAN = "E0430" "unknown-task-in-plan" Error "an abstract step (a decomposition) names no task of the domain";
        TASK_STEP_ARITY = "E0431" "task-step-arity" Error "an abstract step gives its task the wrong number of arguments";
        UNKNOWN_METHOD = "E0432" "unknown-method" Error "a decomposition names no method of the domain";
        WRONG_METHOD = "E0433" "wrong-method" Error "a decomposition's method is a method of another task";
        METHOD_HEAD_MISMATCH = "E0434" "method-head-mismatch" Error "an abstract step's arguments do not unify with its method's `:task` (a constant, a repeated variable, a parameter's type)";
        MISSING_SUBTASK = "E0435" "missing-subtask" Error "a subtask of the method has no step among the decomposition's subtasks";
        UNEXPECTED_SUBTASK = "E0436" "unexpected-subtask" Error "a step listed as a subtask fits no subtask of the method left";
        DUPLICATE_SUBTASK = "E0437" "duplicate-subtask" Error "a decomposition or the `root` line lists the same step twice";
        SUBTASK_LISTING_ORDER = "E0438" "subtask-listing-order" Error "subtasks (or roots) listed in an order the method's (or the `:htn`'s) ordering forbids; pandaPIparser matches them in the listed order";
        ORDERING_VIOLATED = "E0439" "ordering-violated" Error "an ordering of a method or of the `:htn` does not hold in the plan's order or times";
        SHARED_STEP = "E0440" "shared-step" Error "a step is a subtask of two decompositions, or a root and a subtask";
        ORPHAN_STEP = "E0441" "orphan-step" Error "a step that the `root` line does not reach through decompositions";
        DECOMPOSITION_CYCLE = "E0442" "decomposition-cycle" Error "a step is its own subtask, directly or through other decompositions";
        HTN_MISMATCH = "E0443" "htn-mismatch" Error "the roots of the plan are not the tasks of the problem's `:htn`";
        METHOD_PRECONDITION_FALSE = "E0444" "method-precondition-false" Error "a method's precondition or constraint is false where the method is applied";
        ABSTRACT_STEP_TIMING = "E0445" "abstract-step-timing" Error "a timed abstract step does not contain the times of its subtasks";
        ABSTRACT_ACTION_VIOLATED = "E0446" "abstract-action-violated" Error "a HiPOP abstract action's precondition is false where its step starts, or its effect where it ends";
        METHOD_DURATION_VIOLATED = "E0447" "method-duration-violated" Error "a timed abstract step's duration does not satisfy the duration constraint of its durative method or HiPOP abstract action";
        HIERARCHY_NOT_CHECKED = "W0430" "hierarchy-not-checked" Warning "a part of a plan's hierarchy the validator cannot check (method effects and durations, HDDL 2.1 constraints, too many matchings)";

        PLANNER_UNSUPPORTED = "E0501" "planner-unsupported" Error "the planner cannot plan this problem: a construct it does not support, errors in the model, or grounding past its limits";
        NO_PLAN = "E0502" "no-plan" Error "no plan exists with the allowed actions and the methods: the planner explored every partial plan";
        PLANNER_LIMIT = "E0503" "planner-limit" Error "the planner stopped at a limit (time, nodes, memory) before finding a plan";
        PLAN_OPEN_LINK = "I0504" "open-link" Info "a condition that nothing supports in the best partial plan the planner found";
        PLAN_THREAT = "I0505" "unresolved-threat" Info "a step that can delete a condition between its producer and its consumer, in the best partial plan";
        PLAN_ABSTRACT_FLAW = "I0506" "abstract-flaw" Info "an abstract step the best partial plan could not refine with any method";
    }
}

/// A secondary location with a message.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Related {
    pub file: SourceFile,
    pub range: TextRange,
    pub message: String,
}

/// A text replacement that fixes a diagnostic.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Fix {
    pub message: String,
    pub edits: Vec<(SourceFile, TextRange, String)>,
}

/// A diagnostic located in absolute byte ranges of a file.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    pub code: &'static Code,
    pub severity: Severity,
    pub file: SourceFile,
    pub range: TextRange,
    pub message: String,
    pub related: Vec<Related>,
    pub fix: Option<Fix>,
}

/// A diagnostic found while lowering or checking one item, in item-relative ranges.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct LocalDiag {
    pub code: &'static Code,
    pub span: TextRange,
    pub message: String,
    /// Related spans in the same item.
    pub related: Vec<(TextRange, String)>,
    /// A replacement in the same item.
    pub fix: Option<(String, TextRange, String)>,
}

impl LocalDiag {
    pub fn new(code: &'static Code, span: TextRange, message: impl Into<String>) -> LocalDiag {
        LocalDiag { code, span, message: message.into(), related: Vec::new(), fix: None }
    }

    pub fn with_related(mut self, span: TextRange, message: impl Into<String>) -> LocalDiag {
        self.related.push((span, message.into()));
        self
    }

    pub fn with_fix(
        mut self,
        message: impl Into<String>,
        span: TextRange,
        insert: impl Into<String>,
    ) -> LocalDiag {
        self.fix = Some((message.into(), span, insert.into()));
        self
    }
}

/// How many diagnostics of one file the shells show (`hipop check
/// --max-diagnostics`, the language server).
pub const SHOWN_PER_FILE: usize = 200;

/// The diagnostics to show: at most `max` per file (all when `max` is 0),
/// errors first, then warnings, then information, each file's in their order;
/// a file with more ends with one I0008 that says how many more there are, of
/// which severities, at the first of them. What the shells count (the exit
/// status, the summary) is every diagnostic, not only those shown.
pub fn shown_per_file(diagnostics: &[Diagnostic], max: usize) -> Vec<Diagnostic> {
    let mut files: Vec<(SourceFile, Vec<usize>)> = Vec::new();
    let mut index: rustc_hash::FxHashMap<SourceFile, usize> = rustc_hash::FxHashMap::default();
    for (i, d) in diagnostics.iter().enumerate() {
        let at = *index.entry(d.file).or_insert_with(|| {
            files.push((d.file, Vec::new()));
            files.len() - 1
        });
        files[at].1.push(i);
    }
    let mut out = Vec::with_capacity(diagnostics.len().min(files.len() * (max + 1)));
    for (file, all) in files {
        if max == 0 || all.len() <= max {
            out.extend(all.iter().map(|&i| diagnostics[i].clone()));
            continue;
        }
        let mut by_severity = all.clone();
        by_severity.sort_by_key(|&i| diagnostics[i].severity);
        let mut shown = by_severity[..max].to_vec();
        shown.sort_unstable();
        out.extend(shown.iter().map(|&i| diagnostics[i].clone()));
        let hidden = &by_severity[max..];
        let count = |s: Severity| hidden.iter().filter(|&&i| diagnostics[i].severity == s).count();
        let parts: Vec<String> =
            [(Severity::Error, "error"), (Severity::Warning, "warning"), (Severity::Info, "info")]
                .into_iter()
                .map(|(s, word)| (count(s), word))
                .filter(|&(n, _)| n > 0)
                .map(|(n, word)| format!("{n} {word}{}", if n == 1 { "" } else { "s" }))
                .collect();
        let first = hidden.iter().min().map_or(TextRange::default(), |&i| diagnostics[i].range);
        out.push(Diagnostic {
            code: codes::DIAGNOSTICS_NOT_SHOWN,
            severity: codes::DIAGNOSTICS_NOT_SHOWN.severity,
            file,
            range: first,
            message: format!(
                "{} more diagnostic{} in this file not shown ({}), the first of them here: \
                 hipop shows at most {max} per file",
                hidden.len(),
                if hidden.len() == 1 { "" } else { "s" },
                parts.join(", ")
            ),
            related: Vec::new(),
            fix: None,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diagnostic(file: SourceFile, at: u32, code: &'static Code) -> Diagnostic {
        Diagnostic {
            code,
            severity: code.severity,
            file,
            range: TextRange::at(at.into(), 1.into()),
            message: format!("{} at {at}", code.id),
            related: Vec::new(),
            fix: None,
        }
    }

    #[test]
    fn at_most_max_per_file_errors_first_then_what_is_left_out() {
        let mut host = crate::AnalysisHost::new();
        let (a, b) = (host.set_file_text("a.pddl", ""), host.set_file_text("b.pddl", ""));
        // a: warnings at 0..4, errors at 10..13; b: two infos.
        let mut all: Vec<Diagnostic> = (0..4).map(|i| diagnostic(a, i, codes::UNUSED)).collect();
        all.extend((10..13).map(|i| diagnostic(a, i, codes::EXTRA_PAREN)));
        all.extend((0..2).map(|i| diagnostic(b, i, codes::MISSING_MOVE)));
        let shown = shown_per_file(&all, 4);
        let summary: Vec<(SourceFile, &str, u32)> =
            shown.iter().map(|d| (d.file, d.code.id, u32::from(d.range.start()))).collect();
        assert_eq!(
            summary,
            vec![
                (a, "W0201", 0),
                (a, "E0002", 10),
                (a, "E0002", 11),
                (a, "E0002", 12),
                (a, "I0008", 1),
                (b, "I0308", 0),
                (b, "I0308", 1),
            ]
        );
        assert_eq!(
            shown[4].message,
            "3 more diagnostics in this file not shown (3 warnings), the first of them here: \
             hipop shows at most 4 per file"
        );
        assert_eq!(shown[4].severity, Severity::Info);
        assert_eq!(shown_per_file(&all, 0), all);
        assert_eq!(shown_per_file(&all, 7), all);
    }
}
