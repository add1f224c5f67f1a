"""TAVIS-C++ in Python: the batched simulator as a Gymnasium-style VectorEnv (docs/python.md)."""

import inspect

from . import _tavis
from .vector_env import PIXEL_KEYS, BuiltinPolicy, TavisVectorEnv

__all__ = ["make_vec", "TavisVectorEnv", "BuiltinPolicy", "PIXEL_KEYS", "camera_names", "known_tasks",
           "builtin_policy_names", "ACTION_SIZE", "MAX_ENVS", "MAX_EPISODE"]

ACTION_SIZE = _tavis.ACTION_SIZE
MAX_ENVS = _tavis.MAX_ENVS
MAX_EPISODE = _tavis.MAX_EPISODE  # the largest episode index a reset may start


def make_vec(task, **options):
    """N envs of `task` on `robot` (see TavisVectorEnv, whose keyword arguments it takes). camera:
    the protocol, "head" or "fixed" (under "fixed" the head camera is replaced by the fixed one and
    neck actions are zeroed); cameras: the images observed ([] for none); image_size: (height,
    width); threads: 0 = all cores (results do not depend on it); control_ticks_per_step: 60 Hz
    ticks an action is held for, 0 = 3 (20 Hz, the policy rate; the scripted expert acts every
    tick: 1); copy: observations are copies (False: read-only views overwritten by the next step);
    render_mode: None or "rgb_array" (render() tiles the cameras); perturbations: "AXIS:LEVEL"
    levels, one per axis (docs/perturbations.md), every episode run under them."""
    return TavisVectorEnv(task, **options)


make_vec.__signature__ = inspect.signature(TavisVectorEnv)


def camera_names():
    return list(_tavis.camera_names())


def known_tasks():
    return [name.strip() for name in _tavis.known_tasks().split(",")]


def builtin_policy_names():
    return [name.strip() for name in _tavis.builtin_policy_names().split(",")]
