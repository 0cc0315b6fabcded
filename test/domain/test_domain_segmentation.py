"""The segmenter's shared rules (domain.segmentation): classification, labels, runs and cycle index against
the documented table and plain loops."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.domain.phases import PHASE_NAMES, Phase
from ebm_wear_monitor.domain.segmentation import (
    BACKWARD,
    FORWARD,
    STOPPED,
    Labels,
    classify,
    cycle_index,
    phase_of,
    run_ids,
    run_starts,
    runs,
)


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
def test_cycle_index_counts_the_starts_against_a_loop(seed):
    rng = np.random.default_rng(seed)
    n = 100
    starts = np.sort(rng.choice(n, rng.integers(0, 10), replace=False))
    assert cycle_index(starts, n).tolist() == [sum(s <= i for s in starts) for i in range(n)]


def test_labels_count_the_cycles():
    phase, cycle = _random_labels(0)
    assert Labels(phase, cycle).n_cycles == len(set(cycle.tolist())) == cycle[-1] + 1
    assert Labels(np.empty(0, np.int8), np.empty(0, np.int32)).n_cycles == 0


# the table of domain/segmentation's docstring, written out by phase name (000 Fig. 2, 004 eq. 5/9)
_DOCUMENTED = {
    ("forward", False): "clearance_elimination", ("forward", True): "force_generation",
    ("stopped", False): "idle", ("stopped", True): "force_maintenance",
    ("backward", False): "force_release", ("backward", True): "force_release",
}
_DIRECTION = {"forward": 1, "stopped": 0, "backward": -1}


def test_phase_of_gives_the_documented_phases():
    for (direction, contact), name in _DOCUMENTED.items():
        assert phase_of(_DIRECTION[direction], contact).label == name
        assert int(phase_of(_DIRECTION[direction], contact)) == list(PHASE_NAMES).index(name)
    assert (FORWARD, STOPPED, BACKWARD) == (1, 0, -1)


def test_classify_is_phase_of_per_sample_and_idle_without_direction():
    rng = np.random.default_rng(0)
    direction = rng.integers(-1, 3, 300)  # 2: no direction (the offline mode's NaN speed)
    contact = rng.random(300) < 0.5
    phase = classify(direction, contact)
    assert phase.dtype == np.int8
    names = [PHASE_NAMES[p] for p in phase]
    expected = [_DOCUMENTED.get((d, bool(c)), "idle") for d, c in
                zip([{1: "forward", 0: "stopped", -1: "backward"}.get(int(d)) for d in direction], contact,
                    strict=True)]
    assert names == expected
