//! Building green trees.
//!
//! rowan's `GreenNodeBuilder` interns every token through a general-purpose
//! cache keyed by kind and text; on a 5 MB problem that was a third of the
//! parse. Here the kind follows from the text (the lexer is context-free), so
//! tokens are interned by text alone: one-byte tokens (`(`, `)`, ` `, newlines,
//! half of all tokens) in a table, tokens of up to seven bytes (most names and
//! indentation) by their bytes packed in an integer, which hashes in one
//! multiplication and compares without `memcmp`, and longer ones by text.

use rowan::{GreenNode, GreenToken, NodeOrToken};
use rustc_hash::FxHashMap;

use super::kind::SyntaxKind;

pub(crate) type Element = NodeOrToken<GreenNode, GreenToken>;

/// Lists with more children than this have them in groups of this size.
pub const GROUP_SIZE: usize = 512;

pub(crate) struct TreeBuilder<'t> {
    parents: Vec<(SyntaxKind, usize)>,
    children: Vec<Element>,
    single: [Option<GreenToken>; 128],
    short: FxHashMap<u64, GreenToken>,
    long: FxHashMap<&'t [u8], GreenToken>,
}

impl<'t> TreeBuilder<'t> {
    pub(crate) fn new() -> Self {
        TreeBuilder {
            parents: Vec::new(),
            children: Vec::new(),
            single: std::array::from_fn(|_| None),
            short: FxHashMap::default(),
            long: FxHashMap::default(),
        }
    }

    pub(crate) fn start_node(&mut self, kind: SyntaxKind) {
        self.parents.push((kind, self.children.len()));
    }

    /// Appends the token `text[range]`. Interning reads its bytes (no UTF-8
    /// boundary checks on the hot path); the text is sliced only for a new token.
    pub(crate) fn token(&mut self, kind: SyntaxKind, text: &'t str, range: std::ops::Range<usize>) {
        let new = || GreenToken::new(kind.into(), &text[range.clone()]);
        let token = match &text.as_bytes()[range.clone()] {
            &[b] if b < 128 => self.single[b as usize].get_or_insert_with(new).clone(),
            short @ [_, _, ..] if short.len() < 8 => {
                // The bytes, and the length in the last byte: distinct texts, distinct keys.
                let mut key = [0u8; 8];
                key[..short.len()].copy_from_slice(short);
                key[7] = short.len() as u8;
                let key = u64::from_le_bytes(key);
                self.short.entry(key).or_insert_with(new).clone()
            }
            long => self.long.entry(long).or_insert_with(new).clone(),
        };
        debug_assert_eq!(token.kind(), kind.into(), "a token's kind follows from its text");
        self.children.push(NodeOrToken::Token(token));
    }

    pub(crate) fn finish_node(&mut self) {
        let (kind, first) = self.parents.pop().expect("finish_node after start_node");
        let node = if kind == SyntaxKind::List && self.children.len() - first > GROUP_SIZE {
            // A long list (a problem's `:init`): its children go in groups, so
            // that replacing one fact copies a group and the list of groups,
            // not every fact.
            let mut groups: Vec<Element> = Vec::new();
            let mut group: Vec<Element> = Vec::with_capacity(GROUP_SIZE);
            for child in self.children.drain(first..) {
                group.push(child);
                if group.len() == GROUP_SIZE {
                    groups.push(NodeOrToken::Node(GreenNode::new(SyntaxKind::Group.into(), group.drain(..))));
                }
            }
            if !group.is_empty() {
                groups.push(NodeOrToken::Node(GreenNode::new(SyntaxKind::Group.into(), group.drain(..))));
            }
            GreenNode::new(kind.into(), groups)
        } else {
            GreenNode::new(kind.into(), self.children.drain(first..))
        };
        self.children.push(NodeOrToken::Node(node));
    }

    /// Appends elements built elsewhere to the node being built.
    pub(crate) fn extend(&mut self, elements: Vec<Element>) {
        self.children.extend(elements);
    }

    /// The elements built, when no node is left open (a fragment of a list).
    pub(crate) fn into_children(self) -> Vec<Element> {
        debug_assert!(self.parents.is_empty(), "a fragment closes every list it opens");
        self.children
    }

    /// The root: the one node left once every node is finished.
    pub(crate) fn finish(mut self) -> GreenNode {
        assert!(self.parents.is_empty() && self.children.len() == 1, "unbalanced tree builder");
        match self.children.pop() {
            Some(NodeOrToken::Node(node)) => node,
            _ => unreachable!("the root is a node"),
        }
    }
}
