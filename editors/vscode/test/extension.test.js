'use strict';
// Drives the compiled client (out/extension.js) against a minimal stand-in
// for the `vscode` module, to check the wiring that does not need a running
// editor: the error shown when the binary is missing, the restart command and
// the restart on a settings change. (Talking to a real server needs VS Code.)

const test = require('node:test');
const assert = require('node:assert/strict');
const Module = require('node:module');

const events = [];
const commands = new Map();
const configListeners = [];
const settings = { 'server.path': 'hipop-surely-not-installed', 'server.extraArgs': [] };
const disposable = { dispose() {} };

// Anything the client library touches at load time that we do not model
// becomes an inert class, so that `require('vscode-languageclient/node')` works.
const inert = {
  get(target, prop) {
    if (prop in target) return target[prop];
    if (prop === '__esModule' || prop === 'then') return undefined;
    return new Proxy(class {}, inert);
  },
};
const vscodeStub = new Proxy(
  {
    window: {
      createOutputChannel: (name) => ({
        name,
        appendLine: (line) => events.push({ kind: 'log', text: line }),
        show() {},
        dispose() {},
      }),
      showErrorMessage: async (message, ...items) => {
        events.push({ kind: 'error', text: message, items });
        return undefined;
      },
    },
    commands: {
      registerCommand: (id, fn) => {
        commands.set(id, fn);
        return disposable;
      },
      executeCommand: async () => undefined,
    },
    workspace: {
      workspaceFolders: undefined,
      getConfiguration: (section) => {
        assert.equal(section, 'hipop');
        return { get: (key, dflt) => (key in settings ? settings[key] : dflt) };
      },
      onDidChangeConfiguration: (listener) => {
        configListeners.push(listener);
        return disposable;
      },
    },
  },
  inert,
);

const originalLoad = Module._load;
Module._load = function (request, ...rest) {
  if (request === 'vscode') return vscodeStub;
  return originalLoad.call(this, request, ...rest);
};
const extension = require('../out/extension.js');

const errors = () => events.filter((e) => e.kind === 'error');
const settle = () => new Promise((resolve) => setTimeout(resolve, 20));

test('activation with a missing binary shows an error that names the setting', async () => {
  await extension.activate({ subscriptions: [] });
  await settle();
  assert.equal(errors().length, 1);
  const [err] = errors();
  assert.match(err.text, /'hipop-surely-not-installed' was not found on PATH/);
  assert.match(err.text, /"hipop\.server\.path"/);
  assert.match(err.text, /cargo install --path cli/);
  assert.deepEqual(err.items, ['Open Settings', 'Show Output']);
});

test('hipop.restartServer is registered and tries to start again', async () => {
  assert.ok(commands.has('hipop.restartServer'));
  await commands.get('hipop.restartServer')();
  await settle();
  assert.equal(errors().length, 2);
});

test('changing hipop.server.* restarts with the new path; other settings do not', async () => {
  assert.equal(configListeners.length, 1);
  settings['server.path'] = '/nonexistent/dir/hipop';
  configListeners[0]({ affectsConfiguration: (s) => s === 'editor' });
  await settle();
  assert.equal(errors().length, 2, 'unrelated setting must not restart');

  configListeners[0]({ affectsConfiguration: (s) => s === 'hipop.server' || s === 'hipop' });
  await settle();
  assert.equal(errors().length, 3);
  assert.match(errors()[2].text, /no executable file at '\/nonexistent\/dir\/hipop'/);
});

test('deactivate resolves when no server is running', async () => {
  await extension.deactivate();
});

test('the server gets domains, problems and plans (documentSelector)', () => {
  assert.deepEqual(extension.DOCUMENT_SELECTOR, [
    { scheme: 'file', language: 'hipop-pddl' },
    { scheme: 'untitled', language: 'hipop-pddl' },
    { scheme: 'file', language: 'hipop-plan' },
    { scheme: 'untitled', language: 'hipop-plan', pattern: '**/*.{plan,soln,sol,plan.json}' },
    { scheme: 'file', pattern: '**/*.plan.json' },
    { scheme: 'untitled', pattern: '**/*.plan.json' },
  ]);
});

test('the selector patterns name exactly the files the server reads as plans', (t) => {
  const path = require('node:path');
  if (typeof path.matchesGlob !== 'function') {
    t.skip('path.matchesGlob needs Node >= 20.17');
    return;
  }
  // Node's glob has the brace syntax of VS Code's; it warns that it is experimental.
  const emitWarning = process.emitWarning;
  process.emitWarning = (w, ...rest) =>
    /glob/i.test(String(w)) ? undefined : emitWarning.call(process, w, ...rest);
  try {
    const patterns = extension.DOCUMENT_SELECTOR.filter((f) => f.pattern).map((f) => f.pattern);
    const sent = (file) => patterns.some((p) => path.matchesGlob(file, p));
    // The analyzer's is_plan_path: .plan, .soln, .sol, .plan.json.
    for (const file of ['/w/p01.plan', '/w/instance-5.vhpop.plan', '/w/p01.soln', '/w/p01.sol', '/w/p01.plan.json']) {
      assert.ok(sent(file), file);
    }
    for (const file of ['Untitled-1', '/w/domain.pddl', '/w/package.json', '/w/plan.txt', '/w/p01.plans']) {
      assert.ok(!sent(file), file);
    }
  } finally {
    process.emitWarning = emitWarning;
  }
});
