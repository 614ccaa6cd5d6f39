//! Lowering: from one section's syntax to its [`ItemData`].
//!
//! Lowering is lenient: what has the wrong shape is reported (`E0003`,
//! `E0004`) and skipped, and the rest is still lowered, so that later checks
//! see as much of the file as possible.

use rowan::{GreenNode, NodeOrToken, TextRange, TextSize};

use super::*;
use crate::diagnostic::{LocalDiag, codes};
use crate::syntax::{GAtom, GList, GSexp, SyntaxKind};

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

/// Lowers a chunk of `:init` elements, given with their offsets relative to the chunk.
pub fn lower_chunk(
    elements: &[(TextSize, NodeOrToken<&rowan::GreenNodeData, &rowan::GreenTokenData>)],
) -> Lowered {
    let mut cx = Cx { diags: Vec::new() };
    let mut init = Vec::with_capacity(elements.len());
    for &(offset, element) in elements {
        match GSexp::of(element, offset) {
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

/// A subtask id, `(start id)` or `(end id)`.
fn is_order_point(e: &GSexp<'_>) -> bool {
    match e {
        GSexp::Atom(t) => t.kind() == SyntaxKind::Symbol,
        GSexp::List(l) => {
            (l.head_is("start") || l.head_is("end"))
                && l.elements().count() == 2
                && l.elements()
                    .nth(1)
                    .is_some_and(|x| x.as_atom().is_some_and(|t| t.kind() == SyntaxKind::Symbol))
        }
    }
}

/// `(op a b)` or `(a op b)` with `op` a comparison and `a`, `b` order points
/// (`=` between two plain names stays an equality of objects).
fn is_ordering_shape(inner: &[GSexp<'_>]) -> bool {
    let is_op = |s: &GSexp<'_>| s.atom_text().and_then(CmpOp::parse).is_some();
    match inner {
        [op, a, b] if is_op(op) => {
            is_order_point(a)
                && is_order_point(b)
                && !(op.is_atom("=") && a.as_atom().is_some() && b.as_atom().is_some())
        }
        [a, op, b] if is_op(op) => is_order_point(a) && is_order_point(b),
        _ => false,
    }
}

/// The elements of `(and a b …)`, of `()`, or the element itself.
fn conjuncts<'t>(e: &GSexp<'t>) -> Vec<GSexp<'t>> {
    match e {
        GSexp::List(l) if l.head_is("and") => l.elements().skip(1).collect(),
        GSexp::List(l) if l.head().is_none() => Vec::new(),
        other => vec![*other],
    }
}

fn atom_kind(s: &GSexp<'_>) -> Option<SyntaxKind> {
    s.as_atom().map(|t| t.kind())
}

impl Cx {
    fn span(&self, r: TextRange) -> TextRange {
        r
    }

    fn error(&mut self, code: &'static crate::diagnostic::Code, span: TextRange, msg: impl Into<String>) {
        self.diags.push(LocalDiag::new(code, span, msg));
    }

    fn malformed(&mut self, at: &GSexp<'_>, msg: impl Into<String>) {
        let span = self.span(at.range());
        self.error(codes::MALFORMED, span, msg);
    }

    fn name(&self, t: &GAtom<'_>) -> Name {
        Name::new(t.text(), self.span(t.text_range()))
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
                let span = self.span(after);
                self.error(codes::MALFORMED, span, format!("expected {what}"));
                None
            }
        }
    }

    fn section(&mut self, list: &GList<'_>) -> ItemData {
        let elems: Vec<GSexp<'_>> = list.elements().collect();
        let Some(head) = elems.first() else {
            self.error(codes::MALFORMED, self.span(list.range()), "empty section `()`");
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
            ":requirements" => {
                let mut reqs = Vec::new();
                for r in rest {
                    match r {
                        GSexp::Atom(t) if t.kind() == SyntaxKind::Keyword => reqs.push(self.name(t)),
                        other => self.malformed(other, "expected a requirement like `:typing`"),
                    }
                }
                ItemData::Requirements(reqs)
            }
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
                [] => ItemData::Goal(Gd::And(Vec::new(), self.span(list.range()))),
                [_, extra, ..] => {
                    self.malformed(extra, "`:goal` takes one goal description: wrap several in `(and …)`");
                    ItemData::Goal(self.gd(&rest[0]))
                }
            },
            ":htn" | ":tihtn" | ":htnti" => self.htn(list, rest),
            // HPDDL problems list their initial tasks directly.
            ":tasks" => {
                let span = self.span(list.range());
                let subtasks = rest.iter().filter_map(|x| self.subtask(x)).collect();
                let network = TaskNetwork { subtasks, ordered: true, ..TaskNetwork::default() };
                ItemData::Htn(Htn { params: Vec::new(), network, span })
            }
            ":allowed-actions" => {
                let mut names = Vec::new();
                for r in rest {
                    match r {
                        GSexp::Atom(t) if t.kind() == SyntaxKind::Symbol => names.push(self.name(t)),
                        other => self.malformed(other, "expected the name of an action or task"),
                    }
                }
                ItemData::AllowedActions(names)
            }
            ":metric" => match rest {
                [dir, expr] if dir.is_atom("minimize") || dir.is_atom("maximize") => {
                    let t = dir.as_atom().expect("checked atom");
                    ItemData::Metric(self.name(t), self.num_expr(expr))
                }
                _ => {
                    self.error(
                        codes::MALFORMED,
                        self.span(list.range()),
                        "expected `(:metric minimize <expression>)` or `(:metric maximize <expression>)`",
                    );
                    ItemData::Unknown
                }
            },
            ":constraints" => match rest {
                [g] => ItemData::Constraints(self.gd(g)),
                _ => {
                    self.error(
                        codes::MALFORMED,
                        self.span(list.range()),
                        "`:constraints` takes one goal description",
                    );
                    ItemData::Unknown
                }
            },
            _ => {
                self.error(
                    codes::UNKNOWN_SECTION,
                    self.span(head.range()),
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
            if e.is_atom("-") {
                let ty = match elems.get(i + 1) {
                    Some(t) => self.type_ref(t),
                    None => {
                        self.malformed(e, "expected a type after `-`");
                        TypeRef::Implicit
                    }
                };
                if pending.is_empty() {
                    self.malformed(e, "`-` must follow the names it gives a type to");
                }
                out.extend(pending.drain(..).map(|name| Typed { name, ty: ty.clone() }));
                i += 2;
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
                let elems: Vec<GSexp<'_>> = l.elements().collect();
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
            if functions && e.is_atom("-") {
                let ty = match elems.get(i + 1) {
                    Some(t) => self.type_ref(t),
                    None => {
                        self.malformed(e, "expected a type after `-`");
                        TypeRef::Implicit
                    }
                };
                for sig in &mut out[untyped_from..] {
                    sig.result = ty.clone();
                }
                untyped_from = out.len();
                i += 2;
                continue;
            }
            match e {
                GSexp::List(l) => {
                    let inner: Vec<GSexp<'_>> = l.elements().collect();
                    match inner.first() {
                        Some(GSexp::Atom(t)) if t.kind() == SyntaxKind::Symbol => {
                            let name = self.name(t);
                            let params = self.typed_list(&inner[1..], true);
                            out.push(Signature {
                                name,
                                params,
                                result: TypeRef::Implicit,
                                span: self.span(l.range()),
                            });
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
                            self.span(t.text_range()),
                            format!(
                                "`{}` is not a field of {what} (expected one of {})",
                                t.text(),
                                allowed.join(", ")
                            ),
                        );
                    } else if value.is_none() {
                        self.error(
                            codes::MALFORMED,
                            self.span(t.text_range()),
                            format!("`{}` needs a value", t.text()),
                        );
                    } else if let Some((_, first, _)) = out.iter().find(|(k, _, _)| *k == key) {
                        let first = *first;
                        let d = LocalDiag::new(
                            codes::DUPLICATE,
                            self.span(t.text_range()),
                            format!("`{}` is given twice in {what}: only one is allowed", t.text()),
                        )
                        .with_related(first, "first given here");
                        self.diags.push(d);
                    } else {
                        out.push((key, self.span(t.text_range()), value));
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
            ActionKind::Durative => &[":parameters", ":duration", ":condition", ":effect", ":agent"],
            _ => &[":parameters", ":precondition", ":effect", ":agent"],
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
        let allowed =
            &[":parameters", ":precondition", ":condition", ":effect", ":duration", ":agent", ":conflicts"];
        let mut task = Task {
            name,
            params: Vec::new(),
            agent: Vec::new(),
            duration: None,
            precondition: None,
            effect: None,
            conflicts: Vec::new(),
        };
        for (key, _, value) in self.fields(&rest[1..], allowed, "a task") {
            let value = value.expect("fields have values");
            match key.as_str() {
                ":parameters" => task.params = self.params(value),
                ":duration" => task.duration = Some(self.gd(value)),
                ":condition" | ":precondition" => task.precondition = Some(self.gd(value)),
                ":effect" => task.effect = Some(self.effect(value)),
                ":agent" => task.agent = self.agent(value),
                ":conflicts" => task.conflicts = self.conflicts(value),
                _ => {}
            }
        }
        ItemData::Task(Box::new(task))
    }

    fn conflicts(&mut self, e: &GSexp<'_>) -> Vec<Atom> {
        match e {
            GSexp::List(l) if l.head_is("and") => {
                l.elements().skip(1).filter_map(|x| self.atom(&x)).collect()
            }
            GSexp::List(l) if l.head().is_none() => Vec::new(),
            other => self.atom(other).into_iter().collect(),
        }
    }

    fn method(&mut self, durative: bool, head: &GSexp<'_>, rest: &[GSexp<'_>]) -> ItemData {
        let Some(name) = self.expect_name(rest.first(), "the method's name", head.range()) else {
            return ItemData::Unknown;
        };
        let allowed = &[
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
            self.error(codes::MALFORMED, m.name.span, format!("method `{}` has no `:task`", m.name.text));
        }
        ItemData::Method(Box::new(m))
    }

    fn network_field(&mut self, net: &mut TaskNetwork, key: &str, value: &GSexp<'_>) {
        match key {
            ":subtasks" | ":tasks" => net.subtasks = self.subtasks(value),
            ":ordered-subtasks" | ":ordered-tasks" => {
                net.subtasks = self.subtasks(value);
                net.ordered = true;
            }
            ":ordering" | ":order" => net.ordering = self.orderings(value),
            ":causal-links" | ":causallinks" => net.causal_links = self.causal_links(value),
            ":constraints" => net.constraints = Some(self.gd(value)),
            _ => {}
        }
    }

    fn htn(&mut self, list: &GList<'_>, rest: &[GSexp<'_>]) -> ItemData {
        let allowed = &[
            ":parameters",
            ":subtasks",
            ":tasks",
            ":ordered-subtasks",
            ":ordered-tasks",
            ":ordering",
            ":order",
            ":constraints",
        ];
        let mut htn =
            Htn { params: Vec::new(), network: TaskNetwork::default(), span: self.span(list.range()) };
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
                let inner: Vec<GSexp<'_>> = p.elements().collect();
                let Some(GSexp::Atom(t)) = inner.first() else {
                    self.malformed(&rest[0], "expected `(predicate ?x - t …)`");
                    return ItemData::Unknown;
                };
                let params = self.typed_list(&inner[1..], true);
                let atom = Atom {
                    pred: self.name(t),
                    args: params.iter().map(|p| Term::Var(p.name.clone())).collect(),
                    span: self.span(p.range()),
                };
                ItemData::Derived(atom, params, self.gd(body))
            }
            _ => {
                self.error(
                    codes::MALFORMED,
                    self.span(head.range()),
                    "expected `(:derived (p ?x - t) <condition>)`",
                );
                ItemData::Unknown
            }
        }
    }

    fn task_call(&mut self, e: &GSexp<'_>) -> Option<TaskCall> {
        match e {
            GSexp::List(l) => {
                let inner: Vec<GSexp<'_>> = l.elements().collect();
                match inner.first() {
                    Some(GSexp::Atom(t)) if t.kind() == SyntaxKind::Symbol => Some(TaskCall {
                        name: self.name(t),
                        args: inner[1..].iter().filter_map(|a| self.term(a)).collect(),
                        span: self.span(l.range()),
                    }),
                    _ => {
                        self.malformed(e, "expected a task like `(name ?x …)`");
                        None
                    }
                }
            }
            other => {
                self.malformed(other, "expected a task like `(name ?x …)`");
                None
            }
        }
    }

    fn subtasks(&mut self, e: &GSexp<'_>) -> Vec<Subtask> {
        let items = conjuncts(e);
        items.iter().filter_map(|x| self.subtask(x)).collect()
    }

    fn subtask(&mut self, e: &GSexp<'_>) -> Option<Subtask> {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected a subtask like `(t1 (name ?x …))`");
            return None;
        };
        let inner: Vec<GSexp<'_>> = l.elements().collect();
        match inner.as_slice() {
            [GSexp::Atom(id), call @ GSexp::List(_)] if id.kind() == SyntaxKind::Symbol => {
                let id = self.name(id);
                self.task_call(call).map(|call| Subtask { id: Some(id), call })
            }
            _ => self.task_call(e).map(|call| Subtask { id: None, call }),
        }
    }

    fn causal_links(&mut self, e: &GSexp<'_>) -> Vec<CausalLink> {
        let items = conjuncts(e);
        let mut out = Vec::new();
        for x in &items {
            let inner: Vec<GSexp<'_>> = x.as_list().map(|l| l.elements().collect()).unwrap_or_default();
            match inner.as_slice() {
                [GSexp::Atom(from), lit, GSexp::Atom(to)] => {
                    let (from, to) = (self.name(from), self.name(to));
                    let (negated, atom) = match lit.as_list() {
                        Some(l) if l.head_is("not") => {
                            (true, l.elements().nth(1).and_then(|a| self.atom(&a)))
                        }
                        _ => (false, self.atom(lit)),
                    };
                    if let Some(atom) = atom {
                        out.push(CausalLink { from, atom, negated, to });
                    }
                }
                _ => self.malformed(x, "expected a causal link like `(t1 (p ?x) t2)`"),
            }
        }
        out
    }

    fn orderings(&mut self, e: &GSexp<'_>) -> Vec<Ordering> {
        let items = conjuncts(e);
        items.iter().filter_map(|x| self.ordering(x)).collect()
    }

    fn order_point(&mut self, e: &GSexp<'_>) -> Option<OrderPoint> {
        match e {
            GSexp::Atom(t) if t.kind() == SyntaxKind::Symbol || t.kind() == SyntaxKind::Number => {
                Some(OrderPoint { id: self.name(t), endpoint: Endpoint::Whole })
            }
            GSexp::List(l) => {
                let inner: Vec<GSexp<'_>> = l.elements().collect();
                match inner.as_slice() {
                    [which, GSexp::Atom(id)] if which.is_atom("start") || which.is_atom("end") => {
                        Some(OrderPoint {
                            id: self.name(id),
                            endpoint: if which.is_atom("start") { Endpoint::Start } else { Endpoint::End },
                        })
                    }
                    _ => {
                        self.malformed(e, "expected a subtask id, `(start id)` or `(end id)`");
                        None
                    }
                }
            }
            other => {
                self.malformed(other, "expected a subtask id");
                None
            }
        }
    }

    fn ordering(&mut self, e: &GSexp<'_>) -> Option<Ordering> {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected an ordering like `(< t1 t2)`");
            return None;
        };
        let inner: Vec<GSexp<'_>> = l.elements().collect();
        if let [not, inner_e] = inner.as_slice()
            && not.is_atom("not")
        {
            return self.ordering(inner_e).map(|mut o| {
                o.negated = !o.negated;
                o.span = self.span(l.range());
                o
            });
        }
        let op_of = |s: &GSexp| s.atom_text().and_then(CmpOp::parse);
        let (op, a, b) = match inner.as_slice() {
            [op, a, b] if op_of(op).is_some() => (op_of(op)?, a, b),
            [a, op, b] if op_of(op).is_some() => (op_of(op)?, a, b),
            _ => {
                self.malformed(e, "expected an ordering like `(< t1 t2)` or `(t1 < t2)`");
                return None;
            }
        };
        let left = self.order_point(a)?;
        let right = self.order_point(b)?;
        Some(Ordering { op, negated: false, left, right, span: self.span(l.range()) })
    }

    fn term(&mut self, e: &GSexp<'_>) -> Option<Term> {
        match e {
            GSexp::Atom(t) => match t.kind() {
                SyntaxKind::Variable => Some(Term::Var(self.name(t))),
                SyntaxKind::Keyword => {
                    self.malformed(
                        e,
                        format!("expected a variable or an object, found the keyword `{}`", t.text()),
                    );
                    None
                }
                _ => Some(Term::Const(self.name(t))),
            },
            GSexp::List(_) => self.fluent(e).map(|f| Term::Func(Box::new(f))),
        }
    }

    fn atom(&mut self, e: &GSexp<'_>) -> Option<Atom> {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected an atom like `(p ?x)`");
            return None;
        };
        let inner: Vec<GSexp<'_>> = l.elements().collect();
        match inner.first() {
            Some(GSexp::Atom(t)) if t.kind() == SyntaxKind::Symbol => Some(Atom {
                pred: self.name(t),
                args: inner[1..].iter().filter_map(|a| self.term(a)).collect(),
                span: self.span(l.range()),
            }),
            _ => {
                self.malformed(e, "expected an atom like `(p ?x)`");
                None
            }
        }
    }

    fn fluent(&mut self, e: &GSexp<'_>) -> Option<Fluent> {
        match e {
            GSexp::List(l) => {
                let inner: Vec<GSexp<'_>> = l.elements().collect();
                match inner.first() {
                    Some(GSexp::Atom(t)) if t.kind() == SyntaxKind::Symbol => Some(Fluent {
                        func: self.name(t),
                        args: inner[1..].iter().filter_map(|a| self.term(a)).collect(),
                        span: self.span(l.range()),
                    }),
                    _ => {
                        self.malformed(e, "expected a function term like `(f ?x)`");
                        None
                    }
                }
            }
            GSexp::Atom(t) if t.kind() == SyntaxKind::Symbol => {
                Some(Fluent { func: self.name(t), args: Vec::new(), span: self.span(t.text_range()) })
            }
            other => {
                self.malformed(other, "expected a function term like `(f ?x)`");
                None
            }
        }
    }

    fn num_expr(&mut self, e: &GSexp<'_>) -> NumExpr {
        match e {
            GSexp::Atom(t) => match t.kind() {
                SyntaxKind::Number => {
                    NumExpr::Number(Number { text: t.text().into(), span: self.span(t.text_range()) })
                }
                SyntaxKind::Variable if t.text().eq_ignore_ascii_case("?duration") => {
                    NumExpr::Duration(self.span(t.text_range()))
                }
                SyntaxKind::Variable => NumExpr::Var(self.name(t)),
                _ if t.text() == "#t" || t.text().eq_ignore_ascii_case("total-time") => {
                    NumExpr::Special(t.text().to_ascii_lowercase().into(), self.span(t.text_range()))
                }
                _ => NumExpr::Fluent(Fluent {
                    func: self.name(t),
                    args: Vec::new(),
                    span: self.span(t.text_range()),
                }),
            },
            GSexp::List(l) => {
                let inner: Vec<GSexp<'_>> = l.elements().collect();
                let span = self.span(l.range());
                match inner.first().and_then(|h| h.atom_text()) {
                    Some(op @ ("+" | "-" | "*" | "/")) if inner.len() >= 2 => {
                        let op: Box<str> = op.into();
                        NumExpr::Op(op, inner[1..].iter().map(|x| self.num_expr(x)).collect(), span)
                    }
                    Some(h) if h.eq_ignore_ascii_case("total-time") && inner.len() == 1 => {
                        NumExpr::Special("total-time".into(), span)
                    }
                    Some(h) if h.eq_ignore_ascii_case("duration") && inner.len() == 2 => match &inner[1] {
                        GSexp::Atom(t) => NumExpr::TaskDuration(self.name(t), span),
                        other => {
                            self.malformed(other, "expected a subtask id");
                            NumExpr::Special("error".into(), span)
                        }
                    },
                    _ => match self.fluent(e) {
                        Some(f) => NumExpr::Fluent(f),
                        None => NumExpr::Special("error".into(), span),
                    },
                }
            }
        }
    }

    fn timed_head(inner: &[GSexp<'_>]) -> Option<TimeSpec> {
        match inner {
            [at, which, GSexp::List(_)] if at.is_atom("at") && which.is_atom("start") => {
                Some(TimeSpec::AtStart)
            }
            [at, which, GSexp::List(_)] if at.is_atom("at") && which.is_atom("end") => Some(TimeSpec::AtEnd),
            [over, all, GSexp::List(_)] if over.is_atom("over") && all.is_atom("all") => {
                Some(TimeSpec::OverAll)
            }
            _ => None,
        }
    }

    fn quantified_params(&mut self, e: &GSexp<'_>) -> Vec<Typed> {
        self.params(e)
    }

    fn gd(&mut self, e: &GSexp<'_>) -> Gd {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected a condition in parentheses");
            return Gd::And(Vec::new(), self.span(e.range()));
        };
        let span = self.span(l.range());
        let inner: Vec<GSexp<'_>> = l.elements().collect();
        if let Some(ts) = Self::timed_head(&inner) {
            return Gd::Timed(ts, Box::new(self.gd(&inner[2])), span);
        }
        let Some(head) = inner.first() else { return Gd::And(Vec::new(), span) };
        // Orderings between subtasks inside `:constraints`: `(< t1 t2)`, `(t1 < t2)`,
        // `(<= (end t1) (start t2))`.
        if is_ordering_shape(&inner) {
            return match self.ordering(e) {
                Some(o) => Gd::Order(o),
                None => Gd::And(Vec::new(), span),
            };
        }
        let Some(h) = head.atom_text().map(str::to_ascii_lowercase) else {
            self.malformed(head, "expected a predicate or a connective like `and`");
            return Gd::And(Vec::new(), span);
        };
        let args = &inner[1..];
        // HDDL 2.1: `(at (start t1) gd)` / `(at (end t1) gd)`.
        if h == "at"
            && let [GSexp::List(point), body] = args
            && (point.head_is("start") || point.head_is("end"))
        {
            let ids = match point.elements().nth(1) {
                Some(GSexp::Atom(t)) => vec![self.name(&t)],
                _ => Vec::new(),
            };
            let body = self.gd(body);
            return Gd::Modal("at".into(), vec![body], ids, span);
        }
        match h.as_str() {
            "and" => Gd::And(args.iter().map(|x| self.gd(x)).collect(), span),
            "or" => Gd::Or(args.iter().map(|x| self.gd(x)).collect(), span),
            "not" => match args {
                [x] => Gd::Not(Box::new(self.gd(x)), span),
                _ => {
                    self.malformed(e, "`not` takes exactly one condition");
                    Gd::And(Vec::new(), span)
                }
            },
            "imply" => match args {
                [a, b] => Gd::Imply(Box::new(self.gd(a)), Box::new(self.gd(b)), span),
                _ => {
                    self.malformed(e, "`imply` takes two conditions");
                    Gd::And(Vec::new(), span)
                }
            },
            "forall" | "exists" => match args {
                [ps, body] => {
                    let ps = self.quantified_params(ps);
                    let body = Box::new(self.gd(body));
                    if h == "forall" { Gd::Forall(ps, body, span) } else { Gd::Exists(ps, body, span) }
                }
                _ => {
                    self.malformed(e, format!("`{h}` takes a parameter list and a condition"));
                    Gd::And(Vec::new(), span)
                }
            },
            "preference" => match args {
                [GSexp::Atom(n), body] => {
                    let n = self.name(n);
                    Gd::Preference(Some(n), Box::new(self.gd(body)), span)
                }
                [body] => Gd::Preference(None, Box::new(self.gd(body)), span),
                _ => {
                    self.malformed(e, "expected `(preference name <condition>)`");
                    Gd::And(Vec::new(), span)
                }
            },
            "sortof" if args.len() == 3 && args[1].is_atom("-") => match self.term(&args[0]) {
                Some(t) => {
                    let ty = self.type_ref(&args[2]);
                    Gd::Sortof(t, ty, span)
                }
                None => Gd::And(Vec::new(), span),
            },
            "always" | "sometime" | "at-most-once" | "sometime-after" | "sometime-before"
            | "always-within" | "within" | "hold-during" | "hold-after" | "before" | "after" | "between" => {
                self.modal(&h, args, span)
            }
            "=" if args.len() == 2
                && args.iter().all(|a| atom_kind(a).is_some_and(|k| k != SyntaxKind::Number)) =>
            {
                match (self.term(&args[0]), self.term(&args[1])) {
                    (Some(a), Some(b)) => Gd::Equal(a, b, span),
                    _ => Gd::And(Vec::new(), span),
                }
            }
            op if CmpOp::parse(op).is_some() => match args {
                [a, b] => {
                    let (a, b) = (self.num_expr(a), self.num_expr(b));
                    Gd::Compare(CmpOp::parse(op).expect("checked"), a, b, span)
                }
                _ => {
                    self.malformed(e, format!("`{op}` takes two operands"));
                    Gd::And(Vec::new(), span)
                }
            },
            _ => match self.atom(e) {
                Some(a) => Gd::Atom(a),
                None => Gd::And(Vec::new(), span),
            },
        }
    }

    fn modal(&mut self, h: &str, args: &[GSexp<'_>], span: TextRange) -> Gd {
        let mut gds = Vec::new();
        let mut ids = Vec::new();
        for a in args {
            match a {
                GSexp::Atom(t) if t.kind() == SyntaxKind::Number => {}
                GSexp::Atom(t) => ids.push(self.name(t)),
                GSexp::List(l) if (l.head_is("start") || l.head_is("end")) && l.elements().count() == 2 => {
                    if let Some(GSexp::Atom(t)) = l.elements().nth(1) {
                        ids.push(self.name(&t));
                    }
                }
                other => gds.push(self.gd(other)),
            }
        }
        Gd::Modal(h.into(), gds, ids, span)
    }

    fn effect(&mut self, e: &GSexp<'_>) -> Effect {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected an effect in parentheses");
            return Effect::And(Vec::new(), self.span(e.range()));
        };
        let span = self.span(l.range());
        let inner: Vec<GSexp<'_>> = l.elements().collect();
        if let Some(ts) = Self::timed_head(&inner) {
            return Effect::Timed(ts, Box::new(self.effect(&inner[2])), span);
        }
        let Some(head) = inner.first() else { return Effect::And(Vec::new(), span) };
        let Some(h) = head.atom_text().map(str::to_ascii_lowercase) else {
            self.malformed(head, "expected a predicate or `and`, `not`, `forall`, `when`");
            return Effect::And(Vec::new(), span);
        };
        let args = &inner[1..];
        match h.as_str() {
            "and" => Effect::And(args.iter().map(|x| self.effect(x)).collect(), span),
            "not" => match args {
                [x] => match self.atom(x) {
                    Some(a) => Effect::Del(a, span),
                    None => Effect::And(Vec::new(), span),
                },
                _ => {
                    self.malformed(e, "`not` takes exactly one atom");
                    Effect::And(Vec::new(), span)
                }
            },
            "forall" => match args {
                [ps, body] => {
                    let ps = self.quantified_params(ps);
                    Effect::Forall(ps, Box::new(self.effect(body)), span)
                }
                _ => {
                    self.malformed(e, "`forall` takes a parameter list and an effect");
                    Effect::And(Vec::new(), span)
                }
            },
            "when" => match args {
                [c, body] => {
                    let c = self.gd(c);
                    Effect::When(c, Box::new(self.effect(body)), span)
                }
                _ => {
                    self.malformed(e, "`when` takes a condition and an effect");
                    Effect::And(Vec::new(), span)
                }
            },
            "increase" | "decrease" | "assign" | "scale-up" | "scale-down" => match args {
                [target, value] => match self.fluent(target) {
                    Some(f) => {
                        let v = if value.is_atom("undefined") {
                            NumExpr::Special("undefined".into(), self.span(value.range()))
                        } else {
                            self.num_expr(value)
                        };
                        Effect::Numeric(h.as_str().into(), f, v, span)
                    }
                    None => Effect::And(Vec::new(), span),
                },
                _ => {
                    self.malformed(e, format!("`{h}` takes a function term and a value"));
                    Effect::And(Vec::new(), span)
                }
            },
            _ => match self.atom(e) {
                Some(a) => Effect::Add(a),
                None => Effect::And(Vec::new(), span),
            },
        }
    }

    fn init_element(&mut self, e: &GSexp<'_>) -> Option<InitElement> {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected an initial fact like `(p a b)`");
            return None;
        };
        let span = self.span(l.range());
        let inner: Vec<GSexp<'_>> = l.elements().collect();
        match inner.as_slice() {
            [at, GSexp::Atom(n), lit @ GSexp::List(_)]
                if at.is_atom("at") && n.kind() == SyntaxKind::Number =>
            {
                let time = Number { text: n.text().into(), span: self.span(n.text_range()) };
                let inner = self.init_element(lit)?;
                Some(InitElement::Timed(time, Box::new(inner), span))
            }
            [not, x] if not.is_atom("not") => self.atom(x).map(|a| InitElement::NotFact(a, span)),
            [eq, f @ GSexp::List(_), v] if eq.is_atom("=") => {
                let f = self.fluent(f)?;
                match v {
                    GSexp::Atom(t) if t.kind() == SyntaxKind::Symbol => {
                        Some(InitElement::AssignObject(f, self.name(t), span))
                    }
                    _ => {
                        let v = self.num_expr(v);
                        Some(InitElement::Assign(f, v, span))
                    }
                }
            }
            _ => self.atom(e).map(InitElement::Fact),
        }
    }
}
