//! The survivors-repair set of the HiPOP paper (section 5.2): for each of
//! the 72 Survivors problems, an initial problem and three disruptive
//! events, each a problem of its own that a plan of the initial problem is
//! repaired for.
//!
//! The initial problems are the Survivors problems (same grid, maps,
//! robots and survivors) in the repair set's domain
//! ([`super::domain::repair_domain`]): a survivor is evacuated from where it
//! was reported by an abstract action (`evacuate`), whose instances are
//! tied to that location by the problem's `(reported s l)` facts. The
//! events:
//!
//! - [`Event::StartingPos`]: one robot starts elsewhere (any location but
//!   the base); the domain and the goals are unchanged.
//! - [`Event::NewSurvivor`]: a survivor more (anywhere but the base, a
//!   hospital or another survivor), reported where it is: a new goal, and
//!   the evacuations of its location.
//! - [`Event::SurvivorPos`]: a survivor is found 1 to 3 steps (grid
//!   distance) from where it was reported, at a free location: the
//!   evacuations of the old location disappear from the problem (their
//!   `reported` fact is gone) and those of the new location appear. The
//!   goal, `(rescued s)`, names no location and stays.
//!
//! Each event is drawn from its own generator, seeded by the seed, the
//! problem's parameters and the event: the same arguments give the same
//! bytes, and the events of one problem do not depend on each other.

use super::problem::{Setting, allowed_actions, render};
use super::{Map, Params};
use crate::rng::Rng;

/// A disruptive event of section 5.2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Event {
    StartingPos,
    NewSurvivor,
    SurvivorPos,
}

impl Event {
    pub const ALL: [Event; 3] = [Event::StartingPos, Event::NewSurvivor, Event::SurvivorPos];

    /// The paper's name: `startingPos`, `newSurvivor`, `survivorPos`.
    pub fn name(self) -> &'static str {
        match self {
            Event::StartingPos => "startingPos",
            Event::NewSurvivor => "newSurvivor",
            Event::SurvivorPos => "survivorPos",
        }
    }

    fn tag(self) -> u64 {
        match self {
            Event::StartingPos => 1,
            Event::NewSurvivor => 2,
            Event::SurvivorPos => 3,
        }
    }
}

/// The state an event leaves: where the robots start and the survivors are,
/// and what changed, in words.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Scenario {
    pub starts: Vec<usize>,
    pub survivors: Vec<usize>,
    /// One line per change (empty for the initial problem).
    pub changes: Vec<String>,
}

/// The initial problem's scenario: every robot at the base.
pub fn initial(map: &Map) -> Scenario {
    Scenario {
        starts: vec![map.base; map.params.robots()],
        survivors: map.survivors.clone(),
        changes: Vec::new(),
    }
}

/// The generator of `event` for the problem of `params`.
fn rng(params: Params, seed: u64, event: Event) -> Rng {
    let mut state = seed ^ 0x5355_5256_5245_5041; // "SURVREPA"
    for v in [params.teams, params.rows, params.side, params.survivors]
        .map(|v| v as u64)
        .into_iter()
        .chain([event.tag()])
    {
        state = Rng::new(state ^ v).next_u64();
    }
    Rng::new(state)
}

/// The scenario after `event`.
pub fn scenario(map: &Map, event: Event, seed: u64) -> Scenario {
    let mut rng = rng(map.params, seed, event);
    let mut s = initial(map);
    let n = map.width * map.height;
    let name = |l: usize| map.loc_name(l);
    let free =
        |l: usize, s: &Scenario| l != map.base && !map.hospitals.contains(&l) && !s.survivors.contains(&l);
    let pick = |rng: &mut Rng, candidates: &[usize]| candidates[rng.below(candidates.len() as u64) as usize];
    match event {
        Event::StartingPos => {
            let r = rng.below(s.starts.len() as u64) as usize;
            let elsewhere: Vec<usize> = (0..n).filter(|&l| l != map.base).collect();
            let l = pick(&mut rng, &elsewhere);
            s.starts[r] = l;
            s.changes.push(format!(
                "robot r{} starts at {} instead of the base, {}",
                r + 1,
                name(l),
                name(map.base)
            ));
        }
        Event::NewSurvivor => {
            let candidates: Vec<usize> = (0..n).filter(|&l| free(l, &s)).collect();
            let l = pick(&mut rng, &candidates);
            s.survivors.push(l);
            s.changes.push(format!(
                "a new survivor, s{}, is reported at {}: a new goal, (rescued s{})",
                s.survivors.len(),
                name(l),
                s.survivors.len()
            ));
        }
        Event::SurvivorPos => {
            let k = rng.below(s.survivors.len() as u64) as usize;
            let old = s.survivors[k];
            let (ox, oy) = (old % map.width, old / map.width);
            let candidates: Vec<usize> = (0..n)
                .filter(|&l| {
                    let d = (l % map.width).abs_diff(ox) + (l / map.width).abs_diff(oy);
                    (1..=3).contains(&d) && free(l, &s)
                })
                .collect();
            let l = pick(&mut rng, &candidates);
            s.survivors[k] = l;
            s.changes.push(format!(
                "survivor s{} is at {}, not at {} where it was reported: the evacuations of {} are gone, those of {} are new",
                k + 1,
                name(l),
                name(old),
                name(old),
                name(l)
            ));
        }
    }
    s
}

/// The command that regenerates the repair set with `seed`.
pub fn command(seed: u64) -> String {
    if seed == crate::DEFAULT_SEED {
        "cargo run -p hipop-samplegen -- survivors-repair --out DIR".to_string()
    } else {
        format!("cargo run -p hipop-samplegen -- survivors-repair --seed {seed} --out DIR")
    }
}

/// The allowed actions of the repair set: the Survivors ones and `evacuate`.
pub fn allowed() -> Vec<String> {
    let mut out = allowed_actions();
    out.push("evacuate".to_string());
    out
}

/// The stem of an event's problem file: `p-t2-r2-z4-s2-startingPos`; of the
/// initial problem, the Survivors stem.
pub fn stem(params: Params, event: Option<Event>) -> String {
    match event {
        Some(e) => format!("{}-{}", params.stem(), e.name()),
        None => params.stem(),
    }
}

/// The text of the initial problem (`event` `None`) or of an event's problem.
pub fn problem(map: &Map, event: Option<Event>, seed: u64) -> String {
    let p = map.params;
    let scenario = match event {
        Some(e) => scenario(map, e, seed),
        None => initial(map),
    };
    let what = match event {
        Some(e) => format!("event {} of problem {}", e.name(), p.stem()),
        None => format!("initial problem {}", p.stem()),
    };
    let title = vec![
        format!("Survivors-repair benchmark of the HiPOP paper (section 5.2): {what}."),
        format!(
            "Generated by hipop-samplegen (survivors-repair mode), seed {seed}. Do not edit by hand; regenerate with:"
        ),
        format!("  {}", command(seed)),
    ];
    let mut notes = Vec::new();
    if let Some(e) = event {
        notes.push(format!("Event {} (the initial problem is {}.pddl):", e.name(), p.stem()));
        notes.extend(scenario.changes.iter().map(|c| format!("  {c}")));
    }
    let setting = Setting {
        title,
        name: format!("survivors-repair-{}", &stem(p, event)[2..]),
        domain: "survivors-repair",
        allowed: allowed(),
        starts: scenario.starts,
        survivors: scenario.survivors,
        reported: true,
        notes,
    };
    render(map, &setting)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DEFAULT_SEED;

    fn map(teams: usize, rows: usize, side: usize, survivors: usize) -> Map {
        Map::new(Params { teams, rows, side, survivors }, DEFAULT_SEED)
    }

    /// Each event changes what it says and nothing else.
    #[test]
    fn each_event_changes_only_its_part() {
        for params in Params::grid() {
            let m = Map::new(params, DEFAULT_SEED);
            let base = initial(&m);
            let s = scenario(&m, Event::StartingPos, DEFAULT_SEED);
            assert_eq!(s.survivors, base.survivors);
            let moved: Vec<usize> = (0..s.starts.len()).filter(|&r| s.starts[r] != m.base).collect();
            assert_eq!(moved.len(), 1, "{params:?}: one robot starts elsewhere");
            let s = scenario(&m, Event::NewSurvivor, DEFAULT_SEED);
            assert_eq!(s.starts, base.starts);
            assert_eq!(s.survivors[..base.survivors.len()], base.survivors[..]);
            let new = *s.survivors.last().unwrap();
            assert_eq!(s.survivors.len(), base.survivors.len() + 1);
            assert!(new != m.base && !m.hospitals.contains(&new) && !base.survivors.contains(&new));
            let s = scenario(&m, Event::SurvivorPos, DEFAULT_SEED);
            assert_eq!(s.starts, base.starts);
            let changed: Vec<usize> =
                (0..s.survivors.len()).filter(|&k| s.survivors[k] != base.survivors[k]).collect();
            assert_eq!(changed.len(), 1, "{params:?}: one survivor moved");
            let (old, new) = (base.survivors[changed[0]], s.survivors[changed[0]]);
            let d = (old % m.width).abs_diff(new % m.width) + (old / m.width).abs_diff(new / m.width);
            assert!((1..=3).contains(&d), "{params:?}: moved {d} steps");
            assert!(new != m.base && !m.hospitals.contains(&new) && !base.survivors.contains(&new));
        }
    }

    /// The events are drawn per problem and per event: not all problems get
    /// the same robot, and a seed changes them.
    #[test]
    fn events_depend_on_the_problem_and_the_seed() {
        let robots: std::collections::BTreeSet<Vec<usize>> = Params::grid()
            .into_iter()
            .map(|p| scenario(&Map::new(p, DEFAULT_SEED), Event::StartingPos, DEFAULT_SEED).starts)
            .collect();
        assert!(robots.len() > 10, "{robots:?}");
        let m = map(2, 3, 3, 4);
        let other = Map::new(m.params, 7);
        assert_ne!(scenario(&m, Event::NewSurvivor, DEFAULT_SEED), scenario(&other, Event::NewSurvivor, 7));
        assert_eq!(
            scenario(&m, Event::NewSurvivor, DEFAULT_SEED),
            scenario(&m, Event::NewSurvivor, DEFAULT_SEED)
        );
    }

    /// The texts say what changed: the problem's facts and goals, and its
    /// header.
    #[test]
    fn event_texts_state_the_change() {
        let m = map(2, 2, 2, 2);
        let initial = problem(&m, None, DEFAULT_SEED);
        assert!(initial.contains("(define (problem survivors-repair-t2-r2-z4-s2)"));
        assert!(initial.contains("(:domain survivors-repair)"));
        assert!(initial.contains(" evacuate)"));
        assert_eq!(initial.matches("(reported ").count(), 2);
        let new = problem(&m, Some(Event::NewSurvivor), DEFAULT_SEED);
        assert!(new.contains("(define (problem survivors-repair-t2-r2-z4-s2-newSurvivor)"));
        assert!(new.contains("s1 s2 s3 - survivor"));
        assert!(new.contains("(rescued s3)"));
        assert!(new.contains("; Event newSurvivor"));
        let pos = problem(&m, Some(Event::SurvivorPos), DEFAULT_SEED);
        let goals = |t: &str| t[t.find("(:goal").unwrap()..].to_string();
        assert_eq!(goals(&pos), goals(&initial), "survivorPos keeps the goals");
        assert_ne!(pos, initial);
        let start = problem(&m, Some(Event::StartingPos), DEFAULT_SEED);
        assert_eq!(start.matches("(robot-at r").count(), 4);
        let at_base =
            |t: &str| t.lines().filter(|l| l.trim().starts_with("(robot-at") && l.ends_with("l0_0)")).count();
        assert_eq!(at_base(&initial), 4);
        assert_eq!(at_base(&start), 3);
    }
}
