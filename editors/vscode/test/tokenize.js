'use strict';
// Small helper shared by the grammar tests: loads the extension's TextMate
// grammar with vscode-textmate + the oniguruma WASM from node_modules.

const fs = require('node:fs');
const path = require('node:path');
const vsctm = require('vscode-textmate');
const oniguruma = require('vscode-oniguruma');

const ROOT = path.join(__dirname, '..');
const GRAMMAR_PATH = path.join(ROOT, 'syntaxes', 'hipop-pddl.tmLanguage.json');
const SCOPE_NAME = 'source.hipop-pddl';

let grammarPromise;

function loadGrammar() {
  if (!grammarPromise) {
    const wasmPath = require.resolve('vscode-oniguruma/release/onig.wasm');
    const wasm = fs.readFileSync(wasmPath);
    const onigLib = oniguruma
      .loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength))
      .then(() => ({
        createOnigScanner: (sources) => new oniguruma.OnigScanner(sources),
        createOnigString: (s) => new oniguruma.OnigString(s),
      }));
    const registry = new vsctm.Registry({
      onigLib,
      loadGrammar: async (scopeName) => {
        if (scopeName !== SCOPE_NAME) {
          return null;
        }
        const text = fs.readFileSync(GRAMMAR_PATH, 'utf8');
        return vsctm.parseRawGrammar(text, GRAMMAR_PATH);
      },
    });
    grammarPromise = registry.loadGrammar(SCOPE_NAME).then((g) => {
      if (!g) {
        throw new Error(`grammar ${SCOPE_NAME} could not be loaded`);
      }
      return g;
    });
  }
  return grammarPromise;
}

/**
 * Tokenizes `source` (several lines) and returns one array per line of
 * `{ text, scopes }` tokens. Rule state is carried across lines.
 */
async function tokenize(source) {
  const grammar = await loadGrammar();
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

module.exports = { loadGrammar, tokenize, SCOPE_NAME, GRAMMAR_PATH, ROOT };

if (require.main === module) {
  // Debug aid: `node test/tokenize.js FILE` prints every token and its scopes.
  const file = process.argv[2];
  tokenize(fs.readFileSync(file, 'utf8')).then((lines) => {
    lines.forEach((tokens, i) => {
      for (const t of tokens) {
        if (t.text.trim().length > 0) {
          console.log(`${i + 1}\t${JSON.stringify(t.text)}\t${t.scopes.slice(1).join(' ')}`);
        }
      }
    });
  });
}
