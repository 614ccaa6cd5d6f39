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
const editorListeners = [];
const contentProviders = new Map();
const panels = [];
let statusBar;

/** Enough of `vscode.Uri` for the plan views: parse, from, toString, its parts. */
class Uri {
  constructor({ scheme, authority = '', path = '', query = '', fragment = '' }) {
    Object.assign(this, { scheme, authority, path, query, fragment });
  }
  static parse(text) {
    const m = /^([a-z][\w+.-]*):(?:\/\/([^/?#]*))?([^?#]*)(?:\?([^#]*))?(?:#(.*))?$/i.exec(text);
    if (!m) throw new Error(`not a URI: ${text}`);
    const [, scheme, authority = '', path, query = '', fragment = ''] = m;
    return new Uri({ scheme, authority, path: decodeURIComponent(path), query: decodeURIComponent(query), fragment });
  }
  static from(parts) {
    return new Uri(parts);
  }
  static file(path) {
    return new Uri({ scheme: 'file', path });
  }
  toString() {
    const authority = this.authority || this.scheme === 'file' ? `//${this.authority}` : '';
    const query = this.query ? `?${encodeURIComponent(this.query)}` : '';
    return `${this.scheme}:${authority}${encodeURI(this.path)}${query}`;
  }
}

class EventEmitter {
  constructor() {
    this.listeners = [];
    this.event = (listener) => {
      this.listeners.push(listener);
      return disposable;
    };
  }
  fire(value) {
    events.push({ kind: 'changed', uri: value.toString() });
    this.listeners.forEach((l) => l(value));
  }
  dispose() {}
}

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
      showWarningMessage: async (message, ...items) => {
        events.push({ kind: 'warning', text: message, items });
        return undefined;
      },
      showInformationMessage: async (message, ...items) => {
        events.push({ kind: 'info', text: message, items });
        return undefined;
      },
      createStatusBarItem: (id, alignment, priority) => {
        statusBar = { id, alignment, priority, visible: false, show() { this.visible = true; }, hide() { this.visible = false; }, dispose() {} };
        return statusBar;
      },
      onDidChangeActiveTextEditor: (listener) => {
        editorListeners.push(listener);
        return disposable;
      },
      activeTextEditor: undefined,
      showTextDocument: async (doc, options) => {
        events.push({ kind: 'show', uri: doc.uri.toString(), options });
      },
      createWebviewPanel: (viewType, title, showOptions, options) => {
        const panel = {
          viewType, title, showOptions, options, webview: { html: '' },
          reveal() {}, onDidDispose: () => disposable, dispose() {},
        };
        panels.push(panel);
        return panel;
      },
    },
    commands: {
      registerCommand: (id, fn) => {
        commands.set(id, fn);
        return disposable;
      },
      executeCommand: async (id, ...args) => {
        events.push({ kind: 'command', id, args });
        return undefined;
      },
    },
    workspace: {
      workspaceFolders: undefined,
      textDocuments: [],
      registerTextDocumentContentProvider: (scheme, provider) => {
        contentProviders.set(scheme, provider);
        return disposable;
      },
      openTextDocument: async (uri) => {
        const text = await contentProviders.get(uri.scheme).provideTextDocumentContent(uri);
        return { uri, text };
      },
      getConfiguration: (section) => {
        assert.equal(section, 'hipop');
        return { get: (key, dflt) => (key in settings ? settings[key] : dflt) };
      },
      onDidChangeConfiguration: (listener) => {
        configListeners.push(listener);
        return disposable;
      },
    },
    Uri,
    EventEmitter,
    StatusBarAlignment: { Left: 1, Right: 2 },
    ViewColumn: { Active: -1, Beside: -2 },
  },
  inert,
);

// The clients constructed, and how the next one's start ends.
const clients = [];
let serverRuns = 'exit';
// What the fake server answers to a request: a function of the method and params.
let answer = async () => null;
class FakeLanguageClient {
  constructor(id, name, serverOptions, clientOptions) {
    this.serverOptions = serverOptions;
    this.clientOptions = clientOptions;
    this.messages = [];
    this.notifications = new Map();
    this.requests = [];
    this.notificationsSent = [];
    clients.push(this);
  }
  onNotification(method, handler) {
    this.notifications.set(method, handler);
    return disposable;
  }
  async sendNotification(type, params) {
    this.notificationsSent.push({ method: type.method, params });
  }
  async sendRequest(type, params) {
    const method = typeof type === 'string' ? type : type.method;
    this.requests.push({ method, params });
    return answer(method, params);
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

// Planning on save: the settings reach the server, and the plan views ask it.

const PROBLEM = 'file:///w/survey/problem.pddl';
const SOLVED = {
  uri: PROBLEM,
  problem: 'survey-two',
  status: 'solved',
  summary: 'plan: 3 actions, makespan 9.03, 0.01 s',
  current: true,
  repaired: false,
  expanded: 12,
  seconds: 0.01,
  format: 'val',
  text: '0.01: (observe r1 a p1) [2]\n',
  svg: '<?xml version="1.0"?>\n<svg xmlns="http://www.w3.org/2000/svg"/>\n',
};
const infos = () => events.filter((e) => e.kind === 'info');
const warnings = () => events.filter((e) => e.kind === 'warning');
const openProblem = () => {
  vscodeStub.window.activeTextEditor = { document: { uri: Uri.parse(PROBLEM), languageId: 'hipop-pddl' } };
};

/** Restarts on a stand-in server that runs; resolves with the new client. */
async function running(t) {
  settings['server.path'] = fakeServer(t, 'exit 0');
  settings['server.extraArgs'] = [];
  serverRuns = 'ok';
  await commands.get('hipop.restartServer')();
  await settle();
  return clients.at(-1);
}

test('the server starts with the plan settings, and gets them again when they change, without a restart', async (t) => {
  settings['plan.onSave'] = false;
  settings['plan.timeLimit'] = 2.5;
  const client = await running(t);
  assert.deepEqual(client.clientOptions.initializationOptions, { plan: { onSave: false, timeLimit: 2.5 } });
  // Not the client's synchronization: it would also send the settings to a
  // server being restarted for hipop.server.*, and pop up its failure.
  assert.equal(client.clientOptions.synchronize, undefined);
  const count = clients.length;
  settings['plan.timeLimit'] = 0;
  configListeners[0]({ affectsConfiguration: (s) => s === 'hipop.plan' || s === 'hipop' });
  await settle();
  assert.equal(clients.length, count, 'no restart');
  assert.deepEqual(client.notificationsSent, [
    { method: 'workspace/didChangeConfiguration', params: { settings: { hipop: { plan: { onSave: false, timeLimit: 0.1 } } } } },
  ]);
  // A server that is not running gets them when it starts.
  client.running = false;
  configListeners[0]({ affectsConfiguration: (s) => s === 'hipop.plan' || s === 'hipop' });
  await settle();
  assert.equal(client.notificationsSent.length, 1);
  delete settings['plan.onSave'];
  delete settings['plan.timeLimit'];
});

test('hipop/planned shows its summary in the status bar while its problem is active', async (t) => {
  const client = await running(t);
  openProblem();
  editorListeners.forEach((l) => l());
  assert.equal(statusBar.visible, false, 'nothing before a run');
  client.notifications.get('hipop/planned')({ uri: PROBLEM, status: 'solved', summary: SOLVED.summary, repaired: false });
  assert.equal(statusBar.visible, true);
  assert.equal(statusBar.text, '$(check) plan: 3 actions, makespan 9.03, 0.01 s');
  assert.deepEqual(statusBar.command, { title: 'Show Plan', command: 'hipop.showPlan', arguments: [PROBLEM] });
  // Another editor: hidden; back: shown.
  vscodeStub.window.activeTextEditor = undefined;
  editorListeners.forEach((l) => l());
  assert.equal(statusBar.visible, false);
  openProblem();
  editorListeners.forEach((l) => l());
  assert.equal(statusBar.visible, true);
  // A new server has run nothing yet.
  await running(t);
  assert.equal(statusBar.visible, false);
});

test('Show Plan: a read-only hipop-plan document, refreshed by hipop/planned', async (t) => {
  const client = await running(t);
  openProblem();
  answer = async (method) => (method === 'hipop/plan' ? SOLVED : null);
  events.length = 0;
  await commands.get('hipop.showPlan')();
  assert.deepEqual(client.requests.at(-1), { method: 'hipop/plan', params: { uri: PROBLEM } });
  const shown = events.filter((e) => e.kind === 'show');
  assert.equal(shown.length, 1, JSON.stringify(events));
  const uri = Uri.parse(shown[0].uri);
  assert.equal(uri.scheme, 'hipop-plan');
  assert.equal(uri.path, '/survey-two.plan');
  assert.equal(uri.query, PROBLEM);
  assert.equal(await contentProviders.get('hipop-plan').provideTextDocumentContent(uri), SOLVED.text);
  // The next run on the problem: VS Code asks for the text again.
  vscodeStub.workspace.textDocuments = [{ uri }];
  client.notifications.get('hipop/planned')({ uri: PROBLEM, status: 'solved', summary: 'x', repaired: true });
  assert.deepEqual(events.filter((e) => e.kind === 'changed').map((e) => e.uri), [uri.toString()]);
  vscodeStub.workspace.textDocuments = [];
});

test('Show Plan before any run: save the problem to plan it', async (t) => {
  await running(t);
  openProblem();
  answer = async () => null;
  events.length = 0;
  await commands.get('hipop.showPlan')();
  assert.deepEqual(infos().map((e) => e.text), ['hipop: no plan for problem yet: save the problem to plan it.']);
});

test('the plan commands without a problem, or without a server, say so and do not throw', async (t) => {
  await running(t);
  vscodeStub.window.activeTextEditor = undefined;
  events.length = 0;
  for (const id of ['hipop.showPlan', 'hipop.showTimeline', 'hipop.showPlanDiff', 'hipop.writePlanFile']) {
    await commands.get(id)();
  }
  assert.equal(infos().length, 4, JSON.stringify(events));
  assert.match(infos()[0].text, /open a problem/);

  settings['server.path'] = 'hipop-surely-not-installed';
  await commands.get('hipop.restartServer')();
  await settle();
  openProblem();
  events.length = 0;
  for (const id of ['hipop.showPlan', 'hipop.showTimeline', 'hipop.showPlanDiff', 'hipop.writePlanFile']) {
    await commands.get(id)();
  }
  assert.equal(warnings().length, 4, JSON.stringify(events));
  assert.match(warnings()[0].text, /the language server is not running/);
});

test('a failed request is a warning, not a throw', async (t) => {
  await running(t);
  openProblem();
  answer = async () => {
    throw new Error('Request hipop/plan failed');
  };
  events.length = 0;
  await commands.get('hipop.showPlan')();
  assert.deepEqual(warnings().map((e) => e.text), ['hipop: hipop/plan failed: Request hipop/plan failed']);
});

test('Show Plan Timeline: a webview without scripts, showing the SVG, updated by hipop/planned', async (t) => {
  const client = await running(t);
  openProblem();
  answer = async (method) => (method === 'hipop/plan' ? SOLVED : null);
  panels.length = 0;
  await commands.get('hipop.showTimeline')();
  assert.equal(panels.length, 1);
  const [panel] = panels;
  assert.equal(panel.title, 'Timeline: survey-two');
  assert.equal(panel.options.enableScripts, false);
  assert.deepEqual(panel.options.localResourceRoots, []);
  assert.match(panel.webview.html, /content="default-src 'none'; img-src data:; style-src 'unsafe-inline'"/);
  assert.match(panel.webview.html, /<img [^>]*src="data:image\/svg\+xml;base64,/);
  answer = async () => ({ ...SOLVED, summary: 'plan: 4 actions' });
  await client.notifications.get('hipop/planned')({ uri: PROBLEM, status: 'solved', summary: 'plan: 4 actions', repaired: true });
  await settle();
  assert.match(panel.webview.html, /<p>plan: 4 actions<\/p>/);
  // Asked again: the same panel.
  await commands.get('hipop.showTimeline')();
  assert.equal(panels.length, 1);
});

test('Show Repair Diff: a diff editor of before.plan and after.plan; not a repair: say so', async (t) => {
  await running(t);
  openProblem();
  const diff = { uri: PROBLEM, summary: 's', format: 'val', instability: 2, distance: 3, old: 'old\n', new: 'new\n', removed: [], added: [], retimed: [] };
  answer = async (method) => (method === 'hipop/planDiff' ? diff : SOLVED);
  events.length = 0;
  await commands.get('hipop.showPlanDiff')();
  const [call] = events.filter((e) => e.kind === 'command');
  assert.equal(call.id, 'vscode.diff');
  const [before, after, title] = call.args;
  assert.deepEqual([before.path, after.path], ['/survey-two/before.plan', '/survey-two/after.plan']);
  assert.equal(title, 'survey-two: instability 2, distance 3');
  const provider = contentProviders.get('hipop-plan');
  assert.equal(await provider.provideTextDocumentContent(before), 'old\n');
  assert.equal(await provider.provideTextDocumentContent(after), 'new\n');

  answer = async () => null;
  events.length = 0;
  await commands.get('hipop.showPlanDiff')();
  assert.deepEqual(infos().map((e) => e.text), [
    'hipop: the last run was not a repair: change the problem and save it again.',
  ]);
  assert.equal(events.filter((e) => e.kind === 'command').length, 0);
});

test("Write Plan Beside the Problem runs the server's hipop.writePlan", async (t) => {
  const client = await running(t);
  openProblem();
  answer = async (method) => (method === 'workspace/executeCommand' ? { uri: 'file:///w/survey/problem.plan', path: '/w/survey/problem.plan' } : null);
  events.length = 0;
  await commands.get('hipop.writePlanFile')();
  assert.deepEqual(client.requests.at(-1), {
    method: 'workspace/executeCommand',
    params: { command: 'hipop.writePlan', arguments: [PROBLEM] },
  });
  assert.deepEqual(infos().map((e) => [e.text, e.items]), [['hipop: wrote /w/survey/problem.plan', ['Open']]]);
  // The server says why it cannot.
  answer = async () => {
    throw new Error('no plan for this problem yet: save it to plan it');
  };
  events.length = 0;
  await commands.get('hipop.writePlanFile')();
  assert.deepEqual(warnings().map((e) => e.text), [
    'hipop: cannot write the plan: no plan for this problem yet: save it to plan it',
  ]);
});
