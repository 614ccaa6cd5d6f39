//! Deterministic generator of hipop sample missions: the surveillance mission
//! of the HiPOP case study, and scaled-up variants for throughput benchmarks.
//! The same arguments always give the same bytes.

mod emit;
mod geo;
mod rng;
mod world;

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

fn render(world: &World, prov: &Provenance) -> (String, String) {
    (emit::domain(world, prov), emit::problem(world, prov))
}

#[cfg(test)]
mod tests;
