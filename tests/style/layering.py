#!/usr/bin/env python3
"""The layering rule of docs/architecture.md, checked: a library (common/<lib>) uses only other libraries; a service
(services/<name>) or a tool (tools/<name>) uses libraries and its own files, never another service's or tool's.
Exits 1 listing every arrow that breaks it, 0 when there is none.

Usage: layering.py ROOT

A room is common/<lib>, services/<name> or tools/<name> below ROOT. Two kinds of arrow are checked:
  * #include "X" in a C++ file: X is looked up in the including file's folder, its room and every library's
    include/ folder (the include paths the build gives); when none of them has it but another service's or
    tool's room does, or a library includes a file that only services/ or tools/ have, that is a broken arrow.
  * CMake: a room's CMakeLists.txt that links a target another service or tool defines, or names another
    service's or tool's folder (target_include_directories, add_subdirectory, a source path).
"""
import os
import re
import sys

KINDS = ('common', 'services', 'tools')
SOURCE = ('.cpp', '.hpp', '.h', '.cc', '.cxx')
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def room_of(root, path):
    """('common'|'services'|'tools', name) of a path below root, or None."""
    parts = os.path.relpath(path, root).split(os.sep)
    if len(parts) >= 3 and parts[0] in KINDS:
        return parts[0], parts[1]
    return None


def walk(root):
    """Every file below the three kinds of room, by room."""
    rooms = {}
    for kind in KINDS:
        base = os.path.join(root, kind)
        if not os.path.isdir(base):
            continue
        for name in sorted(os.listdir(base)):
            folder = os.path.join(base, name)
            if not os.path.isdir(folder):
                continue
            files = []
            for d, _, names in os.walk(folder):
                files.extend(os.path.join(d, n) for n in names)
            rooms[(kind, name)] = sorted(files)
    return rooms


def label(room):
    return room[0] + '/' + room[1]


def include_problems(root, rooms):
    lib_includes = [os.path.join(root, 'common', r[1], 'include') for r in rooms if r[0] == 'common']
    problems = []
    for room, files in rooms.items():
        for path in files:
            if not path.endswith(SOURCE):
                continue
            with open(path, encoding='utf-8', errors='replace') as f:
                text = f.read()
            for m in INCLUDE.finditer(text):
                target = m.group(1)
                line = text.count('\n', 0, m.start()) + 1
                resolved = os.path.normpath(os.path.join(os.path.dirname(path), target))
                escaped = room_of(root, resolved) if os.path.isfile(resolved) else None
                if escaped and escaped != room and escaped[0] != 'common':
                    others = [escaped]  # a relative path into another service's or tool's folder
                else:
                    own = [os.path.dirname(path), os.path.join(root, *room)]
                    if any(os.path.isfile(os.path.join(d, target)) for d in own):
                        continue
                    if any(os.path.isfile(os.path.join(d, target)) for d in lib_includes):
                        continue  # a library header
                    others = [r for r, fs in rooms.items() if r != room and r[0] != 'common'
                              and any(p.endswith(os.sep + target) for p in fs)]
                    if not others:
                        continue  # a generated or third-party header
                problems.append('%s:%d: %s includes "%s" of %s' % (
                    os.path.relpath(path, root), line, label(room), target, ', '.join(label(o) for o in others)))
    return problems


TARGET_DEF = re.compile(r'add_(?:library|executable)\s*\(\s*([\w.+-]+)')
LINK = re.compile(r'target_link_libraries\s*\(([^)]*)\)', re.S)


def cmake_problems(root, rooms):
    defined = {}  # target -> room (services and tools only: libraries are for everyone)
    lists = {}
    for room, files in rooms.items():
        lists[room] = [p for p in files if os.path.basename(p) == 'CMakeLists.txt' or p.endswith('.cmake')]
        if room[0] == 'common':
            continue
        for p in lists[room]:
            with open(p, encoding='utf-8', errors='replace') as f:
                for t in TARGET_DEF.findall(f.read()):
                    defined[t] = room
    problems = []
    for room, paths in lists.items():
        for p in paths:
            with open(p, encoding='utf-8', errors='replace') as f:
                text = re.sub(r'#[^\n]*', '', f.read())
            rel = os.path.relpath(p, root)
            for m in LINK.finditer(text):
                line = text.count('\n', 0, m.start()) + 1
                for word in m.group(1).split()[1:]:
                    owner = defined.get(word)
                    if owner and owner != room:
                        problems.append('%s:%d: %s links %s of %s' % (rel, line, label(room), word, label(owner)))
            for kind in ('services', 'tools'):
                for m in re.finditer(r'(?:PROJECT_SOURCE_DIR|CMAKE_SOURCE_DIR)\}/%s/([\w.-]+)' % kind, text):
                    other = (kind, m.group(1))
                    if other != room:
                        line = text.count('\n', 0, m.start()) + 1
                        problems.append('%s:%d: %s names the folder of %s' % (rel, line, label(room), label(other)))
    return problems


def main(argv):
    if len(argv) != 2:
        print(__doc__)
        return 2
    root = os.path.abspath(argv[1])
    rooms = walk(root)
    problems = include_problems(root, rooms) + cmake_problems(root, rooms)
    for p in problems:
        print(p)
    kinds = {k: sum(1 for r in rooms if r[0] == k) for k in KINDS}
    print('layering: %d libraries, %d services, %d tools; %d arrows against the rule' % (
        kinds['common'], kinds['services'], kinds['tools'], len(problems)))
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
