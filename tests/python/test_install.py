"""Installing the module: `cmake --install` of the build tree, and `pip install --no-build-isolation .`
into a fresh virtualenv of this Python without network (setup.py driving CMake). Each installed
package is imported from outside the source and build trees and rolled out.

The pip build compiles the libraries again in a folder of its own; with ccache (used when it is
installed, as the main build uses it) those are cache hits, as pip's build is given the build tree's
TAVIS_WERROR: every compile command then equals the build tree's (measured: CI's test build has
-Werror, and without it all 125 of the module's compiles missed the cache, 582 s of ctest)."""

import os
import pathlib
import shutil
import subprocess
import sys
import textwrap

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]

ROLLOUT = textwrap.dedent("""
    import os, sys
    import tavis
    expected = sys.argv[1]
    assert os.path.realpath(tavis.__file__).startswith(os.path.realpath(expected)), (tavis.__file__, expected)
    assert os.path.isfile(os.path.join(os.path.dirname(tavis.__file__), "configs", "robots", "gr1t2.yaml"))
    env = tavis.make_vec("clutter-pick-cube", num_envs=2, cameras=["head"], image_size=(24, 32), threads=1)
    obs, _ = env.reset(seed=0)
    for _ in range(5):
        obs, rewards, terminated, truncated, infos = env.step(env.neutral_actions())
        assert not (terminated | truncated).any()
    assert obs["pixels"]["OBS_HEAD"].shape == (2, 24, 32, 3) and obs["pixels"]["OBS_HEAD"].any()
    print("rollout ok", tavis.__file__)
""")


def clean_environment(**extra):
    """This process's environment without the build tree on PYTHONPATH."""
    environment = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    environment.update(extra)
    return environment


def build_tree_werror():
    """The build tree's TAVIS_WERROR (CMakeCache.txt), "OFF" when it has none."""
    cache = pathlib.Path(os.environ["TAVIS_BUILD_DIR"]) / "CMakeCache.txt"
    for line in cache.read_text().splitlines():
        if line.startswith("TAVIS_WERROR:"):
            return line.split("=", 1)[1]
    return "OFF"


def run(command, **kwargs):
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    assert result.returncode == 0, f"{command}\n{result.stdout[-4000:]}\n{result.stderr[-4000:]}"
    return result.stdout


def test_cmake_install_installs_an_importable_package(tmp_path):
    prefix = tmp_path / "prefix"
    run(["cmake", "--install", os.environ["TAVIS_BUILD_DIR"], "--component", "python", "--prefix", str(prefix)])
    packages = [path.parent for path in prefix.rglob("tavis/__init__.py")]
    assert len(packages) == 1, packages
    site = packages[0].parent
    version = f"python{sys.version_info.major}.{sys.version_info.minor}"
    assert site.relative_to(prefix).parts[:2] == ("lib", version), site
    assert sorted(path.name for path in (packages[0] / "configs" / "robots").iterdir()) == ["gr1t2.yaml", "reachy2.yaml"]
    output = run([sys.executable, "-c", ROLLOUT, str(site)], cwd=tmp_path,
                 env=clean_environment(PYTHONPATH=str(site)))
    assert output.startswith("rollout ok")
    check_installed_tools(sys.executable, site, tmp_path, clean_environment(PYTHONPATH=str(site)))


def check_installed_tools(python, site, cwd, environment):
    """The reference server and baseline are installed beside tavis and run from outside the trees."""
    for package in ("tavis_server", "tavis_baseline"):
        assert (site / package / "__init__.py").is_file(), f"{package} is not installed in {site}"
    assert "--contract" in run([str(python), "-m", "tavis_server", "--help"], cwd=cwd, env=environment)
    assert "checkpoint" in run([str(python), "-m", "tavis_baseline.serve", "--help"], cwd=cwd, env=environment)


def test_pip_installs_into_a_fresh_virtualenv_offline(tmp_path):
    venv = tmp_path / "venv"
    # --system-site-packages: NumPy (and setuptools, wheel) from Debian, nothing downloaded.
    run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)])
    python = venv / "bin" / "python"
    launchers = {}
    if shutil.which("ccache"):
        launchers = {"CMAKE_CXX_COMPILER_LAUNCHER": "ccache", "CMAKE_C_COMPILER_LAUNCHER": "ccache"}
    environment = clean_environment(TAVIS_PIP_BUILD_DIR=str(tmp_path / "pip-build"), PIP_NO_INDEX="1",
                                    PIP_DISABLE_PIP_VERSION_CHECK="1",
                                    CMAKE_BUILD_PARALLEL_LEVEL=os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", "2"),
                                    TAVIS_CMAKE_ARGS=f"-DTAVIS_WERROR={build_tree_werror()}", **launchers)
    run([str(python), "-m", "pip", "install", "--no-build-isolation", "--no-index", str(SOURCE_DIR)],
        cwd=tmp_path, env=environment)
    output = run([str(python), "-c", ROLLOUT, str(venv)], cwd=tmp_path, env=clean_environment())
    assert output.startswith("rollout ok")
    site = next(path.parent for path in venv.rglob("tavis/__init__.py")).parent
    check_installed_tools(python, site, tmp_path, clean_environment())
    assert not (SOURCE_DIR / "tavis.egg-info").exists(), "pip's build wrote into the source tree"
