"""Run-time claiming of the fast kernels' parts: every part exactly once, whatever the order."""

import numpy as np
import pytest
from numba import njit

from corneasim.solver.elements._schedule import claim_part


@njit(cache=True)
def _claim_in_order(n_parts, nt, thread_sequence):
    """Let the threads claim in the given order (one claim per entry, a finished thread's
    entries are skipped) until all are done; returns how often each part was taken and by
    whom (the last taker)."""
    claimed = np.zeros((nt + 1) // 2, np.int64)
    taken = np.zeros(nt, np.int64)
    done = np.zeros(nt, np.bool_)
    count = np.zeros(n_parts, np.int64)
    owner = np.full(n_parts, -1, np.int64)
    k = 0
    while not done.all():
        t = thread_sequence[k % thread_sequence.size]
        k += 1
        if done[t]:
            continue
        p = claim_part(claimed, t, nt, n_parts, taken[t])
        if p < 0:
            done[t] = True
            continue
        taken[t] += 1
        count[p] += 1
        owner[p] = t
    return count, owner


@pytest.mark.parametrize("nt", [1, 2, 3, 4, 5, 8])
@pytest.mark.parametrize("n_parts", [1, 2, 5, 8])
def test_every_part_is_claimed_exactly_once_in_any_interleaving(nt, n_parts):
    rng = np.random.default_rng(nt * 10 + n_parts)
    for _ in range(50):
        sequence = rng.integers(0, nt, 200)
        count, owner = _claim_in_order(n_parts, nt, sequence)
        assert np.all(count == 1)
        assert np.all(owner >= 0)


def test_a_stalled_thread_leaves_its_share_to_its_partner():
    """Thread 1 claims nothing until thread 0 is done: thread 0 then runs all of the range,
    front to back."""
    sequence = np.array([0] * 20 + [1] * 20)
    count, owner = _claim_in_order(8, 2, sequence)
    assert np.all(count == 1) and np.all(owner == 0)


def test_two_threads_at_the_same_pace_take_the_two_halves():
    count, owner = _claim_in_order(8, 2, np.array([0, 1]))
    assert np.all(count == 1)
    assert list(owner) == [0, 0, 0, 0, 1, 1, 1, 1]
