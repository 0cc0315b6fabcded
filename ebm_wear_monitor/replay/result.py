"""What a replay of one unit yields: the interface.md section 4 entry plus the per-application history."""

from __future__ import annotations

from dataclasses import dataclass, field

import pandas as pd

#: columns of the per-application table (one row per completed brake application), SI units
APPLICATION_COLUMNS: dict[str, str] = {
    "index": "application count since the unit was new [-]",
    "stamp_s": "end of the application (back at rest) [s]",
    "screw_raceway_m": "cumulative wear depth of the screw raceway [m]",
    "nut_raceway_m": "cumulative wear depth of the nut raceway [m]",
    "ball_m": "cumulative wear depth (radius loss) of the balls [m]",
    "clearance_model_m": "axial clearance x_ag predicted by the wear model [m]",
    "clearance_observed_m": "axial clearance x_ag observed in this application, NaN if not observable [m]",
    "clearance_observed_std_m": "its 1-sigma error budget (observation.py), NaN if not observable [m]",
    "clearance_estimate_m": "Kalman-filtered axial clearance x_ag [m]",
    "clearance_std_m": "one standard deviation of the estimate [m]",
    "cycles_p05": "remaining brake applications to the clearance limit, 5th percentile [-]",
    "cycles_p50": "... median [-]",
    "cycles_p95": "... 95th percentile [-]",
    "life_status": "remaining-life status after this application: ok | warn | due | insufficient_data",
    "growth_rate_m_per_cycle": "learned clearance growth per application after this one [m]",
    "growth_rate_std_m_per_cycle": "its 1-sigma [m]",
    "peak_force_n": "peak axial force of the application [N]",
    "screw_wear_increment_m": "wear depth of the screw raceway added by this application [m]",
    "nut_wear_increment_m": "... of the nut raceway [m]",
    "ball_wear_increment_m": "... of the balls [m]",
    "wear_rate_factor": "learned clearance growth over the wear model's mean growth per application [-]",
}


@dataclass
class UnitReplay:
    """Result of running the monitor core over one unit's recordings."""

    unit: str
    #: the unit's entry of interface.md section 4 (keys unit, duty_cycles, wear, clearance,
    #: remaining_life, input_faults)
    summary: dict
    #: one row per completed application, columns APPLICATION_COLUMNS
    applications: pd.DataFrame
    bags: list[str] = field(default_factory=list)
    messages: int = 0
    #: prognostics metrics against the simulator's ground truth (replay.prognostics), None without truth
    prognostics: dict | None = None
    #: the ground-truth entry of this unit (bagio.sidecar schema), None without truth
    truth: dict | None = None
    #: the monitor core's persistent state at the end (MonitorState.to_dict()), to continue later
    state: dict | None = None

    def to_json_dict(self) -> dict:
        """Section 4 entry plus ``bags``, ``messages`` and, with ground truth, ``prognostics`` and
        ``ground_truth`` (its ``eol_cycles`` and ``cycles_at_start``)."""
        out = {**self.summary, "unit": self.unit, "bags": self.bags, "messages": self.messages}
        if self.prognostics is not None:
            out["prognostics"] = self.prognostics
            out["ground_truth"] = {k: self.truth.get(k) for k in ("eol_cycles", "cycles_at_start")}
        return out
