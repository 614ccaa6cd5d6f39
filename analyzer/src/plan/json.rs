//! hipop's JSON form of a partial-order plan, schema version 1
//! (docs/plan-formats.md):
//!
//! ```json
//! { "format": "hipop-plan", "version": 1,
//!   "problem": { "domain": "surveillance", "problem": "p01", "hash": "fnv1a64:…" },
//!   "steps": [ { "id": 0, "name": "move", "args": ["r1", "a", "b"], "agents": ["r1"],
//!                "start": 0.0, "duration": 30.98,
//!                "bounds": { "start": [0.0, 4.5], "end": [30.98, null] } },
//!              { "id": 2, "name": "patrol", "args": ["r1"], "method": "m-patrol",
//!                "subtasks": [0, 1], "start": 0.0, "end": 35.99 } ],
//!   "root": [2],
//!   "causal_links": [ { "from": 0, "to": 1,
//!                       "literal": { "predicate": "at", "args": ["r1", "b"] } } ],
//!   "temporal_links": [ { "from": { "step": 0, "point": "end" },
//!                         "to": { "step": 1, "point": "start" }, "min": 0.01 } ] }
//! ```
//!
//! Read with serde_json, keeping every value's place in the file: values are
//! first read as raw slices of the text, whose offsets give the ranges of the
//! AST, then decoded one by one, so that a bad value is one diagnostic at its
//! place and the rest of the plan is still read. Unknown fields are ignored
//! (later minor revisions may add some); a `version` other than 1 is refused.

use rowan::TextRange;
use serde::Deserialize;
use serde::de::DeserializeOwned;
use serde_json::value::RawValue;

use super::lines::range;
use super::{
    Bounds, CausalLink, Decomposition, Interval, LinkEnd, Literal, Number, Plan, PlanFormat, Point,
    ProblemRef, Root, Step, StepId, Symbol, TemporalLink, TimePoint,
};
use crate::diagnostic::codes::{MALFORMED_JSON_PLAN, MALFORMED_STEP};

/// The value of `format` in a hipop JSON plan.
pub const FORMAT_NAME: &str = "hipop-plan";
/// The schema version this reader reads and `hipop plan` writes.
pub const VERSION: u64 = 1;

#[derive(Deserialize)]
struct RawDoc<'a> {
    #[serde(borrow, default)]
    format: Option<&'a RawValue>,
    #[serde(borrow, default)]
    version: Option<&'a RawValue>,
    #[serde(borrow, default)]
    problem: Option<&'a RawValue>,
    #[serde(borrow, default)]
    steps: Option<&'a RawValue>,
    #[serde(borrow, default)]
    root: Option<&'a RawValue>,
    #[serde(borrow, default)]
    causal_links: Option<&'a RawValue>,
    #[serde(borrow, default)]
    temporal_links: Option<&'a RawValue>,
}

#[derive(Deserialize)]
struct RawProblem<'a> {
    #[serde(borrow, default)]
    domain: Option<&'a RawValue>,
    #[serde(borrow, default)]
    problem: Option<&'a RawValue>,
    #[serde(borrow, default)]
    hash: Option<&'a RawValue>,
}

#[derive(Deserialize)]
struct RawStep<'a> {
    #[serde(borrow, default)]
    id: Option<&'a RawValue>,
    #[serde(borrow, default)]
    name: Option<&'a RawValue>,
    #[serde(borrow, default)]
    args: Option<&'a RawValue>,
    #[serde(borrow, default)]
    agents: Option<&'a RawValue>,
    #[serde(borrow, default)]
    start: Option<&'a RawValue>,
    #[serde(borrow, default)]
    end: Option<&'a RawValue>,
    #[serde(borrow, default)]
    duration: Option<&'a RawValue>,
    #[serde(borrow, default)]
    bounds: Option<&'a RawValue>,
    #[serde(borrow, default)]
    method: Option<&'a RawValue>,
    #[serde(borrow, default)]
    subtasks: Option<&'a RawValue>,
}

#[derive(Deserialize)]
struct RawBounds<'a> {
    #[serde(borrow, default)]
    start: Option<&'a RawValue>,
    #[serde(borrow, default)]
    end: Option<&'a RawValue>,
}

#[derive(Deserialize)]
struct RawCausalLink<'a> {
    #[serde(borrow, default)]
    from: Option<&'a RawValue>,
    #[serde(borrow, default)]
    to: Option<&'a RawValue>,
    #[serde(borrow, default)]
    literal: Option<&'a RawValue>,
}

#[derive(Deserialize)]
struct RawLiteral<'a> {
    #[serde(borrow, default)]
    predicate: Option<&'a RawValue>,
    #[serde(borrow, default)]
    args: Option<&'a RawValue>,
    #[serde(borrow, default)]
    negated: Option<&'a RawValue>,
}

#[derive(Deserialize)]
struct RawTemporalLink<'a> {
    #[serde(borrow, default)]
    from: Option<&'a RawValue>,
    #[serde(borrow, default)]
    to: Option<&'a RawValue>,
    #[serde(borrow, default)]
    min: Option<&'a RawValue>,
    #[serde(borrow, default)]
    max: Option<&'a RawValue>,
}

#[derive(Deserialize)]
struct RawTimePoint<'a> {
    #[serde(borrow, default)]
    step: Option<&'a RawValue>,
    #[serde(borrow, default)]
    point: Option<&'a RawValue>,
}

/// A failed decoding: where, and what.
type Fail = (TextRange, String);

/// Decodes raw values of one text, locating them by their offset in it.
struct Cx<'a> {
    text: &'a str,
}

impl<'a> Cx<'a> {
    fn offset(&self, s: &str) -> usize {
        (s.as_ptr() as usize).saturating_sub(self.text.as_ptr() as usize).min(self.text.len())
    }

    fn range(&self, raw: &RawValue) -> TextRange {
        let start = self.offset(raw.get());
        range(start, start + raw.get().len())
    }

    /// The raw text, shortened for a message.
    fn shown(raw: &RawValue) -> String {
        let s = raw.get();
        if s.chars().count() > 40 {
            format!("{}…", s.chars().take(40).collect::<String>())
        } else {
            s.to_string()
        }
    }

    fn decode<T: DeserializeOwned>(&self, raw: &RawValue, what: &str) -> Result<T, Fail> {
        serde_json::from_str(raw.get())
            .map_err(|_| (self.range(raw), format!("{what}, found `{}`", Self::shown(raw))))
    }

    fn borrow<T: Deserialize<'a>>(&self, raw: &'a RawValue, what: &str) -> Result<T, Fail> {
        serde_json::from_str(raw.get())
            .map_err(|_| (self.range(raw), format!("{what}, found `{}`", Self::shown(raw))))
    }

    /// A JSON object (serde would also read a struct from an array, by position).
    fn object<T: Deserialize<'a>>(&self, raw: &'a RawValue, what: &str) -> Result<T, Fail> {
        if !raw.get().starts_with('{') {
            return Err((self.range(raw), format!("{what}, found `{}`", Self::shown(raw))));
        }
        self.borrow(raw, what)
    }

    fn required(
        &self,
        raw: Option<&'a RawValue>,
        at: TextRange,
        field: &str,
        what: &str,
    ) -> Result<&'a RawValue, Fail> {
        raw.ok_or_else(|| (at, format!("missing `{field}`: {what}")))
    }

    fn symbol(&self, raw: &RawValue, what: &str) -> Result<Symbol, Fail> {
        let text: String = self.decode(raw, what)?;
        if text.trim().is_empty() {
            return Err((self.range(raw), format!("{what}, found an empty string")));
        }
        Ok(Symbol { text: text.into(), range: self.range(raw) })
    }

    fn symbols(&self, raw: &'a RawValue, what: &str) -> Result<Vec<Symbol>, Fail> {
        let items: Vec<&'a RawValue> = self.borrow(raw, &format!("expected an array of {what}"))?;
        items.into_iter().map(|r| self.symbol(r, &format!("expected {what}"))).collect()
    }

    fn number(&self, raw: &RawValue, what: &str) -> Result<Number, Fail> {
        let value: f64 = self.decode(raw, what)?;
        if !value.is_finite() {
            return Err((self.range(raw), format!("{what}, found `{}`", Self::shown(raw))));
        }
        Ok(Number { text: raw.get().into(), value, range: self.range(raw) })
    }

    fn optional_number(&self, raw: &RawValue, what: &str) -> Result<Option<f64>, Fail> {
        if raw.get() == "null" {
            return Ok(None);
        }
        self.number(raw, what).map(|n| Some(n.value))
    }

    fn id(&self, raw: &RawValue) -> Result<StepId, Fail> {
        let value: u32 = self.decode(raw, "expected a step id (a non-negative integer)")?;
        Ok(StepId { value, range: self.range(raw) })
    }

    fn interval(&self, raw: &'a RawValue) -> Result<Interval, Fail> {
        let what = "expected `[earliest, latest]`, numbers or `null`";
        let pair: Vec<&'a RawValue> = self.borrow(raw, what)?;
        if pair.len() != 2 {
            return Err((self.range(raw), format!("{what}, found `{}`", Self::shown(raw))));
        }
        Ok(Interval { lo: self.optional_number(pair[0], what)?, hi: self.optional_number(pair[1], what)? })
    }
}

/// Reads a JSON plan.
pub fn read(text: &str) -> Plan {
    let mut plan = Plan::new(PlanFormat::Json);
    let cx = Cx { text };
    let first = text.trim_start_matches(['\u{feff}', ' ', '\t', '\r', '\n']);
    if !first.is_empty() && !first.starts_with('{') {
        let at = text.len() - first.len();
        let end = first.chars().next().map_or(at, |c| at + c.len_utf8());
        plan.diag(
            MALFORMED_JSON_PLAN,
            range(at, end),
            "this is not a JSON plan: a JSON plan is an object with `format`, `version` and `steps`",
        );
        return plan;
    }
    let doc: RawDoc<'_> = match serde_json::from_str(text) {
        Ok(d) => d,
        Err(e) => {
            let at = error_offset(text, &e);
            let message = if e.classify() == serde_json::error::Category::Data {
                // Valid JSON of another shape: serde's message would name our types.
                "a JSON plan is an object with `format`, `version` and `steps`".to_string()
            } else {
                let m = e.to_string();
                m.split(" at line ").next().unwrap_or(&m).to_string()
            };
            let end = text[at..].chars().next().map_or(at, |c| at + c.len_utf8());
            plan.diag(MALFORMED_JSON_PLAN, range(at, end), format!("this is not a JSON plan: {message}"));
            return plan;
        }
    };
    let whole = range(0, text.trim_end().len());
    if let Err((r, m)) = header(&cx, &doc, whole) {
        plan.diag(MALFORMED_JSON_PLAN, r, m);
        return plan;
    }
    if let Some(p) = doc.problem {
        match problem(&cx, p) {
            Ok(p) => plan.problem = Some(p),
            Err((r, m)) => plan.diag(MALFORMED_JSON_PLAN, r, m),
        }
    }
    let steps = cx
        .required(doc.steps, whole, "steps", "a JSON plan lists its steps in `steps`")
        .and_then(|s| cx.borrow::<Vec<&RawValue>>(s, "`steps` must be an array of steps"));
    match steps {
        Ok(steps) => {
            for s in steps {
                match step(&cx, s) {
                    Ok(step) => plan.steps.push(step),
                    Err((r, m)) => {
                        let id = cx.object::<RawStep<'_>>(s, "").ok().and_then(|st| cx.id(st.id?).ok());
                        plan.unreadable.extend(id.map(|id| id.value));
                        plan.diag(MALFORMED_STEP, r, m);
                    }
                }
            }
        }
        Err((r, m)) => plan.diag(MALFORMED_JSON_PLAN, r, m),
    }
    if let Some(root) = doc.root {
        let ids = cx
            .borrow::<Vec<&RawValue>>(root, "`root` must be an array of step ids")
            .and_then(|ids| ids.into_iter().map(|r| cx.id(r)).collect::<Result<Vec<_>, _>>());
        match ids {
            Ok(ids) => plan.root = Some(Root { range: cx.range(root), ids }),
            Err((r, m)) => plan.diag(MALFORMED_JSON_PLAN, r, m),
        }
    }
    if let Some(links) = doc.causal_links {
        match cx.borrow::<Vec<&RawValue>>(links, "`causal_links` must be an array") {
            Ok(links) => {
                for l in links {
                    match causal_link(&cx, l) {
                        Ok(l) => plan.causal_links.push(l),
                        Err((r, m)) => plan.diag(MALFORMED_JSON_PLAN, r, m),
                    }
                }
            }
            Err((r, m)) => plan.diag(MALFORMED_JSON_PLAN, r, m),
        }
    }
    if let Some(links) = doc.temporal_links {
        match cx.borrow::<Vec<&RawValue>>(links, "`temporal_links` must be an array") {
            Ok(links) => {
                for l in links {
                    match temporal_link(&cx, l) {
                        Ok(l) => plan.temporal_links.push(l),
                        Err((r, m)) => plan.diag(MALFORMED_JSON_PLAN, r, m),
                    }
                }
            }
            Err((r, m)) => plan.diag(MALFORMED_JSON_PLAN, r, m),
        }
    }
    plan
}

/// The byte offset of a serde_json error (its line and column are 1-based;
/// the column counts bytes).
fn error_offset(text: &str, e: &serde_json::Error) -> usize {
    let line_start: usize = text
        .split_inclusive('\n')
        .take(e.line().saturating_sub(1))
        .map(str::len)
        .sum::<usize>()
        .min(text.len());
    let mut at = (line_start + e.column().saturating_sub(1)).min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

fn header(cx: &Cx<'_>, doc: &RawDoc<'_>, whole: TextRange) -> Result<(), Fail> {
    let format =
        cx.required(doc.format, whole, "format", "a JSON plan starts with `\"format\": \"hipop-plan\"`")?;
    let name: String = cx.decode(format, "`format` must be \"hipop-plan\"")?;
    if name != FORMAT_NAME {
        return Err((cx.range(format), format!("`format` must be \"{FORMAT_NAME}\", found \"{name}\"")));
    }
    let version =
        cx.required(doc.version, whole, "version", "a JSON plan gives its schema version, `\"version\": 1`")?;
    let v: u64 = cx.decode(version, "`version` must be a positive integer")?;
    if v != VERSION {
        return Err((
            cx.range(version),
            format!("this is version {v} of the JSON plan schema; this hipop reads version {VERSION}"),
        ));
    }
    Ok(())
}

fn problem<'a>(cx: &Cx<'a>, raw: &'a RawValue) -> Result<ProblemRef, Fail> {
    let p: RawProblem<'a> = cx.object(raw, "`problem` must be an object")?;
    let name = |r: Option<&RawValue>, what: &str| r.map(|r| cx.symbol(r, what)).transpose();
    Ok(ProblemRef {
        domain: name(p.domain, "`domain` must be the domain's name")?,
        problem: name(p.problem, "`problem` must be the problem's name")?,
        hash: name(p.hash, "`hash` must be a string")?,
    })
}

fn step<'a>(cx: &Cx<'a>, raw: &'a RawValue) -> Result<Step, Fail> {
    let s: RawStep<'a> = cx.object(raw, "a step is a JSON object")?;
    let at = cx.range(raw);
    let id = cx.id(cx.required(s.id, at, "id", "every step has an integer `id`")?)?;
    let name = cx.symbol(
        cx.required(s.name, at, "name", "every step has the `name` of its action or task")?,
        "`name` must be the name of an action or task",
    )?;
    let args = match s.args {
        Some(a) => cx.symbols(a, "arguments (strings)")?,
        None => Vec::new(),
    };
    let agents = match s.agents {
        Some(a) => cx.symbols(a, "agents (strings)")?,
        None => Vec::new(),
    };
    let start = s.start.map(|r| cx.number(r, "`start` must be a number")).transpose()?;
    let end = s.end.map(|r| cx.number(r, "`end` must be a number")).transpose()?;
    let mut duration = s.duration.map(|r| cx.number(r, "`duration` must be a number")).transpose()?;
    match (&start, &end, &duration) {
        (None, Some(e), _) => {
            return Err((e.range, "`end` without `start`: give the step's start time".into()));
        }
        (Some(st), Some(e), Some(d)) => {
            let scale = 1.0f64.max(e.value.abs());
            if (st.value + d.value - e.value).abs() > 1e-9 * scale {
                return Err((
                    e.range,
                    format!("`end` is {}, but `start` + `duration` is {} + {}", e.text, st.text, d.text),
                ));
            }
        }
        (Some(st), Some(e), None) => {
            let value = e.value - st.value;
            // Rounded to the nanosecond so that `30.98 - 0` does not print as `30.979999…`.
            let value = (value * 1e9).round() / 1e9;
            duration = Some(Number { text: format!("{value}").into(), value, range: e.range });
        }
        _ => {}
    }
    let bounds = match s.bounds {
        Some(b) => {
            let rb: RawBounds<'a> = cx.object(b, "`bounds` must be an object with `start` and `end`")?;
            Some(Bounds {
                start: rb.start.map(|r| cx.interval(r)).transpose()?.unwrap_or_default(),
                end: rb.end.map(|r| cx.interval(r)).transpose()?.unwrap_or_default(),
            })
        }
        None => None,
    };
    let decomposition = match (s.method, s.subtasks) {
        (Some(m), subtasks) => {
            let method = cx.symbol(m, "`method` must be the name of a method")?;
            let subtasks = match subtasks {
                Some(st) => {
                    let ids: Vec<&'a RawValue> = cx.borrow(st, "`subtasks` must be an array of step ids")?;
                    ids.into_iter().map(|r| cx.id(r)).collect::<Result<Vec<_>, _>>()?
                }
                None => Vec::new(),
            };
            Some(Decomposition { method, subtasks })
        }
        (None, Some(st)) => {
            return Err((
                cx.range(st),
                "`subtasks` without `method`: give the method that refines the task".into(),
            ));
        }
        (None, None) => None,
    };
    Ok(Step { range: at, id: Some(id), name, args, start, duration, decomposition, agents, bounds })
}

fn causal_link<'a>(cx: &Cx<'a>, raw: &'a RawValue) -> Result<CausalLink, Fail> {
    let l: RawCausalLink<'a> =
        cx.object(raw, "a causal link is an object with `from`, `to` and `literal`")?;
    let at = cx.range(raw);
    let end = |r: &RawValue, problem: &str| -> Result<LinkEnd, Fail> {
        if r.get() == format!("\"{problem}\"") {
            Ok(LinkEnd::Problem)
        } else {
            cx.id(r).map(LinkEnd::Step).map_err(|(r, _)| (r, format!("expected a step id or \"{problem}\"")))
        }
    };
    let from =
        end(cx.required(l.from, at, "from", "the step that achieves the literal, or \"init\"")?, "init")?;
    let to = end(cx.required(l.to, at, "to", "the step that needs the literal, or \"goal\"")?, "goal")?;
    let lit = cx.required(l.literal, at, "literal", "the literal the link protects")?;
    let rl: RawLiteral<'a> = cx.object(lit, "a literal is an object with `predicate`, `args`, `negated`")?;
    let predicate = cx.symbol(
        cx.required(rl.predicate, cx.range(lit), "predicate", "the literal's predicate")?,
        "`predicate` must be a predicate's name",
    )?;
    let args = match rl.args {
        Some(a) => cx.symbols(a, "arguments (strings)")?,
        None => Vec::new(),
    };
    let negated = match rl.negated {
        Some(n) => cx.decode(n, "`negated` must be true or false")?,
        None => false,
    };
    Ok(CausalLink { range: at, from, to, literal: Literal { negated, predicate, args } })
}

fn time_point<'a>(cx: &Cx<'a>, raw: &'a RawValue) -> Result<TimePoint, Fail> {
    if raw.get() == "\"origin\"" {
        return Ok(TimePoint::Origin);
    }
    let what = "a time point is \"origin\" or `{\"step\": ID, \"point\": \"start\" | \"end\"}`";
    let p: RawTimePoint<'a> = cx.object(raw, what)?;
    let at = cx.range(raw);
    let step = cx.id(cx.required(p.step, at, "step", what)?)?;
    let point = cx.required(p.point, at, "point", what)?;
    let point = match point.get() {
        "\"start\"" => Point::Start,
        "\"end\"" => Point::End,
        _ => {
            return Err((
                cx.range(point),
                format!("`point` must be \"start\" or \"end\", found `{}`", Cx::shown(point)),
            ));
        }
    };
    Ok(TimePoint::Step(step, point))
}

fn temporal_link<'a>(cx: &Cx<'a>, raw: &'a RawValue) -> Result<TemporalLink, Fail> {
    let l: RawTemporalLink<'a> =
        cx.object(raw, "a temporal link is an object with `from`, `to`, `min`, `max`")?;
    let at = cx.range(raw);
    let from = time_point(cx, cx.required(l.from, at, "from", "the earlier time point")?)?;
    let to = time_point(cx, cx.required(l.to, at, "to", "the later time point")?)?;
    let min = l.min.map(|r| cx.optional_number(r, "`min` must be a number or null")).transpose()?.flatten();
    let max = l.max.map(|r| cx.optional_number(r, "`max` must be a number or null")).transpose()?.flatten();
    if min.is_none() && max.is_none() {
        return Err((at, "a temporal link needs `min`, `max` or both".into()));
    }
    Ok(TemporalLink { range: at, from, to, min, max })
}

/// The hash a JSON plan gives in `problem.hash`: FNV-1a (64 bits) of the
/// domain's and the problem's tokens, lower-cased, comments and layout
/// removed, so that reformatting a file keeps its hash and any other edit
/// changes it. Written `fnv1a64:` and 16 hexadecimal digits.
pub fn problem_hash(domain: &str, problem: &str) -> String {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut h = OFFSET;
    let mut feed = |b: u8| {
        h ^= u64::from(b);
        h = h.wrapping_mul(PRIME);
    };
    for (k, text) in [domain, problem].into_iter().enumerate() {
        if k > 0 {
            feed(b'\n');
        }
        let mut first = true;
        for line in text.lines() {
            let code = line.split(';').next().unwrap_or("");
            let spaced = code.replace('(', " ( ").replace(')', " ) ");
            for token in spaced.split_whitespace() {
                if !first {
                    feed(b' ');
                }
                first = false;
                token.bytes().for_each(|b| feed(b.to_ascii_lowercase()));
            }
        }
    }
    format!("fnv1a64:{h:016x}")
}
