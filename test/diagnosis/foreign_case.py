"""A recording of the independently written foreign generator (``validation/foreign``), written as a bag
and diagnosed from disk like a user's (test helper)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from ebm_wear_monitor.diagnosis.bags import recordings_from_bags
from ebm_wear_monitor.diagnosis.pipeline import diagnose_recording
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.schema.diagnose import DiagnosisResult
from ebm_wear_monitor.validation.foreign import case_set, write_case


def foreign_diagnosis(draw: str, case_id: str, tmp_path: Path, n_apps: int | None = None) -> DiagnosisResult:
    """Case ``case_id`` of the case set ``draw`` (``n_apps`` applications, else the case's own number),
    diagnosed against the nominal unit file."""
    case = next(c for c in case_set(draw) if c.case_id == case_id)
    if n_apps is not None:
        case = dataclasses.replace(case, n_apps=n_apps)
    bag = write_case(case, tmp_path)
    rec = next(iter(recordings_from_bags([bag]).values())).recording
    return diagnose_recording(rec, load_unit())
