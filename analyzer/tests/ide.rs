//! Editor features over real fixtures: what hover says about position
//! families and move actions (issue 3: confirmed families are reported as
//! information, on hover among other places).

use std::path::Path;

use hipop_analyzer::{AnalysisHost, TextSize};

/// The hover text at the first occurrence of `needle` (plus `skip` bytes)
/// in `file` of the fixture folder `dir` (a domain and a problem).
fn hover(dir: &str, file: &str, needle: &str, skip: usize) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(dir);
    let mut host = AnalysisHost::new();
    let mut target = None;
    for name in ["domain.pddl", "problem.pddl"] {
        let text = std::fs::read_to_string(root.join(name)).unwrap();
        let at = text.find(needle).map(|i| i + skip);
        let id = host.set_file_text(&format!("{dir}/{name}"), text);
        if name == file {
            target = Some((id, at.expect("needle in file")));
        }
    }
    let (id, at) = target.unwrap();
    let h = host.analysis().hover(id, TextSize::from(at as u32)).unwrap();
    h.map(|h| h.markdown).unwrap_or_default()
}

#[test]
fn hover_on_a_predicate_names_its_confirmed_family_from_the_domain_and_the_problem() {
    let dir = "tests/lints/W0310-triangle-inequality-ok";
    let in_domain = hover(dir, "domain.pddl", "(at ?r", 1);
    insta::assert_snapshot!(in_domain);
    let in_problem = hover(dir, "problem.pddl", "(at ", 1);
    assert!(in_problem.contains("confirmed (Definition 12)"), "{in_problem}");
}

#[test]
fn hover_on_a_move_action_says_so() {
    let h = hover("tests/lints/W0310-triangle-inequality-ok", "domain.pddl", "move", 0);
    insta::assert_snapshot!(h);
}

#[test]
fn hover_on_a_rejected_candidate_says_which_property_fails() {
    let h = hover("samples/broken/I0307-not-a-position-family", "domain.pddl", "(at ?r", 1);
    assert!(h.contains("is not a position family"), "{h}");
    insta::assert_snapshot!(h);
}
