//! A typed view of the s-expression tree: lists and atoms, trivia skipped.

use super::kind::{SyntaxElement, SyntaxKind, SyntaxNode, SyntaxToken};
use rowan::{NodeOrToken, TextRange};

/// An element of a list: an atom or a nested list.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Sexp {
    Atom(SyntaxToken),
    List(List),
}

impl Sexp {
    pub fn range(&self) -> TextRange {
        match self {
            Sexp::Atom(t) => t.text_range(),
            Sexp::List(l) => l.range(),
        }
    }

    pub fn as_atom(&self) -> Option<&SyntaxToken> {
        match self {
            Sexp::Atom(t) => Some(t),
            Sexp::List(_) => None,
        }
    }

    pub fn as_list(&self) -> Option<&List> {
        match self {
            Sexp::List(l) => Some(l),
            Sexp::Atom(_) => None,
        }
    }

    /// The atom's text, if this is an atom.
    pub fn atom_text(&self) -> Option<&str> {
        self.as_atom().map(|t| t.text())
    }

    /// Whether this is the atom `text`, compared case-insensitively like PDDL names.
    pub fn is_atom(&self, text: &str) -> bool {
        self.atom_text().is_some_and(|t| t.eq_ignore_ascii_case(text))
    }
}

/// The children of a node, the children of its `Group` nodes standing in for them.
pub fn flatten_groups(node: &SyntaxNode) -> FlatRed {
    FlatRed { outer: node.children_with_tokens(), inner: None }
}

/// See [`flatten_groups`].
pub struct FlatRed {
    outer: rowan::SyntaxElementChildren<super::kind::Lang>,
    inner: Option<rowan::SyntaxElementChildren<super::kind::Lang>>,
}

impl Iterator for FlatRed {
    type Item = SyntaxElement;

    fn next(&mut self) -> Option<SyntaxElement> {
        loop {
            if let Some(inner) = &mut self.inner {
                if let Some(e) = inner.next() {
                    return Some(e);
                }
                self.inner = None;
            }
            match self.outer.next()? {
                NodeOrToken::Node(g) if g.kind() == SyntaxKind::Group => {
                    self.inner = Some(g.children_with_tokens())
                }
                other => return Some(other),
            }
        }
    }
}

/// A parenthesised list.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct List(pub SyntaxNode);

impl List {
    pub fn cast(node: SyntaxNode) -> Option<List> {
        (node.kind() == SyntaxKind::List).then_some(List(node))
    }

    pub fn range(&self) -> TextRange {
        self.0.text_range()
    }

    /// The significant elements: atoms and lists, without trivia, parentheses and stray `)`.
    pub fn elements(&self) -> impl Iterator<Item = Sexp> + '_ {
        flatten_groups(&self.0).filter_map(|e| match e {
            NodeOrToken::Node(n) => List::cast(n).map(Sexp::List),
            NodeOrToken::Token(t) if t.kind().is_atom() => Some(Sexp::Atom(t)),
            NodeOrToken::Token(_) => None,
        })
    }

    pub fn head(&self) -> Option<Sexp> {
        self.elements().next()
    }

    /// The head atom's text, if the list starts with an atom.
    pub fn head_text(&self) -> Option<String> {
        match self.head()? {
            Sexp::Atom(t) => Some(t.text().to_string()),
            Sexp::List(_) => None,
        }
    }

    pub fn head_is(&self, text: &str) -> bool {
        self.head().is_some_and(|h| h.is_atom(text))
    }

    /// Whether the list ends with its own `)`.
    pub fn is_closed(&self) -> bool {
        // O(1): the last direct child is a `)` token (the first is always the `(`).
        let green = self.0.green();
        let last = match green.children().next_back() {
            Some(NodeOrToken::Node(g)) if g.kind() == SyntaxKind::Group.into() => g.children().next_back(),
            other => other,
        };
        last.is_some_and(|c| {
            c.as_token().is_some_and(|t| t.kind() == SyntaxKind::RParen.into())
                && self.range().len() >= 2.into()
        })
    }

    /// The range of the `(`.
    pub fn open_range(&self) -> TextRange {
        let start = self.range().start();
        TextRange::at(start, 1.into())
    }
}
