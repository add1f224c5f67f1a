"""The baseline policy's configuration, saved with every checkpoint as config.json."""

import dataclasses
import json
from dataclasses import dataclass, field
from typing import List

IMAGE_PREFIX = "observation.images."
# observation.state entries of the neck, zeroed under the fixed-camera protocol (docs/observation.md),
# by the state's size: GR1T2 has 34 entries, Reachy2 19.
NECK_STATE_DIMS = {34: [11, 16, 21], 19: [14, 15, 16]}
NECK_ACTION_DIMS = [14, 15, 16]


@dataclass
class BaselineConfig:
    camera: str = "head"              # "head": OBS_HEAD + wrists; "fixed": OBS_FIXED + wrists
    image_size: List[int] = field(default_factory=lambda: [96, 96])  # (height, width) the CNN sees
    state_dim: int = 34
    action_dim: int = 19
    # Observation history: the network sees `history_frames` frames, `history_stride` frames apart
    # (the newest is the current one): with 2 frames 0.5 s apart it can tell a pause that has just
    # begun from one that is ending, which one frame cannot (docs/baselines.md, "Why history").
    history_frames: int = 2
    history_stride: int = 10
    chunk_size: int = 20              # actions predicted per observation
    n_action_steps: int = 10          # of which this many are executed (select_action's queue)
    # The row of the first target action relative to the observation's row: 1, because a dataset
    # row holds the observation *after* its action (frame t = o_{t+1} with a_t).
    action_offset: int = 1
    cnn_widths: List[int] = field(default_factory=lambda: [32, 64, 96, 128])
    feature_dim: int = 128
    hidden_dim: int = 512
    shift_px: int = 4                 # random-shift augmentation (training only)
    min_std: float = 1e-2
    neck_state_dims: List[int] = field(default_factory=list)   # zeroed under fixed
    neck_action_dims: List[int] = field(default_factory=lambda: list(NECK_ACTION_DIMS))

    def __post_init__(self):
        if self.camera not in ("head", "fixed"):
            raise ValueError(f"camera must be 'head' or 'fixed', got {self.camera!r}")
        if self.history_frames < 1 or self.history_stride < 1:
            raise ValueError(f"history_frames ({self.history_frames}) and history_stride ({self.history_stride}) must be >= 1")
        if not 1 <= self.n_action_steps <= self.chunk_size:
            raise ValueError(f"n_action_steps {self.n_action_steps} must be in 1..chunk_size ({self.chunk_size})")
        if len(self.image_size) != 2 or min(self.image_size) < 16:
            raise ValueError(f"image_size {self.image_size} must be (height, width), each >= 16")
        if self.camera == "fixed" and not self.neck_state_dims:
            if self.state_dim not in NECK_STATE_DIMS:
                raise ValueError(f"fixed camera: no known neck entries for a state of {self.state_dim} dims; "
                                 f"known sizes {sorted(NECK_STATE_DIMS)}")
            self.neck_state_dims = list(NECK_STATE_DIMS[self.state_dim])

    @property
    def image_keys(self):
        first = "OBS_HEAD" if self.camera == "head" else "OBS_FIXED"
        return [IMAGE_PREFIX + name for name in (first, "OBS_WRIST_LEFT", "OBS_WRIST_RIGHT")]

    @property
    def n_obs_steps(self):
        """LeRobot's observation history length, in consecutive policy steps: what a server keeps
        per env and stacks into the batch. The network takes every history_stride-th of them."""
        return (self.history_frames - 1) * self.history_stride + 1

    @property
    def history_positions(self):
        """Which of the n_obs_steps stacked observations (oldest first) the network sees."""
        return [i * self.history_stride for i in range(self.history_frames)]

    @property
    def obs_offsets(self):
        """Frame offsets of the frames the network sees, oldest first (LeRobot delta_timestamps * fps)."""
        return [position - (self.n_obs_steps - 1) for position in self.history_positions]

    @property
    def action_offsets(self):
        return [self.action_offset + i for i in range(self.chunk_size)]

    def to_json(self):
        return json.dumps(dataclasses.asdict(self), indent=2) + "\n"

    @classmethod
    def from_json(cls, text):
        values = json.loads(text)
        known = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(values) - known)
        if unknown:
            raise ValueError(f"config.json has unknown fields {unknown}")
        return cls(**values)
