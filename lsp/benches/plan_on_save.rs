//! `cargo bench -p hipop-lsp --bench plan_on_save`: planning on save through
//! the real server over stdio, on the surveillance sample (the HiPOP paper's
//! case study):
//! - save → inlay hints of the plan: from `didSave` to the hints answered;
//! - a one-goal change, saved → repair diff: from `didSave` to `hipop/planDiff`
//!   answered;
//! - edit → diagnostics while a plan runs, against the same without planning
//!   (median and max over 50 edits).
//!
//! Recorded in docs/benchmarks.md.

#[path = "../tests/common/mod.rs"]
mod common;

use std::path::Path;
use std::time::{Duration, Instant};

use common::{Client, file_uri, range};
use serde_json::{Value, json};

const ROUNDS: usize = 10;
const EDITS: usize = 50;

fn capabilities() -> Value {
    json!({"window": {"workDoneProgress": true}, "workspace": {"inlayHint": {"refreshSupport": true}}})
}

fn server(dir: &Path, options: Value) -> Client {
    // No debounce: the edits measure the work, not the pause.
    let mut client = Client::spawn_with_env(&[("HIPOP_LSP_DEBOUNCE_MS", "0")]);
    client.initialize_with(dir, capabilities(), Value::Null, options);
    client
}

fn save(client: &mut Client, uri: &str) {
    client.notify("textDocument/didSave", json!({"textDocument": {"uri": uri}}));
}

fn planned(client: &mut Client, uri: &str) -> Value {
    client.wait_for("hipop/planned", |n| n["method"] == "hipop/planned" && n["params"]["uri"] == uri)["params"]
        .clone()
}

fn position(text: &str, at: usize) -> (u32, u32) {
    let line = text[..at].matches('\n').count() as u32;
    let col = (at - text[..at].rfind('\n').map_or(0, |i| i + 1)) as u32;
    (line, col)
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn median(times: &mut [Duration]) -> Duration {
    times.sort();
    times[times.len() / 2]
}

fn main() {
    let sample = Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples/surveillance");
    let dir = std::env::temp_dir().join(format!("hipop-plan-on-save-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let domain = std::fs::read_to_string(sample.join("domain.pddl")).expect("the sample's domain");
    let problem = std::fs::read_to_string(sample.join("problem.pddl")).expect("the sample's problem");
    std::fs::write(dir.join("domain.pddl"), &domain).expect("write domain");
    std::fs::write(dir.join("problem.pddl"), &problem).expect("write problem");
    let (duri, puri) = (file_uri(&dir.join("domain.pddl")), file_uri(&dir.join("problem.pddl")));

    // 1. Save → hints. A comment added to the domain before each save makes
    //    the run a plan from scratch (a repair needs the same domain).
    let mut client = server(&dir, json!({"plan": {"timeLimit": 30}}));
    client.open(&duri, &domain);
    client.open(&puri, &problem);
    client.diagnostics(&puri, Some(1));
    let whole = json!({"textDocument": {"uri": puri}, "range": range(0, 0, 5000, 0)});
    let mut to_hints = Vec::new();
    let mut actions = 0;
    for round in 0..ROUNDS {
        client.change(&duri, round as i64 + 2, range(0, 0, 0, 0), ";\n");
        let t = Instant::now();
        save(&mut client, &puri);
        let done = planned(&mut client, &puri);
        assert_eq!(done["status"], "solved", "{done}");
        assert_eq!(done["repaired"], false, "{done}");
        let hints = client.request("textDocument/inlayHint", whole.clone());
        to_hints.push(t.elapsed());
        let summary = hints[0]["label"].as_str().unwrap_or_default().to_string();
        assert!(summary.starts_with("plan: "), "{summary}");
        actions = hints.as_array().map_or(0, Vec::len);
    }

    // 2. A one-goal change, saved → repair diff. Each round removes one
    //    observation goal, then puts it back.
    let goal = "(observed ptobs_22621_1939)";
    let at = problem.find(goal).expect("the goal");
    let (line, col) = position(&problem, at);
    let mut to_diff = Vec::new();
    let mut figures = Vec::new();
    for round in 0..ROUNDS {
        let version = round as i64 + 2;
        if round % 2 == 0 {
            client.change(&puri, version, range(line, col, line, col + goal.len() as u32), "");
        } else {
            client.change(&puri, version, range(line, col, line, col), goal);
        }
        let t = Instant::now();
        save(&mut client, &puri);
        let done = planned(&mut client, &puri);
        assert_eq!(done["status"], "solved", "{done}");
        assert_eq!(done["repaired"], true, "{done}");
        let diff = client.request("hipop/planDiff", json!({"uri": puri}));
        to_diff.push(t.elapsed());
        figures.push((diff["instability"].as_u64().unwrap_or(0), diff["distance"].as_u64().unwrap_or(0)));
    }
    client.shutdown();

    // 3. Edits while a plan runs. Two goals that cannot hold together keep
    //    the search going until it is cancelled.
    let hard = problem.replacen(
        "(:goal (and",
        "(:goal (and (at-r mona1 wpg_11447_1795) (at-r mona1 wpg_10677_1908)",
        1,
    );
    let fact = hard.find("(robot-allowed ressac1 ").expect("a fact");
    let (fline, fcol) = position(&hard, fact);
    let edit_times = |plan: bool| {
        let mut client = server(&dir, json!({"plan": {"onSave": plan, "timeLimit": 120}}));
        client.open(&duri, &domain);
        client.open(&puri, &hard);
        client.diagnostics(&puri, Some(1));
        let mut times = Vec::new();
        for i in 0..EDITS {
            save(&mut client, &puri);
            if plan {
                // The search is under way once it reports progress (after
                // 100 ms).
                client.wait_for("progress", |n| {
                    n["method"] == "$/progress" && n["params"]["value"]["kind"] == "report"
                });
            } else {
                // The same pause after the save, without a search.
                std::thread::sleep(Duration::from_millis(120));
            }
            let version = i as i64 + 2;
            // A space before a fact, then removed: the problem stays plannable,
            // and every version is published.
            let t = Instant::now();
            if i % 2 == 0 {
                client.change(&puri, version, range(fline, fcol, fline, fcol), " ");
            } else {
                client.change(&puri, version, range(fline, fcol, fline, fcol + 1), "");
            }
            let diags = client.diagnostics(&puri, Some(version));
            times.push(t.elapsed());
            assert!(diags.iter().all(|d| d["severity"] != 1), "{diags:?}");
        }
        client.shutdown();
        times
    };
    let mut quiet = edit_times(false);
    let mut busy = edit_times(true);
    let _ = std::fs::remove_dir_all(&dir);

    let max = |t: &[Duration]| t.iter().max().copied().unwrap_or_default();
    println!("| surveillance sample ({} hints) | median | max |", actions);
    println!("|---|---|---|");
    let (m, x) = (ms(median(&mut to_hints)), ms(max(&to_hints)));
    println!("| save → plan hints, {ROUNDS} saves (plan from scratch) | {m:.1} ms | {x:.1} ms |");
    let (m, x) = (ms(median(&mut to_diff)), ms(max(&to_diff)));
    println!("| one-goal change saved → repair diff, {ROUNDS} saves | {m:.1} ms | {x:.1} ms |");
    let (m, x) = (ms(median(&mut quiet)), ms(max(&quiet)));
    println!("| edit → diagnostics, no planning, {EDITS} edits | {m:.2} ms | {x:.2} ms |");
    let (m, x) = (ms(median(&mut busy)), ms(max(&busy)));
    println!("| edit → diagnostics while a plan runs, {EDITS} edits | {m:.2} ms | {x:.2} ms |");
    let (i, d): (Vec<u64>, Vec<u64>) = figures.into_iter().unzip();
    println!("\nrepairs: instability {i:?}, distance {d:?}");
}
