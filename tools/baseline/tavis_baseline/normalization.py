"""Mean/std normalisation constants from a dataset's meta/stats.json.

Two edits, both for stability:
- quaternion dimensions of the action (left wxyz 3-6, right wxyz 10-13) are left unnormalised
  (mean 0, std 1), as the reference's fix_quat_stats does: their values are already O(1) and a
  near-constant component would otherwise be blown up;
- a dimension whose std is below `min_std` (a joint that never moves in the demonstrations, e.g.
  GR1T2's neck roll) gets std `min_std`, so that noise in it cannot become a huge input.
"""

import numpy as np

QUATERNION_ACTION_DIMS = (3, 4, 5, 6, 10, 11, 12, 13)


def mean_std(stats, key, size, min_std, unnormalised=(), where="meta/stats.json"):
    """where: the stats file, for the messages."""
    if not isinstance(stats.get(key), dict) or "mean" not in stats[key] or "std" not in stats[key]:
        raise ValueError(f"{where} has no mean/std for {key!r}")
    try:
        mean = np.asarray(stats[key]["mean"], np.float64).reshape(-1)
        std = np.asarray(stats[key]["std"], np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: the mean/std of {key!r} are not lists of numbers") from None
    if mean.size != size or std.size != size:
        raise ValueError(f"{where}: {key!r} has {mean.size} means / {std.size} stds, the data has {size} dims")
    std = np.maximum(std, min_std)
    for dim in unnormalised:
        mean[dim], std[dim] = 0.0, 1.0
    return mean.astype(np.float32), std.astype(np.float32)
