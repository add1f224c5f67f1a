#!/usr/bin/env python3
"""Checks the layout rules of docs/architecture.md (Design 1) on the source tree; exits 1 naming
every place that breaks one. Run by CTest (`layout_rules`), so CI checks it.

  tools/dev/check_layout.py [REPO_ROOT]

1. One namespace per folder: the code of folder F lives in namespace tavis::F (the path with '/'
   as '::': batch/dataset/video -> tavis::batch::dataset::video) or in namespaces nested inside
   it; anonymous namespaces and blocks of forward declarations of another module's classes are
   allowed. Tests mirror the folders they test (tests/batch/cell -> tavis::batch::cell); the shared
   fixtures of tests/support are tavis::testing. An internal/ folder holds its parent's private
   parts (engine/internal defines PhysicsWorld::Impl): the parent's namespace. The one exception is the math vocabulary every
   module speaks (VOCABULARY below), which is namespace tavis.
2. One folder, one target: every source folder's CMakeLists.txt declares exactly one library or
   program and compiles every .cc file of the folder; an internal/ folder is compiled by its
   parent's target.
3. Dependencies point one way (the table DEPENDENCIES): a module includes only the modules it may
   use, and the runtime in batch/'s root includes nothing of batch's subfolders, which build on it,
   but those below it (BELOW_RUNTIME: batch/perturb/), which include nothing of batch/ but their own.
4. The batch/ root is the runtime alone (RUNTIME_UNITS: the env, the episode loop, policies, the
   observation): any other file there fails, so a feature lands in a folder of its own.
"""
import pathlib
import re
import subprocess
import sys

SOURCE_MODULES = ("kinematics", "configs", "engine", "render", "scenarios", "batch", "tools")
# Headers in namespace tavis: the Eigen-based pose and shape vocabulary and the robot buffers that
# every module uses unqualified (kinematics/pose.h explains the monogram notation).
VOCABULARY = {"kinematics/pose.h", "kinematics/shape.h", "kinematics/robot_buffers.h"}
# Which top-level modules each may include (Design 1): kinematics <- engine <- render,
# engine, kinematics <- scenarios, all of them <- batch <- tools; configs loads files for anyone.
DEPENDENCIES = {
    "kinematics": {"kinematics"},
    "configs": {"configs", "kinematics"},
    "engine": {"engine", "kinematics", "configs"},
    "render": {"render", "engine", "kinematics", "configs"},
    "scenarios": {"scenarios", "engine", "kinematics", "configs"},
    "batch": {"batch", "scenarios", "render", "engine", "kinematics", "configs"},
    "tools": {"tools", "batch", "scenarios", "render", "engine", "kinematics", "configs"},
}
# The batch/ root holds the runtime and nothing else (docs/architecture.md, Design 1): these units
# (NAME.h and/or NAME.cc) and its CMakeLists.txt.
RUNTIME_UNITS = {
    # the env and its control tick, the scene's rendering
    "vec_env", "scene_render", "init_pose_warmup",
    # the episode loop: its schedules, its sinks and its observer
    "episode_driver", "lock_step_ticker", "episode_slots", "episode_sink", "loop_observer", "usable_threads",
    # policies
    "policy", "builtin_policies", "policy_kinds", "action_csv",
    # the observation
    "proprioception", "observation_contract", "camera_protocol",
}
# batch/ subfolders below the runtime: the runtime uses them and they include nothing of batch/
# but their own folder (the perturbation axes, which the env and the renderer apply).
BELOW_RUNTIME = {"batch/perturb"}
# Folders whose code is compiled by another folder's target.
TARGETLESS = re.compile(r"(^|/)internal$")
TARGET_CALL = re.compile(r"^\s*(add_library|add_executable|pybind11_add_module)\s*\(\s*([\w-]+)", re.M)
NAMESPACE_OPEN = re.compile(r"^namespace\s+([\w:]*)\s*\{(.*)$", re.M)
INCLUDE = re.compile(r'^#include "([\w/]+)\.h"', re.M)


def tracked_files(root):
    out = subprocess.check_output(["git", "ls-files", "--cached", "--others", "--exclude-standard"], cwd=root)
    return [pathlib.PurePosixPath(p) for p in out.decode().split("\n") if p]


def expected_namespace(folder):
    parts = list(folder.parts)
    if parts[-1] == "internal":
        parts = parts[:-1]  # a module's private parts: its namespace, or ::internal inside it
    if parts[0] == "tests":
        parts = parts[1:]
        if parts[:1] == ["support"]:
            return "tavis::testing"
    return "::".join(["tavis"] + parts)


def only_forward_declarations(text, start):
    """True if the namespace block opening at `start` holds only `class X;` / `struct X;` lines."""
    end = text.find("}", start)
    body = text[start:end] if end >= 0 else ""
    lines = [l.strip() for l in body.splitlines() if l.strip() and not l.strip().startswith("//")]
    return all(re.fullmatch(r"(class|struct)\s+\w+;", l) for l in lines)


def check_namespaces(root, files, problems):
    for path in files:
        if path.suffix not in (".h", ".cc") or path.parts[0] not in SOURCE_MODULES + ("tests",):
            continue
        if str(path) in VOCABULARY or "node_modules" in path.parts:
            continue
        expected = expected_namespace(path.parent)
        text = (root / path).read_text(encoding="utf-8", errors="replace")
        depth_ok = True
        for match in NAMESPACE_OPEN.finditer(text):
            name = match.group(1)
            if not name:
                continue  # anonymous
            line_start = text.rfind("\n", 0, match.start()) + 1
            if text[line_start:match.start()].strip():
                continue  # not at the start of a line
            if name == expected or name.startswith(expected + "::"):
                continue
            if only_forward_declarations(text, match.end()):
                continue
            # A namespace opened inside the folder's own (e.g. `namespace internal {` within it) nests.
            before = text[: match.start()]
            opened = [m.group(1) for m in NAMESPACE_OPEN.finditer(before) if m.group(1)]
            closed = len(re.findall(r"^\}\s*//\s*namespace\s+[\w:]+", before, re.M))
            if opened[:1] and (opened[0] == expected or opened[0].startswith(expected + "::")) and len(opened) > closed:
                continue
            line = text.count("\n", 0, match.start()) + 1
            problems.append(f"{path}:{line}: namespace {name} in {path.parent}/ (its folder's namespace is {expected})")
            depth_ok = False
        del depth_ok


def check_targets(root, files, problems):
    folders = sorted({p.parent for p in files if p.suffix == ".cc" and p.parts[0] in SOURCE_MODULES})
    for folder in folders:
        if TARGETLESS.search(str(folder)):
            parent_cmake = root / folder.parent / "CMakeLists.txt"
            text = parent_cmake.read_text() if parent_cmake.exists() else ""
            for cc in sorted(p for p in files if p.parent == folder and p.suffix == ".cc"):
                if f"{folder.name}/{cc.name}" not in text:
                    problems.append(f"{cc}: not compiled by {folder.parent}/CMakeLists.txt")
            continue
        cmake = root / folder / "CMakeLists.txt"
        if not cmake.exists():
            problems.append(f"{folder}/: .cc files but no CMakeLists.txt of its own")
            continue
        text = re.sub(r"#.*", "", cmake.read_text())
        targets = TARGET_CALL.findall(text)
        if len(targets) != 1:
            names = ", ".join(t[1] for t in targets) or "none"
            problems.append(f"{folder}/CMakeLists.txt: {len(targets)} targets ({names}), one expected")
        for cc in sorted(p for p in files if p.parent == folder and p.suffix == ".cc"):
            if not re.search(r"(^|[\s/(])" + re.escape(cc.name) + r"(\s|\))", text):
                problems.append(f"{cc}: not compiled by {folder}/CMakeLists.txt")


def check_dependencies(root, files, problems):
    for path in files:
        if path.suffix not in (".h", ".cc") or path.parts[0] not in DEPENDENCIES:
            continue
        module = path.parts[0]
        text = (root / path).read_text(encoding="utf-8", errors="replace")
        for match in INCLUDE.finditer(text):
            target = pathlib.PurePosixPath(match.group(1))
            if target.parts[0] not in DEPENDENCIES:
                continue
            line = text.count("\n", 0, match.start()) + 1
            if target.parts[0] not in DEPENDENCIES[module]:
                problems.append(f"{path}:{line}: {module}/ may not include {target}.h")
            elif module == "batch" and target.parts[0] == "batch":
                source_below = below_runtime(path)
                target_below = below_runtime(target)
                if source_below and target_below != source_below:
                    problems.append(f"{path}:{line}: {source_below}/ is below the runtime and may include only "
                                    f"its own folder of batch/, not {target}.h")
                elif len(path.parts) == 2 and len(target.parts) > 2 and not target_below:
                    problems.append(f"{path}:{line}: the runtime in batch/ may not include {target}.h "
                                    "(subfolders build on the runtime)")


def below_runtime(path):
    """The BELOW_RUNTIME folder `path` lies in, or None."""
    return next((folder for folder in BELOW_RUNTIME if str(path).startswith(folder + "/")), None)


def check_batch_root(files, problems):
    for path in files:
        if len(path.parts) != 2 or path.parts[0] != "batch" or path.name == "CMakeLists.txt":
            continue
        if path.suffix in (".h", ".cc") and path.stem in RUNTIME_UNITS:
            continue
        problems.append(f"{path}: the batch/ root holds only the runtime (the env, the episode loop, policies, the "
                        "observation: RUNTIME_UNITS in tools/dev/check_layout.py); put this in a folder, target and "
                        "namespace of its own under batch/ (docs/architecture.md, Design 1)")


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    files = tracked_files(root)
    problems = []
    check_namespaces(root, files, problems)
    check_targets(root, files, problems)
    check_dependencies(root, files, problems)
    check_batch_root(files, problems)
    for problem in problems:
        print(problem)
    print(f"check_layout: {len(problems)} problem(s) in {len(files)} files")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
