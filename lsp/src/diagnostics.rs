//! Pushing diagnostics for the open documents.
//!
//! Any change can change the diagnostics of other documents (editing a domain
//! changes its problems'), so each publication covers every open document;
//! salsa makes the unchanged ones cheap, and identical re-publications are
//! skipped. A change schedules a publication [`DEBOUNCE`] later; it only runs
//! if nothing changed in between (the session's generation is the same), and
//! it is published under the session lock after checking the generation again,
//! so a publication never describes anything but the latest text.

use std::sync::Arc;
use std::time::Duration;

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

/// Schedules a publication for the state of generation `generation`.
pub(crate) fn schedule(client: &Client, session: &Arc<Mutex<Session>>, generation: u64, when: When) {
    tokio::spawn(publish(client.clone(), session.clone(), generation, when));
}

async fn publish(client: Client, session: Arc<Mutex<Session>>, generation: u64, when: When) {
    if when == When::Debounced {
        tokio::time::sleep(debounce()).await;
    }
    let job = {
        let session = session.lock().await;
        if session.generation() != generation {
            return;
        }
        session.diagnostics_job()
    };
    let batch = match tokio::task::spawn_blocking(move || guarded(|| Ok(compute(job)))).await {
        Ok(Outcome::Done(Some(batch))) => batch,
        // Cancelled by a change, which scheduled its own publication.
        Ok(Outcome::Done(None) | Outcome::Cancelled) => return,
        Ok(Outcome::Panicked(message)) => {
            client.log_message(MessageType::ERROR, format!("hipop: diagnostics failed: {message}")).await;
            return;
        }
        Err(e) => {
            client.log_message(MessageType::ERROR, format!("hipop: diagnostics failed: {e}")).await;
            return;
        }
    };
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

/// The diagnostics of every document of the job; `None` if cancelled. A
/// document whose analysis panics is left out rather than failing the batch.
fn compute(job: DiagnosticsJob) -> Option<Batch> {
    let mut batch = Vec::new();
    let mut files = Files::new(&job.analysis, &job.open, job.encoding, &job.indexes);
    for (uri, version, file) in &job.docs {
        let one = guarded(|| {
            let diags = job.analysis.diagnostics(*file)?;
            diags.iter().filter(|d| d.file == *file).map(|d| convert::diagnostic(d, &mut files)).collect()
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
