"""LeRobot EnvHub entry point: ``make_env(n_envs, use_async_envs, cfg=None)`` returns
``{"tavis": {i: VectorEnv}}``, one TAVIS VectorEnv per task of ``cfg.task`` (a name, a
comma-separated list or a list), the form LeRobot's ``make_env`` normalises every hub result to
(docs/lerobot.md). ``cfg`` is a dict (an unknown key is a KeyError) or an object such as LeRobot's
``EnvConfig``, whose attributes named as make_vec's options override them (task, robot, split,
seed, camera, cameras, image_size, threads, autoreset, perturbations, render_mode); an attribute
that is None, and any other attribute (fps, features, hub_path, ...), leaves the default.

Defaults for LeRobot: ``render_mode="rgb_array"`` (lerobot-eval films episodes through
``env.call("render")``) and ``autoreset=False``: lerobot-eval's rollout latches each env's done and
discards everything after it, so an ended env should cost nothing (what LeRobot's own
FreezeAfterEpisodeEnd does); ``autoreset=True`` gives Gymnasium's SAME_STEP instead.

``use_async_envs`` is accepted and ignored: the envs are already stepped in parallel by C++
threads in this process; a Python subprocess per env would only add copies.
"""

import inspect

import tavis

SUITE = "tavis"
# The options a cfg may override, with make_vec's defaults (TavisVectorEnv's signature declares them).
_OPTIONS = ("robot", "split", "seed", "camera", "cameras", "image_size", "threads", "autoreset", "perturbations",
            "render_mode")
_PARAMETERS = inspect.signature(tavis.TavisVectorEnv).parameters
DEFAULTS = {"task": "clutter-pick-cube", **{name: _PARAMETERS[name].default for name in _OPTIONS},
            "render_mode": "rgb_array", "autoreset": False}


def _options(cfg):
    if cfg is None:
        return {}
    if isinstance(cfg, dict):
        unknown = sorted(key for key in cfg if key not in DEFAULTS)
        if unknown:
            raise KeyError(f"unknown TAVIS env option(s) {unknown} (known: {sorted(DEFAULTS)})")
        return {key: value for key, value in cfg.items() if value is not None}
    return {key: getattr(cfg, key) for key in DEFAULTS if getattr(cfg, key, None) is not None}


def _tasks(task):
    if isinstance(task, str):
        tasks = [name.strip() for name in task.split(",") if name.strip()]
    elif isinstance(task, (list, tuple)):
        tasks = list(task)
    else:
        raise TypeError(f"task must be a name, a comma-separated str or a list of names, got {task!r}")
    if not tasks:
        raise ValueError(f"task names no task: {task!r}")
    return tasks


def make_env(n_envs=1, use_async_envs=False, cfg=None):
    del use_async_envs  # see the module docstring
    options = dict(DEFAULTS)
    options.update(_options(cfg))
    tasks = _tasks(options.pop("task"))
    return {SUITE: {index: tavis.make_vec(task, num_envs=n_envs, **options) for index, task in enumerate(tasks)}}
