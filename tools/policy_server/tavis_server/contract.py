"""The contract the server declares in the metadata frame it sends at connect, under the key
``observation_contract`` (docs/serving.md, "The contract a server declares"): what the served policy
was trained on, so that `tavis eval` sends exactly that without ``--image-size`` or
``--match-dataset``.

The policy (or ``--contract FILE.json``) declares what only it knows: ``cameras`` (camera -> the
image key it was trained on), ``image_width`` / ``image_height``, ``state`` (``{"key", "size"}``) and
optionally ``checkpoint_sha256`` and the ``task`` and ``robot`` it was trained for (tavis names: the
client refuses a cell of another task or robot, which would run and only score about 0; only the
names' form is checked here, since the client is the one that knows which exist). The server adds what follows from how it serves: ``n_obs_steps``
(its observation history), ``chunk_length`` (rows per reply, its ``action_horizon``) and
``executed_steps`` (rows of each reply the client executes before asking again: 1 when every step
must be asked, else the whole reply). A declared value of those three that disagrees with how the
server serves is an error at startup, as is any malformed field: the client checks them again,
since for it the frame comes from the network."""

import re

CONTRACT_KEY = "observation_contract"
VERSION = 1
CAMERAS = ("head", "fixed", "left_wrist", "right_wrist")
DECLARED = ("cameras", "image_width", "image_height", "state", "checkpoint_sha256", "task", "robot")
SERVED = ("n_obs_steps", "chunk_length", "executed_steps")
REQUEST_FIELDS = ("env_index", "episode_index", "step", "is_first", "batch_size")
_KEY = re.compile(r"^[\x21-\x7e]{1,256}$")
_SHA256 = re.compile(r"^[0-9a-f]{64}$")
# A tavis task or robot name, as the client checks it (batch/remote/server_contract.cc).
_NAME = re.compile(r"^[a-z0-9][a-z0-9_-]{0,63}$")


def _int(value, field, low, high):
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise ValueError(f"{CONTRACT_KEY}.{field} must be an int from {low} to {high}, got {value!r}")
    return value


def _key(value, field):
    if not isinstance(value, str) or not _KEY.match(value) or value in REQUEST_FIELDS:
        raise ValueError(f"{CONTRACT_KEY}.{field} must be a key of 1 to 256 printable characters other than the "
                         f"request fields {', '.join(REQUEST_FIELDS)}, got {value!r}")
    return value


def _declared_part(declared):
    if not isinstance(declared, dict):
        raise ValueError(f"{CONTRACT_KEY} must be a dict, got {type(declared).__name__}")
    unknown = sorted(set(declared) - set(DECLARED) - set(SERVED) - {"version"})
    if unknown:
        raise ValueError(f"{CONTRACT_KEY} has unknown fields {unknown} (known: version, {', '.join(DECLARED + SERVED)})")
    if declared.get("version", VERSION) != VERSION:
        raise ValueError(f"{CONTRACT_KEY}.version must be {VERSION}, got {declared['version']!r}")
    cameras = declared.get("cameras")
    if not isinstance(cameras, dict) or not cameras:
        raise ValueError(f"{CONTRACT_KEY}.cameras must be a non-empty dict camera -> key, got {cameras!r}")
    for camera, key in cameras.items():
        if camera not in CAMERAS:
            raise ValueError(f"{CONTRACT_KEY}.cameras: unknown camera {camera!r} (known: {', '.join(CAMERAS)})")
        _key(key, f"cameras.{camera}")
    if "fixed" in cameras and "head" not in cameras:
        raise ValueError(f"{CONTRACT_KEY}.cameras has fixed (which replaces head under the fixed protocol) but no head")
    state = declared.get("state")
    if not isinstance(state, dict) or set(state) != {"key", "size"}:
        raise ValueError(f"{CONTRACT_KEY}.state must be {{'key': KEY, 'size': D}}, got {state!r}")
    contract = {"version": VERSION,
                "cameras": {camera: cameras[camera] for camera in CAMERAS if camera in cameras},
                "image_width": _int(declared.get("image_width"), "image_width", 8, 4096),
                "image_height": _int(declared.get("image_height"), "image_height", 8, 4096),
                "state": {"key": _key(state["key"], "state.key"), "size": _int(state["size"], "state.size", 1, 4096)}}
    sent = [key for camera, key in contract["cameras"].items() if camera != "fixed"] + [state["key"], "prompt", "task"]
    if len(set(sent)) != len(sent):
        raise ValueError(f"{CONTRACT_KEY}: two of the request's keys are the same: {sent}")
    if "checkpoint_sha256" in declared:
        sha = declared["checkpoint_sha256"]
        if not isinstance(sha, str) or not _SHA256.match(sha):
            raise ValueError(f"{CONTRACT_KEY}.checkpoint_sha256 must be 64 lower-case hex digits, got {sha!r}")
        contract["checkpoint_sha256"] = sha
    for field in ("task", "robot"):
        if field in declared:
            name = declared[field]
            if not isinstance(name, str) or not _NAME.fullmatch(name):
                raise ValueError(f"{CONTRACT_KEY}.{field} must be a tavis name of 1 to 64 lower-case letters, digits, "
                                 f"'-' or '_' (e.g. conditional-pick, gr1t2), got {name!r}")
            contract[field] = name
    return contract


def complete_contract(declared, chunk_length, n_obs_steps, consecutive_steps):
    """The contract the metadata frame carries: the declared fields checked, and the served ones
    (n_obs_steps, chunk_length, executed_steps) from how the server serves. ValueError naming the
    field for a malformed declaration or a served field declared otherwise."""
    contract = _declared_part(declared)
    served = {"n_obs_steps": int(n_obs_steps), "chunk_length": int(chunk_length),
              "executed_steps": 1 if consecutive_steps else int(chunk_length)}
    for field, value in served.items():
        if field in declared and declared[field] != value:
            raise ValueError(f"{CONTRACT_KEY}.{field} is declared {declared[field]!r}, but the server serves {value} "
                             f"(n_obs_steps: the policy's history; chunk_length: rows per reply; executed_steps: 1 "
                             f"when every step must be asked, else chunk_length)")
    contract.update(served)
    return contract
