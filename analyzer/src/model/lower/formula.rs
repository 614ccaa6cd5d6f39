//! Lowering formulas: goal descriptions, effects, numeric expressions, terms.

use rowan::TextRange;

use super::network::is_ordering_shape;
use super::{Cx, GSexp, SyntaxKind, elements, glued_type};
use crate::model::*;
use crate::syntax::looks_like_a_number;

impl Cx {
    pub(super) fn term(&mut self, e: &GSexp<'_>) -> Option<Term> {
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

    pub(super) fn atom(&mut self, e: &GSexp<'_>) -> Option<Atom> {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected an atom like `(p ?x)`");
            return None;
        };
        let inner = elements(l);
        self.atom_of(e, &inner)
    }

    /// An atom from the elements of its list `e`, already collected.
    pub(super) fn atom_of(&mut self, e: &GSexp<'_>, inner: &[GSexp<'_>]) -> Option<Atom> {
        let pred = self.applied_name(e, inner, "expected an atom like `(p ?x)`")?;
        Some(Atom { pred, args: self.terms(&inner[1..]), span: e.range() })
    }

    /// The name that `(name term…)` (an atom, a function term, a task call)
    /// applies, from the elements of its list `e`.
    pub(super) fn applied_name(&mut self, e: &GSexp<'_>, inner: &[GSexp<'_>], what: &str) -> Option<Name> {
        match inner.first() {
            Some(GSexp::Atom(t)) if t.kind() == SyntaxKind::Symbol => Some(self.name(t)),
            _ => {
                self.malformed(e, what);
                None
            }
        }
    }

    /// The terms an application applies its name to.
    #[inline]
    pub(super) fn terms(&mut self, elems: &[GSexp<'_>]) -> Args {
        let mut args = Args::new();
        args.reserve_exact(elems.len());
        for e in elems {
            if let Some(t) = self.term(e) {
                args.push(t);
            }
        }
        args
    }

    pub(super) fn fluent(&mut self, e: &GSexp<'_>) -> Option<Fluent> {
        match e {
            GSexp::List(l) => {
                let inner = elements(l);
                let func = self.applied_name(e, &inner, "expected a function term like `(f ?x)`")?;
                Some(Fluent { func, args: self.terms(&inner[1..]), span: e.range() })
            }
            GSexp::Atom(t) if t.kind() == SyntaxKind::Symbol => {
                Some(Fluent { func: self.name(t), args: Args::new(), span: t.text_range() })
            }
            other => {
                self.malformed(other, "expected a function term like `(f ?x)`");
                None
            }
        }
    }

    pub(super) fn num_expr(&mut self, e: &GSexp<'_>) -> NumExpr {
        match e {
            GSexp::Atom(t) => match t.kind() {
                SyntaxKind::Number => NumExpr::Number(Number { text: t.text().into(), span: t.text_range() }),
                SyntaxKind::Variable if t.text().eq_ignore_ascii_case("?duration") => {
                    NumExpr::Duration(t.text_range())
                }
                SyntaxKind::Variable => NumExpr::Var(self.name(t)),
                _ if looks_like_a_number(t.text()) => {
                    self.not_a_number(e);
                    NumExpr::Special("error".into(), t.text_range())
                }
                _ if t.text() == "#t" || t.text().eq_ignore_ascii_case("total-time") => {
                    NumExpr::Special(t.text().to_ascii_lowercase().into(), t.text_range())
                }
                _ => NumExpr::Fluent(Box::new(Fluent {
                    func: self.name(t),
                    args: Args::new(),
                    span: t.text_range(),
                })),
            },
            GSexp::List(l) => {
                let inner = elements(l);
                let span = l.range();
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
                        Some(f) => NumExpr::Fluent(Box::new(f)),
                        None => NumExpr::Special("error".into(), span),
                    },
                }
            }
        }
    }

    /// `E0003` on an atom that starts like a number but is not one PDDL has.
    pub(super) fn not_a_number(&mut self, e: &GSexp<'_>) {
        let text = e.atom_text().unwrap_or_default();
        self.malformed(
            e,
            format!(
                "expected a number: `{text}` is not one (PDDL numbers are digits with an optional decimal \
                 part, like `12` or `0.5`: no exponent, no `+`)"
            ),
        );
    }

    pub(super) fn timed_head(inner: &[GSexp<'_>]) -> Option<TimeSpec> {
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

    pub(super) fn quantified_params(&mut self, e: &GSexp<'_>) -> Vec<Typed> {
        self.params(e)
    }

    pub(super) fn gd(&mut self, e: &GSexp<'_>) -> Gd {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected a condition in parentheses");
            return Gd::And(Vec::new(), e.range());
        };
        let span = l.range();
        let inner = elements(l);
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
            return Gd::Modal("at".into(), vec![body], ids.into(), span);
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
            "sortof" if args.len() == 2 && glued_type(&args[1]).is_some() => match self.term(&args[0]) {
                Some(t) => Gd::Sortof(t, TypeRef::Named(glued_type(&args[1]).expect("checked")), span),
                None => Gd::And(Vec::new(), span),
            },
            "always" | "sometime" | "at-most-once" | "sometime-after" | "sometime-before"
            | "always-within" | "within" | "hold-during" | "hold-after" | "before" | "after" | "between" => {
                self.modal(&h, args, span)
            }
            // `=` between two names or variables compares objects; with a
            // number, `?duration` or what starts like a number, it compares numbers.
            "=" if args.len() == 2
                && args.iter().all(|a| {
                    a.as_atom().is_some_and(|t| {
                        t.kind() != SyntaxKind::Number
                            && !looks_like_a_number(t.text())
                            && !t.text().eq_ignore_ascii_case("?duration")
                    })
                }) =>
            {
                match (self.term(&args[0]), self.term(&args[1])) {
                    (Some(a), Some(b)) => Gd::Equal(a, b, span),
                    _ => Gd::And(Vec::new(), span),
                }
            }
            op if CmpOp::parse(op).is_some() => match args {
                [a, b] => {
                    let (a, b) = (self.num_expr(a), self.num_expr(b));
                    Gd::Compare(CmpOp::parse(op).expect("checked"), Box::new(a), Box::new(b), span)
                }
                _ => {
                    self.malformed(e, format!("`{op}` takes two operands"));
                    Gd::And(Vec::new(), span)
                }
            },
            _ => match self.atom_of(e, &inner) {
                Some(a) => Gd::Atom(a),
                None => Gd::And(Vec::new(), span),
            },
        }
    }

    pub(super) fn modal(&mut self, h: &str, args: &[GSexp<'_>], span: TextRange) -> Gd {
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
        Gd::Modal(h.into(), gds, ids.into(), span)
    }

    pub(super) fn effect(&mut self, e: &GSexp<'_>) -> Effect {
        let GSexp::List(l) = e else {
            self.malformed(e, "expected an effect in parentheses");
            return Effect::And(Vec::new(), e.range());
        };
        let span = l.range();
        let inner = elements(l);
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
                    Effect::When(Box::new(c), Box::new(self.effect(body)), span)
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
                            NumExpr::Special("undefined".into(), value.range())
                        } else {
                            self.num_expr(value)
                        };
                        Effect::Numeric(h.as_str().into(), Box::new(f), v, span)
                    }
                    None => Effect::And(Vec::new(), span),
                },
                _ => {
                    self.malformed(e, format!("`{h}` takes a function term and a value"));
                    Effect::And(Vec::new(), span)
                }
            },
            _ => match self.atom_of(e, &inner) {
                Some(a) => Effect::Add(a),
                None => Effect::And(Vec::new(), span),
            },
        }
    }
}
