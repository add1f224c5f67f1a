"""make_vec(..., perturbations=[...]): the env's scene under perturbation levels, as `tavis eval
--perturb` runs a cell's (the scene is planned by the same C++ function)."""

import numpy as np
import pytest

from conftest import make_small


def test_the_scene_runs_under_the_levels_given_and_each_episode_keeps_its_layout():
    base = make_small(num_envs=1, cameras=["head"])
    dim = make_small(num_envs=1, cameras=["head"], perturbations=["lighting:dim"])
    assert dim.perturbations == ["lighting:dim"]
    base_observation, _ = base.reset(seed=0)
    dim_observation, _ = dim.reset(seed=0)
    # Dimmer light, the same robot pose and the same prompt: a view level changes the images only.
    assert dim_observation["pixels"]["OBS_HEAD"].mean() < base_observation["pixels"]["OBS_HEAD"].mean()
    np.testing.assert_array_equal(dim_observation["agent_pos"], base_observation["agent_pos"])
    assert dim_observation["task"] == base_observation["task"]


def test_an_unknown_level_is_refused_naming_it():
    with pytest.raises(ValueError, match="no level 'pitch-black'"):
        make_small(num_envs=1, cameras=[], perturbations=["lighting:pitch-black"])
    with pytest.raises(TypeError, match="perturbations must be a list of str"):
        make_small(num_envs=1, cameras=[], perturbations="lighting:dim")
