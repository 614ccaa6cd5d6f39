//! The steps of a hierarchical plan resolved against the declarations: each
//! step's action or task, its arguments' objects and their types, with what
//! does not resolve reported (unknown names with suggestions, wrong arity,
//! unknown objects, type mismatches).

use crate::diagnostic::codes;
use crate::model::Str;
use crate::plan::{NameMatching, normalise_name};
use crate::semantics::check::suggest;
use crate::semantics::symbols::Loc;

use super::{Cx, Resolved, a};

impl<'db> Cx<'_, 'db> {
    /// Resolves step `i` to its action or task and objects, reporting what
    /// does not resolve.
    pub(super) fn resolve(&mut self, i: usize) {
        let s = &self.plan.steps[i];
        let m = self.opts.matching;
        if self.artificial_top() == Some(i) {
            // pandaPIparser's artificial root: its subtasks are the top level.
            return;
        }
        let check = s.is_abstract() || self.opts.check_primitive_steps;
        let (key, params, loc) = if s.is_abstract() {
            match self.tasks.get(&s.name.text, m).cloned() {
                Some(k) => {
                    let d = &self.dom.tasks[&k];
                    (k, d.params.clone(), d.loc)
                }
                None => {
                    self.unknown_callable(i, true);
                    return;
                }
            }
        } else {
            match self.actions.get(&s.name.text, m).cloned() {
                Some(k) => {
                    let d = &self.dom.actions[&k];
                    (k, d.params.clone(), d.loc)
                }
                None => {
                    if check {
                        self.unknown_callable(i, false);
                    }
                    self.unresolved_primitives = true;
                    return;
                }
            }
        };
        let what = if s.is_abstract() { "task" } else { "action" };
        if s.args.len() != params.len() {
            if check {
                let code = if s.is_abstract() { codes::TASK_STEP_ARITY } else { codes::STEP_ARITY };
                let names = self.param_names(&key, s.is_abstract());
                let n = s.args.len();
                let mut d = self.diag(
                    code,
                    s.range,
                    format!(
                        "{} gives `{key}` {n} argument{}, but the {what} takes {} ({})",
                        self.step_text(i),
                        if n == 1 { "" } else { "s" },
                        params.len(),
                        names.join(" ")
                    ),
                );
                self.related_loc(&mut d, loc, format!("the {what} is declared here"));
                self.push(d);
            }
            self.unresolved_primitives |= !s.is_abstract();
            return;
        }
        let mut args = Vec::with_capacity(s.args.len());
        let mut ok = true;
        for (k, a) in s.args.iter().enumerate() {
            match self.object_names.get(&a.text, m).cloned() {
                Some(o) if self.fits(&o, &params[k]) => args.push(o),
                Some(o) => {
                    ok = false;
                    if check {
                        self.type_mismatch(i, k, &key, &o, &params[k], loc);
                    }
                }
                None => {
                    ok = false;
                    if check {
                        self.unknown_object(i, k, &params[k]);
                    }
                }
            }
        }
        if !ok {
            self.unresolved_primitives |= !s.is_abstract();
            return;
        }
        self.resolved[i] = Some(Resolved { key, args });
    }

    fn param_names(&self, key: &str, task: bool) -> Vec<String> {
        let d = if task { self.dom.tasks.get(key) } else { self.dom.actions.get(key) };
        d.map(|d| d.param_names.iter().map(|p| p.to_string()).collect()).unwrap_or_default()
    }

    fn unknown_callable(&mut self, i: usize, is_abstract: bool) {
        let s = &self.plan.steps[i];
        let m = self.opts.matching;
        let name = &s.name.text;
        let (code, what, other, other_what) = if is_abstract {
            (codes::UNKNOWN_TASK_IN_PLAN, "task", self.actions.get(name, m).cloned(), "action")
        } else {
            (codes::UNKNOWN_ACTION_IN_PLAN, "action", self.tasks.get(name, m).cloned(), "task")
        };
        let mut d = self.diag(
            code,
            s.name.range,
            format!("{}: the domain has no {what} `{name}`", self.step_text(i)),
        );
        if let Some(other) = other {
            let loc = if is_abstract { self.dom.actions[&other].loc } else { self.dom.tasks[&other].loc };
            d.message = format!(
                "{}: `{name}` is {} {other_what}, not {} {what}",
                self.step_text(i),
                a(other_what),
                a(what)
            );
            self.related_loc(&mut d, loc, format!("the {other_what} is declared here"));
            let hint = if is_abstract {
                "an action is a primitive step: list it before `root`, as `ID action args…`, without `->`"
            } else {
                "a task is an abstract step: write it after `root`, as `ID task args… -> method subtask-ids…`"
            };
            self.hint(&mut d, hint, Vec::new());
        } else if is_abstract && normalise_name(name, NameMatching::Lenient) == "--top" {
            self.hint(
                &mut d,
                "pandaPIparser's artificial root `__top` stands for the problem's `:htn` only as the one id of the `root` line",
                Vec::new(),
            );
        } else {
            let keys: Vec<&str> = if is_abstract {
                self.dom.tasks.keys().map(|k| k.as_str()).collect()
            } else {
                self.dom.actions.keys().map(|k| k.as_str()).collect()
            };
            if let Some(best) = suggest(&name.to_ascii_lowercase(), keys.into_iter()) {
                let best = best.to_string();
                self.hint(&mut d, format!("did you mean `{best}`?"), vec![(s.name.range, best)]);
            }
        }
        self.push(d);
    }

    fn unknown_object(&mut self, i: usize, k: usize, wanted: &[Str]) {
        let s = &self.plan.steps[i];
        let arg = &s.args[k];
        let mut d = self.diag(
            codes::UNKNOWN_OBJECT_IN_PLAN,
            arg.range,
            format!(
                "{}: `{}` is not an object of the problem or a constant of the domain",
                self.step_text(i),
                arg.text
            ),
        );
        let candidates = self.objects.of_types(wanted);
        let names: Vec<&str> = candidates.iter().map(|&o| self.objects.name(o)).collect();
        if let Some(best) = suggest(&arg.text.to_ascii_lowercase(), names.into_iter()) {
            let best = best.to_string();
            self.hint(&mut d, format!("did you mean `{best}`?"), vec![(arg.range, best)]);
        }
        self.push(d);
    }

    fn type_mismatch(&mut self, i: usize, k: usize, key: &str, object: &str, wanted: &[Str], decl: Loc<'db>) {
        let s = &self.plan.steps[i];
        let arg = &s.args[k];
        let param = self.param_names(key, s.is_abstract()).get(k).cloned().unwrap_or_default();
        let mut d = self.diag(
            codes::STEP_TYPE_MISMATCH,
            arg.range,
            format!(
                "{}: `{}` is of type `{}`, but parameter `{param}` of `{key}` has type `{}`",
                self.step_text(i),
                arg.text,
                self.type_of(object),
                wanted.join(" or ")
            ),
        );
        self.related_loc(&mut d, decl, "declared here");
        if let Some(loc) = self.objects.id(object).and_then(|o| self.objects.loc(o)) {
            self.related_loc(&mut d, loc, format!("`{}` is declared here", arg.text));
        }
        self.push(d);
    }
}
