// VS Code client for the hipop language server (`hipop lsp`, stdio).

import * as vscode from 'vscode';
import {
  DocumentFilter,
  LanguageClient,
  LanguageClientOptions,
  ServerOptions,
  TransportKind,
} from 'vscode-languageclient/node';
import { resolveServerCommand } from './serverPath';

const PDDL_LANGUAGE_ID = 'hipop-pddl';
const PLAN_LANGUAGE_ID = 'hipop-plan';
/**
 * The names the server reads as plans (docs/plan-formats.md); it decides by
 * the document's name, not by its language id, and parses anything else as
 * PDDL.
 */
const PLAN_NAMES = '**/*.{plan,soln,sol,plan.json}';
const JSON_PLAN_NAMES = '**/*.plan.json';

/**
 * The documents sent to the server.
 *
 * - Domains and problems: the `hipop-pddl` language (.pddl, .hddl).
 * - Plans: the `hipop-plan` language (.plan, .soln, .sol). An untitled
 *   document only when its name is a plan's: `Untitled-1` switched to
 *   "Plan (hipop)" would be parsed as PDDL and drown in syntax errors.
 * - JSON plans (.plan.json) keep VS Code's own JSON language (colouring,
 *   folding, formatting); they are sent by name, whatever their language.
 */
export const DOCUMENT_SELECTOR: DocumentFilter[] = [
  { scheme: 'file', language: PDDL_LANGUAGE_ID },
  { scheme: 'untitled', language: PDDL_LANGUAGE_ID },
  { scheme: 'file', language: PLAN_LANGUAGE_ID },
  { scheme: 'untitled', language: PLAN_LANGUAGE_ID, pattern: PLAN_NAMES },
  { scheme: 'file', pattern: JSON_PLAN_NAMES },
  { scheme: 'untitled', pattern: JSON_PLAN_NAMES },
];
const CLIENT_ID = 'hipop'; // makes vscode-languageclient honour `hipop.trace.server`
const CLIENT_NAME = 'hipop Language Server';
const INSTALL_HINT = 'Install it with "cargo install --path cli" from the hipop repository, or point the "hipop.server.path" setting at the binary.';

let client: LanguageClient | undefined;
let outputChannel: vscode.OutputChannel;
let traceChannel: vscode.OutputChannel;
// Serialises start/stop so that rapid setting changes cannot race.
let pending: Promise<void> = Promise.resolve();

export function activate(context: vscode.ExtensionContext): Promise<void> {
  outputChannel = vscode.window.createOutputChannel(CLIENT_NAME);
  traceChannel = vscode.window.createOutputChannel(`${CLIENT_NAME} Trace`);
  context.subscriptions.push(outputChannel, traceChannel);

  context.subscriptions.push(
    vscode.commands.registerCommand('hipop.restartServer', () => enqueue(restart)),
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (e.affectsConfiguration('hipop.server')) {
        outputChannel.appendLine('hipop.server.* changed; restarting the language server.');
        void enqueue(restart);
      }
    }),
  );

  return enqueue(start);
}

export function deactivate(): Promise<void> {
  return enqueue(stop);
}

function enqueue(step: () => Promise<void>): Promise<void> {
  pending = pending.then(step, step);
  return pending;
}

async function restart(): Promise<void> {
  await stop();
  await start();
}

async function stop(): Promise<void> {
  const old = client;
  client = undefined;
  if (!old) {
    return;
  }
  try {
    await old.stop(2000);
  } catch (err) {
    outputChannel.appendLine(`Error while stopping the server: ${String(err)}`);
  }
  try {
    await old.dispose();
  } catch {
    // already disposed
  }
}

async function start(): Promise<void> {
  const config = vscode.workspace.getConfiguration('hipop');
  const configuredPath = config.get<string>('server.path', 'hipop');
  const extraArgs = config.get<string[]>('server.extraArgs', []).map(String);
  const cwd = vscode.workspace.workspaceFolders?.[0]?.uri.fsPath;

  const resolved = resolveServerCommand(configuredPath, { cwd });
  if (!resolved.ok) {
    outputChannel.appendLine(`Cannot start the server: hipop.server.path = '${configuredPath}': ${resolved.reason}.`);
    void showStartError(
      `hipop: cannot start the language server: ${resolved.reason} (setting "hipop.server.path" = "${configuredPath}"). ${INSTALL_HINT}`,
    );
    return;
  }

  const args = ['lsp', ...extraArgs];
  outputChannel.appendLine(`Starting ${resolved.command} ${args.join(' ')}`);

  const executable = {
    command: resolved.command,
    args,
    transport: TransportKind.stdio,
    options: cwd ? { cwd } : undefined,
  };
  const serverOptions: ServerOptions = { run: executable, debug: executable };
  const clientOptions: LanguageClientOptions = {
    documentSelector: DOCUMENT_SELECTOR,
    outputChannel,
    traceOutputChannel: traceChannel,
  };

  const next = new LanguageClient(CLIENT_ID, CLIENT_NAME, serverOptions, clientOptions);
  client = next;
  try {
    await next.start();
  } catch (err) {
    outputChannel.appendLine(`Failed to start ${resolved.command}: ${String(err)}`);
    if (client === next) {
      client = undefined;
    }
    try {
      await next.dispose();
    } catch {
      // ignore
    }
    void showStartError(
      `hipop: the language server '${resolved.command} ${args.join(' ')}' failed to start: ${errorMessage(err)}. Check the "hipop.server.path" and "hipop.server.extraArgs" settings.`,
    );
  }
}

function errorMessage(err: unknown): string {
  return err instanceof Error ? err.message : String(err);
}

async function showStartError(message: string): Promise<void> {
  const openSettings = 'Open Settings';
  const showOutput = 'Show Output';
  const choice = await vscode.window.showErrorMessage(message, openSettings, showOutput);
  if (choice === openSettings) {
    await vscode.commands.executeCommand('workbench.action.openSettings', 'hipop.server');
  } else if (choice === showOutput) {
    outputChannel.show(true);
  }
}
