//! Which problem a plan file of the workspace is a plan of.

use crate::db::{Db, SourceFile, Unit, UnitKind, file_units};
use crate::semantics::resolve::{dir_of, workspace_files};

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
    let named = super::parse_plan(db, plan)
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
