'use strict';
// Tokenizes plans in the forms of docs/plan-formats.md (VAL, IPC 2020
// hierarchical, hipop's timing annotations) with the plan grammar, the same
// way as grammar.test.js does for HTN-PDDL, and checks exact scope stacks.
//
// Run: node --test test/plan-grammar.test.js

const test = require('node:test');
const assert = require('node:assert/strict');
const { tokenize, PLAN_SCOPE_NAME } = require('./tokenize');

const S = '.hipop-plan';

const VAL = `; Plan found by some planner
0.000: (move rover1 base ridge) [30.980]
0.01:(MOVE r1 a b)[2]   ; a comment (not code)
30.990: ( observe rover1 ridge rock1 ) [ 15.000 ]
(transmit rover1 ridge rock1)
Time: 54.0`;

const IPC = `Planner log (ignored) 0 1
==>
0 move rover1 base ridge
1 (observe rover1 ridge rock1)
2 move[rover1,ridge,base]
root 3 4
3 inspect rover1 rock1 base -> inspect-direct 0 1 2
4 (go r1) -> <<m;t[a];m2;0;-1>;m3> 0 1
; a comment line inside the block
<==
;@ 0 0.000 [30.980]
;@ 3 0.000
; plain comment`;

const cache = new Map();
function lines(source) {
  if (!cache.has(source)) cache.set(source, tokenize(source, PLAN_SCOPE_NAME));
  return cache.get(source);
}

/** The tokens of the first line of `source` that contains `needle`. */
async function lineTokens(source, needle) {
  const idx = source.split('\n').findIndex((l) => l.includes(needle));
  assert.notEqual(idx, -1, `test bug: no line contains ${JSON.stringify(needle)}`);
  return (await lines(source))[idx];
}

/** Asserts the exact scope stack of the `occurrence`-th token `text` on that line. */
async function expectScopes(source, needle, text, scopes, occurrence = 0) {
  const tokens = await lineTokens(source, needle);
  const matching = tokens.filter((t) => t.text === text);
  assert.ok(
    matching.length > occurrence,
    `no token ${JSON.stringify(text)} (#${occurrence}) on the line with ${JSON.stringify(needle)}; tokens: ` +
      JSON.stringify(tokens.map((t) => t.text)),
  );
  assert.deepEqual(
    matching[occurrence].scopes,
    [PLAN_SCOPE_NAME, ...scopes.map((s) => s + S)],
    `scopes of ${JSON.stringify(text)}`,
  );
}

/** [text, innermost scope] of every non-blank token of the line, for whole-line checks. */
async function summary(source, needle) {
  return (await lineTokens(source, needle))
    .filter((t) => t.text.trim() !== '')
    .map((t) => [t.text, t.scopes.at(-1)]);
}

test('a VAL step: time, action, arguments, duration', async () => {
  assert.deepEqual(await summary(VAL, '0.000: (move'), [
    ['0.000', 'constant.numeric.time' + S],
    [':', 'punctuation.separator.time' + S],
    ['(', 'punctuation.section.parens.begin' + S],
    ['move', 'support.function.action' + S],
    ['rover1', 'variable.other.object' + S],
    ['base', 'variable.other.object' + S],
    ['ridge', 'variable.other.object' + S],
    [')', 'punctuation.section.parens.end' + S],
    ['[', 'punctuation.section.brackets.begin' + S],
    ['30.980', 'constant.numeric.duration' + S],
    [']', 'punctuation.section.brackets.end' + S],
  ]);
});

test('VAL spacing and case as planners print them', async () => {
  await expectScopes(VAL, '0.01:(MOVE', '0.01', ['constant.numeric.time']);
  await expectScopes(VAL, '0.01:(MOVE', 'MOVE', ['support.function.action']);
  await expectScopes(VAL, '0.01:(MOVE', '2', ['constant.numeric.duration']);
  await expectScopes(VAL, '( observe', 'observe', ['support.function.action']);
  await expectScopes(VAL, '( observe', '15.000', ['constant.numeric.duration']);
});

test('; comments, also after a step, swallow parentheses', async () => {
  await expectScopes(VAL, '; Plan found', ';', ['comment.line.semicolon', 'punctuation.definition.comment']);
  await expectScopes(VAL, '0.01:(MOVE', ' a comment (not code)', ['comment.line.semicolon']);
});

test('a sequential step has no time; a planner trailer is left alone', async () => {
  await expectScopes(VAL, '(transmit', '(', ['punctuation.section.parens.begin']);
  await expectScopes(VAL, '(transmit', 'transmit', ['support.function.action']);
  await expectScopes(VAL, '(transmit', 'rock1', ['variable.other.object']);
  assert.deepEqual(await summary(VAL, 'Time: 54.0'), [['Time: 54.0', PLAN_SCOPE_NAME]]);
});

test('==> and <== delimit the hierarchical plan; the log before is plain text', async () => {
  await expectScopes(IPC, '==>', '==>', ['keyword.control.plan.begin']);
  await expectScopes(IPC, '<==', '<==', ['keyword.control.plan.end']);
  assert.deepEqual(await summary(IPC, 'Planner log'), [['Planner log (ignored) 0 1', PLAN_SCOPE_NAME]]);
});

test('an IPC 2020 primitive step: id, action, arguments', async () => {
  assert.deepEqual(await summary(IPC, '0 move rover1'), [
    ['0', 'entity.name.label.step' + S],
    ['move', 'support.function.action' + S],
    ['rover1', 'variable.other.object' + S],
    ['base', 'variable.other.object' + S],
    ['ridge', 'variable.other.object' + S],
  ]);
  await expectScopes(IPC, '1 (observe', '(', ['punctuation.section.parens.begin']);
  await expectScopes(IPC, '1 (observe', 'observe', ['support.function.action']);
  await expectScopes(IPC, '2 move[', 'move', ['support.function.action']);
  await expectScopes(IPC, '2 move[', '[', ['punctuation.section.brackets.begin']);
  await expectScopes(IPC, '2 move[', ',', ['punctuation.separator.comma']);
  await expectScopes(IPC, '2 move[', 'base', ['variable.other.object']);
});

test('root and its step ids', async () => {
  assert.deepEqual(await summary(IPC, 'root 3 4'), [
    ['root', 'keyword.control.root' + S],
    ['3', 'variable.other.label.step' + S],
    ['4', 'variable.other.label.step' + S],
  ]);
});

test('a decomposition: id, task, arguments, ->, method, subtask ids', async () => {
  assert.deepEqual(await summary(IPC, '3 inspect'), [
    ['3', 'entity.name.label.step' + S],
    ['inspect', 'support.function.task' + S],
    ['rover1', 'variable.other.object' + S],
    ['rock1', 'variable.other.object' + S],
    ['base', 'variable.other.object' + S],
    ['->', 'keyword.operator.decomposition' + S],
    ['inspect-direct', 'entity.name.function.method' + S],
    ['0', 'variable.other.label.step' + S],
    ['1', 'variable.other.label.step' + S],
    ['2', 'variable.other.label.step' + S],
  ]);
});

test("pandaPIparser's compressed method names keep their ; and brackets", async () => {
  await expectScopes(IPC, '4 (go r1)', 'go', ['support.function.task']);
  await expectScopes(IPC, '4 (go r1)', '<<m;t[a];m2;0;-1>;m3>', ['entity.name.function.method']);
  await expectScopes(IPC, '4 (go r1)', '1', ['variable.other.label.step']);
});

test('a ; line inside the block is a comment', async () => {
  await expectScopes(IPC, '; a comment line inside', ';', ['comment.line.semicolon', 'punctuation.definition.comment']);
});

test(';@ timing annotations: step id, start, duration', async () => {
  assert.deepEqual(await summary(IPC, ';@ 0 0.000'), [
    [';@', 'keyword.control.annotation' + S],
    ['0', 'variable.other.label.step' + S],
    ['0.000', 'constant.numeric.time' + S],
    ['[', 'punctuation.section.brackets.begin' + S],
    ['30.980', 'constant.numeric.duration' + S],
    [']', 'punctuation.section.brackets.end' + S],
  ]);
  await expectScopes(IPC, ';@ 3 0.000', '0.000', ['constant.numeric.time']);
  await expectScopes(IPC, '; plain comment', ' plain comment', ['comment.line.semicolon']);
});
