//! Hostile input on small stacks.
//!
//! Deep nesting: lists nest at most `syntax::MAX_NESTING` deep. A deeper list
//! is kept as text (one E0007) and the tree never gets deeper, so that every
//! recursion over the tree and over what is read from it (lowering, checks,
//! lints, grounding, validation, the planner, the IDE features, comparing and
//! dropping trees and models) is bounded, whatever the input. Each model here
//! nests one construct as deep as the limit allows, and is analysed on a
//! thread with half the stack the language server's threads have (2 MiB):
//! every feature must fit with a margin of two.
//!
//! Long lists: what walks the elements of one list (the parameters of an
//! action, the variables of a quantifier, the subtasks of a decomposition)
//! does it without recursion.

use hipop_analyzer::planner::{Config, PlannerLimits};
use hipop_analyzer::syntax::{self, MAX_NESTING};
use hipop_analyzer::validate::Options;
use hipop_analyzer::{AnalysisHost, Diagnostic, TextEdit, TextRange, TextSize, codes};

/// Half the stack of tokio's threads (the language server's requests and
/// diagnostics) and of the analyzer's own threads.
const SMALL_STACK: usize = 1 << 20;

fn on_small_stack<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    std::thread::scope(|scope| {
        std::thread::Builder::new()
            .stack_size(SMALL_STACK)
            .spawn_scoped(scope, f)
            .expect("a thread")
            .join()
            .expect("no stack overflow, no panic")
    })
}

/// `open` `depth` times, `core`, then `close` `depth` times.
fn nest(depth: usize, open: &str, core: &str, close: &str) -> String {
    let mut s = String::with_capacity(depth * (open.len() + close.len()) + core.len());
    (0..depth).for_each(|_| s.push_str(open));
    s.push_str(core);
    (0..depth).for_each(|_| s.push_str(close));
    s
}

/// How deep lists nest in a text (comments and strings aside: none here).
fn max_depth(text: &str) -> usize {
    let (mut depth, mut deepest) = (0usize, 0usize);
    for b in text.bytes() {
        match b {
            b'(' => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            b')' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    deepest
}

const REQUIREMENTS: &str = ":strips :typing :negative-preconditions :disjunctive-preconditions \
     :quantified-preconditions :conditional-effects :numeric-fluents :durative-actions :hierarchy \
     :method-preconditions";

/// A domain where `slot` (a precondition, an effect, …) is replaced, and a
/// problem with one object of each type, so that nested quantifiers ground
/// to one instance each.
struct Model {
    name: &'static str,
    domain: String,
    problem: String,
    /// A plan of the problem, in any format hipop reads.
    plan: &'static str,
}

fn pddl_domain(precondition: &str, effect: &str) -> String {
    format!(
        "(define (domain deep) (:requirements {REQUIREMENTS})
  (:types thing)
  (:predicates (p ?x - thing) (q ?x - thing))
  (:functions (f ?x - thing))
  (:action a :parameters (?x - thing)
    :precondition {precondition}
    :effect {effect}))
"
    )
}

fn pddl_problem(goal: &str) -> String {
    format!(
        "(define (problem deep-1) (:domain deep)
  (:objects o - thing)
  (:init (p o) (= (f o) 1))
  (:goal {goal}))
"
    )
}

/// One model per construct that nests, each as deep as allowed.
fn models(extra: usize) -> Vec<Model> {
    // The deepest list of a formula of an action is inside `define` and the
    // action: a formula may nest `MAX_NESTING - 2` deep; `(p ?x)` is its innermost list.
    let k = MAX_NESTING - 3 + extra;
    let and = nest(k, "(and ", "(p ?x)", ")");
    let or = nest(k, "(or (q ?x) ", "(p ?x)", ")");
    let not = nest(k, "(not ", "(p ?x)", ")");
    let imply = nest(k, "(imply (p ?x) ", "(p ?x)", ")");
    // `(forall (?y - thing) …)`: the variable list is one level below the quantifier.
    let forall = nest(k, "(forall (?y - thing) ", "(p ?y)", ")");
    let exists = nest(k, "(exists (?y - thing) ", "(p ?y)", ")");
    let sum = format!("(>= {} 0)", nest(k - 1, "(+ 1 ", "(f ?x)", ")"));
    let effect_and = nest(k, "(and ", "(q ?x)", ")");
    let when = nest(k, "(when (p ?x) ", "(q ?x)", ")");
    let effect_forall = nest(k, "(forall (?y - thing) ", "(q ?y)", ")");
    let increase = format!("(increase (f ?x) {})", nest(k - 1, "(* 1 ", "(f ?x)", ")"));
    let plan = "0: (a o)\n";
    let mut out = Vec::new();
    for (name, pre, eff) in [
        ("and", &and, "(q ?x)"),
        ("or", &or, "(q ?x)"),
        ("not", &not, "(q ?x)"),
        ("imply", &imply, "(q ?x)"),
        ("forall", &forall, "(q ?x)"),
        ("exists", &exists, "(q ?x)"),
        ("numeric", &sum, "(q ?x)"),
        ("effect-and", &"(p ?x)".to_string(), effect_and.as_str()),
        ("when", &"(p ?x)".to_string(), when.as_str()),
        ("effect-forall", &"(p ?x)".to_string(), effect_forall.as_str()),
        ("increase", &"(p ?x)".to_string(), increase.as_str()),
    ] {
        out.push(Model { name, domain: pddl_domain(pre, eff), problem: pddl_problem("(q o)"), plan });
    }
    // A goal, one level less deep than an action's formula.
    out.push(Model {
        name: "goal",
        domain: pddl_domain("(p ?x)", "(q ?x)"),
        problem: pddl_problem(&nest(k, "(and ", "(q o)", ")")),
        plan,
    });
    // Timed conditions and effects of a durative action.
    let timed = |inner: &str| {
        format!(
            "(define (domain deep) (:requirements {REQUIREMENTS})
  (:types thing)
  (:predicates (p ?x - thing) (q ?x - thing))
  (:functions (f ?x - thing))
  (:durative-action a :parameters (?x - thing) :duration (= ?duration 1)
    :condition (at start {inner})
    :effect (at end {})))
",
            nest(k - 1, "(and ", "(q ?x)", ")")
        )
    };
    out.push(Model {
        name: "durative",
        domain: timed(&nest(k - 1, "(and ", "(p ?x)", ")")),
        problem: pddl_problem("(q o)"),
        plan: "0.000: (a o) [1.000]\n",
    });
    // A method's precondition and its ordering (`not` nests orderings).
    let htn = format!(
        "(define (domain deep) (:requirements {REQUIREMENTS})
  (:types thing)
  (:predicates (p ?x - thing) (q ?x - thing))
  (:task t :parameters (?x - thing))
  (:method m :parameters (?x - thing) :task (t ?x)
    :precondition {}
    :subtasks (and (t1 (a ?x)) (t2 (b ?x)))
    :ordering {})
  (:action a :parameters (?x - thing) :precondition (p ?x) :effect (q ?x))
  (:action b :parameters (?x - thing) :precondition (q ?x) :effect (p ?x)))
",
        nest(k, "(and ", "(p ?x)", ")"),
        nest(k, "(not ", "(< t1 t2)", ")"),
    );
    out.push(Model {
        name: "method",
        domain: htn,
        problem: "(define (problem deep-1) (:domain deep)
  (:objects o - thing)
  (:htn :tasks (t o))
  (:init (p o)))
"
        .to_string(),
        plan: "==>\n0 a o\n1 b o\nroot 2\n2 t o -> m 0 1\n<==\n",
    });
    // Timed initial literals nest (`(at 1 (at 2 …))` is read, then rejected).
    let til = format!(
        "(define (problem deep-1) (:domain deep)
  (:objects o - thing)
  (:init (p o) {})
  (:goal (q o)))
",
        nest(MAX_NESTING - 3 + extra, "(at 1 ", "(q o)", ")")
    );
    out.push(Model { name: "init", domain: pddl_domain("(p ?x)", "(q ?x)"), problem: til, plan });
    out
}

fn codes_of(diagnostics: &[Diagnostic]) -> Vec<&'static str> {
    diagnostics.iter().map(|d| d.code.id).collect()
}

/// Everything the analyzer offers, on a domain, its problem and a plan.
fn exercise(model: &Model) -> (Vec<Diagnostic>, Vec<Diagnostic>) {
    let mut host = AnalysisHost::new();
    let d = host.set_file_text("deep/domain.hddl", model.domain.as_str());
    let p = host.set_file_text("deep/problem.hddl", model.problem.as_str());
    let plan = host.set_file_text("deep/problem.plan", model.plan);
    let analysis = host.analysis();
    let domain_diags = analysis.diagnostics(d).expect("not cancelled");
    let problem_diags = analysis.diagnostics(p).expect("not cancelled");
    analysis.diagnostics(plan).expect("not cancelled");
    for (file, text) in [(d, &model.domain), (p, &model.problem)] {
        analysis.document_symbols(file).expect("not cancelled");
        analysis.folding_ranges(file).expect("not cancelled");
        analysis.semantic_tokens(file).expect("not cancelled");
        analysis.code_actions(file, TextRange::up_to(TextSize::of(text.as_str()))).expect("not cancelled");
        // Formatted to the limit (and idempotent); beyond it, refused for the syntax error.
        match analysis.format(file).expect("not cancelled") {
            Ok(formatted) => assert_eq!(hipop_analyzer::ide::format(&formatted).as_ref(), Ok(&formatted)),
            Err(e) => assert_eq!(e.kind, hipop_analyzer::ide::FormatErrorKind::Syntax, "{}", e.message),
        }
        // Every name of the innermost formula and around it.
        for at in (0..text.len()).step_by(7) {
            let at = TextSize::from(at as u32);
            analysis.hover(file, at).expect("not cancelled");
            analysis.goto_definition(file, at).expect("not cancelled");
            analysis.references(file, at, true).expect("not cancelled");
            analysis.document_highlights(file, at).expect("not cancelled");
            analysis.prepare_rename(file, at).expect("not cancelled").ok();
            analysis.rename(file, at, "renamed").expect("not cancelled").ok();
            analysis.completions(file, at).expect("not cancelled");
        }
    }
    analysis.validate_plan(plan, None, p, &Options::default()).expect("not cancelled");
    let limits = PlannerLimits { nodes: Some(200), ..Default::default() };
    let r =
        analysis.run_planner(p, &Config::default(), &limits, &|| false, &mut |_| {}).expect("not cancelled");
    // What the editor shows of the run, on the problem and the domain.
    if let Some(r) = r {
        let (run, _) = r.into_run(limits.time);
        analysis.plan_hints(p, &run).expect("not cancelled");
        if let Some(plan) = &run.plan {
            for (file, text) in [(d, &model.domain), (p, &model.problem)] {
                for at in (0..text.len()).step_by(13) {
                    let plans = [("p".to_string(), plan)];
                    analysis.plan_hover(file, TextSize::from(at as u32), &plans).expect("not cancelled");
                }
            }
        }
    }
    drop(analysis);
    // An edit in the innermost list re-parses it alone, among its deep ancestors.
    let inner = model.domain.rfind("?x)").expect("an innermost `?x`");
    let edit = TextEdit { range: TextRange::at(TextSize::from(inner as u32), 2.into()), insert: "?x".into() };
    host.apply_edits("deep/domain.hddl", vec![edit]).expect("the domain is loaded");
    let again = host.analysis().diagnostics(d).expect("not cancelled");
    assert_eq!(codes_of(&again), codes_of(&domain_diags), "{}: an edit changed nothing", model.name);
    (domain_diags, problem_diags)
}

#[test]
fn formulas_nested_to_the_limit_are_analysed_on_a_small_stack() {
    for model in models(0) {
        for text in [&model.domain, &model.problem] {
            let parse = syntax::parse(text);
            assert!(parse.errors.is_empty(), "{}: {:?}", model.name, parse.errors);
        }
        assert_eq!(max_depth(&model.domain).max(max_depth(&model.problem)), MAX_NESTING, "{}", model.name);
        let (domain, problem) = on_small_stack(|| exercise(&model));
        let all: Vec<&str> = codes_of(&domain).into_iter().chain(codes_of(&problem)).collect();
        assert!(!all.contains(&codes::NESTING_TOO_DEEP.id), "{}: {all:?}", model.name);
    }
}

#[test]
fn one_level_deeper_is_a_located_error_per_list() {
    for model in models(1) {
        let (domain, problem) = on_small_stack(|| exercise(&model));
        for (diagnostics, text) in [(&domain, &model.domain), (&problem, &model.problem)] {
            let deep: Vec<usize> = diagnostics
                .iter()
                .filter(|d| d.code.id == codes::NESTING_TOO_DEEP.id)
                .map(|d| usize::from(d.range.start()))
                .collect();
            // At each `(` that opens a list one level too deep (`(or (q ?x) (p ?x))`
            // has two), and nowhere else.
            let mut depth = 0;
            let mut too_deep = Vec::new();
            for (i, b) in text.bytes().enumerate() {
                match b {
                    b'(' if depth == MAX_NESTING => {
                        too_deep.push(i);
                        depth += 1;
                    }
                    b'(' => depth += 1,
                    b')' => depth -= 1,
                    _ => {}
                }
            }
            assert_eq!(deep, too_deep, "{}: {:?}", model.name, codes_of(diagnostics));
        }
        assert!(
            domain.iter().chain(&problem).any(|d| d.code.id == codes::NESTING_TOO_DEEP.id),
            "{}",
            model.name
        );
    }
}

/// An action of 10,000 parameters and a quantifier of 10,000 variables:
/// grounding (one step per parameter) and evaluating the quantifier (one
/// variable after the other) recursed once per element.
#[test]
fn long_parameter_and_variable_lists_are_walked_without_recursion() {
    let n = 10_000;
    let params: String = (0..n).map(|i| format!(" ?x{i} - thing")).collect();
    let vars: String = (0..n).map(|i| format!(" ?y{i} - thing")).collect();
    let domain = format!(
        "(define (domain long) (:requirements :strips :typing :universal-preconditions)
  (:types thing)
  (:predicates (p ?x - thing) (q))
  (:action a :parameters ({params}) :precondition (and (p ?x0) (forall ({vars}) (p ?y9999))) :effect (q)))
"
    );
    let problem = "(define (problem long-1) (:domain long) (:objects o - thing) (:init (p o)) (:goal (q)))\n";
    let plan = format!("0: (a{})\n", " o".repeat(n));
    let (diagnostics, validation) = std::thread::scope(|scope| {
        std::thread::Builder::new()
            .stack_size(SMALL_STACK / 2)
            .spawn_scoped(scope, || {
                let mut host = AnalysisHost::new();
                let d = host.set_file_text("long/domain.pddl", domain.as_str());
                let p = host.set_file_text("long/problem.pddl", problem);
                let f = host.set_file_text("long/a.plan", plan.as_str());
                let analysis = host.analysis();
                let mut diagnostics = analysis.diagnostics(d).expect("not cancelled");
                diagnostics.extend(analysis.diagnostics(p).expect("not cancelled"));
                let validation = analysis
                    .validate_plan(f, None, p, &Options::default())
                    .expect("not cancelled")
                    .expect("a problem");
                (codes_of(&diagnostics), (validation.checked, validation.valid))
            })
            .expect("a thread")
            .join()
            .expect("no stack overflow")
    });
    assert_eq!(diagnostics, Vec::<&str>::new());
    assert_eq!(validation, (true, true));
}
