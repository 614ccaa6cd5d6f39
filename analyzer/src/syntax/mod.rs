//! Lossless, error-recovering syntax for extended HTN-PDDL.
//!
//! Architecture invariant: this module knows nothing about salsa, the semantic
//! model or LSP. A [`Parse`] is a value: printing its tree gives back the text,
//! byte for byte, whatever the text is.

mod builder;
mod green;
mod kind;
mod lexer;
mod parser;
mod reparse;
mod sexp;

use std::sync::Arc;

pub use green::{GAtom, GList, GSexp};
pub use kind::{Lang, SyntaxElement, SyntaxKind, SyntaxNode, SyntaxToken};
pub use lexer::{BOM, classify_atom, looks_like_a_number};
pub use parser::{FIELD_KEYWORDS, ITEM_HEADS, MAX_NESTING, SECTION_HEADS, SyntaxError, SyntaxErrorKind};
pub use reparse::TextEdit;
pub use rowan::{GreenNode, GreenToken, NodeOrToken, TextRange, TextSize};

pub use sexp::{List, Sexp};

/// A green tree compared by pointer first: unchanged subtrees shared between two
/// parses compare in O(1), which is what salsa's backdating relies on.
#[derive(Clone, Debug)]
pub struct Green(pub GreenNode);

impl PartialEq for Green {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq::<rowan::GreenNodeData>(&*self.0, &*other.0) || self.0 == other.0
    }
}
impl Eq for Green {}

/// The result of parsing a file: the lossless tree and the syntax errors.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Parse {
    pub green: Green,
    pub errors: Arc<[SyntaxError]>,
}

impl Parse {
    pub fn syntax(&self) -> SyntaxNode {
        SyntaxNode::new_root(self.green.0.clone())
    }

    /// The text the tree was parsed from.
    pub fn text(&self) -> String {
        self.syntax().to_string()
    }
}

/// Parses a whole file. Never fails.
pub fn parse(text: &str) -> Parse {
    let tokens = lexer::lex_parallel(text);
    let (green, errors) = parser::parse_file(text, &tokens);
    Parse { green: Green(green), errors: errors.into() }
}

/// Parses `new_text`, which is the text of `old` with `edits` applied in order,
/// re-parsing only the smallest lists that contain the edits when that gives the
/// same result as a full parse, and parsing everything otherwise.
pub fn reparse(old: &Parse, edits: &[TextEdit], new_text: &str) -> Parse {
    let mut current = old.clone();
    for edit in edits {
        match reparse::reparse_list(&current, edit) {
            Some(next) => current = next,
            None => return parse(new_text),
        }
    }
    debug_assert_eq!(current.green.0.text_len(), TextSize::of(new_text));
    if current.green.0.text_len() != TextSize::of(new_text) {
        return parse(new_text);
    }
    current
}

#[cfg(test)]
mod tests;
