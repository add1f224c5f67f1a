"""TAVIS-C++ in Python: the batched simulator as a Gymnasium-style VectorEnv (docs/python.md)."""

from . import _tavis
from .vector_env import PIXEL_KEYS, BuiltinPolicy, TavisVectorEnv

__all__ = ["make_vec", "TavisVectorEnv", "BuiltinPolicy", "PIXEL_KEYS", "camera_names", "known_tasks",
           "builtin_policy_names", "ACTION_SIZE", "MAX_ENVS", "MAX_EPISODE"]

ACTION_SIZE = _tavis.ACTION_SIZE
MAX_ENVS = _tavis.MAX_ENVS
MAX_EPISODE = _tavis.MAX_EPISODE  # the largest episode index a reset may start


def make_vec(task, robot="gr1t2", split="id", num_envs=1, seed=0, camera="head",
             cameras=("head", "left_wrist", "right_wrist"), image_size=(224, 224), threads=0,
             control_ticks_per_step=0, autoreset=True, config_dir=None, copy=True, render_mode=None):
    """N envs of `task` on `robot` (see TavisVectorEnv). camera: the protocol, "head" or "fixed"
    (under "fixed" the head camera is replaced by the fixed one and neck actions are zeroed);
    cameras: the images observed ([] for none); image_size: (height, width); threads: 0 = all
    cores (results do not depend on it); control_ticks_per_step: 60 Hz ticks an action is held
    for, 0 = 3 (20 Hz, the policy rate; the scripted expert acts every tick: 1); copy: observations
    are copies (False: read-only views overwritten by the next step); render_mode: None or
    "rgb_array" (render() tiles the cameras)."""
    return TavisVectorEnv(task, robot=robot, split=split, num_envs=num_envs, seed=seed, camera=camera,
                          cameras=cameras, image_size=image_size, threads=threads,
                          control_ticks_per_step=control_ticks_per_step, autoreset=autoreset, config_dir=config_dir,
                          copy=copy, render_mode=render_mode)


def camera_names():
    return list(_tavis.camera_names())


def known_tasks():
    return [name.strip() for name in _tavis.known_tasks().split(",")]


def builtin_policy_names():
    return [name.strip() for name in _tavis.builtin_policy_names().split(",")]
