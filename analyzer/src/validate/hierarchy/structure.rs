//! The structure of a hierarchical plan: each step's parent, the top level
//! and its roots (pandaPIparser's artificial `__top` included), what the
//! roots reach: steps shared by two decompositions, cycles, orphans and
//! duplicate subtasks.

use rowan::TextRange;

use crate::diagnostic::codes;
use crate::plan::{NameMatching, normalise_name};

use super::{Cx, Top};

impl<'db> Cx<'_, 'db> {
    /// Parents, the top level, what the roots reach: shared steps, cycles,
    /// orphans, duplicate subtasks.
    pub(super) fn structure(&mut self) {
        let n = self.plan.steps.len();
        for i in 0..n {
            let s = &self.plan.steps[i];
            let Some(dec) = &s.decomposition else { continue };
            let mut seen: Vec<u32> = Vec::with_capacity(dec.subtasks.len());
            for sub in &dec.subtasks {
                let Some(j) = self.plan.index_of(sub.value) else { continue };
                if seen.contains(&sub.value) {
                    let first =
                        dec.subtasks.iter().find(|x| x.value == sub.value).map_or(sub.range, |x| x.range);
                    let mut d = self.diag(
                        codes::DUPLICATE_SUBTASK,
                        sub.range,
                        format!("{} lists its subtask {} twice", self.step_text(i), sub.value),
                    );
                    self.related_plan(&mut d, first, "listed here first");
                    self.hint(
                        &mut d,
                        "a step refines one subtask: remove the second id",
                        vec![(sub.range, String::new())],
                    );
                    self.push(d);
                    self.bad_list[i] = true;
                    continue;
                }
                seen.push(sub.value);
                if j == i {
                    let mut d = self.diag(
                        codes::DECOMPOSITION_CYCLE,
                        sub.range,
                        format!("{} lists itself as its own subtask", self.step_text(i)),
                    );
                    self.hint(&mut d, "a step's subtasks are other steps: give the id of the step that refines this subtask", Vec::new());
                    self.push(d);
                    self.bad_list[i] = true;
                    continue;
                }
                match self.parent[j] {
                    Some(p) if p != i => {
                        let mut d = self.diag(
                            codes::SHARED_STEP,
                            sub.range,
                            format!(
                                "{} is a subtask of {} and of {}: a step refines one task only",
                                self.step_text(j),
                                self.step_text(p),
                                self.step_text(i)
                            ),
                        );
                        let other = self.subtask_range(p, sub.value);
                        self.related_plan(
                            &mut d,
                            other,
                            format!("listed as a subtask of step {} here", self.id_value(p)),
                        );
                        self.hint(
                            &mut d,
                            "give each decomposition its own steps: add a step for this subtask with a new id",
                            Vec::new(),
                        );
                        self.push(d);
                        self.bad_list[i] = true;
                    }
                    _ => self.parent[j] = Some(i),
                }
            }
        }
        self.find_top();
        // What the top level reaches, depth first.
        let mut stack: Vec<usize> = Vec::new();
        let top: Vec<usize> = if self.top.implicit {
            (0..n).filter(|&i| self.parent[i].is_none()).collect()
        } else {
            let mut v = Vec::new();
            if let Some(a) = self.top.artificial {
                v.push(a);
            }
            v.extend(self.top.ids.iter().filter_map(|id| self.plan.index_of(id.value)));
            v
        };
        stack.extend(top.iter().rev());
        while let Some(i) = stack.pop() {
            if self.reached[i] {
                continue;
            }
            self.reached[i] = true;
            self.order.push(i);
            if let Some(dec) = &self.plan.steps[i].decomposition {
                for sub in dec.subtasks.iter().rev() {
                    if let Some(j) = self.plan.index_of(sub.value)
                        && self.parent[j] == Some(i)
                    {
                        stack.push(j);
                    }
                }
            }
        }
        if !self.top.implicit {
            self.unreached();
        }
    }

    /// The range of `id` in the subtask list of step `p`.
    fn subtask_range(&self, p: usize, id: u32) -> TextRange {
        let s = &self.plan.steps[p];
        s.decomposition
            .as_ref()
            .and_then(|d| d.subtasks.iter().find(|x| x.value == id))
            .map_or(s.range, |x| x.range)
    }

    /// The `root` line, or the `__top` step, and what is wrong with them.
    fn find_top(&mut self) {
        let Some(root) = &self.plan.root else {
            self.top = Top {
                ids: Vec::new(),
                artificial: None,
                range: self.plan.begin.unwrap_or_default(),
                implicit: true,
            };
            return;
        };
        let mut top = Top { ids: root.ids.clone(), artificial: None, range: root.range, implicit: false };
        if let Some(i) = self.artificial_top() {
            // `root 8` and `8 __top -> __top_method 13 16`.
            let dec = self.plan.steps[i].decomposition.as_ref();
            top = Top {
                ids: dec.map(|d| d.subtasks.clone()).unwrap_or_default(),
                artificial: Some(i),
                range: self.plan.steps[i].range,
                implicit: false,
            };
            if let Some(method) = dec.map(|d| &d.method)
                && normalise_name(&method.text, NameMatching::Lenient) != "--top-method"
            {
                self.top_method(i, method.range, &method.text);
            }
        }
        let mut seen: Vec<u32> = Vec::new();
        for id in &root.ids {
            let Some(j) = self.plan.index_of(id.value) else { continue };
            if seen.contains(&id.value) {
                let mut d = self.diag(
                    codes::DUPLICATE_SUBTASK,
                    id.range,
                    format!("the `root` line lists step {} twice", id.value),
                );
                self.hint(&mut d, "remove the second id", vec![(id.range, String::new())]);
                self.push(d);
                continue;
            }
            seen.push(id.value);
            if let Some(p) = self.parent[j] {
                let mut d = self.diag(
                    codes::SHARED_STEP,
                    id.range,
                    format!("{} is a root and a subtask of {}", self.step_text(j), self.step_text(p)),
                );
                let other = self.subtask_range(p, id.value);
                self.related_plan(&mut d, other, "listed as a subtask here");
                self.hint(
                    &mut d,
                    "a root is a task of the problem, not a subtask of another step: remove it from one of the lists",
                    Vec::new(),
                );
                self.push(d);
            }
        }
        self.top = top;
    }

    /// pandaPIparser's artificial root: the only id of the `root` line, a
    /// step of the task `__top` (which no domain declares).
    pub(super) fn artificial_top(&self) -> Option<usize> {
        let [only] = self.plan.root.as_ref()?.ids.as_slice() else { return None };
        let i = self.plan.index_of(only.value)?;
        let s = &self.plan.steps[i];
        (s.is_abstract() && normalise_name(&s.name.text, NameMatching::Lenient) == "--top").then_some(i)
    }

    /// The artificial root refined by another method than `__top_method`
    /// (pandaPIparser's method of the problem's `:htn`).
    fn top_method(&mut self, i: usize, range: TextRange, name: &str) {
        let (code, message) = match self.methods.get(name, self.opts.matching) {
            Some(key) => {
                let task = self.dom.methods.get(key).and_then(|d| d.task.clone()).unwrap_or_default();
                (
                    codes::WRONG_METHOD,
                    format!(
                        "{} is refined by `{name}`, but `{key}` is a method of `{task}`, not of the artificial root `__top`",
                        self.step_text(i)
                    ),
                )
            }
            None => (
                codes::UNKNOWN_METHOD,
                format!(
                    "{} is refined by `{name}`, but the artificial root `__top` has one method, `__top_method`",
                    self.step_text(i)
                ),
            ),
        };
        let mut d = self.diag(code, range, message);
        self.hint(
            &mut d,
            "pandaPIparser's artificial root is refined by `__top_method` into the tasks of the problem's `:htn`",
            vec![(range, "__top_method".to_string())],
        );
        self.push(d);
    }

    /// Cycles and orphans: steps the top level does not reach.
    fn unreached(&mut self) {
        let n = self.plan.steps.len();
        // A step the roots do not reach is on a cycle of parents, below one,
        // or below a step without parent (an orphan).
        let mut cycle_of: Vec<bool> = vec![false; n];
        for i in 0..n {
            if self.reached[i] || cycle_of[i] {
                continue;
            }
            let mut path = vec![i];
            let mut at = i;
            while let Some(p) = self.parent[at] {
                if self.reached[p] || cycle_of[p] {
                    break;
                }
                if let Some(k) = path.iter().position(|&x| x == p) {
                    let cycle: Vec<usize> = path[k..].to_vec();
                    cycle.iter().for_each(|&c| cycle_of[c] = true);
                    self.report_cycle(&cycle);
                    break;
                }
                path.push(p);
                at = p;
            }
        }
        for i in 0..n {
            if self.reached[i] || cycle_of[i] || Some(i) == self.top.artificial {
                continue;
            }
            // Report the top of each orphan subtree only.
            let mut up = self.parent[i];
            let mut below_other = false;
            while let Some(p) = up {
                if cycle_of[p] || !self.reached[p] {
                    below_other = true;
                    break;
                }
                up = self.parent[p];
            }
            if below_other {
                continue;
            }
            let below = self.count_below(i);
            let what = if self.plan.steps[i].is_abstract() { "abstract step" } else { "primitive step" };
            let mut message = format!(
                "{} is not a root and no decomposition lists it: every {what} must be reached from the `root` line",
                self.step_text(i)
            );
            if below > 0 {
                message.push_str(&format!(" (nor are the {below} steps below it)"));
            }
            let mut d = self.diag(codes::ORPHAN_STEP, self.id_range(i), message);
            match (&self.htn, &self.plan.root) {
                (None, Some(r)) => {
                    let edit = (TextRange::empty(r.range.end()), format!(" {}", self.id_value(i)));
                    self.hint(
                        &mut d,
                        "add it to the `root` line, or list it as a subtask of the step it refines",
                        vec![edit],
                    );
                }
                _ => {
                    self.hint(&mut d, "list it as a subtask of the step it refines, or remove it", Vec::new())
                }
            }
            self.push(d);
        }
    }

    fn count_below(&self, i: usize) -> usize {
        let mut count = 0;
        let mut stack = vec![i];
        let mut seen = vec![false; self.plan.steps.len()];
        while let Some(x) = stack.pop() {
            if std::mem::replace(&mut seen[x], true) {
                continue;
            }
            if let Some(dec) = &self.plan.steps[x].decomposition {
                for sub in &dec.subtasks {
                    if let Some(j) = self.plan.index_of(sub.value)
                        && self.parent[j] == Some(x)
                        && !seen[j]
                    {
                        count += 1;
                        stack.push(j);
                    }
                }
            }
        }
        count
    }

    fn report_cycle(&mut self, cycle: &[usize]) {
        // Report at the step listed first in the file.
        let Some(&first) = cycle.iter().min_by_key(|&&c| self.plan.steps[c].range.start()) else { return };
        let names: Vec<String> = cycle.iter().map(|&c| self.id_value(c).to_string()).collect();
        let mut d = self.diag(
            codes::DECOMPOSITION_CYCLE,
            self.id_range(first),
            format!(
                "the steps {} are subtasks of each other in a cycle: no root reaches them, and none can be refined into actions",
                names.join(" → ")
            ),
        );
        for &c in cycle {
            if c != first {
                self.related_plan(&mut d, self.id_range(c), "on the cycle");
            }
        }
        self.hint(
            &mut d,
            "a decomposition lists the steps that refine its task: break the cycle",
            Vec::new(),
        );
        self.push(d);
        cycle.iter().for_each(|&c| self.bad_list[c] = true);
    }
}
