//! Token and node kinds of the lossless syntax tree.
//!
//! The tree is an s-expression tree: the grammar of PDDL/HDDL is given by the
//! keywords at the head of lists, and is interpreted by the lowering, not by the
//! parser. Keeping the parser this small is what makes it lossless, error
//! recovering and cheap to re-run on one list.

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u16)]
pub enum SyntaxKind {
    // Tokens.
    LParen = 0,
    RParen,
    Whitespace,
    /// `;` up to (not including) the end of the line.
    Comment,
    /// `?name`.
    Variable,
    /// `:name`.
    Keyword,
    /// An integer or decimal number.
    Number,
    /// Any other atom: names, operators (`<`, `-`, `*`), `#t`.
    Symbol,
    // Nodes.
    /// A parenthesised list, possibly missing its `)`.
    List,
    /// A `)` that closes nothing, or a list nested deeper than the limit
    /// (`parser::MAX_NESTING`) as flat tokens: kept so that printing the tree
    /// gives the input back, and skipped by every view of the tree.
    Error,
    /// A run of consecutive children of a long list (see `GROUP_SIZE`): transparent
    /// for every view of the tree, it bounds what an edit copies.
    Group,
    Root,
}

impl SyntaxKind {
    pub fn is_trivia(self) -> bool {
        matches!(self, SyntaxKind::Whitespace | SyntaxKind::Comment)
    }

    pub fn is_atom(self) -> bool {
        matches!(self, SyntaxKind::Variable | SyntaxKind::Keyword | SyntaxKind::Number | SyntaxKind::Symbol)
    }
}

impl From<SyntaxKind> for rowan::SyntaxKind {
    fn from(kind: SyntaxKind) -> Self {
        rowan::SyntaxKind(kind as u16)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Lang {}

impl rowan::Language for Lang {
    type Kind = SyntaxKind;

    fn kind_from_raw(raw: rowan::SyntaxKind) -> SyntaxKind {
        assert!(raw.0 <= SyntaxKind::Root as u16);
        // SAFETY: `SyntaxKind` is `repr(u16)` and the bound was checked above.
        unsafe { std::mem::transmute::<u16, SyntaxKind>(raw.0) }
    }

    fn kind_to_raw(kind: SyntaxKind) -> rowan::SyntaxKind {
        kind.into()
    }
}

pub type SyntaxNode = rowan::SyntaxNode<Lang>;
pub type SyntaxToken = rowan::SyntaxToken<Lang>;
pub type SyntaxElement = rowan::SyntaxElement<Lang>;
