'use strict';
// Unit tests for the hipop.server.path resolution (compiled to out/ by tsc).

const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { resolveServerCommand, expandHome } = require('../out/serverPath');

const posix = process.platform !== 'win32';

function makeTree() {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'hipop-vscode-test-'));
  const bin = path.join(dir, 'bin');
  fs.mkdirSync(bin);
  const exe = path.join(bin, 'hipop');
  fs.writeFileSync(exe, '#!/bin/sh\nexit 0\n');
  fs.chmodSync(exe, 0o755);
  const plain = path.join(bin, 'not-executable');
  fs.writeFileSync(plain, 'data');
  fs.chmodSync(plain, 0o644);
  return { dir, bin, exe, plain };
}

test('a bare name is looked up on PATH', { skip: !posix }, () => {
  const { dir, bin, exe } = makeTree();
  try {
    const env = { PATH: ['/nonexistent', bin].join(':') };
    assert.deepEqual(resolveServerCommand('hipop', { env }), { ok: true, command: exe });
    const missing = resolveServerCommand('hipop-nope', { env });
    assert.equal(missing.ok, false);
    assert.match(missing.reason, /'hipop-nope' was not found on PATH/);
    assert.equal(resolveServerCommand('not-executable', { env }).ok, false);
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
});

test('paths: absolute, relative to the workspace, and ~', { skip: !posix }, () => {
  const { dir, exe, plain } = makeTree();
  try {
    const env = { PATH: '', HOME: dir };
    assert.deepEqual(resolveServerCommand(exe, { env }), { ok: true, command: exe });
    assert.deepEqual(resolveServerCommand('./bin/hipop', { env, cwd: dir }), { ok: true, command: exe });
    assert.deepEqual(resolveServerCommand('~/bin/hipop', { env }), { ok: true, command: exe });
    assert.deepEqual(resolveServerCommand('  ~/bin/hipop  ', { env }), { ok: true, command: exe });
    const bad = resolveServerCommand(plain, { env });
    assert.equal(bad.ok, false);
    assert.match(bad.reason, /no executable file at/);
    assert.equal(resolveServerCommand('./bin', { env, cwd: dir }).ok, false, 'a directory is not a server');
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
});

test('an empty setting is an error', () => {
  assert.deepEqual(resolveServerCommand('   ', { env: {} }), { ok: false, reason: 'the setting is empty' });
});

test('expandHome only touches a leading ~', () => {
  assert.equal(expandHome('~/x', { HOME: '/h' }), path.join('/h', 'x'));
  assert.equal(expandHome('~', { HOME: '/h' }), '/h');
  assert.equal(expandHome('a/~/x', { HOME: '/h' }), 'a/~/x');
  assert.equal(expandHome('~user/x', { HOME: '/h' }), '~user/x');
});
