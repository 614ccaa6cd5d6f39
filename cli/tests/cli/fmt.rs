//! `hipop fmt`: in place, `--check`, standard input, files with syntax errors.

use std::io::Write;
use std::process::Stdio;

use super::*;

/// A small domain laid out carelessly, with comments.
const UNFORMATTED: &str = "; blocks, written in a hurry
(define (domain blocks) (:requirements :strips :typing)   
(:types block)
(:predicates (on ?x ?y - block) ; ?x is on ?y
  (clear ?x - block))


(:action unstack :parameters (?x ?y - block)
    :precondition (and (on ?x ?y) (clear ?x))
    :effect (and (clear ?y) (not (on ?x ?y)))))
";

/// Runs `hipop` in `dir`, with `input` on standard input.
fn hipop_in(dir: &Path, args: &[&str], input: Option<&str>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hipop"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the hipop binary runs");
    let mut stdin = child.stdin.take().expect("piped");
    if let Some(input) = input {
        stdin.write_all(input.as_bytes()).expect("input written");
    }
    drop(stdin);
    child.wait_with_output().expect("hipop exits")
}

#[test]
fn fmt_rewrites_files_that_change_and_check_then_passes() {
    let dir = TempDir::new("fmt-rewrite");
    std::fs::create_dir_all(dir.0.join("models")).unwrap();
    std::fs::write(dir.0.join("models/domain.pddl"), UNFORMATTED).unwrap();
    let o = hipop_in(&dir.0, &["fmt", "--check", "models"], None);
    assert_no_panic(&o);
    assert_eq!(status(&o), 1, "stderr:\n{}", stderr(&o));
    assert_eq!(stdout(&o), "Would reformat: models/domain.pddl\n");
    assert_eq!(stderr(&o), "1 file would be reformatted, 0 files already formatted\n");
    assert_eq!(std::fs::read_to_string(dir.0.join("models/domain.pddl")).unwrap(), UNFORMATTED);

    let o = hipop_in(&dir.0, &["fmt", "models"], None);
    assert_eq!(status(&o), 0, "stderr:\n{}", stderr(&o));
    assert_eq!(stdout(&o), "");
    assert_eq!(stderr(&o), "1 file reformatted, 0 files already formatted\n");
    let formatted = std::fs::read_to_string(dir.0.join("models/domain.pddl")).unwrap();
    insta::assert_snapshot!(formatted);

    for args in [&["fmt", "--check", "models"][..], &["fmt", "models/domain.pddl"]] {
        let o = hipop_in(&dir.0, args, None);
        assert_eq!(status(&o), 0, "{args:?}: stderr:\n{}", stderr(&o));
        assert_eq!(
            stderr(&o),
            "0 files reformatted, 1 file already formatted\n".replace(
                "reformatted",
                if args[1] == "--check" { "would be reformatted" } else { "reformatted" }
            )
        );
    }
    assert_eq!(std::fs::read_to_string(dir.0.join("models/domain.pddl")).unwrap(), formatted);
}

#[test]
fn fmt_dash_formats_standard_input_to_standard_output() {
    let dir = TempDir::new("fmt-stdin");
    let o = hipop_in(&dir.0, &["fmt", "-"], Some(UNFORMATTED));
    assert_no_panic(&o);
    assert_eq!(status(&o), 0, "stderr:\n{}", stderr(&o));
    assert_eq!(stderr(&o), "");
    // The same text as the file formatted in place.
    let file = dir.0.join("domain.pddl");
    std::fs::write(&file, UNFORMATTED).unwrap();
    assert_eq!(status(&hipop_in(&dir.0, &["fmt", "domain.pddl"], None)), 0);
    assert_eq!(stdout(&o), std::fs::read_to_string(&file).unwrap());

    let again = hipop_in(&dir.0, &["fmt", "--check", "-"], Some(&stdout(&o)));
    assert_eq!((status(&again), stdout(&again)), (0, String::new()));
    let check = hipop_in(&dir.0, &["fmt", "--check", "-"], Some(UNFORMATTED));
    assert_eq!((status(&check), stdout(&check)), (1, "Would reformat: <stdin>\n".to_string()));

    let both = hipop_in(&dir.0, &["fmt", "-", "domain.pddl"], None);
    assert_eq!(status(&both), 2);
    assert!(stderr(&both).contains("cannot be given with other paths"), "{}", stderr(&both));
}

#[test]
fn fmt_refuses_a_file_with_a_syntax_error_and_says_where() {
    let dir = TempDir::new("fmt-syntax");
    let broken = dir.copy("samples/broken/E0001-missing-paren.pddl");
    let before = std::fs::read_to_string(&broken).unwrap();
    std::fs::write(dir.0.join("ok.pddl"), UNFORMATTED).unwrap();
    let o = hipop_in(&dir.0, &["fmt", "."], None);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2);
    insta::assert_snapshot!(stderr(&o));
    // The broken file is left alone; the other one is formatted all the same.
    assert_eq!(std::fs::read_to_string(&broken).unwrap(), before);
    assert_ne!(std::fs::read_to_string(dir.0.join("ok.pddl")).unwrap(), UNFORMATTED);

    let o = hipop_in(&dir.0, &["fmt", "-"], Some("(define (domain d)\n  (:types a)"));
    assert_eq!(status(&o), 2);
    assert_eq!(stdout(&o), "");
    assert_eq!(
        stderr(&o),
        "<stdin>:2:12: error: not formatted: syntax error: missing `)`: `(define` is not closed\n"
    );
}

#[test]
fn fmt_refuses_plans_and_missing_paths() {
    let dir = TempDir::new("fmt-plan");
    std::fs::write(dir.0.join("plan.hddl"), "==>\n0 a o\nroot 0\n<==\n").unwrap();
    let o = hipop_in(&dir.0, &["fmt", "plan.hddl", "missing.pddl"], None);
    assert_no_panic(&o);
    assert_eq!(status(&o), 2);
    insta::assert_snapshot!(stderr(&o));
    let o = hipop_in(&dir.0, &["fmt"], None);
    assert_eq!(status(&o), 2, "paths are required");
}

/// docs/formatting.md's example is what `hipop fmt` does.
#[test]
fn the_example_of_docs_formatting_md_is_hipop_fmt_output() {
    let doc =
        std::fs::read_to_string(workspace_root().join("docs/formatting.md")).expect("docs/formatting.md");
    let example = doc.split("## Before and after").nth(1).expect("the example section");
    let blocks: Vec<&str> =
        example.split("```pddl\n").skip(1).take(2).map(|b| b.split("```").next().expect("a block")).collect();
    let [before, after] = blocks[..] else { panic!("two pddl blocks: before and after") };
    assert_ne!(before, after);
    let o = hipop_in(&workspace_root(), &["fmt", "-"], Some(before));
    assert_eq!(status(&o), 0, "stderr:\n{}", stderr(&o));
    assert_eq!(stdout(&o), after, "docs/formatting.md: update the example's result");
}
