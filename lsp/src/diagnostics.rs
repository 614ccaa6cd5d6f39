//! Pushing diagnostics for the open documents.
//!
//! Any change can change the diagnostics of other documents (editing a domain
//! changes its problems'), so each publication covers every open document;
//! salsa makes the unchanged ones cheap, and identical re-publications are
//! skipped. A change schedules a publication [`DEBOUNCE`] later; it only runs
//! if nothing changed in between (the session's generation is the same), and
//! it is published under the session lock after checking the generation again,
//! so a publication never describes anything but the latest text.
//!
//! The syntax and semantic checks are incremental per item and take a few
//! milliseconds; the model-verification lints may ground a large problem
//! (hundreds of milliseconds). When the lints are not ready [`LINTS_WAIT`]
//! after the checks could be, the checks are published first and the lints
//! when they are: typing never waits for grounding.

use std::sync::Arc;
use std::time::Duration;

use hipop_analyzer::diagnostic::{SHOWN_PER_FILE, shown_per_file};
use hipop_analyzer::{Cancellable, Diagnostic, SourceFile};
use tokio::sync::Mutex;
use tower_lsp_server::Client;
use tower_lsp_server::ls_types::{self as lsp, MessageType, Uri};

use crate::convert::{self, Files};
use crate::requests::{Outcome, guarded};
use crate::session::{DiagnosticsJob, Session};

/// The pause after the last keystroke before diagnostics are computed.
pub(crate) const DEBOUNCE: Duration = Duration::from_millis(150);

/// [`DEBOUNCE`], unless `HIPOP_LSP_DEBOUNCE_MS` says otherwise (the latency
/// benchmark sets it to 0 to measure the work itself).
fn debounce() -> Duration {
    static VALUE: std::sync::OnceLock<Duration> = std::sync::OnceLock::new();
    *VALUE.get_or_init(|| {
        std::env::var("HIPOP_LSP_DEBOUNCE_MS")
            .ok()
            .and_then(|v| v.parse().ok())
            .map_or(DEBOUNCE, Duration::from_millis)
    })
}

/// When to publish.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum When {
    /// After [`DEBOUNCE`], if no other change came.
    Debounced,
    /// Now.
    Now,
    /// Now, even what was already published (on save).
    NowForced,
}

/// How long the full diagnostics may take before the checks alone are published.
const LINTS_WAIT: Duration = Duration::from_millis(50);

/// Which diagnostics a batch holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Syntax and semantic checks.
    Checks,
    /// Checks and model-verification lints.
    All,
}

/// Schedules a publication for the state of generation `generation`.
pub(crate) fn schedule(client: &Client, session: &Arc<Mutex<Session>>, generation: u64, when: When) {
    tokio::spawn(publish(client.clone(), session.clone(), generation, when));
}

async fn publish(client: Client, session: Arc<Mutex<Session>>, generation: u64, when: When) {
    if when == When::Debounced {
        tokio::time::sleep(debounce()).await;
    }
    let job = |session: &Session| (session.generation() == generation).then(|| session.diagnostics_job());
    let Some(all_job) = job(&*session.lock().await) else { return };
    let mut all = tokio::task::spawn_blocking(move || guarded(|| Ok(compute(all_job, Phase::All))));
    let first = match tokio::time::timeout(LINTS_WAIT, &mut all).await {
        Ok(done) => done,
        Err(_) => {
            // The lints take a while: publish the checks meanwhile.
            let Some(checks_job) = job(&*session.lock().await) else { return };
            let checks =
                tokio::task::spawn_blocking(move || guarded(|| Ok(compute(checks_job, Phase::Checks))));
            if let Some(batch) = outcome(&client, checks.await).await {
                deliver(&client, &session, generation, when, batch).await;
            }
            all.await
        }
    };
    if let Some(batch) = outcome(&client, first).await {
        deliver(&client, &session, generation, when, batch).await;
    }
}

/// The batch of a computation, or `None` when it was cancelled or failed (logged).
async fn outcome(
    client: &Client,
    result: Result<Outcome<Option<Batch>>, tokio::task::JoinError>,
) -> Option<Batch> {
    match result {
        Ok(Outcome::Done(batch)) => batch,
        // Cancelled by a change, which scheduled its own publication.
        Ok(Outcome::Cancelled) => None,
        Ok(Outcome::Panicked(message)) => {
            client.log_message(MessageType::ERROR, format!("hipop: diagnostics failed: {message}")).await;
            None
        }
        Err(e) => {
            client.log_message(MessageType::ERROR, format!("hipop: diagnostics failed: {e}")).await;
            None
        }
    }
}

/// Publishes a batch if nothing changed since generation `generation`.
async fn deliver(client: &Client, session: &Arc<Mutex<Session>>, generation: u64, when: When, batch: Batch) {
    let mut session = session.lock().await;
    if session.generation() != generation {
        return;
    }
    if when == When::NowForced {
        session.forget_published();
    }
    for (uri, version, diags) in batch {
        if session.record_published(&uri, version, &diags) {
            client.publish_diagnostics(uri, diags, Some(version)).await;
        }
    }
}

type Batch = Vec<(Uri, i32, Vec<lsp::Diagnostic>)>;

/// The flaws in `file` of the best partial plans of the last planner runs
/// that found no plan, while the files planned are unchanged (information
/// diagnostics: open links, threats, abstract flaws, I0504–I0506).
fn plan_flaws(job: &DiagnosticsJob, file: SourceFile) -> Cancellable<Vec<Diagnostic>> {
    let mut out = Vec::new();
    for record in job.plans.values() {
        if record.flaws.iter().any(|d| d.file == file) && record.is_current(&job.analysis)? {
            out.extend(record.flaws.iter().filter(|d| d.file == file).cloned());
        }
    }
    Ok(out)
}

/// The diagnostics of every document of the job (at most [`SHOWN_PER_FILE`]
/// each, then how many more); `None` if cancelled. A document whose analysis
/// panics is left out rather than failing the batch.
fn compute(job: DiagnosticsJob, phase: Phase) -> Option<Batch> {
    let mut batch = Vec::new();
    let mut files = Files::new(&job.analysis, &job.open, job.encoding, &job.indexes);
    for (uri, version, file) in &job.docs {
        let one = guarded(|| {
            let diags = match phase {
                Phase::Checks => job.analysis.check_diagnostics(*file)?,
                Phase::All => job.analysis.diagnostics(*file)?,
            };
            let mut mine: Vec<Diagnostic> = diags.into_iter().filter(|d| d.file == *file).collect();
            if phase == Phase::All {
                mine.extend(plan_flaws(&job, *file)?);
            }
            shown_per_file(&mine, SHOWN_PER_FILE).iter().map(|d| convert::diagnostic(d, &mut files)).collect()
        });
        match one {
            Outcome::Done(diags) => batch.push((uri.clone(), *version, diags)),
            Outcome::Cancelled => return None,
            Outcome::Panicked(message) => {
                eprintln!("hipop: diagnostics of {} failed: {message}", uri.as_str())
            }
        }
    }
    Some(batch)
}
