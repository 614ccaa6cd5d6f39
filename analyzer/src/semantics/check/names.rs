//! Checks of names: what a term, atom or call refers to, arities and types.

use std::borrow::Cow;

use rowan::TextRange;

use super::{Checker, Feature, describe, term_text};
use crate::diagnostic::{Code, codes};
use crate::model::*;
use crate::semantics::symbols::{DeclKind, SigDecl, problem_symbols};

/// The Levenshtein distance between `a` and `b` if it is at most `limit`.
///
/// Computed on bytes (names are ASCII in practice; a multi-byte character
/// counts as several edits, which only makes suggestions more cautious),
/// with an early exit as soon as every cell of a row exceeds `limit`: a big
/// problem has thousands of objects to compare a typo with.
fn distance_within(a: &str, b: &str, limit: usize) -> Option<usize> {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len().abs_diff(b.len()) > limit {
        return None;
    }
    // Two rows, on the stack for the short names that most are.
    let mut rows = smallvec::SmallVec::<[usize; 96]>::from_elem(0, 2 * (b.len() + 1));
    let (prev, cur) = rows.split_at_mut(b.len() + 1);
    let (mut prev, mut cur) = (prev, cur);
    for (j, p) in prev.iter_mut().enumerate() {
        *p = j;
    }
    for (i, &ca) in a.iter().enumerate() {
        cur[0] = i + 1;
        let mut row_min = cur[0];
        for (j, &cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
            row_min = row_min.min(cur[j + 1]);
        }
        if row_min > limit {
            return None;
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    Some(prev[b.len()]).filter(|d| *d <= limit)
}

/// The closest of `candidates` to `name`, if close enough to be a typo.
pub fn suggest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (name.len() / 3).clamp(1, 3);
    let mut scored: Vec<(usize, &str)> = candidates
        .filter(|c| *c != name)
        .filter_map(|c| Some((distance_within(name, c, limit)?, c)))
        .collect();
    scored.sort_unstable();
    scored.dedup();
    match scored.as_slice() {
        // Two equally close names: a guess would be a coin toss.
        [(d1, _), (d2, _), ..] if d1 == d2 => None,
        [(_, c), ..] => Some(c),
        [] => None,
    }
}

/// Whether a constant is a number, which has no type to check.
fn is_number(c: &Name) -> bool {
    matches!(c.key().as_bytes().first(), Some(b'0'..=b'9' | b'-' | b'+' | b'.'))
        && c.key().parse::<f64>().is_ok()
}

impl<'a, 'db> Checker<'a, 'db> {
    pub(super) fn undefined(&mut self, code: &'static Code, what: &str, name: &Name, candidates: Vec<&str>) {
        let suggestion = suggest(name.key(), candidates.into_iter()).map(str::to_string);
        let d = self.diag(code, name.span, format!("undefined {what} `{}`", name.text()));
        if let Some(s) = suggestion {
            d.message.push_str(&format!(" (did you mean `{s}`?)"));
            d.fix = Some((format!("replace with `{s}`"), name.span, s));
        }
    }

    pub(super) fn call_args(&mut self, call: &TaskCall, decl: &SigDecl<'db>, _what: &str) {
        self.args(&call.name, &call.args, call.span, decl, false);
    }

    /// Checks arity and argument types against a declaration.
    pub(super) fn args(
        &mut self,
        name: &Name,
        args: &[Term],
        span: TextRange,
        decl: &SigDecl<'db>,
        wildcards: bool,
    ) {
        if args.len() != decl.params.len() {
            for a in args {
                self.term(a, wildcards);
            }
            return self.arity_mismatch(name, args.len(), span, decl);
        }
        for (arg, param) in args.iter().zip(&decl.params) {
            // The arguments of facts are objects: their path skips `term` and its `Cow`.
            if let Term::Const(c) = arg
                && let Some(ty) = self.object_type(c)
            {
                if !self.dom.fits(ty, param) {
                    self.type_mismatch(name, arg, ty, param, decl);
                }
                continue;
            }
            let Some(ty) = self.term(arg, wildcards) else { continue };
            // A variable of a supertype narrows to the parameter's type (HDDL's
            // "sortof" semantics); an object must fit.
            let ok = match arg {
                Term::Var(_) => self.dom.compatible(&ty, param),
                _ => self.dom.fits(&ty, param),
            };
            if !ok {
                self.type_mismatch(name, arg, &ty, param, decl);
            }
        }
    }

    fn decl_kind(decl: &SigDecl<'db>) -> &'static str {
        match decl.kind {
            DeclKind::Predicate | DeclKind::Derived => "predicate",
            DeclKind::Function => "function",
            DeclKind::Action(_) => "action",
            DeclKind::Task => "task",
        }
    }

    // The reports are out of line: `args` runs for every argument of every
    // fact, and is cheaper without their formatting code around it.
    #[cold]
    fn arity_mismatch(&mut self, name: &Name, given: usize, span: TextRange, decl: &SigDecl<'db>) {
        let expected = decl.params.len();
        let msg = format!(
            "{} `{}` takes {} argument{}, but {} {} given",
            Self::decl_kind(decl),
            name.text(),
            expected,
            if expected == 1 { "" } else { "s" },
            given,
            if given == 1 { "is" } else { "are" }
        );
        self.diag(codes::ARITY, span, msg).related.push((decl.loc, "declared here".into()));
    }

    #[cold]
    fn type_mismatch(&mut self, name: &Name, arg: &Term, ty: &[Str], param: &[Str], decl: &SigDecl<'db>) {
        let msg = format!(
            "`{}` has type {}, but {} `{}` expects {} here",
            term_text(arg),
            describe(ty),
            Self::decl_kind(decl),
            name.text(),
            describe(param)
        );
        self.diag(codes::TYPE_MISMATCH, arg.span(), msg).related.push((decl.loc, "declared here".into()));
    }

    /// The type of a term, reporting what is undefined.
    pub(super) fn term(&mut self, t: &Term, wildcards: bool) -> Option<Cow<'a, [Str]>> {
        match t {
            Term::Const(c) => match self.object_type(c) {
                Some(ty) => Some(Cow::Borrowed(ty)),
                None if is_number(c) => None,
                None => self.constant(c),
            },
            Term::Var(v) => self.variable(v, wildcards),
            Term::Func(f) => self.fluent(f),
        }
    }

    /// The type of the problem object `c` names, if it names one. In a
    /// problem, objects are what most terms name: they are looked up first
    /// (an object named like a domain constant takes its place).
    fn object_type(&self, c: &Name) -> Option<&'a [Str]> {
        if is_number(c) {
            return None;
        }
        self.prob.and_then(|p| p.objects.get(c.key())).map(|d| &d.ty[..])
    }

    fn variable(&mut self, v: &Name, wildcards: bool) -> Option<Cow<'a, [Str]>> {
        if let Some((_, ty)) = self.scope.iter().rev().find(|(n, _)| *n == v.key()) {
            return Some(Cow::Owned(ty.clone()));
        }
        if v.key() == "?duration" && self.durative {
            return None;
        }
        if !wildcards {
            let cands: Vec<String> = self.scope.iter().map(|(n, _)| n.to_string()).collect();
            let suggestion = suggest(v.key(), cands.iter().map(String::as_str)).map(str::to_string);
            let d = self.diag(
                codes::UNDEFINED_VARIABLE,
                v.span,
                format!("variable `{}` is not bound by a parameter or quantifier", v.text()),
            );
            if let Some(s) = suggestion {
                d.message.push_str(&format!(" (did you mean `{s}`?)"));
                d.fix = Some((format!("replace with `{s}`"), v.span, s));
            }
        }
        None
    }

    /// The type of a constant that is not an object of the problem: a domain
    /// constant, or undefined.
    fn constant(&mut self, c: &Name) -> Option<Cow<'a, [Str]>> {
        let dom = self.dom;
        if let Some(d) = dom.constants.get(c.key()) {
            // Only domain constants can be unused declarations.
            if !self.out.uses.constants.contains(c.key()) {
                self.out.uses.constants.insert(c.key_str());
            }
            return Some(Cow::Borrowed(&d.ty));
        }
        if self.prob.is_none() && self.known_domain {
            // pandaPIparser accepts a domain constant that its problems declare as an object.
            let problems = crate::semantics::resolve::problems_of(self.db, self.unit);
            let declaring = problems
                .iter()
                .find_map(|&p| problem_symbols(self.db, p).objects.get(c.key()).map(|o| (p, o.clone())));
            if let Some((p, obj)) = declaring {
                let pname = p.name(self.db).clone().unwrap_or_default();
                let msg = format!(
                    "constant `{}` is not declared in the domain, only as an object of problem `{pname}`",
                    c.text()
                );
                self.diag(codes::CONSTANT_FROM_PROBLEM, c.span, msg)
                    .related
                    .push((obj.loc, "declared here".into()));
                return Some(Cow::Owned(obj.ty));
            }
            if problems.is_empty() {
                let msg = format!(
                    "constant `{}` is not declared in the domain: its problems must declare it as an object",
                    c.text()
                );
                self.diag(codes::CONSTANT_FROM_PROBLEM, c.span, msg);
                return None;
            }
        }
        if self.known_domain {
            let mut cands: Vec<&str> = self.dom.constants.keys().map(|k| &**k).collect();
            if let Some(p) = self.prob {
                cands.extend(p.objects.keys().map(|k| &**k));
            }
            let what = if self.prob.is_some() { "object" } else { "constant" };
            self.undefined(codes::UNDEFINED_OBJECT, what, c, cands);
        }
        None
    }

    pub(super) fn fluent(&mut self, f: &Fluent) -> Option<Cow<'a, [Str]>> {
        if let Some((key, decl)) = &self.last_function
            && *key == f.func.key()
        {
            let decl = *decl;
            self.args(&f.func, &f.args, f.span, decl, false);
            return decl.result.as_deref().map(Cow::Borrowed);
        }
        if !self.out.uses.functions.contains(f.func.key()) {
            self.out.uses.functions.insert(f.func.key_str());
        }
        let dom = self.dom;
        let found = dom.functions.get(f.func.key());
        if let Some(decl) = found {
            self.last_function = Some((f.func.key_str(), decl));
        }
        match found {
            Some(decl) => {
                self.args(&f.func, &f.args, f.span, decl, false);
                decl.result.as_deref().map(Cow::Borrowed)
            }
            None => {
                for a in &f.args {
                    self.term(a, false);
                }
                if self.known_domain {
                    let cands = self.dom.functions.keys().map(|k| &**k).collect();
                    self.undefined(codes::UNDEFINED_FUNCTION, "function", &f.func, cands);
                }
                None
            }
        }
    }

    pub(super) fn atom(&mut self, a: &Atom, wildcards: bool) {
        if let Some((key, decl)) = &self.last_predicate
            && *key == a.pred.key()
        {
            let decl = *decl;
            return self.args(&a.pred, &a.args, a.span, decl, wildcards);
        }
        if !self.out.uses.predicates.contains(a.pred.key()) {
            self.out.uses.predicates.insert(a.pred.key_str());
        }
        let dom = self.dom;
        let found = dom.predicates.get(a.pred.key());
        if let Some(decl) = found {
            self.last_predicate = Some((a.pred.key_str(), decl));
        }
        match found {
            Some(decl) => self.args(&a.pred, &a.args, a.span, decl, wildcards),
            None => {
                for t in &a.args {
                    self.term(t, wildcards);
                }
                if self.known_domain {
                    let cands = self.dom.predicates.keys().map(|k| &**k).collect();
                    self.undefined(codes::UNDEFINED_PREDICATE, "predicate", &a.pred, cands);
                }
            }
        }
    }

    pub(super) fn num_expr(&mut self, e: &NumExpr) {
        match e {
            NumExpr::Number(_) => {}
            NumExpr::Fluent(f) => {
                self.feature(Feature::NumericFluents, f.span);
                self.fluent(f);
            }
            NumExpr::Op(_, args, _) => {
                for a in args {
                    self.num_expr(a);
                }
            }
            NumExpr::Duration(span) => {
                if !self.durative {
                    self.diag(
                        codes::UNDEFINED_VARIABLE,
                        *span,
                        "`?duration` is only defined in durative actions and timed tasks".into(),
                    );
                }
            }
            NumExpr::TaskDuration(id, _) => self.subtask_id(id),
            NumExpr::Special(..) => {}
            NumExpr::Var(v) => {
                self.term(&Term::Var(v.clone()), false);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_are_bounded() {
        assert_eq!(distance_within("kitten", "sitting", 3), Some(3));
        assert_eq!(distance_within("kitten", "sitting", 2), None);
        assert_eq!(distance_within("at-r", "at-r", 0), Some(0));
        assert_eq!(distance_within("wpa_1_2", "wpa_1_3", 1), Some(1));
        assert_eq!(distance_within("a", "abcde", 3), None);
    }

    #[test]
    fn suggestions_need_one_clear_winner() {
        assert_eq!(suggest("movr", ["move", "look"].into_iter()), Some("move"));
        assert_eq!(suggest("t3", ["t1", "t2"].into_iter()), None);
        assert_eq!(suggest("zzzzzz", ["move"].into_iter()), None);
    }
}
