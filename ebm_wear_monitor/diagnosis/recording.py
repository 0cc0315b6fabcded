"""One unit's recording on a common time base: the four input signals of interface.md section 2.

The diagnosis works on screw-side signals as recorded (``screw/angle`` [rad],
``screw/velocity`` [rad/s], ``axial_force`` [N], ``motor/current`` [A]) and refers
them to the motor shaft where 004 eq. 1 needs it (004 eq. 3: theta_m = i_g theta_c).
Bags may deliver the topics at slightly different stamps, late, duplicated or
with gaps; :func:`recording_from_signals` sorts, de-duplicates and linearly
interpolates every signal onto the stamps of ``screw/velocity``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.errors import InputError

SIGNALS = ("angle", "velocity", "axial_force", "current")
TOPIC_OF = {"angle": "screw/angle", "velocity": "screw/velocity",
            "axial_force": "axial_force", "current": "motor/current"}


@dataclass(frozen=True)
class Recording:
    """Samples of one unit on one time base (SI units, screw side as in interface.md section 2)."""

    t: np.ndarray  # sample time [s], strictly increasing
    angle: np.ndarray  # screw angle, unwrapped, apply direction positive [rad]
    velocity: np.ndarray  # screw angular velocity [rad/s]
    axial_force: np.ndarray  # axial (clamp) force, compressive positive [N]
    current: np.ndarray  # motor armature current [A]
    unit: str = "/embu"

    def __post_init__(self) -> None:
        n = self.t.size
        if n < 50:
            raise InputError(f"{self.unit}: only {n} samples; the diagnosis needs at least 50")
        for name in SIGNALS:
            if getattr(self, name).shape != (n,):
                raise InputError(f"{self.unit}: signal '{name}' does not match the time base")
        if not np.all(np.diff(self.t) > 0.0):
            raise InputError(f"{self.unit}: sample times must increase strictly")

    @property
    def dt(self) -> float:
        """Median sample interval [s]."""
        return float(np.median(np.diff(self.t)))


def _clean(stamps: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sort by stamp, drop non-finite samples and duplicate stamps (first kept)."""
    stamps = np.asarray(stamps, dtype=float)
    values = np.asarray(values, dtype=float)
    ok = np.isfinite(stamps) & np.isfinite(values)
    stamps, values = stamps[ok], values[ok]
    order = np.argsort(stamps, kind="stable")
    stamps, values = stamps[order], values[order]
    keep = np.concatenate(([True], np.diff(stamps) > 0.0))[: stamps.size]  # (an empty topic stays empty)
    return stamps[keep], values[keep]


def recording_from_signals(signals: Mapping[str, tuple[np.ndarray, np.ndarray]],
                           unit: str = "/embu") -> Recording:
    """Build a :class:`Recording` from ``{signal: (stamps [s], values)}`` of one namespace.

    Signal names are those of interface.md section 4 (``angle``, ``velocity``,
    ``axial_force``, ``current``; topics in :data:`TOPIC_OF`); all four are needed
    (the twin is driven by the recorded motor current).  Signals are interpolated
    linearly onto the stamps of ``velocity`` within the span common to all.
    """
    series = {}
    for name, topic in TOPIC_OF.items():
        if name not in signals:
            raise InputError(f"{unit}: topic '{topic}' missing; the diagnosis needs all of "
                             f"{', '.join(TOPIC_OF.values())}")
        series[name] = _clean(*signals[name])
        if series[name][0].size < 2:
            raise InputError(f"{unit}: topic '{topic}' has fewer than 2 valid samples")
    base = series["velocity"][0]
    lo = max(s[0][0] for s in series.values())
    hi = min(s[0][-1] for s in series.values())
    base = base[(base >= lo) & (base <= hi)]
    values = {name: np.interp(base, *series[name]) for name in SIGNALS}
    return Recording(base, unit=unit, **values)
