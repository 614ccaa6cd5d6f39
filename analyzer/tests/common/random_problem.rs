//! Random small temporal problems: the types, the generator (raw choices,
//! shrinking towards 0 and shorter lists, then resolved against the types)
//! and their PDDL text, and the validation of a plan found for one. Shared
//! by the property tests of the planner (`planner_props`) and of the repair
//! (`repair_props`).

use std::fmt::Write as _;

use proptest::prelude::*;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum When {
    Start,
    All,
    End,
}

/// A literal over an action's parameters (indices).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Lit {
    pub(crate) at: When,
    pub(crate) neg: bool,
    pub(crate) pred: usize,
    pub(crate) args: Vec<usize>,
}

#[derive(Debug, Clone)]
pub(crate) struct Action {
    pub(crate) durative: bool,
    /// Parameter types.
    pub(crate) params: Vec<usize>,
    pub(crate) duration: u32,
    pub(crate) conds: Vec<Lit>,
    pub(crate) effs: Vec<Lit>,
}

/// A small temporal problem. Types `t0`, `t1`; objects `o0`…; predicates
/// `p0`…; actions `a0`….
#[derive(Clone)]
pub(crate) struct Problem {
    /// Each type's parent (`None`: `object`).
    pub(crate) types: Vec<Option<usize>>,
    pub(crate) objects: Vec<usize>,
    pub(crate) preds: Vec<Vec<usize>>,
    pub(crate) actions: Vec<Action>,
    pub(crate) init: Vec<(usize, Vec<usize>)>,
    /// `(negated, predicate, objects)`.
    pub(crate) goal: Vec<(bool, usize, Vec<usize>)>,
    pub(crate) allowed: Option<Vec<usize>>,
}

impl std::fmt::Debug for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "\n{}", self.text())
    }
}

impl Problem {
    /// A ground atom: predicate `pick` (modulo their number), each argument
    /// the object of its type chosen by `args`.
    pub fn atom(&self, pick: usize, args: &[u8; 2]) -> (usize, Vec<usize>) {
        let pred = pick % self.preds.len();
        let objs = self.preds[pred]
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                let fits: Vec<usize> =
                    (0..self.objects.len()).filter(|&o| self.subtype(self.objects[o], t)).collect();
                fits[args[k] as usize % fits.len()]
            })
            .collect();
        (pred, objs)
    }

    pub(crate) fn subtype(&self, mut t: usize, of: usize) -> bool {
        loop {
            if t == of {
                return true;
            }
            match self.types[t] {
                Some(p) => t = p,
                None => return false,
            }
        }
    }

    fn atom_text(&self, pred: usize, args: &[String]) -> String {
        let mut s = format!("(p{pred}");
        for a in args {
            s.push(' ');
            s.push_str(a);
        }
        s.push(')');
        s
    }

    fn lit_text(&self, l: &Lit) -> String {
        let args: Vec<String> = l.args.iter().map(|i| format!("?x{i}")).collect();
        let a = self.atom_text(l.pred, &args);
        if l.neg { format!("(not {a})") } else { a }
    }

    pub(crate) fn text(&self) -> String {
        let mut s = String::new();
        s.push_str("(define (domain d)\n  (:requirements :strips :typing :negative-preconditions :durative-actions)\n");
        s.push_str("  (:types");
        for (i, p) in self.types.iter().enumerate() {
            match p {
                Some(p) => {
                    let _ = write!(s, " t{i} - t{p}");
                }
                None => {
                    let _ = write!(s, " t{i} - object");
                }
            }
        }
        s.push_str(")\n  (:predicates");
        for (i, args) in self.preds.iter().enumerate() {
            let _ = write!(s, " (p{i}");
            for (k, t) in args.iter().enumerate() {
                let _ = write!(s, " ?v{k} - t{t}");
            }
            s.push(')');
        }
        s.push_str(")\n");
        for (i, a) in self.actions.iter().enumerate() {
            let params: Vec<String> =
                a.params.iter().enumerate().map(|(k, t)| format!("?x{k} - t{t}")).collect();
            let params = params.join(" ");
            if a.durative {
                let timed = |l: &Lit, eff: bool| {
                    let at = match (l.at, eff) {
                        (When::Start, _) => "at start",
                        (When::All, false) => "over all",
                        (_, _) => "at end",
                    };
                    format!("({at} {})", self.lit_text(l))
                };
                let conds: Vec<String> = a.conds.iter().map(|l| timed(l, false)).collect();
                let effs: Vec<String> = a.effs.iter().map(|l| timed(l, true)).collect();
                let _ = write!(
                    s,
                    "  (:durative-action a{i}\n    :parameters ({params})\n    :duration (= ?duration {})\n    :condition (and {})\n    :effect (and {}))\n",
                    a.duration,
                    conds.join(" "),
                    effs.join(" ")
                );
            } else {
                let conds: Vec<String> = a.conds.iter().map(|l| self.lit_text(l)).collect();
                let effs: Vec<String> = a.effs.iter().map(|l| self.lit_text(l)).collect();
                let _ = write!(
                    s,
                    "  (:action a{i}\n    :parameters ({params})\n    :precondition (and {})\n    :effect (and {}))\n",
                    conds.join(" "),
                    effs.join(" ")
                );
            }
        }
        s.push_str(")\n\n(define (problem pr)\n  (:domain d)\n  (:objects");
        for (i, t) in self.objects.iter().enumerate() {
            let _ = write!(s, " o{i} - t{t}");
        }
        s.push_str(")\n  (:init");
        let objs = |args: &[usize]| args.iter().map(|o| format!("o{o}")).collect::<Vec<_>>();
        for (p, args) in &self.init {
            let _ = write!(s, " {}", self.atom_text(*p, &objs(args)));
        }
        s.push_str(")\n  (:goal (and");
        for (neg, p, args) in &self.goal {
            let a = self.atom_text(*p, &objs(args));
            if *neg {
                let _ = write!(s, " (not {a})");
            } else {
                let _ = write!(s, " {a}");
            }
        }
        s.push_str("))");
        if let Some(allowed) = &self.allowed {
            s.push_str("\n  (:allowed-actions");
            for a in allowed {
                let _ = write!(s, " a{a}");
            }
            s.push(')');
        }
        s.push_str(")\n");
        s
    }
}

/// The tuples of objects of these types (subtypes included).
pub(crate) fn tuples(p: &Problem, types: &[usize]) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new()];
    for &t in types {
        let fits: Vec<usize> = (0..p.objects.len()).filter(|&o| p.subtype(p.objects[o], t)).collect();
        out = out
            .iter()
            .flat_map(|prefix| fits.iter().map(move |&o| [prefix.clone(), vec![o]].concat()))
            .collect();
    }
    out
}

// ---------------------------------------------------------------------------
// The generator: raw choices (shrinking towards 0 and shorter lists), then
// resolved against the types.

#[derive(Debug, Clone)]
pub(crate) struct RawLit {
    pub(crate) at: u8,
    pub(crate) neg: bool,
    pub(crate) pred: u8,
    pub(crate) args: [u8; 2],
}

#[derive(Debug, Clone)]
pub(crate) struct RawAction {
    pub(crate) instant: bool,
    pub(crate) params: Vec<u8>,
    pub(crate) duration: u32,
    pub(crate) conds: Vec<RawLit>,
    pub(crate) effs: Vec<RawLit>,
}

#[derive(Debug, Clone)]
pub(crate) struct RawProblem {
    pub(crate) two_types: bool,
    pub(crate) nested: bool,
    pub(crate) all_instant: bool,
    pub(crate) objects: Vec<u8>,
    pub(crate) preds: Vec<Vec<u8>>,
    pub(crate) actions: Vec<RawAction>,
    pub(crate) init: Vec<(u8, [u8; 2])>,
    pub(crate) goal: Vec<(bool, u8, [u8; 2])>,
    pub(crate) allowed: Option<Vec<bool>>,
}

pub(crate) fn raw_lit(neg: f64) -> impl Strategy<Value = RawLit> {
    (0u8..3, prop::bool::weighted(neg), any::<u8>(), any::<[u8; 2]>())
        .prop_map(|(at, neg, pred, args)| RawLit { at, neg, pred, args })
}

pub(crate) fn raw_action() -> impl Strategy<Value = RawAction> {
    (
        prop::bool::weighted(0.2),
        prop::collection::vec(any::<u8>(), 0..=2),
        1u32..=5,
        prop::collection::vec(raw_lit(0.2), 0..=4),
        prop::collection::vec(raw_lit(0.35), 1..=4),
    )
        .prop_map(|(instant, params, duration, conds, effs)| RawAction {
            instant,
            params,
            duration,
            conds,
            effs,
        })
}

pub(crate) fn raw_problem() -> impl Strategy<Value = RawProblem> {
    (
        (any::<bool>(), any::<bool>(), prop::bool::weighted(0.1)),
        prop::collection::vec(any::<u8>(), 2..=4),
        prop::collection::vec(prop::collection::vec(any::<u8>(), 0..=2), 2..=4),
        prop::collection::vec(raw_action(), 2..=5),
        prop::collection::vec((any::<u8>(), any::<[u8; 2]>()), 1..=3),
        prop::collection::vec((prop::bool::weighted(0.1), any::<u8>(), any::<[u8; 2]>()), 1..=3),
        prop::option::weighted(0.25, prop::collection::vec(any::<bool>(), 5)),
    )
        .prop_map(|((two_types, nested, all_instant), objects, preds, actions, init, goal, allowed)| {
            RawProblem { two_types, nested, all_instant, objects, preds, actions, init, goal, allowed }
        })
}

pub(crate) fn build(raw: &RawProblem) -> Problem {
    let types = if raw.two_types { vec![None, if raw.nested { Some(0) } else { None }] } else { vec![None] };
    let nt = types.len();
    // Every type has an object: the first objects are of each type in turn.
    let objects: Vec<usize> =
        raw.objects.iter().enumerate().map(|(i, &t)| if i < nt { i } else { t as usize % nt }).collect();
    let preds: Vec<Vec<usize>> =
        raw.preds.iter().map(|args| args.iter().map(|&t| t as usize % nt).collect()).collect();
    let mut p = Problem {
        types,
        objects,
        preds,
        actions: Vec::new(),
        init: Vec::new(),
        goal: Vec::new(),
        allowed: None,
    };
    for ra in &raw.actions {
        let durative = !(ra.instant || raw.all_instant);
        let params: Vec<usize> = ra.params.iter().map(|&t| t as usize % nt).collect();
        let resolve = |rl: &RawLit, eff: bool| -> Option<Lit> {
            let pred = rl.pred as usize % p.preds.len();
            let mut args = Vec::new();
            for (k, &t) in p.preds[pred].iter().enumerate() {
                let fits: Vec<usize> = (0..params.len()).filter(|&i| p.subtype(params[i], t)).collect();
                if fits.is_empty() {
                    return None;
                }
                args.push(fits[rl.args[k] as usize % fits.len()]);
            }
            let at = match (rl.at % 3, eff) {
                (0, _) => When::Start,
                (1, false) => When::All,
                _ => When::End,
            };
            Some(Lit { at: if durative { at } else { When::Start }, neg: rl.neg, pred, args })
        };
        let conds = ra.conds.iter().filter_map(|l| resolve(l, false)).collect();
        let effs = ra.effs.iter().filter_map(|l| resolve(l, true)).collect();
        p.actions.push(Action { durative, params, duration: ra.duration, conds, effs });
    }
    let ground = |p: &Problem, pred: u8, args: &[u8; 2]| p.atom(pred as usize, args);
    p.init = raw.init.iter().map(|(pr, args)| ground(&p, *pr, args)).collect();
    p.goal =
        raw.goal
            .iter()
            .map(|(neg, pr, args)| {
                // Mostly an atom that some ground effect makes true (false when negated).
                let effects: Vec<(usize, Vec<usize>)> =
                    p.actions
                        .iter()
                        .flat_map(|a| {
                            let p = &p;
                            tuples(p, &a.params).into_iter().flat_map(move |objs| {
                                a.effs.iter().filter(|l| l.neg == *neg).map(move |l| {
                                    (l.pred, l.args.iter().map(|&k| objs[k]).collect::<Vec<_>>())
                                })
                            })
                        })
                        .collect();
                let (pred, objs) = if *pr < 180 && !effects.is_empty() {
                    let pick = (*pr as usize) * 256 + args[0] as usize;
                    effects[pick % effects.len()].clone()
                } else {
                    ground(&p, *pr, args)
                };
                (*neg, pred, objs)
            })
            .collect();
    if let Some(mask) = &raw.allowed {
        let mut allowed: Vec<usize> = (0..p.actions.len()).filter(|&i| mask[i]).collect();
        if allowed.is_empty() {
            allowed.push(0);
        }
        p.allowed = Some(allowed);
    }
    p
}

pub(crate) fn problem() -> impl Strategy<Value = Problem> {
    raw_problem().prop_map(|r| build(&r))
}

/// The diagnostics, a line each, with the text they point at.
pub(crate) fn show(
    host: &hipop_analyzer::AnalysisHost,
    diagnostics: &[hipop_analyzer::Diagnostic],
) -> String {
    let mut out = String::new();
    for d in diagnostics {
        let text = host.analysis().file_text(d.file).unwrap_or_default();
        let at =
            text.get(usize::from(d.range.start())..usize::from(d.range.end()).min(text.len())).unwrap_or("");
        let _ = writeln!(out, "  {} {}: {} [at `{}`]", d.code.id, d.code.name, d.message, at);
    }
    out
}

/// Validates a plan text against the problem: `Err` with the validator's
/// diagnostics when it is not valid. At VAL's default tolerance and at
/// 0.0001: a written plan is valid at every tolerance between
/// (docs/planner.md).
pub(crate) fn validate(
    host: &mut hipop_analyzer::AnalysisHost,
    problem: hipop_analyzer::SourceFile,
    name: &str,
    plan: &str,
) -> Result<(), String> {
    let f = host.set_file_text(name, plan.to_string());
    for tolerance in [0.01, 0.0001] {
        let options = hipop_analyzer::validate::Options { tolerance, ..Default::default() };
        let v = host
            .analysis()
            .validate_plan(f, None, problem, &options)
            .expect("not cancelled")
            .expect("a problem");
        if !(v.valid && v.checked) {
            return Err(format!(
                "the validator rejects {name} at tolerance {tolerance}:\n{}\n{plan}",
                show(host, &v.diagnostics)
            ));
        }
    }
    Ok(())
}
