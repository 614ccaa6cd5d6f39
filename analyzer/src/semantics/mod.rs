//! Semantic analysis: symbol tables, domain resolution, per-item checks and
//! the unit-level checks that need a whole domain or problem.

pub mod check;
pub mod resolve;
mod suppress;
pub mod symbols;

use crate::model::Str;
use rowan::TextRange;
use rustc_hash::FxHashSet;

use crate::db::{
    Db, Item, Section, SourceFile, Unit, UnitKind, file_level_diagnostics, file_units, lower_item,
};
use crate::diagnostic::{Code, Diagnostic, Fix, LocalDiag, Related, codes};
use crate::model::{ActionKind, ItemData};
use check::{Feature, ItemDiag, check_item};
use resolve::{Resolution, problems_of, resolve_domain};
use symbols::{Loc, domain_symbols, problem_symbols};

/// The diagnostics of a domain or problem file's syntax and semantic checks,
/// sorted by position: fast (per item, incremental), without the
/// model-verification lints, which may ground a problem. Plan files, and the
/// lints, are added by the layers above (`ide::diagnostics`, which
/// memoises the result).
pub fn file_checks(db: &dyn Db, file: SourceFile) -> Vec<Diagnostic> {
    let mut out = file_level_diagnostics(db, file).clone();
    for &unit in file_units(db, file) {
        out.extend(unit_diagnostics(db, unit).iter().cloned());
    }
    finish(db, file, out)
}

/// Sorted, without duplicates, without what `; hipop-allow` comments silence.
pub fn finish(db: &dyn Db, file: SourceFile, mut out: Vec<Diagnostic>) -> Vec<Diagnostic> {
    out.sort_by_key(|d| (d.range.start(), d.range.end(), d.code.id));
    out.dedup();
    suppress::apply(file.text(db), &mut out);
    out
}

fn absolute(db: &dyn Db, loc: Loc<'_>) -> (SourceFile, TextRange) {
    (loc.item.file(db), loc.span + loc.item.offset(db))
}

/// A lowering diagnostic: its related spans are in the same item.
fn from_local<'db>(db: &'db dyn Db, item: Item<'db>, d: &LocalDiag) -> Diagnostic {
    let related = d.related.iter().map(|(span, m)| (Loc { item, span: *span }, m.clone())).collect();
    let d = ItemDiag { code: d.code, span: d.span, message: d.message.clone(), related, fix: d.fix.clone() };
    from_item(db, item, &d)
}

fn from_item(db: &dyn Db, item: Item<'_>, d: &ItemDiag<'_>) -> Diagnostic {
    let file = item.file(db);
    let off = item.offset(db);
    Diagnostic {
        code: d.code,
        severity: d.code.severity,
        file,
        range: d.span + off,
        message: d.message.clone(),
        related: d
            .related
            .iter()
            .map(|(loc, m)| {
                let (file, range) = absolute(db, *loc);
                Related { file, range, message: m.clone() }
            })
            .collect(),
        fix: d
            .fix
            .as_ref()
            .map(|(m, r, t)| Fix { message: m.clone(), edits: vec![(file, *r + off, t.clone())] }),
    }
}

fn at(db: &dyn Db, code: &'static Code, loc: Loc<'_>, message: String) -> Diagnostic {
    let (file, range) = absolute(db, loc);
    Diagnostic { code, severity: code.severity, file, range, message, related: Vec::new(), fix: None }
}

/// The diagnostics of one `define`: those of its items, and the unit-level checks.
#[salsa::tracked(returns(ref))]
pub fn unit_diagnostics<'db>(db: &'db dyn Db, unit: Unit<'db>) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for &item in unit.items(db) {
        let lowered = lower_item(db, item);
        out.extend(lowered.diags.iter().map(|d| from_local(db, item, d)));
        out.extend(check_item(db, item).diags.iter().map(|d| from_item(db, item, d)));
        misplaced(db, unit, item, &mut out);
    }
    if let Some(unsupported) = pddl_plus(db, unit) {
        // A PDDL+ domain gets that one warning: the rest would be noise about
        // a language hipop does not claim to check.
        return vec![unsupported];
    }
    match unit.kind(db) {
        UnitKind::Domain => domain_checks(db, unit, &mut out),
        UnitKind::Problem => problem_checks(db, unit, &mut out),
        UnitKind::Unknown => {}
    }
    out
}

fn misplaced(db: &dyn Db, unit: Unit<'_>, item: Item<'_>, out: &mut Vec<Diagnostic>) {
    let in_domain = match unit.kind(db) {
        UnitKind::Domain => true,
        UnitKind::Problem => false,
        UnitKind::Unknown => return,
    };
    if item.section(db).belongs_to_domain().is_some_and(|d| d != in_domain) {
        let (here, there) = if in_domain { ("a domain", "problem") } else { ("a problem", "domain") };
        // The section keyword (`:init`), or the first fact of an `:init` chunk.
        let span = match item.section(db) {
            Section::Init => TextRange::at(0.into(), item.len(db).min(1.into())),
            _ => item.head(db).unwrap_or(TextRange::at(0.into(), 1.into())),
        };
        if item.section(db) == Section::Init && item_is_later_chunk(db, unit, item) {
            return;
        }
        let message = format!("this section belongs in a {there}, not in {here}");
        out.push(at(db, codes::MISPLACED_SECTION, Loc { item, span }, message));
    }
}

/// Whether an `:init` chunk is not the first of its unit (one diagnostic per section).
fn item_is_later_chunk(db: &dyn Db, unit: Unit<'_>, item: Item<'_>) -> bool {
    unit.items(db).iter().find(|i| i.section(db) == Section::Init) != Some(&item)
}

fn duplicates(db: &dyn Db, dups: &[symbols::Duplicate<'_>], out: &mut Vec<Diagnostic>) {
    for d in dups {
        let (code, message) = if d.what == "type" {
            (codes::DUPLICATE_TYPE, format!("type `{}` is declared twice", d.name))
        } else {
            (codes::DUPLICATE, format!("{} `{}` is declared twice", d.what, d.name))
        };
        let mut diag = at(db, code, d.again, message);
        let (file, range) = absolute(db, d.first);
        diag.related.push(Related { file, range, message: "first declared here".into() });
        out.push(diag);
    }
}

/// The requirements declared by a unit and, for a problem, by its domain.
fn declared_requirements(db: &dyn Db, unit: Unit<'_>) -> FxHashSet<Str> {
    let mut reqs = match unit.kind(db) {
        UnitKind::Domain => domain_symbols(db, unit).requirements.clone(),
        _ => problem_symbols(db, unit).requirements.clone(),
    };
    if unit.kind(db) == UnitKind::Problem
        && let Some(d) = resolve_domain(db, unit).domain()
    {
        reqs.extend(domain_symbols(db, d).requirements.iter().cloned());
    }
    reqs
}

fn requirement_checks(db: &dyn Db, unit: Unit<'_>, out: &mut Vec<Diagnostic>) {
    let declared = declared_requirements(db, unit);
    // A problem does not repeat a missing requirement its domain already reports.
    let mut domain_features: FxHashSet<Feature> = FxHashSet::default();
    if unit.kind(db) == UnitKind::Problem
        && let Some(d) = resolve_domain(db, unit).domain()
    {
        for &item in d.items(db) {
            domain_features.extend(check_item(db, item).uses.features.iter().map(|(f, _)| *f));
        }
    }
    // With no `:requirements` at all, STRIPS is assumed and nothing is reported
    // beyond what the file uses — the common case of small hand-written files is
    // to list what they use, so absence is reported like any missing one.
    let mut reported: FxHashSet<Feature> = FxHashSet::default();
    let req_item = unit.items(db).iter().copied().find(|i| i.section(db) == Section::Requirements);
    let mut missing: Vec<(Feature, Item<'_>, TextRange)> = Vec::new();
    for &item in unit.items(db) {
        for &(feature, span) in &check_item(db, item).uses.features {
            let (name, also) = feature.requirement();
            if declared.contains(name)
                || also.iter().any(|a| declared.contains(*a))
                || domain_features.contains(&feature)
                || !reported.insert(feature)
            {
                continue;
            }
            missing.push((feature, item, span));
        }
    }
    // Without a `:requirements`, each fix adds one with all that is missing:
    // applying one fixes them all, and applying them all adds it once.
    let section = match req_item {
        Some(_) => None,
        None => {
            let names: Vec<&str> = missing.iter().map(|(f, _, _)| f.requirement().0).collect();
            new_requirements(db, unit, &names)
        }
    };
    for (feature, item, span) in missing {
        let (name, _) = feature.requirement();
        let message =
            format!("`{name}` is not declared in `:requirements`, but this uses {}", feature.what());
        let mut d = at(db, codes::MISSING_REQUIREMENT, Loc { item, span }, message);
        if let Some((file, at, text)) = &section {
            d.fix = Some(Fix {
                message: format!("add `{}`", text.trim_start()),
                edits: vec![(*file, *at, text.clone())],
            });
        }
        if let Some(r) = req_item {
            let (file, range) = (r.file(db), r.offset(db));
            let len = r.len(db);
            let close = TextRange::empty(range + len - rowan::TextSize::from(1));
            d.related.push(Related {
                file,
                range: TextRange::at(range, len),
                message: "requirements declared here".into(),
            });
            d.fix = Some(Fix {
                message: format!("add `{name}`"),
                edits: vec![(file, close, format!(" {name}"))],
            });
        }
        out.push(d);
    }
}

/// The edit that adds `(:requirements names…)` to a unit that has none:
/// after `(domain name)`, or after a problem's `(:domain name)`.
fn new_requirements(db: &dyn Db, unit: Unit<'_>, names: &[&str]) -> Option<(SourceFile, TextRange, String)> {
    let items = unit.items(db);
    let after = items
        .iter()
        .rposition(|i| i.section(db) == Section::DomainRef)
        .or_else(|| items.iter().position(|i| i.section(db) == Section::Header))?;
    let (file, at, separator) = new_section_after(db, unit, after);
    Some((file, at, format!("{separator}(:requirements {})", names.join(" "))))
}

/// Where a new section goes after the `after`th item of a unit, and what
/// goes before it: a line break and the indentation of the next section,
/// or a space when the next section is on the same line.
pub(crate) fn new_section_after(
    db: &dyn Db,
    unit: Unit<'_>,
    after: usize,
) -> (SourceFile, TextRange, String) {
    let items = unit.items(db);
    let item = items[after];
    let file = item.file(db);
    let text = file.text(db);
    let end = item.offset(db) + item.len(db);
    let end_at = usize::from(end);
    let separator = match items.get(after + 1).map(|i| usize::from(i.offset(db))) {
        Some(n) if !text[end_at..n].contains('\n') => " ".to_string(),
        Some(n) => {
            let line_start = text[..n].rfind('\n').map_or(0, |i| i + 1);
            let indent = &text[line_start..n];
            if indent.chars().all(|c| c == ' ' || c == '\t') { format!("\n{indent}") } else { "\n  ".into() }
        }
        None => "\n  ".into(),
    };
    (file, TextRange::empty(end), separator)
}

fn domain_checks(db: &dyn Db, unit: Unit<'_>, out: &mut Vec<Diagnostic>) {
    let syms = domain_symbols(db, unit);
    duplicates(db, &syms.duplicates, out);
    requirement_checks(db, unit, out);
    unused_declarations(db, unit, out);
}

/// The warning for a domain with PDDL+ processes or events, at the first one:
/// the file is not wrong, hipop does not support it.
fn pddl_plus(db: &dyn Db, unit: Unit<'_>) -> Option<Diagnostic> {
    let plus: Vec<Item<'_>> = unit
        .items(db)
        .iter()
        .copied()
        .filter(|&i| {
            i.section(db) == Section::Action
                && matches!(&lower_item(db, i).data, ItemData::Action(a) if matches!(a.kind, ActionKind::Process | ActionKind::Event))
        })
        .collect();
    if let Some((&first, rest)) = plus.split_first() {
        let span = match &lower_item(db, first).data {
            ItemData::Action(a) => a.name.span,
            _ => TextRange::default(),
        };
        let mut d = at(
            db,
            codes::UNSUPPORTED,
            Loc { item: first, span },
            "PDDL+ processes and events are not supported: hipop does not check this domain, and cannot plan or \
             validate with it"
                .into(),
        );
        for &i in rest {
            if let ItemData::Action(a) = &lower_item(db, i).data {
                let (file, range) = absolute(db, Loc { item: i, span: a.name.span });
                d.related.push(Related { file, range, message: "also PDDL+".into() });
            }
        }
        return Some(d);
    }
    None
}

fn unused_declarations(db: &dyn Db, unit: Unit<'_>, out: &mut Vec<Diagnostic>) {
    let syms = domain_symbols(db, unit);
    // Unused declarations: not referenced by the domain nor by any of its problems.
    let mut used = check::Uses::default();
    let mut merge = |item: Item<'_>| {
        let u = &check_item(db, item).uses;
        used.types.extend(u.types.iter().cloned());
        used.predicates.extend(u.predicates.iter().cloned());
        used.functions.extend(u.functions.iter().cloned());
        used.constants.extend(u.constants.iter().cloned());
    };
    for &item in unit.items(db) {
        merge(item);
    }
    for &p in problems_of(db, unit) {
        for &item in p.items(db) {
            merge(item);
        }
    }
    // A type is used when a used type or declaration refers to it as an ancestor.
    let mut used_types: FxHashSet<&str> = FxHashSet::default();
    for t in &used.types {
        if let Some(anc) = syms.ancestors.get(t) {
            used_types.extend(anc.iter().map(|a| &**a));
        }
    }
    let mut unused: Vec<(Loc<'_>, String)> = Vec::new();
    for (name, decl) in &syms.types {
        if !used_types.contains(&**name) && !used.types.contains(name) {
            unused.push((decl.locs[0], format!("type `{name}` is never used")));
        }
    }
    for (name, decl) in &syms.predicates {
        if !used.predicates.contains(name) {
            unused.push((decl.loc, format!("predicate `{name}` is never used")));
        }
    }
    for (name, decl) in &syms.functions {
        if !used.functions.contains(name) {
            unused.push((decl.loc, format!("function `{name}` is never used")));
        }
    }
    for (name, decl) in &syms.constants {
        if !used.constants.contains(name) {
            unused.push((decl.loc, format!("constant `{name}` is never used")));
        }
    }
    for (loc, message) in unused {
        out.push(at(db, codes::UNUSED, loc, message));
    }
}

fn problem_checks(db: &dyn Db, unit: Unit<'_>, out: &mut Vec<Diagnostic>) {
    let syms = problem_symbols(db, unit);
    duplicates(db, &syms.duplicates, out);
    let range = unit.range(db);
    let file = unit.file(db);
    let domain_item = unit.items(db).iter().copied().find(|i| i.section(db) == Section::DomainRef);
    let ref_loc = |i: Item<'_>| -> (SourceFile, TextRange) {
        match &lower_item(db, i).data {
            ItemData::DomainRef(n) => absolute(db, Loc { item: i, span: n.span }),
            _ => (file, TextRange::at(i.offset(db), 1.into())),
        }
    };
    match resolve_domain(db, unit) {
        Resolution::Found(_) => requirement_checks(db, unit, out),
        // `(:domain)` without a name is already a malformed section.
        Resolution::NoReference if domain_item.is_some() => {}
        Resolution::NoReference => out.push(Diagnostic {
            code: codes::MISSING_DOMAIN,
            severity: codes::MISSING_DOMAIN.severity,
            file,
            range: TextRange::at(range.start(), 1.into()),
            message: "this problem has no `(:domain name)`".into(),
            related: Vec::new(),
            fix: None,
        }),
        Resolution::Missing => {
            let (file, range) = domain_item.map_or((file, range), ref_loc);
            let name = unit.domain_ref(db).clone().unwrap_or_default();
            out.push(Diagnostic {
                code: codes::MISSING_DOMAIN,
                severity: codes::MISSING_DOMAIN.severity,
                file,
                range,
                message: format!("domain `{name}` is not among the files: open or pass its file too"),
                related: Vec::new(),
                fix: None,
            });
        }
        Resolution::Mismatch(other) => {
            requirement_checks(db, unit, out);
            let (file, range) = domain_item.map_or((file, range), ref_loc);
            let name = unit.domain_ref(db).clone().unwrap_or_default();
            let other_name = other.name(db).clone().unwrap_or_default();
            let header = other.items(db).iter().copied().find(|i| i.section(db) == Section::Header);
            let related = header
                .and_then(|h| match &lower_item(db, h).data {
                    ItemData::Header(n) => Some(absolute(db, Loc { item: h, span: n.span })),
                    _ => None,
                })
                .map(|(f, r)| Related {
                    file: f,
                    range: r,
                    message: format!("the domain here is `{other_name}`"),
                });
            out.push(Diagnostic {
                code: codes::DOMAIN_MISMATCH,
                severity: codes::DOMAIN_MISMATCH.severity,
                file,
                range,
                message: format!(
                    "this problem is for domain `{name}`, but the domain beside it is `{other_name}`"
                ),
                related: related.into_iter().collect(),
                fix: Some(Fix {
                    message: format!("use domain `{other_name}`"),
                    edits: vec![(file, range, other_name)],
                }),
            });
        }
    }
}
