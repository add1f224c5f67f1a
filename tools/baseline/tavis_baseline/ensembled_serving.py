"""tavis_server's served object for a checkpoint under temporal ensembling (temporal_ensemble.py):
tavis_server's LeRobot-interface serving (per-slot observation histories, one forward pass over
the envs of a request) with no action queue and every row of each chunk kept, and each env's reply
the ensembled action of its step. serve.make_policy returns it when the chunk execution is
temporal ensembling; tavis_server then serves it as it is."""

import numpy as np
import torch

from tavis_server.lerobot_policy import LeRobotServedPolicy
from tavis_server.slots import drop_connection

from .temporal_ensemble import TemporalEnsemble, check_coefficient


class TemporalEnsembles:
    """One TemporalEnsemble per env slot (connection, env_index), as tavis_server keys all per-episode
    state, started afresh at each episode's first step exactly as the server's action queues are
    (tavis_server/action_queue.py); the server's EpisodeTracker makes sure the steps of an episode
    come one after another."""

    def __init__(self, coefficient):
        self.coefficient = check_coefficient(coefficient)
        self._slots = {}  # (connection, env_index) -> (episode_index, TemporalEnsemble)

    def action(self, observation, start, chunk):
        """The env's action for the observation's step from the chunk predicted at it; a new episode
        (start, or another episode_index than the slot's) starts with no earlier chunk."""
        entry = self._slots.get(observation.slot)
        if start or entry is None or entry[0] != observation.episode_index:
            entry = self._slots[observation.slot] = (observation.episode_index, TemporalEnsemble(self.coefficient))
        return entry[1].add(chunk)

    def forget(self, connection):
        """Drops the ensembles of a closed connection's env slots."""
        drop_connection(self._slots, connection)


class EnsembledServedPolicy(LeRobotServedPolicy):
    def __init__(self, policy, name, device):
        """policy: a BaselinePolicy whose config.temporal_ensemble is set (its predict_action_chunk
        then returns whole chunks)."""
        super().__init__(policy, name, device=device, torch=torch, action_queue="off")
        self.n_action_steps = None  # every row kept: row k is averaged into the step k steps on
        self.consecutive_steps = True  # every step's chunk is averaged in: every step must be asked
        self._ensembles = TemporalEnsembles(policy.config.temporal_ensemble)

    def infer(self, observations, starts):
        """(N, 1, 19): each env's ensembled action for its step, from one forward pass over all N."""
        chunks = self._infer_chunks(observations, starts)
        return np.stack([self._ensembles.action(observation, start, chunk)
                         for observation, start, chunk in zip(observations, starts, chunks)])[:, None]

    def forget(self, connection):
        super().forget(connection)
        self._ensembles.forget(connection)
