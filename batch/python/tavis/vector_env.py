"""The batched TAVIS env as a Gymnasium-style VectorEnv (docs/python.md).

Observations use LeRobot's raw keys: ``pixels`` = {OBS_HEAD | OBS_FIXED, OBS_WRIST_LEFT,
OBS_WRIST_RIGHT: (N, H, W, 3) uint8}, ``agent_pos`` = (N, D) float32 (observation.state) and
``task`` = the prompt per env. The arrays are copies, as Gymnasium's vector envs return by default;
with ``copy=False`` they are read-only views of the simulator's buffers, overwritten by the next
``step``/``reset`` (copy them to keep them).

Episodes: episode i of a cell has the randomness of (seed, i), whichever env runs it. A reset
seed chooses episode indices, as Gymnasium's per-sub-env seeds: ``reset(seed=s)`` starts episodes
s .. s+N-1, a list gives one per env, None continues with the next episodes not dealt yet; the
cell seed is ``make_vec(seed=...)``. With ``autoreset=True`` (Gymnasium's SAME_STEP) an env whose
episode ends starts the next episode in the same step, the ended one's observation.state going
and images to ``infos["final_obs"]``; with ``autoreset=False`` (DISABLED) it stays ended, its actions are
ignored, until ``reset(options={"reset_mask": ...})``.
"""

import json
import math

import numpy as np

from . import _arguments, _tavis, spaces
from ._config_dir import default_config_dir

try:  # Gymnasium is optional: subclass its VectorEnv when it is there.
    import gymnasium
    from gymnasium.vector import VectorEnv as _VectorEnvBase

    try:
        from gymnasium.vector import AutoresetMode as _AutoresetMode
    except ImportError:  # Gymnasium < 1.1 has no AutoresetMode
        _AutoresetMode = None
except ImportError:
    gymnasium = None
    _VectorEnvBase = object
    _AutoresetMode = None

# Camera name -> LeRobot's raw pixel key (TAVIS checkpoints' observation.images.<key>).
PIXEL_KEYS = {
    "head": "OBS_HEAD",
    "fixed": "OBS_FIXED",
    "left_wrist": "OBS_WRIST_LEFT",
    "right_wrist": "OBS_WRIST_RIGHT",
}


def _is_int(value):
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def _autoreset_mode(autoreset):
    name = "SAME_STEP" if autoreset else "DISABLED"
    return getattr(_AutoresetMode, name) if _AutoresetMode is not None else name.lower()


class BuiltinPolicy:
    """A policy built into the simulator ("expert", "hold", "replay") acting on one env.

    ``policy()`` returns the actions of every env for the current state, (N, 19) float64 (rows of
    envs not running are zero); it is reset with the env's episodes.
    """

    def __init__(self, env, core_policy):
        self._env = env
        self._policy = core_policy

    @property
    def name(self):
        return self._policy.name

    @property
    def control_ticks_per_action(self):
        return self._policy.control_ticks_per_action

    def __call__(self, observation=None):
        return self._env._core.act(self._policy)


class TavisVectorEnv(_VectorEnvBase):
    """N envs of one task stepped together in C++; see the module docstring."""

    # The keyword arguments are declared here alone: make_vec takes this signature and the EnvHub
    # entry point (env.py) its defaults; the C++ core reads each by name.
    def __init__(self, task, robot="gr1t2", split="id", num_envs=1, seed=0, camera="head",
                 cameras=("head", "left_wrist", "right_wrist"), image_size=(224, 224), threads=0,
                 control_ticks_per_step=0, autoreset=True, config_dir=None, copy=True, render_mode=None,
                 perturbations=()):
        if isinstance(cameras, str):
            raise ValueError(f"cameras must be a list of camera names, got the string {cameras!r}")
        task, robot, split, camera = (_arguments.require_str(name, value) for name, value in
                                      (("task", task), ("robot", robot), ("split", split), ("camera", camera)))
        num_envs = _arguments.require_int("num_envs", num_envs, 1, _tavis.MAX_ENVS)
        seed = _arguments.require_int("seed", seed, 0, _arguments.MAX_SEED)
        threads = _arguments.require_int("threads", threads, 0, _arguments.MAX_C_INT)
        control_ticks_per_step = _arguments.require_int("control_ticks_per_step", control_ticks_per_step, 0,
                                                        _arguments.MAX_C_INT)
        cameras = _arguments.require_str_list("cameras", cameras)
        perturbations = _arguments.require_str_list("perturbations", perturbations)
        if config_dir is not None:
            config_dir = _arguments.require_path("config_dir", config_dir)
        if not isinstance(image_size, (list, tuple, np.ndarray)) or len(tuple(image_size)) != 2:
            raise ValueError(f"image_size must be (height, width), got {image_size!r}")
        image_size = tuple(_arguments.require_int(f"image_size[{i}]", v, 1, _arguments.MAX_C_INT)
                           for i, v in enumerate(image_size))
        if render_mode not in self.RENDER_MODES:
            raise ValueError(f"render_mode must be one of {self.RENDER_MODES}, got {render_mode!r}")
        if render_mode == "rgb_array" and len(cameras) == 0:
            raise ValueError("render_mode 'rgb_array' tiles the cameras' images: give at least one camera")
        self._core = _tavis.VecEnvCore(
            task=task, robot=robot, split=split, num_envs=num_envs, seed=seed, camera=camera,
            cameras=list(cameras), image_size=tuple(int(v) for v in image_size), threads=threads,
            control_ticks_per_step=control_ticks_per_step, autoreset=bool(autoreset),
            config_dir=config_dir if config_dir is not None else default_config_dir(), perturbations=perturbations)
        self.num_envs = num_envs
        self.task = task
        self.seed = seed
        self.perturbations = perturbations
        self.autoreset = bool(autoreset)
        self.image_size = tuple(image_size)
        self.camera_names = list(self._core.camera_names)
        self.control_ticks_per_step = self._core.control_ticks_per_step
        self._max_episode_steps = self._core.max_episode_steps
        self.copy = bool(copy)
        self.render_mode = render_mode
        self.metadata = {
            "render_modes": [mode for mode in self.RENDER_MODES if mode is not None],
            "render_fps": 60 // self.control_ticks_per_step,
            "autoreset_mode": _autoreset_mode(autoreset),
        }
        self._define_spaces()

    RENDER_MODES = (None, "rgb_array")

    def _define_spaces(self):
        """Gymnasium's spaces when it is installed, else tavis.spaces' stand-ins. The prompts
        (``obs["task"]``) are text and have no space."""
        height, width = self.image_size
        pixels = {PIXEL_KEYS[name]: spaces.box(0, 255, (height, width, 3), np.uint8) for name in self.camera_names}
        single = {"agent_pos": spaces.box(-np.inf, np.inf, (self._core.state_size,), np.float32)}
        if pixels:
            single["pixels"] = spaces.dict_space(pixels)
        self.single_observation_space = spaces.dict_space(single)
        self.single_action_space = spaces.box(-np.inf, np.inf, (_tavis.ACTION_SIZE,), np.float64)
        self.observation_space = spaces.batch_space(self.single_observation_space, self.num_envs)
        self.action_space = spaces.batch_space(self.single_action_space, self.num_envs)

    # Gymnasium's API

    def reset(self, *, seed=None, options=None):
        if options is not None and not isinstance(options, dict):
            raise TypeError(f"options must be None or a dict, got {type(options).__name__} {options!r}")
        mask = np.ones(self.num_envs, dtype=bool)
        if options and options.get("reset_mask") is not None:
            mask = np.asarray(options["reset_mask"])
            if mask.dtype != np.bool_ or mask.shape != (self.num_envs,):
                raise ValueError(f"reset_mask must be a bool array of shape ({self.num_envs},), "
                                 f"got {mask.dtype} {mask.shape}")
        self._core.reset(mask.astype(np.uint8).tolist(), self._episode_indices(seed))
        return self._observation(), self._infos()

    def step(self, actions):
        self._core.step(actions)
        return (self._observation(), self._core.rewards(), self._core.terminated(), self._core.truncated(),
                self._infos())

    def call(self, name, *args, **kwargs):
        if name in ("task_description", "task"):
            return tuple(self._core.prompts())
        if name == "_max_episode_steps":
            return (self._max_episode_steps,) * self.num_envs
        if name == "render":  # one frame per env, as Gymnasium's vector envs call render() on each
            return tuple(self._env_frames())
        value = getattr(self, name)
        return value(*args, **kwargs) if callable(value) else (value,) * self.num_envs

    def get_attr(self, name):
        return self.call(name)

    def render(self):
        """With render_mode "rgb_array": the current images of every env as one (rows*H, cols*C*W, 3)
        uint8 image, each env's cameras side by side (in camera_names order), the envs in a grid
        of cols = ceil(sqrt(N)) columns, row by row (unused tiles black)."""
        envs = self._env_frames()  # (N, H, C*W, 3)
        columns = math.ceil(math.sqrt(self.num_envs))
        rows = math.ceil(self.num_envs / columns)
        tiles = np.zeros((rows * columns, *envs.shape[1:]), dtype=np.uint8)
        tiles[:self.num_envs] = envs
        height, width = envs.shape[1:3]
        return tiles.reshape(rows, columns, height, width, 3).swapaxes(1, 2).reshape(rows * height, columns * width, 3)

    def _env_frames(self):
        """Each env's cameras side by side (camera_names order): (N, H, C*W, 3) uint8."""
        if self.render_mode is None:
            raise ValueError("render() needs an env made with render_mode='rgb_array'")
        pixels = self._core.pixels()
        return np.concatenate([pixels[name] for name in self.camera_names], axis=2)

    @property
    def unwrapped(self):
        """The env itself (Gymnasium's VectorEnv.unwrapped; lerobot-eval reads unwrapped.metadata)."""
        return self

    def close(self, **kwargs):
        """Nothing to release early: the buffers live as long as the env or a view of them."""

    # TAVIS's additions

    def make_policy(self, name, actions_file=""):
        """A built-in policy acting on this env (tavis.builtin_policy_names())."""
        name = _arguments.require_str("name", name)
        actions_file = _arguments.require_path("actions_file", actions_file)
        return BuiltinPolicy(self, self._core.make_policy(name, actions_file))

    def neutral_actions(self):
        """A valid action for every env to step with, (N, 19) float64: the built-in hold policy's
        (each arm at its pose when the episode started, head still, grippers open). Rows of envs
        not running are zero (they are ignored). Works at any control_ticks_per_step."""
        return self._core.neutral_actions()

    def episode_records(self):
        """The ended episodes' records, as `tavis eval` writes them in episodes.jsonl."""
        return [json.loads(line) for line in self._core.episode_json_lines()]

    def write_results(self, out_dir, policy, episodes, first_episode=0, overwrite=False):
        """Writes episodes first_episode .. +episodes-1 as `tavis eval` does: OUT/episodes.jsonl and
        OUT/summary.json. ``policy`` names what acted (the summary's "policy"). As `tavis eval`'s
        folder: ValueError naming OUT while another process (a running `tavis eval`) writes it, or
        when it already holds results, unless ``overwrite`` (which replaces only a cell tavis
        wrote, the old one kept until the new one is in place)."""
        out_dir = _arguments.require_path("out_dir", out_dir)
        policy = _arguments.require_str("policy", policy)
        episodes = _arguments.require_int("episodes", episodes, 1, _tavis.MAX_CELL_EPISODES)
        first_episode = _arguments.require_int("first_episode", first_episode, 0, _tavis.MAX_EPISODE)
        overwrite = _arguments.require_bool("overwrite", overwrite)
        self._core.write_results(out_dir, policy, first_episode, episodes, overwrite)

    # Helpers

    def _episode_indices(self, seed):
        """The episode each env starts (-1: the next one not dealt yet); every index within
        0 .. MAX_EPISODE, checked here so that a bad one is named rather than refused by pybind11."""
        if seed is None:
            return [-1] * self.num_envs
        if _is_int(seed):
            last_first = _tavis.MAX_EPISODE - (self.num_envs - 1)
            if not 0 <= seed <= last_first:
                raise ValueError(f"seed must be an episode index from 0 to {last_first} (reset(seed=s) starts "
                                 f"episodes s .. s+{self.num_envs - 1}), got {int(seed)}")
            return [int(seed) + i for i in range(self.num_envs)]
        if not isinstance(seed, (list, tuple, np.ndarray)):
            raise TypeError(f"seed must be None, an int or a list of {self.num_envs} ints, "
                            f"got {type(seed).__name__} {seed!r}")
        seeds = list(seed)
        if len(seeds) != self.num_envs:
            raise ValueError(f"seed must be an int or {self.num_envs} ints, got {len(seeds)} values")
        for env, s in enumerate(seeds):
            if s is None:
                continue
            if not _is_int(s):
                raise TypeError(f"seed[{env}] must be an episode index (an int) or None (the next one), "
                                f"got {type(s).__name__} {s!r}")
            if not 0 <= s <= _tavis.MAX_EPISODE:
                raise ValueError(f"seed[{env}] must be an episode index from 0 to {_tavis.MAX_EPISODE} "
                                 f"(or None: the next one), got {int(s)}")
        return [-1 if s is None else int(s) for s in seeds]

    def _observation(self):
        pixels = self._core.pixels()
        agent_pos = self._core.agent_pos()
        if self.copy:
            pixels = {name: np.array(view) for name, view in pixels.items()}
            agent_pos = np.array(agent_pos)
        return {
            "pixels": {PIXEL_KEYS[name]: image for name, image in pixels.items()},
            "agent_pos": agent_pos,
            "task": self._core.prompts(),
        }

    def _infos(self):
        ended = self._core.ended()
        ends = np.array(self._core.ended_how(), dtype=object)
        success = ended & (ends == "success")
        final_info = {
            "is_success": success, "_is_success": ended,
            "episode": self._core.ended_episodes(), "_episode": ended,
            "end": np.where(ended, ends, None), "_end": ended,
        }
        infos = {
            "episode": self._core.episodes(), "_episode": np.ones(self.num_envs, dtype=bool),
            "is_success": success, "_is_success": ended,
            "final_info": final_info, "_final_info": ended,
        }
        if self.autoreset:
            final_state = self._core.final_agent_pos()
            final_pixels = self._core.final_pixels() if ended.any() else {}
            final_obs = np.empty(self.num_envs, dtype=object)
            for env in np.flatnonzero(ended):
                final_obs[env] = {"agent_pos": final_state[env]}
                if final_pixels:
                    final_obs[env]["pixels"] = {PIXEL_KEYS[name]: np.array(view[env]) for name, view in final_pixels.items()}
            infos["final_obs"] = final_obs
            infos["_final_obs"] = ended
        return infos
