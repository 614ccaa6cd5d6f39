//! `--gantt` and `--svg FILE`: a plan's per-agent timeline, drawn in the
//! terminal or written as a picture. The layout and the drawing are
//! `hipop_analyzer::plan::timeline`; this module holds the flags (shared by
//! the commands that read a plan and its domain) and writes the results.

use std::path::{Path, PathBuf};

use hipop_analyzer::plan::timeline::{GanttOptions, Timeline, gantt_text, svg, timeline};
use hipop_analyzer::plan::{NameMatching, PlanFormat};
use hipop_analyzer::{Analysis, Cancellable, SourceFile};

use crate::render::print_stdout;

/// The characters of the terminal chart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum GanttStyle {
    /// Box-drawing characters and blocks.
    Unicode,
    /// ASCII only, for terminals and logs without Unicode.
    Ascii,
}

/// The timeline flags, to `#[command(flatten)]` into a command's arguments.
#[derive(Debug, Clone, clap::Args)]
pub struct TimelineArgs {
    /// After the verdict, draw each plan as a Gantt chart on standard output:
    /// one lane per agent (the `:agent` parameters of the domain's actions
    /// and tasks; a step with two agents is in both lanes, steps without
    /// agents in a lane of their own), each step a bar from its start to its
    /// end labelled with a number, abstract steps as brackets above their
    /// subtasks, then a legend of every bar (step, start, end) and the
    /// makespan. The steps of a plan without times follow one another, one
    /// unit of the axis each.
    /// `--gantt=ascii` draws with ASCII characters only.
    #[arg(
        long,
        value_enum,
        value_name = "STYLE",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "unicode"
    )]
    pub gantt: Option<GanttStyle>,
    /// The width of the Gantt chart in columns, lane names included
    /// (default: the `COLUMNS` environment variable, else 100).
    #[arg(long, value_name = "COLUMNS", requires = "gantt")]
    pub gantt_width: Option<usize>,
    /// Write the plan's timeline as a standalone SVG picture to FILE: lanes
    /// per agent, a time axis, one box per step coloured by its action, with
    /// the step and its times as a tooltip. One plan only.
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
}

impl TimelineArgs {
    /// Whether a timeline is wanted at all.
    pub fn wanted(&self) -> bool {
        self.gantt.is_some() || self.svg.is_some()
    }

    /// A usage error, if the flags do not go with the command's other
    /// arguments: `plans` plan files, `human`: whether the output is for
    /// people (the chart would break JSON, SARIF or annotations).
    pub fn check(&self, plans: usize, human: bool) -> Result<(), String> {
        if self.gantt.is_some() && !human {
            return Err("`--gantt` draws for people: use it with `--format human` (the default)".into());
        }
        if self.svg.is_some() && plans != 1 {
            return Err(format!("`--svg FILE` draws one plan, and {plans} are given"));
        }
        Ok(())
    }

    fn gantt_options(&self) -> GanttOptions {
        let width = self
            .gantt_width
            .or_else(|| std::env::var("COLUMNS").ok()?.trim().parse().ok())
            .filter(|&w| w > 0)
            .unwrap_or(GanttOptions::DEFAULT_WIDTH);
        GanttOptions { width, ascii: self.gantt == Some(GanttStyle::Ascii) }
    }
}

/// The timeline of the plan in `plan` (read in `format`, or the format its
/// content shows), with the agents of the domain in `domain`.
pub fn layout(
    analysis: &Analysis,
    plan: SourceFile,
    format: Option<PlanFormat>,
    domain: SourceFile,
    matching: NameMatching,
) -> Cancellable<Timeline> {
    let agents = analysis.plan_agents(domain, matching)?;
    let plan = analysis.plan(plan, format)?;
    Ok(timeline(&plan, &agents))
}

/// Draws `timeline` as `args` asks: the Gantt chart on standard output,
/// under the title `title` (the plan's path), and the SVG picture to its
/// file. `Err` is the message of a file that cannot be written.
pub fn emit(args: &TimelineArgs, timeline: &Timeline, title: &str) -> Result<(), String> {
    if args.gantt.is_some() {
        let options = args.gantt_options();
        print_stdout(&format!("\n{title}\n{}", gantt_text(timeline, &options).trim_end()));
    }
    if let Some(path) = &args.svg {
        write(path, &svg(timeline))?;
    }
    Ok(())
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("{}: cannot write the SVG picture: {e}", path.display()))
}
