"""Fixtures of the baseline's tests: one small dataset made by `tavis demos` (tiny_training.py: 4
episodes of clutter-pick-cube on GR1T2 at 96x72 and 20 fps), shared by the whole session, and a way
to run the tavis program. ctest passes TAVIS_CLI (the program) and TAVIS_JS_DIR (the npm Parquet
readers)."""

import pytest

# The tests import the recording's settings and run_tavis from here.
from tiny_training import CONTROL_HZ, FPS, HEIGHT, SEED, WIDTH, record_demos, run_tavis  # noqa: F401


@pytest.fixture(scope="session")
def demo_dataset(tmp_path_factory):
    return record_demos(tmp_path_factory.mktemp("demos") / "dataset")
