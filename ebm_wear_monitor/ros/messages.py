"""The monitor core's results as ``ebm_wear_msgs`` messages, generated from the result schema.

No field is named here: which record field fills which message field is declared once in
:mod:`ebm_wear_monitor.schema.monitor` (``msg``; the ``/diagnostics`` key-values come from its
``diag`` through :func:`ebm_wear_monitor.schema.diagnostic_values`). ``CycleSummary`` -> ``DutyCycle``,
``MonitorSnapshot`` -> ``WearState`` / ``RemainingLife`` (field meanings and units in
``msg_defs/msg/*.msg``). Conversions by the message field's type: ``builtin_interfaces/Time``
from int64 ns, a status constant ``STATUS_<VALUE>`` for a text value in an integer field, NaN for
an unknown number (``None`` in the core), never a made-up number.
"""

from __future__ import annotations

import math
from typing import Any

from builtin_interfaces.msg import Time
from ebm_wear_msgs.msg import DutyCycle, Float64Stamped, RemainingLife, WearState

from ebm_wear_monitor.schema import Record, message_fields
from ebm_wear_monitor.schema.monitor import CycleSummary, MonitorSnapshot

__all__ = ["DutyCycle", "Float64Stamped", "RemainingLife", "WearState", "duty_cycle", "fill",
           "remaining_life", "stamp", "wear_state"]


def stamp(ns: int | None) -> Time:
    """``builtin_interfaces/Time`` of a stamp in int64 ns (zero time when unknown)."""
    if ns is None:
        return Time()
    sec, nanosec = divmod(int(ns), 1_000_000_000)
    return Time(sec=sec, nanosec=nanosec)


def _convert(msg: Any, name: str, value: object) -> object:
    """``value`` in the type of field ``name`` of ``msg`` (module docstring)."""
    current = getattr(msg, name)
    if isinstance(current, Time):
        return stamp(value)  # type: ignore[arg-type]
    if isinstance(value, str) and isinstance(current, int):
        return getattr(type(msg), f"STATUS_{value.upper()}")
    if isinstance(current, float):
        return math.nan if value is None else float(value)  # type: ignore[arg-type]
    return list(value) if isinstance(value, tuple) else value


def fill(msg: Any, record: Record) -> Any:
    """``msg`` with every field the schema maps from ``record`` set (dotted names: nested fields)."""
    for path, value in message_fields(record, type(msg).__name__):
        *parents, name = path.split(".")
        target = msg
        for part in parents:
            target = getattr(target, part)
        setattr(target, name, _convert(target, name, value))
    return msg


def duty_cycle(c: CycleSummary) -> DutyCycle:
    """One completed brake application; header stamp = its end (back at rest)."""
    return fill(DutyCycle(), c)


def wear_state(s: MonitorSnapshot) -> WearState:
    """Cumulative wear and filtered clearance; header stamp = end of the last integrated segment."""
    return fill(WearState(), s)


def remaining_life(s: MonitorSnapshot) -> RemainingLife:
    """Wear life (p05/p50/p95 applications to the clearance limit) beside the ISO 3408-5 fatigue life."""
    return fill(RemainingLife(), s)

