"""A stand-in with LeRobot's policy interface and a 2-observation history (like Diffusion's
n_obs_steps 2), written so that a test can read its inputs back from its actions.

Chunk row t, for each env of the batch:
  a[0] = state[oldest][0] * 1e-3 (the oldest history entry's step: the tests put the step in state[0])
  a[1] = state[newest][0] * 1e-3
  a[2] = state[newest][1] * 1e-3 (the episode)
  a[7] = mean of the newest OBS_HEAD image (OBS_FIXED when the client sends the fixed camera in its
         place, as under --camera fixed) as the policy saw it (float CHW in [0, 1])
  a[8] = the newest OBS_HEAD image's pixel (channel 2, row 1, column 3), as the policy saw it
  a[9] = UTF-8 length of the task * 1e-3
  a[14] = t * 1e-3
and the neutral action elsewhere. It counts its forward passes and the batch size of each."""

import numpy as np
import torch

NEUTRAL = torch.tensor([0.35, 0.2, 1.0, 1.0, 0.0, 0.0, 0.0, 0.35, -0.2, 1.0, 1.0, 0.0, 0.0, 0.0,
                        0.0, 0.0, 0.0, -1.0, -1.0])


class Config:
    def __init__(self, n_obs_steps, n_action_steps):
        self.n_obs_steps = n_obs_steps
        self.n_action_steps = n_action_steps


class HistoryPolicy(torch.nn.Module):
    def __init__(self, n_obs_steps=2, chunk=4):
        super().__init__()
        self.config = Config(n_obs_steps, chunk)
        self.chunk = chunk
        self.scale = torch.nn.Parameter(torch.tensor(1e-3), requires_grad=False)
        self.batch_sizes = []  # one entry per forward pass
        self.resets = 0
        self.select_action_calls = 0  # the server must take predict_action_chunk when there is one
        self.seen = []  # per forward pass: the batch's keys -> (dtype, shape)

    def reset(self):
        self.resets += 1

    def _features(self, batch):
        state = batch["observation.state"]
        head = batch.get("observation.images.OBS_HEAD", batch.get("observation.images.OBS_FIXED"))
        if self.config.n_obs_steps == 1:
            state, head = state[:, None], head[:, None]
        return state, head

    def predict_action_chunk(self, batch):
        self.seen.append({key: (value.dtype, tuple(value.shape)) for key, value in batch.items()
                          if isinstance(value, torch.Tensor)})
        state, head = self._features(batch)
        size = state.shape[0]
        self.batch_sizes.append(size)
        device = state.device
        actions = NEUTRAL.to(device).repeat(size, self.chunk, 1)
        newest = head[:, -1]
        actions[:, :, 0] = (state[:, 0, 0] * self.scale)[:, None]
        actions[:, :, 1] = (state[:, -1, 0] * self.scale)[:, None]
        actions[:, :, 2] = (state[:, -1, 1] * self.scale)[:, None]
        actions[:, :, 7] = newest.mean(dim=(1, 2, 3))[:, None]
        actions[:, :, 8] = newest[:, 2, 1, 3][:, None]
        lengths = torch.tensor([len(task.encode("utf-8")) for task in batch["task"]], device=device)
        actions[:, :, 9] = lengths[:, None] * self.scale
        actions[:, :, 14] = torch.arange(self.chunk, device=device) * self.scale
        return actions


    def select_action(self, batch):
        """LeRobot's per-step entry point: the first row of a fresh chunk."""
        self.select_action_calls += 1
        return self.predict_action_chunk(batch)[:, 0]


class DiffusionLikePolicy(HistoryPolicy):
    """Shaped like LeRobot's Diffusion (n_obs_steps 2, horizon 16, n_action_steps 8): it predicts
    `horizon` rows and predict_action_chunk returns rows [n_obs_steps - 1, n_obs_steps - 1 +
    n_action_steps) of them. On top of HistoryPolicy's encoding, a[14] is the horizon index of the
    row (1..8) and a[15] the number of this forward pass (1, 2, ...) times 1e-3. It records, per
    forward pass, each env's (episode, [history steps, oldest first])."""

    def __init__(self, n_obs_steps=2, horizon=16, n_action_steps=8):
        super().__init__(n_obs_steps=n_obs_steps, chunk=horizon)
        self.config.n_action_steps = n_action_steps
        self.config.horizon = horizon
        self.histories = []

    def predict_action_chunk(self, batch):
        state = batch["observation.state"]
        state = state[:, None] if self.config.n_obs_steps == 1 else state
        self.histories.append([(round(float(env[-1, 1])), [round(float(step)) for step in env[:, 0]])
                               for env in state])
        actions = super().predict_action_chunk(batch)
        actions[:, :, 15] = len(self.batch_sizes) * 1e-3
        start = self.config.n_obs_steps - 1
        return actions[:, start:start + self.config.n_action_steps]


class SelectOnlyPolicy(torch.nn.Module):
    """LeRobot's interface without predict_action_chunk: select_action keeps its own state (the
    number of calls since reset), which the server must keep apart per env slot."""

    def __init__(self):
        super().__init__()
        self.config = Config(1, 1)
        self.calls_since_reset = 0
        self.calls = 0

    def reset(self):
        self.calls_since_reset = 0

    def select_action(self, batch):
        self.calls_since_reset += 1
        type(self).total_calls = getattr(type(self), "total_calls", 0) + 1
        action = NEUTRAL.clone()[None]
        action[0, 0] = self.calls_since_reset * 1e-3
        action[0, 1] = batch["observation.state"][0, 0] * 1e-3
        return action


def expected_image_values(image):
    """What a[7] and a[8] should hold for an HWC uint8 image: float CHW in [0, 1]."""
    chw = np.moveaxis(image, -1, 0).astype(np.float32) / np.float32(255)
    return chw.mean(dtype=np.float64), chw[2, 1, 3]
