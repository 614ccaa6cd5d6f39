//! Mutual exclusion: events of a happening (or of happenings closer than
//! the tolerance) that interfere, and how to separate them.

use rowan::TextRange;
use rustc_hash::FxHashMap;

use super::{Actor, Event, Run, Touch};
use crate::diagnostic::codes;
use crate::eval::{FluentId, Key, NumOp, Why, fmt_num};
use crate::validate::Failure;
use crate::verify::state::AtomId;

/// How two events of a happening interfere.
#[derive(Debug, Clone, Copy)]
pub(super) enum Interference {
    /// `writer` adds (or deletes) an atom that `reader` reads.
    AtomRead {
        reader: usize,
        writer: usize,
        atom: AtomId,
        added: bool,
    },
    AtomAddDel {
        adder: usize,
        deleter: usize,
        atom: AtomId,
    },
    FluentRead {
        reader: usize,
        writer: usize,
        fluent: FluentId,
        op: NumOp,
    },
    FluentWrite {
        first: usize,
        second: usize,
        fluent: FluentId,
        ops: (NumOp, NumOp),
    },
}

impl Interference {
    pub(super) fn events(self) -> (usize, usize) {
        let (a, b) = match self {
            Interference::AtomRead { reader, writer, .. }
            | Interference::FluentRead { reader, writer, .. } => (reader, writer),
            Interference::AtomAddDel { adder, deleter, .. } => (adder, deleter),
            Interference::FluentWrite { first, second, .. } => (first, second),
        };
        (a.min(b), a.max(b))
    }
}

/// The interfering pairs among events (by index into `touches`), each pair
/// once, with every reason found (VAL's rules of ownership).
pub(super) fn interferences(touches: &[&Touch]) -> Vec<Vec<Interference>> {
    #[derive(Clone, Copy, PartialEq)]
    enum Use {
        Read,
        Add,
        Del,
    }
    let mut atoms: FxHashMap<AtomId, Vec<(usize, Use)>> = FxHashMap::default();
    let mut fluents: FxHashMap<FluentId, Vec<(usize, Option<NumOp>)>> = FxHashMap::default();
    for (e, t) in touches.iter().enumerate() {
        let mut note = |a: AtomId, u: Use| {
            let uses = atoms.entry(a).or_default();
            if !uses.contains(&(e, u)) {
                uses.push((e, u));
            }
        };
        t.reads.iter().for_each(|&a| note(a, Use::Read));
        t.adds.iter().for_each(|&a| note(a, Use::Add));
        t.dels.iter().for_each(|&a| note(a, Use::Del));
        for &f in &t.fluent_reads {
            fluents.entry(f).or_default().push((e, None));
        }
        for &(f, op) in &t.fluent_writes {
            fluents.entry(f).or_default().push((e, Some(op)));
        }
    }
    let mut found: Vec<Vec<Interference>> = Vec::new();
    let mut push = |i: Interference| match found.iter_mut().find(|x| x[0].events() == i.events()) {
        Some(reasons) => reasons.push(i),
        None => found.push(vec![i]),
    };
    let mut atom_ids: Vec<&AtomId> = atoms.keys().collect();
    atom_ids.sort_unstable();
    for atom in atom_ids {
        let uses = &atoms[atom];
        for &(x, ux) in uses {
            for &(y, uy) in uses {
                if x == y {
                    continue;
                }
                match (ux, uy) {
                    (Use::Read, Use::Add | Use::Del) => push(Interference::AtomRead {
                        reader: x,
                        writer: y,
                        atom: *atom,
                        added: uy == Use::Add,
                    }),
                    (Use::Add, Use::Del) => {
                        push(Interference::AtomAddDel { adder: x, deleter: y, atom: *atom })
                    }
                    _ => {}
                }
            }
        }
    }
    let mut fluent_ids: Vec<&FluentId> = fluents.keys().collect();
    fluent_ids.sort_unstable();
    for fluent in fluent_ids {
        let uses = &fluents[fluent];
        for (k, &(x, ox)) in uses.iter().enumerate() {
            for &(y, oy) in &uses[k + 1..] {
                if x == y {
                    continue;
                }
                match (ox, oy) {
                    (None, Some(op)) => {
                        push(Interference::FluentRead { reader: x, writer: y, fluent: *fluent, op })
                    }
                    (Some(op), None) => {
                        push(Interference::FluentRead { reader: y, writer: x, fluent: *fluent, op })
                    }
                    (Some(a), Some(b)) if !(a.is_additive() && b.is_additive()) => {
                        push(Interference::FluentWrite { first: x, second: y, fluent: *fluent, ops: (a, b) })
                    }
                    _ => {}
                }
            }
        }
    }
    found
}

/// The reason to tell of two events' interference: preferably the earlier
/// event changing what the later one reads (a cause and its effect).
pub(super) fn causal(reasons: &[Interference], event: &dyn Fn(usize) -> Event) -> Interference {
    let earlier =
        |a: usize, b: usize| event(a).time < event(b).time || (event(a).time == event(b).time && a < b);
    reasons
        .iter()
        .copied()
        .find(|r| match *r {
            Interference::AtomRead { reader, writer, .. }
            | Interference::FluentRead { reader, writer, .. } => earlier(writer, reader),
            _ => false,
        })
        .unwrap_or(reasons[0])
}

impl<'a, 'db> Run<'a, 'db> {
    /// Moves a step so that its event `m` happens the tolerance after `anchor`.
    pub(super) fn separate(&self, f: Failure<'db>, m: Event, anchor: Event) -> Failure<'db> {
        let Some(i) = m.actor.step() else { return f };
        let tol = self.options.tolerance;
        let new_event = anchor.time + tol;
        let new_start = self.steps[i].time + (new_event - m.time);
        let whom = match anchor.actor {
            Actor::Til(_) => "the timed initial literal".to_string(),
            a => a.step().map_or_else(|| "the step".to_string(), |j| self.plan[j].label()),
        };
        let hint = match m.actor {
            Actor::End(_) => format!(
                "separate them by at least the tolerance ({tol}): {} must end at {} or later, {} after {whom}; start it at {}",
                self.plan[i].label(),
                fmt_num(new_event),
                tol,
                self.edit_time(new_start)
            ),
            _ => format!(
                "separate them by at least the tolerance ({tol}): start {} at {} or later",
                self.plan[i].label(),
                self.edit_time(new_start)
            ),
        };
        let f = f.hint(hint);
        match self.plan[i].time_span {
            Some(span) => f.edit(span, self.edit_time(new_start)),
            None => f,
        }
    }

    /// Why two events of one happening with different times are one happening.
    pub(super) fn grouped(&self, early: Event, late: Event) -> String {
        if late.time > early.time {
            format!(
                ", only {} earlier: at tolerance {}, events no more than {} apart are one happening, whose conditions are checked before its effects",
                fmt_num(late.time - early.time),
                self.options.tolerance,
                fmt_num(self.options.tolerance / 10.0)
            )
        } else {
            ", in the same happening: its conditions are checked before its effects".into()
        }
    }

    /// A false condition that another event of the same happening (`o`, by
    /// the effect at `effect`) makes as needed: `verb`, "makes it true";
    /// `note`, the same for the other step, "makes `(p)` true".
    pub(super) fn too_close(
        &self,
        e: Event,
        o: Event,
        label: &str,
        why: &Why,
        effect: TextRange,
        (verb, note): (&str, &str),
    ) -> Failure<'db> {
        let mut f = Failure::new(
            codes::MUTEX_HAPPENINGS,
            self.event_span(e.actor),
            format!(
                "{}: {label} {}: {} {verb} at {}{}",
                self.event_head(e),
                why.text,
                self.actor_text(o.actor),
                fmt_num(o.time),
                self.grouped(o, e)
            ),
        );
        if let Some(i) = e.actor.step() {
            f = f.at_step(i).model(self.steps[i].loc(why.span), format!("the {label}"));
        }
        if let Some(i) = o.actor.step() {
            f = f.plan(self.plan[i].span, format!("{note} at {}", fmt_num(o.time)));
        }
        f = f.model(self.effect_loc(o.actor, effect), "the effect");
        self.separate(f, e, o)
    }

    /// Two interfering events of one happening.
    pub(super) fn mutex(&self, inter: Interference, event: &dyn Fn(usize) -> Event) -> Failure<'db> {
        let (a, b) = inter.events();
        let (early, late) = (event(a), event(b));
        // Move a step: the later event's, unless it is a timed literal.
        let (moved, anchor) = if late.actor.step().is_some() { (late, early) } else { (early, late) };
        let what = self.interference_text(inter, event);
        let same_step = early.actor.step().is_some() && early.actor.step() == late.actor.step();
        let message = format!(
            "{} interferes with {} at {}{}: {what}",
            self.event_head(moved),
            self.actor_text(anchor.actor),
            fmt_num(anchor.time),
            if late.time > early.time { self.grouped(early, late) } else { String::new() }
        );
        let mut f = Failure::new(codes::MUTEX_HAPPENINGS, self.event_span(moved.actor), message);
        if let Some(i) = moved.actor.step() {
            f = f.at_step(i);
        }
        if let Some(i) = anchor.actor.step().filter(|_| !same_step) {
            f = f.plan(self.plan[i].span, format!("interferes at {}", fmt_num(anchor.time)));
        }
        if same_step {
            let i = moved.actor.step().unwrap_or(0);
            let d = self.options.tolerance;
            let mut f = f.hint(format!(
                "its start and end interfere: give {} a duration of at least {d}",
                self.plan[i].label()
            ));
            if let Some(span) = self.plan[i].duration_span {
                f = f.edit(span, format!("[{}]", self.edit_time(d)));
            }
            return f;
        }
        self.separate(f, moved, anchor)
    }

    /// "the start of step 2 `(drive …)` deletes `(at t a)`, which step 5 `(load …)` reads".
    pub(super) fn interference_text(&self, inter: Interference, event: &dyn Fn(usize) -> Event) -> String {
        let world = self.world();
        let who = |k: usize| self.actor_short(event(k).actor);
        let atom = |a: AtomId| world.show_atom(&self.atom_key(a));
        let fluent = |f: FluentId| world.show_fluent(&self.fluent_key(f));
        match inter {
            Interference::AtomRead { reader, writer, atom: a, added } => format!(
                "{} {} `{}`, which {} reads",
                who(writer),
                if added { "adds" } else { "deletes" },
                atom(a),
                who(reader)
            ),
            Interference::AtomAddDel { adder, deleter, atom: a } => {
                format!("{} adds `{}`, which {} deletes", who(adder), atom(a), who(deleter))
            }
            Interference::FluentRead { reader, writer, fluent: fl, op } => {
                format!(
                    "{} changes `{}` (`{}`), which {} reads",
                    who(writer),
                    fluent(fl),
                    op.name(),
                    who(reader)
                )
            }
            Interference::FluentWrite { first, second, fluent: fl, ops } => format!(
                "{} and {} both change `{}` (`{}` and `{}`), which do not commute",
                who(first),
                who(second),
                fluent(fl),
                ops.0.name(),
                ops.1.name()
            ),
        }
    }

    pub(super) fn atom_key(&self, a: AtomId) -> Key {
        let mut k = Key::new();
        k.push(self.state.atoms.pred(a));
        k.extend_from_slice(self.state.atoms.args(a));
        k
    }

    pub(super) fn fluent_key(&self, f: FluentId) -> Key {
        let mut k = Key::new();
        k.push(self.state.fluents.pred(f));
        k.extend_from_slice(self.state.fluents.args(f));
        k
    }

    /// W0411: interfering events of different happenings closer than the
    /// tolerance (VAL accepts them; PDDL 2.1's ε-separation does not).
    pub(super) fn close_happenings(&mut self) {
        let tol = self.options.tolerance;
        let touched = &self.touched;
        // The events of each happening.
        let mut ranges: Vec<std::ops::Range<usize>> = Vec::new();
        for (k, (_, h, _)) in touched.iter().enumerate() {
            match ranges.last_mut() {
                Some(r) if touched[r.start].1 == *h => r.end = k + 1,
                _ => ranges.push(k..k + 1),
            }
        }
        let mut warned: Vec<(usize, usize)> = Vec::new();
        let mut out = Vec::new();
        for (x, rx) in ranges.iter().enumerate() {
            let last = touched[rx.clone()].iter().map(|t| t.0.time).fold(f64::MIN, f64::max);
            for ry in &ranges[x + 1..] {
                if touched[ry.start].0.time - last >= tol {
                    break;
                }
                let idx: Vec<usize> = rx.clone().chain(ry.clone()).collect();
                let refs: Vec<&Touch> = idx.iter().map(|&k| &touched[k].2).collect();
                let event = |k: usize| touched[idx[k]].0;
                for reasons in interferences(&refs) {
                    let inter = causal(&reasons, &event);
                    let (a, b) = inter.events();
                    let (ea, eb) = (event(a), event(b));
                    let (Some(sa), Some(sb)) = (ea.actor.step(), eb.actor.step()) else { continue };
                    let cross = (idx[a] < ry.start) != (idx[b] < ry.start);
                    if !cross || sa == sb || (eb.time - ea.time).abs() >= tol - 1e-9 {
                        continue;
                    }
                    let pair = (sa.min(sb), sa.max(sb));
                    if warned.contains(&pair) {
                        continue;
                    }
                    warned.push(pair);
                    let (early, late) = if ea.time <= eb.time { (ea, eb) } else { (eb, ea) };
                    let what = self.interference_text(inter, &event);
                    let f = Failure::new(
                        codes::CLOSE_HAPPENINGS,
                        self.event_span(late.actor),
                        format!(
                            "{} interferes with {}, only {} earlier: {what}; VAL accepts it (more than tolerance/10 apart, two happenings), but PDDL 2.1 asks interfering happenings to be at least the tolerance ({tol}) apart",
                            self.event_head(late),
                            self.actor_text(early.actor),
                            fmt_num(late.time - early.time)
                        ),
                    )
                    .at_step(late.actor.step().unwrap_or(0))
                    .plan(self.event_span(early.actor), format!("interferes at {}", fmt_num(early.time)));
                    out.push(self.separate(f, late, early));
                }
            }
        }
        self.failures.extend(out);
    }
}
