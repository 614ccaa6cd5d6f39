//! The IPC 2002 temporal Satellite domain with HiPOP abstract actions (HiPOP
//! paper, section 4.4.1: "Abstract actions are used to calibrate or to
//! perform an observation").
//!
//! The variant domain is the corpus domain, unchanged but for two more
//! requirements (`:hierarchy :method-preconditions`) and two abstract actions
//! appended with their methods: `calibrate_instrument` (turn to the
//! instrument's calibration target, then calibrate) and `get_image` (turn to
//! the direction, then take the image with a calibrated, powered
//! instrument). Its name stays `satellite`, so the corpus problems read
//! against it unmodified; the copies of the problems only gain an
//! `(:allowed-actions …)` section before their final `)`: without it every
//! action is allowed, `calibrate` and `take_image` included (section 4.2.2).
//!
//! Two corpus variants are recognised: `satellite-time-simple-automatic`
//! (constant durations) and `satellite-time-automatic` (durations from the
//! `slew_time` and `calibration_time` fluents).

use std::path::Path;

/// The actions and tasks the problems allow.
pub const ALLOWED: &str = "turn_to switch_on switch_off calibrate_instrument get_image";

/// The variant domain and the problem copies, as `(file name, text)`,
/// `domain.pddl` first, then the problems sorted by their number.
pub fn satellite_abstract(corpus: &Path) -> Result<Vec<(String, String)>, String> {
    let read = |p: &Path| std::fs::read_to_string(p).map_err(|e| format!("cannot read {}: {e}", p.display()));
    let domain = read(&corpus.join("domain.pddl"))?;
    let name = corpus.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let mut files = vec![("domain.pddl".to_string(), variant_domain(&domain, &name)?)];
    let dir = if corpus.join("instances").is_dir() { corpus.join("instances") } else { corpus.to_path_buf() };
    let entries = std::fs::read_dir(&dir).map_err(|e| format!("cannot list {}: {e}", dir.display()))?;
    let mut problems = Vec::new();
    for entry in entries {
        let path = entry.map_err(|e| format!("cannot list {}: {e}", dir.display()))?.path();
        let file = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
        if path.extension().is_some_and(|e| e == "pddl") && file != "domain.pddl" {
            problems.push((file, read(&path)?));
        }
    }
    if problems.is_empty() {
        return Err(format!("no problem (.pddl file) in {}", dir.display()));
    }
    // instance-2 before instance-10.
    problems.sort_by_key(|(f, _)| {
        let digits: String = f.chars().filter(|c| c.is_ascii_digit()).collect();
        (digits.parse::<u64>().unwrap_or(u64::MAX), f.clone())
    });
    for (file, text) in problems {
        let text = with_allowed_actions(&text).map_err(|e| format!("{file}: {e}"))?;
        files.push((file, text));
    }
    Ok(files)
}

/// Whether the corpus domain takes its durations from fluents (the
/// `satellite-time-automatic` variant).
pub fn is_timed(domain: &str) -> bool {
    domain.to_ascii_lowercase().contains("slew_time")
}

/// The byte offset of the last `)` outside comments.
fn last_close(text: &str) -> Option<usize> {
    let mut last = None;
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let code = line.find(';').map_or(line, |c| &line[..c]);
        if let Some(k) = code.rfind(')') {
            last = Some(offset + k);
        }
        offset += line.len();
    }
    last
}

/// The corpus domain with the abstract actions.
pub fn variant_domain(domain: &str, corpus_name: &str) -> Result<String, String> {
    let lower = domain.to_ascii_lowercase();
    let req = lower.find("(:requirements").ok_or("the domain has no (:requirements …)")?;
    let req_end = req + lower[req..].find(')').ok_or("unbalanced (:requirements …)")?;
    let close = last_close(domain).ok_or("the domain has no final `)`")?;
    let timed = is_timed(domain);
    let mut out = String::new();
    out.push_str(&HEADER.replace("{CORPUS}", corpus_name));
    out.push_str(&domain[..req_end]);
    out.push_str(" :hierarchy :method-preconditions");
    out.push_str(&domain[req_end..close]);
    out.push_str(if timed { TASKS_TIMED } else { TASKS_SIMPLE });
    out.push_str(&domain[close..]);
    Ok(out)
}

/// A corpus problem with the `(:allowed-actions …)` section.
pub fn with_allowed_actions(problem: &str) -> Result<String, String> {
    let close = last_close(problem).ok_or("the problem has no final `)`")?;
    let mut out = String::with_capacity(problem.len() + 200);
    out.push_str(&problem[..close]);
    out.push_str(
        "; Added by hipop-samplegen (satellite-abstract): what the planner may insert (HiPOP paper,\n",
    );
    out.push_str("; section 4.2.2); calibrate and take_image only happen inside the abstract actions.\n");
    out.push_str(&format!("(:allowed-actions {ALLOWED})\n"));
    out.push_str(&problem[close..]);
    Ok(out)
}

const HEADER: &str = "\
; The IPC 2002 temporal Satellite domain ({CORPUS}) with HiPOP abstract actions
; (HiPOP paper, section 4.4.1): the corpus domain, unchanged but for the requirements
; :hierarchy and :method-preconditions, and the abstract actions calibrate_instrument and
; get_image appended at the end with their methods.
; Generated by hipop-samplegen (satellite-abstract mode). Do not edit by hand; regenerate with:
;   cargo run -p hipop-samplegen -- satellite-abstract --corpus <ipc2002-temporal>/{CORPUS} --out DIR
";

const TASKS_SIMPLE: &str = "
  ;; HiPOP abstract actions (added by hipop-samplegen). Each one takes the previous direction
  ;; of the satellite, ?d_prev, so that it moves the satellite's pointing like turn_to does
  ;; (pointing stays a position family, with turn_to as its move action); it is ?d itself
  ;; when the satellite already points there (the in_place methods). The durations are
  ;; estimates, long enough for the turning methods: turn_to (5) + calibrate (5) and
  ;; turn_to (5) + take_image (7), plus 1 s for the separation of the two steps. The methods turn
  ;; the satellite, hence the conflict (pointing ?s ?other), ?other being a wildcard: nothing
  ;; may rely on where the satellite points while the abstract action runs.

  ; Calibrate an instrument: turn to its calibration target, then calibrate.
  (:task calibrate_instrument
   :parameters (?s - satellite ?i - instrument ?d - direction ?d_prev - direction)
   :agent (?s)
   :duration (= ?duration 11)
   :condition (and (over all (on_board ?i ?s))
                   (over all (calibration_target ?i ?d))
                   (at start (pointing ?s ?d_prev))
                   (at start (power_on ?i))
                   (over all (power_on ?i))
                   (at end (power_on ?i)))
   :effect (and (at end (not (pointing ?s ?d_prev)))
                (at end (pointing ?s ?d))
                (at end (calibrated ?i)))
   :conflicts (and (pointing ?s ?other)))

  (:method calibrate_instrument_turning
   :parameters (?s - satellite ?i - instrument ?d - direction ?d_prev - direction)
   :task (calibrate_instrument ?s ?i ?d ?d_prev)
   :precondition (and (on_board ?i ?s) (calibration_target ?i ?d) (not (= ?d ?d_prev)))
   :ordered-subtasks (and (t1 (turn_to ?s ?d ?d_prev))
                          (t2 (calibrate ?s ?i ?d))))

  (:method calibrate_instrument_in_place
   :parameters (?s - satellite ?i - instrument ?d - direction)
   :task (calibrate_instrument ?s ?i ?d ?d)
   :precondition (and (on_board ?i ?s) (calibration_target ?i ?d))
   :ordered-subtasks (and (t1 (calibrate ?s ?i ?d))))

  ; Take an image of a direction in a mode: turn to it, then take the image with a calibrated,
  ; powered instrument that supports the mode.
  (:task get_image
   :parameters (?s - satellite ?d - direction ?i - instrument ?m - mode ?d_prev - direction)
   :agent (?s)
   :duration (= ?duration 13)
   :condition (and (over all (on_board ?i ?s))
                   (over all (supports ?i ?m))
                   (at start (pointing ?s ?d_prev))
                   (at start (calibrated ?i))
                   (over all (calibrated ?i))
                   (at start (power_on ?i))
                   (over all (power_on ?i))
                   (at end (power_on ?i)))
   :effect (and (at end (not (pointing ?s ?d_prev)))
                (at end (pointing ?s ?d))
                (at end (have_image ?d ?m)))
   :conflicts (and (pointing ?s ?other)))

  (:method get_image_turning
   :parameters (?s - satellite ?d - direction ?i - instrument ?m - mode ?d_prev - direction)
   :task (get_image ?s ?d ?i ?m ?d_prev)
   :precondition (and (on_board ?i ?s) (supports ?i ?m) (not (= ?d ?d_prev)))
   :ordered-subtasks (and (t1 (turn_to ?s ?d ?d_prev))
                          (t2 (take_image ?s ?d ?i ?m))))

  (:method get_image_in_place
   :parameters (?s - satellite ?d - direction ?i - instrument ?m - mode)
   :task (get_image ?s ?d ?i ?m ?d)
   :precondition (and (on_board ?i ?s) (supports ?i ?m))
   :ordered-subtasks (and (t1 (take_image ?s ?d ?i ?m))))
";

const TASKS_TIMED: &str = "
  ;; HiPOP abstract actions (added by hipop-samplegen). Each one takes the previous direction
  ;; of the satellite, ?d_prev, so that it moves the satellite's pointing like turn_to does
  ;; (pointing stays a position family, with turn_to as its move action). The durations are
  ;; estimates: the slew, then calibrate or take_image (7), plus 1 s for the separation of
  ;; the two steps. The problems give no slew_time
  ;; from a direction to itself, so ?d_prev must differ from ?d and there is no in-place
  ;; method: a satellite already pointing at the direction turns away first. The methods turn
  ;; the satellite, hence the conflict (pointing ?s ?other), ?other being a wildcard: nothing
  ;; may rely on where the satellite points while the abstract action runs.

  ; Calibrate an instrument: turn to its calibration target, then calibrate.
  (:task calibrate_instrument
   :parameters (?s - satellite ?i - instrument ?d - direction ?d_prev - direction)
   :agent (?s)
   :duration (= ?duration (+ (slew_time ?d_prev ?d) (calibration_time ?i ?d) 1))
   :condition (and (over all (on_board ?i ?s))
                   (over all (calibration_target ?i ?d))
                   (over all (not (= ?d ?d_prev)))
                   (at start (pointing ?s ?d_prev))
                   (at start (power_on ?i))
                   (over all (power_on ?i))
                   (at end (power_on ?i)))
   :effect (and (at end (not (pointing ?s ?d_prev)))
                (at end (pointing ?s ?d))
                (at end (calibrated ?i)))
   :conflicts (and (pointing ?s ?other)))

  (:method calibrate_instrument_turning
   :parameters (?s - satellite ?i - instrument ?d - direction ?d_prev - direction)
   :task (calibrate_instrument ?s ?i ?d ?d_prev)
   :precondition (and (on_board ?i ?s) (calibration_target ?i ?d) (not (= ?d ?d_prev)))
   :ordered-subtasks (and (t1 (turn_to ?s ?d ?d_prev))
                          (t2 (calibrate ?s ?i ?d))))

  ; Take an image of a direction in a mode: turn to it, then take the image with a calibrated,
  ; powered instrument that supports the mode.
  (:task get_image
   :parameters (?s - satellite ?d - direction ?i - instrument ?m - mode ?d_prev - direction)
   :agent (?s)
   :duration (= ?duration (+ (slew_time ?d_prev ?d) 8))
   :condition (and (over all (on_board ?i ?s))
                   (over all (supports ?i ?m))
                   (over all (not (= ?d ?d_prev)))
                   (at start (pointing ?s ?d_prev))
                   (at start (calibrated ?i))
                   (over all (calibrated ?i))
                   (at start (power_on ?i))
                   (over all (power_on ?i))
                   (at end (power_on ?i)))
   :effect (and (at end (not (pointing ?s ?d_prev)))
                (at end (pointing ?s ?d))
                (at end (have_image ?d ?m)))
   :conflicts (and (pointing ?s ?other)))

  (:method get_image_turning
   :parameters (?s - satellite ?d - direction ?i - instrument ?m - mode ?d_prev - direction)
   :task (get_image ?s ?d ?i ?m ?d_prev)
   :precondition (and (on_board ?i ?s) (supports ?i ?m) (not (= ?d ?d_prev)))
   :ordered-subtasks (and (t1 (turn_to ?s ?d ?d_prev))
                          (t2 (take_image ?s ?d ?i ?m))))
";
