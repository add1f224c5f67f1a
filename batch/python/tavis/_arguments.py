"""Argument checks for the public API: a wrong type raises a one-line TypeError naming the
argument, instead of pybind11's dump of the C++ signature ("incompatible constructor arguments.
The following argument types are supported: ...")."""

import os

import numpy as np

MAX_SEED = 2**64 - 1
# The largest value a C++ int takes (counts and sizes): beyond it pybind11 would refuse the
# argument with its dump of the signature.
MAX_C_INT = 2**31 - 1


def _shown(value):
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def require_int(name, value, minimum=None, maximum=None):
    """``value`` as an int (a Python or numpy integer, not a bool), within [minimum, maximum]."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__} {_shown(value)}")
    value = int(value)
    if (minimum is not None and value < minimum) or (maximum is not None and value > maximum):
        low = "" if minimum is None else f" from {minimum}"
        high = "" if maximum is None else f" to {maximum}"
        raise ValueError(f"{name} must be an int{low}{high}, got {value}")
    return value


def require_bool(name, value):
    """A bool (or numpy bool): not a truthy int or string, which would be a guess."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be a bool, got {type(value).__name__} {_shown(value)}")
    return bool(value)


def require_str(name, value):
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a str, got {type(value).__name__} {_shown(value)}")
    return value


def require_path(name, value):
    """A str or os.PathLike, as a str."""
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{name} must be a path (str or os.PathLike), got {type(value).__name__} {_shown(value)}")
    return os.fspath(value)


def require_str_list(name, value):
    """A list or tuple of str (not one str, which would be taken letter by letter)."""
    if isinstance(value, str) or not isinstance(value, (list, tuple)):
        raise TypeError(f"{name} must be a list of str, got {type(value).__name__} {_shown(value)}")
    for item in value:
        if not isinstance(item, str):
            raise TypeError(f"{name} must be a list of str, got an item {type(item).__name__} {_shown(item)}")
    return list(value)
