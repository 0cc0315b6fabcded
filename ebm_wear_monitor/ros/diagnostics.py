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

* ERROR: remaining-life status ``due`` (the clearance reached the limit, or p05 at or below the
  unit file's ``monitor.due_cycles``): known from the data already integrated, so it is said
  even when the inputs have stopped;
* STALE: an input has never arrived or has been silent longer than ``stale_timeout_s``;
* ERROR: the core failed on a batch;
* WARN: status ``warn`` (p05 at or below ``monitor.warn_cycles``), an input slower than
  ``min_input_rate_hz``, or new input faults since the previous report;
* OK otherwise, including status ``insufficient_data`` (said in the message).

The remaining-life part of the level is the core's status (monitor/life.py), so
the node, ``ebm-wear replay`` and ``ebm-wear fleet`` say the same thing.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from ebm_wear_monitor.monitor import STATUS_DUE, STATUS_INSUFFICIENT, STATUS_WARN

#: the ROS levels (one-byte ``bytes`` in rclpy)
OK, WARN, ERROR, STALE = (DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR,
                          DiagnosticStatus.STALE)


@dataclass(frozen=True)
class Thresholds:
    """Health thresholds (ROS parameters of the same names, changeable at run time)."""

    stale_timeout_s: float  # [s]
    min_input_rate_hz: float  # [Hz]


@dataclass(frozen=True)
class Health:
    """What :func:`assess` looks at, all SI."""

    life_status: str  # remaining-life status of the core: ok | warn | due | insufficient_data
    life_text: str  # its people-facing description (monitor.life.describe_life)
    input_rate_hz: Mapping[str, float]  # per input topic, over the last period
    input_age_s: Mapping[str, float]  # per input topic, time since the last message; inf = never
    new_faults: int  # input faults counted since the previous report
    core_error: str = ""  # last exception of the core, empty when none


def assess(h: Health, t: Thresholds) -> tuple[bytes, str]:
    """Level and one-line message of a unit's status (module docstring lists the rules)."""
    stale = sorted(k for k, age in h.input_age_s.items() if not age <= t.stale_timeout_s)
    if h.life_status == STATUS_DUE:  # known from the data already integrated: said even when inputs stop
        quiet = "; no recent input on " + ", ".join(stale) if stale else ""
        return ERROR, "remaining life " + h.life_text + quiet
    if stale:
        return STALE, "no recent input on " + ", ".join(stale)
    if h.core_error:
        return ERROR, "monitor core failed: " + h.core_error
    warnings = []
    if h.life_status == STATUS_WARN:
        warnings.append("remaining life " + h.life_text)
    slow = sorted(k for k, r in h.input_rate_hz.items() if r < t.min_input_rate_hz)
    if slow:
        warnings.append("slow input on " + ", ".join(slow))
    if h.new_faults:
        warnings.append(f"{h.new_faults} new input faults")
    if warnings:
        return WARN, "; ".join(warnings)
    if h.life_status == STATUS_INSUFFICIENT:
        return OK, "remaining life " + h.life_text
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
