#!/usr/bin/env python3
"""Lists function bodies longer than a limit (default 80 lines) in the C++ sources, and whether a
comment within the three lines above the function says why ("long:" in it).

  tools/dev/long_functions.py [--limit N] [PATH ...]   (default: the source folders)
"""
import argparse
import pathlib
import re
import subprocess
import sys

SOURCE = ("kinematics", "configs", "engine", "render", "scenarios", "batch", "tools", "bench")
HEAD = re.compile(r"^[A-Za-z_~][\w:<>,&\*\s~\[\]]*\([^;{}]*\)\s*(const)?\s*(override)?\s*(noexcept)?\s*(->[^{]*)?\{\s*$")


def functions(path):
    lines = path.read_text(encoding="utf-8", errors="replace").split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        # A definition starts at column 0 or 2 (member functions inside a class body in a header).
        start = i
        head = line
        j = i
        while not head.rstrip().endswith("{") and j + 1 < len(lines) and j - i < 6 and head.strip() and not head.strip().endswith(";"):
            j += 1
            head += " " + lines[j].strip()
        if (line[:1].isalpha() or line[:1] == "~" or line.startswith("  ") and line[2:3].isalpha()) and HEAD.match(head.strip()) \
                and not re.match(r"\s*(if|for|while|switch|catch|namespace|class|struct|enum|return|else)\b", line):
            depth = 0
            k = j
            for k in range(j, len(lines)):
                code = lines[k].split("//")[0]
                depth += code.count("{") - code.count("}")
                if depth <= 0:
                    break
            yield start, k, lines
            i = k + 1
            continue
        i += 1


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--limit", type=int, default=80)
    parser.add_argument("paths", nargs="*")
    args = parser.parse_args()
    files = args.paths or [p for p in subprocess.check_output(["git", "ls-files", "*.cc", "*.h"]).decode().split()
                           if p.split("/")[0] in SOURCE]
    found = 0
    for name in files:
        path = pathlib.Path(name)
        for start, end, lines in functions(path):
            length = end - start + 1
            if length <= args.limit:
                continue
            above = "\n".join(lines[max(0, start - 3):start])
            why = "long:" in above
            found += 0 if why else 1
            print(f"{name}:{start + 1}: {length} lines{' (says why)' if why else ''}: {lines[start].strip()[:80]}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
