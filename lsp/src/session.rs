//! The server's state: the analysis host, the open documents and the
//! negotiated encoding. It lives behind one `tokio::sync::Mutex`; every
//! notification changes it in one synchronous critical section, so the
//! analyzer's text always equals the documents' text.
//!
//! Every change bumps [`Session::generation`]; diagnostics computed for an
//! older generation are dropped instead of published (see `diagnostics`).

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use hipop_analyzer::ide::PlanRun;
use hipop_analyzer::{Analysis, AnalysisHost, Cancellable, Diagnostic, SourceFile};
use tower_lsp_server::ls_types::{self as lsp, TextDocumentContentChangeEvent, Uri};

use crate::convert::{Files, file_key};
use crate::document::{Applied, Document};
use crate::line_index::{Encoding, LineIndex};
use crate::watch::{DiskChanges, DiskWatcher, Known};
use crate::workspace::{self, Budget, Scan};

pub(crate) struct Session {
    host: AnalysisHost,
    docs: HashMap<Uri, Document>,
    /// Analyzer key → the client's URI of each open document.
    open: Arc<HashMap<String, Uri>>,
    encoding: Encoding,
    /// Whether the client can watch files for us (dynamic registration).
    watch_files: bool,
    /// Whether the client accepts snippets in completions.
    snippets: bool,
    generation: u64,
    budget: Budget,
    /// Folders already loaded from disk.
    scanned: HashSet<PathBuf>,
    /// The workspace folders (loaded recursively).
    roots: Vec<PathBuf>,
    /// The server's own watches of `scanned`, when the client does not watch files.
    disk: Option<DiskWatcher>,
    /// Problems to report to the user, taken after each change.
    warnings: Vec<String>,
    /// What was last published per document, to skip identical re-publications.
    published: HashMap<Uri, (i32, Vec<lsp::Diagnostic>)>,
    /// The last planner run of each problem, by analyzer key.
    plans: Plans,
    last_planned: Option<Uri>,
    pub(crate) plan_settings: PlanSettings,
    /// What the client can do that planning on save uses.
    pub(crate) client_features: ClientFeatures,
}

/// The last planner run of each problem, by the analyzer's key of its file.
pub(crate) type Plans = Arc<HashMap<String, Arc<PlanRecord>>>;

/// A planner run kept for the editor: the run, the flaws of the best partial
/// plan, and the texts it planned (hints and flaws are shown only while the
/// files still have them).
#[derive(Clone)]
pub(crate) struct PlanRecord {
    pub uri: Uri,
    pub problem: SourceFile,
    pub run: PlanRun,
    pub flaws: Vec<Diagnostic>,
    /// The files planned, the problem's first, with their texts then.
    pub inputs: Vec<(SourceFile, Arc<str>)>,
    /// The last plan found for the problem (by this run or an earlier one):
    /// what the next run repairs when only the problem changed.
    pub base: Option<Arc<PlanBase>>,
}

/// A plan found, with the texts of the files it was found for.
pub(crate) struct PlanBase {
    pub plan: hipop_analyzer::planner::output::SolvedPlan,
    pub inputs: Vec<(SourceFile, Arc<str>)>,
}

impl PlanRecord {
    /// Whether the files still have the texts planned.
    pub(crate) fn is_current(&self, analysis: &Analysis) -> Cancellable<bool> {
        for (file, text) in &self.inputs {
            let now = analysis.file_text(*file)?;
            if !Arc::ptr_eq(&now, text) && *now != **text {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The name of the problem planned.
    pub(crate) fn problem_name(&self) -> String {
        match &self.run.plan {
            Some(plan) => plan.problem.clone(),
            None => self.uri.path().as_str().rsplit('/').next().unwrap_or_default().to_string(),
        }
    }
}

/// The settings of planning on save (`hipop.plan.*`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlanSettings {
    pub on_save: bool,
    pub time_limit: std::time::Duration,
}

impl Default for PlanSettings {
    fn default() -> Self {
        PlanSettings { on_save: true, time_limit: std::time::Duration::from_secs(5) }
    }
}

impl PlanSettings {
    /// Applies `{"plan": {"onSave": bool, "timeLimit": seconds}}`, also
    /// under a `"hipop"` key (how clients send a section of their settings).
    pub(crate) fn update(&mut self, settings: &serde_json::Value) {
        let plan = settings.get("hipop").unwrap_or(settings).get("plan");
        let Some(plan) = plan else { return };
        if let Some(on) = plan.get("onSave").and_then(serde_json::Value::as_bool) {
            self.on_save = on;
        }
        if let Some(secs) = plan.get("timeLimit").and_then(serde_json::Value::as_f64)
            && secs.is_finite()
        {
            self.time_limit = std::time::Duration::from_secs_f64(secs.clamp(0.1, 3600.0));
        }
    }
}

/// What the client declared it can do, of what planning uses.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ClientFeatures {
    /// `window/workDoneProgress/create` and `$/progress`.
    pub progress: bool,
    /// `workspace/inlayHint/refresh`.
    pub inlay_hint_refresh: bool,
}

/// A snapshot for one request about one file. It must not be held across an
/// `.await` of a task that changes the session: a change waits for it to drop.
pub(crate) struct Snapshot {
    pub analysis: Analysis,
    pub file: SourceFile,
    pub encoding: Encoding,
    /// Whether the client accepts snippets in completions.
    pub snippets: bool,
    pub open: Arc<HashMap<String, Uri>>,
    pub indexes: HashMap<SourceFile, Arc<LineIndex>>,
    pub plans: Plans,
}

impl Snapshot {
    pub(crate) fn files(&self) -> Files<'_> {
        Files::new(&self.analysis, &self.open, self.encoding, &self.indexes)
    }
}

/// A snapshot for a request about the whole workspace.
pub(crate) struct WorkspaceSnapshot {
    pub analysis: Analysis,
    pub encoding: Encoding,
    pub open: Arc<HashMap<String, Uri>>,
    pub indexes: HashMap<SourceFile, Arc<LineIndex>>,
}

impl WorkspaceSnapshot {
    pub(crate) fn files(&self) -> Files<'_> {
        Files::new(&self.analysis, &self.open, self.encoding, &self.indexes)
    }
}

/// What the diagnostics of all open documents need, taken under the lock.
pub(crate) struct DiagnosticsJob {
    pub analysis: Analysis,
    pub docs: Vec<(Uri, i32, SourceFile)>,
    pub encoding: Encoding,
    pub open: Arc<HashMap<String, Uri>>,
    pub indexes: HashMap<SourceFile, Arc<LineIndex>>,
    pub plans: Plans,
}

impl Default for Session {
    fn default() -> Session {
        Session {
            host: AnalysisHost::new(),
            docs: HashMap::new(),
            open: Arc::default(),
            encoding: Encoding::Utf16,
            watch_files: false,
            snippets: false,
            generation: 0,
            budget: Budget::default(),
            scanned: HashSet::new(),
            roots: Vec::new(),
            disk: None,
            warnings: Vec::new(),
            published: HashMap::new(),
            plans: Arc::default(),
            last_planned: None,
            plan_settings: PlanSettings::default(),
            client_features: ClientFeatures::default(),
        }
    }
}

impl Session {
    pub(crate) fn generation(&self) -> u64 {
        self.generation
    }

    /// Records what was negotiated with the client at `initialize`.
    pub(crate) fn set_client(&mut self, encoding: Encoding, watch_files: bool) {
        self.encoding = encoding;
        self.watch_files = watch_files;
    }

    /// Records whether the client accepts snippets in completions.
    pub(crate) fn set_snippets(&mut self, snippets: bool) {
        self.snippets = snippets;
    }

    pub(crate) fn watch_files(&self) -> bool {
        self.watch_files
    }

    pub(crate) fn budget(&self) -> Budget {
        self.budget
    }

    fn rebuild_open(&mut self) {
        self.open = Arc::new(self.docs.iter().map(|(uri, d)| (d.key.clone(), uri.clone())).collect());
    }

    pub(crate) fn is_open(&self, key: &str) -> bool {
        self.open.contains_key(key)
    }

    /// The problems met since last asked (a folder that cannot be watched).
    pub(crate) fn take_warnings(&mut self) -> Vec<String> {
        std::mem::take(&mut self.warnings)
    }

    /// Records workspace folders, whose new subfolders are loaded when they appear.
    pub(crate) fn add_roots(&mut self, roots: &[PathBuf]) {
        for root in roots {
            if !self.roots.contains(root) {
                self.roots.push(root.clone());
            }
        }
    }

    /// Loads files read from disk; open documents keep their editor text.
    pub(crate) fn load(&mut self, scan: Scan, budget: Budget) {
        self.budget = budget;
        if let Some(disk) = &mut self.disk
            && let Some(failure) = disk.watch(&scan.dirs)
        {
            self.warnings.push(failure);
        }
        self.scanned.extend(scan.dirs);
        for (key, text) in scan.files {
            if !self.is_open(&key) {
                self.host.set_file_text(&key, text);
            }
        }
        self.generation += 1;
    }

    /// Forgets the files under a folder no longer in the workspace, unless open.
    pub(crate) fn unload(&mut self, root: &Path) {
        self.forget_under(root);
        self.roots.retain(|r| !r.starts_with(root));
        self.generation += 1;
    }

    /// Forgets the files and folders under `root` (or the file `root`), except open documents.
    fn forget_under(&mut self, root: &Path) {
        let gone: Vec<String> = self
            .host
            .files()
            .map(|(key, _)| key.to_string())
            .filter(|key| Path::new(key).starts_with(root) && !self.is_open(key))
            .collect();
        for key in &gone {
            self.host.remove_file(key);
        }
        self.scanned.retain(|dir| !dir.starts_with(root));
        if let Some(disk) = &mut self.disk {
            disk.unwatch_under(root);
        }
    }

    /// Starts watching the folders loaded from disk, and those loaded later.
    pub(crate) fn start_watching(&mut self, mut disk: DiskWatcher) -> usize {
        if let Some(failure) = disk.watch(&self.scanned) {
            self.warnings.push(failure);
        }
        let count = disk.len();
        self.disk = Some(disk);
        count
    }

    /// What the file watcher needs to decide what to read.
    pub(crate) fn known(&self) -> Known {
        Known {
            roots: self.roots.clone(),
            scanned: self.scanned.clone(),
            files: self
                .host
                .files()
                .map(|(key, _)| PathBuf::from(key))
                .filter(|p| p.is_absolute() && !self.is_open(&p.to_string_lossy()))
                .collect(),
            budget: self.budget,
        }
    }

    /// Applies what the file watcher found on disk. Open documents keep the
    /// editor's text; a new file is loaded only within the budget.
    pub(crate) fn apply_disk_changes(&mut self, changes: DiskChanges) {
        if !changes.scan.dirs.is_empty() || !changes.scan.files.is_empty() {
            self.load(changes.scan, changes.budget);
        }
        for path in &changes.gone {
            self.forget_under(path);
        }
        for (key, text) in changes.files {
            if self.is_open(&key) {
                continue;
            }
            if self.host.file(&key).is_none() {
                if self.budget.files == 0 || text.len() as u64 > self.budget.bytes {
                    self.budget.exhausted = true;
                    continue;
                }
                self.budget.files -= 1;
                self.budget.bytes -= text.len() as u64;
            }
            // Unchanged texts are left as they are (the host compares).
            self.host.set_file_text(&key, text);
        }
        self.generation += 1;
    }

    pub(crate) fn open(&mut self, uri: Uri, version: i32, text: String) {
        let key = file_key(&uri);
        self.load_folder_of(&key);
        self.host.set_file_text(&key, text.as_str());
        self.docs.insert(uri, Document::new(key, version, text));
        self.rebuild_open();
        self.generation += 1;
    }

    /// Loads the folder of a document opened outside the workspace, where its
    /// domain or problems most likely are.
    fn load_folder_of(&mut self, key: &str) {
        let Some(dir) = Path::new(key).parent().filter(|d| d.is_absolute()) else { return };
        if self.scanned.contains(dir) {
            return;
        }
        let mut scan = Scan::default();
        let mut budget = self.budget;
        workspace::scan(dir, false, &mut budget, &mut scan);
        scan.files.retain(|(k, _)| self.host.file(k).is_none());
        self.load(scan, budget);
    }

    /// Applies a `didChange`. A version not newer than the current one is
    /// rejected: applying it would desynchronize the text.
    pub(crate) fn change(
        &mut self,
        uri: &Uri,
        version: i32,
        changes: Vec<TextDocumentContentChangeEvent>,
    ) -> Result<(), String> {
        let encoding = self.encoding;
        let Some(doc) = self.docs.get_mut(uri) else {
            return Err(format!("change to {} which is not open", uri.as_str()));
        };
        if version <= doc.version {
            return Err(format!("ignored version {version} of {}: already at {}", uri.as_str(), doc.version));
        }
        doc.version = version;
        let applied = doc.apply_changes(changes, encoding);
        let synced = match applied {
            Applied::Edits(edits) => {
                // Both sides applied the same edits; a length check catches a
                // disagreement without comparing megabytes on every keystroke.
                self.host.apply_edits(&doc.key, edits).is_some_and(|t| t.len() == doc.text().len())
            }
            Applied::Replaced => false,
        };
        if !synced {
            self.host.set_file_text(&doc.key, doc.text());
        }
        self.generation += 1;
        Ok(())
    }

    /// Closes a document: the analyzer goes back to the file on disk, if any.
    pub(crate) fn close(&mut self, uri: &Uri) {
        self.published.remove(uri);
        let Some(doc) = self.docs.remove(uri) else { return };
        self.rebuild_open();
        match workspace::uri_path(uri).and_then(|p| workspace::read_text(&p)) {
            Some(text) => drop(self.host.set_file_text(&doc.key, text)),
            None => self.host.remove_file(&doc.key),
        }
        self.generation += 1;
    }

    /// A file changed on disk: the analyzer rereads it, unless it is open
    /// (the editor's text wins) or not PDDL/HDDL.
    pub(crate) fn disk_changed(&mut self, uri: &Uri, deleted: bool) {
        let Some(path) = workspace::uri_path(uri).filter(|p| workspace::is_source(p)) else { return };
        let key = file_key(uri);
        if self.is_open(&key) {
            return;
        }
        match workspace::read_text(&path) {
            Some(text) if !deleted => drop(self.host.set_file_text(&key, text)),
            _ => self.host.remove_file(&key),
        }
        self.generation += 1;
    }

    /// A snapshot for a request about `uri`, open or loaded from disk.
    pub(crate) fn snapshot(&self, uri: &Uri) -> Option<Snapshot> {
        let file = self.host.file(&file_key(uri))?;
        Some(Snapshot {
            analysis: self.host.analysis(),
            file,
            encoding: self.encoding,
            snippets: self.snippets,
            open: self.open.clone(),
            indexes: self.indexes(),
            plans: self.plans.clone(),
        })
    }

    /// A snapshot for a request about the whole workspace.
    pub(crate) fn workspace_snapshot(&self) -> WorkspaceSnapshot {
        WorkspaceSnapshot {
            analysis: self.host.analysis(),
            encoding: self.encoding,
            open: self.open.clone(),
            indexes: self.indexes(),
        }
    }

    /// The line indexes of the open documents, by analyzer file.
    fn indexes(&self) -> HashMap<SourceFile, Arc<LineIndex>> {
        self.docs.values().filter_map(|d| Some((self.host.file(&d.key)?, d.index()))).collect()
    }

    pub(crate) fn diagnostics_job(&self) -> DiagnosticsJob {
        let docs = self
            .docs
            .iter()
            .filter_map(|(uri, d)| Some((uri.clone(), d.version, self.host.file(&d.key)?)))
            .collect();
        DiagnosticsJob {
            analysis: self.host.analysis(),
            docs,
            encoding: self.encoding,
            open: self.open.clone(),
            indexes: self.indexes(),
            plans: self.plans.clone(),
        }
    }

    /// A snapshot of the analysis alone, for a background computation.
    pub(crate) fn analysis(&self) -> Analysis {
        self.host.analysis()
    }

    pub(crate) fn file(&self, key: &str) -> Option<SourceFile> {
        self.host.file(key)
    }

    /// The client's URI of an analyzer file: the open document's, else its path's.
    pub(crate) fn uri_of(&self, key: &str) -> Option<Uri> {
        crate::convert::key_uri(key, &self.open)
    }

    pub(crate) fn plan(&self, key: &str) -> Option<Arc<PlanRecord>> {
        self.plans.get(key).cloned()
    }

    /// Keeps the last run of a problem.
    pub(crate) fn keep_plan(&mut self, key: String, record: PlanRecord) {
        self.last_planned = Some(record.uri.clone());
        Arc::make_mut(&mut self.plans).insert(key, Arc::new(record));
    }

    /// The problem planned last.
    pub(crate) fn last_planned(&self) -> Option<Uri> {
        self.last_planned.clone()
    }

    /// Rereads a file from disk now (a plan the server wrote), unless open.
    pub(crate) fn reread(&mut self, uri: &Uri) {
        self.disk_changed(uri, false);
    }

    /// Records a publication; false if it would repeat the last one.
    pub(crate) fn record_published(&mut self, uri: &Uri, version: i32, diags: &[lsp::Diagnostic]) -> bool {
        if self.docs.get(uri).is_none_or(|d| d.version != version) {
            return false;
        }
        if self.published.get(uri).is_some_and(|(v, d)| *v == version && d == diags) {
            return false;
        }
        self.published.insert(uri.clone(), (version, diags.to_vec()));
        true
    }

    /// Forgets what was published, so that the next publication happens even if unchanged.
    pub(crate) fn forget_published(&mut self) {
        self.published.clear();
    }
}

#[cfg(test)]
mod tests {
    use hipop_analyzer::{Analysis, AnalysisHost, TextRange};
    use proptest::prelude::*;
    use tower_lsp_server::ls_types::{Position, Range};

    use super::*;

    /// What is inserted: keystrokes, keywords, and what hostile or generated
    /// files are made of: long runs of one character and deep nesting (past
    /// the parser's limit of 256).
    fn pieces() -> Vec<String> {
        let mut p: Vec<String> = [
            "(",
            ")",
            " ",
            "\n",
            "\r\n",
            ";",
            "é",
            "😀",
            ":effect",
            "(and ",
            "?x",
            "(:action b",
            "\"",
            "-",
            "7",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        p.extend(["(", ")", ";", "\"", "-", "7", "é", "😀", "\n"].iter().map(|c| c.repeat(1500)));
        p.extend(["(and ", "(not ", "(", "(forall (?y) "].iter().map(|h| h.repeat(300)));
        p.push(format!("{}(p ?x){}", "(and ".repeat(400), ")".repeat(400)));
        // Nested up to the limit inside an action's formula, and small lists
        // that, inserted in its deepest list, are one level too deep.
        p.push(format!("{}(p ?x){}", "(and ".repeat(253), ")".repeat(253)));
        p.extend(["(a)", " (q ?x)", "((a))"].iter().map(|s| s.to_string()));
        p
    }

    fn seeds() -> Vec<String> {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        ["samples/rover-mission/domain.hddl", "samples/transport-htn/domain.hddl"]
            .iter()
            .map(|rel| std::fs::read_to_string(root.join(rel)).expect("a sample"))
            .collect()
    }

    /// A content change: a range (possibly past the end, reversed, or inside
    /// a character of two UTF-16 units) replaced by a piece, or now and then
    /// the whole text.
    fn change(pieces: usize) -> impl Strategy<Value = TextDocumentContentChangeEvent> {
        (0u32..80, 0u32..140, 0u32..3, 0u32..140, 0..pieces, 0u32..30).prop_map(
            move |(line, character, lines, end_character, piece, whole)| TextDocumentContentChangeEvent {
                range: (whole != 0).then(|| {
                    Range::new(Position::new(line, character), Position::new(line + lines, end_character))
                }),
                range_length: None,
                text: pieces_text(piece),
            },
        )
    }

    fn pieces_text(i: usize) -> String {
        static PIECES: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
        PIECES.get_or_init(pieces)[i].clone()
    }

    /// A file's diagnostics, as what an editor shows.
    fn shown(analysis: &Analysis, file: SourceFile) -> Vec<(&'static str, TextRange, String)> {
        let diagnostics = analysis.diagnostics(file).expect("not cancelled");
        diagnostics.iter().map(|d| (d.code.id, d.range, d.message.clone())).collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]

        /// Any sequence of `didChange` batches keeps the analyzer's text equal
        /// to the document's, and its diagnostics equal to those of a fresh
        /// analysis of that text (the incremental re-parse is exact), in both
        /// position encodings.
        #[test]
        fn edit_sequences_keep_the_analysis_exact(
            seed in 0usize..2,
            batches in proptest::collection::vec(proptest::collection::vec(change(pieces().len()), 1..4), 1..6),
            utf8 in any::<bool>(),
        ) {
            let mut session = Session::default();
            session.set_client(if utf8 { Encoding::Utf8 } else { Encoding::Utf16 }, false);
            let uri: Uri = "untitled:domain.hddl".parse().expect("a URI");
            session.open(uri.clone(), 1, seeds()[seed].clone());
            for (version, batch) in (2..).zip(batches) {
                session.change(&uri, version, batch).expect("a newer version");
                let text = session.docs[&uri].text().to_string();
                let job = session.diagnostics_job();
                let (_, _, file) = job.docs[0];
                prop_assert_eq!(&*job.analysis.file_text(file).expect("not cancelled"), text.as_str());
                let mut fresh = AnalysisHost::new();
                let g = fresh.set_file_text("untitled:domain.hddl", text.as_str());
                prop_assert_eq!(shown(&job.analysis, file), shown(&fresh.analysis(), g));
                job.analysis.document_symbols(file).expect("not cancelled");
            }
        }
    }
}
