"""The simulator's ground truth stored beside a bag's data (``<bag>/ground_truth.json``).

A bag written by the digital twin may carry the truth the monitor is trying to
estimate, so replay and fleet reports can judge the remaining-life estimate
with the standard prognostics metrics (``replay.prognostics``). Schema (JSON,
SI units; keys beyond these are kept and ignored)::

    {"units": {"<namespace, e.g. /embu>": {
        "clearance_limit_m": float,   # x_ag at which the unit is due (the RUL threshold) [m]
        "eol_cycles": float,          # true brake-application count (since new) at which x_ag
                                      # reaches clearance_limit_m, from the simulator's own wear
                                      # law, extrapolated when the simulation stops earlier [-]
        "cycles_at_start": int,       # applications the unit had done before this bag [-]
        "clearance_m": [float, ...],  # optional: true x_ag after each application in the bag [m]
        "effects": {...}              # optional: injected effects/faults and their sizes
    }}}

Rosbag2 readers only open the files listed in ``metadata.yaml``, so the extra
file never disturbs ``ros2 bag`` or rosbags.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from ebm_wear_monitor.errors import InputError

GROUND_TRUTH_FILE = "ground_truth.json"


def read_ground_truth(bag: str | os.PathLike) -> dict | None:
    """The ground truth stored with ``bag`` as a dict (schema above), or None when the bag has none."""
    path = Path(bag) / GROUND_TRUTH_FILE
    if not path.is_file():
        return None
    try:
        truth = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: unreadable ground truth: {exc}") from exc
    if not isinstance(truth, dict) or not isinstance(truth.get("units"), dict):
        raise InputError(f"{path}: ground truth has no 'units' mapping")
    for unit, entry in truth["units"].items():
        if not isinstance(entry, dict):
            raise InputError(f"{path}: ground truth of {unit} is not a mapping")
        for key in ("eol_cycles", "cycles_at_start", "clearance_limit_m"):
            value = entry.get(key)
            if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))):
                raise InputError(f"{path}: ground truth {unit} {key}: expected a number, got {value!r}")
    return truth
