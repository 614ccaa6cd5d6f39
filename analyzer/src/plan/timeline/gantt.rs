//! The terminal Gantt chart of a timeline: a time axis, one row per lane
//! (more when steps overlap), each bar labelled with its key (and its name
//! when there is room), then a legend of every bar and the makespan.

use std::fmt::Write as _;

use super::{Bar, RowKind, Timeline, Timing};

/// How [`gantt_text`] draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GanttOptions {
    /// The width of the chart in columns, lane names included. The time axis
    /// gets at least [`GanttOptions::MIN_AXIS`] columns, whatever the width.
    pub width: usize,
    /// Only ASCII characters, for terminals without Unicode.
    pub ascii: bool,
}

impl GanttOptions {
    pub const DEFAULT_WIDTH: usize = 100;
    pub const MIN_AXIS: usize = 20;
}

impl Default for GanttOptions {
    fn default() -> Self {
        GanttOptions { width: GanttOptions::DEFAULT_WIDTH, ascii: false }
    }
}

/// Lane names longer than this are cut.
const LABEL_MAX: usize = 16;

struct Glyphs {
    /// Actions, alternating so that neighbours differ.
    fill: [char; 2],
    instant: char,
    /// Several steps in one column.
    crowded: char,
    side: char,
    rule: char,
    tick_top: char,
    tick_bottom: char,
    corners: [char; 4],
    separator: [char; 3],
    /// Abstract steps: `┌──┐`.
    bracket: [char; 3],
    cut: char,
    arrow: &'static str,
}

const UNICODE: Glyphs = Glyphs {
    fill: ['█', '▒'],
    instant: '◆',
    crowded: '▞',
    side: '│',
    rule: '─',
    tick_top: '┬',
    tick_bottom: '┴',
    corners: ['┌', '┐', '└', '┘'],
    separator: ['├', '╌', '┤'],
    bracket: ['┌', '─', '┐'],
    cut: '…',
    arrow: "→",
};

const ASCII: Glyphs = Glyphs {
    fill: ['#', '='],
    instant: '*',
    crowded: '%',
    side: '|',
    rule: '-',
    tick_top: '+',
    tick_bottom: '+',
    corners: ['+', '+', '+', '+'],
    separator: ['+', '.', '+'],
    bracket: ['[', '-', ']'],
    cut: '~',
    arrow: "->",
};

/// What the chart used, for the key of glyphs.
#[derive(Default)]
struct Used {
    action: bool,
    instant: bool,
    crowded: bool,
    bracket: bool,
}

/// The Gantt chart of `timeline` as text, lines ending in `\n`.
pub fn gantt_text(timeline: &Timeline, options: &GanttOptions) -> String {
    let g = if options.ascii { &ASCII } else { &UNICODE };
    let mut out = String::new();
    if timeline.bars.is_empty() {
        out.push_str("no steps to draw\n");
        undrawn(timeline, &mut out);
        return out;
    }
    let names: Vec<String> = timeline.lanes.iter().map(|l| cut(&l.name, LABEL_MAX, g.cut)).collect();
    let label_w = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
    let cols = options.width.saturating_sub(label_w + 3).max(GanttOptions::MIN_AXIS);
    let col = |t: f64| ((timeline.fraction(t) * cols as f64).round() as usize).min(cols);
    let indent = " ".repeat(label_w + 1);

    // The axis: tick labels over the top rule. A tick is drawn on the cell
    // before its time's boundary (on the borders for the ends): the rule's
    // character `c` is the left border, cell `c - 1`, or the right border.
    let ticks = ticks(timeline, (cols / 10).max(1));
    let mut tick_cols: Vec<(usize, f64)> = Vec::new();
    for &t in &ticks.values {
        let c = col(t);
        let c = if c == cols { cols + 1 } else { c };
        if tick_cols.last().is_none_or(|&(last, _)| last < c) {
            tick_cols.push((c, t));
        }
    }
    let line_len = label_w + 3 + cols;
    let mut labels = vec![' '; line_len];
    let unit = if timeline.timed { "time" } else { "step" };
    let mut free_from = 0;
    if label_w >= unit.len() {
        labels[..unit.len()].copy_from_slice(&unit.chars().collect::<Vec<_>>());
        free_from = unit.len() + 1;
    }
    for &(c, t) in &tick_cols {
        let text: Vec<char> = fmt_tick(t, ticks.step).chars().collect();
        if text.len() > line_len {
            continue;
        }
        // Centred on the tick, inside the line.
        let at = (label_w + 1 + c).saturating_sub((text.len() - 1) / 2).min(line_len - text.len());
        if at < free_from {
            continue;
        }
        labels[at..at + text.len()].copy_from_slice(&text);
        free_from = at + text.len() + 1;
    }
    let labels: String = labels.into_iter().collect();
    let _ = writeln!(out, "{}", labels.trim_end());
    let rule = |tick: char, left: char, right: char| {
        let mut line = vec![g.rule; cols + 2];
        tick_cols.iter().for_each(|&(c, _)| line[c] = tick);
        line[0] = left;
        line[cols + 1] = right;
        format!("{indent}{}", line.into_iter().collect::<String>())
    };
    let _ = writeln!(out, "{}", rule(g.tick_top, g.corners[0], g.corners[1]));

    // The lanes.
    let mut used = Used::default();
    let separate = timeline.lanes.iter().any(|l| l.rows.len() > 1);
    for (l, lane) in timeline.lanes.iter().enumerate() {
        if separate && l > 0 {
            let [left, fill, right] = g.separator;
            let _ = writeln!(out, "{indent}{left}{}{right}", fill.to_string().repeat(cols));
        }
        for (r, row) in lane.rows.iter().enumerate() {
            let name = if r == 0 { names[l].as_str() } else { "" };
            let cells = draw_row(timeline, &row.bars, row.kind, cols, &col, g, &mut used);
            let pad = label_w - name.chars().count();
            let _ = writeln!(out, "{name}{} {}{cells}{}", " ".repeat(pad), g.side, g.side);
        }
    }
    let _ = writeln!(out, "{}", rule(g.tick_bottom, g.corners[2], g.corners[3]));

    // What the glyphs mean, then the legend.
    let mut key = Vec::new();
    if used.action {
        key.push(format!("{}{} action", g.fill[0], g.fill[1]));
    }
    if used.instant {
        key.push(format!("{} instantaneous", g.instant));
    }
    if used.bracket {
        let [l, m, r] = g.bracket;
        key.push(format!("{l}{m}{r} abstract step, over its subtasks"));
    }
    if used.crowded {
        key.push(format!("{} steps too short to tell apart at this width", g.crowded));
    }
    let _ = writeln!(out, "{}", key.join("   "));
    out.push('\n');
    legend(timeline, g, &mut out);
    summary(timeline, &mut out);
    out
}

/// One row of a lane: its bars in `cols` cells.
fn draw_row(
    timeline: &Timeline,
    row: &[usize],
    kind: RowKind,
    cols: usize,
    col: &dyn Fn(f64) -> usize,
    g: &Glyphs,
    used: &mut Used,
) -> String {
    let mut cells = vec![' '; cols];
    let mut next_free = 0;
    let mut alternate = 0;
    for &b in row {
        let bar = &timeline.bars[b];
        let c0 = col(bar.start).min(cols - 1);
        let c1 = if bar.is_instant() { c0 + 1 } else { col(bar.end).clamp(c0 + 1, cols) };
        // Steps of a row do not overlap in time, but may fall in one column.
        let from = c0.max(next_free);
        let to = if from < c1 {
            c1
        } else if from < cols && from == c0 + 1 {
            // One column late rather than hidden.
            from + 1
        } else {
            cells[c0] = g.crowded;
            used.crowded = true;
            continue;
        };
        next_free = to;
        let n = to - from;
        let label = match kind {
            RowKind::Actions if bar.is_instant() => {
                cells[from] = g.instant;
                used.instant = true;
                continue;
            }
            RowKind::Actions => {
                cells[from..to].fill(g.fill[alternate % 2]);
                alternate += 1;
                used.action = true;
                label(bar, n).map(|t| (from, n, t))
            }
            RowKind::Abstract { .. } => {
                used.bracket = true;
                let [left, fill, right] = g.bracket;
                cells[from..to].fill(fill);
                if n >= 2 {
                    cells[from] = left;
                    cells[to - 1] = right;
                    label(bar, n - 2).map(|t| (from + 1, n - 2, t))
                } else {
                    None
                }
            }
        };
        if let Some((at, room, text)) = label {
            let text: Vec<char> = text.chars().collect();
            let at = at + (room - text.len()) / 2;
            cells[at..at + text.len()].copy_from_slice(&text);
        }
    }
    cells.into_iter().collect()
}

/// What a bar of `room` cells shows: its key and name with a cell to spare
/// on each side, else its key with a cell to spare (so that the keys of
/// neighbours do not run together), else nothing.
fn label(bar: &Bar, room: usize) -> Option<String> {
    let full = format!("{} {}", bar.key, bar.name);
    if full.chars().count() + 2 <= room {
        return Some(full);
    }
    let key = bar.key.to_string();
    (key.len() < room).then_some(key)
}

/// Every bar: its key, start, end, id and step (with the method of an abstract step).
fn legend(timeline: &Timeline, g: &Glyphs, out: &mut String) {
    let times: Vec<(String, String)> =
        timeline.bars.iter().map(|b| (fmt_time(timeline, b.start), fmt_time(timeline, b.end))).collect();
    let key_w = timeline.bars.len().to_string().len().max(3);
    let (start_h, end_h) = if timeline.timed { ("start", "end") } else { ("from", "to") };
    let start_w = times.iter().map(|t| t.0.len()).chain([start_h.len()]).max().unwrap_or(0);
    let end_w = times.iter().map(|t| t.1.len()).chain([end_h.len()]).max().unwrap_or(0);
    let ids = timeline.bars.iter().any(|b| b.id.is_some());
    let id_w =
        timeline.bars.iter().filter_map(|b| b.id).map(|i| i.to_string().len()).max().unwrap_or(0).max(2);
    let id_h = if ids { format!("{:>id_w$}  ", "id") } else { String::new() };
    let _ = writeln!(out, "{:>key_w$}  {start_h:>start_w$}  {end_h:>end_w$}  {id_h}step", "key");
    for (b, (start, end)) in timeline.bars.iter().zip(&times) {
        let id = match (ids, b.id) {
            (false, _) => String::new(),
            (true, Some(i)) => format!("{i:>id_w$}  "),
            (true, None) => format!("{:>id_w$}  ", ""),
        };
        let _ = write!(out, "{:>key_w$}  {start:>start_w$}  {end:>end_w$}  {id}{}", b.key, b.call);
        if let Some(m) = &b.method {
            let _ = write!(out, " {} {m}", g.arrow);
        }
        match b.timing {
            Timing::Position if timeline.timed => out.push_str("  (no time: where VAL executes it)"),
            Timing::Subtasks if timeline.timed => out.push_str("  (no time: its subtasks' span)"),
            _ => {}
        }
        out.push('\n');
    }
}

fn summary(timeline: &Timeline, out: &mut String) {
    let plural = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let actions = timeline.actions();
    let abstracts = timeline.bars.len() - actions;
    let mut what = vec![plural(actions, "action", "actions")];
    if abstracts > 0 {
        what.push(plural(abstracts, "abstract step", "abstract steps"));
    }
    what.push(plural(timeline.lanes.len(), "lane", "lanes"));
    if timeline.timed {
        let _ = writeln!(out, "makespan {}: {}", fmt_time(timeline, timeline.makespan), what.join(", "));
    } else {
        let _ = writeln!(out, "no times: one step after the other, in the plan's order; {}", what.join(", "));
    }
    undrawn(timeline, out);
}

fn undrawn(timeline: &Timeline, out: &mut String) {
    let plural = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    if !timeline.undrawn.is_empty() {
        let n = timeline.undrawn.len();
        let _ = writeln!(
            out,
            "{} not drawn: no times of {}, nor subtasks with times",
            plural(n, "abstract step", "abstract steps"),
            if n == 1 { "its own" } else { "their own" }
        );
    }
}

/// A lane name of at most `max` characters.
fn cut(name: &str, max: usize, ellipsis: char) -> String {
    if name.chars().count() <= max {
        return name.to_string();
    }
    let mut s: String = name.chars().take(max - 1).collect();
    s.push(ellipsis);
    s
}

/// The times of the axis's ticks and the step between them.
pub(super) struct Ticks {
    pub values: Vec<f64>,
    pub step: f64,
}

/// About `target` ticks at round times (1, 2 or 5 times a power of ten;
/// whole steps in an untimed plan) from the timeline's start to its end.
pub(super) fn ticks(timeline: &Timeline, target: usize) -> Ticks {
    let (start, end) = (timeline.start, timeline.end);
    let half = end / 2.0 - start / 2.0;
    if half.is_nan() || half <= 0.0 {
        return Ticks { values: vec![start], step: 1.0 };
    }
    let raw = half / target.max(1) as f64 * 2.0;
    let mag = 10f64.powi(raw.log10().floor() as i32);
    let m = raw / mag;
    let nice = if m <= 1.0 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    };
    let mut step = nice * mag;
    if !timeline.timed {
        step = step.max(1.0);
    }
    if !(step > 0.0 && step.is_finite()) {
        return Ticks { values: vec![start, end], step: 1.0 };
    }
    let first = (start / step).ceil() * step;
    let values = (0..=target * 2 + 2)
        .map(|k| first + k as f64 * step)
        .take_while(|&t| t <= end + step * 1e-9)
        .collect();
    Ticks { values, step }
}

/// A tick's label: as few decimals as the step needs.
pub(super) fn fmt_tick(t: f64, step: f64) -> String {
    if t == 0.0 {
        return "0".to_string();
    }
    if t.abs() >= 1e7 || step < 1e-4 {
        return short_exp(&format!("{t:.2e}"));
    }
    let decimals = if step >= 1.0 { 0 } else { ((-step.log10().floor()) as usize).min(4) };
    format!("{t:.decimals$}")
}

/// A time of the legend: three decimals, as VAL prints them; whole steps in
/// an untimed plan.
pub(super) fn fmt_time(timeline: &Timeline, t: f64) -> String {
    if !timeline.timed && t.abs() < 1e15 {
        format!("{t:.0}")
    } else if t.abs() < 1e9 {
        format!("{t:.3}")
    } else {
        short_exp(&format!("{t:.3e}"))
    }
}

/// `1.50e8` → `1.5e8`, `1.00e300` → `1e300`.
fn short_exp(s: &str) -> String {
    match s.split_once('e') {
        Some((mantissa, exp)) if mantissa.contains('.') => {
            format!("{}e{exp}", mantissa.trim_end_matches('0').trim_end_matches('.'))
        }
        _ => s.to_string(),
    }
}
