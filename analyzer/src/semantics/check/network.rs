//! Checks of task networks: subtask ids and ordering cycles.

use rowan::TextRange;
use rustc_hash::FxHashMap;

use super::{Checker, suggest};
use crate::diagnostic::codes;
use crate::model::*;

/// A subtask's start (`true`) or end.
type TimePoint = (Str, bool);

/// The strongly connected component of each node (Kosaraju, iterative).
fn strongly_connected(n: usize, edges: &[(usize, usize, bool, usize)]) -> Vec<usize> {
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut rev: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(a, b, _, _) in edges {
        out[a].push(b);
        rev[b].push(a);
    }
    // First pass: finishing order.
    let mut order = Vec::with_capacity(n);
    let mut seen = vec![false; n];
    for s in 0..n {
        if seen[s] {
            continue;
        }
        seen[s] = true;
        let mut stack = vec![(s, 0usize)];
        while let Some((v, i)) = stack.pop() {
            if i < out[v].len() {
                stack.push((v, i + 1));
                let w = out[v][i];
                if !seen[w] {
                    seen[w] = true;
                    stack.push((w, 0));
                }
            } else {
                order.push(v);
            }
        }
    }
    // Second pass on the reversed graph, in reverse finishing order.
    let mut comp = vec![usize::MAX; n];
    let mut c = 0;
    for &s in order.iter().rev() {
        if comp[s] != usize::MAX {
            continue;
        }
        let mut stack = vec![s];
        comp[s] = c;
        while let Some(v) = stack.pop() {
            for &w in &rev[v] {
                if comp[w] == usize::MAX {
                    comp[w] = c;
                    stack.push(w);
                }
            }
        }
        c += 1;
    }
    comp
}

impl Checker<'_, '_> {
    /// Checks a task network; leaves its ids in `self.ids` for duration constraints.
    pub(super) fn network(&mut self, net: &TaskNetwork) {
        let mut ids: FxHashMap<Str, TextRange> = FxHashMap::default();
        for st in &net.subtasks {
            if let Some(id) = &st.id
                && let Some(first) = ids.insert(id.key_str(), id.span)
            {
                let msg = format!("subtask id `{}` is used twice", id.text());
                let loc = self.loc(first);
                self.diag(codes::DUPLICATE, id.span, msg).related.push((loc, "first used here".into()));
            }
            let dom = self.dom;
            match dom.callable(st.call.name.key()) {
                Some(decl) => self.call_args(&st.call, decl, "subtask"),
                None if !self.known_domain => {}
                None => {
                    let cands = self.dom.actions.keys().chain(self.dom.tasks.keys()).map(|k| &**k).collect();
                    self.undefined(codes::UNDEFINED_ACTION, "action or task", &st.call.name, cands);
                }
            }
        }
        self.ids = Some(ids.keys().cloned().collect());
        for o in &net.ordering {
            for p in [&o.left, &o.right] {
                self.subtask_id(&p.id);
            }
        }
        self.ordering_cycles(&net.ordering);
        for cl in &net.causal_links {
            self.subtask_id(&cl.from);
            self.subtask_id(&cl.to);
            self.atom(&cl.atom, false);
        }
        if let Some(c) = &net.constraints {
            self.gd(c, false);
        }
    }

    pub(super) fn subtask_id(&mut self, id: &Name) {
        let Some(ids) = &self.ids else { return };
        if !ids.contains(id.key()) {
            let cands: Vec<&str> = ids.iter().map(|k| &**k).collect();
            let suggestion = suggest(id.key(), cands.into_iter()).map(str::to_string);
            let d = self.diag(
                codes::UNDEFINED_SUBTASK,
                id.span,
                format!("no subtask has the id `{}`", id.text()),
            );
            if let Some(s) = suggestion {
                d.message.push_str(&format!(" (did you mean `{s}`?)"));
                d.fix = Some((format!("replace with `{s}`"), id.span, s));
            }
        }
    }

    /// Reports a cycle of strict orderings (`t1 < t2 < … < t1`): a strongly
    /// connected component of the time-point graph with a strict edge inside.
    pub(super) fn ordering_cycles(&mut self, orderings: &[Ordering]) {
        // Nodes are time points (subtask id, start?); a whole subtask before another means its end.
        let mut index: FxHashMap<TimePoint, usize> = FxHashMap::default();
        let mut node = |p: &OrderPoint, left: bool| -> usize {
            let start = match p.endpoint {
                Endpoint::Start => true,
                Endpoint::End => false,
                Endpoint::Whole => !left,
            };
            let n = index.len();
            *index.entry((p.id.key_str(), start)).or_insert(n)
        };
        // (from, to, strict, ordering index)
        let mut edges: Vec<(usize, usize, bool, usize)> = Vec::new();
        for (i, o) in orderings.iter().enumerate() {
            if o.negated {
                continue;
            }
            let (from, to, strict) = match o.op {
                CmpOp::Lt => (node(&o.left, true), node(&o.right, false), true),
                CmpOp::Le => (node(&o.left, true), node(&o.right, false), false),
                CmpOp::Gt => (node(&o.right, true), node(&o.left, false), true),
                CmpOp::Ge => (node(&o.right, true), node(&o.left, false), false),
                CmpOp::Eq => continue,
            };
            edges.push((from, to, strict, i));
        }
        // A subtask starts before it ends.
        let points: Vec<(TimePoint, usize)> = index.iter().map(|(k, v)| (k.clone(), *v)).collect();
        for ((id, start), n) in &points {
            if *start && let Some(&end) = index.get(&(id.clone(), false)) {
                edges.push((*n, end, false, usize::MAX));
            }
        }
        let comp = strongly_connected(index.len(), &edges);
        let Some(&(a, _, _, _)) = edges.iter().find(|(a, b, strict, _)| *strict && comp[*a] == comp[*b])
        else {
            return;
        };
        let mut involved: Vec<usize> = edges
            .iter()
            .filter(|(x, y, _, i)| comp[*x] == comp[a] && comp[*y] == comp[a] && *i != usize::MAX)
            .map(|e| e.3)
            .collect();
        involved.sort_unstable();
        involved.dedup();
        let related: Vec<_> = involved[1..]
            .iter()
            .map(|&i| (self.loc(orderings[i].span), "part of the cycle".to_string()))
            .collect();
        let msg = "these orderings form a cycle: no schedule can satisfy them".to_string();
        self.diag(codes::ORDERING_CYCLE, orderings[involved[0]].span, msg).related = related;
    }
}
