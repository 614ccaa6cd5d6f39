//! The IPC 2020 hierarchical plan format, as pandaPIparser reads it, and
//! hipop's timed extension of it:
//!
//! ```text
//! planner log…            (ignored)
//! ==>
//! 0 move r1 a b           (primitive steps, in execution order)
//! 1 observe r1 b p1
//! root 2                  (the top-level tasks)
//! 2 patrol r1 a b -> m-patrol 0 1   (decompositions: task -> method subtasks)
//! <==
//! ;@ 0 0.000 [30.980]     (timing annotations: step, start, duration)
//! ;@ 1 30.990 [5.000]
//! ;@ 2 0.000 [35.990]
//! ```
//!
//! Tolerated like pandaPIparser: anything before `==>`; a missing `<==`
//! (the plan then ends at the first line that is not a decomposition, W0401 if
//! text follows); parentheses around a step (`0 (move r1 a b)`); braced
//! arguments (`0 move[r1,a,b]`); method names of any characters. Timing
//! annotations belong after `<==`, where pandaPIparser stops reading; inside
//! the block they are read, with a warning (W0402), as are `;` comments.

use super::lines::{Line, Token, lines, number, range, step_id};
use super::{Decomposition, Number, Plan, PlanFormat, Root, Step, StepId, Symbol};
use crate::diagnostic::LocalDiag;
use crate::diagnostic::codes::{
    IGNORED_LINE, MALFORMED_PLAN_LINE, MALFORMED_STEP, MISSING_PLAN_START, MIXED_TIMING, UNKNOWN_STEP_ID,
    UNPORTABLE_PLAN_LINE,
};
use rowan::TextRange;
use rustc_hash::FxHashMap;

/// Where the reader is in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Section {
    /// After `==>`, before `root`.
    Primitives,
    /// After `root`.
    Decompositions,
    /// After `<==`.
    After,
    /// The plan ended without `<==` at a line that is not a decomposition:
    /// the rest of the file is ignored.
    Ended,
}

/// A `;@ ID START [DURATION]` annotation.
struct Timing {
    id: StepId,
    start: Number,
    duration: Option<Number>,
    range: TextRange,
}

struct Reader {
    plan: Plan,
    section: Section,
    timings: Vec<Timing>,
    root_seen: bool,
    /// A decomposition line came before any `root` line (reported once).
    missing_root_reported: bool,
    second_plan_reported: bool,
}

/// Reads a hierarchical plan.
pub fn read(text: &str) -> Plan {
    let all: Vec<Line<'_>> = lines(text).collect();
    let mut r = Reader {
        plan: Plan::new(PlanFormat::Hierarchical),
        section: Section::Primitives,
        timings: Vec::new(),
        root_seen: false,
        missing_root_reported: false,
        second_plan_reported: false,
    };
    let begin = all.iter().position(|l| l.tokens().first().is_some_and(|t| t.text == "==>"));
    let first = match begin {
        Some(k) => {
            let marker = all[k].tokens()[0];
            r.plan.begin = Some(marker.range());
            let rest = all[k].rest(marker.end() - all[k].start);
            if !rest.is_blank() {
                r.line(rest);
            }
            k + 1
        }
        None => {
            let plan_like = |l: &Line<'_>| {
                l.tokens()
                    .first()
                    .is_some_and(|t| step_id(*t).is_some() || t.text == "root" || t.text == "<==")
            };
            match all.iter().position(plan_like) {
                Some(k) => {
                    r.plan.diag(
                        MISSING_PLAN_START,
                        all[k].trimmed_range(),
                        "expected a `==>` line before the plan's first step: readers of the IPC 2020 \
                         format skip everything before it",
                    );
                    k
                }
                None => {
                    r.plan.diag(
                        MISSING_PLAN_START,
                        range(0, 0),
                        "no `==>` line and no step: this is not a hierarchical plan",
                    );
                    return r.plan;
                }
            }
        }
    };
    for &line in &all[first..] {
        r.line(line);
    }
    r.apply_timings();
    r.plan
}

/// Splits tokens at parentheses, which pandaPIparser reads as spaces.
fn split_parens<'t>(tokens: &[Token<'t>]) -> Vec<Token<'t>> {
    let mut out = Vec::with_capacity(tokens.len());
    for t in tokens {
        let mut from = 0;
        for (i, c) in t.text.char_indices() {
            if c == '(' || c == ')' {
                if i > from {
                    out.push(Token { start: t.start + from, text: &t.text[from..i] });
                }
                from = i + 1;
            }
        }
        if from < t.text.len() {
            out.push(Token { start: t.start + from, text: &t.text[from..] });
        }
    }
    out
}

fn symbol(t: Token<'_>) -> Symbol {
    Symbol { text: t.text.into(), range: t.range() }
}

/// A task or action with its arguments: `name arg…`, `(name arg…)` or
/// `name[arg,…] arg…`. `None` without a name.
fn task(tokens: &[Token<'_>]) -> Option<(Symbol, Vec<Symbol>)> {
    let words = split_parens(tokens);
    let (first, rest) = words.split_first()?;
    let mut args = Vec::with_capacity(rest.len());
    let name = match first.text.find('[') {
        Some(open) => {
            let inner = &first.text[open + 1..];
            let inner = inner.strip_suffix(']').unwrap_or(inner);
            let mut at = first.start + open + 1;
            for piece in inner.split(',') {
                let lead = piece.len() - piece.trim_start().len();
                let p = piece.trim();
                if !p.is_empty() {
                    args.push(Symbol { text: p.into(), range: range(at + lead, at + lead + p.len()) });
                }
                at += piece.len() + 1;
            }
            Token { start: first.start, text: &first.text[..open] }
        }
        None => *first,
    };
    if name.text.is_empty() {
        return None;
    }
    args.extend(rest.iter().copied().map(symbol));
    Some((symbol(name), args))
}

impl Reader {
    fn line(&mut self, line: Line<'_>) {
        let tokens = line.tokens();
        let Some(first) = tokens.first().copied() else { return };
        match self.section {
            Section::After => {
                if first.text.starts_with(";@") {
                    self.annotation(line, false);
                } else if first.text == "==>" && !self.second_plan_reported {
                    self.second_plan_reported = true;
                    self.plan.diag(
                        IGNORED_LINE,
                        first.range(),
                        "a second plan starts here: only the first plan of a file is read",
                    );
                }
                // Like pandaPIparser, everything else after `<==` is ignored.
            }
            Section::Ended => {
                if first.text.starts_with(";@") {
                    self.annotation(line, true);
                }
            }
            Section::Primitives | Section::Decompositions => {
                if first.text.starts_with(';') {
                    if first.text.starts_with(";@") {
                        self.annotation(line, true);
                    } else {
                        self.plan.diag(
                            UNPORTABLE_PLAN_LINE,
                            line.trimmed_range(),
                            "pandaPIparser does not accept comments between `==>` and `<==`: \
                             it reads this line as a step",
                        );
                    }
                    return;
                }
                // `;` inside a token is part of a name (pandaPIparser's compressed
                // method names have some); a token that starts with `;` starts a comment.
                let comment = tokens.iter().find(|t| t.text.starts_with(';')).map(|t| t.start - line.start);
                let body = match comment {
                    Some(i) => {
                        let comment = line.rest(i);
                        self.plan.diag(
                            UNPORTABLE_PLAN_LINE,
                            comment.trimmed_range(),
                            "pandaPIparser does not accept comments between `==>` and `<==`: \
                             it reads this comment as arguments of the step",
                        );
                        line.until(i)
                    }
                    None => line,
                };
                let tokens = body.tokens();
                if tokens.is_empty() {
                    return;
                }
                match first.text {
                    "<==" => {
                        self.plan.end = Some(first.range());
                        self.section = Section::After;
                    }
                    "root" => self.root(body, &tokens),
                    _ if self.section == Section::Primitives => self.primitive(body, &tokens),
                    _ => self.decomposition(body, &tokens),
                }
            }
        }
    }

    fn root(&mut self, body: Line<'_>, tokens: &[Token<'_>]) {
        if self.root_seen {
            let first = self.plan.root.as_ref().map(|r| r.range);
            let mut d = LocalDiag::new(
                MALFORMED_PLAN_LINE,
                body.trimmed_range(),
                "a second `root` line: a plan has one, listing all its top-level tasks",
            );
            if let Some(first) = first {
                d = d.with_related(first, "the first `root` line");
            }
            self.plan.diagnostics.push(d);
            return;
        }
        if self.missing_root_reported {
            self.plan.diag(
                MALFORMED_PLAN_LINE,
                body.trimmed_range(),
                "the `root` line comes after decomposition lines: write it between the primitive steps \
                 and the decompositions",
            );
        }
        self.root_seen = true;
        let mut ids = Vec::with_capacity(tokens.len().saturating_sub(1));
        for &t in &tokens[1..] {
            match step_id(t) {
                Some(id) => ids.push(id),
                None => self.plan.diag(
                    MALFORMED_PLAN_LINE,
                    t.range(),
                    format!(
                        "`{}` is not a step id: the `root` line lists the ids of the top-level tasks",
                        t.text
                    ),
                ),
            }
        }
        self.plan.root = Some(Root { range: body.trimmed_range(), ids });
        self.section = Section::Decompositions;
    }

    fn primitive(&mut self, body: Line<'_>, tokens: &[Token<'_>]) {
        let Some(id) = step_id(tokens[0]) else {
            self.plan.diag(
                MALFORMED_STEP,
                body.trimmed_range(),
                format!(
                    "expected a primitive step `ID action args…` or `root ID…`; `{}` is not a step id",
                    tokens[0].text
                ),
            );
            return;
        };
        if tokens.iter().any(|t| t.text == "->") {
            if !self.missing_root_reported {
                self.missing_root_reported = true;
                self.plan.diag(
                    MALFORMED_PLAN_LINE,
                    body.trimmed_range(),
                    "a decomposition line before the `root` line: pandaPIparser reads it as a primitive \
                     step (write `root ID…` between the primitive steps and the decompositions)",
                );
            }
            self.section = Section::Decompositions;
            self.decomposition(body, tokens);
            return;
        }
        let Some((name, args)) = task(&tokens[1..]) else {
            self.plan.diag(
                MALFORMED_STEP,
                body.trimmed_range(),
                format!("expected the action's name and arguments after the id `{}`", id.value),
            );
            self.plan.unreadable.push(id.value);
            return;
        };
        self.push(body, id, name, args, None);
    }

    fn decomposition(&mut self, body: Line<'_>, tokens: &[Token<'_>]) {
        let arrow = tokens.iter().position(|t| t.text == "->");
        let Some(id) = step_id(tokens[0]) else {
            if arrow.is_some() {
                self.plan.diag(
                    MALFORMED_STEP,
                    tokens[0].range(),
                    format!(
                        "`{}` is not a step id: a decomposition is `ID task args… -> method subtask-ids…`",
                        tokens[0].text
                    ),
                );
            } else {
                // Without `<==`, the plan ends at the first line that is not a
                // decomposition (pandaPIparser stops there too).
                self.plan.diag(
                    IGNORED_LINE,
                    body.trimmed_range(),
                    "this is not a decomposition line and the plan has no `<==`: the plan ends before \
                     this line, and the rest of the file is ignored",
                );
                self.section = Section::Ended;
            }
            return;
        };
        let Some(arrow) = arrow else {
            self.plan.unreadable.push(id.value);
            self.plan.diag(
                MALFORMED_STEP,
                body.trimmed_range(),
                "expected `-> method subtask-ids…` after the task: every line after `root` is a decomposition",
            );
            return;
        };
        let Some((name, args)) = task(&tokens[1..arrow]) else {
            self.plan.unreadable.push(id.value);
            self.plan.diag(
                MALFORMED_STEP,
                range(usize::from(id.range.start()), tokens[arrow].end()),
                format!("expected the task's name between the id `{}` and `->`", id.value),
            );
            return;
        };
        let Some(&method) = tokens.get(arrow + 1) else {
            self.plan.unreadable.push(id.value);
            self.plan.diag(MALFORMED_STEP, tokens[arrow].range(), "expected the method's name after `->`");
            return;
        };
        let mut subtasks = Vec::with_capacity(tokens.len() - arrow - 2);
        for &t in &tokens[arrow + 2..] {
            match step_id(t) {
                Some(sub) => subtasks.push(sub),
                None => self.plan.diag(
                    MALFORMED_STEP,
                    t.range(),
                    format!(
                        "`{}` is not a step id: the method's name is followed by the ids of its subtasks",
                        t.text
                    ),
                ),
            }
        }
        let decomposition = Decomposition { method: symbol(method), subtasks };
        self.push(body, id, name, args, Some(decomposition));
    }

    fn push(
        &mut self,
        body: Line<'_>,
        id: StepId,
        name: Symbol,
        args: Vec<Symbol>,
        decomposition: Option<Decomposition>,
    ) {
        self.plan.steps.push(Step {
            range: body.trimmed_range(),
            id: Some(id),
            name,
            args,
            start: None,
            duration: None,
            decomposition,
            agents: Vec::new(),
            bounds: None,
        });
    }

    /// `;@ ID START [DURATION]`.
    fn annotation(&mut self, line: Line<'_>, in_block: bool) {
        let Some(at) = line.text.find(";@") else { return };
        let whole = line.rest(at).trimmed_range();
        if in_block {
            self.plan.diag(
                UNPORTABLE_PLAN_LINE,
                whole,
                "a timing annotation before `<==`: pandaPIparser reads it as a step; write `<==` before the \
                 timing annotations",
            );
        }
        let rest = line.rest(at + 2);
        let tokens = rest.tokens();
        let expected = "a timing annotation is `;@ ID START [DURATION]`";
        let Some(id) = tokens.first().and_then(|t| step_id(*t)) else {
            let found = tokens.first().map_or("nothing".to_string(), |t| format!("`{}`", t.text));
            self.plan.diag(
                MALFORMED_PLAN_LINE,
                whole,
                format!("expected a step id after `;@`, found {found}: {expected}"),
            );
            return;
        };
        let start = match tokens.get(1).map(|t| number(t.text, t.start)) {
            Some(Ok(n)) => n,
            Some(Err(m)) => {
                self.plan.diag(
                    MALFORMED_PLAN_LINE,
                    tokens[1].range(),
                    format!("{m}: expected the start time of step {}", id.value),
                );
                return;
            }
            None => {
                self.plan.diag(
                    MALFORMED_PLAN_LINE,
                    whole,
                    format!("expected the start time of step {} after its id: {expected}", id.value),
                );
                return;
            }
        };
        let after = rest.rest(tokens[1].end() - rest.start);
        let duration = if after.is_blank() {
            None
        } else {
            let t = after.text.trim();
            let lead = after.text.len() - after.text.trim_start().len();
            let inner = t.strip_prefix('[').and_then(|s| s.strip_suffix(']'));
            let parsed = inner.map(|s| {
                let l2 = s.len() - s.trim_start().len();
                number(s.trim(), after.start + lead + 1 + l2)
            });
            match parsed {
                Some(Ok(n)) => Some(n),
                Some(Err(m)) => {
                    self.plan.diag(
                        MALFORMED_PLAN_LINE,
                        after.trimmed_range(),
                        format!("{m}: expected the duration of step {}", id.value),
                    );
                    return;
                }
                None => {
                    self.plan.diag(
                        MALFORMED_PLAN_LINE,
                        after.trimmed_range(),
                        format!("expected `[DURATION]` after the start time: {expected}"),
                    );
                    return;
                }
            }
        };
        self.timings.push(Timing { id, start, duration, range: whole });
    }

    /// Gives the steps their annotated times; reports annotations of unknown
    /// steps, second annotations of a step, and primitive steps left without
    /// a time when others have one.
    fn apply_timings(&mut self) {
        if self.timings.is_empty() {
            return;
        }
        let mut index: FxHashMap<u32, usize> = FxHashMap::default();
        for (i, s) in self.plan.steps.iter().enumerate() {
            if let Some(id) = s.id {
                index.entry(id.value).or_insert(i);
            }
        }
        let mut seen: FxHashMap<u32, TextRange> = FxHashMap::default();
        for t in std::mem::take(&mut self.timings) {
            if let Some(&first) = seen.get(&t.id.value) {
                self.plan.diagnostics.push(
                    LocalDiag::new(
                        MALFORMED_PLAN_LINE,
                        t.range,
                        format!("a second timing annotation for step {}", t.id.value),
                    )
                    .with_related(first, "the first one"),
                );
                continue;
            }
            seen.insert(t.id.value, t.range);
            match index.get(&t.id.value) {
                Some(&i) => {
                    let step = &mut self.plan.steps[i];
                    step.start = Some(t.start);
                    step.duration = t.duration;
                }
                None => self.plan.diag(
                    UNKNOWN_STEP_ID,
                    t.id.range,
                    format!(
                        "this timing annotation names the step {}, which the plan does not have",
                        t.id.value
                    ),
                ),
            }
        }
        let timed = self.plan.steps.iter().filter(|s| s.start.is_some()).count();
        let untimed = self.plan.steps.iter().find(|s| !s.is_abstract() && s.start.is_none());
        if let Some(s) = untimed {
            let id = s.id.map_or(0, |i| i.value);
            let range = s.id.map_or(s.range, |i| i.range);
            let message = format!(
                "the primitive step {id} has no timing annotation, but {timed} other step{} {}: \
                 add `;@ {id} START [DURATION]` after `<==`",
                if timed == 1 { "" } else { "s" },
                if timed == 1 { "has one" } else { "have one" }
            );
            self.plan.diag(MIXED_TIMING, range, message);
        }
    }
}
