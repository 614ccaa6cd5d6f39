//! Hostile inputs: deep nesting, runs of extra parentheses, thousands of
//! diagnostics, wide characters.

use super::*;

/// The codes of `hipop check --format json` on one generated file, and the output.
fn check_generated(name: &str, text: &str, extra: &[&str]) -> (Vec<String>, Value, Output) {
    let dir = TempDir::new(name);
    let path = dir.0.join(format!("{name}.pddl"));
    std::fs::write(&path, text).expect("generated file written");
    let mut args = vec!["check", path.to_str().expect("UTF-8 temp path"), "--format", "json"];
    args.extend_from_slice(extra);
    let o = hipop(&args);
    assert_no_panic(&o);
    let doc: Value =
        serde_json::from_str(&stdout(&o)).unwrap_or_else(|e| panic!("{name}: {e}: {}", stderr(&o)));
    let codes = doc["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .map(|d| d["code"].as_str().expect("a code").to_string())
        .collect();
    (codes, doc, o)
}

/// A million nested lists, or a million `(`, are one located error each, not
/// a stack overflow: lists deeper than 256 are kept as text (E0007).
#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let n = 1_000_000;
    let precondition = format!("{}(p ?x){}", "(and ".repeat(n), ")".repeat(n));
    let domain = format!(
        "(define (domain deep) (:predicates (p ?x))\n  (:action a :parameters (?x) :precondition {precondition} :effect (p ?x)))\n"
    );
    let (codes, doc, o) = check_generated("deep-and", &domain, &[]);
    assert_eq!(status(&o), 1);
    assert_eq!(codes, ["E0007"]);
    let location = &doc["diagnostics"][0]["location"];
    // The `(and` one level too deep: define, action and 254 `(and` enclose it;
    // the first `(and` is at column 45.
    let start = &location["start"];
    assert_eq!((start["line"].as_u64(), start["column"].as_u64()), (Some(2), Some(45 + 5 * 254)));

    for n in [200_000, 1_000_000] {
        let (codes, doc, o) = check_generated("open-parens", &"(".repeat(n), &[]);
        assert_eq!(status(&o), 1);
        assert_eq!(codes, ["E0003", "E0007", "E0001"], "{n}");
        assert_eq!(
            doc["diagnostics"][2]["message"],
            format!("missing {n} `)`: a list and the lists around it are not closed")
        );
    }
}

/// 200,000 `)` are one E0002 (a run of the same error is reported once, with
/// its count), in every format.
#[test]
fn a_run_of_extra_parens_is_one_diagnostic() {
    let (codes, doc, o) = check_generated("close-parens", &")".repeat(200_000), &[]);
    assert_eq!(status(&o), 1);
    assert_eq!(codes, ["E0002"]);
    assert_eq!(
        doc["diagnostics"][0]["message"],
        "unexpected `)` (200000 in a row): there is no open `(` to close"
    );
    assert_eq!(doc["diagnostics"][0]["location"]["end"]["column"], 200_001);
    let dir = TempDir::new("close-parens-human");
    let path = dir.0.join("close.pddl");
    std::fs::write(&path, ")".repeat(200_000)).expect("generated file written");
    let o = hipop(&["check", path.to_str().expect("UTF-8 temp path"), "--color", "never"]);
    assert_eq!(status(&o), 1);
    let err = stderr(&o);
    assert_eq!(err.matches("error[E0002]").count(), 1);
    assert!(
        err.ends_with("checked 1 file: 1 error, 0 warnings\n"),
        "{}",
        &err[err.len().saturating_sub(300)..]
    );
}

/// At most 200 diagnostics per file are printed (`--max-diagnostics`), errors
/// first, then one I0008 with how many more; the summary counts them all.
#[test]
fn at_most_max_diagnostics_per_file_are_printed() {
    // 1000 extra `)` that no run joins (an atom between), and the atoms: 1001 errors.
    let text = ") x".repeat(1000);
    let (codes, doc, o) = check_generated("many", &text, &[]);
    assert_eq!(status(&o), 1);
    assert_eq!(codes.len(), 201);
    assert!(codes[..200].iter().all(|c| c == "E0002" || c == "E0003"), "{codes:?}");
    assert_eq!(codes[200], "I0008");
    assert_eq!(
        doc["diagnostics"][200]["message"],
        "801 more diagnostics in this file not shown (801 errors), the first of them here: hipop shows at most 200 per file"
    );
    assert_eq!(doc["summary"]["errors"], 1001);

    let (codes, _, _) = check_generated("many", &text, &["--max-diagnostics", "3"]);
    assert_eq!(codes, ["E0002", "E0003", "E0002", "I0008"]);
    let (codes, _, _) = check_generated("many", &text, &["--max-diagnostics", "0"]);
    assert_eq!(codes.len(), 1001);

    let o = hipop(&[
        "check",
        "tests/limits/five-undefined-predicates.pddl",
        "--max-diagnostics",
        "2",
        "--color",
        "never",
    ]);
    assert_eq!(status(&o), 1);
    let err = stderr(&o);
    assert_eq!(err.matches("error[E0102]").count(), 2, "{err}");
    assert!(
        err.contains("note[I0008]: 4 more diagnostics in this file not shown (3 errors, 1 warning)"),
        "{err}"
    );
    assert!(err.ends_with("checked 1 file: 5 errors, 1 warning\n"), "{err}");
}

/// Columns count characters, not bytes, after characters of two and four bytes.
#[test]
fn columns_count_characters() {
    let line =
        "  (:action a :parameters (?x) :precondition (and (p ?x) (é ?x) (😀 ?x) (q ?x)) :effect (p ?x)))";
    let text = format!("(define (domain d) (:predicates (p ?x)) ; ö ü\n{line}\n");
    let (codes, doc, _) = check_generated("columns", &text, &[]);
    assert_eq!(codes, ["E0102", "E0102", "E0102"]);
    for (d, name) in doc["diagnostics"].as_array().expect("diagnostics").iter().zip(["é", "😀", "q"]) {
        let byte = line.find(&format!("({name} ")).expect("the name") + 1;
        let column = line[..byte].chars().count() as u64 + 1;
        let location = &d["location"];
        assert_eq!(location["start"]["line"], 2);
        assert_eq!(location["start"]["column"].as_u64(), Some(column), "{name}");
        assert_eq!(location["end"]["column"].as_u64(), Some(column + 1), "{name}");
    }
}

/// A line longer than 400 bytes (a generated problem on one line) is shown
/// as a window around each diagnostic, between `…`: the human output stays
/// a few hundred bytes per diagnostic, and the header's line and column are
/// the file's (those of the JSON output), after characters of two bytes.
#[test]
fn a_long_line_is_shown_as_a_window() {
    let actions: Vec<String> = (0..3000)
        .map(|i| format!("(:action a{i} :parameters (?x) :precondition (and (pé ?x) (r ?x)) :effect (q))"))
        .collect();
    let text = format!(
        "(define (domain d) (:requirements :strips) (:predicates (pé ?x) (q)) {})",
        actions.join(" ")
    );
    let (codes, doc, _) = check_generated("long-line", &text, &[]);
    assert_eq!(codes.len(), 201);
    let dir = TempDir::new("long-line-human");
    let path = dir.0.join("long.pddl");
    std::fs::write(&path, &text).expect("generated file written");
    let o = hipop(&["check", path.to_str().expect("UTF-8 temp path"), "--color", "never"]);
    assert_eq!(status(&o), 1);
    let err = stderr(&o);
    assert!(err.len() < 200 * 1000, "{} bytes printed for 200 diagnostics", err.len());
    let blocks: Vec<&str> = err.split("error[E0102]").skip(1).collect();
    assert_eq!(blocks.len(), 200);
    for (block, d) in blocks.iter().zip(doc["diagnostics"].as_array().expect("diagnostics")) {
        let start = &d["location"]["start"];
        let header = format!("long.pddl:{}:{}\n", start["line"], start["column"]);
        assert!(block.contains(&header), "{header} in {block}");
        let lines: Vec<&str> = block.lines().collect();
        let source = lines.iter().find(|l| l.starts_with("1 │ ")).expect("the source line");
        let carets = lines.iter().find(|l| l.contains('^')).expect("the carets");
        assert!(source.starts_with("1 │ …") && source.ends_with('…'), "{source}");
        assert!(source.chars().count() < 2 * 80 + 20, "{source}");
        // The caret is under the undefined predicate.
        let at = carets.chars().position(|c| c == '^').expect("a caret");
        assert_eq!(source.chars().skip(at).take(4).collect::<String>(), "r ?x", "{source}\n{carets}");
    }
}

/// A label longer than a window (200,000 `)` in a row) is underlined on its
/// first bytes: the output does not grow with the run.
#[test]
fn a_long_label_is_underlined_on_its_first_bytes() {
    let dir = TempDir::new("long-label");
    let path = dir.0.join("close.pddl");
    std::fs::write(&path, ")".repeat(200_000)).expect("generated file written");
    let o = hipop(&["check", path.to_str().expect("UTF-8 temp path"), "--color", "never"]);
    let err = stderr(&o);
    assert!(err.len() < 2000, "{} bytes printed", err.len());
    assert!(err.contains("close.pddl:1:1\n"), "{err}");
}
