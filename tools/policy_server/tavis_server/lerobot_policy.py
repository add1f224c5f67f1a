"""Serves an object with LeRobot's policy interface: reset(), select_action(batch) -> (B, D) and,
on LeRobot >= 0.3 policies, predict_action_chunk(batch) -> (B, H, D); config.n_obs_steps (the
observation history, default 1); optional preprocess(batch) -> batch and postprocess(actions) ->
actions callables (LeRobot >= 0.4 keeps normalisation in make_pre_post_processors).

Every piece of per-env state below is kept per env slot: (connection, env_index), observation.slot,
since each client numbers its envs from 0; forget(connection) drops a closed connection's.

Fast path (predict_action_chunk): the server keeps each env slot's last n_obs_steps observations
(filled with copies of the first at an episode's start, as LeRobot's queues are) and answers all
envs of a request with ONE forward pass over the stacked histories. The first n_action_steps rows
of each chunk are kept (LeRobot's Diffusion already returns only the rows [n_obs_steps - 1,
n_obs_steps - 1 + n_action_steps) of its horizon from predict_action_chunk; ACT its chunk_size).

Action queue (on by default when n_obs_steps > 1, see ACTION_QUEUE_MODES): each env executes its
chunk's rows one per step as select_action would; a request is answered from the envs' queues and
only the envs whose queue is used up share one forward pass. Replies then hold one row per env.

Slow path (select_action only): one deep copy of the policy per env slot, reset at each of its
episodes, select_action called once per env (its internal queues keep history and actions), and
each env gets a 1-row chunk, so the client asks again at the next step. N envs cost N calls."""

import collections
import contextlib
import copy

import numpy as np

from .action_queue import ActionQueues
from .actions import ACTION_DIM
from .policy_batch import request_ids, stack_histories, to_numpy, to_policy_batch
from .slots import drop_connection


# auto: queue when the policy keeps an observation history (n_obs_steps > 1). Such a policy needs
# the client to ask at every step anyway (--replan-steps 1), and without the queue every step would
# be a forward pass, i.e. a replan at 20 Hz instead of the reference's n_action_steps per chunk. A
# policy without a history is better served chunk-wise (the client executes --replan-steps rows of
# each reply and asks less often), which the queue would forbid (it needs every step).
ACTION_QUEUE_MODES = ("auto", "on", "off")


class LeRobotServedPolicy:
    def __init__(self, policy, name, device="cpu", preprocess=None, postprocess=None, metadata=None, torch=None,
                 action_queue="auto", n_action_steps=None):
        """torch: the torch module to build input tensors with (on `device`); None: numpy arrays.
        action_queue: auto | on | off (ACTION_QUEUE_MODES). n_action_steps: rows executed per chunk,
        written into policy.config (where LeRobot's models read it) when given; default the config's."""
        if action_queue not in ACTION_QUEUE_MODES:
            raise ValueError(f"action queue mode {action_queue!r} is not one of {', '.join(ACTION_QUEUE_MODES)}")
        if n_action_steps is not None and (isinstance(n_action_steps, bool) or int(n_action_steps) != n_action_steps
                                           or n_action_steps < 1):
            raise ValueError(f"n_action_steps {n_action_steps!r} must be an integer of at least 1")
        self.policy = policy
        self.name = name
        self.device = device
        self.torch = torch
        self.preprocess = preprocess or (lambda batch: batch)
        self.postprocess = postprocess or (lambda actions: actions)
        config = getattr(policy, "config", None)
        if n_action_steps is not None and config is not None:
            config.n_action_steps = int(n_action_steps)
        self.n_obs_steps = int(getattr(config, "n_obs_steps", 1) or 1)
        if self.n_obs_steps < 1:
            raise ValueError(f"policy {name}: config.n_obs_steps {self.n_obs_steps} must be at least 1")
        self.chunked = callable(getattr(policy, "predict_action_chunk", None))
        # LeRobot's select_action executes the first n_action_steps rows of a chunk; so do we.
        if n_action_steps is None:
            n_action_steps = getattr(config, "n_action_steps", None)
        self.n_action_steps = (int(n_action_steps) if n_action_steps is not None else None) if self.chunked else 1
        self.history_length = self.n_obs_steps if self.chunked else 1
        # The select_action slow path needs no server queue: each env's policy copy keeps its own.
        self.queues_actions = self.chunked and (action_queue == "on" or
                                                (action_queue == "auto" and self.n_obs_steps > 1))
        self.consecutive_steps = self.history_length > 1 or self.queues_actions
        self._histories = {}
        self._copies = {}
        self._queues = ActionQueues()
        self.forward_passes = 0
        self.metadata = {"n_obs_steps": self.n_obs_steps,
                         "inference": "predict_action_chunk" if self.chunked else "select_action per env",
                         "action_queue": self.queues_actions,
                         "device": str(device) if torch is not None else "numpy"}
        if self.n_action_steps is not None:
            self.metadata["n_action_steps"] = self.n_action_steps
        horizon = self.n_action_steps or getattr(config, "chunk_size", None) or getattr(config, "horizon", None)
        if self.queues_actions:
            horizon = 1  # one row per reply: the action of the step asked
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
                self._histories[observation.slot] = collections.deque(
                    [observation.arrays] * self.n_obs_steps, maxlen=self.n_obs_steps)
            else:
                self._histories[observation.slot].append(observation.arrays)
        if self.queues_actions:
            return self._infer_queued(observations, starts)
        return self._forward(observations)

    def _infer_queued(self, observations, starts):
        """(N, 1, 19): each env's action for its step, from its queue, or from one forward pass over
        just the envs whose queue is used up (their histories hold this step's observation)."""
        rows = [self._queues.queued_action(observation, start) for observation, start in zip(observations, starts)]
        due = [index for index, row in enumerate(rows) if row is None]
        if due:
            chunks = self._forward([observations[index] for index in due])
            for index, chunk in zip(due, chunks):
                self._queues.fill(observations[index], chunk)
                rows[index] = chunk[0]
        return np.stack(rows)[:, None]

    def _forward(self, observations):
        """One forward pass over these envs' histories: (N, H, 19), H at most n_action_steps."""
        histories = [self._histories[observation.slot] for observation in observations]
        stacked = stack_histories(histories, lambda env: f"env {observations[env].env_index}")
        stacked.update(request_ids(observations))
        batch = self.preprocess(to_policy_batch(stacked, [o.task for o in observations], self.device, self.torch))
        with self._no_grad():
            self.forward_passes += 1
            actions = self.policy.predict_action_chunk(batch)
        actions = to_numpy(self.postprocess(actions))
        if (actions.ndim != 3 or actions.shape[0] != len(observations) or actions.shape[1] < 1
                or actions.shape[2] != ACTION_DIM):
            raise ValueError(f"policy {self.name}: predict_action_chunk gave actions of shape {actions.shape} for "
                             f"{len(observations)} envs; expected ({len(observations)}, H >= 1, {ACTION_DIM})")
        if self.n_action_steps:
            actions = actions[:, :int(self.n_action_steps)]
        return actions

    def _select_one(self, observation, start):
        policy = self._copies.get(observation.slot)
        if policy is None:
            policy = self._copies[observation.slot] = copy.deepcopy(self.policy)
        if start:
            policy.reset()
        stacked = stack_histories([[observation.arrays]], lambda env: f"env {observation.env_index}")
        stacked.update(request_ids([observation]))
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

    def forget(self, connection):
        """Drops the histories, queued chunks and policy copies of a closed connection's env slots."""
        drop_connection(self._histories, connection)
        drop_connection(self._copies, connection)
        self._queues.forget(connection)

    def close(self):
        pass
