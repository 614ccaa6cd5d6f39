//! Formatting domains and problems (`hipop fmt`, `textDocument/formatting`).
//!
//! The layout is a function of the file's tokens, its comments (and whether
//! each ends a line of code or stands on its own line) and where it has blank
//! lines, never of its other whitespace: formatting a formatted file gives it
//! back. The rules (docs/formatting.md):
//!
//! - a list that fits in [`WIDTH`] columns stays on one line, unless it is a
//!   `define`, an action, task or method with two fields or more, or a section
//!   (`:predicates`, `:init`…) holding two lists or more;
//! - otherwise its head stays after the `(` (`(:action move`, `(define (domain
//!   d)`, `(forall (?x - t)`, `(at start`), and the rest goes one element per
//!   line, two spaces deeper than the line the list starts on; a field keyword
//!   stays with its value (`:parameters (?x - block)`); in a typed list each
//!   `a b - t` group gets its own line; a list of atoms only fills its lines;
//! - `)` closes on the line of the last element, except after a comment;
//! - a comment at the end of a line stays at the end of that element's line,
//!   a comment on its own line keeps its own line; blank lines between the
//!   elements of a list that is broken over lines are kept (a run is one);
//! - atoms are copied verbatim; no trailing whitespace; one final newline;
//!   a file whose first line ends with CRLF is written with CRLF; a UTF-8
//!   byte-order mark is kept.
//!
//! A file with a syntax error is not formatted: [`FormatError`] says where
//! the first one is. Neither is a file with atoms outside any list (a plan).

use rowan::{NodeOrToken, TextRange, TextSize};

use crate::syntax::{ITEM_HEADS, Lang, Parse, SECTION_HEADS, SyntaxErrorKind, SyntaxKind};

/// The line width lists are fitted in.
pub const WIDTH: usize = 100;
/// How much deeper the elements of a broken list are indented.
const INDENT: usize = 2;
/// The UTF-8 byte-order mark, which the lexer reads as whitespace.
const BOM: &str = "\u{feff}";

/// Why a file is not formatted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FormatError {
    pub kind: FormatErrorKind,
    /// Where: the first syntax error, the first atom outside any list.
    pub range: TextRange,
    pub message: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FormatErrorKind {
    /// The file has a syntax error (unbalanced parentheses, nesting too deep).
    Syntax,
    /// The file is not a domain or a problem (a plan).
    NotAModel,
}

/// Formats a domain or problem file.
pub fn format(text: &str) -> Result<String, FormatError> {
    format_parse(&crate::syntax::parse(text))
}

/// Formats the file `parse` was parsed from.
pub fn format_parse(parse: &Parse) -> Result<String, FormatError> {
    if let Some(e) = parse.errors.iter().min_by_key(|e| e.range.start()) {
        let what = match e.kind {
            SyntaxErrorKind::MissingParen | SyntaxErrorKind::ExtraParen => "syntax error",
            SyntaxErrorKind::TooDeep => "nesting too deep",
        };
        return Err(FormatError {
            kind: FormatErrorKind::Syntax,
            range: e.range,
            message: format!("{what}: {}", e.message),
        });
    }
    let tree = Tree::build(&parse.green.0)?;
    let mut out =
        Out { buf: String::new(), col: 0, line_indent: 0, line: 0, nl: tree.newline, comments: Vec::new() };
    tree.root(&mut out);
    Ok(out.finish(tree.bom))
}

/// What a list holds.
enum Item<'a> {
    Atom(SyntaxKind, &'a str),
    /// A list, by its index in [`Tree::lists`].
    List(usize),
    /// A comment; `own_line` when nothing but whitespace precedes it on its line.
    Comment {
        text: &'a str,
        own_line: bool,
    },
}

struct Child<'a> {
    item: Item<'a>,
    /// Whether a blank line precedes it.
    blank_before: bool,
}

struct List<'a> {
    children: Vec<Child<'a>>,
    /// The width of the list on one line.
    flat: usize,
    /// Whether a comment is inside, at any depth: then it is broken over lines.
    comment: bool,
    /// Whether it is broken over lines even when it fits (a `define`, an action…).
    forced: bool,
}

struct Tree<'a> {
    /// The lists; the last one is the file itself (its children the top level).
    lists: Vec<List<'a>>,
    root: usize,
    newline: &'static str,
    bom: &'static str,
}

/// Heads whose first argument, a list, stays on their line when broken.
const BINDERS: &[&str] = &[
    "define",
    "forall",
    "exists",
    "when",
    ":derived",
    "increase",
    "decrease",
    "assign",
    "scale-up",
    "scale-down",
    "=",
    "<",
    ">",
    "<=",
    ">=",
];

fn is_in(set: &[&str], atom: &str) -> bool {
    set.iter().any(|k| k.eq_ignore_ascii_case(atom))
}

/// How many line breaks a whitespace token holds (`\n`, `\r\n`, a lone `\r`).
fn line_breaks(ws: &str) -> usize {
    let b = ws.as_bytes();
    (0..b.len()).filter(|&i| b[i] == b'\n' || (b[i] == b'\r' && b.get(i + 1) != Some(&b'\n'))).count()
}

fn width(text: &str) -> usize {
    text.chars().count()
}

impl<'a> Tree<'a> {
    /// Reads the tree of a file without syntax errors, with a loop (no recursion).
    fn build(root: &'a rowan::GreenNodeData) -> Result<Tree<'a>, FormatError> {
        let kind = |raw| <Lang as rowan::Language>::kind_from_raw(raw);
        let mut lists: Vec<List<'a>> = Vec::new();
        // The lists being read, outermost first (the file at the bottom), and
        // whether a blank line preceded each.
        let mut open: Vec<(List<'a>, bool)> =
            vec![(List { children: Vec::new(), flat: 0, comment: false, forced: false }, false)];
        let mut walk: Vec<rowan::Children<'a>> = vec![root.children()];
        let mut at = TextSize::from(0);
        let mut breaks = 0usize;
        let mut start = true;
        let (mut newline, mut bom) = (None, "");
        while let Some(top) = walk.last_mut() {
            let token = match top.next() {
                None => {
                    walk.pop();
                    continue;
                }
                Some(NodeOrToken::Node(n)) => {
                    walk.push(n.children());
                    continue;
                }
                Some(NodeOrToken::Token(t)) => t,
            };
            let (k, text) = (kind(token.kind()), token.text());
            let range = TextRange::at(at, token.text_len());
            at += token.text_len();
            let blank = breaks >= 2;
            match k {
                SyntaxKind::Whitespace => {
                    if start && text == BOM {
                        bom = BOM;
                    }
                    if newline.is_none()
                        && let Some(i) = text.find('\n')
                    {
                        newline = Some(if i > 0 && text.as_bytes()[i - 1] == b'\r' { "\r\n" } else { "\n" });
                    }
                    breaks += line_breaks(text);
                    continue;
                }
                SyntaxKind::Comment => {
                    let own_line = start || breaks > 0;
                    let top = &mut open.last_mut().expect("the file is open").0;
                    top.comment = true;
                    top.children.push(Child {
                        item: Item::Comment { text: text.trim_end(), own_line },
                        blank_before: blank,
                    });
                }
                SyntaxKind::LParen => {
                    open.push((List { children: Vec::new(), flat: 0, comment: false, forced: false }, blank));
                }
                SyntaxKind::RParen => {
                    let (mut list, blank) = open.pop().expect("no syntax error: `)` closes a list");
                    list.finish();
                    let id = lists.len();
                    let (flat, comment) = (list.flat, list.comment);
                    lists.push(list);
                    let Some((parent, _)) = open.last_mut() else {
                        unreachable!("no syntax error: the file is not closed by a `)`")
                    };
                    parent.comment |= comment;
                    parent.flat += flat;
                    parent.children.push(Child { item: Item::List(id), blank_before: blank });
                }
                _ => {
                    if open.len() == 1 {
                        return Err(FormatError {
                            kind: FormatErrorKind::NotAModel,
                            range,
                            message: format!(
                                "`{text}` is outside any list: this is not a domain or a problem (a plan?)"
                            ),
                        });
                    }
                    let top = &mut open.last_mut().expect("a list is open").0;
                    top.flat += width(text);
                    top.children.push(Child { item: Item::Atom(k, text), blank_before: blank });
                }
            }
            // Line breaks are counted from the last token that is not whitespace.
            breaks = 0;
            start = false;
        }
        assert!(open.len() == 1, "no syntax error: every list is closed");
        let (file, _) = open.pop().expect("the file");
        lists.push(file);
        Ok(Tree { root: lists.len() - 1, lists, newline: newline.unwrap_or("\n"), bom })
    }

    fn root(&self, out: &mut Out) {
        let file = &self.lists[self.root];
        let mut first = true;
        for child in &file.children {
            match child.item {
                Item::Comment { text, own_line: false } if !first => out.trailing_comment(text),
                _ => {
                    if !first {
                        out.newline(0, child.blank_before);
                    }
                    self.element(&child.item, out, 0);
                }
            }
            first = false;
        }
        if !first {
            out.buf.push_str(out.nl);
        }
    }

    /// Writes an element at the cursor; `trail` is the width of what follows
    /// it on its line (the `)` closing around it).
    fn element(&self, item: &Item<'a>, out: &mut Out, trail: usize) {
        match *item {
            Item::Atom(_, text) => out.push(text),
            Item::List(id) => self.list(id, out, trail),
            Item::Comment { text, .. } => out.push(text),
        }
    }

    fn elem_width(&self, item: &Item<'a>) -> usize {
        match *item {
            Item::Atom(_, text) => width(text),
            Item::List(id) => self.lists[id].flat,
            Item::Comment { .. } => 0,
        }
    }

    fn flat(&self, id: usize, out: &mut Out) {
        out.push("(");
        let mut first = true;
        for child in &self.lists[id].children {
            if !first {
                out.push(" ");
            }
            first = false;
            match child.item {
                Item::Atom(_, text) => out.push(text),
                Item::List(l) => self.flat(l, out),
                Item::Comment { .. } => unreachable!("a list with a comment is not flat"),
            }
        }
        out.push(")");
    }

    fn list(&self, id: usize, out: &mut Out, trail: usize) {
        let list = &self.lists[id];
        if !list.comment && !list.forced && out.col + list.flat + trail <= WIDTH {
            self.flat(id, out);
            return;
        }
        let indent = out.line_indent;
        let inner = indent + INDENT;
        let joins = self.joins(list);
        // What follows each child on its line, if it is not broken: the rest of
        // its unit, the `)`.
        let mut rest = vec![0usize; list.children.len()];
        let ends_with_comment = matches!(list.children.last().map(|c| &c.item), Some(Item::Comment { .. }));
        let mut after = if ends_with_comment { 0 } else { trail + 1 };
        for (i, child) in list.children.iter().enumerate().rev() {
            if matches!(child.item, Item::Comment { .. }) {
                after = 0;
                continue;
            }
            rest[i] = after;
            after = if joins[i] == Join::Attach { 1 + self.elem_width(&child.item) + rest[i] } else { 0 };
        }
        out.push("(");
        let mut first = true;
        let mut need_newline = false;
        for (i, child) in list.children.iter().enumerate() {
            match child.item {
                Item::Comment { text, own_line: false } => {
                    if first {
                        out.push(text);
                    } else {
                        out.trailing_comment(text);
                    }
                    need_newline = true;
                }
                Item::Comment { text, own_line: true } => {
                    out.newline(inner, child.blank_before && !first);
                    out.push(text);
                    need_newline = true;
                }
                _ => {
                    if need_newline || (!first && joins[i] == Join::Start) {
                        out.newline(inner, child.blank_before && !first);
                    } else if !first {
                        let fits = match joins[i] {
                            Join::FillGroup { width, last } => out.col + 1 + width + rest[last] <= WIDTH,
                            _ => out.col + 1 + self.elem_width(&child.item) + rest[i] <= WIDTH,
                        };
                        if joins[i] == Join::Attach || fits {
                            out.push(" ");
                        } else {
                            out.newline(inner, child.blank_before);
                        }
                    }
                    self.element(&child.item, out, rest[i]);
                    need_newline = false;
                }
            }
            first = false;
        }
        if ends_with_comment {
            out.newline(indent, false);
        }
        out.push(")");
    }

    /// How each element of a broken list joins the one before (comments: unused).
    fn joins(&self, list: &List<'a>) -> Vec<Join> {
        let mut joins = vec![Join::Start; list.children.len()];
        let elements: Vec<usize> = (0..list.children.len())
            .filter(|&i| !matches!(list.children[i].item, Item::Comment { .. }))
            .collect();
        let Some(&e0) = elements.first() else { return joins };
        joins[e0] = Join::Attach;
        let item = |k: usize| &list.children[elements[k]].item;
        let atom = |k: usize| match item(k) {
            Item::Atom(kind, text) => Some((*kind, *text)),
            _ => None,
        };
        let is_dash = |k: usize| atom(k).is_some_and(|(kind, t)| kind == SyntaxKind::Symbol && t == "-");
        let n = elements.len();
        if (1..n).any(is_dash) {
            // A typed list: one line per `a b c - t` group, filled.
            let head = match atom(0) {
                Some((SyntaxKind::Keyword, _)) => true,
                Some((SyntaxKind::Symbol, _)) => {
                    !is_dash(0) && atom(1).is_some_and(|(kind, _)| kind == SyntaxKind::Variable)
                }
                _ => false,
            };
            // Sections (`:types`, `:objects`) have a line per group; parameters
            // and predicates fill their lines with whole groups.
            let per_line = matches!(atom(0), Some((SyntaxKind::Keyword, _)));
            let mut k = usize::from(head);
            while k < n {
                // The group: up to the type after a `-`, or the end.
                let end = (k..n).find(|&j| is_dash(j)).map_or(n - 1, |j| (j + 1).min(n - 1));
                if k > 0 {
                    joins[elements[k]] = if per_line {
                        Join::Start
                    } else {
                        let width = (k..=end).map(|j| self.elem_width(item(j))).sum::<usize>() + end - k;
                        Join::FillGroup { width, last: elements[end] }
                    };
                }
                for j in k + 1..=end {
                    joins[elements[j]] = Join::Fill;
                }
                k = end + 1;
            }
            return joins;
        }
        if (0..n).all(|k| atom(k).is_some()) {
            // Atoms only: fill the lines.
            for &e in &elements[1..] {
                joins[e] = Join::Fill;
            }
            return joins;
        }
        let mut k = 1;
        if let Some((SyntaxKind::Symbol | SyntaxKind::Keyword, head)) = atom(0)
            && n > 1
        {
            let attach = match item(1) {
                Item::Atom(kind, _) => *kind != SyntaxKind::Keyword,
                _ => is_in(BINDERS, head),
            };
            if attach {
                joins[elements[1]] = Join::Attach;
                k = 2;
            }
        }
        while k < n {
            let keyword = atom(k).is_some_and(|(kind, _)| kind == SyntaxKind::Keyword);
            if keyword && k + 1 < n && atom(k + 1).is_none_or(|(kind, _)| kind != SyntaxKind::Keyword) {
                joins[elements[k + 1]] = Join::Attach;
                k += 2;
            } else {
                k += 1;
            }
        }
        joins
    }
}

impl List<'_> {
    /// Completes the widths once every child is read, and whether the list is
    /// always broken.
    fn finish(&mut self) {
        let elements = self.children.iter().filter(|c| !matches!(c.item, Item::Comment { .. }));
        let n = elements.clone().count();
        self.flat += 2 + n.saturating_sub(1);
        let head = match self.children.iter().find(|c| !matches!(c.item, Item::Comment { .. })) {
            Some(Child { item: Item::Atom(_, text), .. }) => *text,
            _ => return,
        };
        let rest = elements.skip(1);
        self.forced = if head.eq_ignore_ascii_case("define") {
            true
        } else if is_in(ITEM_HEADS, head) {
            rest.filter(|c| matches!(c.item, Item::Atom(SyntaxKind::Keyword, _))).count() >= 2
        } else if is_in(SECTION_HEADS, head) {
            rest.filter(|c| matches!(c.item, Item::List(_))).count() >= 2
        } else {
            false
        };
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Join {
    /// On a new line.
    Start,
    /// On the same line as the element before.
    Attach,
    /// On the same line if it fits, else on a new line.
    Fill,
    /// The first element of a group (`?a ?b - t`): on the same line if the
    /// whole group fits, up to its last element (a child index).
    FillGroup { width: usize, last: usize },
}

struct Out {
    buf: String,
    col: usize,
    /// The indentation of the current line.
    line_indent: usize,
    /// The current line's number.
    line: usize,
    nl: &'static str,
    /// The comments that end lines: where in `buf` each goes, its line, the
    /// column the code before it ends at.
    comments: Vec<(usize, usize, usize)>,
}

impl Out {
    /// A comment at the end of the current line: placed by [`Out::finish`].
    fn trailing_comment(&mut self, text: &str) {
        self.comments.push((self.buf.len(), self.line, self.col));
        self.buf.push_str(text);
    }

    /// The text, with the comments that end consecutive lines aligned one
    /// space after the longest of those lines.
    fn finish(self, bom: &str) -> String {
        let mut out = String::with_capacity(bom.len() + self.buf.len() + 8 * self.comments.len());
        out.push_str(bom);
        let mut copied = 0;
        let mut run = 0;
        while run < self.comments.len() {
            let mut end = run + 1;
            while end < self.comments.len() && self.comments[end].1 == self.comments[end - 1].1 + 1 {
                end += 1;
            }
            let column = self.comments[run..end].iter().map(|c| c.2).max().unwrap_or(0) + 1;
            for &(at, _, col) in &self.comments[run..end] {
                out.push_str(&self.buf[copied..at]);
                out.extend(std::iter::repeat_n(' ', column - col));
                copied = at;
            }
            run = end;
        }
        out.push_str(&self.buf[copied..]);
        out
    }

    fn push(&mut self, text: &str) {
        self.buf.push_str(text);
        self.col += width(text);
    }

    fn newline(&mut self, indent: usize, blank: bool) {
        self.buf.push_str(self.nl);
        if blank {
            self.buf.push_str(self.nl);
        }
        self.buf.extend(std::iter::repeat_n(' ', indent));
        self.col = indent;
        self.line_indent = indent;
        self.line += 1 + usize::from(blank);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Formats, and checks that formatting again changes nothing.
    fn fmt(text: &str) -> String {
        let once = format(text).unwrap_or_else(|e| panic!("not formatted: {e:?}"));
        assert_eq!(format(&once).as_ref(), Ok(&once), "formatting twice changes the text:\n{once}");
        once
    }

    #[test]
    fn a_domain_is_laid_out_by_its_structure() {
        let text = "(define (domain d) (:requirements :strips :typing) (:types block - object)
(:predicates (on ?x ?y - block) (clear ?x - block))
(:action stack :parameters (?x ?y - block) :precondition (and (clear ?x) (clear ?y))
:effect (and (on ?x ?y) (not (clear ?y)) (forall (?z - block) (when (and (on ?z ?x) (clear ?z) (clear ?y) (clear ?x)) (and (not (on ?z ?x))))))))";
        assert_eq!(
            fmt(text),
            "(define (domain d)
  (:requirements :strips :typing)
  (:types block - object)
  (:predicates
    (on ?x ?y - block)
    (clear ?x - block))
  (:action stack
    :parameters (?x ?y - block)
    :precondition (and (clear ?x) (clear ?y))
    :effect (and
      (on ?x ?y)
      (not (clear ?y))
      (forall (?z - block)
        (when (and (on ?z ?x) (clear ?z) (clear ?y) (clear ?x)) (and (not (on ?z ?x))))))))
"
        );
    }

    #[test]
    fn comments_stay_where_they_are() {
        let text = "; header\n\n\n(define (domain d) ; the name\n  ; before the predicates\n  (:predicates (p) ; first\n (q)     ; second\n (long-predicate-name)   ; third\n ; last\n )\n(:action a ; name\n :parameters ; none\n () :effect (p)) )  ; end\n";
        assert_eq!(
            fmt(text),
            "; header

(define (domain d) ; the name
  ; before the predicates
  (:predicates
    (p)                   ; first
    (q)                   ; second
    (long-predicate-name) ; third
    ; last
  )
  (:action a    ; name
    :parameters ; none
    ()
    :effect (p))) ; end
"
        );
    }

    #[test]
    fn a_comment_first_in_a_list_keeps_its_line() {
        assert_eq!(fmt("(define ; d\n (domain d))"), "(define ; d\n  (domain d))\n");
        assert_eq!(fmt("(define\n ; d\n (domain d))"), "(define\n  ; d\n  (domain d))\n");
        assert_eq!(fmt("(; d\n define (domain d))"), "(; d\n  define (domain d))\n");
    }

    #[test]
    fn blank_lines_are_kept_between_lines_and_runs_are_one() {
        assert_eq!(
            fmt("(define (domain d)\n\n\n\n  (:types a)   \n\n  (:predicates (p)\n\n (q)))\n\n\n"),
            "(define (domain d)\n\n  (:types a)\n\n  (:predicates\n    (p)\n\n    (q)))\n"
        );
        // Not inside a list that fits on one line.
        assert_eq!(fmt("(and (p)\n\n (q))"), "(and (p) (q))\n");
    }

    #[test]
    fn typed_lists_keep_their_groups() {
        let objects: Vec<String> = (0..30).map(|i| format!("waypoint{i}")).collect();
        let text = format!(
            "(define (problem p) (:domain d) (:objects r1 r2 - robot {} - waypoint))",
            objects.join(" ")
        );
        let out = fmt(&text);
        assert!(
            out.starts_with(
                "(define (problem p)\n  (:domain d)\n  (:objects\n    r1 r2 - robot\n    waypoint0 waypoint1 "
            ),
            "{out}"
        );
        assert!(out.lines().all(|l| l.len() <= WIDTH), "{out}");
        assert!(out.ends_with(" waypoint29 - waypoint))\n"), "{out}");
        // Parameters fill their lines with whole groups.
        let params = "(:action a :parameters (?a-long-name - a-long-type ?b-long-name - b-long-type ?c-long-name - c-long-type ?d - d) :effect (p))";
        assert_eq!(
            fmt(params),
            "(:action a\n  :parameters (?a-long-name - a-long-type ?b-long-name - b-long-type ?c-long-name - c-long-type\n    ?d - d)\n  :effect (p))\n"
        );
    }

    #[test]
    fn atoms_fill_their_lines() {
        let reqs: Vec<String> = (0..20).map(|i| format!(":requirement-{i}")).collect();
        let out = fmt(&format!("(:requirements {})", reqs.join(" ")));
        assert!(out.starts_with("(:requirements :requirement-0 :requirement-1"), "{out}");
        assert!(out.lines().count() > 1 && out.lines().all(|l| l.len() <= WIDTH), "{out}");
        assert!(out.lines().skip(1).all(|l| l.starts_with("  :requirement-")), "{out}");
    }

    #[test]
    fn atoms_are_copied_verbatim() {
        assert_eq!(fmt("(DEFINE (DOMAIN D) (:Types A-b))"), "(DEFINE (DOMAIN D)\n  (:Types A-b))\n");
        assert_eq!(fmt("(p 1.50 -2 été #t)"), "(p 1.50 -2 été #t)\n");
    }

    #[test]
    fn line_ends_and_the_byte_order_mark_are_kept() {
        assert_eq!(fmt("(define (domain d)\r\n  (:types a))\r\n"), "(define (domain d)\r\n  (:types a))\r\n");
        assert_eq!(
            fmt("(define (domain d) ; c   \r\n (:types a))"),
            "(define (domain d) ; c\r\n  (:types a))\r\n"
        );
        assert_eq!(fmt("(p)\n(q)\r\n"), "(p)\n(q)\n");
        assert_eq!(fmt("\u{feff}(p)"), "\u{feff}(p)\n");
    }

    #[test]
    fn empty_files_stay_empty() {
        assert_eq!(fmt(""), "");
        assert_eq!(fmt(" \n\n\t"), "");
        assert_eq!(fmt(";; only a comment   "), ";; only a comment\n");
    }

    #[test]
    fn a_file_with_a_syntax_error_is_not_formatted() {
        let text = "(define (domain d)\n  (:action a :effect (and (p))\n (:action b))";
        let e = format(text).unwrap_err();
        assert_eq!(e.kind, FormatErrorKind::Syntax);
        assert!(e.message.starts_with("syntax error: missing `)`"), "{}", e.message);
        // At the end of `(:action a`, which is not closed.
        let end = text.find("))\n").unwrap() + 1;
        assert_eq!(e.range, TextRange::new((end as u32).into(), (end as u32 + 1).into()));
        let e = format("(p))").unwrap_err();
        assert_eq!((e.kind, e.range), (FormatErrorKind::Syntax, TextRange::new(3.into(), 4.into())));
    }

    #[test]
    fn a_plan_is_not_formatted() {
        let e = format("0.000: (move r a b) [10.000]\n").unwrap_err();
        assert_eq!((e.kind, e.range), (FormatErrorKind::NotAModel, TextRange::new(0.into(), 6.into())));
        assert_eq!(format("==>\n0 move r a b\nroot 1\n").unwrap_err().kind, FormatErrorKind::NotAModel);
    }

    #[test]
    fn nesting_at_the_limit_formats_on_a_small_stack_and_beyond_it_is_refused() {
        let depth = crate::syntax::MAX_NESTING;
        let deep = |n: usize| format!("{}p{}", "(and ".repeat(n), ")".repeat(n));
        let at_limit = deep(depth);
        let out = std::thread::Builder::new()
            .stack_size(2 << 20)
            .spawn(move || (format(&at_limit), format(&comment_each_level(depth))))
            .unwrap()
            .join()
            .unwrap();
        let (flat, broken) = (out.0.unwrap(), out.1.unwrap());
        assert_eq!(flat.matches('(').count(), depth);
        assert_eq!(broken.matches('(').count(), depth);
        let e = format(&deep(depth + 1)).unwrap_err();
        assert!(e.message.starts_with("nesting too deep"), "{}", e.message);

        fn comment_each_level(n: usize) -> String {
            format!("{}p{}", "(and ; c\n".repeat(n), ")".repeat(n))
        }
    }

    #[test]
    fn the_samples_format_idempotently() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples");
        let mut stack = vec![dir];
        let mut formatted = 0;
        while let Some(d) = stack.pop() {
            for entry in std::fs::read_dir(&d).unwrap() {
                let p = entry.unwrap().path();
                if p.is_dir() {
                    stack.push(p);
                } else if matches!(p.extension().and_then(|e| e.to_str()), Some("pddl" | "hddl")) {
                    let text = std::fs::read_to_string(&p).unwrap();
                    if format(&text).is_ok() {
                        fmt(&text);
                        formatted += 1;
                    }
                }
            }
        }
        assert!(formatted > 20, "{formatted}");
    }
}
