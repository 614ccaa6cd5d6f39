//! Snapshot tests of the diagnostics of the deliberately broken fixtures in
//! `samples/broken/` (see its README).
//!
//! - `samples/broken/<CODE>-<name>.{pddl,hddl}`: one file, checked alone;
//! - `samples/broken/<CODE>-<name>/`: a folder whose files are checked together
//!   (a problem and its domain);
//! - `samples/broken/recovery/*`: syntax errors followed by a semantic error, to
//!   show that the parser's recovery lets the rest of the file be analysed.
//!
//! Every diagnostic is rendered as one line `CODE severity line:col-line:col
//! message`, followed by indented lines for the text it covers, its related
//! locations and its fix; the rendering is snapshotted. Besides the snapshots,
//! each fixture asserts what its name or header promises: a fixture named after
//! a code reports that code and no other, and a recovery fixture reports exactly
//! one syntax error, on the line given by its `; expect-syntax-error-line: N`
//! header, and the error of its `; expect-later-error: CODE at line N` header.

use std::path::{Path, PathBuf};

use hipop_analyzer::{AnalysisHost, Code, Diagnostic, Severity, SourceFile, TextRange, codes};

/// The folder of the fixtures.
fn broken_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples/broken")
}

fn is_model_file(p: &Path) -> bool {
    matches!(p.extension().and_then(|e| e.to_str()), Some("pddl" | "hddl"))
}

/// The file or folder name of a fixture.
fn fixture_name(path: &Path) -> String {
    path.file_name().expect("a fixture has a name").to_string_lossy().into_owned()
}

/// The files of a fixture: the file itself, or the model files of a folder, by name.
fn fixture_files(path: &Path) -> Vec<PathBuf> {
    if path.is_dir() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(path)
            .expect("readable fixture folder")
            .map(|e| e.expect("readable entry").path())
            .filter(|p| p.is_file() && is_model_file(p))
            .collect();
        files.sort();
        assert!(!files.is_empty(), "fixture folder {} has no .pddl or .hddl file", path.display());
        files
    } else {
        vec![path.to_path_buf()]
    }
}

/// A file of a fixture as the analyzer saw it.
struct Loaded {
    /// The name shown in the rendering: the path relative to the fixture's folder.
    name: String,
    text: String,
    file: SourceFile,
}

/// Checks the files of a fixture together; returns them and their diagnostics.
fn analyse(path: &Path) -> (Vec<Loaded>, Vec<Diagnostic>) {
    let base = if path.is_dir() { path.to_path_buf() } else { path.parent().expect("parent").to_path_buf() };
    let mut host = AnalysisHost::new();
    let mut loaded = Vec::new();
    for f in fixture_files(path) {
        let text = std::fs::read_to_string(&f).expect("fixtures are UTF-8");
        let rel = f.strip_prefix(&base).expect("fixture file inside its folder");
        let name = rel.to_string_lossy().replace('\\', "/");
        // The analyzer finds a problem's domain by path: keep the fixture's folder.
        let host_path = format!("{}/{name}", fixture_name(&base));
        let file = host.set_file_text(&host_path, text.as_str());
        loaded.push(Loaded { name, text, file });
    }
    let analysis = host.analysis();
    let mut diagnostics = Vec::new();
    for l in &loaded {
        diagnostics.extend(analysis.diagnostics(l.file).expect("nothing cancels a test's analysis"));
    }
    (loaded, diagnostics)
}

/// 1-based line and column (in characters) of a byte offset.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[line_start..].chars().count() + 1)
}

fn file_of(loaded: &[Loaded], file: SourceFile) -> &Loaded {
    loaded.iter().find(|l| l.file == file).expect("diagnostics point into the fixture's files")
}

fn span(loaded: &[Loaded], file: SourceFile, range: TextRange) -> String {
    let text = &file_of(loaded, file).text;
    let (l1, c1) = line_col(text, usize::from(range.start()));
    let (l2, c2) = line_col(text, usize::from(range.end()));
    format!("{l1}:{c1}-{l2}:{c2}")
}

/// The text a range covers, on one line and shortened.
fn excerpt(text: &str, range: TextRange) -> String {
    let s: String = text[usize::from(range.start())..usize::from(range.end())]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    if s.chars().count() > 60 { format!("{} …", s.chars().take(60).collect::<String>()) } else { s }
}

/// One diagnostic as text lines.
fn render_one(loaded: &[Loaded], d: &Diagnostic, out: &mut String) {
    let here = file_of(loaded, d.file);
    out.push_str(&format!(
        "{} {} {} {}\n",
        d.code.id,
        d.severity.as_str(),
        span(loaded, d.file, d.range),
        d.message
    ));
    out.push_str(&format!("  text: `{}`\n", excerpt(&here.text, d.range)));
    for r in &d.related {
        let there = file_of(loaded, r.file);
        out.push_str(&format!(
            "  related: {} {} `{}`: {}\n",
            there.name,
            span(loaded, r.file, r.range),
            excerpt(&there.text, r.range),
            r.message
        ));
    }
    if let Some(fix) = &d.fix {
        out.push_str(&format!("  fix: {}\n", fix.message));
        for (file, range, insert) in &fix.edits {
            out.push_str(&format!(
                "    edit: {} {} -> {insert:?}\n",
                file_of(loaded, *file).name,
                span(loaded, *file, *range)
            ));
        }
    }
}

/// Every diagnostic of a fixture, file by file (with a `== name ==` header when
/// the fixture has several files).
fn render(loaded: &[Loaded], diagnostics: &[Diagnostic]) -> String {
    let mut out = String::new();
    for l in loaded {
        if loaded.len() > 1 {
            out.push_str(&format!("== {} ==\n", l.name));
        }
        let mine: Vec<&Diagnostic> = diagnostics.iter().filter(|d| d.file == l.file).collect();
        if mine.is_empty() {
            out.push_str("(no diagnostics)\n");
        }
        for d in mine {
            render_one(loaded, d, &mut out);
        }
    }
    out
}

/// The code a fixture is named after: `E0102-undefined-predicate.pddl` → E0102.
fn code_of_fixture(name: &str) -> &'static Code {
    let id = name.split('-').next().unwrap_or_default();
    let code = codes::ALL
        .iter()
        .copied()
        .find(|c| c.id == id)
        .unwrap_or_else(|| panic!("fixture `{name}` is not named after a code of the registry"));
    let stem = name.split('.').next().unwrap_or_default();
    assert_eq!(
        stem,
        format!("{}-{}", code.id, code.name),
        "fixture `{name}` must be named `<code>-<name>` after the registry"
    );
    code
}

fn header_comment_is_present(loaded: &[Loaded]) {
    for l in loaded {
        assert!(
            l.text.starts_with(';'),
            "fixture file `{}` must start with a `;` comment saying what is wrong",
            l.name
        );
    }
}

/// Checks a fixture named after a code: it reports that code, and only that code.
fn check_named_fixture(path: &Path) {
    let name = fixture_name(path);
    let code = code_of_fixture(&name);
    let (loaded, diagnostics) = analyse(path);
    header_comment_is_present(&loaded);
    let rendered = render(&loaded, &diagnostics);
    insta::assert_snapshot!(rendered);
    assert!(
        diagnostics.iter().any(|d| d.code.id == code.id),
        "fixture `{name}` does not report {}:\n{rendered}",
        code.id
    );
    // Information (a confirmed position family, say) may accompany any code.
    assert!(
        diagnostics.iter().all(|d| d.code.id == code.id || d.severity == Severity::Info),
        "fixture `{name}` reports other codes than {}:\n{rendered}",
        code.id
    );
    for d in &diagnostics {
        assert_eq!(d.severity, d.code.severity, "a diagnostic's severity is its code's");
    }
}

/// Checks a clean counterpart `tests/lints/<CODE>-<name>-ok…`: a model close to
/// the fixture of that code, without the mistake. It must not report the code.
fn check_clean_counterpart(path: &Path) {
    let name = fixture_name(path);
    let stem = name.split('.').next().unwrap_or_default();
    let code = code_of_fixture(
        stem.strip_suffix("-ok")
            .unwrap_or_else(|| panic!("clean counterpart `{name}` must be named `<code>-<name>-ok`")),
    );
    let (loaded, diagnostics) = analyse(path);
    header_comment_is_present(&loaded);
    let rendered = render(&loaded, &diagnostics);
    insta::assert_snapshot!(rendered);
    assert!(
        diagnostics.iter().all(|d| d.code.id != code.id),
        "clean counterpart `{name}` reports {}:\n{rendered}",
        code.id
    );
}

fn lints_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/lints")
}

#[test]
fn clean_counterparts() {
    // insta's glob fails on no match: there is none until the first lint lands.
    let fixtures = std::fs::read_dir(lints_dir())
        .map_or(0, |d| d.filter(|e| e.as_ref().is_ok_and(|e| e.file_name() != "README.md")).count());
    if fixtures == 0 {
        return;
    }
    insta::glob!("../../tests/lints", "[EWI][0-9][0-9][0-9][0-9]-*-ok*", check_clean_counterpart);
}

/// Every model-verification code (E03xx, W03xx, I03xx) has a clean counterpart.
#[test]
fn every_lint_has_a_clean_counterpart() {
    let names: Vec<String> = std::fs::read_dir(lints_dir())
        .map(|d| d.map(|e| fixture_name(&e.expect("readable entry").path())).collect())
        .unwrap_or_default();
    let missing: Vec<String> = codes::ALL
        .iter()
        .filter(|c| &c.id[1..3] == "03")
        .map(|c| format!("{}-{}-ok", c.id, c.name))
        .filter(|stem| !names.iter().any(|n| n.split('.').next() == Some(stem.as_str())))
        .collect();
    assert!(missing.is_empty(), "lint codes without a clean counterpart in tests/lints: {missing:?}");
}

#[test]
fn single_file_fixtures() {
    insta::glob!("../../samples/broken", "*.{pddl,hddl}", check_named_fixture);
}

#[test]
fn folder_fixtures() {
    insta::glob!("../../samples/broken", "[EWI][0-9][0-9][0-9][0-9]-*", |path| {
        if path.is_dir() {
            check_named_fixture(path);
        }
    });
}

/// The value of a `; key: value` header line.
fn header_value<'t>(text: &'t str, key: &str) -> Option<&'t str> {
    text.lines()
        .take_while(|l| l.starts_with(';'))
        .find_map(|l| l.trim_start_matches(';').trim().strip_prefix(key))
        .map(|v| v.trim_start_matches(':').trim())
}

#[test]
fn recovery_fixtures() {
    insta::glob!("../../samples/broken", "recovery/*.{pddl,hddl}", |path| {
        let (loaded, diagnostics) = analyse(path);
        header_comment_is_present(&loaded);
        let rendered = render(&loaded, &diagnostics);
        insta::assert_snapshot!(rendered);
        let text = &loaded[0].text;
        let name = fixture_name(path);
        let line_of = |d: &Diagnostic| line_col(text, usize::from(d.range.start())).0;

        let expected_line: usize = header_value(text, "expect-syntax-error-line")
            .unwrap_or_else(|| panic!("`{name}` has no `; expect-syntax-error-line: N` header"))
            .parse()
            .expect("a line number");
        let syntax: Vec<&Diagnostic> = diagnostics
            .iter()
            .filter(|d| d.code.id == codes::MISSING_PAREN.id || d.code.id == codes::EXTRA_PAREN.id)
            .collect();
        assert_eq!(syntax.len(), 1, "`{name}` must report exactly one syntax error:\n{rendered}");
        assert_eq!(
            line_of(syntax[0]),
            expected_line,
            "`{name}`: the syntax error is not on the expected line"
        );

        let later = header_value(text, "expect-later-error")
            .unwrap_or_else(|| panic!("`{name}` has no `; expect-later-error: CODE at line N` header"));
        let (code, line) = later.split_once(" at line ").expect("`CODE at line N`");
        let line: usize = line.trim().parse().expect("a line number");
        assert!(
            diagnostics.iter().any(|d| d.code.id == code && line_of(d) == line),
            "`{name}`: the later error {code} at line {line} is not reported:\n{rendered}"
        );
    });
}

/// Every code of the registry has a fixture named after it (I0008 aside). The plan codes
/// (E04xx and W04xx) are about plans, which `hipop check` does not read:
/// the fixtures of reading plans are in `tests/plans/` (`tests/plans.rs`),
/// those of temporal plan validation (E0410–E0429, W0410–W0429) in
/// `tests/validate/` (`analyzer/tests/validate.rs`).
#[test]
fn every_code_has_a_fixture() {
    let names: Vec<String> = std::fs::read_dir(broken_dir())
        .expect("samples/broken exists")
        .map(|e| fixture_name(&e.expect("readable entry").path()))
        .collect();
    let missing: Vec<String> = codes::ALL
        .iter()
        // Plan codes (04) have their fixtures in tests/plans, tests/validate
        // and tests/validate-htn; the planner's (05) in tests/planner, each
        // exercised by analyzer/tests/planner.rs.
        .filter(|c| &c.id[1..3] != "04" && &c.id[1..3] != "05")
        // I0008 says how many diagnostics the shells do not print: its example
        // is `tests/limits/` (cli/tests/cli/hostile.rs).
        .filter(|c| c.id != codes::DIAGNOSTICS_NOT_SHOWN.id)
        .map(|c| format!("{}-{}", c.id, c.name))
        .filter(|stem| {
            !names.iter().any(|n| {
                n == stem || n.strip_suffix(".pddl") == Some(stem) || n.strip_suffix(".hddl") == Some(stem)
            })
        })
        .collect();
    assert!(missing.is_empty(), "codes without a fixture in samples/broken: {missing:?}");
}

/// The README of `samples/broken/` lists every fixture.
#[test]
fn readme_lists_every_fixture() {
    let readme = std::fs::read_to_string(broken_dir().join("README.md")).expect("samples/broken/README.md");
    let mut entries: Vec<PathBuf> =
        std::fs::read_dir(broken_dir()).expect("samples/broken").map(|e| e.expect("entry").path()).collect();
    entries.extend(
        std::fs::read_dir(broken_dir().join("recovery"))
            .expect("samples/broken/recovery")
            .map(|e| e.expect("entry").path()),
    );
    for p in entries {
        let name = fixture_name(&p);
        if name == "README.md" || name == "recovery" {
            continue;
        }
        assert!(readme.contains(&name), "samples/broken/README.md does not mention `{name}`");
    }
}
