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
/// before them: a fix is applied whole or not at all. Returns the indices of
/// the chosen fixes and of the skipped ones.
pub fn select_fixes(fixes: &[&Fix]) -> (Vec<usize>, Vec<usize>) {
    let mut taken: Vec<(SourceFile, TextRange)> = Vec::new();
    let (mut chosen, mut skipped) = (Vec::new(), Vec::new());
    for (i, fix) in fixes.iter().enumerate() {
        let clash = fix.edits.iter().enumerate().any(|(j, (file, range, _))| {
            taken.iter().any(|(f, r)| f == file && overlap(*r, *range))
                || fix.edits[..j].iter().any(|(f, r, _)| f == file && overlap(*r, *range))
        });
        if clash {
            skipped.push(i);
        } else {
            taken.extend(fix.edits.iter().map(|(f, r, _)| (*f, *r)));
            chosen.push(i);
        }
    }
    (chosen, skipped)
}

/// The text with `edits` applied. Edits must not overlap (see
/// [`select_fixes`]); insertions at the same offset keep their order. `None`
/// when an edit is outside the text or not on a character boundary (the text
/// changed since the diagnostics were computed).
pub fn apply_edits(text: &str, edits: &[(TextRange, &str)]) -> Option<String> {
    let mut sorted: Vec<&(TextRange, &str)> = edits.iter().collect();
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
    }
}
