"""Offline replay: recorded input topics through the monitor core's :class:`~ebm_wear_monitor.monitor.Feeder`.

The bags are streamed (:class:`~ebm_wear_monitor.bagio.BagReader`: storage
chunks decoded in bulk by the node's own decoder, ``monitor.wire``) and each
unit's batches go to its own feeder, the component the live node's timer
drives too; the core's decisions depend only on each topic's arrival order and
values, and the snapshot of each application is taken inside the core right
after it, so the replay gives the numbers the node would have published for the
same records, in memory bounded by one storage chunk whatever the length.
``motor/current`` is not read: the wear monitor does not use it (interface.md
section 2).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ebm_wear_monitor.bagio import BagReader, BagRecordings, read_ground_truth
from ebm_wear_monitor.bagio.rates import check_rates
from ebm_wear_monitor.domain.recording import Recording, Signal
from ebm_wear_monitor.domain.signals import MONITOR_SIGNALS
from ebm_wear_monitor.monitor import (
    Application,
    Batch,
    Feeder,
    MonitorConfig,
    MonitorCore,
    MonitorState,
)
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.replay.prognostics import prognostics_metrics
from ebm_wear_monitor.replay.result import APPLICATION_COLUMNS, UnitReplay
from ebm_wear_monitor.schema import from_json, table_row
from ebm_wear_monitor.schema.replay import Prognostics, ReplayDocument


@dataclass
class ReplayResult:
    """All units of one replay, the input topics skipped for a wrong type, and storage damage found."""

    units: list[UnitReplay]
    rejected: dict[str, str] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)

    def to_json_dict(self) -> dict:
        """The replay JSON of interface.md section 4 (schema/replay.py ``ReplayDocument``)."""
        return ReplayDocument([u.entry() for u in self.units], self.rejected, self.problems).to_json_dict()


class UnitRun:
    """One unit's monitor core fed batch by batch; collects the per-application history."""

    def __init__(self, unit: str, params: UnitParams, config: MonitorConfig | None = None,
                 state: MonitorState | None = None) -> None:
        self.unit = unit
        self.feeder = Feeder(MonitorCore(params, config, state))
        self.rows: list[dict] = []
        self._rated: set[str] = set()  # signals whose sample rate has been checked

    def _collect(self, events: list[Application]) -> None:
        self.rows += [table_row("applications", a.cycle, a.snapshot) for a in events]

    def feed(self, batch: Batch) -> None:
        """Queue one batch of this unit's records and collect the applications it completed.

        The first batch holding a signal (two samples or more) checks its sample rate against the
        contract (:func:`~ebm_wear_monitor.bagio.rates.check_rates`: InputError below 100 Hz).
        """
        fresh = {s: Signal(*arrays) for s, arrays in batch.signals.items()
                 if s not in self._rated and arrays[0].size >= 2}
        if fresh:
            check_rates(Recording(self.unit, fresh), fresh)
            self._rated |= set(fresh)
        self._collect(self.feeder.feed(batch))

    def finish(self, bags: Iterable[Path], truth: dict | None) -> UnitReplay:
        """End of the data: everything released; the unit's result (``truth``: its ground-truth entry)."""
        self._collect(self.feeder.finish())
        core = self.feeder.core
        applications = pd.DataFrame(self.rows, columns=list(APPLICATION_COLUMNS))
        return UnitReplay(self.unit, core.snapshot(), applications, bags=[str(b) for b in bags],
                          messages=self.feeder.messages, prognostics=judge(applications, truth), truth=truth,
                          state=core.state.to_dict())


def replay_unit(data: Recording, params: UnitParams, truth: dict | None = None, *,
                config: MonitorConfig | None = None, state: MonitorState | None = None) -> UnitReplay:
    """Run the monitor core over one unit's signals read whole (:func:`bagio.read_bags`).

    With ``state`` (an earlier replay's ``UnitReplay.state``) the core continues from it, as the node
    does after a restart: counts, wear, filter and faults carry on; the applications table holds the
    new applications only. A topic sampled below the contract's 100 Hz is refused (InputError,
    :func:`~ebm_wear_monitor.bagio.rates.check_rates`), before any work.
    """
    check_rates(data, MONITOR_SIGNALS)
    run = UnitRun(data.unit, params, config, state)
    batch = Batch({s: (sig.stamps_ns, sig.values) for s, sig in data.signals.items() if s in MONITOR_SIGNALS})
    for signal, per in data.faults.items():
        for kind, n in per.items():
            batch.count(signal, kind, n)
    run.feed(batch)
    return run.finish(data.bags, truth)


def judge(applications: pd.DataFrame, truth: dict | None) -> Prognostics | None:
    """Prognostics metrics of the median remaining life against ``truth`` (None without end of life).

    Application ``k`` of the table is application ``cycles_at_start + k`` since new.
    """
    if truth is None or truth.get("eol_cycles") is None:
        return None
    since_new = applications["index"].to_numpy(float) + float(truth.get("cycles_at_start") or 0)
    p05, p50, p95 = (applications[f"cycles_{q}"].to_numpy(float) for q in ("p05", "p50", "p95"))
    issued = np.where(np.isfinite(p95), p50, np.nan)  # with p95 unbounded a median is a bound, no forecast
    return from_json(Prognostics, prognostics_metrics(since_new, issued, float(truth["eol_cycles"]),
                                                      rul_p05=p05, rul_p95=p95))


def truth_by_namespace(units: dict[str, list[Path]] | BagRecordings) -> dict[str, dict]:
    """Ground-truth entries per unit from the sidecars of its bags (``{unit: bags}`` or BagRecordings).

    The latest bag's entry is taken, with ``cycles_at_start`` of the *first* bag:
    the replay counts applications from the start of the first bag, so
    application ``k`` of the replay is ``cycles_at_start + k`` since new.
    """
    if isinstance(units, BagRecordings):
        units = {unit: data.bags for unit, data in units.units.items()}
    truths: dict[str, dict] = {}
    for unit, bags in units.items():
        entries = [t["units"][unit] for t in map(read_ground_truth, bags) if t and unit in t["units"]]
        if entries:
            truths[unit] = {**entries[-1], "cycles_at_start": entries[0].get("cycles_at_start", 0)}
    return truths


def replay_bags(paths: Iterable, params: UnitParams, *, config: MonitorConfig | None = None,
                progress: Callable[[int], object] | None = None, total: Callable[[int], object] | None = None,
                stamps: str = "header", strict: bool = False, read_ahead: int = 2) -> ReplayResult:
    """Stream ``paths`` and replay every unit (namespace) found, in unit-name order.

    ``total(n)`` is called once with the progress units of the whole read (from the storages' own
    indexes), ``progress(n)`` after every chunk; ``stamps``/``strict``/``read_ahead`` as for
    :class:`BagReader`.
    """
    with BagReader(paths, signals=MONITOR_SIGNALS, stamps=stamps, strict=strict,
                   read_ahead=read_ahead) as reader:
        if total is not None:
            total(reader.total)
        runs = {unit: UnitRun(unit, params, config) for unit in reader.units}
        for batches in reader.batches(progress):
            for unit, batch in batches.items():
                runs[unit].feed(batch)
        truths = truth_by_namespace(reader.units)
        units = [run.finish(reader.units[unit], truths.get(unit)) for unit, run in runs.items()]
        return ReplayResult(units, dict(reader.rejected), list(reader.problems))
