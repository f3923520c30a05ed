#!/usr/bin/env python3
"""The product's rule "no function over 120 lines", checked: lists every C++ function body in the given
folders longer than LIMIT lines and exits 1 when there is one.

Usage: function_length.py LIMIT FOLDER...

A brace count, not a parser: comments, string, character and raw-string literals are blanked first; a '{' opens a
function body when the text before it ends in ')' (with const / noexcept / override / a trailing return type)
and is not an if / for / while / switch / catch head or a lambda; nested bodies count towards the outermost.
"""
import os
import re
import sys

CONTROL = re.compile(r'\b(if|for|while|switch|catch)\s*\([^;{}]*\)\s*$')
LAMBDA = re.compile(r'\[[^\]]*\]\s*\([^)]*\)\s*(mutable)?\s*(->\s*[\w:<>, ]+)?$')
AFTER_PARAMS = re.compile(r'\)\s*(const)?\s*(noexcept)?\s*(override)?\s*(->\s*[\w:<>, ]+)?$')


def blank(text):
    """The text with comments and literals replaced by spaces (line breaks kept, so line numbers hold)."""
    out, i, n = [], 0, len(text)
    def spaces(a, b):
        return ''.join('\n' if ch == '\n' else ' ' for ch in text[a:b])
    while i < n:
        if text.startswith('//', i):
            j = text.find('\n', i)
            j = n if j < 0 else j
        elif text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == '_')):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(text[i]); i += 1; continue
            end = text.find(')' + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
        elif text[i] in '"\'':
            j = i + 1
            while j < n and text[j] != text[i] and text[j] != '\n':
                j += 2 if text[j] == '\\' else 1
            j += 1
        else:
            out.append(text[i]); i += 1; continue
        out.append(spaces(i, j)); i = j
    return ''.join(out)


def long_functions(path, limit):
    text = blank(open(path, encoding='utf-8', errors='replace').read())
    open_braces, found = [], []  # open_braces: (offset, is a function body)
    for i, ch in enumerate(text):
        if ch == '{':
            head = text[max(0, i - 300):i].rstrip()
            is_body = bool(AFTER_PARAMS.search(head)) and not CONTROL.search(head) and not LAMBDA.search(head)
            open_braces.append((i, is_body))
        elif ch == '}' and open_braces:
            start, is_body = open_braces.pop()
            if is_body and not any(body for _, body in open_braces):
                first, last = text.count('\n', 0, start) + 1, text.count('\n', 0, i) + 1
                if last - first + 1 > limit:
                    names = re.findall(r'([~\w:]+)\s*\(', text[max(0, start - 400):start])
                    found.append((last - first + 1, first, names[-1] if names else '?'))
    return found


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    limit, offenders = int(sys.argv[1]), []
    for folder in sys.argv[2:]:
        for root, _, files in os.walk(folder):
            for name in sorted(files):
                if name.endswith(('.cpp', '.hpp', '.h', '.cc')):
                    path = os.path.join(root, name)
                    offenders += [(n, path, line, fn) for n, line, fn in long_functions(path, limit)]
    for n, path, line, fn in sorted(offenders, reverse=True):
        print(f'{path}:{line}: {fn} is {n} lines (limit {limit})')
    print(f'{len(offenders)} functions over {limit} lines')
    return 1 if offenders else 0


if __name__ == '__main__':
    sys.exit(main())
