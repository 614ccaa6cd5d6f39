//! `hipop check`.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use hipop_analyzer::db::{UnitHeader, UnitKind};
use hipop_analyzer::fix::{apply_edits, select_fixes};
use hipop_analyzer::semantics::resolve::independent_groups;
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
    host.drop_syntax_after_use();
    host.set_triangle_tolerance(options.triangle_tolerance);
    let mut io_errors = Vec::new();
    let mut texts: Vec<(String, Arc<str>)> = Vec::new();
    for input in inputs {
        match input {
            Input::File { path, text } => texts.push((path, Arc::from(text))),
            Input::Problem { path, message } => io_errors.push((path, message)),
        }
    }
    let files: Vec<SourceFile> =
        texts.iter().map(|(path, text)| host.set_file_text(path, text.clone())).collect();
    let explain = options.explain == Some(crate::Explain::Families) && options.format == Format::Human;
    let Some(checked) = check_groups(&mut host, &files, &texts, options, explain) else {
        eprintln!("error: the analysis was interrupted; this is a bug in hipop, please report it");
        return 2;
    };
    let diagnostics: Vec<Diagnostic> = checked.iter().flat_map(|c| c.diagnostics.iter().cloned()).collect();
    let analysis = host.analysis();
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
    for c in &checked {
        c.families.iter().for_each(|r| print!("{r}"));
    }
    let errors = diagnostics.iter().filter(|d| d.severity == Severity::Error).count();
    let warnings = diagnostics.iter().filter(|d| d.severity == Severity::Warning).count();
    // The process ends right after: freeing the database, item by item, would
    // only take time.
    std::mem::forget(host);
    if !io_errors.is_empty() {
        2
    } else if errors > 0 || (options.deny_warnings && warnings > 0) {
        1
    } else {
        0
    }
}

/// What was found in one file: its diagnostics (those silenced by `--allow`
/// left out), and with `--explain families` the explanation of its problems.
#[derive(Default)]
struct Checked {
    diagnostics: Vec<Diagnostic>,
    families: Vec<String>,
}

/// At most this many groups of files are checked at once: each holds its
/// files' trees and grounding while it runs.
const MAX_GROUP_WORKERS: usize = 4;

/// Checks `files` (of `host`, with their `texts`), one result per file. When
/// the files fall into independent groups (a domain with its problems,
/// [`independent_groups`]), each group is checked in a database of its own,
/// dropped when it is done, a few groups at once (one per core, at most
/// [`MAX_GROUP_WORKERS`]): a folder of many domains never holds them all,
/// with every memo, at once. The diagnostics are the same as those of one
/// database, their files those of `host`. `None` if the analysis was
/// cancelled, which nothing does while the CLI reads it.
fn check_groups(
    host: &mut AnalysisHost,
    files: &[SourceFile],
    texts: &[(String, Arc<str>)],
    options: &Options,
    explain: bool,
) -> Option<Vec<Checked>> {
    let groups = groups(texts);
    if groups.len() < 2 {
        return check_all(host, files, options, explain, true);
    }
    // The memory of the syntax trees is returned to the system in the
    // largest group only, where the peak is: in the others it is left for
    // the next group's trees, which a return would fault in again (0.25 s
    // more system time on a folder of 50 domains, docs/benchmarks.md).
    let size = |group: &[usize]| group.iter().map(|&i| texts[i].1.len()).sum::<usize>();
    // The largest groups first, so that the workers end together.
    let mut order: Vec<usize> = (0..groups.len()).collect();
    order.sort_by_key(|&g| (std::cmp::Reverse(size(&groups[g])), g));
    let largest = order[0];
    let check_group = |g: usize| -> Option<Vec<Checked>> {
        let group = &groups[g];
        let mut own = AnalysisHost::new();
        own.drop_syntax_after_use();
        own.set_triangle_tolerance(options.triangle_tolerance);
        let own_files: Vec<SourceFile> =
            group.iter().map(|&i| own.set_file_text(&texts[i].0, texts[i].1.clone())).collect();
        // This group's files are the host's files at the same indices.
        let to_host: HashMap<SourceFile, SourceFile> =
            own_files.iter().zip(group).map(|(&f, &i)| (f, files[i])).collect();
        let mut checked = check_all(&mut own, &own_files, options, explain, g == largest)?;
        for c in &mut checked {
            c.diagnostics.iter_mut().for_each(|d| relocate(d, &to_host));
        }
        Some(checked)
    };
    // Groups share nothing: a few at a time, each in its own thread, taken
    // in turn from `order`.
    let workers =
        std::thread::available_parallelism().map_or(1, |n| n.get()).min(MAX_GROUP_WORKERS).min(groups.len());
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done = Vec::new();
        while let Some(&g) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
            done.push((g, check_group(g)));
        }
        done
    };
    let done: Vec<(usize, Option<Vec<Checked>>)> = std::thread::scope(|scope| {
        let others: Vec<_> = (1..workers).map(|_| scope.spawn(work)).collect();
        let mut done = work();
        for other in others {
            done.extend(other.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)));
        }
        done
    });
    let mut out: Vec<Checked> = files.iter().map(|_| Checked::default()).collect();
    for (g, checked) in done {
        for (c, &i) in checked?.into_iter().zip(&groups[g]) {
            out[i] = c;
        }
    }
    Some(out)
}

/// Checks `files` of `host` (made with [`AnalysisHost::drop_syntax_after_use`]),
/// one result per file: every file parsed first, then the checks, which
/// lower every item, then the syntax trees are dropped, then the lints,
/// which ground the problems on the lowered models. The trees and the
/// grounding are never held at once. With `return_memory`, the memory
/// freed after the parses and after the trees is returned to the system
/// (Satellite pair: peak 85-89 -> 76-79 MB for the parses, at no cost in
/// time; docs/benchmarks.md).
fn check_all(
    host: &mut AnalysisHost,
    files: &[SourceFile],
    options: &Options,
    explain: bool,
    return_memory: bool,
) -> Option<Vec<Checked>> {
    {
        let analysis = host.analysis();
        for &f in files {
            analysis.parse_file(f).ok()?;
        }
        if return_memory {
            crate::return_free_memory();
        }
        for &f in files {
            analysis.check_diagnostics(f).ok()?;
        }
    }
    host.release_syntax();
    if return_memory {
        crate::return_free_memory();
    }
    let analysis = host.analysis();
    let check = |f: SourceFile| -> Option<Checked> {
        let diagnostics = analysis.diagnostics(f).ok()?;
        let diagnostics = diagnostics.into_iter().filter(|d| !options.allow.contains(&d.code)).collect();
        let families = if explain { analysis.explain_families(f).ok()? } else { Vec::new() };
        Some(Checked { diagnostics, families })
    };
    files.iter().map(|&f| check(f)).collect()
}

/// The independent groups of the files, or one group of all when a file's
/// units cannot be told without parsing it (see `scan_unit_headers`) or a file
/// is a plan (a plan's problem is found among the workspace's files).
fn groups(texts: &[(String, Arc<str>)]) -> Vec<Vec<usize>> {
    let all = || vec![(0..texts.len()).collect()];
    let mut headers = Vec::with_capacity(texts.len());
    for (path, text) in texts {
        if hipop_analyzer::db::is_plan_path(path) {
            return all();
        }
        match hipop_analyzer::db::scan_unit_headers(text) {
            Some(h) if h.iter().all(|u| u.kind != UnitKind::Unknown) => headers.push(h),
            _ => return all(),
        }
    }
    let files: Vec<(&str, &[UnitHeader])> =
        texts.iter().zip(&headers).map(|((p, _), h)| (p.as_str(), h.as_slice())).collect();
    independent_groups(&files)
}

/// Moves a diagnostic found in a group's database to the files of the host.
fn relocate(d: &mut Diagnostic, to_host: &HashMap<SourceFile, SourceFile>) {
    let at = |f: &mut SourceFile| {
        if let Some(&h) = to_host.get(f) {
            *f = h;
        }
    };
    at(&mut d.file);
    d.related.iter_mut().for_each(|r| at(&mut r.file));
    if let Some(fix) = &mut d.fix {
        fix.edits.iter_mut().for_each(|(f, _, _)| at(f));
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
