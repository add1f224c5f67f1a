"""Serves an object with LeRobot's policy interface: reset(), select_action(batch) -> (B, D) and,
on LeRobot >= 0.3 policies, predict_action_chunk(batch) -> (B, H, D); config.n_obs_steps (the
observation history, default 1); optional preprocess(batch) -> batch and postprocess(actions) ->
actions callables (LeRobot >= 0.4 keeps normalisation in make_pre_post_processors).

Fast path (predict_action_chunk): the server keeps each env slot's last n_obs_steps observations
(filled with copies of the first at an episode's start, as LeRobot's queues are) and answers all
envs of a request with ONE forward pass over the stacked histories.

Slow path (select_action only): one deep copy of the policy per env slot, reset at each of its
episodes, select_action called once per env (its internal queues keep history and actions), and
each env gets a 1-row chunk, so the client asks again at the next step. N envs cost N calls."""

import collections
import contextlib
import copy

import numpy as np

from .actions import ACTION_DIM
from .policy_batch import stack_histories, to_numpy, to_policy_batch


class LeRobotServedPolicy:
    def __init__(self, policy, name, device="cpu", preprocess=None, postprocess=None, metadata=None, torch=None):
        """torch: the torch module to build input tensors with (on `device`); None: numpy arrays."""
        self.policy = policy
        self.name = name
        self.device = device
        self.torch = torch
        self.preprocess = preprocess or (lambda batch: batch)
        self.postprocess = postprocess or (lambda actions: actions)
        config = getattr(policy, "config", None)
        self.n_obs_steps = int(getattr(config, "n_obs_steps", 1) or 1)
        if self.n_obs_steps < 1:
            raise ValueError(f"policy {name}: config.n_obs_steps {self.n_obs_steps} must be at least 1")
        self.chunked = callable(getattr(policy, "predict_action_chunk", None))
        # LeRobot's select_action executes the first n_action_steps rows of a chunk; so do we.
        self.n_action_steps = getattr(config, "n_action_steps", None) if self.chunked else 1
        self.history_length = self.n_obs_steps if self.chunked else 1
        self._histories = {}
        self._copies = {}
        self.forward_passes = 0
        self.metadata = {"n_obs_steps": self.n_obs_steps,
                         "inference": "predict_action_chunk" if self.chunked else "select_action per env",
                         "device": str(device) if torch is not None else "numpy"}
        horizon = self.n_action_steps or getattr(config, "chunk_size", None) or getattr(config, "horizon", None)
        if horizon is not None:
            self.metadata["action_horizon"] = int(horizon)
        self.metadata.update(metadata or getattr(policy, "metadata", None) or {})
        if hasattr(policy, "reset"):
            policy.reset()

    def infer(self, observations, starts):
        """(N, H, 19) float32 actions for N observations; starts[i]: observation i opens an episode."""
        if self.chunked:
            return self._infer_chunks(observations, starts)
        return np.stack([self._select_one(observation, start) for observation, start in zip(observations, starts)])

    def _infer_chunks(self, observations, starts):
        for observation, start in zip(observations, starts):
            if start:
                self._histories[observation.env_index] = collections.deque(
                    [observation.arrays] * self.n_obs_steps, maxlen=self.n_obs_steps)
            else:
                self._histories[observation.env_index].append(observation.arrays)
        histories = [self._histories[observation.env_index] for observation in observations]
        stacked = stack_histories(histories, lambda env: f"env {observations[env].env_index}")
        batch = self.preprocess(to_policy_batch(stacked, [o.task for o in observations], self.device, self.torch))
        with self._no_grad():
            self.forward_passes += 1
            actions = self.policy.predict_action_chunk(batch)
        actions = to_numpy(self.postprocess(actions))
        if actions.ndim != 3 or actions.shape[0] != len(observations) or actions.shape[2] != ACTION_DIM:
            raise ValueError(f"policy {self.name}: predict_action_chunk gave actions of shape {actions.shape} for "
                             f"{len(observations)} envs; expected ({len(observations)}, H, {ACTION_DIM})")
        if self.n_action_steps:
            actions = actions[:, :int(self.n_action_steps)]
        return actions

    def _select_one(self, observation, start):
        policy = self._copies.get(observation.env_index)
        if policy is None:
            policy = self._copies[observation.env_index] = copy.deepcopy(self.policy)
        if start:
            policy.reset()
        stacked = stack_histories([[observation.arrays]], lambda env: f"env {observation.env_index}")
        batch = self.preprocess(to_policy_batch(stacked, [observation.task], self.device, self.torch))
        with self._no_grad():
            self.forward_passes += 1
            action = policy.select_action(batch)
        action = to_numpy(self.postprocess(action))
        if action.shape != (1, ACTION_DIM):
            raise ValueError(f"policy {self.name}: select_action gave actions of shape {action.shape}; "
                             f"expected (1, {ACTION_DIM})")
        return action  # a 1-row chunk

    def _no_grad(self):
        if self.torch is None:
            return contextlib.nullcontext()
        return self.torch.inference_mode()

    def close(self):
        pass
