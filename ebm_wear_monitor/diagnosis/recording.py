"""One unit's recording resampled onto a common time base: the four input signals of interface.md section 2.

The diagnosis works on screw-side signals as recorded (``screw/angle`` [rad],
``screw/velocity`` [rad/s], ``axial_force`` [N], ``motor/current`` [A]) and refers
them to the motor shaft where 004 eq. 1 needs it (004 eq. 3: theta_m = i_g theta_c).

Topics need not share a rate or stamps (interface.md section 2): angle and velocity
at 2 kHz, force at 1 kHz and current at 500 Hz, each with its own phase and jitter,
is a normal recording.  The recording as read keeps each signal's own int64 ns stamps
(:class:`ebm_wear_monitor.domain.recording.Recording`); the diagnosis takes its float-seconds
view (:meth:`~ebm_wear_monitor.domain.recording.Recording.seconds`, screened by :mod:`.bags`),
and :func:`recording_from_signals` sorts and de-duplicates each
signal and interpolates every one linearly onto the stamps of ``screw/angle``, the
motion itself, within the span common to all.  The native sample interval of each
signal is kept (:attr:`Resampled.native_dt`): it bounds the timing nuisances of
:mod:`.residuals` (a signal sampled every h seconds is ambiguous in its timing by
up to h).  Time is counted from the first common stamp (float seconds keep
sub-microsecond resolution over days that way).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ebm_wear_monitor.domain.signals import DEFAULT_NAMESPACE, INPUT_TOPICS, SIGNALS
from ebm_wear_monitor.errors import InputError


@dataclass(frozen=True)
class Resampled:
    """Samples of one unit resampled on one time base (SI units, screw side as in interface.md section 2)."""

    t: np.ndarray  # sample time [s], strictly increasing
    angle: np.ndarray  # screw angle, unwrapped, apply direction positive [rad]
    velocity: np.ndarray  # screw angular velocity as recorded [rad/s]
    axial_force: np.ndarray  # axial (clamp) force reading, compressive positive [N]
    current: np.ndarray  # motor armature current [A]
    unit: str = DEFAULT_NAMESPACE
    #: median native sample interval of each signal before interpolation [s] (default: the time base's)
    native_dt: dict[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n = self.t.size
        if n < 50:
            raise InputError(f"{self.unit}: only {n} samples; the diagnosis needs at least 50")
        for name in SIGNALS:
            if getattr(self, name).shape != (n,):
                raise InputError(f"{self.unit}: signal '{name}' does not match the time base")
            if not np.all(np.isfinite(getattr(self, name))):
                raise InputError(f"{self.unit}: signal '{name}' holds non-finite values")
        if not np.all(np.diff(self.t) > 0.0):
            raise InputError(f"{self.unit}: sample times must increase strictly")

    @cached_property
    def dt(self) -> float:
        """Median sample interval of the time base [s] (computed once: the fits read it for every model)."""
        return float(np.median(np.diff(self.t)))

    def interval(self, signal: str) -> float:
        """Native sample interval of ``signal`` [s] (the time base's when not recorded)."""
        return float(self.native_dt.get(signal, self.dt))


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
                           unit: str = DEFAULT_NAMESPACE) -> Resampled:
    """Build a :class:`Resampled` from ``{signal: (stamps [s], values)}`` of one namespace.

    Signal names are those of interface.md section 4 (``angle``, ``velocity``, ``axial_force``,
    ``current``; topics in :data:`~ebm_wear_monitor.domain.signals.INPUT_TOPICS`); all four are needed
    (the twin is driven by the recorded motor current).  Signals are interpolated
    linearly onto the stamps of ``angle`` within the span common to angle, force and current.
    """
    series = {}
    for name, topic in INPUT_TOPICS.items():
        if name not in signals:
            raise InputError(f"{unit}: topic '{topic}' missing; the diagnosis needs all of "
                             f"{', '.join(INPUT_TOPICS.values())}")
        series[name] = _clean(*signals[name])
        if series[name][0].size < 2:
            raise InputError(f"{unit}: topic '{topic}' has fewer than 2 valid samples")
    # the span is that of the signals the model uses; the recorded velocity is only compared with the
    # angle's own speed (:mod:`.conventions`), held at its ends where it stops early
    used = [series[name] for name in SIGNALS if name != "velocity"]
    lo = max(s[0][0] for s in used)
    hi = min(s[0][-1] for s in used)
    base = series["angle"][0]
    base = base[(base >= lo) & (base <= hi)]
    if base.size < 2:
        raise InputError(f"{unit}: the topics share no common time span")
    values = {name: np.interp(base, *series[name]) for name in SIGNALS}
    native = {name: float(np.median(np.diff(series[name][0]))) for name in SIGNALS}
    return Resampled(base - base[0], unit=unit, native_dt=native, **values)
