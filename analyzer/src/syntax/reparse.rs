//! Incremental re-parsing of the smallest list around an edit.

use std::sync::Arc;

use rowan::{TextRange, TextSize};

use super::kind::SyntaxKind;
use super::parser::{Parser, ancestor_kind};
use super::sexp::List;
use super::{Green, Parse};

/// A change of the text: `range` (in the old text) is replaced by `insert`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct TextEdit {
    pub range: TextRange,
    pub insert: String,
}

impl TextEdit {
    /// Applies the edit to `text`, which must be the text the range refers to.
    pub fn apply(&self, text: &mut String) {
        text.replace_range(std::ops::Range::<usize>::from(self.range), &self.insert);
    }
}

pub(super) fn reparse_list(old: &Parse, edit: &TextEdit) -> Option<Parse> {
    let root = old.syntax();
    if edit.range.end() > root.text_range().end() {
        return None;
    }
    let covering = root.covering_element(edit.range);
    let start = match covering {
        rowan::NodeOrToken::Node(n) => Some(n),
        rowan::NodeOrToken::Token(t) => t.parent(),
    }?;
    // The smallest list whose parentheses are both outside the edit.
    let list = start.ancestors().filter_map(List::cast).find(|l| {
        let r = l.range();
        r.start() < edit.range.start() && edit.range.end() < r.end() && l.is_closed()
    })?;
    let range = list.range();
    if old.errors.iter().any(|e| e.range.intersect(range).is_some() || range.contains(e.range.start())) {
        return None;
    }
    let mut new_text = list.0.to_string();
    let local = edit.range - range.start();
    new_text.replace_range(std::ops::Range::<usize>::from(local), &edit.insert);

    let mut ancestors: Vec<_> = list
        .0
        .ancestors()
        .skip(1)
        .filter_map(List::cast)
        .map(|l| ancestor_kind(l.head_text().as_deref()))
        .collect();
    ancestors.reverse();
    let tokens = super::lexer::lex_parallel(&new_text);
    let green = Parser::new(&new_text, &tokens).parse_list_in(&ancestors)?;
    let new_list = List(super::SyntaxNode::new_root(green.clone()));
    // Recovery at the list's own `(` and `)` depends on its head: it must keep its role.
    let role = |l: &List| {
        let head = l.head_text();
        let h = head.as_deref().unwrap_or("");
        (ancestor_kind(head.as_deref()), h.starts_with(':'), super::parser::is_section_head(h))
    };
    if role(&new_list) != role(&list) {
        return None;
    }
    debug_assert_eq!(green.kind(), SyntaxKind::List.into());
    let new_root = list.0.replace_with(green);
    let delta = TextSize::of(edit.insert.as_str()).into_i64() - i64::from(u32::from(local.len()));
    let shift = |r: TextRange| -> TextRange {
        if r.start() >= range.end() {
            let s = (i64::from(u32::from(r.start())) + delta) as u32;
            TextRange::at(s.into(), r.len())
        } else {
            r
        }
    };
    let errors: Arc<[_]> = old
        .errors
        .iter()
        .map(|e| {
            let mut e = e.clone();
            e.range = shift(e.range);
            if let Some((r, m)) = e.related.take() {
                e.related = Some((shift(r), m));
            }
            if let Some((r, t)) = e.fix.take() {
                e.fix = Some((shift(r), t));
            }
            e
        })
        .collect();
    Some(Parse { green: Green(new_root), errors })
}

trait IntoI64 {
    fn into_i64(self) -> i64;
}

impl IntoI64 for TextSize {
    fn into_i64(self) -> i64 {
        i64::from(u32::from(self))
    }
}
