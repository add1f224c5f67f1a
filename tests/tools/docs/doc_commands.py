"""The shell commands a Markdown doc gives its reader, as docs_commands_test.py checks them.

A doc writes commands in code blocks: indented four spaces or fenced (```, ```sh). A block is cut
into paragraphs at blank lines, and each paragraph is told apart by its first line: YAML (`key:`),
Python (fenced ```python, `import`, `x = ...`), a file listing (`name/`), or else shell. A shell
paragraph gives one command per line, lines ending in `\\` joined with the next and a `for ...
done` loop kept whole; `# or: COMMAND` is an alternative the doc offers and counts as a command,
other comments do not. A line that starts `tavis SUBCOMMAND` and shows choices (`[--flag`, `a|b`,
`...`) is a synopsis: it and the lines up to the next `tavis` line are one entry (the README's
list of subcommands wraps its lines without `\\`).

Inline code that starts `tavis SUBCOMMAND` or `build/tavis SUBCOMMAND` is collected too: prose
names flags that way (`tavis eval --expert-hz 20`), and a flag named there must exist as well.

A fenced block that the prose just before it tells the reader to save (``save this as `my_policy.py` ``)
is a file the doc's later commands need: saved_files gives its path and text.
"""

import re
from dataclasses import dataclass

FENCE = re.compile(r"^(```+|~~~+)\s*([\w+-]*)")
YAML_LINE = re.compile(r"^[a-z_][\w-]*:(\s|$)")
PYTHON_LINE = re.compile(r"^(import |from \S+ import |\w+(, \w+)* = \S)")
LISTING_LINE = re.compile(r"^[\w.<>*-]+/$")
TAVIS_PROGRAM = r"(?:build/|\$TAVIS\b|[\w.<>*$/{}-]*/bin/)?tavis"
SYNOPSIS_START = re.compile(r"^tavis\s+[a-z]")
INLINE_TAVIS = re.compile(r"`((?:build/)?tavis [a-z][^`]*)`")


@dataclass
class DocCommand:
    doc: str        # path relative to the repository
    line: int       # 1-based line of the command's first line in the doc
    text: str       # the command, continuation lines joined
    kind: str       # "command" (a block's command line), "synopsis" or "inline"
    block: int = 0  # the first line of its code block: a background server lives until the block ends

    def where(self):
        return f"{self.doc}:{self.line}"


def code_blocks(text):
    """Yields (first line number, language, lines) for every fenced and indented block."""
    lines = text.split("\n")
    i, previous_blank = 0, True
    while i < len(lines):
        fence = FENCE.match(lines[i])
        if fence:
            end = i + 1
            while end < len(lines) and not lines[end].startswith(fence.group(1)):
                end += 1
            yield i + 2, fence.group(2) or "", lines[i + 1:end]
            i, previous_blank = end + 1, False
            continue
        if previous_blank and lines[i].startswith("    ") and lines[i].strip():
            end = i
            while end < len(lines) and (lines[end].startswith("    ") or not lines[end].strip()):
                end += 1
            body = [line[4:] for line in lines[i:end]]
            while body and not body[-1].strip():
                body.pop()
            yield i + 1, "", body
            i, previous_blank = end, True
            continue
        previous_blank = not lines[i].strip()
        i += 1


def paragraphs(start, lines):
    """Splits a block's lines at blank lines: (first line number, lines) per paragraph."""
    current, first = [], start
    for number, line in enumerate(lines, start):
        if line.strip():
            if not current:
                first = number
            current.append(line)
        elif current:
            yield first, current
            current = []
    if current:
        yield first, current


def paragraph_kind(language, lines):
    if language in ("yaml", "yml", "json", "python", "py", "text"):
        return {"yml": "yaml", "py": "python"}.get(language, language)
    first = lines[0].strip()
    if YAML_LINE.match(first) and not first.startswith(("http:", "https:")):
        return "yaml"
    if PYTHON_LINE.match(first):
        return "python"
    if LISTING_LINE.match(first):
        return "listing"
    return "shell"


def is_synopsis(text):
    return bool(SYNOPSIS_START.match(text)) and bool(re.search(r"\[--|\w\|\w|\.\.\.| \| --", text))


def logical_lines(first, lines):
    """Joins `\\` continuations and `for ... done` loops: (line number, text) per command."""
    i = 0
    while i < len(lines):
        number, parts = first + i, []
        line = lines[i].strip()
        if line.startswith("for "):
            depth = 0
            while i < len(lines):
                depth += len(re.findall(r"(^|[;\s])for\s", lines[i])) - len(re.findall(r"(^|[;\s])done\b", lines[i]))
                parts.append(lines[i].strip().rstrip("\\").strip())
                i += 1
                if depth <= 0:
                    break
            yield number, " ".join(parts)
            continue
        while True:
            text = lines[i].strip()
            i += 1
            if text.endswith("\\") and i < len(lines):
                parts.append(text[:-1].strip())
                continue
            parts.append(text)
            break
        yield number, " ".join(parts)


def synopsis_entries(first, lines):
    """The README's synopsis list: an entry per `tavis` line, with the lines that follow it."""
    entry, start = [], first
    for number, line in enumerate(lines, first):
        if SYNOPSIS_START.match(line.strip()) and entry:
            yield start, " ".join(entry)
            entry = []
        if not entry:
            start = number
        entry.append(line.strip().rstrip("\\").strip())
    if entry:
        yield start, " ".join(entry)


def shell_commands(doc, text):
    """Every command of a doc's code blocks (DocCommand), and the paragraphs that are not shell."""
    commands, others = [], []
    for start, language, lines in code_blocks(text):
        for first, paragraph in paragraphs(start, lines):
            kind = paragraph_kind(language, paragraph)
            if kind != "shell":
                others.append((doc, first, kind))
                continue
            if is_synopsis(paragraph[0].strip()):
                for number, entry in synopsis_entries(first, paragraph):
                    entry = re.sub(r"\s+#\s.*$", "", entry)
                    commands.append(DocCommand(doc, number, entry, "synopsis" if is_synopsis(entry) else "command",
                                               start))
                continue
            for number, line in logical_lines(first, paragraph):
                if line.startswith("#"):
                    alternative = re.match(r"#\s*or:\s*(.+)", line)
                    if not alternative:
                        continue
                    line = alternative.group(1)
                commands.append(DocCommand(doc, number, line, "synopsis" if is_synopsis(line) else "command", start))
    return commands, others


def inline_tavis_commands(doc, text):
    """Inline code spans that start with `tavis SUBCOMMAND` (the README's and docs' prose)."""
    found = []
    for number, line in enumerate(text.split("\n"), 1):
        for match in INLINE_TAVIS.finditer(line):
            found.append(DocCommand(doc, number, match.group(1).replace("\\|", "|"), "inline"))
    return found


SAVE_AS = re.compile(r"save (?:this|it) as `([^`]+)`", re.I)


def saved_files(text):
    """(line, path, text) of every fenced block whose preceding prose paragraph says "save this as
    `PATH`": the README's `my_policy.py`, which its serve command imports."""
    lines, found = text.split("\n"), []
    for start, _, body in code_blocks(text):
        fence = start - 2                                               # the block's opening fence
        if fence < 0 or not FENCE.match(lines[fence]):
            continue
        prose = []
        i = fence - 1
        while i >= 0 and not lines[i].strip():
            i -= 1
        while i >= 0 and lines[i].strip():
            prose.insert(0, lines[i])
            i -= 1
        match = SAVE_AS.search(" ".join(prose))
        if match:
            found.append((start, match.group(1), "\n".join(body) + "\n"))
    return found
