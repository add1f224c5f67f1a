"""One training step, two ways, the same step in distribution (the same window sampling, the same
random shift and crop, the same schedule, loss, clip and AdamW):

- EagerStep: PyTorch as written; the CPU path (Debian's torch 1.13 has no torch.compile), and
  CUDA with --no-compile. Rows and shift offsets come from a CPU generator, so on the CPU a seed
  gives the same weights run after run.
- GraphedStep (CUDA, PyTorch 2.x): the policy's loss through torch.compile, and the whole step
  (row sampling and random shift drawn on the GPU, forward under bf16 autocast, backward, grad
  clip, AdamW(fused=True, capturable=True) with the learning rate in a device tensor, the loss
  summed for the log) captured once as one CUDA graph; a step is then one fill_ of the learning
  rate and one replay, with no host sync. The GPU was the limit, not the host: most of an eager
  step's GPU time is memory-bound glue around the convolutions (layout and dtype conversions,
  GroupNorm, SiLU), which compile fuses, and the graph removes the ~580 kernel launches a step.

Both: run(step) does step `step` (0-based) at the schedule's learning rate; window_loss() is the
mean loss of the steps since its last call (a host sync; called at log steps only)."""

import time

import torch

from .augment import center_crop, random_crop, random_shift, random_shift_on_device
from .dataset import ACTION, STATE


def autocast(device, cache_enabled=True):
    if device.type == "cuda":
        # A CUDA graph must not capture autocast's weight-cast cache (PyTorch's CUDA-graph notes).
        return torch.autocast("cuda", dtype=torch.bfloat16, cache_enabled=cache_enabled)
    return torch.autocast("cpu", enabled=False)


def batch_loss(policy, data, rows, generator, augment, loss=None, offsets=None):
    """The policy's loss on the windows of `rows`. generator: the CPU generator of the shift
    offsets and crop places (None: drawn on the rows' device); augment False (validation): the
    centre crop, as served; loss: the function to call (default policy.loss);
    offsets: (observation, action) frame offsets as device tensors (default the config's lists)."""
    config = policy.config
    obs_offsets, action_offsets = offsets if offsets is not None else (config.obs_offsets, config.action_offsets)
    batch = data.sample(rows, obs_offsets, action_offsets)
    images = []
    for key in config.image_keys:
        frames = batch[key].float().div_(255)
        if augment:
            frames = (random_shift(frames, config.shift_px, generator) if generator is not None
                      else random_shift_on_device(frames, config.shift_px))
            frames = random_crop(frames, config.crop_size, generator)  # None: drawn on the device
        else:
            frames = center_crop(frames, config.crop_size)  # as served
        images.append(frames)
    draws = policy.training_draws(len(rows), rows.device, generator) if augment else \
        policy.training_draws(len(rows), rows.device, torch.Generator().manual_seed(0))
    return (loss or policy.loss)(images, batch[STATE], batch[ACTION], batch[f"{ACTION}_is_pad"], *draws)


def can_compile(device):
    """Whether GraphedStep compiles and captures here: CUDA and a PyTorch with torch.compile (2.x)."""
    return device.type == "cuda" and hasattr(torch, "compile")


class EagerStep:
    mode = "eager"

    def __init__(self, policy, data, train_rows, batch_size, lr_at, weight_decay, generator, device):
        self.policy, self.data, self.batch_size, self.lr_at = policy, data, batch_size, lr_at
        self.train_rows, self.generator, self.device = train_rows, generator, device
        self.optimizer = torch.optim.AdamW(policy.parameters(), lr=lr_at(0), weight_decay=weight_decay)
        self.prepare_s = 0.0
        self._loss_sum, self._steps = 0.0, 0

    def run(self, step):
        for group in self.optimizer.param_groups:
            group["lr"] = self.lr_at(step)
        rows = self.train_rows[torch.randint(len(self.train_rows), (self.batch_size,), generator=self.generator)]
        with autocast(self.device):
            loss = batch_loss(self.policy, self.data, rows.to(self.device), self.generator, augment=True)
        self.optimizer.zero_grad(set_to_none=True)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(self.policy.parameters(), 1.0)
        self.optimizer.step()
        self._loss_sum += loss.detach()
        self._steps += 1

    def window_loss(self):
        mean = float(self._loss_sum) / max(self._steps, 1)
        self._loss_sum, self._steps = 0.0, 0
        return mean


class GraphedStep:
    """On CUDA: the compiled step captured as one CUDA graph. A graph replays reads and writes at
    the addresses it was captured with, so every tensor the step touches is an attribute of this
    object (rows, offsets, lr, loss_sum, the policy's parameters, the optimizer's state) and lives
    as long as it: a tensor the step read that was freed would be reused by the next eager
    allocation (the validation at a save) and the replay would read garbage indices.

    Elsewhere (the CPU tests: no CUDA graphs, no torch.compile on 1.13) the same _body runs
    uncaptured at every step, with the same device-side sampling, so the step's logic and its
    interplay with saves and validation are exercised where CUDA is not."""

    WARMUP = 3  # eager-stream runs before capture: compile, autotune, allocate the optimizer state

    def __init__(self, policy, data, train_rows, batch_size, lr_at, weight_decay, seed, device):
        started = time.monotonic()
        self.policy, self.data, self.batch_size, self.lr_at, self.device = policy, data, batch_size, lr_at, device
        self.captured = device.type == "cuda"
        self.mode = "compiled + CUDA graph" if self.captured else "device-sampled, uncaptured"
        config = policy.config
        # Everything the step reads lives on the device before capture: the training rows and the
        # offsets of the windows (a Python list would be copied to the device inside the step).
        self.rows = train_rows.to(device)
        self.offsets = (torch.tensor(config.obs_offsets, dtype=torch.int64, device=device),
                        torch.tensor(config.action_offsets, dtype=torch.int64, device=device))
        self.parameters = list(policy.parameters())
        self.loss_sum = torch.zeros((), dtype=torch.float32, device=device)
        self._steps = 0
        if not self.captured:
            self.lr = None
            self.optimizer = torch.optim.AdamW(self.parameters, lr=lr_at(0), weight_decay=weight_decay)
            self.loss_function = policy.loss
            self.prepare_s = time.monotonic() - started
            return
        self.lr = torch.tensor(lr_at(0), dtype=torch.float32, device=device)
        self.optimizer = torch.optim.AdamW(self.parameters, lr=self.lr, weight_decay=weight_decay, fused=True,
                                           capturable=True)
        self.loss_function = torch.compile(policy.loss)

        # The warm-up steps change the weights and the optimizer's moments: keep the initial weights
        # and put them back after capture (capturing runs nothing), so the first replay is step 0.
        initial = [p.detach().clone() for p in self.parameters]
        side = torch.cuda.Stream(device)
        side.wait_stream(torch.cuda.current_stream(device))
        with torch.cuda.stream(side):
            for _ in range(self.WARMUP):
                self.optimizer.zero_grad(set_to_none=True)
                self._body()
        torch.cuda.current_stream(device).wait_stream(side)
        self.optimizer.zero_grad(set_to_none=True)  # backward in the graph then writes, not adds, the grads
        self.graph = torch.cuda.CUDAGraph()
        with torch.cuda.graph(self.graph):
            self._body()
        with torch.no_grad():
            for parameter, value in zip(self.parameters, initial):
                parameter.copy_(value)
            for state in self.optimizer.state.values():
                for value in state.values():
                    if torch.is_tensor(value):
                        value.zero_()  # exp_avg, exp_avg_sq and the (device) step count
            self.loss_sum.zero_()
        torch.cuda.manual_seed(seed)  # the graph reads the generator's seed and offset at each replay
        torch.cuda.synchronize(device)
        self.prepare_s = time.monotonic() - started

    def _body(self):
        """The step, reading and writing only this object's tensors (see the class's note)."""
        picked = self.rows[torch.randint(len(self.rows), (self.batch_size,), device=self.device)]
        with autocast(self.device, cache_enabled=False):
            loss = batch_loss(self.policy, self.data, picked, None, augment=True, loss=self.loss_function,
                              offsets=self.offsets)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(self.parameters, 1.0)
        self.optimizer.step()
        with torch.no_grad():
            self.loss_sum.add_(loss.detach())

    def run(self, step):
        if self.captured:
            self.lr.fill_(self.lr_at(step))
            self.graph.replay()
        else:
            for group in self.optimizer.param_groups:
                group["lr"] = self.lr_at(step)
            self.optimizer.zero_grad(set_to_none=True)
            self._body()
        self._steps += 1

    def window_loss(self):
        mean = float(self.loss_sum) / max(self._steps, 1)
        self.loss_sum.zero_()
        self._steps = 0
        return mean
