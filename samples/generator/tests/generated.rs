//! The generated Survivors files, checked with hipop's own analyzer: every
//! problem is free of errors and warnings, and its witness plans (VAL's
//! format and the timed hierarchical format) are valid, which proves that it
//! can be solved with its allowed actions.

use std::path::Path;

use hipop_analyzer::validate::Options;
use hipop_analyzer::{AnalysisHost, Diagnostic, Severity};
use hipop_samplegen::survivors::Params;
use hipop_samplegen::{DEFAULT_SEED, survivors, survivors_problem};

/// The errors and warnings among `diags`, printed.
fn problems(host: &AnalysisHost, diags: &[Diagnostic]) -> Vec<String> {
    let analysis = host.analysis();
    diags
        .iter()
        .filter(|d| d.severity != Severity::Info)
        .map(|d| {
            let path = analysis.file_path(d.file).unwrap();
            format!("{path}: {} {}", d.code.id, d.message)
        })
        .collect()
}

#[test]
fn every_survivors_problem_is_clean_and_its_witness_plans_are_valid() {
    let domain = survivors::domain::domain();
    let options = Options::default();
    let mut failures = Vec::new();
    let grid = Params::grid();
    assert_eq!(grid.len(), 72);
    for params in grid {
        let files = survivors_problem(params, DEFAULT_SEED, true);
        let mut host = AnalysisHost::new();
        let d = host.set_file_text("/survivors/domain.pddl", domain.clone());
        let [(pname, ptext), (vname, vtext), (hname, htext)] = &files[..] else { panic!("three files") };
        let p = host.set_file_text(&format!("/survivors/{pname}"), ptext.clone());
        let v = host.set_file_text(&format!("/survivors/{vname}"), vtext.clone());
        let h = host.set_file_text(&format!("/survivors/{hname}"), htext.clone());
        let analysis = host.analysis();
        let mut diags = analysis.diagnostics(p).unwrap();
        diags.extend(analysis.diagnostics(d).unwrap());
        failures.extend(problems(&host, &diags));
        for (plan, name) in [(v, vname), (h, hname)] {
            let validation = analysis.validate_plan(plan, None, p, &options).unwrap().expect("a problem");
            if !(validation.valid && validation.checked) {
                failures.push(format!("{name}: invalid"));
            }
            failures.extend(problems(&host, &validation.diagnostics));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The test above would notice a broken plan or a lint: the same checks on
/// damaged copies fail.
#[test]
fn the_checks_notice_broken_witnesses_and_lints() {
    let params = Params { teams: 2, rows: 2, side: 3, survivors: 2 };
    let files = survivors_problem(params, DEFAULT_SEED, true);
    let [(_, ptext), (_, vtext), (_, htext)] = &files[..] else { panic!("three files") };
    let mut host = AnalysisHost::new();
    host.set_file_text("/s/domain.pddl", survivors::domain::domain());
    // explore allowed on its own: the planner could build a patrol's plan twice (W0312).
    let lax = ptext.replace("(:allowed-actions move", "(:allowed-actions explore move");
    let p = host.set_file_text("/s/p.pddl", lax);
    let diags = host.analysis().diagnostics(p).unwrap();
    assert!(diags.iter().any(|d| d.code.id == "W0312"), "{:#?}", problems(&host, &diags));
    let p = host.set_file_text("/s/p.pddl", ptext.clone());
    // The VAL plan without its last step (a rescue): a goal is not reached.
    let cut = &vtext[..vtext.trim_end().rfind('\n').unwrap()];
    let v = host.set_file_text("/s/p.plan", cut.to_string());
    // A patrol refined by the other method with the same subtasks.
    let other = if htext.contains("-by-rows ") {
        ("-by-rows ", "-by-columns ")
    } else {
        ("-by-columns ", "-by-rows ")
    };
    let h = host.set_file_text("/s/p.hier.plan", htext.replacen(other.0, other.1, 1));
    let analysis = host.analysis();
    for plan in [v, h] {
        let validation = analysis.validate_plan(plan, None, p, &Options::default()).unwrap().unwrap();
        assert!(!validation.valid);
    }
}

#[test]
fn survivors_files_are_deterministic_and_named_by_their_parameters() {
    let a = survivors(DEFAULT_SEED, true);
    assert_eq!(a, survivors(DEFAULT_SEED, true));
    assert_eq!(a.len(), 1 + 72 * 3);
    assert_ne!(a[1].1, survivors(7, false)[1].1, "the seed places the survivors");
    let names: std::collections::BTreeSet<&str> = a.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names.len(), a.len());
    for name in ["domain.pddl", "p-t2-r2-z4-s2.pddl", "p-t3-r4-z16-s5.pddl", "p-t2-r3-z9-s4.hier.plan"] {
        assert!(names.contains(name), "{name}");
    }
}

#[test]
fn survivors_samples_are_up_to_date() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../survivors");
    let files = survivors(DEFAULT_SEED, false);
    let mut compared = 0;
    for entry in std::fs::read_dir(&dir).expect("samples/survivors") {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !name.ends_with(".pddl") {
            continue;
        }
        let (_, text) =
            files.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("{name} is not generated"));
        let committed = std::fs::read_to_string(&path).unwrap();
        assert!(committed == *text, "samples/survivors/{name} is stale: regenerate it (see its README)");
        compared += 1;
    }
    assert!(compared >= 4, "the domain and 3 problems are committed");
}
