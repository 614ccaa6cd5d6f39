//! The `LanguageServer` implementation: thin handlers over the session,
//! `features` and `diagnostics`.
//!
//! Notifications take the session lock as their first `.await`: tower-lsp-server
//! polls handlers in arrival order and tokio's mutex is fair, so document
//! changes apply in the order the client sent them.

use std::path::PathBuf;
use std::sync::Arc;

use tokio::sync::Mutex;
use tower_lsp_server::jsonrpc::Result;
use tower_lsp_server::ls_types::*;
use tower_lsp_server::{Client, LanguageServer};

use crate::diagnostics::{self, When};
use crate::planning::{self, Planning};
use crate::requests::{self, Outcome, guarded};
use crate::session::Session;
use crate::watch::{self, DiskWatcher};
use crate::workspace::{self, Scan};
use crate::{capabilities, convert, features, plan_features};

pub(crate) struct Backend {
    client: Client,
    session: Arc<Mutex<Session>>,
    planning: Arc<Planning>,
}

impl Backend {
    pub(crate) fn new(client: Client) -> Backend {
        Backend { client, session: Arc::default(), planning: Arc::default() }
    }

    /// `hipop/plan`: the last planner run on a problem (see `plan_features::plan`).
    pub(crate) async fn plan_request(
        &self,
        params: TextDocumentIdentifier,
    ) -> Result<Option<serde_json::Value>> {
        requests::run(&self.session, &params.uri, "hipop/plan", plan_features::plan).await
    }

    /// `hipop/planDiff`: what the last repair of a problem changed.
    pub(crate) async fn plan_diff_request(
        &self,
        params: TextDocumentIdentifier,
    ) -> Result<Option<serde_json::Value>> {
        requests::run(&self.session, &params.uri, "hipop/planDiff", plan_features::plan_diff).await
    }

    /// `hipop.writePlan`: writes the last plan of a problem beside it, and
    /// reads it back at once so that it is validated like any plan file.
    async fn write_plan(&self, uri: Uri) -> Result<Option<serde_json::Value>> {
        let answer =
            requests::run(&self.session, &uri, "hipop.writePlan", plan_features::plan_to_write).await?;
        let text = match answer {
            None => return Err(invalid_params(format!("{} is not a known problem", uri.as_str()))),
            Some(Err(message)) => return Err(invalid_params(message)),
            Some(Ok(text)) => text,
        };
        let Some(path) = plan_features::plan_path(&uri) else {
            return Err(invalid_params(format!("{} is not a file on disk", uri.as_str())));
        };
        let written = {
            let path = path.clone();
            tokio::task::spawn_blocking(move || std::fs::write(&path, text)).await
        };
        match written {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(invalid_params(format!("{}: cannot write: {e}", path.display()))),
            Err(e) => return Err(invalid_params(format!("{}: cannot write: {e}", path.display()))),
        }
        let Some(plan_uri) = Uri::from_file_path(&path) else { return Ok(None) };
        let reread = plan_uri.clone();
        self.mutate("writing the plan", When::Now, move |s| {
            s.reread(&reread);
            Ok(())
        })
        .await;
        Ok(Some(serde_json::json!({ "uri": plan_uri.as_str(), "path": path.display().to_string() })))
    }

    async fn mutate(
        &self,
        what: &str,
        when: When,
        f: impl FnOnce(&mut Session) -> std::result::Result<(), String>,
    ) {
        mutate(&self.client, &self.session, what, when, f).await
    }

    /// Watches the folders loaded from disk, for a client that does not.
    async fn watch_disk(&self) {
        let (disk, changes) = match DiskWatcher::new() {
            Ok(watcher) => watcher,
            Err(e) => {
                let message = format!("hipop: cannot watch files for changes on disk: {e}");
                self.client.log_message(MessageType::WARNING, message).await;
                return;
            }
        };
        tokio::spawn(watch::run(self.client.clone(), self.session.clone(), changes));
        let mut count = 0;
        self.mutate("watching files", When::Now, |s| {
            count = s.start_watching(disk);
            Ok(())
        })
        .await;
        let message = format!("hipop: watching {count} folders for changes on disk");
        self.client.log_message(MessageType::INFO, message).await;
    }

    /// Reads folders from disk on a blocking thread, then loads them.
    async fn load_folders(&self, roots: Vec<PathBuf>) {
        if roots.is_empty() {
            return;
        }
        let budget = self.session.lock().await.budget();
        let read = tokio::task::spawn_blocking(move || {
            let (mut budget, mut scan) = (budget, Scan::default());
            for root in &roots {
                workspace::scan(root, true, &mut budget, &mut scan);
            }
            (scan, budget, roots)
        });
        let Ok((scan, budget, roots)) = read.await else { return };
        let count = scan.files.len();
        self.mutate("loading the workspace", When::Now, |s| {
            s.add_roots(&roots);
            s.load(scan, budget);
            Ok(())
        })
        .await;
        let mut message = format!("hipop: loaded {count} PDDL/HDDL files");
        if budget.exhausted {
            message.push_str(" (stopped at the limit of 2000 files, 64 MB or 20000 folders)");
        }
        self.client.log_message(MessageType::INFO, message).await;
    }
}

/// Changes the session in one critical section, panic-guarded, then
/// schedules diagnostics for the new state.
pub(crate) async fn mutate(
    client: &Client,
    session: &Arc<Mutex<Session>>,
    what: &str,
    when: When,
    f: impl FnOnce(&mut Session) -> std::result::Result<(), String>,
) {
    let (result, warnings) = {
        let mut state = session.lock().await;
        let result = match guarded(|| Ok(f(&mut state))) {
            Outcome::Done(result) => result,
            Outcome::Panicked(message) => Err(format!("hipop: {what} failed: {message}")),
            Outcome::Cancelled => Ok(()),
        };
        diagnostics::schedule(client, session, state.generation(), when);
        (result, state.take_warnings())
    };
    if let Err(message) = result {
        client.log_message(MessageType::WARNING, message).await;
    }
    for warning in warnings {
        client.log_message(MessageType::WARNING, format!("hipop: {warning}")).await;
    }
}

impl LanguageServer for Backend {
    async fn initialize(&self, params: InitializeParams) -> Result<InitializeResult> {
        let encoding = convert::negotiate_encoding(&params.capabilities);
        let watch = params.capabilities.workspace.as_ref().and_then(|w| w.did_change_watched_files.as_ref());
        // Helix accepts the registration but reports only the writes it makes
        // itself, never a change made outside it (helix-editor/helix#11882):
        // the server watches for it.
        let forwards_only_its_writes =
            params.client_info.as_ref().is_some_and(|c| c.name.eq_ignore_ascii_case("helix"));
        let watch_files =
            watch.and_then(|w| w.dynamic_registration).unwrap_or(false) && !forwards_only_its_writes;
        {
            let mut session = self.session.lock().await;
            session.set_client(encoding, watch_files);
            let snippets = (params.capabilities.text_document.as_ref())
                .and_then(|t| t.completion.as_ref()?.completion_item.as_ref()?.snippet_support)
                .unwrap_or(false);
            session.set_snippets(snippets);
            session.client_features = crate::session::ClientFeatures {
                progress: params
                    .capabilities
                    .window
                    .as_ref()
                    .and_then(|w| w.work_done_progress)
                    .unwrap_or(false),
                inlay_hint_refresh: params
                    .capabilities
                    .workspace
                    .as_ref()
                    .and_then(|w| w.inlay_hint.as_ref())
                    .and_then(|i| i.refresh_support)
                    .unwrap_or(false),
            };
            if let Some(options) = &params.initialization_options {
                session.plan_settings.update(options);
            }
        }
        self.load_folders(workspace::roots(&params)).await;
        Ok(InitializeResult {
            capabilities: capabilities::server_capabilities(encoding),
            server_info: Some(ServerInfo {
                name: "hipop".to_string(),
                version: Some(env!("CARGO_PKG_VERSION").to_string()),
            }),
            // Answers clangd's extension only to the clients that use it.
            offset_encoding: params
                .capabilities
                .offset_encoding
                .as_ref()
                .map(|_| convert::encoding_kind(encoding).as_str().to_string()),
        })
    }

    /// Asks the client to report changes of PDDL/HDDL files on disk, so that a
    /// domain edited elsewhere (or by `git checkout`) is reread; watches the
    /// disk itself when the client cannot or will not.
    async fn initialized(&self, _: InitializedParams) {
        if !self.session.lock().await.watch_files() {
            self.watch_disk().await;
            return;
        }
        let options = DidChangeWatchedFilesRegistrationOptions {
            watchers: vec![FileSystemWatcher {
                glob_pattern: GlobPattern::String("**/*.{pddl,hddl}".to_string()),
                kind: None,
            }],
        };
        let registration = Registration {
            id: "hipop-watched-files".to_string(),
            method: "workspace/didChangeWatchedFiles".to_string(),
            register_options: serde_json::to_value(options).ok(),
        };
        if let Err(e) = self.client.register_capability(vec![registration]).await {
            let message = format!("hipop: the client does not watch files ({e}); the server does");
            self.client.log_message(MessageType::INFO, message).await;
            self.watch_disk().await;
        }
    }

    async fn shutdown(&self) -> Result<()> {
        Ok(())
    }

    async fn did_change_workspace_folders(&self, params: DidChangeWorkspaceFoldersParams) {
        let removed: Vec<PathBuf> =
            params.event.removed.iter().filter_map(|f| workspace::uri_path(&f.uri)).collect();
        self.mutate("removing folders", When::Now, |s| {
            removed.iter().for_each(|root| s.unload(root));
            Ok(())
        })
        .await;
        self.load_folders(params.event.added.iter().filter_map(|f| workspace::uri_path(&f.uri)).collect())
            .await;
    }

    async fn did_change_watched_files(&self, params: DidChangeWatchedFilesParams) {
        self.mutate("didChangeWatchedFiles", When::Now, |s| {
            for change in &params.changes {
                s.disk_changed(&change.uri, change.typ == FileChangeType::DELETED);
            }
            Ok(())
        })
        .await;
    }

    async fn did_open(&self, params: DidOpenTextDocumentParams) {
        let doc = params.text_document;
        self.mutate("didOpen", When::Now, |s| {
            s.open(doc.uri, doc.version, doc.text);
            Ok(())
        })
        .await;
    }

    async fn did_change(&self, params: DidChangeTextDocumentParams) {
        // Stops a plan in progress first: the change waits for nothing.
        self.planning.cancel();
        let doc = params.text_document;
        let changes = params.content_changes;
        self.mutate("didChange", When::Debounced, |s| s.change(&doc.uri, doc.version, changes)).await;
    }

    async fn did_save(&self, params: DidSaveTextDocumentParams) {
        let generation = self.session.lock().await.generation();
        diagnostics::schedule(&self.client, &self.session, generation, When::NowForced);
        let (client, session, planning) = (self.client.clone(), self.session.clone(), self.planning.clone());
        tokio::spawn(planning::on_save(client, session, planning, params.text_document.uri));
    }

    async fn did_change_configuration(&self, params: DidChangeConfigurationParams) {
        self.session.lock().await.plan_settings.update(&params.settings);
    }

    async fn did_close(&self, params: DidCloseTextDocumentParams) {
        let uri = params.text_document.uri;
        self.mutate("didClose", When::Now, |s| {
            s.close(&uri);
            Ok(())
        })
        .await;
        self.client.publish_diagnostics(uri, Vec::new(), None).await;
    }

    async fn document_symbol(&self, params: DocumentSymbolParams) -> Result<Option<DocumentSymbolResponse>> {
        let uri = params.text_document.uri;
        requests::run(&self.session, &uri, "documentSymbol", features::document_symbols).await
    }

    async fn symbol(&self, params: WorkspaceSymbolParams) -> Result<Option<WorkspaceSymbolResponse>> {
        let query = params.query;
        requests::run_workspace(&self.session, "workspace/symbol", move |s| {
            features::workspace_symbols(s, &query)
        })
        .await
    }

    async fn hover(&self, params: HoverParams) -> Result<Option<Hover>> {
        let at = params.text_document_position_params;
        let pos = at.position;
        requests::run(&self.session, &at.text_document.uri, "hover", move |s| features::hover(s, pos)).await
    }

    async fn inlay_hint(&self, params: InlayHintParams) -> Result<Option<Vec<InlayHint>>> {
        let range = params.range;
        let uri = &params.text_document.uri;
        requests::run(&self.session, uri, "inlayHint", move |s| plan_features::inlay_hints(s, range)).await
    }

    async fn execute_command(&self, params: ExecuteCommandParams) -> Result<Option<LSPAny>> {
        match params.command.as_str() {
            capabilities::WRITE_PLAN => {
                // The problem's URI; without one (Helix's :lsp-workspace-command
                // passes none), the problem planned last.
                let given = params.arguments.first();
                let uri = match given {
                    Some(a) => a
                        .as_str()
                        .or_else(|| a.get("uri").and_then(|u| u.as_str()))
                        .and_then(|u| u.parse::<Uri>().ok()),
                    None => self.session.lock().await.last_planned(),
                };
                match uri {
                    Some(uri) => self.write_plan(uri).await,
                    None if given.is_none() => {
                        Err(invalid_params("no plan yet: save a problem to plan it".to_string()))
                    }
                    None => Err(invalid_params(format!(
                        "{}: expected the problem's URI",
                        capabilities::WRITE_PLAN
                    ))),
                }
            }
            other => Err(invalid_params(format!("unknown command `{other}`"))),
        }
    }

    async fn goto_definition(&self, params: GotoDefinitionParams) -> Result<Option<GotoDefinitionResponse>> {
        let at = params.text_document_position_params;
        let pos = at.position;
        let uri = &at.text_document.uri;
        requests::run(&self.session, uri, "definition", move |s| features::definition(s, pos)).await
    }

    async fn references(&self, params: ReferenceParams) -> Result<Option<Vec<Location>>> {
        let at = params.text_document_position;
        let (pos, decl) = (at.position, params.context.include_declaration);
        let uri = &at.text_document.uri;
        requests::run(&self.session, uri, "references", move |s| features::references(s, pos, decl)).await
    }

    async fn document_highlight(
        &self,
        params: DocumentHighlightParams,
    ) -> Result<Option<Vec<DocumentHighlight>>> {
        let at = params.text_document_position_params;
        let pos = at.position;
        let uri = &at.text_document.uri;
        requests::run(&self.session, uri, "documentHighlight", move |s| features::document_highlights(s, pos))
            .await
    }

    async fn prepare_rename(
        &self,
        params: TextDocumentPositionParams,
    ) -> Result<Option<PrepareRenameResponse>> {
        let pos = params.position;
        let uri = &params.text_document.uri;
        let answer =
            requests::run(&self.session, uri, "prepareRename", move |s| features::prepare_rename(s, pos))
                .await?;
        refused(answer)
    }

    async fn rename(&self, params: RenameParams) -> Result<Option<WorkspaceEdit>> {
        let at = params.text_document_position;
        let (pos, name) = (at.position, params.new_name);
        let uri = &at.text_document.uri;
        let answer =
            requests::run(&self.session, uri, "rename", move |s| features::rename(s, pos, &name)).await?;
        refused(answer)
    }

    async fn folding_range(&self, params: FoldingRangeParams) -> Result<Option<Vec<FoldingRange>>> {
        let uri = params.text_document.uri;
        requests::run(&self.session, &uri, "foldingRange", features::folding_ranges).await
    }

    async fn code_action(&self, params: CodeActionParams) -> Result<Option<CodeActionResponse>> {
        // Only quick fixes are offered; a client asking for other kinds gets none.
        if let Some(only) = &params.context.only
            && !only.iter().any(|k| CodeActionKind::QUICKFIX.as_str().starts_with(k.as_str()))
        {
            return Ok(Some(Vec::new()));
        }
        let range = params.range;
        let uri = &params.text_document.uri;
        requests::run(&self.session, uri, "codeAction", move |s| features::code_actions(s, range)).await
    }

    async fn completion(&self, params: CompletionParams) -> Result<Option<CompletionResponse>> {
        let pos = params.text_document_position.position;
        let uri = &params.text_document_position.text_document.uri;
        requests::run(&self.session, uri, "completion", move |s| features::completions(s, pos)).await
    }

    async fn semantic_tokens_full(
        &self,
        params: SemanticTokensParams,
    ) -> Result<Option<SemanticTokensResult>> {
        let uri = params.text_document.uri;
        let tokens =
            requests::run(&self.session, &uri, "semanticTokens", |s| features::semantic_tokens(s, None));
        Ok(tokens.await?.map(SemanticTokensResult::Tokens))
    }

    async fn semantic_tokens_range(
        &self,
        params: SemanticTokensRangeParams,
    ) -> Result<Option<SemanticTokensRangeResult>> {
        let (uri, range) = (params.text_document.uri, params.range);
        let tokens = requests::run(&self.session, &uri, "semanticTokens", move |s| {
            features::semantic_tokens(s, Some(range))
        });
        Ok(tokens.await?.map(SemanticTokensRangeResult::Tokens))
    }

    async fn formatting(&self, params: DocumentFormattingParams) -> Result<Option<Vec<TextEdit>>> {
        let uri = params.text_document.uri;
        requests::run(&self.session, &uri, "formatting", features::formatting).await
    }
}

fn invalid_params(message: String) -> tower_lsp_server::jsonrpc::Error {
    tower_lsp_server::jsonrpc::Error {
        code: tower_lsp_server::jsonrpc::ErrorCode::InvalidParams,
        message: message.into(),
        data: None,
    }
}

/// A rename's answer: nothing for an unknown document, the client shows the
/// reason of a refusal.
fn refused<T>(answer: Option<std::result::Result<T, String>>) -> Result<Option<T>> {
    match answer {
        None => Ok(None),
        Some(Ok(x)) => Ok(Some(x)),
        Some(Err(message)) => Err(tower_lsp_server::jsonrpc::Error {
            code: tower_lsp_server::jsonrpc::ErrorCode::InvalidParams,
            message: message.into(),
            data: None,
        }),
    }
}
