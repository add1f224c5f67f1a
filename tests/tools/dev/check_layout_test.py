#!/usr/bin/env python3
"""tools/dev/check_layout.py on small trees made for the purpose: a tree that keeps the rules
passes; a loose unit in the batch/ root fails naming it and where such code goes; the runtime may
include the folders below it (batch/perturb/) and no other subfolder, and those include nothing of
batch/ but their own folder.

    /usr/bin/python3 check_layout_test.py SOURCE_DIR
"""

import pathlib
import subprocess
import sys
import tempfile
import unittest

SOURCE_DIR = pathlib.Path(sys.argv.pop(1) if len(sys.argv) > 1 else ".").resolve()
CHECK = SOURCE_DIR / "tools" / "dev" / "check_layout.py"


def write(root, path, text):
    full = root / path
    full.parent.mkdir(parents=True, exist_ok=True)
    full.write_text(text)


def unit(namespace, includes=()):
    lines = [f'#include "{include}"' for include in includes]
    return "\n".join(lines + [f"namespace {namespace} {{", "int f();", f"}}  // namespace {namespace}", ""])


class CheckLayoutTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = pathlib.Path(self.tmp.name)
        subprocess.run(["git", "init", "-q"], cwd=self.root, check=True)
        # The runtime with one unit, and one folder below it (the perturbation axes).
        write(self.root, "batch/CMakeLists.txt", "add_library(tavis_batch STATIC vec_env.cc)\n")
        write(self.root, "batch/vec_env.h", unit("tavis::batch"))
        write(self.root, "batch/vec_env.cc", unit("tavis::batch", ["batch/vec_env.h", "batch/perturb/target_move.h"]))
        write(self.root, "batch/perturb/CMakeLists.txt", "add_library(tavis_perturb STATIC target_move.cc)\n")
        write(self.root, "batch/perturb/target_move.h", unit("tavis::batch::perturb"))
        write(self.root, "batch/perturb/target_move.cc", unit("tavis::batch::perturb", ["batch/perturb/target_move.h"]))

    def tearDown(self):
        self.tmp.cleanup()

    def check(self):
        result = subprocess.run([sys.executable, str(CHECK), str(self.root)], capture_output=True, text=True)
        return result.returncode, result.stdout

    def test_a_tree_that_keeps_the_rules_passes(self):
        code, out = self.check()
        self.assertEqual(code, 0, out)
        self.assertIn("check_layout: 0 problem(s)", out)

    def test_a_loose_unit_in_the_batch_root_fails_saying_where_it_goes(self):
        # Compiled by the runtime's target and in its namespace: only the root rule can catch it.
        write(self.root, "batch/CMakeLists.txt", "add_library(tavis_batch STATIC vec_env.cc new_axis.cc)\n")
        write(self.root, "batch/new_axis.h", unit("tavis::batch"))
        write(self.root, "batch/new_axis.cc", unit("tavis::batch", ["batch/new_axis.h"]))
        code, out = self.check()
        self.assertEqual(code, 1, out)
        for path in ("batch/new_axis.h", "batch/new_axis.cc"):
            self.assertIn(f"{path}: the batch/ root holds only the runtime", out)
        self.assertIn("folder, target and namespace of its own under batch/", out)
        self.assertIn("check_layout: 2 problem(s)", out)

    def test_the_runtime_may_include_no_subfolder_above_it(self):
        write(self.root, "batch/vec_env.cc", unit("tavis::batch", ["batch/vec_env.h", "batch/cell/cell_plan.h"]))
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("batch/vec_env.cc:2: the runtime in batch/ may not include batch/cell/cell_plan.h", out)

    def test_a_folder_below_the_runtime_includes_nothing_of_batch_but_its_own(self):
        write(self.root, "batch/perturb/target_move.cc",
              unit("tavis::batch::perturb", ["batch/perturb/target_move.h", "batch/vec_env.h"]))
        code, out = self.check()
        self.assertEqual(code, 1, out)
        self.assertIn("batch/perturb/target_move.cc:2: batch/perturb/ is below the runtime", out)
        self.assertIn("not batch/vec_env.h", out)


if __name__ == "__main__":
    unittest.main()
