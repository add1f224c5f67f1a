"""Shared helpers for the tavis module's tests (ctest runs them with the module on PYTHONPATH)."""

import numpy as np
import pytest

import tavis

TASK = "clutter-pick-cube"
ALL_CAMERAS = ("head", "fixed", "left_wrist", "right_wrist")
SMALL_IMAGES = (32, 40)  # (height, width): small renders keep the tests fast


def make_small(**overrides):
    options = dict(num_envs=3, seed=5, cameras=("head", "left_wrist", "right_wrist"), image_size=SMALL_IMAGES,
                   threads=1)
    options.update(overrides)
    return tavis.make_vec(TASK, **options)


def hold_actions(env):
    """The hold policy's actions for the current state, a plausible constant to step with."""
    return env.make_policy("hold")()


def snapshot(observation):
    """A copy of an observation's arrays (the env's views are overwritten by the next step)."""
    return {"agent_pos": observation["agent_pos"].copy(),
            **{key: view.copy() for key, view in observation["pixels"].items()}}


def assert_same(a, b):
    assert a.keys() == b.keys()
    for key in a:
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)


@pytest.fixture
def small_env():
    return make_small()
