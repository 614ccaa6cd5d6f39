//! The generated Survivors and Satellite files, checked with hipop's own
//! analyzer: every Survivors problem is free of errors and warnings, and its
//! witness plans (VAL's format and the timed hierarchical format) are valid,
//! which proves that it can be solved with its allowed actions; the
//! Satellite variant is free of errors and warnings on the corpus problems.

use std::path::Path;

use hipop_analyzer::validate::Options;
use hipop_analyzer::{AnalysisHost, Diagnostic, Severity};
use hipop_samplegen::survivors::Params;
use hipop_samplegen::{
    DEFAULT_SEED, satellite, survivors, survivors_problem, survivors_repair, survivors_repair_problem,
};

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
    let compared = compare_with_committed("survivors", &survivors(DEFAULT_SEED, false));
    assert!(compared >= 4, "the domain and 3 problems are committed");
}

/// The survivors-repair set (section 5.2 of the paper): every initial
/// problem and every event's problem is free of errors and warnings in the
/// repair set's domain.
#[test]
fn every_survivors_repair_problem_is_clean() {
    let domain = survivors::domain::repair_domain();
    let mut failures = Vec::new();
    let mut host = AnalysisHost::new();
    let d = host.set_file_text("/survivors-repair/domain.pddl", domain);
    failures.extend(problems(&host, &host.analysis().diagnostics(d).unwrap()));
    for params in Params::grid() {
        let files = survivors_repair_problem(params, DEFAULT_SEED);
        assert_eq!(files.len(), 4);
        let ids: Vec<_> = files
            .iter()
            .map(|(name, text)| host.set_file_text(&format!("/survivors-repair/{name}"), text.clone()))
            .collect();
        let analysis = host.analysis();
        for p in ids {
            failures.extend(problems(&host, &analysis.diagnostics(p).unwrap()));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The test above notices a problem whose evacuations have no instance: a
/// survivor reported where it is not cannot be evacuated, so its goal is
/// out of reach (E0313).
#[test]
fn the_repair_checks_notice_an_unreachable_survivor() {
    let params = Params { teams: 2, rows: 2, side: 2, survivors: 2 };
    let files = survivors_repair_problem(params, DEFAULT_SEED);
    let mut host = AnalysisHost::new();
    host.set_file_text("/s/domain.pddl", survivors::domain::repair_domain());
    let (_, text) = &files[0];
    let fact = |s: &str| {
        let at = text.find(&format!("(reported {s} ")).unwrap();
        text[at..at + text[at..].find(')').unwrap() + 1].to_string()
    };
    let wrong = fact("s2").replace("s2", "s1");
    let p = host.set_file_text("/s/p.pddl", text.replace(&fact("s1"), &wrong));
    let diags = host.analysis().diagnostics(p).unwrap();
    assert!(diags.iter().any(|d| d.code.id == "E0313"), "{:#?}", problems(&host, &diags));
}

#[test]
fn survivors_repair_files_are_deterministic_and_named_by_their_event() {
    let a = survivors_repair(DEFAULT_SEED);
    assert_eq!(a, survivors_repair(DEFAULT_SEED));
    assert_eq!(a.len(), 1 + 72 * 4);
    let names: std::collections::BTreeSet<&str> = a.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names.len(), a.len());
    for name in [
        "domain.pddl",
        "p-t2-r2-z4-s2.pddl",
        "p-t2-r2-z4-s2-startingPos.pddl",
        "p-t2-r2-z4-s2-newSurvivor.pddl",
        "p-t3-r4-z16-s5-survivorPos.pddl",
    ] {
        assert!(names.contains(name), "{name}");
    }
    let b = survivors_repair(7);
    assert_eq!(a[0], b[0], "one domain for every seed");
    assert_ne!(a[2].1, b[2].1, "the seed draws the events");
}

#[test]
fn survivors_repair_samples_are_up_to_date() {
    let compared = compare_with_committed("survivors/repair", &survivors_repair(DEFAULT_SEED));
    assert!(compared >= 5, "the domain and one problem with its 3 events are committed");
}

/// The surveillance mission with a robot out of service is clean.
#[test]
fn the_lost_robot_problem_is_clean() {
    let (domain, _) = hipop_samplegen::surveillance(DEFAULT_SEED);
    let (robot, at) = hipop_samplegen::LOST_ROBOT;
    let lost = hipop_samplegen::surveillance_lost(DEFAULT_SEED, robot, at).unwrap();
    let mut host = AnalysisHost::new();
    let d = host.set_file_text("/surveillance/domain.pddl", domain);
    let p = host.set_file_text("/surveillance/problem-lost.pddl", lost);
    let analysis = host.analysis();
    let mut diags = analysis.diagnostics(p).unwrap();
    diags.extend(analysis.diagnostics(d).unwrap());
    let failures = problems(&host, &diags);
    assert!(failures.is_empty(), "{failures:#?}");
}

const CORPUS: &str = "../../../shared/corpora/ipc2002-temporal";

/// The generated Satellite files of a corpus folder, or `None` when the
/// corpus is not on this machine.
fn satellite_files(folder: &str) -> Option<Vec<(String, String)>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(CORPUS).join(folder);
    if !dir.is_dir() {
        eprintln!("{} not found: skipping", dir.display());
        return None;
    }
    Some(satellite::satellite_abstract(&dir).unwrap())
}

#[test]
fn satellite_abstract_is_clean_on_the_corpus() {
    let Some(files) = satellite_files("satellite-time-simple-automatic") else { return };
    assert_eq!(files.len(), 21);
    let mut host = AnalysisHost::new();
    let ids: Vec<_> = files
        .iter()
        .map(|(name, text)| host.set_file_text(&format!("/satellite/{name}"), text.clone()))
        .collect();
    let analysis = host.analysis();
    let mut diags = Vec::new();
    for &f in ids.iter().skip(1) {
        diags.extend(analysis.diagnostics(f).unwrap());
    }
    diags.extend(analysis.diagnostics(ids[0]).unwrap());
    let failures = problems(&host, &diags);
    assert!(failures.is_empty(), "{failures:#?}");
    for (name, text) in &files[1..] {
        assert!(text.contains(&format!("(:allowed-actions {})", satellite::ALLOWED)), "{name}");
    }
}

/// A timed hierarchical plan of instance 1, written by hand, that uses both
/// abstract actions and three of their methods: the abstract actions'
/// conditions, effects and durations agree with their methods.
const SATELLITE_PLAN_1: &str = "\
==>
0 switch_on instrument0 satellite0
1 turn_to satellite0 GroundStation2 Phenomenon6
2 calibrate satellite0 instrument0 GroundStation2
3 take_image satellite0 GroundStation2 instrument0 thermograph0
4 turn_to satellite0 Phenomenon4 GroundStation2
5 take_image satellite0 Phenomenon4 instrument0 thermograph0
6 turn_to satellite0 Star5 Phenomenon4
7 take_image satellite0 Star5 instrument0 thermograph0
8 turn_to satellite0 Phenomenon6 Star5
9 take_image satellite0 Phenomenon6 instrument0 thermograph0
root 0 10 11 12 13 14
10 calibrate_instrument satellite0 instrument0 GroundStation2 Phenomenon6 -> calibrate_instrument_turning 1 2
11 get_image satellite0 GroundStation2 instrument0 thermograph0 GroundStation2 -> get_image_in_place 3
12 get_image satellite0 Phenomenon4 instrument0 thermograph0 GroundStation2 -> get_image_turning 4 5
13 get_image satellite0 Star5 instrument0 thermograph0 Phenomenon4 -> get_image_turning 6 7
14 get_image satellite0 Phenomenon6 instrument0 thermograph0 Star5 -> get_image_turning 8 9
<==
;@ 0 0.000 [2.000]
;@ 1 2.010 [5.000]
;@ 2 7.020 [5.000]
;@ 3 13.020 [7.000]
;@ 4 26.030 [5.000]
;@ 5 31.040 [7.000]
;@ 6 39.040 [5.000]
;@ 7 44.050 [7.000]
;@ 8 52.050 [5.000]
;@ 9 57.060 [7.000]
;@ 10 2.010 [11.000]
;@ 11 13.020 [13.000]
;@ 12 26.030 [13.000]
;@ 13 39.040 [13.000]
;@ 14 52.050 [13.000]
";

#[test]
fn satellite_abstract_actions_agree_with_their_methods() {
    let Some(files) = satellite_files("satellite-time-simple-automatic") else { return };
    let mut host = AnalysisHost::new();
    host.set_file_text("/satellite/domain.pddl", files[0].1.clone());
    let (name, text) = &files[1];
    assert_eq!(name, "instance-1.pddl");
    let p = host.set_file_text("/satellite/instance-1.pddl", text.clone());
    let good = host.set_file_text("/satellite/good.hier.plan", SATELLITE_PLAN_1);
    // get_image lasts 13: a step of 12 is rejected (E0447).
    let short = host.set_file_text(
        "/satellite/short.hier.plan",
        SATELLITE_PLAN_1.replace(";@ 14 52.050 [13.000]", ";@ 14 52.050 [12.000]"),
    );
    let analysis = host.analysis();
    let options = Options::default();
    let v = analysis.validate_plan(good, None, p, &options).unwrap().unwrap();
    assert!(v.valid && v.checked, "{:#?}", problems(&host, &v.diagnostics));
    assert!(problems(&host, &v.diagnostics).is_empty(), "{:#?}", problems(&host, &v.diagnostics));
    let v = analysis.validate_plan(short, None, p, &options).unwrap().unwrap();
    assert!(!v.valid && v.diagnostics.iter().any(|d| d.code.id == "E0447"));
}

#[test]
fn satellite_abstract_sample_is_up_to_date() {
    let Some(files) = satellite_files("satellite-time-simple-automatic") else { return };
    compare_with_committed("satellite-abstract", &files);
}

#[test]
fn satellite_abstract_reads_the_timed_corpus_too() {
    let Some(files) = satellite_files("satellite-time-automatic") else { return };
    assert!(satellite::is_timed(&files[0].1));
    assert!(files[0].1.contains("(+ (slew_time ?d_prev ?d) (calibration_time ?i ?d) 1)"));
    let mut host = AnalysisHost::new();
    let ids: Vec<_> = files
        .iter()
        .map(|(name, text)| host.set_file_text(&format!("/satellite/{name}"), text.clone()))
        .collect();
    let analysis = host.analysis();
    // The corpus's own slew times break the triangle inequality (W0310, 419
    // warnings on the unmodified corpus too); nothing else may be reported.
    let mut failures = Vec::new();
    for &f in &ids {
        let diags: Vec<Diagnostic> =
            analysis.diagnostics(f).unwrap().into_iter().filter(|d| d.code.id != "W0310").collect();
        failures.extend(problems(&host, &diags));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Compares each `.pddl` file committed in `samples/<folder>` with the
/// generated file of that name; the number compared.
fn compare_with_committed(folder: &str, files: &[(String, String)]) -> usize {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(folder);
    let mut compared = 0;
    for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("samples/{folder}: {e}")) {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !name.ends_with(".pddl") {
            continue;
        }
        let (_, text) =
            files.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("{name} is not generated"));
        let committed = std::fs::read_to_string(&path).unwrap();
        assert!(committed == *text, "samples/{folder}/{name} is stale: regenerate it (see its README)");
        compared += 1;
    }
    compared
}

/// The errors and warnings of a generated domain and problem pair.
fn pair_problems(domain: &str, problem: &str) -> Vec<String> {
    let mut host = AnalysisHost::new();
    let d = host.set_file_text("/gen/domain.pddl", domain);
    let p = host.set_file_text("/gen/problem.pddl", problem);
    let analysis = host.analysis();
    let mut diags = analysis.diagnostics(p).unwrap();
    diags.extend(analysis.diagnostics(d).unwrap());
    problems(&host, &diags)
}

#[test]
fn airports_are_clean_deterministic_and_of_the_size_asked() {
    let (d, p) = hipop_samplegen::airport::airport(0.3, DEFAULT_SEED);
    assert_eq!((d.clone(), p.clone()), hipop_samplegen::airport::airport(0.3, DEFAULT_SEED));
    let size = (d.len() + p.len()) as f64 / 1_048_576.0;
    // The airport grows a runway segment at a time: within a quarter at this size.
    assert!((0.225..=0.375).contains(&size), "{size} MiB");
    assert!(d.matches(":durative-action move_").count() > 100);
    assert_eq!(pair_problems(&d, &p), Vec::<String>::new());
    // A broken copy is noticed: an airplane that is not declared.
    let broken = p.replacen("(has-type airplane_a00", "(has-type airplane_zz", 1);
    assert!(!pair_problems(&d, &broken).is_empty());

    let set = hipop_samplegen::airport::airport_set(3, 0.3, DEFAULT_SEED);
    let names: Vec<&str> = set.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "p01-domain.pddl",
            "p01-airport.pddl",
            "p02-domain.pddl",
            "p02-airport.pddl",
            "p03-domain.pddl",
            "p03-airport.pddl"
        ]
    );
    assert!(set[0].1.len() < set[4].1.len());
    assert!(set[3].1.contains("(:domain p02-airport-domain)"));
}

#[test]
fn satellite_time_problems_are_clean_and_of_the_size_asked() {
    let (d, p) = hipop_samplegen::satgen::satellite_time(0.2, DEFAULT_SEED);
    let size = p.len() as f64 / 1_048_576.0;
    assert!((0.19..=0.21).contains(&size), "{size} MiB");
    assert_eq!(pair_problems(&d, &p), Vec::<String>::new());
    let broken = p.replacen("(= (slew_time ", "(= (slew_times ", 1);
    assert!(!pair_problems(&d, &broken).is_empty());
}
