//! The s-expression parser with keyword-driven error recovery.
//!
//! Parsing never fails: every byte ends up in the tree, and a mistake yields a
//! [`SyntaxError`]. Unbalanced parentheses are the only syntax errors at this
//! level; the recovery uses what PDDL keywords tell about the intended nesting:
//!
//! - `(` followed by a section keyword (`(:action`, `(:init`, …) starts a new
//!   item of the enclosing `define`: the lists still open inside that `define`
//!   are missing their `)`, which is reported once, at the end of the last token
//!   before the new item;
//! - a field keyword (`:effect`, `:subtasks`, …) inside a formula of an item
//!   belongs to the item: the formula is missing its `)`;
//! - a `)` that would close an item right before one of its field keywords, or
//!   a `define` right before a new section, is an extra `)`.
//!
//! Lists never nest deeper than [`MAX_NESTING`]: a list that would is kept,
//! up to its matching `)`, as the flat tokens of an `Error` node (printing the
//! tree still gives the text back) and reported once. Every recursion over the
//! tree or over what is read from it (lowering, checks, the comparisons and
//! drops of trees and models) is then bounded, whatever the input.

use rowan::{GreenNode, TextRange};

use super::builder::TreeBuilder;

use super::builder::Element;
use super::kind::SyntaxKind;
use super::lexer::Tokens;

/// What is wrong with the parentheses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SyntaxErrorKind {
    /// A list is not closed.
    MissingParen,
    /// A `)` closes nothing, or closes a list too early (or a run of them).
    ExtraParen,
    /// A list nested deeper than [`MAX_NESTING`], kept as text.
    TooDeep,
}

/// How deep lists may nest: a list inside this many open lists is not read
/// (real PDDL nests about a dozen deep). Bounds every recursion over the tree
/// and the model; small enough for the 2 MiB stacks of the server's threads
/// in unoptimised builds.
pub const MAX_NESTING: usize = 256;

/// A syntax error: a span in the text and a one-line message.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct SyntaxError {
    pub kind: SyntaxErrorKind,
    pub range: TextRange,
    pub message: String,
    /// The `(` that is not closed, for missing parentheses.
    pub related: Option<(TextRange, String)>,
    /// The edit that repairs the parentheses: a range and what replaces it.
    pub fix: Option<(TextRange, String)>,
}

/// Heads of lists that are sections of a `define`.
pub const SECTION_HEADS: &[&str] = &[
    ":requirements",
    ":types",
    ":constants",
    ":predicates",
    ":functions",
    ":action",
    ":durative-action",
    ":task",
    ":method",
    ":durative-method",
    ":process",
    ":event",
    ":derived",
    ":constraints",
    ":domain",
    ":objects",
    ":init",
    ":goal",
    ":metric",
    ":htn",
    ":tihtn",
    ":htnti",
    ":allowed-actions",
    ":tasks",
];

/// Heads of sections whose elements are `:field value` pairs.
pub const ITEM_HEADS: &[&str] = &[
    ":action",
    ":durative-action",
    ":task",
    ":method",
    ":durative-method",
    ":process",
    ":event",
    ":htn",
    ":tihtn",
    ":htnti",
];

/// Field keywords of items.
pub const FIELD_KEYWORDS: &[&str] = &[
    ":parameters",
    ":precondition",
    ":effect",
    ":duration",
    ":condition",
    ":agent",
    ":conflicts",
    ":task",
    ":subtasks",
    ":tasks",
    ":ordered-subtasks",
    ":ordered-tasks",
    ":ordering",
    ":order",
    ":constraints",
    ":causal-links",
    ":causallinks",
];

/// Whether `(atom` starts a section of a `define`.
pub(crate) fn is_section_head(atom: &str) -> bool {
    is_in(SECTION_HEADS, atom)
}

fn is_in(set: &[&str], atom: &str) -> bool {
    set.iter().any(|k| k.eq_ignore_ascii_case(atom))
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Category {
    /// No significant token seen yet.
    Unknown,
    Define,
    Item,
    Other,
}

#[derive(Debug, Clone, Copy)]
struct Frame {
    category: Category,
    /// The `(` and the head atom, for messages.
    open: TextRange,
    head: Option<TextRange>,
    /// End of the last significant token inside this list.
    last: TextRange,
    /// Frames standing for the ancestors of a list being re-parsed alone.
    virtual_: bool,
    /// The innermost `define` and item frames below this one (stack indexes):
    /// recovery finds them in O(1), not by searching the stack.
    define_below: Option<usize>,
    item_below: Option<usize>,
}

/// The tail of a large `:init`, built on another thread since the parse began.
struct Tail {
    /// The `:init`'s first token after the keyword, where the first part starts.
    start: usize,
    /// Where the tail starts, and the `:init`'s closing `)`.
    split: usize,
    close: usize,
    /// How deep lists nest inside the `:init` (1: facts).
    depth: usize,
    built: std::sync::mpsc::Receiver<Vec<Element>>,
}

pub(crate) struct Parser<'t> {
    text: &'t str,
    /// Token kinds; token `i` covers `offsets[i]..offsets[i + 1]`.
    kinds: &'t [SyntaxKind],
    offsets: &'t [u32],
    tail: Option<Tail>,
    pos: usize,
    builder: TreeBuilder<'t>,
    stack: Vec<Frame>,
    errors: Vec<SyntaxError>,
    /// The run of extra `)` reported last (the last error): its last `)`
    /// token, how many it has and why they are extra. The next extra `)`
    /// for the same reason after whitespace only joins it.
    extra_run: Option<(usize, usize, String)>,
    /// Lists opened in text kept as too deep and never closed: part of the
    /// missing `)` reported at the end.
    unclosed: usize,
    /// Set when a re-parse would have to touch an ancestor: the caller falls back to a full parse.
    escaped: bool,
    /// Whether a large `:init` may be built on two threads (tests compare both ways).
    pub(crate) parallel: bool,
}

impl<'t> Parser<'t> {
    pub(crate) fn new(text: &'t str, tokens: &'t Tokens) -> Self {
        Parser {
            text,
            kinds: &tokens.kinds,
            offsets: &tokens.starts,
            tail: None,
            pos: 0,
            builder: TreeBuilder::new(),
            stack: Vec::new(),
            errors: Vec::new(),
            extra_run: None,
            unclosed: 0,
            escaped: false,
            parallel: true,
        }
    }

    fn range(&self, i: usize) -> TextRange {
        TextRange::new(self.offsets[i].into(), self.offsets[i + 1].into())
    }

    fn span(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i] as usize..self.offsets[i + 1] as usize
    }

    fn token_text(&self, i: usize) -> &'t str {
        &self.text[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    fn next_significant(&self, from: usize) -> Option<usize> {
        (from..self.kinds.len()).find(|&i| !self.kinds[i].is_trivia())
    }

    fn bump(&mut self) {
        let kind = self.kinds[self.pos];
        self.builder.token(kind, self.text, self.span(self.pos));
        self.pos += 1;
    }

    /// The stack index of the innermost frame of `category`.
    fn innermost(&self, category: Category) -> Option<usize> {
        let top = self.stack.last()?;
        if top.category == category {
            return Some(self.stack.len() - 1);
        }
        match category {
            Category::Define => top.define_below,
            Category::Item => top.item_below,
            _ => unreachable!("only defines and items are looked up"),
        }
    }

    fn push_frame(&mut self, category: Category, open: TextRange, virtual_: bool) {
        let (define_below, item_below) = (self.innermost(Category::Define), self.innermost(Category::Item));
        self.stack.push(Frame { category, open, head: None, last: open, virtual_, define_below, item_below });
    }

    /// Whether the list starting at token `i` (a `(`) is a section of a `define`.
    fn starts_section(&self, i: usize) -> bool {
        self.next_significant(i + 1)
            .is_some_and(|j| self.kinds[j] == SyntaxKind::Keyword && is_in(SECTION_HEADS, self.token_text(j)))
    }

    /// The head of a list, when it names the list (`define`, `:action`, `and`):
    /// not a variable or a number, which would make a confusing message.
    fn head_text(&self, frame: &Frame) -> &'t str {
        match frame.head.map(|r| &self.text[r]) {
            Some(h) if !h.starts_with('?') && super::lexer::classify_atom(h) != SyntaxKind::Number => h,
            _ => "",
        }
    }

    /// Closes the open lists above `keep` (a stack length), reporting the missing `)` once.
    fn close_missing(&mut self, keep: usize) {
        if self.stack.len() <= keep {
            return;
        }
        if self.stack[keep..].iter().any(|f| f.virtual_) {
            self.escaped = true;
        }
        let innermost = *self.stack.last().expect("non-empty stack");
        let outermost = self.stack[keep];
        let count = self.stack.len() - keep + std::mem::take(&mut self.unclosed);
        let head = self.head_text(&innermost);
        let what = if head.is_empty() { String::from("a list") } else { format!("`({head}`") };
        let message = if count == 1 {
            format!("missing `)`: {what} is not closed")
        } else {
            format!("missing {count} `)`: {what} and the lists around it are not closed")
        };
        let outer_head = self.head_text(&outermost);
        let related = (
            outermost.open,
            if outer_head.is_empty() {
                "this `(` is not closed".to_string()
            } else {
                format!("this `({outer_head}` is not closed")
            },
        );
        self.errors.push(SyntaxError {
            kind: SyntaxErrorKind::MissingParen,
            range: innermost.last,
            message,
            related: Some(related),
            fix: Some((TextRange::empty(innermost.last.end()), ")".repeat(count))),
        });
        while self.stack.len() > keep {
            let frame = self.stack.pop().expect("non-empty stack");
            if !frame.virtual_ {
                self.builder.finish_node();
            }
        }
    }

    /// Parses tokens until the end, or until the stack is back to `stop` lists.
    fn parse_tokens(&mut self, stop: Option<usize>) {
        while self.pos < self.kinds.len() && !self.escaped {
            if stop.is_some_and(|s| self.stack.len() == s) && self.pos > 0 {
                return;
            }
            let kind = self.kinds[self.pos];
            match kind {
                SyntaxKind::Whitespace | SyntaxKind::Comment => self.bump(),
                SyntaxKind::LParen => {
                    if self.starts_section(self.pos) {
                        // A new section: it belongs directly to the innermost `define`.
                        let keep = self.innermost(Category::Define).map_or(0, |i| i + 1);
                        self.close_missing(keep);
                        if self.escaped {
                            return;
                        }
                    }
                    if self.stack.len() >= MAX_NESTING {
                        self.too_deep();
                        continue;
                    }
                    let open = self.range(self.pos);
                    self.builder.start_node(SyntaxKind::List);
                    self.bump();
                    self.push_frame(Category::Unknown, open, false);
                }
                SyntaxKind::RParen => self.close_paren(),
                _ => self.atom(),
            }
        }
    }

    /// Keeps the list starting at the current `(`, which would nest deeper
    /// than [`MAX_NESTING`], as flat tokens in an `Error` node, up to its
    /// matching `)` or the end of the text; reports it once.
    fn too_deep(&mut self) {
        let open = self.range(self.pos);
        self.builder.start_node(SyntaxKind::Error);
        let mut depth = 0usize;
        let mut last = open;
        while self.pos < self.kinds.len() {
            match self.kinds[self.pos] {
                SyntaxKind::LParen => depth += 1,
                SyntaxKind::RParen => depth -= 1,
                _ => {}
            }
            if !self.kinds[self.pos].is_trivia() {
                last = self.range(self.pos);
            }
            self.bump();
            if depth == 0 {
                break;
            }
        }
        self.builder.finish_node();
        self.unclosed += depth;
        if let Some(top) = self.stack.last_mut() {
            top.last = last;
        }
        self.errors.push(SyntaxError {
            kind: SyntaxErrorKind::TooDeep,
            range: open,
            message: format!(
                "lists nested more than {MAX_NESTING} deep: this list is kept as text, not read"
            ),
            related: None,
            fix: None,
        });
    }

    fn atom(&mut self) {
        let range = self.range(self.pos);
        let text = self.token_text(self.pos);
        let kind = self.kinds[self.pos];
        match self.stack.last().map(|f| f.category) {
            Some(Category::Unknown) => {
                let top = self.stack.last_mut().expect("non-empty stack");
                top.head = Some(range);
                top.category = if text.eq_ignore_ascii_case("define") {
                    Category::Define
                } else if kind == SyntaxKind::Keyword && is_in(ITEM_HEADS, text) {
                    Category::Item
                } else {
                    Category::Other
                };
            }
            Some(Category::Other) if kind == SyntaxKind::Keyword && is_in(FIELD_KEYWORDS, text) => {
                // A field keyword inside a formula: the formula is missing its `)`.
                let item = self.innermost(Category::Item);
                let define = self.innermost(Category::Define);
                if let Some(item) = item
                    && define.is_none_or(|d| d < item)
                {
                    self.close_missing(item + 1);
                    if self.escaped {
                        return;
                    }
                }
            }
            _ => {}
        }
        let is_head = self.stack.last().is_some_and(|f| f.head == Some(range));
        if let Some(top) = self.stack.last_mut() {
            top.last = range;
        }
        self.bump();
        if is_head && kind == SyntaxKind::Keyword && text.eq_ignore_ascii_case(":init") {
            self.parallel_interior();
        }
    }

    /// Builds the rest of a large `:init` on two threads, when nothing in it can
    /// trigger recovery: its parentheses balance before the end of the file and
    /// it holds no keyword (so no section or field starts inside). Then the
    /// sequential parser would do nothing but open and close lists, which is
    /// what each half does: the tree is the same, built in about half the time.
    fn parallel_interior(&mut self) {
        if !self.parallel || self.stack.iter().any(|f| f.virtual_) {
            return;
        }
        let start = self.pos;
        // The halves are built without the nesting limit: only an interior
        // that stays within it may be built that way.
        if let Some(tail) = self.tail.take_if(|t| t.start == start)
            && self.stack.len() + tail.depth <= MAX_NESTING
        {
            let first = fragment(self.text, self.kinds, self.offsets, start, tail.split);
            let second = tail
                .built
                .recv()
                .unwrap_or_else(|_| fragment(self.text, self.kinds, self.offsets, tail.split, tail.close));
            self.join_interior(start, tail.close, first, second);
            return;
        }
        let (mut depth, mut deepest) = (0usize, 0usize);
        let mut close = None;
        for i in start..self.kinds.len() {
            match self.kinds[i] {
                SyntaxKind::LParen => {
                    depth += 1;
                    deepest = deepest.max(depth);
                }
                SyntaxKind::RParen if depth == 0 => {
                    close = Some(i);
                    break;
                }
                SyntaxKind::RParen => depth -= 1,
                SyntaxKind::Keyword => return,
                _ => {}
            }
        }
        let Some(close) = close else { return };
        if close - start < PARALLEL_FROM_TOKENS || self.stack.len() + deepest > MAX_NESTING {
            return;
        }
        // Split at the first top-level `(` after the middle.
        let mid = start + (close - start) / 2;
        let mut depth = 0usize;
        let mut split = None;
        for i in start..close {
            match self.kinds[i] {
                SyntaxKind::LParen if depth == 0 && i >= mid => {
                    split = Some(i);
                    break;
                }
                SyntaxKind::LParen => depth += 1,
                SyntaxKind::RParen => depth -= 1,
                _ => {}
            }
        }
        let Some(split) = split else { return };
        let (text, kinds, offsets) = (self.text, self.kinds, self.offsets);
        let halves = std::thread::scope(|scope| {
            let second = scope.spawn(|| fragment(text, kinds, offsets, split, close));
            let first = fragment(text, kinds, offsets, start, split);
            second.join().ok().map(|second| (first, second))
        });
        let Some((first, second)) = halves else { return };
        self.join_interior(start, close, first, second);
    }

    /// Appends the two parts of an `:init` interior built apart, and moves past it.
    fn join_interior(&mut self, start: usize, close: usize, first: Vec<Element>, second: Vec<Element>) {
        self.builder.extend(first);
        self.builder.extend(second);
        if let Some(last) = (start..close).rev().find(|&i| !self.kinds[i].is_trivia()) {
            let range = self.range(last);
            if let Some(top) = self.stack.last_mut() {
                top.last = range;
            }
        }
        self.pos = close;
    }

    fn close_paren(&mut self) {
        let range = self.range(self.pos);
        let Some(top) = self.stack.last().copied() else {
            self.extra_paren("there is no open `(` to close".to_string());
            return;
        };
        if top.virtual_ {
            self.escaped = true;
            return;
        }
        let next = self.next_significant(self.pos + 1);
        let parent_is_define =
            self.stack.len() >= 2 && self.stack[self.stack.len() - 2].category == Category::Define;
        let names_section = top.head.is_some_and(|h| self.text[h].starts_with(':'));
        let extra = match (top.category, next) {
            (Category::Item, Some(j)) => {
                self.kinds[j] == SyntaxKind::Keyword && is_in(FIELD_KEYWORDS, self.token_text(j))
            }
            (Category::Define, Some(j)) => self.kinds[j] == SyntaxKind::LParen && self.starts_section(j),
            // A section of a `define` closed right before a list that is no
            // section (`(:init (at a b)) (road a b))`): the `)` is extra.
            (Category::Other, Some(j)) if parent_is_define && names_section => {
                self.kinds[j] == SyntaxKind::LParen
                    && self.next_significant(j + 1).is_some_and(|k| {
                        matches!(
                            self.kinds[k],
                            SyntaxKind::Symbol | SyntaxKind::Variable | SyntaxKind::Number
                        )
                    })
            }
            _ => false,
        };
        if extra {
            let what = self.head_text(&top);
            self.extra_paren(format!("it closes `({what}` before its end, which follows"));
            if let Some(top) = self.stack.last_mut() {
                top.last = range;
            }
            return;
        }
        self.bump();
        self.builder.finish_node();
        self.stack.pop();
        if let Some(parent) = self.stack.last_mut() {
            parent.last = range;
        }
    }

    /// Reports the current `)` as extra (`reason` says why) and keeps it in an
    /// `Error` node. A run of extra `)` for the same reason, separated by
    /// whitespace only, is one error with its count and the run's range, so
    /// that a file of `)` gives one error, not one per byte.
    fn extra_paren(&mut self, reason: String) {
        let at = self.pos;
        let range = self.range(at);
        self.builder.start_node(SyntaxKind::Error);
        self.bump();
        self.builder.finish_node();
        if let Some((end, count, why)) = &mut self.extra_run
            && *why == reason
            && (*end + 1..at).all(|i| self.kinds[i] == SyntaxKind::Whitespace)
            && let Some(last) = self.errors.last_mut()
        {
            // Only whitespace since the run's last `)`: no other error came between.
            debug_assert_eq!(last.kind, SyntaxErrorKind::ExtraParen);
            *end = at;
            *count += 1;
            last.range = last.range.cover(range);
            last.message = format!("unexpected `)` ({count} in a row): {reason}");
            last.fix = Some((last.range, String::new()));
            return;
        }
        self.errors.push(SyntaxError {
            kind: SyntaxErrorKind::ExtraParen,
            range,
            message: format!("unexpected `)`: {reason}"),
            related: None,
            fix: Some((range, String::new())),
        });
        self.extra_run = Some((at, 1, reason));
    }

    /// Parses a whole file.
    pub(crate) fn parse_file(mut self) -> (GreenNode, Vec<SyntaxError>) {
        self.builder.start_node(SyntaxKind::Root);
        self.parse_tokens(None);
        self.close_missing(0);
        self.builder.finish_node();
        (self.builder.finish(), self.errors)
    }

    /// Parses one list alone, inside ancestors of the given kinds (outermost first).
    ///
    /// Returns `None` when the text is not exactly one list, or when parsing it
    /// would report an error or change its ancestors: then only a full parse is
    /// equivalent.
    pub(crate) fn parse_list_in(mut self, ancestors: &[AncestorKind]) -> Option<GreenNode> {
        if self.kinds.first().copied() != Some(SyntaxKind::LParen) {
            return None;
        }
        let dummy = TextRange::empty(0.into());
        for a in ancestors {
            let category = match a {
                AncestorKind::Define => Category::Define,
                AncestorKind::Item => Category::Item,
                AncestorKind::Other => Category::Other,
            };
            self.push_frame(category, dummy, true);
        }
        let base = self.stack.len();
        // The starting `(` must not itself start a section somewhere else.
        if self.starts_section(0) && ancestors.last() != Some(&AncestorKind::Define) {
            return None;
        }
        self.parse_tokens(Some(base));
        if self.escaped || !self.errors.is_empty() || self.stack.len() != base || self.pos != self.kinds.len()
        {
            return None;
        }
        let green = self.builder.finish();
        (green.kind() == SyntaxKind::List.into()).then_some(green)
    }
}

/// What an ancestor list of a re-parsed list is, as far as recovery cares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum AncestorKind {
    Define,
    Item,
    Other,
}

pub(crate) fn ancestor_kind(head: Option<&str>) -> AncestorKind {
    match head {
        Some(h) if h.eq_ignore_ascii_case("define") => AncestorKind::Define,
        Some(h) if is_in(ITEM_HEADS, h) => AncestorKind::Item,
        _ => AncestorKind::Other,
    }
}

/// The elements of tokens `from..to`, which balance and need no recovery.
fn fragment(text: &str, kinds: &[SyntaxKind], offsets: &[u32], from: usize, to: usize) -> Vec<Element> {
    let span = |i: usize| offsets[i] as usize..offsets[i + 1] as usize;
    let mut builder = TreeBuilder::new();
    for (i, &kind) in kinds.iter().enumerate().take(to).skip(from) {
        match kind {
            SyntaxKind::LParen => {
                builder.start_node(SyntaxKind::List);
                builder.token(kind, text, span(i));
            }
            SyntaxKind::RParen => {
                builder.token(kind, text, span(i));
                builder.finish_node();
            }
            _ => builder.token(kind, text, span(i)),
        }
    }
    builder.into_children()
}

/// A large `:init` to build in parallel: below this many tokens, a thread
/// costs more than it saves.
const PARALLEL_FROM_TOKENS: usize = 50_000;

/// Where the first large `:init` of the tokens is, and where to split it so
/// that a thread started now, building the tail, finishes with the parser,
/// which first parses everything before it, then the head of the `:init`:
/// `(start, split, close, depth)`, `depth` how deep lists nest inside it.
/// `None` when there is none, or when its interior could trigger recovery
/// (a keyword inside, unbalanced parentheses): then the parser decides when
/// it gets there.
fn large_init(text: &str, kinds: &[SyntaxKind], offsets: &[u32]) -> Option<(usize, usize, usize, usize)> {
    let significant = |i: usize| !kinds[i].is_trivia();
    let keyword = (0..kinds.len()).find(|&k| {
        kinds[k] == SyntaxKind::Keyword
            && text[offsets[k] as usize..offsets[k + 1] as usize].eq_ignore_ascii_case(":init")
            && (0..k).rev().find(|&i| significant(i)).is_some_and(|i| kinds[i] == SyntaxKind::LParen)
    })?;
    let start = keyword + 1;
    let (mut depth, mut deepest) = (0usize, 0usize);
    let mut close = None;
    for (i, &kind) in kinds.iter().enumerate().skip(start) {
        match kind {
            SyntaxKind::LParen => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            SyntaxKind::RParen if depth == 0 => {
                close = Some(i);
                break;
            }
            SyntaxKind::RParen => depth -= 1,
            SyntaxKind::Keyword => return None,
            _ => {}
        }
    }
    let close = close?;
    if close - start < PARALLEL_FROM_TOKENS {
        return None;
    }
    // The parser's share: the `keyword` tokens before, then `start..split`.
    let target = (start + close).saturating_sub(keyword) / 2;
    let target = target.clamp(start + (close - start) / 4, close - (close - start) / 4);
    let mut depth = 0usize;
    for (i, &kind) in kinds.iter().enumerate().take(close).skip(start) {
        match kind {
            SyntaxKind::LParen if depth == 0 && i >= target => return Some((start, i, close, deepest)),
            SyntaxKind::LParen => depth += 1,
            SyntaxKind::RParen => depth -= 1,
            _ => {}
        }
    }
    None
}

/// Parses a whole file from its tokens; the tail of a large `:init` is built
/// on a second thread from the start.
pub(crate) fn parse_file(text: &str, tokens: &Tokens) -> (GreenNode, Vec<SyntaxError>) {
    let mut parser = Parser::new(text, tokens);
    let Some((start, split, close, depth)) = large_init(text, &tokens.kinds, &tokens.starts) else {
        return parser.parse_file();
    };
    std::thread::scope(|scope| {
        let (send, built) = std::sync::mpsc::channel();
        let (kinds, offsets) = (&tokens.kinds[..], &tokens.starts[..]);
        scope.spawn(move || {
            // A parser that does not use it (it never happens) drops the receiver.
            let _ = send.send(fragment(text, kinds, offsets, split, close));
        });
        parser.tail = Some(Tail { start, split, close, depth, built });
        parser.parse_file()
    })
}
