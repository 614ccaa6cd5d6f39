'use strict';
// Planning on save against the real `hipop lsp`, over the JSON-RPC library
// the extension's client is built on (vscode-languageserver-protocol, the one
// vscode-languageclient depends on), with the extension's initialization
// options and the settings it sends when they change (out/planProtocol.js):
// a save plans, the hints show the plan, `hipop/plan` gives its text and
// timeline, a save after a change repairs it and `hipop/planDiff` gives both
// plans, `hipop.writePlan` writes it beside the problem.
//
// The server: $HIPOP_BIN, else the workspace's target/debug/hipop (which
// `cargo test` builds before editors/test.sh runs); without either the test
// is skipped, and says so.

const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { spawn } = require('node:child_process');
const { pathToFileURL } = require('node:url');
const {
  createProtocolConnection,
  DidChangeConfigurationNotification,
  ExitNotification,
  ShutdownRequest,
  StreamMessageReader,
  StreamMessageWriter,
} = require('vscode-languageserver-protocol/node');
const { initializationOptions, planConfiguration, PLAN_REQUEST, PLAN_DIFF_REQUEST, PLANNED_NOTIFICATION, WRITE_PLAN_COMMAND } =
  require('../out/planProtocol.js');

const ROOT = path.resolve(__dirname, '..', '..', '..');
const FIXTURE = path.join(ROOT, 'lsp', 'tests', 'fixtures', 'planning');
/** The longest wait for one answer or notification of the server. */
const WAIT = 20_000;

function serverBinary() {
  if (process.env.HIPOP_BIN) {
    return { bin: path.resolve(process.env.HIPOP_BIN) };
  }
  const built = path.join(ROOT, 'target', 'debug', 'hipop');
  if (fs.existsSync(built)) {
    return { bin: built };
  }
  return { why: `no hipop binary: set HIPOP_BIN, or build ${built} (cargo build -p hipop)` };
}

/** The settings the extension has by default, as VS Code gives them. */
const defaults = { 'plan.onSave': true, 'plan.timeLimit': 5 };
const config = { get: (key, dflt) => (key in defaults ? defaults[key] : dflt) };

/** `hipop lsp` on a connection; records what the server sends unasked. */
function startServer(t, bin, cwd) {
  const child = spawn(bin, ['lsp'], { cwd, stdio: ['pipe', 'pipe', 'pipe'] });
  let stderr = '';
  child.stderr.on('data', (d) => {
    stderr += d;
  });
  const exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve({ code, signal })));
  const connection = createProtocolConnection(
    new StreamMessageReader(child.stdout),
    new StreamMessageWriter(child.stdin),
  );
  const received = [];
  const waiters = [];
  const record = (method, params) => {
    const message = { method, params };
    received.push(message);
    for (const w of [...waiters]) {
      if (w.accepts(message)) {
        waiters.splice(waiters.indexOf(w), 1);
        w.resolve(message);
      }
    }
  };
  // What a client answers: VS Code shows the progress and the hints.
  for (const method of ['window/workDoneProgress/create', 'workspace/inlayHint/refresh', 'client/registerCapability']) {
    connection.onRequest(method, (params) => {
      record(method, params);
      return null;
    });
  }
  connection.onNotification((method, params) => record(method, params));
  // The progress of a token the server created (no handler is registered for it).
  connection.onUnhandledProgress((params) => record('$/progress', params));
  connection.listen();
  t.after(() => {
    connection.dispose();
    if (child.exitCode === null && child.signalCode === null) child.kill('SIGKILL');
  });

  /** The next notification (or request) from the server that `accepts`, or one already received since `from`. */
  function waitFor(what, accepts, from = 0) {
    const seen = received.slice(from).find(accepts);
    if (seen) return Promise.resolve(seen);
    return new Promise((resolve, reject) => {
      const waiter = { accepts, resolve };
      waiters.push(waiter);
      const timer = setTimeout(() => {
        waiters.splice(waiters.indexOf(waiter), 1);
        reject(new Error(`no ${what} in ${WAIT} ms; received: ${received.map((m) => m.method).join(', ')}; stderr: ${stderr}`));
      }, WAIT);
      timer.unref();
      const done = waiter.resolve;
      waiter.resolve = (m) => {
        clearTimeout(timer);
        done(m);
      };
    });
  }
  return { connection, received, waitFor, exited, stderr: () => stderr };
}

/** A copy of the planning fixture in a fresh folder: the plan is written beside the problem. */
function scratch(t) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'hipop-vscode-lsp-'));
  t.after(() => fs.rmSync(dir, { recursive: true, force: true }));
  for (const file of ['domain.pddl', 'problem.pddl']) {
    fs.copyFileSync(path.join(FIXTURE, file), path.join(dir, file));
  }
  return dir;
}

/** The line and character of the end of `needle` in `text`. */
function endOf(text, needle) {
  const at = text.indexOf(needle);
  assert.ok(at >= 0, `${needle} not in ${text}`);
  const before = text.slice(0, at + needle.length).split('\n');
  return { line: before.length - 1, character: before.at(-1).length };
}

test('plan on save, hipop/plan, hipop/planDiff and hipop.writePlan, as the extension asks them', { timeout: 60_000 }, async (t) => {
  const { bin, why } = serverBinary();
  if (!bin) {
    t.skip(why);
    return;
  }
  const dir = scratch(t);
  const server = startServer(t, bin, dir);
  const { connection, waitFor } = server;
  const problemPath = path.join(dir, 'problem.pddl');
  const uri = pathToFileURL(problemPath).href;
  const domainUri = pathToFileURL(path.join(dir, 'domain.pddl')).href;
  let text = fs.readFileSync(problemPath, 'utf8');
  let version = 1;
  const request = (type, ...params) =>
    Promise.race([
      connection.sendRequest(type, ...params),
      new Promise((_, reject) =>
        setTimeout(() => reject(new Error(`${type.method ?? type}: no answer in ${WAIT} ms`)), WAIT).unref(),
      ),
    ]);
  const hints = async () =>
    (await request('textDocument/inlayHint', {
      textDocument: { uri },
      range: { start: { line: 0, character: 0 }, end: { line: 100, character: 0 } },
    })) ?? [];
  const label = (hint) => (typeof hint.label === 'string' ? hint.label : hint.label.map((p) => p.value).join(''));
  const planned = (from) =>
    waitFor('hipop/planned', (m) => m.method === PLANNED_NOTIFICATION && m.params.uri === uri, from);

  await t.test('initialize with the extension\'s options and the hipop settings', { timeout: 30_000 }, async () => {
    const init = await request('initialize', {
      processId: process.pid,
      rootUri: pathToFileURL(dir).href,
      workspaceFolders: [{ uri: pathToFileURL(dir).href, name: 'planning' }],
      capabilities: {
        window: { workDoneProgress: true },
        workspace: { inlayHint: { refreshSupport: true }, configuration: true },
        textDocument: { inlayHint: { dynamicRegistration: false }, synchronization: { didSave: true } },
      },
      initializationOptions: initializationOptions(config),
    });
    assert.ok(init.capabilities.inlayHintProvider, JSON.stringify(init.capabilities));
    assert.deepEqual(init.capabilities.executeCommandProvider.commands, [WRITE_PLAN_COMMAND]);
    await connection.sendNotification('initialized', {});
    // What the extension sends when a `hipop.plan` setting changes.
    await connection.sendNotification(DidChangeConfigurationNotification.type, { settings: planConfiguration(config) });
    await connection.sendNotification('textDocument/didOpen', {
      textDocument: { uri, languageId: 'hipop-pddl', version, text },
    });
    await waitFor('the diagnostics of the problem', (m) => m.method === 'textDocument/publishDiagnostics' && m.params.uri === uri);
    assert.deepEqual(await hints(), [], 'no hint before a save');
    assert.equal(await request(PLAN_REQUEST, { uri }), null, 'no plan before a save');
  });

  await t.test('a save plans: progress, hints refreshed, hipop/planned, the summary hint', { timeout: 30_000 }, async () => {
    const from = server.received.length;
    await connection.sendNotification('textDocument/didSave', { textDocument: { uri } });
    const done = await planned(from);
    assert.equal(done.params.status, 'solved', JSON.stringify(done.params));
    assert.equal(done.params.repaired, false);
    assert.match(done.params.summary, /^plan: 3 actions, makespan 9\.03, [\d.]+ s$/);
    const methods = server.received.slice(from).map((m) => m.method);
    assert.ok(methods.includes('window/workDoneProgress/create'), methods.join(', '));
    assert.ok(methods.includes('workspace/inlayHint/refresh'), methods.join(', '));
    const created = server.received.slice(from).find((m) => m.method === 'window/workDoneProgress/create');
    const progress = server.received
      .slice(from)
      .filter((m) => m.method === '$/progress' && m.params.token === created.params.token)
      .map((m) => m.params.value.kind);
    assert.equal(progress[0], 'begin', progress.join(', '));
    assert.equal(progress.at(-1), 'end', progress.join(', '));
    const shown = (await hints()).map((h) => [h.position.line, h.position.character, label(h)]);
    assert.equal(shown.length, 3, JSON.stringify(shown));
    assert.deepEqual(shown[0].slice(0, 2), [1, 28], 'after `(define (problem survey-two)`');
    assert.match(shown[0][2], /^plan: 3 actions, makespan 9\.03, [\d.]+ s$/);
    assert.deepEqual(shown.slice(1).map((h) => h[2]), ['← (observe r1 a p1) @ 0.01', '← (observe r1 b p2) @ 7.03']);
  });

  await t.test('hipop/plan: the plan file and its SVG timeline', { timeout: 30_000 }, async () => {
    const plan = await request(PLAN_REQUEST, { uri });
    assert.equal(plan.uri, uri);
    assert.equal(plan.problem, 'survey-two');
    assert.equal(plan.status, 'solved');
    assert.equal(plan.current, true);
    assert.equal(plan.format, 'val');
    assert.equal(plan.actions, 3);
    assert.ok(plan.text.includes('2.02: (move r1 a b) [5]'), plan.text);
    assert.match(plan.svg.trimStart(), /^(<\?xml|<svg)/);
    assert.ok(plan.svg.includes('<svg'), plan.svg);
    // A domain has no plan of its own.
    assert.equal(await request(PLAN_REQUEST, { uri: domainUri }), null);
    assert.equal(await request(PLAN_DIFF_REQUEST, { uri }), null, 'the first run is not a repair');
  });

  await t.test('a save after a change of the goal repairs the plan; hipop/planDiff', { timeout: 30_000 }, async () => {
    const at = endOf(text, '(observed p2)');
    const added = ' (observed p3)';
    version += 1;
    await connection.sendNotification('textDocument/didChange', {
      textDocument: { uri, version },
      contentChanges: [{ range: { start: at, end: at }, text: added }],
    });
    text = text.replace('(observed p2)', `(observed p2)${added}`);
    fs.writeFileSync(problemPath, text);
    const from = server.received.length;
    await connection.sendNotification('textDocument/didSave', { textDocument: { uri } });
    const done = await planned(from);
    assert.equal(done.params.status, 'solved', JSON.stringify(done.params));
    assert.equal(done.params.repaired, true, JSON.stringify(done.params));
    const shown = (await hints()).map(label);
    assert.match(shown[0], /^repaired plan: 5 actions.*; instability 2, distance 2$/);
    const diff = await request(PLAN_DIFF_REQUEST, { uri });
    assert.equal(diff.uri, uri);
    assert.equal(diff.instability, 2);
    assert.equal(diff.distance, 2);
    assert.equal(diff.format, 'val');
    assert.deepEqual(diff.added.map((s) => s.step), ['(move r1 b c)', '(observe r1 c p3)']);
    assert.ok(diff.old.includes('(observe r1 b p2)') && !diff.old.includes('(observe r1 c p3)'), diff.old);
    assert.ok(diff.new.includes('(observe r1 c p3)'), diff.new);
  });

  await t.test('hipop.writePlan writes problem.plan beside the problem', { timeout: 30_000 }, async () => {
    const plan = await request(PLAN_REQUEST, { uri });
    const written = await request('workspace/executeCommand', { command: WRITE_PLAN_COMMAND, arguments: [uri] });
    const planPath = path.join(dir, 'problem.plan');
    assert.equal(written.path, planPath);
    assert.equal(written.uri, pathToFileURL(planPath).href);
    assert.equal(fs.readFileSync(planPath, 'utf8'), plan.text);
    assert.ok(plan.text.includes('(observe r1 c p3)'), 'the repaired plan');
  });

  await t.test('shutdown and exit', { timeout: 30_000 }, async () => {
    await request(ShutdownRequest.type);
    await connection.sendNotification(ExitNotification.type);
    const exit = await Promise.race([server.exited, new Promise((r) => setTimeout(() => r('still running'), WAIT).unref())]);
    assert.deepEqual(exit, { code: 0, signal: null }, server.stderr());
  });
});
