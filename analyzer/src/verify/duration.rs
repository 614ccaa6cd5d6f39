//! Durations of ground operators, evaluated from the problem's numeric fluents
//! (`(= ?duration (/ (distance ?from ?to) (speed ?r)))` with
//! `(= (distance a b) 30.98)` in `:init`), and the lint `E0305` for those that
//! cannot be.
//!
//! A fluent that some effect changes (`(decrease (fuel ?a) …)`) has no single
//! value: a duration that reads one is not a constant of the instance, so it
//! is left unknown, without a diagnostic (its value in `:init` may even be
//! missing, to be assigned later). Only what is fixed for the whole problem is
//! held against the problem: a missing value of a fluent no effect changes, a
//! division by zero, a term that is not a number.

use rowan::TextRange;

use super::Lint;
use super::ground::{Ground, ground};
use super::lifted::{Duration, Param};
use super::state::{FuncId, InitialState, Interner, ObjId, Objects};
use crate::db::{Db, Unit};
use crate::diagnostic::codes;
use crate::model::{NumExpr, Term};
use crate::semantics::symbols::Loc;

/// A fluent's arguments, evaluated for each instance: no allocation for the usual few.
type Objs = smallvec::SmallVec<[ObjId; 4]>;

/// A term of a compiled expression.
#[derive(Debug, Clone)]
pub(crate) enum CTerm {
    Param(u32),
    Obj(ObjId),
    /// An object fluent used as a term: `(loc ?t)`.
    Fluent(FuncId, Vec<CTerm>, TextRange),
}

/// A numeric expression with names resolved against the operator's parameters
/// and the problem's objects and functions.
#[derive(Debug, Clone)]
pub(crate) enum CExpr {
    Num(f64),
    Fluent {
        func: FuncId,
        args: Vec<CTerm>,
        dynamic: bool,
        span: TextRange,
    },
    Neg(Box<CExpr>),
    /// `+ - * /` over two or more operands.
    Op(u8, Vec<CExpr>, TextRange),
    /// What cannot be a number here, and why.
    Bad(String, TextRange),
}

/// An evaluated value: known, or depending on the state (a fluent some effect changes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Val {
    Known(f64),
    Dynamic,
}

/// Why a duration cannot be evaluated for an instance, and where in the expression.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Failure<'db> {
    pub span: TextRange,
    pub why: String,
    /// The `:init` fact involved (the fluent set to 0 that a division divides by).
    pub fact: Option<Loc<'db>>,
}

pub(crate) struct Compiler<'a, 'db> {
    pub params: &'a [Param],
    pub objects: &'a Objects<'db>,
    pub funcs: &'a mut Interner,
    /// Functions some effect changes, by id.
    pub dynamic: &'a [bool],
}

impl Compiler<'_, '_> {
    pub fn duration(&mut self, d: &Duration) -> Option<CExpr> {
        match d {
            Duration::Exact(e) => Some(self.expr(e)),
            Duration::None | Duration::Bounded(_) => None,
        }
    }

    fn term(&mut self, t: &Term) -> Result<CTerm, (String, TextRange)> {
        match t {
            Term::Var(n) => match self.params.iter().position(|p| p.name == n.key) {
                Some(i) => Ok(CTerm::Param(i as u32)),
                None => Err((format!("`{}` is not a parameter", n.text), n.span)),
            },
            Term::Const(n) => match self.objects.id(&n.key) {
                Some(o) => Ok(CTerm::Obj(o)),
                None => Err((format!("`{}` is not an object of the problem", n.text), n.span)),
            },
            Term::Func(f) => {
                let func = self.funcs.intern(&f.func.key);
                let args = f.args.iter().map(|a| self.term(a)).collect::<Result<_, _>>()?;
                Ok(CTerm::Fluent(func, args, f.span))
            }
        }
    }

    fn expr(&mut self, e: &NumExpr) -> CExpr {
        match e {
            NumExpr::Number(n) => {
                let v = n.value();
                if v.is_finite() {
                    CExpr::Num(v)
                } else {
                    CExpr::Bad(format!("`{}` is not a number", n.text), n.span)
                }
            }
            NumExpr::Fluent(f) => {
                let func = self.funcs.intern(&f.func.key);
                let dynamic = self.dynamic.get(func as usize).copied().unwrap_or(false);
                match f.args.iter().map(|a| self.term(a)).collect::<Result<Vec<_>, _>>() {
                    Ok(args) => CExpr::Fluent { func, args, dynamic, span: f.span },
                    Err((why, span)) => CExpr::Bad(why, span),
                }
            }
            NumExpr::Op(op, args, span) => {
                let args: Vec<CExpr> = args.iter().map(|a| self.expr(a)).collect();
                match (&**op, args.len()) {
                    ("-", 1) => CExpr::Neg(Box::new(args.into_iter().next().unwrap_or(CExpr::Num(0.0)))),
                    ("+" | "-" | "*" | "/", n) if n >= 2 => CExpr::Op(op.as_bytes()[0], args, *span),
                    _ => CExpr::Bad(
                        format!("`{op}` with {} operands is not arithmetic hipop evaluates", args.len()),
                        *span,
                    ),
                }
            }
            NumExpr::Duration(span) => {
                CExpr::Bad("`?duration` has no value inside its own definition".into(), *span)
            }
            NumExpr::TaskDuration(_, span) => {
                CExpr::Bad("a subtask's duration has no value here".into(), *span)
            }
            NumExpr::Special(s, span) => CExpr::Bad(format!("`{s}` has no value before planning"), *span),
            NumExpr::Var(n) => CExpr::Bad(format!("`{}` is an object, not a number", n.text), n.span),
        }
    }
}

/// What expressions are evaluated against.
pub(crate) struct Env<'a, 'db> {
    pub init: &'a InitialState<'db>,
    pub objects: &'a Objects<'db>,
    pub funcs: &'a Interner,
}

impl<'db> Env<'_, 'db> {
    fn term(&self, t: &CTerm, args: &[ObjId]) -> Result<ObjId, Failure<'db>> {
        match t {
            CTerm::Param(i) => Ok(args.get(*i as usize).copied().unwrap_or(u32::MAX)),
            CTerm::Obj(o) => Ok(*o),
            CTerm::Fluent(f, fargs, span) => {
                let fargs = fargs.iter().map(|a| self.term(a, args)).collect::<Result<Objs, _>>()?;
                match self.init.object_fluent(*f, &fargs) {
                    Some((o, _)) => Ok(o),
                    None => Err(Failure {
                        span: *span,
                        why: format!("`{}` has no value in `:init`", self.show_fluent(*f, &fargs)),
                        fact: None,
                    }),
                }
            }
        }
    }

    pub fn show_fluent(&self, f: FuncId, args: &[ObjId]) -> String {
        let mut s = format!("({}", self.funcs.name(f));
        for &a in args {
            s.push(' ');
            s.push_str(self.objects.name(a));
        }
        s.push(')');
        s
    }

    /// A ground expression as text, for messages.
    fn show(&self, e: &CExpr, args: &[ObjId]) -> String {
        let name = |t: &CTerm| match self.term(t, args) {
            Ok(o) => self.objects.name(o).to_string(),
            Err(_) => "?".into(),
        };
        match e {
            CExpr::Num(v) => format!("{v}"),
            CExpr::Fluent { func, args: fargs, .. } => {
                let parts: Vec<String> = fargs.iter().map(name).collect();
                if parts.is_empty() {
                    format!("({})", self.funcs.name(*func))
                } else {
                    format!("({} {})", self.funcs.name(*func), parts.join(" "))
                }
            }
            CExpr::Neg(x) => format!("(- {})", self.show(x, args)),
            CExpr::Op(op, xs, _) => {
                let parts: Vec<String> = xs.iter().map(|x| self.show(x, args)).collect();
                format!("({} {})", *op as char, parts.join(" "))
            }
            CExpr::Bad(..) => "…".into(),
        }
    }

    pub fn eval(&self, e: &CExpr, args: &[ObjId]) -> Result<Val, Failure<'db>> {
        match e {
            CExpr::Num(v) => Ok(Val::Known(*v)),
            CExpr::Bad(why, span) => Err(Failure { span: *span, why: why.clone(), fact: None }),
            CExpr::Fluent { func, args: fargs, dynamic, span } => {
                let fargs = fargs.iter().map(|a| self.term(a, args)).collect::<Result<Objs, _>>()?;
                match (self.init.fluent(*func, &fargs), dynamic) {
                    // Its value at the start is not its value when the action runs.
                    (_, true) => Ok(Val::Dynamic),
                    (Some((v, _)), false) => Ok(Val::Known(v)),
                    (None, false) => Err(Failure {
                        span: *span,
                        why: format!("`{}` has no value in `:init`", self.show_fluent(*func, &fargs)),
                        fact: None,
                    }),
                }
            }
            CExpr::Neg(x) => Ok(match self.eval(x, args)? {
                Val::Known(v) => Val::Known(-v),
                Val::Dynamic => Val::Dynamic,
            }),
            CExpr::Op(op, xs, span) => {
                let mut acc: Option<Val> = None;
                for x in xs {
                    let v = self.eval(x, args)?;
                    acc = Some(match (acc, v) {
                        (None, v) => v,
                        (Some(_), Val::Known(d)) if *op == b'/' && d == 0.0 => {
                            let fact = match x {
                                CExpr::Fluent { func, args: fargs, .. } => fargs
                                    .iter()
                                    .map(|a| self.term(a, args))
                                    .collect::<Result<Objs, _>>()
                                    .ok()
                                    .and_then(|fa| self.init.fluent(*func, &fa))
                                    .map(|(_, loc)| loc),
                                _ => None,
                            };
                            return Err(Failure {
                                span: *span,
                                why: format!(
                                    "`{}` divides by zero (`{}` is 0)",
                                    self.show(e, args),
                                    self.show(x, args)
                                ),
                                fact,
                            });
                        }
                        (Some(Val::Dynamic), _) | (Some(_), Val::Dynamic) => Val::Dynamic,
                        (Some(Val::Known(a)), Val::Known(b)) => Val::Known(match op {
                            b'+' => a + b,
                            b'-' => a - b,
                            b'*' => a * b,
                            _ => a / b,
                        }),
                    });
                }
                match acc {
                    Some(Val::Known(v)) if !v.is_finite() => Err(Failure {
                        span: *span,
                        why: format!("`{}` is too large to be a duration", self.show(e, args)),
                        fact: None,
                    }),
                    Some(v) => Ok(v),
                    None => Ok(Val::Known(0.0)),
                }
            }
        }
    }
}

/// The durations of one operator that could not be evaluated: the first
/// instance that failed, and how many did.
#[derive(Debug, Clone, PartialEq, salsa::SalsaValue)]
pub struct DurationIssue<'db> {
    /// Where in the operator's duration: the fluent without a value, the division.
    pub loc: Loc<'db>,
    /// The operator's name.
    pub operator: String,
    /// The first instance that failed, as `(move r1 a b)`.
    pub instance: String,
    pub why: String,
    /// The `:init` fact involved, if any (a divisor set to 0).
    pub fact: Option<Loc<'db>>,
    /// How many instances failed.
    pub count: usize,
}

/// `E0305`: durations that cannot be evaluated from the problem's fluents.
pub fn duration_lints<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Vec<Lint<'db>> {
    // Grounding is only needed when some duration depends on the problem (or
    // cannot be evaluated at all): constant ones (`(= ?duration 10)`, most
    // of the IPC `time-simple` domains) are fine for every instance.
    let Some(domain) = crate::semantics::check::domain_for(db, problem) else { return Vec::new() };
    let depends = domain.items(db).iter().any(|&i| {
        super::lifted::operator(db, i).as_ref().is_some_and(
            |op| matches!(&op.duration, Duration::Exact(e) if super::state::constant(e).is_none()),
        )
    });
    if !depends {
        return Vec::new();
    }
    let g: &Ground<'db> = ground(db, problem);
    let problem_name = problem.name(db).clone().unwrap_or_default();
    g.duration_issues
        .iter()
        .map(|d| {
            let mut message =
                format!("duration of `{}` cannot be evaluated for `{}`: {}", d.operator, d.instance, d.why);
            if d.count > 1 {
                let others = d.count - 1;
                message.push_str(&format!(
                    " ({others} other instance{} of `{}` neither)",
                    if others == 1 { "" } else { "s" },
                    d.operator
                ));
            }
            let mut lint = Lint::new(codes::DURATION_NOT_EVALUABLE, d.loc, message);
            match (d.fact, g.init.keyword_loc(db)) {
                (Some(fact), _) => lint = lint.related(fact, "set to 0 here"),
                (None, Some(init)) => {
                    lint = lint.related(init, format!("the initial state of problem `{problem_name}`"))
                }
                (None, None) => {}
            }
            lint
        })
        .collect()
}
