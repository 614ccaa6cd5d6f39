//! Watching the workspace on disk, for clients that do not watch files for
//! the server (Neovim's default, Helix): without it, a domain changed outside
//! the editor (`git checkout`, a regenerated file) would never be reread and
//! its open problems would keep stale diagnostics. A client that registers
//! `workspace/didChangeWatchedFiles` does this job itself, and the server
//! then watches nothing (see `server::initialized`).
//!
//! Each folder the server loaded files from is watched on its own, not
//! recursively: the folders the scan skips (`target/`, `.git/`,
//! `node_modules/`, hidden ones) are not watched at all, and the scan's folder
//! budget bounds the number of watches. A folder created inside a workspace
//! folder is scanned and watched when it appears.
//!
//! Events are gathered until [`DEBOUNCE`] passes without one (a checkout
//! changes many files at once), then read from disk off the executor and
//! applied in one change of the session, which re-publishes the diagnostics of
//! the open documents. Open documents are never reread: their text is the
//! editor's.

use std::collections::{BTreeSet, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Duration;

use notify::{EventKind, RecursiveMode, Watcher};
use tokio::sync::Mutex;
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender, unbounded_channel};
use tower_lsp_server::Client;

use crate::diagnostics::When;
use crate::session::Session;
use crate::workspace::{self, Budget, Scan};

/// The quiet time after the last event before the changes are applied.
pub(crate) const DEBOUNCE: Duration = Duration::from_millis(200);

/// What the watcher reports.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Change {
    /// Something happened at this path: look at the disk to know what.
    Path(PathBuf),
    /// Events were lost (the kernel's queue overflowed): look at everything again.
    Rescan,
}

/// The watches of the folders loaded from disk.
pub(crate) struct DiskWatcher {
    watcher: notify::RecommendedWatcher,
    watched: HashSet<PathBuf>,
}

impl DiskWatcher {
    /// A watcher whose events go to the returned receiver.
    pub(crate) fn new() -> notify::Result<(DiskWatcher, UnboundedReceiver<Change>)> {
        let (tx, rx) = unbounded_channel();
        let watcher = notify::recommended_watcher(move |event| forward(&tx, event))?;
        Ok((DiskWatcher { watcher, watched: HashSet::new() }, rx))
    }

    /// Watches each of `dirs` (not recursively); the message of the first failure, if any.
    pub(crate) fn watch<'a>(&mut self, dirs: impl IntoIterator<Item = &'a PathBuf>) -> Option<String> {
        let mut failure = None;
        for dir in dirs {
            if self.watched.contains(dir) {
                continue;
            }
            match self.watcher.watch(dir, RecursiveMode::NonRecursive) {
                Ok(()) => drop(self.watched.insert(dir.clone())),
                Err(e) => drop(failure.get_or_insert_with(|| format!("cannot watch {}: {e}", dir.display()))),
            }
        }
        failure
    }

    /// Stops watching `root` and the folders under it.
    pub(crate) fn unwatch_under(&mut self, root: &Path) {
        let gone: Vec<PathBuf> = self.watched.iter().filter(|d| d.starts_with(root)).cloned().collect();
        for dir in gone {
            // A folder deleted from disk has lost its watch already.
            let _ = self.watcher.unwatch(&dir);
            self.watched.remove(&dir);
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.watched.len()
    }
}

/// Runs on the watcher's thread: passes on the paths of the events that may
/// change a file's text or existence.
fn forward(tx: &UnboundedSender<Change>, event: notify::Result<notify::Event>) {
    let Ok(event) = event else {
        let _ = tx.send(Change::Rescan);
        return;
    };
    if event.need_rescan() {
        let _ = tx.send(Change::Rescan);
        return;
    }
    // Opening or reading a file changes nothing; a write is also reported as a modification.
    if matches!(event.kind, EventKind::Access(_)) {
        return;
    }
    for path in event.paths {
        let _ = tx.send(Change::Path(path));
    }
}

/// What the session knows of the disk, taken under the lock to decide what to read.
#[derive(Debug, Clone, Default)]
pub(crate) struct Known {
    /// The workspace folders, loaded recursively.
    pub roots: Vec<PathBuf>,
    /// The folders already scanned.
    pub scanned: HashSet<PathBuf>,
    /// The files the analyzer has from disk (for a rescan).
    pub files: Vec<PathBuf>,
    pub budget: Budget,
}

/// What was found on disk for a batch of changes.
#[derive(Debug, Default)]
pub(crate) struct DiskChanges {
    /// Source files that exist, with their text (analyzer key, text).
    pub files: Vec<(String, String)>,
    /// Paths that no longer exist: a file, or a folder and everything under it.
    pub gone: Vec<PathBuf>,
    /// New folders inside a workspace folder, scanned.
    pub scan: Scan,
    /// The budget left after the scan.
    pub budget: Budget,
}

impl DiskChanges {
    pub(crate) fn is_empty(&self) -> bool {
        self.files.is_empty() && self.gone.is_empty() && self.scan.dirs.is_empty()
    }
}

/// Whether `dir`, which exists, is a new folder of the workspace to scan and
/// watch: inside a workspace folder, in a folder already scanned (so none of
/// its parents is skipped), not skipped itself, and not scanned yet.
fn is_new_folder(dir: &Path, known: &Known) -> bool {
    !known.scanned.contains(dir)
        && !workspace::is_skipped_dir(dir)
        && dir.parent().is_some_and(|p| known.scanned.contains(p))
        && known.roots.iter().any(|r| dir.starts_with(r))
}

/// Looks at the disk for each changed path. Blocking: file reads and scans.
/// Only the scans of new folders spend the budget here; the session charges
/// new files to it when it applies the changes.
pub(crate) fn read_changes(changes: BTreeSet<Change>, known: &Known) -> DiskChanges {
    let mut paths: BTreeSet<PathBuf> = BTreeSet::new();
    for change in changes {
        match change {
            Change::Path(p) => drop(paths.insert(p)),
            Change::Rescan => {
                // Every file known, and every entry of every folder known (new files).
                paths.extend(known.files.iter().cloned());
                for dir in &known.scanned {
                    let Ok(entries) = std::fs::read_dir(dir) else { continue };
                    paths.extend(entries.flatten().map(|e| e.path()));
                }
            }
        }
    }
    let mut out = DiskChanges { budget: known.budget, ..DiskChanges::default() };
    for path in paths {
        match std::fs::metadata(&path) {
            Ok(m) if m.is_file() && workspace::is_source(&path) => match workspace::read_text(&path) {
                Some(text) => out.files.push((path.to_string_lossy().into_owned(), text)),
                None => out.gone.push(path),
            },
            Ok(m) if m.is_dir() && is_new_folder(&path, known) => {
                workspace::scan(&path, true, &mut out.budget, &mut out.scan);
            }
            Ok(_) => {}
            Err(_) => out.gone.push(path),
        }
    }
    out
}

/// Applies the changes the watcher reports, debounced, until the watcher is dropped.
pub(crate) async fn run(client: Client, session: Arc<Mutex<Session>>, mut rx: UnboundedReceiver<Change>) {
    while let Some(first) = rx.recv().await {
        let mut batch = BTreeSet::from([first]);
        let mut closed = false;
        loop {
            match tokio::time::timeout(DEBOUNCE, rx.recv()).await {
                Ok(Some(change)) => drop(batch.insert(change)),
                Ok(None) => {
                    closed = true;
                    break;
                }
                Err(_) => break,
            }
        }
        let known = session.lock().await.known();
        let Ok(changes) = tokio::task::spawn_blocking(move || read_changes(batch, &known)).await else {
            continue;
        };
        if !changes.is_empty() {
            crate::server::mutate(&client, &session, "reading files changed on disk", When::Now, |s| {
                s.apply_disk_changes(changes);
                Ok(())
            })
            .await;
        }
        if closed {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_new_folders_of_the_workspace_are_scanned() {
        let root = PathBuf::from("/w");
        let known = Known {
            roots: vec![root.clone()],
            scanned: [PathBuf::from("/w"), PathBuf::from("/w/a"), PathBuf::from("/elsewhere")].into(),
            files: Vec::new(),
            budget: Budget::default(),
        };
        assert!(is_new_folder(Path::new("/w/b"), &known));
        assert!(is_new_folder(Path::new("/w/a/c"), &known));
        assert!(!is_new_folder(Path::new("/w/a"), &known), "already scanned");
        assert!(!is_new_folder(Path::new("/w/target"), &known), "skipped");
        assert!(!is_new_folder(Path::new("/w/.git"), &known), "skipped");
        assert!(!is_new_folder(Path::new("/w/x/y"), &known), "its parent was not scanned");
        assert!(!is_new_folder(Path::new("/elsewhere/d"), &known), "not in a workspace folder");
    }

    /// Real events: a write, a new folder with a domain, a deletion; nothing
    /// from a skipped folder.
    #[test]
    fn reads_what_changed_on_disk() {
        let dir = std::env::temp_dir().join(format!("hipop-lsp-watch-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("target")).unwrap();
        std::fs::write(dir.join("d.pddl"), "(define (domain d))").unwrap();
        let mut known = Known { roots: vec![dir.clone()], ..Known::default() };
        let mut scan = Scan::default();
        workspace::scan(&dir, true, &mut known.budget, &mut scan);
        known.scanned = scan.dirs;

        let (mut watcher, mut rx) = DiskWatcher::new().unwrap();
        assert_eq!(watcher.watch(&known.scanned), None);
        assert_eq!(watcher.len(), 1, "target/ is not watched");
        std::fs::write(dir.join("d.pddl"), "(define (domain e))").unwrap();
        std::fs::write(dir.join("target/t.pddl"), "(define (domain t))").unwrap();
        std::fs::write(dir.join("notes.txt"), "not a source").unwrap();
        std::fs::create_dir(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/s.hddl"), "(define (domain s))").unwrap();
        std::fs::remove_file(dir.join("d.pddl")).unwrap();
        std::fs::write(dir.join("d.pddl"), "(define (domain f))").unwrap();

        let mut batch = BTreeSet::new();
        let deadline = std::time::Instant::now() + Duration::from_secs(10);
        while !batch.contains(&Change::Path(dir.join("sub"))) || batch.len() < 3 {
            assert!(std::time::Instant::now() < deadline, "events so far: {batch:?}");
            if let Ok(change) = rx.try_recv() {
                batch.insert(change);
            } else {
                std::thread::sleep(Duration::from_millis(10));
            }
        }
        assert!(!batch.iter().any(|c| matches!(c, Change::Path(p) if p.starts_with(dir.join("target")))));
        let changes = read_changes(batch, &known);
        let key = |p: &str| dir.join(p).to_string_lossy().into_owned();
        let files: Vec<(String, &str)> = changes.files.iter().map(|(k, t)| (k.clone(), t.as_str())).collect();
        assert_eq!(files, [(key("d.pddl"), "(define (domain f))")]);
        assert_eq!(changes.scan.files, [(key("sub/s.hddl"), "(define (domain s))".to_string())]);
        assert!(changes.scan.dirs.contains(&dir.join("sub")));
        assert!(changes.gone.is_empty(), "{:?}", changes.gone);

        std::fs::remove_dir_all(dir.join("sub")).unwrap();
        let gone = read_changes(BTreeSet::from([Change::Path(dir.join("sub"))]), &known);
        assert_eq!(gone.gone, [dir.join("sub")]);

        // Events lost: every known file and every entry of the known folders are looked at.
        std::fs::write(dir.join("new.pddl"), "(define (domain n))").unwrap();
        known.files = vec![dir.join("d.pddl"), dir.join("old.pddl")];
        let rescan = read_changes(BTreeSet::from([Change::Rescan]), &known);
        let files: Vec<&str> = rescan.files.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(files, [key("d.pddl"), key("new.pddl")]);
        assert_eq!(rescan.gone, [dir.join("old.pddl")]);
        assert_eq!(rescan.budget.files, known.budget.files, "known folders are not scanned again");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
