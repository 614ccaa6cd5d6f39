//! Folding ranges and document highlights: where an editor may fold a file,
//! and which occurrences of a name to highlight in it.

use rowan::{TextRange, TextSize};

use crate::db::{Db, SourceFile, parse};
use crate::syntax::{NodeOrToken, SyntaxKind, SyntaxNode};

/// What a folding range holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FoldKind {
    /// A parenthesised list over several lines (a domain, an action, a
    /// condition, a problem's `:init`…).
    List,
    /// Comment lines one under the other.
    Comment,
}

/// A range an editor may fold: it spans two lines at least.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fold {
    pub range: TextRange,
    pub kind: FoldKind,
}

/// The folding ranges of a file, in the order they start: every list that
/// spans several lines (a list missing its `)` ends where the file does),
/// and every run of two comment lines or more.
pub fn folding_ranges(db: &dyn Db, file: SourceFile) -> Vec<Fold> {
    folds(&parse(db, file).syntax())
}

fn folds(root: &SyntaxNode) -> Vec<Fold> {
    let mut out = Vec::new();
    // A run of comments: its range, and how many comments it holds.
    let mut run: Option<(TextRange, usize)> = None;
    fn end_run(run: &mut Option<(TextRange, usize)>, out: &mut Vec<Fold>) {
        if let Some((range, n)) = run.take()
            && n >= 2
        {
            out.push(Fold { range, kind: FoldKind::Comment });
        }
    }
    for element in root.descendants_with_tokens() {
        match element {
            NodeOrToken::Node(node) => {
                if node.kind() == SyntaxKind::List && node.text().contains_char('\n') {
                    out.push(Fold { range: node.text_range(), kind: FoldKind::List });
                }
            }
            NodeOrToken::Token(token) => match token.kind() {
                SyntaxKind::Comment => {
                    run = Some(match run {
                        Some((range, n)) => (range.cover(token.text_range()), n + 1),
                        None => (token.text_range(), 1),
                    });
                }
                // One line break between two comments keeps them in a run;
                // a blank line or anything else ends it.
                SyntaxKind::Whitespace if token.text().matches('\n').count() <= 1 => {}
                _ => end_run(&mut run, &mut out),
            },
        }
    }
    end_run(&mut run, &mut out);
    out.sort_by_key(|f| (f.range.start(), std::cmp::Reverse(f.range.end())));
    out
}

/// An occurrence of a name to highlight.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Highlight {
    pub range: TextRange,
    /// The occurrence declares the name (a parameter, a predicate in
    /// `:predicates`, an object…); the others use it.
    pub declaration: bool,
}

/// The occurrences in `file` of the name at `offset`, as find references
/// gives them ([`super::references`]), the declaration marked.
pub fn document_highlights(db: &dyn Db, file: SourceFile, offset: TextSize) -> Vec<Highlight> {
    let declaration = super::goto_definition(db, file, offset);
    super::references(db, file, offset, true)
        .into_iter()
        .filter(|n| n.file == file)
        .map(|n| Highlight { range: n.range, declaration: declaration.as_ref() == Some(&n) })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn show(text: &str) -> Vec<(FoldKind, String)> {
        folds(&crate::syntax::parse(text).syntax())
            .into_iter()
            .map(|f| (f.kind, text[f.range].lines().next().unwrap_or("").to_string()))
            .collect()
    }

    #[test]
    fn lists_over_several_lines_and_runs_of_comments_fold() {
        let text = "; Domain of the rovers.\n; Second line.\n\n; Alone.\n(define (domain d)\n  (:predicates (at ?r) (free ?r))\n  (:action go ; inline\n    :parameters (?r)\n    :effect (and\n      (at ?r))))\n(oops\n";
        assert_eq!(
            show(text),
            vec![
                (FoldKind::Comment, "; Domain of the rovers.".to_string()),
                (FoldKind::List, "(define (domain d)".to_string()),
                (FoldKind::List, "(:action go ; inline".to_string()),
                (FoldKind::List, "(and".to_string()),
                (FoldKind::List, "(oops".to_string()),
            ]
        );
    }

    #[test]
    fn a_file_on_one_line_has_no_fold() {
        assert_eq!(show("(define (domain d) (:predicates (p))) ; one line"), vec![]);
        assert_eq!(show(""), vec![]);
    }
}
