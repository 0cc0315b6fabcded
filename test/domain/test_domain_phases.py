"""The phase vocabulary (domain.phases): interface.md's names, the codes on disk."""

from __future__ import annotations

import json
from pathlib import Path

from ebm_wear_monitor.domain.phases import APPLICATION_PHASES, PHASE_NAMES, PHASES, Phase

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

