"""The phase vocabulary (domain.phases): interface.md's names, the codes on disk, run helpers."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from ebm_wear_monitor.domain.phases import APPLICATION_PHASES, PHASE_NAMES, PHASES, Phase, run_ids, run_starts

REPO = Path(__file__).resolve().parents[2]
SPEC = REPO.parent.parent / "shared" / "spec" / "interface.md"


def test_names_are_interface_md_section_4s():
    # interface.md section 4: "Phase names: clearance_elimination, force_generation, force_maintenance,
    # force_release (the four phases of 000, Fig. 2)"
    assert PHASES == ("clearance_elimination", "force_generation", "force_maintenance", "force_release")
    assert (*PHASES, "idle") == PHASE_NAMES
    assert [p.label for p in APPLICATION_PHASES] == list(PHASES)
    assert Phase.IDLE not in APPLICATION_PHASES and len(Phase) == 5
    if SPEC.is_file():  # the shared spec beside the repository (not in a fresh clone)
        text = " ".join(SPEC.read_text(encoding="utf-8").split())
        assert "Phase names: " + ", ".join(f"`{p}`" for p in PHASES) in text


def test_codes_are_those_the_committed_bags_ground_truth_uses():
    # bags/healthy was written by the twin before the vocabulary moved here: its sidecar names the codes
    truth = json.loads((REPO / "bags" / "healthy" / "ground_truth.json").read_text(encoding="utf-8"))
    unit = next(iter(truth["units"].values()))
    assert tuple(unit["phase_names"]) == PHASE_NAMES
    assert [int(Phase[n.upper()]) for n in unit["phase_names"]] == list(range(len(Phase)))


def _brute_runs(phase, cycle):
    ids, last = [], None
    for key in zip(cycle, phase, strict=True):
        ids.append(0 if last is None else ids[-1] + (key != last))
        last = key
    return ids


@pytest.mark.parametrize("seed", range(5))
def test_run_ids_and_starts_against_a_loop(seed):
    rng = np.random.default_rng(seed)
    n = 200
    phase = rng.choice(np.array(list(Phase), np.int8), n, p=[0.1, 0.1, 0.1, 0.1, 0.6])
    phase = np.repeat(phase, rng.integers(1, 4, n))[:n]
    cycle = np.cumsum(rng.random(n) < 0.05).astype(np.int32)
    ids = run_ids(phase, cycle)
    assert ids.tolist() == _brute_runs(phase.tolist(), cycle.tolist())
    assert run_starts(ids).tolist() == [i for i in range(n) if i == 0 or ids[i] != ids[i - 1]]
    assert run_starts(np.empty(0)).size == 0
