use super::*;
use proptest::prelude::*;

fn errors(text: &str) -> Vec<String> {
    let p = parse(text);
    assert_eq!(p.text(), text, "parse must be lossless");
    p.errors
        .iter()
        .map(|e| format!("{}..{}: {}", u32::from(e.range.start()), u32::from(e.range.end()), e.message))
        .collect()
}

const DOMAIN: &str = "(define (domain d)
  (:predicates (p ?x) (q ?x))
  (:action a :parameters (?x) :precondition (and (p ?x)) :effect (q ?x))
  (:action b :parameters (?x) :precondition (q ?x) :effect (p ?x)))
";

const PROBLEM: &str = "(define (problem p) (:domain d)
  (:objects a b - thing)
  (:init (p a) (q b) (= (f a) 3))
  (foo) (:goal (and (p b))))
";

/// A problem whose `:init` is long enough to be grouped.
fn big_problem() -> String {
    let mut s = String::from("(define (problem big) (:domain d)\n  (:init\n");
    for i in 0..700 {
        s.push_str(&format!("    (p o{i}) ; fact {i}\n"));
    }
    s.push_str("  )\n  (:goal (p o1)))\n");
    s
}

#[test]
fn a_large_init_built_on_two_threads_is_the_sequential_tree() {
    let mut text = String::from("(define (problem big) (:domain d)\n  (:objects a b - thing)\n  (:init\n");
    for i in 0..6000 {
        text.push_str(&format!("    (road a b) (= (distance a b) {i}.5) ; note {i}\n"));
    }
    text.push_str("  )\n  (:goal (road a b)))\n");
    let parallel = parse(&text);
    let tokens = super::lexer::lex(&text);
    let mut sequential = parser::Parser::new(&text, &tokens);
    sequential.parallel = false;
    let (green, errors) = sequential.parse_file();
    assert_eq!(parallel.text(), text);
    assert!(errors.is_empty() && parallel.errors.is_empty());
    assert_eq!(parallel.green, Green(green));
}

#[test]
fn long_lists_are_grouped_and_print_back() {
    let text = big_problem();
    let p = parse(&text);
    assert_eq!(p.text(), text);
    assert!(p.errors.is_empty());
    let define = p.syntax().children().next().unwrap();
    let init = define.children().find(|n| List::cast(n.clone()).is_some_and(|l| l.head_is(":init"))).unwrap();
    let groups = init.children().filter(|n| n.kind() == SyntaxKind::Group).count();
    assert!(groups >= 2, "{groups} groups");
    // The views see through groups.
    assert_eq!(List::cast(init).unwrap().elements().count(), 701);
}

#[test]
fn well_formed_file_has_no_error() {
    assert!(errors(DOMAIN).is_empty());
}

#[test]
fn missing_paren_before_next_item_is_reported_once() {
    let text = DOMAIN.replace("(and (p ?x)) :effect (q ?x))", "(and (p ?x)) :effect (q ?x)");
    let errs = errors(&text);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert!(errs[0].contains("missing `)`: `(:action` is not closed"), "{errs:?}");
    // The next action is still a separate item of the define.
    let root = parse(&text).syntax();
    let define = root.children().next().unwrap();
    assert_eq!(define.children().count(), 4);
}

#[test]
fn missing_paren_in_formula_before_field() {
    let text = DOMAIN.replace("(and (p ?x)) :effect", "(and (p ?x) :effect");
    let errs = errors(&text);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert!(errs[0].contains("`(and` is not closed"), "{errs:?}");
}

#[test]
fn extra_paren_before_field_is_reported_once() {
    let text = DOMAIN.replace("(and (p ?x)) :effect", "(and (p ?x))) :effect");
    let errs = errors(&text);
    let at = text.find("))) :effect").unwrap() + 2;
    assert_eq!(
        errs,
        vec![format!("{at}..{}: unexpected `)`: it closes `(:action` before its end, which follows", at + 1)]
    );
}

#[test]
fn extra_paren_closing_define_early() {
    let text = DOMAIN.replace("(q ?x))\n  (:action b", "(q ?x)))\n  (:action b");
    let errs = errors(&text);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert!(errs[0].contains("closes `(define`"), "{errs:?}");
}

#[test]
fn extra_paren_closing_a_section_before_a_stray_list() {
    let text = "(define (problem p)\n (:init (p a)) (q b))\n (:goal (p a)))";
    let errs = errors(text);
    assert_eq!(errs, vec!["33..34: unexpected `)`: it closes `(:init` before its end, which follows"]);
}

#[test]
fn stray_paren_at_end_and_missing_at_eof() {
    assert_eq!(errors("(a))"), vec!["3..4: unexpected `)`: there is no open `(` to close"]);
    let errs = errors("(define (domain d)\n (:predicates (p))");
    assert_eq!(errs.len(), 1);
    assert!(errs[0].starts_with("36..37: missing `)`: `(define` is not closed"), "{errs:?}");
}

/// How deep lists nest in a tree, walked without recursion.
fn list_depth(p: &Parse) -> usize {
    let (mut depth, mut deepest) = (0usize, 0usize);
    for event in p.syntax().preorder() {
        match event {
            rowan::WalkEvent::Enter(n) if n.kind() == SyntaxKind::List => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            rowan::WalkEvent::Leave(n) if n.kind() == SyntaxKind::List => depth -= 1,
            _ => {}
        }
    }
    deepest
}

fn kinds(p: &Parse) -> Vec<SyntaxErrorKind> {
    p.errors.iter().map(|e| e.kind).collect()
}

#[test]
fn a_large_text_with_a_wide_character_in_its_middle_is_lexed() {
    // Lexed on two threads from 64 KiB: the middle byte is inside a `😀`.
    let text = format!("{}😀\n{}", "a".repeat(35_000), "b".repeat(35_000));
    assert!(!text.is_char_boundary(text.len() / 2));
    assert_eq!(super::lexer::lex_parallel(&text), super::lexer::lex(&text));
    assert_eq!(parse(&text).text(), text);
}

#[test]
fn lists_deeper_than_the_limit_are_kept_as_text() {
    // `(p)` is the deepest list, at `depth`.
    let nested = |depth: usize| format!("{}(p){}", "(and ".repeat(depth - 1), ")".repeat(depth - 1));
    let at_limit = parse(&nested(MAX_NESTING));
    assert!(at_limit.errors.is_empty(), "{:?}", at_limit.errors);
    assert_eq!(list_depth(&at_limit), MAX_NESTING);
    for depth in [MAX_NESTING + 1, 10_000, 300_000] {
        let text = nested(depth);
        let p = parse(&text);
        assert_eq!(p.text(), text);
        assert_eq!(list_depth(&p), MAX_NESTING);
        assert_eq!(kinds(&p), vec![SyntaxErrorKind::TooDeep], "{depth}");
        // At the `(` one level too deep: `(and ` is five bytes.
        let at = 5 * MAX_NESTING;
        assert_eq!(p.errors[0].range, TextRange::at((at as u32).into(), 1.into()));
        assert_eq!(
            p.errors[0].message,
            format!("lists nested more than {MAX_NESTING} deep: this list is kept as text, not read")
        );
        // The text kept is one flat node up to the matching `)`: what follows is read.
        let after = format!("{text} (q)");
        assert_eq!(list_depth(&parse(&after)), MAX_NESTING);
        assert_eq!(kinds(&parse(&after)), vec![SyntaxErrorKind::TooDeep]);
    }
}

#[test]
fn unclosed_lists_too_deep_are_counted_in_the_missing_paren() {
    for n in [MAX_NESTING + 1, 200_000] {
        let text = "(".repeat(n);
        let p = parse(&text);
        assert_eq!(p.text(), text);
        assert_eq!(kinds(&p), vec![SyntaxErrorKind::TooDeep, SyntaxErrorKind::MissingParen]);
        assert_eq!(
            p.errors[1].message,
            format!("missing {n} `)`: a list and the lists around it are not closed")
        );
        let (range, insert) = p.errors[1].fix.clone().unwrap();
        assert_eq!((range, insert), (TextRange::empty(TextSize::of(text.as_str())), ")".repeat(n)));
        assert_eq!(list_depth(&p), MAX_NESTING);
    }
}

#[test]
fn a_run_of_extra_parens_is_one_error() {
    assert_eq!(errors("))))"), vec!["0..4: unexpected `)` (4 in a row): there is no open `(` to close"]);
    assert_eq!(
        errors("(a) )\n )\t)"),
        vec!["4..10: unexpected `)` (3 in a row): there is no open `(` to close"]
    );
    let p = parse(&")".repeat(200_000));
    assert_eq!(p.errors.len(), 1);
    assert_eq!(p.errors[0].fix, Some((TextRange::new(0.into(), 200_000.into()), String::new())));
    // A comment or an atom between two `)` ends the run: removing the run must not remove them.
    assert_eq!(errors(") ; c\n)").len(), 2);
    assert_eq!(errors(") x )").len(), 2);
}

#[test]
fn a_large_init_nested_too_deep_is_built_sequentially() {
    let mut text = String::from("(define (problem big) (:domain d)\n  (:init\n");
    for i in 0..20_000 {
        text.push_str(&format!("    (road a b) (= (distance a b) {i}.5)\n"));
    }
    text.push_str(&format!("    {}(p){}\n", "(q ".repeat(300), ")".repeat(300)));
    text.push_str("  )\n  (:goal (road a b)))\n");
    let parallel = parse(&text);
    let tokens = super::lexer::lex(&text);
    let mut sequential = parser::Parser::new(&text, &tokens);
    sequential.parallel = false;
    let (green, errors) = sequential.parse_file();
    assert_eq!(parallel.text(), text);
    assert_eq!(kinds(&parallel), vec![SyntaxErrorKind::TooDeep]);
    assert_eq!(&*parallel.errors, &errors[..]);
    assert_eq!(parallel.green, Green(green));
    assert_eq!(list_depth(&parallel), MAX_NESTING);
}

fn reparse_matches(text: &str, start: usize, end: usize, insert: &str) {
    let old = parse(text);
    let mut new_text = text.to_string();
    let edit = TextEdit {
        range: TextRange::new((start as u32).into(), (end as u32).into()),
        insert: insert.to_string(),
    };
    edit.apply(&mut new_text);
    let incremental = reparse(&old, &[edit], &new_text);
    let full = parse(&new_text);
    assert_eq!(incremental, full, "reparse differs from parse for {new_text:?}");
}

#[test]
fn reparse_inside_one_list_shares_the_rest() {
    let old = parse(DOMAIN);
    let at = DOMAIN.find(":effect (q ?x)").unwrap() + 10;
    let edit = TextEdit { range: TextRange::empty((at as u32).into()), insert: "x".into() };
    let mut text = DOMAIN.to_string();
    edit.apply(&mut text);
    let new = reparse(&old, &[edit], &text);
    assert_eq!(new, parse(&text));
    // The predicates section is the same allocation in both trees.
    let pred =
        |p: &Parse| p.syntax().children().next().unwrap().children().nth(1).unwrap().green().into_owned();
    let (a, b) = (pred(&old), pred(&new));
    assert!(std::ptr::eq::<rowan::GreenNodeData>(&*a, &*b));
}

#[test]
fn reparse_falls_back_when_structure_changes() {
    let at = DOMAIN.find("(q ?x))\n").unwrap();
    reparse_matches(DOMAIN, at + 6, at + 7, "");
    reparse_matches(DOMAIN, at + 2, at + 2, "(");
    reparse_matches(DOMAIN, at + 2, at + 2, ") :effect");
    reparse_matches(DOMAIN, at + 2, at + 2, "(:action");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_bytes_parse_losslessly(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes).into_owned();
        prop_assert_eq!(parse(&text).text(), text);
    }

    #[test]
    fn random_sexps_parse_losslessly(text in "[() ;:?a-z\n-]{0,300}") {
        prop_assert_eq!(parse(&text).text(), text);
    }

    #[test]
    fn reparse_equals_parse_in_problems(start in 0usize..PROBLEM.len(), len in 0usize..8, insert in "[() :a-z?]{0,6}") {
        let end = (start + len).min(PROBLEM.len());
        reparse_matches(PROBLEM, start, end, &insert);
    }

    #[test]
    fn reparse_equals_parse(start in 0usize..DOMAIN.len(), len in 0usize..8, insert in "[() :a-z?]{0,6}") {
        let end = (start + len).min(DOMAIN.len());
        reparse_matches(DOMAIN, start, end, &insert);
    }
}

/// A domain whose precondition nests to the limit, give or take `extra`.
fn deep_domain(extra: usize) -> String {
    let k = MAX_NESTING - 4 + extra;
    DOMAIN.replace("(and (p ?x))", &format!("{}(and (p ?x)){}", "(or ".repeat(k), ")".repeat(k)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    // Edits around the limit: in the deepest list (where a list inserted is
    // one too deep) and the lists around it, one level more or less deep.
    #[test]
    fn reparse_equals_parse_near_the_limit(
        extra in 0usize..3,
        at in prop_oneof![0usize..7, 0usize..1_600],
        len in 0usize..4,
        insert in prop_oneof!["[() a?]{0,5}", Just("(a)".to_string()), Just(" (q ?x)".to_string()), Just("((a))".to_string())],
    ) {
        let text = deep_domain(extra);
        // `(p ?x)`, the deepest list.
        let deepest = text.find("(p ?x))").unwrap();
        let start = if at < 7 { deepest + at } else { deepest.saturating_sub(at % 800) + at / 800 * 6 };
        let end = (start + len).min(text.len());
        reparse_matches(&text, start, end, &insert);
    }
}

proptest! {
    // Each case parses a 20 kB file twice: fewer cases.
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn reparse_equals_parse_in_grouped_lists(at in 0usize..40_000, len in 0usize..6, insert in "[() :a-z?\n]{0,5}") {
        let text = big_problem();
        let start = at % text.len();
        let end = (start + len).min(text.len());
        if text.is_char_boundary(start) && text.is_char_boundary(end) {
            reparse_matches(&text, start, end, &insert);
        }
    }
}
