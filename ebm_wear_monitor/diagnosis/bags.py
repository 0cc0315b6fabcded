"""Recordings from bags on disk, screened as the monitor screens its input (``ebm-wear diagnose``, self-test).

Per unit (namespace) of the bags: a topic sampled below the contract's 100 Hz is refused
(:func:`~ebm_wear_monitor.bagio.rates.check_rates`); samples with a non-finite stamp or value, or
beyond the monitor's physical bounds (``absurd``:
:func:`~ebm_wear_monitor.monitor.alignment.absurd_limits`), are dropped and counted, never fitted.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ebm_wear_monitor.bagio import read_bags
from ebm_wear_monitor.bagio.rates import check_rates
from ebm_wear_monitor.diagnosis.recording import Resampled, recording_from_signals
from ebm_wear_monitor.domain.recording import Recording
from ebm_wear_monitor.domain.signals import SIGNALS
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor import MonitorConfig
from ebm_wear_monitor.monitor.alignment import absurd_limits


@dataclass(frozen=True)
class UnitRecording:
    """One unit's screened recording, what was dropped from it, and its raw data (for ``--life``)."""

    recording: Resampled
    faults: dict[str, dict[str, int]]  # {signal: {kind: samples dropped}}
    data: Recording  # the unit's recording as read (int64 ns stamps per signal)

    @property
    def fault_totals(self) -> dict[str, int]:
        kinds = sorted({k for f in self.faults.values() for k in f})
        return {k: sum(f.get(k, 0) for f in self.faults.values()) for k in kinds}


def screen(signals: dict, limits: dict[str, float]) -> tuple[dict, dict[str, dict[str, int]]]:
    """Drop and count unusable samples: ``{signal: (stamps, values)}`` kept, ``{signal: {kind: n}}``.

    ``non_finite``: stamp or value NaN/inf; ``absurd``: |value| above ``limits[signal]`` (signals
    without a limit, the motor current, are only checked for finiteness).
    """
    kept, faults = {}, {}
    for name, (stamps, values) in signals.items():
        stamps, values = np.asarray(stamps, float), np.asarray(values, float)
        finite = np.isfinite(stamps) & np.isfinite(values)
        absurd = finite & (np.abs(values) > limits.get(name, np.inf))
        counts = {"non_finite": int(np.count_nonzero(~finite)), "absurd": int(np.count_nonzero(absurd))}
        faults[name] = {k: v for k, v in counts.items() if v}
        ok = finite & ~absurd
        kept[name] = (stamps[ok], values[ok])
    return kept, {k: v for k, v in faults.items() if v}


def recordings_from_bags(paths: Sequence[str | Path], progress: Callable[[int], object] | None = None
                         ) -> dict[str, UnitRecording]:
    """Every unit of the bags as a screened :class:`UnitRecording`, by namespace (module docstring)."""
    data = read_bags([Path(p) for p in paths], progress=progress)
    if not data.units:
        raise InputError("no unit with input topics found in the bags")
    limits = absurd_limits(MonitorConfig())
    out = {}
    for name, ud in sorted(data.units.items()):
        check_rates(ud, SIGNALS)
        signals, faults = screen(ud.seconds(), limits)
        out[name] = UnitRecording(recording_from_signals(signals, unit=name), faults, ud)
    return out
