"""Observation and action spaces (Gymnasium's, or tavis.spaces' stand-ins without it) and the
env's neutral actions."""

import numpy as np

import tavis
from conftest import SMALL_IMAGES, make_small


def test_spaces_describe_what_the_env_returns():
    env = make_small(num_envs=2, cameras=["head", "right_wrist"])
    observation, _ = env.reset(seed=0)
    state_size = observation["agent_pos"].shape[1]
    single = env.single_observation_space
    assert single["agent_pos"].shape == (state_size,) and single["agent_pos"].dtype == np.float32
    assert set(single["pixels"].keys()) == {"OBS_HEAD", "OBS_WRIST_RIGHT"}
    head = single["pixels"]["OBS_HEAD"]
    assert head.shape == (*SMALL_IMAGES, 3) and head.dtype == np.uint8
    assert head.low.min() == 0 and head.high.max() == 255
    batched = env.observation_space
    assert batched["agent_pos"].shape == (2, state_size)
    assert batched["pixels"]["OBS_HEAD"].shape == (2, *SMALL_IMAGES, 3)
    assert env.single_action_space.shape == (tavis.ACTION_SIZE,) and env.single_action_space.dtype == np.float64
    assert env.action_space.shape == (2, tavis.ACTION_SIZE)

    without_prompts = {key: value for key, value in observation.items() if key != "task"}
    assert batched.contains(without_prompts)
    assert single.contains({"agent_pos": observation["agent_pos"][0],
                            "pixels": {key: image[0] for key, image in observation["pixels"].items()}})
    assert not batched["agent_pos"].contains(observation["agent_pos"][0])
    assert env.action_space.contains(env.neutral_actions())
    assert not env.action_space.contains(np.zeros((3, tavis.ACTION_SIZE)))


def test_samples_lie_in_their_space():
    env = make_small(num_envs=2, cameras=["head"])
    env.observation_space.seed(3)
    sample = env.observation_space.sample()
    assert sample["pixels"]["OBS_HEAD"].shape == (2, *SMALL_IMAGES, 3)
    assert sample["pixels"]["OBS_HEAD"].dtype == np.uint8
    assert env.observation_space.contains(sample)
    assert env.action_space.sample().shape == (2, tavis.ACTION_SIZE)


def test_without_cameras_the_observation_space_has_no_pixels():
    env = make_small(num_envs=1, cameras=[])
    assert set(env.single_observation_space.keys()) == {"agent_pos"}


def test_neutral_actions_hold_the_reset_pose_at_any_rate():
    for ticks in (1, 3):
        env = make_small(num_envs=3, cameras=[], control_ticks_per_step=ticks)
        env.reset(seed=0)
        actions = env.neutral_actions()
        assert actions.shape == (3, tavis.ACTION_SIZE) and actions.dtype == np.float64
        if ticks == 3:
            np.testing.assert_array_equal(actions, env.make_policy("hold")())
        # Valid: a hundred steps of them end no episode (the zero action, an invalid quaternion,
        # ends every episode at once).
        for _ in range(100 // ticks):
            _, _, terminated, truncated, _ = env.step(actions)
            assert not (terminated | truncated).any()
        np.testing.assert_array_equal(env.neutral_actions(), actions)
    _, _, terminated, _, infos = env.step(np.zeros((3, tavis.ACTION_SIZE)))
    assert terminated.all() and set(infos["final_info"]["end"]) == {"invalid_action"}
