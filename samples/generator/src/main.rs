//! `hipop-samplegen`: writes the surveillance mission of the HiPOP case study
//! (and scaled-up variants for throughput benchmarks) as an HTN-PDDL domain
//! and problem. Deterministic: the same arguments give the same bytes.

use std::path::PathBuf;
use std::process::ExitCode;

use hipop_samplegen::{DEFAULT_SEED, big, surveillance};

const HELP: &str = "\
hipop-samplegen: deterministic generator of hipop sample missions.

USAGE:
    hipop-samplegen surveillance [--seed N] [--out DIR]
    hipop-samplegen big --size-mb N [--seed N] [--out DIR]
    hipop-samplegen --help

COMMANDS:
    surveillance    The multi-robot surveillance mission of the HiPOP paper's case study
                    (sections 1.2 and 4.5): 8 robots of 3 types (2 aerial ressac, 3 small
                    road-bound effibot, 3 large mona that also cross grass), about 80
                    waypoints on three layers with Euclidean distances, 25 points of
                    interest, 9 patrols (abstract actions with :agent, :duration and
                    :conflicts, two methods each), 6 mandated meetings opened by timed
                    initial literals, and an :allowed-actions set without observe.
    big             The same domain on a larger zone, for throughput benchmarks: the
                    problem is about N MiB (thousands of waypoints, adjacency and
                    distance facts); the domain grows with the number of patrols.

OPTIONS:
    --seed N        Seed of the pseudo-random generator (default 42). The same seed
                    always gives the same bytes.
    --out DIR       Directory receiving domain.pddl and problem.pddl (default: the
                    current directory); created if missing.
    --size-mb N     Target size of the big problem in MiB (a decimal number, > 0).
    -h, --help      Print this help.

EXAMPLE:
    cargo run -p hipop-samplegen -- surveillance --out samples/surveillance
";

#[derive(Debug, Clone, PartialEq)]
enum Command {
    Help,
    Surveillance { seed: u64, out: PathBuf },
    Big { size_mb: f64, seed: u64, out: PathBuf },
}

fn parse_args(args: &[String]) -> Result<Command, String> {
    let Some(cmd) = args.first() else {
        return Err("missing command".to_string());
    };
    if matches!(cmd.as_str(), "-h" | "--help" | "help") {
        return Ok(Command::Help);
    }
    let mut seed = DEFAULT_SEED;
    let mut out = PathBuf::from(".");
    let mut size_mb = None;
    let mut rest = args[1..].iter();
    while let Some(flag) = rest.next() {
        let mut value = |name: &str| rest.next().cloned().ok_or_else(|| format!("{name} needs a value"));
        match flag.as_str() {
            "-h" | "--help" => return Ok(Command::Help),
            "--seed" => {
                let v = value("--seed")?;
                seed = v.parse().map_err(|_| format!("invalid seed `{v}` (expected an unsigned integer)"))?;
            }
            "--out" => out = PathBuf::from(value("--out")?),
            "--size-mb" if cmd == "big" => {
                let v = value("--size-mb")?;
                let n: f64 =
                    v.parse().map_err(|_| format!("invalid size `{v}` (expected a number of MiB)"))?;
                if !(n > 0.0 && n <= 4096.0) {
                    return Err(format!("size `{v}` out of range (0 < N <= 4096)"));
                }
                size_mb = Some(n);
            }
            other => return Err(format!("unexpected argument `{other}`")),
        }
    }
    match cmd.as_str() {
        "surveillance" => Ok(Command::Surveillance { seed, out }),
        "big" => {
            let size_mb = size_mb.ok_or("big needs --size-mb N")?;
            Ok(Command::Big { size_mb, seed, out })
        }
        other => Err(format!("unknown command `{other}`")),
    }
}

fn write_files(out: &PathBuf, files: &(String, String)) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    for (name, text) in [("domain.pddl", &files.0), ("problem.pddl", &files.1)] {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        eprintln!("wrote {} ({} bytes)", path.display(), text.len());
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match parse_args(&args) {
        Ok(Command::Help) => {
            print!("{HELP}");
            Ok(())
        }
        Ok(Command::Surveillance { seed, out }) => write_files(&out, &surveillance(seed)),
        Ok(Command::Big { size_mb, seed, out }) => write_files(&out, &big(size_mb, seed)),
        Err(e) => Err(format!("{e}\n\nRun `hipop-samplegen --help` for usage.")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_are_parsed() {
        let args = |s: &str| s.split_whitespace().map(String::from).collect::<Vec<_>>();
        assert_eq!(parse_args(&args("--help")), Ok(Command::Help));
        assert_eq!(
            parse_args(&args("surveillance --out x")),
            Ok(Command::Surveillance { seed: DEFAULT_SEED, out: PathBuf::from("x") })
        );
        assert_eq!(
            parse_args(&args("big --size-mb 2.5 --seed 9")),
            Ok(Command::Big { size_mb: 2.5, seed: 9, out: PathBuf::from(".") })
        );
        assert!(parse_args(&args("big")).is_err());
        assert!(parse_args(&args("surveillance --size-mb 3")).is_err());
        assert!(parse_args(&args("surveillance --seed -1")).is_err());
        assert!(parse_args(&args("frobnicate")).is_err());
        assert!(parse_args(&[]).is_err());
    }
}
