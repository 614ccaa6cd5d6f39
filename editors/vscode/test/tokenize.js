'use strict';
// Small helper shared by the grammar tests: loads the extension's TextMate
// grammars (HTN-PDDL and plans) with vscode-textmate + the oniguruma WASM
// from node_modules.

const fs = require('node:fs');
const path = require('node:path');
const vsctm = require('vscode-textmate');
const oniguruma = require('vscode-oniguruma');

const ROOT = path.join(__dirname, '..');
const GRAMMAR_PATH = path.join(ROOT, 'syntaxes', 'hipop-pddl.tmLanguage.json');
const SCOPE_NAME = 'source.hipop-pddl';
const PLAN_GRAMMAR_PATH = path.join(ROOT, 'syntaxes', 'hipop-plan.tmLanguage.json');
const PLAN_SCOPE_NAME = 'source.hipop-plan';
const GRAMMARS = { [SCOPE_NAME]: GRAMMAR_PATH, [PLAN_SCOPE_NAME]: PLAN_GRAMMAR_PATH };

let registry;
const grammarPromises = new Map();

function getRegistry() {
  if (!registry) {
    const wasmPath = require.resolve('vscode-oniguruma/release/onig.wasm');
    const wasm = fs.readFileSync(wasmPath);
    const onigLib = oniguruma
      .loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength))
      .then(() => ({
        createOnigScanner: (sources) => new oniguruma.OnigScanner(sources),
        createOnigString: (s) => new oniguruma.OnigString(s),
      }));
    registry = new vsctm.Registry({
      onigLib,
      loadGrammar: async (scopeName) => {
        const file = GRAMMARS[scopeName];
        if (!file) {
          return null;
        }
        return vsctm.parseRawGrammar(fs.readFileSync(file, 'utf8'), file);
      },
    });
  }
  return registry;
}

/** Loads the grammar `scopeName` (default: the HTN-PDDL grammar). */
function loadGrammar(scopeName = SCOPE_NAME) {
  if (!grammarPromises.has(scopeName)) {
    grammarPromises.set(
      scopeName,
      getRegistry()
        .loadGrammar(scopeName)
        .then((g) => {
          if (!g) {
            throw new Error(`grammar ${scopeName} could not be loaded`);
          }
          return g;
        }),
    );
  }
  return grammarPromises.get(scopeName);
}

/**
 * Tokenizes `source` (several lines) with the grammar `scopeName` and returns
 * one array per line of `{ text, scopes }` tokens. Rule state is carried
 * across lines.
 */
async function tokenize(source, scopeName = SCOPE_NAME) {
  const grammar = await loadGrammar(scopeName);
  let ruleStack = vsctm.INITIAL;
  return source.split('\n').map((line) => {
    const result = grammar.tokenizeLine(line, ruleStack);
    ruleStack = result.ruleStack;
    return result.tokens.map((t) => ({
      text: line.substring(t.startIndex, t.endIndex),
      scopes: t.scopes,
    }));
  });
}

module.exports = {
  loadGrammar,
  tokenize,
  SCOPE_NAME,
  GRAMMAR_PATH,
  PLAN_SCOPE_NAME,
  PLAN_GRAMMAR_PATH,
  ROOT,
};

/** The grammar VS Code would pick for `file`, by its name (package.json). */
function scopeForFile(file) {
  return /\.(plan|soln|sol)$/i.test(file) ? PLAN_SCOPE_NAME : SCOPE_NAME;
}

if (require.main === module) {
  // Debug aid: `node test/tokenize.js FILE` prints every token and its scopes
  // (the plan grammar for .plan, .soln and .sol files).
  const file = process.argv[2];
  tokenize(fs.readFileSync(file, 'utf8'), scopeForFile(file)).then((lines) => {
    lines.forEach((tokens, i) => {
      for (const t of tokens) {
        if (t.text.trim().length > 0) {
          console.log(`${i + 1}\t${JSON.stringify(t.text)}\t${t.scopes.slice(1).join(' ')}`);
        }
      }
    });
  });
}
