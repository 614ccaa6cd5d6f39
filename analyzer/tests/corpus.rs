//! The real files of ../shared/corpora: every domain and problem is read with
//! no error (PDDL+ domains get exactly one), trees print back to the input,
//! and the warnings are a reviewed snapshot.

use std::path::{Path, PathBuf};

use hipop_analyzer::{AnalysisHost, Severity};

fn corpora() -> Option<PathBuf> {
    let dir = std::env::var_os("HIPOP_CORPORA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora"));
    dir.is_dir().then_some(dir)
}

/// Domain and problem files: `.pddl` and `.hddl`, and files without extension
/// that start like one (VAL's Depots problems `pfile1`…).
fn model_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            model_files(&p, out);
            continue;
        }
        match p.extension().and_then(|e| e.to_str()) {
            Some("pddl" | "hddl") => out.push(p),
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

/// Genuine defects of corpus files that hipop finds: (file, code, why). The
/// corpus is never edited, so each is expected, and must still be reported
/// (a change that stops finding it has lost something).
const KNOWN_DEFECTS: &[(&str, &str, &str)] = &[(
    "hddl2.1/satellite/domain.hddl",
    "E0305",
    "its problem gives `turn-time` between image directions only, but the satellite starts \
     pointing at `star0`, a calibration direction: no turn from or to one has a duration",
)];

#[test]
fn corpus_files_check_without_errors() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP corpus test: ../shared/corpora is absent (set HIPOP_CORPORA to its path)");
        return;
    };
    let mut files = Vec::new();
    model_files(&dir, &mut files);
    assert!(files.len() > 1000, "expected the whole corpus, found {} files", files.len());

    let mut host = AnalysisHost::new();
    let mut handles = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let rel = f.strip_prefix(&dir).unwrap().to_string_lossy().replace('\\', "/");
        handles.push((rel.clone(), text.clone(), host.set_file_text(&rel, text)));
    }
    let analysis = host.analysis();
    let mut failures = Vec::new();
    let mut warnings = Vec::new();
    let mut not_models = Vec::new();
    let mut pddl_plus = 0;
    let mut known: Vec<&str> = Vec::new();
    for (rel, text, file) in &handles {
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
        if !text.to_ascii_lowercase().contains("(define") {
            // Plan files named `.hddl` live in the corpus too: one clear diagnostic.
            assert_eq!(diags.len(), 1, "{rel}: {:?}", diags.iter().map(line).collect::<Vec<_>>());
            assert!(diags[0].message.contains("not a domain or problem file"), "{rel}");
            not_models.push(rel.clone());
            continue;
        }
        let is_plus = text.contains("(:process") || text.contains("(:event");
        if is_plus {
            pddl_plus += 1;
            let all: Vec<String> = diags.iter().map(line).collect();
            if diags.len() != 1 || diags[0].code.id != "E0005" || !diags[0].message.contains("PDDL+") {
                failures.push(format!("{rel}: a PDDL+ domain must get exactly one E0005: {all:?}"));
            }
            continue;
        }
        for d in &diags {
            let defect = KNOWN_DEFECTS.iter().find(|(f, code, _)| f == rel && *code == d.code.id);
            match (d.severity, defect) {
                (Severity::Error, Some((f, _, _))) => known.push(f),
                (Severity::Error, None) => failures.push(line(d)),
                _ => warnings.push(line(d)),
            }
        }
    }
    eprintln!(
        "corpus: {} files, {} PDDL+ domains, {} warnings, not domain/problem files: {:?}",
        handles.len(),
        pddl_plus,
        warnings.len(),
        not_models
    );
    assert!(failures.is_empty(), "{} errors in real files:\n{}", failures.len(), failures.join("\n"));
    for (file, code, why) in KNOWN_DEFECTS {
        assert!(known.contains(file), "{file}: the known defect {code} is no longer reported ({why})");
    }
    assert_eq!(pddl_plus, 4, "the VAL samples have four PDDL+ domains");
    insta::assert_snapshot!("corpus_warnings", warnings.join("\n"));
}
