"""The README's Python examples, taken from README.md and run as written: they must work and the
expert must succeed (the README once stepped all-zero actions: every episode ended at step 0).
And its quick start's route to a served cell of one's own policy (issue 47): `my_policy.py`, the
serve command and the eval after it, run as written from a folder laid out as a fresh clone."""

import json
import os
import pathlib
import re
import shlex
import subprocess
import sys

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
README = REPOSITORY / "README.md"


def readme_section(title):
    text = README.read_text()
    section = text[text.index(f"\n## {title}\n"):]
    return section[:section.index("\n## ", 1)]


def readme_python_examples():
    return re.findall(r"```python\n(.*?)```", readme_section("Python"), flags=re.S)


def quick_start_route():
    """The quick start's policy file and its serve and eval commands, as the README writes them."""
    section = readme_section("Quick start")
    policies = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    serve = [line.strip() for line in section.split("\n") if " -m tavis_server " in line]
    evaluate = [line.strip() for line in section.split("\n") if "tavis eval" in line and "--policy openpi" in line]
    assert len(policies) == 1 and len(serve) == 1 and len(evaluate) == 1, section
    return policies[0], serve[0], evaluate[0]


def fresh_clone(root):
    """A folder laid out as a fresh clone: the tracked top-level entries (linked) and this build."""
    tracked = subprocess.check_output(["git", "ls-files"], cwd=REPOSITORY, text=True).split("\n")
    for name in sorted({path.split("/")[0] for path in tracked if path}):
        (root / name).symlink_to(REPOSITORY / name)
    (root / "build").symlink_to(os.environ["TAVIS_BUILD_DIR"])


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


def test_the_quick_start_serves_and_evaluates_my_policy(tmp_path):
    policy, serve, evaluate = quick_start_route()
    clone = tmp_path / "clone"
    clone.mkdir()
    fresh_clone(clone)
    (clone / "my_policy.py").write_text(policy)  # "save this as my_policy.py in the checkout"
    # As written, but on a port of its own (--port 0: the server prints the one it took) and in the
    # foreground of a process this test stops.
    assert serve.endswith(" &") and " --port 8000" in serve, serve
    environment = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    server = subprocess.Popen(["bash", "-c", "exec env " + serve[:-2].replace(" --port 8000", " --port 0")], cwd=clone,
                              env=environment, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = server.stdout.readline()
        listening = re.fullmatch(r"tavis_server: serving \S+ on (ws://\S+)\n", line)
        assert listening, line + server.stderr.read()
        assert "ws://127.0.0.1:8000" in evaluate, evaluate
        command = evaluate.replace("ws://127.0.0.1:8000", listening[1])
        result = subprocess.run(["bash", "-c", command], cwd=clone, env=environment, capture_output=True, text=True,
                                timeout=600)
        assert result.returncode == 0, result.stdout + result.stderr
    finally:
        server.terminate()
        server.wait(timeout=30)
    words = shlex.split(evaluate)
    out = clone / words[words.index("--out") + 1]
    summary = json.loads((out / "summary.json").read_text())
    records = [json.loads(line) for line in (out / "episodes.jsonl").read_text().splitlines()]
    assert summary["n_episodes"] == int(words[words.index("--episodes") + 1]) == len(records)
    assert summary["policy"] == "openpi" and summary["requests"]["count"] > 0
    # The policy's action is a valid one: its episodes run to the time limit, none is refused.
    assert [record["end"] for record in records] == ["time_out"] * len(records), records
