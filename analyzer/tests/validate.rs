//! Plan validation (`hipop_analyzer::validate`) on real material:
//!
//! - every reference plan of `../shared/corpora/reference-plans/ipc2002-temporal`
//!   (each with VAL's verdict beside it, run with `-t 0.001`) gets VAL's verdict
//!   with the tolerance 0.001;
//! - VAL's own Depots sample is invalid at VAL's default tolerance 0.01 and
//!   valid at 0.0001, as VAL's `scripts/validate_testcases.txt` runs it;
//! - VAL's PDDL+ samples get a clear "unsupported" error, never a verdict;
//! - the hand-written plans of `tests/validate/` (valid ones, and invalid ones
//!   with one defect each) get their expected verdict and codes, and their
//!   diagnostics are snapshots (`; expect:` headers, see its README).
//!
//! Plans are read by a tiny reader of VAL's plan lines kept here: the real
//! plan reader lives elsewhere; these tests are about validation.
//! Tests that need the corpora skip, saying so, when they are absent.

use std::path::{Path, PathBuf};

use hipop_analyzer::db::file_units;
use hipop_analyzer::validate::{Options, TimedStep, validate_temporal};
use hipop_analyzer::{AnalysisHost, Diagnostic, Severity, SourceFile, TextRange, codes};

fn corpora() -> Option<PathBuf> {
    let dir = std::env::var_os("HIPOP_CORPORA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpora"));
    dir.is_dir().then_some(dir)
}

fn range(a: usize, b: usize) -> TextRange {
    TextRange::new((a as u32).into(), (b as u32).into())
}

/// Reads VAL plan lines: `[time:] (name args…) [[duration]]`, `;` comments;
/// lines without `(` (planner trailers) are skipped.
fn read_val_plan(text: &str) -> Vec<TimedStep> {
    let mut steps = Vec::new();
    let mut offset = 0;
    for (number, line) in text.split_inclusive('\n').enumerate() {
        let base = offset;
        offset += line.len();
        let body = line.split(';').next().unwrap_or("").trim_end();
        let Some(open) = body.find('(') else { continue };
        let close = open + body[open..].find(')').expect("a step closes its parenthesis");
        let head = body[..open].trim();
        let (time, time_span) = if head.is_empty() {
            (None, None)
        } else {
            let num = head.trim_end_matches(':').trim();
            let at = base + body.find(num).expect("the time is in the line");
            (Some(num.parse::<f64>().expect("a time")), Some(range(at, at + num.len())))
        };
        let mut words: Vec<(String, TextRange)> = Vec::new();
        let inner = &body[open + 1..close];
        let mut i = 0;
        for w in inner.split_whitespace() {
            let at = i + inner[i..].find(w).expect("the word is in the list");
            words.push((w.to_string(), range(base + open + 1 + at, base + open + 1 + at + w.len())));
            i = at + w.len();
        }
        let rest = &body[close + 1..];
        let (duration, duration_span) = match (rest.find('['), rest.find(']')) {
            (Some(l), Some(r)) => {
                let d = rest[l + 1..r].trim().parse::<f64>().expect("a duration");
                (Some(d), Some(range(base + close + 1 + l, base + close + 1 + r + 1)))
            }
            _ => (None, None),
        };
        let first = body.len() - body.trim_start().len();
        let (name, name_span) = words.first().cloned().expect("a step names an action");
        steps.push(TimedStep {
            name,
            args: words[1..].iter().map(|w| w.0.clone()).collect(),
            time,
            duration,
            span: range(base + first, base + body.len()),
            name_span,
            arg_spans: words[1..].iter().map(|w| w.1).collect(),
            time_span,
            duration_span,
            id: None,
            line: number + 1,
        });
    }
    steps
}

/// What a validation gave, owned (the report borrows the database).
struct Outcome {
    valid: bool,
    /// The code that stopped validation before a verdict (E0421, E0422).
    not_judged: Option<&'static str>,
    value: Option<f64>,
    diagnostics: Vec<Diagnostic>,
    /// (name, text, file) of each file, to render diagnostics.
    files: Vec<(String, String, SourceFile)>,
}

/// Validates `plan` against a problem and its domain, given as (name, text).
fn validate(domain: (&str, &str), problem: (&str, &str), plan: (&str, &str), options: &Options) -> Outcome {
    let mut host = AnalysisHost::new();
    let d = host.set_file_text(&format!("m/{}", domain.0), domain.1);
    let p = host.set_file_text(&format!("m/{}", problem.0), problem.1);
    let f = host.set_file_text(&format!("m/{}", plan.0), plan.1);
    let steps = read_val_plan(plan.1);
    let db = host.db();
    let unit = *file_units(db, p).first().expect("the problem has a define");
    let report = validate_temporal(db, unit, &steps, options);
    Outcome {
        valid: report.valid,
        not_judged: report.not_judged().map(|c| c.id),
        value: report.value,
        diagnostics: report.to_diagnostics(db, f),
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
    let col = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
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
        "verdict: {}\nvalue: {}\n",
        match (o.valid, o.not_judged) {
            (_, Some(code)) => format!("none, not validated ({code})"),
            (true, None) => "valid".into(),
            (false, None) => "invalid".into(),
        },
        o.value.map_or("none".to_string(), |v| format!("{v}"))
    );
    for d in &o.diagnostics {
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

fn errors(o: &Outcome) -> Vec<String> {
    o.diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| format!("{} {}", d.code.id, d.message))
        .collect()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn reference_plans_agree_with_val() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP reference plans: ../shared/corpora is absent (set HIPOP_CORPORA to its path)");
        return;
    };
    let refs = dir.join("reference-plans/ipc2002-temporal");
    let mut variants: Vec<PathBuf> = std::fs::read_dir(&refs).unwrap().map(|e| e.unwrap().path()).collect();
    variants.sort();
    let options = Options { tolerance: 0.001, ..Options::default() };
    let (mut checked, mut skipped, mut disagree) = (0, 0, Vec::new());
    for variant in variants {
        let name = variant.file_name().unwrap().to_string_lossy().into_owned();
        let models = dir.join("ipc2002-temporal").join(&name);
        let mut plans: Vec<PathBuf> = std::fs::read_dir(&variant)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "plan"))
            .collect();
        plans.sort();
        for plan in plans {
            let file = plan.file_name().unwrap().to_string_lossy().into_owned();
            let instance = file.split('.').next().unwrap();
            let problem = models.join("instances").join(format!("{instance}.pddl"));
            if !problem.is_file() {
                eprintln!("SKIP {name}/{file}: the corpus has no {name}/instances/{instance}.pddl");
                skipped += 1;
                continue;
            }
            let val = read(&plan.with_extension("plan.val"));
            let expected = val.contains("Plan valid");
            let o = validate(
                ("domain.pddl", &read(&models.join("domain.pddl"))),
                ("problem.pddl", &read(&problem)),
                ("plan.plan", &read(&plan)),
                &options,
            );
            checked += 1;
            if o.valid != expected {
                disagree.push(format!(
                    "{name}/{file}: VAL says {expected}, hipop {}:\n{}",
                    o.valid,
                    render(&o)
                ));
            }
            // VAL's value ("Final value: 34.1") agrees too.
            if let Some(line) = val.lines().find(|l| l.starts_with("Final value:")) {
                let v: f64 = line["Final value:".len()..].trim().parse().unwrap();
                let got = o.value.unwrap_or(f64::NAN);
                if (got - v).abs() > 1e-3 * v.abs().max(1.0) {
                    disagree.push(format!("{name}/{file}: VAL's value is {v}, hipop's {got}"));
                }
            }
            // No warning either: these plans are separated by at least the tolerance.
            assert!(o.diagnostics.is_empty(), "{name}/{file}:\n{}", render(&o));
        }
    }
    eprintln!("reference plans: {checked} checked, {skipped} skipped, {} disagreements", disagree.len());
    assert!(disagree.is_empty(), "{}", disagree.join("\n"));
    assert!(checked >= 30, "expected the reference plans, checked {checked}");
}

#[test]
fn val_depots_sample_depends_on_the_tolerance() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP VAL's Depots sample: ../shared/corpora is absent");
        return;
    };
    let base = dir.join("val-samples/samples/IPC/Depots/Strips");
    let (d, p, plan) =
        (read(&base.join("Depots.pddl")), read(&base.join("pfile1")), read(&base.join("pfile1.plan")));
    let run = |tolerance| {
        validate(
            ("Depots.pddl", &d),
            ("pfile1", &p),
            ("pfile1.plan", &plan),
            &Options { tolerance, ..Options::default() },
        )
    };
    let strict = run(0.01);
    assert!(!strict.valid, "{}", render(&strict));
    assert!(errors(&strict).iter().all(|e| e.starts_with("E0418")), "{}", render(&strict));
    insta::assert_snapshot!("val_depots_tolerance_0.01", render(&strict));
    let fine = run(0.0001);
    assert!(fine.valid && fine.diagnostics.is_empty(), "{}", render(&fine));
    // Steps 0.001 apart are two happenings at 0.001 (VAL groups events
    // within tolerance/10); interfering ones get the warning.
    let middle = run(0.001);
    assert!(middle.valid, "{}", render(&middle));
    assert!(middle.diagnostics.iter().all(|d| d.code.id == codes::CLOSE_HAPPENINGS.id));
    // The test list of VAL names the sample.
    let list = read(&dir.join("val-samples/scripts/validate_testcases.txt"));
    assert!(list.contains("Depots.pddl,pfile1,pfile1.plan"));
}

#[test]
fn pddl_plus_samples_are_unsupported_not_judged() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP VAL's PDDL+ samples: ../shared/corpora is absent");
        return;
    };
    let list = read(&dir.join("val-samples/scripts/validate_testcases.txt"));
    let (mut unsupported, mut judged) = (0, 0);
    for line in list.lines().filter(|l| l.contains("domainsWithEventsAndProcesses")) {
        let fields: Vec<&str> = line.split(',').collect();
        let folder = dir.join("val-samples/scripts").join(fields[3]);
        let (d, p, plan) = (folder.join(fields[0]), folder.join(fields[1]), folder.join(fields[2]));
        if !(d.is_file() && p.is_file() && plan.is_file()) {
            eprintln!("SKIP {line}: a file is missing");
            continue;
        }
        let o = validate(
            ("domain.pddl", &read(&d)),
            ("problem.pddl", &read(&p)),
            ("plan.plan", &read(&plan)),
            &Options::default(),
        );
        if errors(&o).iter().any(|e| e.starts_with("E0421")) {
            // Processes, events, `#t`: one clear error, no verdict on the rest.
            assert_eq!(errors(&o).len(), 1, "{line}:\n{}", render(&o));
            assert_eq!(o.not_judged, Some("E0421"), "{line}: no verdict");
            unsupported += 1;
        } else {
            // A sample of that folder that is plain PDDL 2.1 (Drive) is judged.
            insta::assert_snapshot!(format!("val_sample_{}", fields[2]), render(&o));
            judged += 1;
        }
    }
    eprintln!("VAL's PDDL+ samples: {unsupported} unsupported, {judged} judged");
    assert!(unsupported >= 4, "expected VAL's PDDL+ samples, found {unsupported}");
}

/// The `; key: value` header lines of a fixture.
fn header<'t>(text: &'t str, key: &str) -> Option<&'t str> {
    text.lines()
        .take_while(|l| l.starts_with(';'))
        .find_map(|l| l.trim_start_matches(';').trim().strip_prefix(key))
        .map(|v| v.trim_start_matches(':').trim())
}

fn fixtures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/validate")
}

/// A model file named in a fixture's header: `corpus:<path>` in the corpora,
/// or a path relative to `tests/validate/`. `None` when the corpora are absent.
fn model_file(spec: &str) -> Option<(String, String)> {
    let path = match spec.strip_prefix("corpus:") {
        Some(rest) => corpora()?.join(rest),
        None => fixtures_dir().join(spec),
    };
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    Some((name, read(&path)))
}

fn check_fixture(path: &Path) {
    let text = read(path);
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    assert!(text.starts_with(';'), "{name} must start with `;` comments saying what it is");
    let get = |key| header(&text, key).unwrap_or_else(|| panic!("{name} has no `; {key}:` header"));
    let (Some(domain), Some(problem)) = (model_file(get("domain")), model_file(get("problem"))) else {
        eprintln!("SKIP {name}: ../shared/corpora is absent");
        return;
    };
    let tolerance = header(&text, "tolerance").map_or(0.01, |t| t.parse().expect("a tolerance"));
    let options = Options {
        tolerance,
        lenient: header(&text, "lenient").is_some(),
        keep_going: false,
        ignore_listed_order: false,
    };
    let o = validate((&domain.0, &domain.1), (&problem.0, &problem.1), (&name, &text), &options);
    let rendered = render(&o);
    insta::assert_snapshot!(rendered);
    let expect: Vec<&str> = get("expect").split_whitespace().collect();
    let codes_seen: Vec<&str> = o.diagnostics.iter().map(|d| d.code.id).collect();
    match expect.split_first() {
        Some((&"valid", rest)) => {
            assert!(o.valid, "{name} should be valid:\n{rendered}");
            assert_eq!(codes_seen, rest, "{name}: unexpected warnings:\n{rendered}");
        }
        Some((&"invalid", rest)) => {
            assert!(!o.valid, "{name} should be invalid:\n{rendered}");
            let mut want = rest.to_vec();
            want.sort_unstable();
            let mut seen = codes_seen.clone();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen, want, "{name}: expected exactly the codes {rest:?}:\n{rendered}");
        }
        _ => panic!("{name}: `; expect:` is `valid [CODES]` or `invalid CODES`"),
    }
    // E0421 and E0422 leave a plan without a verdict; no other code does.
    assert_eq!(
        o.not_judged.is_some(),
        codes_seen.iter().any(|&c| c == "E0421" || c == "E0422"),
        "{name}: a plan is not judged exactly when it needs what is not checked:\n{rendered}"
    );
    // A fixture named after a code reports it.
    let code = name.split('-').next().unwrap_or_default();
    if code.len() == 5 && code[1..].chars().all(|c| c.is_ascii_digit()) {
        assert!(codes_seen.contains(&code), "{name} does not report {code}:\n{rendered}");
    }
}

#[test]
fn hand_written_plans() {
    insta::glob!("../../tests/validate", "*.plan", check_fixture);
}

/// Every plan-validation code of this validator (E0410–E0429, W0410–W0429)
/// has a fixture in `tests/validate/` named after it.
#[test]
fn every_validation_code_has_a_fixture() {
    let names: Vec<String> = std::fs::read_dir(fixtures_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let missing: Vec<String> = codes::ALL
        .iter()
        .filter(|c| (410..430).contains(&c.id[1..].parse::<u32>().unwrap_or(0)))
        .map(|c| format!("{}-{}", c.id, c.name))
        .filter(|stem| !names.iter().any(|n| n.starts_with(stem.as_str())))
        .collect();
    assert!(missing.is_empty(), "validation codes without a fixture in tests/validate: {missing:?}");
}

#[test]
fn the_reader_of_these_tests_keeps_spans() {
    let text = "; a comment\n0.000: (lift h0 c1 p0 d0) [1.000] ; trailing\n(drive t0 a b)\n";
    let steps = read_val_plan(text);
    assert_eq!(steps.len(), 2);
    let s = &steps[0];
    let at = |r: TextRange| &text[usize::from(r.start())..usize::from(r.end())];
    assert_eq!(
        (at(s.span), at(s.name_span), at(s.arg_spans[3])),
        ("0.000: (lift h0 c1 p0 d0) [1.000]", "lift", "d0")
    );
    assert_eq!((at(s.time_span.unwrap()), at(s.duration_span.unwrap())), ("0.000", "[1.000]"));
    assert_eq!((steps[1].time, steps[1].duration, at(steps[1].span)), (None, None, "(drive t0 a b)"));
    assert_eq!((steps[0].line, steps[1].line), (2, 3));
}

/// A plan of 10,000 steps (the valid Depots plan, then truck0 driving back
/// and forth) validates, and says how long it took.
#[test]
fn ten_thousand_steps() {
    let Some(dir) = corpora() else {
        eprintln!("SKIP 10,000 steps: ../shared/corpora is absent");
        return;
    };
    let models = dir.join("ipc2002-temporal/depots-time-simple-automatic");
    let base = read(&fixtures_dir().join("valid-depots-time-simple-1.plan"));
    let mut plan = base.clone();
    let mut t = 28.05;
    for k in 0..(10_000 - read_val_plan(&base).len()) {
        let (from, to) =
            if k % 2 == 0 { ("distributor1", "distributor0") } else { ("distributor0", "distributor1") };
        plan.push_str(&format!("{t:.3}: (drive truck0 {from} {to}) [10.000]\n"));
        t += 10.01;
    }
    assert_eq!(read_val_plan(&plan).len(), 10_000);
    let started = std::time::Instant::now();
    let o = validate(
        ("domain.pddl", &read(&models.join("domain.pddl"))),
        ("problem.pddl", &read(&models.join("instances/instance-1.pddl"))),
        ("plan.plan", &plan),
        &Options::default(),
    );
    eprintln!("10,000 steps validated in {:?} (with parsing and checking the model)", started.elapsed());
    assert!(o.valid, "{}", render(&o));
}
