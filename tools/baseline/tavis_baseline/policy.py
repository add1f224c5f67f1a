"""The reference learned baseline: per-camera encoders (a CNN, or vision.py's ResNet-18) + state,
over a short observation history, to an L1-trained chunk of future actions (docs/baselines.md
says why this model).

It exposes LeRobot's policy interface, so tavis_server serves it like a LeRobot policy:
reset(), select_action(batch) (one action per call from a queue of n_action_steps, LeRobot's name
for config.executed_steps),
predict_action_chunk(batch) and config.n_obs_steps. Batches are LeRobot's: images float in [0, 1]
as (B, n_obs_steps, 3, H, W) (or (B, 3, H, W) for one step) under the dataset keys,
observation.state (B, n_obs_steps, D), the n_obs_steps consecutive policy steps up to now; the
network looks at every history_stride-th of them (config.history_positions). Images of another
size are resized to config.image_size.
"""

import hashlib
from collections import deque

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

from .act_head import ActHead
from .augment import center_crop
from .config import ACT_OPTIONS, BaselineConfig
from .flow_head import FlowHead
from .temporal_ensemble import TemporalEnsemble
from .vision import ResNet18Encoder

STATE = "observation.state"
ACTION = "action"
# The ids tavis_server adds to each batch (tavis_server.policy_batch.request_ids) that key the flow
# head's serving noise. Not env_index: the cell's episode_index already names the scene, and which
# env slot runs an episode depends on --envs, which must not change a record.
NOISE_IDS = ("episode_index", "step")
NOISE_FROM = ("from (noise_seed, episode_index, step) of the request; from (noise_seed, the observation) "
              "for a batch without them")


class CameraEncoder(nn.Module):
    """Stride-2 conv stages (GroupNorm, SiLU), flattened (keeps where things are), to a feature;
    feature_dim None: the last stage's map alone (the ACT head takes its positions as tokens)."""

    def __init__(self, widths, image_size, feature_dim):
        super().__init__()
        layers = []
        channels = 3
        for width in widths:
            layers += [nn.Conv2d(channels, width, 3, stride=2, padding=1), nn.GroupNorm(8, width), nn.SiLU()]
            channels = width
        self.conv = nn.Sequential(*layers)
        height, width = image_size
        for _ in widths:
            height, width = (height + 1) // 2, (width + 1) // 2
        self.map_shape = (channels, height, width)
        if feature_dim is None:
            return
        self.project = nn.Sequential(nn.Flatten(), nn.Linear(channels * height * width, feature_dim), nn.LayerNorm(feature_dim))

    def feature_map(self, images):
        return self.conv(images - 0.5)

    def forward(self, images):
        return self.project(self.feature_map(images))


class BaselinePolicy(nn.Module):
    name = "tavis_baseline"

    def __init__(self, config: BaselineConfig, state_mean, state_std, action_mean, action_std):
        super().__init__()
        self.config = config
        self.register_buffer("state_mean", torch.as_tensor(state_mean, dtype=torch.float32))
        self.register_buffer("state_std", torch.as_tensor(state_std, dtype=torch.float32))
        self.register_buffer("action_mean", torch.as_tensor(action_mean, dtype=torch.float32))
        self.register_buffer("action_std", torch.as_tensor(action_std, dtype=torch.float32))
        state_keep = torch.ones(config.state_dim)
        state_keep[config.neck_state_dims if config.camera == "fixed" else []] = 0
        self.register_buffer("state_keep", state_keep)
        self.encoders = nn.ModuleList(self.camera_encoder() for _ in config.image_keys)
        self.state_encoder = nn.Sequential(nn.Linear(config.state_dim, config.feature_dim), nn.LayerNorm(config.feature_dim))
        tokens = (len(config.image_keys) + 1) * config.history_frames
        if config.head == "l1":
            self.head = nn.Sequential(
                nn.Linear(tokens * config.feature_dim, config.hidden_dim), nn.SiLU(),
                nn.Linear(config.hidden_dim, config.hidden_dim), nn.SiLU(),
                nn.Linear(config.hidden_dim, config.chunk_size * config.action_dim))
        elif config.head == "flow":
            self.flow = FlowHead(tokens * config.feature_dim, config.chunk_size, config.action_dim, config.flow_width)
        else:
            channels, height, width = self.encoders[0].map_shape
            self.act = ActHead(channels, len(config.image_keys) * config.history_frames * height * width,
                               config.feature_dim, config.history_frames, config.chunk_size, config.action_dim,
                               config.act_d_model, config.act_heads, config.act_encoder_layers,
                               config.act_decoder_layers, config.act_vae_layers, config.act_feedforward,
                               config.act_dropout, config.act_latent_dim)
        self._queue = deque()
        self._ensemble = None  # select_action's, under temporal ensembling
        self.declared_contract = None  # set by serve.make_policy: the metadata's observation_contract

    @property
    def metadata(self):
        """What tavis_server adds to its handshake: how this policy wants to be driven."""
        c = self.config
        return {"policy_class": self.name, "camera": c.camera, "image_size_hw": list(c.image_size),
                "history_frames": c.history_frames, "history_stride": c.history_stride,
                "chunk_size": c.chunk_size, "head": c.head, "vision": c.vision,
                **({"vision_width": c.vision_width} if c.vision != "cnn" else {}),
                **({"crop_hw": c.crop_size} if c.crop_ratio < 1 else {}),
                **({"flow_steps": c.flow_steps, "noise": NOISE_FROM} if c.head == "flow" else {}),
                **({"act": {name[4:]: getattr(c, name) for name in ACT_OPTIONS}, "latent": "z = 0 when served"}
                   if c.head == "act" else {}),
                **({"temporal_ensemble": c.temporal_ensemble} if c.temporal_ensemble is not None else {}),
                "executed_steps": c.executed_steps, "chunk_execution": c.chunk_execution,
                "client_replan_steps": 1,
                # serve.make_policy's: what the checkpoint was trained on (tavis_server's contract.py)
                **({"observation_contract": self.declared_contract} if self.declared_contract else {})}

    # -- the network -----------------------------------------------------------------------------
    def camera_encoder(self):
        """One camera's encoder (config.vision), for images of config.crop_size."""
        c = self.config
        if c.vision == "resnet18":
            if c.head == "act":
                raise ValueError("the act head attends to the cnn's feature maps; vision resnet18 is not offered with it")
            return ResNet18Encoder(c.vision_width, c.crop_size, c.feature_dim)
        # ACT attends to the feature maps' positions: no projection (feature_dim None).
        return CameraEncoder(c.cnn_widths, c.crop_size, None if c.head == "act" else c.feature_dim)

    def features(self, images, state):
        """images: list of (B, T, 3, H, W) float in [0, 1], one per config.image_keys; state: (B, T, D).
        Returns the observation's features (B, T * (cameras + 1) * feature_dim)."""
        batch, steps = state.shape[:2]
        features = [encoder(frames.flatten(0, 1)).view(batch, steps, -1) for encoder, frames in zip(self.encoders, images)]
        features.append(self.state_features(state))
        return torch.cat(features, dim=-1).flatten(1)

    def state_features(self, state):
        """(B, T, feature_dim): each history frame's state, neck entries kept or zeroed, normalised."""
        return self.state_encoder((state * self.state_keep - self.state_mean) / self.state_std)

    def observation_tokens(self, images, state):
        """The ACT head's inputs: every position of every camera's feature map of every history frame
        (B, cameras * T * h * w, channels), and the states' features (B, T, feature_dim)."""
        batch = state.shape[0]
        maps = [encoder.feature_map(frames.flatten(0, 1)) for encoder, frames in zip(self.encoders, images)]
        tokens = [map_.flatten(2).transpose(1, 2).reshape(batch, -1, map_.shape[1]) for map_ in maps]  # (B, T*h*w, C)
        return torch.cat(tokens, dim=1), self.state_features(state)

    def normalized_chunk(self, images, state, noise=None):
        """The normalised action chunk (B, chunk_size, action_dim): the L1 head's regression, the
        flow head's sample from `noise` (B, chunk_size, action_dim), or the ACT head's at z = 0."""
        if self.config.head == "act":
            return self.act.sample(*self.observation_tokens(images, state))
        features = self.features(images, state)
        if self.config.head == "flow":
            return self.flow.sample(features, noise, self.config.flow_steps)
        return self.head(features).view(features.shape[0], self.config.chunk_size, self.config.action_dim)

    def normalize_action(self, action):
        if self.config.camera == "fixed":  # the env zeroes the neck actions: learn to output zero
            action = action.clone()
            action[..., self.config.neck_action_dims] = 0
        return (action - self.action_mean) / self.action_std

    def training_draws(self, batch, device, generator=None):
        """The head's training draws for a batch of `batch`, from the CPU `generator`, or on `device`
        when None: the flow head's noise and times (noise, t), the ACT head's reparameterisation
        noise (eps,); () for the L1 head, which draws nothing."""
        def draw(sample, *shape):
            return sample(shape, device=device) if generator is None else sample(shape, generator=generator).to(device)

        if self.config.head == "flow":
            return draw(torch.randn, batch, self.config.chunk_size, self.config.action_dim), draw(torch.rand, batch)
        if self.config.head == "act":
            return (draw(torch.randn, batch, self.config.act_latent_dim),)
        return ()

    def loss(self, images, state, action, action_is_pad, *draws):
        """The L1 head: mean L1 between the predicted and target normalised chunks over the
        non-padded targets. The flow head: its velocity loss, with draws = training_draws(...). The ACT
        head: that L1 (its chunk decoded from the posterior's z) + act_kl_weight x its KL term."""
        if self.config.head == "flow":
            noise, t = draws
            return self.flow.loss(self.features(images, state), self.normalize_action(action), ~action_is_pad, noise, t)
        if self.config.head == "act":
            chunk, kl = self.act.chunk_and_kl(*self.observation_tokens(images, state), self.normalize_action(action),
                                              ~action_is_pad, *draws)
        else:
            chunk, kl = self.normalized_chunk(images, state), None
        error = (chunk.float() - self.normalize_action(action)).abs()
        valid = (~action_is_pad).unsqueeze(-1).to(error.dtype)
        l1 = (error * valid).sum() / (valid.sum() * error.shape[-1]).clamp(min=1)
        return l1 if kl is None else l1 + self.config.act_kl_weight * kl

    # -- LeRobot's interface -----------------------------------------------------------------------
    def reset(self):
        self._queue.clear()
        self._ensemble = None

    def _inputs(self, batch):
        """The network's inputs from a LeRobot batch of n_obs_steps consecutive observations."""
        steps = self.config.n_obs_steps
        positions = self.config.history_positions
        state = batch[STATE].to(self.state_mean.device, torch.float32)
        if state.dim() == 2:
            state = state.unsqueeze(1)
        if state.shape[1] != steps or state.shape[2] != self.config.state_dim:
            raise ValueError(f"{STATE} has shape {tuple(state.shape)}, expected (B, {steps}, {self.config.state_dim})")
        state = state[:, positions]
        images = []
        height, width = self.config.image_size
        for key in self.config.image_keys:
            if key not in batch:
                raise KeyError(f"the batch has no {key!r} (keys: {', '.join(sorted(batch))})")
            frames = batch[key].to(self.state_mean.device, torch.float32)
            if frames.dim() == 4:
                frames = frames.unsqueeze(1)
            if frames.shape[1] != steps or frames.shape[2] != 3:
                raise ValueError(f"{key} has shape {tuple(frames.shape)}, expected (B, {steps}, 3, H, W)")
            frames = frames[:, positions]
            if frames.shape[-2:] != (height, width):
                flat = F.interpolate(frames.flatten(0, 1), size=(height, width), mode="bilinear", align_corners=False,
                                     antialias=True)
                frames = flat.view(*frames.shape[:3], height, width)
            images.append(center_crop(frames, self.config.crop_size))  # the training crop's centre
        return images, state

    @torch.no_grad()
    def predict_action_chunk(self, batch):
        """The next n_action_steps actions for each env: (B, n_action_steps, action_dim) float32; under
        temporal ensembling the whole chunk (B, chunk_size, action_dim), every row averaged in."""
        was_training = self.training
        self.eval()
        images, state = self._inputs(batch)
        noise = None
        if self.config.head == "flow":
            noise = self.serving_noise(images, state, self.request_ids(batch, state.shape[0]))
        chunk = self.normalized_chunk(images, state, noise).float() * self.action_std + self.action_mean
        if self.config.camera == "fixed":
            chunk[..., self.config.neck_action_dims] = 0
        self.train(was_training)
        return chunk if self.config.temporal_ensemble is not None else chunk[:, :self.config.n_action_steps]

    @staticmethod
    def request_ids(batch, envs):
        """One (episode_index, step) per env from the ids tavis_server puts in a batch (NOISE_IDS), or
        None when the batch has none (a batch built by hand, or by another server)."""
        if not all(key in batch for key in NOISE_IDS):
            return None
        columns = []
        for key in NOISE_IDS:
            values = torch.as_tensor(batch[key]).reshape(-1)
            if values.numel() != envs or values.is_floating_point():
                raise ValueError(f"the batch's {key} {values.tolist()} must hold one whole number per env ({envs})")
            columns.append(values.cpu().tolist())
        return list(zip(*columns))

    def serving_noise(self, images, state, ids=None):
        """The flow's starting noise for each env, a function of (config.noise_seed, the env's
        (episode_index, step) in `ids`), or without ids of (noise_seed, the env's newest observation:
        its state and its frames as uint8): the same episode's step (or observation) gets the same
        chunk, whichever envs share its batch and whichever env runs it, so a served episode repeats
        run after run."""
        if ids is None:
            newest = [torch.round(frames[:, -1] * 255).to(torch.uint8).cpu().numpy() for frames in images]
            states = state[:, -1].float().cpu().numpy()
        noises = []
        for env in range(state.shape[0]):
            digest = hashlib.blake2b(np.int64(self.config.noise_seed).tobytes(), digest_size=8)
            if ids is not None:
                digest.update(np.asarray(ids[env], dtype=np.int64).tobytes())
            else:
                digest.update(states[env].tobytes())
                for frames in newest:
                    digest.update(frames[env].tobytes())
            generator = torch.Generator().manual_seed(int.from_bytes(digest.digest(), "little") & (2 ** 63 - 1))
            noises.append(torch.randn((self.config.chunk_size, self.config.action_dim), generator=generator))
        return torch.stack(noises).to(state.device)

    @torch.no_grad()
    def select_action(self, batch):
        """One action per env (B, action_dim), from a queue refilled with a new chunk when empty; under
        temporal ensembling the ensembled action of a forward pass at every call."""
        if self.config.temporal_ensemble is not None:
            if self._ensemble is None:
                self._ensemble = TemporalEnsemble(self.config.temporal_ensemble)
            chunk = self.predict_action_chunk(batch)
            return torch.from_numpy(self._ensemble.add(chunk.cpu().numpy())).to(chunk.device)
        if not self._queue:
            self._queue.extend(self.predict_action_chunk(batch).transpose(0, 1))
        return self._queue.popleft()
