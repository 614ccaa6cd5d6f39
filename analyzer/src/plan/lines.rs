//! Lines, tokens and numbers of the text plan formats.

use rowan::{TextRange, TextSize};

use super::Number;

/// A line of a plan file, without its line break (`\n`, `\r\n`) and, on the
/// first line, without a byte-order mark.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Line<'t> {
    /// Absolute offset of the line's first byte.
    pub start: usize,
    pub text: &'t str,
}

impl<'t> Line<'t> {
    /// The part of the line from byte `from` (relative) on, as a line of its own.
    pub fn rest(self, from: usize) -> Line<'t> {
        Line { start: self.start + from, text: &self.text[from..] }
    }

    /// The line up to byte `to` (relative).
    pub fn until(self, to: usize) -> Line<'t> {
        Line { start: self.start, text: &self.text[..to] }
    }

    pub fn is_blank(self) -> bool {
        self.text.trim().is_empty()
    }

    /// The range of the line's text without surrounding whitespace (an empty
    /// range at the line's start when it is blank).
    pub fn trimmed_range(self) -> TextRange {
        let lead = self.text.len() - self.text.trim_start().len();
        let trimmed = self.text.trim();
        range(self.start + lead, self.start + lead + trimmed.len())
    }

    /// The whitespace-separated tokens, with their absolute starts.
    pub fn tokens(self) -> Vec<Token<'t>> {
        let mut out = Vec::new();
        let mut at = None;
        for (i, c) in self.text.char_indices() {
            match (c.is_whitespace(), at) {
                (true, Some(s)) => {
                    out.push(Token { start: self.start + s, text: &self.text[s..i] });
                    at = None;
                }
                (false, None) => at = Some(i),
                _ => {}
            }
        }
        if let Some(s) = at {
            out.push(Token { start: self.start + s, text: &self.text[s..] });
        }
        out
    }

    /// Where a `;` comment starts (relative), if any.
    pub fn comment_start(self) -> Option<usize> {
        self.text.find(';')
    }
}

/// A whitespace-separated token and its absolute start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Token<'t> {
    pub start: usize,
    pub text: &'t str,
}

impl Token<'_> {
    pub fn range(self) -> TextRange {
        range(self.start, self.start + self.text.len())
    }

    pub fn end(self) -> usize {
        self.start + self.text.len()
    }
}

/// The lines of a text.
pub(crate) fn lines(text: &str) -> impl Iterator<Item = Line<'_>> {
    let bom = if text.starts_with('\u{feff}') { '\u{feff}'.len_utf8() } else { 0 };
    let mut start = bom;
    let body = &text[bom..];
    body.split('\n').map(move |raw| {
        let line = Line { start, text: raw.strip_suffix('\r').unwrap_or(raw) };
        start += raw.len() + 1;
        line
    })
}

pub(crate) fn range(start: usize, end: usize) -> TextRange {
    // Plan files are read whole by the shells, which cap them far below 4 GiB.
    let at = |x: usize| TextSize::new(u32::try_from(x).unwrap_or(u32::MAX));
    TextRange::new(at(start), at(end.max(start)))
}

/// Whether a token could be meant as a number: only digits, `.`, signs and
/// exponents, with at least one digit.
pub(crate) fn is_numeric_token(s: &str) -> bool {
    s.bytes().any(|b| b.is_ascii_digit()) && s.bytes().all(|b| b.is_ascii_digit() || b".+-eE".contains(&b))
}

/// Reads a number written at `start`: `12`, `0.000`, `.5`, `1e-3`; not `inf`
/// or `nan`, and only finite values.
pub(crate) fn number(text: &str, start: usize) -> Result<Number, String> {
    let shown = if text.chars().count() > 24 {
        format!("{}…", text.chars().take(24).collect::<String>())
    } else {
        text.to_string()
    };
    if !is_numeric_token(text) {
        return Err(format!("`{shown}` is not a number"));
    }
    match text.parse::<f64>() {
        Ok(value) if value.is_finite() => {
            Ok(Number { text: text.into(), value, range: range(start, start + text.len()) })
        }
        Ok(_) => Err(format!("`{shown}` is too large a number")),
        Err(_) => Err(format!("`{shown}` is not a number")),
    }
}

/// Reads a step id: a non-negative integer that fits 32 bits.
pub(crate) fn step_id(token: Token<'_>) -> Option<super::StepId> {
    if token.text.is_empty() || !token.text.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    token.text.parse::<u32>().ok().map(|value| super::StepId { value, range: token.range() })
}

/// Whether a trimmed line looks like a timed VAL step: a number, `:`, and more.
pub(crate) fn looks_like_val_step(t: &str) -> bool {
    let end = t.find(|c: char| !(c.is_ascii_digit() || ".+-eE".contains(c))).unwrap_or(t.len());
    end > 0 && is_numeric_token(&t[..end]) && t[end..].trim_start().starts_with(':')
}
