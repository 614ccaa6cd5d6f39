//! `hipop-samplegen`: writes the surveillance mission of the HiPOP case study
//! (and scaled-up variants for throughput benchmarks), the Survivors benchmark
//! of the paper and the IPC 2002 Satellite problems with abstract actions, as
//! HTN-PDDL domains and problems. Deterministic: the same arguments give the
//! same bytes.

use std::path::PathBuf;
use std::process::ExitCode;

use hipop_samplegen::{
    DEFAULT_SEED, LOST_ROBOT, airport, big, satellite, surveillance, surveillance_lost, survivors,
    survivors_repair, wide_action,
};

const HELP: &str = "\
hipop-samplegen: deterministic generator of hipop sample missions.

USAGE:
    hipop-samplegen surveillance [--seed N] [--out DIR]
    hipop-samplegen surveillance-lost [--seed N] [--robot NAME] [--at S] [--out DIR]
    hipop-samplegen big --size-mb N [--seed N] [--out DIR]
    hipop-samplegen survivors [--seed N] [--witness] [--out DIR]
    hipop-samplegen survivors-repair [--seed N] [--out DIR]
    hipop-samplegen satellite-abstract --corpus DIR [--out DIR]
    hipop-samplegen airport --size-mb N [--seed N] [--out DIR]
    hipop-samplegen airport-set --pairs N --size-mb N [--seed N] [--out DIR]
    hipop-samplegen satellite-time --size-mb N [--seed N] [--out DIR]
    hipop-samplegen wide-action [--objects N] [--every-instance] [--out DIR]
    hipop-samplegen --help

COMMANDS:
    surveillance    The multi-robot surveillance mission of the HiPOP paper's case study
                    (sections 1.2 and 4.5): 8 robots of 3 types (2 aerial ressac, 3 small
                    road-bound effibot, 3 large mona that also cross grass), about 80
                    waypoints on three layers with Euclidean distances, 25 points of
                    interest, 9 patrols (abstract actions with :agent, :duration and
                    :conflicts, two methods each), 6 mandated meetings opened by timed
                    initial literals, and an :allowed-actions set without observe.
    surveillance-lost
                    The mission's problem after a robot goes out of service (section 5.5 of the
                    paper): timed initial literals end, at S seconds, its visible and visible-com
                    facts, so that it can no longer observe or communicate; writes
                    problem-lost-NAME.pddl (default: mona2 at 3000 s).
    big             The same domain on a larger zone, for throughput benchmarks: the
                    problem is about N MiB (thousands of waypoints, adjacency and
                    distance facts); the domain grows with the number of patrols.
    survivors       The Survivors benchmark of the HiPOP paper (section 4.4.1): one domain
                    and 72 problems, p-tT-rR-zZ-sS.pddl for 2 or 3 teams of 2 robots, 2 to
                    4 rows of 2 zones of Z = 4, 9 or 16 locations, S = 2 to 5 survivors and
                    2 hospitals; patrols (one per team and zone) are abstract actions.
    survivors-repair
                    The survivors-repair set of the paper (section 5.2): the 72 problems in a
                    domain where survivors are evacuated by an abstract action tied to where they
                    were reported, each with the problems after three disruptive events:
                    STEM-startingPos.pddl (a robot starts elsewhere), STEM-newSurvivor.pddl (a new
                    survivor) and STEM-survivorPos.pddl (a survivor found elsewhere).
    airport         An airport in the shape of the IPC 2004 Airport domains (temporal), for
                    the throughput benchmarks of `hipop check`: a large domain whose segments and
                    airplanes are constants and whose actions are nearly ground (a move per pair
                    of adjacent segments, direction and airplane type), and its problem; writes
                    domain.pddl and problem.pddl, about N MiB together.
    airport-set     A folder like the IPC 2004 Airport set: pNN-domain.pddl and pNN-airport.pddl
                    for NN = 01 to the number of pairs, the sizes growing linearly up to N MiB
                    for the last pair.
    satellite-time  A problem of the IPC 2002 temporal Satellite domain with durations from
                    fluents, of about N MiB (ten satellites, the slew time of every pair of
                    directions), and the domain; writes domain.pddl and problem.pddl.
    satellite-abstract
                    The IPC 2002 temporal Satellite domain of the corpus folder DIR with
                    abstract actions (calibrate_instrument, get_image), and a copy of each
                    of its problems with an (:allowed-actions ...) section added.
    wide-action     One action with four parameters and no precondition over N objects
                    (default 300: 8.1 × 10⁹ instances), and a goal that needs one of them;
                    with --every-instance, a goal that needs them all.

OPTIONS:
    --seed N        Seed of the pseudo-random generator (default 42). The same seed
                    always gives the same bytes.
    --out DIR       Directory receiving the files (default: the current directory);
                    created if missing.
    --size-mb N     Target size in MiB (a decimal number, > 0): big and satellite-time, of the
                    problem; airport, of the pair; airport-set, of the largest pair.
    --robot NAME    surveillance-lost: the robot out of service (default mona2).
    --at S          surveillance-lost: from when, in whole seconds (default 3000).
    --witness       survivors: also write, per problem, a plan that solves it, in VAL's
                    format (STEM.plan) and in hipop's timed hierarchical format
                    (STEM.hier.plan).
    --corpus DIR    satellite-abstract: the corpus folder (its domain.pddl and
                    instances/*.pddl), e.g. .../ipc2002-temporal/satellite-time-simple-automatic
    --pairs N       airport-set: the number of domain and problem pairs.
    --objects N     wide-action: the number of objects (default 300, at least 4).
    --every-instance
                    wide-action: the goal needs every instance of the action.
    -h, --help      Print this help.

EXAMPLES:
    cargo run -p hipop-samplegen -- surveillance --out samples/surveillance
    cargo run -p hipop-samplegen -- survivors --witness --out /tmp/survivors
";

#[derive(Debug, Clone, PartialEq)]
enum Command {
    Help,
    Surveillance { seed: u64, out: PathBuf },
    SurveillanceLost { seed: u64, robot: String, at: u64, out: PathBuf },
    Big { size_mb: f64, seed: u64, out: PathBuf },
    Survivors { seed: u64, witness: bool, out: PathBuf },
    SurvivorsRepair { seed: u64, out: PathBuf },
    SatelliteAbstract { corpus: PathBuf, out: PathBuf },
    Airport { size_mb: f64, seed: u64, out: PathBuf },
    AirportSet { pairs: usize, size_mb: f64, seed: u64, out: PathBuf },
    SatelliteTime { size_mb: f64, seed: u64, out: PathBuf },
    WideAction { objects: usize, every_instance: bool, out: PathBuf },
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
    let mut witness = false;
    let mut corpus = None;
    let mut pairs = None;
    let (mut objects, mut every_instance) = (300, false);
    let (mut robot, mut at) = (LOST_ROBOT.0.to_string(), LOST_ROBOT.1);
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
            "--size-mb" if matches!(cmd.as_str(), "big" | "airport" | "airport-set" | "satellite-time") => {
                let v = value("--size-mb")?;
                let n: f64 =
                    v.parse().map_err(|_| format!("invalid size `{v}` (expected a number of MiB)"))?;
                if !(n > 0.0 && n <= 4096.0) {
                    return Err(format!("size `{v}` out of range (0 < N <= 4096)"));
                }
                size_mb = Some(n);
            }
            "--pairs" if cmd == "airport-set" => {
                let v = value("--pairs")?;
                let n: usize =
                    v.parse().map_err(|_| format!("invalid count `{v}` (expected a positive integer)"))?;
                if !(1..=99).contains(&n) {
                    return Err(format!("count `{v}` out of range (1 to 99)"));
                }
                pairs = Some(n);
            }
            "--witness" if cmd == "survivors" => witness = true,
            "--robot" if cmd == "surveillance-lost" => robot = value("--robot")?,
            "--at" if cmd == "surveillance-lost" => {
                let v = value("--at")?;
                at = v.parse().map_err(|_| format!("invalid time `{v}` (expected whole seconds)"))?;
            }
            "--corpus" if cmd == "satellite-abstract" => corpus = Some(PathBuf::from(value("--corpus")?)),
            "--objects" if cmd == "wide-action" => {
                let v = value("--objects")?;
                objects = v
                    .parse()
                    .ok()
                    .filter(|n| (4..=100_000).contains(n))
                    .ok_or_else(|| format!("invalid number of objects `{v}` (4 to 100000)"))?;
            }
            "--every-instance" if cmd == "wide-action" => every_instance = true,
            other => return Err(format!("unexpected argument `{other}`")),
        }
    }
    match cmd.as_str() {
        "surveillance" => Ok(Command::Surveillance { seed, out }),
        "surveillance-lost" => Ok(Command::SurveillanceLost { seed, robot, at, out }),
        "big" => {
            let size_mb = size_mb.ok_or("big needs --size-mb N")?;
            Ok(Command::Big { size_mb, seed, out })
        }
        "airport" => {
            let size_mb = size_mb.ok_or("airport needs --size-mb N")?;
            Ok(Command::Airport { size_mb, seed, out })
        }
        "airport-set" => {
            let size_mb = size_mb.ok_or("airport-set needs --size-mb N")?;
            let pairs = pairs.ok_or("airport-set needs --pairs N")?;
            Ok(Command::AirportSet { pairs, size_mb, seed, out })
        }
        "satellite-time" => {
            let size_mb = size_mb.ok_or("satellite-time needs --size-mb N")?;
            Ok(Command::SatelliteTime { size_mb, seed, out })
        }
        "survivors" => Ok(Command::Survivors { seed, witness, out }),
        "survivors-repair" => Ok(Command::SurvivorsRepair { seed, out }),
        "satellite-abstract" => {
            let corpus = corpus.ok_or("satellite-abstract needs --corpus DIR")?;
            Ok(Command::SatelliteAbstract { corpus, out })
        }
        "wide-action" => Ok(Command::WideAction { objects, every_instance, out }),
        other => Err(format!("unknown command `{other}`")),
    }
}

fn write_files(out: &PathBuf, files: &(String, String)) -> Result<(), String> {
    let files = [("domain.pddl".to_string(), files.0.clone()), ("problem.pddl".to_string(), files.1.clone())];
    write_all(out, &files, true)
}

/// Writes `(file name, text)` pairs into `out`; lists each file, or only counts them.
fn write_all(out: &PathBuf, files: &[(String, String)], list: bool) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let mut bytes = 0;
    for (name, text) in files {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        bytes += text.len();
        if list {
            eprintln!("wrote {} ({} bytes)", path.display(), text.len());
        }
    }
    if !list {
        eprintln!("wrote {} files ({bytes} bytes) in {}", files.len(), out.display());
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
        Ok(Command::SurveillanceLost { seed, robot, at, out }) => surveillance_lost(seed, &robot, at)
            .and_then(|text| write_all(&out, &[(format!("problem-lost-{robot}.pddl"), text)], true)),
        Ok(Command::Big { size_mb, seed, out }) => write_files(&out, &big(size_mb, seed)),
        Ok(Command::Airport { size_mb, seed, out }) => write_files(&out, &airport::airport(size_mb, seed)),
        Ok(Command::AirportSet { pairs, size_mb, seed, out }) => {
            write_all(&out, &airport::airport_set(pairs, size_mb, seed), false)
        }
        Ok(Command::SatelliteTime { size_mb, seed, out }) => {
            write_files(&out, &hipop_samplegen::satgen::satellite_time(size_mb, seed))
        }
        Ok(Command::Survivors { seed, witness, out }) => write_all(&out, &survivors(seed, witness), false),
        Ok(Command::SurvivorsRepair { seed, out }) => write_all(&out, &survivors_repair(seed), false),
        Ok(Command::SatelliteAbstract { corpus, out }) => {
            satellite::satellite_abstract(&corpus).and_then(|files| write_all(&out, &files, false))
        }
        Ok(Command::WideAction { objects, every_instance, out }) => {
            write_files(&out, &wide_action(objects, every_instance))
        }
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
        assert_eq!(
            parse_args(&args("survivors --witness --out d")),
            Ok(Command::Survivors { seed: DEFAULT_SEED, witness: true, out: PathBuf::from("d") })
        );
        assert_eq!(
            parse_args(&args("satellite-abstract --corpus c --out d")),
            Ok(Command::SatelliteAbstract { corpus: PathBuf::from("c"), out: PathBuf::from("d") })
        );
        assert_eq!(
            parse_args(&args("survivors-repair --seed 3")),
            Ok(Command::SurvivorsRepair { seed: 3, out: PathBuf::from(".") })
        );
        assert_eq!(
            parse_args(&args("wide-action --objects 40 --every-instance")),
            Ok(Command::WideAction { objects: 40, every_instance: true, out: PathBuf::from(".") })
        );
        assert!(parse_args(&args("wide-action --objects 3")).is_err());
        assert_eq!(
            parse_args(&args("wide-action")),
            Ok(Command::WideAction { objects: 300, every_instance: false, out: PathBuf::from(".") })
        );
        assert!(parse_args(&args("survivors-repair --witness")).is_err());
        assert_eq!(
            parse_args(&args("surveillance-lost --robot mona1 --at 100")),
            Ok(Command::SurveillanceLost {
                seed: DEFAULT_SEED,
                robot: "mona1".into(),
                at: 100,
                out: PathBuf::from(".")
            })
        );
        assert!(parse_args(&args("surveillance-lost --at -3")).is_err());
        assert!(parse_args(&args("surveillance --robot mona1")).is_err());
        assert!(parse_args(&args("satellite-abstract --out d")).is_err());
        assert!(parse_args(&args("surveillance --witness")).is_err());
        assert!(parse_args(&args("big")).is_err());
        assert_eq!(
            parse_args(&args("airport-set --pairs 50 --size-mb 2.1")),
            Ok(Command::AirportSet { pairs: 50, size_mb: 2.1, seed: DEFAULT_SEED, out: PathBuf::from(".") })
        );
        assert!(parse_args(&args("airport-set --size-mb 2")).is_err());
        assert!(parse_args(&args("airport-set --pairs 0 --size-mb 2")).is_err());
        assert!(parse_args(&args("airport --pairs 3 --size-mb 2")).is_err());
        assert_eq!(
            parse_args(&args("satellite-time --size-mb 3.25")),
            Ok(Command::SatelliteTime { size_mb: 3.25, seed: DEFAULT_SEED, out: PathBuf::from(".") })
        );
        assert!(parse_args(&args("surveillance --size-mb 3")).is_err());
        assert!(parse_args(&args("surveillance --seed -1")).is_err());
        assert!(parse_args(&args("frobnicate")).is_err());
        assert!(parse_args(&[]).is_err());
    }
}
