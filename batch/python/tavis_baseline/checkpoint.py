"""A checkpoint folder: config.json (BaselineConfig), stats.json (the normalisation constants the
policy was built with, from the dataset's meta/stats.json) and model.pt (the state dict). Each
file is written to FILE.tmp and renamed, so an interrupted save leaves the previous one whole."""

import json
import os
from pathlib import Path

import torch

from .config import BaselineConfig
from .policy import BaselinePolicy


def _write_atomically(path, write):
    temporary = path.with_name(path.name + ".tmp")
    write(temporary)
    os.replace(temporary, path)


def save(policy, folder, extra=None):
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    stats = {name: getattr(policy, name).cpu().tolist() for name in ("state_mean", "state_std", "action_mean", "action_std")}
    _write_atomically(folder / "config.json", lambda p: p.write_text(policy.config.to_json()))
    _write_atomically(folder / "stats.json", lambda p: p.write_text(json.dumps(stats) + "\n"))
    state = {key: value.detach().cpu() for key, value in policy.state_dict().items()}
    _write_atomically(folder / "model.pt", lambda p: torch.save(state, p))
    if extra is not None:
        _write_atomically(folder / "training.json", lambda p: p.write_text(json.dumps(extra, indent=2) + "\n"))


def load(folder, device="cpu"):
    """The policy saved in `folder`, in eval mode on `device`."""
    folder = Path(folder)
    for name in ("config.json", "stats.json", "model.pt"):
        if not (folder / name).is_file():
            raise ValueError(f"{folder} is not a tavis_baseline checkpoint: {name} is missing")
    config = BaselineConfig.from_json((folder / "config.json").read_text())
    stats = json.loads((folder / "stats.json").read_text())
    policy = BaselinePolicy(config, stats["state_mean"], stats["state_std"], stats["action_mean"], stats["action_std"])
    policy.load_state_dict(torch.load(folder / "model.pt", map_location="cpu"))
    return policy.to(device).eval()
