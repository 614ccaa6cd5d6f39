//! Symbol tables of a domain and of a problem, built from the lowered items.
//!
//! Locations are item-relative ([`Loc`]), so a table stays equal when text
//! moves around it, and the checks that read it are not re-run.

use crate::model::Str;
use rowan::TextRange;
use rustc_hash::{FxHashMap, FxHashSet};

use crate::db::{Db, Item, Section, Unit, UnitKind, lower_item};
use crate::model::{ActionKind, ItemData, TypeRef, Typed};

/// A span inside an item.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, salsa::SalsaValue)]
pub struct Loc<'db> {
    pub item: Item<'db>,
    pub span: TextRange,
}

/// The alternatives of a type annotation, lower-cased; `object` when implicit.
pub type TypeSet = Vec<Str>;

pub fn type_set(t: &TypeRef) -> TypeSet {
    match t {
        TypeRef::Implicit => vec!["object".into()],
        _ => t.names().iter().map(|n| n.key_str()).collect(),
    }
}

#[derive(Debug, Clone, PartialEq, Eq, salsa::SalsaValue)]
pub struct TypeDecl<'db> {
    pub parents: Vec<Str>,
    pub locs: Vec<Loc<'db>>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DeclKind {
    Predicate,
    Function,
    Action(ActionKind),
    Task,
    Derived,
}

/// A predicate, function, action or task: its parameter types and where it is declared.
#[derive(Debug, Clone, PartialEq, Eq, salsa::SalsaValue)]
pub struct SigDecl<'db> {
    pub kind: DeclKind,
    pub params: Vec<TypeSet>,
    /// Parameter names, for hover.
    pub param_names: Vec<Str>,
    pub result: Option<TypeSet>,
    pub loc: Loc<'db>,
}

#[derive(Debug, Clone, PartialEq, Eq, salsa::SalsaValue)]
pub struct ObjDecl<'db> {
    /// The name as declared (the table's key is its lower-cased form).
    pub name: Str,
    pub ty: TypeSet,
    pub loc: Loc<'db>,
}

#[derive(Debug, Clone, PartialEq, Eq, salsa::SalsaValue)]
pub struct MethodDecl<'db> {
    pub task: Option<Str>,
    pub loc: Loc<'db>,
}

/// A second declaration of a name.
#[derive(Debug, Clone, PartialEq, Eq, salsa::SalsaValue)]
pub struct Duplicate<'db> {
    pub what: &'static str,
    pub name: Str,
    pub first: Loc<'db>,
    pub again: Loc<'db>,
}

/// Everything a domain declares.
#[derive(Debug, Clone, PartialEq, Eq, Default, salsa::SalsaValue)]
pub struct DomainSymbols<'db> {
    pub requirements: FxHashSet<Str>,
    pub has_types_section: bool,
    pub types: FxHashMap<Str, TypeDecl<'db>>,
    /// Every declared type's ancestors (itself included, `object` last).
    pub ancestors: FxHashMap<Str, Vec<Str>>,
    pub constants: FxHashMap<Str, ObjDecl<'db>>,
    pub predicates: FxHashMap<Str, SigDecl<'db>>,
    pub functions: FxHashMap<Str, SigDecl<'db>>,
    pub actions: FxHashMap<Str, SigDecl<'db>>,
    pub tasks: FxHashMap<Str, SigDecl<'db>>,
    pub methods: FxHashMap<Str, MethodDecl<'db>>,
    pub duplicates: Vec<Duplicate<'db>>,
    /// Types whose ancestry loops back to themselves.
    pub cyclic_types: Vec<Str>,
}

impl<'db> DomainSymbols<'db> {
    pub fn is_type(&self, t: &str) -> bool {
        t == "object" || t == "number" || self.types.contains_key(t)
    }

    /// Whether `sub` is `sup` or one of its subtypes.
    pub fn is_subtype(&self, sub: &str, sup: &str) -> bool {
        if sub == sup || sup == "object" {
            return true;
        }
        self.ancestors.get(sub).is_some_and(|a| a.iter().any(|x| &**x == sup))
    }

    /// Whether every alternative of `arg` fits some alternative of `param`.
    #[inline]
    pub fn fits(&self, arg: &[Str], param: &[Str]) -> bool {
        // The common case, a plain type given where it is expected, needs no
        // lookup: it is tested inline, for every argument of every fact.
        if let [a] = arg
            && param.iter().any(|p| p.as_str() == a.as_str())
        {
            return true;
        }
        self.fits_by_ancestry(arg, param)
    }

    fn fits_by_ancestry(&self, arg: &[Str], param: &[Str]) -> bool {
        arg.iter().all(|a| {
            // Every declared type has its ancestors: one lookup tells whether
            // `a` is a type and which types it fits.
            let ancestors = self.ancestors.get(a);
            if ancestors.is_none() && !self.is_type(a) {
                return true;
            }
            param.iter().any(|p| {
                a == p || p == "object" || ancestors.is_some_and(|up| up.contains(p)) || !self.is_type(p)
            })
        })
    }

    /// Whether some object could have both types: every alternative of `arg`
    /// fits `param`, or they have a common subtype (a variable of a supertype
    /// narrows to the parameter's type).
    pub fn compatible(&self, arg: &[Str], param: &[Str]) -> bool {
        self.fits(arg, param)
            || arg.iter().any(|a| {
                param.iter().any(|p| {
                    self.is_subtype(p, a)
                        || self.types.keys().any(|t| self.is_subtype(t, a) && self.is_subtype(t, p))
                })
            })
    }

    /// An action or a task.
    pub fn callable(&self, name: &str) -> Option<&SigDecl<'db>> {
        self.actions.get(name).or_else(|| self.tasks.get(name))
    }
}

fn sig<'db>(kind: DeclKind, params: &[Typed], result: Option<TypeSet>, loc: Loc<'db>) -> SigDecl<'db> {
    SigDecl {
        kind,
        params: params.iter().map(|p| type_set(&p.ty)).collect(),
        param_names: params.iter().map(|p| p.name.text_str()).collect(),
        result,
        loc,
    }
}

fn insert<'db, T>(
    map: &mut FxHashMap<Str, T>,
    dups: &mut Vec<Duplicate<'db>>,
    what: &'static str,
    name: &str,
    value: T,
    loc_of: impl Fn(&T) -> Loc<'db>,
) {
    if let Some(first) = map.get(name) {
        dups.push(Duplicate { what, name: name.into(), first: loc_of(first), again: loc_of(&value) });
    } else {
        map.insert(name.into(), value);
    }
}

/// The symbol table of a domain unit.
#[salsa::tracked(returns(ref))]
pub fn domain_symbols<'db>(db: &'db dyn Db, unit: Unit<'db>) -> DomainSymbols<'db> {
    let mut s = DomainSymbols::default();
    if unit.kind(db) != UnitKind::Domain {
        return s;
    }
    for &item in unit.items(db) {
        let loc = |span| Loc { item, span };
        match &lower_item(db, item).data {
            ItemData::Requirements(reqs) => s.requirements.extend(reqs.iter().map(|r| r.key_str())),
            ItemData::Types(types) => {
                s.has_types_section = true;
                for t in types {
                    let parents = match &t.ty {
                        TypeRef::Implicit => Vec::new(),
                        other => type_set(other),
                    };
                    match s.types.get_mut(t.name.key()) {
                        // Declared twice: a warning (real files do it), parents merge.
                        Some(decl) => {
                            s.duplicates.push(Duplicate {
                                what: "type",
                                name: t.name.key_str(),
                                first: decl.locs[0],
                                again: loc(t.name.span),
                            });
                            decl.parents.extend(parents);
                            decl.locs.push(loc(t.name.span));
                        }
                        None => {
                            s.types
                                .insert(t.name.key_str(), TypeDecl { parents, locs: vec![loc(t.name.span)] });
                        }
                    }
                }
            }
            ItemData::Constants(cs) => {
                for c in cs {
                    let value =
                        ObjDecl { name: c.name.text_str(), ty: type_set(&c.ty), loc: loc(c.name.span) };
                    insert(&mut s.constants, &mut s.duplicates, "constant", c.name.key(), value, |d| d.loc);
                }
            }
            ItemData::Predicates(ps) => {
                for p in ps {
                    let value = sig(DeclKind::Predicate, &p.params, None, loc(p.name.span));
                    insert(&mut s.predicates, &mut s.duplicates, "predicate", p.name.key(), value, |d| d.loc);
                }
            }
            ItemData::Functions(fs) => {
                for f in fs {
                    let result = match &f.result {
                        TypeRef::Implicit => vec!["number".into()],
                        other => type_set(other),
                    };
                    let value = sig(DeclKind::Function, &f.params, Some(result), loc(f.name.span));
                    insert(&mut s.functions, &mut s.duplicates, "function", f.name.key(), value, |d| d.loc);
                }
            }
            ItemData::Derived(atom, params, _) => {
                let value = sig(DeclKind::Derived, params, None, loc(atom.pred.span));
                // A derived predicate may be declared in `:predicates` too.
                s.predicates.entry(atom.pred.key_str()).or_insert(value);
            }
            ItemData::Action(a) => {
                let value = sig(DeclKind::Action(a.kind), &a.params, None, loc(a.name.span));
                if let Some(t) = s.tasks.get(a.name.key()) {
                    let first = t.loc;
                    s.duplicates.push(Duplicate {
                        what: "action or task",
                        name: a.name.key_str(),
                        first,
                        again: value.loc,
                    });
                } else {
                    insert(&mut s.actions, &mut s.duplicates, "action", a.name.key(), value, |d| d.loc);
                }
            }
            ItemData::Task(t) => {
                let value = sig(DeclKind::Task, &t.params, None, loc(t.name.span));
                if let Some(a) = s.actions.get(t.name.key()) {
                    let first = a.loc;
                    s.duplicates.push(Duplicate {
                        what: "action or task",
                        name: t.name.key_str(),
                        first,
                        again: value.loc,
                    });
                } else {
                    insert(&mut s.tasks, &mut s.duplicates, "task", t.name.key(), value, |d| d.loc);
                }
            }
            ItemData::Method(m) => {
                let value =
                    MethodDecl { task: m.task.as_ref().map(|t| t.name.key_str()), loc: loc(m.name.span) };
                insert(&mut s.methods, &mut s.duplicates, "method", m.name.key(), value, |d| d.loc);
            }
            _ => {}
        }
    }
    // A type used as a parent is declared by that use (VAL and pandaPIparser agree).
    let implicit: Vec<(Str, Loc<'db>)> = s
        .types
        .values()
        .flat_map(|d| d.parents.iter().map(move |p| (p.clone(), d.locs[0])))
        .filter(|(p, _)| &**p != "object" && !s.types.contains_key(p))
        .collect();
    for (p, loc) in implicit {
        s.types.entry(p).or_insert(TypeDecl { parents: Vec::new(), locs: vec![loc] });
    }
    // Ancestors, with cycle detection.
    let names: Vec<Str> = s.types.keys().cloned().collect();
    for name in names {
        let mut seen: Vec<Str> = vec![name.clone()];
        let mut stack: Vec<Str> = s.types[&name].parents.clone();
        let mut cyclic = false;
        while let Some(t) = stack.pop() {
            if t == name {
                cyclic = true;
                continue;
            }
            if seen.contains(&t) {
                continue;
            }
            if let Some(d) = s.types.get(&t) {
                stack.extend(d.parents.iter().cloned());
            }
            seen.push(t);
        }
        if !seen.iter().any(|t| &**t == "object") {
            seen.push("object".into());
        }
        if cyclic {
            s.cyclic_types.push(name.clone());
        }
        s.ancestors.insert(name, seen);
    }
    s.cyclic_types.sort();
    s
}

/// What a problem declares.
#[derive(Debug, Clone, PartialEq, Eq, Default, salsa::SalsaValue)]
pub struct ProblemSymbols<'db> {
    pub requirements: FxHashSet<Str>,
    pub objects: FxHashMap<Str, ObjDecl<'db>>,
    pub duplicates: Vec<Duplicate<'db>>,
}

/// The symbol table of a problem unit.
#[salsa::tracked(returns(ref))]
pub fn problem_symbols<'db>(db: &'db dyn Db, unit: Unit<'db>) -> ProblemSymbols<'db> {
    let mut s = ProblemSymbols::default();
    // Only these sections declare anything: lowering the others (a large
    // `:init`) here would serialise what the checks lower in parallel.
    let declares = |i: &&Item<'db>| matches!(i.section(db), Section::Requirements | Section::Objects);
    for &item in unit.items(db).iter().filter(declares) {
        match &lower_item(db, item).data {
            ItemData::Requirements(reqs) => s.requirements.extend(reqs.iter().map(|r| r.key_str())),
            ItemData::Objects(objs) => {
                for o in objs {
                    let value = ObjDecl {
                        name: o.name.text_str(),
                        ty: type_set(&o.ty),
                        loc: Loc { item, span: o.name.span },
                    };
                    insert(&mut s.objects, &mut s.duplicates, "object", o.name.key(), value, |d| d.loc);
                }
            }
            _ => {}
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `fits` agrees with its definition: every alternative of the argument
    /// that is a type is a subtype of some alternative of the parameter that
    /// is a type, or the parameter has an alternative that is not a type.
    #[test]
    fn fits_is_subtyping_of_every_alternative() {
        let mut d = DomainSymbols::default();
        // car - vehicle - object, truck - vehicle, place (a root), undeclared names.
        for (t, up) in [
            ("car", &["car", "vehicle", "object"][..]),
            ("truck", &["truck", "vehicle", "object"]),
            ("vehicle", &["vehicle", "object"]),
            ("place", &["place", "object"]),
        ] {
            d.types.insert(t.into(), TypeDecl { parents: Vec::new(), locs: Vec::new() });
            d.ancestors.insert(t.into(), up.iter().map(|&u| Str::from(u)).collect());
        }
        let names = ["car", "truck", "vehicle", "place", "object", "number", "ghost"];
        let sets: Vec<Vec<Str>> = names
            .iter()
            .map(|&n| vec![Str::from(n)])
            .chain(names.iter().flat_map(|&a| names.iter().map(move |&b| vec![Str::from(a), Str::from(b)])))
            .collect();
        let definition = |arg: &[Str], param: &[Str]| {
            arg.iter().all(|a| !d.is_type(a) || param.iter().any(|p| !d.is_type(p) || d.is_subtype(a, p)))
        };
        for arg in &sets {
            for param in &sets {
                assert_eq!(d.fits(arg, param), definition(arg, param), "{arg:?} in {param:?}");
            }
        }
        assert!(d.fits(&["car".into()], &["vehicle".into()]));
        assert!(!d.fits(&["vehicle".into()], &["car".into()]));
    }
}
