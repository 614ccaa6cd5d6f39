//! `cargo bench -p hipop --bench check_cli`: `hipop check` end to end, as a
//! user runs it (the release binary in a child process: reading the files,
//! parsing, checking, the model-verification lints, printing), on generated
//! inputs of the shape of issue 19's: an airport domain and problem of about
//! 2.2 MB in the shape of the IPC 2004 Airport domains, a folder of 100 such
//! files (50 pairs growing up to that size, like the IPC set), and a 3.4 MB
//! Satellite problem with the slew time of every pair of directions. Reports
//! the wall time (median of the runs), the throughput, the peak resident set
//! of the child (`wait4`'s `ru_maxrss`) and its ratio to the input's size.
//! Results are recorded in docs/benchmarks.md.
//!
//! `HIPOP_CHECK_BIN=path` measures another `hipop` binary on the same inputs
//! (an older build, for a before/after comparison); `HIPOP_CHECK_RUNS=n` sets
//! the number of runs per input (default 5).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const MIB: f64 = 1_048_576.0;

/// Wall time and peak resident set (bytes) of one `hipop check` of `path`.
// The child is waited for with `wait4`, which also gives its resource usage.
#[allow(clippy::zombie_processes)]
fn run(bin: &Path, path: &Path) -> (Duration, u64) {
    let start = Instant::now();
    let child = Command::new(bin)
        .args(["check", "--format", "json"])
        .arg(path)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("hipop starts");
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: a zeroed rusage is a valid value for wait4 to fill.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `pid` is our child, not yet waited for; the pointers are to live locals.
    let waited = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    let elapsed = start.elapsed();
    assert_eq!(waited, pid, "wait4 failed");
    assert!(libc::WIFEXITED(status), "hipop check did not exit normally");
    // Linux reports ru_maxrss in KiB.
    (elapsed, usage.ru_maxrss as u64 * 1024)
}

fn size_of(path: &Path) -> u64 {
    if path.is_dir() {
        std::fs::read_dir(path).unwrap().map(|e| size_of(&e.unwrap().path())).sum()
    } else {
        std::fs::metadata(path).unwrap().len()
    }
}

fn write(dir: &Path, files: &[(String, String)]) {
    std::fs::create_dir_all(dir).unwrap();
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
}

fn main() {
    // `cargo bench` passes `--bench`; the harness takes no options.
    let bin = std::env::var_os("HIPOP_CHECK_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_hipop")));
    let runs: usize = std::env::var("HIPOP_CHECK_RUNS").ok().and_then(|r| r.parse().ok()).unwrap_or(5).max(1);
    let root = std::env::temp_dir().join(format!("hipop-check-bench-{}", std::process::id()));
    let seed = hipop_samplegen::DEFAULT_SEED;
    let pair =
        |(d, p): (String, String)| vec![("domain.pddl".to_string(), d), ("problem.pddl".to_string(), p)];
    // 2.2 MB, 2.2 MB for the largest pair of the folder, and 3.4 MB (decimal).
    let inputs = [
        ("airport domain + problem", "airport", pair(hipop_samplegen::airport::airport(2.2e6 / MIB, seed))),
        (
            "airport folder: 50 domains + 50 problems, up to 2.2 MB a pair",
            "airport-set",
            hipop_samplegen::airport::airport_set(50, 2.2e6 / MIB, seed),
        ),
        (
            "Satellite (time) problem of 3.4 MB + domain",
            "satellite",
            pair(hipop_samplegen::satgen::satellite_time(3.4e6 / MIB, seed)),
        ),
    ];
    println!("`{}`, {runs} runs per input\n", bin.display());
    println!("| input | size | wall time, median | throughput | peak RSS, median | RSS / input |");
    println!("|---|---|---|---|---|---|");
    for (title, dir, files) in inputs {
        let dir = root.join(dir);
        write(&dir, &files);
        drop(files);
        let bytes = size_of(&dir);
        let (mut times, mut peaks): (Vec<Duration>, Vec<u64>) = (0..runs).map(|_| run(&bin, &dir)).unzip();
        times.sort();
        peaks.sort();
        let (time, peak) = (times[runs / 2], peaks[runs / 2]);
        println!(
            "| {title} | {:.2} MB | {:.3} s | {:.1} MB/s | {:.0} MB | {:.1} |",
            bytes as f64 / 1e6,
            time.as_secs_f64(),
            bytes as f64 / 1e6 / time.as_secs_f64(),
            peak as f64 / 1e6,
            peak as f64 / bytes as f64
        );
    }
    let _ = std::fs::remove_dir_all(&root);
}
