"""LeRobot's EnvHub entry point and the rollout loop lerobot-eval runs against it."""

import numpy as np
import pytest

from tavis import env as envhub


def test_make_env_builds_the_configured_vector_env():
    env = envhub.make_env(n_envs=2, use_async_envs=True,
                          cfg={"task": "occluded-reach", "image_size": (24, 24), "seed": 3, "threads": 1})["tavis"][0]
    observation, _ = env.reset(seed=[0, 1])
    assert env.num_envs == 2 and env.seed == 3
    assert observation["pixels"]["OBS_HEAD"].shape == (2, 24, 24, 3)
    assert len(env.call("task_description")) == 2
    # lerobot-eval's loop: 2-D actions, success from final_info, done latched.
    done = np.zeros(2, dtype=bool)
    for _ in range(3):
        observation, rewards, terminated, truncated, infos = env.step(env.neutral_actions().astype(np.float32))
        done |= terminated | truncated
        assert infos["final_info"]["is_success"].shape == (2,)
    assert rewards.dtype == np.float32


def test_make_env_rejects_unknown_options():
    with pytest.raises(KeyError, match="no_such_option"):
        envhub.make_env(n_envs=1, use_async_envs=False, cfg={"no_such_option": 1})
