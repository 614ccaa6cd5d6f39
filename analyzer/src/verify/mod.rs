//! Model verification: the checks a HiPOP mission must pass before the planner
//! can be trusted with it (sections 4.2 and 4.3 of the HiPOP paper).
//!
//! - [`lifted`]: the STRIPS view of actions, tasks and methods the checks share.

pub mod lifted;
