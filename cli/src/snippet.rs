//! The source codespan-reporting shows under a diagnostic. Lines and columns
//! are [`Sources::line_col`]'s (characters; a byte-order mark is not one),
//! found in logarithmic time. A line longer than [`LONG_LINE`] bytes is
//! shown as a window of about [`CONTEXT`] bytes on each side of what the
//! label points at (of its first [`CONTEXT`] bytes), between `…`: a file of
//! one long line (a generated problem) prints a few hundred bytes per
//! diagnostic, not the whole line each time.

use std::ops::Range;

use codespan_reporting::files::{Error, Files};

use crate::render::Sources;

/// Lines longer than this (in bytes) are shown as a window.
pub(crate) const LONG_LINE: usize = 400;
/// The bytes shown on each side of a label in a long line (fewer at a
/// character's boundary).
pub(crate) const CONTEXT: usize = 80;

/// A file of [`Sources`], or a window of one of its lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FileId {
    Real(usize),
    Window(usize),
}

/// A window of a long line: `text` is `…` (unless the line starts there),
/// the line's bytes from `start`, and `…` (unless the line ends there).
struct Window {
    file: usize,
    /// The line's index in the file.
    line: usize,
    text: String,
    /// Where in the file `text` starts after its leading `…`.
    start: usize,
    /// The length of the leading `…` (0 or 3).
    prefix: usize,
}

/// The files codespan-reporting reads for one diagnostic.
pub(crate) struct View<'s> {
    sources: &'s Sources,
    windows: Vec<Window>,
}

impl<'s> View<'s> {
    pub(crate) fn new(sources: &'s Sources) -> View<'s> {
        View { sources, windows: Vec::new() }
    }

    /// Where codespan-reporting finds `range` of file `id`: the file itself
    /// when the line the range starts on is short, else a window of that
    /// line (the range cut at the line's end).
    pub(crate) fn place(&mut self, id: usize, range: Range<usize>) -> (FileId, Range<usize>) {
        let text = self.sources.text(id);
        let start = range.start.min(text.len());
        let line = self.sources.line_index(id, start);
        let lines = self.sources.line_range(id, line);
        let content_end = if text[..lines.end].ends_with('\n') { lines.end - 1 } else { lines.end };
        let end = range.end.clamp(start, content_end.max(start));
        let end_line_long = self.sources.line_range(id, self.sources.line_index(id, end)).len() > LONG_LINE;
        if lines.len() <= LONG_LINE && !end_line_long {
            return (FileId::Real(id), range);
        }
        // A label longer than the context is underlined on its first bytes.
        let end = ceil_boundary(text, end.min(start + CONTEXT));
        let from = floor_boundary(text, start.saturating_sub(CONTEXT).max(lines.start));
        let to = ceil_boundary(text, end.saturating_add(CONTEXT).min(content_end).max(end));
        let prefix = if from > lines.start { "…" } else { "" };
        let suffix = if to < content_end { "…" } else { "" };
        let window = Window {
            file: id,
            line,
            text: format!("{prefix}{}{suffix}", &text[from..to]),
            start: from,
            prefix: prefix.len(),
        };
        let shift = |at: usize| at - from + prefix.len();
        self.windows.push(window);
        (FileId::Window(self.windows.len() - 1), shift(start)..shift(end))
    }
}

/// The largest character boundary at or before `at`.
fn floor_boundary(text: &str, mut at: usize) -> usize {
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// The smallest character boundary at or after `at`.
fn ceil_boundary(text: &str, mut at: usize) -> usize {
    while !text.is_char_boundary(at) {
        at += 1;
    }
    at
}

impl<'a> Files<'a> for View<'_> {
    type FileId = FileId;
    type Name = String;
    type Source = &'a str;

    fn name(&'a self, id: FileId) -> Result<String, Error> {
        let file = match id {
            FileId::Real(file) => file,
            FileId::Window(w) => self.windows.get(w).ok_or(Error::FileMissing)?.file,
        };
        Ok(self.sources.name(file).to_string())
    }

    fn source(&'a self, id: FileId) -> Result<&'a str, Error> {
        match id {
            FileId::Real(file) => Ok(self.sources.text(file)),
            FileId::Window(w) => Ok(&self.windows.get(w).ok_or(Error::FileMissing)?.text),
        }
    }

    fn line_index(&'a self, id: FileId, byte_index: usize) -> Result<usize, Error> {
        match id {
            FileId::Real(file) => Ok(self.sources.line_index(file, byte_index)),
            FileId::Window(w) => Ok(self.windows.get(w).ok_or(Error::FileMissing)?.line),
        }
    }

    fn line_range(&'a self, id: FileId, line_index: usize) -> Result<Range<usize>, Error> {
        match id {
            FileId::Real(file) => {
                let lines = self.sources.line_count(file);
                if line_index >= lines {
                    return Err(Error::LineTooLarge { given: line_index, max: lines.saturating_sub(1) });
                }
                Ok(self.sources.line_range(file, line_index))
            }
            FileId::Window(w) => {
                let window = self.windows.get(w).ok_or(Error::FileMissing)?;
                if line_index != window.line {
                    return Err(Error::LineTooLarge { given: line_index, max: window.line });
                }
                Ok(0..window.text.len())
            }
        }
    }

    fn column_number(&'a self, id: FileId, _line_index: usize, byte_index: usize) -> Result<usize, Error> {
        let (file, at) = match id {
            FileId::Real(file) => (file, byte_index),
            FileId::Window(w) => {
                let window = self.windows.get(w).ok_or(Error::FileMissing)?;
                (window.file, window.start + byte_index.saturating_sub(window.prefix))
            }
        };
        Ok(self.sources.line_col(file, at).1)
    }
}
