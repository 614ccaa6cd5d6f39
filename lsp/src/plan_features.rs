//! What the editor asks of the last planner runs (see `planning`): inlay
//! hints on a problem, what hover adds, the plan (`hipop/plan`), the repair
//! diff (`hipop/planDiff`), and the plan written beside its problem
//! (`hipop.writePlan`). Each runs on a snapshot, like the other requests.

use std::path::PathBuf;

use hipop_analyzer::Cancellable;
use hipop_analyzer::ide::{PlanHintKind, PlanRun};
use hipop_analyzer::planner::Status;
use hipop_analyzer::planner::output::SolvedPlan;
use serde_json::{Value, json};
use tower_lsp_server::ls_types as lsp;

use crate::planning::status_name;
use crate::session::{PlanRecord, Snapshot};

/// What the summary says when the problem or its domain was edited since.
const OUTDATED: &str = " (edited since: save to plan again)";

/// The record of the run on the snapshot's file.
fn record(snap: &Snapshot) -> Cancellable<Option<&PlanRecord>> {
    let key = snap.analysis.file_path(snap.file)?;
    Ok(snap.plans.get(&key).map(|r| &**r))
}

/// The inlay hints of the last run on the document, in `range`. The hints
/// of goals and tasks are shown only on the text planned; an edited
/// problem keeps its summary, marked out of date.
pub(crate) fn inlay_hints(snap: &Snapshot, range: lsp::Range) -> Cancellable<Option<Vec<lsp::InlayHint>>> {
    let Some(record) = record(snap)? else { return Ok(None) };
    let file = snap.files().get(snap.file)?;
    let current = record.is_current(&snap.analysis)?;
    let mut hints = snap.analysis.plan_hints(snap.file, &record.run)?;
    if !current {
        hints.retain(|h| h.kind == PlanHintKind::Summary);
        for h in &mut hints {
            h.label.push_str(OUTDATED);
        }
    }
    let (start, end) = (file.offset(range.start), file.offset(range.end));
    let hints = hints
        .into_iter()
        .filter(|h| (start..=end).contains(&u32::from(h.offset)))
        .map(|h| {
            let at = file.range(hipop_analyzer::TextRange::empty(h.offset)).start;
            lsp::InlayHint {
                position: at,
                label: lsp::InlayHintLabel::String(h.label),
                kind: None,
                text_edits: None,
                tooltip: h.tooltip.map(lsp::InlayHintTooltip::String),
                padding_left: Some(true),
                padding_right: None,
                data: None,
            }
        })
        .collect();
    Ok(Some(hints))
}

/// What the last plans of the document's problems say of the name at
/// `offset`: the last plan of the problem itself, or of each problem of a
/// domain.
pub(crate) fn hover_addition(snap: &Snapshot, offset: u32) -> Cancellable<Option<String>> {
    if snap.plans.is_empty() {
        return Ok(None);
    }
    let mut plans: Vec<(String, &SolvedPlan)> = Vec::new();
    for problem in snap.analysis.problems_to_plan(snap.file)? {
        let key = snap.analysis.file_path(problem)?;
        if let Some(r) = snap.plans.get(&key)
            && let Some(plan) = &r.run.plan
            && r.run.status == Status::Solved
        {
            plans.push((r.problem_name(), plan));
        }
    }
    snap.analysis.plan_hover(snap.file, offset.into(), &plans)
}

/// The plan's text as `hipop plan` writes it, and its format.
fn plan_text(plan: &SolvedPlan, run: &PlanRun) -> (String, &'static str) {
    let header = format!(
        "hipop plan for problem {} of domain {}\n{}",
        plan.problem,
        plan.domain,
        hipop_analyzer::ide::summary(run)
    );
    if plan.is_hierarchical() {
        (plan.to_hierarchical(&header), "hierarchical")
    } else {
        (plan.to_val(&header), "val")
    }
}

/// `hipop/plan`: the last run on the document: its summary, and when a
/// plan was found its text and its timeline as SVG; `null` before any run.
pub(crate) fn plan(snap: &Snapshot) -> Cancellable<Option<Value>> {
    let Some(record) = record(snap)? else { return Ok(None) };
    let run = &record.run;
    let mut answer = json!({
        "uri": record.uri.as_str(),
        "problem": record.problem_name(),
        "status": status_name(&run.status),
        "summary": hipop_analyzer::ide::summary(run),
        "current": record.is_current(&snap.analysis)?,
        "repaired": run.repair.is_some(),
        "expanded": run.stats.expanded,
        "seconds": run.stats.elapsed.as_secs_f64(),
    });
    if let (Status::Solved, Some(plan)) = (&run.status, &run.plan) {
        let (text, format) = plan_text(plan, run);
        answer["makespan"] = json!(plan.makespan);
        answer["actions"] = json!(plan.primitive().count());
        answer["format"] = json!(format);
        answer["text"] = json!(text);
        answer["svg"] = json!(snap.analysis.solved_plan_svg(record.problem, plan)?);
    }
    Ok(Some(answer))
}

/// `hipop/planDiff`: when the last run repaired an earlier plan, both plans'
/// texts (for a diff view), the two stability figures and the changes;
/// `null` otherwise.
pub(crate) fn plan_diff(snap: &Snapshot) -> Cancellable<Option<Value>> {
    let Some(record) = record(snap)? else { return Ok(None) };
    let run = &record.run;
    let (Some(repair), Some(new)) = (&run.repair, &run.plan) else { return Ok(None) };
    let (a, b, d) = snap.analysis.solved_plan_diff(record.problem, &repair.old, new)?;
    let step = |p: &hipop_analyzer::plan::Plan, i: usize| {
        let s = &p.steps[i];
        let mut text = format!("({}", s.name.text);
        for arg in &s.args {
            text.push(' ');
            text.push_str(&arg.text);
        }
        text.push(')');
        json!({ "step": text, "start": s.start.as_ref().map(|n| n.value) })
    };
    let old_run = PlanRun { plan: Some(repair.old.clone()), repair: None, ..run.clone() };
    let (old_text, _) = plan_text(&repair.old, &old_run);
    let (new_text, format) = plan_text(new, run);
    Ok(Some(json!({
        "uri": record.uri.as_str(),
        "summary": hipop_analyzer::ide::summary(run),
        "format": format,
        "instability": d.instability,
        "distance": d.distance,
        "old": old_text,
        "new": new_text,
        "removed": d.removed.iter().map(|&i| step(&a, i)).collect::<Vec<_>>(),
        "added": d.added.iter().map(|&i| step(&b, i)).collect::<Vec<_>>(),
        "retimed": d.retimed.iter().map(|&(i, j)| json!({ "old": step(&a, i), "new": step(&b, j) })).collect::<Vec<_>>(),
    })))
}

/// Where `hipop.writePlan` writes the plan of a problem: beside it, named
/// like it with `.plan` for its extension.
pub(crate) fn plan_path(problem: &lsp::Uri) -> Option<PathBuf> {
    let path = crate::workspace::uri_path(problem)?;
    Some(path.with_extension("plan"))
}

/// The text `hipop.writePlan` writes, or why there is none.
pub(crate) fn plan_to_write(snap: &Snapshot) -> Cancellable<Option<Result<String, String>>> {
    let Some(record) = record(snap)? else {
        return Ok(Some(Err("no plan for this problem yet: save it to plan it".to_string())));
    };
    let run = &record.run;
    Ok(Some(match (&run.status, &run.plan) {
        (Status::Solved, Some(plan)) => Ok(plan_text(plan, run).0),
        _ => Err(format!("the last run found no plan: {}", hipop_analyzer::ide::summary(run))),
    }))
}
