use super::*;
use crate::AnalysisHost;

const DOMAIN: &str = "\
(define (domain rovers)
  (:requirements :typing :durative-actions :hierarchy)
  (:types robot vehicle - object rover - robot waypoint)
  (:constants base - waypoint)
  (:predicates (at ?r - robot ?w - waypoint) (visited ?w - waypoint) (free ?r - robot))
  (:functions (distance ?a ?b - waypoint))
  (:durative-action move
    :parameters (?r - robot ?from ?to - waypoint)
    :duration (= ?duration (distance ?from ?to))
    :condition (and (at start (at ?r ?from)))
    :effect (and (at end (at ?r ?to))))
  (:task visit :parameters (?r - robot ?w - waypoint))
  (:method visit-direct
    :parameters (?r - robot ?w - waypoint)
    :task (visit ?r ?w)
    :ordered-subtasks (and (move ?r base ?w))))
";

const PROBLEM: &str = "\
(define (problem p1) (:domain rovers)
  (:objects r1 - rover v1 - vehicle w1 w2 - waypoint)
  (:init (at r1 w1))
  (:goal (and (visited w2))))
";

/// The completions at `$0` of `fixture`, saved as `edited.pddl` next to
/// the domain and problem above: one line per completion, with its
/// kind and detail.
fn complete(fixture: &str) -> String {
    let at = fixture.find("$0").expect("the fixture has a cursor");
    let text = fixture.replacen("$0", "", 1);
    let mut host = AnalysisHost::new();
    host.set_file_text("dir/problem.pddl", PROBLEM);
    // A domain edited replaces the one above.
    let file = if text.contains("(domain ") {
        host.set_file_text("dir/domain.pddl", text.as_str())
    } else {
        host.set_file_text("dir/domain.pddl", DOMAIN);
        host.set_file_text("dir/edited.pddl", text.as_str())
    };
    let items = host.analysis().completions(file, TextSize::from(at as u32)).unwrap();
    let mut out = String::new();
    for c in items {
        assert_eq!(usize::from(c.range.end()), at, "{c:?}");
        let detail = c.detail.as_deref().map(|d| format!("  {d}")).unwrap_or_default();
        let snippet =
            if c.snippet { format!("\n    {}", c.insert.replace('\n', "\n    ")) } else { String::new() };
        out.push_str(&format!("{:?} {}{detail}{snippet}\n", c.kind, c.label));
    }
    out
}

fn labels(fixture: &str) -> Vec<String> {
    let lines = complete(fixture);
    let entries = lines.lines().filter(|l| !l.starts_with(' '));
    entries
        .map(|l| l.split("  ").next().unwrap_or("").split_once(' ').unwrap_or_default().1.to_string())
        .collect()
}

/// The domain above, left open, followed by `body`.
fn in_domain(body: &str) -> String {
    let open = DOMAIN.trim_end().strip_suffix(')').expect("the domain ends with `)`");
    format!("{open}\n{body}")
}

#[test]
fn sections_of_a_domain_not_yet_declared() {
    insta::assert_snapshot!(complete(&in_domain("  ($0")));
    // A half-typed keyword is replaced whole, `:` included.
    let labels = labels(&in_domain("  (:dur$0"));
    assert_eq!(labels, [":durative-action", ":durative-method", ":durative-action …"]);
}

#[test]
fn sections_of_a_problem() {
    insta::assert_snapshot!(complete("(define (problem p) (:domain rovers)\n  ($0"));
}

#[test]
fn top_level_offers_define_and_a_problem_skeleton_with_the_domain_of_the_folder() {
    insta::assert_snapshot!(complete("($0"));
    // Outside any list, the skeleton brings its parentheses.
    let text = complete("; a comment\n$0");
    assert!(text.contains("(define (problem ${1:name})") && text.contains("(:domain ${2:rovers})"), "{text}");
    // Nothing inside a comment.
    assert_eq!(complete("; (at $0"), "");
}

#[test]
fn fields_of_an_action_not_present_yet() {
    insta::assert_snapshot!(complete(&in_domain("  (:durative-action go :parameters (?r - robot) :$0")));
    // After a field keyword comes its value, not another keyword.
    assert_eq!(labels(&in_domain("  (:action go :parameters $0")), Vec::<String>::new());
    // A method's, with `:precondition` taken by `:condition`.
    let methods = labels(&in_domain("  (:method m :condition (and) $0)"));
    assert!(methods.contains(&":subtasks".to_string()) && !methods.contains(&":precondition".to_string()));
    // A field keyword typed in an unclosed formula belongs to the item.
    let open = labels(&in_domain("  (:action go :parameters (?r - robot) :precondition (and (at ?r) :ef$0"));
    assert_eq!(open, [":effect"]);
}

#[test]
fn formulas_offer_predicates_with_signatures_and_connectives() {
    insta::assert_snapshot!(complete(&in_domain(
        "  (:action go :parameters (?r - robot) :precondition (and ($0"
    )));
    // Timed connectives in a durative action's condition only.
    let timed = labels(&in_domain("(:durative-action go :condition (and ($0"));
    assert!(timed.contains(&"at start".to_string()), "{timed:?}");
    let effect = labels(&in_domain("(:action go :effect (and ($0"));
    assert!(effect.contains(&"increase".to_string()) && !effect.contains(&"at start".to_string()));
    // Under the `not` of an effect, atoms only.
    assert_eq!(labels(&in_domain("(:action go :effect (not (vi$0")), ["visited"]);
    // Functions in a numeric context.
    assert_eq!(labels(&in_domain("(:action go :effect (increase (d$0")), ["distance"]);
}

#[test]
fn arguments_are_the_variables_in_scope_those_of_the_right_type_first() {
    insta::assert_snapshot!(complete(&in_domain(
        "(:action go :parameters (?w - waypoint ?r - rover ?v - vehicle)\n  :precondition (forall (?x - \
             waypoint) (at $0"
    )));
    // A half-typed variable; the variables of a `forall` are out of scope
    // outside it.
    assert_eq!(
        labels(&in_domain(
            "(:action go :parameters (?w - waypoint) :precondition (and (forall (?x) (visited ?x)) (visited \
                 ?$0"
        )),
        ["?w"]
    );
}

#[test]
fn arguments_in_a_problem_are_its_objects_and_the_constants() {
    insta::assert_snapshot!(complete(
        "(define (problem p2) (:domain rovers)\n  (:objects r1 - rover v1 - vehicle w1 - waypoint)\n  (:init \
             (at $0"
    ));
}

#[test]
fn subtasks_and_the_task_of_a_method() {
    insta::assert_snapshot!(complete(&in_domain("(:method m :ordered-subtasks (and ($0")));
    assert_eq!(labels(&in_domain("(:method m :task ($0")), ["visit"]);
    // A subtask without an id takes the variables; one with an id, nothing.
    let args = labels(&in_domain("(:method m :parameters (?y - rover) :subtasks (and (visit $0"));
    assert_eq!(args, ["?y", "base"]);
    assert_eq!(labels(&in_domain("(:method m :parameters (?y) :subtasks (and (t1 $0")), Vec::<String>::new());
    // A problem's task network takes its objects.
    let htn = labels(
        "(define (problem p) (:domain rovers) (:objects r1 - rover w1 - waypoint)\n  (:htn \
                          :subtasks (and (visit $0",
    );
    assert_eq!(htn, ["r1", "base", "w1"]);
    assert_eq!(labels(&in_domain("(:method m :parameters (?x - rover) :task (visit $0")), ["?x", "base"]);
}

#[test]
fn types_after_a_dash() {
    insta::assert_snapshot!(complete(&in_domain("(:predicates (p ?x - $0")));
    assert!(labels("(define (domain rovers) (:functions (f) - $0").contains(&"number".to_string()));
    assert_eq!(labels("(define (domain rovers) (:predicates (p ?x $0"), Vec::<String>::new());
}

#[test]
fn requirements_not_declared_yet() {
    let reqs = labels("(define (domain d) (:requirements :typing :dur$0");
    assert_eq!(
        reqs,
        [":duration-inequalities", ":durative-actions", ":durative-methods", ":disjunctive-preconditions"]
    );
    let all = labels("(define (domain d) (:requirements :typing $0)");
    assert!(!all.contains(&":typing".to_string()) && all.contains(&":hierarchy".to_string()));
    assert_eq!(all.len(), KNOWN_REQUIREMENTS.len() - 1);
}

#[test]
fn the_domain_of_a_problem() {
    assert_eq!(labels("(define (problem p) (:domain $0"), ["rovers"]);
}

#[test]
fn any_text_any_offset() {
    // Every offset of files with unbalanced and odd text: no panic, and
    // every range ends at the cursor.
    for text in [DOMAIN, PROBLEM, "(((", ")))(", "(define (domain", "(:action ?x - - (either", "é(à ?ü"] {
        let mut host = AnalysisHost::new();
        let file = host.set_file_text("x.pddl", text);
        for at in (0..=text.len()).filter(|&i| text.is_char_boundary(i)) {
            for c in host.analysis().completions(file, TextSize::from(at as u32)).unwrap() {
                assert_eq!(usize::from(c.range.end()), at);
            }
        }
    }
}
