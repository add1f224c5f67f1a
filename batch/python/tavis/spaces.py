"""Observation and action spaces: Gymnasium's when it is installed, else small stand-ins with the
same attributes (shape, dtype, low, high, spaces), sample() and contains(), so code that reads
``env.single_action_space.shape`` works without Gymnasium (Debian has none)."""

import numpy as np

try:
    from gymnasium import spaces as _gymnasium_spaces
    from gymnasium.vector.utils import batch_space as _gymnasium_batch_space
except ImportError:
    _gymnasium_spaces = None
    _gymnasium_batch_space = None


class Box:
    """An array of `shape` and `dtype` with every entry in [low, high] (Gymnasium's Box)."""

    def __init__(self, low, high, shape, dtype, seed=None):
        self.shape = tuple(int(n) for n in shape)
        self.dtype = np.dtype(dtype)
        self.low = np.full(self.shape, low, dtype=self.dtype)
        self.high = np.full(self.shape, high, dtype=self.dtype)
        self.np_random = np.random.default_rng(seed)

    def seed(self, seed=None):
        self.np_random = np.random.default_rng(seed)
        return [seed]

    def sample(self):
        if self.dtype.kind in "ui":
            return self.np_random.integers(self.low, self.high, size=self.shape, dtype=self.dtype, endpoint=True)
        # Unbounded entries are drawn from a standard normal, as Gymnasium's Box does.
        values = self.np_random.standard_normal(self.shape)
        bounded = np.isfinite(self.low) & np.isfinite(self.high)
        values[bounded] = self.np_random.uniform(self.low[bounded], self.high[bounded])
        return values.astype(self.dtype)

    def contains(self, x):
        x = np.asarray(x)
        return (x.shape == self.shape and np.can_cast(x.dtype, self.dtype)
                and bool(np.all(x >= self.low)) and bool(np.all(x <= self.high)))

    __contains__ = contains

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


class Dict:
    """A dict of spaces, one per key (Gymnasium's Dict)."""

    def __init__(self, spaces):
        self.spaces = dict(spaces)
        self.shape = None
        self.dtype = None

    def seed(self, seed=None):
        for offset, space in enumerate(self.spaces.values()):
            space.seed(None if seed is None else seed + offset)
        return [seed]

    def sample(self):
        return {key: space.sample() for key, space in self.spaces.items()}

    def contains(self, x):
        return (isinstance(x, dict) and x.keys() == self.spaces.keys()
                and all(space.contains(x[key]) for key, space in self.spaces.items()))

    __contains__ = contains

    def __getitem__(self, key):
        return self.spaces[key]

    def keys(self):
        return self.spaces.keys()

    def __repr__(self):
        return "Dict(" + ", ".join(f"{key!r}: {space!r}" for key, space in self.spaces.items()) + ")"


def box(low, high, shape, dtype):
    if _gymnasium_spaces is not None:
        return _gymnasium_spaces.Box(low, high, shape, dtype)
    return Box(low, high, shape, dtype)


def dict_space(spaces):
    if _gymnasium_spaces is not None:
        return _gymnasium_spaces.Dict(spaces)
    return Dict(spaces)


def batch_space(space, n):
    """The space of n stacked samples of `space` (Gymnasium's batch_space for Box and Dict)."""
    if _gymnasium_batch_space is not None:
        return _gymnasium_batch_space(space, n)
    if isinstance(space, Dict):
        return Dict({key: batch_space(sub, n) for key, sub in space.spaces.items()})
    batched = Box(0, 0, (n, *space.shape), space.dtype)
    batched.low = np.broadcast_to(space.low, batched.shape).copy()
    batched.high = np.broadcast_to(space.high, batched.shape).copy()
    return batched
