//! Finding a problem's domain among the workspace's files (and a plan's
//! problem: `plan::problem`).

use crate::db::{Db, SourceFile, Unit, UnitKind, Workspace, file_units};

/// Where a problem's domain is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, salsa::SalsaValue)]
pub enum Resolution<'db> {
    Found(Unit<'db>),
    /// The only domain beside the problem (same file or folder), named otherwise:
    /// used for checking, with a warning.
    Mismatch(Unit<'db>),
    Missing,
    /// The problem has no `(:domain …)`.
    NoReference,
}

impl<'db> Resolution<'db> {
    /// The domain to check the problem against, if any.
    pub fn domain(self) -> Option<Unit<'db>> {
        match self {
            Resolution::Found(u) | Resolution::Mismatch(u) => Some(u),
            Resolution::Missing | Resolution::NoReference => None,
        }
    }
}

/// The folder of a path (`""` for a bare name).
pub fn dir_of(path: &str) -> &str {
    path.rfind(['/', '\\']).map_or("", |i| &path[..i])
}

fn common_prefix(a: &str, b: &str) -> usize {
    a.bytes().zip(b.bytes()).take_while(|(x, y)| x == y).count()
}

/// The domain and problem files of the workspace (plans are not), or just
/// `file` when there is no workspace.
pub fn workspace_files(db: &dyn Db, file: SourceFile) -> Vec<SourceFile> {
    let mut files = match Workspace::try_get(db) {
        Some(ws) => ws.files(db).clone(),
        None => Vec::new(),
    };
    if !files.contains(&file) {
        files.push(file);
    }
    files.retain(|&f| !crate::db::is_plan_file(db, f));
    files
}

/// The domain a problem unit refers to, in this order: the domain of that name
/// in the same file; the one of that name in the same folder; the only domain
/// in the same file or folder whatever its name (a mismatch: real files have
/// it); the one of that name with the closest path.
#[salsa::tracked(returns(copy))]
pub fn resolve_domain<'db>(db: &'db dyn Db, problem: Unit<'db>) -> Resolution<'db> {
    let file = problem.file(db);
    let Some(wanted) = problem.domain_ref(db).clone() else { return Resolution::NoReference };
    let path = file.path(db);
    let dir = dir_of(path);
    let mut named: Option<((u8, usize, usize), Unit<'db>)> = None;
    let mut beside: Vec<Unit<'db>> = Vec::new();
    for f in workspace_files(db, file) {
        let rank = if f == file {
            2
        } else if dir_of(f.path(db)) == dir {
            1
        } else {
            0
        };
        for &unit in file_units(db, f) {
            if unit.kind(db) != UnitKind::Domain {
                continue;
            }
            if rank > 0 {
                beside.push(unit);
            }
            if unit.name(db).as_deref() == Some(wanted.as_str()) {
                // Folders like Monroe's pair `pfile01-…-domain.hddl` with `pfile01-….hddl`.
                let score = (rank, common_prefix(dir_of(f.path(db)), dir), common_prefix(f.path(db), path));
                if named.is_none_or(|(s, _)| score > s) {
                    named = Some((score, unit));
                }
            }
        }
    }
    match named {
        Some(((rank, ..), unit)) if rank > 0 => Resolution::Found(unit),
        _ if beside.len() == 1 => Resolution::Mismatch(beside[0]),
        Some((_, unit)) => Resolution::Found(unit),
        None => Resolution::Missing,
    }
}

/// The problem units of the workspace whose domain is `domain`.
#[salsa::tracked(returns(ref))]
pub fn problems_of<'db>(db: &'db dyn Db, domain: Unit<'db>) -> Vec<Unit<'db>> {
    let file = domain.file(db);
    let mut out = Vec::new();
    for f in workspace_files(db, file) {
        for &unit in file_units(db, f) {
            if unit.kind(db) == UnitKind::Problem && resolve_domain(db, unit).domain() == Some(domain) {
                out.push(unit);
            }
        }
    }
    out
}
