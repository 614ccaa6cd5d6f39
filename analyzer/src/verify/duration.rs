//! Durations of ground operators, evaluated from the problem's numeric fluents
//! (`(= ?duration (/ (distance ?from ?to) (speed ?r)))` with
//! `(= (distance a b) 30.98)` in `:init`), and the lints for those that
//! cannot be.
//!
//! A fluent that some effect changes (`(decrease (fuel ?a) …)`) has no single
//! value: a duration that reads one is not a constant of the instance, so it
//! is left unknown, without a diagnostic (its value in `:init` may even be
//! missing, to be assigned later). Only what is fixed for the whole problem is
//! held against the problem.
//!
//! In PDDL 2.1 an instance whose duration is undefined (it reads a fluent
//! without value) is simply not applicable: problems give `turn-time` only
//! between the directions that matter. That is a note (`I0306`). A duration
//! that is negative or not a finite number (a division by zero) for some
//! instances is a warning (`W0315`). Only an action none of whose instances
//! has a duration is an error (`E0305`): it can never be in a plan.

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

impl CExpr {
    /// Where the expression is written, when it says.
    fn span(&self) -> Option<TextRange> {
        match self {
            CExpr::Num(_) => None,
            CExpr::Fluent { span, .. } | CExpr::Op(_, _, span) | CExpr::Bad(_, span) => Some(*span),
            CExpr::Neg(x) => x.span(),
        }
    }
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
    /// The duration reads a fluent without value: it is undefined, and the
    /// instance not applicable. Otherwise it is invalid (negative, a
    /// division by zero, not a number).
    pub undefined: bool,
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
            Term::Var(n) => match self.params.iter().position(|p| p.name == n.key()) {
                Some(i) => Ok(CTerm::Param(i as u32)),
                None => Err((format!("`{}` is not a parameter", n.text()), n.span)),
            },
            Term::Const(n) => match self.objects.id(n.key()) {
                Some(o) => Ok(CTerm::Obj(o)),
                None => Err((format!("`{}` is not an object of the problem", n.text()), n.span)),
            },
            Term::Func(f) => {
                let func = self.funcs.intern(f.func.key());
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
                let func = self.funcs.intern(f.func.key());
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
            NumExpr::Var(n) => CExpr::Bad(format!("`{}` is an object, not a number", n.text()), n.span),
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
                        undefined: true,
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

    /// The duration `e` gives an instance: an error when it is undefined,
    /// negative or not a finite number. `at`: where to report a failure the
    /// expression has no span for (a constant).
    pub fn duration(&self, e: &CExpr, args: &[ObjId], at: TextRange) -> Result<Val, Failure<'db>> {
        match self.eval(e, args)? {
            Val::Known(v) if v < 0.0 || !v.is_finite() => Err(Failure {
                span: e.span().unwrap_or(at),
                why: format!("`{}` is {v}: a duration cannot be negative", self.show(e, args)),
                fact: None,
                undefined: false,
            }),
            v => Ok(v),
        }
    }

    pub fn eval(&self, e: &CExpr, args: &[ObjId]) -> Result<Val, Failure<'db>> {
        match e {
            CExpr::Num(v) => Ok(Val::Known(*v)),
            CExpr::Bad(why, span) => {
                Err(Failure { span: *span, why: why.clone(), fact: None, undefined: false })
            }
            CExpr::Fluent { func, args: fargs, dynamic, span } => {
                let fargs = fargs.iter().map(|a| self.term(a, args)).collect::<Result<Objs, _>>()?;
                match (self.init.fluent_value(*func, &fargs), dynamic) {
                    // Its value at the start is not its value when the action runs.
                    (_, true) => Ok(Val::Dynamic),
                    (Some(v), false) => Ok(Val::Known(v)),
                    (None, false) => Err(Failure {
                        span: *span,
                        why: format!("`{}` has no value in `:init`", self.show_fluent(*func, &fargs)),
                        fact: None,
                        undefined: true,
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
                                undefined: false,
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
                        undefined: false,
                    }),
                    Some(v) => Ok(v),
                    None => Ok(Val::Known(0.0)),
                }
            }
        }
    }
}

/// What is wrong with the durations of one operator in a problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum IssueKind {
    /// No instance has a duration (`E0305`).
    NoInstance,
    /// Some instances have an undefined duration (`I0306`).
    Undefined,
    /// Some instances have a negative or non-finite duration (`W0315`).
    Invalid,
}

/// The durations of one operator that could not be evaluated: the first
/// instance that failed, and how many did.
#[derive(Debug, Clone, PartialEq, salsa::SalsaValue)]
pub struct DurationIssue<'db> {
    pub kind: IssueKind,
    /// Where in the operator's duration: the fluent without a value, the division.
    pub loc: Loc<'db>,
    /// The operator's name.
    pub operator: String,
    /// The first instance that failed, as `(move r1 a b)`.
    pub instance: String,
    pub why: String,
    /// The `:init` fact involved, if any (a divisor set to 0).
    pub fact: Option<Loc<'db>>,
    /// How many instances failed this way.
    pub count: usize,
    /// How many instances the operator has.
    pub total: usize,
}

/// The instances of one operator whose duration failed, by kind of failure:
/// gathered while grounding, turned into [`DurationIssue`]s at the end.
#[derive(Debug, Default)]
pub(crate) struct Tally<'db> {
    undefined: Option<DurationIssue<'db>>,
    invalid: Option<DurationIssue<'db>>,
    total: usize,
}

impl<'db> Tally<'db> {
    /// Counts an instance; `failed` when its duration failed, with a way to
    /// build the issue of the first failure.
    pub fn instance(&mut self, failed: Option<(Failure<'db>, &dyn Fn(Failure<'db>) -> DurationIssue<'db>)>) {
        self.total += 1;
        let Some((f, issue)) = failed else { return };
        let slot = if f.undefined { &mut self.undefined } else { &mut self.invalid };
        match slot {
            Some(i) => i.count += 1,
            None => *slot = Some(issue(f)),
        }
    }

    /// The issues: one `NoInstance` when no instance has a duration (on the
    /// first invalid one, which says more than a missing value), otherwise
    /// one per kind of failure.
    pub fn issues(self) -> Vec<DurationIssue<'db>> {
        let total = self.total;
        let failed =
            self.undefined.as_ref().map_or(0, |i| i.count) + self.invalid.as_ref().map_or(0, |i| i.count);
        let with_total = |mut i: DurationIssue<'db>, kind| {
            i.kind = kind;
            i.total = total;
            i
        };
        if failed > 0 && failed == total {
            let mut first = self.invalid.or(self.undefined).expect("some instance failed");
            first.count = failed;
            return vec![with_total(first, IssueKind::NoInstance)];
        }
        let undefined = self.undefined.map(|i| with_total(i, IssueKind::Undefined));
        let invalid = self.invalid.map(|i| with_total(i, IssueKind::Invalid));
        undefined.into_iter().chain(invalid).collect()
    }
}

/// `E0305`, `I0306`, `W0315`: durations that cannot be evaluated from the
/// problem's fluents, or that are negative.
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
    let init = g.init.keyword_loc(db);
    g.duration_issues
        .iter()
        .map(|d| {
            let (n, total, op) = (d.count, d.total, &d.operator);
            let (code, message) = match d.kind {
                IssueKind::NoInstance => (
                    codes::DURATION_NOT_EVALUABLE,
                    format!(
                        "no instance of `{op}` has a duration in problem `{problem_name}`, so it can never be \
                         applied: for `{}`, {}{}",
                        d.instance,
                        d.why,
                        others(n, "neither")
                    ),
                ),
                IssueKind::Undefined => (
                    codes::DURATION_UNDEFINED,
                    format!(
                        "{n} of the {total} instances of `{op}` {} no duration in problem `{problem_name}` and \
                         {} not applicable (PDDL 2.1): for `{}`, {}",
                        if n == 1 { "has" } else { "have" },
                        if n == 1 { "is" } else { "are" },
                        d.instance,
                        d.why
                    ),
                ),
                IssueKind::Invalid => (
                    codes::INVALID_DURATION_VALUE,
                    format!(
                        "the duration of `{op}` is invalid for {n} of its {total} instances in problem \
                         `{problem_name}`, which {} not applicable: for `{}`, {}",
                        if n == 1 { "is" } else { "are" },
                        d.instance,
                        d.why
                    ),
                ),
            };
            // A note concerns the problem: on its `:init`, so that a domain
            // with many problems is not flooded; the others on the duration.
            let (here, there) = match (d.kind, init) {
                (IssueKind::Undefined, Some(init)) => (init, Some((d.loc, format!("the duration of `{op}`")))),
                (_, Some(init)) if d.fact.is_none() => {
                    (d.loc, Some((init, format!("the initial state of problem `{problem_name}`"))))
                }
                _ => (d.loc, None),
            };
            let mut lint = Lint::new(code, here, message);
            if let Some(fact) = d.fact {
                lint = lint.related(fact, "set to 0 here");
            }
            if let Some((loc, message)) = there {
                lint = lint.related(loc, message);
            }
            lint
        })
        .collect()
}

/// ` (3 other instances of it neither)`, or nothing for one.
fn others(count: usize, neither: &str) -> String {
    match count.saturating_sub(1) {
        0 => String::new(),
        1 => format!(" (1 other instance {neither})"),
        n => format!(" ({n} other instances {neither})"),
    }
}
