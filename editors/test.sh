#!/usr/bin/env bash
# Checks the editor integrations:
#   - editors/helix/languages.toml parses as TOML and declares the hipop-pddl,
#     hipop-plan and hipop-plan-json languages with the hipop server; the
#     queries it needs exist (needs python3 >= 3.11)
#   - editors/vscode: npm ci && npm run compile && npm test, whose
#     test/lsp.test.js drives `hipop lsp` (HIPOP_BIN, else the workspace's
#     target/debug/hipop, which scripts/test's `cargo test` builds first; it
#     is skipped, and says so, without either); the end-to-end
#     test in a real VS Code (editors/vscode/e2e/run, run before each
#     release: it installs code-server) is only checked to parse here
# Exits non-zero on any failure. Missing node/npm (or python3 >= 3.11) is
# reported as SKIP and does not fail the run.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

echo "== editors: helix/languages.toml"
if command -v python3 >/dev/null 2>&1 && python3 -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else 1)'; then
  python3 - "$here/helix/languages.toml" <<'PY'
import os, sys, tomllib
path = sys.argv[1]
with open(path, "rb") as f:
    conf = tomllib.load(f)
server = conf["language-server"]["hipop"]
assert server["command"] == "hipop" and server["args"] == ["lsp"], server
names = [l["name"] for l in conf["language"]]
assert names == ["hipop-pddl", "hipop-plan", "hipop-plan-json"], names
langs = {l["name"]: l for l in conf["language"]}
for name, lang in langs.items():
    assert lang["language-servers"] == ["hipop"], lang
    assert lang["scope"] == f"source.{name}", lang
lang = langs["hipop-pddl"]
assert lang["file-types"] == ["pddl", "hddl"], lang
assert lang["comment-token"] == ";", lang
# Plans: the names the server reads as plans (docs/plan-formats.md).
lang = langs["hipop-plan"]
assert lang["file-types"] == ["plan", "soln", "sol"], lang
assert lang["comment-token"] == ";", lang
lang = langs["hipop-plan-json"]
assert lang["file-types"] == [{"glob": "*.plan.json"}], lang
assert lang["grammar"] == "json", lang
assert "comment-token" not in lang, lang
query = os.path.join(os.path.dirname(path), "runtime", "queries", "hipop-plan-json", "highlights.scm")
with open(query) as f:
    assert f.read().strip() == "; inherits: json", query
print(f"ok: {path} parses as TOML and declares hipop-pddl, hipop-plan and hipop-plan-json with the hipop server")
PY
else
  echo "SKIP: python3 >= 3.11 (tomllib) not found; helix/languages.toml not validated"
fi

echo "== editors: vscode extension"
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  echo "SKIP: node/npm not found; VS Code extension not built or tested"
  exit 0
fi
echo "node $(node --version), npm $(npm --version 2>/dev/null)"

# The server of test/lsp.test.js: the workspace's build (in CARGO_TARGET_DIR
# when it is set).
if [ -z "${HIPOP_BIN:-}" ]; then
  target="${CARGO_TARGET_DIR:-$here/../target}"
  if [ -x "$target/debug/hipop" ]; then
    HIPOP_BIN="$(cd "$target/debug" && pwd)/hipop"
    export HIPOP_BIN
  fi
fi
if [ -n "${HIPOP_BIN:-}" ]; then
  echo "server for test/lsp.test.js: $HIPOP_BIN"
else
  echo "SKIP (test/lsp.test.js): no hipop binary; build it (cargo build -p hipop) or set HIPOP_BIN"
fi

cd "$here/vscode"
npm ci --no-audit --no-fund
npm run compile
npm test
bash -n e2e/run
node --check e2e/e2e.test.js
echo "ok: e2e/run and e2e/e2e.test.js parse (the end-to-end test itself runs before each release)"
