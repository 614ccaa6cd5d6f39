//! `hipop diff PLAN_A PLAN_B`: what changed between two plans of the same
//! mission (docs/plan-formats.md). The comparison is
//! `hipop_analyzer::plan::diff`; this module reads the files and prints.

use std::fmt::Write as _;
use std::path::Path;

use hipop_analyzer::plan::diff::{DiffOptions, PlanDiff, diff};
use hipop_analyzer::plan::{NameMatching, Plan, PlanFormat, Step};
use hipop_analyzer::{AnalysisHost, Diagnostic, Severity, SourceFile};
use serde_json::{Value, json};

use crate::ColorWhen;
use crate::render::{Rendered, Sources, print_stdout};
use hipop_analyzer::diagnostic::SHOWN_PER_FILE;

/// How `hipop diff` prints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum DiffFormat {
    /// A summary per agent, then every change with its place in the files.
    Human,
    /// One JSON document (schema in docs/plan-formats.md).
    Json,
    /// A unified-diff-like text, per agent, that editors colour.
    Unified,
}

pub struct Options {
    pub format: DiffFormat,
    pub color: ColorWhen,
    pub domain: Option<std::path::PathBuf>,
    pub plan_format: Option<PlanFormat>,
    pub tolerance: f64,
    pub lenient: bool,
}

/// The label of steps whose agent is unknown.
const UNKNOWN_AGENT: &str = "(unknown agent)";

/// Reads one file given on the command line (`what`: "a plan file"); `Err`
/// is the message of an I/O problem.
pub(crate) fn read(path: &Path, what: &str) -> Result<String, String> {
    let shown = path.display();
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => return Err(format!("{shown}: is a folder, expected {what}")),
        Ok(_) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(format!("{shown}: no such file")),
        Err(e) => return Err(format!("{shown}: cannot read: {e}")),
    }
    let bytes = std::fs::read(path).map_err(|e| format!("{shown}: cannot read: {e}"))?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        format!("{shown}: not UTF-8 text (invalid byte at offset {at}): save the file as UTF-8")
    })
}

/// Compares the plans and prints the differences; returns the exit status:
/// 0 the same, 1 different, 2 a usage, I/O or parse error.
pub fn run(path_a: &Path, path_b: &Path, options: &Options) -> u8 {
    let mut host = AnalysisHost::new();
    let mut io_errors = Vec::new();
    let mut load = |host: &mut AnalysisHost, path: &Path| match read(path, "a plan file") {
        Ok(text) => Some(host.set_file_text(&crate::inputs::key(path), text)),
        Err(m) => {
            io_errors.push(m);
            None
        }
    };
    let fa = load(&mut host, path_a);
    let fb = load(&mut host, path_b);
    let fd = options.domain.as_deref().and_then(|d| load(&mut host, d));
    if !io_errors.is_empty() {
        io_errors.iter().for_each(|m| eprintln!("error: {m}"));
        return 2;
    }
    let (Some(fa), Some(fb)) = (fa, fb) else { return 2 };
    let analysis = host.analysis();
    let interrupted = |_: hipop_analyzer::Cancelled| {
        eprintln!("error: the analysis was interrupted; this is a bug in hipop, please report it");
        2u8
    };
    let matching = if options.lenient { NameMatching::Lenient } else { NameMatching::CaseInsensitive };
    let result = (|| {
        let a = analysis.plan(fa, options.plan_format)?;
        let b = analysis.plan(fb, options.plan_format)?;
        let mut diagnostics = analysis.plan_diagnostics(fa, options.plan_format)?;
        if fb != fa {
            diagnostics.extend(analysis.plan_diagnostics(fb, options.plan_format)?);
        }
        let agents = match fd {
            Some(d) => Some(analysis.plan_agents(d, matching)?),
            None => None,
        };
        let domain_ok = match fd {
            Some(d) => analysis.with_db(|db| {
                hipop_analyzer::db::file_units(db, d)
                    .iter()
                    .any(|u| u.kind(db) == hipop_analyzer::db::UnitKind::Domain)
            })?,
            None => true,
        };
        Ok::<_, hipop_analyzer::Cancelled>((a, b, diagnostics, agents, domain_ok))
    })();
    let (a, b, diagnostics, agents, domain_ok) = match result {
        Ok(r) => r,
        Err(e) => return interrupted(e),
    };
    let files: Vec<SourceFile> = [Some(fa), Some(fb), fd].into_iter().flatten().collect();
    let sources = Sources::new(&analysis, &files);
    if !diagnostics.is_empty() {
        let rendered = Rendered {
            sources: &sources,
            diagnostics: &diagnostics,
            io_errors: &[],
            files: 2,
            max_per_file: SHOWN_PER_FILE,
        };
        let mut stream = crate::render::stderr(options.color);
        rendered.emit_human(&mut stream);
        let _ = std::io::Write::flush(&mut stream);
    }
    if diagnostics.iter().any(|d: &Diagnostic| d.severity == Severity::Error) {
        eprintln!("error: the plans cannot be compared: fix the errors above");
        return 2;
    }
    if !domain_ok {
        let d = options.domain.as_deref().map(Path::display).map(|d| d.to_string()).unwrap_or_default();
        eprintln!("error: {d}: no `(define (domain …) …)` in this file: `--domain` takes the plans' domain");
        return 2;
    }
    let table = agents.unwrap_or_default();
    let d = diff(&a, &b, &table, &DiffOptions { tolerance: options.tolerance, matching });
    let view = View { a: &a, b: &b, fa, fb, sources: &sources, diff: &d, domain: fd.is_some() };
    let out = match options.format {
        DiffFormat::Human => view.human(),
        DiffFormat::Json => serde_json::to_string_pretty(&view.json()).unwrap_or_default(),
        DiffFormat::Unified => view.unified(),
    };
    print_stdout(out.trim_end_matches('\n'));
    if d.is_empty() { 0 } else { 1 }
}

/// The two plans, their diff, and where their steps are.
struct View<'a> {
    a: &'a Plan,
    b: &'a Plan,
    fa: SourceFile,
    fb: SourceFile,
    sources: &'a Sources,
    diff: &'a PlanDiff,
    domain: bool,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    A,
    B,
}

/// How the human output names a step, before its text: by the id the plan
/// file gives it (`step 3 `), none in a VAL plan (the place, `file:line:col`,
/// says which line); the one rule of `hipop_analyzer::plan::step_label`.
fn id_label(s: &Step) -> String {
    s.id.map_or_else(String::new, |id| format!("step {} ", id.value))
}

/// Two matched steps' ids: `step 4 `, `step 4 → step 6 `.
fn id_labels(a: &Step, b: &Step) -> String {
    match (a.id, b.id) {
        (Some(x), Some(y)) if x.value != y.value => format!("step {} → step {} ", x.value, y.value),
        (Some(x), _) => format!("step {} ", x.value),
        (None, Some(y)) => format!("step {} ", y.value),
        (None, None) => String::new(),
    }
}

/// A step as a line of a VAL plan, or `task args -> method` for an abstract step.
fn step_text(s: &Step) -> String {
    let mut out = String::new();
    if let Some(t) = &s.start {
        let _ = write!(out, "{}: ", t.text);
    }
    out.push_str(&s.call());
    if let Some(d) = &s.duration {
        let _ = write!(out, " [{}]", d.text);
    }
    if let Some(dec) = &s.decomposition {
        let _ = write!(out, " -> {}", dec.method.text);
    }
    out
}

/// A difference of times, rounded to the nanosecond: `26.0 - 25.02` is
/// `0.98`, not `0.9800000000000004`.
fn rounded(x: f64) -> f64 {
    (x * 1e9).round() / 1e9
}

/// A duration or time difference, signed, with three decimals.
fn delta(x: f64) -> String {
    format!("{}{:.3}", if x >= 0.0 { "+" } else { "-" }, x.abs())
}

impl View<'_> {
    fn plan(&self, side: Side) -> &Plan {
        if side == Side::A { self.a } else { self.b }
    }

    fn file(&self, side: Side) -> SourceFile {
        if side == Side::A { self.fa } else { self.fb }
    }

    /// The path as given on the command line.
    fn path(&self, side: Side) -> String {
        self.sources.path_of(self.file(side))
    }

    /// `(line, column)` of a step.
    fn line_col(&self, side: Side, i: usize) -> (usize, usize) {
        let step = &self.plan(side).steps[i];
        let offset = usize::from(step.range.start());
        self.sources.id(self.file(side)).map_or((0, 0), |id| self.sources.line_col(id, offset))
    }

    fn place(&self, side: Side, i: usize) -> String {
        let (l, c) = self.line_col(side, i);
        format!("{}:{l}:{c}", self.path(side))
    }

    fn agents(&self, side: Side, i: usize) -> &[String] {
        if side == Side::A { &self.diff.agents_a[i] } else { &self.diff.agents_b[i] }
    }

    fn agents_text(&self, side: Side, i: usize) -> String {
        let a = self.agents(side, i);
        if a.is_empty() { "agent unknown".to_string() } else { format!("agent {}", a.join(" ")) }
    }

    fn human(&self) -> String {
        let d = self.diff;
        let mut out = String::new();
        let _ = writeln!(out, "--- {}\n+++ {}", self.path(Side::A), self.path(Side::B));
        if d.is_empty() {
            let _ = writeln!(
                out,
                "\nthe plans are the same: {} action{} and {} abstract step{} matched",
                d.matched.len(),
                if d.matched.len() == 1 { "" } else { "s" },
                d.abstract_matched.len(),
                if d.abstract_matched.len() == 1 { "" } else { "s" }
            );
        } else {
            out.push('\n');
            self.agent_table(&mut out);
            let section = |out: &mut String, title: &str, rows: Vec<(String, String)>| {
                if rows.is_empty() {
                    return;
                }
                let _ = writeln!(out, "\n{title} ({}):", rows.len());
                let width = rows.iter().map(|(p, _)| p.chars().count()).max().unwrap_or(0);
                for (place, what) in rows {
                    let _ = writeln!(out, "  {place:width$}  {what}");
                }
            };
            let one = |side: Side, i: usize| {
                (
                    self.place(side, i),
                    format!(
                        "{}{}  ({})",
                        id_label(&self.plan(side).steps[i]),
                        step_text(&self.plan(side).steps[i]),
                        self.agents_text(side, i)
                    ),
                )
            };
            section(&mut out, "removed", d.removed.iter().map(|&x| one(Side::A, x)).collect());
            section(&mut out, "added", d.added.iter().map(|&y| one(Side::B, y)).collect());
            let retimed = d
                .retimed
                .iter()
                .map(|&(x, y)| {
                    let (sa, sb) = (&self.a.steps[x], &self.b.steps[y]);
                    let num = |n: &Option<hipop_analyzer::plan::Number>| n.as_ref().map_or(0.0, |n| n.value);
                    let text = |n: &Option<hipop_analyzer::plan::Number>| {
                        n.as_ref().map_or_else(|| "0".to_string(), |n| n.text.to_string())
                    };
                    let mut what = format!(
                        "{}{}: start {} → {} ({})",
                        id_labels(sa, sb),
                        sb.call(),
                        text(&sa.start),
                        text(&sb.start),
                        delta(num(&sb.start) - num(&sa.start))
                    );
                    if (num(&sb.duration) - num(&sa.duration)).abs() > 0.0 {
                        let _ = write!(
                            what,
                            ", duration {} → {} ({})",
                            text(&sa.duration),
                            text(&sb.duration),
                            delta(num(&sb.duration) - num(&sa.duration))
                        );
                    }
                    (format!("{} → {}", self.place(Side::A, x), self.place(Side::B, y)), what)
                })
                .collect();
            section(&mut out, "retimed", retimed);
            let methods = d
                .method_changes
                .iter()
                .map(|&(x, y)| {
                    let m = |s: &Step| {
                        s.decomposition.as_ref().map_or(String::new(), |d| d.method.text.to_string())
                    };
                    let what = format!(
                        "{}{}: {} → {}",
                        id_labels(&self.a.steps[x], &self.b.steps[y]),
                        self.b.steps[y].call(),
                        m(&self.a.steps[x]),
                        m(&self.b.steps[y])
                    );
                    (format!("{} → {}", self.place(Side::A, x), self.place(Side::B, y)), what)
                })
                .collect();
            section(&mut out, "method changes", methods);
            section(
                &mut out,
                "abstract steps removed",
                d.abstract_removed
                    .iter()
                    .map(|&x| {
                        let s = &self.a.steps[x];
                        (self.place(Side::A, x), format!("{}{}", id_label(s), step_text(s)))
                    })
                    .collect(),
            );
            section(
                &mut out,
                "abstract steps added",
                d.abstract_added
                    .iter()
                    .map(|&y| {
                        let s = &self.b.steps[y];
                        (self.place(Side::B, y), format!("{}{}", id_label(s), step_text(s)))
                    })
                    .collect(),
            );
        }
        let _ = writeln!(
            out,
            "\ninstability: {} (actions changed: {} removed, {} added, {} retimed)",
            d.instability,
            d.removed.len(),
            d.added.len(),
            d.retimed.len()
        );
        let _ = writeln!(
            out,
            "distance (Fox et al.): {} (|A∖B| = {}, |B∖A| = {})",
            d.distance,
            d.removed.len(),
            d.added.len()
        );
        if !self.domain && d.per_agent.iter().any(|r| r.agent.is_none()) {
            let _ = writeln!(out, "(agents: give the domain with `--domain` to group the changes by agent)");
        }
        out
    }

    fn agent_table(&self, out: &mut String) {
        let header = ["agent", "unchanged", "removed", "added", "retimed", "methods"];
        let rows: Vec<[String; 6]> = self
            .diff
            .per_agent
            .iter()
            .map(|r| {
                [
                    r.agent.clone().unwrap_or_else(|| UNKNOWN_AGENT.to_string()),
                    r.unchanged.to_string(),
                    r.removed.to_string(),
                    r.added.to_string(),
                    r.retimed.to_string(),
                    r.method_changes.to_string(),
                ]
            })
            .collect();
        let mut widths = header.map(|h| h.chars().count());
        for row in &rows {
            for (w, cell) in widths.iter_mut().zip(row) {
                *w = (*w).max(cell.chars().count());
            }
        }
        let line = |cells: [&str; 6]| {
            let mut s = format!("{:w$}", cells[0], w = widths[0]);
            for (k, c) in cells.iter().enumerate().skip(1) {
                let _ = write!(s, "  {c:>w$}", w = widths[k]);
            }
            s
        };
        let _ = writeln!(out, "{}", line(header));
        for row in &rows {
            let _ = writeln!(out, "{}", line([&row[0], &row[1], &row[2], &row[3], &row[4], &row[5]]));
        }
    }

    fn step_json(&self, side: Side, i: usize) -> Value {
        let s = &self.plan(side).steps[i];
        let (line, column) = self.line_col(side, i);
        json!({
            "file": self.path(side),
            "line": line,
            "column": column,
            "id": s.id.map(|id| id.value),
            "name": s.name.text.as_str(),
            "args": s.args.iter().map(|a| a.text.as_str()).collect::<Vec<_>>(),
            "start": s.start.as_ref().map(|n| n.value),
            "duration": s.duration.as_ref().map(|n| n.value),
            "method": s.decomposition.as_ref().map(|d| d.method.text.as_str()),
            "agents": self.agents(side, i),
        })
    }

    fn json(&self) -> Value {
        let d = self.diff;
        let num = |n: &Option<hipop_analyzer::plan::Number>| n.as_ref().map_or(0.0, |n| n.value);
        json!({
            "version": 1,
            "a": self.path(Side::A),
            "b": self.path(Side::B),
            "same": d.is_empty(),
            "instability": d.instability,
            "distance": d.distance,
            "summary": {
                "matched": d.matched.len(),
                "removed": d.removed.len(),
                "added": d.added.len(),
                "retimed": d.retimed.len(),
                "abstract_matched": d.abstract_matched.len(),
                "abstract_removed": d.abstract_removed.len(),
                "abstract_added": d.abstract_added.len(),
                "method_changes": d.method_changes.len(),
            },
            "agents": d.per_agent.iter().map(|r| json!({
                "agent": r.agent,
                "unchanged": r.unchanged,
                "removed": r.removed,
                "added": r.added,
                "retimed": r.retimed,
                "method_changes": r.method_changes,
            })).collect::<Vec<_>>(),
            "removed": d.removed.iter().map(|&x| self.step_json(Side::A, x)).collect::<Vec<_>>(),
            "added": d.added.iter().map(|&y| self.step_json(Side::B, y)).collect::<Vec<_>>(),
            "retimed": d.retimed.iter().map(|&(x, y)| json!({
                "a": self.step_json(Side::A, x),
                "b": self.step_json(Side::B, y),
                "start_change": rounded(num(&self.b.steps[y].start) - num(&self.a.steps[x].start)),
                "duration_change": rounded(num(&self.b.steps[y].duration) - num(&self.a.steps[x].duration)),
            })).collect::<Vec<_>>(),
            "method_changes": d.method_changes.iter().map(|&(x, y)| json!({
                "a": self.step_json(Side::A, x),
                "b": self.step_json(Side::B, y),
            })).collect::<Vec<_>>(),
            "abstract_removed": d.abstract_removed.iter().map(|&x| self.step_json(Side::A, x)).collect::<Vec<_>>(),
            "abstract_added": d.abstract_added.iter().map(|&y| self.step_json(Side::B, y)).collect::<Vec<_>>(),
        })
    }

    /// Every action of both plans on one timeline per agent: ` ` unchanged,
    /// `-` removed (or before a retiming), `+` added (or after it); hunks of
    /// changes with three unchanged lines around them. The abstract steps
    /// that changed follow, in a hunk of their own.
    fn unified(&self) -> String {
        let d = self.diff;
        let timed = self.a.is_timed() && self.b.is_timed();
        // Where each step of B comes in B's order of occurrence.
        let order_b: std::collections::HashMap<usize, usize> =
            hipop_analyzer::plan::diff::occurrences(self.b)
                .into_iter()
                .enumerate()
                .map(|(k, i)| (i, k))
                .collect();
        let match_of_a: std::collections::HashMap<usize, usize> = d.matched.iter().copied().collect();
        let retimed: std::collections::HashSet<usize> = d.retimed.iter().map(|&(_, y)| y).collect();
        // (position, tie-break, agents, prefix, text)
        struct Line {
            at: f64,
            tie: u8,
            agents: Vec<String>,
            prefix: char,
            text: String,
        }
        let mut lines: Vec<Line> = Vec::new();
        let time = |s: &Step| s.start.as_ref().map_or(0.0, |n| n.value);
        for &(x, y) in &d.matched {
            let at = if timed { time(&self.b.steps[y]) } else { order_b[&y] as f64 };
            // As in the counts: B's agents, or A's when only A gives them.
            let agents = if self.agents(Side::B, y).is_empty() {
                self.agents(Side::A, x)
            } else {
                self.agents(Side::B, y)
            };
            if retimed.contains(&y) {
                let at_a = if timed { time(&self.a.steps[x]) } else { at };
                lines.push(Line {
                    at: at_a,
                    tie: 0,
                    agents: agents.to_vec(),
                    prefix: '-',
                    text: step_text(&self.a.steps[x]),
                });
                lines.push(Line {
                    at,
                    tie: 1,
                    agents: agents.to_vec(),
                    prefix: '+',
                    text: step_text(&self.b.steps[y]),
                });
            } else {
                lines.push(Line {
                    at,
                    tie: 2,
                    agents: agents.to_vec(),
                    prefix: ' ',
                    text: step_text(&self.b.steps[y]),
                });
            }
        }
        for &y in &d.added {
            let at = if timed { time(&self.b.steps[y]) } else { order_b[&y] as f64 };
            lines.push(Line {
                at,
                tie: 1,
                agents: self.agents(Side::B, y).to_vec(),
                prefix: '+',
                text: step_text(&self.b.steps[y]),
            });
        }
        // A removed step goes after the step of B matched with the last
        // matched step before it in A (in untimed plans).
        let occ_a = hipop_analyzer::plan::diff::occurrences(self.a);
        let mut last_b: Option<f64> = None;
        let removed: std::collections::HashSet<usize> = d.removed.iter().copied().collect();
        for &x in &occ_a {
            if let Some(&y) = match_of_a.get(&x) {
                last_b = Some(order_b[&y] as f64);
            } else if removed.contains(&x) {
                let at = if timed { time(&self.a.steps[x]) } else { last_b.map_or(-0.5, |b| b + 0.5) };
                lines.push(Line {
                    at,
                    tie: 0,
                    agents: self.agents(Side::A, x).to_vec(),
                    prefix: '-',
                    text: step_text(&self.a.steps[x]),
                });
            }
        }
        lines.sort_by(|p, q| p.at.total_cmp(&q.at).then(p.tie.cmp(&q.tie)));
        // One timeline per agent.
        let mut groups: Vec<(String, Vec<&Line>)> = Vec::new();
        for r in &d.per_agent {
            let name = r.agent.clone().unwrap_or_else(|| UNKNOWN_AGENT.to_string());
            let key = r.agent.as_deref().map(|a| a.to_ascii_lowercase());
            let mine: Vec<&Line> = lines
                .iter()
                .filter(|l| match &key {
                    None => l.agents.is_empty(),
                    Some(k) => l.agents.iter().any(|a| a.to_ascii_lowercase() == *k),
                })
                .collect();
            groups.push((name, mine));
        }
        let mut out = format!("--- {}\n+++ {}\n", self.path(Side::A), self.path(Side::B));
        const CONTEXT: usize = 3;
        for (name, mine) in &groups {
            let changed: Vec<usize> = (0..mine.len()).filter(|&k| mine[k].prefix != ' ').collect();
            if changed.is_empty() {
                continue;
            }
            // Hunks: changed lines with their context, merged when they touch.
            let mut hunks: Vec<(usize, usize)> = Vec::new();
            for &k in &changed {
                let (lo, hi) = (k.saturating_sub(CONTEXT), (k + CONTEXT + 1).min(mine.len()));
                match hunks.last_mut() {
                    Some((_, end)) if lo <= *end => *end = (*end).max(hi),
                    _ => hunks.push((lo, hi)),
                }
            }
            for (lo, hi) in hunks {
                let _ = writeln!(out, "@@ {name} @@");
                for l in &mine[lo..hi] {
                    let _ = writeln!(out, "{}{}", l.prefix, l.text);
                }
            }
        }
        if !(d.method_changes.is_empty() && d.abstract_removed.is_empty() && d.abstract_added.is_empty()) {
            let _ = writeln!(out, "@@ abstract steps @@");
            for &x in &d.abstract_removed {
                let _ = writeln!(out, "-{}", step_text(&self.a.steps[x]));
            }
            for &(x, y) in &d.method_changes {
                let _ = writeln!(out, "-{}", step_text(&self.a.steps[x]));
                let _ = writeln!(out, "+{}", step_text(&self.b.steps[y]));
            }
            for &y in &d.abstract_added {
                let _ = writeln!(out, "+{}", step_text(&self.b.steps[y]));
            }
        }
        out
    }
}
