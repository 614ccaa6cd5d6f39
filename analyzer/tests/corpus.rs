//! The real files of ../shared/corpora: every domain and problem of every
//! folder checks with no error (a PDDL+ domain gets exactly one warning,
//! W0207), the plans among them (a plan saved as `.hddl`, the reference
//! plans) read without error, trees print back to the input, and the
//! warnings and notes are a reviewed snapshot. A real file is the ground
//! truth: an error on one is a defect of hipop until shown otherwise.

use std::path::{Path, PathBuf};

use hipop_analyzer::{AnalysisHost, Severity};

/// The folders of the corpora (MANIFEST.md there), in the order of their names.
const FOLDERS: &[&str] =
    &["hddl2.1", "ipc2002-temporal", "ipc2020-hddl", "pandaPIparser-tests", "reference-plans", "val-samples"];

fn corpora() -> Option<PathBuf> {
    let dir = std::env::var_os("HIPOP_CORPORA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora"));
    dir.is_dir().then_some(dir)
}

/// Domain and problem files: `.pddl` and `.hddl`, and files without extension
/// that start like one (VAL's Depots problems `pfile1`…). With `plans`, also
/// plan files (`.plan`).
fn model_files(dir: &Path, plans: bool, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            model_files(&p, plans, out);
            continue;
        }
        match p.extension().and_then(|e| e.to_str()) {
            Some("pddl" | "hddl") => out.push(p),
            Some("plan") if plans => out.push(p),
            None => {
                let text = std::fs::read_to_string(&p).unwrap_or_default();
                if text.trim_start().to_ascii_lowercase().starts_with("(define") {
                    out.push(p);
                }
            }
            _ => {}
        }
    }
}

/// What one folder gave.
#[derive(Default)]
struct Tally {
    files: usize,
    errors: usize,
    warnings: usize,
    notes: usize,
    not_a_family: usize,
}

#[test]
fn corpus_files_check_without_errors() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP corpus test: ../shared/corpora is absent (set HIPOP_CORPORA to its path)");
        return;
    };
    let mut files: Vec<(usize, PathBuf)> = Vec::new();
    let mut present = 0;
    for (k, folder) in FOLDERS.iter().enumerate() {
        let path = dir.join(folder);
        if !path.is_dir() {
            eprintln!("SKIP corpus folder {folder}: absent from {}", dir.display());
            continue;
        }
        present += 1;
        let mut found = Vec::new();
        // The reference plans are the folder's content: they must read.
        model_files(&path, *folder == "reference-plans", &mut found);
        files.extend(found.into_iter().map(|f| (k, f)));
    }
    if present == FOLDERS.len() {
        assert!(files.len() > 1000, "expected the whole corpus, found {} files", files.len());
    }

    let mut host = AnalysisHost::new();
    let mut handles = Vec::new();
    for (k, f) in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let rel = f.strip_prefix(&dir).unwrap().to_string_lossy().replace('\\', "/");
        handles.push((*k, rel.clone(), text.clone(), host.set_file_text(&rel, text)));
    }
    let analysis = host.analysis();
    let mut tallies: Vec<Tally> = FOLDERS.iter().map(|_| Tally::default()).collect();
    let mut failures = Vec::new();
    let mut warnings = Vec::new();
    let mut plans = Vec::new();
    let mut pddl_plus = 0;
    for (k, rel, text, file) in &handles {
        assert_eq!(
            &hipop_analyzer::syntax::parse(text).text(),
            text,
            "{rel}: the tree must print back the input"
        );
        let diags = analysis.diagnostics(*file).unwrap();
        let line = |d: &hipop_analyzer::Diagnostic| {
            let l = text[..usize::from(d.range.start())].matches('\n').count() + 1;
            format!("{rel}:{l}: {} {}", d.code.id, d.message)
        };
        let tally = &mut tallies[*k];
        tally.files += 1;
        for d in &diags {
            match d.severity {
                Severity::Error => tally.errors += 1,
                Severity::Warning => tally.warnings += 1,
                Severity::Info => tally.notes += 1,
            }
            tally.not_a_family += usize::from(d.code.id == "I0307");
        }
        if !text.to_ascii_lowercase().contains("(define") {
            // Plans: the reference plans, and one saved as `.hddl`.
            plans.push(rel.clone());
        }
        let is_plus = text.contains("(:process") || text.contains("(:event");
        if is_plus {
            pddl_plus += 1;
            let all: Vec<String> = diags.iter().map(line).collect();
            if diags.len() != 1 || diags[0].code.id != "W0207" || !diags[0].message.contains("PDDL+") {
                failures.push(format!("{rel}: a PDDL+ domain must get exactly one W0207: {all:?}"));
            }
            continue;
        }
        for d in &diags {
            match d.severity {
                Severity::Error => failures.push(line(d)),
                _ => warnings.push(line(d)),
            }
        }
    }
    eprintln!("corpus: {} files, {} PDDL+ domains, {} plans", handles.len(), pddl_plus, plans.len());
    eprintln!(
        "{:<22} {:>6} {:>7} {:>9} {:>6} {:>6}",
        "folder", "files", "errors", "warnings", "notes", "I0307"
    );
    for (folder, t) in FOLDERS.iter().zip(&tallies) {
        eprintln!(
            "{folder:<22} {:>6} {:>7} {:>9} {:>6} {:>6}",
            t.files, t.errors, t.warnings, t.notes, t.not_a_family
        );
    }
    assert!(failures.is_empty(), "{} errors in real files:\n{}", failures.len(), failures.join("\n"));
    if present == FOLDERS.len() {
        assert_eq!(pddl_plus, 4, "the VAL samples have four PDDL+ domains");
        let hddl_plans = plans.iter().filter(|p| !p.starts_with("reference-plans/")).count();
        assert_eq!(hddl_plans, 1, "the IPC 2020 feature tests keep one plan as `.hddl`: {plans:?}");
        assert!(tallies.iter().all(|t| t.files > 0), "every folder has files");
        insta::assert_snapshot!("corpus_warnings", warnings.join("\n"));
    }
}

/// The significant tokens of a text (atoms and parentheses), and its comments
/// without their trailing whitespace, in order.
fn tokens_and_comments(text: &str) -> (Vec<String>, Vec<String>) {
    use hipop_analyzer::syntax::{NodeOrToken, SyntaxKind};
    let (mut tokens, mut comments) = (Vec::new(), Vec::new());
    for e in hipop_analyzer::syntax::parse(text).syntax().descendants_with_tokens() {
        if let NodeOrToken::Token(t) = e {
            match t.kind() {
                SyntaxKind::Whitespace => {}
                SyntaxKind::Comment => comments.push(t.text().trim_end().to_string()),
                _ => tokens.push(t.text().to_string()),
            }
        }
    }
    (tokens, comments)
}

/// Every domain and problem of the corpora formats: formatting again changes
/// nothing, the formatted file has the same atoms and parentheses in the same
/// order, the same comments in the same order, no syntax error, and the same
/// diagnostics (of the checks; each problem against its formatted domain),
/// each on the same text. Files that are plans are refused, and only they.
#[test]
fn corpus_files_format_idempotently_and_safely() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP corpus formatting test: ../shared/corpora is absent (set HIPOP_CORPORA to its path)");
        return;
    };
    let started = std::time::Instant::now();
    let mut files = Vec::new();
    for folder in FOLDERS {
        let path = dir.join(folder);
        if path.is_dir() {
            model_files(&path, false, &mut files);
        } else {
            eprintln!("SKIP corpus folder {folder}: absent from {}", dir.display());
        }
    }
    let (mut original, mut formatted) = (AnalysisHost::new(), AnalysisHost::new());
    let mut pairs = Vec::new();
    let mut failures = Vec::new();
    let (mut changed, mut plans, mut bytes) = (0, 0, 0);
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        bytes += text.len();
        let rel = f.strip_prefix(&dir).unwrap().to_string_lossy().replace('\\', "/");
        let once = match hipop_analyzer::ide::format(&text) {
            Ok(once) => once,
            Err(e) if e.kind == hipop_analyzer::ide::FormatErrorKind::NotAModel => {
                plans += 1;
                if text.to_ascii_lowercase().contains("(define") {
                    failures.push(format!("{rel}: refused as not a model: {}", e.message));
                }
                continue;
            }
            Err(e) => {
                failures.push(format!("{rel}: not formatted: {}", e.message));
                continue;
            }
        };
        changed += usize::from(once != text);
        match hipop_analyzer::ide::format(&once) {
            Ok(twice) if twice == once => {}
            Ok(twice) => {
                let line = once.lines().zip(twice.lines()).position(|(a, b)| a != b).map_or(0, |l| l + 1);
                failures.push(format!("{rel}: formatting twice changes line {line} of the first result"));
            }
            Err(e) => failures.push(format!("{rel}: the formatted file does not format: {}", e.message)),
        }
        if !hipop_analyzer::syntax::parse(&once).errors.is_empty() {
            failures.push(format!("{rel}: the formatted file has syntax errors"));
        }
        let (before, after) = (tokens_and_comments(&text), tokens_and_comments(&once));
        if before.0 != after.0 {
            failures.push(format!("{rel}: the formatted file's atoms and parentheses differ"));
        }
        if before.1 != after.1 {
            failures.push(format!("{rel}: the formatted file's comments differ"));
        }
        let a = original.set_file_text(&rel, text.clone());
        let b = formatted.set_file_text(&rel, once.clone());
        pairs.push((rel, text, once, a, b));
    }
    let (original, formatted) = (original.analysis(), formatted.analysis());
    // What a diagnostic says, and the atoms and parentheses it is on.
    let said = |text: &str, d: &hipop_analyzer::Diagnostic| {
        let on = tokens_and_comments(&text[d.range]).0.join(" ");
        format!("{} {} `{on}`", d.code.id, d.message)
    };
    let mut diagnostics = 0;
    for (rel, text, once, a, b) in &pairs {
        let before: Vec<String> =
            original.check_diagnostics(*a).unwrap().iter().map(|d| said(text, d)).collect();
        let after: Vec<String> =
            formatted.check_diagnostics(*b).unwrap().iter().map(|d| said(once, d)).collect();
        diagnostics += before.len();
        if before != after {
            failures.push(format!("{rel}: the diagnostics differ:\n  before {before:?}\n  after  {after:?}"));
        }
    }
    eprintln!(
        "corpus formatting: {} files ({} KB), {changed} changed, {plans} plans refused, {diagnostics} diagnostics compared, in {:.1?}",
        pairs.len(),
        bytes / 1024,
        started.elapsed()
    );
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
    if FOLDERS.iter().all(|f| dir.join(f).is_dir()) {
        assert!(pairs.len() > 1000, "expected the whole corpus, found {} files", pairs.len());
        assert_eq!(plans, 1, "the IPC 2020 feature tests keep one plan as `.hddl`");
    }
}
