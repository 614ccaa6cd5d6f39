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

/// Every section of the outline is selected by its keyword (`:predicates`),
/// not by its `(`; a long `:init`, split in chunks, by the keyword of its first.
#[test]
fn document_symbols_select_a_section_by_its_keyword() {
    let mut host = AnalysisHost::new();
    let domain = "(define (domain d)\n  (:requirements :typing)\n  ( :types robot)\n  (:predicates (at ?r - robot))\n  (:functions (f))\n  (:action go :parameters (?r - robot) :effect (at ?r)))\n";
    let facts: String = (0..1500).map(|i| format!(" (at r{i})")).collect();
    let objects: String = (0..1500).map(|i| format!(" r{i}")).collect();
    let problem = format!(
        "(define (problem p) (:domain d)\n  (:objects{objects} - robot)\n  (:init{facts})\n  (:goal (at r0)))\n"
    );
    let short = "(define (problem q) (:domain d) (:objects a - robot) (:init (at a)) (:goal (at a)))\n";
    let files = [("w/d.pddl", domain.to_string()), ("w/p.pddl", problem), ("w/q.pddl", short.to_string())];
    let ids: Vec<_> = files.iter().map(|(path, text)| host.set_file_text(path, text.as_str())).collect();
    let analysis = host.analysis();
    let mut seen = Vec::new();
    for (id, (_, text)) in ids.into_iter().zip(&files) {
        for unit in analysis.document_symbols(id).unwrap() {
            for s in unit.children.iter().filter(|s| s.kind == hipop_analyzer::ide::SymbolKind::Section) {
                let selected = &text[s.selection_range];
                assert_eq!(selected, s.name, "{} {:?}", s.name, s.selection_range);
                assert!(s.range.contains_range(s.selection_range), "{}", s.name);
                seen.push(s.name.clone());
            }
        }
    }
    assert_eq!(
        seen,
        [":types", ":predicates", ":functions", ":objects", ":init", ":goal", ":objects", ":init", ":goal"]
    );
}

/// Workspace symbols: every declaration of every domain and problem, matched
/// ignoring case by prefix, substring or characters in order, best first.
#[test]
fn workspace_symbols_match_by_prefix_substring_and_characters_in_order() {
    let mut host = AnalysisHost::new();
    let domain = "(define (domain Logistics) (:types truck)\n  (:predicates (at ?t - truck))\n  (:action pick-up :parameters (?t - truck) :effect (at ?t))\n  (:action drop :parameters (?t - truck) :effect (not (at ?t))))\n";
    let problem = "(define (problem deliver-1) (:domain logistics) (:objects truck-a - truck) (:init) (:goal (at truck-a)))\n";
    host.set_file_text("/w/domain.pddl", domain);
    host.set_file_text("/w/p1.pddl", problem);
    // A plan file has no declarations.
    host.set_file_text("/w/p1.plan", "0: (pick-up truck-a) [1]\n");
    let analysis = host.analysis();
    let names = |query: &str| -> Vec<(String, Option<String>)> {
        let symbols = analysis.workspace_symbols(query).unwrap();
        symbols.into_iter().map(|s| (s.name, s.container)).collect()
    };
    let some = |s: &str| Some(s.to_string());
    assert_eq!(
        names("TRUCK"),
        [("truck".into(), some("Logistics")), ("truck-a".into(), some("deliver-1")),],
        "exact before prefix; case ignored"
    );
    assert_eq!(names("pkup"), [("pick-up".into(), some("Logistics"))], "characters in order");
    assert_eq!(names("ver"), [("deliver-1".into(), None)], "a substring; a problem has no container");
    assert!(names("zz").is_empty());
    let everything = names("");
    assert_eq!(everything.len(), 7, "{everything:?}");

    let symbols = analysis.workspace_symbols("drop").unwrap();
    let drop = &symbols[0];
    assert_eq!(drop.kind, hipop_analyzer::ide::SymbolKind::Action);
    assert_eq!(&domain[drop.range], "drop");
    assert_eq!(analysis.file_path(drop.file).unwrap(), "/w/domain.pddl");
}
