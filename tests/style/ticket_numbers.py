#!/usr/bin/env python3
"""History lives in git, not in code comments: no "issue <n>, finding <m>", "Issue-<n> suite" or "ticket <n>" in the
product's sources and scripts. A ticket number means nothing to a reader of the code; the why stays, the number goes.
Exits 1 listing every line that cites one (file:line: text), 0 when there is none.

Usage: ticket_numbers.py ROOT [FOLDER...]   (folders below ROOT; default common services tools tests deploy)

Checked: every text file of the folders except data (.csv, .json, .jsonl, .txt, recorded runs) and Markdown (docs
may tell history). A citation is the word issue/finding/ticket (any case, also plural), then a space or a hyphen,
an optional '#', and a number.
"""
import os
import re
import sys

FOLDERS = ('common', 'services', 'tools', 'tests', 'deploy')
SKIP_EXT = ('.csv', '.json', '.jsonl', '.txt', '.md', '.png', '.jpg', '.gz', '.zip', '.pem', '.p7s', '.der', '.db')
CITATION = re.compile(r'\b(issues?|findings?|tickets?)[- ]#?[0-9]+', re.I)


def offenders(root, folders):
    for folder in folders:
        base = os.path.join(root, folder)
        for d, dirs, names in os.walk(base):
            dirs[:] = sorted(x for x in dirs if not x.startswith('.') and x != 'node_modules')
            for n in sorted(names):
                path = os.path.join(d, n)
                if n.lower().endswith(SKIP_EXT):
                    continue
                try:
                    with open(path, encoding='utf-8') as f:
                        lines = f.readlines()
                except (UnicodeDecodeError, OSError):
                    continue  # binary: no comments to read
                for i, line in enumerate(lines, 1):
                    if CITATION.search(line):
                        yield '%s:%d: %s' % (os.path.relpath(path, root), i, line.strip())


def main(argv):
    if len(argv) < 2 or argv[1] in ('-h', '--help'):
        print(__doc__)
        return 2
    root = argv[1]
    found = list(offenders(root, argv[2:] or FOLDERS))
    for line in found:
        print(line)
    print('ticket_numbers: %d lines cite a ticket number' % len(found))
    return 1 if found else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
