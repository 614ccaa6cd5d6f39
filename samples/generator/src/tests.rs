//! Tests of the generator: determinism, geometry of the durations, and a small
//! structural check of the generated texts (declarations against uses).

use std::collections::{HashMap, HashSet};

use super::*;

/// A minimal s-expression reader for the generated files (comments dropped).
#[derive(Debug, Clone, PartialEq)]
enum Sx {
    Atom(String),
    List(Vec<Sx>),
}

impl Sx {
    fn atom(&self) -> Option<&str> {
        match self {
            Sx::Atom(a) => Some(a),
            Sx::List(_) => None,
        }
    }
    fn list(&self) -> &[Sx] {
        match self {
            Sx::List(l) => l,
            Sx::Atom(a) => panic!("expected a list, found `{a}`"),
        }
    }
    fn head(&self) -> Option<&str> {
        match self {
            Sx::List(l) => l.first().and_then(Sx::atom),
            Sx::Atom(_) => None,
        }
    }
}

fn read(text: &str) -> Sx {
    let mut stack: Vec<Vec<Sx>> = vec![Vec::new()];
    let mut atom = String::new();
    let flush = |atom: &mut String, stack: &mut Vec<Vec<Sx>>| {
        if !atom.is_empty() {
            stack.last_mut().unwrap().push(Sx::Atom(std::mem::take(atom).to_ascii_lowercase()));
        }
    };
    let mut comment = false;
    for c in text.chars() {
        if comment {
            comment = c != '\n';
            continue;
        }
        match c {
            ';' => {
                flush(&mut atom, &mut stack);
                comment = true;
            }
            '(' => {
                flush(&mut atom, &mut stack);
                stack.push(Vec::new());
            }
            ')' => {
                flush(&mut atom, &mut stack);
                let l = stack.pop().unwrap();
                stack.last_mut().expect("unbalanced `)`").push(Sx::List(l));
            }
            c if c.is_whitespace() => flush(&mut atom, &mut stack),
            c => atom.push(c),
        }
    }
    assert_eq!(stack.len(), 1, "unbalanced `(`");
    let mut top = stack.pop().unwrap();
    assert_eq!(top.len(), 1, "expected one top-level form");
    top.pop().unwrap()
}

fn section<'a>(define: &'a Sx, head: &str) -> Vec<&'a Sx> {
    define.list().iter().filter(|s| s.head() == Some(head)).collect()
}

/// `a b - t c - u` → [(a, t), (b, t), (c, u)].
fn typed(items: &[Sx]) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut pending = Vec::new();
    let mut i = 0;
    while i < items.len() {
        let a = items[i].atom().expect("atom in typed list");
        if a == "-" {
            let t = items[i + 1].atom().expect("type name");
            out.extend(pending.drain(..).map(|n: String| (n, t.to_string())));
            i += 2;
        } else {
            pending.push(a.to_string());
            i += 1;
        }
    }
    out.extend(pending.into_iter().map(|n| (n, "object".to_string())));
    out
}

/// Parses `(= (distance a b) d)` and `(= (speed r) s)` facts from a problem.
fn fluents(problem: &Sx) -> (HashMap<(String, String), f64>, HashMap<String, f64>) {
    let init = section(problem, ":init")[0];
    let mut dist = HashMap::new();
    let mut speed = HashMap::new();
    for f in &init.list()[1..] {
        if f.head() == Some("=") {
            let l = f.list();
            let lhs = l[1].list();
            let v: f64 = l[2].atom().unwrap().parse().unwrap();
            match lhs[0].atom().unwrap() {
                "distance" => {
                    dist.insert((lhs[1].atom().unwrap().to_string(), lhs[2].atom().unwrap().to_string()), v);
                }
                "speed" => {
                    speed.insert(lhs[1].atom().unwrap().to_string(), v);
                }
                other => panic!("unexpected fluent {other}"),
            }
        }
    }
    (dist, speed)
}

#[test]
fn same_seed_gives_identical_bytes() {
    assert_eq!(surveillance(42), surveillance(42));
    assert_eq!(surveillance(7), surveillance(7));
    assert_ne!(surveillance(42).1, surveillance(43).1);
    assert_eq!(big(0.3, 5), big(0.3, 5));
}

#[test]
fn default_seed_matches_the_committed_samples() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../surveillance");
    let (Ok(domain), Ok(problem)) =
        (std::fs::read_to_string(dir.join("domain.pddl")), std::fs::read_to_string(dir.join("problem.pddl")))
    else {
        eprintln!("samples/surveillance not found: skipping the comparison");
        return;
    };
    let (d, p) = surveillance(DEFAULT_SEED);
    assert!(d == domain && p == problem, "samples/surveillance is stale: regenerate it (see its README)");
    let (robot, at) = crate::LOST_ROBOT;
    let lost = std::fs::read_to_string(dir.join(format!("problem-lost-{robot}.pddl")))
        .expect("the lost-robot problem");
    assert!(
        lost == crate::surveillance_lost(DEFAULT_SEED, robot, at).unwrap(),
        "samples/surveillance/problem-lost-{robot}.pddl is stale: regenerate it (see its README)"
    );
}

/// The lost-robot problem is the mission's problem, with timed initial
/// literals that end, at the time, every visible and visible-com fact of
/// the robot, and of no other; an unknown robot is an error.
#[test]
fn the_lost_robot_problem_ends_its_sensing_and_communication() {
    let (_, problem) = surveillance(DEFAULT_SEED);
    let lost = crate::surveillance_lost(DEFAULT_SEED, "mona2", 3000).unwrap();
    let init = |t: &str| -> Vec<String> {
        let a = t.find("(:init").unwrap();
        let b = t.find("(:goal").unwrap();
        t[a..b].lines().map(|l| l.trim().to_string()).filter(|l| l.starts_with('(')).collect()
    };
    let (before, after) = (init(&problem), init(&lost));
    let added: Vec<&String> = after.iter().filter(|l| !before.contains(l)).collect();
    let of_mona2: Vec<&String> = before
        .iter()
        .filter(|l| {
            let w: Vec<&str> = l.trim_matches(|c| c == '(' || c == ')').split_whitespace().collect();
            (w[0] == "visible" && w[1] == "mona2")
                || (w[0] == "visible-com" && (w[1] == "mona2" || w[2] == "mona2"))
        })
        .collect();
    assert!(!of_mona2.is_empty());
    assert_eq!(added.len(), of_mona2.len());
    for f in of_mona2 {
        assert!(added.contains(&&format!("(at 3000.0 (not {f}))")), "{f}");
    }
    assert_eq!(before.len() + added.len(), after.len(), "nothing else changes");
    assert_eq!(problem[problem.find("(:goal").unwrap()..], lost[lost.find("(:goal").unwrap()..]);
    assert!(crate::surveillance_lost(DEFAULT_SEED, "robby", 3000).unwrap_err().contains("mona2"));
}

/// Durations are distance / speed: the direct move between two adjacent
/// waypoints is never slower than a detour through other waypoints.
fn check_triangle_inequality(problem_text: &str) {
    let problem = read(problem_text);
    let (dist, speed) = fluents(&problem);
    assert!(!dist.is_empty() && !speed.is_empty());
    let mut adj: HashMap<&str, Vec<(&str, f64)>> = HashMap::new();
    for ((a, b), &d) in &dist {
        assert!(d > 0.0, "null distance {a} {b}");
        assert_eq!(dist.get(&(b.clone(), a.clone())), Some(&d), "asymmetric distance {a} {b}");
        adj.entry(a).or_default().push((b, d));
    }
    // Triangles, for every robot speed.
    for (&a, nbrs) in &adj {
        for &(b, ab) in nbrs {
            for &(c, bc) in &adj[b] {
                if c == a {
                    continue;
                }
                if let Some(&ac) = dist.get(&(a.to_string(), c.to_string())) {
                    for &s in speed.values() {
                        assert!(ac / s <= ab / s + bc / s + 1e-9, "triangle {a} {b} {c}: {ac} > {ab} + {bc}");
                    }
                }
            }
        }
    }
    // Paths: no detour shorter than a direct edge (Dijkstra bounded by the edge).
    for ((a, b), &d) in &dist {
        let mut best: HashMap<&str, f64> = HashMap::from([(a.as_str(), 0.0)]);
        let mut frontier = vec![a.as_str()];
        while let Some(u) = frontier.pop() {
            let du = best[u];
            for &(v, w) in &adj[u] {
                if (u == a && v == b) || (u == b && v == a) {
                    continue;
                }
                let nd = du + w;
                if nd < d - 1e-9 && best.get(v).is_none_or(|&x| nd < x) {
                    best.insert(v, nd);
                    frontier.push(v);
                }
            }
        }
        assert!(
            !best.contains_key(b.as_str()),
            "edge {a} {b} of {d} m has a shorter detour of {} m",
            best[b.as_str()]
        );
    }
}

#[test]
fn durations_satisfy_the_triangle_inequality() {
    for seed in [DEFAULT_SEED, 1, 2, 3, 1234] {
        check_triangle_inequality(&surveillance(seed).1);
    }
    check_triangle_inequality(&big(0.3, DEFAULT_SEED).1);
}

#[test]
fn distances_are_euclidean_from_the_names() {
    let problem = read(&surveillance(DEFAULT_SEED).1);
    let (dist, _) = fluents(&problem);
    let coords = |name: &str| {
        let parts: Vec<&str> = name.split('_').collect();
        (parts[1].parse::<f64>().unwrap(), parts[2].parse::<f64>().unwrap())
    };
    for ((a, b), &d) in &dist {
        let ((ax, ay), (bx, by)) = (coords(a), coords(b));
        let euclid = ((ax - bx).powi(2) + (ay - by).powi(2)).sqrt() / 10.0;
        assert!((euclid - d).abs() <= 0.005 + 1e-9, "{a} {b}: {d} vs {euclid}");
    }
}

/// Declarations against uses, as the checker will see them: predicates,
/// functions, constants, objects, arities and types.
fn check_declarations(domain_text: &str, problem_text: &str) -> Vec<String> {
    let domain = read(domain_text);
    let problem = read(problem_text);
    let mut errors = Vec::new();
    // Types.
    let mut parent: HashMap<String, String> = HashMap::new();
    for (t, p) in typed(&section(&domain, ":types")[0].list()[1..]) {
        parent.insert(t, p);
    }
    let is_sub = |t: &str, of: &str| {
        let mut t = t.to_string();
        loop {
            if t == of {
                return true;
            }
            match parent.get(&t) {
                Some(p) => t = p.clone(),
                None => return of == "object",
            }
        }
    };
    // Predicates and functions.
    let mut preds: HashMap<String, Vec<String>> = HashMap::new();
    for p in &section(&domain, ":predicates")[0].list()[1..] {
        let l = p.list();
        let args = typed(&l[1..]).into_iter().map(|(_, t)| t).collect();
        preds.insert(l[0].atom().unwrap().to_string(), args);
    }
    let mut funcs: HashMap<String, Vec<String>> = HashMap::new();
    for f in section(&domain, ":functions")[0].list()[1..].iter().filter(|f| f.atom().is_none()) {
        let l = f.list();
        funcs.insert(l[0].atom().unwrap().to_string(), typed(&l[1..]).into_iter().map(|(_, t)| t).collect());
    }
    // Constants and objects.
    let mut objects: HashMap<String, String> = HashMap::new();
    for (n, t) in typed(&section(&domain, ":constants")[0].list()[1..])
        .into_iter()
        .chain(typed(&section(&problem, ":objects")[0].list()[1..]))
    {
        if objects.insert(n.clone(), t).is_some() {
            errors.push(format!("duplicate object {n}"));
        }
    }
    // Actions and tasks with their parameter types.
    let mut operators: HashMap<String, Vec<String>> = HashMap::new();
    for item in section(&domain, ":durative-action").into_iter().chain(section(&domain, ":task")) {
        let l = item.list();
        let params = l.iter().position(|s| s.atom() == Some(":parameters")).unwrap();
        let types = typed(l[params + 1].list()).into_iter().map(|(_, t)| t).collect();
        operators.insert(l[1].atom().unwrap().to_string(), types);
    }
    let mut used_preds = HashSet::new();
    let mut used_funcs = HashSet::new();
    let mut used_objects = HashSet::new();
    /// Called on every list with its head, its arguments and the variables in scope.
    type Visit<'a> = dyn FnMut(&str, &[Sx], &HashMap<String, String>) + 'a;
    // Walks an expression; `vars` gives the types of the variables in scope.
    fn walk(e: &Sx, vars: &HashMap<String, String>, ctx: &mut Visit<'_>) {
        if let Sx::List(l) = e {
            if let Some(h) = l.first().and_then(Sx::atom) {
                ctx(h, &l[1..], vars);
            }
            for s in l {
                walk(s, vars, ctx);
            }
        }
    }
    let structural: HashSet<&str> =
        ["and", "not", "at", "over", "start", "end", "all", "=", "/", "<"].into_iter().collect();
    let mut check = |h: &str, args: &[Sx], vars: &HashMap<String, String>| {
        if h.starts_with('?') {
            // `:agent (?r1 ?r2)` and parameter lists: variables of the item.
            for v in std::iter::once(h).chain(args.iter().filter_map(Sx::atom)) {
                if v.starts_with('?') && !vars.contains_key(v) {
                    errors.push(format!("variable {v} is not a parameter"));
                }
            }
            return;
        }
        let sig = if let Some(s) = preds.get(h) {
            used_preds.insert(h.to_string());
            s
        } else if let Some(s) = funcs.get(h) {
            used_funcs.insert(h.to_string());
            s
        } else if let Some(s) = operators.get(h) {
            s
        } else {
            let task_id = h.len() > 1 && h.starts_with('t') && h[1..].bytes().all(|b| b.is_ascii_digit());
            if !structural.contains(h) && !h.starts_with(':') && !task_id {
                errors.push(format!("undeclared `{h}`"));
            }
            return;
        };
        if sig.len() != args.len() {
            errors.push(format!("`{h}` used with {} arguments instead of {}", args.len(), sig.len()));
            return;
        }
        for (a, want) in args.iter().zip(sig) {
            let Some(a) = a.atom() else { continue };
            let ty = if a.starts_with('?') {
                match vars.get(a) {
                    Some(t) => t.clone(),
                    None if a == "?w" => continue, // conflict wildcard
                    None => {
                        errors.push(format!("variable {a} of `{h}` is not a parameter"));
                        continue;
                    }
                }
            } else if let Some(t) = objects.get(a) {
                used_objects.insert(a.to_string());
                t.clone()
            } else {
                errors.push(format!("undeclared object {a} in `{h}`"));
                continue;
            };
            if !is_sub(&ty, want) {
                errors.push(format!("{a} of type {ty} given to `{h}` for a {want}"));
            }
        }
    };
    for item in ["durative-action", "task", "method"].iter().flat_map(|k| section(&domain, &format!(":{k}")))
    {
        let l = item.list();
        let params = l.iter().position(|s| s.atom() == Some(":parameters")).unwrap();
        let mut vars: HashMap<String, String> = typed(l[params + 1].list()).into_iter().collect();
        vars.insert("?duration".to_string(), "number".to_string());
        for (k, s) in l.iter().enumerate().skip(2) {
            if k == params + 1 || s.atom().is_some() {
                continue;
            }
            // Subtask lists `(t1 (move ...))`: walk the inner task.
            walk(s, &vars, &mut check);
        }
    }
    let no_vars = HashMap::new();
    for sec in [":init", ":goal"] {
        for s in section(&problem, sec) {
            walk(s, &no_vars, &mut check);
        }
    }
    for p in preds.keys() {
        if !used_preds.contains(p) {
            errors.push(format!("predicate {p} never used"));
        }
    }
    for f in funcs.keys() {
        if !used_funcs.contains(f) {
            errors.push(format!("function {f} never used"));
        }
    }
    for o in objects.keys() {
        if !used_objects.contains(o) {
            errors.push(format!("object {o} never used"));
        }
    }
    let allowed = section(&problem, ":allowed-actions")[0].list()[1..].to_vec();
    for a in &allowed {
        let a = a.atom().unwrap();
        if !operators.contains_key(a) {
            errors.push(format!("allowed action {a} is not declared"));
        }
        if a == "observe" {
            errors.push("observe must not be allowed alone".to_string());
        }
    }
    errors.sort();
    errors.dedup();
    errors
}

#[test]
fn generated_files_declare_what_they_use() {
    for (d, p) in [surveillance(DEFAULT_SEED), surveillance(99), big(0.3, 3)] {
        let errors = check_declarations(&d, &p);
        assert!(errors.is_empty(), "{errors:#?}");
    }
}

#[test]
fn surveillance_has_the_case_study_scale() {
    let world = world::generate(&Params::surveillance(), DEFAULT_SEED);
    assert_eq!(world.robots.len(), 8);
    assert!((70..=90).contains(&world.waypoints.len()), "{} waypoints", world.waypoints.len());
    assert_eq!(world.pois.len(), 25);
    assert_eq!(world.meetings.len(), 6);
    for t in world::RobotType::ALL {
        assert!(world.patrols.iter().any(|p| p.rtype == t), "no patrol for {t:?}");
    }
    for p in &world.patrols {
        assert_eq!(p.walk.first(), p.walk.last(), "{} is not closed", p.name);
        assert!(p.walk.len() >= 3);
    }
    // Every point of interest is observed by exactly one patrol.
    let mut seen = vec![0; world.pois.len()];
    for p in &world.patrols {
        for &(k, _) in &p.observations {
            seen[k] += 1;
        }
    }
    assert!(seen.iter().all(|&n| n == 1), "{seen:?}");
    // Every meeting has communication positions and a sound window.
    for (m, meeting) in world.meetings.iter().enumerate() {
        assert!(world.visible_com.iter().any(|v| v.0 == m));
        assert!(meeting.open_s + world::COMMUNICATE_S <= meeting.close_s);
    }
    // Every robot takes part in one or two meetings.
    for r in 0..world.robots.len() {
        let n = world.meetings.iter().filter(|m| m.r1 == r || m.r2 == r).count();
        assert!((1..=2).contains(&n), "robot {r} in {n} meetings");
    }
}

#[test]
fn big_reaches_about_the_requested_size() {
    let (_, problem) = big(1.0, DEFAULT_SEED);
    let mib = problem.len() as f64 / MIB;
    assert!((0.85..=1.15).contains(&mib), "{mib} MiB");
    assert!(problem.lines().filter(|l| l.contains("(adjacent ")).count() > 2000);
}

#[test]
fn the_structural_check_notices_mistakes() {
    let (d, p) = surveillance(DEFAULT_SEED);
    let bad_arity = d.replacen("(at end (at-r ?r ?to))", "(at end (at-r ?r))", 1);
    assert!(!check_declarations(&bad_arity, &p).is_empty());
    let bad_variable = d.replacen("(move ?r ", "(move ?x ", 1);
    assert!(!check_declarations(&bad_variable, &p).is_empty());
    let unused = d.replacen("(met ?r1 ?r2 - robot))", "(met ?r1 ?r2 - robot) (spare ?r - robot))", 1);
    assert!(check_declarations(&unused, &p).iter().any(|e| e.contains("spare")));
    let bad_type = p.replacen("(robot-allowed ressac1 ", "(robot-allowed ptobs_", 1);
    assert!(!check_declarations(&d, &bad_type).is_empty());
}
