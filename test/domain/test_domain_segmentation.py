"""The segmentation vocabulary (domain.segmentation): labels, runs and cycle index against plain loops."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.domain.phases import Phase
from ebm_wear_monitor.domain.segmentation import Labels, run_ids, run_starts, runs, starts_up_to


def _random_labels(seed: int, n: int = 200) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    phase = rng.choice(np.array(list(Phase), np.int8), n, p=[0.1, 0.1, 0.1, 0.1, 0.6])
    phase = np.repeat(phase, rng.integers(1, 4, n))[:n]
    cycle = np.cumsum(rng.random(n) < 0.05).astype(np.int32)
    return phase, cycle


def _brute_runs(phase, cycle):
    ids, last = [], None
    for key in zip(cycle, phase, strict=True):
        ids.append(0 if last is None else ids[-1] + (key != last))
        last = key
    return ids


@pytest.mark.parametrize("seed", range(5))
def test_run_ids_and_starts_against_a_loop(seed):
    phase, cycle = _random_labels(seed)
    n = phase.size
    ids = run_ids(phase, cycle)
    assert ids.tolist() == _brute_runs(phase.tolist(), cycle.tolist())
    assert run_starts(ids).tolist() == [i for i in range(n) if i == 0 or ids[i] != ids[i - 1]]
    assert run_starts(np.empty(0)).size == 0


@pytest.mark.parametrize("seed", range(5))
def test_runs_rebuild_the_sequence(seed):
    phase, _ = _random_labels(seed)
    starts, lengths = runs(phase)
    assert lengths.sum() == phase.size and np.all(lengths > 0)
    assert np.array_equal(np.repeat(phase[starts], lengths), phase)
    assert np.all(phase[starts[1:]] != phase[starts[1:] - 1])


@pytest.mark.parametrize("seed", range(5))
def test_starts_up_to_counts_against_a_loop(seed):
    rng = np.random.default_rng(seed)
    n = 100
    starts = np.sort(rng.choice(n, rng.integers(0, 10), replace=False))
    assert starts_up_to(starts, n).tolist() == [sum(s <= i for s in starts) for i in range(n)]


def test_labels_count_the_cycles():
    phase, cycle = _random_labels(0)
    assert Labels(phase, cycle).n_cycles == len(set(cycle.tolist())) == cycle[-1] + 1
    assert Labels(np.empty(0, np.int8), np.empty(0, np.int32)).n_cycles == 0
