//! `hipop plan`: exit statuses.

use super::*;

/// `hipop plan`: 0 with a plan that `hipop validate` accepts, 1 when no plan
/// exists, 3 when a limit stops the search, 2 for a usage error.
#[test]
fn plan_exit_statuses() {
    let rover = ["samples/rover-mission/domain.hddl", "samples/rover-mission/problem.hddl"];
    let dir = TempDir::new("plan-exit");
    let out = format!("{}/rover.plan", dir.path());
    let o = hipop(&["plan", rover[0], rover[1], "-o", &out, "--quiet"]);
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
