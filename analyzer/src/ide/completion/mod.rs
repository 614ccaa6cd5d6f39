//! Completion by context, read from the lossless tree around the cursor (it
//! is error-recovering, so the half-typed text of an edit still has a
//! shape): the keywords of a section, the declarations of the domain with
//! their signatures, the variables in scope, requirement names, and
//! skeletons of a durative action, of a task with a method and of a problem.

use rowan::{TextRange, TextSize};

mod position;

use super::match_rank;
use crate::db::{Db, Section, SourceFile, Unit, UnitKind, file_units, parse};
use crate::model::{ACTION_FIELDS, DURATIVE_ACTION_FIELDS, HTN_FIELDS, METHOD_FIELDS, Str, TASK_FIELDS};
use crate::semantics::check::{KNOWN_REQUIREMENTS, domain_for};
use crate::semantics::resolve::{dir_of, workspace_files};
use crate::semantics::symbols::{DomainSymbols, Loc, SigDecl, TypeSet, domain_symbols, problem_symbols};
use crate::syntax::{SECTION_HEADS, SyntaxKind};
use position::{Frame, Role, elements, frames, is_connective, is_item, variables};

/// What a completion inserts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CompletionKind {
    /// A section or field keyword, a connective.
    Keyword,
    Requirement,
    Type,
    Predicate,
    Function,
    Action,
    Task,
    Constant,
    Object,
    Variable,
    /// A domain's name, after `:domain`.
    Domain,
    /// A skeleton with placeholders.
    Snippet,
}

/// One completion.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Completion {
    pub label: String,
    pub kind: CompletionKind,
    /// The signature, or what the item is.
    pub detail: Option<String>,
    /// What replaces [`Completion::range`]: plain text, or a snippet
    /// (`${1:name}` placeholders) when [`Completion::snippet`].
    pub insert: String,
    pub snippet: bool,
    /// Sorts the completions, best first.
    pub sort: String,
    /// The word being typed, which the completion replaces (empty when
    /// nothing is typed yet).
    pub range: TextRange,
}

/// The sections a domain may have, in PDDL's order (aliases and the PDDL+
/// sections hipop does not support left out).
fn sections(kind: UnitKind) -> impl Iterator<Item = &'static str> {
    const ALIASES: &[&str] = &[":process", ":event", ":tihtn", ":htnti", ":tasks"];
    SECTION_HEADS.iter().copied().filter(move |h| {
        let belongs = Section::of(Some(h)).belongs_to_domain();
        !ALIASES.contains(h)
            && match kind {
                UnitKind::Domain => belongs != Some(false),
                UnitKind::Problem => belongs != Some(true),
                UnitKind::Unknown => true,
            }
    })
}

/// Whether a section may appear more than once in a `define`.
fn repeatable(head: &str) -> bool {
    matches!(Section::of(Some(head)), Section::Action | Section::Task | Section::Method | Section::Derived)
}

/// Completions at `offset` of `file`, best first.
pub fn completions(db: &dyn Db, file: SourceFile, offset: TextSize) -> Vec<Completion> {
    if crate::db::is_plan_file(db, file) {
        return Vec::new();
    }
    let text = file.text(db);
    let offset = offset.min(TextSize::of(&**text));
    let root = parse(db, file).syntax();
    // The word being typed, which the completion replaces.
    let mut word = TextRange::empty(offset);
    if let Some(t) = root.token_at_offset(offset).left_biased() {
        if t.kind() == SyntaxKind::Comment && t.text_range().start() < offset {
            return Vec::new();
        }
        if t.kind().is_atom() && t.text_range().start() < offset {
            word = TextRange::new(t.text_range().start(), offset);
        }
    }
    let frames = frames(&root, word.start());
    let unit = file_units(db, file).iter().copied().find(|u| u.range(db).contains_inclusive(offset));
    let mut cx = Context {
        db,
        file,
        unit,
        domain: unit.and_then(|u| domain_for(db, u)),
        word,
        prefix: text[word].to_ascii_lowercase(),
        out: Vec::new(),
    };
    cx.complete(&frames);
    let Context { out, prefix, .. } = cx;
    // The words that match what is typed, those that begin with it first.
    let mut out: Vec<Completion> = out
        .into_iter()
        .filter_map(|mut c| {
            let rank = match_rank(&c.label, &prefix)?;
            c.sort = format!("{}{}", rank.min(2), c.sort);
            Some(c)
        })
        .collect();
    out.sort_by(|a, b| a.sort.cmp(&b.sort));
    out.dedup_by(|a, b| a.label == b.label && a.kind == b.kind);
    out
}

struct Context<'db> {
    db: &'db dyn Db,
    file: SourceFile,
    unit: Option<Unit<'db>>,
    domain: Option<Unit<'db>>,
    word: TextRange,
    /// The word typed, lower-cased.
    prefix: String,
    out: Vec<Completion>,
}

impl<'db> Context<'db> {
    fn push(&mut self, rank: u8, kind: CompletionKind, label: &str, detail: Option<String>) {
        self.out.push(Completion {
            label: label.to_string(),
            kind,
            detail,
            insert: label.to_string(),
            snippet: false,
            sort: format!("{rank}{label}"),
            range: self.word,
        });
    }

    fn snippet(&mut self, label: &str, detail: &str, body: String) {
        self.out.push(Completion {
            label: label.to_string(),
            kind: CompletionKind::Snippet,
            detail: Some(detail.to_string()),
            insert: body,
            snippet: true,
            sort: format!("9{label}"),
            range: self.word,
        });
    }

    fn symbols(&self) -> Option<&'db DomainSymbols<'db>> {
        self.domain.map(|d| domain_symbols(self.db, d))
    }

    fn unit_kind(&self) -> UnitKind {
        self.unit.map_or(UnitKind::Unknown, |u| u.kind(self.db))
    }

    /// The text of a declaration's name, as written.
    fn name_at(&self, loc: Loc<'_>) -> String {
        let file = loc.item.file(self.db);
        let range = loc.span + loc.item.offset(self.db);
        file.text(self.db).get(std::ops::Range::<usize>::from(range)).unwrap_or_default().to_string()
    }

    fn complete(&mut self, frames: &[Frame]) {
        let Some(list) = frames.last() else {
            // At the top level, outside any list.
            self.top_level(true);
            return;
        };
        let head_position = list.before == 0;
        if head_position {
            self.at_head(frames, list);
        } else {
            self.at_argument(frames, list);
        }
    }

    fn top_level(&mut self, wrap: bool) {
        let (open, close) = if wrap { ("(", ")") } else { ("", "") };
        let domain = self.workspace_domain().unwrap_or_else(|| "domain".into());
        if !wrap {
            self.push(0, CompletionKind::Keyword, "define", None);
        }
        self.snippet(
            "define (problem …)",
            "problem skeleton",
            format!(
                "{open}define (problem ${{1:name}})\n  (:domain ${{2:{domain}}})\n  (:objects ${{3}})\n  (:init \
                 ${{4}})\n  (:goal (and ${{0}})){close}"
            ),
        );
    }

    /// The name of a domain of the workspace, for a problem's `:domain`: one
    /// in the file's folder first.
    fn workspace_domain(&self) -> Option<String> {
        let dir = dir_of(self.file.path(self.db)).to_string();
        let mut found: Vec<(bool, String, String)> = Vec::new();
        for f in workspace_files(self.db, self.file) {
            for &u in file_units(self.db, f) {
                if u.kind(self.db) == UnitKind::Domain
                    && let Some(name) = u.name(self.db)
                {
                    found.push((dir_of(f.path(self.db)) != dir, f.path(self.db).clone(), name.clone()));
                }
            }
        }
        found.sort();
        found.into_iter().next().map(|(_, _, name)| name)
    }

    /// The sections not yet in the `define`, and the skeletons of items.
    fn sections(&mut self, define: Option<&Frame>, wrap: bool) {
        let present: Vec<String> = define
            .map(|d| {
                d.elems
                    .iter()
                    .filter_map(|e| e.as_node())
                    .filter_map(|n| {
                        elements(n).first().and_then(|h| h.as_token().map(|t| t.text().to_ascii_lowercase()))
                    })
                    .collect()
            })
            .unwrap_or_default();
        let kind = self.unit_kind();
        if !wrap {
            for (i, head) in sections(kind).enumerate() {
                if repeatable(head) || !present.iter().any(|p| p == head) {
                    // PDDL's order of sections.
                    self.out.push(Completion {
                        label: head.to_string(),
                        kind: CompletionKind::Keyword,
                        detail: None,
                        insert: head.to_string(),
                        snippet: false,
                        sort: format!("0{i:02}"),
                        range: self.word,
                    });
                }
            }
        }
        if kind != UnitKind::Problem {
            let (open, close) = if wrap { ("(", ")") } else { ("", "") };
            self.snippet(
                ":durative-action …",
                "durative action skeleton",
                format!(
                    "{open}:durative-action ${{1:name}}\n  :parameters (${{2}})\n  :duration (= ?duration \
                     ${{3:1}})\n  :condition (and (at start ${{4}}))\n  :effect (and (at end ${{0}})){close}"
                ),
            );
            self.snippet(
                ":task … :method …",
                "task and a method for it",
                format!(
                    "{open}:task ${{1:name}}\n  :parameters (${{2}}))\n(:method ${{3:m}}\n  :parameters \
                     (${{2}})\n  :task (${{1:name}} ${{4}})\n  :ordered-subtasks (and ${{0}}){close}"
                ),
            );
        }
    }

    fn at_head(&mut self, frames: &[Frame], list: &Frame) {
        let parent = frames.len().checked_sub(2).map(|i| &frames[i]);
        match list.role {
            Role::Define => {}
            Role::Other if parent.is_none() => self.top_level(false),
            Role::Section => {
                let define = parent.filter(|p| p.role == Role::Define);
                if define.is_some_and(|d| d.index_of(&list.node) == 1) {
                    self.push(0, CompletionKind::Keyword, "domain", None);
                    self.push(0, CompletionKind::Keyword, "problem", None);
                }
                self.sections(define, false);
            }
            Role::NewSection => self.sections(frames.iter().find(|f| f.role == Role::Define), false),
            Role::Gd { durative } => {
                self.predicates(0);
                let mut words =
                    vec!["and", "or", "not", "imply", "forall", "exists", "=", "<", "<=", ">", ">="];
                if durative {
                    words.extend(["at start", "over all", "at end"]);
                }
                self.keywords(1, &words);
            }
            Role::Effect { durative } => {
                self.predicates(0);
                let mut words = vec![
                    "and",
                    "not",
                    "forall",
                    "when",
                    "increase",
                    "decrease",
                    "assign",
                    "scale-up",
                    "scale-down",
                ];
                if durative {
                    words.extend(["at start", "at end"]);
                }
                self.keywords(1, &words);
            }
            Role::Atom => self.predicates(0),
            Role::Init => {
                self.predicates(0);
                self.keywords(1, &["not", "="]);
            }
            Role::Num | Role::Fluent | Role::Term => self.functions(0),
            Role::Duration => self.keywords(0, &["=", "<=", ">=", "and"]),
            Role::Subtasks => {
                self.callables(0, false);
                self.keywords(1, &["and"]);
            }
            Role::Subtask | Role::Call { tasks_only: false } => self.callables(0, false),
            Role::Call { tasks_only: true } => self.callables(0, true),
            Role::Either => self.keywords(0, &["either"]),
            Role::Typed | Role::Decl | Role::Other => {}
        }
    }

    fn at_argument(&mut self, frames: &[Frame], list: &Frame) {
        let head = list.head().unwrap_or_default();
        let index = list.before;
        // A field keyword typed inside a formula of an item left open
        // belongs to the item (the parser reads it so).
        if self.prefix.starts_with(':')
            && let Some(item) = frames
                .iter()
                .rev()
                .find(|f| f.role == Role::Section && is_item(&f.head().unwrap_or_default()))
            && !std::ptr::eq(item, list)
        {
            self.fields(item);
            return;
        }
        match list.role {
            Role::Define => self.sections(Some(list), true),
            Role::Other if frames.len() == 1 => {}
            Role::Section => match head.as_str() {
                ":requirements" => self.requirements(list),
                ":domain" if index == 1 => {
                    if let Some(name) = self.workspace_domain() {
                        self.push(0, CompletionKind::Domain, &name, Some("domain".into()));
                    }
                }
                ":types" | ":constants" | ":objects" => self.types_after_dash(list, false),
                ":functions" => self.types_after_dash(list, true),
                h if is_item(h) && index >= 2 && !list.previous().is_some_and(|p| p.starts_with(':')) => {
                    self.fields(list)
                }
                h if is_item(h) && self.prefix.starts_with(':') => self.fields(list),
                _ => {}
            },
            Role::Typed | Role::Decl => self.types_after_dash(list, false),
            Role::Either => self.types(0),
            Role::Gd { durative } | Role::Effect { durative } => match head.as_str() {
                // `at` may be a predicate too.
                "at" if durative && index == 1 => {
                    self.keywords(0, &["start", "end"]);
                    self.arguments(frames, list, Namespace::Predicate)
                }
                "at" if durative && matches!(list.atom(1).as_deref(), Some("start" | "end")) => {}
                "over" if durative && index == 1 => self.keywords(0, &["all"]),
                "=" => self.terms(frames, None),
                h if is_connective(h) => {}
                _ => self.arguments(frames, list, Namespace::Predicate),
            },
            Role::Atom | Role::Init => match head.as_str() {
                "not" | "=" => {}
                // A timed initial literal, `(at 10 (p))`, or the predicate `at`.
                "at" if list.elems.get(1).is_some_and(|e| e.kind() == SyntaxKind::Number) => {}
                _ => self.arguments(frames, list, Namespace::Predicate),
            },
            Role::Num | Role::Fluent | Role::Duration => match head.as_str() {
                "+" | "-" | "*" | "/" | "=" | "<=" | ">=" | "<" | ">" => {
                    if frames.iter().any(|f| f.head().as_deref() == Some(":durative-action")) {
                        self.push(
                            0,
                            CompletionKind::Variable,
                            "?duration",
                            Some("the action's duration".into()),
                        );
                    }
                    self.terms(frames, Some(&vec!["number".into()]))
                }
                "and" | "at" => {}
                _ => self.arguments(frames, list, Namespace::Function),
            },
            Role::Term => self.arguments(frames, list, Namespace::Function),
            Role::Call { .. } => self.arguments(frames, list, Namespace::Callable),
            // `(deliver ?p …)` without an id; `(t1 …)` has none to offer.
            Role::Subtasks | Role::Subtask => {
                if head != "and" && self.symbols().is_some_and(|s| s.callable(&head).is_some()) {
                    self.arguments(frames, list, Namespace::Callable)
                }
            }
            Role::NewSection | Role::Other => {}
        }
    }

    fn keywords(&mut self, rank: u8, words: &[&str]) {
        for w in words {
            self.push(rank, CompletionKind::Keyword, w, None);
        }
    }

    /// The field keywords an item does not have yet.
    fn fields(&mut self, item: &Frame) {
        let head = item.head().unwrap_or_default();
        let fields: &[&str] = match head.as_str() {
            ":durative-action" => DURATIVE_ACTION_FIELDS,
            ":action" | ":process" | ":event" => ACTION_FIELDS,
            ":task" => TASK_FIELDS,
            ":method" | ":durative-method" => METHOD_FIELDS,
            _ => HTN_FIELDS,
        };
        let present: Vec<String> = (1..item.elems.len())
            .filter(|&i| i != item.before || self.word.is_empty())
            .filter_map(|i| item.atom(i))
            .collect();
        // Aliases of a field present are present too.
        let alias = |f: &str| match f {
            ":precondition" | ":condition" => 0,
            ":subtasks" | ":tasks" | ":ordered-subtasks" | ":ordered-tasks" => 1,
            ":ordering" | ":order" => 2,
            ":causal-links" | ":causallinks" => 3,
            _ => 10,
        };
        for (i, f) in fields.iter().enumerate() {
            let taken = present.iter().any(|p| p == f || (alias(p) < 10 && alias(p) == alias(f)));
            // The rarer spellings of a field are not offered.
            let rare = matches!(*f, ":tasks" | ":ordered-tasks" | ":order" | ":causallinks");
            if !taken && !rare {
                self.out.push(Completion {
                    label: f.to_string(),
                    kind: CompletionKind::Keyword,
                    detail: None,
                    insert: f.to_string(),
                    snippet: false,
                    sort: format!("0{i:02}"),
                    range: self.word,
                });
            }
        }
    }

    fn requirements(&mut self, list: &Frame) {
        let present: Vec<String> = (1..list.elems.len()).filter_map(|i| list.atom(i)).collect();
        for r in KNOWN_REQUIREMENTS {
            if !present.iter().any(|p| p == r) || self.prefix == *r {
                self.push(0, CompletionKind::Requirement, r, None);
            }
        }
    }

    /// Types after `-` in a typed list.
    fn types_after_dash(&mut self, list: &Frame, numeric: bool) {
        if list.previous().as_deref() == Some("-") {
            if numeric {
                self.push(0, CompletionKind::Type, "number", Some("built-in type".into()));
            }
            self.types(0);
        }
    }

    fn types(&mut self, rank: u8) {
        self.push(rank + 1, CompletionKind::Type, "object", Some("built-in type".into()));
        let Some(syms) = self.symbols() else { return };
        let mut found: Vec<(String, String)> = Vec::new();
        for (key, t) in &syms.types {
            let name = t.locs.first().map_or_else(|| key.to_string(), |l| self.name_at(*l));
            let detail = match syms.ancestors.get(key) {
                Some(a) if a.len() > 1 => format!("type {name} - {}", a[1..].join(" - ")),
                _ => format!("type {name}"),
            };
            found.push((name, detail));
        }
        for (name, detail) in found {
            self.push(rank, CompletionKind::Type, &name, Some(detail));
        }
    }

    fn sig_items(&mut self, rank: u8, kind: CompletionKind, what: &str, decls: Vec<(Str, &SigDecl<'_>)>) {
        let found: Vec<(String, String)> = decls
            .into_iter()
            .map(|(key, d)| {
                let name = self.name_at(d.loc);
                let name = if name.is_empty() { key.to_string() } else { name };
                let detail = format!("{what} {}", super::sig_text(&name, d));
                (name, detail)
            })
            .collect();
        for (name, detail) in found {
            self.push(rank, kind, &name, Some(detail));
        }
    }

    fn predicates(&mut self, rank: u8) {
        let Some(syms) = self.symbols() else { return };
        let decls = syms.predicates.iter().map(|(k, d)| (k.clone(), d)).collect();
        self.sig_items(rank, CompletionKind::Predicate, "predicate", decls);
    }

    fn functions(&mut self, rank: u8) {
        let Some(syms) = self.symbols() else { return };
        let decls = syms.functions.iter().map(|(k, d)| (k.clone(), d)).collect();
        self.sig_items(rank, CompletionKind::Function, "function", decls);
    }

    fn callables(&mut self, rank: u8, tasks_only: bool) {
        let Some(syms) = self.symbols() else { return };
        let tasks = syms.tasks.iter().map(|(k, d)| (k.clone(), d)).collect();
        self.sig_items(rank, CompletionKind::Task, "task", tasks);
        if !tasks_only {
            let actions = syms.actions.iter().map(|(k, d)| (k.clone(), d)).collect();
            self.sig_items(rank + 1, CompletionKind::Action, "action", actions);
        }
    }

    /// The arguments of a use of a predicate, function or callable: the
    /// terms whose type fits the parameter's first.
    fn arguments(&mut self, frames: &[Frame], list: &Frame, ns: Namespace) {
        let Some(head) = list.head() else { return };
        let index = list.before - 1;
        let param: Option<TypeSet> = self.symbols().and_then(|s| {
            let decl = match ns {
                Namespace::Predicate => s.predicates.get(head.as_str()),
                Namespace::Function => s.functions.get(head.as_str()),
                Namespace::Callable => s.callable(&head),
            };
            decl.and_then(|d| d.params.get(index).cloned())
        });
        self.terms(frames, param.as_ref());
    }

    /// The terms in scope: variables in a domain, objects in a problem, and
    /// constants; those that fit `param` first.
    fn terms(&mut self, frames: &[Frame], param: Option<&TypeSet>) {
        let syms = self.symbols();
        let fits = |ty: &TypeSet| match (param, syms) {
            (Some(p), Some(s)) => s.fits(ty, p),
            _ => true,
        };
        let mut found: Vec<(u8, CompletionKind, String, String)> = Vec::new();
        let problem = self.unit_kind() == UnitKind::Problem;
        let in_item =
            frames.iter().any(|f| f.role == Role::Section && is_item(&f.head().unwrap_or_default()));
        if !problem || in_item {
            for (name, ty) in variables(frames) {
                let detail = format!("{name} - {}", ty.join(" "));
                found.push((u8::from(!fits(&ty)), CompletionKind::Variable, name, detail));
            }
        }
        if problem && let Some(u) = self.unit {
            for o in problem_symbols(self.db, u).objects.values() {
                let detail = format!("object {} - {}", o.name, o.ty.join(" "));
                found.push((2 + u8::from(!fits(&o.ty)), CompletionKind::Object, o.name.to_string(), detail));
            }
        }
        if let Some(s) = syms {
            for c in s.constants.values() {
                let detail = format!("constant {} - {}", c.name, c.ty.join(" "));
                found.push((
                    2 + u8::from(!fits(&c.ty)),
                    CompletionKind::Constant,
                    c.name.to_string(),
                    detail,
                ));
            }
        }
        for (rank, kind, name, detail) in found {
            self.push(rank, kind, &name, Some(detail));
        }
    }
}

#[derive(Debug, Clone, Copy)]
enum Namespace {
    Predicate,
    Function,
    Callable,
}

#[cfg(test)]
mod tests;
