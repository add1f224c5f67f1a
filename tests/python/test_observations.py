"""Observations: zero-copy views with LeRobot's raw keys; determinism; reset_mask."""

import numpy as np

import tavis
from conftest import ALL_CAMERAS, SMALL_IMAGES, assert_same, hold_actions, make_small, snapshot


def address(array):
    return array.__array_interface__["data"][0]


def test_observation_keys_shapes_and_dtypes(small_env):
    observation, infos = small_env.reset(seed=0)
    assert set(observation["pixels"]) == {"OBS_HEAD", "OBS_WRIST_LEFT", "OBS_WRIST_RIGHT"}
    for view in observation["pixels"].values():
        assert view.shape == (3, *SMALL_IMAGES, 3) and view.dtype == np.uint8
        assert view.any(), "a rendered image is not all black"
    assert observation["agent_pos"].shape == (3, small_env._core.state_size)
    assert observation["agent_pos"].dtype == np.float32
    assert observation["task"] == ["Find the red cube and pick it up."] * 3
    assert list(infos["episode"]) == [0, 1, 2]
    assert small_env.call("task_description") == tuple(observation["task"])
    assert small_env.call("_max_episode_steps") == (400,) * 3


def test_fixed_protocol_observes_the_fixed_camera():
    env = make_small(camera="fixed", cameras=["head"])
    observation, _ = env.reset(seed=0)
    assert list(observation["pixels"]) == ["OBS_FIXED"]


def test_views_do_not_copy_and_stay_at_one_address(small_env):
    observation, _ = small_env.reset(seed=0)
    views = [*observation["pixels"].values(), observation["agent_pos"]]
    addresses = [address(view) for view in views]
    before = snapshot(observation)
    for view in views:
        assert not view.flags.owndata
        assert not view.flags.writeable
        assert view.base is not None
    # Images of one env are one block per env: the views of the cameras interleave in it.
    head, left = observation["pixels"]["OBS_HEAD"], observation["pixels"]["OBS_WRIST_LEFT"]
    assert address(left) - address(head) == head[0].nbytes
    observation, *_ = small_env.step(hold_actions(small_env))
    after = [*observation["pixels"].values(), observation["agent_pos"]]
    assert [address(view) for view in after] == addresses
    # The old views show the new step (valid until the next step, as documented).
    np.testing.assert_array_equal(views[0], after[0])
    assert not np.array_equal(before["OBS_HEAD"], after[0]) or not np.array_equal(before["agent_pos"], after[-1])


def test_views_keep_the_env_alive():
    observation, _ = make_small().reset(seed=0)
    head = observation["pixels"]["OBS_HEAD"]
    expected = head.copy()
    del observation
    import gc
    gc.collect()
    np.testing.assert_array_equal(head, expected)


def rollout(env, steps, seed=0):
    observation, _ = env.reset(seed=seed)
    frames = [snapshot(observation)]
    actions = hold_actions(env)
    actions[:, 0] += 0.05  # move the left hand: the images change
    results = []
    for _ in range(steps):
        observation, rewards, terminated, truncated, infos = env.step(actions)
        frames.append(snapshot(observation))
        results.append((rewards.copy(), terminated.copy(), truncated.copy(), infos["episode"].copy()))
    return frames, results


def test_same_seed_same_observations_and_results():
    frames_a, results_a = rollout(make_small(cameras=ALL_CAMERAS), 6)
    frames_b, results_b = rollout(make_small(cameras=ALL_CAMERAS), 6)
    for a, b in zip(frames_a, frames_b):
        assert_same(a, b)
    for a, b in zip(results_a, results_b):
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y)
    frames_c, _ = rollout(make_small(seed=6, cameras=ALL_CAMERAS), 0)
    # The head starts looking away from the table; the fixed camera sees the layout.
    assert not np.array_equal(frames_a[0]["OBS_FIXED"], frames_c[0]["OBS_FIXED"]), "another seed, another scene"


def test_one_and_two_threads_are_identical():
    frames_1, results_1 = rollout(make_small(threads=1, cameras=ALL_CAMERAS), 6)
    frames_2, results_2 = rollout(make_small(threads=2, cameras=ALL_CAMERAS), 6)
    for a, b in zip(frames_1, frames_2):
        assert_same(a, b)
    for a, b in zip(results_1, results_2):
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y)


def test_reset_mask_resets_only_the_masked_envs(small_env):
    first, _ = small_env.reset(seed=0)
    initial = snapshot(first)
    observation, *_ = small_env.step(hold_actions(small_env) + 0.05)
    moved = snapshot(observation)
    observation, infos = small_env.reset(seed=0, options={"reset_mask": np.array([True, False, False])})
    now = snapshot(observation)
    for key in now:
        np.testing.assert_array_equal(now[key][0], initial[key][0], err_msg=key)
        np.testing.assert_array_equal(now[key][1:], moved[key][1:], err_msg=key)
    assert not np.array_equal(moved["agent_pos"][0], initial["agent_pos"][0])
    assert list(infos["episode"]) == [0, 1, 2]
    # Without a seed the masked env takes the next episode not dealt yet.
    _, infos = small_env.reset(options={"reset_mask": np.array([False, True, False])})
    assert list(infos["episode"]) == [0, 3, 2]


def test_ended_episode_autoresets_in_the_same_step(small_env):
    small_env.reset(seed=0)
    actions = hold_actions(small_env)
    actions[1, 0] = 100.0  # an IK target 100 m away: env 1's episode ends invalid_action
    _, rewards, terminated, truncated, infos = small_env.step(actions)
    assert list(terminated) == [False, True, False] and not truncated.any() and not rewards.any()
    assert infos["_final_info"].tolist() == [False, True, False]
    assert infos["final_info"]["end"][1] == "invalid_action"
    assert infos["final_info"]["episode"][1] == 1 and not infos["is_success"][1]
    assert infos["final_obs"][1]["agent_pos"].shape == (small_env._core.state_size,)
    assert list(infos["episode"]) == [0, 3, 2], "env 1 runs the next episode"
    assert small_env.metadata["autoreset_mode"] in ("same_step", getattr(tavis.vector_env._AutoresetMode, "SAME_STEP", None))


def test_without_autoreset_an_ended_env_waits_for_reset():
    env = make_small(autoreset=False)
    env.reset(seed=0)
    actions = hold_actions(env)
    actions[1, 0] = 100.0
    _, _, terminated, _, infos = env.step(actions)
    assert terminated.tolist() == [False, True, False]
    assert "final_obs" not in infos
    _, _, terminated, _, infos = env.step(hold_actions(env))
    assert not terminated.any(), "an end is reported once"
    assert list(infos["episode"]) == [0, 1, 2]
    _, infos = env.reset(options={"reset_mask": np.array([False, True, False])})
    assert list(infos["episode"]) == [0, 3, 2]
