//! The salsa database and its inputs: the files' paths and texts, the
//! workspace (the set of files) and the settings. The bottom layer of the
//! analyzer after the syntax: every query takes a [`Db`], and nothing here
//! depends on what the queries compute.

use std::sync::Arc;

use crate::syntax::{Parse, TextEdit};

/// The database trait every query takes.
#[salsa::db]
pub trait Db: salsa::Database {}

/// A file: its path (for display and to find a problem's domain) and its text.
#[salsa::input(debug)]
pub struct SourceFile {
    #[returns(ref)]
    pub path: String,
    #[returns(ref)]
    pub text: Arc<str>,
    /// The previous parse and the edits that led to `text`, when known: lets
    /// [`crate::db::parse`] re-parse only what changed. Never changes the result.
    #[returns(ref)]
    pub reparse_hint: Option<Arc<ReparseHint>>,
}

/// A previous parse and the edits applied since.
#[derive(Debug)]
pub struct ReparseHint {
    pub base: Parse,
    pub edits: Vec<TextEdit>,
}

/// The files that make up the workspace: a problem's domain is looked up among them.
#[salsa::input(singleton, debug)]
pub struct Workspace {
    #[returns(ref)]
    pub files: Vec<SourceFile>,
}

/// User settings of the analysis (command-line options, editor settings).
#[salsa::input(singleton, debug)]
pub struct Settings {
    /// How much slower than a detour a direct move may be before the triangle
    /// inequality of move durations is reported (Definition 14, property 6),
    /// in the unit of durations.
    #[returns(copy)]
    pub triangle_tolerance: f64,
    /// How plan files of the workspace are validated (tolerance, names).
    #[returns(copy)]
    pub plan_options: ValidationOptions,
    /// Whether each item holds its syntax (the default), or only the path to
    /// it in its file's tree, found again when needed: the command line,
    /// which drops the trees once the items are lowered
    /// ([`crate::AnalysisHost::drop_syntax_after_use`]).
    #[returns(copy)]
    pub syntax_in_items: bool,
}

impl Settings {
    /// VAL's default tolerance between happenings: durations computed from
    /// distances rounded to two decimals differ from the exact sums by that much.
    pub const DEFAULT_TRIANGLE_TOLERANCE: f64 = 0.01;
}

/// The triangle tolerance in force.
pub fn triangle_tolerance(db: &dyn Db) -> f64 {
    Settings::try_get(db).map_or(Settings::DEFAULT_TRIANGLE_TOLERANCE, |s| s.triangle_tolerance(db))
}

/// Whether items hold their syntax ([`Settings::syntax_in_items`]).
pub fn syntax_in_items(db: &dyn Db) -> bool {
    Settings::try_get(db).is_none_or(|s| s.syntax_in_items(db))
}

/// The plan-validation options in force.
pub fn plan_options(db: &dyn Db) -> ValidationOptions {
    Settings::try_get(db).map_or_else(ValidationOptions::default, |s| s.plan_options(db))
}

/// How plans are validated (`hipop validate`'s options, and the settings
/// with which the plan files of the workspace are validated).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValidationOptions {
    /// VAL's `-t`: events closer than `tolerance / 10` are one happening;
    /// durations may miss their constraint by less than it. Default 0.01.
    pub tolerance: f64,
    /// Besides case, `-` and `_` in names are interchangeable (planners
    /// mangle names; pandaPIparser's `-l`).
    pub lenient: bool,
    /// Keep executing after a failed happening (VAL's `-c`), applying its
    /// effects anyway, to find later failures. Later failures may be
    /// consequences of the first.
    pub keep_going: bool,
    /// Hierarchical plans: accept a decomposition's subtasks listed in any
    /// order, not only one the method's ordering allows (pandaPIparser's `-o`).
    pub ignore_listed_order: bool,
}

impl ValidationOptions {
    pub const DEFAULT_TOLERANCE: f64 = 0.01;
}

impl Default for ValidationOptions {
    fn default() -> Self {
        ValidationOptions {
            tolerance: ValidationOptions::DEFAULT_TOLERANCE,
            lenient: false,
            keep_going: false,
            ignore_listed_order: false,
        }
    }
}

/// The concrete database.
#[salsa::db]
#[derive(Clone, Default)]
pub struct RootDatabase {
    storage: salsa::Storage<Self>,
}

impl RootDatabase {
    /// A database that reports every salsa event to `callback` (used by tests
    /// that check what is re-executed).
    pub fn with_event_callback(callback: Box<dyn Fn(salsa::Event) + Send + Sync + 'static>) -> Self {
        RootDatabase { storage: salsa::Storage::new(Some(callback)) }
    }
}

#[salsa::db]
impl salsa::Database for RootDatabase {}

#[salsa::db]
impl Db for RootDatabase {}
