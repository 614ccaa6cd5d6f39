//! Incrementality: salsa re-executes only what an edit can change.

use std::sync::{Arc, Mutex};

use hipop_analyzer::{AnalysisHost, TextEdit, TextRange, TextSize};

const DOMAIN: &str = "(define (domain d)
  (:requirements :typing)
  (:types robot waypoint)
  (:predicates (at-r ?r - robot ?w - waypoint) (seen ?w - waypoint))
  ; Move between waypoints.
  (:action move
    :parameters (?r - robot ?a ?b - waypoint)
    :precondition (at-r ?r ?a)
    :effect (and (not (at-r ?r ?a)) (at-r ?r ?b)))
  (:action look
    :parameters (?r - robot ?w - waypoint)
    :precondition (at-r ?r ?w)
    :effect (seen ?w)) ; the end of look
  (:action wait
    :parameters (?r - robot ?w - waypoint)
    :precondition (at-r ?r ?w)
    :effect (at-r ?r ?w)))
";

/// A host that records which queries execute, and the log.
fn host() -> (AnalysisHost, Arc<Mutex<Vec<String>>>) {
    let log = Arc::new(Mutex::new(Vec::new()));
    let sink = log.clone();
    let host = AnalysisHost::with_event_callback(Box::new(move |event| {
        if let salsa::EventKind::WillExecute { database_key } = event.kind {
            sink.lock().unwrap().push(format!("{database_key:?}"));
        }
    }));
    (host, log)
}

fn executed(log: &Arc<Mutex<Vec<String>>>, query: &str) -> usize {
    log.lock().unwrap().iter().filter(|e| e.starts_with(&format!("{query}("))).count()
}

fn edit_at(text: &str, needle: &str, delta: usize, remove: usize, insert: &str) -> TextEdit {
    let at = text.find(needle).expect("needle in text") + delta;
    TextEdit {
        range: TextRange::at(TextSize::from(at as u32), TextSize::from(remove as u32)),
        insert: insert.into(),
    }
}

#[test]
fn editing_one_action_rechecks_only_that_action() {
    let (mut host, log) = host();
    let file = host.set_file_text("d.pddl", DOMAIN);
    let before = host.analysis().diagnostics(file).unwrap();
    assert!(before.is_empty(), "{before:?}");
    assert_eq!(executed(&log, "check_item"), 7, "first run checks every item: {:?}", log.lock().unwrap());
    log.lock().unwrap().clear();

    // Change the body of `look`: `(seen ?w)` becomes `(seen ?r)`, a type error.
    host.apply_edits("d.pddl", vec![edit_at(DOMAIN, "(seen ?w)) ;", 6, 2, "?r")]).unwrap();
    let after = host.analysis().diagnostics(file).unwrap();
    assert_eq!(after.len(), 1);
    assert_eq!(after[0].code.id, "E0111");
    assert_eq!(executed(&log, "lower_item"), 1, "{:?}", log.lock().unwrap());
    assert_eq!(executed(&log, "check_item"), 1, "{:?}", log.lock().unwrap());
}

#[test]
fn editing_an_action_renaming_nothing_keeps_symbols_backdated() {
    let (mut host, log) = host();
    let file = host.set_file_text("d.pddl", DOMAIN);
    host.analysis().diagnostics(file).unwrap();
    log.lock().unwrap().clear();
    // Inserting text in `move` shifts every later item: they keep their checks.
    host.apply_edits("d.pddl", vec![edit_at(DOMAIN, "(at-r ?r ?b)))", 12, 0, " (seen ?b)")]).unwrap();
    assert!(host.analysis().diagnostics(file).unwrap().is_empty());
    assert_eq!(executed(&log, "check_item"), 1, "{:?}", log.lock().unwrap());
    assert_eq!(executed(&log, "domain_symbols"), 1, "the table is recomputed, then backdated");
}

#[test]
fn editing_a_comment_changes_no_semantic_result() {
    let (mut host, log) = host();
    let file = host.set_file_text("d.pddl", DOMAIN);
    let before = host.analysis().diagnostics(file).unwrap();
    log.lock().unwrap().clear();

    // A comment between items: no item changes.
    host.apply_edits("d.pddl", vec![edit_at(DOMAIN, "; Move between", 2, 4, "Drive")]).unwrap();
    assert_eq!(host.analysis().diagnostics(file).unwrap(), before);
    assert_eq!(executed(&log, "lower_item"), 0, "{:?}", log.lock().unwrap());
    assert_eq!(executed(&log, "check_item"), 0, "{:?}", log.lock().unwrap());
    log.lock().unwrap().clear();

    // A comment at the end of an item: its syntax changes, its model does not.
    let text = host.analysis().file_text(file).unwrap().to_string();
    host.apply_edits("d.pddl", vec![edit_at(&text, "; the end of look", 6, 3, "END")]).unwrap();
    assert_eq!(host.analysis().diagnostics(file).unwrap(), before);
    assert_eq!(executed(&log, "check_item"), 0, "{:?}", log.lock().unwrap());
    assert_eq!(executed(&log, "domain_symbols"), 0, "{:?}", log.lock().unwrap());
}

#[test]
fn editing_one_init_fact_rechecks_one_chunk() {
    let mut problem = String::from("(define (problem p) (:domain d)\n  (:objects r1 - robot");
    for i in 0..500 {
        problem.push_str(&format!(" w{i}"));
    }
    problem.push_str(" - waypoint)\n  (:init\n");
    for i in 0..500 {
        problem.push_str(&format!("    (at-r r1 w{i})\n"));
    }
    problem.push_str("  )\n  (:goal (seen w3)))\n");
    let (mut host, log) = host();
    host.set_file_text("d.pddl", DOMAIN);
    let p = host.set_file_text("p.pddl", problem.clone());
    let d = host.analysis().diagnostics(p).unwrap();
    assert!(d.is_empty(), "{d:?}");
    log.lock().unwrap().clear();

    host.apply_edits("p.pddl", vec![edit_at(&problem, "(at-r r1 w250)", 9, 4, "w99")]).unwrap();
    assert!(host.analysis().diagnostics(p).unwrap().is_empty());
    assert_eq!(executed(&log, "check_item"), 1, "{:?}", log.lock().unwrap());
    assert_eq!(executed(&log, "lower_item"), 1, "{:?}", log.lock().unwrap());
}

#[test]
fn grounding_reruns_only_when_what_it_reads_changes() {
    let domain = "(define (domain m) (:requirements :typing :durative-actions :numeric-fluents)
  (:types robot waypoint)
  (:predicates (at-r ?r - robot ?w - waypoint) (road ?a ?b - waypoint))
  (:functions (distance ?a ?b - waypoint))
  (:durative-action move :parameters (?r - robot ?a ?b - waypoint)
    :duration (= ?duration (distance ?a ?b))
    :condition (and (at start (at-r ?r ?a)) (over all (road ?a ?b)))
    :effect (and (at start (not (at-r ?r ?a))) (at end (at-r ?r ?b)))))
";
    let problem = "(define (problem p) (:domain m) (:objects r1 - robot a b - waypoint)
  (:init (at-r r1 a) (road a b) (= (distance a b) 12.5))
  (:goal (at-r r1 b)))
";
    let (mut host, log) = host();
    host.set_file_text("d.pddl", domain);
    let p = host.set_file_text("p.pddl", problem);
    assert!(quiet(&host.analysis().diagnostics(p).unwrap()));
    assert_eq!(executed(&log, "ground"), 1, "{:?}", log.lock().unwrap());
    log.lock().unwrap().clear();

    // The goal is not read by grounding.
    host.apply_edits("p.pddl", vec![edit_at(problem, "(:goal (at-r r1 b)", 16, 1, "a")]).unwrap();
    assert!(quiet(&host.analysis().diagnostics(p).unwrap()));
    assert_eq!(executed(&log, "ground"), 0, "{:?}", log.lock().unwrap());
    log.lock().unwrap().clear();

    // A value of `:init` is.
    host.apply_edits("p.pddl", vec![edit_at(problem, "12.5", 0, 4, "13.5")]).unwrap();
    assert!(quiet(&host.analysis().diagnostics(p).unwrap()));
    assert_eq!(executed(&log, "ground"), 1, "{:?}", log.lock().unwrap());
}

/// No error or warning (information, such as a position family without a move
/// between every two positions, may remain).
fn quiet(diagnostics: &[hipop_analyzer::Diagnostic]) -> bool {
    diagnostics.iter().all(|d| d.severity == hipop_analyzer::Severity::Info)
}

/// The command line's path (`AnalysisHost::drop_syntax_after_use`): once the
/// checks have lowered every item, the syntax trees are dropped, and the
/// lints, which ground the problem, run on the lowered models without
/// parsing again. The diagnostics are those of a host that keeps the trees.
#[test]
fn the_lints_run_without_the_dropped_trees() {
    // More than 512 facts: the `:init` is in groups, each an item of its own.
    let waypoints: String = (0..600).map(|i| format!(" w{i}")).collect();
    let facts: String = (2..600).map(|i| format!("\n    (seen w{i})")).collect();
    let problem = format!(
        "(define (problem p) (:domain d)
  (:objects r1 - robot{waypoints} - waypoint)
  (:init (at-r r1 w0){facts})
  (:goal (at-r r1 w599))
  (:allowed-actions move))
"
    );
    let mut keeping = AnalysisHost::new();
    let kept: Vec<_> = ["d.pddl", "p.pddl"]
        .iter()
        .zip([DOMAIN, &problem])
        .map(|(path, text)| keeping.set_file_text(path, text))
        .collect();
    let expected: Vec<_> = kept.iter().map(|&f| keeping.analysis().diagnostics(f).unwrap()).collect();
    // A lint of the ground problem: `look` and `wait` are dead, on the
    // section's keyword.
    let keyword = TextSize::from(problem.find(":allowed-actions").unwrap() as u32);
    assert!(expected[1].iter().any(|d| d.code.id == "W0311" && d.range.start() == keyword), "{expected:?}");

    let (mut host, log) = host();
    host.drop_syntax_after_use();
    let files: Vec<_> = ["d.pddl", "p.pddl"]
        .iter()
        .zip([DOMAIN, &problem])
        .map(|(path, text)| host.set_file_text(path, text))
        .collect();
    for &f in &files {
        host.analysis().check_diagnostics(f).unwrap();
    }
    host.release_syntax();
    log.lock().unwrap().clear();
    let found: Vec<_> = files.iter().map(|&f| host.analysis().diagnostics(f).unwrap()).collect();
    // The two databases number their files differently: compare the rest.
    let shown = |all: &[Vec<hipop_analyzer::Diagnostic>]| -> Vec<String> {
        let shown = |d: &hipop_analyzer::Diagnostic| {
            let related: Vec<_> = d.related.iter().map(|r| (r.range, &r.message)).collect();
            format!("{} {:?} {} {related:?} {:?}", d.code.id, d.range, d.message, d.fix.is_some())
        };
        all.iter().map(|ds| ds.iter().map(shown).collect::<Vec<_>>().join("\n")).collect()
    };
    assert_eq!(shown(&found), shown(&expected));
    assert_eq!(executed(&log, "problem_lints"), 1, "{:?}", log.lock().unwrap());
    assert_eq!(executed(&log, "parse"), 0, "{:?}", log.lock().unwrap());
    assert_eq!(executed(&log, "located_syntax"), 0, "{:?}", log.lock().unwrap());
    // The trees were dropped: asking for one parses its file again.
    hipop_analyzer::db::parse(host.db(), files[1]);
    assert_eq!(executed(&log, "parse"), 1, "{:?}", log.lock().unwrap());
}
