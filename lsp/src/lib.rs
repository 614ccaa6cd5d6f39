//! The hipop language server: LSP over stdio, on top of the analyzer.
//!
//! Architecture invariant: LSP types (`ls_types`) appear only in this crate;
//! the analyzer answers in byte offsets and plain data, and `convert` turns
//! them into LSP in the encoding negotiated with the client.

mod capabilities;
mod convert;
mod diagnostics;
mod document;
mod features;
mod line_index;
mod plan_features;
mod planning;
mod requests;
mod server;
mod session;
mod watch;
mod workspace;

use std::time::Duration;

use tower_lsp_server::{LspService, Server};

/// Serves LSP on stdin/stdout until the client sends `exit` or closes stdin.
pub fn run_stdio() -> std::io::Result<()> {
    let runtime = tokio::runtime::Builder::new_multi_thread().enable_all().build()?;
    runtime.block_on(async {
        let (service, socket) = LspService::build(server::Backend::new)
            .custom_method("hipop/plan", server::Backend::plan_request)
            .custom_method("hipop/planDiff", server::Backend::plan_diff_request)
            .finish();
        Server::new(tokio::io::stdin(), tokio::io::stdout(), socket).serve(service).await;
    });
    // Tokio reads stdin on a blocking thread that may never return; don't wait for it.
    runtime.shutdown_timeout(Duration::from_millis(100));
    Ok(())
}
