//! `cargo bench -p hipop-lsp --bench latency`: the time from a one-character
//! `didChange` inside one `:init` fact of a 5 MB problem to the
//! `publishDiagnostics` for that version, through the real server over stdio
//! (debounce set to 0 to measure the work, not the pause). Recorded in
//! docs/benchmarks.md.

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::{Duration, Instant};

use common::{Client, file_uri, pos};
use serde_json::json;

fn main() {
    let dir = std::env::temp_dir().join(format!("hipop-latency-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let (domain, problem) = hipop_samplegen::big(5.0, hipop_samplegen::DEFAULT_SEED);
    std::fs::write(dir.join("domain.pddl"), &domain).expect("write domain");
    std::fs::write(dir.join("problem.pddl"), &problem).expect("write problem");
    let uri = file_uri(&dir.join("problem.pddl"));

    let mut client = Client::spawn_with_env(&[("HIPOP_LSP_DEBOUNCE_MS", "0")]);
    client.initialize(&dir, json!({"general": {"positionEncodings": ["utf-16"]}}));
    let start = Instant::now();
    client.open(&uri, &problem);
    let first = client.diagnostics(&uri, Some(1));
    assert!(first.is_empty(), "the generated problem is clean: {first:?}");
    let open = start.elapsed();

    // The middle `(= (distance A B) x)` fact: toggle one character of A, which
    // makes it an undefined object and back, so that every edit publishes.
    let facts: Vec<usize> = problem.match_indices("(= (distance ").map(|(i, _)| i).collect();
    let at = facts[facts.len() / 2] + "(= (distance ".len();
    let line = problem[..at].matches('\n').count() as u32;
    let col = (at - problem[..at].rfind('\n').map_or(0, |i| i + 1)) as u32;
    let original = &problem[at..at + 1];
    let mut times: Vec<Duration> = Vec::new();
    for i in 0..40i64 {
        let insert = if i % 2 == 0 { "Z" } else { original };
        let version = i + 2;
        let t = Instant::now();
        client.change(&uri, version, json!({"start": pos(line, col), "end": pos(line, col + 1)}), insert);
        let diags = client.diagnostics(&uri, Some(version));
        times.push(t.elapsed());
        assert_eq!(diags.len(), usize::from(i % 2 == 0), "{diags:?}");
    }
    client.shutdown();
    let _ = std::fs::remove_dir_all(&dir);
    times.sort();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!("| server, 5 MB problem ({:.2} MB) | time |", problem.len() as f64 / 1e6);
    println!("|---|---|");
    println!("| didOpen → first publishDiagnostics | {:.1} ms |", ms(open));
    println!(
        "| one-character didChange → publishDiagnostics, median of {} | {:.2} ms |",
        times.len(),
        ms(times[times.len() / 2])
    );
    println!("| same, 90th percentile | {:.2} ms |", ms(times[times.len() * 9 / 10]));
}
