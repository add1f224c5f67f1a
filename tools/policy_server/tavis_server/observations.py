"""The two request forms of serving protocol v1 (per-env and batched), split into one
EnvObservation per env so that everything downstream handles both alike.

Each observation carries the connection it came on: env slots are numbered per client (every
`tavis eval` cell, and every cell of a sweep running side by side, counts its envs from 0), so
per-episode state is keyed by the slot (connection, env_index), never by env_index alone."""

import dataclasses

import numpy as np

ID_KEYS = ("env_index", "episode_index", "step", "is_first")
TEXT_KEYS = ("prompt", "task")


@dataclasses.dataclass
class EnvObservation:
    env_index: int
    episode_index: int
    step: int
    is_first: bool
    task: str  # the request's "task", else its "prompt", else ""
    arrays: dict  # every other key: ndarray of this env alone (images H x W x 3 uint8, state (D,))
    text: dict = dataclasses.field(default_factory=dict)  # "prompt"/"task" as sent
    connection: int = 0  # the server's number of the connection the request came on

    @property
    def slot(self):
        """The key of this env's per-episode state: (connection, env_index)."""
        return (self.connection, self.env_index)


def _integer(value, key, where):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{where}: {key} must be an integer, got {value!r}")
    return int(value)


def _flag(value, key, where):
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{where}: {key} must be a bool, got {value!r}")
    return bool(value)


def _one(request, where, connection):
    missing = [key for key in ID_KEYS if key not in request]
    if missing:
        raise ValueError(f"{where}: missing {', '.join(missing)} (serving protocol v1 needs {', '.join(ID_KEYS)})")
    text = {key: request[key] for key in TEXT_KEYS if key in request}
    for key, value in text.items():
        if not isinstance(value, str):
            raise ValueError(f"{where}: {key} must be a str, got {type(value).__name__}")
    arrays = {}
    for key, value in request.items():
        if key in ID_KEYS or key in TEXT_KEYS:
            continue
        if not isinstance(value, np.ndarray):
            raise ValueError(f"{where}: {key} must be an array, got {type(value).__name__}")
        arrays[key] = value
    return EnvObservation(env_index=_integer(request["env_index"], "env_index", where),
                          episode_index=_integer(request["episode_index"], "episode_index", where),
                          step=_integer(request["step"], "step", where),
                          is_first=_flag(request["is_first"], "is_first", where),
                          task=text.get("task", text.get("prompt", "")), arrays=arrays, text=text,
                          connection=connection)


def split_request(request, connection=0):
    """Returns (observations, batched): a per-env request gives one observation, a batched one
    (it carries "batch_size") one per env in the request's order, each marked with `connection`.
    Raises ValueError naming the key when the request breaks the protocol."""
    if not isinstance(request, dict):
        raise ValueError(f"a request must be a map, got {type(request).__name__}")
    if "batch_size" not in request:
        return [_one(request, "request", connection)], False
    size = request["batch_size"]
    size = _integer(size, "batch_size", "batched request")
    if size < 1:
        raise ValueError(f"batched request: batch_size {size} must be at least 1")
    columns = {}
    for key, value in request.items():
        if key == "batch_size":
            continue
        if key in TEXT_KEYS:
            if not isinstance(value, list) or len(value) != size:
                raise ValueError(f"batched request: {key} must be a list of batch_size={size} str")
        elif not isinstance(value, np.ndarray) or value.ndim < 1 or value.shape[0] != size:
            shape = value.shape if isinstance(value, np.ndarray) else type(value).__name__
            raise ValueError(f"batched request: {key} must be an array of leading length batch_size={size}, got {shape}")
        columns[key] = value
    observations = []
    for row in range(size):
        single = {}
        for key, value in columns.items():
            item = value[row]
            single[key] = item.item() if key in ID_KEYS and isinstance(item, np.generic) else item
        observations.append(_one(single, f"batched request row {row}", connection))
    envs = [observation.env_index for observation in observations]
    if len(set(envs)) != len(envs):
        raise ValueError(f"batched request: env_index {envs} names an env twice")
    return observations, True
