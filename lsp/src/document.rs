//! The server's copy of an open document: its text, line index and version.
//!
//! The copy exists to turn LSP ranges (lines and columns of the text *before*
//! each change) into byte offsets; the analyzer keeps its own text, which the
//! session keeps equal to this one.

use hipop_analyzer::{TextEdit, TextRange};
use tower_lsp_server::ls_types::TextDocumentContentChangeEvent;

use crate::convert;
use std::sync::Arc;

use crate::line_index::{Encoding, LineIndex};

pub(crate) struct Document {
    /// The analyzer's name for the file (a path, or the URI if it is not a file).
    pub key: String,
    pub version: i32,
    text: String,
    /// Shared with the snapshots that convert this document's positions;
    /// copied on write only while one of them still holds it.
    index: Arc<LineIndex>,
}

/// What a batch of content changes did, for the analyzer.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum Applied {
    /// Only ranged edits, in order: the analyzer can re-parse incrementally.
    Edits(Vec<TextEdit>),
    /// At least one change replaced the whole text.
    Replaced,
}

impl Document {
    pub(crate) fn new(key: String, version: i32, text: String) -> Document {
        let index = Arc::new(LineIndex::new(&text));
        Document { key, version, text, index }
    }

    /// The line index of the current text.
    pub(crate) fn index(&self) -> Arc<LineIndex> {
        self.index.clone()
    }

    pub(crate) fn text(&self) -> &str {
        &self.text
    }

    /// Applies content changes in order: each range refers to the text left by
    /// the previous change, so the line index is rebuilt after each one.
    /// Ranges are clamped to the text, and a reversed range is read forwards.
    pub(crate) fn apply_changes(
        &mut self,
        changes: Vec<TextDocumentContentChangeEvent>,
        enc: Encoding,
    ) -> Applied {
        let mut edits = Vec::new();
        let mut replaced = false;
        for change in changes {
            match change.range {
                None => {
                    self.text = change.text;
                    self.index = Arc::new(LineIndex::new(&self.text));
                    edits.clear();
                    replaced = true;
                }
                Some(range) => {
                    let a = convert::offset(&self.index, &self.text, range.start, enc);
                    let b = convert::offset(&self.index, &self.text, range.end, enc);
                    let (start, end) = (a.min(b), a.max(b));
                    self.text.replace_range(start as usize..end as usize, &change.text);
                    Arc::make_mut(&mut self.index).edit(&self.text, start, end, change.text.len() as u32);
                    edits.push(TextEdit {
                        range: TextRange::new(start.into(), end.into()),
                        insert: change.text,
                    });
                }
            }
        }
        if replaced { Applied::Replaced } else { Applied::Edits(edits) }
    }
}

#[cfg(test)]
mod tests {
    use tower_lsp_server::ls_types::{Position, Range};

    use super::*;

    fn edit(l1: u32, c1: u32, l2: u32, c2: u32, text: &str) -> TextDocumentContentChangeEvent {
        TextDocumentContentChangeEvent {
            range: Some(Range::new(Position::new(l1, c1), Position::new(l2, c2))),
            range_length: None,
            text: text.to_string(),
        }
    }

    fn full(text: &str) -> TextDocumentContentChangeEvent {
        TextDocumentContentChangeEvent { range: None, range_length: None, text: text.to_string() }
    }

    #[test]
    fn edits_apply_in_order_against_the_previous_text() {
        let mut doc = Document::new("d".into(), 1, "(a)\n(b)\n".into());
        // Insert a line, then edit what is now line 2 (formerly line 1).
        let applied =
            doc.apply_changes(vec![edit(0, 0, 0, 0, "(x)\n"), edit(2, 1, 2, 2, "c")], Encoding::Utf16);
        assert_eq!(doc.text(), "(x)\n(a)\n(c)\n");
        let Applied::Edits(edits) = applied else { panic!("expected edits") };
        assert_eq!(edits.len(), 2);
        assert_eq!(edits[1].range, TextRange::new(9.into(), 10.into()));
        let mut replay = "(a)\n(b)\n".to_string();
        edits.iter().for_each(|e| e.apply(&mut replay));
        assert_eq!(replay, doc.text());
    }

    #[test]
    fn utf16_columns_after_an_emoji_and_crlf() {
        let mut doc = Document::new("d".into(), 1, "; 😀\r\n(at é x)\r\n".into());
        // Line 1: `(at é x)`; UTF-16 column 6 is `x`.
        doc.apply_changes(vec![edit(1, 6, 1, 7, "y")], Encoding::Utf16);
        assert_eq!(doc.text(), "; 😀\r\n(at é y)\r\n");
        // Line 0: the emoji spans UTF-16 columns 2..4.
        doc.apply_changes(vec![edit(0, 2, 0, 4, "ok")], Encoding::Utf16);
        assert_eq!(doc.text(), "; ok\r\n(at é y)\r\n");
        // In UTF-8, `é` is two columns.
        doc.apply_changes(vec![edit(1, 7, 1, 8, "z")], Encoding::Utf8);
        assert_eq!(doc.text(), "; ok\r\n(at é z)\r\n");
    }

    #[test]
    fn full_replacement_then_edits_is_a_replacement() {
        let mut doc = Document::new("d".into(), 1, "old".into());
        let applied = doc.apply_changes(vec![full("(a)\n"), edit(0, 1, 0, 2, "b")], Encoding::Utf16);
        assert_eq!(applied, Applied::Replaced);
        assert_eq!(doc.text(), "(b)\n");
    }

    #[test]
    fn ranges_past_the_end_clamp_and_reversed_ranges_are_read_forwards() {
        let mut doc = Document::new("d".into(), 1, "ab\ncd".into());
        doc.apply_changes(vec![edit(1, 1, 9, 9, "!")], Encoding::Utf16);
        assert_eq!(doc.text(), "ab\nc!");
        doc.apply_changes(vec![edit(0, 2, 0, 0, "x")], Encoding::Utf16);
        assert_eq!(doc.text(), "x\nc!");
    }
}
