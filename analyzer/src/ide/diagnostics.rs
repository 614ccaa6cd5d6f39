//! A file's diagnostics, assembled from every layer: the syntax and semantic
//! checks (`semantics`), the model-verification lints (`verify`) and, for a
//! plan file, its validation against its problem (`validate`). What the
//! shells publish.

use crate::db::{Db, SourceFile, Unit, UnitKind, file_units, is_plan_file};
use crate::diagnostic::Diagnostic;
use crate::semantics::{self, resolve::problems_of};

/// The fast diagnostics of a file, sorted by position: a domain's or a
/// problem's syntax and semantic checks (per item, incremental, a few
/// milliseconds), or a plan file's reading and validation. Without the
/// model-verification lints, which may ground a problem (see
/// [`file_diagnostics`]): the server publishes these first.
#[salsa::tracked(returns(ref))]
pub fn file_check_diagnostics(db: &dyn Db, file: SourceFile) -> Vec<Diagnostic> {
    if is_plan_file(db, file) {
        let out = crate::validate::plan_file_diagnostics(db, file).clone();
        return semantics::finish(db, file, out);
    }
    semantics::file_checks(db, file)
}

/// Every diagnostic of a file, sorted by position: the checks and the
/// model-verification lints.
#[salsa::tracked(returns(ref))]
pub fn file_diagnostics(db: &dyn Db, file: SourceFile) -> Vec<Diagnostic> {
    let mut out = file_check_diagnostics(db, file).clone();
    for &unit in file_units(db, file) {
        // A domain's own lints, and those its problems (open or in the
        // workspace) find in it; a problem's lints.
        let lints = crate::verify::domain_lints(db, unit).iter();
        let problems: &[Unit<'_>] = match unit.kind(db) {
            UnitKind::Domain => problems_of(db, unit),
            UnitKind::Problem => std::slice::from_ref(&unit),
            UnitKind::Unknown => &[],
        };
        let lints = lints.chain(problems.iter().flat_map(|&p| crate::verify::problem_lints(db, p)));
        out.extend(lints.map(|l| l.to_diagnostic(db)).filter(|d| d.file == file));
    }
    semantics::finish(db, file, out)
}
