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

test('one language id covers .pddl and .hddl', () => {
  assert.equal(pkg.contributes.languages.length, 1);
  const lang = pkg.contributes.languages[0];
  assert.equal(lang.id, 'hipop-pddl');
  assert.deepEqual(lang.extensions, ['.pddl', '.hddl']);
  assert.equal(lang.aliases[0], 'HTN-PDDL (hipop)');
  assert.ok(fs.existsSync(path.join(ROOT, lang.configuration)));
  assert.deepEqual(pkg.activationEvents, ['onLanguage:hipop-pddl']);
});

test('the grammar contribution points at a grammar with the same scopeName', () => {
  const [g] = pkg.contributes.grammars;
  assert.equal(g.language, 'hipop-pddl');
  assert.equal(g.scopeName, 'source.hipop-pddl');
  const grammar = readJson(g.path);
  assert.equal(grammar.scopeName, g.scopeName);
});

test('every #include in the grammar names an existing repository rule', () => {
  const grammar = readJson(pkg.contributes.grammars[0].path);
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
  assert.deepEqual(missing, []);
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

test('settings and the restart command are contributed', () => {
  const props = pkg.contributes.configuration.properties;
  assert.equal(props['hipop.server.path'].type, 'string');
  assert.equal(props['hipop.server.path'].default, 'hipop');
  assert.equal(props['hipop.server.extraArgs'].type, 'array');
  assert.deepEqual(props['hipop.server.extraArgs'].default, []);
  assert.deepEqual(props['hipop.trace.server'].enum, ['off', 'messages', 'verbose']);
  assert.equal(props['hipop.trace.server'].default, 'off');
  assert.deepEqual(
    pkg.contributes.commands.map((c) => c.command),
    ['hipop.restartServer'],
  );
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
