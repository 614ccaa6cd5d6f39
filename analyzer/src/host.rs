//! The entry point for the CLI and the server: an [`AnalysisHost`] owns the
//! database and applies changes; an [`Analysis`] is a snapshot that answers
//! questions, and is cancelled when a change is applied.

use std::panic::{AssertUnwindSafe, UnwindSafe};
use std::sync::Arc;

use rustc_hash::FxHashMap;
use salsa::Setter;

use crate::db::{ReparseHint, RootDatabase, Settings, SourceFile, Workspace, parse};
use crate::diagnostic::Diagnostic;
use crate::plan::agents::AgentTable;
use crate::plan::{NameMatching, Plan, PlanFormat};
use crate::syntax::{TextEdit, TextSize};

/// What a repair gives (`hipop repair`).
pub struct RepairResult {
    pub status: crate::planner::Status,
    /// The stage that found the plan.
    pub stage: Option<crate::repair::Stage>,
    pub plan: Option<crate::planner::output::SolvedPlan>,
    /// The old plan's steps, as read against the new problem.
    pub old: Vec<crate::repair::OldStep>,
    pub removed: Vec<crate::repair::Removed>,
    pub stages: Vec<crate::repair::StageRun>,
    /// The goals dropped: meetings that could not be kept.
    pub dropped: Vec<crate::repair::DroppedGoal>,
    pub stats: crate::planner::Stats,
    /// Why there is no plan, located in the domain and the problem.
    pub diagnostics: Vec<Diagnostic>,
}

/// What [`Analysis::run_planner`] found.
#[derive(Debug, Clone)]
pub struct PlanningResult {
    pub status: crate::planner::Status,
    pub plan: Option<crate::planner::output::SolvedPlan>,
    pub stats: crate::planner::Stats,
    /// Why there is no plan (E0501, I0504–I0506), in the domain and the problem.
    pub diagnostics: Vec<Diagnostic>,
}

impl PlanningResult {
    /// The run as an editor keeps it, given the time limit it had, and
    /// what the planner said of the problem.
    pub fn into_run(self, time_limit: Option<std::time::Duration>) -> (crate::ide::PlanRun, Vec<Diagnostic>) {
        let run = crate::ide::PlanRun {
            status: self.status,
            plan: self.plan,
            stats: self.stats,
            time_limit,
            flaws: self.diagnostics.len(),
            repair: None,
        };
        (run, self.diagnostics)
    }
}

/// A request was cancelled by a newer change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cancelled;

pub type Cancellable<T> = Result<T, Cancelled>;

/// Owns the database; the only place where inputs change.
#[derive(Default)]
pub struct AnalysisHost {
    db: RootDatabase,
    files: FxHashMap<String, SourceFile>,
    workspace: Option<Workspace>,
    settings: Option<Settings>,
    /// An empty file outside the workspace, whose tree is the one
    /// [`AnalysisHost::release_syntax`] keeps.
    empty: Option<SourceFile>,
}

impl AnalysisHost {
    pub fn new() -> AnalysisHost {
        AnalysisHost::default()
    }

    /// A host whose database reports salsa events (for incrementality tests).
    pub fn with_event_callback(callback: Box<dyn Fn(salsa::Event) + Send + Sync + 'static>) -> AnalysisHost {
        AnalysisHost { db: RootDatabase::with_event_callback(callback), ..AnalysisHost::default() }
    }

    /// Sets the tolerance of the triangle-inequality lint (W0310); negative
    /// or non-finite values are replaced by the default.
    pub fn set_triangle_tolerance(&mut self, tolerance: f64) {
        let tolerance = if tolerance.is_finite() && tolerance >= 0.0 {
            tolerance
        } else {
            Settings::DEFAULT_TRIANGLE_TOLERANCE
        };
        let s = self.settings();
        if s.triangle_tolerance(&self.db) != tolerance {
            s.set_triangle_tolerance(&mut self.db).to(tolerance);
        }
    }

    /// Sets how plan files of the workspace are validated (VAL's tolerance,
    /// lenient names); a negative or non-finite tolerance is replaced by the default.
    pub fn set_plan_options(&mut self, mut options: crate::input::ValidationOptions) {
        if !(options.tolerance.is_finite() && options.tolerance >= 0.0) {
            options.tolerance = crate::input::ValidationOptions::DEFAULT_TOLERANCE;
        }
        let s = self.settings();
        if s.plan_options(&self.db) != options {
            s.set_plan_options(&mut self.db).to(options);
        }
    }

    /// The settings input, created with the defaults the first time.
    fn settings(&mut self) -> Settings {
        *self.settings.get_or_insert_with(|| {
            Settings::new(
                &self.db,
                Settings::DEFAULT_TRIANGLE_TOLERANCE,
                crate::input::ValidationOptions::default(),
                true,
            )
        })
    }

    pub fn file(&self, path: &str) -> Option<SourceFile> {
        self.files.get(path).copied()
    }

    fn sync_workspace(&mut self) {
        let mut files: Vec<SourceFile> = self.files.values().copied().collect();
        files.sort_by_key(|f| f.path(&self.db).clone());
        match self.workspace {
            Some(ws) => {
                if ws.files(&self.db) != &files {
                    ws.set_files(&mut self.db).to(files);
                }
            }
            None => self.workspace = Some(Workspace::new(&self.db, files)),
        }
    }

    /// Adds a file, or replaces its whole text.
    pub fn set_file_text(&mut self, path: &str, text: impl Into<Arc<str>>) -> SourceFile {
        let text = text.into();
        match self.files.get(path).copied() {
            Some(file) => {
                if **file.text(&self.db) != *text {
                    file.set_text(&mut self.db).to(text);
                    file.set_reparse_hint(&mut self.db).to(None);
                }
                file
            }
            None => {
                let file = SourceFile::new(&self.db, path.to_string(), text, None);
                self.files.insert(path.to_string(), file);
                self.sync_workspace();
                file
            }
        }
    }

    /// Applies edits (in order, each relative to the text after the previous
    /// ones) to a file, re-parsing incrementally. Returns the new text.
    pub fn apply_edits(&mut self, path: &str, edits: Vec<TextEdit>) -> Option<Arc<str>> {
        let file = self.files.get(path).copied()?;
        let base = parse(&self.db, file).clone();
        let mut text = file.text(&self.db).to_string();
        for e in &edits {
            let (start, end) = (usize::from(e.range.start()), usize::from(e.range.end()));
            if start > end || end > text.len() || !text.is_char_boundary(start) || !text.is_char_boundary(end)
            {
                return None;
            }
            e.apply(&mut text);
        }
        let text: Arc<str> = text.into();
        file.set_text(&mut self.db).to(text.clone());
        file.set_reparse_hint(&mut self.db).to(Some(Arc::new(ReparseHint { base, edits })));
        Some(text)
    }

    pub fn remove_file(&mut self, path: &str) {
        if self.files.remove(path).is_some() {
            self.sync_workspace();
        }
    }

    pub fn files(&self) -> impl Iterator<Item = (&str, SourceFile)> {
        self.files.iter().map(|(p, f)| (p.as_str(), *f))
    }

    /// For a database that checks its files once (the command line): items
    /// hold the path to their syntax, not the syntax, and the syntax trees
    /// of the files can be dropped once the items are lowered
    /// ([`AnalysisHost::release_syntax`]). Call before the first question:
    /// salsa's LRU counts only the uses it sees after this. The language
    /// server keeps every tree (re-parsing after an edit starts from the
    /// old one) and items that hold their syntax (an edit then compares
    /// each item's node with the old one, with no query per item).
    pub fn drop_syntax_after_use(&mut self) {
        crate::db::set_syntax_lru_capacity(&mut self.db, 1);
        let s = self.settings();
        if s.syntax_in_items(&self.db) {
            s.set_syntax_in_items(&mut self.db).to(false);
        }
    }

    /// After [`AnalysisHost::drop_syntax_after_use`], drops the syntax trees
    /// read so far: the checks, once run, have lowered every item, and the
    /// lints read the lowered models, not the syntax (a question that needs
    /// a tree again parses its file again). salsa evicts at the start of a
    /// revision and keeps the most recently used value of each query: an
    /// empty file's tree, and one item's syntax (a section, or one group of
    /// an `:init`). The memos stay valid: nothing is computed again that
    /// does not need a tree.
    pub fn release_syntax(&mut self) {
        use salsa::Database;
        let empty =
            *self.empty.get_or_insert_with(|| SourceFile::new(&self.db, String::new(), Arc::from(""), None));
        parse(&self.db, empty);
        self.db.synthetic_write(salsa::Durability::LOW);
    }

    /// A snapshot to answer questions, possibly on another thread.
    pub fn analysis(&self) -> Analysis {
        Analysis { db: self.db.clone() }
    }

    /// Cancels every running query on snapshots (they return `Err(Cancelled)`).
    pub fn request_cancellation(&mut self) {
        use salsa::Database;
        self.db.trigger_cancellation();
    }

    pub fn db(&self) -> &RootDatabase {
        &self.db
    }
}

/// A snapshot of the database.
#[derive(Clone)]
pub struct Analysis {
    db: RootDatabase,
}

impl Analysis {
    /// Runs `f`, turning salsa's cancellation unwinding into `Err(Cancelled)`.
    pub fn with_db<T>(&self, f: impl FnOnce(&RootDatabase) -> T + UnwindSafe) -> Cancellable<T> {
        let db = AssertUnwindSafe(&self.db);
        salsa::Cancelled::catch(move || f(*db)).map_err(|_| Cancelled)
    }

    /// A handle that cancels this snapshot's running query.
    pub fn cancellation_token(&self) -> salsa::CancellationToken {
        use salsa::Database;
        self.db.cancellation_token()
    }

    /// Every diagnostic of a file: the checks and the model-verification lints.
    pub fn diagnostics(&self, file: SourceFile) -> Cancellable<Vec<Diagnostic>> {
        self.warm_up(file)?;
        self.with_db(|db| crate::ide::diagnostics::file_diagnostics(db, file).clone())
    }

    /// Parses `file` and finds its units and items, which every question
    /// about it reads first. The command line does this for every file
    /// before checking any, so that the memory parsing frees (the lexer's
    /// tokens, the parser's working memory, much of it on other threads)
    /// can be returned to the system before the checks allocate theirs.
    pub fn parse_file(&self, file: SourceFile) -> Cancellable<()> {
        self.with_db(|db| {
            crate::db::file_units(db, file);
        })
    }

    /// The diagnostics of the syntax and semantic checks only: what the
    /// language server publishes first, while the lints (which may ground a
    /// large problem) are computed.
    pub fn check_diagnostics(&self, file: SourceFile) -> Cancellable<Vec<Diagnostic>> {
        self.warm_up(file)?;
        self.with_db(|db| crate::ide::diagnostics::file_check_diagnostics(db, file).clone())
    }

    /// Checks the items of a large file on every core before collecting its
    /// diagnostics. Each thread has its own database handle (salsa's rule);
    /// results land in the shared memo tables.
    fn warm_up(&self, file: SourceFile) -> Cancellable<()> {
        // Below this much text, starting threads costs more than it saves.
        const PARALLEL_FROM_BYTES: usize = 64 * 1024;
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(8);
        let items = self.with_db(|db| {
            let units = crate::db::file_units(db, file);
            // The domain's symbols are shared by every check: compute them once, first.
            for &u in units {
                if let Some(d) = crate::semantics::check::domain_for(db, u) {
                    crate::semantics::symbols::domain_symbols(db, d);
                }
            }
            units.iter().map(|u| u.items(db).len()).sum::<usize>()
        })?;
        let bytes = self.with_db(|db| file.text(db).len())?;
        if threads < 2 || items < 2 || bytes < PARALLEL_FROM_BYTES {
            return Ok(());
        }
        let share = |db: &RootDatabase, t: usize| {
            let units = crate::db::file_units(db, file);
            let all = units.iter().flat_map(|u| u.items(db).iter().copied());
            for item in all.skip(t).step_by(threads) {
                crate::semantics::check::check_item(db, item);
            }
        };
        std::thread::scope(|scope| {
            for t in 1..threads {
                let db = self.db.clone();
                scope.spawn(move || {
                    // A cancelled warm-up is harmless: the caller's own query unwinds too.
                    let _ = salsa::Cancelled::catch(AssertUnwindSafe(|| share(&db, t)));
                });
            }
            // This thread takes the first share.
            self.with_db(|db| share(db, 0))
        })
    }

    /// `hipop check --explain families`: the position families of each
    /// problem of the file, as text.
    pub fn explain_families(&self, file: SourceFile) -> Cancellable<Vec<String>> {
        self.with_db(|db| {
            crate::db::file_units(db, file)
                .iter()
                .filter(|u| u.kind(db) == crate::db::UnitKind::Problem)
                .map(|&u| crate::verify::families::explain(db, u))
                .collect()
        })
    }

    pub fn document_symbols(&self, file: SourceFile) -> Cancellable<Vec<crate::ide::DocumentSymbol>> {
        self.with_db(|db| crate::ide::document_symbols(db, file))
    }

    /// The declarations of the workspace matching `query` (`workspace/symbol`).
    pub fn workspace_symbols(&self, query: &str) -> Cancellable<Vec<crate::ide::WorkspaceSymbol>> {
        self.with_db(|db| crate::ide::workspace_symbols(db, query))
    }

    pub fn hover(&self, file: SourceFile, offset: TextSize) -> Cancellable<Option<crate::ide::HoverResult>> {
        self.with_db(|db| crate::ide::hover(db, file, offset))
    }

    pub fn goto_definition(
        &self,
        file: SourceFile,
        offset: TextSize,
    ) -> Cancellable<Option<crate::ide::NavTarget>> {
        self.with_db(|db| crate::ide::goto_definition(db, file, offset))
    }

    pub fn references(
        &self,
        file: SourceFile,
        offset: TextSize,
        include_declaration: bool,
    ) -> Cancellable<Vec<crate::ide::NavTarget>> {
        self.with_db(|db| crate::ide::references(db, file, offset, include_declaration))
    }

    pub fn document_highlights(
        &self,
        file: SourceFile,
        offset: TextSize,
    ) -> Cancellable<Vec<crate::ide::Highlight>> {
        self.with_db(|db| crate::ide::document_highlights(db, file, offset))
    }

    /// The name at `offset` a rename would change, and its text; why not.
    pub fn prepare_rename(
        &self,
        file: SourceFile,
        offset: TextSize,
    ) -> Cancellable<Result<(rowan::TextRange, String), crate::ide::RenameError>> {
        self.with_db(|db| crate::ide::prepare_rename(db, file, offset))
    }

    /// Where to write `new_name` to rename the name at `offset`, in every
    /// file of its domain; why not.
    pub fn rename(
        &self,
        file: SourceFile,
        offset: TextSize,
        new_name: &str,
    ) -> Cancellable<Result<Vec<crate::ide::NavTarget>, crate::ide::RenameError>> {
        self.with_db(|db| crate::ide::rename(db, file, offset, new_name))
    }

    /// The code actions for `range` of `file` beyond the diagnostics' fixes.
    pub fn code_actions(
        &self,
        file: SourceFile,
        range: rowan::TextRange,
    ) -> Cancellable<Vec<crate::ide::CodeAction>> {
        self.with_db(|db| crate::ide::code_actions(db, file, range))
    }

    /// The file formatted (docs/formatting.md); why not: a syntax error, a
    /// plan file (only domains and problems are formatted).
    pub fn format(&self, file: SourceFile) -> Cancellable<Result<String, crate::ide::FormatError>> {
        self.with_db(|db| {
            if crate::db::is_plan_file(db, file) {
                return Err(crate::ide::FormatError {
                    kind: crate::ide::FormatErrorKind::NotAModel,
                    range: rowan::TextRange::empty(0.into()),
                    message: "a plan: only domains and problems are formatted".to_string(),
                });
            }
            crate::ide::format_parse(parse(db, file))
        })
    }

    /// The completions at `offset` of `file`, best first.
    pub fn completions(
        &self,
        file: SourceFile,
        offset: TextSize,
    ) -> Cancellable<Vec<crate::ide::Completion>> {
        self.with_db(|db| crate::ide::completions(db, file, offset))
    }

    /// The semantic tokens of `file`, in order.
    pub fn semantic_tokens(&self, file: SourceFile) -> Cancellable<Vec<crate::ide::HighlightToken>> {
        self.with_db(|db| crate::ide::semantic_tokens(db, file))
    }

    pub fn folding_ranges(&self, file: SourceFile) -> Cancellable<Vec<crate::ide::Fold>> {
        self.with_db(|db| crate::ide::folding_ranges(db, file))
    }

    pub fn file_text(&self, file: SourceFile) -> Cancellable<Arc<str>> {
        self.with_db(|db| file.text(db).clone())
    }

    pub fn file_path(&self, file: SourceFile) -> Cancellable<String> {
        self.with_db(|db| file.path(db).clone())
    }

    /// The plan in a file, read in `format`, or in the format its content
    /// shows (docs/plan-formats.md).
    pub fn plan(&self, file: SourceFile, format: Option<PlanFormat>) -> Cancellable<Plan> {
        self.with_db(|db| match format {
            Some(f) => crate::plan::parse_plan_as(db, file, f).clone(),
            None => crate::plan::parse_plan(db, file).clone(),
        })
    }

    /// Validates the plan in `plan` (read in `format`, or the format its
    /// content shows) against the first problem of the file `problem`, and
    /// that problem's domain. `None` when that file has no problem.
    pub fn validate_plan(
        &self,
        plan: SourceFile,
        format: Option<PlanFormat>,
        problem: SourceFile,
        options: &crate::input::ValidationOptions,
    ) -> Cancellable<Option<crate::validate::Validation>> {
        self.with_db(|db| {
            let unit = first_problem(db, problem)?;
            Some(crate::validate::validate_plan(db, plan, format, unit, options))
        })
    }

    /// Runs the HiPOP planner on the first problem of the file `problem`.
    /// `None` when that file has no problem. `cancel` is polled during the
    /// search (the language server sets it on every edit); `progress` is
    /// called about every 100 ms.
    pub fn run_planner(
        &self,
        problem: SourceFile,
        config: &crate::planner::Config,
        limits: &crate::planner::PlannerLimits,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&crate::planner::Progress),
    ) -> Cancellable<Option<PlanningResult>> {
        let db = &self.db;
        let run = AssertUnwindSafe(move || {
            // The time limit counts the parse and the checks too (a large
            // problem's, on a loaded machine, took a second).
            let started = std::time::Instant::now();
            let unit = first_problem(db, problem)?;
            let limits = &limits.spent_since(started);
            let cancel = || {
                // A pending change of the inputs stops the search (the
                // change waits for this snapshot to be dropped).
                salsa::Database::unwind_if_revision_cancelled(db);
                cancel()
            };
            let out = crate::planner::plan(db, unit, config, limits, &cancel, progress);
            Some(PlanningResult {
                status: out.status,
                plan: out.plan,
                stats: out.stats,
                diagnostics: out.lints.iter().map(|l| l.to_diagnostic(db)).collect(),
            })
        });
        salsa::Cancelled::catch(run).map_err(|_| Cancelled)
    }

    /// Repairs the plan in `old` (read in `format`, or the format its
    /// content shows) for the first problem of the file `problem` (section
    /// 5 of the HiPOP paper). `None` when that file has no problem.
    #[allow(clippy::too_many_arguments)]
    pub fn run_repair(
        &self,
        problem: SourceFile,
        old: SourceFile,
        format: Option<PlanFormat>,
        config: &crate::planner::Config,
        limits: &crate::planner::PlannerLimits,
        options: &crate::repair::RepairOptions,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&crate::planner::Progress),
    ) -> Cancellable<Option<RepairResult>> {
        let db = &self.db;
        let run = AssertUnwindSafe(move || {
            // The time limit counts the parse and the checks too.
            let started = std::time::Instant::now();
            let unit = first_problem(db, problem)?;
            let plan = match format {
                Some(f) => crate::plan::parse_plan_as(db, old, f),
                None => crate::plan::parse_plan(db, old),
            };
            let limits = &limits.spent_since(started);
            let cancel = || {
                salsa::Database::unwind_if_revision_cancelled(db);
                cancel()
            };
            let out = crate::repair::repair(db, unit, plan, config, limits, options, &cancel, progress);
            Some(repair_result(db, out))
        });
        salsa::Cancelled::catch(run).map_err(|_| Cancelled)
    }

    /// Repairs `old` (the text of a plan in `format`, or the format its
    /// content shows), as [`Analysis::run_repair`] does with a plan file:
    /// for a shell that keeps the last plan of a problem in memory.
    #[allow(clippy::too_many_arguments)]
    pub fn run_repair_text(
        &self,
        problem: SourceFile,
        old: &str,
        format: Option<PlanFormat>,
        config: &crate::planner::Config,
        limits: &crate::planner::PlannerLimits,
        options: &crate::repair::RepairOptions,
        cancel: &dyn Fn() -> bool,
        progress: &mut dyn FnMut(&crate::planner::Progress),
    ) -> Cancellable<Option<RepairResult>> {
        let db = &self.db;
        let plan = crate::plan::read_plan(old, format);
        let run = AssertUnwindSafe(move || {
            let unit = first_problem(db, problem)?;
            let cancel = || {
                // A pending change of the inputs stops the search (the
                // change waits for this snapshot to be dropped).
                salsa::Database::unwind_if_revision_cancelled(db);
                cancel()
            };
            let out = crate::repair::repair(db, unit, &plan, config, limits, options, &cancel, progress);
            Some(repair_result(db, out))
        });
        salsa::Cancelled::catch(run).map_err(|_| Cancelled)
    }

    /// The files holding the problems a planner run on save of `file` covers:
    /// `file` itself when it has a problem, else the problems of the
    /// workspace whose domain `file` defines.
    pub fn problems_to_plan(&self, file: SourceFile) -> Cancellable<Vec<SourceFile>> {
        self.with_db(|db| {
            if first_problem(db, file).is_some() {
                return vec![file];
            }
            let mut out: Vec<SourceFile> = crate::db::file_units(db, file)
                .iter()
                .filter(|u| u.kind(db) == crate::db::UnitKind::Domain)
                .flat_map(|&d| crate::semantics::resolve::problems_of(db, d).iter().map(|p| p.file(db)))
                .collect();
            out.dedup();
            out
        })
    }

    /// The files a planner run on the first problem of `problem` reads: that
    /// file, then its domain's when it is found.
    pub fn plan_inputs(&self, problem: SourceFile) -> Cancellable<Vec<SourceFile>> {
        self.with_db(|db| {
            let mut files = vec![problem];
            if let Some(d) =
                first_problem(db, problem).and_then(|u| crate::semantics::check::domain_for(db, u))
                && d.file(db) != problem
            {
                files.push(d.file(db));
            }
            files
        })
    }

    /// The inlay hints of a planner run on the first problem of `file`.
    pub fn plan_hints(
        &self,
        file: SourceFile,
        run: &crate::ide::PlanRun,
    ) -> Cancellable<Vec<crate::ide::PlanHint>> {
        self.with_db(|db| crate::ide::plan_hints(db, file, run))
    }

    /// What the last plans of the problems of `file` say of the name at `offset`.
    pub fn plan_hover(
        &self,
        file: SourceFile,
        offset: TextSize,
        plans: &[(String, &crate::planner::output::SolvedPlan)],
    ) -> Cancellable<Option<String>> {
        self.with_db(|db| crate::ide::plan_hover(db, file, offset, plans))
    }

    /// How `new` differs from `old`, two plans of the first problem of
    /// `problem`, with the agents its domain gives the steps (`hipop diff`).
    pub fn solved_plan_diff(
        &self,
        problem: SourceFile,
        old: &crate::planner::output::SolvedPlan,
        new: &crate::planner::output::SolvedPlan,
    ) -> Cancellable<(Plan, Plan, crate::plan::diff::PlanDiff)> {
        self.with_db(|db| {
            let a = crate::plan::read_plan(&old.to_json(), Some(PlanFormat::Json));
            let b = crate::plan::read_plan(&new.to_json(), Some(PlanFormat::Json));
            let agents = problem_agents(db, problem);
            let options = crate::plan::diff::DiffOptions {
                matching: NameMatching::CaseInsensitive,
                ..Default::default()
            };
            let d = crate::plan::diff::diff(&a, &b, &agents, &options);
            (a, b, d)
        })
    }

    /// The timeline of a solved plan of the first problem of `problem`, as SVG.
    pub fn solved_plan_svg(
        &self,
        problem: SourceFile,
        plan: &crate::planner::output::SolvedPlan,
    ) -> Cancellable<String> {
        self.with_db(|db| {
            let p = crate::plan::read_plan(&plan.to_json(), Some(PlanFormat::Json));
            let agents = problem_agents(db, problem);
            crate::plan::timeline::svg(&crate::plan::timeline::timeline(&p, &agents))
        })
    }

    /// The diagnostics of reading a plan (E0401–E0409, W0401–W0409).
    pub fn plan_diagnostics(
        &self,
        file: SourceFile,
        format: Option<PlanFormat>,
    ) -> Cancellable<Vec<Diagnostic>> {
        self.with_db(|db| match format {
            Some(f) => crate::plan::parse_plan_as(db, file, f).file_diagnostics(file),
            None => crate::plan::parse_plan(db, file).file_diagnostics(file),
        })
    }

    /// The agents of the actions and tasks of the domains in a file (their `:agent`).
    pub fn plan_agents(&self, domain: SourceFile, matching: NameMatching) -> Cancellable<AgentTable> {
        self.with_db(|db| AgentTable::from_domain(db, domain, matching))
    }
}

fn repair_result(db: &dyn crate::db::Db, out: crate::repair::RepairOutcome<'_>) -> RepairResult {
    RepairResult {
        status: out.status,
        stage: out.stage,
        plan: out.plan,
        old: out.old,
        removed: out.removed,
        stages: out.stages,
        dropped: out.dropped,
        stats: out.stats,
        diagnostics: out.lints.iter().map(|l| l.to_diagnostic(db)).collect(),
    }
}

/// The agents of the steps of the plans of the first problem of `problem`
/// (from its domain's `:agent`s), names compared case-insensitively.
fn problem_agents(db: &dyn crate::db::Db, problem: SourceFile) -> AgentTable {
    first_problem(db, problem)
        .and_then(|u| crate::semantics::check::domain_for(db, u))
        .map(|d| AgentTable::from_domain(db, d.file(db), NameMatching::CaseInsensitive))
        .unwrap_or_default()
}

/// The first problem of a file.
pub(crate) fn first_problem<'db>(
    db: &'db dyn crate::db::Db,
    file: SourceFile,
) -> Option<crate::db::Unit<'db>> {
    crate::db::file_units(db, file).iter().copied().find(|u| u.kind(db) == crate::db::UnitKind::Problem)
}
