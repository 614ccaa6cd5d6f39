#!/usr/bin/env python3
"""Regenerates docs/diagnostics.md, docs/lints.md, docs/validation.md and
docs/validation-temporal.md from their templates in docs/src/, the registry in
analyzer/src/diagnostic.rs and the real output of hipop on each fixture
(samples/broken, tests/plans, tests/validate, tests/validate-htn), so the
examples never drift from the code. Codes E03xx/W03xx/I03xx (model
verification) are documented in lints.md, codes E0410-E0429/W0410-W0429
(temporal plan validation) in validation-temporal.md, the other codes
E04xx/W04xx (reading plans, validating hierarchical plans) in validation.md,
the others in diagnostics.md; every code has a section in one. The examples
of validation-temporal.md are the plans of tests/validate and their snapshots
(analyzer/tests/validate.rs), those of the hierarchical validation in
validation.md the plans of tests/validate-htn and theirs
(analyzer/tests/validate_htn.rs), so they never drift either.

Directives in the templates:
    @@TABLE@@               the table of the codes of the page
    @@FIXTURE path@@        a model fixture and what `hipop check` prints on it
    @@FILE path@@           a file, shown as text (a plan, say)
    @@RUN args…@@           what `hipop args… --color never` prints, and its exit status
    @@PLAN name@@           a plan of tests/validate and its snapshot
    @@HTN name@@            a plan of tests/validate-htn and its snapshot

    python3 scripts/gen-diagnostics-doc.py          # rewrite the document
    python3 scripts/gen-diagnostics-doc.py --check  # fail if it is out of date

Needs target/debug/hipop (`cargo build -p hipop`)."""
import os, re, subprocess, sys
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
os.chdir(root)
tpl = open('docs/src/diagnostics.template.md').read()
lints_tpl = open('docs/src/lints.template.md').read()
plans_tpl = open('docs/src/validation.template.md').read()
validation_tpl = open('docs/src/validation-temporal.template.md').read()
reg = open('analyzer/src/diagnostic.rs').read()
rows = []
codes = []
def is_lint(cid):
    return cid[1:3] == '03'
def is_validation(cid):
    return 410 <= int(cid[1:]) < 430
def is_plan(cid):
    return cid[1:3] == '04' and not is_validation(cid)
def page_of(cid):
    if is_lint(cid):
        return 'lints.md'
    if is_validation(cid):
        return 'validation-temporal.md'
    return 'validation.md' if is_plan(cid) else ''
for m in re.finditer(r'^\s*([A-Z_]+) = "(\w+)" "([\w-]+)" (\w+) "(.*)";\s*$', reg, re.M):
    _, cid, name, sev, summary = m.groups()
    codes.append((cid, name))
    page = page_of(cid)
    rows.append(f'| [{cid}]({page}#{cid.lower()}-{name}) | `{name}` | {sev.lower()} | {summary} |')
assert rows, 'no code found in the registry'
tpl = tpl.replace('@@TABLE@@', '\n'.join(rows))
lints_tpl = lints_tpl.replace('@@TABLE@@', '\n'.join(r.replace('](lints.md#', '](#') for r in rows if is_lint(r[3:8])))
plans_tpl = plans_tpl.replace('@@TABLE@@', '\n'.join(r.replace('](validation.md#', '](#') for r in rows if is_plan(r[3:8])))
validation_tpl = validation_tpl.replace('@@TABLE@@', '\n'.join(
    r.replace('](validation-temporal.md#', '](#') for r in rows if is_validation(r[3:8])))
for cid, name in codes:
    doc = lints_tpl if is_lint(cid) else validation_tpl if is_validation(cid) else plans_tpl if is_plan(cid) else tpl
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
def show_file(path):
    lang = 'json' if path.endswith('.json') else 'text'
    return f'`{os.path.basename(path)}`:\n\n```{lang}\n{strip_header(open(path).read())}\n```'
def run(args):
    argv = args.split()
    r = subprocess.run([hipop] + argv + ['--color', 'never'], capture_output=True, text=True)
    assert r.returncode in (0, 1, 2, 3) and 'panicked' not in r.stderr, (args, r.returncode, r.stderr)
    shown = '\n'.join(x for x in (r.stderr.rstrip(), r.stdout.rstrip()) if x)
    return f'`hipop {args}` prints (exit status {r.returncode}):\n\n```text\n{shown}\n```'
def plan(name):
    """A plan of tests/validate without its header, and its snapshot."""
    path = f'tests/validate/{name}.plan'
    snap = open(f'analyzer/tests/snapshots/validate__check_fixture@{name}.plan.snap').read()
    # The insta header is between the first two `---` lines.
    body = snap.split('\n---\n', 1)[1] if snap.startswith('---\n') else snap
    header = open(path).read().split('\n')
    models = [l.split(':', 1)[1].strip() for l in header if l.startswith(('; domain:', '; problem:'))]
    models = [m.replace('corpus:', '../shared/corpora/') if m.startswith('corpus:') else f'tests/validate/{m}' for m in models]
    tol = next((l.split(':', 1)[1].strip() for l in header if l.startswith('; tolerance:')), '0.01')
    return '\n'.join([
        f'[`{name}.plan`](../{path}), for `{models[0]}` and `{models[1]}` at tolerance {tol}:\n',
        f'```lisp\n{strip_header(open(path).read())}\n```\n',
        'gives:\n',
        f'```text\n{body.strip()}\n```',
    ])
def htn(name):
    """A plan of tests/validate-htn without its header, and its snapshot."""
    path = f'tests/validate-htn/{name}.plan'
    snap = open(f'analyzer/tests/snapshots/validate_htn__check_fixture@{name}.plan.snap').read()
    body = snap.split('\n---\n', 1)[1] if snap.startswith('---\n') else snap
    header = open(path).read().split('\n')
    models = [l.split(':', 1)[1].strip() for l in header if l.startswith(('; domain:', '; problem:'))]
    models = [f'tests/validate-htn/{m}' for m in models]
    return '\n'.join([
        f'[`{name}.plan`](../{path}), for [`{os.path.basename(models[0])}`](../{models[0]}) and '
        f'[`{os.path.basename(models[1])}`](../{models[1]}):\n',
        f'```text\n{strip_header(open(path).read())}\n```\n',
        'gives:\n',
        f'```text\n{body.strip()}\n```',
    ])
stale = []
outputs = [
    ('docs/diagnostics.md', tpl),
    ('docs/lints.md', lints_tpl),
    ('docs/validation.md', plans_tpl),
    ('docs/validation-temporal.md', validation_tpl),
]
for out, text in outputs:
    text = re.sub(r'@@FIXTURE (\S+)@@', lambda m: fixture(m.group(1)), text)
    text = re.sub(r'@@PLAN (\S+)@@', lambda m: plan(m.group(1)), text)
    text = re.sub(r'@@HTN (\S+)@@', lambda m: htn(m.group(1)), text)
    text = re.sub(r'@@FILE (\S+)@@', lambda m: show_file(m.group(1)), text)
    text = re.sub(r'@@RUN ([^@]+)@@', lambda m: run(m.group(1).strip()), text)
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
    print('docs/diagnostics.md, docs/lints.md, docs/validation.md and docs/validation-temporal.md are up to date')
