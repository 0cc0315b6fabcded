"""Recordings of the third world (``validation/third``), written as bags with its CLI and scored from
disk by the foreign self-test's scorer, like a user's (test helper)."""

from __future__ import annotations

from pathlib import Path

from ebm_wear_monitor.diagnosis.foreign_selftest import run_third
from ebm_wear_monitor.schema.diagnose import ForeignSelftest
from ebm_wear_monitor.validation.third.__main__ import main as write_world


def third_diagnosis(out: Path, seed: int, *case_ids: str, jobs: int = 1) -> ForeignSelftest:
    """The cases ``case_ids`` of the third world's draw ``seed``, written to ``out`` and scored."""
    if write_world(["write", "--out", str(out), "--seed", str(seed), "--only", ",".join(case_ids),
                    "--jobs", str(jobs)]) != 0:
        raise RuntimeError(f"the third world did not write {case_ids} of seed {seed}")
    return run_third(out, jobs=jobs)
