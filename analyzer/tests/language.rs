//! Small language cases: what is accepted, and what each misuse reports.

use hipop_analyzer::AnalysisHost;

/// The codes reported for `text`, with the text each one covers.
fn codes(text: &str) -> Vec<(String, String)> {
    let mut host = AnalysisHost::new();
    let f = host.set_file_text("d.hddl", text);
    host.analysis()
        .diagnostics(f)
        .unwrap()
        .iter()
        .map(|d| {
            (
                d.code.id.to_string(),
                text[usize::from(d.range.start())..usize::from(d.range.end())].to_string(),
            )
        })
        .collect()
}

const HEAD: &str = "(define (domain d)
  (:requirements :typing :hierarchy :durative-actions :durative-methods :method-constraints)
  (:types robot)
  (:predicates (ready ?r - robot) (done ?r - robot))
  (:task work :parameters (?r - robot))
  (:durative-action step :parameters (?r - robot) :duration (= ?duration 1)
    :condition (at start (ready ?r)) :effect (at end (done ?r)))
  (:method work-step :parameters (?r - robot) :task (work ?r) :subtasks (and (step ?r)))
";

fn domain(rest: &str) -> String {
    format!("{HEAD}{rest})\n")
}

#[test]
fn hddl21_timed_and_ordering_constraints_are_understood() {
    let text = domain(
        "  (:durative-method m :parameters (?r - robot) :task (work ?r)
    :subtasks (and (t1 (step ?r)) (t2 (step ?r)))
    :constraints (and (< t1 t2) (<= (end t1) (start t2)) (at (start t1) (ready ?r))))",
    );
    assert_eq!(codes(&text), vec![]);
}

#[test]
fn ordering_constraints_name_subtasks() {
    let text = domain(
        "  (:durative-method m :parameters (?r - robot) :task (work ?r)
    :subtasks (and (t1 (step ?r)) (t2 (step ?r)))
    :constraints (and (< t1 t9)))",
    );
    assert_eq!(codes(&text), vec![("E0108".to_string(), "t9".to_string())]);
}

#[test]
fn a_field_given_twice_is_reported() {
    let text =
        domain("  (:action a :parameters (?r - robot) :precondition (ready ?r) :precondition (done ?r))");
    assert_eq!(codes(&text), vec![("E0109".to_string(), ":precondition".to_string())]);
}

#[test]
fn timed_conditions_need_a_duration() {
    let text = domain(
        "  (:action a :parameters (?r - robot) :precondition (at start (ready ?r)) :effect (done ?r))",
    );
    assert_eq!(codes(&text), vec![("E0003".to_string(), "(at start (ready ?r))".to_string())]);
}

#[test]
fn ordering_cycles_are_found_through_timed_points() {
    let text = domain(
        "  (:durative-method m :parameters (?r - robot) :task (work ?r)
    :subtasks (and (t1 (step ?r)) (t2 (step ?r)))
    :ordering (and (< t1 t2) (< (end t2) (start t1))))",
    );
    assert_eq!(codes(&text), vec![("E0113".to_string(), "(< t1 t2)".to_string())]);
}

#[test]
fn a_byte_order_mark_at_the_start_is_trivia() {
    let text = "\u{feff}(define (domain d) (:predicates (p)) (:action a :parameters () :effect (p)))\n";
    assert_eq!(hipop_analyzer::syntax::parse(text).text(), text);
    assert_eq!(codes(text), vec![]);
}

/// The fixtures of `tests/reading/`, by file name.
fn reading_fixture(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/reading").join(name);
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn a_type_glued_to_its_dash_is_read_as_a_type() {
    let text = reading_fixture("dash-glued-type.hddl");
    assert_eq!(codes(&text), vec![]);
    // The type's name, not its `-`, is what refers to the declaration.
    let mut host = AnalysisHost::new();
    let f = host.set_file_text("d.hddl", text.as_str());
    let at = text.find("?r -Robot").unwrap() + 4;
    let target = host.analysis().goto_definition(f, hipop_analyzer::TextSize::from(at as u32 + 1)).unwrap();
    let range = target.expect("a definition").range;
    assert_eq!(&text[usize::from(range.start())..usize::from(range.end())], "Robot");
    assert!(
        host.analysis().goto_definition(f, hipop_analyzer::TextSize::from(at as u32 - 1)).unwrap().is_none()
    );
}

#[test]
fn a_lone_dash_still_needs_a_type_and_names_before_it() {
    let text = "(define (domain d) (:requirements :typing) (:types -Thing)\n  (:predicates (p ?x -)))\n";
    assert_eq!(
        codes(text),
        vec![
            ("E0003".to_string(), "-Thing".to_string()),
            ("W0201".to_string(), "p".to_string()),
            ("E0003".to_string(), "-".to_string())
        ]
    );
}

/// `1e999`, `1e5`, `+3` are not PDDL numbers: where a number is expected they
/// are reported as such, not read as names (which made `(= ?duration 1e999)`
/// an `=` "between objects" and a duration inequality).
#[test]
fn what_starts_like_a_number_but_is_not_one_is_reported_where_a_number_is_expected() {
    let text = "(define (domain num)
  (:requirements :durative-actions :numeric-fluents :timed-initial-literals)
  (:predicates (p) (q))
  (:functions (f))
  (:durative-action a :parameters () :duration (= ?duration 1e999)
    :condition (at start (p)) :effect (and (at end (q)) (at end (increase (f) +3)))))
(define (problem n) (:domain num)
  (:init (p) (= (f) 1e5) (at 1e3 (q)) (= (f) .5))
  (:goal (q)) (:metric minimize (* 2E1 (total-time))))
";
    let expected = ["1e999", "+3", "1e5", "1e3", "2E1"];
    assert_eq!(codes(text), expected.map(|n| ("E0003".to_string(), n.to_string())).to_vec());
    let mut host = AnalysisHost::new();
    let f = host.set_file_text("n.pddl", text);
    let diags = host.analysis().diagnostics(f).unwrap();
    assert!(diags.iter().all(|d| d.message.starts_with("expected a number")), "{diags:#?}");
}

/// A constant duration that is negative or infinite: no instance of the
/// action can be applied (E0115). Before, it passed silently.
#[test]
fn a_negative_or_infinite_constant_duration_is_an_error() {
    let action = |name: &str, duration: &str| {
        format!(
            "  (:durative-action {name} :parameters (?r - robot) :duration {duration}
    :condition (at start (ready ?r)) :effect (at end (done ?r)))\n"
        )
    };
    let text = domain(
        &[
            action("a", "(= ?duration -5)"),
            action("b", "(= ?duration (- 2 7))"),
            action("c", "(= ?duration (/ 1 0))"),
            action("d", "(and (>= ?duration 1) (<= ?duration -1))"),
            action("e", "(>= -1 ?duration)"),
            action("f", "(and (>= ?duration -1) (<= ?duration 0))"),
            action("g", "(= ?duration 0)"),
        ]
        .concat(),
    );
    let found: Vec<(String, String)> = codes(&text).into_iter().filter(|(c, _)| c == "E0115").collect();
    assert_eq!(
        found,
        [
            "(= ?duration -5)",
            "(= ?duration (- 2 7))",
            "(= ?duration (/ 1 0))",
            "(<= ?duration -1)",
            "(>= -1 ?duration)"
        ]
        .map(|s| ("E0115".to_string(), s.to_string()))
        .to_vec()
    );
}

/// A plan saved as `.hddl` (as in the IPC 2020 feature tests) is read and
/// validated as a plan of the problem beside it; before, it was E0003 "not a
/// domain or problem file".
#[test]
fn a_plan_saved_as_hddl_is_validated_as_a_plan() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/reading/plan-saved-as-hddl");
    let mut host = AnalysisHost::new();
    let mut files = Vec::new();
    for name in ["domain.hddl", "problem.hddl", "plan.hddl"] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        files.push(host.set_file_text(&format!("lamp/{name}"), text));
    }
    let plan = files[2];
    assert_eq!(host.analysis().diagnostics(plan).unwrap(), vec![]);
    for &f in &files[..2] {
        assert_eq!(host.analysis().diagnostics(f).unwrap(), vec![]);
    }
    // A wrong plan of it gets the validator's errors.
    let wrong = "==>\n0 switch-on\nroot 1\n1 light -> by-magic 0\n<==\n";
    host.set_file_text("lamp/plan.hddl", wrong);
    let codes: Vec<&str> = host.analysis().diagnostics(plan).unwrap().iter().map(|d| d.code.id).collect();
    assert_eq!(codes, ["E0432"]);
    // What is neither a domain, a problem nor a plan is still E0003.
    host.set_file_text("lamp/plan.hddl", "(:action a)\n");
    let codes: Vec<&str> = host.analysis().diagnostics(plan).unwrap().iter().map(|d| d.code.id).collect();
    assert_eq!(codes, ["E0003"]);
}
