"""The baseline policy's configuration, saved with every checkpoint as config.json."""

import dataclasses
import json
from dataclasses import dataclass, field
from typing import List, Optional

from .temporal_ensemble import check_coefficient

IMAGE_PREFIX = "observation.images."
# observation.state entries of the neck, zeroed under the fixed-camera protocol (docs/observation.md),
# by the state's size: GR1T2 has 34 entries, Reachy2 19.
NECK_STATE_DIMS = {34: [11, 16, 21], 19: [14, 15, 16]}
NECK_ACTION_DIMS = [14, 15, 16]
EXECUTED_STEPS_DEFAULT = 10
HEADS = ("l1", "flow", "act")
VISIONS = ("cnn", "resnet18")
# The ACT head's sizes (act_head.py), each train's --act-... option: small defaults for 96x96 images
# and 200-2,000 demonstrations (ACT's own are d_model 512, feedforward 3200, for 480x640 and 50).
ACT_OPTIONS = {"act_d_model": "transformer width", "act_heads": "attention heads",
               "act_encoder_layers": "layers of the observation encoder", "act_decoder_layers": "decoder layers",
               "act_vae_layers": "layers of the CVAE's encoder (training only)",
               "act_feedforward": "feed-forward width of every layer", "act_dropout": "dropout of every layer",
               "act_latent_dim": "dims of the latent z", "act_kl_weight": "weight of the KL term of the loss"}
EXECUTION_DEFAULT_WHY = (
    "measured (docs/baselines.md, 'Chunk execution'): each checkpoint served both ways on the same "
    "96 scenes, a queue of 10 rows beat re-planning every step at 8,000 training steps on conditional-pick "
    "(22 : 0 paired, exact McNemar p = 5e-07) and wait-then-act (12 : 6), and at the recipe's 1,800 steps "
    "(conditional-pick id 18.1 % against 3.8 %, three seeds); re-planning won only on one 30,000-step "
    "wait-then-act checkpoint (24 : 6, p = 0.0014)")


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
    # Rows of each predicted chunk executed per forward pass when served (EXECUTION_DEFAULT_WHY):
    # k > 1 runs k rows open loop from tavis_server's action queue; 1 re-plans at every policy step.
    # LeRobot's name for it is n_action_steps (the property below).
    executed_steps: int = EXECUTED_STEPS_DEFAULT
    # The row of the first target action relative to the observation's row: 1, because a dataset
    # row holds the observation *after* its action (frame t = o_{t+1} with a_t).
    action_offset: int = 1
    # The action head: "l1" (an MLP regressing the chunk with L1, the control) or "flow" (flow
    # matching over the chunk, flow_head.py), sampled in flow_steps Euler steps when served, its
    # noise derived from (noise_seed, the request's episode and step) so that served records repeat
    # run to run (policy.serving_noise).
    head: str = "l1"
    flow_steps: int = 10
    flow_width: int = 256
    noise_seed: int = 0
    # The ACT head ("act", act_head.py): a CVAE transformer, served at z = 0 (deterministic).
    act_d_model: int = 256
    act_heads: int = 8
    act_encoder_layers: int = 4
    act_decoder_layers: int = 1
    act_vae_layers: int = 4
    act_feedforward: int = 1024
    act_dropout: float = 0.1
    act_latent_dim: int = 32
    act_kl_weight: float = 10.0
    # Temporal ensembling (temporal_ensemble.py), ACT's m (e.g. 0.01), or None: served chunks are
    # then executed by a forward pass every step (executed_steps 1), each step's action the
    # exp(-m * i)-weighted mean of every chunk's row for it.
    temporal_ensemble: Optional[float] = None
    cnn_widths: List[int] = field(default_factory=lambda: [32, 64, 96, 128])
    # The camera encoder: "cnn" (CameraEncoder: stride-2 convs, flattened) or "resnet18" (vision.py:
    # Diffusion Policy's ResNet-18 with GroupNorm and a spatial softmax, vision_width base channels).
    # A config.json without these fields predates them: it was a cnn, and loads as one.
    vision: str = "cnn"
    vision_width: int = 64
    # Random-crop augmentation (LeRobot's diffusion policy): the encoder sees a crop of crop_ratio of
    # each side (crop_size), at a random place in training and the centre when served; 1.0: no crop.
    crop_ratio: float = 1.0
    feature_dim: int = 128
    hidden_dim: int = 512
    shift_px: int = 4                 # random-shift augmentation (training only)
    min_std: float = 1e-2
    neck_state_dims: List[int] = field(default_factory=list)   # zeroed under fixed
    neck_action_dims: List[int] = field(default_factory=lambda: list(NECK_ACTION_DIMS))
    # The tavis task and robot of the dataset trained on (dataset_origin.py), which serve.py declares
    # so that `tavis eval` refuses a cell of another; None: not known (several tasks, a dataset not
    # written by `tavis demos`, or a config.json that predates the fields), and nothing is declared.
    task: Optional[str] = None
    robot: Optional[str] = None

    def __post_init__(self):
        if self.camera not in ("head", "fixed"):
            raise ValueError(f"camera must be 'head' or 'fixed', got {self.camera!r}")
        if self.history_frames < 1 or self.history_stride < 1:
            raise ValueError(f"history_frames ({self.history_frames}) and history_stride ({self.history_stride}) must be >= 1")
        if (isinstance(self.executed_steps, bool) or not isinstance(self.executed_steps, int)
                or not 1 <= self.executed_steps <= self.chunk_size):
            raise ValueError(f"executed_steps {self.executed_steps!r} must be a whole number in 1..chunk_size "
                             f"({self.chunk_size})")
        if self.head not in HEADS:
            raise ValueError(f"head must be one of {', '.join(HEADS)}, got {self.head!r}")
        if not 1 <= self.flow_steps <= 100 or self.flow_width < 8 or self.flow_width % 8:
            raise ValueError(f"flow_steps {self.flow_steps} must be in 1..100 and flow_width {self.flow_width} "
                             f"a multiple of 8")
        act_sizes = [getattr(self, name) for name in ACT_OPTIONS if name not in ("act_dropout", "act_kl_weight")]
        if (min(act_sizes) < 1 or self.act_d_model % self.act_heads or not 0 <= self.act_dropout < 1
                or not 0 <= self.act_kl_weight < float("inf")):
            raise ValueError(f"act sizes {dict(zip(ACT_OPTIONS, act_sizes))} must be >= 1 with act_d_model a multiple "
                             f"of act_heads, act_dropout {self.act_dropout} in [0, 1) and act_kl_weight "
                             f"{self.act_kl_weight} >= 0")
        if self.temporal_ensemble is not None:
            self.temporal_ensemble = check_coefficient(self.temporal_ensemble)
            if self.executed_steps != 1:
                raise ValueError(f"temporal ensembling runs a forward pass every step: executed_steps must be 1, "
                                 f"got {self.executed_steps}")
        if len(self.image_size) != 2 or min(self.image_size) < 16:
            raise ValueError(f"image_size {self.image_size} must be (height, width), each >= 16")
        if self.vision not in VISIONS:
            raise ValueError(f"vision must be one of {', '.join(VISIONS)}, got {self.vision!r}")
        if isinstance(self.vision_width, bool) or not isinstance(self.vision_width, int) or self.vision_width < 4:
            raise ValueError(f"vision_width {self.vision_width!r} must be a whole number >= 4")
        if not 0 < self.crop_ratio <= 1 or min(self.crop_size) < 8:
            raise ValueError(f"crop_ratio {self.crop_ratio!r} must be in (0, 1] and leave each side of image_size "
                             f"{self.image_size} at least 8 pixels")
        for name in ("task", "robot"):
            value = getattr(self, name)
            if value is not None and (not isinstance(value, str) or not value):
                raise ValueError(f"{name} must be a tavis {name} name or null, got {value!r}")
        if self.camera == "fixed" and not self.neck_state_dims:
            if self.state_dim not in NECK_STATE_DIMS:
                raise ValueError(f"fixed camera: no known neck entries for a state of {self.state_dim} dims; "
                                 f"known sizes {sorted(NECK_STATE_DIMS)}")
            self.neck_state_dims = list(NECK_STATE_DIMS[self.state_dim])

    @property
    def n_action_steps(self):
        """LeRobot's name for executed_steps: the rows predict_action_chunk returns and select_action
        queues; tavis_server sets it when given --n-action-steps."""
        return self.executed_steps

    @n_action_steps.setter
    def n_action_steps(self, value):
        self.execute_with(value, self.temporal_ensemble)

    def execute_with(self, executed_steps, temporal_ensemble=None):
        """Replaces how chunks are executed (serve's --executed-steps / --temporal-ensemble), both settings
        at once; a bad pair raises ValueError and changes nothing."""
        previous = self.executed_steps, self.temporal_ensemble
        self.executed_steps, self.temporal_ensemble = executed_steps, temporal_ensemble
        try:
            self.__post_init__()
        except ValueError:
            self.executed_steps, self.temporal_ensemble = previous
            raise

    @property
    def chunk_execution(self):
        """How a served chunk is executed, in words (the policy's metadata, so summary.json's)."""
        if self.temporal_ensemble is not None:
            return (f"temporal ensembling (m = {self.temporal_ensemble:g}): one forward pass per policy step, each "
                    f"step's action the mean of every chunk's row for it, the i-th oldest chunk weighted "
                    f"exp(-{self.temporal_ensemble:g} * i)")
        if self.executed_steps == 1:
            return "re-plan every step: one forward pass per policy step, the first row of its chunk executed"
        return (f"queue of {self.executed_steps} rows: one forward pass every {self.executed_steps} policy steps, "
                f"its first {self.executed_steps} rows executed one per step, open loop")

    @property
    def crop_size(self):
        """(height, width) of the crop the encoder sees: crop_ratio of image_size, rounded."""
        return [int(round(side * self.crop_ratio)) for side in self.image_size]

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
    def from_json(cls, text, where="config.json", notes=None):
        """The config in `text` (a config.json). A config written before executed_steps was a setting
        holds n_action_steps instead, the length of tavis_server's queue it was always served with:
        it is served so again, and `notes` (a list) gets a line that says so."""
        values = json.loads(text)
        if "executed_steps" not in values and "n_action_steps" in values:
            values["executed_steps"] = values.pop("n_action_steps")
            if notes is not None:
                notes.append(f"{where} predates the executed_steps setting: it is served as it always was, with a "
                             f"queue of its n_action_steps {values['executed_steps']} rows (`--executed-steps 1` "
                             f"re-plans every step instead)")
        known = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(values) - known)
        if unknown:
            raise ValueError(f"{where} has unknown fields {unknown}")
        return cls(**values)
