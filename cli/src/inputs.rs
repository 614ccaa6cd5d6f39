//! Collecting the files to check from the paths given on the command line.

use std::path::{Path, PathBuf};

/// A file to check, or why it can't be.
pub enum Input {
    File { path: String, text: String },
    Problem { path: String, message: String },
}

/// The name a file is known by in the analysis: its path as given, written
/// the same way whatever way it was given (`a//b.pddl`, `a/./b.pddl` and
/// `./a/b.pddl` are `a/b.pddl`), so that files are in the same folder when
/// their folders are (a problem finds the domain beside it by its folder).
pub fn key(path: &Path) -> String {
    use std::path::Component;
    let mut parts = path.components().peekable();
    if parts.peek() == Some(&Component::CurDir) && path.components().count() > 1 {
        parts.next();
    }
    parts.collect::<PathBuf>().display().to_string()
}

fn is_model_file(p: &Path) -> bool {
    matches!(p.extension().and_then(|e| e.to_str()), Some("pddl" | "hddl" | "PDDL" | "HDDL"))
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>, problems: &mut Vec<Input>) {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) => {
            problems.push(Input::Problem {
                path: dir.display().to_string(),
                message: format!("cannot read folder: {e}"),
            });
            return;
        }
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for p in paths {
        let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.starts_with('.') || name == "target" || name == "node_modules" {
            continue;
        }
        if p.is_dir() {
            walk(&p, out, problems);
        } else if is_model_file(&p) {
            out.push(p);
        }
    }
}

/// Reads the files named by `paths`: files as given (whatever their extension),
/// folders recursively for `.pddl` and `.hddl` files.
pub fn collect(paths: &[PathBuf]) -> Vec<Input> {
    let mut files = Vec::new();
    let mut out = Vec::new();
    for p in paths {
        match std::fs::metadata(p) {
            Ok(m) if m.is_dir() => walk(p, &mut files, &mut out),
            Ok(_) => files.push(p.clone()),
            Err(e) => out.push(Input::Problem {
                path: p.display().to_string(),
                message: if e.kind() == std::io::ErrorKind::NotFound {
                    "no such file or folder".to_string()
                } else {
                    format!("cannot read: {e}")
                },
            }),
        }
    }
    let mut files: Vec<(String, PathBuf)> = files.into_iter().map(|f| (key(&f), f)).collect();
    files.dedup_by(|a, b| a.0 == b.0);
    for (path, f) in files {
        match std::fs::read(&f) {
            Ok(bytes) => match String::from_utf8(bytes) {
                Ok(text) => out.push(Input::File { path, text }),
                Err(e) => {
                    let at = e.utf8_error().valid_up_to();
                    out.push(Input::Problem {
                        path,
                        message: format!(
                            "not UTF-8 text (invalid byte at offset {at}): save the file as UTF-8"
                        ),
                    })
                }
            },
            Err(e) => out.push(Input::Problem { path, message: format!("cannot read: {e}") }),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::key;
    use std::path::Path;

    #[test]
    fn paths_are_named_the_same_way_however_given() {
        assert_eq!(key(Path::new("a//b.pddl")), "a/b.pddl");
        assert_eq!(key(Path::new("a/./b.pddl")), "a/b.pddl");
        assert_eq!(key(Path::new("./a/b.pddl")), "a/b.pddl");
        assert_eq!(key(Path::new("/x//y/")), "/x/y");
        assert_eq!(key(Path::new("b.pddl")), "b.pddl");
        assert_eq!(key(Path::new(".")), ".");
    }
}
