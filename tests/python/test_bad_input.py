"""Bad input raises ValueError or KeyError naming the bad value; the env stays usable."""

import numpy as np
import pytest

import tavis
from conftest import TASK, hold_actions, make_small


@pytest.fixture
def env():
    env = make_small(num_envs=2, cameras=[], control_ticks_per_step=3)
    env.reset(seed=0)
    return env


@pytest.mark.parametrize("actions, message", [
    (np.zeros((2, 18)), r"shape \(2, 19\), got \(2, 18\)"),
    (np.zeros((3, 19)), r"shape \(2, 19\), got \(3, 19\)"),
    (np.zeros(38), r"shape \(2, 19\), got \(38\)"),
    (np.zeros((2, 19), dtype=np.int64), "dtype float32 or float64, got int64"),
    (np.zeros((2, 19), dtype=np.float16), "dtype float32 or float64, got float16"),
    ([[0.0] * 19] * 2, "numpy array"),
])
def test_wrong_actions_raise_value_error(env, actions, message):
    with pytest.raises(ValueError, match=message):
        env.step(actions)
    env.step(hold_actions(env))  # still usable


@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_non_finite_action_raises_value_error_before_anything_moves(env, value):
    before = env._core.agent_pos().copy()
    actions = hold_actions(env)
    actions[1, 7] = value
    with pytest.raises(ValueError, match="env 1, entry 7 is not finite"):
        env.step(actions.astype(np.float32))
    np.testing.assert_array_equal(env._core.agent_pos(), before)
    _, _, terminated, _, _ = env.step(hold_actions(env))
    assert not terminated.any()


@pytest.mark.parametrize("option, value, message", [
    ("task", "no-such-task", "unknown task 'no-such-task'"),
    ("robot", "no-such-robot", "no-such-robot"),
    ("camera", "sideways", "sideways"),
    ("cameras", ["head", "tail"], "unknown camera 'tail'"),
    ("split", "ood-everything", "unknown split 'ood-everything'"),
])
def test_unknown_names_raise_key_error(option, value, message):
    options = {"task": TASK, "num_envs": 1, "cameras": []}
    options[option] = value
    with pytest.raises(KeyError, match=message):
        tavis.make_vec(**options)


def test_unknown_policy_raises_key_error(env):
    with pytest.raises(KeyError, match="no-such-policy"):
        env.make_policy("no-such-policy")


@pytest.mark.parametrize("options, message", [
    ({"num_envs": 0}, "num_envs must be an int from 1 to 4096, got 0"),
    ({"num_envs": 4097}, "num_envs must be an int from 1 to 4096, got 4097"),
    ({"num_envs": 10**6}, "num_envs must be an int from 1 to 4096, got 1000000"),
    ({"render_mode": "human"}, "render_mode must be one of .*'human'"),
    ({"render_mode": "rgb_array"}, "at least one camera"),
    ({"image_size": (0, 10)}, "0"),
    ({"control_ticks_per_step": 1, "cameras": ["head"]}, "multiple of 3"),
])
def test_bad_values_raise_value_error(options, message):
    settings = {"task": TASK, "num_envs": 1, "cameras": []}
    settings.update(options)
    with pytest.raises(ValueError, match=message):
        tavis.make_vec(**settings)


def test_bad_reset_arguments_raise_value_error(env):
    with pytest.raises(ValueError, match="reset_mask must be a bool array of shape"):
        env.reset(options={"reset_mask": np.array([1, 0])})
    with pytest.raises(ValueError, match="selects no env"):
        env.reset(options={"reset_mask": np.array([False, False])})
    with pytest.raises(ValueError, match=r"seed\[1\] must be an episode index from 0 to \d+ \(or None: the next one\), got -4"):
        env.reset(seed=[0, -4])
    with pytest.raises(ValueError, match="2 ints, got 3"):
        env.reset(seed=[0, 1, 2])


def test_step_before_reset_and_policy_at_another_rate_raise_value_error():
    env = make_small(num_envs=1, cameras=[])
    with pytest.raises(ValueError, match="reset"):
        env.step(np.zeros((1, 19)))
    with pytest.raises(ValueError, match="neutral actions before reset"):
        env.neutral_actions()
    with pytest.raises(ValueError, match="control_ticks_per_step=1"):
        env.make_policy("expert")


def test_writing_episodes_not_ended_raises_value_error(env, tmp_path):
    with pytest.raises(ValueError, match="episode 0 has not ended"):
        env.write_results(tmp_path / "out", "hold", 4)


def test_a_policy_of_another_env_raises_value_error(env):
    other = make_small(num_envs=5, cameras=[], control_ticks_per_step=3)
    policy = other.make_policy("hold")
    with pytest.raises(ValueError, match="another env"):
        env._core.act(policy._policy)


# A wrong type is one line naming the argument. Before: pybind11's "incompatible constructor
# arguments. The following argument types are supported: 1. tavis._tavis.VecEnvCore(task: str, ..."
@pytest.mark.parametrize("options, message", [
    ({"num_envs": "4"}, "num_envs must be an int, got str '4'"),
    ({"num_envs": 2.5}, "num_envs must be an int, got float 2.5"),
    ({"seed": "x"}, "seed must be an int, got str 'x'"),
    ({"task": 5}, "task must be a str, got int 5"),
    ({"robot": None}, "robot must be a str, got NoneType None"),
    ({"threads": "a"}, "threads must be an int, got str 'a'"),
    ({"control_ticks_per_step": 1.5}, "control_ticks_per_step must be an int, got float 1.5"),
    ({"cameras": [1, 2]}, "cameras must be a list of str, got an item int 1"),
    ({"image_size": ("a", 2), "cameras": ["head"]}, r"image_size\[0\] must be an int, got str 'a'"),
    ({"config_dir": 5}, r"config_dir must be a path \(str or os.PathLike\), got int 5"),
])
def test_wrong_types_raise_one_line_type_error_naming_the_argument(options, message):
    settings = {"task": TASK, "num_envs": 1, "cameras": []}
    settings.update(options)
    with pytest.raises(TypeError, match="^" + message + "$") as error:
        tavis.make_vec(**settings)
    assert "\n" not in str(error.value)


def test_negative_seed_raises_value_error():
    with pytest.raises(ValueError, match="seed must be an int from 0 to 18446744073709551615, got -1"):
        tavis.make_vec(task=TASK, num_envs=1, cameras=[], seed=-1)


def test_wrong_types_in_methods_raise_one_line_type_error(env, tmp_path):
    for call, message in [
        (lambda: env.make_policy(5), "name must be a str, got int 5"),
        (lambda: env.make_policy("replay", 5), r"actions_file must be a path \(str or os.PathLike\), got int 5"),
        (lambda: env.write_results(tmp_path / "out", 5, 1), "policy must be a str, got int 5"),
        (lambda: env.write_results(tmp_path / "out", "hold", "1"), "episodes must be an int, got str '1'"),
        (lambda: env.reset(seed=1.5), "seed must be None, an int or a list of 2 ints, got float 1.5"),
    ]:
        with pytest.raises(TypeError, match="^" + message + "$") as error:
            call()
        assert "\n" not in str(error.value)
    assert not (tmp_path / "out").exists()
    env.step(hold_actions(env))  # still usable


# A number beyond what the C++ side takes is named with the range allowed, in one line. Before:
# pybind11's "reset(): incompatible function arguments. The following argument types are
# supported: 1. (self: tavis._tavis.VecEnvCore, mask: List[int], episodes: List[int]) ...".
@pytest.mark.parametrize("call, error, message", [
    (lambda env, out: env.reset(seed=2**70), ValueError,
     rf"seed must be an episode index from 0 to {tavis.MAX_EPISODE - 1} \(reset\(seed=s\) starts episodes s \.\. s\+1\), "
     rf"got {2**70}"),
    (lambda env, out: env.reset(seed=tavis.MAX_EPISODE), ValueError, f"got {tavis.MAX_EPISODE}$"),
    (lambda env, out: env.reset(seed=-1), ValueError, "seed must be an episode index from 0 to .*, got -1$"),
    (lambda env, out: env.reset(seed=[2**70, None]), ValueError,
     rf"seed\[0\] must be an episode index from 0 to {tavis.MAX_EPISODE} \(or None: the next one\), got {2**70}"),
    (lambda env, out: env.reset(seed=[0, 1.5]), TypeError,
     r"seed\[1\] must be an episode index \(an int\) or None \(the next one\), got float 1.5"),
    (lambda env, out: env.reset(seed=[0, True]), TypeError, r"seed\[1\] must be an episode index .*, got bool True"),
    (lambda env, out: env.reset(seed=True), TypeError, "seed must be None, an int or a list of 2 ints, got bool True"),
    (lambda env, out: env.reset(options="reset_mask"), TypeError, "options must be None or a dict, got str 'reset_mask'"),
    (lambda env, out: env.write_results(out, "hold", 1, first_episode=2**70), ValueError,
     rf"first_episode must be an int from 0 to {tavis.MAX_EPISODE}, got {2**70}"),
    (lambda env, out: env.write_results(out, "hold", 2**70), ValueError,
     rf"episodes must be an int from 1 to 100000000, got {2**70}"),
    (lambda env, out: env.write_results(out, "hold", 0), ValueError, "episodes must be an int from 1 to 100000000, got 0"),
])
def test_out_of_range_arguments_name_the_value_and_the_range(env, tmp_path, call, error, message):
    with pytest.raises(error, match=message) as raised:
        call(env, tmp_path / "out")
    assert "\n" not in str(raised.value) and "incompatible" not in str(raised.value)
    assert not (tmp_path / "out").exists()
    env.step(hold_actions(env))  # still usable


@pytest.mark.parametrize("options, message", [
    ({"num_envs": 2**70}, f"num_envs must be an int from 1 to 4096, got {2**70}"),
    ({"threads": 2**40}, f"threads must be an int from 0 to 2147483647, got {2**40}"),
    ({"threads": -1}, "threads must be an int from 0 to 2147483647, got -1"),
    ({"control_ticks_per_step": 2**40}, f"control_ticks_per_step must be an int from 0 to 2147483647, got {2**40}"),
    ({"image_size": (2**40, 8), "cameras": ["head"]}, rf"image_size\[0\] must be an int from 1 to 2147483647, got {2**40}"),
    ({"seed": 2**64}, f"seed must be an int from 0 to {2**64 - 1}, got {2**64}"),
])
def test_out_of_range_settings_name_the_value_and_the_range(options, message):
    settings = {"task": TASK, "num_envs": 1, "cameras": []}
    settings.update(options)
    with pytest.raises(ValueError, match="^" + message + "$"):
        tavis.make_vec(**settings)


def test_the_largest_episode_index_runs(env):
    env.reset(seed=tavis.MAX_EPISODE - 1)
    assert list(env._core.episodes()) == [tavis.MAX_EPISODE - 1, tavis.MAX_EPISODE]
    env.step(hold_actions(env))
