//! `hipop plan`: exit statuses.

use super::*;

/// `hipop plan`: 0 with a plan that `hipop validate` accepts, 1 when no plan
/// exists, 3 when a limit stops the search, 2 for a usage error.
#[test]
fn plan_exit_statuses() {
    let rover = ["samples/rover-mission/domain.hddl", "samples/rover-mission/problem.hddl"];
    let dir = TempDir::new("plan-exit");
    let out = format!("{}/rover.plan", dir.path());
    let o = hipop(&["plan", rover[0], rover[1], "-o", &out, "--quiet", "--time-limit", "2"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    let v = hipop(&["validate", rover[0], rover[1], &out]);
    assert_eq!(status(&v), 0, "the plan written does not validate:\n{}{}", stdout(&v), stderr(&v));

    let no_plan = "tests/planner/no-plan.pddl";
    let o = hipop(&["plan", no_plan, no_plan, "--color", "never"]);
    assert_eq!(status(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("E0502"), "{}", stderr(&o));

    let survivors = ["samples/survivors/domain.pddl", "samples/survivors/p-t3-r4-z16-s5.pddl"];
    let o = hipop(&["plan", survivors[0], survivors[1], "--node-limit", "10", "--color", "never"]);
    assert_eq!(status(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("the node limit"), "{}", stderr(&o));

    // The memory limit is the heap the process holds: 1 MiB is gone before
    // the search starts, so it stops at its first check.
    let o = hipop(&["plan", survivors[0], survivors[1], "--memory-limit", "1", "--color", "never"]);
    assert_eq!(status(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("the memory limit"), "{}", stderr(&o));

    let o = hipop(&["plan", rover[0], rover[1], "--config", "AR-fast"]);
    assert_eq!(status(&o), 2);
    assert!(stderr(&o).contains("unknown part `fast`"), "{}", stderr(&o));
}

/// `hipop repair`: a plan repaired for a problem with one more goal keeps
/// its actions and validates (exit 0); with the abstract action the goals
/// need no longer allowed, no plan even after the full replan (exit 1);
/// an unreadable old plan is an input error (exit 2).
#[test]
fn repair_exit_statuses() {
    let dir = TempDir::new("repair");
    let domain = "samples/satellite-abstract/domain.pddl";
    let problem = "samples/satellite-abstract/instance-1.pddl";
    let old = dir.0.join("old.plan");
    let old_s = old.to_str().expect("UTF-8 temp path");
    let o = hipop(&["plan", domain, problem, "-o", old_s, "-q", "--first"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    let text = std::fs::read_to_string(workspace_root().join(problem)).expect("the problem");
    let write = |name: &str, text: String| {
        let path = dir.0.join(name);
        std::fs::write(&path, text).expect("written");
        path.to_str().expect("UTF-8 temp path").to_string()
    };
    let more = write(
        "more.pddl",
        text.replace(
            "(have_image Phenomenon6 thermograph0)",
            "(have_image Phenomenon6 thermograph0) (have_image Star0 thermograph0)",
        ),
    );
    let repaired = dir.0.join("repaired.plan");
    let repaired_s = repaired.to_str().expect("UTF-8 temp path");
    let o = hipop(&["repair", domain, &more, old_s, "-o", repaired_s]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("stage 1 (obsolete steps removed): 14 steps of the old plan kept, 4 goals, repaired"),
        "{err}"
    );
    assert!(err.contains("10 actions kept, 0 removed, 2 added"), "{err}");
    let o = hipop(&["validate", domain, &more, repaired_s]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    // Side by side with a replan from scratch.
    let o = hipop(&["repair", domain, &more, old_s, "-o", repaired_s, "-q", "--compare-replan"]);
    assert_eq!(status(&o), 0, "{}", stderr(&o));
    let err = stderr(&o);
    let row = |name: &str| {
        err.lines()
            .find(|l| l.starts_with(name))
            .map(|l| l.split_whitespace().map(String::from).collect::<Vec<_>>())
    };
    assert_eq!(row("found").map(|r| r[1..3].join(" ")), Some("stage 1".to_string()), "{err}");
    let instability = row("instability").unwrap_or_else(|| panic!("{err}"));
    assert_eq!(instability[1], "2", "{err}");
    assert!(instability[2].parse::<usize>().is_ok(), "{err}");

    let fewer = write("fewer.pddl", text.replace("calibrate_instrument get_image)", "calibrate_instrument)"));
    let o = hipop(&["repair", domain, &fewer, old_s, "--executed", "0"]);
    assert_eq!(status(&o), 1, "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("obsolete: the action is no longer allowed"), "{err}");
    assert!(err.contains("no plan, even after the full replan"), "{err}");

    let broken = write("broken.plan", "0.0: (turn_to satellite0\n".into());
    let o = hipop(&["repair", domain, problem, &broken]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("the old plan cannot be read"), "{}", stderr(&o));
}

/// The limits hold where the planner does not look at them: grounding the
/// methods of the IPC 2020 Monroe problems takes seconds to minutes and
/// about 170 MB, and `hipop plan --time-limit 0.1` (reading and checking
/// the files count, and take about that), or `--memory-limit 64`,
/// ends with exit status 3 and says so (without the watchdog it ran on, and
/// ended with another status).
#[test]
fn the_limits_hold_while_grounding() {
    let corpora = std::env::var_os("HIPOP_CORPORA")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace_root().join("../shared/corpora"));
    let dir = corpora.join("ipc2020-hddl/partial-order/Monroe-Fully-Observable");
    if !dir.is_dir() {
        eprintln!("SKIP: {} is absent (set HIPOP_CORPORA)", dir.display());
        return;
    }
    let name = "pfile01-p-0088-quell-riot-1-tlt";
    let domain = dir.join(format!("{name}-domain.hddl"));
    let problem = dir.join(format!("{name}.hddl"));
    let (d, p) = (domain.to_str().expect("UTF-8 path"), problem.to_str().expect("UTF-8 path"));
    let o = hipop(&["plan", d, p, "--time-limit", "0.1", "--color", "never"]);
    assert_eq!(status(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("the time limit (0.1 s) was reached"), "{}", stderr(&o));
    let o = hipop(&["plan", d, p, "--time-limit", "0.1", "--format", "json"]);
    assert_eq!(status(&o), 3, "{}", stderr(&o));
    let doc: Value = serde_json::from_str(&stdout(&o)).expect("JSON on standard output");
    assert_eq!((doc["status"].as_str(), doc["limit"].as_str()), (Some("limit"), Some("time")));
    let o = hipop(&["plan", d, p, "--memory-limit", "64", "--time-limit", "600", "--color", "never"]);
    assert_eq!(status(&o), 3, "{}", stderr(&o));
    assert!(stderr(&o).contains("the memory limit (64 MiB) was reached"), "{}", stderr(&o));
}

/// A problem finds the only domain beside it, named otherwise (as in the IPC
/// 2020 Barman-BDI folder), however its folder is written: `dir//p.pddl`
/// and `./dir/p.pddl` are in the same folder as `dir/d.pddl`. Before, the
/// folder read `dir/` and the problem had no domain (E0114).
#[test]
fn a_folder_is_the_same_however_its_path_is_written() {
    let dir = TempDir::new("paths");
    let domain =
        "(define (domain agent) (:predicates (done)) (:action finish :parameters () :effect (done)))\n";
    let problem = "(define (problem p) (:domain other-name) (:init) (:goal (done)))\n";
    std::fs::write(dir.0.join("d.pddl"), domain).expect("written");
    std::fs::write(dir.0.join("p.pddl"), problem).expect("written");
    let d = format!("{}/d.pddl", dir.path());
    for p in [format!("{}//p.pddl", dir.path()), format!("{}/./p.pddl", dir.path())] {
        let o = hipop(&["check", &d, &p, "--color", "never"]);
        assert!(!stdout(&o).contains("E0114") && !stderr(&o).contains("E0114"), "{p}:\n{}", stdout(&o));
        let o = hipop(&["plan", &d, &p, "--first", "-q"]);
        assert_eq!(status(&o), 0, "{p}: {}", stderr(&o));
    }
}
