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
