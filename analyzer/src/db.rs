//! The structure of a file: its parse, its `define` units and their items,
//! each item's model. The inputs these queries read are in [`crate::input`].
//!
//! Incrementality rests on two decisions:
//! - an item's syntax is its green tree, which has no absolute position, and
//!   its model uses item-relative spans: editing one item leaves every other
//!   item's model equal, so their checks are not re-run;
//! - `:init` sections are split into chunks of facts, each an item, so that an
//!   edit in one fact of a 5 MB problem re-checks one chunk.

use rowan::{NodeOrToken, TextRange, TextSize};

use crate::diagnostic::{Diagnostic, Severity, codes};
use crate::model::{self, Lowered};
use crate::syntax::{self, GList, GSexp, Green, List, Parse, SyntaxKind};

// The inputs, with the queries that read them: a query needs both.
pub use crate::input::{
    Db, ReparseHint, RootDatabase, Settings, SourceFile, Workspace, plan_options, syntax_in_items,
    triangle_tolerance,
};

/// Parses a file. Not compared for backdating: the tree changes whenever the text does.
///
/// Its memo may be evicted (`lru`, unbounded unless
/// [`AnalysisHost::drop_syntax_after_use`](crate::AnalysisHost::drop_syntax_after_use)
/// bounds it): once a file's items are lowered, the checks and the lints
/// read their models, not the tree.
#[salsa::tracked(returns(ref), no_eq, lru = 0)]
pub fn parse(db: &dyn Db, file: SourceFile) -> Parse {
    let text = file.text(db);
    match file.reparse_hint(db) {
        Some(hint) => syntax::reparse(&hint.base, &hint.edits, text),
        None => syntax::parse(text),
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UnitKind {
    Domain,
    Problem,
    /// A `define` without a `(domain …)` or `(problem …)` header.
    Unknown,
}

/// The section an item is, from its head keyword.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Section {
    Header,
    DomainRef,
    Requirements,
    Types,
    Constants,
    Predicates,
    Functions,
    Action,
    Task,
    Method,
    Derived,
    Objects,
    Init,
    Goal,
    Htn,
    AllowedActions,
    Metric,
    Constraints,
    Other,
}

impl Section {
    pub(crate) fn of(head: Option<&str>) -> Section {
        let Some(h) = head else { return Section::Other };
        match h.to_ascii_lowercase().as_str() {
            "domain" | "problem" => Section::Header,
            ":domain" => Section::DomainRef,
            ":requirements" => Section::Requirements,
            ":types" => Section::Types,
            ":constants" => Section::Constants,
            ":predicates" => Section::Predicates,
            ":functions" => Section::Functions,
            ":action" | ":durative-action" | ":process" | ":event" => Section::Action,
            ":task" => Section::Task,
            ":method" | ":durative-method" => Section::Method,
            ":derived" => Section::Derived,
            ":objects" => Section::Objects,
            ":init" => Section::Init,
            ":goal" => Section::Goal,
            ":htn" | ":tihtn" | ":htnti" | ":tasks" => Section::Htn,
            ":allowed-actions" => Section::AllowedActions,
            ":metric" => Section::Metric,
            ":constraints" => Section::Constraints,
            _ => Section::Other,
        }
    }

    /// Whether the section belongs in a domain (`Some(true)`), a problem (`Some(false)`), or both.
    pub fn belongs_to_domain(self) -> Option<bool> {
        match self {
            Section::Types
            | Section::Constants
            | Section::Predicates
            | Section::Functions
            | Section::Action
            | Section::Task
            | Section::Method
            | Section::Derived => Some(true),
            Section::DomainRef
            | Section::Objects
            | Section::Init
            | Section::Goal
            | Section::Htn
            | Section::AllowedActions
            | Section::Metric => Some(false),
            _ => None,
        }
    }
}

/// One `(define …)` of a file.
#[salsa::tracked(debug)]
pub struct Unit<'db> {
    #[returns(copy)]
    pub file: SourceFile,
    #[returns(copy)]
    pub index: u32,
    #[tracked]
    #[returns(copy)]
    pub kind: UnitKind,
    /// The lower-cased name from `(domain name)` / `(problem name)`.
    #[tracked]
    #[returns(ref)]
    pub name: Option<String>,
    /// For problems: the lower-cased name from `(:domain name)`.
    #[tracked]
    #[returns(ref)]
    pub domain_ref: Option<String>,
    #[tracked]
    #[returns(ref)]
    pub items: Vec<Item<'db>>,
    /// Absolute range of the `define` list (read only to locate unit-level diagnostics).
    #[tracked]
    #[returns(copy)]
    pub range: TextRange,
}

/// The syntax of an item: a section list, or a chunk of `:init` elements.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ItemSyntax {
    List(Green),
    /// The facts of a `Group` node of a long `:init` (the parser groups long
    /// lists), or of a whole short `:init` list. `after_keyword`: the node
    /// starts with `(:init`, which is not a fact. Compared pointer-first: an
    /// edit elsewhere leaves the group the same allocation.
    Chunk {
        node: Green,
        after_keyword: bool,
    },
}

impl ItemSyntax {
    /// The length of the item's text.
    pub fn text_len(&self) -> TextSize {
        match self {
            ItemSyntax::List(g) | ItemSyntax::Chunk { node: g, .. } => g.0.text_len(),
        }
    }
}

/// Where an item's node is in its file's tree: the index of the child taken
/// at each level on the way down from the root (`Group` nodes included).
/// Without [`syntax_in_items`], items keep this, not the node, so that
/// holding the items does not hold the tree ([`item_syntax`] finds the node).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NodePath {
    steps: [u32; 4],
    depth: u8,
    /// For an `:init` chunk, whether it starts with `(:init`; `None` for a section.
    chunk: Option<bool>,
}

impl NodePath {
    /// The path to child `index` of the node at `self`.
    fn child(mut self, index: usize) -> NodePath {
        self.steps[usize::from(self.depth)] = index as u32;
        self.depth += 1;
        self
    }

    fn root() -> NodePath {
        NodePath { steps: [0; 4], depth: 0, chunk: None }
    }

    /// The node at the end of the path, if the tree has one there.
    fn locate<'a>(&self, root: &'a rowan::GreenNodeData) -> Option<&'a rowan::GreenNodeData> {
        let mut node = root;
        for &i in &self.steps[..usize::from(self.depth)] {
            node = node.children().nth(i as usize)?.into_node()?;
        }
        Some(node)
    }
}

/// One section of a `define`, or a chunk of its `:init`.
#[salsa::tracked(debug)]
pub struct Item<'db> {
    #[returns(copy)]
    pub file: SourceFile,
    #[returns(copy)]
    pub unit: u32,
    #[returns(copy)]
    pub unit_kind: UnitKind,
    #[returns(copy)]
    pub section: Section,
    /// The declared name, for actions, tasks and methods (part of the identity, so
    /// that inserting an action does not shift the identity of the others).
    #[returns(ref)]
    pub name: Option<String>,
    /// The item's syntax, with [`syntax_in_items`] (compared pointer-first:
    /// an edit elsewhere leaves it the same allocation, and [`lower_item`]
    /// is not run again); read through [`item_syntax`].
    #[tracked]
    #[returns(ref)]
    pub syntax: Option<ItemSyntax>,
    /// Where the item's syntax is in the file's tree ([`item_syntax`]).
    #[tracked]
    #[returns(copy)]
    pub node_path: NodePath,
    /// The length of the item's text.
    #[tracked]
    #[returns(copy)]
    pub len: TextSize,
    /// The range of a section's head (`:action`, `:objects`…: what is
    /// first in its list), or of the `:init` keyword in the first chunk of
    /// an `:init`; relative to the item. Read by diagnostics that point at
    /// the section, so that they need not read its syntax.
    #[tracked]
    #[returns(copy)]
    pub head: Option<TextRange>,
    /// Absolute offset of the item's first byte (read only to locate results).
    #[tracked]
    #[returns(copy)]
    pub offset: TextSize,
}

/// The syntax of an item: the one it holds, or, without [`syntax_in_items`],
/// the one found in its file's tree.
pub fn item_syntax<'db>(db: &'db dyn Db, item: Item<'db>) -> &'db ItemSyntax {
    match item.syntax(db) {
        Some(syntax) => syntax,
        None => located_syntax(db, item),
    }
}

/// The syntax of an item that does not hold it, found in its file's tree.
/// Its memo may be evicted, as [`parse`]'s: the command line drops the trees
/// once the items are lowered.
#[salsa::tracked(returns(ref), lru = 0)]
fn located_syntax<'db>(db: &'db dyn Db, item: Item<'db>) -> ItemSyntax {
    let path = item.node_path(db);
    let root = &parse(db, item.file(db)).green.0;
    // The path was read from this tree by `file_units`, in the same revision.
    let node = path.locate(root).map_or_else(
        || rowan::GreenNode::new(SyntaxKind::Error.into(), std::iter::empty()),
        |n| n.to_owned(),
    );
    match path.chunk {
        Some(after_keyword) => ItemSyntax::Chunk { node: Green(node), after_keyword },
        None => ItemSyntax::List(Green(node)),
    }
}

/// Bounds how many memos of [`parse`] and of the syntax of items that do
/// not hold it are kept between revisions (0: all).
pub(crate) fn set_syntax_lru_capacity(db: &mut dyn Db, capacity: usize) {
    parse::set_lru_capacity(db, capacity);
    located_syntax::set_lru_capacity(db, capacity);
}

/// The range of the `:init` keyword among the first few children of the
/// first chunk of an `:init` (it starts with `(` and `:init`), relative to it.
fn init_keyword(node: &rowan::GreenNodeData) -> Option<TextRange> {
    let mut at = TextSize::from(0);
    for child in node.children().take(4) {
        if let NodeOrToken::Token(t) = child
            && t.text().eq_ignore_ascii_case(":init")
        {
            return Some(TextRange::at(at, t.text_len()));
        }
        at += child.text_len();
    }
    None
}

fn header_of(list: &GList<'_>) -> (UnitKind, Option<String>) {
    for e in list.elements().skip(1) {
        if let GSexp::List(l) = e {
            let mut elems = l.elements();
            let kind = match elems.next() {
                Some(h) if h.is_atom("domain") => UnitKind::Domain,
                Some(h) if h.is_atom("problem") => UnitKind::Problem,
                _ => continue,
            };
            return (kind, elems.next().and_then(|n| n.atom_text()).map(str::to_ascii_lowercase));
        }
    }
    (UnitKind::Unknown, None)
}

/// The `define` lists at the top level of a tree, with their paths.
fn defines(root: &rowan::GreenNodeData) -> impl Iterator<Item = (NodePath, GList<'_>)> {
    let mut at = TextSize::from(0);
    root.children().enumerate().filter_map(move |(i, c)| {
        let start = at;
        at += c.text_len();
        match c {
            NodeOrToken::Node(n) => {
                GList::root(n, start).filter(|l| l.head_is("define")).map(|l| (NodePath::root().child(i), l))
            }
            NodeOrToken::Token(_) => None,
        }
    })
}

/// The lists among the children of `list` (at `path`), seen through its
/// groups, each with its path.
fn child_lists<'a>(list: &GList<'a>, path: NodePath) -> Vec<(NodePath, GList<'a>)> {
    let mut out = Vec::new();
    for (i, (start, c)) in list.direct_children().enumerate() {
        let NodeOrToken::Node(n) = c else { continue };
        if n.kind() == SyntaxKind::Group.into() {
            let mut at = start;
            for (j, c) in n.children().enumerate() {
                if let NodeOrToken::Node(m) = c
                    && let Some(l) = GList::root(m, at)
                {
                    out.push((path.child(i).child(j), l));
                }
                at += c.text_len();
            }
        } else if let Some(l) = GList::root(n, start) {
            out.push((path.child(i), l));
        }
    }
    out
}

/// Whether a path names a plan file (docs/plan-formats.md): `.plan`, `.soln`,
/// `.sol`, or `.plan.json`. Plans are read by [`crate::plan`], not parsed as
/// PDDL, and are not domains or problems of the workspace.
pub fn is_plan_path(path: &str) -> bool {
    let name = path.rsplit(['/', '\\']).next().unwrap_or(path).to_ascii_lowercase();
    [".plan", ".soln", ".sol", ".plan.json"].iter().any(|ext| name.ends_with(ext))
}

/// Whether a file is a plan: by its name ([`is_plan_path`]), or, for a file
/// named like a domain, because it holds no `define` and reads as a plan
/// ([`reads_as_plan`]): the IPC 2020 feature tests keep a plan in
/// `plans/sortof.hddl`.
#[salsa::tracked(returns(copy))]
pub fn is_plan_file(db: &dyn Db, file: SourceFile) -> bool {
    if is_plan_path(file.path(db)) {
        return true;
    }
    let root = &parse(db, file).green.0;
    defines(root).next().is_none() && reads_as_plan(file.text(db))
}

/// Whether a text that is not a domain or a problem is a plan all the same
/// (a plan saved as `.hddl`, as in the IPC 2020 feature tests): it has an
/// IPC 2020 `==>` line, or every line that is not a comment is a timed VAL
/// step (`0.000: (move r1 a b) [10.000]`). Untimed `(…)` lines are not
/// enough: they are also what a domain without its `(define` looks like.
fn reads_as_plan(text: &str) -> bool {
    let mut steps = 0usize;
    for line in text.lines() {
        let t = line.trim_start_matches('\u{feff}').trim();
        if t.starts_with("==>") {
            return true;
        }
        if t.is_empty() || t.starts_with(';') {
            continue;
        }
        let time = t.find(|c: char| !(c.is_ascii_digit() || ".+-eE".contains(c))).unwrap_or(t.len());
        if time == 0 || t[..time].parse::<f64>().is_err() || !t[time..].trim_start().starts_with(':') {
            return false;
        }
        steps += 1;
    }
    steps > 0
}

/// The `define` units of a file and their items (none in a plan file).
#[salsa::tracked(returns(ref))]
pub fn file_units(db: &dyn Db, file: SourceFile) -> Vec<Unit<'_>> {
    if is_plan_file(db, file) {
        return Vec::new();
    }
    let root = &parse(db, file).green.0;
    let hold = syntax_in_items(db);
    let mut units = Vec::new();
    for (index, (path, list)) in defines(root).enumerate() {
        let index = index as u32;
        let (kind, name) = header_of(&list);
        let mut domain_ref = None;
        let mut items = Vec::new();
        for (path, child) in child_lists(&list, path) {
            let section = Section::of(child.head_text());
            let offset = child.range().start();
            match section {
                Section::Init => {
                    // One chunk per group of the list (the parser groups long
                    // lists), or the whole list when it is short.
                    let groups: Vec<(NodePath, TextSize, &rowan::GreenNodeData)> = child
                        .direct_children()
                        .enumerate()
                        .filter_map(|(i, (start, c))| match c {
                            NodeOrToken::Node(n) if n.kind() == SyntaxKind::Group.into() => {
                                Some((path.child(i), start, n))
                            }
                            _ => None,
                        })
                        .collect();
                    if groups.is_empty() {
                        let node_path = NodePath { chunk: Some(true), ..path };
                        let head = init_keyword(child.green());
                        let len = child.green().text_len();
                        let syntax = hold.then(|| ItemSyntax::Chunk {
                            node: Green(child.green().to_owned()),
                            after_keyword: true,
                        });
                        items.push(Item::new(
                            db, file, index, kind, section, None, syntax, node_path, len, head, offset,
                        ));
                    }
                    for (k, (path, start, group)) in groups.into_iter().enumerate() {
                        let node_path = NodePath { chunk: Some(k == 0), ..path };
                        let head = if k == 0 { init_keyword(group) } else { None };
                        let len = group.text_len();
                        let syntax = hold.then(|| ItemSyntax::Chunk {
                            node: Green(group.to_owned()),
                            after_keyword: k == 0,
                        });
                        items.push(Item::new(
                            db, file, index, kind, section, None, syntax, node_path, len, head, start,
                        ));
                    }
                }
                _ => {
                    let second =
                        || child.elements().nth(1).and_then(|n| n.atom_text().map(str::to_ascii_lowercase));
                    if section == Section::DomainRef {
                        domain_ref = second();
                    }
                    let name = match section {
                        Section::Action | Section::Task | Section::Method => second(),
                        _ => None,
                    };
                    let head = child.head().map(|h| h.range() - offset);
                    let len = child.green().text_len();
                    let syntax = hold.then(|| ItemSyntax::List(Green(child.green().to_owned())));
                    items.push(Item::new(
                        db, file, index, kind, section, name, syntax, path, len, head, offset,
                    ));
                }
            }
        }
        units.push(Unit::new(db, file, index, kind, name, domain_ref, items, list.range()));
    }
    units
}

/// The header of one `define` unit: what [`file_units`] records of it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnitHeader {
    pub kind: UnitKind,
    /// The lower-cased name from `(domain name)` / `(problem name)`.
    pub name: Option<String>,
    /// For problems: the lower-cased name from `(:domain name)`.
    pub domain_ref: Option<String>,
}

/// The kind, name and domain reference of each unit [`file_units`] finds in
/// `text`, read in one pass over its bytes without building a tree (a
/// fraction of the cost of parsing). Only for a text whose lists all close,
/// that closes none too many and that nests well below the parser's limit:
/// there the tree is the text's plain s-expressions, and the answer is the
/// same. `None` for any other text, whose reading depends on the parser's
/// recovery, and for a text without a `define` (it may read as a plan).
pub fn scan_unit_headers(text: &str) -> Option<Vec<UnitHeader>> {
    /// An open list: how many elements it has so far, and its first two when they are atoms.
    #[derive(Default)]
    struct Open {
        count: u32,
        head: Option<(usize, usize)>,
        second: Option<(usize, usize)>,
    }
    const DEPTH_LIMIT: usize = syntax::MAX_NESTING / 2;
    let bytes = text.as_bytes();
    let atom = |r: Option<(usize, usize)>| r.map(|(a, b)| &text[a..b]);
    let mut open: Vec<Open> = Vec::new();
    let mut units = Vec::new();
    let (mut header, mut domain_ref): (Option<(UnitKind, Option<String>)>, Option<String>) = (None, None);
    let mut i = if text.starts_with(syntax::BOM) { syntax::BOM.len() } else { 0 };
    while i < bytes.len() {
        match bytes[i] {
            b'(' => {
                if let Some(parent) = open.last_mut() {
                    parent.count += 1;
                }
                if open.len() >= DEPTH_LIMIT {
                    return None;
                }
                open.push(Open::default());
                i += 1;
            }
            b')' => {
                let list = open.pop()?;
                i += 1;
                let is = |r: Option<(usize, usize)>, word: &str| {
                    atom(r).is_some_and(|t| t.eq_ignore_ascii_case(word))
                };
                match open.len() {
                    // A section of a top-level list: of a `define`, its header or `(:domain …)`.
                    1 if is(open[0].head, "define") => {
                        let lower = |r| atom(r).map(str::to_ascii_lowercase);
                        if header.is_none() {
                            if is(list.head, "domain") {
                                header = Some((UnitKind::Domain, lower(list.second)));
                            } else if is(list.head, "problem") {
                                header = Some((UnitKind::Problem, lower(list.second)));
                            }
                        }
                        if is(list.head, ":domain") {
                            domain_ref = lower(list.second);
                        }
                    }
                    0 => {
                        let (h, d) = (header.take(), domain_ref.take());
                        if is(list.head, "define") {
                            let (kind, name) = h.unwrap_or((UnitKind::Unknown, None));
                            units.push(UnitHeader { kind, name, domain_ref: d });
                        }
                    }
                    _ => {}
                }
            }
            b';' => {
                while i < bytes.len() && bytes[i] != b'\n' && bytes[i] != b'\r' {
                    i += 1;
                }
            }
            b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c => i += 1,
            _ => {
                let start = i;
                while i < bytes.len()
                    && !matches!(bytes[i], b'(' | b')' | b';' | b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c)
                {
                    i += 1;
                }
                if let Some(list) = open.last_mut() {
                    match list.count {
                        0 => list.head = Some((start, i)),
                        1 => list.second = Some((start, i)),
                        _ => {}
                    }
                    list.count += 1;
                }
            }
        }
    }
    (open.is_empty() && !units.is_empty()).then_some(units)
}

/// Lowers one item to its model.
#[salsa::tracked(returns(ref))]
pub fn lower_item<'db>(db: &'db dyn Db, item: Item<'db>) -> Lowered {
    match item_syntax(db, item) {
        ItemSyntax::List(green) => model::lower_list(&green.0),
        ItemSyntax::Chunk { node, after_keyword } => model::lower_chunk(&node.0, usize::from(*after_keyword)),
    }
}

/// Diagnostics about a domain or problem file's top level: syntax errors and
/// what is not a `define`. Plan files are read by [`crate::plan`] instead.
#[salsa::tracked(returns(ref))]
pub fn file_level_diagnostics(db: &dyn Db, file: SourceFile) -> Vec<Diagnostic> {
    if is_plan_file(db, file) {
        return Vec::new();
    }
    let parse = parse(db, file);
    let mut out: Vec<Diagnostic> = parse
        .errors
        .iter()
        .map(|e| Diagnostic {
            code: match e.kind {
                syntax::SyntaxErrorKind::MissingParen => codes::MISSING_PAREN,
                syntax::SyntaxErrorKind::ExtraParen => codes::EXTRA_PAREN,
                syntax::SyntaxErrorKind::TooDeep => codes::NESTING_TOO_DEEP,
            },
            severity: Severity::Error,
            file,
            range: e.range,
            message: e.message.clone(),
            related: e
                .related
                .iter()
                .map(|(r, m)| crate::diagnostic::Related { file, range: *r, message: m.clone() })
                .collect(),
            fix: e.fix.as_ref().map(|(range, text)| crate::diagnostic::Fix {
                message: fix_message(*range, text),
                edits: vec![(file, *range, text.clone())],
            }),
        })
        .collect();
    let root = parse.syntax();
    let mut saw_define = false;
    let mut stray = Vec::new();
    for e in root.children_with_tokens() {
        let (range, what) = match &e {
            NodeOrToken::Node(n) => match List::cast(n.clone()) {
                Some(l) if l.head_is("define") => {
                    saw_define = true;
                    let green = n.green();
                    let list = GList::root(&green, l.range().start());
                    if list.is_some_and(|g| header_of(&g).0 == UnitKind::Unknown) {
                        let at = l.head().map_or(l.open_range(), |h| h.range());
                        out.push(structure_error(
                            file,
                            at,
                            "expected `(domain name)` or `(problem name)` after `define`",
                        ));
                    }
                    continue;
                }
                Some(l) => (l.range(), "expected `(define …)` at the top level"),
                None => continue,
            },
            NodeOrToken::Token(t) if t.kind().is_atom() => {
                (t.text_range(), "expected `(define …)` at the top level")
            }
            NodeOrToken::Token(_) => continue,
        };
        stray.push(structure_error(file, range, what));
    }
    if !saw_define {
        // Not a domain or problem at all (a plan, say): one diagnostic, not one per line.
        if let Some(first) = stray.first_mut() {
            first.message =
                "expected `(define (domain …) …)` or `(define (problem …) …)`: this is not a domain or problem file"
                    .into();
            stray.truncate(1);
        }
    }
    out.extend(stray);
    out
}

/// What the fix of a syntax error does: remove the `)` of the range, or insert `)`.
fn fix_message(range: TextRange, text: &str) -> String {
    match (text.len(), u32::from(range.len())) {
        (0, 1) => "remove this `)`".into(),
        (0, _) => "remove these `)`".into(),
        (n, _) if n <= 8 => format!("insert `{text}`"),
        (n, _) => format!("insert {n} `)`"),
    }
}

fn structure_error(file: SourceFile, range: TextRange, message: &str) -> Diagnostic {
    Diagnostic {
        code: codes::MALFORMED,
        severity: Severity::Error,
        file,
        range,
        message: message.to_string(),
        related: Vec::new(),
        fix: None,
    }
}
