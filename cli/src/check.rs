//! `hipop check`.

use hipop_analyzer::{AnalysisHost, Diagnostic, Severity};

use crate::inputs::{Input, collect};
use crate::render::{Rendered, Sources};
use crate::{ColorWhen, Format};

pub struct Options {
    pub format: Format,
    pub deny_warnings: bool,
    pub color: ColorWhen,
    /// Codes silenced for this run.
    pub allow: Vec<&'static hipop_analyzer::Code>,
    pub triangle_tolerance: f64,
}

/// Checks the files and prints the diagnostics; returns the exit status.
pub fn run(paths: &[std::path::PathBuf], options: &Options) -> u8 {
    let inputs = collect(paths);
    let mut host = AnalysisHost::new();
    host.set_triangle_tolerance(options.triangle_tolerance);
    let mut io_errors = Vec::new();
    let mut files = Vec::new();
    for input in inputs {
        match input {
            Input::File { path, text } => files.push(host.set_file_text(&path, text)),
            Input::Problem { path, message } => io_errors.push((path, message)),
        }
    }
    let analysis = host.analysis();
    let mut diagnostics: Vec<Diagnostic> = Vec::new();
    for &f in &files {
        match analysis.diagnostics(f) {
            Ok(d) => diagnostics.extend(d.into_iter().filter(|d| !options.allow.contains(&d.code))),
            // Nothing writes to the database while the CLI reads it, so this
            // cannot happen; if it ever did, say so rather than print half a result.
            Err(_) => {
                eprintln!("error: the analysis was interrupted; this is a bug in hipop, please report it");
                return 2;
            }
        }
    }
    let sources = Sources::new(&analysis, &files);
    let rendered =
        Rendered { sources: &sources, diagnostics: &diagnostics, io_errors: &io_errors, files: files.len() };
    match options.format {
        Format::Human => rendered.human(options.color),
        Format::Json => rendered.json(),
        Format::Sarif => rendered.sarif(),
        Format::Github => rendered.github(),
    }
    let errors = diagnostics.iter().filter(|d| d.severity == Severity::Error).count();
    let warnings = diagnostics.iter().filter(|d| d.severity == Severity::Warning).count();
    if !io_errors.is_empty() {
        2
    } else if errors > 0 || (options.deny_warnings && warnings > 0) {
        1
    } else {
        0
    }
}
