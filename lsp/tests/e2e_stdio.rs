//! End-to-end tests: spawn `hipop lsp` and speak JSON-RPC to it over stdio.

mod common;

use common::{Client, Scratch, at, file_uri, fixture, range};
use serde_json::{Value, json};

fn read(rel: &str) -> (String, String) {
    let path = fixture(rel);
    (file_uri(&path), std::fs::read_to_string(&path).expect("fixture"))
}

fn codes(diags: &[Value]) -> Vec<&str> {
    diags.iter().filter_map(|d| d["code"].as_str()).collect()
}

fn find<'a>(diags: &'a [Value], code: &str) -> &'a Value {
    diags.iter().find(|d| d["code"] == code).unwrap_or_else(|| panic!("no {code} in {diags:#?}"))
}

/// initialize → didOpen → diagnostics → didChange → new diagnostics → hover →
/// definition → references → symbols → shutdown.
#[test]
fn a_full_session() {
    let mut client = Client::spawn();
    let init = client.initialize(&fixture("blocks"), json!({}));
    assert_eq!(init["serverInfo"]["name"], "hipop");
    assert_eq!(init["capabilities"]["positionEncoding"], "utf-16");
    assert_eq!(init["capabilities"]["textDocumentSync"]["change"], 2, "incremental sync");

    let (uri, text) = read("blocks/domain.pddl");
    client.open(&uri, &text);
    let diags = client.diagnostics(&uri, Some(1));
    // `held` is not unused: the problem, loaded from disk, uses it.
    assert_eq!(codes(&diags), ["E0102"]);
    let undefined = find(&diags, "E0102");
    assert_eq!(undefined["range"], range(12, 18, 12, 25));
    assert_eq!(undefined["severity"], 1);
    assert_eq!(undefined["source"], "hipop");
    assert_eq!(undefined["message"], "undefined predicate `holding`");

    // Fix it: `holding` → `held`.
    client.change(&uri, 2, range(12, 18, 12, 25), "held");
    assert_eq!(client.diagnostics(&uri, Some(2)), Vec::<Value>::new());
    // Saving publishes again, at once.
    client.notify("textDocument/didSave", json!({"textDocument": {"uri": uri}}));
    assert_eq!(client.diagnostics(&uri, Some(2)), Vec::<Value>::new());
    assert_eq!(client.published_versions(&uri), [1, 2, 2]);

    // Hover on the use of `on-table`: its signature and the comment above its declaration.
    let hover = client.request("textDocument/hover", at(&uri, 11, 26));
    let markdown = hover["contents"]["value"].as_str().expect("markdown hover");
    assert_eq!(hover["contents"]["kind"], "markdown");
    assert!(markdown.contains("predicate (on-table ?b - block)"), "{markdown}");
    assert!(markdown.contains("The block lies on the table."), "{markdown}");
    assert_eq!(hover["range"], range(11, 24, 11, 32));
    // And on `clear`: the comment after its declaration.
    let hover = client.request("textDocument/hover", at(&uri, 11, 39));
    assert!(hover["contents"]["value"].as_str().unwrap_or("").contains("nothing is on top of ?b"), "{hover}");

    let definition = client.request("textDocument/definition", at(&uri, 11, 26));
    assert_eq!(definition, json!({"uri": uri, "range": range(6, 5, 6, 13)}));

    // References span the domain and its problem, which was loaded from disk.
    let refs = client.request(
        "textDocument/references",
        json!({"textDocument": {"uri": uri}, "position": {"line": 11, "character": 26}, "context": {"includeDeclaration": true}}),
    );
    let problem_uri = file_uri(&fixture("blocks/problem.pddl"));
    let mut found: Vec<(String, Value)> = refs
        .as_array()
        .expect("locations")
        .iter()
        .map(|l| (l["uri"].as_str().unwrap_or("").to_string(), l["range"].clone()))
        .collect();
    found.sort_by_key(|(u, r)| (u.clone(), r["start"]["line"].as_i64()));
    let expected = [
        (uri.clone(), range(6, 5, 6, 13)),
        (uri.clone(), range(11, 24, 11, 32)),
        (uri.clone(), range(12, 33, 12, 41)),
        (problem_uri, range(3, 10, 3, 18)),
    ];
    assert_eq!(found, expected);

    let symbols = client.request("textDocument/documentSymbol", json!({"textDocument": {"uri": uri}}));
    assert_eq!(symbols[0]["name"], "blocks");
    let children: Vec<&str> = symbols[0]["children"]
        .as_array()
        .expect("children")
        .iter()
        .filter_map(|c| c["name"].as_str())
        .collect();
    assert!(children.contains(&"pick-up") && children.contains(&":predicates"), "{children:?}");
    // A section is selected by its keyword, not by its `(`.
    let predicates = symbols[0]["children"].as_array().unwrap().iter().find(|c| c["name"] == ":predicates");
    assert_eq!(predicates.expect(":predicates")["selectionRange"], range(4, 3, 4, 14));

    client.shutdown();
}

/// Document highlights are the occurrences in the document (the problem's
/// are not), the declaration a write; folding ranges are the lists over
/// several lines.
#[test]
fn document_highlights_and_folding_ranges() {
    let mut client = Client::spawn();
    let init = client.initialize(&fixture("blocks"), json!({}));
    assert_eq!(init["capabilities"]["documentHighlightProvider"], true);
    assert_eq!(init["capabilities"]["foldingRangeProvider"], true);
    let (uri, text) = read("blocks/domain.pddl");
    client.open(&uri, &text);
    client.diagnostics(&uri, Some(1));

    let highlights = client.request("textDocument/documentHighlight", at(&uri, 11, 26));
    let write = 3;
    let read = 2;
    assert_eq!(
        highlights,
        json!([
            {"range": range(6, 5, 6, 13), "kind": write},
            {"range": range(11, 24, 11, 32), "kind": read},
            {"range": range(12, 36, 12, 44), "kind": read},
        ])
    );
    // Nothing to highlight on a parenthesis.
    assert_eq!(client.request("textDocument/documentHighlight", at(&uri, 1, 0)), json!([]));

    let folds = client.request("textDocument/foldingRange", json!({"textDocument": {"uri": uri}}));
    assert_eq!(
        folds,
        json!([
            {"startLine": 1, "endLine": 12},
            {"startLine": 4, "endLine": 8},
            {"startLine": 9, "endLine": 12},
        ])
    );
    // A comment of three lines folds as a comment.
    client.change(&uri, 2, range(0, 0, 0, 0), "; one\n; two\n");
    client.diagnostics(&uri, Some(2));
    let folds = client.request("textDocument/foldingRange", json!({"textDocument": {"uri": uri}}));
    assert_eq!(folds[0], json!({"startLine": 0, "endLine": 2, "kind": "comment"}));
    assert_eq!(folds[1], json!({"startLine": 3, "endLine": 14}));
    client.shutdown();
}

/// Rename changes the domain and its problem (loaded from disk, not open);
/// a rename that would merge two names, or with nothing declared to
/// rename, is refused with the reason.
#[test]
fn rename_across_the_domain_and_its_problems() {
    let mut client = Client::spawn();
    let init = client.initialize(&fixture("blocks"), json!({}));
    assert_eq!(init["capabilities"]["renameProvider"]["prepareProvider"], true);
    let (uri, text) = read("blocks/domain.pddl");
    client.open(&uri, &text);
    client.diagnostics(&uri, Some(1));

    let prepared = client.request("textDocument/prepareRename", at(&uri, 11, 26));
    assert_eq!(prepared, json!({"range": range(11, 24, 11, 32), "placeholder": "on-table"}));
    let edit = client.request(
        "textDocument/rename",
        json!({"textDocument": {"uri": uri}, "position": {"line": 11, "character": 26}, "newName": "on-floor"}),
    );
    let problem_uri = file_uri(&fixture("blocks/problem.pddl"));
    let at_ranges = |u: &str| -> Vec<Value> {
        let mut edits: Vec<Value> = edit["changes"][u].as_array().expect("edits of the file").clone();
        edits.sort_by_key(|e| {
            (e["range"]["start"]["line"].as_i64(), e["range"]["start"]["character"].as_i64())
        });
        assert!(edits.iter().all(|e| e["newText"] == "on-floor"), "{edits:?}");
        edits.iter().map(|e| e["range"].clone()).collect()
    };
    assert_eq!(at_ranges(&uri), [range(6, 5, 6, 13), range(11, 24, 11, 32), range(12, 36, 12, 44)]);
    assert_eq!(at_ranges(&problem_uri), [range(3, 10, 3, 18)]);

    let refused = client.request_raw(
        "textDocument/rename",
        json!({"textDocument": {"uri": uri}, "position": {"line": 11, "character": 26}, "newName": "clear"}),
    );
    assert_eq!(refused["error"]["message"], "`clear` is already declared: the two would merge");
    let nothing = client.request_raw("textDocument/prepareRename", at(&uri, 1, 0));
    assert_eq!(nothing["error"]["message"], "no name to rename here");
    client.shutdown();
}

/// A position past the end of the document, or in a document the server does
/// not know, is clamped or answered with nothing, never a crash.
#[test]
fn out_of_range_positions_and_unknown_documents() {
    let mut client = Client::spawn();
    client.initialize(&fixture("blocks"), json!({}));
    let (uri, text) = read("blocks/domain.pddl");
    client.open(&uri, &text);
    client.diagnostics(&uri, Some(1));
    for (line, character) in [(999, 999), (0, 9999), (12, 4000), (u32::MAX, u32::MAX)] {
        let response = client.request_raw("textDocument/hover", at(&uri, line, character));
        assert!(response.get("error").is_none(), "{response}");
        let response = client.request_raw("textDocument/definition", at(&uri, line, character));
        assert!(response.get("error").is_none(), "{response}");
    }
    let unknown = "file:///nowhere/x.pddl";
    assert_eq!(client.request("textDocument/hover", at(unknown, 0, 0)), Value::Null);
    // A change out of range is clamped: appending after the end still works.
    client.change(&uri, 2, range(400, 0, 400, 0), "\n; the end\n");
    let diags = client.diagnostics(&uri, Some(2));
    assert_eq!(codes(&diags), ["E0102"]);
    // The server still answers.
    assert!(client.request("textDocument/hover", at(&uri, 11, 26)).is_object());
    client.shutdown();
}

/// Columns count UTF-16 units by default and bytes once UTF-8 is negotiated;
/// incremental edits use the same unit.
#[test]
fn utf16_by_default_utf8_when_negotiated() {
    let (uri, text) = read("unicode/domain.pddl");
    // `    :effect (and (été ?x) (😀 ?x))))`: `été` is 3 UTF-16 units but 5 bytes; 😀 is 2 units, 4 bytes.
    for (capabilities, encoding, start, end) in [
        (json!({}), "utf-16", 27, 29),
        (json!({"general": {"positionEncodings": ["utf-16", "utf-8"]}}), "utf-8", 29, 33),
    ] {
        let mut client = Client::spawn();
        let init = client.initialize(&fixture("unicode"), capabilities);
        assert_eq!(init["capabilities"]["positionEncoding"], encoding);
        client.open(&uri, &text);
        let diags = client.diagnostics(&uri, Some(1));
        assert_eq!(find(&diags, "E0102")["range"], range(7, start, 7, end), "{encoding}");
        assert_eq!(
            find(&diags, "W0201")["tags"],
            json!([1]),
            "unused `prêt` is tagged unnecessary: {diags:#?}"
        );
        // Replace 😀 by `prêt`, in the negotiated unit.
        client.change(&uri, 2, range(7, start, 7, end), "prêt");
        assert_eq!(client.diagnostics(&uri, Some(2)), Vec::<Value>::new(), "{encoding}");
        // Hover on `prêt`, just inserted after the non-ASCII `été`.
        let hover = client.request("textDocument/hover", at(&uri, 7, start + 1));
        assert!(hover["contents"]["value"].as_str().unwrap_or("").contains("predicate (prêt ?x)"), "{hover}");
        assert_eq!(hover["range"]["start"]["character"], start);
        client.shutdown();
    }
}

/// A burst of changes: diagnostics come for the last version, versions never
/// go back, and a change with an old version is rejected.
#[test]
fn stale_versions_are_never_published() {
    let mut client = Client::spawn();
    client.initialize(&fixture("blocks"), json!({}));
    let (uri, text) = read("blocks/domain.pddl");
    client.open(&uri, &text);
    client.diagnostics(&uri, Some(1));
    // Type `held` over `holding` one keystroke at a time: h, he, hel, held...
    let mut version = 1;
    let target = "held";
    for n in 1..=target.len() {
        version += 1;
        let end = if n == 1 { 25 } else { 18 + n as u32 - 1 };
        client.change(&uri, version, range(12, 18, 12, end), &target[..n]);
    }
    assert_eq!(client.diagnostics(&uri, Some(version)), Vec::<Value>::new());
    let versions = client.published_versions(&uri);
    assert!(versions.windows(2).all(|w| w[0] <= w[1]), "versions went back: {versions:?}");
    assert_eq!(versions.last(), Some(&version));

    // An old version is ignored (and logged); the text stays the same.
    client.change(&uri, 2, range(12, 18, 12, 22), "holding");
    client.wait_for("a warning", |n| {
        n["method"] == "window/logMessage"
            && n["params"]["message"].as_str().unwrap_or("").contains("ignored version")
    });
    let definition = client.request("textDocument/definition", at(&uri, 12, 19));
    assert_eq!(definition["range"], range(8, 5, 8, 9), "`held` is still there");
    client.shutdown();
}

/// Editing a domain re-publishes the diagnostics of its open problems.
#[test]
fn a_problem_follows_its_domain() {
    let mut client = Client::spawn();
    client.initialize(&fixture("blocks"), json!({}));
    let (domain_uri, domain) = read("blocks/domain.pddl");
    let (problem_uri, problem) = read("blocks/problem.pddl");
    client.open(&problem_uri, &problem);
    assert_eq!(client.diagnostics(&problem_uri, Some(1)), Vec::<Value>::new());
    client.open(&domain_uri, &domain);
    client.diagnostics(&domain_uri, Some(1));
    // Rename the declaration of `held`: the problem's goal no longer resolves.
    client.change(&domain_uri, 2, range(8, 5, 8, 9), "grasped");
    let diags = client.diagnostics(&problem_uri, Some(1));
    let undefined = find(&diags, "E0102");
    assert_eq!(undefined["range"], range(4, 10, 4, 14));
    client.shutdown();
}

/// A domain that starts with a UTF-8 byte-order mark: loaded from disk, its
/// positions are those the editor shows (without the mark); opened with the
/// mark in its text, it reads without error and the mark is one character.
#[test]
fn a_byte_order_mark_is_not_a_character_of_the_file() {
    let mut client = Client::spawn();
    client.initialize(&fixture("bom"), json!({}));
    let (domain_uri, domain) = read("bom/domain.pddl");
    assert!(domain.starts_with('\u{feff}'), "the fixture starts with a byte-order mark");
    let (problem_uri, problem) = read("bom/problem.pddl");
    client.open(&problem_uri, &problem);
    assert_eq!(client.diagnostics(&problem_uri, Some(1)), Vec::<Value>::new());
    // `ready` in `(:init (ready))`, declared on the domain's first line at
    // character 35 as the editor counts (36 with the mark).
    let definition = client.request("textDocument/definition", at(&problem_uri, 1, 11));
    assert_eq!(definition["uri"], domain_uri);
    assert_eq!(definition["range"], range(0, 35, 0, 40));

    client.open(&domain_uri, &domain);
    assert_eq!(client.diagnostics(&domain_uri, Some(1)), Vec::<Value>::new());
    client.change(&domain_uri, 2, range(0, 36, 0, 41), "prêt");
    let diags = client.diagnostics(&domain_uri, Some(2));
    assert_eq!(codes(&diags), ["W0201", "E0102"], "{diags:#?}");
    assert_eq!(find(&diags, "W0201")["range"], range(0, 36, 0, 40));
    client.shutdown();
}

/// A fix of the analyzer is offered as a quick fix; its related location is in another file.
#[test]
fn quick_fix_and_related_information() {
    let mut client = Client::spawn();
    client.initialize(&fixture("blocks"), json!({}));
    let uri = file_uri(&fixture("blocks/unsaved.pddl"));
    client.open(&uri, "(define (problem p) (:domain blocs)\n  (:objects a - block)\n  (:init (clear a)) (:goal (held a)))\n");
    let diags = client.diagnostics(&uri, Some(1));
    let mismatch = find(&diags, "W0205");
    assert_eq!(mismatch["range"], range(0, 29, 0, 34));
    let related = &mismatch["relatedInformation"][0]["location"];
    assert_eq!(related["uri"], file_uri(&fixture("blocks/domain.pddl")));
    assert_eq!(related["range"], range(1, 16, 1, 22));

    let actions = client.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": uri}, "range": range(0, 30, 0, 30), "context": {"diagnostics": []}}),
    );
    let action = &actions[0];
    assert_eq!(action["kind"], "quickfix");
    assert_eq!(action["title"], "use domain `blocks`");
    assert_eq!(action["edit"]["changes"][&uri], json!([{"range": range(0, 29, 0, 34), "newText": "blocks"}]));
    let refactors = client.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": uri}, "range": range(0, 30, 0, 30), "context": {"diagnostics": [], "only": ["refactor"]}}),
    );
    assert_eq!(refactors, json!([]));

    // Closing clears the document's diagnostics.
    client.notify("textDocument/didClose", json!({"textDocument": {"uri": uri}}));
    client.wait_for("cleared diagnostics", |n| {
        n["method"] == "textDocument/publishDiagnostics"
            && n["params"]["uri"] == uri
            && n["params"]["diagnostics"] == json!([])
    });
    client.shutdown();
}

/// The fix of a domain lint (E0301: add the missing conflict) is a quick fix too.
#[test]
fn quick_fix_of_a_lint() {
    let mut client = Client::spawn();
    client.initialize(&fixture("blocks"), json!({}));
    let uri = file_uri(&fixture("blocks/unsaved-patrol.hddl"));
    let text = "(define (domain patrol) (:requirements :hierarchy) (:predicates (at ?r ?w))
  (:action move :parameters (?r ?a ?b) :precondition (at ?r ?a) :effect (and (not (at ?r ?a)) (at ?r ?b)))
  (:task go :parameters (?r) :conflicts (and))
  (:method m :parameters (?r ?a ?b) :task (go ?r) :subtasks (and (move ?r ?a ?b))))
";
    client.open(&uri, text);
    let diags = client.diagnostics(&uri, Some(1));
    let uncovered = find(&diags, "E0301");
    assert_eq!(uncovered["range"], range(2, 29, 2, 39), "on `:conflicts`");
    let actions = client.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": uri}, "range": range(2, 31, 2, 31), "context": {"diagnostics": []}}),
    );
    let action = &actions[0];
    assert_eq!(action["title"], "add `(at ?r ?a)` to the conflicts of `go`");
    assert_eq!(
        action["edit"]["changes"][&uri],
        json!([{"range": range(2, 44, 2, 44), "newText": " (at ?r ?a)"}])
    );
    client.shutdown();
}

/// An undeclared predicate can be declared, with the arity and types of its
/// use, at the end of `:predicates`.
#[test]
fn an_undeclared_predicate_is_declared_by_a_code_action() {
    let mut client = Client::spawn();
    client.initialize(&fixture("blocks"), json!({}));
    let (uri, text) = read("blocks/domain.pddl");
    client.open(&uri, &text);
    assert_eq!(codes(&client.diagnostics(&uri, Some(1))), ["E0102"]);
    let actions = client.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": uri}, "range": range(12, 20, 12, 20), "context": {"diagnostics": []}}),
    );
    let declare = actions
        .as_array()
        .expect("actions")
        .iter()
        .find(|a| a["title"] == "declare `(holding ?b - block)` in `:predicates`")
        .unwrap_or_else(|| panic!("no declaration among {actions:#}"));
    assert_eq!(declare["kind"], "quickfix");
    assert_eq!(
        declare["edit"]["changes"][&uri],
        json!([{"range": range(8, 21, 8, 21), "newText": " (holding ?b - block)"}])
    );
    client.shutdown();
}

/// The labels of a completion answer.
fn labels(items: &Value) -> Vec<&str> {
    items.as_array().expect("completion items").iter().filter_map(|i| i["label"].as_str()).collect()
}

/// Completion replaces the word being typed, counted in UTF-16 units; a
/// problem's arguments are its objects, of the parameter's type first; the
/// skeleton of a problem is a snippet for the clients that take snippets,
/// and plain text for the others.
#[test]
fn completion_by_context() {
    let snippets = json!({"textDocument": {"completion": {"completionItem": {"snippetSupport": true}}}});
    let mut client = Client::spawn();
    let init = client.initialize(&fixture("blocks"), snippets);
    assert_eq!(init["capabilities"]["completionProvider"]["triggerCharacters"], json!(["(", "?", ":"]));
    let uri = file_uri(&fixture("blocks/scratch-problem.pddl"));
    let text = "(define (problem p) (:domain blocks)\n  (:objects bé1 - block)\n  (:init (on-table bé";
    client.open(&uri, text);
    client.diagnostics(&uri, Some(1));
    // After `bé`: two UTF-16 units from column 19 (three bytes).
    let items = client.request("textDocument/completion", at(&uri, 2, 21));
    assert_eq!(labels(&items), ["bé1"]);
    assert_eq!(items[0]["kind"], 12, "an object is a value");
    assert_eq!(items[0]["detail"], "object bé1 - block");
    assert_eq!(items[0]["textEdit"], json!({"range": range(2, 19, 2, 21), "newText": "bé1"}));
    // After `(`: the predicates with their signatures, and `not`.
    client.change(&uri, 2, range(2, 9, 2, 21), "(");
    client.diagnostics(&uri, Some(2));
    let items = client.request("textDocument/completion", at(&uri, 2, 10));
    assert_eq!(labels(&items)[..3], ["clear", "held", "on-table"]);
    assert_eq!(items[0]["detail"], "predicate (clear ?b - block)");
    assert_eq!(items[0]["textEdit"]["range"], range(2, 10, 2, 10));

    let new = file_uri(&fixture("blocks/scratch-new.pddl"));
    client.open(&new, "(");
    client.diagnostics(&new, Some(1));
    let items = client.request("textDocument/completion", at(&new, 0, 1));
    let skeleton = items.as_array().unwrap().iter().find(|i| i["kind"] == 15).expect("a snippet");
    assert_eq!(skeleton["insertTextFormat"], 2);
    let body = skeleton["textEdit"]["newText"].as_str().unwrap();
    assert!(body.starts_with("define (problem ${1:name})\n  (:domain ${2:blocks})"), "{body}");
    client.shutdown();

    // Without snippets, the skeleton is its text.
    let mut client = Client::spawn();
    client.initialize(&fixture("blocks"), json!({}));
    client.open(&new, "(");
    client.diagnostics(&new, Some(1));
    let items = client.request("textDocument/completion", at(&new, 0, 1));
    let skeleton = items.as_array().unwrap().iter().find(|i| i["kind"] == 15).expect("a snippet");
    assert_eq!(skeleton["insertTextFormat"], 1);
    let body = skeleton["textEdit"]["newText"].as_str().unwrap();
    assert!(body.starts_with("define (problem name)\n  (:domain blocks)") && !body.contains('$'), "{body}");
    client.shutdown();
}

/// Semantic tokens, absolute: (line, start, length, type, modifiers).
fn decode(tokens: &Value) -> Vec<(u64, u64, u64, u64, u64)> {
    let data: Vec<u64> = tokens["data"].as_array().expect("data").iter().filter_map(Value::as_u64).collect();
    let (mut line, mut start) = (0, 0);
    data.chunks(5)
        .map(|t| {
            line += t[0];
            start = if t[0] == 0 { start + t[1] } else { t[1] };
            (line, start, t[2], t[3], t[4])
        })
        .collect()
}

/// Semantic tokens count columns in the negotiated unit: `été` is 3 UTF-16
/// units and 5 bytes; a predicate is a function, its declaration marked;
/// a range asks for its lines only.
#[test]
fn semantic_tokens_in_the_negotiated_encoding() {
    let (uri, text) = read("unicode/domain.pddl");
    for (capabilities, ete, emoji) in [
        (json!({}), (18, 3), (27, 2)),
        (json!({"general": {"positionEncodings": ["utf-8"]}}), (18, 5), (29, 4)),
    ] {
        let mut client = Client::spawn();
        let init = client.initialize(&fixture("unicode"), capabilities);
        let provider = &init["capabilities"]["semanticTokensProvider"];
        let types: Vec<&str> =
            provider["legend"]["tokenTypes"].as_array().unwrap().iter().filter_map(|t| t.as_str()).collect();
        let modifiers: Vec<&str> = provider["legend"]["tokenModifiers"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|t| t.as_str())
            .collect();
        assert_eq!(provider["full"], true);
        let function = types.iter().position(|t| *t == "function").unwrap() as u64;
        let comment = types.iter().position(|t| *t == "comment").unwrap() as u64;
        let declaration = 1 << modifiers.iter().position(|m| *m == "declaration").unwrap();
        client.open(&uri, &text);
        client.diagnostics(&uri, Some(1));
        let tokens = decode(
            &client.request("textDocument/semanticTokens/full", json!({"textDocument": {"uri": uri}})),
        );
        let first_line = text.lines().next().unwrap();
        let units = if ete.1 == 3 { first_line.encode_utf16().count() } else { first_line.len() };
        assert_eq!(tokens[0], (0, 0, units as u64, comment, 0));
        assert!(tokens.contains(&(3, 16, ete.1, function, declaration)), "{tokens:?}");
        assert!(tokens.contains(&(7, ete.0, ete.1, function, 0)), "{tokens:?}");
        assert!(tokens.contains(&(7, emoji.0, emoji.1, function, 0)), "{tokens:?}");
        let line7 = client.request(
            "textDocument/semanticTokens/range",
            json!({"textDocument": {"uri": uri}, "range": range(7, 0, 8, 0)}),
        );
        let line7 = decode(&line7);
        assert!(line7.iter().all(|t| t.0 == 7), "{line7:?}");
        assert_eq!(line7, tokens.iter().copied().filter(|t| t.0 == 7).collect::<Vec<_>>());
        client.shutdown();
    }
}

/// In a domain without `:requirements` nor `:predicates`, the quick fixes
/// make them: the requirement after the domain's name, the predicate after
/// the types.
#[test]
fn missing_sections_are_made_by_code_actions() {
    let mut client = Client::spawn();
    client.initialize(&fixture("blocks"), json!({}));
    let uri = file_uri(&fixture("blocks/scratch-bare.pddl"));
    let text = "(define (domain bare)\n  (:types block)\n  (:action a :parameters (?b - block) :effect (ready ?b)))\n";
    client.open(&uri, text);
    assert_eq!(codes(&client.diagnostics(&uri, Some(1))), ["W0203", "E0102"]);
    let actions = client.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": uri}, "range": range(0, 0, 3, 0), "context": {"diagnostics": []}}),
    );
    let edits: Vec<(&str, &str, Value)> = actions
        .as_array()
        .expect("actions")
        .iter()
        .map(|a| {
            (a["title"].as_str().unwrap(), a["kind"].as_str().unwrap(), a["edit"]["changes"][&uri].clone())
        })
        .collect();
    assert!(
        edits.contains(&(
            "add `(:requirements :typing)`",
            "quickfix",
            json!([{"range": range(0, 21, 0, 21), "newText": "\n  (:requirements :typing)"}])
        )),
        "{edits:#?}"
    );
    assert!(
        edits.contains(&(
            "declare `(ready ?b - block)` in a new `:predicates`",
            "quickfix",
            json!([{"range": range(1, 16, 1, 16), "newText": "\n  (:predicates (ready ?b - block))"}])
        )),
        "{edits:#?}"
    );
    client.shutdown();
}

/// A copy of the `blocks` fixture in a fresh folder, to change on disk.
fn scratch_copy(name: &str) -> Scratch {
    Scratch::with_fixture(&format!("lsp-{name}"), "blocks", &["domain.pddl", "problem.pddl"])
}

/// A domain changed or deleted on disk, reported by the client's file watcher,
/// changes the diagnostics of its open problem.
#[test]
fn watched_files_are_reread() {
    let dir = scratch_copy("watch");
    let mut client = Client::spawn();
    client.initialize(&dir, json!({"workspace": {"didChangeWatchedFiles": {"dynamicRegistration": true}}}));
    let registration = client.wait_for("registerCapability", |m| m["method"] == "client/registerCapability");
    let registered = &registration["params"]["registrations"][0];
    assert_eq!(registered["method"], "workspace/didChangeWatchedFiles");
    assert_eq!(registered["registerOptions"]["watchers"][0]["globPattern"], "**/*.{pddl,hddl}");

    let problem = dir.join("problem.pddl");
    let problem_uri = file_uri(&problem);
    client.open(&problem_uri, &std::fs::read_to_string(&problem).expect("problem"));
    assert_eq!(client.diagnostics(&problem_uri, Some(1)), Vec::<Value>::new());

    let domain = dir.join("domain.pddl");
    let text = std::fs::read_to_string(&domain).expect("domain");
    std::fs::write(&domain, text.replace("(held ?b - block)", "(grasped ?b - block)")).expect("writing");
    let changed = json!({"changes": [{"uri": file_uri(&domain), "type": 2}]});
    client.notify("workspace/didChangeWatchedFiles", changed);
    assert_eq!(codes(&client.diagnostics(&problem_uri, Some(1))), ["E0102"]);

    std::fs::remove_file(&domain).expect("deleting");
    client.notify(
        "workspace/didChangeWatchedFiles",
        json!({"changes": [{"uri": file_uri(&domain), "type": 3}]}),
    );
    assert_eq!(codes(&client.diagnostics(&problem_uri, Some(1))), ["E0114"]);
    // The client watches: the server does not watch too.
    assert!(!client.log.iter().any(|m| log_says(m, "for changes on disk")), "{:#?}", client.log);
    client.shutdown();
}

fn log_says(message: &Value, text: &str) -> bool {
    message["method"] == "window/logMessage"
        && message["params"]["message"].as_str().is_some_and(|m| m.contains(text))
}

/// A client that does not watch files for the server (Neovim's default), that
/// refuses to, or that reports only its own writes (Helix): the server
/// watches the workspace itself. A domain changed, deleted, then created in
/// a new folder, all on disk and unknown to the client, changes the
/// diagnostics of its open problem.
#[test]
fn files_changed_on_disk_are_reread_without_a_client_watcher() {
    let watching = json!({"workspace": {"didChangeWatchedFiles": {"dynamicRegistration": true}}});
    let helix = json!({"name": "helix", "version": "25.07.1"});
    for (name, capabilities, client_info) in [
        ("no-watcher", json!({}), Value::Null),
        ("refusing", watching.clone(), Value::Null),
        ("helix", watching, helix),
    ] {
        let dir = scratch_copy(name);
        let mut client = Client::spawn();
        client.refuse.push("client/registerCapability");
        client.initialize_as(&dir, capabilities, client_info);
        client.wait_for("the server's watch", |m| log_says(m, "watching 1 folders for changes on disk"));
        let registered = client.log.iter().any(|m| m["method"] == "client/registerCapability");
        assert_eq!(registered, name == "refusing", "{name}");

        let problem = dir.join("problem.pddl");
        let problem_uri = file_uri(&problem);
        client.open(&problem_uri, &std::fs::read_to_string(&problem).expect("problem"));
        assert_eq!(client.diagnostics(&problem_uri, Some(1)), Vec::<Value>::new(), "{name}");

        let domain = dir.join("domain.pddl");
        let text = std::fs::read_to_string(&domain).expect("domain");
        std::fs::write(&domain, text.replace("(held ?b - block)", "(grasped ?b - block)")).expect("writing");
        assert_eq!(codes(&client.diagnostics(&problem_uri, Some(1))), ["E0102"], "{name}");

        std::fs::remove_file(&domain).expect("deleting");
        assert_eq!(codes(&client.diagnostics(&problem_uri, Some(1))), ["E0114"], "{name}");

        // A folder that appears (a checkout) is loaded and watched.
        std::fs::create_dir(dir.join("models")).expect("a new folder");
        std::fs::write(dir.join("models/domain.pddl"), &text).expect("writing");
        assert_eq!(client.diagnostics(&problem_uri, Some(1)), Vec::<Value>::new(), "{name}");
        std::fs::write(dir.join("models/domain.pddl"), text.replace("(held ?b", "(grasped ?b"))
            .expect("writing");
        assert_eq!(codes(&client.diagnostics(&problem_uri, Some(1))), ["E0102"], "{name}");
        client.shutdown();
    }
}

/// A workspace folder added later brings its domain; removed, takes it away.
/// The problem is an unsaved buffer whose URI is not a file.
#[test]
fn workspace_folders_come_and_go() {
    let empty = Scratch::new("lsp-empty");
    let mut client = Client::spawn();
    client.initialize(&empty, json!({}));
    let uri = "untitled:Untitled-1";
    client.open(uri, "(define (problem p) (:domain blocks)\n  (:objects a - block)\n  (:init (clear a)) (:goal (held a)))\n");
    assert_eq!(codes(&client.diagnostics(uri, Some(1))), ["E0114"]);

    let folder = json!([{"uri": file_uri(&fixture("blocks")), "name": "blocks"}]);
    client.notify("workspace/didChangeWorkspaceFolders", json!({"event": {"added": folder, "removed": []}}));
    assert_eq!(client.diagnostics(uri, Some(1)), Vec::<Value>::new());
    let definition = client.request("textDocument/definition", at(uri, 2, 29));
    assert_eq!(definition["uri"], file_uri(&fixture("blocks/domain.pddl")));

    client.notify("workspace/didChangeWorkspaceFolders", json!({"event": {"added": [], "removed": folder}}));
    assert_eq!(codes(&client.diagnostics(uri, Some(1))), ["E0114"]);
    client.shutdown();
}

/// Changes interleaved with requests on a large file: every request is
/// answered (a result, or `ContentModified` when a change overtook it), the
/// last version's diagnostics arrive, and nothing hangs.
#[test]
fn requests_racing_with_changes() {
    let root = common::workspace_root().join("samples/surveillance");
    let mut client = Client::spawn();
    client.initialize(&root, json!({}));
    let path = root.join("problem.pddl");
    let uri = file_uri(&path);
    client.open(&uri, &std::fs::read_to_string(&path).expect("sample"));
    let mut pending = Vec::new();
    let last = 41;
    for version in 2..=last {
        // Type a comment at the top, one character per change.
        let col = (version - 2) as u32;
        client.change(&uri, version, range(0, col, 0, col), if version == 2 { ";" } else { "x" });
        // On the domain name in `(:domain surveillance)`.
        pending.push(client.send_request("textDocument/hover", at(&uri, 11, 14)));
        pending
            .push(client.send_request("textDocument/documentSymbol", json!({"textDocument": {"uri": uri}})));
        pending.push(client.send_request(
            "textDocument/references",
            json!({"textDocument": {"uri": uri}, "position": {"line": 11, "character": 14}, "context": {"includeDeclaration": true}}),
        ));
    }
    let mut final_diagnostics = false;
    while !pending.is_empty() || !final_diagnostics {
        let message = client.recv();
        if Client::is_response(&message) {
            let id = message["id"].as_i64().expect("an id");
            assert!(pending.contains(&id), "unexpected response {message}");
            pending.retain(|&p| p != id);
            if let Some(error) = message.get("error") {
                assert_eq!(error["code"], -32801, "only ContentModified is acceptable: {message}");
            }
        } else if message["method"] == "textDocument/publishDiagnostics" && message["params"]["uri"] == uri {
            final_diagnostics = message["params"]["version"] == last;
        }
    }
    let versions = client.published_versions(&uri);
    assert!(versions.windows(2).all(|w| w[0] <= w[1]), "versions went back: {versions:?}");
    client.shutdown();
}

/// A plan open next to its domain and problem (found by its file name) is
/// validated live: the failures are its diagnostics, and an edit that fixes
/// the plan clears them.
#[test]
fn a_plan_is_validated_against_its_problem() {
    let mut client = Client::spawn();
    client.initialize(&fixture("plan"), json!({}));
    let (uri, text) = read("plan/problem.plan");
    client.open(&uri, &text);
    let diags = client.diagnostics(&uri, Some(1));
    assert_eq!(codes(&diags), ["E0419"], "{diags:#?}");
    // Hover on a step: its action, its time window, its verdict.
    let hover = client.request("textDocument/hover", at(&uri, 1, 10));
    let markdown = hover["contents"]["value"].as_str().expect("markdown hover");
    assert!(markdown.contains("durative action (drive ?r - robot ?from ?to - place)"), "{markdown}");
    assert!(markdown.contains("from 0.000 to 5.000 (duration 5.000)"), "{markdown}");
    assert!(markdown.ends_with("**valid**"), "{markdown}");
    assert_eq!(hover["range"], range(1, 0, 1, 34));
    // Go to definition: from the step's action to the domain.
    let definition = client.request("textDocument/definition", at(&uri, 1, 10));
    assert_eq!(
        definition,
        json!({"uri": file_uri(&fixture("plan/domain.pddl")), "range": range(5, 20, 5, 25)})
    );
    // Delete the drive back home (line 2).
    client.change(&uri, 2, range(2, 0, 3, 0), "");
    assert_eq!(client.diagnostics(&uri, Some(2)), Vec::<Value>::new());
    client.shutdown();
}

/// `workspace/symbol` (Helix's Space S): the declarations of every file of the
/// workspace, open or not, matched by the query.
#[test]
fn workspace_symbols_cover_files_not_open() {
    let mut client = Client::spawn();
    let init = client.initialize(&fixture("blocks"), json!({}));
    assert_eq!(init["capabilities"]["workspaceSymbolProvider"], true);
    let symbols = client.request("workspace/symbol", json!({"query": "pkup"}));
    assert_eq!(
        symbols,
        json!([{
            "name": "pick-up",
            "kind": 12,
            "location": {"uri": file_uri(&fixture("blocks/domain.pddl")), "range": range(9, 11, 9, 18)},
            "containerName": "blocks",
        }])
    );
    let names: Vec<String> = client
        .request("workspace/symbol", json!({"query": ""}))
        .as_array()
        .expect("symbols")
        .iter()
        .filter_map(|s| s["name"].as_str().map(String::from))
        .collect();
    for name in ["blocks", "block", "on-table", "clear", "held", "pick-up", "a"] {
        assert!(names.iter().any(|n| n == name), "{name} in {names:?}");
    }
    client.shutdown();
}

/// Hostile documents: a million nested lists, a million `(`, 200,000 `)`,
/// a thousand errors. The server publishes a few located diagnostics for
/// each (lists deeper than 256 are kept as text, runs of one error are one
/// diagnostic, at most 200 per document), and keeps answering.
#[test]
fn hostile_documents_leave_the_server_answering() {
    let mut client = Client::spawn();
    client.initialize(&fixture("blocks"), json!({}));
    let uri = |name: &str| file_uri(&fixture(&format!("blocks/{name}")));

    let n = 1_000_000;
    let deep = format!(
        "(define (domain deep) (:predicates (p ?x))\n  (:action a :parameters (?x) :precondition {}(p ?x){} :effect (p ?x)))\n",
        "(and ".repeat(n),
        ")".repeat(n)
    );
    client.open(&uri("deep.pddl"), &deep);
    let diags = client.diagnostics(&uri("deep.pddl"), Some(1));
    assert_eq!(codes(&diags), ["E0007"]);
    // The `(and` inside 256 lists: define, action, and 254 `(and` from column 44.
    assert_eq!(diags[0]["range"]["start"], json!({"line": 1, "character": 44 + 5 * 254}));
    // The effect's `p`, after the million lists kept as text.
    let effect = deep.rfind("(p ?x)))").expect("the effect") + 1;
    let column = (effect - deep.find('\n').expect("two lines") - 1) as u32;
    let hover = client.request("textDocument/hover", at(&uri("deep.pddl"), 1, column));
    let markdown = hover["contents"]["value"].as_str().expect("markdown hover");
    assert!(markdown.contains("predicate (p ?x)"), "{markdown}");
    // An edit next to the deepest list read still re-checks.
    client.change(&uri("deep.pddl"), 2, range(1, column, 1, column + 1), "q");
    // `q` is undefined, and `p` unused now: the precondition is kept as text.
    assert_eq!(codes(&client.diagnostics(&uri("deep.pddl"), Some(2))), ["W0201", "E0007", "E0102"]);

    client.open(&uri("open.pddl"), &"(".repeat(n));
    assert_eq!(codes(&client.diagnostics(&uri("open.pddl"), Some(1))), ["E0003", "E0007", "E0001"]);

    client.open(&uri("close.pddl"), &")".repeat(200_000));
    let diags = client.diagnostics(&uri("close.pddl"), Some(1));
    assert_eq!(codes(&diags), ["E0002"]);
    assert_eq!(diags[0]["range"], range(0, 0, 0, 200_000));

    client.open(&uri("many.pddl"), &") x".repeat(1000));
    let diags = client.diagnostics(&uri("many.pddl"), Some(1));
    assert_eq!(diags.len(), 201);
    assert_eq!(diags[200]["code"], "I0008");
    assert_eq!(diags[200]["severity"], 3);

    // Saving them plans nothing (no problem), and the plan requests answer.
    for name in ["deep.pddl", "open.pddl", "close.pddl", "many.pddl"] {
        client.notify("textDocument/didSave", json!({"textDocument": {"uri": uri(name)}}));
        let whole = json!({"textDocument": {"uri": uri(name)}, "range": range(0, 0, 10, 0)});
        assert_eq!(client.request("textDocument/inlayHint", whole), Value::Null);
        assert_eq!(client.request("hipop/plan", json!({"uri": uri(name)})), Value::Null);
        assert_eq!(client.request("hipop/planDiff", json!({"uri": uri(name)})), Value::Null);
        for (line, character) in [(0, 0), (0, 1), (1, 44 + 5 * 300), (0, 199_999)] {
            let answer = client.request_raw("textDocument/completion", at(&uri(name), line, character));
            assert!(answer.get("error").is_none(), "{name}: {answer}");
        }
        let document = json!({"textDocument": {"uri": uri(name)}});
        let answer = client.request_raw("textDocument/semanticTokens/full", document);
        assert!(answer["result"]["data"].is_array(), "{name}: {answer}");
    }
    let symbols =
        client.request("textDocument/documentSymbol", json!({"textDocument": {"uri": uri("deep.pddl")}}));
    assert_eq!(symbols[0]["name"], "deep");
    client.shutdown();
}

/// The text with LSP edits applied (positions in UTF-16 code units).
fn apply_edits(text: &str, edits: &Value) -> String {
    let offset = |pos: &Value| {
        let (line, character) = (pos["line"].as_u64().unwrap() as usize, pos["character"].as_u64().unwrap());
        let start: usize = text.split_inclusive('\n').take(line).map(str::len).sum();
        let mut units = 0;
        let rest = &text[start..];
        let col = rest.char_indices().find(|(_, c)| {
            let found = units >= character;
            units += c.len_utf16() as u64;
            found
        });
        start + col.map_or(rest.len(), |(i, _)| i)
    };
    let mut edits: Vec<&Value> = edits.as_array().expect("edits").iter().collect();
    edits.sort_by_key(|e| std::cmp::Reverse(offset(&e["range"]["start"])));
    let mut out = text.to_string();
    for e in edits {
        let (a, b) = (offset(&e["range"]["start"]), offset(&e["range"]["end"]));
        out.replace_range(a..b, e["newText"].as_str().expect("newText"));
    }
    out
}

/// `textDocument/formatting` gives what `hipop fmt` writes, as edits of the
/// lines that change; nothing to do on a formatted document; no answer on a
/// document with a syntax error, or a plan.
#[test]
fn formatting_gives_what_hipop_fmt_writes() {
    use std::io::Write;
    let mut client = Client::spawn();
    let init = client.initialize(&fixture("blocks"), json!({}));
    assert_eq!(init["capabilities"]["documentFormattingProvider"], true);
    let (uri, _) = read("blocks/domain.pddl");
    // Laid out carelessly, with a comment and a name out of the ASCII range.
    let text = "; Blocks.\n(define (domain blocks) (:requirements :strips :typing)\n(:types block) ; the blocks\n(:predicates (on-table ?b - block) (clear ?b - block) (held ?b - block) (été ?b - block))\n(:action pick-up :parameters (?b - block) :precondition (and (on-table ?b) (clear ?b)) :effect (and (held ?b) (not (on-table ?b)))))\n";
    client.open(&uri, text);
    client.diagnostics(&uri, Some(1));
    let format = |client: &mut Client| {
        client.request(
            "textDocument/formatting",
            json!({"textDocument": {"uri": uri}, "options": {"tabSize": 2, "insertSpaces": true}}),
        )
    };
    let edits = format(&mut client);
    assert_eq!(edits.as_array().map(Vec::len), Some(1), "{edits}");
    // The first line does not change: it is not in the edit.
    assert_eq!(edits[0]["range"]["start"], json!({"line": 1, "character": 0}));
    let formatted = apply_edits(text, &edits);

    let mut fmt = std::process::Command::new(common::hipop_bin())
        .args(["fmt", "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("hipop fmt runs");
    fmt.stdin.take().expect("stdin").write_all(text.as_bytes()).expect("written");
    let out = fmt.wait_with_output().expect("hipop fmt exits");
    assert!(out.status.success());
    assert_eq!(formatted, String::from_utf8(out.stdout).expect("UTF-8"));

    // Formatted, it stays as it is.
    client.change(&uri, 2, range(0, 0, 5, 0), &formatted);
    client.diagnostics(&uri, Some(2));
    assert_eq!(format(&mut client), json!([]));
    // A syntax error: no answer.
    client.change(&uri, 3, range(0, 0, 0, 0), "(");
    client.diagnostics(&uri, Some(3));
    assert_eq!(format(&mut client), Value::Null);
    // A plan is not formatted.
    let (plan, plan_text) = read("plan/problem.plan");
    client.open(&plan, &plan_text);
    let answer = client.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": plan}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    assert_eq!(answer, Value::Null);
    client.shutdown();
}
