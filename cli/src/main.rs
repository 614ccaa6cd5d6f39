//! `hipop`: a thin shell over the analyzer. Reads files, asks the analyzer,
//! prints; all the language knowledge lives in `hipop-analyzer`.

mod check;
mod diff;
mod fmt;
mod inputs;
mod memory;
mod plan;
mod render;
mod repair;
mod snippet;
mod timeline;
mod validate;

use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

/// Parsing and checking allocate many small nodes on several threads, and
/// free some on another thread than the one that allocated them: mimalloc
/// does this with less work and far fewer system calls than the system
/// allocator (docs/benchmarks.md). Counted, so that the planner's memory
/// limit is the heap the process holds.
#[global_allocator]
static GLOBAL: hipop_analyzer::alloc::Counting<mimalloc::MiMalloc> =
    hipop_analyzer::alloc::Counting::new(mimalloc::MiMalloc);

/// Returns the memory the allocator holds free to the system at once
/// (mimalloc's `mi_collect(true)`). `hipop check` calls it once the syntax
/// trees are dropped: mimalloc keeps their pages, free, for its small
/// blocks, and returns them only after a delay longer than a check, while
/// the lints' grounding allocates large arrays it cannot place there, so
/// that the trees and the grounding both counted in the resident set
/// (docs/benchmarks.md).
pub(crate) fn return_free_memory() {
    // The function is in the mimalloc library linked above; the `mimalloc`
    // crate declares it only with its `extended` feature.
    unsafe extern "C" {
        fn mi_collect(force: bool);
    }
    // SAFETY: `mi_collect` takes a C `bool` (one byte, as Rust's), may be
    // called from any thread at any time, and only returns free memory.
    unsafe { mi_collect(true) }
}

/// Check multi-robot missions written in extended HTN-PDDL (PDDL 2.1 temporal
/// domains, HDDL hierarchical domains and the HiPOP extensions), and serve them
/// to editors.
#[derive(Debug, Parser)]
#[command(name = "hipop", version, about, long_about = None, arg_required_else_help = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Check domains and problems: syntax, names, arities, types, requirements.
    ///
    /// Each problem is checked against its domain, found by `(:domain name)` among
    /// the files given (a domain in the same folder is preferred).
    ///
    /// Exit status: 0 when no error is found (and no warning with `--deny warnings`),
    /// 1 when some are, 2 on a usage or I/O error (bad path, unreadable or non-UTF-8 file).
    Check(CheckArgs),
    /// Compare two plans of the same mission: actions removed, added and
    /// retimed, per agent, methods changed, and the stability figures.
    ///
    /// Plans may be in any format hipop reads (VAL, IPC 2020 hierarchical,
    /// timed hierarchical, JSON; docs/plan-formats.md), not necessarily the same.
    /// The HiPOP paper's instability counts the actions removed, added and
    /// retimed; Fox et al.'s distance |A∖B| + |B∖A| those removed and added.
    ///
    /// Exit status, like diff(1): 0 when the plans are the same, 1 when they
    /// differ, 2 on a usage, I/O or plan syntax error.
    Diff(DiffArgs),
    /// Validate plans against a domain and a problem, like VAL (PDDL 2.1
    /// temporal and sequential plans) and pandaPIparser's verifier
    /// (hierarchical plans).
    ///
    /// Plans may be in any format hipop reads (VAL, IPC 2020 hierarchical,
    /// timed hierarchical, JSON; docs/plan-formats.md). Each failure is
    /// reported at the step of the plan with what failed, why, and a hint
    /// (docs/validation-temporal.md). `--gantt` and `--svg FILE` draw the
    /// plan per agent, as a chart in the terminal or a picture (docs/plan-formats.md,
    /// "Timelines").
    ///
    /// Exit status: 0 when every plan is valid (with `--expect invalid`: when
    /// every plan is invalid), 1 when some plan is not, 2 on a usage or I/O
    /// error, a plan that cannot be read, a domain or problem with errors
    /// (PDDL+ processes and events among them), or a plan that needs what the
    /// validator does not check (E0421: no verdict).
    /// With several plans, the worst status; 2 too when the SVG picture
    /// cannot be written.
    Validate(ValidateArgs),
    /// Plan: run the HiPOP planner (hybrid partial-order and hierarchical
    /// planning, section 4 of the HiPOP paper) on a problem and write the plan.
    ///
    /// The plan goes to standard output (or `-o FILE`) in VAL's format, or in
    /// the IPC 2020 hierarchical format with hipop's timing annotations when it
    /// has abstract steps, or as hipop's JSON plan; a summary goes to standard
    /// error. Without a plan, the flaws of the best partial plan are reported
    /// where they are in the domain and the problem (docs/planner.md).
    ///
    /// Exit status: 0 a plan was found, 1 no plan exists with the allowed
    /// actions and the methods, 3 a limit was reached first, 2 a usage or
    /// input error (or a model with errors or constructs the planner does
    /// not support).
    Plan(PlanArgs),
    /// Repair a plan after a disruptive event (section 5 of the HiPOP paper):
    /// search again from what is left of the old plan for the new problem,
    /// removing more of it each time the search fails, a full replan last.
    ///
    /// PROBLEM is the problem after the event; OLD_PLAN the plan being
    /// executed, in any format hipop reads. Stage 1 removes the steps the
    /// new problem cannot have and those that support nothing; later stages
    /// remove rings of steps around them; abstract steps are un-refined as a
    /// whole (docs/repair.md). The steps that stay keep their old times
    /// where that delays the plan's end no further than the old steps ended
    /// and breaks no deadline. The report (standard error) gives each stage,
    /// the steps removed and why, and the stability figures of `hipop diff`.
    ///
    /// Exit status: 0 repaired, 1 no plan even after the full replan, 3 a
    /// limit reached, 2 on a usage or input error (a model with errors, an
    /// old plan that cannot be read).
    Repair(RepairArgs),
    /// Format domains and problems in place (docs/formatting.md).
    ///
    /// Folders are searched for `.pddl` and `.hddl` files, like `hipop check`
    /// does; a file is written only when formatting changes it. Comments,
    /// blank lines between elements and the case of names are kept; a file
    /// with a syntax error is not formatted (the error is reported at its
    /// place), nor is a plan. `hipop fmt -` formats standard input to standard
    /// output, for editors. A summary goes to standard error.
    ///
    /// Exit status: 0 when every file is formatted (or, with `--check`,
    /// already was), 1 with `--check` when some file would change, 2 on a
    /// usage or I/O error or a file with a syntax error.
    Fmt(FmtArgs),
    /// Run the language server on standard input and output (for editors).
    ///
    /// Exit status: 0 after the client's `exit` or the end of standard input,
    /// 2 on a usage error (such as a transport other than standard input and
    /// output) or an I/O error.
    Lsp(LspArgs),
}

/// The transports of the language server convention: clients add one of
/// `--stdio`, `--pipe=NAME`, `--socket=PORT` or `--node-ipc` to the server's
/// command line (vscode-languageclient does, by its `transport` option).
/// hipop serves standard input and output only: `--stdio` is accepted, the
/// others are refused with a message that says so rather than as unknown
/// arguments.
#[derive(Debug, clap::Args)]
struct LspArgs {
    /// Serve on standard input and output: the default and the only
    /// transport (language clients pass it).
    #[arg(long)]
    stdio: bool,
    /// Refused: a named pipe or Unix socket to connect to.
    #[arg(long, value_name = "NAME", hide = true)]
    pipe: Option<String>,
    /// Refused: a TCP port to connect to.
    #[arg(long, value_name = "PORT", hide = true)]
    socket: Option<String>,
    /// Refused: Node.js's IPC channel.
    #[arg(long = "node-ipc", hide = true)]
    node_ipc: bool,
}

impl LspArgs {
    /// The transport asked for other than standard input and output, as
    /// written on the command line.
    fn unsupported_transport(&self) -> Option<String> {
        if let Some(name) = &self.pipe {
            Some(format!("--pipe={name}"))
        } else if let Some(port) = &self.socket {
            Some(format!("--socket={port}"))
        } else if self.node_ipc {
            Some("--node-ipc".to_owned())
        } else {
            None
        }
    }
}

#[derive(Debug, clap::Args)]
struct FmtArgs {
    /// Files and folders to format; `-` formats standard input to standard output.
    #[arg(required = true, value_name = "PATH")]
    paths: Vec<std::path::PathBuf>,
    /// Write nothing: print each file that formatting would change
    /// (`Would reformat: PATH`) and exit with 1 if there is one.
    #[arg(long)]
    check: bool,
}

#[derive(Debug, clap::Args)]
struct PlanArgs {
    /// The domain file.
    domain: std::path::PathBuf,
    /// The problem file (its first problem is planned).
    problem: std::path::PathBuf,
    /// Write the plan to this file rather than to standard output.
    #[arg(short = 'o', long, value_name = "FILE")]
    output: Option<std::path::PathBuf>,
    /// How the plan is written.
    #[arg(long, value_enum, default_value_t = plan::PlanOutput::Auto)]
    format: plan::PlanOutput,
    /// The planner configuration, named like the paper's: dash-separated
    /// parts among `AR` (advance reuse) or `R` (reuse), `time`, `local`,
    /// `sorted` or `threatFirst` (open-link order), `motion` or `ncm`
    /// (geometric reasoning), `eager` (every threat as soon as it appears),
    /// `nolookahead` (A* without the greedy completion), `nosteps` (no open
    /// list ranked by plan size), `types` (position families of one key
    /// type: the `at` of trucks), `refine`, `front`, `greedy` or `links`
    /// (in purely hierarchical problems, refinements first, plans grown
    /// from their front like a progression planner's, the same with `h`
    /// weighing 20 rather than 5, or links first only; by default
    /// refinements first for 8,192 expansions and a quarter of the time,
    /// then from the front for a quarter, then greedily from the front for
    /// a quarter, then links first), `forward` or
    /// `noforward` (in problems without a hierarchy, the forward phase, a
    /// progression search, first, or not at all; by default after the
    /// partial-order search's first quarter of the time), `bare`
    /// (ignore abstract actions).
    /// `AR-time-local-motion-eager-nolookahead-nosteps` is the
    /// paper's search (docs/planner.md).
    #[arg(long, value_name = "NAME", default_value = hipop_analyzer::planner::Config::DEFAULT, value_parser = plan::parse_config)]
    config: hipop_analyzer::planner::Config,
    /// Stop after this many seconds, reading, checking and grounding the files
    /// included; the best plan found by then is written (exit status 3 when
    /// there is none).
    #[arg(long, value_name = "SECONDS", default_value = "60", value_parser = plan::parse_seconds)]
    time_limit: std::time::Duration,
    /// Stop after expanding this many partial plans.
    #[arg(long, value_name = "N")]
    node_limit: Option<u64>,
    /// Stop when the process holds more than this many mebibytes (its heap
    /// or its resident set, whichever is larger).
    #[arg(long, value_name = "MIB", default_value_t = 4096)]
    memory_limit: usize,
    /// Print progress (plans expanded, open list, best f) about every 100 ms,
    /// and each better plan as it is found.
    #[arg(long)]
    progress: bool,
    /// Return the first plan found. By default the search goes on within the
    /// time limit for plans of smaller makespan, until none left in the open
    /// list can do better, and writes the best.
    #[arg(long)]
    first: bool,
    /// Do not print the summary line.
    #[arg(short, long)]
    quiet: bool,
    /// Print the search statistics: plans expanded and generated, time,
    /// plans per second, ground operators, method instances, open list peak,
    /// the most steps of a plan expanded.
    #[arg(long)]
    stats: bool,
    /// The plan's timeline, one lane per agent (`--gantt` after the plan on
    /// standard output: use `-o FILE` to keep them apart; `--svg FILE`).
    #[command(flatten)]
    timeline: timeline::TimelineArgs,
    /// When to use colours in diagnostics.
    #[arg(long, value_enum, default_value_t = ColorWhen::Auto)]
    color: ColorWhen,
}

#[derive(Debug, clap::Args)]
struct RepairArgs {
    /// The domain file (after the event).
    domain: std::path::PathBuf,
    /// The problem file after the event (its first problem).
    problem: std::path::PathBuf,
    /// The plan being executed (VAL, hierarchical, timed hierarchical or JSON).
    old_plan: std::path::PathBuf,
    /// Write the repaired plan to this file rather than to standard output.
    #[arg(short = 'o', long, value_name = "FILE")]
    output: Option<std::path::PathBuf>,
    /// How the repaired plan is written.
    #[arg(long, value_enum, default_value_t = plan::PlanOutput::Auto)]
    format: plan::PlanOutput,
    /// Steps of the old plan that started before this time are executed or
    /// running: fixed at their times, never removed.
    #[arg(long, value_name = "T")]
    now: Option<f64>,
    /// The ids of steps executed (fixed, never removed), comma-separated.
    #[arg(long, value_name = "ID,...", value_delimiter = ',')]
    executed: Vec<u32>,
    /// Agents out of communication: their steps are frozen, never removed.
    #[arg(long, value_name = "AGENT,...", value_delimiter = ',')]
    unreachable: Vec<String>,
    /// repairFlat: discard the old plan's hierarchy, keep its actions.
    #[arg(long)]
    flat: bool,
    /// Also plan from scratch (same configuration and limits) and print the
    /// repair and the replan side by side: time, actions, makespan, instability.
    #[arg(long)]
    compare_replan: bool,
    /// The planner configuration (as for `hipop plan`).
    #[arg(long, value_name = "NAME", default_value = hipop_analyzer::planner::Config::DEFAULT, value_parser = plan::parse_config)]
    config: hipop_analyzer::planner::Config,
    /// Stop after this many seconds in all (each repair stage gets a quarter).
    #[arg(long, value_name = "SECONDS", default_value = "60", value_parser = plan::parse_seconds)]
    time_limit: std::time::Duration,
    /// Do not print the report.
    #[arg(short, long)]
    quiet: bool,
    /// Print the last search's statistics.
    #[arg(long)]
    stats: bool,
    /// When to use colours in diagnostics.
    #[arg(long, value_enum, default_value_t = ColorWhen::Auto)]
    color: ColorWhen,
}

#[derive(Debug, clap::Args)]
struct DiffArgs {
    /// The plan before (a repair, say).
    plan_a: std::path::PathBuf,
    /// The plan after.
    plan_b: std::path::PathBuf,
    /// The domain of the plans: groups the changes by agent, the `:agent`
    /// parameters of each action and task. Without it, steps have an unknown
    /// agent (JSON plans give theirs).
    #[arg(long, value_name = "FILE")]
    domain: Option<std::path::PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = diff::DiffFormat::Human)]
    format: diff::DiffFormat,
    /// The plans' format, when its detection from their content is not wanted.
    #[arg(long, value_enum, default_value_t = PlanFormatArg::Auto)]
    plan_format: PlanFormatArg,
    /// How much a start time or a duration may change before the step counts as retimed.
    #[arg(long, value_name = "DURATION", default_value_t = 0.001, value_parser = parse_tolerance)]
    tolerance: f64,
    /// Compare names like pandaPIparser's `-l`: `-` and `_` interchangeable
    /// (case is always ignored, as in PDDL).
    #[arg(long)]
    lenient: bool,
    /// When to use colours in diagnostics.
    #[arg(long, value_enum, default_value_t = ColorWhen::Auto)]
    color: ColorWhen,
}

#[derive(Debug, clap::Args)]
struct ValidateArgs {
    /// The domain file.
    domain: std::path::PathBuf,
    /// The problem file (its first problem is used).
    problem: std::path::PathBuf,
    /// One or more plan files.
    #[arg(required = true)]
    plans: Vec<std::path::PathBuf>,
    /// VAL's `-t`: events closer than a tenth of it are one happening, and a
    /// duration may miss its constraint by less than it.
    #[arg(short = 't', long, value_name = "DURATION", default_value_t = 0.01, value_parser = parse_tolerance)]
    tolerance: f64,
    /// Like pandaPIparser's `-l`: in names, `-` and `_` are interchangeable
    /// (case is always ignored, as in PDDL).
    #[arg(short = 'l', long)]
    lenient: bool,
    /// Like VAL's `-c`: keep executing after a failure to find the later ones
    /// (which may be consequences of the first).
    #[arg(short = 'c', long)]
    keep_going: bool,
    /// Like pandaPIparser's `-o`: in a hierarchical plan, a decomposition may
    /// list its subtasks in any order, not only one its method's ordering allows.
    #[arg(short = 'o', long)]
    ignore_listed_order: bool,
    /// The verdict the plans should have: `invalid` for regression suites of
    /// known-bad plans (exit 0 when each plan is invalid).
    #[arg(long, value_enum, default_value_t = validate::Expect::Valid)]
    expect: validate::Expect,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    format: Format,
    /// The plans' format, when its detection from their content is not wanted.
    #[arg(long, value_enum, default_value_t = PlanFormatArg::Auto)]
    plan_format: PlanFormatArg,
    /// When to use colours in human output.
    #[arg(long, value_enum, default_value_t = ColorWhen::Auto)]
    color: ColorWhen,
    #[command(flatten)]
    timeline: timeline::TimelineArgs,
}

/// A plan format, or its detection from the content.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum PlanFormatArg {
    Auto,
    /// VAL's `time: (action args) [duration]`, or a sequential plan.
    Val,
    /// IPC 2020 (`==>` … `root` … `<==`), with or without timing annotations.
    Hierarchical,
    /// hipop's JSON plan.
    Json,
}

impl PlanFormatArg {
    fn format(self) -> Option<hipop_analyzer::plan::PlanFormat> {
        use hipop_analyzer::plan::PlanFormat;
        match self {
            PlanFormatArg::Auto => None,
            PlanFormatArg::Val => Some(PlanFormat::Val),
            PlanFormatArg::Hierarchical => Some(PlanFormat::Hierarchical),
            PlanFormatArg::Json => Some(PlanFormat::Json),
        }
    }
}

#[derive(Debug, clap::Args)]
struct CheckArgs {
    /// Files or folders to check; folders are searched for `.pddl` and `.hddl` files.
    #[arg(default_value = ".")]
    paths: Vec<std::path::PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    format: Format,
    /// Treat warnings as errors for the exit status.
    #[arg(long, value_enum)]
    deny: Option<Deny>,
    /// Silence a diagnostic code for this run, by id (`W0310`) or name
    /// (`triangle-inequality`); repeatable. In a file, `; hipop-allow: CODE`
    /// silences one occurrence (see docs/lints.md).
    #[arg(long, value_name = "CODE", value_parser = parse_code)]
    allow: Vec<&'static hipop_analyzer::Code>,
    /// How much slower than a detour through another position a direct move may
    /// be before W0310 triangle-inequality is reported, in the unit of durations.
    #[arg(long, value_name = "DURATION", default_value_t = 0.01, value_parser = parse_tolerance)]
    triangle_tolerance: f64,
    /// After the diagnostics, explain what hipop found out about the model:
    /// `families` lists the position families of each problem (Definition 12
    /// of the HiPOP paper) with their move actions, and the candidates that
    /// are not families with the reason.
    #[arg(long, value_enum, value_name = "TOPIC")]
    explain: Option<Explain>,
    /// When to use colours in human output.
    #[arg(long, value_enum, default_value_t = ColorWhen::Auto)]
    color: ColorWhen,
    /// Apply the fixes of the diagnostics (the `help:` lines) to the files,
    /// then check again and report what remains. Fixes that would overlap one
    /// already applied are skipped (run again to apply them).
    #[arg(long)]
    fix: bool,
    /// Print at most this many diagnostics per file, errors first, then one
    /// (I0008) saying how many more there are; 0 prints them all. The
    /// summary and the exit status count them all.
    #[arg(long, value_name = "N", default_value_t = hipop_analyzer::diagnostic::SHOWN_PER_FILE)]
    max_diagnostics: usize,
}

/// How diagnostics are printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Compiler-style messages with source excerpts.
    Human,
    /// One JSON document (schema in docs/cli.md).
    Json,
    /// SARIF 2.1.0, for GitHub code scanning.
    Sarif,
    /// GitHub Actions workflow annotations.
    Github,
}

/// What `--explain` explains.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Explain {
    /// Position families and move actions, per problem.
    Families,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Deny {
    Warnings,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ColorWhen {
    Auto,
    Always,
    Never,
}

/// A code of the registry, by id or name.
fn parse_code(s: &str) -> Result<&'static hipop_analyzer::Code, String> {
    hipop_analyzer::codes::ALL
        .iter()
        .copied()
        .find(|c| c.id.eq_ignore_ascii_case(s) || c.name.eq_ignore_ascii_case(s))
        .ok_or_else(|| format!("`{s}` is not a diagnostic code (see docs/diagnostics.md and docs/lints.md)"))
}

fn parse_tolerance(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(t) if t.is_finite() && t >= 0.0 => Ok(t),
        _ => Err(format!("`{s}` is not a duration (a number, 0 or more)")),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Check(args) => {
            let options = check::Options {
                format: args.format,
                deny_warnings: args.deny == Some(Deny::Warnings),
                color: args.color,
                allow: args.allow,
                triangle_tolerance: args.triangle_tolerance,
                explain: args.explain,
                fix: args.fix,
                max_diagnostics: args.max_diagnostics,
            };
            ExitCode::from(check::run(&args.paths, &options))
        }
        Command::Diff(args) => {
            let options = diff::Options {
                format: args.format,
                color: args.color,
                domain: args.domain,
                plan_format: args.plan_format.format(),
                tolerance: args.tolerance,
                lenient: args.lenient,
            };
            ExitCode::from(diff::run(&args.plan_a, &args.plan_b, &options))
        }
        Command::Validate(args) => {
            let options = validate::Options {
                format: args.format,
                color: args.color,
                plan_format: args.plan_format.format(),
                validate: hipop_analyzer::validate::Options {
                    tolerance: args.tolerance,
                    lenient: args.lenient,
                    keep_going: args.keep_going,
                    ignore_listed_order: args.ignore_listed_order,
                },
                expect: args.expect,
                timeline: args.timeline,
            };
            ExitCode::from(validate::run(&args.domain, &args.problem, &args.plans, &options))
        }
        Command::Plan(args) => {
            let options = plan::Options {
                output: args.output,
                format: args.format,
                config: args.config,
                limits: hipop_analyzer::planner::PlannerLimits {
                    time: Some(args.time_limit),
                    nodes: args.node_limit,
                    memory: Some(args.memory_limit.saturating_mul(1 << 20)),
                    memory_in_use: Some(memory::in_use),
                    // The process exits once the plan is written.
                    exits_after: true,
                    first: args.first,
                    ..Default::default()
                },
                color: args.color,
                quiet: args.quiet,
                progress: args.progress,
                stats: args.stats,
                timeline: args.timeline,
            };
            ExitCode::from(plan::run(&args.domain, &args.problem, &options))
        }
        Command::Repair(args) => {
            let options = repair::Options {
                output: args.output,
                format: args.format,
                config: args.config,
                limits: hipop_analyzer::planner::PlannerLimits {
                    time: Some(args.time_limit),
                    memory_in_use: Some(memory::in_use),
                    ..Default::default()
                },
                repair: hipop_analyzer::repair::RepairOptions {
                    execution: repair::execution(args.now, args.executed, args.unreachable),
                    flat: args.flat,
                },
                color: args.color,
                quiet: args.quiet,
                stats: args.stats,
                compare_replan: args.compare_replan,
            };
            ExitCode::from(repair::run(&args.domain, &args.problem, &args.old_plan, &options))
        }
        Command::Fmt(args) => ExitCode::from(fmt::run(&args.paths, &fmt::Options { check: args.check })),
        Command::Lsp(args) => {
            if let Some(transport) = args.unsupported_transport() {
                let mut cli = <Cli as clap::CommandFactory>::command();
                cli.build();
                let lsp = cli.find_subcommand_mut("lsp").expect("the lsp subcommand exists");
                lsp.error(
                    clap::error::ErrorKind::ArgumentConflict,
                    format!(
                        "`{transport}`: hipop lsp serves only standard input and output (drop the argument, or pass `--stdio`)"
                    ),
                )
                .exit();
            }
            run_lsp()
        }
    }
}

fn run_lsp() -> ExitCode {
    match hipop_lsp::run_stdio() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("hipop lsp: {e}");
            ExitCode::from(2)
        }
    }
}
