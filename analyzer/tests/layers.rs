//! The analyzer's modules form layers (ARCHITECTURE.md, "Layers"): a module
//! may use the modules of lower layers only. This test reads every `crate::`
//! path of the analyzer's sources and fails on a use that goes up or across
//! (a back-edge), and on a top-level module that has no layer yet.
//!
//! Unit-test modules (a `#[cfg(test)] mod` to the end of a file, and
//! `tests.rs` files) are exempt: a test may drive a lower layer through the host.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The layers, bottom first. Modules of one layer may not use each other.
const LAYERS: &[&[&str]] = &[
    &["syntax", "alloc"],
    &["input"],
    &["diagnostic"],
    &["model"],
    &["db"],
    &["fix"],
    &["semantics"],
    &["verify"],
    &["eval"],
    &["plan"],
    &["validate", "planner"],
    &["repair"],
    &["ide"],
    &["host"],
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).expect("readable source folder").flatten().collect();
    entries.sort_by_key(|e| e.path());
    for e in entries {
        let path = e.path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|x| x == "rs") {
            out.push(path);
        }
    }
}

/// The top-level modules `lib.rs` re-exports items of: `crate::Diagnostic` is
/// a use of `diagnostic`.
fn root_reexports(lib: &str) -> BTreeMap<String, String> {
    let mut map = BTreeMap::new();
    for stmt in lib.split(';') {
        let stmt = stmt.trim();
        let Some(rest) = stmt.rsplit('\n').next().and_then(|l| l.trim().strip_prefix("pub use ")) else {
            continue;
        };
        let Some((module, names)) = rest.split_once("::") else { continue };
        let names = names.trim_start_matches('{').trim_end_matches('}');
        for name in names.split(',') {
            let name = name.split(" as ").last().unwrap_or(name).trim();
            if !name.is_empty() {
                map.insert(name.to_string(), module.to_string());
            }
        }
    }
    map
}

fn ident_at(s: &str) -> &str {
    let end = s.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(s.len());
    &s[..end]
}

/// The top-level modules a line of code names through `crate::`, including
/// those of a `use crate::{a::b, c}` group (which may span lines: `group`
/// carries an open group's brace depth from one line to the next).
fn uses(line: &str, group: &mut Option<usize>, roots: &BTreeMap<String, String>) -> Vec<String> {
    let mut found = Vec::new();
    let mut name = |ident: &str| {
        if !ident.is_empty() {
            found.push(roots.get(ident).cloned().unwrap_or_else(|| ident.to_string()));
        }
    };
    let mut rest = line;
    if let Some(depth) = group.as_mut() {
        // Inside `use crate::{ … }`: each name at depth 1 is a module.
        let mut at_item_start = true;
        for (i, c) in rest.char_indices() {
            match c {
                '{' => *depth += 1,
                '}' => {
                    *depth -= 1;
                    if *depth == 0 {
                        rest = &rest[i + 1..];
                        break;
                    }
                }
                ',' if *depth == 1 => at_item_start = true,
                c if c.is_whitespace() => {}
                _ => {
                    if at_item_start && *depth == 1 {
                        name(ident_at(&rest[i..]));
                    }
                    at_item_start = false;
                }
            }
        }
        if *depth > 0 {
            return found;
        }
        *group = None;
    }
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        if let Some(inner) = after.strip_prefix('{') {
            *group = Some(1);
            found.extend(uses(inner, group, roots));
            return found;
        }
        name(ident_at(after));
        rest = after;
    }
    found
}

#[test]
fn no_module_uses_a_higher_or_sibling_layer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let roots = root_reexports(&std::fs::read_to_string(src.join("lib.rs")).expect("lib.rs"));
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut problems = Vec::new();
    let mut unplaced = Vec::new();
    for path in &files {
        let rel = path.strip_prefix(&src).expect("under src");
        let first = rel.components().next().expect("a component").as_os_str().to_string_lossy();
        let module = first.trim_end_matches(".rs");
        if module == "lib" || rel.file_name().is_some_and(|n| n == "tests.rs") {
            continue;
        }
        let Some(from) = layer_of(module) else {
            unplaced.push(module.to_string());
            continue;
        };
        let text = std::fs::read_to_string(path).expect("readable source");
        let mut group = None;
        let lines: Vec<&str> = text.lines().collect();
        for (n, line) in lines.iter().enumerate() {
            let code = line.trim_start();
            let next = lines[n + 1..].iter().map(|l| l.trim_start()).find(|l| !l.is_empty());
            if code.starts_with("#[cfg(test)]")
                && next.is_some_and(|l| l.split_whitespace().any(|w| w == "mod"))
            {
                break;
            }
            if code.starts_with("//") {
                continue;
            }
            for used in uses(line, &mut group, &roots) {
                if used == module || used == "self" || used == "super" {
                    continue;
                }
                match layer_of(&used) {
                    Some(to) if to < from => {}
                    Some(_) => problems.push(format!(
                        "{}:{}: `{module}` uses `{used}`, which is not in a lower layer",
                        rel.display(),
                        n + 1
                    )),
                    None => unplaced.push(used),
                }
            }
        }
    }
    unplaced.sort();
    unplaced.dedup();
    assert!(
        unplaced.is_empty(),
        "modules without a layer in tests/layers.rs (add them to LAYERS): {unplaced:?}"
    );
    assert!(problems.is_empty(), "back-edges between the analyzer's layers:\n{}", problems.join("\n"));
}

/// The scanner sees every form of use the analyzer writes (so that the test
/// above cannot pass by not seeing them).
#[test]
fn the_scanner_sees_each_form_of_use() {
    let roots = BTreeMap::from([("Diagnostic".to_string(), "diagnostic".to_string())]);
    let mut group = None;
    let seen = |line: &str, group: &mut Option<usize>| uses(line, group, &roots);
    assert_eq!(seen("use crate::plan::parse_plan;", &mut group), ["plan"]);
    assert_eq!(seen("    let x = crate::validate::run(crate::db::f(db));", &mut group), ["validate", "db"]);
    assert_eq!(
        seen("use crate::{db::{Db, Unit}, model, Diagnostic};", &mut group),
        ["db", "model", "diagnostic"]
    );
    assert_eq!(seen("use crate::{", &mut group), Vec::<String>::new());
    assert_eq!(seen("    verify::{a, b},", &mut group), ["verify"]);
    assert_eq!(seen("    host,", &mut group), ["host"]);
    assert_eq!(seen("};", &mut group), Vec::<String>::new());
    assert!(group.is_none());
    assert_eq!(seen("fn f() {}", &mut group), Vec::<String>::new());
    let roots = root_reexports(
        "pub mod db;\npub use db::SourceFile;\npub use host::{Analysis, AnalysisHost as Host};",
    );
    assert_eq!(roots.get("SourceFile").map(String::as_str), Some("db"));
    assert_eq!(roots.get("Host").map(String::as_str), Some("host"));
    assert_eq!(roots.get("Analysis").map(String::as_str), Some("host"));
}
