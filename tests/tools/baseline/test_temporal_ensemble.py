"""Temporal ensembling (tavis_baseline/temporal_ensemble.py): its arithmetic against a hand-computed
example, and its per-env, per-episode state as the server keeps it (ensembled_serving.py)."""

import math

import numpy as np
import pytest

from tavis_baseline.config import BaselineConfig
from tavis_baseline.ensembled_serving import TemporalEnsembles
from tavis_baseline.temporal_ensemble import TemporalEnsemble
from tavis_server.observations import EnvObservation

# Chunks of 3 rows of 1-dim actions, one predicted at each step 0..3.
CHUNKS = [[[1.0], [2.0], [3.0]], [[10.0], [20.0], [30.0]], [[100.0], [200.0], [300.0]], [[5.0], [6.0], [7.0]]]


def test_each_step_is_the_weighted_mean_of_every_chunks_row_for_it_oldest_weighted_most():
    ensemble = TemporalEnsemble(0.5)
    actions = [float(ensemble.add(np.array(chunk))[0]) for chunk in CHUNKS]
    w1, w2 = math.exp(-0.5), math.exp(-1.0)  # the weights of the chunks 1 and 2 after the oldest
    expected = [1.0,                                            # step 0: chunk 0's row 0
                (2.0 + w1 * 10.0) / (1 + w1),                   # step 1: chunk 0's row 1, chunk 1's row 0
                (3.0 + w1 * 20.0 + w2 * 100.0) / (1 + w1 + w2),  # step 2: rows 2, 1, 0 of chunks 0, 1, 2
                (30.0 + w1 * 200.0 + w2 * 5.0) / (1 + w1 + w2)]  # step 3: chunk 0 has no row 3 any more
    np.testing.assert_allclose(actions, expected, rtol=1e-6)
    assert actions[1] == pytest.approx(5.0203, abs=1e-4)  # (2 + 0.60653 * 10) / 1.60653, by hand


def test_m_zero_is_the_plain_mean_and_reset_forgets():
    ensemble = TemporalEnsemble(0)
    for chunk in CHUNKS[:3]:
        action = ensemble.add(np.array(chunk))
    assert action[0] == pytest.approx((3.0 + 20.0 + 100.0) / 3)
    ensemble.reset()
    assert ensemble.add(np.array(CHUNKS[3]))[0] == 5.0


def test_a_batch_of_envs_is_ensembled_env_by_env():
    ensemble = TemporalEnsemble(0.01)
    first = np.stack([np.array(CHUNKS[0]), np.array(CHUNKS[1])])  # (2 envs, 3 rows, 1)
    second = np.stack([np.array(CHUNKS[2]), np.array(CHUNKS[3])])
    ensemble.add(first)
    action = ensemble.add(second)
    w = math.exp(-0.01)
    np.testing.assert_allclose(action[:, 0], [(2.0 + w * 100.0) / (1 + w), (20.0 + w * 5.0) / (1 + w)], rtol=1e-6)
    with pytest.raises(ValueError, match="shape"):
        ensemble.add(np.zeros((2, 4, 1)))


def observation(env, episode, step, connection=0):
    return EnvObservation(env_index=env, episode_index=episode, step=step, is_first=step == 0, task="", arrays={},
                          connection=connection)


def test_the_servers_ensembles_start_afresh_at_each_episode_and_are_kept_per_slot():
    ensembles = TemporalEnsembles(0.0)
    chunk = [np.array(c) for c in CHUNKS]
    assert ensembles.action(observation(0, 0, 0), True, chunk[0])[0] == 1.0
    assert ensembles.action(observation(1, 0, 0), True, chunk[2])[0] == 100.0  # another env: its own
    assert ensembles.action(observation(0, 0, 0, connection=1), True, chunk[3])[0] == 5.0  # another client
    assert ensembles.action(observation(0, 0, 1), False, chunk[1])[0] == pytest.approx((2.0 + 10.0) / 2)
    # Env 0's next episode: nothing of the last one is averaged in.
    assert ensembles.action(observation(0, 1, 0), True, chunk[2])[0] == 100.0
    ensembles.forget(0)
    assert ensembles.action(observation(0, 0, 1, connection=1), False, chunk[1])[0] == pytest.approx((6.0 + 10.0) / 2)


@pytest.mark.parametrize("bad", [-0.1, float("nan"), float("inf"), True, "0.01"])
def test_bad_coefficients_are_refused_by_name(bad):
    with pytest.raises(ValueError, match="temporal_ensemble"):
        BaselineConfig(executed_steps=1, temporal_ensemble=bad)


def test_temporal_ensembling_needs_a_forward_pass_every_step():
    with pytest.raises(ValueError, match="executed_steps must be 1, got 4"):
        BaselineConfig(executed_steps=4, temporal_ensemble=0.01)
    config = BaselineConfig(executed_steps=1, temporal_ensemble=0.01)
    assert config.chunk_execution.startswith("temporal ensembling (m = 0.01)")
    with pytest.raises(ValueError):
        config.n_action_steps = 4
    assert config.executed_steps == 1 and config.temporal_ensemble == 0.01  # unchanged
    config.execute_with(4, None)
    assert config.chunk_execution.startswith("queue of 4 rows")
