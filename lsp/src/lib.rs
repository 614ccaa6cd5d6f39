//! The hipop language server.
