"""LeRobot's delta_timestamps padding rule (tavis_baseline/windows.py), on hand-made indices.

The rule: for row i of an episode whose rows are [start, end) and frame offset d, the query is
i + d; the row used is the query clamped into [start, end - 1], and `_is_pad` is true exactly when
the query falls outside [start, end)."""

import pytest
import torch

from tavis_baseline.windows import delta_offsets, window_indices


def test_windows_clamp_to_the_episode_and_mark_padding():
    # One episode of rows [10, 15); rows at its start, middle and end.
    frames = torch.tensor([10, 12, 14])
    start = torch.tensor([10, 10, 10])
    end = torch.tensor([15, 15, 15])
    indices, is_pad = window_indices(frames, start, end, [-2, 0, 1, 3])
    assert indices.tolist() == [[10, 10, 11, 13],
                                [10, 12, 13, 14],
                                [12, 14, 14, 14]]
    assert is_pad.tolist() == [[True, False, False, False],
                               [False, False, False, True],
                               [False, False, True, True]]


def test_windows_never_cross_into_a_neighbouring_episode():
    # Rows 4 (last of episode [0, 5)) and 5 (first of episode [5, 9)).
    indices, is_pad = window_indices(torch.tensor([4, 5]), torch.tensor([0, 5]), torch.tensor([5, 9]), [-1, 1])
    assert indices.tolist() == [[3, 4], [5, 6]]
    assert is_pad.tolist() == [[False, True], [True, False]]


def test_delta_timestamps_become_frame_offsets():
    assert delta_offsets([-0.1, 0.0, 0.05], 20) == [-2, 0, 1]
    with pytest.raises(ValueError, match="0.03"):
        delta_offsets([0.03], 20)
