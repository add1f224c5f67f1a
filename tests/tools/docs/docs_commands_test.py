"""Every command in README.md and docs/*.md, as written (issue 46, acceptance 5).

doc_commands.py extracts the commands of the docs' code blocks and the `tavis ...` of their
inline code. Each is checked against the program and the repository:

- `tavis SUBCOMMAND` (as `build/tavis`, `tavis` on PATH, a bundle's `bin/tavis` or inside `bench/ab.sh
  "..."` and `sbatch --wrap "..."`): the subcommand exists and every flag named is in its `--help`;
  a command with concrete values is parsed by the program itself (`--help` appended: CLI11 converts
  every value and runs its validator, a number's range or a camera protocol, before it prints the
  help; a value the command checks later, such as `--video-format`, is checked only when run), and
  each choice of a synopsis's `--flag a|b` likewise.
- `python3 -m MODULE`: MODULE imports from the repository root with the PYTHONPATH the doc gives
  (none: none), and every flag named is in its source; a script (`bench/x.py`) exists.
- A repository script (`.ci/build`, `tools/...`, `bench/ab.sh`) is tracked and executable, and every
  flag named is in its text; any repository path an argument names (`configs/sweeps/x.yaml`) exists.
- `cmake`: every `--target` is a target of the build, every `--component` an install component and
  every `-DTAVIS_...` an option.
- What a command writes in the repository (`--out results/x`, `-B build-py`, `> plain.cg`, a venv)
  is ignored by .gitignore, so that following the docs leaves `git status` clean.

Then every command with no placeholder (DIR, FILE.csv, `<version>`, `a|b`, `$VAR`) is run, as
written, from a folder laid out as a fresh clone (the repository's tracked top-level entries, and
`build` this build), with `tavis` on PATH as the docs allow: it must exit 0, and every file or folder
it leaves in the clone's root must be ignored by .gitignore. `/tmp/` in a command is a private
temporary folder, so that runs do not meet. A file the doc tells the reader to save (the README's
`my_policy.py`) is saved in the clone first. A command the doc starts in the background
(`tavis_server ... --port 8000 &`) is a server: it is started, waited for until its port listens,
serves the commands after it in its code block, and is stopped with SIGTERM when the block ends
(it must exit 0); it gets a free port of its own, rewritten in its `--port` and the block's
`ws://127.0.0.1:PORT`. The commands that are not run are NOT_RUN below, each with why (a GPU, a
cluster, a build, minutes of work); an entry that matches no doc command fails the test, so the
list stays true.

    /usr/bin/python3 docs_commands_test.py TAVIS_BINARY SOURCE_DIR BUILD_DIR
"""

import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from doc_commands import TAVIS_PROGRAM, inline_tavis_commands, saved_files, shell_commands  # noqa: E402
from tool_script_support import check as count_check, failures, passed_count  # noqa: E402

TAVIS, SOURCE, BUILD = (os.path.abspath(p) for p in sys.argv[1:4])

# Doc commands not run here, matched against each simple command (`a && b`: a and b apart) from its
# start. Each is still checked as above.
NOT_RUN = [
    (r"\.ci/build", "builds the project: CI runs it before this test (the README's test command)"),
    (r"ctest ", "runs the whole suite, this test among them"),
    (r"\.ci/install-deps", "installs Debian packages (root)"),
    (r"tools/bundle/make_bundle\.sh|tools/bundle/check_bundle\.sh|tar xzf tavis-|tavis-\*/bin/tavis ",
     "builds or unpacks the portable bundle: bundle_runs_outside_the_build runs make_bundle.sh and check_bundle.sh"),
    (r"debootstrap ", "creates a Debian root (root, network)"),
    (r"build/tavis compare results/reference ",
     "compares the two served evaluations before it (their policy servers are placeholders); "
     "compare_command_test.cc runs `tavis compare` on cells it evaluates"),
    (r"cmake -S ", "configures a build (minutes); .ci/build configures the one this test runs in"),
    (r"cmake --build ", "builds targets; .ci/build built them for this test"),
    (r"cmake --install build --component python *$",
     "installs the module into the system's Python (/usr/local, root); the same with --prefix venv is run"),
    (r"build/tavis demos --task clutter-pick-cube --robot gr1t2 --episodes 100 ",
     "100 episodes of four 640x480 cameras at 60 fps: minutes on 2 cores (parsed with --help)"),
    (r"build/tavis demos --task conditional-pick --robot gr1t2 (--split id )?--episodes 200 ",
     "200 episodes, for the GPU baseline (parsed with --help)"),
    (r"build/tavis sweep configs/sweeps/acceptance\.yaml", "96 cells of 96 episodes (parsed with --help)"),
    (r"tavis sweep /tmp/p8\.yaml", "512 cells of 8 episodes (parsed with --help)"),
    (r"tavis sweep +configs/sweeps/perturbations\.yaml", "512 cells of 96 episodes (parsed with --help)"),
    (r"build/tavis eval --task clutter-pick-cube .*--policy (openpi|replay)",
     "a served clutter-pick-cube cell of 96 episodes of your own policy (MODULE:FACTORY; minutes served on 2 "
     "cores), and a replay of its episode 7 (parsed with --help)"),
    (r"tavis eval +--task multi-shelf-scan --perturb distractors:two --perturb runtime:move|"
     r"tavis eval +--task clutter-pick-cube --perturb appearance:table-wood",
     "96 episodes each, as build/tavis eval runs here (parsed with --help)"),
    (r"PYTHONPATH=tools/baseline:tools/policy_server python3 -m tavis_baseline\.train .*--device cuda",
     "trains on a CUDA GPU (docs/baselines.md: minutes on an H200, hours on a CPU)"),
    (r"PYTHONPATH=tools/baseline:tools/policy_server python3 -m tavis_baseline\.serve ckpt/|"
     r"build/tavis eval --task conditional-pick --robot gr1t2 --camera head (--split id )?--episodes 96 .*--policy openpi",
     "serves, and evaluates on 96 episodes, a checkpoint that the GPU training before it writes (ckpt/); "
     "the published checkpoint is served on the CPU and evaluated instead (docs/baselines.md, \"On the CPU\")"),
    (r"PYTHONPATH=tools/policy_server python3 -m tavis_server --policy tavis_server\.lerobot_checkpoint:load ",
     "serves a LeRobot checkpoint on CUDA: LeRobot cannot be installed here (Python 3.11, torch 1.13; docs/serving.md)"),
    (r"tools/baseline/gpu_table_runs\.sh", "the GPU table: a lent GPU machine, 25 minutes"),
    (r"sbatch |job=\$\(sbatch |TAVIS=\S+ sbatch |N=\d+$|tavis sweep merge --out /scratch/",
     "needs a Slurm cluster and its shards: slurm_sweep_job_array runs tools/slurm/sweep_array.sbatch and merges"),
    (r"valgrind |callgrind_annotate ", "callgrind runs of the render benchmark (minutes) and their reports"),
    (r"for (round|i) in ", "benchmark loops (minutes)"),
    (r"git worktree add ", "a second checkout of an old commit, built for an A/B benchmark"),
    (r"bench/ab\.sh ", "an A/B benchmark of two builds (minutes)"),
    (r"PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead\.py", "a benchmark: 7 rounds of 3 s per case"),
]

PYTHONS = re.compile(r"^(/usr/bin/python3|python3(\.\d+)?|venv/bin/python|\$VIRTUAL_ENV/bin/python)$")
# Programs the docs use that are not the project's: run when concrete, otherwise not checked.
EXTERNAL = {"tar", "sed", "grep", "echo", "paste", "valgrind", "callgrind_annotate", "debootstrap", "sbatch",
            "git", "ctest", "cmake", "mount", "lerobot-eval"}
# DIR, FILE.csv, I/N, DIR_i, ws://HOST:PORT, <version>, ..., $VAR, a|b, [optional].
PLACEHOLDER = re.compile(r"<[^>]*>|\.\.\.|\$|(?<![A-Za-z0-9])[A-Z][A-Z0-9]*(?![a-z0-9])|\w\|\w|\[|\]")
OUTPUT_FLAGS = {"--out", "--record", "--json-out", "-B", "--prefix"}


def check(condition, message):
    """tool_script_support's counted check, returning the condition."""
    count_check(condition, message)
    return condition


def tracked():
    """{path: git mode} of every tracked file."""
    out = subprocess.check_output(["git", "ls-files", "-s"], cwd=SOURCE, text=True)
    files = {}
    for line in out.splitlines():
        mode, _, _, path = line.split(None, 3)
        files[path] = mode
    return files


TRACKED = tracked()
TOP_LEVEL = sorted({path.split("/")[0] for path in TRACKED})
HELP = {}


def tavis_help(subcommand):
    if subcommand not in HELP:
        result = subprocess.run([TAVIS, *subcommand.split(), "--help"], capture_output=True, text=True, timeout=60)
        HELP[subcommand] = result.stdout if result.returncode == 0 else None
    return HELP[subcommand]


def flags_in(text):
    return sorted(set(re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", text)))


def is_placeholder(text):
    return bool(PLACEHOLDER.search(text))


def has_placeholder(command_text):
    """A command to fill in rather than run: a placeholder outside quotes and variable names."""
    text = re.sub(r"'[^']*'|\"[^\"]*\"", "", command_text)
    text = re.sub(r"(^|\s)[A-Za-z_]\w*=", r"\1", text)
    return is_placeholder(text)


def cmake_names(pattern):
    names = set()
    for path in TRACKED:
        if path.endswith(("CMakeLists.txt", ".cmake")):
            with open(os.path.join(SOURCE, path), encoding="utf-8") as f:
                names.update(re.findall(pattern, f.read()))
    return names


CMAKE_TARGETS = cmake_names(r"(?:add_library|add_executable|pybind11_add_module|add_custom_target|tavis_add_\w+)\(\s*([\w-]+)")
CMAKE_COMPONENTS = cmake_names(r"COMPONENT\s+(\w+)")
CMAKE_OPTIONS = cmake_names(r"\b(TAVIS_[A-Z0-9_]+)\b")


def ignored(path):
    """True if .gitignore ignores `path` (relative to the repository; a folder ends with '/')."""
    return subprocess.run(["git", "check-ignore", "-q", "--no-index", "--", path], cwd=SOURCE).returncode == 0


def check_output_path(command, path, is_folder=True):
    if not path or path.startswith(("/", "~", "$")) or is_placeholder(path.split("/")[0]):
        return
    first = path.split("/")[0]
    if first in (".", ".."):
        return
    name = first + "/" if (is_folder or "/" in path) else first
    check(ignored(name), f"{command.where()}: `{command.text}` writes {path} in the repository, which .gitignore does not ignore ({name})")


def check_repo_paths(command, tokens):
    """Arguments that name a file of the repository (configs/..., tools/...) must exist."""
    for token in tokens:
        value = token.split("=", 1)[1] if token.startswith("--") and "=" in token else token
        if "/" not in value or is_placeholder(value) or value.startswith(("/", "ws://", "http")):
            continue
        first = value.split("/")[0]
        if first in TOP_LEVEL and first not in ("build", "results", "datasets"):
            exists = value in TRACKED or any(p.startswith(value.rstrip("/") + "/") for p in TRACKED)
            check(exists, f"{command.where()}: `{command.text}` names {value}, which is not in the repository")


def check_tavis(command, words, concrete):
    """words: what follows the program. The subcommand exists, its flags are in --help, and a
    concrete command's values are accepted by the program's parser."""
    if not words or words[0].startswith("-"):
        check(bool(words) and words[0] in ("--help", "--version"), f"{command.where()}: `{command.text}` names no subcommand")
        return
    subcommand = "sweep merge" if words[:2] == ["sweep", "merge"] else words[0]
    help_text = tavis_help(subcommand)
    if not check(help_text is not None, f"{command.where()}: `tavis {subcommand}` is not a subcommand of tavis ({command.text})"):
        return
    for flag in flags_in(" ".join(words)):
        check(flag in flags_in(help_text), f"{command.where()}: `tavis {subcommand}` has no {flag} (`{command.text}`)")
    arguments = words[len(subcommand.split()):]
    for i, word in enumerate(arguments):
        if word in OUTPUT_FLAGS and i + 1 < len(arguments):
            check_output_path(command, arguments[i + 1])
    if subcommand == "eval" and "--out" not in arguments and "--help" not in arguments:
        check_output_path(command, "results/")
    check_repo_paths(command, arguments)
    if concrete:
        result = subprocess.run([TAVIS, *words, "--help"], capture_output=True, text=True, timeout=60)
        check(result.returncode == 0, f"{command.where()}: `{command.text}`: tavis does not parse it: {result.stderr.strip()}")
    elif command.kind != "inline":
        # Each choice of a synopsis's `--flag a|b|c` (lower-case, no placeholder) must be accepted.
        for flag, value in re.findall(r"(--[a-z][a-z0-9-]*)[ =]([a-z0-9][\w.,:-]*(?:\|[a-z0-9][\w.,:-]*)+)", " ".join(arguments)):
            for choice in value.split("|"):
                result = subprocess.run([TAVIS, *subcommand.split(), flag, choice, "--help"], capture_output=True,
                                        text=True, timeout=60)
                check(result.returncode == 0,
                      f"{command.where()}: `tavis {subcommand} {flag} {choice}` is refused: {result.stderr.strip()}")


def module_origin(python, module, pythonpath):
    """The file a `python -m MODULE` runs from the repository root with that PYTHONPATH, or None."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    probe = "import importlib.util, sys\nspec = importlib.util.find_spec(sys.argv[1])\nprint(spec.origin if spec else '')"
    result = subprocess.run([python, "-c", probe, module], cwd=SOURCE, env=env, capture_output=True, text=True, timeout=60)
    return result.stdout.strip() if result.returncode == 0 and result.stdout.strip() else None


def check_python(command, assignments, words):
    if "-m" in words[:2]:
        module = words[words.index("-m") + 1]
        if module in ("venv", "pip", "pybind11"):
            return
        pythonpath = assignments.get("PYTHONPATH", "")
        if is_placeholder(pythonpath):
            return
        origin = module_origin("/usr/bin/python3", module, pythonpath)
        where = f"with PYTHONPATH={pythonpath}" if pythonpath else "without a PYTHONPATH"
        if not check(origin is not None, f"{command.where()}: `{command.text}`: No module named {module} from the repository root {where}"):
            return
        sources = [origin]
        if os.path.basename(origin) in ("__init__.py", "__main__.py"):
            folder = os.path.dirname(origin)
            sources = [os.path.join(folder, name) for name in os.listdir(folder) if name.endswith(".py")]
        text = "".join(open(path, encoding="utf-8").read() for path in sources)
        rest = words[words.index("-m") + 2:]
        for flag in flags_in(" ".join(rest)):
            check(f'"{flag}"' in text or f"'{flag}'" in text, f"{command.where()}: {module} has no {flag} (`{command.text}`)")
        for i, word in enumerate(rest):
            if word == "--out" and i + 1 < len(rest):
                check_output_path(command, rest[i + 1])
        return
    if words and words[0] not in ("-c",) and not words[0].startswith("-"):
        check_script(command, words[0], words[1:])


def check_script(command, path, arguments):
    mode = TRACKED.get(path)
    if not check(mode is not None, f"{command.where()}: `{command.text}`: {path} is not in the repository"):
        return
    if not path.endswith(".py"):
        check(mode == "100755", f"{command.where()}: {path} is not executable (mode {mode})")
    with open(os.path.join(SOURCE, path), encoding="utf-8") as f:
        text = f.read()
    for flag in flags_in(" ".join(a.split("=")[0] for a in arguments if a.startswith("--"))):
        check(flag in text, f"{command.where()}: {path} has no {flag} (`{command.text}`)")
    check_repo_paths(command, arguments)
    if path == "bench/ab.sh" and len(arguments) >= 2:
        check_tavis(command, shlex.split(arguments[1]), False)


def check_cmake(command, words):
    for i, word in enumerate(words):
        following = words[i + 1:]
        if word == "--target":
            for target in following:
                if target.startswith("-"):
                    break
                check(target in CMAKE_TARGETS, f"{command.where()}: no CMake target {target} (`{command.text}`)")
        if word == "--component" and following:
            check(following[0] in CMAKE_COMPONENTS, f"{command.where()}: no install component {following[0]}")
        option = re.match(r"-D(TAVIS_\w+)=", word)
        if option:
            check(option.group(1) in CMAKE_OPTIONS, f"{command.where()}: no CMake option {option.group(1)}")
        if word in OUTPUT_FLAGS and following:
            check_output_path(command, following[0])


def simple_commands(text):
    """Splits a command line at &&, ||, ; and & (pipelines stay whole): (text, background) of each
    part, background when the part ends with a single & (a server the doc starts in the background)."""
    if text.startswith("for "):
        return [(text, False)]                                          # a loop is one command
    text = re.sub(r"\$\(\([^)]*\)\)", "0", text)                     # $((N - 1))
    parts, current, quote, i = [], "", None, 0
    while i < len(text):
        c = text[i]
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c == "#" and (not current or current[-1].isspace()):
            break
        elif text.startswith("&&", i) or text.startswith("||", i):
            parts.append((current, False))
            current, i = "", i + 2
            continue
        elif c in ";&" and not text.startswith("&&", i):
            parts.append((current, c == "&"))
            current, i = "", i + 1
            continue
        current += c
        i += 1
    parts.append((current, False))
    return [(p.strip(), background) for p, background in parts if p.strip()]


def check_command(command, part):
    """The static checks of one simple command (a pipeline's first program)."""
    part = re.sub(r"^(\w+)=\$\((.*)\)$", r"\2", part)                  # job=$(sbatch ...)
    pipeline = part.split(" | ")[0] if command.kind == "command" else part
    if pipeline.startswith("for "):
        return                                                          # a benchmark loop
    redirect = re.search(r"(?:^|\s)>\s*(\S+)\s*$", pipeline)
    if redirect:
        check_output_path(command, redirect.group(1), is_folder=False)
        pipeline = pipeline[:redirect.start()]
    try:
        # A synopsis or prose is not shell: `the paper's` is an apostrophe, not a quote.
        words = shlex.split(pipeline) if command.kind == "command" else pipeline.split()
    except ValueError as error:
        check(False, f"{command.where()}: cannot read `{part}` as a shell command: {error}")
        return
    assignments = {}
    while words and re.match(r"^[A-Za-z_]\w*=", words[0]):
        name, value = words.pop(0).split("=", 1)
        assignments[name] = value
    if not words:
        return
    program, arguments = words[0], words[1:]
    for word in arguments:
        output = re.match(r"--[\w-]*out-file=(\S+)", word)
        if output:
            check_output_path(command, output.group(1), is_folder=False)
    if re.fullmatch(TAVIS_PROGRAM, program) or (program == "tavis"):
        check_tavis(command, arguments, not has_placeholder(part) and command.kind == "command")
    elif PYTHONS.match(program):
        check_python(command, assignments, arguments)
        if program == "/usr/bin/python3" and arguments[:1] == ["-m"] and arguments[1:2] == ["venv"]:
            check_output_path(command, arguments[-1])
    elif program == "cmake":
        check_cmake(command, arguments)
    elif program == "sbatch":
        check_repo_paths(command, arguments)
        if "--wrap" in arguments:
            check_command(command, arguments[arguments.index("--wrap") + 1])
    elif program in ("for", "do", "done"):
        return
    elif "/" in program and program.split("/")[0] in TOP_LEVEL and not program.startswith(("build/", "/")):
        check_script(command, program, arguments)
    else:
        check(program in EXTERNAL or program.startswith(("build/", "/tmp/", "venv/")),
              f"{command.where()}: `{part}`: {program} is neither the project's nor a program this test knows")


def not_run_reason(part):
    for i, (pattern, reason) in enumerate(NOT_RUN):
        if re.match(pattern, part):
            USED.add(i)
            return reason
    return None


USED = set()


def fresh_clone(root, docs_files):
    """A folder laid out as a fresh clone: the tracked top-level entries (linked) and build, with the
    files the docs tell the reader to save there (docs_files: (doc, line, path, text))."""
    for name in TOP_LEVEL:
        os.symlink(os.path.join(SOURCE, name), os.path.join(root, name))
    os.symlink(BUILD, os.path.join(root, "build"))
    for doc, line, path, text in docs_files:
        target = os.path.join(root, path)
        if check("/" not in path and path not in TRACKED and not os.path.exists(target),
                 f"{doc}:{line}: the file the doc saves, {path}, is not a new file of the checkout's root"):
            with open(target, "w", encoding="utf-8") as f:
                f.write(text)
            print(f"SAVED    {doc}:{line}: {path}")
    bin_dir = os.path.join(os.path.dirname(root), "bin")
    os.makedirs(bin_dir, exist_ok=True)
    os.symlink(TAVIS, os.path.join(bin_dir, "tavis"))
    return bin_dir


PIP_BUILD_DIR = os.path.join(os.path.dirname(os.path.realpath(BUILD)), f"build-docs-pip-{os.getpid()}")


def build_tree_werror():
    """The build tree's TAVIS_WERROR (CMakeCache.txt), "OFF" when it has none."""
    with open(os.path.join(BUILD, "CMakeCache.txt"), encoding="utf-8") as f:
        for line in f:
            if line.startswith("TAVIS_WERROR:"):
                return line.strip().split("=", 1)[1]
    return "OFF"


def run_environment(bin_dir):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PATH"] = bin_dir + os.pathsep + env.get("PATH", "")
    # docs/python.md's `pip install .` builds the module again (setup.py): a minute when ccache
    # serves its objects, ten otherwise. It does when every compile command equals the build tree's:
    # the build tree's TAVIS_WERROR (TAVIS_CMAKE_ARGS, which the doc names), and pip's build folder
    # (TAVIS_PIP_BUILD_DIR) beside the build tree, so that a CCACHE_BASEDIR's relative paths match.
    env.setdefault("TAVIS_CMAKE_ARGS", f"-DTAVIS_WERROR={build_tree_werror()}")
    env["TAVIS_PIP_BUILD_DIR"] = PIP_BUILD_DIR
    return env


def check_left(command, part, clone, before):
    """Every file or folder a command left in the clone's root is ignored by .gitignore."""
    for name in sorted(set(os.listdir(clone)) - before):
        folder = os.path.isdir(os.path.join(clone, name))
        check(ignored(name + ("/" if folder else "")),
              f"{command.where()}: `{part}` left {name} in the clone's root, which .gitignore does not ignore")


def run_as_written(command, part, clone, env, private_tmp):
    text = part.replace("/tmp/", private_tmp + "/")
    before = set(os.listdir(clone))
    start = time.time()
    try:
        result = subprocess.run(["bash", "-c", text], cwd=clone, env=env, capture_output=True, text=True, timeout=300)
    except subprocess.TimeoutExpired as error:
        check(False, f"{command.where()}: `{part}` did not end within 300 s:\n{str(error.stdout or '')[-2000:]}")
        return
    took = time.time() - start
    check(result.returncode == 0,
          f"{command.where()}: `{part}` exited {result.returncode}:\n{result.stdout[-2000:]}\n{result.stderr[-2000:]}")
    check_left(command, part, clone, before)
    print(f"RUN      {command.where()}: {part}  -> exit {result.returncode} in {took:.1f} s", flush=True)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Servers:
    """The servers a doc starts in the background (`COMMAND --port N &`), as its reader does: each
    is started, waited for until its port accepts a connection, and serves the commands after it in
    the same code block; when the block ends it is stopped as the README's `kill %1` stops it
    (SIGTERM), and must then exit 0 (docs/serving.md). Each gets a free port of its own, its
    `--port N` and the block's later `ws://127.0.0.1:N` rewritten to it, so that two runs of this
    test (or another test's server) do not meet on the doc's port."""

    START_S = 240       # a checkpoint's server imports torch and loads the weights first

    def __init__(self, clone, env, private_tmp):
        self.clone, self.env, self.private_tmp = clone, env, private_tmp
        self.running, self.ports, self.block = [], {}, None

    def enter(self, command):
        """Stops the servers of an earlier block before a command of another block."""
        if (command.doc, command.block) != self.block:
            self.stop_all()
            self.block = (command.doc, command.block)

    def rewrite(self, text):
        for doc_port, port in self.ports.items():
            text = re.sub(rf"(ws://(?:127\.0\.0\.1|localhost):){doc_port}(?!\d)", rf"\g<1>{port}", text)
        return text

    def start(self, command, part):
        match = re.search(r"--port[ =](\d+)(?!\d)", part)
        if not check(match is not None, f"{command.where()}: `{part}` runs in the background but names no --port to wait for"):
            return
        port = free_port()
        self.ports[match.group(1)] = port
        text = (part[:match.start()] + f"--port {port}" + part[match.end():]).replace("/tmp/", self.private_tmp + "/")
        log_path = os.path.join(self.private_tmp, f"server-{port}.log")
        before = set(os.listdir(self.clone))
        started = time.time()
        with open(log_path, "w") as log:
            # exec: the signal reaches the server itself, not a shell waiting for it.
            process = subprocess.Popen(["bash", "-c", "exec env " + text], cwd=self.clone, env=self.env, stdout=log,
                                       stderr=subprocess.STDOUT, start_new_session=True)
        while True:
            if process.poll() is not None:
                check(False, f"{command.where()}: `{part}` exited {process.returncode} before it listened on port "
                             f"{port}:\n{self.log_tail(log_path)}")
                return
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                pass
            if time.time() - started > self.START_S:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
                check(False, f"{command.where()}: `{part}` did not listen on port {port} within {self.START_S} s:\n"
                             f"{self.log_tail(log_path)}")
                return
            time.sleep(0.2)
        print(f"SERVE    {command.where()}: {text}  -> listening after {time.time() - started:.1f} s", flush=True)
        self.running.append((command, part, process, log_path, before))

    @staticmethod
    def log_tail(log_path):
        with open(log_path, encoding="utf-8", errors="replace") as f:
            return f.read()[-3000:]

    def stop_all(self):
        for command, part, process, log_path, before in self.running:
            alive = process.poll() is None
            if alive:
                os.killpg(process.pid, signal.SIGTERM)
            try:
                code = process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                code = process.wait()
            what = "SIGTERM stopped it with exit" if alive else "it stopped before its block's commands had run, exit"
            check(alive and code == 0, f"{command.where()}: `{part}`: {what} {code}:\n{self.log_tail(log_path)}")
            check_left(command, part, self.clone, before)
            print(f"STOPPED  {command.where()}: {what} {code}", flush=True)
        self.running, self.ports = [], {}


def main():
    docs = sorted(p for p in TRACKED if p == "README.md" or re.fullmatch(r"docs/[^/]+\.md", p))
    commands, docs_files = [], []
    for doc in docs:
        with open(os.path.join(SOURCE, doc), encoding="utf-8") as f:
            text = f.read()
        found, _ = shell_commands(doc, text)
        commands += found + inline_tavis_commands(doc, text)
        docs_files += [(doc, line, path, body) for line, path, body in saved_files(text)]
    check(len(commands) > 50, f"only {len(commands)} commands found in {len(docs)} docs: the extraction is broken")
    counts = {"run": 0, "served": 0, "not run": 0, "template": 0}
    with tempfile.TemporaryDirectory(prefix="tavis-docs-") as work:
        clone, private_tmp = os.path.join(work, "clone"), os.path.join(work, "tmp")
        os.makedirs(clone)
        os.makedirs(private_tmp)
        env = run_environment(fresh_clone(clone, docs_files))
        servers = Servers(clone, env, private_tmp)
        try:
            for command in commands:
                if command.kind == "command":
                    servers.enter(command)
                for part, background in simple_commands(command.text):
                    check_command(command, part)
                    if command.kind != "command":
                        continue
                    reason = not_run_reason(part)
                    if reason:
                        counts["not run"] += 1
                        print(f"NOT RUN  {command.where()}: {part}  ({reason})")
                    elif has_placeholder(part):
                        counts["template"] += 1
                        print(f"TEMPLATE {command.where()}: {part}  (checked, not runnable as written)")
                    elif background:
                        counts["served"] += 1
                        servers.start(command, part)
                    else:
                        counts["run"] += 1
                        run_as_written(command, servers.rewrite(part), clone, env, private_tmp)
        finally:
            servers.stop_all()
            shutil.rmtree(PIP_BUILD_DIR, ignore_errors=True)
    for i, (pattern, _) in enumerate(NOT_RUN):
        check(i in USED, f"NOT_RUN entry {pattern!r} matches no command of the docs: remove it")
    print(f"commands: {counts['run']} run, {counts['served']} started as servers, {counts['not run']} not run, "
          f"{counts['template']} templates")
    print(f"{passed_count()} checks passed, {len(failures)} failed, {len(commands)} commands in {len(docs)} docs")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
