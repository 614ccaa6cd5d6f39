#!/usr/bin/env python3
"""Regenerates docs/diagnostics.md from docs/src/diagnostics.template.md, the
registry in analyzer/src/diagnostic.rs and the real output of `hipop check` on
each fixture of samples/broken, so the examples never drift from the code.

    python3 scripts/gen-diagnostics-doc.py          # rewrite the document
    python3 scripts/gen-diagnostics-doc.py --check  # fail if it is out of date

Needs target/debug/hipop (`cargo build -p hipop`)."""
import os, re, subprocess, sys
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
os.chdir(root)
tpl = open('docs/src/diagnostics.template.md').read()
reg = open('analyzer/src/diagnostic.rs').read()
rows = []
for m in re.finditer(r'^\s*([A-Z_]+) = "(\w+)" "([\w-]+)" (\w+) "(.*)";\s*$', reg, re.M):
    _, cid, name, sev, summary = m.groups()
    rows.append(f'| [{cid}](#{cid.lower()}-{name}) | `{name}` | {sev.lower()} | {summary} |')
assert rows, 'no code found in the registry' 
tpl = tpl.replace('@@TABLE@@', '\n'.join(rows))
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
tpl = re.sub(r'@@FIXTURE (\S+)@@', lambda m: fixture(m.group(1)), tpl)
assert '@@' not in tpl
if '--check' in sys.argv:
    if open('docs/diagnostics.md').read() != tpl:
        sys.exit('docs/diagnostics.md is out of date: run python3 scripts/gen-diagnostics-doc.py')
    print('docs/diagnostics.md is up to date')
else:
    open('docs/diagnostics.md', 'w').write(tpl)
    print('written', len(tpl.split('\n')), 'lines')
