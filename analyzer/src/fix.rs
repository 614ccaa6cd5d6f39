//! Applying the fixes of diagnostics to texts (`hipop check --fix`). Pure:
//! the CLI reads and writes the files.

use rowan::TextRange;

use crate::db::SourceFile;
use crate::diagnostic::Fix;

/// Whether two edits touch the same text. Insertions at the same offset do
/// not overlap (they are applied in order), nor does an insertion at either
/// end of a replacement.
fn overlap(a: TextRange, b: TextRange) -> bool {
    let inside = |p: TextRange, r: TextRange| p.is_empty() && r.start() < p.start() && p.start() < r.end();
    a.start().max(b.start()) < a.end().min(b.end()) || inside(a, b) || inside(b, a)
}

/// Chooses, in order, the fixes whose edits overlap no edit of a fix chosen
/// before them: a fix is applied whole or not at all. A fix that makes the
/// very edits of fixes chosen before it is chosen too ([`apply_edits`]
/// makes an edit once). Returns the indices of the chosen fixes and of the
/// skipped ones.
pub fn select_fixes(fixes: &[&Fix]) -> (Vec<usize>, Vec<usize>) {
    let mut taken: Vec<(SourceFile, TextRange)> = Vec::new();
    let mut made: Vec<&(SourceFile, TextRange, String)> = Vec::new();
    let (mut chosen, mut skipped) = (Vec::new(), Vec::new());
    for (i, fix) in fixes.iter().enumerate() {
        if !fix.edits.is_empty() && fix.edits.iter().all(|e| made.contains(&e)) {
            chosen.push(i);
            continue;
        }
        let clash = fix.edits.iter().enumerate().any(|(j, (file, range, _))| {
            taken.iter().any(|(f, r)| f == file && overlap(*r, *range))
                || fix.edits[..j].iter().any(|(f, r, _)| f == file && overlap(*r, *range))
        });
        if clash {
            skipped.push(i);
        } else {
            taken.extend(fix.edits.iter().map(|(f, r, _)| (*f, *r)));
            made.extend(fix.edits.iter());
            chosen.push(i);
        }
    }
    (chosen, skipped)
}

/// The text with `edits` applied. Edits must not overlap (see
/// [`select_fixes`]); insertions at the same offset keep their order, and
/// an edit equal to one before it is made once (two fixes may make the same
/// edit: add the `:requirements` that two warnings miss). `None`
/// when an edit is outside the text or not on a character boundary (the text
/// changed since the diagnostics were computed).
pub fn apply_edits(text: &str, edits: &[(TextRange, &str)]) -> Option<String> {
    let mut sorted: Vec<&(TextRange, &str)> = Vec::with_capacity(edits.len());
    let mut seen: rustc_hash::FxHashSet<&(TextRange, &str)> = rustc_hash::FxHashSet::default();
    sorted.extend(edits.iter().filter(|e| seen.insert(*e)));
    // Stable: equal starts keep their order; an insertion goes before a
    // replacement that starts where it is.
    sorted.sort_by_key(|(r, _)| (r.start(), r.end()));
    let mut out = String::with_capacity(text.len());
    let mut at = 0usize;
    for (range, insert) in sorted {
        let (start, end) = (usize::from(range.start()), usize::from(range.end()));
        if start < at || !text.is_char_boundary(start) || !text.is_char_boundary(end) || end > text.len() {
            return None;
        }
        out.push_str(&text[at..start]);
        out.push_str(insert);
        at = end;
    }
    out.push_str(&text[at..]);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AnalysisHost;

    fn r(a: u32, b: u32) -> TextRange {
        TextRange::new(a.into(), b.into())
    }

    #[test]
    fn edits_apply_in_order() {
        let text = "(and (p))";
        assert_eq!(
            apply_edits(text, &[(r(8, 8), " (q)"), (r(8, 8), " (s)")]).as_deref(),
            Some("(and (p) (q) (s))")
        );
        assert_eq!(apply_edits(text, &[(r(5, 8), "(r)"), (r(0, 0), ";\n")]).as_deref(), Some(";\n(and (r))"));
        assert_eq!(apply_edits(text, &[(r(5, 8), "")]).as_deref(), Some("(and )"));
        assert_eq!(apply_edits(text, &[(r(5, 20), "")]), None, "outside the text");
        assert_eq!(apply_edits(text, &[(r(1, 5), ""), (r(2, 6), "")]), None, "overlapping");
        assert_eq!(apply_edits("é", &[(r(1, 1), "x")]), None, "inside a character");
    }

    #[test]
    fn overlapping_fixes_are_skipped() {
        assert!(overlap(r(1, 5), r(4, 6)));
        assert!(overlap(r(1, 5), r(3, 3)));
        assert!(!overlap(r(1, 5), r(5, 5)));
        assert!(!overlap(r(3, 3), r(3, 3)));
        assert!(!overlap(r(1, 5), r(5, 9)));

        let mut host = AnalysisHost::new();
        let f = host.set_file_text("a.pddl", "(define (domain d))");
        let g = host.set_file_text("b.pddl", "(define (domain e))");
        let fix = |edits: Vec<(SourceFile, TextRange, &str)>| Fix {
            message: String::new(),
            edits: edits.into_iter().map(|(f, r, t)| (f, r, t.to_string())).collect(),
        };
        let a = fix(vec![(f, r(1, 5), "x")]);
        let b = fix(vec![(g, r(1, 5), "y")]); // another file
        let c = fix(vec![(f, r(0, 0), "("), (f, r(4, 5), "z")]); // overlaps `a` by one edit
        let d = fix(vec![(f, r(5, 5), "w")]);
        assert_eq!(select_fixes(&[&a, &b, &c, &d]), (vec![0, 1, 3], vec![2]));
        // The same edits again: chosen, and made once.
        let again = fix(vec![(f, r(5, 5), "w")]);
        assert_eq!(select_fixes(&[&d, &a, &again]), (vec![0, 1, 2], vec![]));
        assert_eq!(
            apply_edits("abcdef", &[(r(5, 5), "w"), (r(1, 2), "x"), (r(5, 5), "w")]).as_deref(),
            Some("axcdewf")
        );
    }

    /// The fixes of the missing requirements of `text`, applied together.
    fn fix_requirements(text: &str) -> (Vec<String>, String) {
        let mut host = AnalysisHost::new();
        let f = host.set_file_text("domain.pddl", text);
        let diags = host.analysis().diagnostics(f).unwrap();
        let fixes: Vec<&Fix> = diags
            .iter()
            .filter(|d| d.code == crate::codes::MISSING_REQUIREMENT)
            .filter_map(|d| d.fix.as_ref())
            .collect();
        let (chosen, _) = select_fixes(&fixes);
        let edits: Vec<(TextRange, &str)> =
            chosen.iter().flat_map(|&i| &fixes[i].edits).map(|(_, r, t)| (*r, t.as_str())).collect();
        let fixed = apply_edits(text, &edits).expect("the fixes apply");
        let f = host.set_file_text("domain.pddl", fixed.as_str());
        let left = host.analysis().diagnostics(f).unwrap();
        assert!(!left.iter().any(|d| d.code == crate::codes::MISSING_REQUIREMENT), "{fixed}");
        (fixes.iter().map(|f| f.message.clone()).collect(), fixed)
    }

    #[test]
    fn missing_requirements_are_added_to_a_requirements_section_made_once() {
        let text = "(define (domain d)\n  (:types t)\n  (:predicates (p ?x - t))\n  (:durative-action a \
                    :parameters (?x - t) :duration (= ?duration 1)\n    :condition (at start (p ?x)) :effect \
                    (at end (p ?x))))\n";
        let (messages, fixed) = fix_requirements(text);
        assert_eq!(
            messages,
            [
                "add `(:requirements :typing :durative-actions)`",
                "add `(:requirements :typing :durative-actions)`"
            ]
        );
        assert!(
            fixed
                .starts_with("(define (domain d)\n  (:requirements :typing :durative-actions)\n  (:types t)"),
            "{fixed}"
        );
        // With a section, each is added to it.
        let (messages, fixed) =
            fix_requirements(&text.replace("(:types", "(:requirements :strips)\n  (:types"));
        assert_eq!(messages, ["add `:typing`", "add `:durative-actions`"]);
        assert!(fixed.contains("(:requirements :strips :typing :durative-actions)"), "{fixed}");
        // A problem's goes after its `(:domain …)`, on the same line as the next section when it is.
        let mut host = AnalysisHost::new();
        host.set_file_text("dom.pddl", "(define (domain e) (:requirements :strips) (:predicates (q)))");
        let problem = "(define (problem p) (:domain e) (:init (at 5 (q))) (:goal (q)))";
        let p = host.set_file_text("p.pddl", problem);
        let diags = host.analysis().diagnostics(p).unwrap();
        let fix =
            diags.iter().find_map(|d| d.fix.as_ref().filter(|_| d.code == crate::codes::MISSING_REQUIREMENT));
        let (_, at, insert) = &fix.expect("a fix").edits[0];
        let fixed = apply_edits(problem, &[(*at, insert.as_str())]).unwrap();
        assert_eq!(
            fixed,
            "(define (problem p) (:domain e) (:requirements :timed-initial-literals) (:init (at 5 (q))) (:goal (q)))"
        );
    }
}
