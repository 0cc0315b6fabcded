"""Conversion of the monitor core's results into ``ebm_wear_msgs`` messages and diagnostic key-values.

Pure field mapping, no computation: ``CycleSummary`` -> ``DutyCycle``,
``MonitorSnapshot`` -> ``WearState`` / ``RemainingLife`` (field meanings and
units in ``msg_defs/msg/*.msg``). Unknown values (``None`` in the core) become
NaN in the messages, never a made-up number.
"""

from __future__ import annotations

import math
from typing import Any

from builtin_interfaces.msg import Time
from ebm_wear_msgs.msg import DutyCycle, Float64Stamped, RemainingLife, WearState

from ebm_wear_monitor.monitor import (
    STATUS_DUE,
    STATUS_INSUFFICIENT,
    STATUS_OK,
    STATUS_WARN,
    CycleSummary,
    MonitorSnapshot,
)

__all__ = ["DutyCycle", "Float64Stamped", "RemainingLife", "WearState", "diagnostic_values", "duty_cycle",
           "remaining_life", "stamp", "wear_state"]

_LIFE_STATUS = {STATUS_OK: RemainingLife.STATUS_OK, STATUS_WARN: RemainingLife.STATUS_WARN,
                STATUS_DUE: RemainingLife.STATUS_DUE,
                STATUS_INSUFFICIENT: RemainingLife.STATUS_INSUFFICIENT_DATA}


def stamp(ns: int | None) -> Time:
    """``builtin_interfaces/Time`` of a stamp in int64 ns (zero time when unknown)."""
    if ns is None:
        return Time()
    sec, nanosec = divmod(int(ns), 1_000_000_000)
    return Time(sec=sec, nanosec=nanosec)


def _num(value: float | None) -> float:
    return math.nan if value is None else float(value)


def duty_cycle(c: CycleSummary) -> DutyCycle:
    """One completed brake application; header stamp = its end (back at rest)."""
    msg = DutyCycle(index=c.index, start=stamp(c.start_ns), peak_force_n=c.peak_force_n,
                    peak_speed_rad_s=c.peak_speed_rad_s, stroke_rad=c.stroke_rad,
                    screw_wear_m=list(c.screw_wear_m), nut_wear_m=list(c.nut_wear_m),
                    ball_wear_m=list(c.ball_wear_m), clearance_observed_m=c.clearance_observed_m,
                    clearance_observed_std_m=c.clearance_observed_std_m,
                    clearance_estimate_m=c.clearance_estimate_m)
    (msg.clearance_elimination_s, msg.force_generation_s, msg.force_maintenance_s,
     msg.force_release_s) = c.phase_durations_s
    msg.header.stamp = stamp(c.end_ns)
    return msg


def wear_state(s: MonitorSnapshot) -> WearState:
    """Cumulative wear and filtered clearance; header stamp = end of the last integrated segment."""
    msg = WearState(duty_cycles=s.duty_cycles, observations=s.observations, screw_raceway_m=s.wear_screw_m,
                    nut_raceway_m=s.wear_nut_m,
                    ball_m=s.wear_ball_m, clearance_model_m=s.clearance_model_m,
                    clearance_estimate_m=s.clearance_estimate_m, clearance_std_m=s.clearance_std_m,
                    wear_rate_factor=s.wear_rate_factor, wear_rate_factor_std=s.wear_rate_factor_std,
                    growth_rate_m_per_cycle=s.growth_rate_m_per_cycle,
                    growth_rate_std_m_per_cycle=s.growth_rate_std_m_per_cycle)
    msg.header.stamp = stamp(s.last_stamp_ns)
    return msg


def remaining_life(s: MonitorSnapshot) -> RemainingLife:
    """Wear life (p05/p50/p95 applications to the clearance limit) beside the ISO 3408-5 fatigue life."""
    msg = RemainingLife(status=_LIFE_STATUS[s.life_status], limit_m=s.limit_m,
                        clearance_estimate_m=s.clearance_estimate_m, cycles_p05=_num(s.cycles_p05),
                        cycles_p50=_num(s.cycles_p50), cycles_p95=_num(s.cycles_p95),
                        seconds_p05=_num(s.seconds_p05), seconds_p50=_num(s.seconds_p50),
                        seconds_p95=_num(s.seconds_p95), usage_span_s=_num(s.usage_span_s),
                        growth_rate_m_per_cycle=s.growth_rate_m_per_cycle,
                        growth_rate_std_m_per_cycle=s.growth_rate_std_m_per_cycle,
                        hours_p50=_num(s.hours_p50), applications_per_hour=_num(s.applications_per_hour),
                        fatigue_l10_revolutions=_num(s.fatigue_l10_revolutions),
                        fatigue_cubic_mean_load_n=_num(s.fatigue_cubic_mean_load_n),
                        fatigue_remaining_cycles=_num(s.fatigue_remaining_cycles),
                        limiting_mechanism=s.limiting_mechanism)
    msg.header.stamp = stamp(s.last_stamp_ns)
    return msg


def diagnostic_values(s: MonitorSnapshot) -> dict[str, Any]:
    """Key-values of the unit's diagnostic status: wear, clearance, remaining life, fatigue, faults."""
    return {
        "duty_cycles": s.duty_cycles,
        "wear_screw_raceway_m": s.wear_screw_m, "wear_nut_raceway_m": s.wear_nut_m,
        "wear_ball_m": s.wear_ball_m,
        "clearance_model_m": s.clearance_model_m, "clearance_estimate_m": s.clearance_estimate_m,
        "clearance_std_m": s.clearance_std_m, "clearance_limit_m": s.limit_m,
        "wear_rate_factor": s.wear_rate_factor, "wear_rate_factor_std": s.wear_rate_factor_std,
        "remaining_life_status": s.life_status, "remaining_cycles_p05": _num(s.cycles_p05),
        "remaining_cycles_p50": _num(s.cycles_p50), "remaining_cycles_p95": _num(s.cycles_p95),
        "remaining_seconds_p05": _num(s.seconds_p05), "remaining_seconds_p50": _num(s.seconds_p50),
        "remaining_seconds_p95": _num(s.seconds_p95), "usage_span_s": _num(s.usage_span_s),
        "growth_rate_m_per_cycle": s.growth_rate_m_per_cycle,
        "growth_rate_std_m_per_cycle": s.growth_rate_std_m_per_cycle,
        "clearance_steps": s.clearance_steps, "growth_changes": s.growth_changes,
        "remaining_hours_p50": _num(s.hours_p50), "fatigue_l10_revolutions": _num(s.fatigue_l10_revolutions),
        "fatigue_remaining_cycles": _num(s.fatigue_remaining_cycles),
        "limiting_mechanism": s.limiting_mechanism, "pending_samples": s.pending_samples,
    } | {f"fault_{k}": v for k, v in s.input_faults.items()} | {
        f"segments_{k}": v for k, v in s.segments.items()}
