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

/// A host with the files of fixture folders, each under `w/` with its name
/// (so that a plan finds its problem beside it), and the text of each.
fn workspace(files: &[&str]) -> (AnalysisHost, Vec<(hipop_analyzer::SourceFile, String)>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut host = AnalysisHost::new();
    let mut out = Vec::new();
    for rel in files {
        let text = std::fs::read_to_string(root.join(rel)).unwrap();
        let name = Path::new(rel).file_name().unwrap().to_str().unwrap();
        out.push((host.set_file_text(&format!("w/{name}"), text.as_str()), text));
    }
    (host, out)
}

/// The byte offset of the `nth` occurrence of `needle` in `text`, plus `skip`.
fn at(text: &str, needle: &str, nth: usize, skip: usize) -> TextSize {
    let i = text.match_indices(needle).nth(nth).unwrap_or_else(|| panic!("{needle} #{nth}")).0;
    TextSize::from((i + skip) as u32)
}

const SHUTTLE: [&str; 4] = [
    "tests/ide/shuttle/domain.pddl",
    "tests/ide/shuttle/problem.pddl",
    "tests/ide/shuttle/problem.plan",
    "tests/ide/shuttle/problem.plan.json",
];

/// Hover on a step of a VAL plan: the action's signature and the bound
/// arguments, the time window, and the validator's verdict on that step.
#[test]
fn hover_on_a_plan_step_shows_its_action_time_window_and_verdict() {
    let (host, files) = workspace(&SHUTTLE);
    let (plan, text) = &files[2];
    let analysis = host.analysis();
    let hover = |needle: &str, skip| analysis.hover(*plan, at(text, needle, 0, skip)).unwrap().unwrap();

    let first = hover("(drive r home", 2);
    assert_eq!(&text[first.range], "0.000: (drive r home dock) [5.000]");
    insta::assert_snapshot!("plan_hover_valid_step", first.markdown);

    let second = hover("yard", 0);
    assert_eq!(&text[second.range], "5.010: (drive r yard depot) [5.000]");
    insta::assert_snapshot!("plan_hover_invalid_step", second.markdown);

    let honk = hover("honk", 0);
    assert!(honk.markdown.starts_with("```pddl\naction (honk ?r - robot)\n```"), "{}", honk.markdown);
    assert!(honk.markdown.contains("\n\nat 6.000\n\n"), "{}", honk.markdown);

    // Nothing on the comment line.
    assert_eq!(analysis.hover(*plan, at(text, "first drive", 0, 0)).unwrap(), None);
}

/// A sequential plan (no times, no ids): a step is placed by its order in the
/// file, in words that do not read as a step's name.
#[test]
fn hover_on_a_sequential_step_gives_its_place_in_the_order() {
    let (host, _) = workspace(&SHUTTLE[..2]);
    let mut host = host;
    let text = "(drive r home dock)\n(drive r dock yard)\n(honk r)\n";
    let plan = host.set_file_text("w/problem.plan", text);
    let analysis = host.analysis();
    let hover = |needle: &str| analysis.hover(plan, at(text, needle, 0, 1)).unwrap().unwrap().markdown;
    assert!(
        hover("(drive r home").contains("untimed (sequential: 1st in the plan's order)"),
        "{}",
        hover("(drive r home")
    );
    assert!(hover("(drive r dock").contains("untimed (sequential: 2nd in the plan's order)"));
    assert!(hover("(honk").contains("untimed (sequential: 3rd in the plan's order)"));
}

/// A JSON plan: the step's flexibility; a plan without a problem beside it is
/// not validated, and says so.
#[test]
fn hover_on_a_json_step_and_on_a_plan_without_its_problem() {
    let (host, files) = workspace(&SHUTTLE);
    let (json, text) = &files[3];
    let h = host.analysis().hover(*json, at(text, "\"drive\"", 0, 1)).unwrap().unwrap();
    assert!(h.markdown.contains("durative action (drive ?r - robot ?from ?to - place)"), "{}", h.markdown);
    assert!(
        h.markdown.contains("from 0.000 to 5.000 (duration 5.000); may start from 0.000 to 2.500"),
        "{}",
        h.markdown
    );
    assert!(h.markdown.ends_with("**valid**"), "{}", h.markdown);

    let (host, files) = workspace(&SHUTTLE[2..3]);
    let (plan, text) = &files[0];
    let h = host.analysis().hover(*plan, at(text, "(drive", 0, 1)).unwrap().unwrap();
    assert!(h.markdown.starts_with("```pddl\n(drive r home dock)\n```"), "{}", h.markdown);
    assert!(h.markdown.ends_with("**not validated**: no problem found for this plan"), "{}", h.markdown);
}

/// Go to definition from a plan: the action, a constant of the domain, an
/// object of the problem.
#[test]
fn definition_from_a_plan_step_goes_to_the_domain_and_the_problem() {
    let (host, files) = workspace(&SHUTTLE);
    let (plan, text) = &files[2];
    let analysis = host.analysis();
    let goto = |needle: &str, nth| {
        let target = analysis.goto_definition(*plan, at(text, needle, nth, 1)).unwrap().expect(needle);
        let path = analysis.file_path(target.file).unwrap();
        let file_text = &files.iter().find(|(f, _)| *f == target.file).unwrap().1;
        (path, file_text[target.range].to_string(), target.range.start())
    };
    let (path, name, start) = goto("drive", 1);
    assert_eq!((path.as_str(), name.as_str()), ("w/domain.pddl", "drive"));
    assert_eq!(start, at(&files[0].1, "(:durative-action drive", 0, 18));
    assert_eq!(goto("depot", 0).1, "depot", "a constant of the domain");
    let (path, name, _) = goto(" yard", 0);
    assert_eq!((path.as_str(), name.as_str()), ("w/problem.pddl", "yard"));
    assert_eq!(goto("honk", 0).1, "honk");
}

/// An IPC 2020 hierarchical plan: hover on an abstract step shows its task
/// and method; go to definition leads from the task to the task, from the
/// method to the method, and from a listed subtask id to that step.
#[test]
fn hierarchical_plan_steps_lead_to_tasks_and_methods() {
    let (host, files) = workspace(&[
        "tests/validate-htn/models/transport.hddl",
        "tests/validate-htn/models/transport-1.hddl",
        "tests/validate-htn/valid-transport.plan",
    ]);
    // The plan is named after its problem so that it is found beside it.
    let mut host = host;
    let text = files[2].1.clone();
    let plan = host.set_file_text("w/transport-1.plan", text.as_str());
    let domain = &files[0].1;
    let analysis = host.analysis();

    let h = analysis.hover(plan, at(&text, "9 deliver p1 c", 0, 3)).unwrap().unwrap();
    assert_eq!(&text[h.range], "9 deliver p1 c -> m-deliver 10 1 11 3");
    insta::assert_snapshot!("plan_hover_abstract_step", h.markdown);
    let h = analysis.hover(plan, at(&text, "0 drive truck depot b", 0, 3)).unwrap().unwrap();
    assert!(h.markdown.contains("untimed (step 0)"), "{}", h.markdown);
    assert!(h.markdown.ends_with("**valid**"), "{}", h.markdown);

    let goto = |needle: &str, nth, skip| {
        let target = analysis.goto_definition(plan, at(&text, needle, nth, skip)).unwrap().expect(needle);
        (analysis.file_path(target.file).unwrap(), target.range)
    };
    let (path, range) = goto("deliver p1", 0, 0);
    assert_eq!((path.as_str(), &domain[range]), ("w/transport.hddl", "deliver"));
    assert!(domain[..usize::from(range.start())].ends_with("(:task "), "the task, not a method");
    let (path, range) = goto("m-deliver", 0, 0);
    assert_eq!((path.as_str(), &domain[range]), ("w/transport.hddl", "m-deliver"));
    // `11` in `-> m-deliver 10 1 11 3`: the step with id 11.
    let (path, range) = goto("m-deliver 10 1 11", 0, 15);
    assert_eq!((path.as_str(), &text[range]), ("w/transport-1.plan", "11"));
    assert!(text[usize::from(range.start())..].starts_with("11 get-to truck c"));
}

/// The diagnostics of a fixture folder of `tests/reading` (a domain and a
/// problem), as `code message`; `edit` changes the problem's text first.
fn check_reading(dir: &str, edit: impl Fn(String) -> String) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/reading").join(dir);
    let mut host = AnalysisHost::new();
    let mut files = Vec::new();
    for name in ["domain.pddl", "problem.pddl"] {
        let mut text = std::fs::read_to_string(root.join(name)).unwrap();
        if name == "problem.pddl" {
            text = edit(text);
        }
        files.push(host.set_file_text(&format!("{dir}/{name}"), text));
    }
    let analysis = host.analysis();
    files
        .iter()
        .flat_map(|&f| analysis.diagnostics(f).unwrap())
        .map(|d| format!("{} {}", d.code.id, d.message))
        .collect()
}

/// On an ordinary domain where nobody meant a position family (no HiPOP
/// extension, no move action), the candidates that are not families are not
/// reported (I0307 fired on every problem of IPC blocksworld and airport);
/// hover still explains them. With a HiPOP extension, they are reported.
#[test]
fn family_notes_only_where_a_family_was_likely_meant() {
    assert_eq!(check_reading("family-notes", |t| t), Vec::<String>::new());
    let h = hover("tests/reading/family-notes", "domain.pddl", "(on ?b ?on", 1);
    assert!(h.contains("`on ? *` is not a position family"), "{h}");
    let with_allowed =
        check_reading("family-notes", |t| t.replace("(:goal", "(:allowed-actions move)\n  (:goal"));
    let notes: Vec<&String> = with_allowed.iter().filter(|d| d.starts_with("I0307")).collect();
    assert_eq!(notes.len(), 2, "{with_allowed:#?}");
}

/// A family of one argument has no key: the note names the initial state,
/// not an empty name (it said "`` has 2 positions"). Shown because `move`
/// is a move action of the family.
#[test]
fn a_family_of_one_argument_is_not_an_empty_name() {
    let diags = check_reading("one-argument-family", |t| t);
    assert_eq!(
        diags,
        ["I0307 `at-robby *` is not a position family (Definition 12, property 1): the initial state has 2 \
          positions: `(at-robby rooma)` and `(at-robby roomb)`; hipop does not use position reasoning for it"]
    );
}

/// Instances whose duration is undefined are never applied: they are not
/// move actions of a family (the road a → b has no distance: 2 moves, not 3).
#[test]
fn instances_without_a_duration_are_not_moves() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/planner/duration-undefined-for-some-moves.pddl");
    let mut host = AnalysisHost::new();
    let f = host.set_file_text("roads.pddl", std::fs::read_to_string(path).unwrap());
    let explained = host.analysis().explain_families(f).unwrap().concat();
    assert!(explained.contains("move actions: `move` (2 ground moves)"), "{explained}");
}
