//! Unit tests of the plan reader: format detection, ranges, names, the hash.

use super::*;

fn at(text: &str, r: TextRange) -> &str {
    &text[usize::from(r.start())..usize::from(r.end())]
}

#[test]
fn detection_looks_at_the_content() {
    assert_eq!(detect_format(""), PlanFormat::Val);
    assert_eq!(detect_format("0.0: (a b) [1]\n"), PlanFormat::Val);
    assert_eq!(detect_format("(a b)\n(c)\n"), PlanFormat::Val);
    assert_eq!(detect_format("  \n{ \"format\": \"hipop-plan\" }"), PlanFormat::Json);
    assert_eq!(detect_format("log 1 2 3\n==>\n0 a\nroot\n<=="), PlanFormat::Hierarchical);
    // No `==>`: the IPC lines outnumber the VAL ones.
    assert_eq!(detect_format("0 a b\n1 c\nroot 2\n2 t -> m 0 1\n"), PlanFormat::Hierarchical);
    // A VAL plan with a planner's trailer stays a VAL plan.
    assert_eq!(detect_format("0.0: (a b) [1]\nTime: 1\n"), PlanFormat::Val);
    // A `==>` in a comment is not a marker.
    assert_eq!(detect_format("; ==>\n(a)\n"), PlanFormat::Val);
}

#[test]
fn val_ranges_and_numbers_as_written() {
    let text = "\u{feff}0.010:(Move R1 a b)[2.50] ; c\r\n(look r1)\r\n";
    let plan = read_plan(text, None);
    assert_eq!(plan.format, PlanFormat::Val);
    let s = &plan.steps[0];
    assert_eq!(at(text, s.range), "0.010:(Move R1 a b)[2.50]");
    assert_eq!(at(text, s.name.range), "Move");
    assert_eq!(s.start.as_ref().map(|n| (n.text.as_str(), n.value)), Some(("0.010", 0.01)));
    assert_eq!(s.duration.as_ref().map(|n| at(text, n.range)), Some("2.50"));
    assert_eq!(s.end(), Some(2.51));
    assert_eq!(s.args.iter().map(|a| a.text.as_str()).collect::<Vec<_>>(), ["R1", "a", "b"]);
    // The second step has no time: a warning, not an error.
    assert!(!plan.has_errors());
    assert_eq!(plan.diagnostics.len(), 1);
    assert_eq!(plan.diagnostics[0].code.id, "W0403");
}

#[test]
fn hierarchical_forms_pandapiparser_accepts() {
    let text = "==> 0 (a x)\n1 b[y,z] w\nroot 2\n2 t x -> <m;t[x];m2;0;-1> 0 1\n";
    let plan = read_plan(text, None);
    assert!(plan.diagnostics.is_empty(), "{:?}", plan.diagnostics);
    assert_eq!(plan.steps.len(), 3);
    assert_eq!(plan.steps[0].call(), "(a x)");
    assert_eq!(plan.steps[1].call(), "(b y z w)");
    assert_eq!(at(text, plan.steps[1].args[1].range), "z");
    let d = plan.steps[2].decomposition.as_ref().expect("abstract");
    assert_eq!(d.method.text, "<m;t[x];m2;0;-1>");
    assert_eq!(plan.index_of(2), Some(2));
    assert_eq!(plan.step_by_id(1).map(Step::call).as_deref(), Some("(b y z w)"));
    assert!(plan.is_hierarchical() && !plan.is_timed());
    assert_eq!(plan.primitive_steps().count(), 2);
    assert_eq!(plan.abstract_steps().count(), 1);
}

#[test]
fn timing_annotations_give_times() {
    let text = "==>\n0 a\nroot 1\n1 t -> m 0\n<==\n;@ 1 0 [3]\n;@ 0 0.5 [2.5]\n";
    let plan = read_plan(text, None);
    assert!(plan.diagnostics.is_empty(), "{:?}", plan.diagnostics);
    assert!(plan.is_timed());
    assert_eq!(plan.steps[0].start.as_ref().map(|n| n.value), Some(0.5));
    assert_eq!(plan.steps[0].end(), Some(3.0));
    assert_eq!(plan.steps[1].duration.as_ref().map(|n| at(text, n.range)), Some("3"));
}

#[test]
fn json_ranges_point_into_the_file() {
    let text =
        r#"{"format":"hipop-plan","version":1,"steps":[{"id":4,"name":"go","args":["r1"],"start":1.50}]}"#;
    let plan = read_plan(text, None);
    assert!(plan.diagnostics.is_empty(), "{:?}", plan.diagnostics);
    let s = &plan.steps[0];
    assert_eq!(at(text, s.name.range), "\"go\"");
    assert_eq!(at(text, s.args[0].range), "\"r1\"");
    assert_eq!(s.start.as_ref().map(|n| n.text.as_str()), Some("1.50"));
    assert_eq!(at(text, s.id.expect("id").range), "4");
    assert!(at(text, s.range).starts_with("{\"id\":4"));
}

#[test]
fn names_normalise() {
    assert_eq!(normalise_name("Move_To", NameMatching::Exact), "Move_To");
    assert_eq!(normalise_name("Move_To", NameMatching::CaseInsensitive), "move_to");
    assert_eq!(normalise_name("Move_To", NameMatching::Lenient), "move-to");
    assert_eq!(normalise_name("déjà_vu", NameMatching::Lenient), "déjà-vu");
    assert!(matches!(normalise_name("move-to", NameMatching::Lenient), Cow::Borrowed(_)));
}

#[test]
fn problem_hash_ignores_layout_and_comments() {
    let d = "(define (domain d) (:predicates (p)))";
    let p = "(define (problem p) (:domain d) (:init (p)) (:goal (p)))";
    let h = json::problem_hash(d, p);
    assert!(h.starts_with("fnv1a64:") && h.len() == 8 + 16, "{h}");
    let d2 = "; a comment\n(define (DOMAIN d)\n  (:predicates   (p) ) )";
    assert_eq!(json::problem_hash(d2, p), h);
    assert_ne!(json::problem_hash(d, "(define (problem p) (:domain d) (:init) (:goal (p)))"), h);
    // The domain and the problem are told apart.
    assert_ne!(json::problem_hash(p, d), h);
}

#[test]
fn json_of_another_shape_says_what_a_plan_is() {
    let plan = read_plan("[1, 2]", Some(PlanFormat::Json));
    assert_eq!(plan.diagnostics.len(), 1);
    assert_eq!(plan.diagnostics[0].code.id, "E0406");
    assert!(
        plan.diagnostics[0].message.contains("an object with `format`"),
        "{}",
        plan.diagnostics[0].message
    );
    assert!(!plan.diagnostics[0].message.contains("RawDoc"));
}
