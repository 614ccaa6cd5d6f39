//! Code actions beyond the diagnostics' own fixes: declaring a predicate
//! that is used but declared nowhere, with the arity and types of its use,
//! in the domain's `:predicates` or in a new one.

use rowan::TextRange;

use super::{RefKind, declaration, occurrences};
use crate::db::{Db, Item, Section, SourceFile, file_units, lower_item, parse};
use crate::model::{ItemData, TypeRef, Typed};
use crate::semantics::check::domain_for;
use crate::semantics::new_section_after;
use crate::syntax::{NodeOrToken, SyntaxKind};

/// An edit the user may choose: a title and the text to insert or replace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CodeAction {
    pub title: String,
    pub edits: Vec<(SourceFile, TextRange, String)>,
}

/// The actions for the names in `range` of `file`: for each predicate used
/// there and declared nowhere, its declaration added at the end of the
/// domain's `:predicates`, or in a new `(:predicates …)` after the
/// `:requirements`, `:types` and `:constants` (PDDL's order), with one
/// parameter per argument of the use: a variable keeps its name and the
/// type its action, task or method gives it; another argument becomes
/// `?x1`, `?x2`… untyped.
pub fn code_actions(db: &dyn Db, file: SourceFile, range: TextRange) -> Vec<CodeAction> {
    let mut out: Vec<CodeAction> = Vec::new();
    // The predicates offered already, by key.
    let mut offered: rustc_hash::FxHashSet<String> = rustc_hash::FxHashSet::default();
    let root = parse(db, file).syntax();
    for &unit in file_units(db, file) {
        let Some(domain) = domain_for(db, unit) else { continue };
        let predicates = domain
            .items(db)
            .iter()
            .copied()
            .find(|&i| matches!(lower_item(db, i).data, ItemData::Predicates(_)));
        // Without `:predicates`, one is made after the sections PDDL puts
        // before it (or after the domain's name).
        let new_section = || {
            let items = domain.items(db);
            let before = |s| {
                matches!(s, Section::Header | Section::Requirements | Section::Types | Section::Constants)
            };
            let after = items.iter().rposition(|i| before(i.section(db)))?;
            Some(new_section_after(db, domain, after))
        };
        for &item in unit.items(db) {
            let data = &lower_item(db, item).data;
            let mut uses = Vec::new();
            occurrences(data, |o| {
                let at = o.name.span + item.offset(db);
                if o.kind == RefKind::Predicate && !o.decl && at.intersect(range).is_some() {
                    uses.push((o.name.key().to_string(), o.name.text().to_string(), at));
                }
            });
            for (key, text, at) in uses {
                if offered.contains(&key) || declaration(db, unit, item, RefKind::Predicate, &key).is_some() {
                    continue;
                }
                let Some(args) = arguments(&root, at) else { continue };
                let params = parameters(data, &args);
                let decl = if params.is_empty() { format!("({text})") } else { format!("({text} {params})") };
                let (title, edit) = match predicates {
                    Some(p) => (
                        format!("declare `{decl}` in `:predicates`"),
                        (p.file(db), end_of(db, p), format!(" {decl}")),
                    ),
                    None => {
                        let Some((file, at, separator)) = new_section() else { continue };
                        let edit = (file, at, format!("{separator}(:predicates {decl})"));
                        (format!("declare `{decl}` in a new `:predicates`"), edit)
                    }
                };
                offered.insert(key);
                out.push(CodeAction { title, edits: vec![edit] });
            }
        }
    }
    out
}

/// The arguments of the atom whose name is at `at`: the texts of the
/// elements after its head.
fn arguments(root: &crate::syntax::SyntaxNode, at: TextRange) -> Option<Vec<String>> {
    let token = root.token_at_offset(at.start()).right_biased()?;
    let list = token.parent()?;
    if list.kind() != SyntaxKind::List {
        return None;
    }
    let elements: Vec<String> = list
        .children_with_tokens()
        .filter(|e| !e.kind().is_trivia() && !matches!(e.kind(), SyntaxKind::LParen | SyntaxKind::RParen))
        .map(|e| match e {
            NodeOrToken::Node(n) => n.text().to_string(),
            NodeOrToken::Token(t) => t.text().to_string(),
        })
        .collect();
    Some(elements.into_iter().skip(1).collect())
}

/// The parameters of a declaration for a use with `args`, typed from the
/// parameters of the item that uses it.
fn parameters(data: &ItemData, args: &[String]) -> String {
    let declared: &[Typed] = match data {
        ItemData::Action(a) => &a.params,
        ItemData::Task(t) => &t.params,
        ItemData::Method(m) => &m.params,
        _ => &[],
    };
    let mut out: Vec<String> = Vec::new();
    for (i, arg) in args.iter().enumerate() {
        if !arg.starts_with('?') {
            out.push(format!("?x{}", i + 1));
            continue;
        }
        let ty = declared.iter().find(|p| p.name.key().eq_ignore_ascii_case(arg)).map(|p| &p.ty);
        out.push(match ty {
            Some(TypeRef::Named(t)) => format!("{arg} - {}", t.text()),
            Some(TypeRef::Either(ts)) => {
                format!(
                    "{arg} - (either {})",
                    ts.iter().map(|t| t.text().to_string()).collect::<Vec<_>>().join(" ")
                )
            }
            _ => arg.clone(),
        });
    }
    out.join(" ")
}

/// Just before the `)` that closes an item (its end, if it has none).
fn end_of(db: &dyn Db, item: Item<'_>) -> TextRange {
    let start = item.offset(db);
    let file_text = item.file(db).text(db);
    let text = &file_text[TextRange::at(start, item.len(db))];
    let at = match text.trim_end().strip_suffix(')') {
        Some(inner) => inner.len(),
        None => text.len(),
    };
    TextRange::empty(start + rowan::TextSize::from(at as u32))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AnalysisHost;

    fn host_with(text: &str) -> (AnalysisHost, SourceFile) {
        let mut host = AnalysisHost::new();
        let f = host.set_file_text("other.pddl", text);
        (host, f)
    }

    #[test]
    fn an_undeclared_predicate_is_declared_with_the_types_of_its_use() {
        let domain = "(define (domain d)\n  (:requirements :typing)\n  (:types block)\n  (:predicates (on ?b - block))\n  (:action pick\n    :parameters (?b - block ?h - hand)\n    :precondition (and (on ?b) (holding ?h ?b) (near b1))\n    :effect (not (on ?b))))\n";
        let mut host = AnalysisHost::new();
        let d = host.set_file_text("domain.pddl", domain);
        let whole = TextRange::up_to((domain.len() as u32).into());
        let actions = host.analysis().code_actions(d, whole).unwrap();
        let titles: Vec<&str> = actions.iter().map(|a| a.title.as_str()).collect();
        assert_eq!(
            titles,
            [
                "declare `(holding ?h - hand ?b - block)` in `:predicates`",
                "declare `(near ?x1)` in `:predicates`"
            ]
        );
        // Applied, the first declares it where the others are.
        let (_, at, insert) = &actions[0].edits[0];
        let mut fixed = domain.to_string();
        fixed.insert_str(usize::from(at.start()), insert);
        assert!(fixed.contains("(:predicates (on ?b - block) (holding ?h - hand ?b - block))"), "{fixed}");
        // One action per predicate, whatever names begin like it.
        let both =
            "(define (domain d) (:predicates (p))\n  (:action a :precondition (and (onto) (on) (onto))))\n";
        let b = host_with(both);
        let titles: Vec<String> =
            b.0.analysis()
                .code_actions(b.1, TextRange::up_to((both.len() as u32).into()))
                .unwrap()
                .into_iter()
                .map(|a| a.title)
                .collect();
        assert_eq!(titles, ["declare `(onto)` in `:predicates`", "declare `(on)` in `:predicates`"]);
        // Nothing for a declared predicate, nor outside the range.
        let on = domain.find("(on ?b) (holding").unwrap() as u32 + 1;
        assert_eq!(host.analysis().code_actions(d, TextRange::at(on.into(), 2.into())).unwrap(), vec![]);
    }

    #[test]
    fn without_predicates_a_section_is_made_after_types_and_constants() {
        let domain = "(define (domain d)\n  (:requirements :typing)\n  (:types t)\n  (:constants c - t)\n  (:action \
                      a :parameters (?x - t)\n    :effect (ready ?x)))\n";
        let (host, d) = host_with(domain);
        let actions =
            host.analysis().code_actions(d, TextRange::up_to((domain.len() as u32).into())).unwrap();
        assert_eq!(actions.len(), 1);
        assert_eq!(actions[0].title, "declare `(ready ?x - t)` in a new `:predicates`");
        let (_, at, insert) = &actions[0].edits[0];
        let fixed = crate::fix::apply_edits(domain, &[(*at, insert.as_str())]).unwrap();
        assert!(fixed.contains("(:constants c - t)\n  (:predicates (ready ?x - t))\n  (:action"), "{fixed}");
        // With no section before it, after the domain's name.
        let bare = "(define (domain d) (:action a :effect (p)))";
        let (host, d) = host_with(bare);
        let actions = host.analysis().code_actions(d, TextRange::up_to((bare.len() as u32).into())).unwrap();
        let (_, at, insert) = &actions[0].edits[0];
        let fixed = crate::fix::apply_edits(bare, &[(*at, insert.as_str())]).unwrap();
        assert_eq!(fixed, "(define (domain d) (:predicates (p)) (:action a :effect (p)))");
    }
}
