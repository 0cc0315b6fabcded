"""Offline replay: recorded input topics through :class:`~ebm_wear_monitor.monitor.MonitorCore`, unchanged.

The live node and the replay share the monitor core and the bulk CDR decoder
(``bagio.cdr``), and the core is chunk-invariant (its decisions depend on
per-topic arrival order and values only), so a replay gives the numbers the
node would have published for the same messages.

The samples are fed in windows of ``HISTORY_WINDOW_S`` of header-stamp time
(per topic, by the running maximum of its stamps, so late messages stay in
arrival order); after each window that completed a brake application the
core's snapshot gives the remaining-life distribution and cumulative wear for
the per-application history (as the node publishes them after each
processing tick). A brake application lasts longer than a window, so no
window completes two; if one ever did, only its last application gets the
snapshot's values and the others NaN, never copied numbers. ``motor/current`` is
not fed: the wear monitor does not use it (interface.md section 2).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ebm_wear_monitor.bagio import Recording, UnitData, read_bags, read_ground_truth
from ebm_wear_monitor.bagio.rates import check_rates
from ebm_wear_monitor.monitor import (
    SIGNALS,
    CycleSummary,
    MonitorConfig,
    MonitorCore,
    MonitorSnapshot,
    MonitorState,
)
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.replay.prognostics import prognostics_metrics
from ebm_wear_monitor.replay.result import APPLICATION_COLUMNS, UnitReplay

#: header-stamp time fed to the core between two snapshots [s]
HISTORY_WINDOW_S = 0.25
_STAMP_CLIP = 1e12  # [s]; keeps window keys of absurd or non-finite stamps representable


@dataclass
class ReplayResult:
    """All units of one replay, and the input topics skipped for a wrong type."""

    units: list[UnitReplay]
    rejected: dict[str, str] = field(default_factory=dict)

    def to_json_dict(self) -> dict:
        """The replay JSON of interface.md section 4 (plus ``rejected_topics``)."""
        return {"units": [u.to_json_dict() for u in self.units], "rejected_topics": self.rejected}


def _window_bounds(data: UnitData, window_s: float) -> dict[str, np.ndarray]:
    """Per signal, the end index of each window (the same windows for every signal)."""
    keys = {}
    for name in SIGNALS:
        if name in data.signals:
            stamps = data.signals[name].stamps
            run = np.fmax.accumulate(stamps) if len(stamps) else np.empty(0)
            run = np.clip(np.nan_to_num(run, nan=-_STAMP_CLIP), -_STAMP_CLIP, _STAMP_CLIP)
            keys[name] = np.floor(run / window_s).astype(np.int64)
    edges = np.unique(np.concatenate(list(keys.values()) or [np.empty(0, np.int64)]))
    return {name: np.searchsorted(k, edges, side="right") for name, k in keys.items()}


def _row(cycle: CycleSummary, snap: MonitorSnapshot | None) -> dict:
    row = {"index": cycle.index, "stamp_s": cycle.end_s, "clearance_model_m": cycle.clearance_model_m,
           "clearance_observed_m": cycle.clearance_observed_m,
           "clearance_estimate_m": cycle.clearance_estimate_m, "clearance_std_m": cycle.clearance_std_m,
           "peak_force_n": cycle.peak_force_n,
           "screw_wear_increment_m": sum(cycle.screw_wear_m), "nut_wear_increment_m": sum(cycle.nut_wear_m),
           "ball_wear_increment_m": sum(cycle.ball_wear_m), "wear_rate_factor": cycle.wear_rate_factor}
    for key, attr in (("screw_raceway_m", "wear_screw_m"), ("nut_raceway_m", "wear_nut_m"),
                      ("ball_m", "wear_ball_m"), ("cycles_p05", "cycles_p05"), ("cycles_p50", "cycles_p50"),
                      ("cycles_p95", "cycles_p95")):
        value = getattr(snap, attr) if snap is not None else None
        row[key] = math.nan if value is None else float(value)
    return row


def replay_unit(data: UnitData, params: UnitParams, truth: dict | None = None, *,
                config: MonitorConfig | None = None, progress: Callable[[int], object] | None = None,
                window_s: float = HISTORY_WINDOW_S, state: MonitorState | None = None) -> UnitReplay:
    """Run the monitor core over one unit's signals; ``truth`` is its ground-truth entry (bagio.sidecar).

    With ``state`` (an earlier replay's ``UnitReplay.state``) the core continues from it, as the node
    does after a restart: counts, wear, filter and faults carry on; the applications table holds the
    new applications only. A topic sampled below the contract's 100 Hz is refused (InputError,
    :func:`~ebm_wear_monitor.bagio.rates.check_rates`), before any work.
    """
    check_rates(data, SIGNALS)
    core = MonitorCore(params, config, state)
    bounds = _window_bounds(data, window_s)
    n_windows = len(next(iter(bounds.values()), []))
    start = dict.fromkeys(bounds, 0)
    rows: list[dict] = []
    for w in range(n_windows):
        fed = 0
        for name, ends in bounds.items():
            a, b = start[name], ends[w]
            if b > a:
                sig = data.signals[name]
                core.add(name, sig.stamps[a:b], sig.values[a:b])
                fed += b - a
            start[name] = b
        cycles = core.process(final=w == n_windows - 1)
        if cycles:
            snap = core.snapshot()
            rows += [_row(c, snap if i == len(cycles) - 1 else None) for i, c in enumerate(cycles)]
        if progress is not None and fed:
            progress(fed)
    if not n_windows:
        core.process(final=True)
    applications = pd.DataFrame(rows, columns=list(APPLICATION_COLUMNS))
    result = UnitReplay(data.unit, {"unit": data.unit, **core.snapshot().to_json_dict()}, applications,
                        bags=[str(b) for b in data.bags], messages=data.messages, truth=truth,
                        state=core.state.to_dict())
    result.prognostics = judge(applications, truth)
    return result


def judge(applications: pd.DataFrame, truth: dict | None) -> dict | None:
    """Prognostics metrics of the median remaining life against ``truth`` (None without end of life).

    Application ``k`` of the table is application ``cycles_at_start + k`` since new.
    """
    if truth is None or truth.get("eol_cycles") is None:
        return None
    since_new = applications["index"].to_numpy(float) + float(truth.get("cycles_at_start") or 0)
    rul = applications["cycles_p50"].to_numpy(float)
    return prognostics_metrics(since_new, rul, float(truth["eol_cycles"]))


def truth_by_namespace(recording: Recording) -> dict[str, dict]:
    """Ground-truth entries per unit from the bags' sidecars.

    The latest bag's entry is taken, with ``cycles_at_start`` of the *first* bag:
    the replay counts applications from the start of the first bag, so
    application ``k`` of the replay is ``cycles_at_start + k`` since new.
    """
    truths: dict[str, dict] = {}
    for unit, data in recording.units.items():
        entries = [t["units"][unit] for t in map(read_ground_truth, data.bags) if t and unit in t["units"]]
        if entries:
            truths[unit] = {**entries[-1], "cycles_at_start": entries[0].get("cycles_at_start", 0)}
    return truths


def replay_bags(paths: Iterable, params: UnitParams, *, config: MonitorConfig | None = None,
                read_progress: Callable[[int], object] | None = None,
                progress: Callable[[int], object] | None = None) -> ReplayResult:
    """Read ``paths`` and replay every unit (namespace) found, in unit-name order."""
    recording = read_bags(paths, progress=read_progress)
    truths = truth_by_namespace(recording)
    units = [replay_unit(data, params, truths.get(ns), config=config, progress=progress)
             for ns, data in recording.units.items()]
    return ReplayResult(units, dict(recording.rejected))
