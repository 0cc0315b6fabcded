"""A small diagnostic updater: one ``DiagnosticStatus`` per unit on ``/diagnostics``.

``diagnostic_updater`` is not available as a wheel here, so this module does
its job for the wear monitor: at a fixed period it publishes a
``diagnostic_msgs/DiagnosticArray`` holding one status named with the node's
fully qualified name (``/train7/car3/embu2/wear_monitor``), the unit's
namespace as ``hardware_id``, a level and key-values (wear, clearance,
remaining life, input rates, staleness, fault counts). The ``/`` separators of
the name give the train > car > EMBU tree that ``config/diagnostic_aggregator.yaml``
and robot monitors display.

Levels (ROS convention), decided by :func:`assess`, worst first:

* STALE: an input has never arrived or has been silent longer than ``stale_timeout_s``;
* ERROR: the clearance estimate reached the unit's limit, or the core failed on a batch;
* WARN: clearance above ``clearance_warn_fraction`` of the limit, p05 remaining
  applications below ``remaining_cycles_warn``, an input slower than
  ``min_input_rate_hz``, or new input faults since the previous report;
* OK otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

#: the ROS levels (one-byte ``bytes`` in rclpy)
OK, WARN, ERROR, STALE = (DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR,
                          DiagnosticStatus.STALE)


@dataclass(frozen=True)
class Thresholds:
    """Health thresholds (ROS parameters of the same names, changeable at run time)."""

    stale_timeout_s: float  # [s]
    min_input_rate_hz: float  # [Hz]
    clearance_warn_fraction: float  # [-] of the clearance limit
    remaining_cycles_warn: float  # [-] p05 brake applications


@dataclass(frozen=True)
class Health:
    """What :func:`assess` looks at, all SI; NaN where unknown."""

    clearance_estimate_m: float
    clearance_limit_m: float
    cycles_p05: float
    input_rate_hz: Mapping[str, float]  # per input topic, over the last period
    input_age_s: Mapping[str, float]  # per input topic, time since the last message; inf = never
    new_faults: int  # input faults counted since the previous report
    core_error: str = ""  # last exception of the core, empty when none


def assess(h: Health, t: Thresholds) -> tuple[bytes, str]:
    """Level and one-line message of a unit's status (module docstring lists the rules)."""
    stale = sorted(k for k, age in h.input_age_s.items() if not age <= t.stale_timeout_s)
    if stale:
        return STALE, "no recent input on " + ", ".join(stale)
    if h.core_error:
        return ERROR, "monitor core failed: " + h.core_error
    if h.clearance_estimate_m >= h.clearance_limit_m:
        return ERROR, (f"clearance {h.clearance_estimate_m:.4g} m reached the limit "
                       f"{h.clearance_limit_m:.4g} m")
    warnings = []
    if h.clearance_estimate_m >= t.clearance_warn_fraction * h.clearance_limit_m:
        warnings.append(f"clearance {h.clearance_estimate_m:.4g} m above "
                        f"{t.clearance_warn_fraction:g} of the limit")
    if h.cycles_p05 < t.remaining_cycles_warn:
        warnings.append(f"p05 remaining life {h.cycles_p05:.4g} applications")
    slow = sorted(k for k, r in h.input_rate_hz.items() if r < t.min_input_rate_hz)
    if slow:
        warnings.append("slow input on " + ", ".join(slow))
    if h.new_faults:
        warnings.append(f"{h.new_faults} new input faults")
    if warnings:
        return WARN, "; ".join(warnings)
    return OK, "ok"


def _text(value: object) -> str:
    if isinstance(value, float):
        return "nan" if math.isnan(value) else f"{value:.9g}"
    return str(value)


def unit_status(name: str, hardware_id: str, level: bytes, message: str,
                values: Mapping[str, object]) -> DiagnosticStatus:
    """One ``DiagnosticStatus``; ``values`` become key-values (floats to 9 significant digits)."""
    return DiagnosticStatus(level=level, name=name, message=message, hardware_id=hardware_id,
                            values=[KeyValue(key=k, value=_text(v)) for k, v in values.items()])


def diagnostic_array(stamp, statuses: list[DiagnosticStatus]) -> DiagnosticArray:
    """The ``/diagnostics`` message (``stamp``: a ``builtin_interfaces/Time``)."""
    msg = DiagnosticArray(status=statuses)
    msg.header.stamp = stamp
    return msg


def namespace_parts(namespace: str) -> dict[str, str]:
    """``/train7/car3/embu2`` -> {"train": "train7", "car": "car3", "embu": "embu2"} (absent parts omitted).

    The last namespace segment is the EMBU, the one before it the car, the one
    before that the train: the layout ``config/diagnostic_aggregator.yaml`` groups by.
    """
    parts = [p for p in namespace.split("/") if p]
    return dict(zip(("embu", "car", "train"), reversed(parts), strict=False))
