// What the extension and the hipop server say to each other about plans, and
// the pure parts of the plan views: the initialization options built from
// the settings, the names of the read-only plan documents, the diff's title
// and the timeline's page.
//
// Kept free of any `vscode` import so that it can be unit-tested with plain
// node, and used by the test that drives the real server (test/lsp.test.js).

/** The server's notification at the end of each run on a problem. */
export const PLANNED_NOTIFICATION = 'hipop/planned';
/** The server's request for the last run on a problem. */
export const PLAN_REQUEST = 'hipop/plan';
/** The server's request for what the last repair of a problem changed. */
export const PLAN_DIFF_REQUEST = 'hipop/planDiff';
/**
 * The palette's commands. The server's own `hipop.writePlan` is not one of
 * them: vscode-languageclient registers a VS Code command of that id itself.
 */
export const PLAN_COMMANDS = {
  showPlan: 'hipop.showPlan',
  showTimeline: 'hipop.showTimeline',
  showPlanDiff: 'hipop.showPlanDiff',
  writePlanFile: 'hipop.writePlanFile',
} as const;

/** The server's command that writes `NAME.plan` beside the problem. */
export const WRITE_PLAN_COMMAND = 'hipop.writePlan';

export type PlanStatus = 'solved' | 'no-plan' | 'limit' | 'refused';

/** `hipop/planned`. */
export interface Planned {
  uri: string;
  status: PlanStatus;
  summary: string;
  repaired: boolean;
}

/** The answer to `hipop/plan` (null before any run). */
export interface PlanAnswer {
  uri: string;
  /** The problem's name. */
  problem: string;
  status: PlanStatus;
  summary: string;
  /** Whether the files are unchanged since the run. */
  current: boolean;
  repaired: boolean;
  expanded: number;
  seconds: number;
  // Only when the run found a plan:
  makespan?: number;
  actions?: number;
  format?: 'val' | 'hierarchical';
  /** The plan, as a plan file. */
  text?: string;
  /** Its timeline, an SVG document. */
  svg?: string;
}

/** A step of a plan, in the answer to `hipop/planDiff`. */
export interface PlanStep {
  step: string;
  start: number | null;
}

/** The answer to `hipop/planDiff` (null unless the last run was a repair). */
export interface PlanDiffAnswer {
  uri: string;
  summary: string;
  format: 'val' | 'hierarchical';
  instability: number;
  distance: number;
  /** The plan that was repaired, as a plan file. */
  old: string;
  /** The repaired plan. */
  new: string;
  removed: PlanStep[];
  added: PlanStep[];
  retimed: { old: PlanStep; new: PlanStep }[];
}

/** The answer to the command `hipop.writePlan`. */
export interface WrittenPlan {
  uri: string;
  path: string;
}

/** The settings of planning on save, as the server reads them. */
export interface PlanSettings {
  onSave: boolean;
  /** Seconds. */
  timeLimit: number;
}

export const DEFAULT_PLAN_SETTINGS: PlanSettings = { onSave: true, timeLimit: 5 };
/** The shortest time limit the server takes (it raises shorter ones). */
export const MIN_TIME_LIMIT = 0.1;

/** Reads a setting of the `hipop` section (`vscode.WorkspaceConfiguration` is one). */
export interface SettingsReader {
  get<T>(key: string, defaultValue: T): T;
}

/**
 * `hipop.plan.onSave` and `hipop.plan.timeLimit`, as the server reads them.
 * A value of the wrong type (settings.json is hand-edited) falls back to the
 * default; a time limit below the minimum is raised to it.
 */
export function planSettings(config: SettingsReader): PlanSettings {
  const onSave: unknown = config.get<unknown>('plan.onSave', DEFAULT_PLAN_SETTINGS.onSave);
  const timeLimit: unknown = config.get<unknown>('plan.timeLimit', DEFAULT_PLAN_SETTINGS.timeLimit);
  return {
    onSave: typeof onSave === 'boolean' ? onSave : DEFAULT_PLAN_SETTINGS.onSave,
    timeLimit:
      typeof timeLimit === 'number' && Number.isFinite(timeLimit)
        ? Math.max(timeLimit, MIN_TIME_LIMIT)
        : DEFAULT_PLAN_SETTINGS.timeLimit,
  };
}

/** The server's initialization options: `{ plan: { onSave, timeLimit } }`. */
export function initializationOptions(config: SettingsReader): { plan: PlanSettings } {
  return { plan: planSettings(config) };
}

/**
 * The settings of `workspace/didChangeConfiguration` when a `hipop.plan`
 * setting changes: `{ hipop: { plan: { onSave, timeLimit } } }`.
 */
export function planConfiguration(config: SettingsReader): { hipop: { plan: PlanSettings } } {
  return { hipop: initializationOptions(config) };
}

/** The scheme of the read-only plan documents. */
export const PLAN_SCHEME = 'hipop-plan';

/** What a plan document shows: the last plan, or a side of the repair diff. */
export type PlanView = 'plan' | 'before' | 'after';

/** The parts of a plan document's URI (`vscode.Uri.from` takes them). */
export interface PlanDocument {
  scheme: string;
  path: string;
  /** The problem's URI. */
  query: string;
}

/** A name usable as one segment of a path: the problem's, or its file's. */
export function documentName(name: string): string {
  const safe = name.replace(/[^A-Za-z0-9._-]+/g, '_').replace(/^\.+/, '');
  return safe.length > 0 ? safe : 'plan';
}

/**
 * The read-only document that shows a plan of a problem:
 * `hipop-plan:/NAME.plan` for the last plan, `hipop-plan:/NAME/before.plan`
 * and `…/after.plan` for both sides of the last repair. The name ends in
 * `.plan`, so VS Code gives it the `hipop-plan` language and its grammar;
 * the problem's URI is the query.
 */
export function planDocument(problemUri: string, name: string, view: PlanView): PlanDocument {
  const base = documentName(name);
  const path = view === 'plan' ? `/${base}.plan` : `/${base}/${view}.plan`;
  return { scheme: PLAN_SCHEME, path, query: problemUri };
}

/** What a plan document shows, from its URI's parts; undefined for another document. */
export function parsePlanDocument(doc: {
  scheme: string;
  path: string;
  query: string;
}): { problemUri: string; view: PlanView } | undefined {
  if (doc.scheme !== PLAN_SCHEME || doc.query.length === 0) {
    return undefined;
  }
  const m = /^\/[^/]+(?:\/(before|after))?\.plan$/.exec(doc.path);
  if (!m) {
    return undefined;
  }
  return { problemUri: doc.query, view: (m[1] as PlanView | undefined) ?? 'plan' };
}

/** The diff editor's title: `survey-two: instability 2, distance 2`. */
export function diffTitle(problem: string, diff: Pick<PlanDiffAnswer, 'instability' | 'distance'>): string {
  return `${problem}: instability ${diff.instability}, distance ${diff.distance}`;
}

/** The file name at the end of a URI, without its extension (`problem` for `…/problem.pddl`). */
export function fileStem(uri: string): string {
  const last = uri.replace(/[?#].*$/, '').split('/').pop() ?? '';
  let name = last;
  try {
    name = decodeURIComponent(last);
  } catch {
    // keep it encoded
  }
  const dot = name.lastIndexOf('.');
  return dot > 0 ? name.slice(0, dot) : name;
}

/** The text of a plan document when there is no plan to show (a plan file's comment). */
export function noPlanText(why: string): string {
  return `; ${why.replace(/\r?\n/g, ' ')}\n`;
}

/** What a plan document shows for an answer to `hipop/plan`. */
export function planDocumentText(plan: PlanAnswer | null): string {
  if (!plan) {
    return noPlanText('no plan yet: save the problem to plan it');
  }
  if (plan.text === undefined) {
    return noPlanText(`the last run found no plan: ${plan.summary}`);
  }
  return plan.text;
}

/** What a side of the diff shows for an answer to `hipop/planDiff`. */
export function diffDocumentText(diff: PlanDiffAnswer | null, view: 'before' | 'after'): string {
  if (!diff) {
    return noPlanText('the last run was not a repair: change the problem and save it again');
  }
  return view === 'before' ? diff.old : diff.new;
}

function escapeHtml(text: string): string {
  return text.replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);
}

/** The content security policy of the timeline: no script, images only from data: URIs. */
export const TIMELINE_CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'";

/** Whether a text is an SVG document (the server's timeline), not something else. */
export function isSvgDocument(svg: string): boolean {
  const start = svg.trimStart();
  return start.startsWith('<?xml') || start.startsWith('<svg');
}

/**
 * The timeline's page for an answer to `hipop/plan`: the SVG as an image
 * (a `data:` URI: an image runs no script), under a policy that allows
 * nothing else; the run's summary above it, or why there is no timeline.
 */
export function timelineHtml(plan: PlanAnswer | null, name: string): string {
  let body: string;
  if (!plan) {
    body = '<p>No plan yet: save the problem to plan it.</p>';
  } else if (plan.svg === undefined) {
    body = `<p>The last run found no plan: ${escapeHtml(plan.summary)}</p>`;
  } else if (!isSvgDocument(plan.svg)) {
    body = '<p>The server sent a timeline that is not an SVG document.</p>';
  } else {
    const data = Buffer.from(plan.svg, 'utf8').toString('base64');
    const stale = plan.current ? '' : ' (edited since: save to plan again)';
    body =
      `<p>${escapeHtml(plan.summary)}${escapeHtml(stale)}</p>\n` +
      `<img alt="the timeline of the plan of ${escapeHtml(name)}" src="data:image/svg+xml;base64,${data}">`;
  }
  return [
    '<!DOCTYPE html>',
    '<html lang="en">',
    '<head>',
    '<meta charset="utf-8">',
    `<meta http-equiv="Content-Security-Policy" content="${TIMELINE_CSP}">`,
    `<title>Timeline: ${escapeHtml(name)}</title>`,
    '<style>body { padding: 8px; } img { background: #fff; max-width: none; }</style>',
    '</head>',
    '<body>',
    body,
    '</body>',
    '</html>',
  ].join('\n');
}

/** The status bar's text for a run: an icon for its status, then its summary. */
export function statusText(planned: Pick<Planned, 'status' | 'summary'>): string {
  const icon: Record<PlanStatus, string> = {
    solved: '$(check)',
    'no-plan': '$(error)',
    limit: '$(watch)',
    refused: '$(circle-slash)',
  };
  return `${icon[planned.status] ?? '$(info)'} ${planned.summary}`;
}
