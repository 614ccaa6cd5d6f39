//! The timeline as a standalone SVG picture: lanes labelled on the left, a
//! time axis with gridlines, one rectangle per step and lane coloured by its
//! action (with a tooltip), abstract steps as outlined bands over their
//! subtasks, a dashed line joining the lanes of a step with several agents
//! (the meetings of the HiPOP paper's figures), and a key of the colours.
//! Nothing external: no fonts, styles or scripts to fetch.

use std::fmt::Write as _;

use rustc_hash::FxHashMap;

use super::gantt::{fmt_tick, fmt_time, ticks};
use super::{Bar, RowKind, Timeline, Timing};

/// The axis is wide enough for the shortest action to be this wide…
const MIN_BAR_PX: f64 = 8.0;
/// …within these bounds.
const MIN_AXIS_PX: f64 = 800.0;
const MAX_AXIS_PX: f64 = 4000.0;
const CHAR_PX: f64 = 7.0;
/// Lane names longer than this are cut.
const LABEL_MAX: usize = 24;
const TOP: f64 = 56.0;
const ACTION_ROW: f64 = 22.0;
const ABSTRACT_ROW: f64 = 12.0;
const LANE_PAD: f64 = 4.0;
const RIGHT: f64 = 32.0;

/// Colours for action names (Tableau 20), chosen by a hash of the name
/// ([`colours`]).
const PALETTE: [&str; 20] = [
    "#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1", "#ff9da7", "#9c755f",
    "#bab0ac", "#a0cbe8", "#ffbe7d", "#ff9d9a", "#86bcb6", "#8cd17d", "#f1ce63", "#d4a6c8", "#fabfd2",
    "#d7b5a6", "#79706e",
];

/// The preferred colour of an action or task (an index in [`PALETTE`]),
/// from a hash of its name (case ignored).
pub(super) fn preferred_colour(name: &str) -> usize {
    // FNV-1a, 32 bits.
    let mut h: u32 = 0x811c_9dc5;
    for b in name.bytes().map(|b| b.to_ascii_lowercase()) {
        h ^= u32::from(b);
        h = h.wrapping_mul(0x0100_0193);
    }
    h as usize % PALETTE.len()
}

/// The colour of each name of the timeline (lower-cased): its preferred
/// colour, or, when a name met before (in the order of the bars) has it,
/// the next colour of the palette no name has yet, so that the actions of
/// one picture differ while there are colours left.
pub(super) fn colours(timeline: &Timeline) -> FxHashMap<String, &'static str> {
    let mut taken = [false; PALETTE.len()];
    let mut out = FxHashMap::default();
    for b in &timeline.bars {
        let key = b.name.to_ascii_lowercase();
        if out.contains_key(&key) {
            continue;
        }
        let preferred = preferred_colour(&key);
        let slot = (0..PALETTE.len())
            .map(|k| (preferred + k) % PALETTE.len())
            .find(|&c| !taken[c])
            .unwrap_or(preferred);
        taken[slot] = true;
        out.insert(key, PALETTE[slot]);
    }
    out
}

/// Dark or light text, whichever reads on `fill` (`#rrggbb`).
fn text_colour(fill: &str) -> &'static str {
    let channel = |i: usize| u32::from_str_radix(&fill[i..i + 2], 16).unwrap_or(0) as f64;
    let luminance = 0.299 * channel(1) + 0.587 * channel(3) + 0.114 * channel(5);
    if luminance > 140.0 { "#1a1a1a" } else { "#ffffff" }
}

/// `s` with XML's special characters escaped, and the characters XML 1.0
/// does not allow replaced by U+FFFD.
pub(super) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if (c as u32) < 0x20 || c == '\u{fffe}' || c == '\u{ffff}' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

/// A coordinate: one decimal at most.
fn px(v: f64) -> String {
    let s = format!("{v:.1}");
    s.strip_suffix(".0").map_or(s.clone(), str::to_string)
}

/// A lane name of at most [`LABEL_MAX`] characters.
fn cut(name: &str) -> String {
    if name.chars().count() <= LABEL_MAX {
        return name.to_string();
    }
    let mut s: String = name.chars().take(LABEL_MAX - 1).collect();
    s.push('…');
    s
}

/// What a step's tooltip says: the step, its times, its lanes.
fn tooltip(timeline: &Timeline, bar: &Bar) -> String {
    let mut t = String::new();
    if let Some(id) = bar.id {
        let _ = write!(t, "{id} ");
    }
    t.push_str(&bar.call);
    if let Some(m) = &bar.method {
        let _ = write!(t, " → {m}");
    }
    t.push('\n');
    if timeline.timed {
        let _ = write!(
            t,
            "{} – {} (duration {})",
            fmt_time(timeline, bar.start),
            fmt_time(timeline, bar.end),
            fmt_time(timeline, bar.end - bar.start)
        );
    } else {
        let _ = write!(t, "steps {} – {} of the plan (no times)", fmt_time(timeline, bar.start), {
            fmt_time(timeline, bar.end)
        });
    }
    match bar.timing {
        Timing::Position if timeline.timed => t.push_str(", no time in the plan: where VAL executes it"),
        Timing::Subtasks => t.push_str(", the span of its subtasks"),
        _ => {}
    }
    let lanes: Vec<&str> = bar.lanes.iter().map(|&l| timeline.lanes[l].name.as_str()).collect();
    let _ = write!(t, "\n{}: {}", if lanes.len() == 1 { "lane" } else { "lanes" }, lanes.join(", "));
    t
}

/// The timeline as a standalone SVG document.
pub fn svg(timeline: &Timeline) -> String {
    let label_chars = timeline.lanes.iter().map(|l| cut(&l.name).chars().count()).max().unwrap_or(0);
    let left = 16.0 + label_chars.max(4) as f64 * CHAR_PX;
    // Wide enough for the shortest action to show, within bounds.
    let shortest = timeline
        .bars
        .iter()
        .filter(|b| !b.is_abstract() && !b.is_instant())
        .map(|b| timeline.fraction(b.end) - timeline.fraction(b.start))
        .filter(|f| *f > 0.0)
        .fold(1.0, f64::min);
    let axis = (MIN_BAR_PX / shortest).clamp(MIN_AXIS_PX, MAX_AXIS_PX);
    let x = |t: f64| left + timeline.fraction(t) * axis;
    let width = left + axis + RIGHT;

    // Where each lane and row is.
    let mut lane_top = Vec::with_capacity(timeline.lanes.len());
    let mut row_top: Vec<Vec<f64>> = Vec::with_capacity(timeline.lanes.len());
    let mut y = TOP;
    for lane in &timeline.lanes {
        lane_top.push(y);
        y += LANE_PAD;
        let mut tops = Vec::with_capacity(lane.rows.len());
        for row in &lane.rows {
            tops.push(y);
            y += if row.kind == RowKind::Actions { ACTION_ROW } else { ABSTRACT_ROW };
        }
        row_top.push(tops);
        y += LANE_PAD;
    }
    let lanes_bottom = y.max(TOP + ACTION_ROW);

    // The key of colours: each name once, in order of first bar.
    let mut names: Vec<(&str, bool)> = Vec::new();
    for b in &timeline.bars {
        if !names.iter().any(|(n, a)| n.eq_ignore_ascii_case(&b.name) && *a == b.is_abstract()) {
            names.push((&b.name, b.is_abstract()));
        }
    }
    let mut key_items: Vec<(f64, f64, &str, bool)> = Vec::new();
    let (mut kx, mut ky) = (left, lanes_bottom + 36.0);
    for &(name, is_abstract) in &names {
        let w = 18.0 + name.chars().count() as f64 * CHAR_PX + 16.0;
        if kx + w > width && kx > left {
            kx = left;
            ky += 18.0;
        }
        key_items.push((kx, ky, name, is_abstract));
        kx += w;
    }
    let height = if names.is_empty() { lanes_bottom + 24.0 } else { ky + 16.0 };

    let palette = colours(timeline);
    let colour = |name: &str| palette.get(&name.to_ascii_lowercase()).copied().unwrap_or(PALETTE[0]);
    let mut out = String::new();
    let _ = writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#,
        w = px(width),
        h = px(height)
    );
    let actions = timeline.actions();
    let summary = if timeline.timed {
        format!(
            "makespan {} · {actions} action{} · {} lane{}",
            fmt_time(timeline, timeline.makespan),
            if actions == 1 { "" } else { "s" },
            timeline.lanes.len(),
            if timeline.lanes.len() == 1 { "" } else { "s" }
        )
    } else {
        format!(
            "{actions} action{} in the plan's order (no times) · {} lane{}",
            if actions == 1 { "" } else { "s" },
            timeline.lanes.len(),
            if timeline.lanes.len() == 1 { "" } else { "s" }
        )
    };
    let _ = writeln!(out, "<title>Timeline: {}</title>", escape(&summary));
    let _ = writeln!(out, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
    let _ = writeln!(out, r#"<text x="{}" y="20" font-size="14" font-weight="bold">{}</text>"#, px(left), {
        escape(&summary)
    });

    // Lane stripes and names.
    for (l, lane) in timeline.lanes.iter().enumerate() {
        let bottom = lane_top.get(l + 1).copied().unwrap_or(lanes_bottom);
        let fill = if l % 2 == 0 { "#f4f4f4" } else { "#ffffff" };
        let _ = writeln!(
            out,
            r#"<rect x="0" y="{}" width="{}" height="{}" fill="{fill}"/>"#,
            px(lane_top[l]),
            px(width),
            px(bottom - lane_top[l])
        );
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" text-anchor="end" dominant-baseline="middle">{}</text>"#,
            px(left - 8.0),
            px((lane_top[l] + bottom) / 2.0),
            escape(&cut(&lane.name))
        );
    }

    // The axis: gridlines and tick labels, the unit.
    let ticks = ticks(timeline, (axis / 100.0).max(1.0) as usize);
    let _ = writeln!(out, r##"<g stroke="#cccccc" stroke-width="1">"##);
    for &t in &ticks.values {
        let _ = writeln!(
            out,
            r#"<line x1="{x}" y1="{}" x2="{x}" y2="{}"/>"#,
            px(TOP - 6.0),
            px(lanes_bottom),
            x = px(x(t))
        );
    }
    let _ = writeln!(out, "</g>");
    let _ = writeln!(out, r##"<g text-anchor="middle" fill="#444444">"##);
    for &t in &ticks.values {
        let _ = writeln!(out, r#"<text x="{}" y="{}">{}</text>"#, px(x(t)), px(TOP - 10.0), {
            escape(&fmt_tick(t, ticks.step))
        });
    }
    let _ = writeln!(out, "</g>");
    let unit = if timeline.timed { "time" } else { "step" };
    let _ = writeln!(
        out,
        r##"<text x="{}" y="{}" text-anchor="end" fill="#444444">{unit}</text>"##,
        px(left - 8.0),
        px(TOP - 10.0)
    );
    let _ = writeln!(
        out,
        r##"<line x1="{l}" y1="{y}" x2="{r}" y2="{y}" stroke="#888888"/>"##,
        l = px(left),
        r = px(left + axis),
        y = px(TOP)
    );

    // Where a bar is drawn in each of its lanes: (lane, top of its row, row kind).
    let mut places: Vec<Vec<(usize, f64, RowKind)>> = vec![Vec::new(); timeline.bars.len()];
    for (l, lane) in timeline.lanes.iter().enumerate() {
        for (r, row) in lane.rows.iter().enumerate() {
            for &b in &row.bars {
                places[b].push((l, row_top[l][r], row.kind));
            }
        }
    }
    let bar_x = |bar: &Bar| {
        let (x0, x1) = (x(bar.start), x(bar.end));
        if x1 - x0 < 3.0 { (x0 - 1.5, 3.0) } else { (x0, x1 - x0) }
    };

    // Steps with several agents: a dashed line across their lanes.
    let _ = writeln!(out, r##"<g stroke="#333333" stroke-width="1.5" stroke-dasharray="3 2">"##);
    for (b, bar) in timeline.bars.iter().enumerate() {
        if bar.is_abstract() || places[b].len() < 2 {
            continue;
        }
        let (x0, w) = bar_x(bar);
        let centre = |&(_, top, _): &(usize, f64, RowKind)| top + ACTION_ROW / 2.0;
        let y0 = places[b].iter().map(centre).fold(f64::INFINITY, f64::min);
        let y1 = places[b].iter().map(centre).fold(f64::NEG_INFINITY, f64::max);
        let _ = writeln!(
            out,
            r#"<line x1="{cx}" y1="{}" x2="{cx}" y2="{}"/>"#,
            px(y0),
            px(y1),
            cx = px(x0 + w / 2.0)
        );
    }
    let _ = writeln!(out, "</g>");

    // The bars: abstract steps as outlined bands, actions as filled boxes.
    for (b, bar) in timeline.bars.iter().enumerate() {
        let fill = colour(&bar.name);
        let (x0, w) = bar_x(bar);
        let _ = writeln!(out, "<g><title>{}</title>", escape(&tooltip(timeline, bar)));
        for &(_, top, kind) in &places[b] {
            if kind == RowKind::Actions {
                let _ = writeln!(
                    out,
                    r##"<rect x="{}" y="{}" width="{}" height="{}" rx="2" fill="{fill}" stroke="#333333" stroke-width="0.5"/>"##,
                    px(x0),
                    px(top + 3.0),
                    px(w),
                    px(ACTION_ROW - 6.0)
                );
                if w >= bar.name.chars().count() as f64 * 6.5 + 6.0 {
                    let _ = writeln!(
                        out,
                        r#"<text x="{}" y="{}" font-size="11" fill="{}">{}</text>"#,
                        px(x0 + 3.0),
                        px(top + 15.0),
                        text_colour(fill),
                        escape(&bar.name)
                    );
                }
            } else {
                let _ = writeln!(
                    out,
                    r#"<rect x="{}" y="{}" width="{}" height="{}" fill="{fill}" fill-opacity="0.2" stroke="{fill}" stroke-width="1.5"/>"#,
                    px(x0),
                    px(top + 2.0),
                    px(w),
                    px(ABSTRACT_ROW - 4.0)
                );
                if w >= bar.name.chars().count() as f64 * 5.5 + 6.0 {
                    let _ = writeln!(
                        out,
                        r##"<text x="{}" y="{}" font-size="8" fill="#1a1a1a">{}</text>"##,
                        px(x0 + 3.0),
                        px(top + 9.0),
                        escape(&bar.name)
                    );
                }
            }
        }
        let _ = writeln!(out, "</g>");
    }

    // The key of colours.
    for (kx, ky, name, is_abstract) in key_items {
        let fill = colour(name);
        if is_abstract {
            let _ = writeln!(
                out,
                r#"<rect x="{}" y="{}" width="12" height="8" fill="{fill}" fill-opacity="0.2" stroke="{fill}" stroke-width="1.5"/>"#,
                px(kx),
                px(ky - 8.0)
            );
        } else {
            let _ = writeln!(
                out,
                r##"<rect x="{}" y="{}" width="12" height="12" fill="{fill}" stroke="#333333" stroke-width="0.5"/>"##,
                px(kx),
                px(ky - 10.0)
            );
        }
        let _ = writeln!(out, r#"<text x="{}" y="{}">{}</text>"#, px(kx + 18.0), px(ky), escape(name));
    }
    let _ = writeln!(out, "</svg>");
    out
}
