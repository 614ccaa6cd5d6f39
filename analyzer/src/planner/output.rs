//! What the planner hands back: the solved plan with its earliest schedule
//! ([`SolvedPlan`]), written in VAL's format, in the IPC 2020 hierarchical
//! format with hipop's timing annotations, or as hipop's JSON plan
//! (docs/plan-formats.md); and, when there is no plan, the flaws of the best
//! partial plan located in the domain and the problem.

use std::fmt::Write;

use serde_json::{Value, json};

use super::heuristic::Heuristic;
use super::plan::{GOAL, Kind, OpenOrigin, Plan, ThreatKind};
use super::stn::{ORIGIN, Tp};
use super::task::{End, Task, atom_of, is_neg};
use crate::db::{Db, lower_item};
use crate::diagnostic::codes;
use crate::model::ItemData;
use crate::semantics::symbols::Loc;
use crate::verify::Lint;

/// A step of a solved plan.
#[derive(Debug, Clone, PartialEq)]
pub struct SolvedStep {
    pub id: usize,
    pub name: String,
    pub args: Vec<String>,
    pub agents: Vec<String>,
    /// When it starts: the earliest schedule, written as [`tidy`] gives it.
    pub start: f64,
    /// `start + duration` when the step has a duration, as VAL computes it.
    pub end: f64,
    /// The model's duration, exactly (a durative action, an abstract action
    /// that declares one); `None` for an `:action` and an HDDL task.
    pub duration: Option<f64>,
    /// A durative action (VAL writes its duration); abstract steps are not.
    pub durative: bool,
    pub is_abstract: bool,
    pub method: Option<String>,
    /// Subtasks, in start order.
    pub subtasks: Vec<usize>,
    /// Earliest and latest start, earliest and latest end, without delaying the plan's end.
    pub bounds: [(f64, f64); 2],
}

impl SolvedStep {
    /// How long the step lasts as written: its duration, else its span.
    pub fn length(&self) -> f64 {
        self.duration.unwrap_or_else(|| tidy(self.end - self.start))
    }
}

/// A causal link: `None` is the initial state (`from`) or the goal (`to`).
#[derive(Debug, Clone, PartialEq)]
pub struct SolvedLink {
    pub from: Option<usize>,
    pub to: Option<usize>,
    pub predicate: String,
    pub args: Vec<String>,
    pub negated: bool,
}

/// A time point: `None` is the origin; `true` for a step's end.
pub type SolvedPoint = Option<(usize, bool)>;

/// `min ≤ to − from ≤ max`.
#[derive(Debug, Clone, PartialEq)]
pub struct SolvedOrder {
    pub from: SolvedPoint,
    pub to: SolvedPoint,
    pub min: Option<f64>,
    pub max: Option<f64>,
}

/// A plan the planner found, with everything the output formats need.
#[derive(Debug, Clone, PartialEq)]
pub struct SolvedPlan {
    pub domain: String,
    pub problem: String,
    pub hash: String,
    /// Primitive steps first, by start time; then abstract steps.
    pub steps: Vec<SolvedStep>,
    pub root: Vec<usize>,
    pub causal_links: Vec<SolvedLink>,
    pub temporal_links: Vec<SolvedOrder>,
    pub makespan: f64,
}

/// Builds the solved plan from the search's final plan.
pub fn solved(db: &dyn Db, task: &Task<'_>, p: &Plan) -> SolvedPlan {
    let g = task.g;
    // Names as declared: matching is case-insensitive, but a verifier that
    // compares names exactly (pandaPIparser without `-l`) rejects
    // `groundstation2` for `GroundStation2`.
    let obj = |o: u32| g.objects.declared(o).to_string();
    let declared = |item, key: &str| match &lower_item(db, item).data {
        ItemData::Action(a) => a.name.text().to_string(),
        ItemData::Task(t) => t.name.text().to_string(),
        ItemData::Method(m) => m.name.text().to_string(),
        _ => key.to_string(),
    };
    // Output order: primitive steps by start, then abstract ones by start.
    // A choice among an `:htn` task's instances is not written: the
    // instance chosen is a root. Nor is a choice among a split subtask's
    // instances: the instance chosen is a subtask of the choice's method.
    let choice = |s: u32| p.op_of(s).is_some_and(|o| task.ops[o as usize].choice);
    let mut order: Vec<u32> =
        (0..p.steps.len() as u32).filter(|&s| p.op_of(s).is_some() && !choice(s)).collect();
    let key = |s: u32| {
        let st = p.steps[s as usize];
        let abs = task.ops[p.op_of(s).expect("op step") as usize].is_abstract;
        (abs, p.stn.est(st.start), st.start)
    };
    order.sort_by(|&a, &b| {
        let (ka, kb) = (key(a), key(b));
        ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1)).then(ka.2.cmp(&kb.2))
    });
    let mut id_of = vec![usize::MAX; p.steps.len()];
    for (i, &s) in order.iter().enumerate() {
        id_of[s as usize] = i;
    }
    let horizon = p.stn.est(p.goal_tp);
    let lst = p.stn.latest(horizon);
    // Times as written: the earliest schedule (exact durations, dependent
    // happenings ε apart), each time the shortest decimal within `TIDY` of
    // it. A step with a duration ends its written start plus its exact
    // duration later, as VAL computes its end.
    let at = |tp: u32| tidy(p.stn.est(tp));
    let mut steps: Vec<SolvedStep> = order
        .iter()
        .enumerate()
        .map(|(i, &s)| {
            let st = p.steps[s as usize];
            let op = &task.ops[p.op_of(s).expect("op step") as usize];
            let start = at(st.start);
            let duration = if op.instant { None } else { op.duration.or_else(|| p.fixed_duration(s)) };
            let end = duration.map_or_else(|| at(st.end), |d| start + d);
            SolvedStep {
                id: i,
                name: declared(op.item, &op.name),
                args: op.args.iter().map(|&o| obj(o)).collect(),
                agents: op.agents.iter().map(|&o| obj(o)).collect(),
                start,
                end,
                duration,
                durative: !op.is_abstract && !op.instant,
                is_abstract: op.is_abstract,
                method: st.method.map(|m| {
                    let m = &task.methods[m as usize];
                    declared(m.item, &m.name)
                }),
                subtasks: Vec::new(),
                bounds: [
                    (start, tidy(lst[st.start as usize]).max(start)),
                    (end, tidy(lst[st.end as usize]).max(end)),
                ],
            }
        })
        .collect();
    let mut root = Vec::new();
    for &s in &order {
        // A step chosen for a split subtask is its method's.
        let mut parent = p.steps[s as usize].parent;
        while let Some(q) = parent.filter(|&q| choice(q)) {
            parent = p.steps[q as usize].parent;
        }
        match parent {
            Some(parent) => {
                let (pid, cid) = (id_of[parent as usize], id_of[s as usize]);
                steps[pid].subtasks.push(cid);
            }
            None => root.push(id_of[s as usize]),
        }
    }
    for st in &mut steps {
        let mut subs = std::mem::take(&mut st.subtasks);
        subs.sort_by(|&a, &b| {
            (steps_start(&order, p, a)).total_cmp(&steps_start(&order, p, b)).then(a.cmp(&b))
        });
        st.subtasks = subs;
    }
    root.sort_by(|&a, &b| steps_start(&order, p, a).total_cmp(&steps_start(&order, p, b)).then(a.cmp(&b)));
    let step_ref = |s: u32| -> Option<Option<usize>> {
        match p.steps[s as usize].kind {
            Kind::Init | Kind::Goal => Some(None),
            Kind::Til(_) => None,
            Kind::Op(_) => Some(Some(id_of[s as usize]).filter(|&id| id != usize::MAX)),
        }
    };
    let causal_links = p
        .links
        .iter()
        .filter_map(|l| {
            let from = step_ref(l.from)?;
            let to = step_ref(l.to)?;
            let atom = atom_of(l.lit);
            Some(SolvedLink {
                from,
                to,
                predicate: g.predicates.name(g.atoms.pred(atom)).to_string(),
                args: g.atoms.args(atom).iter().map(|&o| obj(o)).collect(),
                negated: is_neg(l.lit),
            })
        })
        .collect();
    // Time point → step point.
    let mut point: Vec<Option<SolvedPoint>> = vec![None; p.stn.len()];
    point[ORIGIN as usize] = Some(None);
    // A choice's points are its instance's (the step it refines into,
    // within it): orderings through the choice hold for the instance.
    let mut written = id_of.clone();
    for (s, st) in p.steps.iter().enumerate() {
        if let Some(q) = st.parent.filter(|&q| choice(q)) {
            written[q as usize] = id_of[s];
        }
    }
    for (s, st) in p.steps.iter().enumerate() {
        if let Kind::Op(_) = st.kind {
            let id = written[s];
            if id == usize::MAX {
                continue;
            }
            point[st.start as usize] = Some(Some((id, false)));
            if st.end != st.start {
                point[st.end as usize] = Some(Some((id, true)));
            }
        }
    }
    let mut temporal_links = Vec::new();
    for a in 0..p.stn.len() as Tp {
        for e in p.stn.edges(a) {
            let (Some(from), Some(to)) = (point[a as usize], point[e.to as usize]) else { continue };
            let same_step = matches!((from, to), (Some((x, _)), Some((y, _))) if x == y);
            if same_step || e.w < 0.0 && to.is_some() {
                continue;
            }
            if to.is_none() {
                // t_0 ≥ t_a − d: a deadline of `a`.
                temporal_links.push(SolvedOrder { from: None, to: from, min: None, max: Some(-e.w) });
            } else {
                temporal_links.push(SolvedOrder { from, to, min: Some(e.w), max: None });
            }
        }
    }
    let domain_unit = crate::semantics::check::domain_for(db, task.problem);
    let domain = domain_unit.and_then(|d| d.name(db).clone()).unwrap_or_default();
    let problem = task.problem.name(db).clone().unwrap_or_default();
    let hash = crate::plan::json::problem_hash(
        &domain_unit.map(|d| d.file(db).text(db).to_string()).unwrap_or_default(),
        task.problem.file(db).text(db),
    );
    let makespan = steps.iter().filter(|s| !s.is_abstract).map(|s| s.end).fold(0.0, f64::max);
    let _ = GOAL;
    SolvedPlan { domain, problem, hash, steps, root, causal_links, temporal_links, makespan }
}

fn steps_start(order: &[u32], p: &Plan, id: usize) -> f64 {
    p.stn.est(p.steps[order[id] as usize].start)
}

/// How far a written time may be from the schedule's: far below every
/// tolerance a plan is checked at (VAL's happenings are a tenth of it wide,
/// 1e-5 at 1e-4), and two of them together below the validator's 1e-9
/// slack on separations, so that happenings ε apart stay ε apart.
const TIDY: f64 = 1e-10;

/// The number with the fewest decimals within [`TIDY`] of `x`: the
/// schedule's sums are written as the decimals they stand for
/// (`0.1 + 0.2` as 0.3, not 0.30000000000000004). Durations are never
/// tidied: they are written exactly.
pub fn tidy(x: f64) -> f64 {
    if !x.is_finite() {
        return x;
    }
    for decimals in 0..=17 {
        if let Ok(v) = format!("{x:.decimals$}").parse::<f64>()
            && (v - x).abs() <= TIDY
        {
            return v;
        }
    }
    x
}

/// A number as written in a plan: the shortest text that reads back as the
/// same `f64` (Rust's `Display`: never an exponent, which VAL cannot read).
fn num(x: f64) -> String {
    // No `-0`.
    let x = if x == 0.0 { 0.0 } else { x };
    format!("{x}")
}

impl SolvedPlan {
    /// The primitive steps, by start time.
    pub fn primitive(&self) -> impl Iterator<Item = &SolvedStep> {
        self.steps.iter().filter(|s| !s.is_abstract)
    }

    pub fn is_hierarchical(&self) -> bool {
        self.steps.iter().any(|s| s.is_abstract)
    }

    /// For each primitive step, its id and the plan left without it and
    /// without the steps whose every causal link served only removed steps.
    /// None of these plans is valid when the plan has no redundant step: how
    /// the plan bench and the tests check it.
    pub fn without_each_step(&self) -> impl Iterator<Item = (usize, SolvedPlan)> + '_ {
        let n = self.steps.len();
        // The producers of each step's conditions, and how many consumers
        // each producer serves (the goal counts, and is never removed).
        let mut producers: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut serves = vec![0usize; n];
        for l in &self.causal_links {
            if let Some(from) = l.from.filter(|&f| f < n) {
                serves[from] += 1;
                if let Some(to) = l.to.filter(|&t| t < n) {
                    producers[to].push(from);
                }
            }
        }
        self.primitive().map(|st| st.id).filter(move |&s| s < n).map(move |s| {
            let mut removed = vec![false; n];
            let mut left = serves.clone();
            let mut work = vec![s];
            removed[s] = true;
            while let Some(r) = work.pop() {
                for &p in &producers[r] {
                    left[p] -= 1;
                    if left[p] == 0 && !removed[p] {
                        removed[p] = true;
                        work.push(p);
                    }
                }
            }
            let mut rest = self.clone();
            rest.steps.retain(|st| !removed.get(st.id).copied().unwrap_or(false));
            (s, rest)
        })
    }

    /// VAL's format: `0.000: (move r1 a b) [30.980]`, by start time.
    pub fn to_val(&self, header: &str) -> String {
        let mut out = String::new();
        for line in header.lines() {
            let _ = writeln!(out, "; {line}");
        }
        for s in self.primitive() {
            let _ = write!(out, "{}: ({}", num(s.start), s.name);
            for a in &s.args {
                let _ = write!(out, " {a}");
            }
            out.push(')');
            if s.durative {
                let _ = write!(out, " [{}]", num(s.length()));
            }
            out.push('\n');
        }
        out
    }

    /// The IPC 2020 hierarchical format, with `;@ ID START [DURATION]`
    /// timing annotations after `<==`.
    pub fn to_hierarchical(&self, header: &str) -> String {
        let mut out = String::new();
        for line in header.lines() {
            let _ = writeln!(out, "; {line}");
        }
        out.push_str("==>\n");
        for s in self.primitive() {
            let _ = write!(out, "{} {}", s.id, s.name);
            for a in &s.args {
                let _ = write!(out, " {a}");
            }
            out.push('\n');
        }
        out.push_str("root");
        for r in &self.root {
            let _ = write!(out, " {r}");
        }
        out.push('\n');
        for s in self.steps.iter().filter(|s| s.is_abstract) {
            let _ = write!(out, "{} {}", s.id, s.name);
            for a in &s.args {
                let _ = write!(out, " {a}");
            }
            let _ = write!(out, " -> {}", s.method.as_deref().unwrap_or("?"));
            for c in &s.subtasks {
                let _ = write!(out, " {c}");
            }
            out.push('\n');
        }
        out.push_str("<==\n");
        for s in &self.steps {
            if s.durative || s.is_abstract {
                let _ = writeln!(out, ";@ {} {} [{}]", s.id, num(s.start), num(s.length()));
            } else {
                let _ = writeln!(out, ";@ {} {}", s.id, num(s.start));
            }
        }
        out
    }

    /// hipop's JSON plan, schema version 1.
    pub fn to_json(&self) -> String {
        // serde_json writes the shortest text that reads back the same.
        let round = |x: f64| if x == 0.0 { 0.0 } else { x }; // no -0
        let steps: Vec<Value> = self
            .steps
            .iter()
            .map(|s| {
                let mut v = json!({
                    "id": s.id,
                    "name": s.name,
                    "args": s.args,
                    "start": round(s.start),
                });
                if !s.agents.is_empty() {
                    v["agents"] = json!(s.agents);
                }
                if s.durative || s.is_abstract {
                    v["duration"] = json!(round(s.length()));
                }
                v["bounds"] = json!({
                    "start": [round(s.bounds[0].0), round(s.bounds[0].1)],
                    "end": [round(s.bounds[1].0), round(s.bounds[1].1)],
                });
                if let Some(m) = &s.method {
                    v["method"] = json!(m);
                    v["subtasks"] = json!(s.subtasks);
                }
                v
            })
            .collect();
        let point = |p: SolvedPoint| match p {
            None => json!("origin"),
            Some((id, end)) => json!({ "step": id, "point": if end { "end" } else { "start" } }),
        };
        let doc = json!({
            "format": crate::plan::json::FORMAT_NAME,
            "version": crate::plan::json::VERSION,
            "problem": { "domain": self.domain, "problem": self.problem, "hash": self.hash },
            "makespan": round(self.makespan),
            "steps": steps,
            "root": self.root,
            "causal_links": self.causal_links.iter().map(|l| {
                let mut lit = json!({ "predicate": l.predicate, "args": l.args });
                if l.negated {
                    lit["negated"] = json!(true);
                }
                json!({
                    "from": l.from.map_or(json!("init"), |f| json!(f)),
                    "to": l.to.map_or(json!("goal"), |t| json!(t)),
                    "literal": lit,
                })
            }).collect::<Vec<_>>(),
            "temporal_links": self.temporal_links.iter().map(|t| {
                let mut v = json!({ "from": point(t.from), "to": point(t.to) });
                if let Some(m) = t.min { v["min"] = json!(round(m)); }
                if let Some(m) = t.max { v["max"] = json!(round(m)); }
                v
            }).collect::<Vec<_>>(),
        });
        let mut s = serde_json::to_string_pretty(&doc).unwrap_or_default();
        s.push('\n');
        s
    }
}

/// The flaws of the best partial plan, located: open links at their
/// condition or goal literal, threats at the threatened condition with the
/// threatening operator, abstract flaws at the task.
pub fn flaws<'db>(db: &'db dyn Db, task: &Task<'db>, best: Option<&Plan>, h: &Heuristic) -> Vec<Lint<'db>> {
    let Some(p) = best else { return Vec::new() };
    let mut out = Vec::new();
    let step_text = |s: u32| match p.steps[s as usize].kind {
        Kind::Op(o) => task.show_op(o),
        Kind::Goal => "the goal".to_string(),
        Kind::Init => "the initial state".to_string(),
        Kind::Til(_) => "a timed initial literal".to_string(),
    };
    let cond_loc = |o: &super::plan::Open| -> Option<Loc<'db>> {
        match o.origin {
            OpenOrigin::Goal(i) => task.goals.get(i as usize).map(|g| g.1),
            OpenOrigin::Cond(c) => {
                p.op_of(o.step).and_then(|op| task.ops[op as usize].conds.get(c as usize)).map(|c| c.loc)
            }
            OpenOrigin::MethodPre(m, c) => task.methods[m as usize].pre.get(c as usize).map(|c| c.loc),
            OpenOrigin::AbstractEffect => p.op_of(o.step).map(|op| item_name_loc(db, task, op)),
        }
    };
    for o in p.open.iter().take(20) {
        let Some(loc) = cond_loc(o) else { continue };
        let why = if !h.reachable(o.lit) && !task.holds_initially(o.lit) {
            "no allowed action achieves it, even ignoring deletions"
        } else {
            "no step of the best partial plan achieves it in time"
        };
        out.push(Lint::new(
            codes::PLAN_OPEN_LINK,
            loc,
            format!("open link: {} for {}: {why}", task.show_lit(o.lit), step_text(o.step)),
        ));
    }
    for t in p.threats.iter().take(10) {
        let link = p.links[t.link as usize];
        let what = match t.kind {
            ThreatKind::Delete(_) => "deletes",
            ThreatKind::Position(_) => "moves away from",
            ThreatKind::Conflict => "conflicts with",
        };
        let loc = match p.op_of(link.to) {
            Some(op) => task.ops[op as usize].conds.iter().find(|c| c.lit == link.lit).map(|c| c.loc),
            None => task.goals.iter().find(|g| g.0 == link.lit).map(|g| g.1),
        };
        let Some(loc) = loc else { continue };
        let mut lint = Lint::new(
            codes::PLAN_THREAT,
            loc,
            format!(
                "threat: {} {what} {} between {} and {}",
                step_text(t.step),
                task.show_lit(link.lit),
                step_text(link.from),
                step_text(link.to)
            ),
        );
        if let Some(op) = p.op_of(t.step) {
            lint = lint.related(item_name_loc(db, task, op), "the threatening action");
        }
        out.push(lint);
    }
    for &s in p.abstracts.iter().take(10) {
        let Some(op) = p.op_of(s) else { continue };
        let loc = match p.steps[s as usize].parent {
            None => task
                .htn
                .iter()
                .flatten()
                .find_map(|n| n.tasks.iter().find(|t| t.0 == op).map(|t| t.1))
                .unwrap_or_else(|| item_name_loc(db, task, op)),
            Some(_) => item_name_loc(db, task, op),
        };
        let o = &task.ops[op as usize];
        // The shortest method instance, when even it cannot fit in the
        // task's duration: no plan can refine the task anywhere.
        let too_long = o.duration.and_then(|d| {
            let spans = o.methods.iter().map(|&m| (m, min_span(task, m)));
            let (m, span) = spans.min_by(|a, b| a.1.total_cmp(&b.1))?;
            (span > d + 1e-9).then_some((m, span, d))
        });
        let why = match too_long {
            _ if o.methods.is_empty() => "no method instance refines it".to_string(),
            Some((m, span, d)) => format!(
                "no method instance fits in its duration {}: the shortest, {}, needs at least {} (0.01 s between ordered subtasks)",
                num(d),
                task.methods[m as usize].name,
                num(tidy(span))
            ),
            None => "no method instance refines it consistently with the rest of the plan".to_string(),
        };
        out.push(Lint::new(
            codes::PLAN_ABSTRACT_FLAW,
            loc,
            format!("abstract flaw: {} {why}", task.show_op(op)),
        ));
    }
    out
}

/// The least time method instance `m` spans: its subtasks' durations along
/// the longest chain of its orderings, a strict ordering separating its two
/// happenings by ε (links between its subtasks can only add to it).
fn min_span(task: &Task<'_>, m: u32) -> f64 {
    let method = &task.methods[m as usize];
    let n = method.subtasks.len();
    let dur = |i: usize| {
        let op = &task.ops[method.subtasks[i].1 as usize];
        if op.instant { 0.0 } else { op.duration.unwrap_or(0.0) }
    };
    let node = |(i, e): (usize, End)| 2 * i + usize::from(e == End::End);
    // Longest distances from the refined step's start (every subtask starts
    // at or after it); the orderings are acyclic, so 2n rounds settle them.
    let mut at = vec![0.0f64; 2 * n];
    for _ in 0..2 * n {
        let mut changed = false;
        for i in 0..n {
            if at[2 * i] + dur(i) > at[2 * i + 1] + 1e-12 {
                at[2 * i + 1] = at[2 * i] + dur(i);
                changed = true;
            }
        }
        for o in &method.orders {
            let (a, b) = (node(o.from), node(o.to));
            let w = if o.strict { super::stn::EPS } else { 0.0 };
            if at[a] + w > at[b] + 1e-12 {
                at[b] = at[a] + w;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    at.iter().copied().fold(0.0, f64::max)
}

/// The name of an operator's declaration.
fn item_name_loc<'db>(db: &'db dyn Db, task: &Task<'db>, op: u32) -> Loc<'db> {
    let item = task.ops[op as usize].item;
    let span = match &lower_item(db, item).data {
        ItemData::Action(a) => a.name.span,
        ItemData::Task(t) => t.name.span,
        _ => rowan::TextRange::default(),
    };
    Loc { item, span }
}
