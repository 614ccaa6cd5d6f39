//! Model verification: the checks a HiPOP mission must pass before the planner
//! can be trusted with it (sections 4.2 and 4.3 of the HiPOP paper).
//!
//! - [`lifted`]: the STRIPS view of actions, tasks and methods the checks share.
//! - [`geometry`]: candidate position families and the triangle inequality of
//!   move durations, as pure functions.
//! - [`conflicts`]: conflicts of abstract actions (E0301, W0302) and tasks
//!   without methods (E0303, W0304).
//! - [`state`], [`ground`], [`reach`]: the ground problem (objects, atoms, the
//!   initial state, the instances of actions, tasks and methods) and relaxed
//!   reachability, the base of the problem lints.
//!   `instantiate.rs` is the engine behind [`ground`].
//! - [`duration`]: durations evaluated from the problem's fluents (`E0305`).
//! - [`families`]: position families and move actions confirmed on the ground
//!   problem (Definitions 12 and 14: I0307, I0308, W0309, W0310).
//! - `allowed`: lints of `(:allowed-actions …)` (section 4.2.2: W0311, W0312)
//!   and of what the allowed set and the methods can achieve (E0313: goals and
//!   `:htn` tasks out of reach).
//! - `decompose`: the relaxed decomposition over ground methods that E0313
//!   uses, and methods whose subtasks have no instance in a problem (W0314).
//!
//! Lints are found in two salsa queries: [`domain_lints`] (what a domain alone
//! shows) and [`problem_lints`] (what needs a problem and its domain; they may
//! point into the domain file, where the language server shows them once a
//! problem of that domain is open). Both return [`Lint`]s located by item
//! ([`Loc`]), so that typing elsewhere in a file does not re-run them; the
//! cheap conversion to absolute [`Diagnostic`]s happens last.
//!
//! Problem lints run only when the problem and its domain have no errors (the
//! model they reason on would not be the one the user wrote), and not on
//! PDDL+ domains.

mod allowed;
pub mod conflicts;
mod decompose;
pub mod duration;
pub mod families;
pub mod geometry;
pub mod ground;
mod instantiate;
pub mod lifted;
pub mod reach;
mod relevance;
pub mod state;
mod tdg;

use crate::db::{Db, Unit, UnitKind};
use crate::diagnostic::{Code, Diagnostic, Fix, Related, Severity};
use crate::semantics::symbols::Loc;

/// A lint result, located in items.
#[derive(Debug, Clone, PartialEq, Eq, Hash, salsa::SalsaValue)]
pub struct Lint<'db> {
    pub code: &'static Code,
    pub loc: Loc<'db>,
    pub message: String,
    pub related: Vec<(Loc<'db>, String)>,
    pub fix: Option<LintFix<'db>>,
}

/// Replacements of spans of items.
#[derive(Debug, Clone, PartialEq, Eq, Hash, salsa::SalsaValue)]
pub struct LintFix<'db> {
    pub message: String,
    pub edits: Vec<(Loc<'db>, String)>,
}

impl<'db> Lint<'db> {
    pub fn new(code: &'static Code, loc: Loc<'db>, message: impl Into<String>) -> Self {
        Lint { code, loc, message: message.into(), related: Vec::new(), fix: None }
    }

    pub fn related(mut self, loc: Loc<'db>, message: impl Into<String>) -> Self {
        self.related.push((loc, message.into()));
        self
    }

    /// The diagnostic in absolute ranges.
    pub fn to_diagnostic(&self, db: &'db dyn Db) -> Diagnostic {
        let abs = |loc: Loc<'db>| (loc.item.file(db), loc.span + loc.item.offset(db));
        let (file, range) = abs(self.loc);
        Diagnostic {
            code: self.code,
            severity: self.code.severity,
            file,
            range,
            message: self.message.clone(),
            related: self
                .related
                .iter()
                .map(|(loc, message)| {
                    let (file, range) = abs(*loc);
                    Related { file, range, message: message.clone() }
                })
                .collect(),
            fix: self.fix.as_ref().map(|f| Fix {
                message: f.message.clone(),
                edits: f
                    .edits
                    .iter()
                    .map(|(loc, text)| {
                        let (file, range) = abs(*loc);
                        (file, range, text.clone())
                    })
                    .collect(),
            }),
        }
    }
}

/// The lints of a domain alone.
#[salsa::tracked(returns(ref))]
pub fn domain_lints<'db>(db: &'db dyn Db, unit: Unit<'db>) -> Vec<Lint<'db>> {
    let mut out = Vec::new();
    if unit.kind(db) != UnitKind::Domain {
        return out;
    }
    conflicts::conflict_lints(db, unit, &mut out);
    conflicts::method_less_tasks(db, unit, &mut out);
    out
}

/// The lints of a problem with its domain (some located in the domain).
#[salsa::tracked(returns(ref))]
pub fn problem_lints<'db>(db: &'db dyn Db, unit: Unit<'db>) -> Vec<Lint<'db>> {
    let mut out = Vec::new();
    if unit.kind(db) != UnitKind::Problem || !model_is_clean(db, unit) || is_pddl_plus(db, unit) {
        return out;
    }
    out.extend(duration::duration_lints(db, unit));
    let Some(domain) = crate::semantics::check::domain_for(db, unit) else { return out };
    let fams = families::families(db, unit);
    out.extend(fams.lints.iter().cloned());
    out.extend(families::rejected_lints(fams));
    allowed::lints(db, unit, domain, &|name| fams.is_move(name, db), &mut out);
    out.extend(decompose::decomposition_lints(db, unit).iter().cloned());
    out
}

/// Whether a problem's domain is PDDL+ (W0207): hipop does not reason on
/// processes and events, so the problem lints would be wrong.
fn is_pddl_plus(db: &dyn Db, problem: Unit<'_>) -> bool {
    crate::semantics::check::domain_for(db, problem).is_some_and(|d| {
        crate::semantics::unit_diagnostics(db, d)
            .iter()
            .any(|d| d.code == crate::diagnostic::codes::UNSUPPORTED)
    })
}

/// Whether a problem and its domain are free of errors.
pub(crate) fn model_is_clean(db: &dyn Db, problem: Unit<'_>) -> bool {
    let Some(domain) = crate::semantics::check::domain_for(db, problem) else { return false };
    let clean =
        |u: Unit<'_>| crate::semantics::unit_diagnostics(db, u).iter().all(|d| d.severity != Severity::Error);
    clean(domain) && clean(problem)
}
