//! `hipop fmt`: formats domains and problems in place, checks that they are
//! formatted, or formats standard input to standard output.

use std::io::{Read, Write};
use std::path::PathBuf;

use hipop_analyzer::AnalysisHost;
use hipop_analyzer::ide::FormatErrorKind;

use crate::inputs::{Input, collect};

pub struct Options {
    /// Write nothing: list the files that would change.
    pub check: bool,
}

/// The 1-based line and column (in characters) of a byte offset.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (before.matches('\n').count() + 1, before[line_start..].chars().count() + 1)
}

/// Formats one file's text: the text and the formatted text, or why not.
fn format_text(host: &mut AnalysisHost, path: &str, text: String) -> Result<(String, String), String> {
    let file = host.set_file_text(path, text.clone());
    match host.analysis().format(file) {
        Ok(Ok(formatted)) => Ok((text, formatted)),
        Ok(Err(e)) => Err(match e.kind {
            FormatErrorKind::Syntax => {
                let (line, col) = line_col(&text, usize::from(e.range.start()));
                format!("{path}:{line}:{col}: error: not formatted: {}", e.message)
            }
            FormatErrorKind::NotAModel => format!("{path}: error: not formatted: {}", e.message),
        }),
        // Nothing writes to the database while the CLI reads it.
        Err(_) => Err(format!(
            "{path}: error: the analysis was interrupted; this is a bug in hipop, please report it"
        )),
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "file" } else { "files" }
}

/// Formats the files; returns the exit status.
pub fn run(paths: &[PathBuf], options: &Options) -> u8 {
    if paths.iter().any(|p| p.as_os_str() == "-") {
        if paths.len() > 1 {
            eprintln!("error: `-` (standard input) cannot be given with other paths");
            return 2;
        }
        return stdin(options);
    }
    let mut host = AnalysisHost::new();
    let (mut changed, mut unchanged, mut errors) = (0usize, 0usize, 0usize);
    for input in collect(paths) {
        let (path, text) = match input {
            Input::File { path, text } => (path, text),
            Input::Problem { path, message } => {
                eprintln!("{path}: error: {message}");
                errors += 1;
                continue;
            }
        };
        let (text, formatted) = match format_text(&mut host, &path, text.clone()) {
            Ok(f) => f,
            Err(message) => {
                eprintln!("{message}");
                errors += 1;
                continue;
            }
        };
        if formatted == text {
            unchanged += 1;
        } else if options.check {
            println!("Would reformat: {path}");
            changed += 1;
        } else if let Err(e) = std::fs::write(&path, &formatted) {
            eprintln!("{path}: error: cannot write: {e}");
            errors += 1;
        } else {
            changed += 1;
        }
    }
    let done = if options.check { "would be reformatted" } else { "reformatted" };
    let mut summary =
        format!("{changed} {} {done}, {unchanged} {} already formatted", plural(changed), plural(unchanged));
    if errors > 0 {
        summary.push_str(&format!(", {errors} {} with errors", plural(errors)));
    }
    eprintln!("{summary}");
    if errors > 0 {
        2
    } else if options.check && changed > 0 {
        1
    } else {
        0
    }
}

/// Formats standard input to standard output (what editors call).
fn stdin(options: &Options) -> u8 {
    let mut bytes = Vec::new();
    if let Err(e) = std::io::stdin().read_to_end(&mut bytes) {
        eprintln!("<stdin>: error: cannot read: {e}");
        return 2;
    }
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            let at = e.utf8_error().valid_up_to();
            eprintln!("<stdin>: error: not UTF-8 text (invalid byte at offset {at})");
            return 2;
        }
    };
    let mut host = AnalysisHost::new();
    let (text, formatted) = match format_text(&mut host, "<stdin>", text.clone()) {
        Ok(f) => f,
        Err(message) => {
            eprintln!("{message}");
            return 2;
        }
    };
    if options.check {
        if formatted == text {
            return 0;
        }
        println!("Would reformat: <stdin>");
        return 1;
    }
    let mut out = std::io::stdout().lock();
    if out.write_all(formatted.as_bytes()).and_then(|()| out.flush()).is_err() {
        return 2;
    }
    0
}
