//! `hipop validate DOMAIN PROBLEM PLAN...`: does each plan solve the problem?
//! The validation is `hipop_analyzer::validate`; this module reads the files,
//! prints the verdicts and the diagnostics, and computes the exit status.

use std::path::{Path, PathBuf};

use hipop_analyzer::plan::{NameMatching, PlanFormat};
use hipop_analyzer::validate::{Options as ValidateOptions, Validation};
use hipop_analyzer::{AnalysisHost, Code, Diagnostic, Severity, SourceFile, codes};
use serde_json::{Value, json};

use crate::render::{Rendered, Sources, print_stdout};
use crate::{ColorWhen, Format};
use hipop_analyzer::diagnostic::SHOWN_PER_FILE;

/// Which verdict a run expects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Expect {
    /// The plans solve the problem (exit 0 when they do).
    Valid,
    /// The plans do not (exit 0 when each is invalid): regression suites of known-bad plans.
    Invalid,
}

pub struct Options {
    pub format: Format,
    pub color: ColorWhen,
    pub plan_format: Option<PlanFormat>,
    pub validate: ValidateOptions,
    pub expect: Expect,
    /// `--gantt`, `--svg FILE`.
    pub timeline: crate::timeline::TimelineArgs,
}

/// The outcome of one plan.
enum Verdict {
    Valid,
    Invalid,
    /// Not validated: unreadable file, or plan syntax errors.
    Unreadable,
    /// Read, but validation stopped before a verdict at what it does not
    /// check (E0421) or a model it cannot validate against (E0422).
    NotJudged(&'static Code),
}

impl Verdict {
    fn as_str(&self) -> &'static str {
        match self {
            Verdict::Valid => "valid",
            Verdict::Invalid => "invalid",
            Verdict::Unreadable => "unreadable",
            Verdict::NotJudged(c) if *c == codes::UNSUPPORTED_IN_PLAN => "unsupported",
            Verdict::NotJudged(_) => "not-validated",
        }
    }
}

struct PlanResult {
    path: String,
    file: Option<SourceFile>,
    verdict: Verdict,
    validation: Option<Validation>,
    io_error: Option<String>,
}

/// Validates every plan; returns the worst exit status: 0 every plan has the
/// expected verdict, 1 some has not, 2 a usage, I/O or parse error.
pub fn run(domain: &Path, problem: &Path, plans: &[PathBuf], options: &Options) -> u8 {
    if let Err(m) = options.timeline.check(plans.len(), options.format == Format::Human) {
        eprintln!("error: {m}");
        return 2;
    }
    let mut host = AnalysisHost::new();
    host.set_plan_options(options.validate);
    let mut io_errors: Vec<(String, String)> = Vec::new();
    let mut load = |host: &mut AnalysisHost, path: &Path, what: &str| match crate::diff::read(path, what) {
        Ok(text) => Some(host.set_file_text(&crate::inputs::key(path), text)),
        Err(m) => {
            io_errors.push((path.display().to_string(), m));
            None
        }
    };
    let fd = load(&mut host, domain, "a domain file");
    let fp = load(&mut host, problem, "a problem file");
    let plan_files: Vec<(PathBuf, Option<SourceFile>)> =
        plans.iter().map(|p| (p.clone(), load(&mut host, p, "a plan file"))).collect();
    let (Some(fd), Some(fp)) = (fd, fp) else {
        io_errors.iter().for_each(|(_, m)| eprintln!("error: {m}"));
        return 2;
    };
    let analysis = host.analysis();
    let interrupted = |_: hipop_analyzer::Cancelled| {
        eprintln!("error: the analysis was interrupted; this is a bug in hipop, please report it");
        2u8
    };

    // The model first: a plan is only validated against a model without errors.
    let mut model = match (analysis.check_diagnostics(fd), analysis.check_diagnostics(fp)) {
        (Ok(mut d), Ok(p)) => {
            d.extend(p);
            d
        }
        (Err(e), _) | (_, Err(e)) => return interrupted(e),
    };
    model.retain(|d| d.severity == Severity::Error);
    let model_files = [fd, fp];
    if !model.is_empty() {
        let sources = Sources::new(&analysis, &model_files);
        let rendered = Rendered {
            sources: &sources,
            diagnostics: &model,
            io_errors: &[],
            files: 2,
            max_per_file: SHOWN_PER_FILE,
        };
        let mut stream = crate::render::stderr(options.color);
        rendered.emit_human(&mut stream);
        let _ = std::io::Write::flush(&mut stream);
        eprintln!("error: the domain or the problem has errors: fix them before validating plans");
        return 2;
    }

    let mut results = Vec::new();
    let mut diagnostics: Vec<Diagnostic> = Vec::new();
    for (path, file) in &plan_files {
        let shown = path.display().to_string();
        let Some(file) = *file else {
            let io_error = io_errors.iter().find(|(p, _)| *p == shown).map(|(_, m)| m.clone());
            results.push(PlanResult {
                path: shown,
                file: None,
                verdict: Verdict::Unreadable,
                validation: None,
                io_error,
            });
            continue;
        };
        let validation = match analysis.validate_plan(file, options.plan_format, fp, &options.validate) {
            Ok(Some(v)) => v,
            Ok(None) => {
                eprintln!("error: {}: no `(define (problem …) …)` in this file", problem.display());
                return 2;
            }
            Err(e) => return interrupted(e),
        };
        let verdict = if !validation.checked {
            Verdict::Unreadable
        } else if let Some(code) = validation.not_judged {
            Verdict::NotJudged(code)
        } else if validation.valid {
            Verdict::Valid
        } else {
            Verdict::Invalid
        };
        diagnostics.extend(validation.diagnostics.iter().cloned());
        results.push(PlanResult {
            path: shown,
            file: Some(file),
            verdict,
            validation: Some(validation),
            io_error: None,
        });
    }

    let mut files: Vec<SourceFile> = model_files.to_vec();
    files.extend(plan_files.iter().filter_map(|(_, f)| *f));
    let sources = Sources::new(&analysis, &files);
    let plan_io: Vec<(String, String)> =
        results.iter().filter_map(|r| r.io_error.clone().map(|m| (r.path.clone(), m))).collect();
    let rendered = Rendered {
        sources: &sources,
        diagnostics: &diagnostics,
        io_errors: &plan_io,
        files: plans.len(),
        max_per_file: SHOWN_PER_FILE,
    };
    match options.format {
        Format::Human => {
            let mut stream = crate::render::stderr(options.color);
            rendered.emit_human(&mut stream);
            let _ = std::io::Write::flush(&mut stream);
            for r in &results {
                eprintln!("{}", summary_line(r, options.expect));
            }
        }
        Format::Json => {
            let doc = json!({
                "version": 1,
                "expect": match options.expect { Expect::Valid => "valid", Expect::Invalid => "invalid" },
                "tolerance": options.validate.tolerance,
                "plans": results.iter().map(plan_json).collect::<Vec<_>>(),
                "diagnostics": rendered.json_diagnostics(),
            });
            print_stdout(&serde_json::to_string_pretty(&doc).unwrap_or_default());
        }
        Format::Sarif => rendered.sarif(),
        Format::Github => rendered.github(),
    }
    let mut worst = results.iter().map(|r| status(&r.verdict, options.expect)).max().unwrap_or(0);
    if options.timeline.wanted() {
        let matching =
            if options.validate.lenient { NameMatching::Lenient } else { NameMatching::CaseInsensitive };
        for r in &results {
            // Valid or not, a plan that was read is drawn: the chart shows what it says.
            let (Some(file), Some(true)) = (r.file, r.validation.as_ref().map(|v| v.checked)) else {
                eprintln!("{}: not drawn: the plan cannot be read", r.path);
                continue;
            };
            let drawn = match crate::timeline::layout(&analysis, file, options.plan_format, fd, matching) {
                Ok(timeline) => crate::timeline::emit(&options.timeline, &timeline, &r.path),
                Err(e) => return interrupted(e),
            };
            if let Err(m) = drawn {
                eprintln!("error: {m}");
                worst = 2;
            }
        }
    }
    worst
}

/// 0 the expected verdict, 1 the other, 2 not validated.
fn status(verdict: &Verdict, expect: Expect) -> u8 {
    match (verdict, expect) {
        (Verdict::Unreadable | Verdict::NotJudged(_), _) => 2,
        (Verdict::Valid, Expect::Valid) | (Verdict::Invalid, Expect::Invalid) => 0,
        _ => 1,
    }
}

fn summary_line(r: &PlanResult, expect: Expect) -> String {
    let errors = |v: &Validation| v.diagnostics.iter().filter(|d| d.severity == Severity::Error).count();
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    let expected = match (&r.verdict, expect) {
        (Verdict::Invalid, Expect::Invalid) => " (as expected)",
        (Verdict::Valid, Expect::Invalid) => " (expected invalid)",
        _ => "",
    };
    match (&r.verdict, &r.validation) {
        (Verdict::Valid, Some(v)) => format!(
            "{}: valid{expected}: makespan {}, value {}",
            r.path,
            v.makespan.map_or("?".into(), |m| format!("{m:.3}")),
            v.value.map_or("?".into(), |m| format!("{m:.3}"))
        ),
        (Verdict::Invalid, Some(v)) => {
            let n = errors(v);
            format!("{}: invalid{expected}: {n} error{}", r.path, plural(n))
        }
        (Verdict::NotJudged(code), Some(_)) => {
            let why = if *code == codes::UNSUPPORTED_IN_PLAN {
                "it needs what the validator does not check"
            } else {
                "the domain or the problem cannot be validated against"
            };
            format!("{}: not validated: {why} ({})", r.path, code.id)
        }
        (_, Some(v)) => {
            let n = errors(v);
            format!("{}: not validated: the plan cannot be read ({n} error{})", r.path, plural(n))
        }
        (_, None) => {
            format!("{}: not validated: {}", r.path, r.io_error.as_deref().unwrap_or("cannot be read"))
        }
    }
}

fn plan_json(r: &PlanResult) -> Value {
    json!({
        "path": r.path,
        "verdict": r.verdict.as_str(),
        "makespan": r.validation.as_ref().and_then(|v| v.makespan),
        "value": r.validation.as_ref().and_then(|v| v.value),
        "errors": r.validation.as_ref().map_or(0, |v| v.diagnostics.iter().filter(|d| d.severity == Severity::Error).count()),
        "io_error": r.io_error,
    })
}
