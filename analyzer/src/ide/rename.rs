//! Rename: every occurrence of a declared name, across the domain and every
//! problem of that domain, refused where the result would not mean the same.

use rowan::{TextRange, TextSize};

use super::{NavTarget, RefKind, declaration, occurrence_at, references};
use crate::db::{Db, Item, SourceFile, Unit};

/// Why a name cannot be renamed (shown to the user as is).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenameError(pub String);

/// The name at `offset` that a rename would change, and its text: a name
/// with a declaration (not a requirement, not a built-in such as `object`).
pub fn prepare_rename(
    db: &dyn Db,
    file: SourceFile,
    offset: TextSize,
) -> Result<(TextRange, String), RenameError> {
    let (.., range) = renamable(db, file, offset)?;
    Ok((range, file.text(db)[range].to_string()))
}

/// The occurrence at `offset` if it names something a rename can change.
fn renamable(
    db: &dyn Db,
    file: SourceFile,
    offset: TextSize,
) -> Result<(Unit<'_>, Item<'_>, RefKind, String, TextRange), RenameError> {
    if crate::db::is_plan_file(db, file) {
        return Err(RenameError("rename a name in its domain or problem, not in a plan".into()));
    }
    let (unit, item, kind, key, range) =
        occurrence_at(db, file, offset).ok_or_else(|| RenameError("no name to rename here".into()))?;
    if kind == RefKind::Requirement {
        return Err(RenameError(format!("`{key}` is a requirement of PDDL: it cannot be renamed")));
    }
    if declaration(db, unit, item, kind, &key).is_none() {
        return Err(RenameError(format!("`{key}` is declared nowhere: there is nothing to rename")));
    }
    Ok((unit, item, kind, key, range))
}

/// The edits that rename the name at `offset` to `new_name`: each
/// occurrence's range, in every file of the domain and its problems.
pub fn rename(
    db: &dyn Db,
    file: SourceFile,
    offset: TextSize,
    new_name: &str,
) -> Result<Vec<NavTarget>, RenameError> {
    let (unit, item, kind, key, _) = renamable(db, file, offset)?;
    check_name(kind, new_name)?;
    let new_key = new_name.to_ascii_lowercase();
    // The same name in another case rewrites the occurrences; a domain's
    // name has one declaration whatever the name asked.
    if new_key != key
        && kind != RefKind::UnitName
        && let Some(other) = declaration(db, unit, item, kind, &new_key)
    {
        let place = if other.file == file { "" } else { " in another file" };
        return Err(RenameError(format!("`{new_name}` is already declared{place}: the two would merge")));
    }
    Ok(references(db, file, offset, true))
}

/// Whether `name` can stand where a name of `kind` does: a `?variable` for
/// variables, a plain name (a letter, then letters, digits, `-` and `_`) for
/// the others.
fn check_name(kind: RefKind, name: &str) -> Result<(), RenameError> {
    let plain = |s: &str| {
        let mut chars = s.chars();
        chars.next().is_some_and(|c| c.is_ascii_alphabetic())
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    };
    let ok = match kind {
        RefKind::Variable => name.strip_prefix('?').is_some_and(plain),
        _ => plain(name),
    };
    if ok {
        return Ok(());
    }
    Err(RenameError(match kind {
        RefKind::Variable => {
            format!("`{name}` is not a variable: `?`, a letter, then letters, digits, `-` or `_`")
        }
        _ => format!("`{name}` is not a name: a letter, then letters, digits, `-` or `_`"),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AnalysisHost;

    const DOMAIN: &str = "(define (domain d)\n  (:types block)\n  (:predicates (on ?b - block) (clear ?b - block))\n  (:action pick\n    :parameters (?b - block)\n    :precondition (clear ?b)\n    :effect (not (on ?b))))\n";
    const PROBLEM: &str = "(define (problem p) (:domain d)\n  (:objects a b - block)\n  (:init (on a) (clear b))\n  (:goal (clear a)))\n";

    fn edits(
        host: &AnalysisHost,
        file: SourceFile,
        at: &str,
        nth: usize,
        new: &str,
    ) -> Result<Vec<String>, String> {
        let text = host.analysis().file_text(file).unwrap();
        let offset = text.match_indices(at).nth(nth).expect("in the text").0 as u32;
        let out = host.analysis().rename(file, offset.into(), new).unwrap().map_err(|e| e.0)?;
        Ok(out
            .into_iter()
            .map(|n| {
                let t = host.analysis().file_text(n.file).unwrap();
                let path = host.analysis().file_path(n.file).unwrap();
                format!("{path}:{}", &t[..usize::from(n.range.start())].lines().count())
            })
            .collect())
    }

    fn host() -> (AnalysisHost, SourceFile, SourceFile) {
        let mut host = AnalysisHost::new();
        let d = host.set_file_text("domain.pddl", DOMAIN);
        let p = host.set_file_text("problem.pddl", PROBLEM);
        (host, d, p)
    }

    #[test]
    fn a_predicate_is_renamed_in_the_domain_and_its_problems() {
        let (host, d, p) = host();
        let expect = ["domain.pddl:3", "domain.pddl:7", "problem.pddl:3"];
        assert_eq!(edits(&host, d, "on ?b", 0, "above"), Ok(expect.map(String::from).to_vec()));
        // From the problem too.
        assert_eq!(edits(&host, p, "on a", 0, "above"), Ok(expect.map(String::from).to_vec()));
        // A variable stays in its item.
        assert_eq!(
            edits(&host, d, "?b", 2, "?x"),
            Ok(vec!["domain.pddl:5".into(), "domain.pddl:6".into(), "domain.pddl:7".into()])
        );
    }

    #[test]
    fn a_rename_that_would_change_the_meaning_is_refused() {
        let (host, d, p) = host();
        assert_eq!(
            edits(&host, d, "on ?b", 0, "clear").unwrap_err(),
            "`clear` is already declared: the two would merge"
        );
        assert!(edits(&host, d, "on ?b", 0, "2x").unwrap_err().contains("is not a name"));
        assert!(edits(&host, d, "?b", 2, "x").unwrap_err().contains("is not a variable"));
        assert!(edits(&host, p, "a b", 0, "b").unwrap_err().contains("already declared"));
        // Another case of the same name is fine.
        assert!(edits(&host, d, "on ?b", 0, "ON").is_ok());
        // The domain's name, in the domain and in the problem's `:domain`.
        assert_eq!(
            edits(&host, d, "d)", 0, "blocks"),
            Ok(vec!["domain.pddl:1".into(), "problem.pddl:1".into()])
        );
    }

    #[test]
    fn only_declared_names_can_be_renamed() {
        let (host, d, _) = host();
        let prepare = |at: &str| {
            let offset = DOMAIN.find(at).expect("in the text") as u32;
            host.analysis().prepare_rename(d, offset.into()).unwrap()
        };
        let clear = DOMAIN.find("clear ?b - block").unwrap() as u32;
        assert_eq!(
            prepare("clear ?b - block"),
            Ok((TextRange::new(clear.into(), (clear + 5).into()), "clear".into()))
        );
        assert!(prepare("(define").is_err());
        assert_eq!(prepare("block)\n  (:pred").unwrap().1, "block");
    }
}
