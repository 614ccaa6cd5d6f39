//! Lowering task networks: subtasks, orderings (prefix, infix and timed),
//! causal links, and calls of tasks.

use super::{Cx, Elems, GSexp, SyntaxKind, elements};
use crate::model::*;

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
pub(super) fn is_ordering_shape(inner: &[GSexp<'_>]) -> bool {
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

impl Cx {
    pub(super) fn network_field(&mut self, net: &mut TaskNetwork, key: &str, value: &GSexp<'_>) {
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

    pub(super) fn task_call(&mut self, e: &GSexp<'_>) -> Option<TaskCall> {
        match e {
            GSexp::List(l) => {
                let inner = elements(l);
                let name = self.applied_name(e, &inner, "expected a task like `(name ?x …)`")?;
                Some(TaskCall { name, args: self.terms(&inner[1..]), span: e.range() })
            }
            other => {
                self.malformed(other, "expected a task like `(name ?x …)`");
                None
            }
        }
    }

    pub(super) fn subtasks(&mut self, e: &GSexp<'_>) -> Vec<Subtask> {
        let items = conjuncts(e);
        items.iter().filter_map(|x| self.subtask(x)).collect()
    }

    pub(super) fn subtask(&mut self, e: &GSexp<'_>) -> Option<Subtask> {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected a subtask like `(t1 (name ?x …))`");
            return None;
        };
        let inner = elements(l);
        match inner.as_slice() {
            [GSexp::Atom(id), call @ GSexp::List(_)] if id.kind() == SyntaxKind::Symbol => {
                let id = self.name(id);
                self.task_call(call).map(|call| Subtask { id: Some(id), call })
            }
            _ => self.task_call(e).map(|call| Subtask { id: None, call }),
        }
    }

    pub(super) fn causal_links(&mut self, e: &GSexp<'_>) -> Vec<CausalLink> {
        let items = conjuncts(e);
        let mut out = Vec::new();
        for x in &items {
            let inner: Elems<'_> = x.as_list().map(elements).unwrap_or_default();
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

    pub(super) fn orderings(&mut self, e: &GSexp<'_>) -> Vec<Ordering> {
        let items = conjuncts(e);
        items.iter().filter_map(|x| self.ordering(x)).collect()
    }

    pub(super) fn order_point(&mut self, e: &GSexp<'_>) -> Option<OrderPoint> {
        match e {
            GSexp::Atom(t) if t.kind() == SyntaxKind::Symbol || t.kind() == SyntaxKind::Number => {
                Some(OrderPoint { id: self.name(t), endpoint: Endpoint::Whole })
            }
            GSexp::List(l) => {
                let inner = elements(l);
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

    pub(super) fn ordering(&mut self, e: &GSexp<'_>) -> Option<Ordering> {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected an ordering like `(< t1 t2)`");
            return None;
        };
        let inner = elements(l);
        if let [not, inner_e] = inner.as_slice()
            && not.is_atom("not")
        {
            return self.ordering(inner_e).map(|mut o| {
                o.negated = !o.negated;
                o.span = l.range();
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
        Some(Ordering { op, negated: false, left, right, span: l.range() })
    }
}
