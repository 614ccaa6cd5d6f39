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

/// Splits files into groups that can each be checked in a database of their
/// own with the same diagnostics as all together: `files` are the paths and
/// unit headers ([`crate::db::scan_unit_headers`]) of a workspace's domain
/// and problem files. Returns the groups as indices into `files`, each in
/// increasing order, the groups in the order of their first file.
///
/// Files see each other only through [`resolve_domain`] and [`problems_of`].
/// A problem is put with every domain its resolution may pick: the domains of
/// the name it refers to in its own file or folder when there are some (one
/// of them is the answer, whatever else the workspace holds); otherwise the
/// domains of that name anywhere and every domain in its file or folder (the
/// candidates of a mismatch). In its group, a problem's resolution then sees
/// the same candidates that decide it, in the same order, and a domain's
/// problems are all there.
pub fn independent_groups(files: &[(&str, &[crate::db::UnitHeader])]) -> Vec<Vec<usize>> {
    use rustc_hash::FxHashMap;
    let mut parent: Vec<usize> = (0..files.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut union = |a: usize, b: usize| {
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        if ra != rb {
            parent[ra.max(rb)] = ra.min(rb);
        }
    };
    // The files holding a domain of each name, and those holding any domain, per folder.
    let mut named: FxHashMap<&str, Vec<usize>> = FxHashMap::default();
    let mut in_dir: FxHashMap<&str, Vec<usize>> = FxHashMap::default();
    for (i, (path, units)) in files.iter().enumerate() {
        for u in units.iter().filter(|u| u.kind == UnitKind::Domain) {
            if let Some(name) = &u.name {
                named.entry(name.as_str()).or_default().push(i);
            }
            let dir = in_dir.entry(dir_of(path)).or_default();
            if dir.last() != Some(&i) {
                dir.push(i);
            }
        }
    }
    for (i, (path, units)) in files.iter().enumerate() {
        let dir = dir_of(path);
        for wanted in
            units.iter().filter(|u| u.kind == UnitKind::Problem).filter_map(|u| u.domain_ref.as_deref())
        {
            let candidates = named.get(wanted).map_or(&[][..], |v| v.as_slice());
            let near: Vec<usize> =
                candidates.iter().copied().filter(|&j| j == i || dir_of(files[j].0) == dir).collect();
            if near.is_empty() {
                candidates.iter().for_each(|&j| union(i, j));
                in_dir.get(dir).into_iter().flatten().for_each(|&j| union(i, j));
            } else {
                near.into_iter().for_each(|j| union(i, j));
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut index: FxHashMap<usize, usize> = FxHashMap::default();
    for i in 0..files.len() {
        let r = root(&mut parent, i);
        let g = *index.entry(r).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push(i);
    }
    groups
}
