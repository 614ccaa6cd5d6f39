//! Plans (docs/plan-formats.md): every plan of the corpora is read without
//! error, each plan diagnostic has a fixture in `tests/plans/` whose
//! diagnostics are snapshotted, `hipop diff` is snapshotted on fixture
//! pairs, and the reader never panics, whatever the input.

use std::path::{Path, PathBuf};

use hipop_analyzer::plan::agents::AgentTable;
use hipop_analyzer::plan::diff::{DiffOptions, PlanDiff, diff};
use hipop_analyzer::plan::{NameMatching, Plan, PlanFormat, detect_format, read_plan};
use hipop_analyzer::{AnalysisHost, Severity, TextRange, codes};
use proptest::prelude::*;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn corpora() -> Option<PathBuf> {
    let dir = std::env::var_os("HIPOP_CORPORA")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace().join("../shared/corpora"));
    dir.is_dir().then_some(dir)
}

/// The plan files of a folder: files named like a plan (`*.plan`,
/// `*plan*.txt`, …; not the verdicts `*.val` and `*.panda`, not domains and
/// problems, pictures or documents), and any file with a `==>` line.
fn plan_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            plan_files(&p, out);
            continue;
        }
        let name = p.file_name().unwrap().to_string_lossy().to_ascii_lowercase();
        let ext = p.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
        let text = std::fs::read_to_string(&p).unwrap_or_default();
        let marked = text.lines().any(|l| l.trim() == "==>");
        let named = name.contains("plan")
            && !matches!(ext.as_str(), "val" | "panda" | "pddl" | "hddl" | "pdf" | "png" | "md");
        if marked || named {
            out.push(p);
        }
    }
}

/// One line per diagnostic: `CODE severity line:col-line:col message`.
fn render(text: &str, plan: &Plan) -> String {
    let line_col = |offset: usize| {
        let before = &text[..offset.min(text.len())];
        let line = before.matches('\n').count() + 1;
        let start = before.rfind('\n').map_or(0, |i| i + 1);
        (line, before[start..].chars().count() + 1)
    };
    let span = |r: TextRange| {
        let (l1, c1) = line_col(usize::from(r.start()));
        let (l2, c2) = line_col(usize::from(r.end()));
        format!("{l1}:{c1}-{l2}:{c2}")
    };
    let mut out = String::new();
    for d in &plan.diagnostics {
        out.push_str(&format!("{} {} {} {}\n", d.code.id, d.code.severity.as_str(), span(d.span), d.message));
        let covered = &text[usize::from(d.span.start())..usize::from(d.span.end())];
        out.push_str(&format!("  text: `{covered}`\n"));
        for (r, m) in &d.related {
            out.push_str(&format!("  related: {} {m}\n", span(*r)));
        }
    }
    if out.is_empty() {
        out.push_str("(no diagnostics)\n");
    }
    out
}

/// A short description of what was read, for the snapshots.
fn summary(plan: &Plan) -> String {
    let mut out = format!("format: {}\n", plan.format.as_str());
    for s in &plan.steps {
        let id = s.id.map_or(String::new(), |i| format!("{} ", i.value));
        let time = s.start.as_ref().map_or(String::new(), |n| format!("@{} ", n.text));
        let dur = s.duration.as_ref().map_or(String::new(), |n| format!(" [{}]", n.text));
        let dec = s.decomposition.as_ref().map_or(String::new(), |d| {
            let subs: Vec<String> = d.subtasks.iter().map(|i| i.value.to_string()).collect();
            format!(" -> {} {}", d.method.text, subs.join(" "))
        });
        out.push_str(&format!("  {id}{time}{}{dur}{dec}\n", s.call()));
    }
    if let Some(r) = &plan.root {
        let ids: Vec<String> = r.ids.iter().map(|i| i.value.to_string()).collect();
        out.push_str(&format!("  root {}\n", ids.join(" ")));
    }
    if let Some(p) = &plan.problem {
        let name = |s: &Option<hipop_analyzer::plan::Symbol>| {
            s.as_ref().map_or("-".to_string(), |s| s.text.to_string())
        };
        out.push_str(&format!("  problem {} {} {}\n", name(&p.domain), name(&p.problem), name(&p.hash)));
    }
    for l in &plan.causal_links {
        out.push_str(&format!("  causal link {:?} -> {:?}: {}\n", l.from, l.to, l.literal.predicate.text));
    }
    for l in &plan.temporal_links {
        out.push_str(&format!("  temporal link {:?} -> {:?}: [{:?}, {:?}]\n", l.from, l.to, l.min, l.max));
    }
    out
}

#[test]
fn corpus_plans_read_without_errors() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP corpus plan test: ../shared/corpora is absent (set HIPOP_CORPORA to its path)");
        return;
    };
    let mut files = Vec::new();
    plan_files(&dir, &mut files);
    assert!(files.len() >= 90, "expected the corpus's plans, found {}", files.len());
    let mut failures = Vec::new();
    let mut warnings = Vec::new();
    let (mut val, mut hier) = (0, 0);
    for f in &files {
        let rel = f.strip_prefix(&dir).unwrap().to_string_lossy().replace('\\', "/");
        let text = std::fs::read_to_string(f).unwrap();
        let plan = read_plan(&text, None);
        let marked = text.lines().any(|l| l.trim() == "==>");
        let expected = if marked { PlanFormat::Hierarchical } else { PlanFormat::Val };
        if plan.format != expected {
            failures.push(format!("{rel}: read as {:?}, expected {expected:?}", plan.format));
        }
        match plan.format {
            PlanFormat::Val => val += 1,
            _ => hier += 1,
        }
        if plan.steps.is_empty() {
            failures.push(format!("{rel}: no step read"));
        }
        for d in &plan.diagnostics {
            let line = text[..usize::from(d.span.start())].matches('\n').count() + 1;
            let shown = format!("{rel}:{line}: {} {}", d.code.id, d.message);
            if d.code.severity == Severity::Error {
                failures.push(shown);
            } else {
                warnings.push(shown);
            }
        }
    }
    eprintln!(
        "corpus plans: {} files, {val} VAL, {hier} hierarchical, {} warnings",
        files.len(),
        warnings.len()
    );
    assert!(failures.is_empty(), "{} errors in real plans:\n{}", failures.len(), failures.join("\n"));
    insta::assert_snapshot!("corpus_plan_warnings", warnings.join("\n"));
}

/// The fixtures of the plan diagnostics: `tests/plans/<CODE>-<name>.<ext>`.
fn fixtures_dir() -> PathBuf {
    workspace().join("tests/plans")
}

#[test]
fn plan_fixtures() {
    insta::glob!("../../tests/plans", "[EW]04[0-9][0-9]-*", |path| {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(path).unwrap();
        let plan = read_plan(&text, None);
        let id = &name[..5];
        let code = codes::ALL.iter().find(|c| c.id == id).unwrap_or_else(|| panic!("{name}: no code {id}"));
        let stem = name.split('.').next().unwrap();
        assert_eq!(
            stem,
            format!("{}-{}", code.id, code.name),
            "fixture `{name}` is named `<code>-<name>.<ext>`"
        );
        let rendered = format!("{}\n{}", render(&text, &plan), summary(&plan));
        insta::assert_snapshot!(rendered);
        assert!(plan.diagnostics.iter().any(|d| d.code.id == id), "{name} does not report {id}:\n{rendered}");
        assert!(
            plan.diagnostics.iter().all(|d| d.code.id == id),
            "{name} reports other codes than {id}:\n{rendered}"
        );
    });
}

/// Every plan-syntax code (E0401–E0409, W0401–W0409) has a fixture in `tests/plans/`.
#[test]
fn every_plan_code_has_a_fixture() {
    let names: Vec<String> = std::fs::read_dir(fixtures_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let missing: Vec<String> = codes::ALL
        .iter()
        .filter(|c| &c.id[1..4] == "040")
        .map(|c| format!("{}-{}", c.id, c.name))
        .filter(|stem| !names.iter().any(|n| n.split('.').next() == Some(stem.as_str())))
        .collect();
    assert!(missing.is_empty(), "plan codes without a fixture in tests/plans: {missing:?}");
}

/// Clean plans of every format, read without any diagnostic.
#[test]
fn clean_plans() {
    insta::glob!("../../tests/plans", "ok/*", |path| {
        let text = std::fs::read_to_string(path).unwrap();
        let plan = read_plan(&text, None);
        let rendered = format!("{}\n{}", render(&text, &plan), summary(&plan));
        assert!(plan.diagnostics.is_empty(), "{}:\n{rendered}", path.display());
        insta::assert_snapshot!(rendered);
    });
}

/// More malformed plans, several mistakes each: what is reported, and what is still read.
#[test]
fn malformed_plans() {
    insta::glob!("../../tests/plans", "malformed/*", |path| {
        let text = std::fs::read_to_string(path).unwrap();
        let plan = read_plan(&text, None);
        assert!(!plan.diagnostics.is_empty(), "{} reads without a diagnostic", path.display());
        insta::assert_snapshot!(format!("{}\n{}", render(&text, &plan), summary(&plan)));
    });
}

/// Renders a diff as the snapshots show it: every change, per agent, and the figures.
fn render_diff(a: &Plan, b: &Plan, d: &PlanDiff) -> String {
    let step = |p: &Plan, i: usize| {
        let s = &p.steps[i];
        let time = s.start.as_ref().map_or(String::new(), |n| format!("{}: ", n.text));
        let dur = s.duration.as_ref().map_or(String::new(), |n| format!(" [{}]", n.text));
        format!("{time}{}{dur}", s.call())
    };
    let mut out = String::new();
    for &x in &d.removed {
        out.push_str(&format!("- {}\n", step(a, x)));
    }
    for &y in &d.added {
        out.push_str(&format!("+ {}\n", step(b, y)));
    }
    for &(x, y) in &d.retimed {
        out.push_str(&format!("~ {} => {}\n", step(a, x), step(b, y)));
    }
    for &x in &d.abstract_removed {
        out.push_str(&format!("- abstract {}\n", a.steps[x].call()));
    }
    for &y in &d.abstract_added {
        out.push_str(&format!("+ abstract {}\n", b.steps[y].call()));
    }
    for &(x, y) in &d.method_changes {
        let m = |p: &Plan, i: usize| p.steps[i].decomposition.as_ref().unwrap().method.text.to_string();
        out.push_str(&format!("method {}: {} => {}\n", b.steps[y].call(), m(a, x), m(b, y)));
    }
    for r in &d.per_agent {
        out.push_str(&format!(
            "agent {}: unchanged {}, removed {}, added {}, retimed {}, methods {}\n",
            r.agent.as_deref().unwrap_or("(unknown agent)"),
            r.unchanged,
            r.removed,
            r.added,
            r.retimed,
            r.method_changes
        ));
    }
    out.push_str(&format!(
        "instability {}, distance {}, same: {}\n",
        d.instability,
        d.distance,
        d.is_empty()
    ));
    out
}

/// `tests/plans/diff/<case>/`: `a.*` and `b.*`, and an optional `domain.*`
/// whose `:agent` declarations group the changes.
#[test]
fn diff_fixtures() {
    let mut dirs: Vec<PathBuf> =
        std::fs::read_dir(fixtures_dir().join("diff")).unwrap().map(|e| e.unwrap().path()).collect();
    dirs.sort();
    assert!(dirs.len() >= 4, "tests/plans/diff has the diff fixtures");
    for dir in &dirs {
        let case = dir.file_name().unwrap().to_string_lossy().into_owned();
        let mut a = None;
        let mut b = None;
        let mut domain = None;
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if !p.is_file() {
                continue;
            }
            let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&p).unwrap();
            match stem.as_str() {
                "a" => a = Some(text),
                "b" => b = Some(text),
                "domain" => domain = Some(text),
                _ => {}
            }
        }
        let (Some(a), Some(b)) = (a, b) else { panic!("{}: expected a.* and b.*", dir.display()) };
        let (a, b) = (read_plan(&a, None), read_plan(&b, None));
        assert!(!a.has_errors() && !b.has_errors(), "{}: fixture plans must read cleanly", dir.display());
        let mut host = AnalysisHost::new();
        let table = match domain {
            Some(text) => {
                let f = host.set_file_text("domain.pddl", text);
                host.analysis().plan_agents(f, NameMatching::CaseInsensitive).unwrap()
            }
            None => AgentTable::default(),
        };
        let d = diff(&a, &b, &table, &DiffOptions::default());
        insta::assert_snapshot!(format!("diff@{case}"), render_diff(&a, &b, &d));
        // Comparing a plan with itself finds nothing.
        let same = diff(&a, &a, &table, &DiffOptions::default());
        assert!(same.is_empty() && same.instability == 0 && same.distance == 0);
    }
}

/// The salsa query and the host API agree with the pure reader.
#[test]
fn host_reads_plans() {
    let mut host = AnalysisHost::new();
    let text = "==>\n0 move r1 a b\nroot 1\n1 go r1 b -> m 0\n<==\n;@ 0 0.0 [2.5]\n";
    let f = host.set_file_text("p.plan", text);
    let analysis = host.analysis();
    let plan = analysis.plan(f, None).unwrap();
    assert_eq!(plan, read_plan(text, None));
    assert_eq!(plan.format, PlanFormat::Hierarchical);
    assert_eq!(plan.steps[0].start.as_ref().unwrap().text, "0.0");
    assert!(analysis.plan_diagnostics(f, None).unwrap().is_empty());
    // Forcing another format reads the same text otherwise.
    let forced = analysis.plan(f, Some(PlanFormat::Val)).unwrap();
    assert_eq!(forced.format, PlanFormat::Val);
    assert!(forced.has_errors() || forced.diagnostics.iter().any(|d| d.code.id == "W0401"));
}

fn seeds() -> Vec<String> {
    let mut texts = vec![
        "0.000: (move r1 a b) [30.980]\n30.990: (observe r1 b p1) [5.000] ; done\n".to_string(),
        "(move r1 a b)\n(observe r1 b p1)\n".to_string(),
        "log\n==>\n0 move r1 a b\n1 observe r1 b p1\nroot 2\n2 patrol r1 -> m-patrol 0 1\n<==\n;@ 0 0 [1]\n"
            .to_string(),
    ];
    for dir in [fixtures_dir(), fixtures_dir().join("ok")] {
        if let Ok(entries) = std::fs::read_dir(dir) {
            texts.extend(entries.filter_map(|e| std::fs::read_to_string(e.ok()?.path()).ok()));
        }
    }
    texts
}

const PIECES: &[&str] = &[
    "(",
    ")",
    "[",
    "]",
    ":",
    " ",
    "\n",
    "\r\n",
    ";",
    ";@",
    "==>",
    "<==",
    "root",
    "->",
    "0",
    "1.5",
    "-",
    "é",
    "{",
    "}",
    "\"",
    ",",
    "\"steps\"",
    "\"id\"",
    "null",
    "1e999",
];

fn mutate(text: &str, ops: &[(u16, u8, bool)]) -> String {
    let mut t = text.to_string();
    for &(pos, piece, delete) in ops {
        let mut at = usize::from(pos) % (t.len() + 1);
        while !t.is_char_boundary(at) {
            at -= 1;
        }
        if delete {
            let mut end = (at + 1 + usize::from(piece) % 8).min(t.len());
            while !t.is_char_boundary(end) {
                end += 1;
            }
            t.replace_range(at..end, "");
        } else {
            t.insert_str(at, PIECES[usize::from(piece) % PIECES.len()]);
        }
    }
    t
}

fn read_every_way(text: &str) {
    for format in [None, Some(PlanFormat::Val), Some(PlanFormat::Hierarchical), Some(PlanFormat::Json)] {
        let plan = read_plan(text, format);
        for d in &plan.diagnostics {
            assert!(usize::from(d.span.end()) <= text.len(), "a diagnostic past the end");
            assert!(text.is_char_boundary(usize::from(d.span.start())));
            assert!(text.is_char_boundary(usize::from(d.span.end())));
        }
        for s in &plan.steps {
            assert!(usize::from(s.range.end()) <= text.len());
        }
        let d = diff(&plan, &read_plan(text, None), &AgentTable::default(), &DiffOptions::default());
        assert!(d.instability >= d.distance);
    }
    let _ = detect_format(text);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        read_every_way(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn mutated_plans_never_panic(
        seed in any::<prop::sample::Index>(),
        ops in proptest::collection::vec((any::<u16>(), any::<u8>(), any::<bool>()), 1..12),
    ) {
        let seeds = seeds();
        let text = mutate(seed.get::<String>(&seeds), &ops);
        read_every_way(&text);
    }
}

/// A plan file of the workspace is read as a plan (not as PDDL), is not a
/// domain or problem of the workspace, and is matched with its problem by
/// name: the problem file whose name is the longest prefix of the plan's.
#[test]
fn plan_files_in_the_workspace_are_plans_of_the_problem_their_name_starts_with() {
    use hipop_analyzer::plan::plan_problem;
    let mut host = hipop_analyzer::AnalysisHost::new();
    let domain = "(define (domain d) (:predicates (p)) (:action a :parameters () :effect (p)))";
    host.set_file_text("/w/domain.pddl", domain);
    host.set_file_text("/w/p01.pddl", "(define (problem p01) (:domain d) (:init) (:goal (p)))");
    host.set_file_text("/w/p0.pddl", "(define (problem p0) (:domain d) (:init) (:goal (p)))");
    let plan = host.set_file_text("/w/p01.aries.plan", "0: (a) [1]\n1: (a b c\n");
    let lone = host.set_file_text("/elsewhere/x.plan", "(a)\n");
    let db = host.db();
    let unit = plan_problem(db, plan).expect("a problem");
    assert_eq!(unit.name(db).as_deref(), Some("p01"));
    assert_eq!(plan_problem(db, lone), None);
    let codes: Vec<&str> =
        host.analysis().diagnostics(plan).unwrap().iter().map(|d| d.code.id).collect::<Vec<_>>();
    assert_eq!(codes, ["E0401"], "read as a plan, not as PDDL");
}
