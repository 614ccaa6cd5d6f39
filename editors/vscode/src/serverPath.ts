// Resolution of the `hipop.server.path` setting to an executable.
//
// Kept free of any `vscode` import so that it can be unit-tested with plain
// node (see test/serverPath.test.js).

import * as fs from 'fs';
import * as os from 'os';
import * as path from 'path';

export interface ResolveOptions {
  /** Environment to read PATH / PATHEXT / HOME from. Defaults to process.env. */
  env?: NodeJS.ProcessEnv;
  /** Directory that relative paths are resolved against (first workspace folder). */
  cwd?: string;
  /** Platform; defaults to process.platform. */
  platform?: NodeJS.Platform;
}

export type Resolution =
  | { ok: true; command: string }
  | { ok: false; reason: string };

/** Expands a leading `~` (or `~/...`) to the home directory. */
export function expandHome(p: string, env: NodeJS.ProcessEnv = process.env): string {
  if (p === '~' || p.startsWith('~/') || p.startsWith('~\\')) {
    const home = env.HOME || env.USERPROFILE || os.homedir();
    return path.join(home, p.slice(1));
  }
  return p;
}

function isExecutableFile(file: string, platform: NodeJS.Platform): boolean {
  try {
    const st = fs.statSync(file);
    if (!st.isFile()) {
      return false;
    }
    if (platform === 'win32') {
      return true;
    }
    fs.accessSync(file, fs.constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

function candidates(base: string, env: NodeJS.ProcessEnv, platform: NodeJS.Platform): string[] {
  if (platform !== 'win32' || path.extname(base) !== '') {
    return [base];
  }
  const exts = (env.PATHEXT || '.EXE;.CMD;.BAT;.COM').split(';').filter((e) => e.length > 0);
  return [base, ...exts.map((e) => base + e.toLowerCase()), ...exts.map((e) => base + e)];
}

/**
 * Turns the configured server path into an absolute executable path.
 *
 * - empty / whitespace: error
 * - contains a path separator (or starts with `~`): taken as a file path,
 *   `~` expanded, relative paths resolved against `cwd`
 * - a bare name: searched for on PATH (with PATHEXT on Windows)
 */
export function resolveServerCommand(configured: string, opts: ResolveOptions = {}): Resolution {
  const env = opts.env ?? process.env;
  const platform = opts.platform ?? process.platform;
  const value = configured.trim();
  if (value.length === 0) {
    return { ok: false, reason: 'the setting is empty' };
  }

  const expanded = expandHome(value, env);
  const hasSeparator = expanded.includes('/') || (platform === 'win32' && expanded.includes('\\'));
  if (hasSeparator) {
    const absolute = path.isAbsolute(expanded)
      ? expanded
      : path.resolve(opts.cwd ?? process.cwd(), expanded);
    for (const c of candidates(absolute, env, platform)) {
      if (isExecutableFile(c, platform)) {
        return { ok: true, command: c };
      }
    }
    return { ok: false, reason: `no executable file at '${absolute}'` };
  }

  const pathVar = env.PATH ?? env.Path ?? '';
  const sep = platform === 'win32' ? ';' : ':';
  for (const dir of pathVar.split(sep)) {
    if (dir.length === 0) {
      continue;
    }
    for (const c of candidates(path.join(dir, expanded), env, platform)) {
      if (isExecutableFile(c, platform)) {
        return { ok: true, command: c };
      }
    }
  }
  return { ok: false, reason: `'${expanded}' was not found on PATH` };
}
