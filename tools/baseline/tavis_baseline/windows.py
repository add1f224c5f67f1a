"""LeRobot's delta_timestamps windows, as frame offsets, with its padding rule at episode edges.

LeRobot (LeRobotDataset._get_query_indices) turns each delta timestamp d into a frame offset
round(d * fps). For the frame at absolute index i of an episode whose rows are [start, end):

    query  = i + offset
    index  = min(max(query, start), end - 1)      # clamped into the episode
    is_pad = query < start or query >= end        # `<key>_is_pad`

so a window that reaches before the episode repeats its first frame, one that reaches past the end
repeats its last frame, and the mask says which entries are such copies. Policies ignore padded
action targets in their loss; padded observations are kept (they are the repeated first frame).
"""

import torch


def delta_offsets(delta_timestamps, fps, tolerance_s=1e-4):
    """Frame offsets of `delta_timestamps` (seconds); ValueError if one is not on a frame."""
    offsets = []
    for delta in delta_timestamps:
        offset = round(delta * fps)
        if abs(offset / fps - delta) > tolerance_s:
            raise ValueError(f"delta timestamp {delta} s is not a multiple of 1/{fps} s")
        offsets.append(offset)
    return offsets


def window_indices(frames, episode_start, episode_end, offsets):
    """(indices, is_pad) for absolute frame indices `frames` (int64 tensor, shape (B,)).

    episode_start / episode_end: per-frame tensors of the episode's first row and one past its last
    (shape (B,)); offsets: a list of K ints. Returns two (B, K) tensors: the clamped row indices
    and the padding mask.
    """
    offsets = torch.as_tensor(offsets, dtype=torch.int64, device=frames.device)
    query = frames[:, None] + offsets[None, :]
    start = episode_start[:, None]
    end = episode_end[:, None]
    is_pad = (query < start) | (query >= end)
    indices = torch.minimum(torch.maximum(query, start), end - 1)
    return indices, is_pad
