"""A flow-matching action head over the whole chunk (Diffusion Policy's family, in its
rectified-flow form): a small 1-D temporal conv net over the chunk's rows, FiLM-conditioned on the
observation features and the flow time, that predicts the velocity from noise to the normalised
action chunk. It can model several modes where the L1 head averages them (which arm, which side).

Training: x0 ~ N(0, I), x1 the target chunk, t ~ U(0, 1), x_t = (1 - t) x0 + t x1; the loss is
the mean squared error between the predicted and the true velocity x1 - x0 over the non-padded
rows. Sampling: `steps` Euler steps from x0 at t = 0 to t = 1.

The noise is an argument, never drawn here: the trainer draws it (from its CPU generator, or on
the GPU inside the CUDA graph), and serving derives it from (seed, episode index, step) of the
request, or from the observation when a batch carries no ids (policy.py), so a served episode is
the same run after run."""

import math

import torch
from torch import nn


class FlowHead(nn.Module):
    def __init__(self, condition_dim, chunk_size, action_dim, width=256, blocks=3, time_dim=64):
        super().__init__()
        self.chunk_size, self.action_dim, self.time_dim = chunk_size, action_dim, time_dim
        self.condition = nn.Sequential(nn.Linear(condition_dim + time_dim, width), nn.SiLU(), nn.Linear(width, width))
        self.inputs = nn.Conv1d(action_dim, width, 1)
        self.convs = nn.ModuleList(nn.Conv1d(width, width, 3, padding=1) for _ in range(blocks))
        self.norms = nn.ModuleList(nn.GroupNorm(8, width) for _ in range(blocks))
        self.films = nn.ModuleList(nn.Linear(width, 2 * width) for _ in range(blocks))
        self.outputs = nn.Conv1d(width, action_dim, 1)
        nn.init.zeros_(self.outputs.weight)  # start at zero velocity: a stable first step
        nn.init.zeros_(self.outputs.bias)

    def time_embedding(self, t):
        half = self.time_dim // 2
        frequencies = torch.exp(torch.arange(half, device=t.device, dtype=torch.float32) * (-math.log(1000.0) / half))
        angles = t.float()[:, None] * 1000.0 * frequencies[None]
        return torch.cat([angles.sin(), angles.cos()], dim=-1)

    def velocity(self, x, t, condition):
        """x: (B, chunk, A) the chunk at flow time t (B,); condition: (B, condition_dim)."""
        context = torch.nn.functional.silu(self.condition(torch.cat([condition, self.time_embedding(t).to(condition.dtype)], -1)))
        hidden = self.inputs(x.transpose(1, 2))
        for conv, norm, film in zip(self.convs, self.norms, self.films):
            scale, shift = film(context).unsqueeze(-1).chunk(2, dim=1)
            hidden = hidden + torch.nn.functional.silu(norm(conv(hidden)) * (1 + scale) + shift)
        return self.outputs(hidden).transpose(1, 2)

    def loss(self, condition, target, valid, noise, t):
        """Mean squared velocity error over the valid rows; target (B, chunk, A) normalised; valid
        (B, chunk) bool; noise like target; t (B,) in [0, 1)."""
        t_ = t[:, None, None].to(target.dtype)
        x = (1 - t_) * noise + t_ * target
        error = (self.velocity(x, t, condition).float() - (target - noise)).pow(2)
        weight = valid.unsqueeze(-1).to(error.dtype)
        return (error * weight).sum() / (weight.sum() * error.shape[-1]).clamp(min=1)

    def sample(self, condition, noise, steps):
        """The chunk reached from `noise` (B, chunk, A) by `steps` Euler steps of the flow."""
        x = noise
        dt = 1.0 / steps
        for k in range(steps):
            t = torch.full((x.shape[0],), k * dt, device=x.device)
            x = x + dt * self.velocity(x, t, condition).float()
        return x
