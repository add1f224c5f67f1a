"""LeRobot EnvHub entry point: ``make_env(n_envs, use_async_envs, cfg=None)`` returns a TAVIS
VectorEnv, so ``lerobot-eval`` can load it with ``trust_remote_code=True`` without changes to
LeRobot (docs/python.md). ``cfg`` is a dict or an object whose attributes override make_vec's
arguments (task, robot, split, seed, camera, cameras, image_size, threads, autoreset,
perturbations).

``use_async_envs`` is accepted and ignored: the envs are already stepped in parallel by C++
threads in this process; a Python subprocess per env would only add copies.
"""

import inspect

import tavis

# The options a cfg may override, with make_vec's defaults (TavisVectorEnv's signature declares them).
_OPTIONS = ("robot", "split", "seed", "camera", "cameras", "image_size", "threads", "autoreset", "perturbations")
_PARAMETERS = inspect.signature(tavis.TavisVectorEnv).parameters
DEFAULTS = {"task": "clutter-pick-cube", **{name: _PARAMETERS[name].default for name in _OPTIONS}}


def _options(cfg):
    if cfg is None:
        return {}
    items = cfg.items() if isinstance(cfg, dict) else vars(cfg).items()
    options = {key: value for key, value in items if key in DEFAULTS}
    unknown = sorted(key for key, _ in (cfg.items() if isinstance(cfg, dict) else []) if key not in DEFAULTS)
    if unknown:
        raise KeyError(f"unknown TAVIS env option(s) {unknown} (known: {sorted(DEFAULTS)})")
    return options


def make_env(n_envs=1, use_async_envs=False, cfg=None):
    del use_async_envs  # see the module docstring
    options = dict(DEFAULTS)
    options.update(_options(cfg))
    return tavis.make_vec(num_envs=n_envs, **options)
