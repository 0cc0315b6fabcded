"""MonitorState: everything the monitor must remember across restarts, as plain JSON-able values.

Only quantities that summarise *completed* segments are kept (cumulative wear,
applications, the clearance tracker (its anchor filter bank and last records, tracker.py),
fatigue sums, fault counts), plus the
stamp up to which data was integrated: a resumed monitor drops samples at or
before it, so replaying data it has already seen can never count wear twice.
A brake application in progress at a crash is lost, never half counted: the
resumed wear is never above the truth and is short by at most the
applications since the last checkpoint.

Version 2 (issue 11) replaced the two-state filter ``filter_x`` / ``filter_P``
([x_ag, f]) and ``rejections_in_row`` by ``tracker``. A version-1 state is
migrated on load (:func:`MonitorState.from_dict`): its clearance and wear-rate
factor become the prior of the new filter bank, every other value is kept.
Version 3 (issue 14) renamed ``wear_screw_m``/``wear_nut_m``/``wear_ball_m`` to the results'
names ``screw_raceway_m``/``nut_raceway_m``/``ball_m``; older states are migrated on load.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields
from typing import Any

from ebm_wear_monitor.monitor.kalman import COMPONENTS, Bank
from ebm_wear_monitor.monitor.tracker import Record

STATE_VERSION = 3
#: version 3 names the wear depths as the results do (schema/monitor.py); version 2 keys -> version 3
_V2_NAMES = {"wear_screw_m": "screw_raceway_m", "wear_nut_m": "nut_raceway_m", "wear_ball_m": "ball_m"}


class StateError(ValueError):
    """A state mapping is malformed (wrong version, missing key, wrong type, non-finite number)."""


@dataclass
class MonitorState:
    """Persistent state of one unit's monitor. Lengths in m, stamps in int ns since the epoch."""

    unit_name: str = ""
    unit_digest: str = ""  # UnitParams.digest() of the parameters that produced it
    duty_cycles: int = 0  # completed brake applications
    segments: dict[str, int] = field(default_factory=dict)  # closed segments per kind
    screw_raceway_m: float = 0.0  # cumulative wear depth of the screw raceway [m]
    nut_raceway_m: float = 0.0  # ... nut raceway [m]
    ball_m: float = 0.0  # ... balls [m]
    tracker: dict[str, Any] | None = None  # ClearanceTracker.to_dict(); None before the first application
    observations: int = 0  # clearance observations made (finite ones handed to the filter)
    clearance_steps: int = 0  # steps of the clearance detected (tracker.py)
    growth_changes: int = 0  # changes of the growth rate detected (tracker.py)
    model_clearance_at_filter_m: float | None = None  # model clearance at the last filter step [m]
    sum_f3_rot: float = 0.0  # sum |F|^3 |d theta| [N^3 rad] (ISO 3408-5 cubic-mean load)
    sum_rot_rad: float = 0.0  # sum |d theta| [rad]
    first_cycle_ns: int | None = None  # start of the first completed application [ns]
    last_cycle_ns: int | None = None  # start of the last completed application [ns] (usage rate)
    last_stamp_ns: int | None = None  # end of the last closed segment [ns]: data up to it is integrated
    input_faults: dict[str, dict[str, int]] = field(default_factory=dict)  # per topic (and "stream")
    force_baseline_n: float = 0.0  # rest level (offset) of the force sensor [N], segmentation.py
    force_lag_weight: float = 0.0  # pooled force-sensor lag, observation.py: sum 1/var [1/s^2]
    force_lag_weighted_sum: float = 0.0  # ... sum tau/var [1/s]
    version: int = STATE_VERSION

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Any) -> MonitorState:
        """Validate and build; raises :class:`StateError` with the offending key."""
        if not isinstance(data, dict):
            raise StateError("state is not a mapping")
        if data.get("version") == 1:
            data = _migrate_v1(data)
        if data.get("version") == 2:
            data = {_V2_NAMES.get(k, k): v for k, v in data.items()} | {"version": STATE_VERSION}
        if data.get("version") != STATE_VERSION:
            raise StateError(f"unsupported state version {data.get('version')!r} (expected {STATE_VERSION})")
        unknown = set(data) - {f.name for f in fields(cls)}
        if unknown:
            raise StateError(f"unknown state key(s): {', '.join(sorted(unknown))}")
        state = cls(**data)
        for name in ("duty_cycles", "observations", "clearance_steps", "growth_changes"):
            v = getattr(state, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 0:
                raise StateError(f"{name}: expected a count, got {v!r}")
        for name in ("screw_raceway_m", "nut_raceway_m", "ball_m", "sum_f3_rot", "sum_rot_rad"):
            v = getattr(state, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
                raise StateError(f"{name}: expected a finite number >= 0, got {v!r}")
        for name in ("force_baseline_n", "force_lag_weighted_sum", "force_lag_weight"):
            b = getattr(state, name)
            if isinstance(b, bool) or not isinstance(b, (int, float)) or not math.isfinite(b):
                raise StateError(f"{name}: expected a finite number, got {b!r}")
        if state.force_lag_weight < 0.0:
            raise StateError(f"force_lag_weight: expected >= 0, got {state.force_lag_weight!r}")
        for name in ("first_cycle_ns", "last_cycle_ns", "last_stamp_ns"):
            v = getattr(state, name)
            if v is not None and (isinstance(v, bool) or not isinstance(v, int)):
                raise StateError(f"{name}: expected integer nanoseconds or null, got {v!r}")
        if state.tracker is not None:
            _check_tracker(state.tracker)
        if not isinstance(state.segments, dict) or not isinstance(state.input_faults, dict):
            raise StateError("segments and input_faults must be mappings")
        for counts in [state.segments, *state.input_faults.values()]:
            if not isinstance(counts, dict) or not all(
                    isinstance(n, int) and n >= 0 for n in counts.values()):
                raise StateError("segments and input_faults must map names to counts")
        return state


def _check_tracker(tracker: Any) -> None:
    """StateError unless ``tracker`` is ClearanceTracker.to_dict() (or a migrated version-1 filter)."""
    if isinstance(tracker, dict) and set(tracker) == {"legacy_filter"}:
        return
    if not isinstance(tracker, dict) or set(tracker) != {"anchor", "records"}:
        raise StateError("tracker must be a mapping with 'anchor' and 'records'")
    try:
        Bank.from_dict(tracker["anchor"], COMPONENTS)
        if not isinstance(tracker["records"], list):
            raise ValueError("tracker records must be a list")
        for item in tracker["records"]:
            Record.from_list(item)
    except (KeyError, TypeError, ValueError) as exc:
        raise StateError(f"tracker: {exc}") from None


def _migrate_v1(data: dict[str, Any]) -> dict[str, Any]:
    """A version-1 state as version 2 (then migrated to 3): the [x_ag, f] filter becomes
    ``legacy_filter`` (the prior of the new bank, core.py), ``rejections_in_row`` is dropped."""
    data = dict(data)
    x, P = data.pop("filter_x", None), data.pop("filter_P", None)
    data.pop("rejections_in_row", None)
    if x is not None:
        ok = (isinstance(x, list) and len(x) == 2 and isinstance(P, list) and len(P) == 2
              and all(isinstance(r, list) and len(r) == 2 for r in P)
              and all(isinstance(v, (int, float)) and math.isfinite(v) for v in [*x, *P[0], *P[1]]))
        if not ok:
            raise StateError("version-1 filter_x must be 2 finite numbers and filter_P a finite 2x2 matrix")
        data["tracker"] = {"legacy_filter": {"x": x, "P": P}}
    data["version"] = 2
    return data
