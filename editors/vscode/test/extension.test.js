'use strict';
// Drives the compiled client (out/extension.js) against a minimal stand-in
// for the `vscode` module, to check the wiring that does not need a running
// editor: the error shown when the binary is missing, the restart command and
// the restart on a settings change, the server's command line and the error
// shown when it fails to start. The language client is a stand-in too, which
// spawns the command line it is given as vscode-languageclient does and
// writes the server's stderr to the output channel with `append`. (Talking to
// a real server in a real VS Code is e2e/run.)

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
        append: (text) => events.push({ kind: 'append', text }),
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

// The clients constructed, and how the next one's start ends.
const clients = [];
let serverRuns = 'exit';
class FakeLanguageClient {
  constructor(id, name, serverOptions, clientOptions) {
    this.serverOptions = serverOptions;
    this.clientOptions = clientOptions;
    this.messages = [];
    clients.push(this);
  }
  error(message, data, showNotification = true) {
    this.messages.push({ message, showNotification });
  }
  createDefaultErrorHandler() {
    return { error: () => ({ action: 'default error' }), closed: () => ({ action: 'default closed' }) };
  }
  isRunning() {
    return this.running === true;
  }
  async start() {
    if (serverRuns === 'ok') {
      this.running = true;
      return;
    }
    // As vscode-languageclient 9: spawn `command args`, stderr to the output
    // channel; the server exits, the first write to it fails, the error
    // handler is asked, the client reports, and `start` resolves (or, for
    // other failures, rejects) with the client not running.
    const { command, args, options } = this.serverOptions.run;
    const child = require('node:child_process').spawn(command, args, { ...options, stdio: 'pipe' });
    child.stderr.on('data', (d) => this.clientOptions.outputChannel.append(d.toString()));
    await new Promise((resolve) => child.on('exit', resolve));
    const handler = this.clientOptions.errorHandler;
    this.duringStart = { error: handler.error(new Error('write EPIPE'), undefined, 1), closed: handler.closed() };
    this.error("hipop Language Server client: couldn't create connection to server.", undefined, 'force');
    if (serverRuns === 'reject') throw new Error('Pending response rejected since connection got disposed');
  }
  async stop() {}
  async dispose() {}
}

const originalLoad = Module._load;
Module._load = function (request, ...rest) {
  if (request === 'vscode') return vscodeStub;
  const loaded = originalLoad.call(this, request, ...rest);
  return request === 'vscode-languageclient/node' ? { ...loaded, LanguageClient: FakeLanguageClient } : loaded;
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

/** An executable script in a fresh folder, standing in for `hipop`. */
function fakeServer(t, body) {
  const fs = require('node:fs');
  const os = require('node:os');
  const path = require('node:path');
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'hipop-vscode-test-'));
  t.after(() => fs.rmSync(dir, { recursive: true, force: true }));
  const file = path.join(dir, 'hipop');
  fs.writeFileSync(file, `#!/bin/sh\n${body}\n`, { mode: 0o755 });
  return file;
}

// vscode-languageclient appends `--stdio` to the command line when the
// transport is `stdio`; `hipop lsp` refused it, and VS Code had no server.
test('the server runs as `hipop lsp <extraArgs>` over stdio, with nothing appended, as logged', async (t) => {
  const server = fakeServer(t, 'exit 0');
  events.length = 0;
  serverRuns = 'ok';
  settings['server.path'] = server;
  settings['server.extraArgs'] = ['--log', 'x'];
  await commands.get('hipop.restartServer')();
  await settle();
  assert.deepEqual(errors(), []);
  const run = clients.at(-1).serverOptions.run;
  assert.deepEqual(run, { command: server, args: ['lsp', '--log', 'x'], options: undefined });
  assert.equal(run.transport, undefined, 'a transport makes vscode-languageclient append --stdio, --pipe=… or --socket=…');
  assert.deepEqual(clients.at(-1).serverOptions.debug, run);
  assert.ok(
    events.some((e) => e.kind === 'log' && e.text === `Starting ${server} lsp --log x`),
    JSON.stringify(events),
  );
});

test('a server that fails to start: one error, with the first line it printed; its stderr in the output channel', async (t) => {
  const server = fakeServer(
    t,
    `printf "\\nerror: unexpected argument '%s' found\\n\\nUsage: hipop lsp\\n" "$2" >&2; exit 2`,
  );
  events.length = 0;
  serverRuns = 'exit';
  settings['server.path'] = server;
  settings['server.extraArgs'] = ['--bogus'];
  await commands.get('hipop.restartServer')();
  await settle();
  assert.equal(errors().length, 1, JSON.stringify(events));
  const [err] = errors();
  assert.equal(
    err.text,
    `hipop: the language server '${server} lsp --bogus' failed to start: it said "error: unexpected argument '--bogus' found". Check the "hipop.server.path" and "hipop.server.extraArgs" settings.`,
  );
  assert.deepEqual(err.items, ['Open Settings', 'Show Output']);
  const stderr = events.filter((e) => e.kind === 'append').map((e) => e.text).join('');
  assert.match(stderr, /error: unexpected argument '--bogus' found\n\nUsage: hipop lsp/);
  // No message of the client's own ('write EPIPE'), no restart, while it starts.
  const { CloseAction, ErrorAction } = require('vscode-languageclient/node');
  const started = clients.at(-1);
  assert.equal(started.clientOptions.initializationFailedHandler(new Error('x')), false);
  assert.deepEqual(started.duringStart, {
    error: { action: ErrorAction.Shutdown, handled: true },
    closed: { action: CloseAction.DoNotRestart, handled: true },
  });
  assert.deepEqual(started.messages, [
    { message: "hipop Language Server client: couldn't create connection to server.", showNotification: false },
  ]);
});

test('once the server runs, a broken connection gets the client\'s default handling', async (t) => {
  const server = fakeServer(t, 'exit 0');
  serverRuns = 'ok';
  settings['server.path'] = server;
  settings['server.extraArgs'] = [];
  await commands.get('hipop.restartServer')();
  await settle();
  const running = clients.at(-1);
  const { errorHandler } = running.clientOptions;
  assert.deepEqual(errorHandler.error(new Error('x'), undefined, 1), { action: 'default error' });
  assert.deepEqual(errorHandler.closed(), { action: 'default closed' });
  running.error('Connection to server got closed.', undefined, 'force');
  assert.deepEqual(running.messages.at(-1), { message: 'Connection to server got closed.', showNotification: 'force' });
});

test('a server that fails to start silently: the client error is shown', async (t) => {
  const server = fakeServer(t, 'exit 3');
  events.length = 0;
  serverRuns = 'reject';
  settings['server.path'] = server;
  settings['server.extraArgs'] = [];
  await commands.get('hipop.restartServer')();
  await settle();
  assert.equal(errors().length, 1, JSON.stringify(events));
  assert.match(errors()[0].text, /^hipop: the language server '.* lsp' failed to start: Pending response rejected since connection got disposed\. Check/);
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
