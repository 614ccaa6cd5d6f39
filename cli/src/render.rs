//! Printing diagnostics: human (codespan-reporting), JSON, SARIF 2.1.0, GitHub annotations.

use std::collections::HashMap;
use std::io::Write;

use codespan_reporting::diagnostic::{Diagnostic as CsDiagnostic, Label, Severity as CsSeverity};
use codespan_reporting::term::{
    self,
    termcolor::{BufferedStandardStream, ColorChoice},
};
use hipop_analyzer::diagnostic::shown_per_file;
use hipop_analyzer::{Analysis, Diagnostic, Severity, SourceFile, TextRange, codes};
use serde_json::{Value, json};

use crate::ColorWhen;
use crate::snippet::{FileId, View};

/// The texts of the files, with what converts a byte offset to a line and
/// column in logarithmic time (a file of one long line may have thousands of
/// diagnostics).
pub struct Sources {
    texts: Vec<std::sync::Arc<str>>,
    ids: HashMap<SourceFile, usize>,
    paths: Vec<String>,
    line_starts: Vec<Vec<usize>>,
    /// Per file, the start of each character of more than one byte, with the
    /// extra bytes of those up to and including it (empty for ASCII text).
    wide: Vec<Vec<(usize, usize)>>,
}

impl Sources {
    pub fn new(analysis: &Analysis, files: &[SourceFile]) -> Sources {
        let mut s = Sources {
            texts: Vec::new(),
            ids: HashMap::new(),
            paths: Vec::new(),
            line_starts: Vec::new(),
            wide: Vec::new(),
        };
        for &f in files {
            let (Ok(path), Ok(text)) = (analysis.file_path(f), analysis.file_text(f)) else { continue };
            let starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
            let mut wide = Vec::new();
            if !text.is_ascii() {
                let mut extra = 0;
                for (i, c) in text.char_indices().filter(|(_, c)| !c.is_ascii()) {
                    extra += c.len_utf8() - 1;
                    wide.push((i, extra));
                }
            }
            let id = s.texts.len();
            s.texts.push(text);
            s.ids.insert(f, id);
            s.paths.push(path);
            s.line_starts.push(starts);
            s.wide.push(wide);
        }
        s
    }

    pub(crate) fn id(&self, file: SourceFile) -> Option<usize> {
        self.ids.get(&file).copied()
    }

    fn path(&self, file: SourceFile) -> String {
        self.id(file).map(|i| self.paths[i].clone()).unwrap_or_default()
    }

    pub(crate) fn path_of(&self, file: SourceFile) -> String {
        self.path(file)
    }

    pub(crate) fn text(&self, id: usize) -> &str {
        self.texts.get(id).map_or("", |t| t.as_ref())
    }

    /// The path of file `id`, as given.
    pub(crate) fn name(&self, id: usize) -> &str {
        self.paths.get(id).map_or("", |p| p.as_str())
    }

    pub(crate) fn line_count(&self, id: usize) -> usize {
        self.line_starts[id].len()
    }

    /// The index of the line `offset` is on.
    pub(crate) fn line_index(&self, id: usize, offset: usize) -> usize {
        self.line_starts[id].partition_point(|&s| s <= offset).saturating_sub(1)
    }

    /// The bytes of line `line`, with its line break.
    pub(crate) fn line_range(&self, id: usize, line: usize) -> std::ops::Range<usize> {
        let starts = &self.line_starts[id];
        let end = starts.get(line + 1).copied().unwrap_or(self.text(id).len());
        starts[line.min(starts.len() - 1)]..end
    }

    /// 1-based line and column (in characters) of a byte offset. A
    /// byte-order mark is not a column: editors do not show it.
    pub(crate) fn line_col(&self, id: usize, offset: usize) -> (usize, usize) {
        let starts = &self.line_starts[id];
        let line = starts.partition_point(|&s| s <= offset).saturating_sub(1);
        let text = self.text(id);
        let offset = offset.min(text.len());
        // The extra bytes of the wide characters that start before `at`.
        let wide = &self.wide[id];
        let extra = |at: usize| match wide.partition_point(|&(start, _)| start < at) {
            0 => 0,
            n => wide[n - 1].1,
        };
        let col = (offset - starts[line]).saturating_sub(extra(offset) - extra(starts[line]));
        // A byte-order mark is not a column.
        let bom = bom_len(text);
        let col = if line == 0 && bom > 0 && offset >= bom { col - 1 } else { col };
        (line + 1, col + 1)
    }
}

/// The length of the UTF-8 byte-order mark `text` starts with, if any.
fn bom_len(text: &str) -> usize {
    if text.starts_with('\u{feff}') { '\u{feff}'.len_utf8() } else { 0 }
}

pub struct Rendered<'a> {
    pub sources: &'a Sources,
    /// Every diagnostic: the summary counts them all.
    pub diagnostics: &'a [Diagnostic],
    pub io_errors: &'a [(String, String)],
    pub files: usize,
    /// At most this many diagnostics are printed per file (0: all), then one
    /// I0008 saying how many more there are (`diagnostic::shown_per_file`).
    pub max_per_file: usize,
}

impl Rendered<'_> {
    /// What is printed of the diagnostics.
    fn shown(&self) -> Vec<Diagnostic> {
        shown_per_file(self.diagnostics, self.max_per_file)
    }

    fn path(&self, file: SourceFile) -> String {
        self.sources.path(file)
    }

    fn counts(&self) -> (usize, usize) {
        let e = self.diagnostics.iter().filter(|d| d.severity == Severity::Error).count();
        let w = self.diagnostics.iter().filter(|d| d.severity == Severity::Warning).count();
        (e, w)
    }

    pub fn human(&self, color: ColorWhen) {
        let mut out = stderr(color);
        self.emit_human(&mut out);
        let (e, w) = self.counts();
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let unreadable = self.io_errors.len();
        let _ = if unreadable > 0 {
            writeln!(
                out,
                "checked {} file{}: {e} error{}, {w} warning{}; {unreadable} path{} could not be read",
                self.files,
                plural(self.files),
                plural(e),
                plural(w),
                plural(unreadable)
            )
        } else {
            writeln!(
                out,
                "checked {} file{}: {e} error{}, {w} warning{}",
                self.files,
                plural(self.files),
                plural(e),
                plural(w)
            )
        };
        let _ = out.flush();
    }

    /// The I/O errors and diagnostics, compiler-style, without the summary line.
    pub fn emit_human(&self, out: &mut dyn codespan_reporting::term::WriteStyle) {
        let config = term::Config::default();
        for (path, message) in self.io_errors {
            let _ = writeln!(out, "error: {path}: {message}");
        }
        for d in &self.shown() {
            let mut view = View::new(self.sources);
            if let Some(cs) = self.to_codespan(d, &mut view) {
                let _ = term::emit_to_write_style(out, &config, &view, &cs);
            }
        }
    }

    fn to_codespan(&self, d: &Diagnostic, view: &mut View<'_>) -> Option<CsDiagnostic<FileId>> {
        let id = self.sources.id(d.file)?;
        let severity = match d.severity {
            Severity::Error => CsSeverity::Error,
            Severity::Warning => CsSeverity::Warning,
            Severity::Info => CsSeverity::Note,
        };
        let (file, at) = view.place(id, range(d.range));
        let mut labels = vec![Label::primary(file, at)];
        for r in &d.related {
            if let Some(rid) = self.sources.id(r.file) {
                let (file, at) = view.place(rid, range(r.range));
                labels.push(Label::secondary(file, at).with_message(r.message.clone()));
            }
        }
        let mut notes = vec![format!("{}: {}", d.code.id, d.code.name)];
        if let Some(fix) = &d.fix {
            notes.push(format!("help: {}", fix.message));
        }
        Some(
            CsDiagnostic::new(severity)
                .with_message(&d.message)
                .with_code(d.code.id)
                .with_labels(labels)
                .with_notes(notes),
        )
    }

    fn location(&self, file: SourceFile, r: TextRange) -> Value {
        let path = self.path(file);
        let Some(id) = self.sources.id(file) else { return json!({ "file": path }) };
        let (l1, c1) = self.sources.line_col(id, usize::from(r.start()));
        let (l2, c2) = self.sources.line_col(id, usize::from(r.end()));
        json!({
            "file": path,
            "start": { "line": l1, "column": c1, "offset": u32::from(r.start()) },
            "end": { "line": l2, "column": c2, "offset": u32::from(r.end()) },
        })
    }

    pub fn json(&self) {
        let (e, w) = self.counts();
        let doc = json!({
            "version": 1,
            "diagnostics": self.json_diagnostics(),
            "io_errors": self.io_errors.iter().map(|(p, m)| json!({"path": p, "message": m})).collect::<Vec<_>>(),
            "summary": { "files": self.files, "errors": e, "warnings": w },
        });
        print_stdout(&serde_json::to_string_pretty(&doc).unwrap_or_default());
    }

    /// Each diagnostic as JSON (the `diagnostics` of `--format json`, docs/cli.md).
    pub fn json_diagnostics(&self) -> Vec<Value> {
        self.shown()
            .iter()
            .map(|d| {
                json!({
                    "code": d.code.id,
                    "name": d.code.name,
                    "severity": d.severity.as_str(),
                    "message": d.message,
                    "location": self.location(d.file, d.range),
                    "related": d.related.iter().map(|r| json!({
                        "message": r.message,
                        "location": self.location(r.file, r.range),
                    })).collect::<Vec<_>>(),
                    "fix": d.fix.as_ref().map(|f| json!({
                        "message": f.message,
                        "edits": f.edits.iter().map(|(file, r, text)| json!({
                            "location": self.location(*file, *r),
                            "insert": text,
                        })).collect::<Vec<_>>(),
                    })),
                })
            })
            .collect()
    }

    fn sarif_region(&self, file: SourceFile, r: TextRange) -> Value {
        let path = self.path(file);
        let Some(id) = self.sources.id(file) else { return json!({}) };
        let (l1, c1) = self.sources.line_col(id, usize::from(r.start()));
        let (l2, c2) = self.sources.line_col(id, usize::from(r.end()));
        json!({
            "artifactLocation": { "uri": sarif_uri(&path) },
            "region": { "startLine": l1, "startColumn": c1, "endLine": l2, "endColumn": c2 },
        })
    }

    pub fn sarif(&self) {
        let rules: Vec<Value> = codes::ALL
            .iter()
            .map(|c| {
                json!({
                    "id": c.id,
                    "name": c.name,
                    "shortDescription": { "text": c.summary },
                    "defaultConfiguration": { "level": sarif_level(c.severity) },
                })
            })
            .collect();
        let results: Vec<Value> = self
            .shown()
            .iter()
            .map(|d| {
                let rule_index = codes::ALL.iter().position(|c| c.id == d.code.id).unwrap_or(0);
                json!({
                    "ruleId": d.code.id,
                    "ruleIndex": rule_index,
                    "level": sarif_level(d.severity),
                    "message": { "text": d.message },
                    "locations": [ { "physicalLocation": self.sarif_region(d.file, d.range) } ],
                    "relatedLocations": d.related.iter().enumerate().map(|(i, r)| json!({
                        "id": i,
                        "message": { "text": r.message },
                        "physicalLocation": self.sarif_region(r.file, r.range),
                    })).collect::<Vec<_>>(),
                })
            })
            .collect();
        let mut notifications: Vec<Value> = Vec::new();
        for (path, message) in self.io_errors {
            notifications.push(json!({
                "level": "error",
                "message": { "text": format!("{path}: {message}") },
            }));
        }
        let doc = json!({
            "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
            "version": "2.1.0",
            "runs": [ {
                "tool": { "driver": {
                    "name": "hipop",
                    "version": env!("CARGO_PKG_VERSION"),
                    "rules": rules,
                } },
                "columnKind": "unicodeCodePoints",
                "invocations": [ {
                    "executionSuccessful": self.io_errors.is_empty(),
                    "toolExecutionNotifications": notifications,
                } ],
                "results": results,
            } ],
        });
        print_stdout(&serde_json::to_string_pretty(&doc).unwrap_or_default());
    }

    pub fn github(&self) {
        let mut out = String::new();
        for (path, message) in self.io_errors {
            out.push_str(&format!(
                "::error file={},title=hipop::{}\n",
                escape_property(path),
                escape_data(message)
            ));
        }
        for d in &self.shown() {
            let path = self.path(d.file);
            let level = match d.severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
                Severity::Info => "notice",
            };
            let Some(id) = self.sources.id(d.file) else { continue };
            let (l1, c1) = self.sources.line_col(id, usize::from(d.range.start()));
            let (l2, c2) = self.sources.line_col(id, usize::from(d.range.end()));
            out.push_str(&format!(
                "::{level} file={},line={l1},col={c1},endLine={l2},endColumn={c2},title={}::{}\n",
                escape_property(&path),
                escape_property(&format!("{} {}", d.code.id, d.code.name)),
                escape_data(&d.message)
            ));
        }
        print_stdout(out.trim_end_matches('\n'));
    }
}

/// Standard error for diagnostics, buffered: the renderer writes a source
/// line and its carets a character at a time. Flush it before writing to
/// standard error otherwise.
pub fn stderr(color: ColorWhen) -> BufferedStandardStream {
    BufferedStandardStream::stderr(color_choice(color))
}

/// Colours on stderr: `auto` means when it is a terminal.
pub fn color_choice(color: ColorWhen) -> ColorChoice {
    match color {
        ColorWhen::Always => ColorChoice::Always,
        ColorWhen::Never => ColorChoice::Never,
        ColorWhen::Auto => {
            if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
                ColorChoice::Auto
            } else {
                ColorChoice::Never
            }
        }
    }
}

/// Prints to stdout; a closed pipe (`hipop check … | head`) ends the output quietly.
pub fn print_stdout(text: &str) {
    let mut out = std::io::stdout().lock();
    if writeln!(out, "{text}").and_then(|()| out.flush()).is_err() {
        std::process::exit(0);
    }
}

fn range(r: TextRange) -> std::ops::Range<usize> {
    usize::from(r.start())..usize::from(r.end())
}

fn sarif_level(s: Severity) -> &'static str {
    match s {
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Info => "note",
    }
}

fn sarif_uri(path: &str) -> String {
    path.trim_start_matches("./").replace('\\', "/").replace(' ', "%20")
}

/// GitHub workflow command escaping (message part).
fn escape_data(s: &str) -> String {
    s.replace('%', "%25").replace('\r', "%0D").replace('\n', "%0A")
}

/// GitHub workflow command escaping (property values).
fn escape_property(s: &str) -> String {
    escape_data(s).replace(':', "%3A").replace(',', "%2C")
}
