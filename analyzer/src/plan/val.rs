//! VAL's plan format (PDDL 2.1): one step per line, `time: (action args…)
//! [duration]`, time and duration optional, `;` comments.
//!
//! Tolerated: any spacing (`0.01:(a b)[2]`), upper case, blank lines, and
//! lines of other text (a planner's `Time: 0` trailer), which are reported as
//! ignored (W0401). One malformed step is one E0401; what can be read of it
//! is kept (a missing `:` after the time, an unclosed `(` or `[`).

use super::lines::{Line, lines, number, range};
use super::{Number, Plan, PlanFormat, Step, Symbol};
use crate::diagnostic::codes::{IGNORED_LINE, MALFORMED_STEP, MIXED_TIMING};

/// Reads a VAL plan.
pub fn read(text: &str) -> Plan {
    let mut plan = Plan::new(PlanFormat::Val);
    for line in lines(text) {
        let body = match line.comment_start() {
            Some(i) => line.until(i),
            None => line,
        };
        if !body.is_blank() {
            step_line(&mut plan, body);
        }
    }
    mixed_timing(&mut plan);
    plan
}

/// Reports the first step without a time in a plan whose other steps have one.
fn mixed_timing(plan: &mut Plan) {
    let timed = plan.steps.iter().filter(|s| s.start.is_some()).count();
    if timed == 0 || timed == plan.steps.len() {
        return;
    }
    if let Some(s) = plan.steps.iter().find(|s| s.start.is_none()) {
        let (range, call) = (s.range, s.call());
        plan.diag(
            MIXED_TIMING,
            range,
            format!(
                "`{call}` has no start time, but {timed} other step{} of the plan {}: write `time: {call}`",
                if timed == 1 { "" } else { "s" },
                if timed == 1 { "has one" } else { "have one" }
            ),
        );
    }
}

fn skip_ws(t: &str, mut i: usize) -> usize {
    while let Some(c) = t[i..].chars().next() {
        if !c.is_whitespace() {
            break;
        }
        i += c.len_utf8();
    }
    i
}

/// The end of the word at `i`: up to whitespace or one of `stops`.
fn word_end(t: &str, i: usize, stops: &[char]) -> usize {
    t[i..].find(|c: char| c.is_whitespace() || stops.contains(&c)).map_or(t.len(), |k| i + k)
}

/// Whether a word starts like a number (a digit, or `.`, `+`, `-` before one).
fn starts_like_number(w: &str) -> bool {
    let b = w.as_bytes();
    match b.first() {
        Some(c) if c.is_ascii_digit() => true,
        Some(b'.' | b'+' | b'-') => b.get(1).is_some_and(|c| c.is_ascii_digit() || *c == b'.'),
        _ => false,
    }
}

fn step_line(plan: &mut Plan, line: Line<'_>) {
    let t = line.text;
    let at = |i: usize| line.start + i;
    let whole = line.trimmed_range();
    let mut i = skip_ws(t, 0);
    let mut start: Option<Number> = None;
    if !t[i..].starts_with('(') {
        let end = word_end(t, i, &[':', '(']);
        let word = &t[i..end];
        if !starts_like_number(word) {
            plan.diag(
                IGNORED_LINE,
                whole,
                "this line is not a plan step and is ignored (a step is `time: (action args…) [duration]`, \
                 or `(action args…)` in a sequential plan)",
            );
            return;
        }
        match number(word, at(i)) {
            Ok(n) => start = Some(n),
            Err(m) => {
                plan.diag(
                    MALFORMED_STEP,
                    range(at(i), at(end)),
                    format!("{m}: expected the step's start time"),
                );
                return;
            }
        }
        let time_end = end;
        i = skip_ws(t, end);
        if t[i..].starts_with(':') {
            i = skip_ws(t, i + 1);
        } else if t[i..].starts_with('(') {
            plan.diag(
                MALFORMED_STEP,
                range(at(time_end), at(time_end)),
                format!("expected `:` after the start time `{word}`"),
            );
        } else {
            plan.diag(
                MALFORMED_STEP,
                whole,
                format!("expected `: (action args…)` after the start time `{word}`"),
            );
            return;
        }
    }
    if !t[i..].starts_with('(') {
        let what = if i >= t.len() { "nothing".to_string() } else { format!("`{}`", t[i..].trim_end()) };
        plan.diag(
            MALFORMED_STEP,
            range(at(i), at(t.trim_end().len())),
            format!("expected `(action args…)` after the start time, found {what}"),
        );
        return;
    }
    let open = i;
    i += 1;
    let mut words: Vec<Symbol> = Vec::new();
    loop {
        i = skip_ws(t, i);
        match t[i..].chars().next() {
            None => {
                plan.diag(
                    MALFORMED_STEP,
                    range(at(open), at(open + 1)),
                    "this `(` is not closed: expected `)` after the step's arguments",
                );
                break;
            }
            Some(')') => {
                i += 1;
                break;
            }
            Some('[') => {
                // `(move r1 a b [30.9]`: the `)` is missing before the duration.
                plan.diag(
                    MALFORMED_STEP,
                    range(at(open), at(open + 1)),
                    "this `(` is not closed: expected `)` after the step's arguments",
                );
                break;
            }
            Some('(') => {
                plan.diag(
                    MALFORMED_STEP,
                    range(at(i), at(i + 1)),
                    "unexpected `(`: a step is `(action arg…)`, and its arguments are names",
                );
                return;
            }
            Some(_) => {
                let end = word_end(t, i, &['(', ')', '[']);
                words.push(Symbol { text: t[i..end].into(), range: range(at(i), at(end)) });
                i = end;
            }
        }
    }
    let call_end = i;
    let mut words = words.into_iter();
    let Some(name) = words.next() else {
        plan.diag(MALFORMED_STEP, range(at(open), at(call_end)), "expected an action's name in `()`");
        return;
    };
    let args: Vec<Symbol> = words.collect();
    i = skip_ws(t, i);
    let mut duration = None;
    let mut step_end = call_end;
    if t[i..].starts_with('[') {
        let open = i;
        let (inner_end, close_end) = match t[i..].find(']') {
            Some(k) => (i + k, i + k + 1),
            None => {
                plan.diag(
                    MALFORMED_STEP,
                    range(at(open), at(open + 1)),
                    "this `[` is not closed: expected `]` after the duration",
                );
                (t.len(), t.len())
            }
        };
        let inner = &t[open + 1..inner_end];
        let lead = inner.len() - inner.trim_start().len();
        let word = inner.trim();
        let word_at = open + 1 + lead;
        if word.is_empty() {
            plan.diag(MALFORMED_STEP, range(at(open), at(close_end)), "expected a duration in `[]`");
        } else {
            match number(word, at(word_at)) {
                Ok(n) => duration = Some(n),
                Err(m) => plan.diag(
                    MALFORMED_STEP,
                    range(at(word_at), at(word_at + word.len())),
                    format!("{m}: expected the step's duration"),
                ),
            }
        }
        i = close_end;
        step_end = close_end;
    }
    i = skip_ws(t, i);
    if i < t.len() {
        let extra = t[i..].trim_end();
        plan.diag(
            MALFORMED_STEP,
            range(at(i), at(i + extra.len())),
            format!(
                "unexpected `{extra}` after the step: one step per line, `time: (action args…) [duration]`"
            ),
        );
    }
    let first = start.as_ref().map_or(open, |n| usize::from(n.range.start()) - line.start);
    plan.steps.push(Step {
        range: range(at(first), at(step_end)),
        id: None,
        name,
        args,
        start,
        duration,
        decomposition: None,
        agents: Vec::new(),
        bounds: None,
    });
}
