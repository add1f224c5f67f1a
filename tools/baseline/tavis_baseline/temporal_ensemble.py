"""ACT's temporal ensembling (Zhao et al. 2023), a way to execute predicted chunks: a forward pass at
every policy step, and each step's action the weighted mean of every chunk's prediction for that
step (the chunk of the pass k steps ago predicts it in its row k), the oldest chunk weighted 1 and
the i-th after it exp(-m * i). m = 0.01 (ACT's) weights a chunk 19 steps newer 0.83; m = 0 is the
plain mean; a larger m follows the newer passes more. The arithmetic is float64 numpy, the same on
every machine: the ensembled actions are a function of the chunks alone.

TemporalEnsemble keeps the chunks of one env (or of one batch of envs stepped together, as LeRobot's
select_action does); ensembled_serving.py keeps one per env slot of tavis_server."""

import collections
import math

import numpy as np

DEFAULT_COEFFICIENT = 0.01


def check_coefficient(value, what="temporal_ensemble"):
    """`value` if it is a finite number >= 0, else ValueError naming it."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 <= value < math.inf:
        raise ValueError(f"{what} {value!r} must be a finite number >= 0 (ACT's m, e.g. {DEFAULT_COEFFICIENT})")
    return float(value)


class TemporalEnsemble:
    def __init__(self, coefficient):
        self.coefficient = check_coefficient(coefficient)
        self._chunks = collections.deque()  # the chunks of the last chunk_size steps, oldest first

    def reset(self):
        self._chunks.clear()

    def add(self, chunk):
        """This step's action (..., A) float32, given the chunk (..., H, A) predicted at this step."""
        chunk = np.asarray(chunk, dtype=np.float64)
        if self._chunks and self._chunks[-1].shape != chunk.shape:
            raise ValueError(f"a chunk of shape {chunk.shape} after chunks of {self._chunks[-1].shape}")
        self._chunks.append(chunk)
        if len(self._chunks) > chunk.shape[-2]:  # the pass chunk_size steps ago has no row for this step
            self._chunks.popleft()
        count = len(self._chunks)
        rows = np.stack([old[..., count - 1 - i, :] for i, old in enumerate(self._chunks)])  # oldest first
        weights = np.exp(-self.coefficient * np.arange(count))
        return np.tensordot(weights / weights.sum(), rows, axes=1).astype(np.float32)
