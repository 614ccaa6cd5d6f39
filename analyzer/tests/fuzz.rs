//! The parser and the analysis never panic, whatever the input: random bytes,
//! long runs of one character and deep nesting, and random mutations of real
//! files (among them runs and deep nesting); and incremental re-parsing after
//! an edit gives exactly what parsing from scratch gives.

use std::path::Path;

use hipop_analyzer::{AnalysisHost, TextEdit, TextRange, TextSize, syntax};
use proptest::prelude::*;

/// Real files to mutate: the samples (always here) and a few corpus files (when present).
fn seeds() -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut paths = vec![
        root.join("samples/rover-mission/domain.hddl"),
        root.join("samples/rover-mission/problem.hddl"),
        root.join("samples/transport-htn/domain.hddl"),
    ];
    let corpora = root.join("../shared/corpora");
    for rel in [
        "ipc2002-temporal/rovers-time-automatic/domain.pddl",
        "ipc2002-temporal/zenotravel-time-automatic/domain.pddl",
        "ipc2020-hddl/partial-order/Transport/domain.hddl",
        "ipc2020-hddl/partial-order/Transport/pfile01.hddl",
        "hddl2.1/satellite/domain.hddl",
    ] {
        paths.push(corpora.join(rel));
    }
    let mut texts: Vec<String> = paths.iter().filter_map(|p| std::fs::read_to_string(p).ok()).collect();
    // A problem whose `:init` is long enough for the parser to group it.
    let mut big = String::from(
        "(define (problem big) (:domain rover-mission)\n  (:objects r1 - rover w1 w2 - waypoint)\n  (:init\n",
    );
    for i in 0..400 {
        big.push_str(&format!("    (at r1 w{}) (= (distance w1 w2) {i}.5)\n", 1 + i % 2));
    }
    big.push_str("  )\n  (:goal (at r1 w2)))\n");
    texts.push(big);
    texts
}

const PIECES: &[&str] = &[
    "(",
    ")",
    " ",
    "\n",
    ";",
    ":effect",
    ":action",
    "(:action a",
    "?x",
    "and",
    "not",
    "-",
    "é",
    "(at start",
    "=",
    "0.5",
];

/// Characters of long runs: parentheses, comments, quotes, signs, digits, a
/// two-byte and a four-byte character, spaces and line breaks.
const RUN_CHARS: &[char] = &['(', ')', ';', '"', '-', '7', '.', 'é', '😀', ' ', '\n', '\r', '?', ':'];

/// A run of `n` times one of [`RUN_CHARS`], or `n` nested lists with a head
/// (closed or not): what hostile or generated files are made of. The depths
/// go past `syntax::MAX_NESTING` (256).
#[derive(Debug, Clone)]
enum Hostile {
    Run(usize, usize),
    Nest { depth: usize, head: usize, closed: bool },
}

impl Hostile {
    fn text(&self) -> String {
        match *self {
            Hostile::Run(c, n) => RUN_CHARS[c].to_string().repeat(n),
            Hostile::Nest { depth, head, closed } => {
                let head = ["and ", "not ", "or ", "", ":action ", "forall (?x) ", "+ 1 "][head];
                let mut s = format!("({head}").repeat(depth);
                s.push_str("(p ?x)");
                if closed {
                    s.push_str(&")".repeat(depth));
                }
                s
            }
        }
    }
}

fn hostile() -> impl Strategy<Value = Hostile> {
    prop_oneof![
        (0..RUN_CHARS.len(), prop_oneof![1usize..300, 1usize..20_000]).prop_map(|(c, n)| Hostile::Run(c, n)),
        (prop_oneof![1usize..300, 250usize..262, 1usize..5_000], 0usize..7, any::<bool>())
            .prop_map(|(depth, head, closed)| Hostile::Nest { depth, head, closed }),
    ]
}

#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize, usize),
    Insert(usize, usize),
    Duplicate(usize, usize, usize),
    InsertHostile(usize, Hostile),
    /// Wraps the text between two offsets in this many lists.
    Wrap(usize, usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), 0usize..40).prop_map(|(a, n)| Mutation::Delete(a, n)),
        4 => (any::<usize>(), 0..PIECES.len()).prop_map(|(a, p)| Mutation::Insert(a, p)),
        4 => (any::<usize>(), 0usize..200, any::<usize>()).prop_map(|(a, n, b)| Mutation::Duplicate(a, n, b)),
        1 => (any::<usize>(), hostile()).prop_map(|(a, h)| Mutation::InsertHostile(a, h)),
        1 => (any::<usize>(), 0usize..400, prop_oneof![1usize..20, 250usize..300])
            .prop_map(|(a, n, k)| Mutation::Wrap(a, n, k)),
    ]
}

fn boundary(text: &str, mut at: usize) -> usize {
    at %= text.len() + 1;
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// The edits a mutation makes, in order: ranges of the text each leaves and
/// their replacements.
fn as_edits(text: &str, m: &Mutation) -> Vec<TextEdit> {
    let edit = |start: usize, end: usize, insert: String| TextEdit {
        range: TextRange::new(TextSize::from(start as u32), TextSize::from(end as u32)),
        insert,
    };
    match m {
        Mutation::InsertHostile(a, h) => {
            let s = boundary(text, *a);
            return vec![edit(s, s, h.text())];
        }
        &Mutation::Wrap(a, n, k) => {
            let s = boundary(text, a);
            let e = boundary(text, s + n.min(text.len() - s));
            // The `)` first: inserting the `(` would move it.
            return vec![edit(e, e, ")".repeat(k)), edit(s, s, "(".repeat(k))];
        }
        _ => {}
    }
    let (start, end, insert) = match *m {
        Mutation::Delete(a, n) => {
            let s = boundary(text, a);
            (s, boundary(text, s + n.min(text.len() - s)), String::new())
        }
        Mutation::Insert(a, p) => {
            let s = boundary(text, a);
            (s, s, PIECES[p].to_string())
        }
        Mutation::Duplicate(a, n, b) => {
            let s = boundary(text, a);
            let e = boundary(text, s + n.min(text.len() - s));
            let at = boundary(text, b);
            (at, at, text[s..e].to_string())
        }
        Mutation::InsertHostile(..) | Mutation::Wrap(..) => unreachable!("handled above"),
    };
    vec![edit(start, end, insert)]
}

/// A run whose plan achieves the goals `(p a)` and `(at r1 w1)` and refines
/// the task `(t a)`: what the editor's hints look for in any file.
fn some_run() -> hipop_analyzer::ide::PlanRun {
    use hipop_analyzer::planner::output::{SolvedLink, SolvedPlan, SolvedStep};
    let step = |id: usize, name: &str, args: &[&str], is_abstract: bool| SolvedStep {
        id,
        name: name.to_string(),
        args: args.iter().map(|a| a.to_string()).collect(),
        agents: vec!["r1".to_string()],
        start: 0.0,
        end: 1.0,
        duration: Some(1.0),
        durative: true,
        is_abstract,
        method: is_abstract.then(|| "m".to_string()),
        subtasks: if is_abstract { vec![0] } else { Vec::new() },
        bounds: [(0.0, 0.0), (1.0, 1.0)],
    };
    let link = |predicate: &str, args: &[&str]| SolvedLink {
        from: Some(0),
        to: None,
        predicate: predicate.to_string(),
        args: args.iter().map(|a| a.to_string()).collect(),
        negated: false,
    };
    let plan = SolvedPlan {
        domain: "d".to_string(),
        problem: "p".to_string(),
        hash: String::new(),
        steps: vec![step(0, "a", &["a"], false), step(1, "t", &["a"], true)],
        root: vec![1],
        causal_links: vec![link("p", &["a"]), link("at", &["r1", "w1"])],
        temporal_links: Vec::new(),
        makespan: 1.0,
    };
    hipop_analyzer::ide::PlanRun {
        status: hipop_analyzer::planner::Status::Solved,
        plan: Some(plan),
        stats: Default::default(),
        time_limit: None,
        flaws: 0,
        repair: None,
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2000)) {
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let mut host = AnalysisHost::new();
        let f = host.set_file_text("x.pddl", text.clone());
        let a = host.analysis();
        a.diagnostics(f).unwrap();
        a.document_symbols(f).unwrap();
        prop_assert_eq!(syntax::parse(&text).text(), text);
    }

    #[test]
    fn runs_and_deep_nesting_never_panic(
        parts in proptest::collection::vec(prop_oneof![
            2 => hostile().prop_map(|h| h.text()),
            1 => "[() ;:?a-z\n-]{0,40}",
        ], 1..6),
        probes in proptest::collection::vec(any::<usize>(), 3),
    ) {
        let text: String = parts.concat();
        let parse = syntax::parse(&text);
        prop_assert_eq!(parse.text(), text.clone());
        let mut host = AnalysisHost::new();
        let f = host.set_file_text("x.hddl", text.clone());
        let a = host.analysis();
        a.diagnostics(f).unwrap();
        a.document_symbols(f).unwrap();
        a.folding_ranges(f).unwrap();
        a.semantic_tokens(f).unwrap();
        a.code_actions(f, TextRange::up_to(TextSize::of(text.as_str()))).unwrap();
        if let Ok(once) = a.format(f).unwrap() {
            // Formatting is idempotent and keeps every atom, parenthesis and comment.
            prop_assert_eq!(hipop_analyzer::ide::format(&once), Ok(once.clone()));
            let significant = |t: &str| -> Vec<String> {
                syntax::parse(t)
                    .syntax()
                    .descendants_with_tokens()
                    .filter_map(|e| e.into_token())
                    .filter(|t| t.kind() != syntax::SyntaxKind::Whitespace)
                    .map(|t| t.text().trim_end().to_string())
                    .collect()
            };
            prop_assert_eq!(significant(&once), significant(&text));
        }
        let run = some_run();
        a.plan_hints(f, &run).unwrap();
        let plans = [("p".to_string(), run.plan.as_ref().unwrap())];
        for p in probes {
            let at = TextSize::from(boundary(&text, p) as u32);
            a.hover(f, at).unwrap();
            a.references(f, at, true).unwrap();
            a.document_highlights(f, at).unwrap();
            a.rename(f, at, "renamed").unwrap().ok();
            a.plan_hover(f, at, &plans).unwrap();
            a.completions(f, at).unwrap();
        }
    }

    #[test]
    fn mutated_real_files_never_panic_and_reparse_exactly(
        seed in 0usize..64,
        mutations in proptest::collection::vec(mutation(), 1..6),
        probes in proptest::collection::vec(any::<usize>(), 4),
    ) {
        let seeds = seeds();
        let original = &seeds[seed % seeds.len()];
        let mut incremental = AnalysisHost::new();
        let f = incremental.set_file_text("d.hddl", original.clone());
        incremental.analysis().diagnostics(f).unwrap();
        let mut text = original.clone();
        for m in &mutations {
            let edits = as_edits(&text, m);
            edits.iter().for_each(|e| e.apply(&mut text));
            incremental.apply_edits("d.hddl", edits).unwrap();
        }
        prop_assert_eq!(syntax::parse(&text).text(), text.clone());
        let mut scratch = AnalysisHost::new();
        let g = scratch.set_file_text("d.hddl", text.clone());
        let a = incremental.analysis();
        let b = scratch.analysis();
        let shown = |a: &hipop_analyzer::Analysis, f| {
            a.diagnostics(f)
                .unwrap()
                .iter()
                .map(|d| {
                    let related: Vec<_> = d.related.iter().map(|r| (r.range, r.message.clone())).collect();
                    let fix = d.fix.as_ref().map(|x| x.edits.iter().map(|(_, r, t)| (*r, t.clone())).collect::<Vec<_>>());
                    (d.code.id, d.range, d.message.clone(), related, fix)
                })
                .collect::<Vec<_>>()
        };
        prop_assert_eq!(shown(&a, f), shown(&b, g));
        for p in probes {
            let at = TextSize::from(boundary(&text, p) as u32);
            a.hover(f, at).unwrap();
            a.goto_definition(f, at).unwrap();
            a.references(f, at, true).unwrap();
        }
        a.document_symbols(f).unwrap();
        a.plan_hints(f, &some_run()).unwrap();
    }
}
