"""A stand-in for LeRobot (which cannot be installed here) checking tavis/env.py against the contract
LeRobot documents and lerobot-eval relies on (docs/lerobot.md lists what this covers and what not):

- EnvHub: `make_env(n_envs=, use_async_envs=)` and `make_env(..., cfg=EnvConfig)` return
  `{suite: {task_id: VectorEnv}}`;
- lerobot-eval's rollout: `reset(seed=[...], options={"lerobot_new_rollout": True})`,
  `call("_max_episode_steps")[0]`, `call("task_description")` / `call("task")` (one str per env),
  `preprocess_observation`'s raw keys (`pixels` {camera: (N, H, W, 3) uint8, channel last},
  `agent_pos` (N, D) float32), `step` of (N, action_dim) float32 actions returning reward (N,) and
  bool terminated/truncated (N,), success in `info["final_info"]["is_success"]`, done latched;
- video: `np.stack(env.call("render")[:n])` and `env.unwrapped.metadata["render_fps"]`;
- the spaces hold what reset and step return; autoreset off (ended envs stay ended) and on
  (SAME_STEP: `final_obs`); `close()`.
Every task, under both camera protocols."""

import dataclasses

import numpy as np
import pytest

import tavis
from tavis import env as envhub

NEW_ROLLOUT_OPTION = "lerobot_new_rollout"  # lerobot.envs.utils: rollout()'s reset option
SIZE = (16, 16)


@dataclasses.dataclass
class EnvConfigStandIn:
    """The fields every LeRobot EnvConfig has (task None by default), plus a hub config's hub_path and
    TAVIS's own options as a registered config would declare them."""
    task: object = None
    fps: int = 30
    features: dict = dataclasses.field(default_factory=dict)
    features_map: dict = dataclasses.field(default_factory=dict)
    max_parallel_tasks: int = 1
    disable_env_checker: bool = True
    hub_path: str = "org/tavis@0123abc:batch/python/tavis/env.py"
    camera: str = "head"
    image_size: tuple = SIZE
    threads: int = 1
    perturbations: tuple = ()


def normalized(result):
    """LeRobot's _normalize_hub_result: a dict is taken as {suite: {task_id: env}}."""
    assert isinstance(result, dict) and len(result) == 1
    (suite, envs), = result.items()
    assert isinstance(suite, str) and all(isinstance(i, int) for i in envs)
    return envs


def preprocess(observation):
    """What lerobot.envs.utils.preprocess_observation asserts of the raw keys."""
    images = {}
    for key, image in observation["pixels"].items():
        assert image.ndim == 4 and image.dtype == np.uint8
        _, h, w, c = image.shape
        assert c < h and c < w, "channel last"
        images[f"observation.images.{key}"] = image.astype(np.float32).transpose(0, 3, 1, 2) / 255
    state = observation["agent_pos"].astype(np.float32)
    assert state.ndim == 2
    return images, state


def rollout(env, seeds, end_env_at=None):
    """lerobot-eval's loop, capped at a few steps; env 0 gets an invalid action at step end_env_at."""
    observation, info = env.reset(seed=seeds, options={NEW_ROLLOUT_OPTION: True})
    max_steps = env.call("_max_episode_steps")[0]
    assert isinstance(max_steps, int) and max_steps > 0
    tasks = list(env.call("task_description"))
    assert len(tasks) == env.num_envs and all(isinstance(t, str) and t for t in tasks)
    assert list(env.call("task")) == tasks
    done = np.zeros(env.num_envs, dtype=bool)
    ended_at = {}
    for step in range(4):
        images, state = preprocess(observation)
        assert env.single_observation_space["agent_pos"].shape == state.shape[1:]
        assert {k: dict(observation)[k] for k in ("pixels", "agent_pos")} in env.observation_space
        actions = env.neutral_actions().astype(np.float32)
        if step == end_env_at:
            actions[0] = 0.0  # the zero quaternion: invalid_action ends env 0's episode
        observation, reward, terminated, truncated, info = env.step(actions)
        assert reward.shape == (env.num_envs,) and terminated.dtype == np.bool_ and truncated.dtype == np.bool_
        success = info["final_info"]["is_success"]
        assert success.shape == (env.num_envs,) and success.dtype == np.bool_
        for i in np.flatnonzero(terminated | truncated):
            ended_at.setdefault(int(i), []).append(step)
        done |= terminated | truncated
        frames = np.stack(env.call("render")[:env.num_envs])
        assert frames.shape[0] == env.num_envs and frames.dtype == np.uint8 and frames.shape[-1] == 3
    assert isinstance(env.unwrapped.metadata["render_fps"], int)
    return done, ended_at, info


@pytest.mark.parametrize("camera", ["head", "fixed"])
def test_every_task_meets_the_contract(camera):
    tasks = tavis.known_tasks()
    cfg = EnvConfigStandIn(task=",".join(tasks), camera=camera)
    envs = normalized(envhub.make_env(n_envs=2, use_async_envs=True, cfg=cfg))
    assert sorted(envs) == list(range(len(tasks)))
    for index, env in envs.items():
        assert env.task == tasks[index] and env.num_envs == 2 and env.autoreset is False
        wanted = {"OBS_HEAD" if camera == "head" else "OBS_FIXED", "OBS_WRIST_LEFT", "OBS_WRIST_RIGHT"}
        assert set(env.single_observation_space["pixels"].keys()) == wanted
        done, ended_at, _ = rollout(env, [0, 1], end_env_at=1)
        # Autoreset off: env 0 ends once and stays ended while lerobot-eval steps the batch on.
        assert done[0] and ended_at[0] == [1], f"{tasks[index]}: env 0 ended at {ended_at}"
        env.close()


def test_without_cfg_the_hub_call_gives_the_default_task():
    envs = normalized(envhub.make_env(n_envs=1, use_async_envs=False))
    assert envs[0].task == envhub.DEFAULTS["task"] and envs[0].render_mode == "rgb_array"


def test_autoreset_on_starts_the_next_episode_in_the_same_step():
    envs = normalized(envhub.make_env(n_envs=2, cfg={"image_size": SIZE, "threads": 1, "autoreset": True}))
    _, ended_at, info = rollout(envs[0], [0, 1], end_env_at=3)
    assert ended_at[0] == [3] and info["_final_obs"][0] and "agent_pos" in info["final_obs"][0]


def test_a_config_object_leaves_unset_and_foreign_fields_alone():
    cfg = EnvConfigStandIn(camera="fixed")  # task None, fps and features are LeRobot's, not ours
    env = normalized(envhub.make_env(n_envs=1, cfg=cfg))[0]
    assert env.task == envhub.DEFAULTS["task"] and "OBS_FIXED" in env.single_observation_space["pixels"].keys()


def test_unknown_dict_options_and_empty_tasks_are_refused():
    with pytest.raises(KeyError, match="no_such_option"):
        envhub.make_env(cfg={"no_such_option": 1})
    with pytest.raises(ValueError, match="names no task"):
        envhub.make_env(cfg={"task": " , "})
