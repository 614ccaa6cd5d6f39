// VS Code client for the hipop language server (`hipop lsp`, stdio).

import * as vscode from 'vscode';
import {
  CloseAction,
  DidChangeConfigurationNotification,
  DocumentFilter,
  ErrorAction,
  ErrorHandler,
  Executable,
  LanguageClient,
  LanguageClientOptions,
  ServerOptions,
} from 'vscode-languageclient/node';
import { PlanViews } from './plan';
import { initializationOptions, planConfiguration } from './planProtocol';
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
let planViews: PlanViews | undefined;
// Serialises start/stop so that rapid setting changes cannot race.
let pending: Promise<void> = Promise.resolve();

export function activate(context: vscode.ExtensionContext): Promise<void> {
  outputChannel = vscode.window.createOutputChannel(CLIENT_NAME);
  traceChannel = vscode.window.createOutputChannel(`${CLIENT_NAME} Trace`);
  context.subscriptions.push(outputChannel, traceChannel);
  planViews = new PlanViews(() => client);
  context.subscriptions.push(planViews);

  context.subscriptions.push(
    vscode.commands.registerCommand('hipop.restartServer', () => enqueue(restart)),
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (e.affectsConfiguration('hipop.server')) {
        outputChannel.appendLine('hipop.server.* changed; restarting the language server.');
        void enqueue(restart);
      } else if (e.affectsConfiguration('hipop.plan')) {
        void enqueue(sendPlanSettings);
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

  const executable = serverExecutable(resolved.command, extraArgs, cwd);
  const commandLine = [executable.command, ...(executable.args ?? [])].join(' ');
  outputChannel.appendLine(`Starting ${commandLine}`);

  const serverOptions: ServerOptions = { run: executable, debug: executable };
  const stderr = new StderrTap(outputChannel);
  const errors = new StartErrors();
  const clientOptions: LanguageClientOptions = {
    documentSelector: DOCUMENT_SELECTOR,
    outputChannel: stderr.channel,
    traceOutputChannel: traceChannel,
    // A failed start is reported once, below, with what the server printed.
    initializationFailedHandler: () => false,
    errorHandler: errors,
    // Planning on save; a change of these settings is sent as it is made
    // (sendPlanSettings), without a restart.
    initializationOptions: initializationOptions(config),
  };

  const next = new HipopClient(serverOptions, clientOptions, errors);
  errors.afterStart = next.createDefaultErrorHandler();
  client = next;
  planViews?.attach(next);
  try {
    await next.start();
    if (!next.isRunning()) {
      // vscode-languageclient 9 resolves `start` when the connection
      // closes while it starts (the server exited at once).
      throw errors.lastError ?? new Error('the connection to the server closed while it started');
    }
    errors.starting = false;
  } catch (err) {
    // (`errors.starting` stays true: this client is disposed, quietly.)
    outputChannel.appendLine(`Failed to start ${commandLine}: ${String(err)}`);
    if (client === next) {
      client = undefined;
    }
    try {
      await next.dispose();
    } catch {
      // ignore
    }
    // The server's last words may still be in the pipe when the write to
    // its closed stdin fails.
    await new Promise((resolve) => setTimeout(resolve, STDERR_GRACE_MS));
    const said = stderr.firstLine();
    void showStartError(
      `hipop: the language server '${commandLine}' failed to start: ${said ? `it said "${said}"` : errorMessage(err)}. Check the "hipop.server.path" and "hipop.server.extraArgs" settings.`,
    );
  }
}

/**
 * Sends the `hipop.plan.*` settings to the running server
 * (`workspace/didChangeConfiguration`). Not through the client's
 * `synchronize.configurationSection`: that sends each change of any `hipop`
 * setting, also to a server being restarted for a new `hipop.server.path`,
 * and shows its failure as an error.
 */
async function sendPlanSettings(): Promise<void> {
  if (!client?.isRunning()) {
    return; // the next start reads them
  }
  const settings = planConfiguration(vscode.workspace.getConfiguration('hipop'));
  try {
    await client.sendNotification(DidChangeConfigurationNotification.type, { settings });
  } catch (err) {
    outputChannel.appendLine(`Cannot send the hipop.plan settings to the server: ${String(err)}`);
  }
}

/**
 * How the server is run: `hipop lsp <extraArgs...>`, on standard input and
 * output. No `transport` is given: with `TransportKind.stdio`,
 * vscode-languageclient appends `--stdio`, which a `hipop` built before the
 * flag was accepted refuses (exit 2: no server at all); without it the
 * client still speaks over stdio, and the command line is exactly the one
 * logged and documented.
 */
export function serverExecutable(command: string, extraArgs: string[], cwd: string | undefined): Executable {
  return { command, args: ['lsp', ...extraArgs], options: cwd ? { cwd } : undefined };
}

/**
 * While the server starts, a broken connection (a server that exited at
 * once: "write EPIPE") is neither shown nor restarted: `start` rejects, and
 * one message says what the server printed. Once it runs, the client's
 * default handling (restarts, then a message) applies.
 */
class StartErrors implements ErrorHandler {
  starting = true;
  afterStart: ErrorHandler | undefined;
  /** The last connection error while starting. */
  lastError: Error | undefined;

  error(...args: Parameters<ErrorHandler['error']>): ReturnType<ErrorHandler['error']> {
    if (this.starting || !this.afterStart) {
      this.lastError = args[0];
      return { action: ErrorAction.Shutdown, handled: true };
    }
    return this.afterStart.error(...args);
  }

  closed(): ReturnType<ErrorHandler['closed']> {
    if (this.starting || !this.afterStart) {
      return { action: CloseAction.DoNotRestart, handled: true };
    }
    return this.afterStart.closed();
  }
}

/**
 * The language client, whose own messages only go to the output channel
 * while the server starts (vscode-languageclient shows "couldn't create
 * connection to server" and "write EPIPE" for a server that exited at once;
 * `start` then reports the failure once, with what the server said).
 */
class HipopClient extends LanguageClient {
  constructor(
    serverOptions: ServerOptions,
    clientOptions: LanguageClientOptions,
    private readonly startErrors: StartErrors,
  ) {
    super(CLIENT_ID, CLIENT_NAME, serverOptions, clientOptions);
  }

  override error(message: string, data?: unknown, showNotification: boolean | 'force' = true): void {
    super.error(message, data, this.startErrors.starting ? false : showNotification);
  }
}

/** How long a failed start waits for the server's standard error. */
const STDERR_GRACE_MS = 250;

/**
 * The output channel given to the client, which also keeps the start of
 * the server's standard error: vscode-languageclient writes the server's
 * stderr with `append` and its own messages with `appendLine`.
 */
class StderrTap {
  private text = '';
  readonly channel: vscode.OutputChannel;

  constructor(target: vscode.OutputChannel) {
    this.channel = new Proxy(target, {
      get: (obj, prop, receiver) => {
        if (prop === 'append') {
          return (value: string) => {
            if (this.text.length < 4096) {
              this.text += value;
            }
            obj.append(value);
          };
        }
        const value = Reflect.get(obj, prop, receiver);
        return typeof value === 'function' ? value.bind(obj) : value;
      },
    });
  }

  /** The first non-empty line the server wrote to stderr, if any. */
  firstLine(): string | undefined {
    return this.text
      .split(/\r?\n/)
      .map((line) => line.trim())
      .find((line) => line.length > 0);
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
