'use strict';
// Tokenizes real PDDL / HDDL with the extension's TextMate grammar (the same
// engine VS Code uses: vscode-textmate + oniguruma WASM) and checks the exact
// scope stack of individual tokens. No VS Code download needed.
//
// Run: node --test test/grammar.test.js

const test = require('node:test');
const assert = require('node:assert/strict');
const { tokenize, SCOPE_NAME } = require('./tokenize');

const S = '.hipop-pddl';

const DOMAIN = `; Rover domain: durative actions, HDDL tasks and methods, HiPOP extensions
(define (domain rover-htn)
  (:requirements :typing :durative-actions :hierarchy :numeric-fluents)
  (:types robot location - object
          vehicle - (either robot thing))
  (:predicates (at ?r - robot ?l - location) (at-robby ?robot-1))
  (:functions (fuel ?r - robot))
  (:task deliver :parameters (?p - package ?l - location))
  (:durative-action move-to ; trailing comment (not code)
    :parameters (?r - robot ?from ?to - location)
    :agent ?r
    :duration (= ?duration 10.5)
    :condition (and (at start (at ?r ?from)) (over all (ok ?r)))
    :effect (and (at end (not (at ?r ?from)))
                 (at end (decrease (fuel ?r) 2))
                 (forall (?x - robot) (when (ok ?x) (scale-up (fuel ?x) 1))))
    :conflicts (move-to ?r ?to ?from))
  (:method m-deliver
    :parameters (?p - package ?l - location ?r - robot)
    :task (deliver ?p ?l)
    :ordered-subtasks (and (t1 (move-to ?r ?l ?l)) (t2 (noop)))
    :ordering (< t1 t2))
  (:durative-method dm-deliver
    :parameters ()
    :task (deliver ?p ?l))
  (:action pick-up :parameters ()))
(define (problem p1) (:domain rover-htn)
  (:objects r1 - robot)
  (:htn :parameters () :ordered-subtasks (and (t1 (deliver p1 l1))))
  (:init (at r1 l1) (at 10 (ok r1)) (= (fuel r1) -3))
  (:metric minimize (total-time)))`;

let linesPromise;
function lines() {
  linesPromise ??= tokenize(DOMAIN);
  return linesPromise;
}

/** Finds line `lineNo` (1-based) of DOMAIN that contains `needle`, for readable tests. */
function lineOf(needle) {
  const idx = DOMAIN.split('\n').findIndex((l) => l.includes(needle));
  assert.notEqual(idx, -1, `test bug: no line contains ${JSON.stringify(needle)}`);
  return idx;
}

/**
 * Returns the scope stack of the `occurrence`-th token whose text is exactly
 * `text` on the first line that contains `lineNeedle`.
 */
async function scopesOf(lineNeedle, text, occurrence = 0) {
  const idx = lineOf(lineNeedle);
  const tokens = (await lines())[idx];
  const matching = tokens.filter((t) => t.text === text);
  assert.ok(
    matching.length > occurrence,
    `no token ${JSON.stringify(text)} (#${occurrence}) on line ${idx + 1}; tokens: ` +
      JSON.stringify(tokens.map((t) => t.text)),
  );
  return matching[occurrence].scopes;
}

/** Asserts the exact scope stack: the root scope followed by `scopes` (suffix added). */
async function expectScopes(lineNeedle, text, scopes, occurrence = 0) {
  const actual = await scopesOf(lineNeedle, text, occurrence);
  assert.deepEqual(actual, [SCOPE_NAME, ...scopes.map((s) => s + S)], `scopes of ${JSON.stringify(text)}`);
}

test('a ; line comment is comment.line.semicolon', async () => {
  await expectScopes('; Rover domain', ';', ['comment.line.semicolon', 'punctuation.definition.comment']);
  await expectScopes('; Rover domain', ' Rover domain: durative actions, HDDL tasks and methods, HiPOP extensions', [
    'comment.line.semicolon',
  ]);
});

test('a trailing comment swallows parentheses and keywords', async () => {
  await expectScopes('trailing comment', ' trailing comment (not code)', ['comment.line.semicolon']);
});

test('define / domain / problem and the domain name', async () => {
  await expectScopes('(define (domain', 'define', ['keyword.control.define']);
  await expectScopes('(define (domain', 'domain', ['keyword.control.define']);
  await expectScopes('(define (domain', 'rover-htn', ['entity.name.namespace']);
  await expectScopes('(define (problem', 'problem', ['keyword.control.define']);
  await expectScopes('(define (problem', ':domain', ['keyword.control.section']);
  await expectScopes('(define (problem', 'rover-htn', ['entity.name.namespace']);
});

test(':durative-action is a section keyword and its name is entity.name.function', async () => {
  await expectScopes('(:durative-action', ':durative-action', ['keyword.control.section']);
  await expectScopes('(:durative-action', 'move-to', ['entity.name.function']);
});

test('names of :action, :task, :method and :durative-method are entity.name.function', async () => {
  await expectScopes('(:action pick-up', 'pick-up', ['entity.name.function']);
  await expectScopes('(:task deliver', ':task', ['keyword.control.section']);
  await expectScopes('(:task deliver', 'deliver', ['entity.name.function']);
  await expectScopes('(:method m-deliver', ':method', ['keyword.control.section']);
  await expectScopes('(:method m-deliver', 'm-deliver', ['entity.name.function']);
  await expectScopes('(:durative-method', ':durative-method', ['keyword.control.section']);
  await expectScopes('(:durative-method', 'dm-deliver', ['entity.name.function']);
});

test('section keywords after ( are keyword.control.section', async () => {
  for (const [needle, kw] of [
    ['(:requirements', ':requirements'],
    ['(:types', ':types'],
    ['(:predicates', ':predicates'],
    ['(:functions', ':functions'],
    ['(:objects', ':objects'],
    ['(:htn', ':htn'],
    ['(:init', ':init'],
    ['(:metric', ':metric'],
  ]) {
    await expectScopes(needle, kw, ['keyword.control.section']);
  }
});

test('fields inside definitions are keyword.other.field, including :conflicts and :agent', async () => {
  await expectScopes(':conflicts', ':conflicts', ['keyword.other.field']);
  await expectScopes(':agent ?r', ':agent', ['keyword.other.field']);
  await expectScopes('    :parameters (?r - robot ?from', ':parameters', ['keyword.other.field']);
  await expectScopes(':duration (=', ':duration', ['keyword.other.field']);
  await expectScopes(':condition (and', ':condition', ['keyword.other.field']);
  await expectScopes(':effect (and', ':effect', ['keyword.other.field']);
  await expectScopes('    :task (deliver ?p ?l)', ':task', ['keyword.other.field']);
  await expectScopes(':ordered-subtasks (and (t1 (move-to', ':ordered-subtasks', ['keyword.other.field']);
  await expectScopes(':ordering', ':ordering', ['keyword.other.field']);
});

test('requirements are constant.language.requirement', async () => {
  await expectScopes('(:requirements', ':typing', ['constant.language.requirement']);
  await expectScopes('(:requirements', ':durative-actions', ['constant.language.requirement']);
  await expectScopes('(:requirements', ':numeric-fluents', ['constant.language.requirement']);
});

test('?r and ?robot-1 are single variable.parameter tokens', async () => {
  await expectScopes(':agent ?r', '?r', ['variable.parameter']);
  await expectScopes('(at-robby', '?robot-1', ['variable.parameter']);
  await expectScopes(':duration (=', '?duration', ['variable.parameter']);
});

test('at start / at end / over all are keyword.operator.temporal', async () => {
  await expectScopes(':condition (and', 'at start', ['keyword.operator.temporal']);
  await expectScopes(':condition (and', 'over all', ['keyword.operator.temporal']);
  await expectScopes(':effect (and', 'at end', ['keyword.operator.temporal']);
  // timed initial literal
  await expectScopes('(:init', 'at', ['keyword.operator.temporal'], 1);
});

test('the predicate `at` is not mistaken for a temporal qualifier', async () => {
  await expectScopes(':condition (and', 'at', ['support.function']);
  await expectScopes('(:predicates', 'at', ['support.function']);
  await expectScopes('(:predicates', 'at-robby', ['support.function']);
  await expectScopes('(:init', 'at', ['support.function'], 0);
});

test('numbers are constant.numeric', async () => {
  await expectScopes(':duration (=', '10.5', ['constant.numeric']);
  await expectScopes('(decrease (fuel ?r) 2)', '2', ['constant.numeric']);
  await expectScopes('(:init', '10', ['constant.numeric']);
  await expectScopes('(:init', '-3', ['constant.numeric']);
});

test('the type after - is entity.name.type', async () => {
  await expectScopes('    :parameters (?r - robot ?from', '-', ['punctuation.separator.type']);
  await expectScopes('    :parameters (?r - robot ?from', 'robot', ['entity.name.type']);
  await expectScopes('    :parameters (?r - robot ?from', 'location', ['entity.name.type']);
  await expectScopes('(:objects r1', 'robot', ['entity.name.type']);
});

test('a type glued to its dash (?x -Type, IPC 2023) is entity.name.type', async () => {
  const [types, preds] = await tokenize('(:types Location Robot -Object)\n(:predicates (at ?r -Robot ?l - Location))');
  const scope = (line, text) => line.find((t) => t.text === text).scopes.at(-1);
  assert.equal(scope(types, '-'), 'punctuation.separator.type' + S);
  assert.equal(scope(types, 'Object'), 'entity.name.type' + S);
  assert.equal(scope(types, 'Location'), 'entity.name.type' + S);
  assert.equal(scope(preds, '-'), 'punctuation.separator.type' + S);
  assert.equal(scope(preds, 'Robot'), 'entity.name.type' + S);
  assert.equal(scope(preds, 'Location'), 'entity.name.type' + S);
});

test('(:types ...) names and (either ...) members are types, either is storage.type', async () => {
  await expectScopes('(:types robot', 'robot', ['entity.name.type']);
  await expectScopes('(:types robot', 'object', ['entity.name.type']);
  await expectScopes('vehicle - (either', 'vehicle', ['entity.name.type']);
  await expectScopes('vehicle - (either', 'either', ['storage.type']);
  await expectScopes('vehicle - (either', 'thing', ['entity.name.type']);
});

test('logical and numeric operators', async () => {
  await expectScopes(':condition (and', 'and', ['keyword.operator.logical']);
  await expectScopes(':effect (and', 'not', ['keyword.operator.logical']);
  await expectScopes('(forall (?x - robot)', 'forall', ['keyword.operator.logical']);
  await expectScopes('(forall (?x - robot)', 'when', ['keyword.operator.logical']);
  await expectScopes('(decrease (fuel ?r) 2)', 'decrease', ['keyword.operator.numeric']);
  await expectScopes('(forall (?x - robot)', 'scale-up', ['keyword.operator.numeric']);
  await expectScopes(':duration (=', '=', ['keyword.operator.comparison']);
  await expectScopes('(:metric', 'minimize', ['keyword.operator.optimization']);
});

test('applications and subtask labels', async () => {
  await expectScopes('    :task (deliver ?p ?l)', 'deliver', ['support.function']);
  await expectScopes(':conflicts', 'move-to', ['support.function']);
  await expectScopes(':ordered-subtasks (and (t1 (move-to', 't1', ['entity.name.label.subtask']);
  await expectScopes(':ordered-subtasks (and (t1 (move-to', 'move-to', ['support.function']);
});

test('parentheses are punctuation', async () => {
  await expectScopes('(:functions', '(', ['punctuation.section.parens.begin']);
  await expectScopes('(:functions', ')', ['punctuation.section.parens.end']);
});

test('a definition name on the line after the keyword is still entity.name.function', async () => {
  const [l1, l2, l3, l4] = await tokenize('(:durative-action ; the name follows\n  ; another comment\n  long-move\n  :parameters ())');
  assert.deepEqual(
    l1.map((t) => [t.text, t.scopes.at(-1)]),
    [
      ['(', 'punctuation.section.parens.begin' + S],
      [':durative-action', 'keyword.control.section' + S],
      [' ', SCOPE_NAME],
      [';', 'punctuation.definition.comment' + S],
      [' the name follows', 'comment.line.semicolon' + S],
    ],
  );
  assert.equal(l2.find((t) => t.text === ';').scopes.at(-1), 'punctuation.definition.comment' + S);
  assert.deepEqual(l3.find((t) => t.text === 'long-move').scopes, [SCOPE_NAME, 'entity.name.function' + S]);
  assert.deepEqual(l4.find((t) => t.text === ':parameters').scopes, [SCOPE_NAME, 'keyword.other.field' + S]);
});
