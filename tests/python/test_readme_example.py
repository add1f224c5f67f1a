"""The README's Python examples, taken from README.md and run as written: they must work and the
expert must succeed (the README once stepped all-zero actions: every episode ended at step 0)."""

import os
import pathlib
import re
import subprocess
import sys

README = pathlib.Path(__file__).resolve().parents[2] / "README.md"


def readme_python_examples():
    text = README.read_text()
    section = text[text.index("\n## Python\n"):]
    section = section[:section.index("\n## ", 1)]
    return re.findall(r"```python\n(.*?)```", section, flags=re.S)


def run(code, cwd):
    # The examples run in a folder of their own: PYTHONPATH must not depend on this one.
    environment = dict(os.environ)
    paths = environment.get("PYTHONPATH", "").split(os.pathsep)
    environment["PYTHONPATH"] = os.pathsep.join(os.path.abspath(path) for path in paths if path)
    result = subprocess.run([sys.executable, "-c", code], cwd=cwd, env=environment, capture_output=True, text=True,
                            timeout=240)
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_the_readme_has_both_examples():
    assert len(readme_python_examples()) == 2


def test_the_expert_example_succeeds(tmp_path):
    output = run(readme_python_examples()[0], tmp_path)
    match = re.fullmatch(r"(\d+) successes in (\d+) episodes\n", output)
    assert match, output
    successes, episodes = int(match[1]), int(match[2])
    assert episodes >= 16 and successes > 0


def test_the_images_example_renders(tmp_path):
    output = run(readme_python_examples()[1], tmp_path)
    assert output.splitlines()[-1] == "render (448, 1344, 3)"
    assert "OBS_HEAD" in output and "(19,)" in output
