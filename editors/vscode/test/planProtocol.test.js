'use strict';
// The pure parts of the plan views (out/planProtocol.js, which imports no
// `vscode`): the initialization options built from the settings, the plan
// documents' names, the diff's title and the timeline's page.

const test = require('node:test');
const assert = require('node:assert/strict');
const protocol = require('../out/planProtocol.js');

/** A `WorkspaceConfiguration` of the `hipop` section holding `values`. */
const settings = (values) => ({ get: (key, dflt) => (key in values ? values[key] : dflt) });

test('initialization options: the defaults when nothing is set', () => {
  assert.deepEqual(protocol.initializationOptions(settings({})), { plan: { onSave: true, timeLimit: 5 } });
});

test('initialization options: the settings as the server reads them', () => {
  assert.deepEqual(
    protocol.initializationOptions(settings({ 'plan.onSave': false, 'plan.timeLimit': 12.5 })),
    { plan: { onSave: false, timeLimit: 12.5 } },
  );
});

test('initialization options: a hand-edited value of the wrong type falls back to the default', () => {
  assert.deepEqual(
    protocol.initializationOptions(settings({ 'plan.onSave': 'no', 'plan.timeLimit': '10' })),
    { plan: { onSave: true, timeLimit: 5 } },
  );
  assert.deepEqual(
    protocol.initializationOptions(settings({ 'plan.timeLimit': Number.POSITIVE_INFINITY })).plan.timeLimit,
    5,
  );
  assert.equal(protocol.initializationOptions(settings({ 'plan.timeLimit': null })).plan.timeLimit, 5);
});

test('initialization options: a time limit below the minimum is raised to it', () => {
  assert.equal(protocol.initializationOptions(settings({ 'plan.timeLimit': 0 })).plan.timeLimit, 0.1);
  assert.equal(protocol.initializationOptions(settings({ 'plan.timeLimit': -3 })).plan.timeLimit, 0.1);
  assert.equal(protocol.initializationOptions(settings({ 'plan.timeLimit': 0.25 })).plan.timeLimit, 0.25);
});

const PROBLEM = 'file:///work/survey/problem.pddl';

test('the plan document: hipop-plan:/NAME.plan, the problem in its query', () => {
  assert.deepEqual(protocol.planDocument(PROBLEM, 'survey-two', 'plan'), {
    scheme: 'hipop-plan',
    path: '/survey-two.plan',
    query: PROBLEM,
  });
  assert.deepEqual(protocol.parsePlanDocument(protocol.planDocument(PROBLEM, 'survey-two', 'plan')), {
    problemUri: PROBLEM,
    view: 'plan',
  });
});

test('the diff documents: …/NAME/before.plan and …/NAME/after.plan', () => {
  for (const view of ['before', 'after']) {
    const doc = protocol.planDocument(PROBLEM, 'survey-two', view);
    assert.deepEqual(doc, { scheme: 'hipop-plan', path: `/survey-two/${view}.plan`, query: PROBLEM });
    assert.deepEqual(protocol.parsePlanDocument(doc), { problemUri: PROBLEM, view });
  }
});

test('every plan document ends in .plan: VS Code gives it the hipop-plan language', () => {
  const pkg = require('../package.json');
  const plan = pkg.contributes.languages.find((l) => l.id === 'hipop-plan');
  for (const view of ['plan', 'before', 'after']) {
    const { path } = protocol.planDocument(PROBLEM, 'survey-two', view);
    assert.ok(plan.extensions.some((ext) => path.endsWith(ext)), path);
  }
});

test('a name that is not a path segment is made one', () => {
  assert.equal(protocol.planDocument(PROBLEM, 'a/b c', 'plan').path, '/a_b_c.plan');
  assert.equal(protocol.planDocument(PROBLEM, '..', 'plan').path, '/plan.plan');
  assert.equal(protocol.planDocument(PROBLEM, '', 'before').path, '/plan/before.plan');
  assert.equal(protocol.planDocument(PROBLEM, 'p-01_x.y', 'plan').path, '/p-01_x.y.plan');
});

test('other documents are not plan documents', () => {
  for (const doc of [
    { scheme: 'file', path: '/survey-two.plan', query: PROBLEM },
    { scheme: 'hipop-plan', path: '/survey-two.plan', query: '' },
    { scheme: 'hipop-plan', path: '/survey-two.pddl', query: PROBLEM },
    { scheme: 'hipop-plan', path: '/survey-two/middle.plan', query: PROBLEM },
    { scheme: 'hipop-plan', path: '/a/b/before.plan', query: PROBLEM },
  ]) {
    assert.equal(protocol.parsePlanDocument(doc), undefined, JSON.stringify(doc));
  }
});

test('the diff title names the problem and both figures', () => {
  assert.equal(
    protocol.diffTitle('survey-two', { instability: 2, distance: 2 }),
    'survey-two: instability 2, distance 2',
  );
});

test('a file stem from a URI', () => {
  assert.equal(protocol.fileStem(PROBLEM), 'problem');
  assert.equal(protocol.fileStem('file:///w/p%2001.hddl'), 'p 01');
  assert.equal(protocol.fileStem('untitled:Untitled-1'), 'untitled:Untitled-1');
  assert.equal(protocol.fileStem('file:///w/.hidden'), '.hidden');
});

const SOLVED = {
  uri: PROBLEM,
  problem: 'survey-two',
  status: 'solved',
  summary: 'plan: 3 actions, makespan 9.03, 0.01 s',
  current: true,
  repaired: false,
  expanded: 12,
  seconds: 0.01,
  makespan: 9.03,
  actions: 3,
  format: 'val',
  text: '0.01: (observe r1 a p1) [2]\n',
  svg: '<?xml version="1.0"?>\n<svg xmlns="http://www.w3.org/2000/svg"><text>move</text></svg>\n',
};
const NO_PLAN = { ...SOLVED, status: 'no-plan', summary: 'no plan exists: <why>' };
for (const key of ['makespan', 'actions', 'format', 'text', 'svg']) delete NO_PLAN[key];

test('what a plan document shows: the plan, or why there is none, as a comment', () => {
  assert.equal(protocol.planDocumentText(SOLVED), SOLVED.text);
  assert.equal(protocol.planDocumentText(null), '; no plan yet: save the problem to plan it\n');
  assert.equal(protocol.planDocumentText(NO_PLAN), '; the last run found no plan: no plan exists: <why>\n');
  assert.equal(protocol.noPlanText('a\nb'), '; a b\n');
});

test('what the diff documents show: the old and the new plan', () => {
  const diff = { old: 'old\n', new: 'new\n', instability: 2, distance: 2 };
  assert.equal(protocol.diffDocumentText(diff, 'before'), 'old\n');
  assert.equal(protocol.diffDocumentText(diff, 'after'), 'new\n');
  assert.match(protocol.diffDocumentText(null, 'after'), /^; the last run was not a repair: change the problem and save it again\n$/);
});

test('the timeline: the SVG as a data: image under a policy that allows nothing else', () => {
  const html = protocol.timelineHtml(SOLVED, 'survey-two');
  assert.ok(
    html.includes(
      `<meta http-equiv="Content-Security-Policy" content="default-src 'none'; img-src data:; style-src 'unsafe-inline'">`,
    ),
    html,
  );
  const m = /<img [^>]*src="data:image\/svg\+xml;base64,([A-Za-z0-9+/=]+)">/.exec(html);
  assert.ok(m, html);
  assert.equal(Buffer.from(m[1], 'base64').toString('utf8'), SOLVED.svg);
  assert.ok(html.includes('<p>plan: 3 actions, makespan 9.03, 0.01 s</p>'), html);
  assert.ok(!/<script|<svg/i.test(html), 'the SVG is not inlined');
});

test('the timeline says when the files changed since the run', () => {
  const html = protocol.timelineHtml({ ...SOLVED, current: false }, 'survey-two');
  assert.ok(html.includes('(edited since: save to plan again)'), html);
});

test('the timeline of a run without plan says why, escaped', () => {
  const html = protocol.timelineHtml(NO_PLAN, 'survey-two');
  assert.ok(html.includes('<p>The last run found no plan: no plan exists: &#60;why&#62;</p>'), html);
  assert.ok(!html.includes('<img'), html);
  assert.match(protocol.timelineHtml(null, 'survey-two'), /No plan yet: save the problem to plan it/);
});

test('a timeline that is not an SVG document is not shown', () => {
  for (const svg of ['<html><script>alert(1)</script></html>', 'plain text', '']) {
    const html = protocol.timelineHtml({ ...SOLVED, svg }, 'survey-two');
    assert.ok(!html.includes('<img'), svg);
    assert.ok(!html.includes('alert'), svg);
  }
  assert.ok(protocol.isSvgDocument('  <svg xmlns="http://www.w3.org/2000/svg"/>'));
  assert.ok(protocol.isSvgDocument('<?xml version="1.0"?><svg/>'));
});

test('the status bar: an icon for the status, then the summary', () => {
  assert.equal(protocol.statusText(SOLVED), '$(check) plan: 3 actions, makespan 9.03, 0.01 s');
  assert.equal(protocol.statusText({ status: 'no-plan', summary: 'no plan exists' }), '$(error) no plan exists');
  assert.equal(protocol.statusText({ status: 'limit', summary: 'x' }), '$(watch) x');
  assert.equal(protocol.statusText({ status: 'refused', summary: 'x' }), '$(circle-slash) x');
});
