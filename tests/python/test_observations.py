"""Observations: LeRobot's raw keys, copies by default or zero-copy views; determinism; reset_mask;
autoreset's final observations."""

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


def test_observations_are_copies_by_default(small_env):
    observation, _ = small_env.reset(seed=0)
    for array in [*observation["pixels"].values(), observation["agent_pos"]]:
        assert array.flags.owndata and array.flags.writeable and array.flags.c_contiguous
    # A replay buffer that keeps the observations as returned holds every state.
    actions = hold_actions(small_env)
    buffer = []
    for step in range(30):
        actions[:, 0] += 0.004  # the left hand moves on: every step is a new state
        observation, *_ = small_env.step(actions)
        buffer.append(observation)
    states = {row.tobytes() for row in (obs["agent_pos"][0] for obs in buffer)}
    images = {obs["pixels"]["OBS_WRIST_LEFT"][0].tobytes() for obs in buffer}
    assert len(states) == 30 and len(images) > 1
    np.testing.assert_array_equal(buffer[-1]["agent_pos"], small_env._core.agent_pos())
    np.testing.assert_array_equal(buffer[-1]["pixels"]["OBS_HEAD"], small_env._core.pixels()["head"])


def test_views_are_shared_when_asked_for():
    env = make_small(copy=False)
    env.reset(seed=0)
    actions = hold_actions(env)
    buffer = []
    for step in range(30):
        actions[:, 0] += 0.004
        observation, *_ = env.step(actions)
        buffer.append(observation)
    # Every entry is the same buffer, showing the latest step.
    assert len({obs["agent_pos"][0].tobytes() for obs in buffer}) == 1
    assert len({address(obs["agent_pos"]) for obs in buffer}) == 1


def test_views_do_not_copy_and_stay_at_one_address():
    small_env = make_small(copy=False)
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
    observation, _ = make_small(copy=False).reset(seed=0)
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
    assert set(infos["final_obs"][1]["pixels"]) == {"OBS_HEAD", "OBS_WRIST_LEFT", "OBS_WRIST_RIGHT"}
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


def test_final_observation_has_the_ended_episodes_images():
    env = make_small(cameras=["fixed", "left_wrist"])
    before, _ = env.reset(seed=0)
    actions = hold_actions(env)
    actions[1, 0] = 100.0  # env 1's action is refused before anything moves: its final state is its last
    observation, _, terminated, _, infos = env.step(actions)
    assert terminated.tolist() == [False, True, False]
    final = infos["final_obs"][1]
    np.testing.assert_array_equal(final["agent_pos"], before["agent_pos"][1])
    for key in ("OBS_FIXED", "OBS_WRIST_LEFT"):
        assert final["pixels"][key].shape == (*SMALL_IMAGES, 3) and final["pixels"][key].dtype == np.uint8
        np.testing.assert_array_equal(final["pixels"][key], before["pixels"][key][1], err_msg=key)
    # The observation itself is the next episode's (another layout in the fixed camera).
    assert not np.array_equal(observation["pixels"]["OBS_FIXED"][1], before["pixels"]["OBS_FIXED"][1])
    assert infos["final_obs"][0] is None and infos["final_obs"][2] is None


def test_render_tiles_every_env_s_cameras():
    env = make_small(num_envs=5, cameras=["fixed", "left_wrist"], render_mode="rgb_array")
    observation, _ = env.reset(seed=0)
    frame = env.render()
    height, width = SMALL_IMAGES
    # 5 envs: a 2 x 3 grid of tiles, each the env's two cameras side by side; the sixth is black.
    assert frame.shape == (2 * height, 3 * 2 * width, 3) and frame.dtype == np.uint8
    for env_index in range(5):
        row, column = divmod(env_index, 3)
        tile = frame[row * height:(row + 1) * height, column * 2 * width:(column + 1) * 2 * width]
        np.testing.assert_array_equal(tile[:, :width], observation["pixels"]["OBS_FIXED"][env_index])
        np.testing.assert_array_equal(tile[:, width:], observation["pixels"]["OBS_WRIST_LEFT"][env_index])
    assert not frame[height:, 2 * 2 * width:].any()
    observation, *_ = env.step(env.neutral_actions())
    np.testing.assert_array_equal(env.render()[:height, :width], observation["pixels"]["OBS_FIXED"][0])
    assert env.metadata["render_modes"] == ["rgb_array"]
