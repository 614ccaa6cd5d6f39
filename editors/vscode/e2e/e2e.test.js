'use strict';
// The extension in a real VS Code: code-server, a fresh profile with the
// packaged extension, `hipop.server.path` pointing at the hipop binary under
// test, a workspace holding a copy of one broken sample and of a domain and
// problem that the server plans on save, and Chromium driven
// by playwright-core doing what a user does. Run by ./run, which builds and
// installs everything and sets the environment read below.

const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const { spawn, execFileSync } = require('node:child_process');
const { chromium } = require('playwright-core');

function required(name) {
  const value = process.env[name];
  if (!value) throw new Error(`${name} is not set: run editors/vscode/e2e/run`);
  return value;
}
const HIPOP = required('HIPOP_BIN');
const WORK = required('E2E_WORK');
const ROOT = required('E2E_ROOT');
const VSIX = required('E2E_VSIX');
const CODE_SERVER = required('E2E_CODE_SERVER');
const CHROMIUM = required('CHROMIUM');

const SAMPLE = 'E0102-undefined-predicate.pddl';
/** A domain and a problem that the server plans on save (3 actions). */
const PLANNING = path.join(ROOT, 'lsp', 'tests', 'fixtures', 'planning');
const CHANNEL = 'hipop Language Server';
/** One wait for something VS Code shows (the machine may be busy). */
const SHOWN = 60_000;

const dirs = {
  userData: path.join(WORK, 'user-data'),
  extensions: path.join(WORK, 'extensions'),
  workspace: path.join(WORK, 'workspace'),
  browser: path.join(WORK, 'chromium-profile'),
  xdgConfig: path.join(WORK, 'xdg-config'),
  xdgData: path.join(WORK, 'xdg-data'),
  tmp: path.join(WORK, 'tmp'),
};
// The user's settings, and the remote machine's: `hipop.server.*` are
// machine settings, which a remote window (code-server's, like Remote-SSH's)
// takes from the machine it runs the extension on, not from the user's.
const userSettingsFile = path.join(dirs.userData, 'User', 'settings.json');
const machineSettingsFile = path.join(dirs.userData, 'Machine', 'settings.json');
const machineSettings = { 'hipop.server.path': HIPOP };
const userSettings = {
  'security.workspace.trust.enabled': false,
  'telemetry.telemetryLevel': 'off',
  'update.mode': 'none',
  'extensions.autoCheckUpdates': false,
  'extensions.autoUpdate': false,
  'extensions.ignoreRecommendations': true,
  'workbench.startupEditor': 'none',
  'workbench.tips.enabled': false,
  'chat.commandCenter.enabled': false,
  'chat.disableAIFeatures': true,
};
// code-server keeps its config and logs under XDG folders, and VS Code its
// sockets in TMPDIR: fresh ones, removed with the work folder.
const codeServerEnv = {
  ...process.env,
  XDG_CONFIG_HOME: dirs.xdgConfig,
  XDG_DATA_HOME: dirs.xdgData,
  TMPDIR: dirs.tmp,
};

let server;
let context;
let page;

test.before(async () => {
  for (const dir of Object.values(dirs)) fs.mkdirSync(dir, { recursive: true });
  fs.copyFileSync(path.join(ROOT, 'samples', 'broken', SAMPLE), path.join(dirs.workspace, SAMPLE));
  for (const file of ['domain.pddl', 'problem.pddl']) {
    fs.copyFileSync(path.join(PLANNING, file), path.join(dirs.workspace, file));
  }
  for (const [file, settings] of [[userSettingsFile, userSettings], [machineSettingsFile, machineSettings]]) {
    fs.mkdirSync(path.dirname(file), { recursive: true });
    fs.writeFileSync(file, JSON.stringify(settings, null, 2));
  }

  const installed = execFileSync(
    CODE_SERVER,
    ['--user-data-dir', dirs.userData, '--extensions-dir', dirs.extensions, '--install-extension', VSIX],
    { env: codeServerEnv, encoding: 'utf8' },
  );
  assert.match(installed, /successfully installed/, installed);

  server = await startCodeServer();
  context = await chromium.launchPersistentContext(dirs.browser, {
    executablePath: CHROMIUM,
    headless: true,
    args: [
      '--no-sandbox',
      '--disable-gpu',
      '--disable-quic',
      '--no-first-run',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
    ],
    viewport: { width: 1400, height: 900 },
  });
  page = context.pages()[0] ?? (await context.newPage());
  await page.goto(server.url);
  await page.locator('.monaco-workbench').waitFor({ timeout: SHOWN });
});

test.after(async () => {
  await context?.close();
  if (server) {
    // The whole process group: code-server, its extension host and the
    // servers that extensions started.
    process.kill(-server.process.pid, 'SIGTERM');
    await server.exited;
  }
});

/** Starts code-server on a free loopback port; resolves with its address. */
function startCodeServer() {
  const log = fs.createWriteStream(path.join(WORK, 'code-server.log'));
  const child = spawn(
    CODE_SERVER,
    [
      '--bind-addr', '127.0.0.1:0',
      '--auth', 'none',
      '--user-data-dir', dirs.userData,
      '--extensions-dir', dirs.extensions,
      '--disable-telemetry',
      '--disable-update-check',
      '--disable-workspace-trust',
      '--disable-getting-started-override',
      '--ignore-last-opened',
      dirs.workspace,
    ],
    { env: codeServerEnv, stdio: ['ignore', 'pipe', 'pipe'], detached: true },
  );
  const exited = new Promise((resolve) => child.on('exit', resolve));
  return new Promise((resolve, reject) => {
    let output = '';
    const timer = setTimeout(() => reject(new Error(`code-server did not start in ${SHOWN} ms:\n${output}`)), SHOWN);
    const read = (chunk) => {
      log.write(chunk);
      output += chunk;
      const m = /HTTP server listening on (http:\/\/127\.0\.0\.1:\d+\/)/.exec(output);
      if (m) {
        clearTimeout(timer);
        resolve({ url: m[1], process: child, exited });
      }
    };
    child.stdout.on('data', read);
    child.stderr.on('data', read);
    child.on('exit', (code) => reject(new Error(`code-server exited (${code}):\n${output}`)));
  });
}

/** A test that leaves a screenshot in the work folder when it fails. */
function check(name, body) {
  test(name, async () => {
    try {
      await body();
    } catch (err) {
      const file = path.join(WORK, `failure-${name.replace(/[^a-z0-9]+/gi, '-').slice(0, 60)}.png`);
      await page?.screenshot({ path: file }).catch(() => {});
      err.message += `\n(screenshot: ${file})`;
      throw err;
    }
  });
}

/**
 * Runs a command from the command palette, by its title: the one whose
 * label is `title` (code-server may add the remote's address in
 * parentheses), not one that begins like it.
 */
async function runCommand(title) {
  await page.keyboard.press('F1');
  const input = page.locator('.quick-input-widget input');
  await input.waitFor({ timeout: SHOWN });
  await input.fill(`>${title}`);
  const label = page.locator('.quick-input-list .monaco-list-row .label-name', { hasText: title });
  const exact = label.filter({ hasText: new RegExp(`^\\s*${title.replace(/[.*+?^${}()|[\]\\]/g, '\\$&')}(\\s*\\([^)]*\\))?\\s*$`) });
  await exact.first().waitFor({ timeout: SHOWN });
  await exact.first().click();
}

/** Retries `check` until it passes, for at most SHOWN ms. */
async function assertEventually(check) {
  const until = Date.now() + SHOWN;
  for (;;) {
    try {
      return check();
    } catch (err) {
      if (Date.now() > until) throw err;
      await new Promise((resolve) => setTimeout(resolve, 200));
    }
  }
}

/** The text of the lines a Monaco editor shows, with plain spaces. */
async function editorText(editor) {
  return (await editor.locator('.view-lines').innerText()).replace(/\u00a0/g, ' ');
}

/** Shows the extension's output channel; resolves with its editor. */
async function showOutputChannel() {
  await runCommand('Output: Show Output Channels...');
  const input = page.locator('.quick-input-widget input');
  await input.fill(CHANNEL);
  await page.locator('.quick-input-list .monaco-list-row', { hasText: CHANNEL }).first().waitFor({ timeout: SHOWN });
  await input.press('Enter');
  return page.locator('.output-view .monaco-editor, #workbench\\.panel\\.output .monaco-editor').first();
}

check('a broken sample opens, and its diagnostic shows in the Problems panel', async () => {
  await page.getByRole('treeitem', { name: SAMPLE }).click({ timeout: SHOWN });
  const editor = page.locator('.editor-instance .monaco-editor').first();
  await editor.locator('.view-lines', { hasText: 'domain rovers' }).waitFor({ timeout: SHOWN });
  // The squiggle first, then the panel.
  await editor.locator('.squiggly-error').first().waitFor({ timeout: SHOWN });
  await runCommand('View: Focus Problems (Errors, Warnings, Infos)');
  const row = page.locator('.markers-panel .monaco-list-row', { hasText: 'undefined predicate' });
  await row.first().waitFor({ timeout: SHOWN });
  const text = (await row.first().innerText()).replace(/\s+/g, ' ');
  assert.match(text, /undefined predicate `observd` \(did you mean `observed`\?\)/, text);
  assert.match(text, /E0102/, text);
  assert.match(text, /\[Ln 19, Col 20\]/, text);
});

check('hovering a predicate shows its declaration', async () => {
  const editor = page.locator('.editor-instance .monaco-editor').first();
  // `observed` in `:effect (observed ?t))` of the action observe.
  const line = editor.locator('.view-line', { hasText: ':effect (observed ?t))' });
  const word = line.locator('span span', { hasText: /^observed$/ });
  await word.hover({ timeout: SHOWN });
  const hover = page.locator('.monaco-hover:not(.hidden)', { hasText: 'observed' });
  await hover.first().waitFor({ timeout: SHOWN });
  const text = (await hover.first().innerText()).replace(/\s+/g, ' ');
  assert.match(text, /\(observed \?t - target\)/, text);
});

check('the output channel shows the command line the server was started with', async () => {
  const output = await showOutputChannel();
  await output.locator('.view-lines', { hasText: 'Starting' }).waitFor({ timeout: SHOWN });
  const text = await editorText(output);
  assert.ok(text.split('\n').includes(`Starting ${HIPOP} lsp`), text);
});

check('saving a problem plans it: its summary shows after (problem …), and in the status bar', async () => {
  await page.getByRole('treeitem', { name: 'problem.pddl' }).click({ timeout: SHOWN });
  const editor = page.locator('.editor-instance .monaco-editor', { hasText: 'survey-two' }).first();
  await editor.locator('.view-lines', { hasText: '(:goal' }).waitFor({ timeout: SHOWN });
  await editor.locator('.view-lines').click();
  await page.keyboard.press('Control+S');
  // An inlay hint: text in the line, after `(define (problem survey-two)`.
  const line = editor.locator('.view-line', { hasText: 'plan: 3 actions' });
  await line.first().waitFor({ timeout: SHOWN });
  const text = (await line.first().innerText()).replace(/\u00a0/g, ' ');
  assert.match(text, /\(define \(problem survey-two\)\s*plan: 3 actions, makespan 9\.03, [\d.]+ s/, text);
  const goals = await editorText(editor);
  assert.match(goals, /\(observed p1\)\s*← \(observe r1 a p1\) @ 0\.01/, goals);
  await page.locator('.statusbar-item', { hasText: 'plan: 3 actions' }).first().waitFor({ timeout: SHOWN });
});

check('hipop: Show Plan opens the plan in a read-only editor', async () => {
  await runCommand('hipop: Show Plan');
  const tab = page.locator('.tab', { hasText: 'survey-two.plan' });
  await tab.first().waitFor({ timeout: SHOWN });
  const plan = page.locator('.editor-instance .monaco-editor', { hasText: '(move r1 a b)' }).first();
  await plan.waitFor({ timeout: SHOWN });
  const text = await editorText(plan);
  assert.match(text, /2\.02: \(move r1 a b\) \[5\]/, text);
  // Typing changes nothing: VS Code says the editor is read-only.
  await plan.locator('.view-lines').click();
  await page.keyboard.type('x');
  await page.locator('.monaco-editor-overlaymessage', { hasText: 'read-only' }).first().waitFor({ timeout: SHOWN });
  assert.equal(await editorText(plan), text);
});

check('hipop: Show Plan Timeline shows the SVG timeline in a panel', async () => {
  // The commands are offered for domains and problems: back to the problem.
  await page.getByRole('treeitem', { name: 'problem.pddl' }).click({ timeout: SHOWN });
  await runCommand('hipop: Show Plan Timeline');
  await page.locator('.tab', { hasText: 'Timeline: survey-two' }).first().waitFor({ timeout: SHOWN });
  // A webview: the page in an iframe inside VS Code's iframe.
  const view = page.frameLocator('iframe.webview.ready').frameLocator('iframe#active-frame');
  await view.locator('p', { hasText: 'plan: 3 actions' }).waitFor({ timeout: SHOWN });
  const image = view.locator('img[src^="data:image/svg+xml;base64,"]');
  await image.waitFor({ timeout: SHOWN });
  // Loaded under the page's policy, and drawn.
  const width = await image.evaluate((img) => img.naturalWidth);
  assert.ok(width > 100, `the image is ${width} px wide`);
});

check('a server that refuses its arguments: one error that says why, and its stderr in the output channel', async () => {
  // Edit the remote settings as a user does; the change restarts the
  // server with the new arguments.
  await runCommand('Preferences: Open Remote Settings (JSON)');
  const json = page.locator('.editor-instance .monaco-editor', { hasText: 'hipop.server.path' }).first();
  await json.waitFor({ timeout: SHOWN });
  await json.locator('.view-lines').click();
  const edited = { ...machineSettings, 'hipop.server.extraArgs': ['--socket=5007'] };
  await page.keyboard.press('Control+A');
  await page.keyboard.press('Delete');
  // One line: typing a newline would auto-indent and auto-close.
  await page.keyboard.insertText(JSON.stringify(edited));
  await page.keyboard.press('Control+S');
  await assertEventually(() => assert.deepEqual(JSON.parse(fs.readFileSync(machineSettingsFile, 'utf8')), edited));
  const toast = page.locator('.notifications-toasts .notification-toast', { hasText: 'failed to start' });
  await toast.first().waitFor({ timeout: SHOWN });
  const text = (await toast.first().innerText()).replace(/\s+/g, ' ');
  assert.match(text, /hipop lsp --socket=5007' failed to start: it said "error: `--socket=5007`: hipop lsp serves only standard input and output/, text);
  const others = await page.locator('.notifications-toasts .notification-toast', { hasText: /EPIPE|hipop/ }).allInnerTexts();
  assert.equal(others.length, 1, `one pop-up, not ${JSON.stringify(others)}`);

  const output = await showOutputChannel();
  await output.locator('.view-lines', { hasText: 'serves only' }).waitFor({ timeout: SHOWN });
  // The editor shows only the lines that fit: make room for all of them.
  await runCommand('View: Toggle Maximized Panel');
  await output.locator('.view-lines', { hasText: 'Starting' }).first().waitFor({ timeout: SHOWN });
  const log = await editorText(output);
  assert.ok(log.includes(`Starting ${HIPOP} lsp --socket=5007`), log);
  assert.match(log, /error: `--socket=5007`: hipop lsp serves only standard input and output/, log);
});
