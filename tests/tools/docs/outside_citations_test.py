"""No tracked file cites a file that a clone does not have (issue 46, item 14).

Notes and source comments were written beside a `shared` folder of reference material and a
development machine's /work checkout; neither is in a clone, so a reader who follows such a
citation finds nothing. Every tracked text file (docs, sources, comments, scripts) is read, and a
path-like citation fails the test when it

- starts at a folder named `shared` (after any number of `../` steps) and is not a tracked path,
  or
- is an absolute path under the development machine's `work` folder at the root (its checkouts).

The word itself (`shared_ptr`, "shared by all envs", `lib/shared/x.h` inside the repository) is
not a citation. Reads the tree through git, as tools/dev/check_layout.py does.

    /usr/bin/python3 outside_citations_test.py SOURCE_DIR
"""

import os
import re
import subprocess
import sys

FOLDER = "shared"
# A path that begins with the folder (optionally after ../ steps), at the start of a word.
SHARED_PATH = re.compile(r"(?<![\w./-])((?:\.\./)*" + FOLDER + r"/[\w./-]*)")
MACHINE_PATH = re.compile(r"(?<![\w.-])(/" + "work" + r"/[\w./-]*)")


def tracked_files(root):
    out = subprocess.check_output(["git", "ls-files", "--cached", "--others", "--exclude-standard"], cwd=root)
    return [p for p in out.decode().split("\n") if p]


def citations(root, files):
    tracked = set(files)
    found = []
    for path in files:
        full = os.path.join(root, path)
        if not os.path.isfile(full) or os.path.getsize(full) > 4_000_000:
            continue
        try:
            with open(full, encoding="utf-8") as f:
                text = f.read()
        except UnicodeDecodeError:
            continue  # images, videos, Parquet: not text
        for number, line in enumerate(text.split("\n"), 1):
            for match in SHARED_PATH.finditer(line):
                cited = match.group(1).rstrip(".")
                inside = os.path.normpath(os.path.join(os.path.dirname(path), cited))
                if cited.lstrip("./") in tracked or inside in tracked:
                    continue
                found.append(f"{path}:{number}: cites {cited}, which is not in the repository")
            for match in MACHINE_PATH.finditer(line):
                found.append(f"{path}:{number}: cites {match.group(1)}, a path of the development machine")
    return found


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
    files = tracked_files(root)
    found = citations(root, files)
    for line in found:
        print("FAIL:", line)
    print(f"outside_citations: {len(found)} citation(s) of files outside the repository in {len(files)} files")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
