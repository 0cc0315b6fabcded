"""The monitor core's results, each quantity declared once: :class:`CycleSummary`, :class:`MonitorSnapshot`.

Every output of the node, the replay and the fleet is generated from these declarations
(:mod:`.fields`): the replay/fleet JSON entry of interface.md section 4 (``json``), the
``DutyCycle``, ``WearState`` and ``RemainingLife`` messages of ``msg_defs/msg/`` (``msg``), the
``/diagnostics`` key-values (``diag``), and the columns of the fleet's ``units.parquet``
(``units``) and of the per-application table (``applications``). Names: the Python attribute is
interface.md's JSON name where the contract names the quantity (``screw_raceway_m``, not
``wear_screw_m``); the other spellings are the fixed message fields and the historical
diagnostics keys and table columns, kept so that no reader breaks, and declared here only.
SI units throughout; an unknown number is None (null in JSON, NaN in messages, keys and tables).
"""

from __future__ import annotations

import json
from dataclasses import dataclass

from ebm_wear_monitor.schema.fields import Column, Record, quantity

STATUS_OK = "ok"
STATUS_WARN = "warn"
STATUS_DUE = "due"
STATUS_INSUFFICIENT = "insufficient_data"
#: remaining-life statuses (interface.md section 4; semantics in monitor/life.py)
STATUSES = (STATUS_OK, STATUS_WARN, STATUS_DUE, STATUS_INSUFFICIENT)
#: what limits the life first (monitor/life.py ``limiting_mechanism``)
MECHANISMS = ("wear", "fatigue", "unknown")

_STAMP = "header.stamp"
_WEAR, _LIFE, _CYCLE = "WearState", "RemainingLife", "DutyCycle"


def _seconds(ns: int) -> float:
    return ns * 1e-9


def _text(value: object) -> str:
    return json.dumps(value, sort_keys=True)


def _total(counts: dict[str, int]) -> int:
    return sum(counts.values())


@dataclass(frozen=True)
class CycleSummary(Record):
    """One completed brake application (the ``DutyCycle`` message, a row of the applications table)."""

    index: int = quantity("-", "application count since the unit was new (1-based)",
                          msg={_CYCLE: "index"}, columns={"applications": "index"})
    start_ns: int = quantity("ns", "start of clearance elimination", msg={_CYCLE: "start"})
    end_ns: int = quantity("ns", "end of the application (back at rest after force release)",
                           msg={_CYCLE: _STAMP}, columns={"applications": Column("stamp_s", _seconds)})
    phase_durations_s: tuple[float, float, float, float] = quantity(
        "s", "duration of each phase of 000 Fig. 2 (domain.phases.PHASES order)",
        msg={_CYCLE: ("clearance_elimination_s", "force_generation_s", "force_maintenance_s",
                      "force_release_s")})
    peak_force_n: float = quantity("N", "peak axial force", msg={_CYCLE: "peak_force_n"},
                                   columns={"applications": "peak_force_n"})
    peak_speed_rad_s: float = quantity("rad/s", "peak |screw velocity|", msg={_CYCLE: "peak_speed_rad_s"})
    stroke_rad: float = quantity(
        "rad", "screw rotation from the rest position to peak force (NaN: rest unknown)",
        msg={_CYCLE: "stroke_rad"})
    screw_wear_m: tuple[float, float, float, float] = quantity(
        "m", "screw-raceway wear depth added by this application, per phase", msg={_CYCLE: "screw_wear_m"},
        columns={"applications": Column("screw_wear_increment_m", sum)})
    nut_wear_m: tuple[float, float, float, float] = quantity(
        "m", "nut-raceway wear depth added by this application, per phase", msg={_CYCLE: "nut_wear_m"},
        columns={"applications": Column("nut_wear_increment_m", sum)})
    ball_wear_m: tuple[float, float, float, float] = quantity(
        "m", "ball wear depth added by this application, per phase", msg={_CYCLE: "ball_wear_m"},
        columns={"applications": Column("ball_wear_increment_m", sum)})
    clearance_observed_m: float = quantity(
        "m", "axial clearance x_ag observed in this application (NaN: not observable)",
        msg={_CYCLE: "clearance_observed_m"}, columns={"applications": "clearance_observed_m"})
    clearance_observed_std_m: float = quantity(
        "m", "1-sigma error budget of the observation (observation.py; NaN: not observable)",
        msg={_CYCLE: "clearance_observed_std_m"}, columns={"applications": "clearance_observed_std_m"})
    clearance_model_m: float = quantity("m", "axial clearance x_ag predicted by the wear model after it",
                                        columns={"applications": "clearance_model_m"})
    clearance_estimate_m: float = quantity("m", "filtered axial clearance x_ag after it",
                                           msg={_CYCLE: "clearance_estimate_m"},
                                           columns={"applications": "clearance_estimate_m"})
    clearance_std_m: float = quantity("m", "1-sigma of the filtered clearance",
                                      columns={"applications": "clearance_std_m"})
    growth_rate_m_per_cycle: float = quantity("m", "learned clearance growth per application (the next one)",
                                              columns={"applications": "growth_rate_m_per_cycle"})
    growth_rate_std_m_per_cycle: float = quantity("m", "1-sigma of the learned growth per application",
                                                  columns={"applications": "growth_rate_std_m_per_cycle"})
    wear_rate_factor: float = quantity("-", "learned growth over the wear model's mean growth (NaN: none)",
                                       columns={"applications": "wear_rate_factor"})
    wear_rate_factor_std: float = quantity("-", "1-sigma of wear_rate_factor")

    @property
    def start_s(self) -> float:
        return _seconds(self.start_ns)

    @property
    def end_s(self) -> float:
        return _seconds(self.end_ns)


@dataclass(frozen=True)
class MonitorSnapshot(Record):
    """Totals now: the replay/fleet JSON entry, ``WearState``, ``RemainingLife``, ``/diagnostics``."""

    duty_cycles: int = quantity("-", "completed brake applications", json="duty_cycles",
                                msg={_WEAR: "duty_cycles"},
                                diag="duty_cycles", columns={"units": "duty_cycles"})
    screw_raceway_m: float = quantity(
        "m", "cumulative wear depth of the screw raceway", json="wear/screw_raceway_m",
        msg={_WEAR: "screw_raceway_m"}, diag="wear_screw_raceway_m",
        columns={"units": "screw_raceway_m", "applications": "screw_raceway_m"})
    nut_raceway_m: float = quantity(
        "m", "cumulative wear depth of the nut raceway", json="wear/nut_raceway_m",
        msg={_WEAR: "nut_raceway_m"}, diag="wear_nut_raceway_m",
        columns={"units": "nut_raceway_m", "applications": "nut_raceway_m"})
    ball_m: float = quantity(
        "m", "cumulative wear depth (radius loss) of the balls", json="wear/ball_m", msg={_WEAR: "ball_m"},
        diag="wear_ball_m", columns={"units": "ball_m", "applications": "ball_m"})
    clearance_model_m: float = quantity(
        "m", "axial clearance x_ag predicted by the wear model", json="clearance/model_m",
        msg={_WEAR: "clearance_model_m"}, diag="clearance_model_m", columns={"units": "clearance_model_m"})
    clearance_estimate_m: float = quantity(
        "m", "filtered axial clearance x_ag", json="clearance/estimate_m",
        msg={_WEAR: "clearance_estimate_m", _LIFE: "clearance_estimate_m"}, diag="clearance_estimate_m",
        columns={"units": "clearance_estimate_m"})
    clearance_std_m: float = quantity(
        "m", "1-sigma of the filtered clearance", json="clearance/std_m", msg={_WEAR: "clearance_std_m"},
        diag="clearance_std_m", columns={"units": "clearance_std_m"})
    wear_rate_factor: float = quantity(
        "-", "learned clearance growth over the wear model's mean growth (1: model right; NaN: none)",
        json="clearance/wear_rate_factor", msg={_WEAR: "wear_rate_factor"}, diag="wear_rate_factor",
        columns={"units": "clearance_wear_rate_factor"})
    wear_rate_factor_std: float = quantity(
        "-", "1-sigma of wear_rate_factor", json="clearance/wear_rate_factor_std",
        msg={_WEAR: "wear_rate_factor_std"}, diag="wear_rate_factor_std",
        columns={"units": "clearance_wear_rate_factor_std"})
    observations: int = quantity(
        "-", "clearance observations handed to the filter", json="clearance/observations",
        msg={_WEAR: "observations"}, columns={"units": "clearance_observations"})
    clearance_steps: int = quantity("-", "steps of the clearance detected (tracker.py)",
                                    json="clearance/steps", diag="clearance_steps",
                                    columns={"units": "clearance_steps"})
    growth_changes: int = quantity("-", "changes of the growth rate detected (tracker.py)",
                                   json="clearance/growth_changes", diag="growth_changes",
                                   columns={"units": "clearance_growth_changes"})
    limit_m: float = quantity(
        "m", "clearance x_ag at which maintenance is due (unit file monitor.clearance_limit)",
        json="remaining_life/limit_m", msg={_LIFE: "limit_m"}, diag="clearance_limit_m",
        columns={"units": "limit_m"})
    cycles_p05: float | None = quantity(
        "-", "brake applications until x_ag reaches the limit, 5th percentile (null: unknown or unbounded)",
        json="remaining_life/cycles_p05", msg={_LIFE: "cycles_p05"}, diag="remaining_cycles_p05",
        columns={"units": "cycles_p05", "applications": "cycles_p05"})
    cycles_p50: float | None = quantity(
        "-", "brake applications until x_ag reaches the limit, median", json="remaining_life/cycles_p50",
        msg={_LIFE: "cycles_p50"}, diag="remaining_cycles_p50",
        columns={"units": "cycles_p50", "applications": "cycles_p50"})
    cycles_p95: float | None = quantity(
        "-", "brake applications until x_ag reaches the limit, 95th percentile (null: unbounded)",
        json="remaining_life/cycles_p95", msg={_LIFE: "cycles_p95"}, diag="remaining_cycles_p95",
        columns={"units": "cycles_p95", "applications": "cycles_p95"})
    life_status: str = quantity(
        "", "remaining-life status (monitor/life.py)", json="remaining_life/status", msg={_LIFE: "status"},
        diag="remaining_life_status", columns={"units": "status", "applications": "life_status"},
        enum=STATUSES)
    applications_per_hour: float | None = quantity(
        "1/h", "observed usage", json="remaining_life/applications_per_hour",
        msg={_LIFE: "applications_per_hour"},
        columns={"units": "applications_per_hour"})
    hours_p50: float | None = quantity(
        "h", "median remaining life at the observed usage", json="remaining_life/hours_p50",
        msg={_LIFE: "hours_p50"}, diag="remaining_hours_p50", columns={"units": "hours_p50"})
    seconds_p05: float | None = quantity(
        "s", "remaining life at the observed usage, 5th percentile", json="remaining_life/seconds_p05",
        msg={_LIFE: "seconds_p05"}, diag="remaining_seconds_p05", columns={"units": "seconds_p05"})
    seconds_p50: float | None = quantity(
        "s", "remaining life at the observed usage, median", json="remaining_life/seconds_p50",
        msg={_LIFE: "seconds_p50"}, diag="remaining_seconds_p50", columns={"units": "seconds_p50"})
    seconds_p95: float | None = quantity(
        "s", "remaining life at the observed usage, 95th percentile", json="remaining_life/seconds_p95",
        msg={_LIFE: "seconds_p95"}, diag="remaining_seconds_p95", columns={"units": "seconds_p95"})
    usage_span_s: float | None = quantity(
        "s", "stamp span over which the usage was observed", json="remaining_life/usage_span_s",
        msg={_LIFE: "usage_span_s"}, diag="usage_span_s", columns={"units": "usage_span_s"})
    growth_rate_m_per_cycle: float = quantity(
        "m", "learned clearance growth per application", json="remaining_life/growth_rate_m_per_cycle",
        msg={_WEAR: "growth_rate_m_per_cycle", _LIFE: "growth_rate_m_per_cycle"},
        diag="growth_rate_m_per_cycle",
        columns={"units": "growth_rate_m_per_cycle"})
    growth_rate_std_m_per_cycle: float = quantity(
        "m", "1-sigma of the learned growth per application",
        json="remaining_life/growth_rate_std_m_per_cycle",
        msg={_WEAR: "growth_rate_std_m_per_cycle", _LIFE: "growth_rate_std_m_per_cycle"},
        diag="growth_rate_std_m_per_cycle", columns={"units": "growth_rate_std_m_per_cycle"})
    fatigue_l10_revolutions: float | None = quantity(
        "rev", "ISO 3408-5 basic rating life L10 at the cubic-mean load (null without C_a)",
        json="remaining_life/fatigue_l10_revolutions", msg={_LIFE: "fatigue_l10_revolutions"},
        diag="fatigue_l10_revolutions", columns={"units": "fatigue_l10_revolutions"})
    fatigue_cubic_mean_load_n: float | None = quantity(
        "N", "cubic-mean axial load over the revolutions seen (ISO 3408-5)",
        json="remaining_life/fatigue_cubic_mean_load_n", msg={_LIFE: "fatigue_cubic_mean_load_n"},
        columns={"units": "fatigue_cubic_mean_load_n"})
    revolutions: float = quantity("rev", "screw revolutions seen", json="remaining_life/revolutions",
                                  columns={"units": "revolutions"})
    fatigue_remaining_cycles: float | None = quantity(
        "-", "brake applications left to L10 at the observed revolutions per application",
        json="remaining_life/fatigue_remaining_cycles", msg={_LIFE: "fatigue_remaining_cycles"},
        diag="fatigue_remaining_cycles", columns={"units": "fatigue_remaining_cycles"})
    limiting_mechanism: str = quantity(
        "", "what limits the life first", json="remaining_life/limiting_mechanism",
        msg={_LIFE: "limiting_mechanism"}, diag="limiting_mechanism", columns={"units": "limiting_mechanism"},
        enum=MECHANISMS)
    input_faults: dict[str, int] = quantity(
        "-", "input samples dropped or events counted, per kind (alignment.FAULT_KINDS)", json="input_faults",
        diag="fault_{}",
        columns={"units": (Column("input_faults", _text), Column("input_faults_total", _total))})
    input_faults_by_signal: dict[str, dict[str, int]] = quantity(
        "-", "input faults per signal and kind", json="input_faults_by_signal",
        columns={"units": Column("input_faults_by_signal", _text)})
    input_rates_hz: dict[str, float | None] = quantity(
        "Hz", "accepted samples per second of stamp span, per signal", json="input_rates_hz")
    segments: dict[str, int] = quantity(
        "-", "closed segments per kind (cycle, incomplete, motion, interrupted, partial)", json="segments",
        diag="segments_{}")
    last_stamp_ns: int | None = quantity(
        "ns", "end of the last closed segment: data up to here is integrated", json="last_stamp_ns",
        msg={_WEAR: _STAMP, _LIFE: _STAMP})
    pending_samples: int = quantity("-", "samples still waiting in the reorder window",
                                    diag="pending_samples")
