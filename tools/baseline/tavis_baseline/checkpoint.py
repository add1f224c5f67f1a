"""A checkpoint folder: config.json (BaselineConfig), stats.json (the normalisation constants the
policy was built with, from the dataset's meta/stats.json), model.pt (the state dict) and
training.json (how it was trained).

A save writes every file to NAME.tmp first and then renames them all, one after another, with
SIGINT and SIGTERM held back in between: an interrupted save leaves the previous checkpoint
whole (its files are replaced only once every new one is complete), and Ctrl-C cannot land
between two renames. The .tmp files are created afresh (an existing one, even a link, is
removed first), so a save never writes through a link into another file."""

import json
import os
import signal
from contextlib import contextmanager
from pathlib import Path

import torch

from .config import BaselineConfig
from .policy import BaselinePolicy

FILES = ("config.json", "stats.json", "model.pt", "training.json")
TEMPORARY_SUFFIX = ".tmp"


def temporary_path(path):
    path = Path(path)
    return path.with_name(path.name + TEMPORARY_SUFFIX)


def create_fresh(path, mode="w"):
    """`path` opened for writing as a new file: whatever was there (a leftover, a link) is removed
    first and the file is created exclusively, so nothing outside it is ever written."""
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass
    return os.fdopen(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644), mode)


@contextmanager
def signals_held():
    """SIGINT and SIGTERM wait until the block is done (a no-op where signal masks do not exist)."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def save(policy, folder, extra=None, staged=()):
    """Saves `policy` (and `extra` as training.json) into `folder`. staged: more (temporary, final)
    paths, already complete, renamed together with the checkpoint's files (the trainer's new log
    on its first save)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    stats = {name: getattr(policy, name).cpu().tolist() for name in ("state_mean", "state_std", "action_mean", "action_std")}
    state = {key: value.detach().cpu() for key, value in policy.state_dict().items()}
    renames = []

    def write(name, text=None, tensors=None):
        final = folder / name
        with create_fresh(temporary_path(final), "w" if text is not None else "wb") as file:
            if text is not None:
                file.write(text)
            else:
                torch.save(tensors, file)
        renames.append((temporary_path(final), final))

    write("config.json", policy.config.to_json())
    write("stats.json", json.dumps(stats) + "\n")
    write("model.pt", tensors=state)
    if extra is not None:
        write("training.json", json.dumps(extra, indent=2) + "\n")
    with signals_held():
        for temporary, final in list(renames) + list(staged):
            os.replace(temporary, final)


def load(folder, device="cpu", notes=None):
    """The policy saved in `folder`, in eval mode on `device`. notes: a list that gets a line for each
    setting the checkpoint predates (it gets the documented default)."""
    folder = Path(folder)
    for name in ("config.json", "stats.json", "model.pt"):
        if not (folder / name).is_file():
            raise ValueError(f"{folder} is not a tavis_baseline checkpoint: {name} is missing")
    config = BaselineConfig.from_json((folder / "config.json").read_text(), where=folder / "config.json", notes=notes)
    stats = json.loads((folder / "stats.json").read_text())
    policy = BaselinePolicy(config, stats["state_mean"], stats["state_std"], stats["action_mean"], stats["action_std"])
    policy.load_state_dict(torch.load(folder / "model.pt", map_location="cpu"))
    return policy.to(device).eval()
