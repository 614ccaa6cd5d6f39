//! The hipop analyzer: a pure function from file texts to syntax, semantic model
//! and diagnostics, incremental through salsa.
//!
//! Architecture invariant: no I/O, no printing, no LSP types. Positions are
//! byte offsets; the CLI and the server convert them.

pub mod alloc;
pub mod db;
pub mod diagnostic;
pub(crate) mod eval;
pub mod fix;
mod host;
pub mod ide;
pub mod input;
pub mod model;
pub mod plan;
pub mod planner;
pub mod repair;
pub mod semantics;
pub mod syntax;
pub mod validate;
pub mod verify;

pub use db::SourceFile;
pub use diagnostic::{Code, Diagnostic, Fix, Related, Severity, codes};
pub use host::{Analysis, AnalysisHost, Cancellable, Cancelled, PlanningResult, RepairResult};
pub use syntax::{TextEdit, TextRange, TextSize};
