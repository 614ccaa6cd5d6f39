//! Planning on save, over stdio against `hipop lsp`: the plan inline (inlay
//! hints, hover), `hipop/plan`, `hipop.writePlan`, the repair diff, the flaws
//! of a problem without plan, and cancellation by an edit.

mod common;

use common::*;
use serde_json::{Value, json};

/// A copy of the `planning` fixture in a fresh folder (plans are written beside it).
fn scratch(name: &str) -> Scratch {
    let name = format!("planning-{name}");
    Scratch::with_fixture(&name, "planning", &["domain.pddl", "problem.pddl", "unreachable.pddl"])
}

/// What a client that shows progress and refreshes inlay hints declares.
fn capabilities() -> Value {
    json!({
        "window": {"workDoneProgress": true},
        "workspace": {"inlayHint": {"refreshSupport": true}},
    })
}

fn save(client: &mut Client, uri: &str) {
    client.notify("textDocument/didSave", json!({"textDocument": {"uri": uri}}));
}

/// Waits for the end of the run on `uri`.
fn planned(client: &mut Client, uri: &str) -> Value {
    let n = client.wait_for("hipop/planned", |n| n["method"] == "hipop/planned" && n["params"]["uri"] == uri);
    n["params"].clone()
}

fn hints(client: &mut Client, uri: &str) -> Vec<(u64, u64, String)> {
    let result = client.request(
        "textDocument/inlayHint",
        json!({"textDocument": {"uri": uri}, "range": range(0, 0, 100, 0)}),
    );
    // `null` before any run.
    result
        .as_array()
        .cloned()
        .unwrap_or_default()
        .iter()
        .map(|h| {
            let p = &h["position"];
            (
                p["line"].as_u64().unwrap(),
                p["character"].as_u64().unwrap(),
                h["label"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

/// The elapsed time of a summary ("…, 0.01 s") masked, for comparisons.
fn masked(label: &str) -> String {
    match label.find(" s") {
        Some(end) => {
            let start = label[..end].rfind(", ").map_or(0, |i| i + 2);
            format!("{}T{}", &label[..start], &label[end..])
        }
        None => label.to_string(),
    }
}

#[test]
fn saving_a_problem_plans_it_and_shows_the_plan_inline() {
    let dir = scratch("save");
    let mut client = Client::spawn();
    client.initialize(&dir, capabilities());
    let uri = file_uri(&dir.join("problem.pddl"));
    let text = std::fs::read_to_string(dir.join("problem.pddl")).unwrap();
    client.open(&uri, &text);
    client.diagnostics(&uri, Some(1));
    // Nothing before a save.
    assert_eq!(hints(&mut client, &uri), vec![]);
    assert_eq!(client.request("hipop/plan", json!({"uri": uri})), Value::Null);
    save(&mut client, &uri);
    let done = planned(&mut client, &uri);
    assert_eq!(done["status"], "solved", "{done}");
    assert!(!done["repaired"].as_bool().unwrap());
    // The run reported its progress, and asked the client to show the hints.
    let methods: Vec<&str> = client.log.iter().filter_map(|m| m["method"].as_str()).collect();
    assert!(methods.contains(&"window/workDoneProgress/create"), "{methods:?}");
    assert!(methods.contains(&"workspace/inlayHint/refresh"), "{methods:?}");
    let progress: Vec<&Value> = client.log.iter().filter(|m| m["method"] == "$/progress").collect();
    assert_eq!(progress.first().map(|p| &p["params"]["value"]["kind"]), Some(&json!("begin")));
    assert_eq!(progress.last().map(|p| &p["params"]["value"]["kind"]), Some(&json!("end")));
    // The summary after `(problem …)`, the achiever of each goal after it.
    let shown: Vec<(u64, u64, String)> =
        hints(&mut client, &uri).into_iter().map(|(l, c, s)| (l, c, masked(&s))).collect();
    assert_eq!(
        shown,
        vec![
            (1, 28, "plan: 3 actions, makespan 9.03, T s".to_string()),
            (5, 27, "← (observe r1 a p1) @ 0.01".to_string()),
            (5, 41, "← (observe r1 b p2) @ 7.03".to_string()),
        ]
    );
    // Hover on an action of the domain says how the plan uses it.
    let domain = file_uri(&dir.join("domain.pddl"));
    let hover = client.request("textDocument/hover", at(&domain, 5, 22));
    let said = hover["contents"]["value"].as_str().unwrap();
    assert!(said.contains("durative action (move ?r - robot"), "{said}");
    assert!(
        said.contains("**Last plan**") && said.contains("1 step of the last plan of `survey-two`"),
        "{said}"
    );
    // The plan and its timeline.
    let plan = client.request("hipop/plan", json!({"uri": uri}));
    assert_eq!(plan["status"], "solved");
    assert_eq!(plan["format"], "val");
    assert!(plan["text"].as_str().unwrap().contains("2.02: (move r1 a b) [5]"), "{plan}");
    assert!(plan["svg"].as_str().unwrap().contains("<svg"), "{plan}");
    // Written beside the problem, then read like any plan file: valid.
    let written =
        client.request("workspace/executeCommand", json!({"command": "hipop.writePlan", "arguments": [uri]}));
    let path = dir.join("problem.plan");
    assert_eq!(written["path"], path.display().to_string());
    let plan_text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(plan_text, plan["text"].as_str().unwrap());
    let plan_uri = file_uri(&path);
    client.open(&plan_uri, &plan_text);
    assert_eq!(client.diagnostics(&plan_uri, Some(1)), Vec::<Value>::new());
    client.shutdown();
}

#[test]
fn saving_a_changed_problem_repairs_the_last_plan_and_shows_the_diff() {
    let dir = scratch("repair");
    let mut client = Client::spawn();
    client.initialize(&dir, capabilities());
    let uri = file_uri(&dir.join("problem.pddl"));
    let text = std::fs::read_to_string(dir.join("problem.pddl")).unwrap();
    client.open(&uri, &text);
    save(&mut client, &uri);
    assert_eq!(planned(&mut client, &uri)["status"], "solved");
    assert_eq!(client.request("hipop/planDiff", json!({"uri": uri})), Value::Null);
    // A third point of interest to observe.
    client.change(&uri, 2, range(5, 41, 5, 41), " (observed p3)");
    save(&mut client, &uri);
    let done = planned(&mut client, &uri);
    assert_eq!(done["status"], "solved", "{done}");
    assert_eq!(done["repaired"], true, "{done}");
    let shown = hints(&mut client, &uri);
    assert!(shown[0].2.starts_with("repaired plan: 5 actions"), "{shown:?}");
    assert!(shown[0].2.ends_with("; instability 2, distance 2"), "{shown:?}");
    assert_eq!(shown.len(), 4, "{shown:?}");
    assert!(shown[3].2.starts_with("← (observe r1 c p3) @ "), "{shown:?}");
    let diff = client.request("hipop/planDiff", json!({"uri": uri}));
    assert_eq!(diff["instability"], 2, "{diff}");
    assert_eq!(diff["distance"], 2, "{diff}");
    let added: Vec<&str> =
        diff["added"].as_array().unwrap().iter().map(|s| s["step"].as_str().unwrap()).collect();
    assert_eq!(added, ["(move r1 b c)", "(observe r1 c p3)"]);
    assert!(diff["old"].as_str().unwrap().contains("(observe r1 b p2)"));
    assert!(diff["new"].as_str().unwrap().contains("(observe r1 c p3)"));
    // Without an argument (Helix's :lsp-workspace-command), the plan of the
    // problem planned last is written.
    client.request("workspace/executeCommand", json!({"command": "hipop.writePlan"}));
    let written = std::fs::read_to_string(dir.join("problem.plan")).unwrap();
    assert!(written.contains("(observe r1 c p3)"), "{written}");
    // An edit since: the summary says so, the goal hints are gone.
    client.change(&uri, 3, range(0, 0, 0, 0), " ");
    let shown = hints(&mut client, &uri);
    assert_eq!(shown.len(), 1, "{shown:?}");
    assert!(shown[0].2.ends_with("(edited since: save to plan again)"), "{shown:?}");
    client.shutdown();
}

#[test]
fn without_a_plan_the_flaws_are_information_on_the_problem() {
    let dir = scratch("flaws");
    let mut client = Client::spawn();
    client.initialize(&dir, capabilities());
    let uri = file_uri(&dir.join("unreachable.pddl"));
    let text = std::fs::read_to_string(dir.join("unreachable.pddl")).unwrap();
    client.open(&uri, &text);
    client.diagnostics(&uri, Some(1));
    save(&mut client, &uri);
    let done = planned(&mut client, &uri);
    assert_eq!(done["status"], "no-plan", "{done}");
    let shown = hints(&mut client, &uri);
    assert_eq!(shown.len(), 1, "{shown:?}");
    assert!(shown[0].2.starts_with("no plan exists: "), "{shown:?}");
    // The flaws, published with the file's other diagnostics (before the
    // end of the run is notified).
    let has_flaws = |n: &Value| {
        n["method"] == "textDocument/publishDiagnostics"
            && n["params"]["uri"] == uri
            && n["params"]["diagnostics"].as_array().is_some_and(|d| d.iter().any(|d| d["code"] == "I0504"))
    };
    let flaws = match client.log.iter().find(|n| has_flaws(n)) {
        Some(n) => n.clone(),
        None => client.wait_for("the flaws", has_flaws),
    };
    let open_link =
        flaws["params"]["diagnostics"].as_array().unwrap().iter().find(|d| d["code"] == "I0504").unwrap();
    assert_eq!(open_link["severity"], 3, "{open_link}");
    assert_eq!(open_link["range"]["start"]["line"], 5, "{open_link}");
    client.shutdown();
}

#[test]
fn planning_on_save_can_be_turned_off() {
    let dir = scratch("off");
    let mut client = Client::spawn();
    let uri = file_uri(&dir.join("problem.pddl"));
    client.initialize_with(&dir, capabilities(), Value::Null, json!({"plan": {"onSave": false}}));
    let text = std::fs::read_to_string(dir.join("problem.pddl")).unwrap();
    client.open(&uri, &text);
    save(&mut client, &uri);
    client.diagnostics(&uri, Some(1));
    // Turned on again by the settings: the next save plans.
    client.notify(
        "workspace/didChangeConfiguration",
        json!({"settings": {"hipop": {"plan": {"onSave": true}}}}),
    );
    assert_eq!(client.request("hipop/plan", json!({"uri": uri})), Value::Null);
    save(&mut client, &uri);
    assert_eq!(planned(&mut client, &uri)["status"], "solved");
    let methods: Vec<&str> = client.log.iter().filter_map(|m| m["method"].as_str()).collect();
    assert_eq!(methods.iter().filter(|m| **m == "hipop/planned").count(), 1, "{methods:?}");
    client.shutdown();
}

/// An edit while a plan runs stops it: the edit's diagnostics come at once,
/// the run ends without a plan kept, and the next save plans again.
#[test]
fn an_edit_cancels_the_plan_in_progress() {
    let dir = fixture("endless");
    let mut client = Client::spawn();
    let uri = file_uri(&dir.join("problem.pddl"));
    client.initialize_with(&dir, capabilities(), Value::Null, json!({"plan": {"timeLimit": 120}}));
    let text = std::fs::read_to_string(dir.join("problem.pddl")).unwrap();
    client.open(&uri, &text);
    client.diagnostics(&uri, Some(1));
    save(&mut client, &uri);
    // The search is under way once it reports how far it is.
    client.wait_for("a progress report", |n| {
        n["method"] == "$/progress" && n["params"]["value"]["kind"] == "report"
    });
    let edited = std::time::Instant::now();
    client.change(&uri, 2, range(0, 0, 0, 0), " ");
    client.diagnostics(&uri, Some(2));
    // Without the cancellation the edit would wait for the time limit.
    assert!(edited.elapsed() < std::time::Duration::from_secs(10), "{:?}", edited.elapsed());
    let is_end = |n: &Value| n["method"] == "$/progress" && n["params"]["value"]["kind"] == "end";
    let end = match client.log.iter().find(|n| is_end(n)) {
        Some(n) => n.clone(),
        None => client.wait_for("the end of the run", is_end),
    };
    assert_eq!(end["params"]["value"]["message"], "cancelled by an edit", "{end}");
    assert_eq!(client.request("hipop/plan", json!({"uri": uri})), Value::Null);
    let methods: Vec<&str> = client.log.iter().filter_map(|m| m["method"].as_str()).collect();
    assert!(!methods.contains(&"hipop/planned"), "{methods:?}");
    client.shutdown();
}
