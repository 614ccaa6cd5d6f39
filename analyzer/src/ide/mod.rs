//! What the shells ask, in byte offsets: a file's diagnostics, document
//! symbols, hover, go to definition, find references, document highlights,
//! folding ranges, rename, formatting. Plain data out; the server converts to LSP.

mod actions;
mod completion;
pub mod diagnostics;
mod format;
mod highlight;
mod outline;
mod plan;
mod planned;
mod refs;
mod rename;

use crate::model::Str;
use rowan::{TextRange, TextSize};

pub use actions::{CodeAction, code_actions};
pub use completion::{Completion, CompletionKind, completions};
pub use format::{FormatError, FormatErrorKind, WIDTH as FORMAT_WIDTH, format, format_parse};
pub use highlight::{HighlightKind, HighlightToken, semantic_tokens};
pub use outline::{Fold, FoldKind, Highlight, document_highlights, folding_ranges};
pub use planned::{
    PlanHint, PlanHintKind, PlanRun, RepairSummary, plan_hints, plan_hover, step_text, summary,
};
pub use refs::{Occurrence, RefKind, occurrences};
pub use rename::{RenameError, prepare_rename, rename};

use crate::db::{Db, Item, ItemSyntax, Section, SourceFile, Unit, UnitKind, file_units, lower_item};
use crate::model::{ActionKind, ItemData, TypeRef};
use crate::semantics::check::domain_for;
use crate::semantics::resolve::problems_of;
use crate::semantics::symbols::{Loc, SigDecl, domain_symbols, problem_symbols};
use crate::syntax::Lang;

/// The absolute range of an item.
pub fn item_range(db: &dyn Db, item: Item<'_>) -> TextRange {
    let len = item.len(db);
    TextRange::at(item.offset(db), len)
}

fn abs(db: &dyn Db, loc: Loc<'_>) -> (SourceFile, TextRange) {
    (loc.item.file(db), loc.span + loc.item.offset(db))
}

/// The kind of a document symbol.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SymbolKind {
    Domain,
    Problem,
    Section,
    Type,
    Constant,
    Object,
    Predicate,
    Function,
    Action,
    Task,
    Method,
}

/// An entry of the outline.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DocumentSymbol {
    pub name: String,
    pub detail: Option<String>,
    pub kind: SymbolKind,
    pub range: TextRange,
    pub selection_range: TextRange,
    pub children: Vec<DocumentSymbol>,
}

/// The outline of a file: its units and their declarations.
pub fn document_symbols(db: &dyn Db, file: SourceFile) -> Vec<DocumentSymbol> {
    let mut out = Vec::new();
    for &unit in file_units(db, file) {
        let mut children = Vec::new();
        let mut unit_name = (unit.name(db).clone().unwrap_or_else(|| "define".into()), unit.range(db));
        let mut init_done = false;
        for &item in unit.items(db) {
            let off = item.offset(db);
            let range = item_range(db, item);
            let sym = |name: &str, kind, span: TextRange, detail: Option<String>| DocumentSymbol {
                name: name.to_string(),
                detail,
                kind,
                range,
                selection_range: span + off,
                children: Vec::new(),
            };
            let leaf = |name: &str, kind, span: TextRange| DocumentSymbol {
                name: name.to_string(),
                detail: None,
                kind,
                range: span + off,
                selection_range: span + off,
                children: Vec::new(),
            };
            // A section is selected by its keyword (`:predicates`).
            let keyword = section_keyword(db, item).unwrap_or(TextRange::at(range.start(), 1.into()));
            let section = |name: &str, kids: Vec<DocumentSymbol>| DocumentSymbol {
                name: name.to_string(),
                detail: None,
                kind: SymbolKind::Section,
                range,
                selection_range: keyword,
                children: kids,
            };
            match &lower_item(db, item).data {
                ItemData::Header(n) => unit_name = (n.text().to_string(), n.span + off),
                ItemData::Types(ts) => children.push(section(
                    ":types",
                    ts.iter().map(|t| leaf(t.name.text(), SymbolKind::Type, t.name.span)).collect(),
                )),
                ItemData::Constants(cs) => children.push(section(
                    ":constants",
                    cs.iter().map(|t| leaf(t.name.text(), SymbolKind::Constant, t.name.span)).collect(),
                )),
                ItemData::Objects(cs) => children.push(section(
                    ":objects",
                    cs.iter().map(|t| leaf(t.name.text(), SymbolKind::Object, t.name.span)).collect(),
                )),
                ItemData::Predicates(ps) => children.push(section(
                    ":predicates",
                    ps.iter().map(|p| leaf(p.name.text(), SymbolKind::Predicate, p.name.span)).collect(),
                )),
                ItemData::Functions(ps) => children.push(section(
                    ":functions",
                    ps.iter().map(|p| leaf(p.name.text(), SymbolKind::Function, p.name.span)).collect(),
                )),
                ItemData::Action(a) => {
                    let detail = match a.kind {
                        ActionKind::Durative => "durative action",
                        ActionKind::Action => "action",
                        ActionKind::Process => "process",
                        ActionKind::Event => "event",
                    };
                    children.push(sym(a.name.text(), SymbolKind::Action, a.name.span, Some(detail.into())))
                }
                ItemData::Task(t) => {
                    children.push(sym(t.name.text(), SymbolKind::Task, t.name.span, Some("task".into())))
                }
                ItemData::Method(m) => {
                    let detail = m.task.as_ref().map(|t| format!("method of {}", t.name.text()));
                    children.push(sym(m.name.text(), SymbolKind::Method, m.name.span, detail))
                }
                ItemData::Init(_) if !init_done => {
                    init_done = true;
                    // One entry for the whole `:init`, whatever its chunks.
                    let chunks: Vec<TextRange> = unit
                        .items(db)
                        .iter()
                        .filter(|i| i.section(db) == Section::Init)
                        .map(|&i| item_range(db, i))
                        .collect();
                    let whole = chunks.iter().fold(chunks[0], |a, b| a.cover(*b));
                    let mut s = section(":init", Vec::new());
                    s.range = whole;
                    children.push(s);
                }
                ItemData::Goal(_) => children.push(section(":goal", Vec::new())),
                ItemData::Htn(_) => children.push(section(":htn", Vec::new())),
                ItemData::AllowedActions(_) => children.push(section(":allowed-actions", Vec::new())),
                _ => {}
            }
        }
        out.push(DocumentSymbol {
            name: unit_name.0,
            detail: None,
            kind: if unit.kind(db) == UnitKind::Problem { SymbolKind::Problem } else { SymbolKind::Domain },
            range: unit.range(db),
            selection_range: unit_name.1,
            children,
        });
    }
    out
}

/// A symbol of the workspace, for `workspace/symbol`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WorkspaceSymbol {
    pub name: String,
    pub kind: SymbolKind,
    pub file: SourceFile,
    /// The name's range.
    pub range: TextRange,
    /// The domain or problem it is declared in.
    pub container: Option<String>,
}

/// How many symbols [`workspace_symbols`] returns at most: the best matches.
pub const WORKSPACE_SYMBOLS_LIMIT: usize = 1000;

/// How well `name` matches `query` (lower-cased), best first: equal, prefix,
/// substring, then the query's characters in order (`pkup` finds `pick-up`);
/// `None` when it does not match. Case is ignored, as PDDL does.
fn match_rank(name: &str, query: &str) -> Option<u8> {
    if query.is_empty() {
        return Some(0);
    }
    let name = name.to_lowercase();
    if name == query {
        Some(0)
    } else if name.starts_with(query) {
        Some(1)
    } else if name.contains(query) {
        Some(2)
    } else {
        let mut chars = name.chars();
        query.chars().all(|q| chars.any(|c| c == q)).then_some(3)
    }
}

/// The declarations of every domain and problem of the workspace whose name
/// matches `query` ([`match_rank`]): domains, problems, types, constants,
/// objects, predicates, functions, actions, tasks and methods, best matches
/// first, at most [`WORKSPACE_SYMBOLS_LIMIT`].
pub fn workspace_symbols(db: &dyn Db, query: &str) -> Vec<WorkspaceSymbol> {
    let query = query.trim().to_lowercase();
    let files = crate::db::Workspace::try_get(db).map(|ws| ws.files(db).clone()).unwrap_or_default();
    let mut found: Vec<(u8, WorkspaceSymbol)> = Vec::new();
    for file in files {
        for unit in document_symbols(db, file) {
            let container = Some(unit.name.clone());
            let mut add = |s: &DocumentSymbol, container: Option<String>| {
                if s.kind != SymbolKind::Section
                    && let Some(rank) = match_rank(&s.name, &query)
                {
                    let symbol = WorkspaceSymbol {
                        name: s.name.clone(),
                        kind: s.kind,
                        file,
                        range: s.selection_range,
                        container,
                    };
                    found.push((rank, symbol));
                }
            };
            add(&unit, None);
            for child in &unit.children {
                add(child, container.clone());
                for grandchild in &child.children {
                    add(grandchild, container.clone());
                }
            }
        }
    }
    found.sort_by(|(ra, a), (rb, b)| {
        (ra, a.name.len(), &a.name, a.file.path(db), a.range.start()).cmp(&(
            rb,
            b.name.len(),
            &b.name,
            b.file.path(db),
            b.range.start(),
        ))
    });
    found.truncate(WORKSPACE_SYMBOLS_LIMIT);
    found.into_iter().map(|(_, s)| s).collect()
}

/// The absolute range of the keyword that heads an item (`:predicates`, the
/// `:init` of the first chunk of an `:init`): the first atom of its syntax,
/// seeing through the groups of a long list, before any nested list.
fn section_keyword(db: &dyn Db, item: Item<'_>) -> Option<TextRange> {
    fn first_atom(node: &rowan::GreenNodeData, mut at: TextSize) -> Result<TextRange, bool> {
        for child in node.children() {
            let kind = <Lang as rowan::Language>::kind_from_raw(child.kind());
            match child {
                rowan::NodeOrToken::Token(t) if kind.is_atom() => return Ok(TextRange::at(at, t.text_len())),
                rowan::NodeOrToken::Node(n) if kind == crate::syntax::SyntaxKind::Group => {
                    // `Err(true)`: a nested list ends the search.
                    match first_atom(n, at) {
                        Err(false) => {}
                        found => return found,
                    }
                }
                rowan::NodeOrToken::Node(_) => return Err(true),
                rowan::NodeOrToken::Token(_) => {}
            }
            at += child.text_len();
        }
        Err(false)
    }
    let (ItemSyntax::List(green) | ItemSyntax::Chunk { node: green, .. }) = crate::db::item_syntax(db, item);
    first_atom(&green.0, item.offset(db)).ok()
}

/// The item of a file that contains `offset`.
pub fn item_at(db: &dyn Db, file: SourceFile, offset: TextSize) -> Option<(Unit<'_>, Item<'_>)> {
    for &unit in file_units(db, file) {
        if !unit.range(db).contains_inclusive(offset) {
            continue;
        }
        for &item in unit.items(db) {
            if item_range(db, item).contains_inclusive(offset) {
                return Some((unit, item));
            }
        }
    }
    None
}

/// The name occurrence at `offset`, with its item.
pub fn occurrence_at(
    db: &dyn Db,
    file: SourceFile,
    offset: TextSize,
) -> Option<(Unit<'_>, Item<'_>, RefKind, String, TextRange)> {
    let (unit, item) = item_at(db, file, offset)?;
    let rel = offset.checked_sub(item.offset(db))?;
    let mut found = None;
    occurrences(&lower_item(db, item).data, |o| {
        if found.is_none() && o.name.span.contains_inclusive(rel) {
            found = Some((o.kind, o.name.key().to_string(), o.name.span + item.offset(db)));
        }
    });
    let (kind, key, range) = found?;
    Some((unit, item, kind, key, range))
}

/// A place to navigate to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NavTarget {
    pub file: SourceFile,
    /// The name's range.
    pub range: TextRange,
}

fn local_decl(db: &dyn Db, item: Item<'_>, kind: RefKind, key: &str) -> Option<TextRange> {
    let mut found = None;
    occurrences(&lower_item(db, item).data, |o| {
        if found.is_none() && o.decl && o.kind == kind && o.name.key() == key {
            found = Some(o.name.span + item.offset(db));
        }
    });
    found
}

/// Where the symbol named `key` of `kind` is declared, seen from `unit`.
fn declaration<'db>(
    db: &'db dyn Db,
    unit: Unit<'db>,
    item: Item<'db>,
    kind: RefKind,
    key: &str,
) -> Option<NavTarget> {
    let file = item.file(db);
    let nav = |(file, range): (SourceFile, TextRange)| NavTarget { file, range };
    let domain = domain_for(db, unit);
    let dom = domain.map(|d| domain_symbols(db, d));
    match kind {
        RefKind::Variable | RefKind::SubtaskId => {
            local_decl(db, item, kind, key).map(|range| NavTarget { file, range })
        }
        RefKind::Type => dom?.types.get(key).map(|t| nav(abs(db, t.locs[0]))),
        RefKind::Predicate => dom?.predicates.get(key).map(|d| nav(abs(db, d.loc))),
        RefKind::Function => dom?.functions.get(key).map(|d| nav(abs(db, d.loc))),
        RefKind::Callable | RefKind::Task => dom?.callable(key).map(|d| nav(abs(db, d.loc))),
        RefKind::Method => dom?.methods.get(key).map(|d| nav(abs(db, d.loc))),
        RefKind::Object => {
            if let Some(c) = dom.and_then(|d| d.constants.get(key)) {
                return Some(nav(abs(db, c.loc)));
            }
            if unit.kind(db) == UnitKind::Problem {
                return problem_symbols(db, unit).objects.get(key).map(|o| nav(abs(db, o.loc)));
            }
            None
        }
        RefKind::UnitName => {
            let target = if unit.kind(db) == UnitKind::Problem { domain? } else { unit };
            target.items(db).iter().find_map(|&i| match &lower_item(db, i).data {
                ItemData::Header(n) => Some(NavTarget { file: i.file(db), range: n.span + i.offset(db) }),
                _ => None,
            })
        }
        RefKind::Requirement => None,
    }
}

/// Go to definition; in a plan file, from a step to its action, task, method
/// or objects in the domain and problem.
pub fn goto_definition(db: &dyn Db, file: SourceFile, offset: TextSize) -> Option<NavTarget> {
    if crate::db::is_plan_file(db, file) {
        return plan::definition(db, file, offset);
    }
    let (unit, item, kind, key, _) = occurrence_at(db, file, offset)?;
    declaration(db, unit, item, kind, &key)
}

fn same_namespace(a: RefKind, b: RefKind) -> bool {
    let norm = |k| if k == RefKind::Task { RefKind::Callable } else { k };
    norm(a) == norm(b)
}

/// Every occurrence of the symbol at `offset`, across the domain and its problems.
pub fn references(
    db: &dyn Db,
    file: SourceFile,
    offset: TextSize,
    include_declaration: bool,
) -> Vec<NavTarget> {
    let Some((unit, item, kind, key, _)) = occurrence_at(db, file, offset) else { return Vec::new() };
    let mut out = Vec::new();
    let mut scan = |i: Item<'_>| {
        occurrences(&lower_item(db, i).data, |o| {
            if same_namespace(o.kind, kind) && *o.name.key() == *key && (include_declaration || !o.decl) {
                out.push(NavTarget { file: i.file(db), range: o.name.span + i.offset(db) });
            }
        });
    };
    match kind {
        RefKind::Variable | RefKind::SubtaskId => scan(item),
        RefKind::Requirement => {}
        _ => {
            let domain = domain_for(db, unit);
            // Problem objects are local to their problem; everything else is shared.
            let local_object = kind == RefKind::Object
                && domain.is_none_or(|d| !domain_symbols(db, d).constants.contains_key(key.as_str()));
            let mut units: Vec<Unit<'_>> = Vec::new();
            if local_object {
                units.push(unit);
            } else if let Some(d) = domain {
                units.push(d);
                units.extend(problems_of(db, d).iter().copied());
            } else {
                units.push(unit);
            }
            for u in units {
                for &i in u.items(db) {
                    scan(i);
                }
            }
        }
    }
    if include_declaration
        && let Some(decl) = declaration(db, unit, item, kind, &key)
        && !out.contains(&decl)
    {
        out.push(decl);
    }
    out.sort_by_key(|n| (n.file.path(db).clone(), n.range.start()));
    out.dedup();
    out
}

/// Hover text (Markdown) for the symbol at `offset`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HoverResult {
    pub range: TextRange,
    pub markdown: String,
}

fn params_text(names: &[Str], types: &[Vec<Str>]) -> String {
    let mut out = String::new();
    let mut i = 0;
    while i < names.len() {
        let mut j = i;
        while j + 1 < names.len() && types[j + 1] == types[i] {
            j += 1;
        }
        for n in &names[i..=j] {
            if !out.is_empty() {
                out.push(' ');
            }
            out.push_str(n);
        }
        let t = &types[i];
        if !(t.len() == 1 && &*t[0] == "object") {
            out.push_str(" - ");
            if t.len() == 1 {
                out.push_str(&t[0]);
            } else {
                out.push_str(&format!("(either {})", t.join(" ")));
            }
        }
        i = j + 1;
    }
    out
}

fn sig_text(name: &str, d: &SigDecl<'_>) -> String {
    let params = params_text(&d.param_names, &d.params);
    let call = if params.is_empty() { format!("({name})") } else { format!("({name} {params})") };
    match &d.result {
        Some(r) if !(r.len() == 1 && &*r[0] == "number") => format!("{call} - {}", r.join(" ")),
        Some(_) => format!("{call} - number"),
        None => call,
    }
}

/// The comment block right above a declaration's line, and a comment after it on the same line.
pub fn doc_comment(text: &str, at: TextSize) -> Option<String> {
    let at = usize::from(at).min(text.len());
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[at..].find('\n').map_or(text.len(), |i| at + i);
    let mut lines: Vec<&str> = Vec::new();
    let mut end = line_start;
    while end > 0 {
        let prev_start = text[..end - 1].rfind('\n').map_or(0, |i| i + 1);
        let line = text[prev_start..end - 1].trim();
        match line.strip_prefix(';') {
            Some(c) => lines.push(c.trim_start_matches(';').trim()),
            None => break,
        }
        end = prev_start;
    }
    lines.reverse();
    if let Some(i) = text[at..line_end].find(';') {
        lines.push(text[at + i..line_end].trim_start_matches(';').trim());
    }
    let doc = lines.join("\n").trim().to_string();
    (!doc.is_empty()).then_some(doc)
}

/// Hover: the declaration's signature and its comment; in a plan file, a
/// step's signature, time window and validity.
pub fn hover(db: &dyn Db, file: SourceFile, offset: TextSize) -> Option<HoverResult> {
    if crate::db::is_plan_file(db, file) {
        return plan::hover(db, file, offset);
    }
    let (unit, item, kind, key, range) = occurrence_at(db, file, offset)?;
    let domain = domain_for(db, unit);
    let dom = domain.map(|d| domain_symbols(db, d));
    let decl = declaration(db, unit, item, kind, &key);
    let signature = match kind {
        RefKind::Predicate => dom
            .and_then(|d| d.predicates.get(key.as_str()))
            .map(|d| format!("predicate {}", sig_text(&key, d))),
        RefKind::Function => {
            dom.and_then(|d| d.functions.get(key.as_str())).map(|d| format!("function {}", sig_text(&key, d)))
        }
        RefKind::Callable | RefKind::Task => dom.and_then(|d| d.callable(&key)).map(|d| {
            let what = match d.kind {
                crate::semantics::symbols::DeclKind::Action(ActionKind::Durative) => "durative action",
                crate::semantics::symbols::DeclKind::Task => "task",
                _ => "action",
            };
            format!("{what} {}", sig_text(&key, d))
        }),
        RefKind::Method => dom.and_then(|d| d.methods.get(key.as_str())).map(|m| match &m.task {
            Some(t) => format!("method {key} of task {t}"),
            None => format!("method {key}"),
        }),
        RefKind::Type => dom.map(|d| match d.ancestors.get(key.as_str()) {
            Some(anc) if anc.len() > 1 => format!("type {key} - {}", anc[1..].join(" - ")),
            _ => format!("type {key}"),
        }),
        RefKind::Object => {
            let constant = dom.and_then(|d| d.constants.get(key.as_str()));
            let object = (unit.kind(db) == UnitKind::Problem)
                .then(|| problem_symbols(db, unit))
                .and_then(|p| p.objects.get(key.as_str()));
            match (constant, object) {
                (Some(c), _) => Some(format!("constant {key} - {}", c.ty.join(" "))),
                (None, Some(o)) => Some(format!("object {key} - {}", o.ty.join(" "))),
                _ => None,
            }
        }
        RefKind::Variable => {
            let params = match &lower_item(db, item).data {
                ItemData::Action(a) => &a.params[..],
                ItemData::Task(t) => &t.params[..],
                ItemData::Method(m) => &m.params[..],
                ItemData::Htn(h) => &h.params[..],
                _ => &[],
            };
            let ty = params.iter().find(|p| *p.name.key() == *key).map(|p| type_text(&p.ty));
            Some(match ty {
                Some(t) => format!("parameter {key} - {t}"),
                None => format!("variable {key}"),
            })
        }
        RefKind::SubtaskId => Some(format!("subtask {key}")),
        RefKind::UnitName => Some(format!("domain {key}")),
        RefKind::Requirement => Some(format!("requirement {key}")),
    }?;
    let mut markdown = format!("```pddl\n{signature}\n```");
    if let Some(d) = decl
        && let Some(doc) = doc_comment(d.file.text(db), d.range.start())
    {
        markdown.push_str("\n\n");
        markdown.push_str(&doc);
    }
    for line in family_notes(db, unit, domain, kind, &key) {
        markdown.push_str("\n\n");
        markdown.push_str(&line);
    }
    Some(HoverResult { range, markdown })
}

/// How many problems of a domain hover consults for position families.
const FAMILY_PROBLEMS: usize = 3;

/// What model verification says about a predicate (a position family or
/// not) or an action (a move action) in the problem hovered, or in the first
/// problems of the domain hovered whose models are free of errors.
fn family_notes(
    db: &dyn Db,
    unit: Unit<'_>,
    domain: Option<Unit<'_>>,
    kind: RefKind,
    key: &str,
) -> Vec<String> {
    if !matches!(kind, RefKind::Predicate | RefKind::Callable) {
        return Vec::new();
    }
    let problems: Vec<Unit<'_>> = match (unit.kind(db), domain) {
        (UnitKind::Problem, _) => vec![unit],
        (_, Some(d)) => problems_of(db, d).clone(),
        _ => Vec::new(),
    };
    problems
        .into_iter()
        .filter(|&p| crate::verify::model_is_clean(db, p))
        .take(FAMILY_PROBLEMS)
        .filter_map(|p| match kind {
            RefKind::Predicate => crate::verify::families::describe_predicate(db, p, key),
            _ => crate::verify::families::describe_action(db, p, key),
        })
        .collect()
}

fn type_text(t: &TypeRef) -> String {
    match t {
        TypeRef::Implicit => "object".into(),
        TypeRef::Named(n) => n.text().to_string(),
        TypeRef::Either(ns) => {
            format!("(either {})", ns.iter().map(|n| n.text()).collect::<Vec<_>>().join(" "))
        }
    }
}
