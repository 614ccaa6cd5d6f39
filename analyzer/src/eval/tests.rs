use super::*;
use crate::AnalysisHost;
use crate::db::{Db, Unit, file_units, lower_item};
use crate::model::{Action, Gd, ItemData};
use crate::semantics::check::domain_for;
use crate::semantics::symbols::{domain_symbols, problem_symbols};
use crate::verify::state::{Atoms, initial_state};

const DOMAIN: &str = "(define (domain d) (:requirements :adl :fluents :durative-actions)
  (:types block - object small - block)
  (:constants table - object)
  (:predicates (on ?x ?y) (clear ?x) (red ?x))
  (:functions (weight ?x) (total))
  (:action paint :parameters (?x - object)
    :effect (and (forall (?y - block) (when (on ?y ?x) (red ?y)))
                 (when (red ?x) (not (clear ?x)))))
  (:action pour :parameters (?x - block)
    :effect (and (increase (weight ?x) 2) (decrease (total) (* 2 (weight ?x)))
                 (scale-up (weight ?x) 3) (assign (total) (+ (total) 1))))
  (:action spill :parameters (?x - block) :effect (assign (total) (/ (total) (- (weight ?x) (weight ?x)))))
  (:durative-action hold :parameters (?x - block) :duration (= ?duration 2)
    :condition (at start (clear ?x))
    :effect (and (at start (not (clear ?x))) (at end (clear ?x))
                 (at end (increase (total) (* ?duration 2)))
                 (when (and (at start (red ?x)) (over all (clear table))) (at end (on ?x table))))))";

const PROBLEM: &str = "(define (problem p) (:domain d)
  (:objects b1 b2 - block s1 - small)
  (:init (clear b1) (clear b2) (clear s1) (red s1) (on b1 table) (clear table)
         (= (weight b1) 5) (= (total) 10))
  (:goal (and)))";

/// Runs `f` with the world and initial state of `problem` (its `:goal`
/// replaced by `goal`), the goal and the domain's actions by name.
fn with(goal: &str, f: impl FnOnce(&World<'_, '_>, &State, &Gd, &[&Action])) {
    let mut host = AnalysisHost::new();
    host.set_file_text("m/domain.pddl", DOMAIN);
    let p =
        host.set_file_text("m/problem.pddl", PROBLEM.replace("(:goal (and))", &format!("(:goal {goal})")));
    let db: &dyn Db = host.db();
    let problem: Unit<'_> = file_units(db, p)[0];
    let domain = domain_for(db, problem).expect("the domain");
    let objects = Objects::new(domain_symbols(db, domain), problem_symbols(db, problem));
    let (mut preds, mut funcs, mut atoms) = (Interner::default(), Interner::default(), Atoms::default());
    for n in ["on", "clear", "red"] {
        preds.intern(n);
    }
    for n in ["weight", "total"] {
        funcs.intern(n);
    }
    let init = initial_state(db, problem, &objects, &mut preds, &mut funcs, &mut atoms);
    let mut state = State::new(atoms, Atoms::default());
    for &(a, _) in &init.facts {
        state.set(a, true);
    }
    for (key, (v, _)) in init.fluents.iter() {
        let f = state.fluent(key);
        state.set_value(f, Some(*v));
    }
    let world = World { objects: &objects, preds: &preds, funcs: &funcs };
    let goal = problem
        .items(db)
        .iter()
        .find_map(|&i| match &lower_item(db, i).data {
            ItemData::Goal(g) => Some(g),
            _ => None,
        })
        .expect("a goal");
    let actions: Vec<&Action> = domain
        .items(db)
        .iter()
        .filter_map(|&i| match &lower_item(db, i).data {
            ItemData::Action(a) => Some(&**a),
            _ => None,
        })
        .collect();
    f(&world, &state, goal, &actions);
}

fn holds(goal: &str) -> bool {
    let mut out = false;
    with(goal, |world, state, g, _| {
        let eval = Eval { world, state, duration: None, total_time: None };
        out = eval.holds(g, &mut Binding::default()).expect("evaluates");
    });
    out
}

fn why(goal: &str) -> Vec<String> {
    let mut out = Vec::new();
    with(goal, |world, state, g, _| {
        let eval = Eval { world, state, duration: None, total_time: None };
        out = eval
            .why_false(g, &mut Binding::default(), false)
            .expect("evaluates")
            .into_iter()
            .map(|w| w.text)
            .collect();
    });
    out
}

#[test]
fn quantifiers_range_over_subtypes_and_constants() {
    // `small` is a `block`: s1 is among the blocks.
    assert!(holds("(forall (?x - block) (clear ?x))"));
    assert!(!holds("(forall (?x - block) (red ?x))"));
    assert!(holds("(exists (?x - block) (red ?x))"));
    assert!(!holds("(exists (?x - small) (on ?x table))"));
    // `object` includes the domain's constant `table`.
    assert!(holds("(forall (?x) (clear ?x))"));
    assert!(!holds("(forall (?x - object) (or (= ?x table) (red ?x)))"));
    assert!(holds("(forall (?x - block) (imply (on ?x table) (clear ?x)))"));
    assert!(holds("(exists (?x ?y) (and (on ?x ?y) (not (= ?x ?y))))"));
    assert!(holds("(not (exists (?x - block) (on table ?x)))"));
    assert!(holds("(sortof s1 - block)"));
}

#[test]
fn why_names_the_false_literals_and_instances() {
    assert_eq!(
        why("(and (clear b1) (red b1) (not (clear b2)))"),
        ["`(red b1)` is false", "`(clear b2)` is true"]
    );
    assert_eq!(why("(forall (?x - block) (red ?x))"), ["`(red b1)` is false (for ?x = b1)"]);
    assert_eq!(why("(exists (?x - block) (on ?x b2))"), ["`(exists (?x - block) (on ?x b2))` is false"]);
    assert_eq!(why("(or (red b1) (red b2))"), ["`(red b1)` is false", "`(red b2)` is false"]);
    assert_eq!(why("(imply (red s1) (on s1 table))"), ["`(on s1 table)` is false"]);
    assert_eq!(why("(> (weight b1) (total))"), ["`(> (weight b1) (total))` is false (5.0 > 10.0 fails)"]);
    assert!(why("(clear b1)").is_empty());
}

#[test]
fn a_fluent_without_value_is_an_error_not_false() {
    with("(< (weight b2) 3)", |world, state, g, _| {
        let eval = Eval { world, state, duration: None, total_time: None };
        let err = eval.holds(g, &mut Binding::default()).unwrap_err();
        assert_eq!(err.kind, ErrorKind::Undefined);
        assert_eq!(err.message, "`(weight b2)` has no value");
        assert_eq!(world.show_fluent(&err.fluent.expect("the fluent")), "(weight b2)");
    });
}

fn find<'m>(actions: &[&'m Action], name: &str) -> &'m Action {
    actions.iter().find(|a| a.name.key() == name).expect("the action")
}

fn bind<'m>(a: &'m Action, world: &World<'_, '_>, args: &[&str]) -> Binding<'m> {
    let mut b = Binding::default();
    for (p, o) in a.params.iter().zip(args) {
        b.push(p.name.key(), world.objects.id(o).expect("an object"));
    }
    b
}

fn shown(world: &World<'_, '_>, keys: &[(Key, TextRange)]) -> Vec<String> {
    keys.iter().map(|(k, _)| world.show_atom(k)).collect()
}

#[test]
fn conditional_effects_read_the_state_before() {
    with("(and)", |world, state, _, actions| {
        let eval = Eval { world, state, duration: None, total_time: None };
        let paint = find(actions, "paint");
        let mut out = Changes::default();
        eval.effects(
            &paint.effect.clone().unwrap(),
            &mut bind(paint, world, &["table"]),
            Phase::Instant,
            &mut Vec::new(),
            &mut out,
        )
        .unwrap();
        // b1 is on the table: it is painted; the table is not red: still clear.
        assert_eq!(shown(world, &out.adds), ["(red b1)"]);
        assert!(out.dels.is_empty());
        // The conditions that fired are read: (on b1 table); those that did not are not.
        let reads: Vec<String> = out.reads.atoms.iter().map(|k| world.show_atom(k)).collect();
        assert_eq!(reads, ["(on b1 table)"]);
        let mut out = Changes::default();
        eval.effects(
            paint.effect.as_ref().unwrap(),
            &mut bind(paint, world, &["s1"]),
            Phase::Instant,
            &mut Vec::new(),
            &mut out,
        )
        .unwrap();
        assert!(out.adds.is_empty());
        assert_eq!(shown(world, &out.dels), ["(clear s1)"]);
    });
}

#[test]
fn numeric_effects_evaluate_right_hand_sides_before() {
    with("(and)", |world, state, _, actions| {
        let eval = Eval { world, state, duration: None, total_time: None };
        let pour = find(actions, "pour");
        let mut out = Changes::default();
        eval.effects(
            pour.effect.as_ref().unwrap(),
            &mut bind(pour, world, &["b1"]),
            Phase::Instant,
            &mut Vec::new(),
            &mut out,
        )
        .unwrap();
        let got: Vec<(String, &str, f64)> =
            out.updates.iter().map(|u| (world.show_fluent(&u.fluent), u.op.name(), u.value)).collect();
        assert_eq!(
            got,
            [
                ("(weight b1)".to_string(), "increase", 2.0),
                ("(total)".to_string(), "decrease", 10.0),
                ("(weight b1)".to_string(), "scale-up", 3.0),
                ("(total)".to_string(), "assign", 11.0),
            ]
        );
        let fluents: Vec<String> = out.reads.fluents.iter().map(|k| world.show_fluent(k)).collect();
        assert_eq!(fluents, ["(weight b1)", "(total)"]);
        // Applied in order, as a happening applies them.
        let mut v = Some(5.0);
        for u in out.updates.iter().filter(|u| world.show_fluent(&u.fluent) == "(weight b1)") {
            v = u.op.apply(v, u.value);
        }
        assert_eq!(v, Some(21.0));
        assert_eq!(NumOp::Increase.apply(None, 1.0), None);
        assert_eq!(NumOp::Assign.apply(None, 1.0), Some(1.0));
        assert_eq!(NumOp::ScaleDown.apply(Some(1.0), 0.0), None);

        let spill = find(actions, "spill");
        let err = eval
            .effects(
                spill.effect.as_ref().unwrap(),
                &mut bind(spill, world, &["b1"]),
                Phase::Instant,
                &mut Vec::new(),
                &mut Changes::default(),
            )
            .unwrap_err();
        assert_eq!(err.kind, ErrorKind::Arithmetic);
        assert_eq!(err.message, "division by zero in `(/ (total) (- (weight b1) (weight b1)))`");
    });
}

#[test]
fn durative_effects_by_phase_with_duration_and_spanning_conditions() {
    with("(and)", |world, state, _, actions| {
        let hold = find(actions, "hold");
        let effect = hold.effect.as_ref().unwrap();
        let eval = Eval { world, state, duration: Some(2.0), total_time: None };
        let mut spanning = Vec::new();
        let mut start = Changes::default();
        eval.effects(effect, &mut bind(hold, world, &["s1"]), Phase::Start, &mut spanning, &mut start)
            .unwrap();
        assert_eq!(shown(world, &start.dels), ["(clear s1)"]);
        assert!(start.adds.is_empty() && start.updates.is_empty());
        // (red s1) held at the start: the conditional end effect is alive.
        assert_eq!(spanning.len(), 1);
        assert!(spanning[0].alive);
        let mut end = Changes::default();
        eval.effects(effect, &mut bind(hold, world, &["s1"]), Phase::End, &mut spanning, &mut end).unwrap();
        assert_eq!(shown(world, &end.adds), ["(clear s1)", "(on s1 table)"]);
        assert_eq!(end.updates[0].value, 4.0, "`?duration` in an effect");
        // Once the `over all` part fails, the end effect does not happen.
        spanning[0].alive = false;
        let mut end = Changes::default();
        eval.effects(effect, &mut bind(hold, world, &["s1"]), Phase::End, &mut spanning, &mut end).unwrap();
        assert_eq!(shown(world, &end.adds), ["(clear s1)"]);
        // b1 is not red: no spanning effect is alive for it.
        let mut spanning = Vec::new();
        eval.effects(
            effect,
            &mut bind(hold, world, &["b1"]),
            Phase::Start,
            &mut spanning,
            &mut Changes::default(),
        )
        .unwrap();
        assert!(!spanning[0].alive);
        // The conditions split by time.
        let parts = split_timed(hold.precondition.as_ref().unwrap());
        assert_eq!((parts.start.len(), parts.over_all.len(), parts.end.len()), (1, 0, 0));
    });
}

#[test]
fn numbers_in_messages() {
    assert_eq!(fmt_num(130.0), "130.0");
    assert_eq!(fmt_num(0.1 + 0.2), "0.3");
    assert_eq!(fmt_num(16.1), "16.1");
    assert_eq!(fmt_num(-2.5), "-2.5");
    assert_eq!(fmt_num(2.61 + 1.5), "4.11");
    assert_eq!(fmt_num(1e300), format!("{}", 1e300), "no overflow to `inf`");
    assert_eq!(fmt_exact(7.999999999995), "7.999999999995");
    assert_eq!(fmt_exact(8.0), "8.0");
    // A failing comparison never shows two different numbers alike.
    let s = |(a, b, exact): (String, String, bool)| (a, b, exact);
    assert_eq!(s(fmt_operands(7.999999999995, 8.0)), ("7.999999999995".into(), "8.0".into(), true));
    assert_eq!(s(fmt_operands(0.1 + 0.2, 0.3)), ("0.30000000000000004".into(), "0.3".into(), true));
    assert_eq!(s(fmt_operands(12.0000000001, 30.0)), ("12.0".into(), "30.0".into(), false));
    assert_eq!(s(fmt_operands(8.0, 8.0)), ("8.0".into(), "8.0".into(), false));
}

#[test]
fn a_comparison_failing_by_a_float_error_shows_the_digits_that_fail() {
    with("(>= (total) 10.000000000001)", |world, state, goal, _| {
        let eval = Eval { world, state, duration: None, total_time: None };
        let why = eval.why_false(goal, &mut Binding::default(), false).unwrap();
        assert_eq!(why.len(), 1);
        assert!(why[0].text.ends_with("(10.0 >= 10.000000000001 fails)"), "{}", why[0].text);
        assert!(why[0].exact);
    });
}
