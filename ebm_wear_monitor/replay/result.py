"""What a replay of one unit yields: the interface.md section 4 entry plus the per-application history.

The entry's layout, and the per-application table's columns, are declared in
:mod:`ebm_wear_monitor.schema` (``ReplayEntry``; ``CycleSummary`` and ``MonitorSnapshot`` columns
of the ``applications`` table); this module only holds the values.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import pandas as pd

from ebm_wear_monitor.schema import table_columns
from ebm_wear_monitor.schema.monitor import CycleSummary, MonitorSnapshot
from ebm_wear_monitor.schema.replay import GroundTruth, Prognostics, ReplayEntry

#: columns of the per-application table (one row per completed brake application): description [unit]
APPLICATION_COLUMNS: dict[str, str] = table_columns("applications", CycleSummary, MonitorSnapshot)


@dataclass
class UnitReplay:
    """Result of running the monitor core over one unit's recordings."""

    unit: str  # namespace (replay) or folder relative to the fleet root
    snapshot: MonitorSnapshot  # the core's totals at the end of the data
    #: one row per completed application, columns APPLICATION_COLUMNS
    applications: pd.DataFrame
    bags: list[str] = field(default_factory=list)
    messages: int = 0
    #: prognostics metrics against the simulator's ground truth (replay.prognostics), None without truth
    prognostics: Prognostics | None = None
    #: the ground-truth entry of this unit (bagio.sidecar schema), None without truth
    truth: dict | None = None
    #: the monitor core's persistent state at the end (MonitorState.to_dict()), to continue later
    state: dict | None = None

    def entry(self) -> ReplayEntry:
        """The typed section 4 entry; ``ground_truth`` (eol_cycles, cycles_at_start) beside prognostics."""
        truth = None
        if self.prognostics is not None and self.truth is not None:
            truth = GroundTruth(self.truth.get("eol_cycles"), self.truth.get("cycles_at_start"))
        return ReplayEntry(self.unit, self.snapshot, self.bags, self.messages, self.prognostics, truth)

    def to_json_dict(self) -> dict:
        """The section 4 entry as JSON (schema/replay.py ``ReplayEntry``)."""
        return self.entry().to_json_dict()
