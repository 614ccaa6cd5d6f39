'use strict';
// Consistency checks between package.json, the grammar, the language
// configuration and the compiled client. Run after `npm run compile`
// (`npm test` does that through its `pretest` script).

const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');

const ROOT = path.join(__dirname, '..');
const readJson = (rel) => JSON.parse(fs.readFileSync(path.join(ROOT, rel), 'utf8'));
const pkg = readJson('package.json');

function minVersion(range) {
  const m = /(\d+)\.(\d+)\.(\d+)/.exec(range);
  assert.ok(m, `cannot read a version out of ${JSON.stringify(range)}`);
  return m.slice(1, 4).map(Number);
}
function cmp(a, b) {
  for (let i = 0; i < 3; i++) {
    if (a[i] !== b[i]) return a[i] - b[i];
  }
  return 0;
}

const language = (id) => {
  const found = pkg.contributes.languages.filter((l) => l.id === id);
  assert.equal(found.length, 1, `exactly one language ${id}`);
  return found[0];
};
const grammarOf = (id) => {
  const found = pkg.contributes.grammars.filter((g) => g.language === id);
  assert.equal(found.length, 1, `exactly one grammar for ${id}`);
  return found[0];
};

test('two languages: hipop-pddl and hipop-plan', () => {
  assert.deepEqual(
    pkg.contributes.languages.map((l) => l.id),
    ['hipop-pddl', 'hipop-plan'],
  );
  assert.deepEqual(pkg.activationEvents, [
    'onLanguage:hipop-pddl',
    'onLanguage:hipop-plan',
    'workspaceContains:**/*.plan.json',
  ]);
});

test('one language id covers .pddl and .hddl', () => {
  const lang = language('hipop-pddl');
  assert.deepEqual(lang.extensions, ['.pddl', '.hddl']);
  assert.equal(lang.aliases[0], 'HTN-PDDL (hipop)');
  assert.equal(lang.configuration, './language-configuration.json');
  assert.ok(fs.existsSync(path.join(ROOT, lang.configuration)));
});

test('hipop-plan covers .plan, .soln and .sol with its own configuration', () => {
  const lang = language('hipop-plan');
  assert.deepEqual(lang.extensions, ['.plan', '.soln', '.sol']);
  assert.equal(lang.aliases[0], 'Plan (hipop)');
  assert.equal(lang.configuration, './language-configuration-plan.json');
  assert.ok(fs.existsSync(path.join(ROOT, lang.configuration)));
});

test('no language claims .plan.json files: they stay JSON', () => {
  for (const lang of pkg.contributes.languages) {
    for (const ext of lang.extensions ?? []) {
      assert.ok(!ext.endsWith('.json'), `${lang.id} claims ${ext}`);
    }
    assert.equal(lang.filenamePatterns, undefined, `${lang.id} has filenamePatterns`);
    assert.equal(lang.filenames, undefined, `${lang.id} has filenames`);
  }
});

test('each language has a grammar whose file has the same scopeName', () => {
  assert.equal(pkg.contributes.grammars.length, 2);
  for (const [id, scope] of [
    ['hipop-pddl', 'source.hipop-pddl'],
    ['hipop-plan', 'source.hipop-plan'],
  ]) {
    const g = grammarOf(id);
    assert.equal(g.scopeName, scope);
    const grammar = readJson(g.path);
    assert.equal(grammar.scopeName, g.scopeName);
  }
});

test('every #include in the grammars names an existing repository rule', () => {
  for (const g of pkg.contributes.grammars) {
    const grammar = readJson(g.path);
    const missing = [];
    const walk = (node) => {
      if (Array.isArray(node)) return node.forEach(walk);
      if (node && typeof node === 'object') {
        if (typeof node.include === 'string' && node.include.startsWith('#')) {
          if (!(node.include.slice(1) in grammar.repository)) missing.push(node.include);
        }
        Object.values(node).forEach(walk);
      }
    };
    walk(grammar);
    assert.deepEqual(missing, [], g.path);
  }
});

test('language-configuration: ; comments, () brackets, PDDL word pattern', () => {
  const conf = readJson('language-configuration.json');
  assert.equal(conf.comments.lineComment, ';');
  assert.deepEqual(conf.brackets, [['(', ')']]);
  assert.ok(conf.autoClosingPairs.some((p) => p.open === '(' && p.close === ')'));
  const word = new RegExp(conf.wordPattern, 'g');
  const words = (s) => s.match(word);
  assert.deepEqual(words('(at ?robot-1 loc_2)'), ['at', '?robot-1', 'loc_2']);
  assert.deepEqual(words('(:durative-action move'), [':durative-action', 'move']);
  assert.deepEqual(words('(= ?duration 10.5)'), ['?duration', '10.5']);
});

test('plan language-configuration: ; comments, () and [] brackets, plan word pattern', () => {
  const conf = readJson('language-configuration-plan.json');
  assert.equal(conf.comments.lineComment, ';');
  assert.deepEqual(conf.brackets, [['(', ')'], ['[', ']']]);
  for (const [open, close] of conf.brackets) {
    assert.ok(conf.autoClosingPairs.some((p) => p.open === open && p.close === close), open);
  }
  const word = new RegExp(conf.wordPattern, 'g');
  const words = (s) => s.match(word);
  assert.deepEqual(words('0.000: (move rover-1 base_2 ridge) [30.980]'), [
    '0.000', 'move', 'rover-1', 'base_2', 'ridge', '30.980',
  ]);
  assert.deepEqual(words('3 inspect r1 -> inspect-direct 0 1'), ['3', 'inspect', 'r1', 'inspect-direct', '0', '1']);
  assert.deepEqual(words(';@ 0 1e-3 [.5]'), ['0', '1e-3', '.5']);
});

test('settings and the restart command are contributed', () => {
  const props = pkg.contributes.configuration.properties;
  assert.equal(props['hipop.server.path'].type, 'string');
  assert.equal(props['hipop.server.path'].default, 'hipop');
  assert.equal(props['hipop.server.extraArgs'].type, 'array');
  assert.deepEqual(props['hipop.server.extraArgs'].default, []);
  assert.deepEqual(props['hipop.trace.server'].enum, ['off', 'messages', 'verbose']);
  assert.equal(props['hipop.trace.server'].default, 'off');
  assert.equal(pkg.contributes.commands[0].command, 'hipop.restartServer');
});

test('planning on save: hipop.plan.onSave and hipop.plan.timeLimit, described', () => {
  const props = pkg.contributes.configuration.properties;
  const onSave = props['hipop.plan.onSave'];
  assert.equal(onSave.type, 'boolean');
  assert.equal(onSave.default, true);
  const limit = props['hipop.plan.timeLimit'];
  assert.equal(limit.type, 'number');
  assert.equal(limit.default, 5);
  assert.equal(limit.minimum, 0.1);
  for (const prop of [onSave, limit]) {
    assert.match(prop.markdownDescription, /\S/);
    assert.equal(prop.scope, undefined, 'a user or workspace setting like any other');
  }
  // The defaults are the client's and the server's (lsp/src/session.rs).
  const { DEFAULT_PLAN_SETTINGS, MIN_TIME_LIMIT } = require('../out/planProtocol.js');
  assert.deepEqual(DEFAULT_PLAN_SETTINGS, { onSave: onSave.default, timeLimit: limit.default });
  assert.equal(MIN_TIME_LIMIT, limit.minimum);
});

test('the plan commands are in the palette, in category hipop, for domains and problems only', () => {
  const plan = [
    ['hipop.showPlan', 'Show Plan'],
    ['hipop.showTimeline', 'Show Plan Timeline'],
    ['hipop.showPlanDiff', 'Show Repair Diff'],
    ['hipop.writePlanFile', 'Write Plan Beside the Problem'],
  ];
  assert.deepEqual(
    pkg.contributes.commands.map((c) => [c.command, c.title]),
    [['hipop.restartServer', 'Restart Language Server'], ...plan],
  );
  for (const c of pkg.contributes.commands) {
    assert.equal(c.category, 'hipop', c.command);
  }
  assert.deepEqual(
    pkg.contributes.menus.commandPalette,
    plan.map(([command]) => ({ command, when: 'editorLangId == hipop-pddl' })),
  );
  // The compiled client registers exactly these.
  const { PLAN_COMMANDS } = require('../out/planProtocol.js');
  assert.deepEqual(Object.values(PLAN_COMMANDS), plan.map(([command]) => command));
});

// vscode-languageclient registers a VS Code command for each command the
// server declares (executeCommandProvider): a contributed command of the
// same id would be registered twice, and the second registration throws.
test("no contributed command has the id of a server's command", () => {
  const { WRITE_PLAN_COMMAND } = require('../out/planProtocol.js');
  assert.equal(WRITE_PLAN_COMMAND, 'hipop.writePlan');
  const ids = pkg.contributes.commands.map((c) => c.command);
  assert.ok(!ids.includes(WRITE_PLAN_COMMAND), ids.join(', '));
});

test('engines.vscode satisfies vscode-languageclient and @types/vscode', () => {
  const engine = minVersion(pkg.engines.vscode);
  const lc = JSON.parse(
    fs.readFileSync(require.resolve('vscode-languageclient/package.json'), 'utf8'),
  );
  assert.ok(
    cmp(engine, minVersion(lc.engines.vscode)) >= 0,
    `engines.vscode ${pkg.engines.vscode} is older than vscode-languageclient's ${lc.engines.vscode}`,
  );
  const types = JSON.parse(
    fs.readFileSync(require.resolve('@types/vscode/package.json'), 'utf8'),
  );
  assert.ok(
    cmp(minVersion(types.version), engine) <= 0,
    `@types/vscode ${types.version} is newer than engines.vscode ${pkg.engines.vscode} (vsce rejects that)`,
  );
});

test('the compiled entry point exists and exports activate/deactivate', () => {
  const main = path.join(ROOT, pkg.main);
  assert.ok(fs.existsSync(main), `${pkg.main} missing: run npm run compile`);
  const src = fs.readFileSync(main, 'utf8');
  assert.match(src, /exports\.activate = activate/);
  assert.match(src, /exports\.deactivate = deactivate/);
});

// `vsce package` stops on a relative link in README.md unless it can tell
// the repository to rewrite it against; hipop names no public repository.
test('README.md, shown in the extension view, has no relative link', () => {
  const readme = fs.readFileSync(path.join(ROOT, 'README.md'), 'utf8');
  const relative = [...readme.matchAll(/!?\[[^\]]*\]\(([^)\s]+)[^)]*\)|<(?:a|img)\s[^>]*(?:href|src)="([^"]+)"/g)]
    .map((m) => m[1] ?? m[2])
    .filter((target) => !/^(https?:|mailto:|#)/.test(target));
  assert.deepEqual(relative, []);
});

test('package.json names no placeholder repository', () => {
  assert.ok(!JSON.stringify(pkg).includes('example.invalid'), 'a placeholder address');
  if (pkg.repository !== undefined) {
    const url = typeof pkg.repository === 'string' ? pkg.repository : pkg.repository.url;
    assert.match(url, /^https:\/\//);
  }
});

test('.vscodeignore leaves the tests and the end-to-end test out of the .vsix', () => {
  const ignored = fs
    .readFileSync(path.join(ROOT, '.vscodeignore'), 'utf8')
    .split('\n')
    .map((l) => l.trim());
  for (const folder of ['src/**', 'test/**', 'e2e/**']) {
    assert.ok(ignored.includes(folder), folder);
  }
});

// test/lsp.test.js talks to the server through vscode-languageserver-protocol:
// the same version as the extension's client, so that it speaks as it does.
test("the protocol library of the server test is the client's", () => {
  const lc = JSON.parse(fs.readFileSync(require.resolve('vscode-languageclient/package.json'), 'utf8'));
  assert.equal(pkg.devDependencies['vscode-languageserver-protocol'], lc.dependencies['vscode-languageserver-protocol']);
  const used = JSON.parse(
    fs.readFileSync(require.resolve('vscode-languageserver-protocol/package.json'), 'utf8'),
  );
  assert.equal(used.version, lc.dependencies['vscode-languageserver-protocol']);
});
