#!/usr/bin/env python3
"""Regenerates docs/diagnostics.md and docs/lints.md from their templates in
docs/src/, the registry in analyzer/src/diagnostic.rs and the real output of
`hipop check` on each fixture of samples/broken, so the examples never drift
from the code. Codes E03xx/W03xx/I03xx (model verification) are documented in
lints.md, the others in diagnostics.md; every code has a section in one.

    python3 scripts/gen-diagnostics-doc.py          # rewrite the document
    python3 scripts/gen-diagnostics-doc.py --check  # fail if it is out of date

Needs target/debug/hipop (`cargo build -p hipop`)."""
import os, re, subprocess, sys
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
os.chdir(root)
tpl = open('docs/src/diagnostics.template.md').read()
lints_tpl = open('docs/src/lints.template.md').read()
reg = open('analyzer/src/diagnostic.rs').read()
rows = []
codes = []
def is_lint(cid):
    return cid[1:3] == '03'
for m in re.finditer(r'^\s*([A-Z_]+) = "(\w+)" "([\w-]+)" (\w+) "(.*)";\s*$', reg, re.M):
    _, cid, name, sev, summary = m.groups()
    codes.append((cid, name))
    page = 'lints.md' if is_lint(cid) else ''
    rows.append(f'| [{cid}]({page}#{cid.lower()}-{name}) | `{name}` | {sev.lower()} | {summary} |')
assert rows, 'no code found in the registry'
tpl = tpl.replace('@@TABLE@@', '\n'.join(rows))
lints_tpl = lints_tpl.replace('@@TABLE@@', '\n'.join(r.replace('](lints.md#', '](#') for r in rows if is_lint(r[3:8])))
for cid, name in codes:
    doc = lints_tpl if is_lint(cid) else tpl
    assert f'### {cid} {name}' in doc, f'code {cid} {name} has no `### {cid} {name}` section in its template'

features = [
 ('typed declarations (`- type`, `(:types …)`)', ':typing', ':adl'),
 ('a negative condition `(not …)` in a precondition or goal', ':negative-preconditions', ':adl'),
 ('`or`, `imply` in a condition', ':disjunctive-preconditions', ':adl'),
 ('`exists`', ':existential-preconditions', ':quantified-preconditions`, `:adl'),
 ('`forall` in a condition', ':universal-preconditions', ':quantified-preconditions`, `:adl'),
 ('`when`, `forall` in an effect', ':conditional-effects', ':adl'),
 ('`=` between objects', ':equality', ':adl'),
 ('`(:functions …)`, numeric expressions, assignments', ':numeric-fluents', ':fluents'),
 ('`(:durative-action …)`', ':durative-actions', ':time'),
 ('a `:duration` other than `(= ?duration …)`', ':duration-inequalities', ''),
 ('a timed initial literal `(at 10 …)`', ':timed-initial-literals', ''),
 ('`(:derived …)`', ':derived-predicates', ''),
 ('`(preference …)`', ':preferences', ''),
 ('`(:constraints …)`', ':constraints', ':method-constraints'),
 ('tasks, methods, `:htn`, `(:tasks …)`', ':hierarchy', ':hierachie`, `:htn'),
 ('a method precondition', ':method-preconditions', ''),
]
frows = [f'| {f} | `{r}` | ' + (f'`{a}`' if a else '') + ' |' for f, r, a in features]
tpl = tpl.replace('@@FEATURES@@', '\n'.join(frows))
hipop = os.path.join(root, 'target/debug/hipop')
def strip_header(text):
    lines = text.split('\n')
    i = 0
    while i < len(lines) and lines[i].startswith(';'):
        i += 1
    while i < len(lines) and lines[i].strip() == '':
        i += 1
    return '\n'.join(lines[i:]).rstrip('\n')
def fixture(name):
    path = f'samples/broken/{name}'
    out = []
    if os.path.isdir(path):
        for f in sorted(os.listdir(path)):
            if f.endswith(('.pddl', '.hddl')):
                out.append(f'`{f}`:\n\n```lisp\n{strip_header(open(os.path.join(path, f)).read())}\n```\n')
    else:
        out.append(f'```lisp\n{strip_header(open(path).read())}\n```\n')
    r = subprocess.run([hipop, 'check', path, '--color', 'never'], capture_output=True, text=True)
    assert r.returncode in (0, 1), (path, r.returncode, r.stderr)
    out.append(f'`hipop check {path} --color never` prints (exit status {r.returncode}):\n')
    out.append(f'```text\n{r.stderr.rstrip()}\n```')
    return '\n'.join(out)
stale = []
for out, text in [('docs/diagnostics.md', tpl), ('docs/lints.md', lints_tpl)]:
    text = re.sub(r'@@FIXTURE (\S+)@@', lambda m: fixture(m.group(1)), text)
    assert '@@' not in text, out
    if '--check' in sys.argv:
        if not os.path.exists(out) or open(out).read() != text:
            stale.append(out)
    else:
        open(out, 'w').write(text)
        print('written', out, len(text.split('\n')), 'lines')
if stale:
    sys.exit(f'{", ".join(stale)} out of date: run python3 scripts/gen-diagnostics-doc.py')
if '--check' in sys.argv:
    print('docs/diagnostics.md and docs/lints.md are up to date')
