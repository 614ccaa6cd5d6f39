//! `hipop check` checks a folder one group of files at a time (a domain and
//! its problems, `semantics::resolve::independent_groups`), each in a
//! database of its own: the unit headers read without parsing are those of
//! the parse, and every file's diagnostics are the same in its group's
//! database as in one database of every file.

use std::path::{Path, PathBuf};

use hipop_analyzer::db::{UnitHeader, UnitKind, file_units, scan_unit_headers};
use hipop_analyzer::semantics::resolve::independent_groups;
use hipop_analyzer::{AnalysisHost, Diagnostic};

fn corpora() -> Option<PathBuf> {
    let dir = std::env::var_os("HIPOP_CORPORA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora"));
    dir.is_dir().then_some(dir)
}

fn model_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            model_files(&p, out);
        } else if matches!(p.extension().and_then(|e| e.to_str()), Some("pddl" | "hddl")) {
            out.push(p);
        }
    }
}

/// The headers `file_units` finds, from the parse.
fn parsed_headers(text: &str) -> Vec<UnitHeader> {
    let mut host = AnalysisHost::new();
    let f = host.set_file_text("f.pddl", text);
    host.analysis()
        .with_db(|db| {
            file_units(db, f)
                .iter()
                .map(|u| UnitHeader {
                    kind: u.kind(db),
                    name: u.name(db).clone(),
                    domain_ref: u.domain_ref(db).clone(),
                })
                .collect()
        })
        .unwrap()
}

#[test]
fn scanned_headers_are_those_of_the_parse() {
    let cases = [
        "(define (domain D) (:predicates (p)))",
        "\u{feff}; (define (domain no))\n(DEFINE (Problem P1) (:DOMAIN Dom) (:init))",
        "(define (problem p) (:domain a) (:domain b))",
        "(define (problem p) (:domain a) (:domain (b)))",
        "(define (problem) (:domain))",
        "(define (x) (domain d))",
        "(define (domain a)) (define (problem b) (:domain a)) (other (domain c))",
        "(define (domain a) (:action x :parameters (?x) :effect (and (p ?x) (not (q)))))\n(define (problem p) (:domain a))",
        "atom (define (domain a)) 12",
    ];
    for text in cases {
        assert_eq!(scan_unit_headers(text), Some(parsed_headers(text)), "{text}");
    }
    // What the parser recovers from, or what may be a plan, is not read.
    for text in
        ["(define (domain a)", "(define (domain a)))", ")(define (domain a))", "", "; nothing", "(a b)"]
    {
        assert_eq!(scan_unit_headers(text), None, "{text}");
    }
    let deep = format!("(define (domain a) {}{})", "(".repeat(300), ")".repeat(300));
    assert_eq!(scan_unit_headers(&deep), None);

    let Some(dir) = corpora() else {
        eprintln!("SKIP corpus part: ../shared/corpora is absent (set HIPOP_CORPORA to its path)");
        return;
    };
    let mut files = Vec::new();
    model_files(&dir, &mut files);
    let mut scanned = 0;
    for f in &files {
        let Ok(text) = std::fs::read_to_string(f) else { continue };
        if let Some(h) = scan_unit_headers(&text) {
            assert_eq!(h, parsed_headers(&text), "{}", f.display());
            scanned += 1;
        }
    }
    eprintln!("{scanned} of {} corpus files read without parsing", files.len());
    assert!(scanned * 10 > files.len() * 9, "{scanned} of {} files scanned", files.len());
}

/// Every file's diagnostics, in one database of all the files and in a database per group.
fn compare(files: &[(String, String)]) -> usize {
    let headers: Vec<Vec<UnitHeader>> = files.iter().map(|(_, t)| scan_unit_headers(t).unwrap()).collect();
    let input: Vec<(&str, &[UnitHeader])> =
        files.iter().zip(&headers).map(|((p, _), h)| (p.as_str(), h.as_slice())).collect();
    let groups = independent_groups(&input);
    let mut all = AnalysisHost::new();
    let handles: Vec<_> = files.iter().map(|(p, t)| all.set_file_text(p, t.as_str())).collect();
    let analysis = all.analysis();
    let text = |a: &hipop_analyzer::Analysis, d: &Diagnostic| {
        let path = |f| a.file_path(f).unwrap();
        let related: Vec<String> =
            d.related.iter().map(|r| format!("{}:{:?} {}", path(r.file), r.range, r.message)).collect();
        let fix = d.fix.as_ref().map(|f| {
            let edits: Vec<String> =
                f.edits.iter().map(|(e, r, t)| format!("{}:{r:?}={t}", path(*e))).collect();
            format!("{} {edits:?}", f.message)
        });
        format!("{} {} {:?} {} {related:?} {fix:?}", path(d.file), d.code.id, d.range, d.message)
    };
    for group in &groups {
        let mut own = AnalysisHost::new();
        let own_files: Vec<_> =
            group.iter().map(|&i| own.set_file_text(&files[i].0, files[i].1.as_str())).collect();
        let own_analysis = own.analysis();
        for (&f, &i) in own_files.iter().zip(group) {
            let expected: Vec<String> =
                analysis.diagnostics(handles[i]).unwrap().iter().map(|d| text(&analysis, d)).collect();
            let got: Vec<String> =
                own_analysis.diagnostics(f).unwrap().iter().map(|d| text(&own_analysis, d)).collect();
            assert_eq!(got, expected, "{}", files[i].0);
        }
    }
    groups.len()
}

#[test]
fn a_group_has_what_its_files_need() {
    let domain = |name: &str| {
        format!("(define (domain {name}) (:predicates (p)) (:action a :parameters () :effect (p)))")
    };
    let problem = |name: &str, domain: &str| {
        format!("(define (problem {name}) (:domain {domain}) (:objects o) (:init) (:goal (p)))")
    };
    let files: Vec<(String, String)> = [
        // Pairs by name, in one folder.
        ("set/p01-domain.pddl", domain("d1")),
        ("set/p01.pddl", problem("p1", "d1")),
        ("set/p02-domain.pddl", domain("d2")),
        ("set/p02.pddl", problem("p2", "d2")),
        // A domain of that name elsewhere too: the one beside wins, the other stays apart.
        ("other/d2.pddl", domain("d2")),
        // No domain of that name beside, one domain beside: a mismatch.
        ("lone/domain.pddl", domain("lone")),
        ("lone/problem.pddl", problem("q", "elsewhere")),
        // No domain beside: the closest of that name.
        ("far/a/problem.pddl", problem("r", "d3")),
        ("far/b/domain.pddl", domain("d3")),
        ("far/c/domain.pddl", domain("d3")),
        // Missing.
        ("nowhere/problem.pddl", problem("s", "none")),
    ]
    .into_iter()
    .map(|(p, t)| (p.to_string(), t))
    .collect();
    let headers: Vec<Vec<UnitHeader>> = files.iter().map(|(_, t)| scan_unit_headers(t).unwrap()).collect();
    assert!(headers.iter().all(|h| h[0].kind != UnitKind::Unknown));
    let input: Vec<(&str, &[UnitHeader])> =
        files.iter().zip(&headers).map(|((p, _), h)| (p.as_str(), h.as_slice())).collect();
    assert_eq!(
        independent_groups(&input),
        vec![vec![0, 1], vec![2, 3], vec![4], vec![5, 6], vec![7, 8, 9], vec![10]]
    );
    assert_eq!(compare(&files), 6);
}

#[test]
fn corpus_groups_give_the_diagnostics_of_one_database() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP corpus test: ../shared/corpora is absent (set HIPOP_CORPORA to its path)");
        return;
    };
    // Folders of pairs (pandaPIparser's tests, HDDL 2.1) and of one domain for many problems.
    for folder in ["pandaPIparser-tests", "hddl2.1", "ipc2002-temporal/depots-time-simple-automatic"] {
        let path = dir.join(folder);
        if !path.is_dir() {
            eprintln!("SKIP corpus folder {folder}: absent");
            continue;
        }
        let mut found = Vec::new();
        model_files(&path, &mut found);
        let files: Vec<(String, String)> = found
            .iter()
            .filter_map(|f| {
                let text = std::fs::read_to_string(f).ok()?;
                scan_unit_headers(&text)?;
                Some((f.strip_prefix(&dir).unwrap().to_string_lossy().replace('\\', "/"), text))
            })
            .collect();
        let groups = compare(&files);
        eprintln!("{folder}: {} files in {groups} groups", files.len());
    }
}
