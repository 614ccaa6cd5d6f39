//! `hipop validate`: verdicts against VAL's on its samples, PDDL+ plans not
//! judged, the fixtures of each kind of defect, timelines.

use super::*;

/// The VAL Depots sample (`../shared/corpora/val-samples`), relative to the
/// workspace root, or `None` (with a visible message) when the corpus is absent.
fn depots_sample() -> Option<[&'static str; 3]> {
    const DIR: &str = "../shared/corpora/val-samples/samples/IPC/Depots/Strips";
    if !workspace_root().join(DIR).is_dir() {
        eprintln!("SKIP: ../shared/corpora is absent");
        return None;
    }
    Some([
        "../shared/corpora/val-samples/samples/IPC/Depots/Strips/Depots.pddl",
        "../shared/corpora/val-samples/samples/IPC/Depots/Strips/pfile1",
        "../shared/corpora/val-samples/samples/IPC/Depots/Strips/pfile1.plan",
    ])
}

#[test]
fn validate_agrees_with_val_on_the_depots_sample_and_its_tolerance() {
    let Some([d, p, plan]) = depots_sample() else { return };
    // Steps 0.001 apart: one happening at VAL's default tolerance 0.01.
    let o = hipop(&["validate", d, p, plan, "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("error[E0418]"), "{}", stderr(&o));
    assert!(stderr(&o).ends_with("pfile1.plan: invalid: 3 errors\n"), "{}", stderr(&o));
    let o = hipop(&["validate", d, p, plan, "-t", "0.0001"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("pfile1.plan: valid: makespan 0.004"), "{}", stderr(&o));
    // A regression suite of known-bad plans.
    let o = hipop(&["validate", d, p, plan, "--expect", "invalid"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    assert!(stderr(&o).contains("invalid (as expected)"), "{}", stderr(&o));
}

#[test]
fn validate_json_reports_each_plan_and_the_worst_status() {
    let Some([d, p, plan]) = depots_sample() else { return };
    let o = hipop(&["validate", d, p, plan, "no/such.plan", "--format", "json", "-t", "0.0001"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2, "an unreadable plan is a usage error: {}", stderr(&o));
    let doc: Value = serde_json::from_str(&stdout(&o)).expect("one JSON document");
    let verdicts: Vec<&str> =
        doc["plans"].as_array().unwrap().iter().map(|p| p["verdict"].as_str().unwrap()).collect();
    assert_eq!(verdicts, ["valid", "unreadable"]);
    assert_eq!(doc["plans"][1]["io_error"], "no/such.plan: no such file");
}

#[test]
fn validate_refuses_a_model_with_errors_and_an_unreadable_plan() {
    let o = hipop(&["validate", E0102, E0102, "tests/plans/ok/temporal.plan", "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("fix them before validating plans"), "{}", stderr(&o));
    let Some([d, p, _]) = depots_sample() else { return };
    let o = hipop(&["validate", d, p, "tests/plans/E0401-malformed-step.plan", "--color", "never"]);
    assert_eq!(status(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("not validated: the plan cannot be read"), "{}", stderr(&o));
}

/// Runs `hipop validate` on a PDDL+ model and plan, with `--expect valid`
/// and `--expect invalid`: each gets no verdict (exit 2). Returns the human
/// output of the first run.
fn validate_pddl_plus(domain: &str, problem: &str, plan: &str) -> String {
    let o = hipop(&["validate", domain, problem, plan, "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2, "{}", stderr(&o));
    let e = hipop(&["validate", domain, problem, plan, "--expect", "invalid", "--color", "never"]);
    assert_eq!(status(&e), 2, "no verdict, so not the expected one either: {}", stderr(&e));
    stderr(&o)
}

const PDDL_PLUS: &str = "tests/validate/models/pddl-plus";

#[test]
fn validate_gives_no_verdict_on_a_pddl_plus_process() {
    let d = format!("{PDDL_PLUS}-process.pddl");
    let (p, plan) =
        (format!("{PDDL_PLUS}-problem.pddl"), "tests/validate/E0421-unsupported-in-plan-process.plan");
    let err = validate_pddl_plus(&d, &p, plan);
    // The domain is only a warning for `hipop check` (W0207): the plan is
    // read, and the validator says it cannot judge it.
    assert!(err.contains("error[E0421]") && err.contains("not validated"), "{err}");
}

#[test]
fn validate_gives_no_verdict_on_a_pddl_plus_event() {
    let d = format!("{PDDL_PLUS}-event.pddl");
    let (p, plan) =
        (format!("{PDDL_PLUS}-problem.pddl"), "tests/validate/E0421-unsupported-in-plan-event.plan");
    let err = validate_pddl_plus(&d, &p, plan);
    // The domain is only a warning for `hipop check` (W0207): the plan is
    // read, and the validator says it cannot judge it.
    assert!(err.contains("error[E0421]") && err.contains("not validated"), "{err}");
}

/// `#t` without a process or an event: the model checks, the plan is read,
/// and validation says it cannot judge it (E0421), in every format.
#[test]
fn validate_gives_no_verdict_on_a_continuous_effect() {
    let d = format!("{PDDL_PLUS}-continuous.pddl");
    let (p, plan) =
        (format!("{PDDL_PLUS}-problem.pddl"), "tests/validate/E0421-unsupported-in-plan-continuous.plan");
    let err = validate_pddl_plus(&d, &p, plan);
    assert!(err.contains("error[E0421]"), "{err}");
    assert!(
        err.ends_with(&format!(
            "{plan}: not validated: it needs what the validator does not check (E0421)\n"
        )),
        "{err}"
    );
    let o = hipop(&["validate", &d, &p, plan, "--format", "json"]);
    assert_eq!(status(&o), 2, "{}", stderr(&o));
    let doc: Value = serde_json::from_str(&stdout(&o)).expect("one JSON document");
    assert_eq!(doc["plans"][0]["verdict"], "unsupported");
    assert_eq!(doc["plans"][0]["makespan"], Value::Null);
    for format in ["sarif", "github"] {
        assert_eq!(status(&hipop(&["validate", &d, &p, plan, "--format", format])), 2, "{format}");
    }
}

/// VAL's PDDL+ samples: those with processes and events, and the Tanks
/// sample (continuous effects only), are read but not judged (E0421); the
/// Drive sample, plain PDDL 2.1 in that folder, gets a verdict.
#[test]
fn validate_gives_no_verdict_on_vals_pddl_plus_samples() {
    const DIR: &str = "../shared/corpora/val-samples/samples/domainsWithEventsAndProcesses";
    if !workspace_root().join(DIR).is_dir() {
        eprintln!("SKIP: ../shared/corpora is absent");
        return;
    }
    let sample = |folder: &str, files: [&str; 3]| files.map(|f| format!("{DIR}/{folder}/{f}"));
    let refused = [
        sample("Coffee", ["coffeemaking.pddl", "coffeeproblem.pddl", "coffeeplan.txt"]),
        sample(
            "VendingMachine",
            ["vendingmachine.pddl", "vendingmachine-problem.pddl", "vendingmachineplan.txt"],
        ),
        sample(
            "Sleeping Beauty with Capacitor",
            ["sleepingbeauty.pddl", "sleepingbeauty-problem.pddl", "sleepingbeautyplan.txt"],
        ),
    ];
    for [d, p, plan] in &refused {
        let err = validate_pddl_plus(d, p, plan);
        assert!(err.contains("error[E0421]") && !err.contains("W0207"), "{plan}: {err}");
    }
    let [d, p, plan] =
        sample("Tanks and a Bucket Toricelli", ["tank-domain.pddl", "tank-problem.pddl", "tankplan.txt"]);
    let err = validate_pddl_plus(&d, &p, &plan);
    assert!(err.contains("error[E0421]") && err.contains("continuous effects (`#t`)"), "{err}");
    assert!(err.ends_with("not validated: it needs what the validator does not check (E0421)\n"), "{err}");
    let [d, p, plan] = sample("Drive", ["drivedomain.pddl", "drive-problem.pddl", "driveplan.txt"]);
    let o = hipop(&["validate", &d, &p, &plan]);
    assert_eq!(status(&o), 1, "VAL says the Drive plan is invalid at tolerance 0.01: {}", stderr(&o));
}

/// `hipop validate` on every plan of tests/validate and tests/validate-htn
/// (one defect each, or valid): the human and the JSON output, as snapshots. Each plan's header
/// names its domain, problem and tolerance (`corpus:` is ../shared/corpora).
#[test]
fn validate_output_for_each_kind_of_defect() {
    if !workspace_root().join("../shared/corpora").is_dir() {
        eprintln!("SKIP: ../shared/corpora is absent");
        return;
    }
    validate_fixtures("tests/validate", 20);
    validate_fixtures("tests/validate-htn", 20);
}

fn validate_fixtures(folder: &str, at_least: usize) {
    let dir = workspace_root().join(folder);
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".plan"))
        .collect();
    names.sort();
    assert!(names.len() >= at_least, "{names:?}");
    for name in names {
        let text = std::fs::read_to_string(dir.join(&name)).unwrap();
        let header = |key: &str| {
            text.lines().find_map(|l| l.strip_prefix(&format!("; {key}:")).map(|v| v.trim().to_string()))
        };
        let model = |v: String| match v.strip_prefix("corpus:") {
            Some(rest) => format!("../shared/corpora/{rest}"),
            None => format!("{folder}/{v}"),
        };
        let (Some(d), Some(p)) = (header("domain").map(model), header("problem").map(model)) else {
            panic!("{name}: no `; domain:` or `; problem:` header")
        };
        let tolerance = header("tolerance").unwrap_or_else(|| "0.01".into());
        let plan = format!("{folder}/{name}");
        let mut args = vec!["validate", &d, &p, &plan, "-t", &tolerance, "--color", "never"];
        if header("ignore-listed-order").is_some() {
            args.push("--ignore-listed-order");
        }
        let human = hipop(&args);
        assert_no_panic(&human);
        let expect_valid = header("expect").is_some_and(|e| e.starts_with("valid"));
        // No verdict (exit 2): a model with errors (E0422's broken domain) is
        // refused before any plan is read; a plan that needs what the
        // validator does not check (E0421: a PDDL+ domain, only a warning for
        // `hipop check`, W0207) is read but not judged.
        let not_judged = name.starts_with("E0422") || name.starts_with("E0421");
        let wanted = if not_judged {
            2
        } else if expect_valid {
            0
        } else {
            1
        };
        assert_eq!(status(&human), wanted, "{name}: {}", stderr(&human));
        insta::assert_snapshot!(format!("validate_human@{name}"), stderr(&human));
        let refused = stderr(&human).contains("fix them before validating plans");
        if !refused {
            let json = hipop(&[&args[..], &["--format", "json"][..]].concat());
            let doc: Value = serde_json::from_str(&stdout(&json)).expect("one JSON document");
            insta::assert_json_snapshot!(format!("validate_json@{name}"), doc);
        }
    }
}

const TIMELINE: [&str; 2] = ["tests/plans/timeline/domain.hddl", "tests/plans/timeline/problem.hddl"];

/// `--gantt` draws each plan after its verdict (on standard output, the
/// verdict on standard error), `--svg FILE` writes the picture.
#[test]
fn validate_gantt_and_svg() {
    let tmp = TempDir::new("timeline");
    let picture = format!("{}/plan.svg", tmp.path());
    let [d, p] = TIMELINE;
    let plan = "tests/plans/timeline/hierarchical.plan";
    let o = hipop(&["validate", d, p, plan, "--gantt", "--gantt-width", "80", "--svg", &picture]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    assert_eq!(stderr(&o), format!("{plan}: valid: makespan 32.000, value 32.000\n"));
    insta::assert_snapshot!(stdout(&o));
    // docs/plan-formats.md shows this very chart.
    let doc = std::fs::read_to_string(workspace_root().join("docs/plan-formats.md")).unwrap();
    let chart = stdout(&o).trim_start().strip_prefix(&format!("{plan}\n")).unwrap().to_string();
    assert!(doc.contains(&chart), "docs/plan-formats.md, Timelines: update the example to\n{chart}");
    let svg = std::fs::read_to_string(&picture).expect("the picture is written");
    assert!(svg.starts_with("<?xml") && svg.trim_end().ends_with("</svg>"), "{svg}");
    assert!(svg.contains("(communicate r1 r2 hill lake)"), "{svg}");

    // ASCII, several plans (an invalid one is drawn too), each under its path.
    let seq = "tests/plans/timeline/sequential.plan";
    let o = hipop(&["validate", d, p, seq, plan, "--gantt=ascii", "--gantt-width", "70", "--color", "never"]);
    assert_eq!(status(&o), 1, "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.is_ascii(), "{out}");
    assert!(out.starts_with(&format!("\n{seq}\nstep")), "{out}");
    assert!(out.contains(&format!("\n{plan}\ntime")), "{out}");
}

#[test]
fn validate_timeline_flags_refuse_what_they_cannot_do() {
    let [d, p] = TIMELINE;
    let plan = "tests/plans/timeline/temporal.plan";
    let o = hipop(&["validate", d, p, plan, "--format", "json", "--gantt"]);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("`--gantt` draws for people"), "{}", stderr(&o));
    assert_eq!(stdout(&o), "");
    let o = hipop(&["validate", d, p, plan, plan, "--svg", "never-written.svg"]);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("`--svg FILE` draws one plan, and 2 are given"), "{}", stderr(&o));
    assert!(!workspace_root().join("never-written.svg").exists());
    let o = hipop(&["validate", d, p, plan, "--svg", "no/such/folder/plan.svg"]);
    assert_eq!(status(&o), 2, "a picture that cannot be written");
    assert!(stderr(&o).contains("cannot write the SVG picture"), "{}", stderr(&o));
    // A plan that cannot be read is not drawn.
    let o =
        hipop(&["validate", d, p, "tests/plans/E0401-malformed-step.plan", "--gantt", "--color", "never"]);
    assert_eq!(status(&o), 2);
    assert!(
        stderr(&o).contains("E0401-malformed-step.plan: not drawn: the plan cannot be read"),
        "{}",
        stderr(&o)
    );
    assert_eq!(stdout(&o), "");
    // The flags are explained.
    let help = stdout(&hipop(&["validate", "--help"]));
    assert!(help.contains("--gantt[=<STYLE>]") && help.contains("--svg <FILE>"), "{help}");
}
