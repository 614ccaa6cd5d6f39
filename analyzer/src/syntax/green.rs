//! An allocation-free view of green trees as s-expressions, with absolute
//! offsets computed on the fly. Lowering and item splitting read the tree
//! through this view: creating red nodes (`SyntaxNode`) allocates per node,
//! which dominated the cost of checking a 5 MB problem.

use rowan::{GreenNodeData, GreenTokenData, Language, NodeOrToken, TextRange, TextSize};

use super::kind::{Lang, SyntaxKind};

/// An atom: its kind, text and range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GAtom<'a> {
    kind: SyntaxKind,
    text: &'a str,
    range: TextRange,
}

impl<'a> GAtom<'a> {
    pub fn kind(&self) -> SyntaxKind {
        self.kind
    }
    pub fn text(&self) -> &'a str {
        self.text
    }
    pub fn text_range(&self) -> TextRange {
        self.range
    }
}

/// A list node and where it starts.
#[derive(Debug, Clone, Copy)]
pub struct GList<'a> {
    node: &'a GreenNodeData,
    start: TextSize,
}

/// The children of a list, the children of its groups flattened, with their starts.
pub struct FlatChildren<'a> {
    outer: rowan::Children<'a>,
    inner: Option<rowan::Children<'a>>,
    at: TextSize,
}

impl<'a> Iterator for FlatChildren<'a> {
    type Item = (TextSize, NodeOrToken<&'a GreenNodeData, &'a GreenTokenData>);

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            if let Some(inner) = &mut self.inner {
                if let Some(c) = inner.next() {
                    let start = self.at;
                    self.at += c.text_len();
                    return Some((start, c));
                }
                self.inner = None;
            }
            match self.outer.next()? {
                NodeOrToken::Node(n) if kind_of(n.kind()) == SyntaxKind::Group => {
                    self.inner = Some(n.children())
                }
                c => {
                    let start = self.at;
                    self.at += c.text_len();
                    return Some((start, c));
                }
            }
        }
    }
}

/// An element of a list.
#[derive(Debug, Clone, Copy)]
pub enum GSexp<'a> {
    Atom(GAtom<'a>),
    List(GList<'a>),
}

fn kind_of(raw: rowan::SyntaxKind) -> SyntaxKind {
    Lang::kind_from_raw(raw)
}

impl<'a> GSexp<'a> {
    /// The element for a green child starting at `start`, if it is significant.
    pub fn of(
        element: NodeOrToken<&'a GreenNodeData, &'a GreenTokenData>,
        start: TextSize,
    ) -> Option<GSexp<'a>> {
        match element {
            NodeOrToken::Node(n) if kind_of(n.kind()) == SyntaxKind::List => {
                Some(GSexp::List(GList { node: n, start }))
            }
            NodeOrToken::Token(t) if kind_of(t.kind()).is_atom() => Some(GSexp::Atom(GAtom {
                kind: kind_of(t.kind()),
                text: t.text(),
                range: TextRange::at(start, t.text_len()),
            })),
            _ => None,
        }
    }

    pub fn range(&self) -> TextRange {
        match self {
            GSexp::Atom(a) => a.range,
            GSexp::List(l) => l.range(),
        }
    }

    pub fn as_atom(&self) -> Option<&GAtom<'a>> {
        match self {
            GSexp::Atom(a) => Some(a),
            GSexp::List(_) => None,
        }
    }

    pub fn as_list(&self) -> Option<&GList<'a>> {
        match self {
            GSexp::List(l) => Some(l),
            GSexp::Atom(_) => None,
        }
    }

    pub fn atom_text(&self) -> Option<&'a str> {
        self.as_atom().map(|a| a.text)
    }

    /// Whether this is the atom `text`, compared case-insensitively like PDDL names.
    pub fn is_atom(&self, text: &str) -> bool {
        self.atom_text().is_some_and(|t| t.eq_ignore_ascii_case(text))
    }
}

impl<'a> GList<'a> {
    /// A list that is the root of its own tree (offsets start at `start`).
    pub fn root(node: &'a GreenNodeData, start: TextSize) -> Option<GList<'a>> {
        (kind_of(node.kind()) == SyntaxKind::List).then_some(GList { node, start })
    }

    pub fn range(&self) -> TextRange {
        TextRange::at(self.start, self.node.text_len())
    }

    pub fn green(&self) -> &'a GreenNodeData {
        self.node
    }

    /// Every child with its absolute start, trivia and parentheses included;
    /// the children of `Group` nodes stand in for the groups.
    pub fn children(&self) -> FlatChildren<'a> {
        FlatChildren { outer: self.node.children(), inner: None, at: self.start }
    }

    /// The direct children, groups included, with their absolute starts.
    pub fn direct_children(
        &self,
    ) -> impl Iterator<Item = (TextSize, NodeOrToken<&'a GreenNodeData, &'a GreenTokenData>)> + 'a {
        let mut at = self.start;
        self.node.children().map(move |c| {
            let start = at;
            at += c.text_len();
            (start, c)
        })
    }

    /// The significant elements: atoms and lists.
    pub fn elements(&self) -> impl Iterator<Item = GSexp<'a>> + 'a {
        self.children().filter_map(|(start, c)| GSexp::of(c, start))
    }

    pub fn head(&self) -> Option<GSexp<'a>> {
        self.elements().next()
    }

    pub fn head_text(&self) -> Option<&'a str> {
        self.head().and_then(|h| h.atom_text())
    }

    pub fn head_is(&self, text: &str) -> bool {
        self.head().is_some_and(|h| h.is_atom(text))
    }
}
