"""docs/cli.md lists every subcommand of `tavis` and exactly the flags its `--help` has (issue 47,
acceptance 5): the reference cannot drift from the program.

The subcommands are those `tavis --help` lists under "Subcommands:", and theirs in turn (`tavis
sweep merge`); `tavis` itself is one too (`--version`). A subcommand's flags are the long options
of its `--help` ("Options:"), `--help` aside. In docs/cli.md a subcommand is the level-2 heading
`` ## `tavis SUBCOMMAND` `` and its flags are the table rows whose first cell starts with a flag
(`` | `--task TASK` | ... ``) up to the next level-2 heading. Each difference is a failure naming
the subcommand and the flag: a flag of `--help` missing from the page, a flag on the page that
`--help` no longer has, a subcommand without a section, a section of no subcommand.

    /usr/bin/python3 cli_reference_test.py TAVIS_BINARY SOURCE_DIR
"""

import os
import re
import subprocess
import sys

REFERENCE = "docs/cli.md"
SECTION = re.compile(r"^## `tavis((?: [a-z][a-z-]*)*)`\s*$")
FLAG_ROW = re.compile(r"^\|\s*`(--[a-z][a-z0-9-]*)")
HELP_OPTION = re.compile(r"^  (?:-\w,)?(--[a-z][a-z0-9-]*)")
HELP_SUBCOMMAND = re.compile(r"^  ([a-z][a-z-]*)\s")


def help_text(tavis, subcommand):
    result = subprocess.run([tavis, *subcommand.split(), "--help"], capture_output=True, text=True, timeout=60)
    if result.returncode != 0:
        raise SystemExit(f"`tavis {subcommand} --help` exited {result.returncode}: {result.stderr.strip()}")
    return result.stdout


def help_section(text, title):
    """The lines of one "Title:" block of a CLI11 help text (up to the next unindented line)."""
    lines, inside = [], False
    for line in text.split("\n"):
        if line == title + ":":
            inside = True
        elif inside and line and not line.startswith(" "):
            break
        elif inside:
            lines.append(line)
    return lines


def program_flags(tavis):
    """{subcommand ("" for tavis itself): set of its long flags}, every subcommand at any depth."""
    flags, pending = {}, [""]
    while pending:
        subcommand = pending.pop(0)
        text = help_text(tavis, subcommand)
        options = {m.group(1) for m in map(HELP_OPTION.match, help_section(text, "Options")) if m}
        flags[subcommand] = options - {"--help"}
        for match in map(HELP_SUBCOMMAND.match, help_section(text, "Subcommands")):
            if match:
                pending.append((subcommand + " " + match.group(1)).strip())
    return flags


def documented_flags(text):
    """{subcommand: {flag: line number}} from the page's sections and their flag tables."""
    documented, current = {}, None
    for number, line in enumerate(text.split("\n"), 1):
        if line.startswith("## "):
            section = SECTION.match(line)
            current = section.group(1).strip() if section else None
            if current is not None:
                documented.setdefault(current, {})
            continue
        row = FLAG_ROW.match(line)
        if row and current is not None:
            documented[current].setdefault(row.group(1), number)
    return documented


def differences(program, documented):
    found = []
    for subcommand in sorted(program):
        name = f"tavis {subcommand}".strip()
        if subcommand not in documented:
            found.append(f"{REFERENCE} has no section `## `{name}``: the subcommand `{name}` is undocumented")
            continue
        for flag in sorted(program[subcommand] - documented[subcommand].keys()):
            found.append(f"{REFERENCE}: `{name} {flag}` is in `{name} --help` but missing from the `{name}` table")
        for flag in sorted(documented[subcommand].keys() - program[subcommand]):
            found.append(f"{REFERENCE}:{documented[subcommand][flag]}: `{name} {flag}` is listed, "
                         f"but `{name} --help` has no {flag}")
    for subcommand in sorted(documented.keys() - program.keys()):
        name = f"tavis {subcommand}".strip()
        found.append(f"{REFERENCE} documents `{name}`, which is not a subcommand of tavis")
    return found


def main():
    tavis, source = (os.path.abspath(p) for p in sys.argv[1:3])
    with open(os.path.join(source, REFERENCE), encoding="utf-8") as f:
        documented = documented_flags(f.read())
    program = program_flags(tavis)
    found = differences(program, documented)
    for line in found:
        print("FAIL:", line)
    total = sum(len(flags) for flags in program.values())
    print(f"cli_reference: {len(program)} subcommands, {total} flags in --help, {len(found)} difference(s) "
          f"with {REFERENCE}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
