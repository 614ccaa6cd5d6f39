//! Loading `.pddl`/`.hddl` files from disk.
//!
//! A problem finds its domain among all the files the analyzer knows, so the
//! server loads the workspace folders at `initialize`, and the folder of any
//! document opened outside them. A budget caps what a large or unlucky root
//! (a home directory) can cost.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use tower_lsp_server::ls_types::{InitializeParams, Uri};

/// Directories never worth scanning.
const SKIPPED_DIRS: &[&str] = &["target", "node_modules"];

/// What is left to load, over the whole session.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Budget {
    pub files: usize,
    pub bytes: u64,
    /// Folders listed: bounds the walk of a root with few sources but many folders.
    pub dirs: usize,
    /// Set once a file was skipped for lack of budget.
    pub exhausted: bool,
}

impl Default for Budget {
    fn default() -> Budget {
        Budget { files: 2_000, bytes: 64 << 20, dirs: 20_000, exhausted: false }
    }
}

/// The files read by a scan, and the directories it listed.
#[derive(Debug, Default)]
pub(crate) struct Scan {
    /// `(analyzer key, text)`.
    pub files: Vec<(String, String)>,
    pub dirs: HashSet<PathBuf>,
}

/// The local path of a `file:` URI.
pub(crate) fn uri_path(uri: &Uri) -> Option<PathBuf> {
    if !uri.as_str().starts_with("file:") {
        return None;
    }
    uri.to_file_path().map(|p| p.into_owned())
}

/// The folders to load: the workspace folders, else the root.
pub(crate) fn roots(params: &InitializeParams) -> Vec<PathBuf> {
    if let Some(folders) = &params.workspace_folders
        && !folders.is_empty()
    {
        return folders.iter().filter_map(|f| uri_path(&f.uri)).collect();
    }
    #[expect(deprecated, reason = "old clients only send `rootUri` or `rootPath`")]
    match (&params.root_uri, &params.root_path) {
        (Some(uri), _) => uri_path(uri).into_iter().collect(),
        (None, path) => path.iter().map(PathBuf::from).collect(),
    }
}

pub(crate) fn is_source(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("pddl") || e.eq_ignore_ascii_case("hddl"))
}

pub(crate) fn is_skipped_dir(path: &Path) -> bool {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    name.starts_with('.') || SKIPPED_DIRS.contains(&name)
}

/// Reads the source files of `dir`, and of its subfolders if `recursive`.
/// Symbolic links to folders are not followed, so a scan always ends.
pub(crate) fn scan(dir: &Path, recursive: bool, budget: &mut Budget, out: &mut Scan) {
    let mut stack = vec![dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        if budget.files == 0 || budget.dirs == 0 {
            budget.exhausted = true;
            return;
        }
        if !out.dirs.insert(dir.clone()) {
            continue;
        }
        budget.dirs -= 1;
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        let mut entries: Vec<_> = entries.flatten().collect();
        entries.sort_by_key(|e| e.file_name());
        for entry in entries {
            let Ok(kind) = entry.file_type() else { continue };
            let path = entry.path();
            if kind.is_dir() {
                if recursive && !is_skipped_dir(&path) {
                    stack.push(path);
                }
            } else if is_source(&path) {
                read_file(&path, entry.metadata().map_or(0, |m| m.len()), budget, out);
            }
        }
    }
}

fn read_file(path: &Path, len: u64, budget: &mut Budget, out: &mut Scan) {
    if budget.files == 0 || len > budget.bytes {
        budget.exhausted = true;
        return;
    }
    let Some(text) = read_text(path) else { return };
    budget.files -= 1;
    budget.bytes = budget.bytes.saturating_sub(text.len() as u64);
    out.files.push((path.to_string_lossy().into_owned(), text));
}

/// A file's text as an editor shows it: bytes that are not UTF-8 are
/// replaced (the diagnostics still locate the rest), and a UTF-8 byte-order
/// mark at its start is dropped. Editors read the mark as an encoding, not
/// as a character, and send the text without it: positions in a file loaded
/// from disk must be the editor's.
pub(crate) fn read_text(path: &Path) -> Option<String> {
    let bytes = std::fs::read(path).ok()?;
    let mut text =
        String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned());
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Some(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scans_sources_skips_build_folders_and_respects_the_budget() {
        let root = std::env::temp_dir().join(format!("hipop-lsp-scan-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        for dir in ["a", "target", ".git", "a/b"] {
            std::fs::create_dir_all(root.join(dir)).unwrap();
        }
        for file in ["d.pddl", "a/p.HDDL", "a/b/q.hddl", "target/t.pddl", ".git/g.pddl", "a/readme.md"] {
            std::fs::write(root.join(file), "(define)").unwrap();
        }
        let mut budget = Budget::default();
        let mut out = Scan::default();
        scan(&root, true, &mut budget, &mut out);
        let mut names: Vec<String> =
            out.files.iter().map(|(k, _)| k.trim_start_matches(root.to_str().unwrap()).to_string()).collect();
        names.sort();
        assert_eq!(names, ["/a/b/q.hddl", "/a/p.HDDL", "/d.pddl"]);
        assert!(!budget.exhausted);

        let mut small = Budget { files: 1, ..Budget::default() };
        let mut out = Scan::default();
        scan(&root, true, &mut small, &mut out);
        assert_eq!(out.files.len(), 1);
        assert!(small.exhausted);
        let _ = std::fs::remove_dir_all(&root);
    }
}
