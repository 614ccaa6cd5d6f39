//! `hipop check`: the output formats, `--deny`, `--allow` and allow comments,
//! `--fix`, paths and files that cannot be read.

use super::*;

#[test]
fn clean_samples_check_without_diagnostics() {
    let o = hipop(&["check", "samples/rover-mission", "samples/transport-htn", "samples/surveillance"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "stderr:\n{}", stderr(&o));
    assert!(stderr(&o).contains("0 errors, 0 warnings"), "stderr:\n{}", stderr(&o));
}

/// `samples/` holds the deliberately broken fixtures of `samples/broken/`: checking
/// the whole folder fails, and only because of them.
#[test]
fn samples_folder_fails_only_in_broken_fixtures() {
    let o = hipop(&["check", "samples/", "--format", "json"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let doc: Value = serde_json::from_str(&stdout(&o)).expect("JSON output");
    let diagnostics = doc["diagnostics"].as_array().expect("diagnostics array");
    assert!(!diagnostics.is_empty());
    // The clean samples have information (their position families), no error or warning.
    for d in diagnostics.iter().filter(|d| d["severity"] != "info") {
        let file = d["location"]["file"].as_str().expect("file");
        assert!(file.starts_with("samples/broken/"), "unexpected diagnostic outside samples/broken/: {d}");
    }
}

#[test]
fn human_format() {
    let o = hipop(&["check", E0102, "--format", "human", "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    assert_eq!(stdout(&o), "", "human diagnostics go to stderr");
    insta::assert_snapshot!(stderr(&o));
}

#[test]
fn human_is_the_default_format() {
    let default = hipop(&["check", E0102, "--color", "never"]);
    let human = hipop(&["check", E0102, "--format", "human", "--color", "never"]);
    assert_eq!(stderr(&default), stderr(&human));
    assert_eq!(status(&default), 1);
}

#[test]
fn json_format() {
    let o = hipop(&["check", E0102, "--format", "json"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let out = stdout(&o);
    let doc: Value = serde_json::from_str(&out).expect("one JSON document");
    assert_eq!(doc["diagnostics"][0]["code"], "E0102");
    assert_eq!(doc["summary"]["errors"], 1);
    insta::assert_snapshot!(out);
}

#[test]
fn github_format() {
    let o = hipop(&["check", E0102, "--format", "github"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let out = stdout(&o);
    assert!(out.lines().all(|l| l.starts_with("::")), "only workflow commands on stdout:\n{out}");
    insta::assert_snapshot!(out);
}

#[test]
fn sarif_format() {
    let o = hipop(&["check", E0102, "--format", "sarif"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1);
    let mut doc: Value = serde_json::from_str(&stdout(&o)).expect("one JSON document");
    assert_eq!(doc["version"], "2.1.0");
    let run = &doc["runs"][0];
    assert_eq!(run["tool"]["driver"]["name"], "hipop");
    let rule_ids: Vec<&str> = run["tool"]["driver"]["rules"]
        .as_array()
        .expect("rules array")
        .iter()
        .map(|r| r["id"].as_str().expect("rule id"))
        .collect();
    let results = run["results"].as_array().expect("results array");
    assert!(!results.is_empty());
    for r in results {
        let id = r["ruleId"].as_str().expect("ruleId");
        assert!(rule_ids.contains(&id), "result rule `{id}` is not among the driver's rules");
        let index = r["ruleIndex"].as_u64().expect("ruleIndex") as usize;
        assert_eq!(rule_ids[index], id, "ruleIndex points at the result's rule");
    }
    assert_eq!(results[0]["ruleId"], "E0102");
    // The tool version changes with every release: keep it out of the snapshot.
    doc["runs"][0]["tool"]["driver"]["version"] = Value::from("[version]");
    insta::assert_snapshot!(serde_json::to_string_pretty(&doc).expect("serialisable"));
}

#[test]
fn deny_warnings_turns_warnings_into_failure() {
    let without = hipop(&["check", WARNING_ONLY, "--color", "never"]);
    assert_no_panic(&without);
    assert_eq!(status(&without), 0, "a warning alone does not fail:\n{}", stderr(&without));
    assert!(stderr(&without).contains("0 errors, 1 warning"), "stderr:\n{}", stderr(&without));

    let with = hipop(&["check", WARNING_ONLY, "--deny", "warnings", "--color", "never"]);
    assert_no_panic(&with);
    assert_eq!(status(&with), 1, "with --deny warnings a warning fails:\n{}", stderr(&with));
}

#[test]
fn allow_silences_a_code_by_id_or_name() {
    for code in ["W0201", "unused-declaration"] {
        let o = hipop(&["check", "--deny", "warnings", "--allow", code, WARNING_ONLY]);
        assert_no_panic(&o);
        assert_eq!(status(&o), 0, "{code}: {}", stderr(&o));
        assert!(!stderr(&o).contains("W0201"), "{}", stderr(&o));
    }
    // Other codes are still reported.
    let o = hipop(&["check", "--allow", "W0201", E0102]);
    assert_eq!(status(&o), 1);
    let o = hipop(&["check", "--allow", "W9999", E0102]);
    assert_eq!(status(&o), 2, "an unknown code is a usage error");
    assert!(stderr(&o).contains("`W9999` is not a diagnostic code"), "{}", stderr(&o));
}

#[test]
fn allow_comments_silence_an_occurrence_or_a_file() {
    let dir = std::env::temp_dir().join(format!("hipop-allow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let original = std::fs::read_to_string(workspace_root().join(WARNING_ONLY)).unwrap();
    let path = dir.join("d.pddl");
    let check = |text: &str| {
        std::fs::write(&path, text).unwrap();
        let o = hipop(&["check", "--deny", "warnings", path.to_str().unwrap()]);
        assert_no_panic(&o);
        status(&o)
    };
    assert_eq!(check(&original), 1);
    assert_eq!(check(&format!("{original}\n; hipop-allow-file: unused-declaration\n")), 0);
    assert_eq!(check(&format!("{original}\n; hipop-allow-file: W0202\n")), 1, "another code");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn nonexistent_path_is_a_usage_error() {
    let o = hipop(&["check", "samples/no-such-mission.pddl"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2);
    let err = stderr(&o);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("samples/no-such-mission.pddl")).collect();
    assert_eq!(lines.len(), 1, "one line names the missing path:\n{err}");
    assert!(lines[0].starts_with("error:"), "stderr:\n{err}");
    assert!(lines[0].contains("no such file"), "stderr:\n{err}");
}

#[test]
fn non_utf8_file_is_reported_without_panic() {
    let path = std::env::temp_dir().join(format!("hipop-cli-test-{}-not-utf8.pddl", std::process::id()));
    std::fs::write(&path, [0xff, 0xfe]).expect("temp file written");
    let file = TempFile(path);
    let o = hipop(&["check", file.0.to_str().expect("UTF-8 temp path"), "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2);
    let err = stderr(&o);
    let line = err.lines().find(|l| l.contains("not-utf8.pddl")).expect("a line names the file");
    assert!(line.starts_with("error:"), "stderr:\n{err}");
    assert!(line.contains("UTF-8"), "the message says what is wrong:\n{err}");
}

/// A file that starts with a UTF-8 byte-order mark reads without error, and
/// its columns are the editor's: the mark is not one.
#[test]
fn a_byte_order_mark_is_not_a_column() {
    let file = "tests/reading/byte-order-mark.pddl";
    let o = hipop(&["check", file, "--color", "never"]);
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "stderr:\n{}", stderr(&o));
    assert!(stderr(&o).contains(&format!("{file}:1:51")), "stderr:\n{}", stderr(&o));
    let o = hipop(&["check", file, "--format", "json"]);
    let doc: Value = serde_json::from_str(&stdout(&o)).expect("JSON output");
    let d = &doc["diagnostics"][0];
    assert_eq!(d["code"], "W0201");
    assert_eq!(d["location"]["start"], serde_json::json!({"line": 1, "column": 51, "offset": 53}));
}

#[test]
fn fix_applies_fixes_then_checks_again() {
    let dir = TempDir::new("fix");
    let conflicts = dir.copy("samples/broken/E0301-uncovered-conflict.hddl");
    let typo = dir.copy("samples/broken/E0105-undefined-task.hddl");
    let before = std::fs::read_to_string(&conflicts).unwrap();

    let o = hipop(&["check", "--fix", dir.path(), "--color", "never"]);
    assert_no_panic(&o);
    let err = stderr(&o);
    assert_eq!(status(&o), 0, "everything was fixed:\n{err}");
    assert!(err.contains("fixed 2 diagnostics in 2 files"), "stderr:\n{err}");
    assert!(err.contains("checked 2 files: 0 errors, 0 warnings"), "the check after the fixes:\n{err}");

    // Only the `:conflicts` line changed, comments and layout kept.
    let after = std::fs::read_to_string(&conflicts).unwrap();
    assert_eq!(
        after,
        before.replace(":conflicts (and (at-r ?r ?home)))", ":conflicts (and (at-r ?r ?home) (at-r ?r ?w)))")
    );
    assert!(std::fs::read_to_string(&typo).unwrap().contains(":task (goto ?r ?to)"));

    let again = hipop(&["check", "--fix", dir.path(), "--color", "never"]);
    assert_eq!(status(&again), 0);
    assert!(stderr(&again).contains("nothing to fix"), "stderr:\n{}", stderr(&again));
}

#[test]
fn fix_leaves_what_it_cannot_fix_and_fails() {
    let dir = TempDir::new("fix-remaining");
    let cycle = dir.copy("samples/broken/E0113-ordering-cycle.hddl");
    let before = std::fs::read_to_string(&cycle).unwrap();
    let o = hipop(&["check", "--fix", dir.path(), "--color", "never"]);
    assert_no_panic(&o);
    let err = stderr(&o);
    assert_eq!(status(&o), 1, "the error remains:\n{err}");
    assert!(err.contains("nothing to fix") && err.contains("E0113"), "stderr:\n{err}");
    assert_eq!(std::fs::read_to_string(&cycle).unwrap(), before, "the file is untouched");
}

#[test]
fn fix_skips_overlapping_fixes() {
    // Two literals to add to a single-atom `:conflicts`: both fixes wrap it
    // into `(and …)`, so only the first is applied; a second run applies the other.
    let dir = TempDir::new("fix-overlap");
    let path = dir.0.join("d.hddl");
    let domain = "; two uncovered literals
(define (domain d)
  (:requirements :hierarchy)
  (:predicates (at ?r ?w) (busy ?r) (seen ?w))
  (:action move :parameters (?r ?a ?b)
    :precondition (and (at ?r ?a) (busy ?r) (seen ?a))
    :effect (and (not (at ?r ?a)) (not (busy ?r)) (at ?r ?b) (seen ?b)))
  (:task goto :parameters (?r ?to) :conflicts (seen ?to))
  (:method m :parameters (?r ?from ?to) :task (goto ?r ?to)
    :subtasks (and (move ?r ?from ?to))))
";
    std::fs::write(&path, domain).unwrap();
    let run = || hipop(&["check", "--fix", dir.path(), "--color", "never"]);

    let o = run();
    assert_no_panic(&o);
    let err = stderr(&o);
    assert!(err.contains("fixed 1 diagnostic in 1 file"), "stderr:\n{err}");
    assert!(err.contains("skipped 1 fix that would overlap another"), "stderr:\n{err}");
    assert_eq!(status(&o), 1, "one E0301 remains:\n{err}");
    assert!(err.contains("checked 1 file: 1 error, 1 warning"), "stderr:\n{err}");

    let o = run();
    let err = stderr(&o);
    assert!(err.contains("fixed 1 diagnostic in 1 file"), "stderr:\n{err}");
    assert!(!err.contains("skipped"), "stderr:\n{err}");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains(":conflicts (and (seen ?to) (at ?r ?from) (busy ?r))"),
        "both literals added, one `and`:\n{text}"
    );
    // `(seen ?to)` is added by `move` but deleted by nothing: W0302 remains.
    assert_eq!(status(&o), 0, "stderr:\n{err}");
    assert!(err.contains("W0302"), "stderr:\n{err}");
}

/// The files of a folder fall into independent groups (a domain with its
/// problems), checked a few at a time in threads of their own: the folder's
/// diagnostics are those of its entries checked one by one, in the order of
/// its files.
#[test]
fn a_folder_of_many_groups_reports_as_its_entries_one_by_one() {
    let diagnostics = |path: &str| -> Vec<Value> {
        let o = hipop(&["check", path, "--format", "json", "--max-diagnostics", "0"]);
        assert_no_panic(&o);
        let doc: Value = serde_json::from_str(&stdout(&o)).expect("JSON output");
        doc["diagnostics"].as_array().expect("diagnostics array").clone()
    };
    let folder = "samples/broken";
    let mut entries: Vec<std::path::PathBuf> = std::fs::read_dir(workspace_root().join(folder))
        .expect("samples/broken")
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.is_dir() || p.extension().is_some_and(|e| e == "pddl" || e == "hddl"))
        .collect();
    entries.sort();
    assert!(entries.len() > 20, "samples/broken holds the broken fixtures");
    let one_by_one: Vec<Value> = entries
        .iter()
        .flat_map(|p| diagnostics(&format!("{folder}/{}", p.file_name().unwrap().to_str().unwrap())))
        .collect();
    let all = diagnostics(folder);
    assert!(all.len() > 20, "the broken fixtures have diagnostics");
    assert_eq!(all, one_by_one);
}
