//! Running a request on a snapshot: off the async executor, panic-guarded and
//! cancellable.
//!
//! A request takes a snapshot under the session lock, releases the lock and
//! computes on a blocking thread. A change meanwhile cancels the snapshot's
//! queries (they return `Err(Cancelled)`); the request is then retried once on
//! a fresh snapshot before answering `ContentModified`. A panic becomes a
//! JSON-RPC internal error instead of taking the server down. When the client
//! cancels a request, the framework drops its future, and a drop guard cancels
//! the snapshot so that the blocking thread stops early too.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;

use hipop_analyzer::{Analysis, Cancellable, Cancelled};
use tokio::sync::Mutex;
use tower_lsp_server::jsonrpc::{Error, ErrorCode, Result};
use tower_lsp_server::ls_types::Uri;

use crate::session::{Session, Snapshot, WorkspaceSnapshot};

/// How many snapshots a request tries before giving up on a busy editor.
const ATTEMPTS: usize = 2;

/// How a guarded computation ended.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum Outcome<T> {
    Done(T),
    Cancelled,
    Panicked(String),
}

/// Runs `f`, turning a panic into [`Outcome::Panicked`].
pub(crate) fn guarded<T>(f: impl FnOnce() -> Cancellable<T>) -> Outcome<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(value)) => Outcome::Done(value),
        Ok(Err(Cancelled)) => Outcome::Cancelled,
        Err(payload) => Outcome::Panicked(panic_message(payload.as_ref())),
    }
}

pub(crate) fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_string()
    }
}

/// Calls its closure when dropped: cancels a snapshot whose request was abandoned.
struct OnDrop(Option<Box<dyn FnOnce() + Send>>);

impl Drop for OnDrop {
    fn drop(&mut self) {
        if let Some(f) = self.0.take() {
            f();
        }
    }
}

fn internal_error(method: &str, message: &str) -> Error {
    Error {
        code: ErrorCode::InternalError,
        message: format!("hipop: {method} failed: {message}").into(),
        data: None,
    }
}

/// Answers a request about `uri` with `f` run on a snapshot. A file the
/// analyzer does not know gets the empty answer, `T::default()`.
pub(crate) async fn run<T, F>(session: &Mutex<Session>, uri: &Uri, method: &'static str, f: F) -> Result<T>
where
    T: Default + Send + 'static,
    F: Fn(&Snapshot) -> Cancellable<T> + Send + Sync + 'static,
{
    run_on(session, method, |s| s.snapshot(uri), |s| &s.analysis, f).await
}

/// Answers a request about the whole workspace with `f` run on a snapshot.
pub(crate) async fn run_workspace<T, F>(session: &Mutex<Session>, method: &'static str, f: F) -> Result<T>
where
    T: Default + Send + 'static,
    F: Fn(&WorkspaceSnapshot) -> Cancellable<T> + Send + Sync + 'static,
{
    run_on(session, method, |s| Some(s.workspace_snapshot()), |s| &s.analysis, f).await
}

/// Answers with `f` run on the snapshot `take` takes under the lock; `None`
/// gets the empty answer, `T::default()`.
async fn run_on<S, T, F>(
    session: &Mutex<Session>,
    method: &'static str,
    take: impl Fn(&Session) -> Option<S>,
    analysis: fn(&S) -> &Analysis,
    f: F,
) -> Result<T>
where
    S: Send + 'static,
    T: Default + Send + 'static,
    F: Fn(&S) -> Cancellable<T> + Send + Sync + 'static,
{
    let f = Arc::new(f);
    for _ in 0..ATTEMPTS {
        let Some(snapshot) = take(&*session.lock().await) else { return Ok(T::default()) };
        let token = analysis(&snapshot).cancellation_token();
        let _cancel_if_abandoned = OnDrop(Some(Box::new(move || token.cancel())));
        let f = f.clone();
        let outcome = tokio::task::spawn_blocking(move || guarded(|| f(&snapshot))).await;
        match outcome {
            Ok(Outcome::Done(value)) => return Ok(value),
            Ok(Outcome::Cancelled) => continue,
            Ok(Outcome::Panicked(message)) => return Err(internal_error(method, &message)),
            Err(join_error) => return Err(internal_error(method, &join_error.to_string())),
        }
    }
    Err(Error { code: ErrorCode::ContentModified, message: "the document changed".into(), data: None })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_an_outcome() {
        let quiet = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        let outcome: Outcome<()> = guarded(|| panic!("boom {}", 42));
        std::panic::set_hook(quiet);
        assert_eq!(outcome, Outcome::Panicked("boom 42".to_string()));
        assert_eq!(guarded(|| Err::<(), _>(Cancelled)), Outcome::Cancelled);
        assert_eq!(guarded(|| Ok(1)), Outcome::Done(1));
    }

    #[test]
    fn a_panic_is_an_internal_error() {
        let e = internal_error("hover", "boom");
        assert_eq!(e.code, ErrorCode::InternalError);
        assert!(e.message.contains("hover failed: boom"));
    }
}
