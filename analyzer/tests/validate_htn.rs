//! Hierarchical plan validation (`hipop_analyzer::validate::hierarchy`):
//!
//! - every IPC 2020 hierarchical reference plan of
//!   `../shared/corpora/reference-plans/ipc2020-hddl` (each with
//!   pandaPIparser's verdict beside it) gets pandaPIparser's verdict: its
//!   hierarchy validates clean, and its primitive steps execute (the
//!   temporal validator, which a hierarchical plan's actions go through);
//! - pandaPIparser's own test plans: the valid ones are clean, the `-wrong`
//!   and `-non-existing-method` ones are rejected with the right code;
//! - the hand-written plans of `tests/validate-htn/` (one defect each) get
//!   their expected verdict and codes, and their diagnostics are snapshots.
//!
//! Tests that need the corpora skip, saying so, when they are absent.

use std::path::{Path, PathBuf};

use hipop_analyzer::db::{UnitKind, file_units};
use hipop_analyzer::plan::{NameMatching, read_plan};
use hipop_analyzer::validate::hierarchy::{HierarchyOptions, HierarchyReport, validate_hierarchy};
use hipop_analyzer::validate::{Options, timed_steps, validate_temporal};
use hipop_analyzer::{AnalysisHost, Diagnostic, Severity, SourceFile, TextRange, codes};

fn corpora() -> Option<PathBuf> {
    let dir = std::env::var_os("HIPOP_CORPORA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora"));
    dir.is_dir().then_some(dir)
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// What a validation gave, owned (diagnostics name files of the host).
struct Outcome {
    /// The hierarchy's verdict.
    report: HierarchyReport,
    /// The primitive steps executed by the temporal validator: its verdict
    /// and diagnostics.
    executable: bool,
    execution: Vec<Diagnostic>,
    /// The plan reader's diagnostics.
    reading: Vec<Diagnostic>,
    files: Vec<(String, String, SourceFile)>,
}

impl Outcome {
    fn valid(&self) -> bool {
        self.report.valid && self.executable
    }

    fn all(&self) -> impl Iterator<Item = &Diagnostic> {
        self.reading.iter().chain(&self.report.diagnostics).chain(&self.execution)
    }
}

/// Validates a plan for a problem and its domain, each given as (name, text).
fn validate(
    domain: (&str, &str),
    problem: (&str, &str),
    plan: (&str, &str),
    options: &HierarchyOptions,
) -> Outcome {
    let mut host = AnalysisHost::new();
    let d = host.set_file_text(&format!("m/{}", domain.0), domain.1);
    let p = host.set_file_text(&format!("m/{}", problem.0), problem.1);
    let f = host.set_file_text(&format!("m/{}", plan.0), plan.1);
    let db = host.db();
    let unit = *file_units(db, p)
        .iter()
        .find(|u| u.kind(db) == UnitKind::Problem)
        .expect("the problem file has a problem");
    let read = read_plan(plan.1, None);
    let report = validate_hierarchy(
        db,
        unit,
        &read,
        f,
        &HierarchyOptions { check_primitive_steps: false, ..*options },
    );
    let temporal = Options { lenient: options.matching == NameMatching::Lenient, ..Options::default() };
    let exec = validate_temporal(db, unit, &timed_steps(&read, plan.1), &temporal);
    Outcome {
        report,
        executable: exec.valid,
        execution: exec.to_diagnostics(db, f),
        reading: read.file_diagnostics(f),
        files: vec![
            (domain.0.to_string(), domain.1.to_string(), d),
            (problem.0.to_string(), problem.1.to_string(), p),
            (plan.0.to_string(), plan.1.to_string(), f),
        ],
    }
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before[before.rfind('\n').map_or(0, |i| i + 1)..].chars().count() + 1;
    (line, col)
}

fn render(o: &Outcome) -> String {
    let at = |file: SourceFile, r: TextRange| {
        let (name, text, _) = o.files.iter().find(|(_, _, f)| *f == file).expect("a known file");
        let (l1, c1) = line_col(text, usize::from(r.start()));
        let (l2, c2) = line_col(text, usize::from(r.end()));
        format!("{name} {l1}:{c1}-{l2}:{c2}")
    };
    let mut out = format!(
        "verdict: {} (hierarchy {}, execution {}; method preconditions {})\n",
        if o.valid() { "valid" } else { "invalid" },
        if o.report.valid { "valid" } else { "invalid" },
        if o.executable { "valid" } else { "invalid" },
        if o.report.preconditions_checked { "checked" } else { "not checked" },
    );
    for d in o.all() {
        out.push_str(&format!(
            "\n{} {} {}\n  {}\n",
            d.code.id,
            d.severity.as_str(),
            at(d.file, d.range),
            d.message
        ));
        for r in &d.related {
            out.push_str(&format!("  related {}: {}\n", at(r.file, r.range), r.message));
        }
        if let Some(fix) = &d.fix {
            out.push_str(&format!("  help: {}\n", fix.message));
            for (file, r, text) in &fix.edits {
                out.push_str(&format!("  edit {}: {text:?}\n", at(*file, *r)));
            }
        }
    }
    out
}

fn lenient() -> HierarchyOptions {
    HierarchyOptions { matching: NameMatching::Lenient, ..HierarchyOptions::default() }
}

/// The domain of a problem of the IPC 2020 corpus: `domain.hddl` beside it,
/// or `<problem>-domain.hddl` (PCP has one domain per problem).
fn domain_of(problem: &Path) -> Option<PathBuf> {
    let stem = problem.file_stem()?.to_string_lossy().into_owned();
    let dir = problem.parent()?;
    [dir.join(format!("{stem}-domain.hddl")), dir.join("domain.hddl")].into_iter().find(|p| p.is_file())
}

#[test]
fn reference_plans_agree_with_pandapiparser() {
    let Some(dir) = corpora() else {
        eprintln!(
            "SKIP hierarchical reference plans: ../shared/corpora is absent (set HIPOP_CORPORA to its path)"
        );
        return;
    };
    let refs = dir.join("reference-plans/ipc2020-hddl");
    let mut plans = Vec::new();
    for order in ["partial-order", "total-order"] {
        let Ok(domains) = std::fs::read_dir(refs.join(order)) else { continue };
        for d in domains {
            let d = d.unwrap().path();
            for f in std::fs::read_dir(&d).unwrap() {
                let f = f.unwrap().path();
                if f.extension().is_some_and(|e| e == "plan") {
                    plans.push(f);
                }
            }
        }
    }
    plans.sort();
    let (mut checked, mut skipped, mut disagree) = (0, 0, Vec::new());
    for plan in &plans {
        let rel = plan.strip_prefix(&refs).unwrap();
        let folder = rel.parent().unwrap();
        let file = plan.file_name().unwrap().to_string_lossy().into_owned();
        let instance = file.split(".aries").next().unwrap();
        let problem = dir.join("ipc2020-hddl").join(folder).join(format!("{instance}.hddl"));
        let Some(domain) = problem.is_file().then(|| domain_of(&problem)).flatten() else {
            eprintln!(
                "SKIP {}: the corpus has no ipc2020-hddl/{}/{instance}.hddl and its domain",
                rel.display(),
                folder.display()
            );
            skipped += 1;
            continue;
        };
        let verdict = read(&plan.with_extension("plan.panda"));
        let expected = verdict.contains("Plan verification result: true");
        let o = validate(
            ("domain.hddl", &read(&domain)),
            ("problem.hddl", &read(&problem)),
            (&file, &read(plan)),
            &lenient(),
        );
        checked += 1;
        if o.valid() != expected || o.all().any(|d| d.severity == Severity::Error) {
            disagree.push(format!("{}: pandaPIparser says {expected}:\n{}", rel.display(), render(&o)));
        }
        assert!(
            o.report.preconditions_checked,
            "{}: method preconditions not checked:\n{}",
            rel.display(),
            render(&o)
        );
        // Every decomposition matched its method (pandaPIparser's `__top` aside).
        let parsed = read_plan(&read(plan), None);
        let top = parsed.abstract_steps().filter(|(_, s)| s.name.text == "__top").count();
        assert_eq!(
            o.report.methods.len() + top,
            parsed.abstract_steps().count(),
            "{}: not every decomposition matched:\n{}",
            rel.display(),
            render(&o)
        );
        // No warning either: nothing in these domains is out of the validator's reach.
        assert!(o.report.diagnostics.is_empty(), "{}:\n{}", rel.display(), render(&o));
    }
    eprintln!(
        "hierarchical reference plans: {checked} checked, {skipped} skipped (no domain in the corpus), {} disagreements",
        disagree.len()
    );
    assert!(disagree.is_empty(), "{}", disagree.join("\n"));
    assert!(checked >= 20, "expected the reference plans, checked {checked}");
}

/// pandaPIparser's test plans, with the model each was written for.
#[test]
fn pandapiparser_test_plans() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP pandaPIparser's test plans: ../shared/corpora is absent");
        return;
    };
    let tests = dir.join("pandaPIparser-tests/tests");
    let po = dir.join("ipc2020-hddl/partial-order");
    let to = dir.join("ipc2020-hddl/total-order");
    // (plan, domain, problem, expected codes: empty for a valid plan)
    let cases: Vec<(&str, PathBuf, PathBuf, &[&str])> = vec![
        ("empty.plan", tests.join("empty-d.hddl"), tests.join("empty-p.hddl"), &[]),
        (
            "plan-for-transport-pfile01.txt",
            po.join("Transport/domain.hddl"),
            po.join("Transport/pfile01.hddl"),
            &[],
        ),
        (
            "plan-for-transport-pfile01-notop.txt",
            po.join("Transport/domain.hddl"),
            po.join("Transport/pfile01.hddl"),
            &[],
        ),
        // Its primitive steps are listed `… 5 7 6`: in that order (the order of
        // execution, and pandaPIparser's `primitive_plan`, read line by line),
        // step 7 drops the package at city_loc_2 before step 6 drives there,
        // against the ordering of `m_deliver_ordering_0`.
        (
            "plan-for-transport-pfile01-total-order.txt",
            to.join("Transport/domain.hddl"),
            to.join("Transport/pfile01.hddl"),
            &["E0439", "E0415"],
        ),
        (
            "plan-for-transport-pfile01-wrong.txt",
            po.join("Transport/domain.hddl"),
            po.join("Transport/pfile01.hddl"),
            &["E0438"],
        ),
        (
            "plan-for-transport-pfile01-non-existing-method.txt",
            po.join("Transport/domain.hddl"),
            po.join("Transport/pfile01.hddl"),
            &["E0432"],
        ),
    ];
    // PANDA's raw plans, which pandaPIparser's converter (`-c`) translates back
    // into verifiable plans (compressed method names `<…;…>`, compiled tasks
    // `__MakeMethodSubTasksUniqueCompilation…`, method-precondition actions):
    // hipop does not undo PANDA's compilations; they are rejected, by name.
    let converter_inputs = [
        ("rover01.plan", po.join("Rover/domain.hddl"), po.join("Rover/pfile01.hddl")),
        (
            "woodworking-00.plan",
            po.join("Woodworking/domain.hddl"),
            po.join("Woodworking/00--p01-variant.hddl"),
        ),
    ];
    for (plan, domain, problem) in converter_inputs {
        let path = tests.join(plan);
        if !(path.is_file() && domain.is_file() && problem.is_file()) {
            eprintln!("SKIP {plan}: a file is missing");
            continue;
        }
        let o = validate(
            ("domain.hddl", &read(&domain)),
            ("problem.hddl", &read(&problem)),
            (plan, &read(&path)),
            &lenient(),
        );
        assert!(!o.valid(), "{plan}:\n{}", render(&o));
        assert!(
            o.all().any(|d| d.code.id == "E0430"),
            "{plan}: PANDA's compiled tasks are named:\n{}",
            render(&o)
        );
    }
    for (plan, domain, problem, expected) in cases {
        let path = tests.join(plan);
        if !(path.is_file() && domain.is_file() && problem.is_file()) {
            eprintln!("SKIP {plan}: a file is missing");
            continue;
        }
        let o = validate(
            ("domain.hddl", &read(&domain)),
            ("problem.hddl", &read(&problem)),
            (plan, &read(&path)),
            &lenient(),
        );
        let rendered = render(&o);
        let mut seen: Vec<&str> =
            o.all().filter(|d| d.severity == Severity::Error).map(|d| d.code.id).collect();
        seen.dedup();
        assert_eq!(seen, expected, "{plan}:\n{rendered}");
        assert_eq!(o.valid(), expected.is_empty(), "{plan}:\n{rendered}");
        if !expected.is_empty() {
            insta::assert_snapshot!(format!("pandapiparser@{plan}"), rendered);
        }
    }
}

/// The `; key: value` header lines of a fixture.
fn header<'t>(text: &'t str, key: &str) -> Option<&'t str> {
    text.lines()
        .take_while(|l| l.starts_with(';'))
        .find_map(|l| l.trim_start_matches(';').trim().strip_prefix(key))
        .map(|v| v.trim_start_matches(':').trim())
}

fn fixtures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/validate-htn")
}

fn check_fixture(path: &Path) {
    let text = read(path);
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    assert!(text.starts_with(';'), "{name} must start with `;` comments saying what it is");
    let get = |key| header(&text, key).unwrap_or_else(|| panic!("{name} has no `; {key}:` header"));
    let model = |spec: &str| {
        let p = fixtures_dir().join(spec);
        (p.file_name().unwrap().to_string_lossy().into_owned(), read(&p))
    };
    let (domain, problem) = (model(get("domain")), model(get("problem")));
    let mut options = HierarchyOptions::default();
    if header(&text, "lenient").is_some() {
        options.matching = NameMatching::Lenient;
    }
    if header(&text, "ignore-listed-order").is_some() {
        options.listed_order = false;
    }
    let o = validate((&domain.0, &domain.1), (&problem.0, &problem.1), (&name, &text), &options);
    let rendered = render(&o);
    insta::assert_snapshot!(rendered);
    let expect: Vec<&str> = get("expect").split_whitespace().collect();
    let codes_seen: Vec<&str> = o.all().map(|d| d.code.id).collect();
    match expect.split_first() {
        Some((&"valid", rest)) => {
            assert!(o.valid(), "{name} should be valid:\n{rendered}");
            assert_eq!(codes_seen, rest, "{name}: unexpected warnings:\n{rendered}");
        }
        Some((&"invalid", rest)) => {
            assert!(!o.valid(), "{name} should be invalid:\n{rendered}");
            let mut want = rest.to_vec();
            want.sort_unstable();
            let mut seen = codes_seen.clone();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen, want, "{name}: expected exactly the codes {rest:?}:\n{rendered}");
        }
        _ => panic!("{name}: `; expect:` is `valid [CODES]` or `invalid CODES`"),
    }
    let code = name.split('-').next().unwrap_or_default();
    if code.len() == 5 && code[1..].chars().all(|c| c.is_ascii_digit()) {
        assert!(codes_seen.contains(&code), "{name} does not report {code}:\n{rendered}");
    }
}

#[test]
fn fixture() {
    insta::glob!("../../tests/validate-htn", "*.plan", check_fixture);
}

/// Every hierarchical-validation code (E0430–E0449, W0430–W0449) has a
/// fixture in `tests/validate-htn/` named after it.
#[test]
fn every_hierarchy_code_has_a_fixture() {
    let names: Vec<String> = std::fs::read_dir(fixtures_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let missing: Vec<String> = codes::ALL
        .iter()
        .filter(|c| (430..450).contains(&c.id[1..].parse::<u32>().unwrap_or(0)))
        .map(|c| format!("{}-{}", c.id, c.name))
        .filter(|stem| !names.iter().any(|n| n.starts_with(stem.as_str())))
        .collect();
    assert!(missing.is_empty(), "hierarchy codes without a fixture in tests/validate-htn: {missing:?}");
}

/// The models of the fixtures, by name.
fn model(name: &str) -> (String, String) {
    (name.to_string(), read(&fixtures_dir().join("models").join(name)))
}

/// Primitive steps are checked when asked (the validator used alone), and
/// left to the temporal validator otherwise: one mistake, one diagnostic.
#[test]
fn primitive_steps_are_checked_when_asked() {
    let (d, p) = (model("transport.hddl"), model("transport-1.hddl"));
    let plan = read(&fixtures_dir().join("valid-transport.plan"))
        .replace("0 drive truck depot b", "0 drve truck depot b");
    let mut host = AnalysisHost::new();
    host.set_file_text("m/transport.hddl", d.1);
    let pf = host.set_file_text("m/transport-1.hddl", p.1);
    let f = host.set_file_text("m/p.plan", plan.clone());
    let db = host.db();
    let unit = file_units(db, pf)[0];
    let read = read_plan(&plan, None);
    let alone = validate_hierarchy(db, unit, &read, f, &HierarchyOptions::default());
    let ids: Vec<&str> = alone.diagnostics.iter().map(|d| d.code.id).collect();
    assert_eq!(ids, ["E0410"], "{:?}", alone.diagnostics);
    assert!(alone.diagnostics[0].fix.as_ref().is_some_and(|f| f.message.contains("`drive`")));
    // The step's parent does not match without it, silently; preconditions are not evaluated.
    assert!(!alone.valid && !alone.preconditions_checked);
    let with_temporal = validate_hierarchy(
        db,
        unit,
        &read,
        f,
        &HierarchyOptions { check_primitive_steps: false, ..Default::default() },
    );
    assert!(with_temporal.diagnostics.is_empty(), "{:?}", with_temporal.diagnostics);
}

/// A plan of 10,000 steps (2,500 surveys of 4 steps) validates quickly.
#[test]
fn ten_thousand_steps() {
    let (d, p) = (model("survey.hddl"), model("survey-1.hddl"));
    let n = 2500;
    let mut plan = String::from("==>\n");
    for k in 0..n {
        let b = 3 * k;
        plan.push_str(&format!(
            "{b} move r1 base hill\n{} look r1 hill\n{} move r1 hill base\n",
            b + 1,
            b + 2
        ));
    }
    let roots: Vec<String> = (0..n).map(|k| (3 * n + k).to_string()).collect();
    plan.push_str(&format!("root {}\n", roots.join(" ")));
    for k in 0..n {
        let b = 3 * k;
        plan.push_str(&format!(
            "{} survey r1 base hill -> survey-there-and-back {b} {} {}\n",
            3 * n + k,
            b + 1,
            b + 2
        ));
    }
    plan.push_str("<==\n");
    let mut host = AnalysisHost::new();
    host.set_file_text("m/survey.hddl", d.1);
    let pf = host.set_file_text("m/survey-1.hddl", p.1);
    let f = host.set_file_text("m/p.plan", plan.clone());
    let db = host.db();
    let unit = file_units(db, pf)[0];
    let parsed = read_plan(&plan, None);
    assert_eq!(parsed.steps.len(), 4 * n);
    // Warm the model's queries, then time the validation alone.
    let _ = validate_hierarchy(db, unit, &read_plan("==>\n<==\n", None), f, &HierarchyOptions::default());
    let start = std::time::Instant::now();
    let report = validate_hierarchy(db, unit, &parsed, f, &HierarchyOptions::default());
    let took = start.elapsed();
    eprintln!("hierarchy of a plan of {} steps validated in {took:?}", 4 * n);
    assert!(report.valid && report.diagnostics.is_empty() && report.preconditions_checked);
    assert_eq!(report.methods.len(), n);
    assert!(took.as_secs_f64() < 10.0, "{took:?}");
}

const PIECES: &[&str] = &[
    " ",
    "\n",
    "->",
    "root ",
    "0",
    "1",
    "9",
    "12",
    "42",
    "deliver",
    "get-to",
    "m-drive",
    "m-here",
    "m-deliver",
    "m-drive-via",
    "truck",
    "depot",
    "p1",
    "c",
    "__top",
    "__top_method",
    ";@ 1 5.0 [1]\n",
    "<==\n",
    "==>\n",
];

fn mutate(text: &str, ops: &[(u16, u8, bool)]) -> String {
    let mut t = text.to_string();
    for &(pos, piece, delete) in ops {
        let mut at = usize::from(pos) % (t.len() + 1);
        while !t.is_char_boundary(at) {
            at -= 1;
        }
        if delete {
            let mut end = (at + 1 + usize::from(piece) % 6).min(t.len());
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

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 256, ..Default::default() })]

    /// Mangled plans never make the validator panic, and its ranges are in the plan.
    #[test]
    fn mangled_plans_never_panic(
        which in 0usize..3,
        ops in proptest::collection::vec((proptest::prelude::any::<u16>(), proptest::prelude::any::<u8>(), proptest::prelude::any::<bool>()), 1..10),
    ) {
        let (base, d, p) = match which {
            0 => ("valid-transport.plan", "transport.hddl", "transport-1.hddl"),
            1 => ("E0439-ordering-violated.plan", "transport.hddl", "transport-1.hddl"),
            _ => ("valid-survey-timed.plan", "survey.hddl", "survey-1.hddl"),
        };
        let text = mutate(&read(&fixtures_dir().join(base)), &ops);
        let (d, p) = (model(d), model(p));
        let mut host = AnalysisHost::new();
        host.set_file_text("m/d.hddl", d.1);
        let pf = host.set_file_text("m/p.hddl", p.1);
        let f = host.set_file_text("m/x.plan", text.clone());
        let db = host.db();
        let unit = file_units(db, pf)[0];
        for listed_order in [true, false] {
            let options = HierarchyOptions { listed_order, matching: NameMatching::Lenient, ..Default::default() };
            let report = validate_hierarchy(db, unit, &read_plan(&text, None), f, &options);
            for d in report.diagnostics.iter().filter(|d| d.file == f) {
                proptest::prop_assert!(usize::from(d.range.end()) <= text.len());
            }
        }
    }
}

/// A JSON plan with methods is validated like the same plan in the IPC 2020 form.
#[test]
fn json_plans_are_validated_too() {
    let (d, p) = (model("survey.hddl"), model("survey-1.hddl"));
    let json = r#"{"format": "hipop-plan", "version": 1, "steps": [
        {"id": 0, "name": "move", "args": ["r1", "base", "hill"], "start": 0.0, "duration": 10.0},
        {"id": 1, "name": "look", "args": ["r1", "hill"], "start": 10.01, "duration": 5.0},
        {"id": 2, "name": "move", "args": ["r1", "hill", "base"], "start": 15.02, "duration": 10.0},
        {"id": 3, "name": "send", "args": ["r1", "hill", "base"], "start": 25.03, "duration": 2.0},
        {"id": 4, "name": "survey", "args": ["r1", "base", "hill"], "method": "survey-there-and-back",
         "subtasks": [0, 2, 1], "start": 0.0, "duration": 25.02}],
      "root": [4, 3]}"#;
    let o = validate((&d.0, &d.1), (&p.0, &p.1), ("plan.json", json), &HierarchyOptions::default());
    // The subtasks are listed out of the method's order: the same diagnostic as in the IPC 2020 form.
    let ids: Vec<&str> = o.all().map(|d| d.code.id).collect();
    assert_eq!(ids, ["E0438"], "{}", render(&o));
    let fixed = json.replace("[0, 2, 1]", "[0, 1, 2]");
    let o = validate((&d.0, &d.1), (&p.0, &p.1), ("plan.json", &fixed), &HierarchyOptions::default());
    assert!(o.valid() && o.all().next().is_none(), "{}", render(&o));
    assert_eq!(o.report.methods.len(), 1);
    assert_eq!(o.report.methods[0].method, "survey-there-and-back");
    assert_eq!(o.report.methods[0].subtasks, [0, 1, 2]);
}

/// A variable that only a method's precondition mentions may take any value
/// that makes the precondition true (pandaPIparser's semantics).
#[test]
fn precondition_variables_without_value_are_existential() {
    let (d, p) = (model("transport.hddl"), model("transport-1.hddl"));
    let plan = read(&fixtures_dir().join("valid-transport.plan"));
    let with = |pre: &str| {
        d.1.replace(
            ":parameters (?v - vehicle ?from ?to - location)\n    :task (get-to ?v ?to)\n    :precondition (and (at ?v ?from) (not (= ?from ?to)))",
            &format!(":parameters (?v - vehicle ?from ?to ?x - location)\n    :task (get-to ?v ?to)\n    :precondition {pre}"),
        )
    };
    // Some place has a road to where the truck is.
    let some = with("(and (at ?v ?from) (road ?x ?from))");
    assert_ne!(some, d.1, "the test edits `m-drive`");
    let o = validate((&d.0, &some), (&p.0, &p.1), ("p.plan", &plan), &HierarchyOptions::default());
    assert!(o.valid() && o.all().next().is_none(), "{}", render(&o));
    // No place has a road to itself: false whatever `?x` is.
    let none = with("(and (at ?v ?from) (road ?x ?x))");
    let o = validate((&d.0, &none), (&p.0, &p.1), ("p.plan", &plan), &HierarchyOptions::default());
    let ids: Vec<&str> = o.all().map(|d| d.code.id).collect();
    assert!(!o.valid() && ids.iter().all(|c| *c == "E0444") && ids.len() == 4, "{}", render(&o));
    assert!(o.report.diagnostics[0].message.contains("no value of ?x makes it true"), "{}", render(&o));
}

/// The plans of the IPC 2020 feature tests (empty methods, a primitive root,
/// `forall`, `sortof`) are valid.
#[test]
fn ipc2020_feature_test_plans() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP the IPC 2020 feature tests: ../shared/corpora is absent");
        return;
    };
    let tests = dir.join("ipc2020-hddl/tests/ipc2020-feature-tests");
    let Ok(entries) = std::fs::read_dir(tests.join("plans")) else {
        eprintln!("SKIP the IPC 2020 feature tests: no plans folder");
        return;
    };
    let mut plans: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
    plans.sort();
    let mut checked = 0;
    for plan in plans {
        // `plans/sortof.hddl` is a plan too.
        let name = plan.file_stem().unwrap().to_string_lossy().into_owned();
        let (domain, problem) =
            (tests.join(format!("{name}-domain.hddl")), tests.join(format!("{name}.hddl")));
        if !(domain.is_file() && problem.is_file()) {
            eprintln!("SKIP feature test {name}: no model");
            continue;
        }
        let o = validate(
            ("domain.hddl", &read(&domain)),
            ("problem.hddl", &read(&problem)),
            ("plan.plan", &read(&plan)),
            &HierarchyOptions::default(),
        );
        assert!(o.valid() && o.all().next().is_none(), "{name}:\n{}", render(&o));
        checked += 1;
    }
    eprintln!("IPC 2020 feature test plans: {checked} valid");
    assert!(checked >= 3, "expected the feature tests' plans, checked {checked}");
}
