#!/usr/bin/env python3
"""One name per room, checked: every library folder common/<f> is CMake target causal_<f> and C++ namespace
causal::<f>, with its public headers under include/causal/<f>/. Exits 1 listing every mismatch, 0 when there is none.

Usage: library_names.py ROOT

Rules for common/<f> (a folder with a CMakeLists.txt):
  * targets: add_library(causal_<f> ...) exists; any further target of the folder (a part that must link without
    the rest, e.g. causal_io_time without zlib) is named causal_<f>_<part>;
  * headers: every file below <f>/include/ is below <f>/include/causal/<f>/;
  * namespaces: every `namespace causal...` block in the folder's files is causal::<f> or nested in it
    (causal::<f>::detail, ...). A block of another causal namespace that only forward-declares (class X; /
    struct X;) is allowed: it names the other library's types, it defines nothing there.
"""
import os
import re
import sys

SOURCE = ('.cpp', '.hpp', '.h')
TARGET = re.compile(r'add_library\(\s*([A-Za-z0-9_]+)')
NAMESPACE = re.compile(r'^\s*namespace\s+(causal(?:::[A-Za-z_]\w*)*)\s*\{', re.M)
# Folders not yet renamed (skipped): empty once every library follows the rule.
PENDING = set()
FORWARD = re.compile(r'^\s*(?:(?:class|struct)\s+\w+\s*;\s*(?://.*)?|//.*)?\s*$')


def block_body(text, open_brace):
    """Text between the brace at open_brace and its match."""
    depth = 0
    for i in range(open_brace, len(text)):
        if text[i] == '{':
            depth += 1
        elif text[i] == '}':
            depth -= 1
            if depth == 0:
                return text[open_brace + 1:i]
    return text[open_brace + 1:]


def only_forward_declarations(body):
    return all(FORWARD.match(line) for line in body.split('\n'))


def check_folder(root, name):
    folder = os.path.join(root, 'common', name)
    problems = []
    targets = []
    for d, _, files in os.walk(folder):
        for f in files:
            if f == 'CMakeLists.txt':
                with open(os.path.join(d, f)) as h:
                    targets += TARGET.findall(h.read())
    own = 'causal_' + name
    if own not in targets:
        problems.append('common/%s: no target %s (targets: %s)' % (name, own, ', '.join(targets) or 'none'))
    for t in targets:
        if t != own and not t.startswith(own + '_'):
            problems.append('common/%s: target %s is not %s or %s_<part>' % (name, t, own, own))
    include = os.path.join(folder, 'include')
    for d, _, files in os.walk(include):
        for f in files:
            rel = os.path.relpath(os.path.join(d, f), include)
            if not rel.startswith(os.path.join('causal', name) + os.sep):
                problems.append('common/%s/include/%s: not below include/causal/%s/' % (name, rel, name))
    space = 'causal::' + name
    for d, _, files in os.walk(folder):
        for f in sorted(files):
            if not f.endswith(SOURCE):
                continue
            path = os.path.join(d, f)
            with open(path, encoding='utf-8', errors='replace') as h:
                text = h.read()
            for m in NAMESPACE.finditer(text):
                ns = m.group(1)
                if ns == space or ns.startswith(space + '::'):
                    continue
                if only_forward_declarations(block_body(text, m.end() - 1)):
                    continue
                line = text.count('\n', 0, m.start(1)) + 1
                problems.append('%s:%d: namespace %s in common/%s (expected %s)' % (
                    os.path.relpath(path, root), line, ns, name, space))
    return problems


def main(argv):
    if len(argv) != 2 or argv[1] in ('-h', '--help'):
        print(__doc__)
        return 2
    root = argv[1]
    base = os.path.join(root, 'common')
    folders = sorted(n for n in os.listdir(base)
                     if os.path.isfile(os.path.join(base, n, 'CMakeLists.txt')) and n not in PENDING)
    problems = []
    for name in folders:
        problems += check_folder(root, name)
    for p in problems:
        print(p)
    print('library_names: %d libraries; %d mismatches of folder, target and namespace' % (len(folders), len(problems)))
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
