//! The resolvers of each flaw: the child plans that solve it (section
//! 4.2.2 of the HiPOP paper), and the plans the search starts from. Threats
//! are ordered one way or the other (in place when only one way is left);
//! open links get a causal link from a step that can come before or a new
//! step of 𝒜; abstract flaws get each method instance that does not only go
//! round a loop; visits extend an itinerary; interfering happenings and late
//! timed literals are ordered.

use super::super::itinerary::Geo;
use super::super::numeric;
use super::super::plan::{GOAL, INIT, Kind, Open, OpenOrigin, Plan, Threat, ThreatKind};
use super::super::stn::{EPS, ORIGIN, Tp};
use super::super::task::{End, Lit, Task, atom_of, is_neg};
use super::{Flaw, Search};

impl Search<'_, '_> {
    /// Adds a step (its open links bounded by their itineraries).
    pub(super) fn add_step(&self, p: &mut Plan, op: u32, parent: Option<u32>) -> Option<u32> {
        let before = p.open.len();
        let s = p.add_step(self.task, self.h, op, parent)?;
        if let Some(geo) = &self.geo {
            for k in before..p.open.len() {
                let o = p.open[k];
                if !geo.bound(self.task, p, &o) {
                    return None;
                }
            }
        }
        Some(s)
    }

    /// Adds an open link of another origin (bounded by its itinerary).
    pub(super) fn add_open(&self, p: &mut Plan, o: Open) -> bool {
        if let Some(geo) = &self.geo
            && !geo.bound(self.task, p, &o)
        {
            return false;
        }
        p.add_open(o);
        true
    }

    /// Whether an open link is a visit of an itinerary.
    pub(super) fn is_visit(&self, o: &Open) -> bool {
        self.geo.is_some() && Geo::position(self.task, o.lit).is_some()
    }

    /// The initial plans: init, goal, timed literals, the goal's open links,
    /// and the `:htn` tasks with their orderings, one plan per ground
    /// initial task network (the bindings of the `:htn` parameters).
    pub fn initial(&self) -> Vec<Plan> {
        let Some(mut p) = Plan::initial(self.task) else { return Vec::new() };
        if let Some(geo) = &self.geo {
            p.tails = std::rc::Rc::new(geo.initial_tails(self.task));
        }
        for (i, &(l, _)) in self.task.goals.iter().enumerate() {
            let o = Open {
                step: GOAL,
                lit: l,
                need: p.goal_tp,
                until: p.goal_tp,
                cond: u32::MAX,
                origin: OpenOrigin::Goal(i as u32),
                after_start: false,
            };
            if !self.add_open(&mut p, o) {
                return Vec::new();
            }
        }
        let Some(nets) = &self.task.htn else { return vec![p] };
        nets.iter()
            .filter_map(|net| {
                let mut p = p.clone();
                let mut ids = Vec::new();
                for &(op, _) in &net.tasks {
                    ids.push(self.add_step(&mut p, op, None)?);
                }
                for o in &net.orders {
                    let a = p.steps[ids[o.from.0] as usize].tp(o.from.1);
                    let b = p.steps[ids[o.to.0] as usize].tp(o.to.1);
                    if !p.stn.add(a, b, if o.strict { EPS } else { 0.0 }) {
                        return None;
                    }
                }
                Some(p)
            })
            .collect()
    }

    /// Producers of a literal that could come before `need` and that are
    /// the last of their family before it (4.3.1): `(step, time point)`.
    pub(super) fn producers(&self, p: &Plan, o: &Open, out: &mut Vec<(u32, Tp)>) {
        self.producers_among(p, o, &mut self.every_effect(p), &mut self.every_effect(p), out);
    }

    /// Every effect of a plan's steps, as `(step, literal, time point)`.
    fn every_effect<'a>(&'a self, p: &'a Plan) -> impl Iterator<Item = (u32, Lit, Tp)> + 'a {
        (0..p.steps.len() as u32).flat_map(move |s| p.effects(self.task, s).map(move |(l, tp)| (s, l, tp)))
    }

    /// [`Search::producers`] from an index of the plan's effects, built once
    /// for a plan whose steps do not change while it is linked (a start
    /// plan): the effects of the literal, and the position changes of its
    /// family, instead of every step's effects for each open link.
    pub(super) fn producers_indexed(&self, p: &Plan, o: &Open, index: &Effects, out: &mut Vec<(u32, Tp)>) {
        let group =
            if is_neg(o.lit) { None } else { self.task.family[atom_of(o.lit) as usize].map(|(g, _)| g) };
        let of_lit = index.by_lit.get(&o.lit).map_or(&[][..], Vec::as_slice);
        let of_group = group.and_then(|g| index.by_group.get(&g)).map_or(&[][..], Vec::as_slice);
        self.producers_among(p, o, &mut of_lit.iter().copied(), &mut of_group.iter().copied(), out);
    }

    /// The producers of open link `o` among `effects`, without those that a
    /// position change among `changes` of the same member necessarily
    /// follows before the need; effects as `(step, literal, time point)`,
    /// in the plan's order.
    fn producers_among(
        &self,
        p: &Plan,
        o: &Open,
        effects: &mut dyn Iterator<Item = (u32, Lit, Tp)>,
        changes: &mut dyn Iterator<Item = (u32, Lit, Tp)>,
        out: &mut Vec<(u32, Tp)>,
    ) {
        out.clear();
        if self.task.holds_initially(o.lit) && o.step != INIT {
            out.push((INIT, ORIGIN));
        }
        for (s, l, tp) in effects {
            let own_start = s == o.step && o.after_start && tp == o.need;
            if l == o.lit
                && (tp != o.need || own_start)
                && (own_start || !p.stn.before(o.need, tp))
                && !(s == o.step && tp == o.until)
            {
                out.push((s, tp));
            }
        }
        // The last known position: drop producers that another position
        // change of the same member necessarily follows before the need.
        if !is_neg(o.lit)
            && let Some((group, _)) = self.task.family[atom_of(o.lit) as usize]
            && !out.is_empty()
        {
            let changes: Vec<Tp> = changes
                .filter(|&(_, l, tp)| {
                    !is_neg(l)
                        && l != o.lit
                        && self.task.family[atom_of(l) as usize].is_some_and(|(g, _)| g == group)
                        && p.stn.before(tp, o.need)
                })
                .map(|(_, _, tp)| tp)
                .collect();
            out.retain(|&(_, e)| !changes.iter().any(|&c| (e == ORIGIN || p.stn.before(e, c)) && c != e));
        }
    }

    /// Whether refining step `s` with method `m` only goes round a loop: a
    /// subtask of `m` is the ground task of `s` or of one of its ancestors
    /// (same task, same arguments), and no method on the way from that task
    /// down (`m` included) adds an action that changes the state (a pure
    /// loop), or the
    /// repeat goes through other tasks and has arguments (a cycle:
    /// `get-to truck1 city2` again below `get-to truck1 city1` below itself
    /// means driving back to where the truck was). A task that recurses
    /// into itself directly through actions (`S → t S y`, PCP's;
    /// `remove-all r → remove t r, remove-all r`, any "repeat until done"
    /// task) makes progress and is kept.
    pub(super) fn only_loops(&self, p: &Plan, s: u32, m: u32) -> bool {
        // A method makes progress when one of its actions changes the state:
        // deletes something or adds what it does not need (`drive l l` on a
        // road from a place to itself does not).
        let changes = |op: &super::super::task::Op<'_>| {
            op.effs.iter().any(|e| is_neg(e.lit) || !op.conds.iter().any(|c| c.lit == e.lit))
        };
        let primitive = |m: u32| {
            self.task.methods[m as usize].subtasks.iter().any(|&(_, op)| {
                let op = &self.task.ops[op as usize];
                !op.is_abstract && changes(op)
            })
        };
        // `s` and its ancestors, each with whether an action that changes
        // the state was added on the way down from it to `m`'s subtasks.
        let mut above = vec![(s, primitive(m))];
        while let Some(parent) = p.steps[above[above.len() - 1].0 as usize].parent {
            let progress = above[above.len() - 1].1 || p.steps[parent as usize].method.is_some_and(primitive);
            above.push((parent, progress));
        }
        self.task.methods[m as usize].subtasks.iter().any(|&(_, sub)| {
            // The nearest step above (or `s` itself) with the same ground task decides.
            above.iter().find(|&&(cur, _)| p.op_of(cur) == Some(sub)).is_some_and(|&(cur, progress)| {
                let through_others = cur != s && !self.task.ops[sub as usize].args.is_empty();
                !progress || through_others
            })
        })
    }

    /// The two ways to solve a threat: the threatening happening (or
    /// abstract step) before the producer, or after the link's protection.
    pub(super) fn threat_orders(&self, p: &Plan, t: &Threat) -> [(Tp, Tp); 2] {
        let link = p.links[t.link as usize];
        let step = p.steps[t.step as usize];
        match t.kind {
            ThreatKind::Delete(tp) | ThreatKind::Position(tp) => [(tp, link.from_tp), (link.until, tp)],
            ThreatKind::Conflict => [(step.end, link.from_tp), (link.until, step.start)],
        }
    }

    /// Drops the threats that are no longer threats and orders in place,
    /// until none is left, those that one ordering only still solves: false
    /// when one has none (the plan is dead). `exact` asks the network
    /// whether each ordering can be added (a dry run of its propagation);
    /// else only the closure is read (an ordering it does not contradict).
    pub(super) fn force_threats(&self, p: &mut Plan, exact: bool) -> bool {
        loop {
            let mut forced = false;
            let mut i = p.threats.len();
            while i > 0 {
                i -= 1;
                let t = p.threats[i];
                if !p.still_threat(self.task, &t) {
                    std::rc::Rc::make_mut(&mut p.threats).remove(i);
                    continue;
                }
                let ok = |p: &Plan, a: Tp, b: Tp| {
                    if exact { p.stn.allows(a, b, EPS) } else { !p.stn.before(b, a) && b != a }
                };
                let [(a1, b1), (a2, b2)] = self.threat_orders(p, &t);
                let (a, b) = match (ok(p, a1, b1), ok(p, a2, b2)) {
                    (false, false) => return false,
                    (true, true) => continue,
                    (true, false) => (a1, b1),
                    (false, true) => (a2, b2),
                };
                if !p.stn.add(a, b, EPS) {
                    return false;
                }
                std::rc::Rc::make_mut(&mut p.threats).remove(i);
                forced = true;
            }
            if !forced {
                return true;
            }
        }
    }

    /// The children of a plan for its chosen flaw.
    pub(super) fn resolvers(&self, p: &Plan, flaw: Flaw, out: &mut Vec<Plan>) {
        match flaw {
            Flaw::Threat(i) => {
                let t: Threat = p.threats[i];
                for (a, b) in self.threat_orders(p, &t) {
                    let mut c = p.clone();
                    std::rc::Rc::make_mut(&mut c.threats).remove(i);
                    if c.stn.add(a, b, EPS) {
                        out.push(c);
                    }
                }
            }
            Flaw::Open(i) => self.open_resolvers(p, i, out),
            Flaw::Abstract(i) => self.refinements_made(p, i, out, &mut |_| {}),
            Flaw::Visit(b) => {
                if let Some(geo) = &self.geo {
                    geo.extend(self.task, self.h, p, &b, out);
                }
            }
            Flaw::Late(til) => {
                for step in p.steps.iter() {
                    if self.elementary(step.kind) {
                        let mut c = p.clone();
                        if c.stn.add(til, step.end, EPS) {
                            out.push(c);
                        }
                    }
                }
                // Or a new step of 𝒜 after it (an elementary one; a move
                // only through an itinerary).
                for (op, o) in self.task.ops.iter().enumerate() {
                    let op = op as u32;
                    if !o.allowed
                        || o.dead
                        || o.is_abstract
                        || self.geo.is_some() && self.task.moves.contains_key(&op)
                    {
                        continue;
                    }
                    let mut c = p.clone();
                    let Some(s) = self.add_step(&mut c, op, None) else { continue };
                    let end = c.steps[s as usize].end;
                    if c.stn.add(til, end, EPS) {
                        out.push(c);
                    }
                }
            }
            Flaw::NumOrder(a, b) => {
                for (x, y) in [(a, b), (b, a)] {
                    let mut c = p.clone();
                    if c.stn.add(x, y, EPS) {
                        out.push(c);
                    }
                }
            }
            Flaw::Numeric(f) => self.numeric_resolvers(p, &f, out),
            Flaw::Mutex(a, b) => {
                for (x, y) in [(a, b), (b, a)] {
                    let mut c = p.clone();
                    if c.stn.add(x, y, EPS) {
                        out.push(c);
                    }
                }
            }
            Flaw::Front(refine) => self.front_resolvers(p, refine, out),
            Flaw::Dead => {}
        }
    }

    /// A numeric condition that does not hold: a step of 𝒜 whose effect on
    /// the fluent makes it hold (a `refuel` before a `fly`), inserted before
    /// the happening that reads it. Its conditions on positions of members
    /// with itineraries are linked at once to a step that puts the member
    /// there (each such producer a child): the itinerary went past it, and
    /// the new step fits in a stay the plan already has. The other orderings
    /// of the steps that touch the fluent were the siblings of this plan.
    pub(super) fn numeric_resolvers(&self, p: &Plan, f: &numeric::Failed, out: &mut Vec<Plan>) {
        let task = self.task;
        let Some(o) = p.op_of(f.step) else { return };
        let Some(cond) = task.ops[o as usize].num_conds.get(f.cond as usize) else { return };
        for &h in &task.numeric.writers[f.res as usize] {
            let op = &task.ops[h as usize];
            if !op.allowed || op.dead || op.is_abstract || !numeric::helps(task, h, f.res, f.value, cond) {
                continue;
            }
            let mut c = p.clone();
            let Some(s) = c.add_step(task, self.h, h, None) else { continue };
            let writes_at_end = op.num_effs.iter().any(|e| e.res == f.res && e.at == End::End);
            let step = c.steps[s as usize];
            let write = if writes_at_end { step.end } else { step.start };
            if !c.stn.add(write, f.tp, EPS) {
                continue;
            }
            self.link_positions(c, s, out);
        }
    }

    /// Links the open conditions of step `s` on positions of members with
    /// itineraries to each step that can put the member there before.
    fn link_positions(&self, p: Plan, s: u32, out: &mut Vec<Plan>) {
        let found = p.open.iter().position(|o| o.step == s && self.is_visit(o));
        let Some(i) = found else {
            out.push(p);
            return;
        };
        let o = p.open[i];
        let mut prod = Vec::new();
        self.producers(&p, &o, &mut prod);
        let mut base = p;
        base.remove_open(i);
        for (from, tp) in prod {
            let mut c = base.clone();
            if c.add_link(self.task, from, tp, &o) {
                self.link_positions(c, s, out);
            }
        }
    }

    /// The resolvers of open link `i`: causal links, then new steps.
    pub(super) fn open_resolvers(&self, p: &Plan, i: usize, out: &mut Vec<Plan>) {
        self.open_links(p, i, out);
        self.open_steps(p, i, out);
    }

    /// Plan `p` without its open link `i`, and that link.
    fn without_open(p: &Plan, i: usize) -> (Plan, Open) {
        let o = p.open[i];
        let mut base = p.clone();
        base.remove_open(i);
        (base, o)
    }

    /// The resolvers of open link `i` that link it to a step of the plan.
    pub(super) fn open_links(&self, p: &Plan, i: usize, out: &mut Vec<Plan>) {
        self.open_links_made(p, i, out, &mut |_| {});
    }

    /// [`Search::open_links`], telling `made` how each child was made.
    fn open_links_made(&self, p: &Plan, i: usize, out: &mut Vec<Plan>, made: &mut dyn FnMut(Made)) {
        let (base, o) = Self::without_open(p, i);
        // Causal links to existing steps. An abstract step's own effect is
        // its method's to achieve: only the steps it holds support it.
        // Another step would make a method that does not do what its
        // abstract action says; a new one, a second patrol inserted for
        // the first one's observations, at no cost in makespan when its
        // robot is idle (an endless plateau of equal f).
        let mut prod = Vec::new();
        self.producers(p, &o, &mut prod);
        if o.origin == OpenOrigin::AbstractEffect {
            prod.retain(|&(s, _)| s != o.step && p.descends(s, o.step));
        }
        for &(s, tp) in &prod {
            if self.past_limit() {
                return;
            }
            let by = By::Link(s, tp);
            if let Some(c) = self.made_by(base.clone(), &o, by) {
                out.push(c);
                made(Made::Link { open: i as u32, by });
            }
        }
    }

    /// The resolvers of open link `i` that insert a new step from 𝒜 (none
    /// for an abstract step's own effect; a visit gets its moves from its
    /// itinerary).
    pub(super) fn open_steps(&self, p: &Plan, i: usize, out: &mut Vec<Plan>) {
        self.open_steps_made(p, i, out, &mut |_| {});
    }

    /// [`Search::open_steps`], telling `made` how each child was made.
    fn open_steps_made(&self, p: &Plan, i: usize, out: &mut Vec<Plan>, made: &mut dyn FnMut(Made)) {
        if p.open[i].origin == OpenOrigin::AbstractEffect {
            return;
        }
        let Some(achievers) = self.task.achievers.get(&p.open[i].lit) else { return };
        let (base, o) = Self::without_open(p, i);
        let position = self.is_visit(&o);
        for &(op, at) in achievers {
            if self.past_limit() {
                return;
            }
            if position && self.task.moves.contains_key(&op) {
                continue;
            }
            if self.config.bare && self.task.ops[op as usize].is_abstract {
                continue;
            }
            let by = By::Step(op, at);
            if let Some(c) = self.made_by(base.clone(), &o, by) {
                out.push(c);
                made(Made::Link { open: i as u32, by });
            }
        }
    }

    /// The resolvers of open link `i` ([`Search::open_resolvers`]), with
    /// how each was made, in the same order.
    pub(super) fn open_resolvers_made(&self, p: &Plan, i: usize, out: &mut Vec<Plan>, made: &mut Vec<Made>) {
        self.open_links_made(p, i, out, &mut |m| made.push(m));
        self.open_steps_made(p, i, out, &mut |m| made.push(m));
    }

    /// The refinements of the abstract step at index `i` of `p.abstracts`:
    /// a child per method instance of its task that does not only go round
    /// a loop ([`Search::only_loops`]) and whose network takes it, telling
    /// `made` how each was made.
    pub(super) fn refinements_made(
        &self,
        p: &Plan,
        i: usize,
        out: &mut Vec<Plan>,
        made: &mut dyn FnMut(Made),
    ) {
        let s = p.abstracts[i];
        let Kind::Op(op) = p.steps[s as usize].kind else { return };
        for &m in &self.task.ops[op as usize].methods {
            if self.only_loops(p, s, m) {
                self.loops.set(self.loops.get() + 1);
                continue;
            }
            if let Some(c) = self.refined(p, i, m) {
                out.push(c);
                made(Made::Refined { at: i as u32, method: m });
            }
        }
    }

    /// `p` with the abstract step at index `i` of `p.abstracts` refined by
    /// method instance `m`: `None` when the network refuses it.
    fn refined(&self, p: &Plan, i: usize, m: u32) -> Option<Plan> {
        let s = p.abstracts[i];
        let mut c = p.clone();
        std::rc::Rc::make_mut(&mut c.abstracts).remove(i);
        self.refine(&mut c, s, m).then_some(c)
    }

    /// `base` (a plan without open link `o`) with `o` solved `by` a causal
    /// link to a step there or a new step: `None` when the network refuses
    /// it.
    fn made_by(&self, mut base: Plan, o: &Open, by: By) -> Option<Plan> {
        let (s, tp) = match by {
            By::Link(s, tp) => (s, tp),
            By::Step(op, at) => {
                let s = self.add_step(&mut base, op, None)?;
                (s, base.steps[s as usize].tp(at))
            }
        };
        base.add_link(self.task, s, tp, o).then_some(base)
    }

    /// The child of `parent` that [`Search::open_resolvers_made`] or
    /// [`Search::refinements_made`] made as `made`, made again: the same
    /// plan, not scored yet.
    pub(super) fn remake(&self, parent: &Plan, made: Made) -> Option<Plan> {
        match made {
            Made::Link { open, by } => {
                let i = open as usize;
                if i >= parent.open.len() {
                    return None;
                }
                let (base, o) = Self::without_open(parent, i);
                self.made_by(base, &o, by)
            }
            Made::Refined { at, method } => {
                let i = at as usize;
                if i >= parent.abstracts.len() {
                    return None;
                }
                self.refined(parent, i, method)
            }
        }
    }

    /// Refines abstract step `s` with method instance `m`: its subtasks as
    /// children within the step, the method's orderings, its precondition,
    /// and the step's own effects as open links its subtasks must achieve.
    pub(super) fn refine(&self, p: &mut Plan, s: u32, m: u32) -> bool {
        let method = &self.task.methods[m as usize];
        if let Some(st) = p.steps.get_mut(s as usize) {
            st.method = Some(m);
        }
        let mut ids = Vec::with_capacity(method.subtasks.len());
        for &(_, op) in &method.subtasks {
            match self.add_step(p, op, Some(s)) {
                Some(id) => ids.push(id),
                None => return false,
            }
        }
        for o in &method.orders {
            let a = p.steps[ids[o.from.0] as usize].tp(o.from.1);
            let b = p.steps[ids[o.to.0] as usize].tp(o.to.1);
            if !p.stn.add(a, b, if o.strict { EPS } else { 0.0 }) {
                return false;
            }
        }
        let step = p.steps[s as usize];
        for (ci, c) in method.pre.iter().enumerate() {
            let o = Open {
                step: s,
                lit: c.lit,
                need: step.start,
                until: step.start,
                cond: u32::MAX,
                origin: OpenOrigin::MethodPre(m, ci as u32),
                after_start: false,
            };
            // A position the step's itinerary already brought its member
            // to: the same causal link, or the method does not apply.
            let linked = match self.geo.as_ref().and_then(|_| Geo::position(self.task, c.lit)) {
                Some((g, _)) => p.links.iter().copied().find(|l| {
                    l.to == s
                        && l.need == step.start
                        && Geo::position(self.task, l.lit).is_some_and(|(g2, _)| g2 == g)
                }),
                None => None,
            };
            if let Some(l) = linked {
                if !(l.lit == c.lit && p.add_link(self.task, l.from, l.from_tp, &o)) {
                    return false;
                }
                continue;
            }
            if !self.add_open(p, o) {
                return false;
            }
        }
        let Kind::Op(op) = step.kind else { return true };
        for e in &self.task.ops[op as usize].effs {
            let tp = step.tp(e.at);
            let o = Open {
                step: s,
                lit: e.lit,
                need: tp,
                until: tp,
                cond: u32::MAX,
                origin: OpenOrigin::AbstractEffect,
                after_start: false,
            };
            if !self.add_open(p, o) {
                return false;
            }
        }
        true
    }
}

/// How a child of an open link or of an abstract flaw was made from its
/// parent: enough to make it again ([`Search::remake`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Made {
    /// The open link at this index of the parent's, supported `by`.
    Link { open: u32, by: By },
    /// The abstract step at index `at` of the parent's `abstracts`,
    /// refined by method instance `method`.
    Refined { at: u32, method: u32 },
}

/// What supports the open link of a [`Made`] child.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum By {
    /// A causal link from this step of the parent, at this time point.
    Link(u32, Tp),
    /// A new step of this operator, linked from this end of it.
    Step(u32, End),
}

/// The effects of a plan's steps by literal, and its position changes by
/// family group, each as `(step, literal, time point)` in the plan's order:
/// [`Search::producers_indexed`].
pub(super) struct Effects {
    by_lit: rustc_hash::FxHashMap<Lit, Vec<(u32, Lit, Tp)>>,
    by_group: rustc_hash::FxHashMap<u32, Vec<(u32, Lit, Tp)>>,
}

impl Effects {
    pub(super) fn new(task: &Task<'_>, p: &Plan) -> Effects {
        Effects::indexing(task, p, |_| true)
    }

    /// The index of the effects on `lits` and on the position groups of
    /// their atoms only: enough for the producers of open links on `lits`.
    pub(super) fn for_lits(task: &Task<'_>, p: &Plan, lits: impl Iterator<Item = Lit>) -> Effects {
        let group = |l: Lit| if is_neg(l) { None } else { task.family[atom_of(l) as usize].map(|(g, _)| g) };
        let (mut wanted, mut groups) = (rustc_hash::FxHashSet::default(), rustc_hash::FxHashSet::default());
        for l in lits {
            wanted.insert(l);
            groups.extend(group(l));
        }
        Effects::indexing(task, p, |l| wanted.contains(&l) || group(l).is_some_and(|g| groups.contains(&g)))
    }

    fn indexing(task: &Task<'_>, p: &Plan, keep: impl Fn(Lit) -> bool) -> Effects {
        let mut out = Effects { by_lit: Default::default(), by_group: Default::default() };
        for s in 0..p.steps.len() as u32 {
            for (l, tp) in p.effects(task, s) {
                if !keep(l) {
                    continue;
                }
                out.by_lit.entry(l).or_default().push((s, l, tp));
                if !is_neg(l)
                    && let Some((g, _)) = task.family[atom_of(l) as usize]
                {
                    out.by_group.entry(g).or_default().push((s, l, tp));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use std::time::{Duration, Instant};

    use super::super::super::{PlannerLimits, Stats};
    use super::super::Flaw;

    /// Three ways to make the goal: three children, unless the time limit
    /// of a running search has passed.
    const DOMAIN: &str = "(define (domain d) (:requirements :durative-actions)
      (:predicates (done))
      (:durative-action a :parameters () :duration (= ?duration 1) :effect (at end (done)))
      (:durative-action b :parameters () :duration (= ?duration 2) :effect (at end (done)))
      (:durative-action c :parameters () :duration (= ?duration 3) :effect (at end (done))))";
    const PROBLEM: &str = "(define (problem p) (:domain d) (:init) (:goal (done)))";

    #[test]
    fn past_the_time_limit_an_expansion_makes_no_more_children() {
        super::super::test_support::with_search(
            ("domain.pddl", "problem.pddl"),
            DOMAIN,
            PROBLEM,
            |_, search| {
                let mut roots = search.initial();
                let Some(Flaw::Open(goal)) = search.select(&mut roots[0]) else { panic!("the goal is open") };
                let children = |search: &super::Search<'_, '_>| {
                    let mut out = Vec::new();
                    search.resolvers(&roots[0], Flaw::Open(goal), &mut out);
                    out.len()
                };
                assert_eq!(children(search), 3);
                let mut stats = Stats::default();
                assert_eq!(search.expand(&roots[0], Flaw::Open(goal), &mut stats, &mut |_| {}).len(), 3);
                // The limit has passed: the expansion stops.
                search.until.set(Some(Instant::now()));
                assert_eq!(children(search), 0);
                assert!(search.expand(&roots[0], Flaw::Open(goal), &mut stats, &mut |_| {}).is_empty());
                // A search stopped by its limit leaves none behind it: what
                // reports its best partial plan gets every child.
                search.until.set(None);
                let limits =
                    PlannerLimits { time: Some(Duration::from_nanos(1)), ..PlannerLimits::default() };
                let mut best = None;
                let end =
                    search.run(search.initial(), &limits, &|| false, &mut |_| {}, &mut stats, &mut best);
                assert!(matches!(end, super::super::End2::Limit(_)));
                assert!(!search.past_limit());
                assert_eq!(children(search), 3);
            },
        );
    }

    /// `finish` makes both goals; `mark ?x` (five instances) makes `(p)`
    /// alone, quicker. A descent links the goal's `(p)` to the `finish`
    /// already there, and the five `mark` steps that could support it
    /// instead are never made: an open link's new steps are only made when
    /// the descent comes back to it after its causal links.
    const LAZY: &str = "(define (domain lazy)
  (:requirements :durative-actions :typing)
  (:types thing)
  (:predicates (p) (done))
  (:durative-action finish :parameters () :duration (= ?duration 5)
    :effect (and (at end (done)) (at end (p))))
  (:durative-action mark :parameters (?x - thing) :duration (= ?duration 1)
    :effect (at end (p))))";

    #[test]
    fn a_descent_makes_new_steps_only_after_the_causal_links() {
        let problem = "(define (problem p) (:domain lazy)
  (:objects a b c d e - thing) (:init) (:goal (and (done) (p))))";
        super::super::test_support::with_search(
            ("domain.pddl", "problem.pddl"),
            LAZY,
            problem,
            |_, search| {
                let mut stats = Stats::default();
                let found = search.probe(search.initial(), 100, 100, &|_| true, &mut stats, &|| false, true);
                let plan = found.expect("a plan");
                let ops: Vec<&str> = (0..plan.steps.len() as u32)
                    .filter_map(|s| plan.op_of(s))
                    .map(|o| &*search.task.ops[o as usize].name)
                    .collect();
                assert_eq!(ops, ["finish"]);
                // `finish` for `(done)`, then the link to it for `(p)`.
                assert_eq!(stats.generated, 2);
            },
        )
    }

    /// Two aircraft-like tokens: `spend-a` and `spend-b` each need the
    /// token at their start and use it up at their end, `mint` makes one:
    /// children of open links with threats to settle (one ordering left).
    const TOKEN: &str = "(define (domain token)
  (:requirements :durative-actions)
  (:predicates (token) (a) (b))
  (:durative-action spend-a :parameters () :duration (= ?duration 1)
    :condition (at start (token)) :effect (and (at end (not (token))) (at end (a))))
  (:durative-action spend-b :parameters () :duration (= ?duration 2)
    :condition (at start (token)) :effect (and (at end (not (token))) (at end (b))))
  (:durative-action mint :parameters () :duration (= ?duration 5)
    :effect (at end (token))))";

    /// Whether two plans are the same: steps, links, flaws and network
    /// (earliest times and the closure).
    fn same(a: &super::Plan, b: &super::Plan) -> bool {
        let n = a.stn.len() as u32;
        a.steps.iter().eq(b.steps.iter())
            && a.links.iter().eq(b.links.iter())
            && a.open.iter().eq(b.open.iter())
            && a.threats == b.threats
            && a.abstracts == b.abstracts
            && a.clock == b.clock
            && n == b.stn.len() as u32
            && (0..n).all(|x| a.stn.est(x) == b.stn.est(x))
            && (0..n).all(|x| (0..n).all(|y| a.stn.before(x, y) == b.stn.before(x, y)))
    }

    /// The search keeps the children of an open link as their parent and
    /// how each was made: made again and settled, each is the plan that
    /// was scored, at every level of the search down to the plans found.
    #[test]
    fn a_child_of_an_open_link_made_again_is_the_plan_scored() {
        let problem = "(define (problem p) (:domain token) (:init (token)) (:goal (and (a) (b))))";
        super::super::test_support::with_search(
            ("domain.pddl", "problem.pddl"),
            TOKEN,
            problem,
            |_, search| {
                let mut stats = Stats::default();
                let mut level = search.initial();
                let (mut made, mut settled) = (0, 0);
                for _ in 0..6 {
                    let mut next = Vec::new();
                    for mut p in level {
                        p.stn.flush();
                        p.stn.defer();
                        let Some(flaw) = search.select(&mut p) else { continue };
                        let recipe = matches!(flaw, Flaw::Open(_) | Flaw::Abstract(_));
                        for c in search.expand(&p, flaw, &mut stats, &mut |_| {}) {
                            assert_eq!(c.made.is_some(), recipe);
                            if let Some(how) = c.made {
                                let again = search.remade(&p, how).expect("made again");
                                assert!(same(&again, &c.plan), "{how:?}");
                                let unsettled = search.remake(&p, how).expect("made again");
                                settled += usize::from(!same(&unsettled, &c.plan));
                                made += 1;
                            }
                            next.push(c.plan);
                        }
                    }
                    level = next;
                }
                // Links to every step and new steps alike; and the settling
                // mattered for some (a threat ordered in place).
                assert!(made >= 10, "{made}");
                assert!(settled > 0);
            },
        )
    }

    /// Two tasks that each spend the one token, unordered, the first by
    /// spending it or by minting one first: refinements whose new steps
    /// threaten the other task's link.
    const TOKEN_HTN: &str = "(define (domain token-htn)
  (:requirements :hierarchy :negative-preconditions)
  (:predicates (token) (a) (b))
  (:task both :parameters ())
  (:task get-a :parameters ())
  (:task get-b :parameters ())
  (:method both-any :parameters () :task (both) :subtasks (and (get-a) (get-b)))
  (:method a-spend :parameters () :task (get-a) :ordered-subtasks (and (spend-a)))
  (:method a-mint :parameters () :task (get-a) :ordered-subtasks (and (mint) (spend-a)))
  (:method b-spend :parameters () :task (get-b) :ordered-subtasks (and (spend-b)))
  (:action spend-a :parameters () :precondition (token) :effect (and (not (token)) (a)))
  (:action spend-b :parameters () :precondition (token) :effect (and (not (token)) (b)))
  (:action mint :parameters () :effect (token)))";

    /// The search keeps the children of an abstract flaw as their parent,
    /// the abstract step and the method instance: made again and settled,
    /// each is the plan that was scored (and the same as the plan the
    /// resolvers make), at every level of the search.
    #[test]
    fn a_refinement_made_again_is_the_plan_scored() {
        let problem = "(define (problem p) (:domain token-htn)
  (:htn :subtasks (and (both))) (:init (token)))";
        // Links first: a task's `spend` is linked to its token before the
        // other task is refined.
        let links = super::super::super::Config { links: true, ..Default::default() };
        super::super::test_support::with_search_as(
            links,
            ("domain.hddl", "problem.hddl"),
            TOKEN_HTN,
            problem,
            |_, search| {
                let mut stats = Stats::default();
                let mut level = search.initial();
                let (mut refined, mut linked, mut threatened) = (0, 0, 0);
                for _ in 0..12 {
                    let mut next = Vec::new();
                    for mut p in level {
                        p.stn.flush();
                        p.stn.defer();
                        let Some(flaw) = search.select(&mut p) else { continue };
                        let mut eager = Vec::new();
                        if let Flaw::Abstract(i) = flaw {
                            search.resolvers(&p, Flaw::Abstract(i), &mut eager);
                        }
                        let abstract_flaw = !eager.is_empty();
                        for c in search.expand(&p, flaw, &mut stats, &mut |_| {}) {
                            assert_eq!(abstract_flaw, matches!(c.made, Some(super::Made::Refined { .. })));
                            if let Some(how) = c.made {
                                let again = search.remade(&p, how).expect("made again");
                                assert!(same(&again, &c.plan), "{how:?}");
                                let unsettled = search.remake(&p, how).expect("made again");
                                if abstract_flaw {
                                    assert!(eager.iter().any(|e| same(e, &unsettled)), "{how:?}");
                                    threatened += usize::from(!c.plan.threats.is_empty());
                                    refined += 1;
                                } else {
                                    linked += 1;
                                }
                            }
                            next.push(c.plan);
                        }
                    }
                    level = next;
                }
                // Every method of each task, in both orders of the tasks;
                // and refinements with threats left to settle.
                assert!(refined >= 5, "{refined}");
                assert!(linked > 0);
                assert!(threatened > 0);
            },
        )
    }
}
