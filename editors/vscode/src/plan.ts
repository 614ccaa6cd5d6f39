// The views of the plans the server finds on save: the plan in a read-only
// editor, its timeline in a webview, the repair's diff in a diff editor, the
// last run's summary in the status bar, and the command that writes the plan
// beside the problem.

import * as vscode from 'vscode';
import { ExecuteCommandRequest, LanguageClient } from 'vscode-languageclient/node';
import {
  PLAN_COMMANDS,
  PLAN_DIFF_REQUEST,
  PLAN_REQUEST,
  PLAN_SCHEME,
  PLANNED_NOTIFICATION,
  PlanAnswer,
  PlanDiffAnswer,
  Planned,
  WRITE_PLAN_COMMAND,
  WrittenPlan,
  diffDocumentText,
  diffTitle,
  fileStem,
  parsePlanDocument,
  planDocument,
  planDocumentText,
  statusText,
  timelineHtml,
} from './planProtocol';

const PDDL_LANGUAGE_ID = 'hipop-pddl';

const NO_SERVER = 'hipop: the language server is not running (see the "hipop Language Server" output, or run "hipop: Restart Language Server").';
const NO_PROBLEM = 'hipop: open a problem (a .pddl or .hddl file) first.';

/**
 * The plan views. `client` gives the running language client, if any;
 * `attach` is called with each new client, before it starts.
 */
export class PlanViews implements vscode.TextDocumentContentProvider, vscode.Disposable {
  private readonly changed = new vscode.EventEmitter<vscode.Uri>();
  readonly onDidChange = this.changed.event;
  /** The last `hipop/planned` of each problem, by URI. */
  private readonly runs = new Map<string, Planned>();
  /** The timeline panel of each problem, by URI. */
  private readonly timelines = new Map<string, vscode.WebviewPanel>();
  private readonly status: vscode.StatusBarItem;
  private readonly disposables: vscode.Disposable[] = [];

  constructor(private readonly client: () => LanguageClient | undefined) {
    this.status = vscode.window.createStatusBarItem('hipop.plan', vscode.StatusBarAlignment.Left, 0);
    this.status.name = 'hipop plan';
    this.disposables.push(
      this.changed,
      this.status,
      vscode.workspace.registerTextDocumentContentProvider(PLAN_SCHEME, this),
      vscode.commands.registerCommand(PLAN_COMMANDS.showPlan, (uri?: unknown) => this.showPlan(uri)),
      vscode.commands.registerCommand(PLAN_COMMANDS.showTimeline, (uri?: unknown) => this.showTimeline(uri)),
      vscode.commands.registerCommand(PLAN_COMMANDS.showPlanDiff, (uri?: unknown) => this.showPlanDiff(uri)),
      vscode.commands.registerCommand(PLAN_COMMANDS.writePlanFile, (uri?: unknown) => this.writePlanFile(uri)),
      vscode.window.onDidChangeActiveTextEditor(() => this.updateStatus()),
    );
  }

  dispose(): void {
    for (const panel of this.timelines.values()) {
      panel.dispose();
    }
    this.disposables.forEach((d) => d.dispose());
  }

  /**
   * Listens to a new client's `hipop/planned` (until it is disposed);
   * forgets the last runs of the one before.
   */
  attach(client: LanguageClient): void {
    this.runs.clear();
    this.updateStatus();
    client.onNotification(PLANNED_NOTIFICATION, (params: Planned) => {
      void this.planned(params);
    });
  }

  /** A run ended: the status bar, the open plan documents and timelines of its problem show it. */
  private async planned(params: Planned): Promise<void> {
    const key = normalize(params.uri);
    this.runs.set(key, params);
    this.updateStatus();
    for (const doc of vscode.workspace.textDocuments) {
      const shown = parsePlanDocument(doc.uri);
      if (shown && normalize(shown.problemUri) === key) {
        this.changed.fire(doc.uri);
      }
    }
    const panel = this.timelines.get(key);
    if (panel) {
      const plan = await this.request<PlanAnswer>(PLAN_REQUEST, key, false);
      if (plan !== undefined && this.timelines.get(key) === panel) {
        panel.webview.html = timelineHtml(plan, plan?.problem ?? fileStem(key));
      }
    }
  }

  /** The text of a plan document, asked of the server each time it is shown or changed. */
  async provideTextDocumentContent(uri: vscode.Uri): Promise<string> {
    const shown = parsePlanDocument(uri);
    if (!shown) {
      return '';
    }
    if (shown.view === 'plan') {
      const plan = await this.request<PlanAnswer>(PLAN_REQUEST, shown.problemUri, false);
      return plan === undefined ? '; the language server is not running\n' : planDocumentText(plan);
    }
    const diff = await this.request<PlanDiffAnswer>(PLAN_DIFF_REQUEST, shown.problemUri, false);
    return diff === undefined ? '; the language server is not running\n' : diffDocumentText(diff, shown.view);
  }

  /**
   * The problem a command is about and the last run on it; `undefined`
   * once the user was told why there is none.
   */
  private async lastRun(arg: unknown): Promise<{ problem: string; plan: PlanAnswer } | undefined> {
    const problem = this.problemOf(arg);
    if (!problem) {
      return undefined;
    }
    const plan = await this.request<PlanAnswer>(PLAN_REQUEST, problem, true);
    if (plan === undefined) {
      return undefined;
    }
    if (plan === null) {
      void vscode.window.showInformationMessage(`hipop: no plan for ${fileStem(problem)} yet: save the problem to plan it.`);
      return undefined;
    }
    return { problem, plan };
  }

  private async showPlan(arg: unknown): Promise<void> {
    const last = await this.lastRun(arg);
    if (!last) {
      return;
    }
    const { problem, plan } = last;
    const doc = await vscode.workspace.openTextDocument(vscode.Uri.from(planDocument(problem, plan.problem, 'plan')));
    await vscode.window.showTextDocument(doc, { preview: false, viewColumn: vscode.ViewColumn.Beside });
    if (plan.text === undefined) {
      void vscode.window.showInformationMessage(`hipop: the last run found no plan: ${plan.summary}`);
    }
  }

  private async showTimeline(arg: unknown): Promise<void> {
    const last = await this.lastRun(arg);
    if (!last) {
      return;
    }
    const { problem, plan } = last;
    let panel = this.timelines.get(problem);
    if (panel) {
      panel.reveal(undefined, true);
    } else {
      panel = vscode.window.createWebviewPanel(
        'hipop.timeline',
        `Timeline: ${plan.problem}`,
        { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
        { enableScripts: false, enableForms: false, localResourceRoots: [] },
      );
      const opened = panel;
      this.timelines.set(problem, opened);
      opened.onDidDispose(() => {
        if (this.timelines.get(problem) === opened) {
          this.timelines.delete(problem);
        }
      });
    }
    panel.webview.html = timelineHtml(plan, plan.problem);
  }

  private async showPlanDiff(arg: unknown): Promise<void> {
    const problem = this.problemOf(arg);
    if (!problem) {
      return;
    }
    const diff = await this.request<PlanDiffAnswer>(PLAN_DIFF_REQUEST, problem, true);
    if (diff === undefined) {
      return;
    }
    if (diff === null) {
      void vscode.window.showInformationMessage(
        'hipop: the last run was not a repair: change the problem and save it again.',
      );
      return;
    }
    const plan = await this.request<PlanAnswer>(PLAN_REQUEST, problem, false);
    const name = plan?.problem ?? fileStem(problem);
    const before = vscode.Uri.from(planDocument(problem, name, 'before'));
    const after = vscode.Uri.from(planDocument(problem, name, 'after'));
    // Already open: show the last repair, not the one before.
    this.changed.fire(before);
    this.changed.fire(after);
    await vscode.commands.executeCommand('vscode.diff', before, after, diffTitle(name, diff), { preview: false });
  }

  private async writePlanFile(arg: unknown): Promise<void> {
    const problem = this.problemOf(arg);
    if (!problem) {
      return;
    }
    const client = this.runningClient();
    if (!client) {
      return;
    }
    let written: WrittenPlan | null;
    try {
      written = (await client.sendRequest(ExecuteCommandRequest.type, {
        command: WRITE_PLAN_COMMAND,
        arguments: [problem],
      })) as WrittenPlan | null;
    } catch (err) {
      void vscode.window.showWarningMessage(`hipop: cannot write the plan: ${errorMessage(err)}`);
      return;
    }
    if (!written) {
      return;
    }
    const open = 'Open';
    const choice = await vscode.window.showInformationMessage(`hipop: wrote ${written.path}`, open);
    if (choice === open) {
      await vscode.window.showTextDocument(vscode.Uri.file(written.path));
    }
  }

  /**
   * The problem a command is about: the URI it was given (the status bar
   * gives one), else the active editor's, a domain or problem or a plan
   * document (whose problem it is). Says why when there is none.
   */
  private problemOf(arg: unknown): string | undefined {
    if (arg instanceof vscode.Uri) {
      return normalize(arg.toString());
    }
    if (typeof arg === 'string' && arg.length > 0) {
      return normalize(arg);
    }
    const problem = activeProblem();
    if (!problem) {
      void vscode.window.showInformationMessage(NO_PROBLEM);
    }
    return problem;
  }

  private runningClient(): LanguageClient | undefined {
    const client = this.client();
    if (!client) {
      void vscode.window.showWarningMessage(NO_SERVER);
    }
    return client;
  }

  /**
   * Asks the server about a problem. `undefined` when there is no server or
   * the request failed (said in a message when `loud`); `null` when the
   * server has nothing.
   */
  private async request<T>(method: string, problem: string, loud: boolean): Promise<T | null | undefined> {
    const client = loud ? this.runningClient() : this.client();
    if (!client) {
      return undefined;
    }
    try {
      return await client.sendRequest<T | null>(method, { uri: problem });
    } catch (err) {
      if (loud) {
        void vscode.window.showWarningMessage(`hipop: ${method} failed: ${errorMessage(err)}`);
      }
      return undefined;
    }
  }

  /** Shows the last run of the active editor's problem, if any. */
  private updateStatus(): void {
    const problem = activeProblem();
    const run = problem ? this.runs.get(problem) : undefined;
    if (!problem || !run) {
      this.status.hide();
      return;
    }
    this.status.text = statusText(run);
    this.status.tooltip = `hipop: the last run on ${fileStem(problem)}${run.repaired ? ' (a repair)' : ''}. Click to show the plan.`;
    this.status.command = { title: 'Show Plan', command: PLAN_COMMANDS.showPlan, arguments: [problem] };
    this.status.show();
  }
}

/** The active editor's problem (or domain): its URI, or a plan document's problem. */
function activeProblem(): string | undefined {
  const doc = vscode.window.activeTextEditor?.document;
  if (!doc) {
    return undefined;
  }
  const shown = parsePlanDocument(doc.uri);
  if (shown) {
    return normalize(shown.problemUri);
  }
  return doc.languageId === PDDL_LANGUAGE_ID ? normalize(doc.uri.toString()) : undefined;
}

/** A URI as the language client sends it (`vscode.Uri#toString`), whoever wrote it. */
function normalize(uri: string): string {
  try {
    return vscode.Uri.parse(uri, true).toString();
  } catch {
    return uri;
  }
}

function errorMessage(err: unknown): string {
  return err instanceof Error ? err.message : String(err);
}
