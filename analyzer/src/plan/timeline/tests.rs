//! Tests of the timelines: the layout (lanes, rows, times) on the fixtures of
//! `tests/plans/timeline/`, snapshots of both renderers, and no panic (and
//! well-formed SVG) on empty, untimed, zero-length, huge and malformed plans.

use proptest::prelude::*;

use super::*;
use crate::AnalysisHost;
use crate::plan::{NameMatching, read_plan};

const DOMAIN: &str = include_str!("../../../../tests/plans/timeline/domain.hddl");
const TEMPORAL: &str = include_str!("../../../../tests/plans/timeline/temporal.plan");
const HIERARCHICAL: &str = include_str!("../../../../tests/plans/timeline/hierarchical.plan");
const SEQUENTIAL: &str = include_str!("../../../../tests/plans/timeline/sequential.plan");

fn agents() -> AgentTable {
    let mut host = AnalysisHost::new();
    let file = host.set_file_text("domain.hddl", DOMAIN);
    host.analysis().plan_agents(file, NameMatching::CaseInsensitive).expect("not cancelled")
}

fn layout(plan: &str) -> Timeline {
    timeline(&read_plan(plan, None), &agents())
}

/// Each lane's name and rows, as `kind: key key…`.
fn rows(tl: &Timeline) -> Vec<String> {
    let mut out = Vec::new();
    for lane in &tl.lanes {
        for row in &lane.rows {
            let kind = match row.kind {
                RowKind::Abstract { depth } => format!("abstract {depth}"),
                RowKind::Actions => "actions".to_string(),
            };
            let keys: Vec<String> = row.bars.iter().map(|&b| tl.bars[b].key.to_string()).collect();
            out.push(format!("{} {kind}: {}", lane.name, keys.join(" ")));
        }
    }
    out
}

fn bar<'t>(tl: &'t Timeline, call: &str) -> &'t Bar {
    tl.bars.iter().find(|b| b.call == call).unwrap_or_else(|| panic!("no bar {call}"))
}

/// Parses `svg` as XML, and checks it is one `<svg>` with a rectangle per step and lane.
fn assert_well_formed(svg: &str, tl: &Timeline) {
    let doc = roxmltree::Document::parse(svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    let drawn: usize = tl.bars.iter().map(|b| b.lanes.len()).sum();
    let titled = doc.descendants().filter(|n| n.has_tag_name("g") && n.first_element_child().is_some());
    let rects_in_groups: usize = titled
        .filter(|g| g.first_element_child().is_some_and(|c| c.has_tag_name("title")))
        .map(|g| g.children().filter(|c| c.has_tag_name("rect")).count())
        .sum();
    assert_eq!(rects_in_groups, drawn, "one rectangle per step and lane");
}

#[test]
fn lanes_in_order_of_first_appearance_with_the_unknown_agent_last() {
    let tl = layout(TEMPORAL);
    assert!(tl.timed);
    let names: Vec<&str> = tl.lanes.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["r1", "r2", NO_AGENT]);
    // The meeting is in both robots' lanes; it overlaps each one's observation.
    let meet = bar(&tl, "(communicate r1 r2 hill lake)");
    assert_eq!(meet.lanes, [0, 1]);
    assert_eq!(
        rows(&tl),
        ["r1 actions: 1 3", "r1 actions: 5", "r2 actions: 2 4", "r2 actions: 5", "(no agent) actions: 6"]
    );
    assert_eq!((tl.start, tl.end, tl.makespan), (0.0, 32.0, 32.0));
    assert!(tl.undrawn.is_empty());
}

#[test]
fn abstract_steps_are_bands_above_their_subtasks() {
    let tl = layout(HIERARCHICAL);
    let own = bar(&tl, "(patrol r1 base hill t1)");
    assert_eq!((own.start, own.end, own.timing), (0.0, 25.01, Timing::Given));
    assert_eq!(own.method.as_deref(), Some("patrol-go"));
    // No annotation: the span of its subtasks.
    let derived = bar(&tl, "(patrol r2 base lake t2)");
    assert_eq!((derived.start, derived.end, derived.timing), (0.0, 10.01 + 15.0, Timing::Subtasks));
    assert_eq!(
        rows(&tl),
        [
            "r1 abstract 0: 1",
            "r1 actions: 3 5",
            "r1 actions: 7",
            "r2 abstract 0: 2",
            "r2 actions: 4 6",
            "r2 actions: 7",
            "(no agent) actions: 8"
        ]
    );
    // The makespan is the actions'.
    assert_eq!(tl.makespan, 32.0);
}

#[test]
fn an_abstract_step_without_agents_is_in_its_subtasks_lanes_and_nested_ones_deeper() {
    let plan = "==>\n0 move r1 base hill\n1 move r2 base lake\n\
                root 4\n4 mission -> both 2 3\n2 patrol r1 base hill t1 -> m 0\n\
                3 patrol r2 base lake t2 -> m 1\n<==\n";
    let tl = layout(plan);
    assert!(!tl.timed);
    let mission = bar(&tl, "(mission)");
    assert_eq!((mission.lanes.clone(), mission.depth), (vec![0, 1], 0));
    assert_eq!(bar(&tl, "(patrol r2 base lake t2)").depth, 1);
    assert_eq!(
        rows(&tl),
        [
            "r1 abstract 0: 1",
            "r1 abstract 1: 2",
            "r1 actions: 3",
            "r2 abstract 0: 1",
            "r2 abstract 1: 4",
            "r2 actions: 5"
        ]
    );
}

#[test]
fn untimed_steps_are_placed_at_their_index() {
    let tl = layout(SEQUENTIAL);
    assert!(!tl.timed);
    let places: Vec<(f64, f64)> = tl.bars.iter().map(|b| (b.start, b.end)).collect();
    assert_eq!(places, [(0.0, 1.0), (1.0, 2.0), (2.0, 3.0), (3.0, 4.0), (4.0, 5.0), (5.0, 6.0)]);
    assert!(tl.bars.iter().all(|b| b.timing == Timing::Position));
    // In a timed plan, a step without a time is where VAL executes it.
    let tl = layout("0.5: (move r1 base hill) [10]\n(upload t1)\n(upload t2)\n");
    let places: Vec<(f64, f64)> = tl.bars.iter().map(|b| (b.start, b.end)).collect();
    assert_eq!(places, [(0.5, 10.5), (1.0, 1.0), (2.0, 2.0)]);
}

#[test]
fn instantaneous_steps_do_not_share_a_row_with_a_step_starting_at_their_time() {
    let tl =
        layout("0: (move r1 a b) [10]\n10: (move r1 b c)\n10: (move r1 b d) [5]\n15: (move r1 d e) [1]\n");
    assert_eq!(rows(&tl), ["r1 actions: 1 2 4", "r1 actions: 3"]);
}

#[test]
fn gantt_unicode() {
    let tl = layout(TEMPORAL);
    insta::assert_snapshot!(gantt_text(&tl, &GanttOptions { width: 80, ascii: false }));
}

#[test]
fn gantt_ascii() {
    let tl = layout(TEMPORAL);
    let text = gantt_text(&tl, &GanttOptions { width: 80, ascii: true });
    assert!(text.is_ascii(), "{text}");
    insta::assert_snapshot!(text);
}

#[test]
fn gantt_hierarchical() {
    let tl = layout(HIERARCHICAL);
    insta::assert_snapshot!(gantt_text(&tl, &GanttOptions { width: 100, ascii: false }));
    let ascii = gantt_text(&tl, &GanttOptions { width: 100, ascii: true });
    assert!(ascii.is_ascii(), "{ascii}");
    insta::assert_snapshot!("gantt_hierarchical_ascii", ascii);
}

#[test]
fn gantt_untimed() {
    let tl = layout(SEQUENTIAL);
    insta::assert_snapshot!(gantt_text(&tl, &GanttOptions { width: 60, ascii: false }));
}

#[test]
fn gantt_rows_have_the_same_width() {
    for plan in [TEMPORAL, HIERARCHICAL, SEQUENTIAL] {
        let tl = layout(plan);
        for width in [0, 30, 80, 200] {
            for ascii in [false, true] {
                let text = gantt_text(&tl, &GanttOptions { width, ascii });
                let chart: Vec<usize> = text
                    .lines()
                    .skip(1)
                    .take_while(|l| !l.is_empty() && !l.contains("action"))
                    .map(|l| l.chars().count())
                    .collect();
                assert!(chart.len() > 2 && chart.iter().all(|&w| w == chart[0]), "{text}");
                assert!(width < 40 || chart[0] == width, "{width}: {text}");
            }
        }
    }
}

#[test]
fn svg_temporal() {
    let tl = layout(TEMPORAL);
    let svg = svg(&tl);
    assert_well_formed(&svg, &tl);
    insta::assert_snapshot!(svg);
}

#[test]
fn svg_hierarchical() {
    let tl = layout(HIERARCHICAL);
    let svg = svg(&tl);
    assert_well_formed(&svg, &tl);
    assert!(svg.contains("patrol-go"), "the tooltip names the method");
    insta::assert_snapshot!(svg);
}

#[test]
fn svg_escapes_names() {
    let plan = r#"{"format": "hipop-plan", "version": 1, "steps": [
        {"id": 0, "name": "a<b&c", "args": ["\"x'", "]]>"], "agents": ["r<1>"], "start": 0, "duration": 5},
        {"id": 1, "name": "ctl\u0001", "args": [], "agents": ["r&2"], "start": 1, "duration": 2}]}"#;
    let parsed = read_plan(plan, None);
    assert!(!parsed.has_errors(), "{:?}", parsed.diagnostics);
    let tl = timeline(&parsed, &AgentTable::default());
    let svg = svg(&tl);
    assert_well_formed(&svg, &tl);
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let texts: Vec<&str> = doc.descendants().filter_map(|n| n.text()).collect();
    assert!(texts.contains(&"r<1>") && texts.contains(&"r&2"), "{texts:?}");
    assert!(texts.iter().any(|t| t.starts_with("0 (a<b&c \"x' ]]>)")), "{texts:?}");
}

/// Plans that are hard to draw: each is laid out and drawn without panic,
/// and its SVG is well-formed.
#[test]
fn no_panic_on_degenerate_plans() {
    let cases = [
        "",
        "; nothing\n",
        "0: (move r1 a b) [0]\n0: (move r1 a c) [0]\n0: (upload t1)\n",
        "(move r1 a b)\n",
        "0: (move r1 a b) [1e300]\n1e300: (move r2 a b) [1e300]\n",
        "1.7e308: (move r1 a b) [1.7e308]\n0: (move r2 a b) [1]\n",
        "100000000000000000000: (move r1 a b) [1]\n100000000000000000001: (move r1 b c) [1]\n",
        "0: (move r1 a b) [0.000001]\n1000000: (move r1 b c) [1]\n",
        "5: (move r1 a b) [-10]\n",
        // A decomposition cycle, and an abstract step without subtasks nor times.
        "==>\n0 move r1 a b\nroot 1\n1 t -> m 2 0\n2 u -> m 1\n3 lone -> m\n<==\n",
        "==>\nroot 1\n1 t -> m\n<==\n;@ 1 3 [2]\n",
    ];
    let agents = agents();
    for case in cases {
        let plan = read_plan(case, None);
        let tl = timeline(&plan, &agents);
        for width in [0, 1, 50, 120] {
            for ascii in [false, true] {
                let text = gantt_text(&tl, &GanttOptions { width, ascii });
                assert!(!text.is_empty(), "{case}");
            }
        }
        assert_well_formed(&svg(&tl), &tl);
    }
    let empty = timeline(&read_plan("", None), &agents);
    assert!(empty.bars.is_empty() && empty.lanes.is_empty());
    assert_eq!(gantt_text(&empty, &GanttOptions::default()), "no steps to draw\n");
    let cycle = timeline(&read_plan(cases[9], None), &agents);
    assert!(cycle.undrawn.contains(&3), "the lone abstract step is not drawn: {:?}", cycle.undrawn);
}

#[test]
fn colours_are_stable_ignore_case_and_differ_in_a_picture() {
    assert_eq!(svg::preferred_colour("move"), svg::preferred_colour("MOVE"));
    // `move` and `upload` prefer the same colour: the second gets the next one.
    assert_eq!(svg::preferred_colour("move"), svg::preferred_colour("upload"));
    let palette = svg::colours(&layout(TEMPORAL));
    let mut used: Vec<&str> = palette.values().copied().collect();
    used.sort_unstable();
    used.dedup();
    assert_eq!(used.len(), 4, "{palette:?}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Random timed plans of three robots: drawn without panic, chart rows
    /// of equal width, SVG well-formed.
    #[test]
    fn random_plans_are_drawn(
        steps in prop::collection::vec((0u8..3, 0u8..3, -2.0f64..1e4, prop::option::of(0.0f64..500.0)), 0..40),
        width in 0usize..160,
    ) {
        let mut text = String::new();
        for (robot, action, start, duration) in &steps {
            let name = ["move", "observe", "upload"][*action as usize];
            text.push_str(&format!("{start}: ({name} r{robot} a b)"));
            if let Some(d) = duration {
                text.push_str(&format!(" [{d}]"));
            }
            text.push('\n');
        }
        let tl = timeline(&read_plan(&text, None), &AgentTable::default());
        let chart = gantt_text(&tl, &GanttOptions { width, ascii: false });
        let lines: Vec<usize> = chart.lines().skip(1).take_while(|l| !l.is_empty() && l.contains(['│', '┌', '└', '├'])).map(|l| l.chars().count()).collect();
        prop_assert!(lines.iter().all(|&w| w == lines[0]), "{}", chart);
        let svg = svg(&tl);
        prop_assert!(roxmltree::Document::parse(&svg).is_ok());
    }
}
