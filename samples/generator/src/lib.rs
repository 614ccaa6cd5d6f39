//! Deterministic generator of hipop sample missions: the surveillance mission
//! of the HiPOP case study, scaled-up variants for throughput benchmarks, the
//! Survivors benchmark of the paper (with witness plans), the IPC 2002
//! Satellite problems with abstract actions, the wide-action problem
//! (grounding by relevance), and large inputs for the throughput benchmarks
//! of `hipop check` (airports in the shape of the IPC 2004 Airport domains,
//! large Satellite problems). The same arguments always give the same bytes.

pub mod airport;
mod emit;
mod geo;
mod rng;
pub mod satellite;
pub mod satgen;
pub mod survivors;
mod wide;
mod world;

pub use wide::wide_action;

use emit::Provenance;
use world::{Params, World};

/// The seed of the committed samples.
pub const DEFAULT_SEED: u64 = 42;
const MIB: f64 = 1_048_576.0;

/// The domain and problem texts of the case study.
pub fn surveillance(seed: u64) -> (String, String) {
    let world = world::generate(&Params::surveillance(), seed);
    let prov = Provenance {
        mode: "surveillance".to_string(),
        seed,
        command: if seed == DEFAULT_SEED {
            "cargo run -p hipop-samplegen -- surveillance --out samples/surveillance".to_string()
        } else {
            format!("cargo run -p hipop-samplegen -- surveillance --seed {seed} --out DIR")
        },
    };
    render(&world, &prov)
}

/// The robot that goes out of service in the committed lost-robot problem,
/// and when: `mona2` at 3000 s, on its way from its first patrol to its
/// second, its meetings held.
pub const LOST_ROBOT: (&str, u64) = ("mona2", 3000);

/// The case study's problem after robot `robot` goes out of service at
/// `at_s` seconds (section 5.5 of the paper): it can no longer observe or
/// communicate from then on. `Err` when the mission has no such robot.
pub fn surveillance_lost(seed: u64, robot: &str, at_s: u64) -> Result<String, String> {
    let world = world::generate(&Params::surveillance(), seed);
    let prov = Provenance {
        mode: "surveillance-lost".to_string(),
        seed,
        command: if seed == DEFAULT_SEED && (robot, at_s) == LOST_ROBOT {
            "cargo run -p hipop-samplegen -- surveillance-lost --out samples/surveillance".to_string()
        } else {
            format!(
                "cargo run -p hipop-samplegen -- surveillance-lost --seed {seed} --robot {robot} --at {at_s} --out DIR"
            )
        },
    };
    emit::lost_problem(&world, &prov, robot, at_s).ok_or_else(|| {
        let names: Vec<&str> = world.robots.iter().map(|r| r.name.as_str()).collect();
        format!("no robot `{robot}` in the mission (robots: {})", names.join(", "))
    })
}

/// The domain and problem texts of a big instance whose problem is about `size_mb` MiB.
pub fn big(size_mb: f64, seed: u64) -> (String, String) {
    let prov = Provenance {
        mode: "big".to_string(),
        seed,
        command: format!(
            "cargo run --release -p hipop-samplegen -- big --size-mb {size_mb} --seed {seed} --out DIR"
        ),
    };
    let target = size_mb * MIB;
    // The problem's size grows about linearly with the zone's area: measure, then rescale.
    let mut area = (target / 105_000.0).max(1.0);
    let mut files = render(&world::generate(&Params::scaled(area), seed), &prov);
    for _ in 0..4 {
        let ratio = target / files.1.len() as f64;
        if (0.98..=1.02).contains(&ratio) || (area <= 1.0 && ratio < 1.0) {
            break;
        }
        area = (area * ratio).max(1.0);
        files = render(&world::generate(&Params::scaled(area), seed), &prov);
    }
    files
}

/// The Survivors benchmark (paper, section 4.4.1): `domain.pddl` and the 72
/// problems, as `(file name, text)` in a fixed order; with `witness`, each
/// problem is followed by its witness plans, `STEM.plan` (VAL's format) and
/// `STEM.hier.plan` (hipop's timed hierarchical format).
pub fn survivors(seed: u64, witness: bool) -> Vec<(String, String)> {
    let mut files = vec![("domain.pddl".to_string(), survivors::domain::domain())];
    for params in survivors::Params::grid() {
        files.extend(survivors_problem(params, seed, witness));
    }
    files
}

/// One problem of the Survivors benchmark, and its witness plans when asked.
pub fn survivors_problem(params: survivors::Params, seed: u64, witness: bool) -> Vec<(String, String)> {
    let map = survivors::Map::new(params, seed);
    let stem = params.stem();
    let mut files = vec![(format!("{stem}.pddl"), survivors::problem::problem(&map, seed))];
    if witness {
        let plan = survivors::witness::Witness::new(&map);
        files.push((format!("{stem}.plan"), plan.val(&stem)));
        files.push((format!("{stem}.hier.plan"), plan.hierarchical(&stem)));
    }
    files
}

/// The survivors-repair set (paper, section 5.2): the repair set's
/// `domain.pddl`, then for each of the 72 problems its initial problem
/// `STEM.pddl` and the problems after each event, `STEM-startingPos.pddl`,
/// `STEM-newSurvivor.pddl` and `STEM-survivorPos.pddl`, in a fixed order.
pub fn survivors_repair(seed: u64) -> Vec<(String, String)> {
    let mut files = vec![("domain.pddl".to_string(), survivors::domain::repair_domain())];
    for params in survivors::Params::grid() {
        files.extend(survivors_repair_problem(params, seed));
    }
    files
}

/// The initial problem of one problem of the survivors-repair set and its
/// three events' problems.
pub fn survivors_repair_problem(params: survivors::Params, seed: u64) -> Vec<(String, String)> {
    use survivors::repair::{Event, problem, stem};
    let map = survivors::Map::new(params, seed);
    std::iter::once(None)
        .chain(Event::ALL.map(Some))
        .map(|e| (format!("{}.pddl", stem(params, e)), problem(&map, e, seed)))
        .collect()
}

fn render(world: &World, prov: &Provenance) -> (String, String) {
    (emit::domain(world, prov), emit::problem(world, prov))
}

#[cfg(test)]
mod tests;
