//! Where the cursor is: the lists around it, what each is from where it
//! sits (a section, a goal, an effect, subtasks, a typed list…), and the
//! variables in scope there. Read from the lossless tree, which keeps a
//! shape in half-typed text.

use crate::semantics::symbols::TypeSet;
use crate::syntax::{NodeOrToken, SyntaxElement, SyntaxKind, SyntaxNode};
use rowan::TextSize;

/// What a list is, from where it sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Role {
    Define,
    /// A section or item of a `define`.
    Section,
    /// A list where a field keyword of an item was expected: the item is
    /// not closed and a new section begins.
    NewSection,
    /// A goal description; `durative`: timed (`at start`…) are allowed.
    Gd {
        durative: bool,
    },
    Effect {
        durative: bool,
    },
    /// An atom only (under a `not` of an effect).
    Atom,
    Init,
    /// A numeric expression.
    Num,
    /// The fluent assigned by a numeric effect.
    Fluent,
    /// A duration constraint.
    Duration,
    /// A method's or network's subtasks (`and` or one subtask).
    Subtasks,
    /// A subtask: `(id (call))` or `(call)`.
    Subtask,
    /// A call of a task or action (`tasks_only`: the `:task` of a method).
    Call {
        tasks_only: bool,
    },
    /// The terms of an atom: a function term.
    Term,
    /// A typed list of parameters or variables.
    Typed,
    /// A declaration in `:predicates` or `:functions`.
    Decl,
    /// `(either …)`.
    Either,
    Other,
}

/// A list around the cursor.
pub(super) struct Frame {
    pub(super) node: SyntaxNode,
    /// The significant elements of the list (groups seen through).
    pub(super) elems: Vec<SyntaxElement>,
    /// How many of them are before the word being typed.
    pub(super) before: usize,
    pub(super) role: Role,
}

impl Frame {
    pub(super) fn atom(&self, i: usize) -> Option<String> {
        match self.elems.get(i)? {
            NodeOrToken::Token(t) if t.kind().is_atom() => Some(t.text().to_ascii_lowercase()),
            _ => None,
        }
    }

    pub(super) fn head(&self) -> Option<String> {
        self.atom(0)
    }

    /// The element just before the word being typed.
    pub(super) fn previous(&self) -> Option<String> {
        self.before.checked_sub(1).and_then(|i| self.atom(i))
    }

    /// The index in the list of a child list.
    pub(super) fn index_of(&self, child: &SyntaxNode) -> usize {
        self.elems.iter().position(|e| e.as_node() == Some(child)).unwrap_or(self.elems.len())
    }
}

/// The significant elements of a list: atoms and lists, through groups.
pub(super) fn elements(list: &SyntaxNode) -> Vec<SyntaxElement> {
    pub(super) fn walk(node: &SyntaxNode, out: &mut Vec<SyntaxElement>) {
        for child in node.children_with_tokens() {
            match child.kind() {
                SyntaxKind::Group => {
                    if let NodeOrToken::Node(g) = &child {
                        walk(g, out);
                    }
                }
                SyntaxKind::Error | SyntaxKind::LParen | SyntaxKind::RParen => {}
                k if k.is_trivia() => {}
                _ => out.push(child),
            }
        }
    }
    let mut out = Vec::new();
    walk(list, &mut out);
    out
}

/// Whether `at` is inside `list`: after its `(` and not after its `)`.
pub(super) fn inside(list: &SyntaxNode, at: TextSize) -> bool {
    let range = list.text_range();
    if at <= range.start() {
        return false;
    }
    match list.last_token() {
        Some(t) if t.kind() == SyntaxKind::RParen => {
            // Its own `)`, not that of a nested list left open.
            let owner = t.parent_ancestors().find(|n| n.kind() != SyntaxKind::Group);
            if owner.as_ref() == Some(list) { at <= t.text_range().start() } else { at <= range.end() }
        }
        _ => at <= range.end(),
    }
}

/// The role of a list from its parent's.
pub(super) fn child_role(parent: &Frame, items: &[Frame], index: usize) -> Role {
    let head = parent.head().unwrap_or_default();
    let durative = items.iter().any(|f| {
        f.role == Role::Section
            && matches!(f.head().as_deref(), Some(":durative-action" | ":durative-method" | ":task"))
    });
    let prev = index.checked_sub(1).and_then(|i| parent.atom(i));
    match parent.role {
        Role::Define => Role::Section,
        Role::Section => match head.as_str() {
            ":goal" | ":constraints" => Role::Gd { durative: false },
            ":init" => Role::Init,
            ":metric" => Role::Num,
            ":predicates" | ":functions" => Role::Decl,
            ":derived" if index == 2 => Role::Gd { durative: false },
            ":derived" => Role::Decl,
            ":types" | ":constants" | ":objects" => Role::Either,
            h if is_item(h) => match prev.as_deref() {
                Some(":parameters") => Role::Typed,
                Some(":precondition") => Role::Gd { durative: false },
                Some(":condition") => Role::Gd { durative },
                Some(":effect") => Role::Effect { durative },
                Some(":duration") => Role::Duration,
                Some(":task") => Role::Call { tasks_only: true },
                Some(":subtasks" | ":tasks" | ":ordered-subtasks" | ":ordered-tasks") => Role::Subtasks,
                Some(":constraints") => Role::Gd { durative: false },
                Some(k) if k.starts_with(':') => Role::Other,
                _ if index >= 2 => Role::NewSection,
                _ => Role::Other,
            },
            _ => Role::Other,
        },
        Role::Gd { durative } => match head.as_str() {
            "and" | "or" | "not" | "imply" | "preference" => Role::Gd { durative },
            "forall" | "exists" if index == 1 => Role::Typed,
            "forall" | "exists" => Role::Gd { durative },
            "at" | "over"
                if durative && matches!(parent.atom(1).as_deref(), Some("start" | "end" | "all")) =>
            {
                Role::Gd { durative: false }
            }
            "<" | "<=" | ">" | ">=" => Role::Num,
            "=" => Role::Term,
            h if is_modal(h) => Role::Gd { durative },
            _ => Role::Term,
        },
        Role::Effect { durative } => match head.as_str() {
            "and" => Role::Effect { durative },
            "not" => Role::Atom,
            "forall" if index == 1 => Role::Typed,
            "forall" => Role::Effect { durative },
            "when" if index == 1 => Role::Gd { durative },
            "when" => Role::Effect { durative },
            "at" if durative && matches!(parent.atom(1).as_deref(), Some("start" | "end")) => {
                Role::Effect { durative: false }
            }
            h if is_numeric_effect(h) && index == 1 => Role::Fluent,
            h if is_numeric_effect(h) => Role::Num,
            _ => Role::Term,
        },
        Role::Init => match head.as_str() {
            "not" => Role::Atom,
            "=" if index == 1 => Role::Fluent,
            "=" => Role::Num,
            "at" if parent.elems.get(1).is_some_and(|e| e.kind() == SyntaxKind::Number) => Role::Init,
            _ => Role::Term,
        },
        Role::Duration => match head.as_str() {
            "and" => Role::Duration,
            "at" => Role::Duration,
            _ => Role::Num,
        },
        Role::Num | Role::Fluent => Role::Num,
        Role::Subtasks => match head.as_str() {
            "and" => Role::Subtask,
            _ if index == 1 => Role::Call { tasks_only: false },
            _ => Role::Term,
        },
        Role::Subtask => Role::Call { tasks_only: false },
        Role::Call { .. } | Role::Term | Role::Atom => Role::Term,
        Role::Typed | Role::Decl | Role::Either => Role::Either,
        Role::NewSection | Role::Other => Role::Other,
    }
}

pub(super) fn is_item(head: &str) -> bool {
    crate::syntax::ITEM_HEADS.contains(&head)
}

pub(super) fn is_modal(head: &str) -> bool {
    matches!(
        head,
        "always"
            | "sometime"
            | "at-most-once"
            | "sometime-after"
            | "sometime-before"
            | "always-within"
            | "within"
            | "hold-during"
            | "hold-after"
    )
}

pub(super) fn is_numeric_effect(head: &str) -> bool {
    matches!(head, "increase" | "decrease" | "assign" | "scale-up" | "scale-down")
}

/// The lists around `at`, outermost first, with their roles.
pub(super) fn frames(root: &SyntaxNode, at: TextSize) -> Vec<Frame> {
    let mut out: Vec<Frame> = Vec::new();
    let mut node = root.clone();
    loop {
        let elems = elements(&node);
        let Some(child) = elems
            .iter()
            .filter_map(|e| e.as_node())
            .find(|n| n.kind() == SyntaxKind::List && inside(n, at))
            .cloned()
        else {
            break;
        };
        let role = match out.last() {
            None => {
                if elements(&child)
                    .first()
                    .is_some_and(|h| h.as_token().is_some_and(|t| t.text() == "define"))
                {
                    Role::Define
                } else {
                    Role::Other
                }
            }
            Some(parent) => child_role(parent, &out, parent.index_of(&child)),
        };
        let child_elems = elements(&child);
        let before = child_elems.iter().take_while(|e| e.text_range().end() <= at).count();
        out.push(Frame { node: child.clone(), elems: child_elems, before, role });
        node = child;
    }
    out
}

pub(super) fn is_connective(head: &str) -> bool {
    matches!(head, "and" | "or" | "not" | "imply" | "forall" | "exists" | "when" | "over" | "preference")
        || is_modal(head)
        || is_numeric_effect(head)
}

/// The variables in scope at the cursor: the parameters of the item and the
/// variables of the `forall` and `exists` around it, innermost last, with
/// their types (lower-cased).
pub(super) fn variables(frames: &[Frame]) -> Vec<(String, TypeSet)> {
    let mut out: Vec<(String, TypeSet)> = Vec::new();
    for (depth, f) in frames.iter().enumerate() {
        let head = f.head().unwrap_or_default();
        let lists: Vec<&SyntaxNode> = if f.role == Role::Section && is_item(&head) {
            (1..f.elems.len())
                .filter(|&i| f.atom(i).as_deref() == Some(":parameters"))
                .filter_map(|i| f.elems.get(i + 1).and_then(|e| e.as_node()))
                .collect()
        } else if matches!(head.as_str(), "forall" | "exists")
            && frames.get(depth + 1).is_some_and(|inner| f.index_of(&inner.node) >= 2)
        {
            f.elems.get(1).and_then(|e| e.as_node()).into_iter().collect()
        } else {
            Vec::new()
        };
        for l in lists {
            for (name, ty) in typed_list(l) {
                out.retain(|(n, _)| *n != name);
                out.push((name, ty));
            }
        }
    }
    out
}

/// The variables of a typed list and their types.
pub(super) fn typed_list(list: &SyntaxNode) -> Vec<(String, TypeSet)> {
    let elems = elements(list);
    let mut out: Vec<(String, TypeSet)> = Vec::new();
    let mut pending: Vec<String> = Vec::new();
    let mut i = 0;
    while i < elems.len() {
        match &elems[i] {
            NodeOrToken::Token(t) if t.text() == "-" => {
                let ty: TypeSet = match elems.get(i + 1) {
                    Some(NodeOrToken::Token(t)) => vec![t.text().to_ascii_lowercase().into()],
                    Some(NodeOrToken::Node(n)) => elements(n)
                        .iter()
                        .skip(1)
                        .filter_map(|e| e.as_token().map(|t| t.text().to_ascii_lowercase().into()))
                        .collect(),
                    None => vec!["object".into()],
                };
                out.extend(pending.drain(..).map(|n| (n, ty.clone())));
                i += 2;
                continue;
            }
            NodeOrToken::Token(t) if t.kind() == SyntaxKind::Variable => pending.push(t.text().to_string()),
            _ => {}
        }
        i += 1;
    }
    out.extend(pending.into_iter().map(|n| (n, vec!["object".into()])));
    out
}
