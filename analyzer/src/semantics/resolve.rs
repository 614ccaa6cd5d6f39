//! Finding a problem's domain among the workspace's files.

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

fn dir_of(path: &str) -> &str {
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
    files.retain(|f| !crate::db::is_plan_path(f.path(db)));
    files
}

/// The problem a plan file is a plan of, among the workspace's files, in this
/// order: the problem named by a JSON plan's `problem`; a problem file in the
/// same folder whose name without extension is the longest prefix of the
/// plan's name (`instance-5.vhpop.plan` → `instance-5.pddl`, `p01.plan.json` →
/// `p01.hddl`); the only problem in the same folder.
#[salsa::tracked(returns(copy))]
pub fn plan_problem(db: &dyn Db, plan: SourceFile) -> Option<Unit<'_>> {
    let path = plan.path(db);
    let dir = dir_of(path);
    let plan_name = &path[dir.len()..].trim_start_matches(['/', '\\']).to_ascii_lowercase();
    let named = crate::plan::parse_plan(db, plan)
        .problem
        .as_ref()
        .and_then(|p| p.problem.as_ref())
        .map(|s| s.text.to_ascii_lowercase().to_string());
    let mut by_name = None;
    let mut by_prefix: Option<(usize, Unit<'_>)> = None;
    let mut beside = Vec::new();
    for f in workspace_files(db, plan) {
        if f == plan {
            continue;
        }
        let f_path = f.path(db);
        let same_dir = dir_of(f_path) == dir;
        let stem = f_path[dir_of(f_path).len()..].trim_start_matches(['/', '\\']).to_ascii_lowercase();
        let stem = stem.rsplit_once('.').map_or(stem.as_str(), |(s, _)| s).to_string();
        for &unit in file_units(db, f) {
            if unit.kind(db) != UnitKind::Problem {
                continue;
            }
            let unit_name = unit.name(db).as_deref().map(str::to_ascii_lowercase);
            if named.is_some() && unit_name == named && by_name.is_none() {
                by_name = Some(unit);
            }
            if same_dir {
                beside.push(unit);
                let prefix = plan_name.strip_prefix(stem.as_str());
                if !stem.is_empty()
                    && prefix.is_some_and(|rest| rest.starts_with('.'))
                    && by_prefix.is_none_or(|(len, _)| stem.len() > len)
                {
                    by_prefix = Some((stem.len(), unit));
                }
            }
        }
    }
    by_name.or(by_prefix.map(|(_, u)| u)).or(if beside.len() == 1 { Some(beside[0]) } else { None })
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
