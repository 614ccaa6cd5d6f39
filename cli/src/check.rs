//! `hipop check`.

use hipop_analyzer::fix::{apply_edits, select_fixes};
use hipop_analyzer::{AnalysisHost, Diagnostic, Fix, Severity, SourceFile, TextRange};

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
    pub explain: Option<crate::Explain>,
    /// Apply the fixes of the diagnostics first, then check what remains.
    pub fix: bool,
    /// At most this many diagnostics are printed per file (0: all).
    pub max_diagnostics: usize,
}

/// Checks the files and prints the diagnostics; returns the exit status.
pub fn run(paths: &[std::path::PathBuf], options: &Options) -> u8 {
    if options.fix
        && let Err(status) = fix(paths, options)
    {
        return status;
    }
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
    let rendered = Rendered {
        sources: &sources,
        diagnostics: &diagnostics,
        io_errors: &io_errors,
        files: files.len(),
        max_per_file: options.max_diagnostics,
    };
    match options.format {
        Format::Human => rendered.human(options.color),
        Format::Json => rendered.json(),
        Format::Sarif => rendered.sarif(),
        Format::Github => rendered.github(),
    }
    // Machine-readable formats own standard output: the explanation is for people.
    if options.explain == Some(crate::Explain::Families) && options.format == Format::Human {
        for &f in &files {
            match analysis.explain_families(f) {
                Ok(reports) => reports.iter().for_each(|r| print!("{r}")),
                Err(_) => return 2,
            }
        }
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

/// Applies every fix of the diagnostics of the files (those silenced by
/// `--allow` excepted), at most one per overlapping text, writes the files
/// that changed and says what was done. Unreadable inputs are left to the
/// check that follows, which reports them.
fn fix(paths: &[std::path::PathBuf], options: &Options) -> Result<(), u8> {
    let mut host = AnalysisHost::new();
    host.set_triangle_tolerance(options.triangle_tolerance);
    let files: Vec<SourceFile> = collect(paths)
        .into_iter()
        .filter_map(|input| match input {
            Input::File { path, text } => Some(host.set_file_text(&path, text)),
            Input::Problem { .. } => None,
        })
        .collect();
    let analysis = host.analysis();
    let interrupted = |_| {
        eprintln!("error: the analysis was interrupted; this is a bug in hipop, please report it");
        2
    };
    let mut diagnostics: Vec<Diagnostic> = Vec::new();
    for &f in &files {
        diagnostics.extend(analysis.diagnostics(f).map_err(interrupted)?);
    }
    let fixes: Vec<&Fix> = diagnostics
        .iter()
        .filter(|d| !options.allow.contains(&d.code))
        .filter_map(|d| d.fix.as_ref())
        .collect();
    if fixes.is_empty() {
        eprintln!("nothing to fix");
        return Ok(());
    }
    let (chosen, skipped) = select_fixes(&fixes);
    let mut written = 0;
    for &f in &files {
        let edits: Vec<(TextRange, &str)> = chosen
            .iter()
            .flat_map(|&i| &fixes[i].edits)
            .filter(|(file, _, _)| *file == f)
            .map(|(_, range, text)| (*range, text.as_str()))
            .collect();
        if edits.is_empty() {
            continue;
        }
        let path = analysis.file_path(f).map_err(interrupted)?;
        let text = analysis.file_text(f).map_err(interrupted)?;
        let Some(new) = apply_edits(&text, &edits) else {
            eprintln!(
                "error: the fixes of {path} do not apply to its text; this is a bug in hipop, please report it"
            );
            return Err(2);
        };
        if let Err(e) = std::fs::write(&path, new) {
            eprintln!("error: {path}: cannot write the fixes: {e}");
            return Err(2);
        }
        written += 1;
    }
    let plural = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    eprintln!(
        "fixed {} in {}",
        plural(chosen.len(), "diagnostic", "diagnostics"),
        plural(written, "file", "files")
    );
    if !skipped.is_empty() {
        eprintln!(
            "skipped {} that would overlap another: run `hipop check --fix` again",
            plural(skipped.len(), "fix", "fixes")
        );
    }
    Ok(())
}
