//! Lowering: from one section's syntax to its [`ItemData`].
//!
//! Lowering is lenient: what has the wrong shape is reported (`E0003`,
//! `E0004`) and skipped, and the rest is still lowered, so that later checks
//! see as much of the file as possible.

use rowan::{GreenNode, NodeOrToken, TextRange, TextSize};

mod formula;
mod network;

use super::*;
use crate::diagnostic::{LocalDiag, codes};
use crate::syntax::{GAtom, GList, GSexp, Lang, SyntaxKind};

/// The fields of an action, a process and an event.
pub const ACTION_FIELDS: &[&str] = &[":parameters", ":precondition", ":effect", ":agent"];

/// The fields of a durative action.
pub const DURATIVE_ACTION_FIELDS: &[&str] = &[":parameters", ":duration", ":condition", ":effect", ":agent"];

/// The fields of a task.
pub const TASK_FIELDS: &[&str] =
    &[":parameters", ":precondition", ":condition", ":effect", ":duration", ":agent", ":conflicts"];

/// The fields of a method.
pub const METHOD_FIELDS: &[&str] = &[
    ":parameters",
    ":task",
    ":precondition",
    ":condition",
    ":duration",
    ":effect",
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

/// The fields of an initial task network.
pub const HTN_FIELDS: &[&str] = &[
    ":parameters",
    ":subtasks",
    ":tasks",
    ":ordered-subtasks",
    ":ordered-tasks",
    ":ordering",
    ":order",
    ":constraints",
];

/// The model of one item and what was wrong with its shape.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Lowered {
    pub data: ItemData,
    pub diags: Vec<LocalDiag>,
}

/// Lowers a section (a list that is a child of a `define`).
pub fn lower_list(green: &GreenNode) -> Lowered {
    let mut cx = Cx { diags: Vec::new() };
    let data = match GList::root(green, TextSize::from(0)) {
        Some(list) => cx.section(&list),
        None => ItemData::Unknown,
    };
    Lowered { data, diags: cx.diags }
}

/// Lowers a chunk of `:init` elements: the significant children of `node`
/// after the first `skip`, with spans relative to the start of `node`.
pub fn lower_chunk(node: &rowan::GreenNodeData, skip: usize) -> Lowered {
    let mut cx = Cx { diags: Vec::new() };
    // A guess at the number of elements, which mostly alternate with whitespace.
    let mut init = Vec::with_capacity(node.children().len() / 2);
    let mut skip = skip;
    let mut at = TextSize::from(0);
    for child in node.children() {
        let start = at;
        at += child.text_len();
        match GSexp::of(child, start) {
            Some(_) if skip > 0 => skip -= 1,
            Some(sexp @ GSexp::List(_)) => {
                if let Some(e) = cx.init_element(&sexp) {
                    init.push(e);
                }
            }
            Some(atom) => cx.malformed(&atom, "expected an initial fact like `(p a b)`"),
            None => {}
        }
    }
    Lowered { data: ItemData::Init(init), diags: cx.diags }
}

struct Cx {
    diags: Vec<LocalDiag>,
}

/// The elements of a list, on the stack for the short lists that facts and atoms are.
type Elems<'t> = smallvec::SmallVec<[GSexp<'t>; 6]>;

/// The elements of `list`, like `list.elements().collect()`.
///
/// Lowering a large `:init` is mostly this loop over the children of short
/// lists: walking the direct children inline costs half of what the
/// general iterator does, which flattens groups one child at a time. Only
/// long lists have groups, and they take the general path. Inlined, the
/// elements are collected where they are used instead of copied there.
#[inline(always)]
fn elements<'t>(list: &GList<'t>) -> Elems<'t> {
    let mut elems = Elems::new();
    for (start, child) in list.direct_children() {
        if let NodeOrToken::Node(n) = child
            && n.kind() == SyntaxKind::Group.into()
        {
            return list.elements().collect();
        }
        if let Some(e) = GSexp::of(child, start) {
            elems.push(e);
        }
    }
    elems
}

fn atom_kind(s: &GSexp<'_>) -> Option<SyntaxKind> {
    s.as_atom().map(|t| t.kind())
}

impl Cx {
    fn error(&mut self, code: &'static crate::diagnostic::Code, span: TextRange, msg: impl Into<String>) {
        self.diags.push(LocalDiag::new(code, span, msg));
    }

    fn malformed(&mut self, at: &GSexp<'_>, msg: impl Into<String>) {
        let span = at.range();
        self.error(codes::MALFORMED, span, msg);
    }

    fn name(&self, t: &GAtom<'_>) -> Name {
        Name::new(t.text(), t.text_range())
    }

    /// An atom that names something (not a variable, keyword or list).
    fn expect_name(&mut self, s: Option<&GSexp<'_>>, what: &str, after: TextRange) -> Option<Name> {
        match s {
            Some(GSexp::Atom(t)) if matches!(t.kind(), SyntaxKind::Symbol | SyntaxKind::Number) => {
                Some(self.name(t))
            }
            Some(other) => {
                self.malformed(other, format!("expected {what}"));
                None
            }
            None => {
                let span = after;
                self.error(codes::MALFORMED, span, format!("expected {what}"));
                None
            }
        }
    }

    /// The atoms of kind `kind` in `elems`; anything else is reported with `what`.
    fn names_of(&mut self, elems: &[GSexp<'_>], kind: SyntaxKind, what: &str) -> Vec<Name> {
        let mut names = Vec::new();
        for e in elems {
            match e {
                GSexp::Atom(t) if t.kind() == kind => names.push(self.name(t)),
                other => self.malformed(other, what),
            }
        }
        names
    }

    fn section(&mut self, list: &GList<'_>) -> ItemData {
        let elems = elements(list);
        let Some(head) = elems.first() else {
            self.error(codes::MALFORMED, list.range(), "empty section `()`");
            return ItemData::Unknown;
        };
        let Some(head_text) = head.atom_text().map(str::to_ascii_lowercase) else {
            self.malformed(head, "expected a section keyword such as `:action` or `:init`");
            return ItemData::Unknown;
        };
        let rest = &elems[1..];
        match head_text.as_str() {
            "domain" | "problem" => {
                match self.expect_name(rest.first(), &format!("the {head_text} name"), head.range()) {
                    Some(n) => ItemData::Header(n),
                    None => ItemData::Unknown,
                }
            }
            ":domain" => match self.expect_name(rest.first(), "the domain name", head.range()) {
                Some(n) => ItemData::DomainRef(n),
                None => ItemData::Unknown,
            },
            ":requirements" => ItemData::Requirements(self.names_of(
                rest,
                SyntaxKind::Keyword,
                "expected a requirement like `:typing`",
            )),
            ":types" => ItemData::Types(self.typed_list(rest, false)),
            ":constants" => ItemData::Constants(self.typed_list(rest, false)),
            ":objects" => ItemData::Objects(self.typed_list(rest, false)),
            ":predicates" => ItemData::Predicates(self.signatures(rest, false)),
            ":functions" => ItemData::Functions(self.signatures(rest, true)),
            ":action" => self.action(ActionKind::Action, head, rest),
            ":durative-action" => self.action(ActionKind::Durative, head, rest),
            ":process" => self.action(ActionKind::Process, head, rest),
            ":event" => self.action(ActionKind::Event, head, rest),
            ":task" => self.task(head, rest),
            ":method" => self.method(false, head, rest),
            ":durative-method" => self.method(true, head, rest),
            ":derived" => self.derived(head, rest),
            ":init" => ItemData::Init(rest.iter().filter_map(|e| self.init_element(e)).collect()),
            ":goal" => match rest {
                [g] => ItemData::Goal(self.gd(g)),
                [] => ItemData::Goal(Gd::And(Vec::new(), list.range())),
                [_, extra, ..] => {
                    self.malformed(extra, "`:goal` takes one goal description: wrap several in `(and …)`");
                    ItemData::Goal(self.gd(&rest[0]))
                }
            },
            ":htn" | ":tihtn" | ":htnti" => self.htn(list, rest),
            // HPDDL problems list their initial tasks directly.
            ":tasks" => {
                let span = list.range();
                let subtasks = rest.iter().filter_map(|x| self.subtask(x)).collect();
                let network = TaskNetwork { subtasks, ordered: true, ..TaskNetwork::default() };
                ItemData::Htn(Htn { params: Vec::new(), network, span })
            }
            ":allowed-actions" => ItemData::AllowedActions(self.names_of(
                rest,
                SyntaxKind::Symbol,
                "expected the name of an action or task",
            )),
            ":metric" => match rest {
                [dir, expr] if dir.is_atom("minimize") || dir.is_atom("maximize") => {
                    let t = dir.as_atom().expect("checked atom");
                    ItemData::Metric(self.name(t), self.num_expr(expr))
                }
                _ => {
                    self.error(
                        codes::MALFORMED,
                        list.range(),
                        "expected `(:metric minimize <expression>)` or `(:metric maximize <expression>)`",
                    );
                    ItemData::Unknown
                }
            },
            ":constraints" => match rest {
                [g] => ItemData::Constraints(self.gd(g)),
                _ => {
                    self.error(codes::MALFORMED, list.range(), "`:constraints` takes one goal description");
                    ItemData::Unknown
                }
            },
            _ => {
                self.error(
                    codes::UNKNOWN_SECTION,
                    head.range(),
                    format!("unknown section `{}`", head.atom_text().unwrap_or_default()),
                );
                ItemData::Unknown
            }
        }
    }

    /// `a b - t c - (either u v) d`.
    fn typed_list(&mut self, elems: &[GSexp<'_>], variables: bool) -> Vec<Typed> {
        let mut out = Vec::new();
        let mut pending: Vec<Name> = Vec::new();
        let mut i = 0;
        while i < elems.len() {
            let e = &elems[i];
            let glued = glued_type(e);
            if e.is_atom("-") || glued.is_some() {
                let (ty, next) = match (glued, elems.get(i + 1)) {
                    (Some(name), _) => (TypeRef::Named(name), i + 1),
                    (None, Some(t)) => (self.type_ref(t), i + 2),
                    (None, None) => {
                        self.malformed(e, "expected a type after `-`");
                        (TypeRef::Implicit, i + 2)
                    }
                };
                if pending.is_empty() {
                    self.malformed(e, "`-` must follow the names it gives a type to");
                }
                out.extend(pending.drain(..).map(|name| Typed { name, ty: ty.clone() }));
                i = next;
                continue;
            }
            match e {
                GSexp::Atom(t) if variables && t.kind() == SyntaxKind::Variable => pending.push(self.name(t)),
                GSexp::Atom(t)
                    if !variables && matches!(t.kind(), SyntaxKind::Symbol | SyntaxKind::Number) =>
                {
                    pending.push(self.name(t))
                }
                other if variables => self.malformed(other, "expected a variable like `?x`"),
                other => self.malformed(other, "expected a name"),
            }
            i += 1;
        }
        out.extend(pending.into_iter().map(|name| Typed { name, ty: TypeRef::Implicit }));
        out
    }

    fn type_ref(&mut self, e: &GSexp<'_>) -> TypeRef {
        match e {
            GSexp::Atom(t) if t.kind() == SyntaxKind::Symbol => TypeRef::Named(self.name(t)),
            GSexp::List(l) if l.head_is("either") => {
                let mut names = Vec::new();
                for x in l.elements().skip(1) {
                    match &x {
                        GSexp::Atom(t) if t.kind() == SyntaxKind::Symbol => names.push(self.name(t)),
                        other => self.malformed(other, "expected a type name"),
                    }
                }
                TypeRef::Either(names)
            }
            other => {
                self.malformed(other, "expected a type name or `(either …)`");
                TypeRef::Implicit
            }
        }
    }

    fn params(&mut self, e: &GSexp<'_>) -> Vec<Typed> {
        match e {
            GSexp::List(l) => {
                let elems = elements(l);
                self.typed_list(&elems, true)
            }
            other => {
                self.malformed(other, "expected a parameter list like `(?x - t)`");
                Vec::new()
            }
        }
    }

    fn signatures(&mut self, elems: &[GSexp<'_>], functions: bool) -> Vec<Signature> {
        let mut out: Vec<Signature> = Vec::new();
        let mut untyped_from = 0;
        let mut i = 0;
        while i < elems.len() {
            let e = &elems[i];
            let glued = if functions { glued_type(e) } else { None };
            if functions && (e.is_atom("-") || glued.is_some()) {
                let (ty, next) = match (glued, elems.get(i + 1)) {
                    (Some(name), _) => (TypeRef::Named(name), i + 1),
                    (None, Some(t)) => (self.type_ref(t), i + 2),
                    (None, None) => {
                        self.malformed(e, "expected a type after `-`");
                        (TypeRef::Implicit, i + 2)
                    }
                };
                for sig in &mut out[untyped_from..] {
                    sig.result = ty.clone();
                }
                untyped_from = out.len();
                i = next;
                continue;
            }
            match e {
                GSexp::List(l) => {
                    let inner = elements(l);
                    match inner.first() {
                        Some(GSexp::Atom(t)) if t.kind() == SyntaxKind::Symbol => {
                            let name = self.name(t);
                            let params = self.typed_list(&inner[1..], true);
                            out.push(Signature { name, params, result: TypeRef::Implicit, span: l.range() });
                        }
                        Some(other) => self.malformed(other, "expected a name"),
                        None => self.malformed(e, "expected a declaration like `(name ?x - t)`"),
                    }
                }
                other => self.malformed(
                    other,
                    if functions {
                        "expected a declaration like `(f ?x - t) - number`"
                    } else {
                        "expected a declaration like `(p ?x - t)`"
                    },
                ),
            }
            i += 1;
        }
        out
    }

    /// Splits `:field value :field value` pairs.
    fn fields<'a, 't>(
        &mut self,
        rest: &'a [GSexp<'t>],
        allowed: &[&str],
        what: &str,
    ) -> Vec<(String, TextRange, Option<&'a GSexp<'t>>)> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < rest.len() {
            let e = &rest[i];
            match e {
                GSexp::Atom(t) if t.kind() == SyntaxKind::Keyword => {
                    let key = t.text().to_ascii_lowercase();
                    let value = rest.get(i + 1).filter(|v| atom_kind(v) != Some(SyntaxKind::Keyword));
                    if !allowed.contains(&key.as_str()) {
                        self.error(
                            codes::UNKNOWN_SECTION,
                            t.text_range(),
                            format!(
                                "`{}` is not a field of {what} (expected one of {})",
                                t.text(),
                                allowed.join(", ")
                            ),
                        );
                    } else if value.is_none() {
                        self.error(codes::MALFORMED, t.text_range(), format!("`{}` needs a value", t.text()));
                    } else if let Some((_, first, _)) = out.iter().find(|(k, _, _)| *k == key) {
                        let first = *first;
                        let d = LocalDiag::new(
                            codes::DUPLICATE,
                            t.text_range(),
                            format!("`{}` is given twice in {what}: only one is allowed", t.text()),
                        )
                        .with_related(first, "first given here");
                        self.diags.push(d);
                    } else {
                        out.push((key, t.text_range(), value));
                    }
                    i += if value.is_some() { 2 } else { 1 };
                }
                other => {
                    self.malformed(other, format!("expected a field keyword of {what}"));
                    i += 1;
                }
            }
        }
        out
    }

    fn agent(&mut self, e: &GSexp<'_>) -> Vec<Name> {
        match e {
            GSexp::Atom(t) if t.kind() == SyntaxKind::Variable => vec![self.name(t)],
            GSexp::List(l) => l
                .elements()
                .filter_map(|x| match &x {
                    GSexp::Atom(t) if t.kind() == SyntaxKind::Variable => Some(self.name(t)),
                    other => {
                        self.malformed(other, "expected a parameter variable like `?r`");
                        None
                    }
                })
                .collect(),
            other => {
                self.malformed(other, "expected the agent's variables, like `(?r)`");
                Vec::new()
            }
        }
    }

    fn action(&mut self, kind: ActionKind, head: &GSexp<'_>, rest: &[GSexp<'_>]) -> ItemData {
        let what = match kind {
            ActionKind::Action => "an action",
            ActionKind::Durative => "a durative action",
            ActionKind::Process => "a process",
            ActionKind::Event => "an event",
        };
        let Some(name) = self.expect_name(rest.first(), "the action's name", head.range()) else {
            return ItemData::Unknown;
        };
        let allowed: &[&str] = match kind {
            ActionKind::Durative => DURATIVE_ACTION_FIELDS,
            _ => ACTION_FIELDS,
        };
        let mut action = Action {
            kind,
            name,
            params: Vec::new(),
            agent: Vec::new(),
            duration: None,
            precondition: None,
            effect: None,
        };
        for (key, _, value) in self.fields(&rest[1..], allowed, what) {
            let value = value.expect("fields have values");
            match key.as_str() {
                ":parameters" => action.params = self.params(value),
                ":duration" => action.duration = Some(self.gd(value)),
                ":condition" | ":precondition" => action.precondition = Some(self.gd(value)),
                ":effect" => action.effect = Some(self.effect(value)),
                ":agent" => action.agent = self.agent(value),
                _ => {}
            }
        }
        ItemData::Action(Box::new(action))
    }

    fn task(&mut self, head: &GSexp<'_>, rest: &[GSexp<'_>]) -> ItemData {
        let Some(name) = self.expect_name(rest.first(), "the task's name", head.range()) else {
            return ItemData::Unknown;
        };
        let allowed = TASK_FIELDS;
        let mut task = Task {
            name,
            params: Vec::new(),
            agent: Vec::new(),
            duration: None,
            precondition: None,
            effect: None,
            conflicts: None,
        };
        for (key, keyword, value) in self.fields(&rest[1..], allowed, "a task") {
            let value = value.expect("fields have values");
            match key.as_str() {
                ":parameters" => task.params = self.params(value),
                ":duration" => task.duration = Some(self.gd(value)),
                ":condition" | ":precondition" => task.precondition = Some(self.gd(value)),
                ":effect" => task.effect = Some(self.effect(value)),
                ":agent" => task.agent = self.agent(value),
                ":conflicts" => task.conflicts = Some(self.conflicts(keyword, value)),
                _ => {}
            }
        }
        ItemData::Task(Box::new(task))
    }

    fn conflicts(&mut self, keyword: TextRange, e: &GSexp<'_>) -> Conflicts {
        let (atoms, form) = match e {
            GSexp::List(l) if l.head_is("and") => {
                let atoms = l.elements().skip(1).filter_map(|x| self.atom(&x)).collect();
                (atoms, and_insertion(l))
            }
            GSexp::List(l) if l.head().is_none() => {
                (Vec::new(), if is_closed(l) { ConflictsForm::Empty } else { ConflictsForm::Other })
            }
            other => {
                let atom = self.atom(other);
                let form = match other {
                    GSexp::List(l) if atom.is_some() && is_closed(l) => ConflictsForm::Atom,
                    _ => ConflictsForm::Other,
                };
                (atom.into_iter().collect(), form)
            }
        };
        Conflicts { atoms, keyword, span: e.range(), form }
    }

    fn method(&mut self, durative: bool, head: &GSexp<'_>, rest: &[GSexp<'_>]) -> ItemData {
        let Some(name) = self.expect_name(rest.first(), "the method's name", head.range()) else {
            return ItemData::Unknown;
        };
        let allowed = METHOD_FIELDS;
        let mut m = Method {
            durative,
            name,
            params: Vec::new(),
            task: None,
            precondition: None,
            duration: None,
            effect: None,
            network: TaskNetwork::default(),
        };
        let fields = self.fields(&rest[1..], allowed, "a method");
        for (key, _, value) in fields {
            let value = value.expect("fields have values");
            match key.as_str() {
                ":parameters" => m.params = self.params(value),
                ":task" => m.task = self.task_call(value),
                ":precondition" | ":condition" => m.precondition = Some(self.gd(value)),
                ":duration" => m.duration = Some(self.gd(value)),
                ":effect" => m.effect = Some(self.effect(value)),
                _ => self.network_field(&mut m.network, &key, value),
            }
        }
        if m.task.is_none() {
            self.error(codes::MALFORMED, m.name.span, format!("method `{}` has no `:task`", m.name.text()));
        }
        ItemData::Method(Box::new(m))
    }

    fn htn(&mut self, list: &GList<'_>, rest: &[GSexp<'_>]) -> ItemData {
        let allowed = HTN_FIELDS;
        let mut htn = Htn { params: Vec::new(), network: TaskNetwork::default(), span: list.range() };
        for (key, _, value) in self.fields(rest, allowed, "an initial task network") {
            let value = value.expect("fields have values");
            match key.as_str() {
                ":parameters" => htn.params = self.params(value),
                _ => self.network_field(&mut htn.network, &key, value),
            }
        }
        ItemData::Htn(htn)
    }

    fn derived(&mut self, head: &GSexp<'_>, rest: &[GSexp<'_>]) -> ItemData {
        match rest {
            [GSexp::List(p), body] => {
                let inner = elements(p);
                let Some(GSexp::Atom(t)) = inner.first() else {
                    self.malformed(&rest[0], "expected `(predicate ?x - t …)`");
                    return ItemData::Unknown;
                };
                let params = self.typed_list(&inner[1..], true);
                let atom = Atom {
                    pred: self.name(t),
                    args: params.iter().map(|p| Term::Var(p.name.clone())).collect(),
                    span: p.range(),
                };
                ItemData::Derived(atom, params, self.gd(body))
            }
            _ => {
                self.error(codes::MALFORMED, head.range(), "expected `(:derived (p ?x - t) <condition>)`");
                ItemData::Unknown
            }
        }
    }

    fn init_element(&mut self, e: &GSexp<'_>) -> Option<InitElement> {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected an initial fact like `(p a b)`");
            return None;
        };
        let span = l.range();
        let inner = elements(l);
        match inner.as_slice() {
            [at, GSexp::Atom(n), lit @ GSexp::List(_)]
                if at.is_atom("at") && n.kind() == SyntaxKind::Number =>
            {
                let time = Number { text: n.text().into(), span: n.text_range() };
                let inner = self.init_element(lit)?;
                Some(InitElement::Timed(time, Box::new(inner), span))
            }
            [at, t @ GSexp::Atom(n), GSexp::List(_)]
                if at.is_atom("at") && crate::syntax::looks_like_a_number(n.text()) =>
            {
                self.not_a_number(t);
                None
            }
            [not, x] if not.is_atom("not") => self.atom(x).map(|a| InitElement::NotFact(a, span)),
            [eq, f @ GSexp::List(_), v] if eq.is_atom("=") => {
                let f = self.fluent(f)?;
                match v {
                    GSexp::Atom(t)
                        if t.kind() == SyntaxKind::Symbol
                            && !crate::syntax::looks_like_a_number(t.text()) =>
                    {
                        Some(InitElement::AssignObject(f, self.name(t), span))
                    }
                    _ => {
                        let v = self.num_expr(v);
                        Some(InitElement::Assign(f, v, span))
                    }
                }
            }
            // `atom_of`, inlined: a fact built in place is not moved once more.
            _ => {
                let pred = self.applied_name(e, &inner, "expected an atom like `(p ?x)`")?;
                Some(InitElement::Fact(Atom { pred, args: self.terms(&inner[1..]), span }))
            }
        }
    }
}

/// `-Type` written without a space, as IPC 2023 domains write typed lists
/// (`?x -Location`): the type name it glues to `-`, located without the `-`.
/// A name cannot start with `-`, so this is no other reading of the atom.
pub(super) fn glued_type(e: &GSexp<'_>) -> Option<Name> {
    let t = e.as_atom()?;
    let name = t.text().strip_prefix('-')?;
    if t.kind() != SyntaxKind::Symbol || !name.starts_with(|c: char| c.is_alphabetic()) {
        return None;
    }
    let start = t.text_range().start() + TextSize::from(1);
    Some(Name::new(name, TextRange::new(start, t.text_range().end())))
}

/// Whether a list ends with its `)` (recovery leaves unclosed lists open).
fn is_closed(l: &GList<'_>) -> bool {
    let last = l.children().last();
    matches!(last, Some((_, NodeOrToken::Token(t))) if <Lang as rowan::Language>::kind_from_raw(t.kind()) == SyntaxKind::RParen)
}

/// Where a new atom goes in `(and …)`: after the last element, on a line of
/// its own when the last element is on one (with its indentation), so that
/// an edit keeps the user's layout and leaves comments where they are.
fn and_insertion(l: &GList<'_>) -> ConflictsForm {
    if !is_closed(l) {
        return ConflictsForm::Other;
    }
    let mut trivia = String::new();
    let mut last: Option<(TextSize, String)> = None;
    let mut close = None;
    for (start, c) in l.children() {
        match c {
            NodeOrToken::Token(t) => match <Lang as rowan::Language>::kind_from_raw(t.kind()) {
                SyntaxKind::Whitespace => trivia.push_str(t.text()),
                SyntaxKind::Comment => trivia.clear(),
                SyntaxKind::RParen => close = Some(start),
                SyntaxKind::LParen => {}
                _ => {
                    last = Some((start + t.text_len(), std::mem::take(&mut trivia)));
                }
            },
            NodeOrToken::Node(n) => last = Some((start + n.text_len(), std::mem::take(&mut trivia))),
        }
    }
    let Some(close) = close else { return ConflictsForm::Other };
    match last {
        // `(and)`: the head is the last element.
        Some((at, before)) if l.elements().count() > 1 => {
            let sep = match before.rfind('\n') {
                Some(i) => format!("\n{}", &before[i + 1..]),
                None => " ".to_string(),
            };
            ConflictsForm::And { at, sep: sep.into() }
        }
        _ => ConflictsForm::And { at: close, sep: " ".into() },
    }
}
