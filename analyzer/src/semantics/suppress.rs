//! `; hipop-allow: CODE` comments: diagnostics the user chose to silence.
//!
//! - `; hipop-allow: W0310` at the end of a line silences the codes given on
//!   that line; alone on its line, on the next line;
//! - `; hipop-allow-file: W0310` silences them in the whole file.
//!
//! Codes are given by id (`W0310`) or name (`triangle-inequality`), separated by
//! commas or spaces. A `;` always starts a comment in PDDL, so the text is
//! scanned line by line, without the tree.

use rustc_hash::FxHashMap;

use crate::diagnostic::Diagnostic;

#[derive(Debug, Default)]
struct Allowed<'t> {
    file: Vec<&'t str>,
    /// 0-based line → codes.
    lines: FxHashMap<usize, Vec<&'t str>>,
}

fn allowed(text: &str) -> Allowed<'_> {
    let mut out = Allowed::default();
    if !text.contains("hipop-allow") {
        return out;
    }
    for (line, content) in text.lines().enumerate() {
        let Some(semi) = content.find(';') else { continue };
        let comment = content[semi..].trim_start_matches(';').trim_start();
        let (codes, target) = if let Some(rest) = comment.strip_prefix("hipop-allow-file:") {
            (rest, None)
        } else if let Some(rest) = comment.strip_prefix("hipop-allow:") {
            let alone = content[..semi].trim().is_empty();
            (rest, Some(if alone { line + 1 } else { line }))
        } else {
            continue;
        };
        let codes = codes.split([',', ' ', '\t']).map(str::trim).filter(|c| !c.is_empty());
        match target {
            None => out.file.extend(codes),
            Some(l) => out.lines.entry(l).or_default().extend(codes),
        }
    }
    out
}

/// Removes the diagnostics of `text`'s file that its comments silence.
pub(crate) fn apply(text: &str, diagnostics: &mut Vec<Diagnostic>) {
    let allowed = allowed(text);
    if allowed.file.is_empty() && allowed.lines.is_empty() {
        return;
    }
    let matches = |codes: &[&str], d: &Diagnostic| {
        codes.iter().any(|c| c.eq_ignore_ascii_case(d.code.id) || c.eq_ignore_ascii_case(d.code.name))
    };
    // Diagnostics are sorted by start: count lines with one cursor.
    let (mut at, mut line) = (0, 0);
    diagnostics.retain(|d| {
        if matches(&allowed.file, d) {
            return false;
        }
        let start = usize::from(d.range.start()).min(text.len());
        if start < at {
            (at, line) = (0, 0);
        }
        line += text.as_bytes()[at..start].iter().filter(|&&b| b == b'\n').count();
        at = start;
        !allowed.lines.get(&line).is_some_and(|codes| matches(codes, d))
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_are_read() {
        let a = allowed(
            "(p) ; hipop-allow: W0310, dead-action\n  ; hipop-allow: E0102\n(q)\n; hipop-allow-file: W0201\n",
        );
        assert_eq!(a.lines[&0], ["W0310", "dead-action"]);
        assert_eq!(a.lines[&2], ["E0102"]);
        assert_eq!(a.file, ["W0201"]);
    }

    fn codes(text: &str) -> Vec<&'static str> {
        let mut host = crate::AnalysisHost::new();
        let f = host.set_file_text("d.pddl", text);
        host.analysis().diagnostics(f).unwrap().iter().map(|d| d.code.id).collect()
    }

    #[test]
    fn an_occurrence_is_silenced_on_its_line_or_from_the_line_above() {
        let base = "(define (domain d) (:predicates\n  (p)\n  (q)))\n";
        assert_eq!(codes(base), ["W0201", "W0201"]);
        let same_line = base.replace("(p)", "(p) ; hipop-allow: W0201");
        assert_eq!(codes(&same_line), ["W0201"]);
        let above = base.replace("  (q)", "  ; hipop-allow: unused-declaration\n  (q)");
        assert_eq!(codes(&above), ["W0201"]);
        let other = base.replace("(p)", "(p) ; hipop-allow: W0202");
        assert_eq!(codes(&other), ["W0201", "W0201"]);
    }
}
