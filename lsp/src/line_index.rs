//! Lines and columns of a text, in the three position encodings of LSP.
//!
//! The analyzer speaks byte offsets; LSP speaks `(line, character)` where a
//! character is a UTF-8 byte, a UTF-16 code unit (the default) or a code point.
//! Lines end at `\n`, `\r\n` or a lone `\r`, as LSP counts them (and not at the
//! other Unicode separators, which is why this is not ropey's default).
//!
//! Conversions never fail: positions past the end of a line or of the text are
//! clamped, and a column that falls inside a character snaps to its start,
//! because a client's stale or sloppy position must not crash a request.

/// The unit of `Position.character`, negotiated at `initialize`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Encoding {
    Utf8,
    Utf16,
    Utf32,
}

impl Encoding {
    /// How many units of this encoding `c` takes.
    fn len(self, c: char) -> u32 {
        match self {
            Encoding::Utf8 => c.len_utf8() as u32,
            Encoding::Utf16 => c.len_utf16() as u32,
            Encoding::Utf32 => 1,
        }
    }
}

/// A zero-based line and column, the column in some [`Encoding`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct LineCol {
    pub line: u32,
    pub col: u32,
}

/// The start offsets of the lines of one text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct LineIndex {
    /// `starts[i]` is the byte offset of line `i`; `starts[0] == 0`.
    starts: Vec<u32>,
    len: u32,
}

/// Pushes the line starts `s` with `lo <= s <= hi` of `text`, in order (a line
/// starts after `\n`, and after a `\r` not followed by `\n`).
fn scan(text: &[u8], lo: usize, hi: usize, starts: &mut Vec<u32>) {
    let hi = hi.min(text.len());
    for s in lo.max(1)..=hi {
        let begins = match text[s - 1] {
            b'\n' => true,
            b'\r' => text.get(s) != Some(&b'\n'),
            _ => false,
        };
        if begins {
            starts.push(s as u32);
        }
    }
}

impl LineIndex {
    pub(crate) fn new(text: &str) -> LineIndex {
        let mut starts = vec![0];
        scan(text.as_bytes(), 1, text.len(), &mut starts);
        LineIndex { starts, len: text.len() as u32 }
    }

    /// Updates the index after `start..old_end` was replaced by `inserted`
    /// bytes, `text` being the new text: the line starts before the edit are
    /// kept, those after it shifted, and only the edited lines scanned. On a
    /// 5 MB file this is what keeps typing fast.
    pub(crate) fn edit(&mut self, text: &str, start: u32, old_end: u32, inserted: u32) {
        let new_end = start + inserted;
        let delta = i64::from(new_end) - i64::from(old_end);
        // A line start `s` depends on the bytes at `s - 1` and `s`: the starts in
        // `start..=old_end + 1` may change; the ones after move by `delta`.
        let keep = self.starts.partition_point(|&s| s < start.max(1));
        let after = self.starts.partition_point(|&s| s <= old_end + 1);
        let tail: Vec<u32> = self.starts[after..].iter().map(|&s| (i64::from(s) + delta) as u32).collect();
        self.starts.truncate(keep);
        let scan_to = (i64::from(old_end) + 1 + delta) as usize;
        scan(text.as_bytes(), start.max(1) as usize, scan_to, &mut self.starts);
        self.starts.extend(tail);
        self.len = text.len() as u32;
    }

    pub(crate) fn line_count(&self) -> usize {
        self.starts.len()
    }

    /// The byte range of line `line` without its terminator.
    fn line_bounds(&self, text: &str, line: usize) -> (usize, usize) {
        let start = self.starts[line] as usize;
        let mut end = self.starts.get(line + 1).map_or(self.len as usize, |&s| s as usize);
        let bytes = text.as_bytes();
        if end > start && bytes.get(end - 1) == Some(&b'\n') {
            end -= 1;
        }
        if end > start && bytes.get(end - 1) == Some(&b'\r') {
            end -= 1;
        }
        (start, end)
    }

    /// The byte offset of `pos`, clamped to the text.
    ///
    /// `text` must be the text this index was built from.
    pub(crate) fn offset(&self, text: &str, pos: LineCol, enc: Encoding) -> u32 {
        let line = pos.line as usize;
        if line >= self.line_count() {
            return self.len;
        }
        let (start, end) = self.line_bounds(text, line);
        let mut units = 0;
        for (i, c) in text[start..end].char_indices() {
            let next = units + enc.len(c);
            if next > pos.col {
                return (start + i) as u32;
            }
            units = next;
        }
        end as u32
    }

    /// The position of byte `offset`, clamped to the text and snapped back to a character start.
    pub(crate) fn line_col(&self, text: &str, offset: u32, enc: Encoding) -> LineCol {
        let mut offset = offset.min(self.len) as usize;
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.starts.partition_point(|&s| s as usize <= offset) - 1;
        let start = self.starts[line] as usize;
        let col = match enc {
            Encoding::Utf8 => (offset - start) as u32,
            _ => text[start..offset].chars().map(|c| enc.len(c)).sum(),
        };
        LineCol { line: line as u32, col }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lc(line: u32, col: u32) -> LineCol {
        LineCol { line, col }
    }

    #[test]
    fn edits_update_the_index_like_a_rebuild() {
        // Every edit of every small text over this alphabet, including ones
        // that make or break `\r\n` pairs at their borders.
        let texts = ["", "a\nb", "a\r\nb\rc\n", "\r\r\n\n", "ab\r", "\nx\ry"];
        let inserts = ["", "\n", "\r", "\r\n", "x", "\nq\r"];
        for text in texts {
            for start in 0..=text.len() {
                for end in start..=text.len() {
                    for ins in inserts {
                        let mut new = text.to_string();
                        new.replace_range(start..end, ins);
                        let mut idx = LineIndex::new(text);
                        idx.edit(&new, start as u32, end as u32, ins.len() as u32);
                        assert_eq!(idx, LineIndex::new(&new), "{text:?} [{start}..{end}] <- {ins:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn lines_end_at_lf_crlf_and_cr_only() {
        let text = "a\nb\r\nc\rd\u{2028}e\u{c}f";
        let idx = LineIndex::new(text);
        assert_eq!(idx.starts, vec![0, 2, 5, 7]);
        // The CRLF pair is one terminator: column 1 of line 1 is before `\r`.
        assert_eq!(idx.offset(text, lc(1, 5), Encoding::Utf16), 3);
        assert_eq!(idx.line_col(text, 3, Encoding::Utf16), lc(1, 1));
        assert_eq!(idx.offset(text, lc(3, 0), Encoding::Utf16), 7);
    }

    #[test]
    fn utf16_counts_surrogate_pairs() {
        // 😀 is 4 bytes, 2 UTF-16 units, 1 code point; é is 2 bytes, 1 unit.
        let text = "; é😀 x\n(p)";
        let idx = LineIndex::new(text);
        let x = text.find('x').unwrap() as u32;
        assert_eq!(idx.line_col(text, x, Encoding::Utf8), lc(0, 9));
        assert_eq!(idx.line_col(text, x, Encoding::Utf16), lc(0, 6));
        assert_eq!(idx.line_col(text, x, Encoding::Utf32), lc(0, 5));
        for enc in [Encoding::Utf8, Encoding::Utf16, Encoding::Utf32] {
            let pos = idx.line_col(text, x, enc);
            assert_eq!(idx.offset(text, pos, enc), x, "{enc:?}");
        }
    }

    #[test]
    fn inside_a_character_snaps_to_its_start() {
        let text = "😀x";
        let idx = LineIndex::new(text);
        assert_eq!(idx.offset(text, lc(0, 1), Encoding::Utf16), 0);
        assert_eq!(idx.offset(text, lc(0, 2), Encoding::Utf16), 4);
        assert_eq!(idx.offset(text, lc(0, 3), Encoding::Utf8), 0);
        assert_eq!(idx.line_col(text, 2, Encoding::Utf16), lc(0, 0));
    }

    #[test]
    fn out_of_range_positions_clamp() {
        let text = "ab\r\ncd";
        let idx = LineIndex::new(text);
        assert_eq!(idx.offset(text, lc(0, 99), Encoding::Utf16), 2);
        assert_eq!(idx.offset(text, lc(7, 0), Encoding::Utf16), 6);
        assert_eq!(idx.line_col(text, 99, Encoding::Utf16), lc(1, 2));
        let empty = LineIndex::new("");
        assert_eq!(empty.offset("", lc(3, 3), Encoding::Utf8), 0);
        assert_eq!(empty.line_col("", 3, Encoding::Utf8), lc(0, 0));
    }

    #[test]
    fn trailing_newline_opens_an_empty_last_line() {
        let text = "a\n";
        let idx = LineIndex::new(text);
        assert_eq!(idx.line_count(), 2);
        assert_eq!(idx.line_col(text, 2, Encoding::Utf16), lc(1, 0));
        assert_eq!(idx.offset(text, lc(1, 0), Encoding::Utf16), 2);
    }
}
