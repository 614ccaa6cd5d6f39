//! Planning on save. Saving a problem (or a domain: each open problem of
//! it) runs the HiPOP planner on a blocking thread with the time budget of
//! the settings, reports `$/progress` while it runs, and keeps the run in
//! the session: inlay hints, hover, the flaws as diagnostics, `hipop/plan`,
//! `hipop/planDiff` and `hipop.writePlan` read it.
//!
//! When the problem changed since its last plan (same domain), the run
//! repairs that plan instead of planning from scratch (section 5 of the
//! HiPOP paper), and shows what changed.
//!
//! Every edit and every save bumps [`Planning::epoch`]: a run polls it and
//! stops, so a newer text never waits for an older plan. A change of the
//! inputs that is not an edit (a file opened, a file changed on disk) also
//! interrupts the search (the analyzer's snapshot is cancelled); the run then
//! starts again on the new inputs.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use hipop_analyzer::ide::{PlanRun, RepairSummary};
use hipop_analyzer::plan::PlanFormat;
use hipop_analyzer::planner::output::SolvedPlan;
use hipop_analyzer::planner::{Config, PlannerLimits, Progress, Status};
use hipop_analyzer::repair::RepairOptions;
use hipop_analyzer::{Analysis, AnalysisHost, Cancellable, Diagnostic, Related, Severity, SourceFile};
use serde_json::{Value, json};
use tokio::sync::{Mutex, mpsc};
use tower_lsp_server::ls_types::{self as lsp, MessageType, NumberOrString, ProgressToken, Uri};
use tower_lsp_server::{Client, NotCancellable, OngoingProgress, Unbounded};

use crate::convert::file_key;
use crate::diagnostics::{self, When};
use crate::requests::{Outcome, guarded};
use crate::session::{PlanRecord, PlanSettings, Session};

/// How many times a run interrupted by a change that is not an edit starts again.
const RESTARTS: usize = 3;

/// The heap a run may use, in bytes.
const MEMORY_LIMIT: usize = 2 << 30;

/// The state of planning shared by the handlers, outside the session lock
/// so that an edit cancels a run without waiting for anything.
#[derive(Default)]
pub(crate) struct Planning {
    epoch: Arc<AtomicU64>,
    tokens: AtomicU64,
}

impl Planning {
    /// Stops the runs in progress (an edit, a save).
    pub(crate) fn cancel(&self) -> u64 {
        self.epoch.fetch_add(1, Ordering::SeqCst) + 1
    }
}

/// The notification sent when a run ends: `hipop/planned`.
pub(crate) enum Planned {}

impl lsp::notification::Notification for Planned {
    type Params = Value;
    const METHOD: &'static str = "hipop/planned";
}

/// Plans the problems a save of `uri` concerns.
pub(crate) async fn on_save(client: Client, session: Arc<Mutex<Session>>, planning: Arc<Planning>, uri: Uri) {
    let epoch = planning.cancel();
    let (analysis, file, settings) = {
        let s = session.lock().await;
        let Some(file) = s.file(&file_key(&uri)) else { return };
        (s.analysis(), file, s.plan_settings)
    };
    if !settings.on_save {
        return;
    }
    let found = tokio::task::spawn_blocking(move || {
        guarded(|| {
            let problems = analysis.problems_to_plan(file)?;
            problems.into_iter().map(|p| Ok((p, analysis.file_path(p)?))).collect::<Cancellable<Vec<_>>>()
        })
    })
    .await;
    let Ok(Outcome::Done(problems)) = found else { return };
    for (problem, key) in problems {
        // A domain's problems are planned when they are open.
        if problem != file && !session.lock().await.is_open(&key) {
            continue;
        }
        if planning.epoch.load(Ordering::SeqCst) != epoch {
            return;
        }
        plan_one(&client, &session, &planning, epoch, problem, key).await;
    }
}

/// Plans one problem and keeps the run, unless a newer edit or save came.
async fn plan_one(
    client: &Client,
    session: &Arc<Mutex<Session>>,
    planning: &Arc<Planning>,
    epoch: u64,
    problem: SourceFile,
    key: String,
) {
    for _ in 0..RESTARTS {
        let (analysis, previous, settings, features, uri) = {
            let s = session.lock().await;
            let Some(uri) = s.uri_of(&key) else { return };
            (s.analysis(), s.plan(&key), s.plan_settings, s.client_features, uri)
        };
        let progress = if features.progress { begin_progress(client, planning, &uri).await } else { None };
        let (tx, mut rx) = mpsc::unbounded_channel::<Progress>();
        let current = planning.epoch.clone();
        let job_uri = uri.clone();
        let (done_tx, mut done) = tokio::sync::oneshot::channel();
        let spawned = std::thread::Builder::new().name("hipop-plan".to_string()).spawn(move || {
            lower_priority();
            let cancel = move || current.load(Ordering::SeqCst) != epoch;
            let mut report = move |p: &Progress| {
                // The receiver is gone only once the run is over.
                let _ = tx.send(*p);
            };
            let outcome =
                guarded(move || run(analysis, problem, job_uri, previous, settings, &cancel, &mut report));
            let _ = done_tx.send(outcome);
        });
        if let Err(e) = spawned {
            client.log_message(MessageType::ERROR, format!("hipop: cannot start planning: {e}")).await;
            return;
        }
        let outcome = loop {
            tokio::select! {
                finished = &mut done => break finished,
                Some(p) = rx.recv() => {
                    if let Some(progress) = &progress {
                        let message = format!("{} plans expanded, best f {:.2}", p.expanded, p.best_f);
                        progress.report(message).await;
                    }
                }
            }
        };
        let stale = planning.epoch.load(Ordering::SeqCst) != epoch;
        let (record, summary) = match outcome {
            _ if stale => (None, "cancelled by an edit".to_string()),
            Ok(Outcome::Done(Some(record))) => {
                let summary = hipop_analyzer::ide::summary(&record.run);
                (Some(record), summary)
            }
            Ok(Outcome::Done(None)) => (None, "no problem to plan in this file".to_string()),
            Ok(Outcome::Cancelled) => {
                if let Some(progress) = progress {
                    progress.finish_with_message("interrupted by a change: planning again").await;
                }
                continue;
            }
            Ok(Outcome::Panicked(message)) => {
                client.log_message(MessageType::ERROR, format!("hipop: planning failed: {message}")).await;
                (None, "planning failed: see the server's log".to_string())
            }
            // The thread ended without an answer (it cannot: `guarded`).
            Err(_) => (None, "planning failed".to_string()),
        };
        if let Some(progress) = progress {
            progress.finish_with_message(summary.clone()).await;
        }
        let Some(record) = record else { return };
        let notice = json!({
            "uri": uri.as_str(),
            "status": status_name(&record.run.status),
            "summary": summary,
            "repaired": record.run.repair.is_some(),
        });
        let generation = {
            let mut s = session.lock().await;
            if planning.epoch.load(Ordering::SeqCst) != epoch {
                return;
            }
            s.keep_plan(key.clone(), record);
            s.generation()
        };
        diagnostics::schedule(client, session, generation, When::NowForced);
        if features.inlay_hint_refresh {
            // A client that cannot refresh asks again on its next change.
            let _ = client.inlay_hint_refresh().await;
        }
        client.send_notification::<Planned>(notice).await;
        return;
    }
}

/// Gives the calling thread (the planner's) the lowest scheduling priority:
/// on a machine with fewer cores than busy threads, the diagnostics of an
/// edit get the processor first, while the search notices its cancellation
/// and frees its plans. On Linux the nice value is per thread.
fn lower_priority() {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: gettid has no preconditions; setpriority only reads its
        // arguments, and lowering a priority is always permitted. A failure
        // leaves the priority as it was, which is harmless.
        unsafe {
            let tid = libc::syscall(libc::SYS_gettid) as libc::id_t;
            libc::setpriority(libc::PRIO_PROCESS, tid, 19);
        }
    }
}

/// Creates a progress token and begins the report, when the client agrees.
async fn begin_progress(
    client: &Client,
    planning: &Planning,
    uri: &Uri,
) -> Option<OngoingProgress<Unbounded, NotCancellable>> {
    let n = planning.tokens.fetch_add(1, Ordering::SeqCst);
    let token: ProgressToken = NumberOrString::String(format!("hipop/plan/{n}"));
    client.create_work_done_progress(token.clone()).await.ok()?;
    let name = uri.as_str().rsplit('/').next().unwrap_or_default().to_string();
    Some(client.progress(token, format!("hipop: planning {name}")).with_message("grounding").begin().await)
}

pub(crate) fn status_name(status: &Status) -> &'static str {
    match status {
        Status::Solved => "solved",
        Status::NoPlan => "no-plan",
        Status::Limit(_) => "limit",
        Status::Refused => "refused",
    }
}

/// One run: a repair of the last plan when only the problem changed since,
/// else a plan from scratch; `None` when there is nothing to plan (no
/// problem in the file).
///
/// The search runs on a database of its own, holding copies of the files
/// planned: the session's snapshot is dropped first, so that an edit never
/// waits for the search to notice that it is cancelled (a change of the
/// session's inputs waits for every snapshot of them to be dropped).
fn run(
    analysis: Analysis,
    problem: SourceFile,
    uri: Uri,
    previous: Option<Arc<PlanRecord>>,
    settings: PlanSettings,
    cancel: &dyn Fn() -> bool,
    progress: &mut dyn FnMut(&Progress),
) -> Cancellable<Option<PlanRecord>> {
    let files = analysis.plan_inputs(problem)?;
    let mut inputs = Vec::new();
    for &f in &files {
        inputs.push((f, analysis.file_text(f)?));
    }
    // The last plan found, and whether the domain is still the one it was found for.
    let base = previous.as_ref().and_then(|p| p.base.clone());
    if let Some(prev) = &previous
        && !matches!(prev.run.status, Status::Limit(_))
        && prev.is_current(&analysis)?
        && prev.inputs.len() == inputs.len()
    {
        // Nothing changed since: the same verdict (a limit reached is
        // tried again: the time limit may have changed).
        return Ok(Some(PlanRecord { uri, ..PlanRecord::clone(prev) }));
    }
    let mut errors = false;
    for &f in &files {
        errors |= analysis.check_diagnostics(f)?.iter().any(|d| d.severity == Severity::Error && d.file == f);
    }
    let time_limit = Some(settings.time_limit);
    if errors {
        let run = PlanRun {
            status: Status::Refused,
            plan: None,
            stats: Default::default(),
            time_limit,
            flaws: 0,
            repair: None,
        };
        return Ok(Some(PlanRecord { uri, problem, run, flaws: Vec::new(), inputs, base }));
    }
    // The run's own database: the files by their keys, so that what it
    // says of them maps back to the session's.
    let mut keys = Vec::new();
    for &(f, _) in &inputs {
        keys.push(analysis.file_path(f)?);
    }
    drop(analysis);
    let mut host = AnalysisHost::new();
    let own: Vec<SourceFile> =
        keys.iter().zip(&inputs).map(|(k, (_, text))| host.set_file_text(k, text.clone())).collect();
    let to_session = |file: SourceFile| own.iter().position(|&f| f == file).map(|i| inputs[i].0);
    let analysis = host.analysis();
    let problem_in_session = problem;
    let problem = own[0];
    let config = Config::parse(Config::DEFAULT).unwrap_or_default();
    let limits = PlannerLimits {
        time: time_limit,
        memory: Some(MEMORY_LIMIT),
        memory_in_use: Some(hipop_analyzer::alloc::in_use),
        ..PlannerLimits::default()
    };
    let same_domain = |b: &crate::session::PlanBase| b.inputs.iter().skip(1).eq(inputs.iter().skip(1));
    let (run, flaws) = match base.as_ref().filter(|b| same_domain(b)) {
        Some(b) => {
            let old = &b.plan;
            let options = RepairOptions::default();
            let text = old.to_json();
            let Some(r) = analysis.run_repair_text(
                problem,
                &text,
                Some(PlanFormat::Json),
                &config,
                &limits,
                &options,
                cancel,
                progress,
            )?
            else {
                return Ok(None);
            };
            let repair = match (&r.status, &r.plan) {
                (Status::Solved, Some(new)) => {
                    let (_, _, d) = analysis.solved_plan_diff(problem, old, new)?;
                    Some(RepairSummary {
                        old: SolvedPlan::clone(old),
                        instability: d.instability,
                        distance: d.distance,
                    })
                }
                _ => None,
            };
            let flaws = r.diagnostics.len();
            let run = PlanRun { status: r.status, plan: r.plan, stats: r.stats, time_limit, flaws, repair };
            (run, r.diagnostics)
        }
        None => {
            let Some(r) = analysis.run_planner(problem, &config, &limits, cancel, progress)? else {
                return Ok(None);
            };
            r.into_run(time_limit)
        }
    };
    // What the planner says of the problem is information in the editor:
    // the files are not wrong because no plan was found. Only what is said
    // of the files planned is kept.
    let flaws = flaws
        .into_iter()
        .filter_map(|d| {
            let file = to_session(d.file)?;
            let related = d
                .related
                .into_iter()
                .filter_map(|r| Some(Related { file: to_session(r.file)?, ..r }))
                .collect();
            Some(Diagnostic { severity: Severity::Info, file, related, fix: None, ..d })
        })
        .collect();
    let problem = problem_in_session;
    let base = match (&run.status, &run.plan) {
        (Status::Solved, Some(plan)) => {
            Some(Arc::new(crate::session::PlanBase { plan: plan.clone(), inputs: inputs.clone() }))
        }
        _ => base,
    };
    Ok(Some(PlanRecord { uri, problem, run, flaws, inputs, base }))
}
