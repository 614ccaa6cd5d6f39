//! Every name occurrence of an item's model, with what it refers to.

use crate::model::*;

/// What a name is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RefKind {
    Type,
    Predicate,
    Function,
    /// An action or a task (subtasks, allowed actions).
    Callable,
    /// The task of a method.
    Task,
    Method,
    /// A constant or an object.
    Object,
    Variable,
    SubtaskId,
    Requirement,
    UnitName,
}

/// A name occurrence: a declaration or a use.
#[derive(Debug, Clone, Copy)]
pub struct Occurrence<'a> {
    pub kind: RefKind,
    pub name: &'a Name,
    pub decl: bool,
}

struct V<'a, F: FnMut(Occurrence<'a>)>(F, std::marker::PhantomData<&'a ()>);

impl<'a, F: FnMut(Occurrence<'a>)> V<'a, F> {
    fn put(&mut self, kind: RefKind, name: &'a Name, decl: bool) {
        (self.0)(Occurrence { kind, name, decl });
    }

    fn type_ref(&mut self, t: &'a TypeRef) {
        for n in t.names() {
            self.put(RefKind::Type, n, false);
        }
    }

    fn typed(&mut self, list: &'a [Typed], kind: RefKind) {
        for t in list {
            self.put(kind, &t.name, true);
            self.type_ref(&t.ty);
        }
    }

    fn term(&mut self, t: &'a Term) {
        match t {
            Term::Var(n) => self.put(RefKind::Variable, n, false),
            Term::Const(n) => self.put(RefKind::Object, n, false),
            Term::Func(f) => self.fluent(f),
        }
    }

    fn fluent(&mut self, f: &'a Fluent) {
        self.put(RefKind::Function, &f.func, false);
        for a in &f.args {
            self.term(a);
        }
    }

    fn atom(&mut self, a: &'a Atom) {
        self.put(RefKind::Predicate, &a.pred, false);
        for t in &a.args {
            self.term(t);
        }
    }

    fn num(&mut self, e: &'a NumExpr) {
        match e {
            NumExpr::Fluent(f) => self.fluent(f),
            NumExpr::Op(_, args, _) => args.iter().for_each(|a| self.num(a)),
            NumExpr::TaskDuration(id, _) => self.put(RefKind::SubtaskId, id, false),
            NumExpr::Var(v) => self.put(RefKind::Variable, v, false),
            NumExpr::Number(_) | NumExpr::Duration(_) | NumExpr::Special(..) => {}
        }
    }

    fn gd(&mut self, g: &'a Gd) {
        match g {
            Gd::Atom(a) => self.atom(a),
            Gd::Equal(a, b, _) => {
                self.term(a);
                self.term(b);
            }
            Gd::Compare(_, a, b, _) => {
                self.num(a);
                self.num(b);
            }
            Gd::Not(x, _) | Gd::Timed(_, x, _) | Gd::Preference(_, x, _) => self.gd(x),
            Gd::And(v, _) | Gd::Or(v, _) => v.iter().for_each(|x| self.gd(x)),
            Gd::Imply(a, b, _) => {
                self.gd(a);
                self.gd(b);
            }
            Gd::Forall(ps, body, _) | Gd::Exists(ps, body, _) => {
                self.typed(ps, RefKind::Variable);
                self.gd(body);
            }
            Gd::Modal(_, gds, ids, _) => {
                gds.iter().for_each(|x| self.gd(x));
                ids.iter().for_each(|i| self.put(RefKind::SubtaskId, i, false));
            }
            Gd::Order(o) => self.ordering(o),
            Gd::Sortof(t, ty, _) => {
                self.term(t);
                self.type_ref(ty);
            }
        }
    }

    fn effect(&mut self, e: &'a Effect) {
        match e {
            Effect::Add(a) | Effect::Del(a, _) => self.atom(a),
            Effect::And(v, _) => v.iter().for_each(|x| self.effect(x)),
            Effect::Forall(ps, body, _) => {
                self.typed(ps, RefKind::Variable);
                self.effect(body);
            }
            Effect::When(c, body, _) => {
                self.gd(c);
                self.effect(body);
            }
            Effect::Numeric(_, f, v, _) => {
                self.fluent(f);
                self.num(v);
            }
            Effect::Timed(_, x, _) => self.effect(x),
        }
    }

    fn ordering(&mut self, o: &'a Ordering) {
        self.put(RefKind::SubtaskId, &o.left.id, false);
        self.put(RefKind::SubtaskId, &o.right.id, false);
    }

    fn call(&mut self, c: &'a TaskCall, kind: RefKind) {
        self.put(kind, &c.name, false);
        c.args.iter().for_each(|a| self.term(a));
    }

    fn network(&mut self, n: &'a TaskNetwork) {
        for st in &n.subtasks {
            if let Some(id) = &st.id {
                self.put(RefKind::SubtaskId, id, true);
            }
            self.call(&st.call, RefKind::Callable);
        }
        n.ordering.iter().for_each(|o| self.ordering(o));
        if let Some(c) = &n.constraints {
            self.gd(c);
        }
        for cl in &n.causal_links {
            self.put(RefKind::SubtaskId, &cl.from, false);
            self.atom(&cl.atom);
            self.put(RefKind::SubtaskId, &cl.to, false);
        }
    }

    fn init(&mut self, e: &'a InitElement) {
        match e {
            InitElement::Fact(a) | InitElement::NotFact(a, _) => self.atom(a),
            InitElement::Assign(f, v, _) => {
                self.fluent(f);
                self.num(v);
            }
            InitElement::AssignObject(f, o, _) => {
                self.fluent(f);
                self.put(RefKind::Object, o, false);
            }
            InitElement::Timed(_, x, _) => self.init(x),
        }
    }

    fn item(&mut self, data: &'a ItemData) {
        match data {
            ItemData::Header(n) => self.put(RefKind::UnitName, n, true),
            ItemData::DomainRef(n) => self.put(RefKind::UnitName, n, false),
            ItemData::Requirements(rs) => rs.iter().for_each(|r| self.put(RefKind::Requirement, r, false)),
            ItemData::Types(ts) => self.typed(ts, RefKind::Type),
            ItemData::Constants(cs) | ItemData::Objects(cs) => self.typed(cs, RefKind::Object),
            ItemData::Predicates(sigs) | ItemData::Functions(sigs) => {
                let kind = if matches!(data, ItemData::Predicates(_)) {
                    RefKind::Predicate
                } else {
                    RefKind::Function
                };
                for s in sigs {
                    self.put(kind, &s.name, true);
                    self.typed(&s.params, RefKind::Variable);
                    if !matches!(&s.result, TypeRef::Named(n) if n.key() == "number") {
                        self.type_ref(&s.result);
                    }
                }
            }
            ItemData::Action(a) => {
                self.put(RefKind::Callable, &a.name, true);
                self.typed(&a.params, RefKind::Variable);
                a.agent.iter().for_each(|v| self.put(RefKind::Variable, v, false));
                for g in [&a.duration, &a.precondition].into_iter().flatten() {
                    self.gd(g);
                }
                if let Some(e) = &a.effect {
                    self.effect(e);
                }
            }
            ItemData::Task(t) => {
                self.put(RefKind::Callable, &t.name, true);
                self.typed(&t.params, RefKind::Variable);
                t.agent.iter().for_each(|v| self.put(RefKind::Variable, v, false));
                for g in [&t.duration, &t.precondition].into_iter().flatten() {
                    self.gd(g);
                }
                if let Some(e) = &t.effect {
                    self.effect(e);
                }
                t.conflicts.iter().flat_map(|c| &c.atoms).for_each(|a| self.atom(a));
            }
            ItemData::Method(m) => {
                self.put(RefKind::Method, &m.name, true);
                self.typed(&m.params, RefKind::Variable);
                if let Some(t) = &m.task {
                    self.call(t, RefKind::Task);
                }
                for g in [&m.precondition, &m.duration].into_iter().flatten() {
                    self.gd(g);
                }
                self.network(&m.network);
                if let Some(e) = &m.effect {
                    self.effect(e);
                }
            }
            ItemData::Derived(a, ps, body) => {
                self.put(RefKind::Predicate, &a.pred, true);
                self.typed(ps, RefKind::Variable);
                self.gd(body);
            }
            ItemData::Init(es) => es.iter().for_each(|e| self.init(e)),
            ItemData::Goal(g) | ItemData::Constraints(g) => self.gd(g),
            ItemData::Htn(h) => {
                self.typed(&h.params, RefKind::Variable);
                self.network(&h.network);
            }
            ItemData::AllowedActions(ns) => ns.iter().for_each(|n| self.put(RefKind::Callable, n, false)),
            ItemData::Metric(_, e) => self.num(e),
            ItemData::Unknown => {}
        }
    }
}

/// Calls `f` on every name occurrence of an item, in source order within each construct.
pub fn occurrences<'a>(data: &'a ItemData, f: impl FnMut(Occurrence<'a>)) {
    V(f, std::marker::PhantomData).item(data);
}
