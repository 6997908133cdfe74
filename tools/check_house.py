#!/usr/bin/env python3
"""check_house.py - the rooms of docs/core.md, checked on the source tree.

  tools/check_house.py [ROOT]

Fails (exit 1, one line a finding) when
  - a source file of core/, io/ or app/ has more than 700 lines;
  - a function has more than 150 lines (from its opening brace at column 0 to the closing one:
    the layout .clang-format gives every function);
  - a room of app/ includes a header of a room it may not (the map in docs/core.md; CMake's
    include paths refuse most of these too, this names them);
  - core/ includes anything but its own headers and the C library, or io/include/ anything
    from io/src/.
"""
import os
import re
import sys

MAX_FILE_LINES = 700
MAX_FUNCTION_LINES = 150
SOURCES = (".c", ".h", ".cpp", ".hpp")

# app's rooms and the rooms each may include (besides itself, core and io)
APP_ROOMS = {
    "base": set(),
    "scene": {"base"},
    "render": {"scene", "base"},
    "commands": {"scene", "base"},
    "view": {"render", "scene", "base"},
    "export": {"scene", "base"},
    "bench": {"render", "scene", "base"},
}


def sources(root, top):
    for d, _, files in os.walk(os.path.join(root, top)):
        for f in sorted(files):
            if f.endswith(SOURCES):
                yield os.path.join(d, f)


def long_functions(lines):
    """(first line, length, name) of each function body longer than the limit."""
    start = None
    for i, line in enumerate(lines):
        if line.startswith("{") and start is None:
            start = i
        elif line.startswith("}") and start is not None:
            if i - start > MAX_FUNCTION_LINES:
                head = lines[start - 1] if start > 0 else ""
                m = re.search(r"(\w+)\s*\(", head) or re.search(r"(\w+)", head)
                # a signature over several lines: the name is on the first of them
                j = start - 1
                while j > 0 and not re.search(r"\w+\s*\(", lines[j]):
                    j -= 1
                m = re.search(r"(\w+)\s*\(", lines[j]) if j >= 0 else m
                yield start + 1, i - start, m.group(1) if m else "?"
            start = None


def headers_by_room(root):
    rooms = {}
    for room in APP_ROOMS:
        for path in sources(root, os.path.join("app", room)):
            if path.endswith((".h", ".hpp")):
                rooms.setdefault(os.path.basename(path), room)
    return rooms


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                           os.path.join(os.path.dirname(__file__), ".."))
    found = []
    owner = headers_by_room(root)
    include = re.compile(r'^\s*#\s*include\s*"([^"]+)"')
    for top in ("core", "io", "app"):
        for path in sources(root, top):
            rel = os.path.relpath(path, root)
            with open(path, encoding="utf-8", errors="replace") as f:
                lines = f.read().split("\n")
            n = len(lines) - (1 if lines and lines[-1] == "" else 0)
            if n > MAX_FILE_LINES:
                found.append(f"{rel}: {n} lines (at most {MAX_FILE_LINES})")
            for first, length, name in long_functions(lines):
                found.append(f"{rel}:{first}: {name}: {length} lines (at most "
                             f"{MAX_FUNCTION_LINES})")
            parts = rel.split(os.sep)
            for k, line in enumerate(lines, 1):
                m = include.match(line)
                if not m:
                    continue
                h = os.path.basename(m.group(1))
                if parts[0] == "core" and not h.startswith("tp_") and parts[1] == "include":
                    found.append(f"{rel}:{k}: a public header includes \"{h}\"")
                if parts[0] == "io" and parts[1] == "include" and h.endswith(".hpp"):
                    found.append(f"{rel}:{k}: a public header includes io/src's \"{h}\"")
                if parts[0] == "app" and len(parts) > 2 and parts[1] in APP_ROOMS:
                    room, other = parts[1], owner.get(h)
                    if other and other != room and other not in APP_ROOMS[room]:
                        found.append(f"{rel}:{k}: app/{room} includes \"{h}\" of app/{other}")
    for line in found:
        print(line)
    if found:
        print(f"check_house: {len(found)} finding(s); the rules are in docs/core.md, "
              "\"The rooms\"", file=sys.stderr)
        return 1
    print("check_house: every file, function and include within the rooms' rules")
    return 0


if __name__ == "__main__":
    sys.exit(main())
