"""Every threshold of the monitor core, with its unit, valid range and the reasoning behind its default.

One :class:`MonitorConfig` is shared by the live node (each field is a ROS
parameter of the same name, declared from :func:`parameter_specs`) and by
``ebm-wear replay`` / ``ebm-wear fleet`` (defaults), so both run the same
numbers. Thresholds that depend on the unit are given *relative to the unit*
(a nut speed converted through the lead, a contact displacement converted
through the clamp stiffness K_b of 004 eq. 6) and resolved into absolute values
by :meth:`MonitorConfig.resolve`, so nothing is tuned to one recording.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.physics import METHODS as WEAR_METHODS

_NOISE_MULTIPLE = 9.0  # 'on' thresholds >= 9 sigma of the sensor noise, 'off' (half) >= 4.5 sigma


def _p(default: Any, unit: str, lo: float | None, hi: float | None, doc: str, *,
       choices: tuple[str, ...] | None = None) -> Any:
    """A config field carrying its documentation: ``unit``, closed range [lo, hi] (or the allowed
    ``choices`` of a string field) and a description."""
    metadata = {"unit": unit, "range": (lo, hi), "doc": doc}
    if choices is not None:
        metadata["choices"] = choices
    return field(default=default, metadata=metadata)


@dataclass(frozen=True)
class MonitorConfig:
    """Thresholds and noise figures of the monitor core. SI units; ranges are inclusive."""

    # ---- physics
    wear_method: str = _p(
        "surrogate", "", None, None,
        "wear model of the physics core: 'surrogate' (fast table) or 'direct' (000 Fig. 6 solve)",
        choices=WEAR_METHODS)

    # ---- input alignment (alignment.py)
    reorder_window_s: float = _p(
        0.2, "s", 1e-6, 60.0,
        "a sample may arrive this much (in header stamp) behind the newest of its topic and still be "
        "sorted in; older ones are counted 'late' and dropped. 0.2 s = 200 periods at 1 kHz, far above "
        "DDS delivery jitter (sub-ms, environment.md)")
    stamp_quantum_s: float = _p(
        1e-6, "s", 1e-9, 0.01,
        "header stamps are floored to this quantum; two samples of one topic in the same quantum are "
        "duplicates. 1 us is far below any sample period of interface.md (100 Hz to 2 kHz)")
    time_base: str = _p(
        "axial_force", "", None, None,
        "the topic whose stamps are the common time base: the other topics are interpolated linearly at "
        "its stamps (interface.md section 2: topics need not share rates or stamps). The force, because "
        "wear and the clearance observation are functions of the load at the instants it was measured",
        choices=("axial_force", "angle", "velocity"))
    max_interpolation_s: float = _p(
        0.025, "s", 1e-6, 10.0,
        "a topic is interpolated at a base stamp only between two of its samples at most this far apart; "
        "wider, its value there is 'missing'. 25 ms: one dropped sample at the slowest rate of "
        "interface.md (100 Hz) plus jitter")
    stale_after_s: float = _p(
        2.0, "s", 0.01, 3600.0,
        "a topic whose newest stamp lags the median topic's by more than this no longer holds the "
        "others back (its missing samples are counted)")
    backwards_jump_s: float = _p(
        1.0, "s", 0.0, 1e6,
        "a stamp further than this behind its topic's newest is counted 'stamp_backwards' (clock reset, "
        "bag played in a loop) rather than 'late'; one further than this ahead is a clock jump that "
        "the next reanchor_after_samples samples must confirm")
    reanchor_after_samples: int = _p(
        10, "-", 1, 1 << 20,
        "a stamp more than backwards_jump_s ahead of its topic's newest (and a topic's first stamp) is "
        "accepted only once this many samples in a row continue from it (each within backwards_jump_s "
        "of the one before); otherwise it is a 'stamp_glitch' and dropped. 10: up to 9 glitched stamps "
        "in a row are rejected, for 10 periods of latency (10 ms at 1 kHz)")
    gap_s: float = _p(
        0.1, "s", 1e-4, 3600.0,
        "consecutive aligned samples further apart than this are a 'gap': no wear is integrated across "
        "it and a brake application in progress is closed as interrupted (10 periods at 100 Hz)")
    max_abs_angle_rad: float = _p(
        1e7, "rad", 1.0, 1e15,
        "|screw angle| above this is 'absurd' (1e7 rad = 8e3 km of nut travel at a 5 mm lead)")
    max_speed_rad_s: float = _p(
        2000.0, "rad/s", 1.0, 1e7,
        "|screw speed| above this is 'absurd' (19,000 rpm of the screw, beyond any EMB motor and gear)")
    max_force_n: float = _p(
        1e6, "N", 1.0, 1e9,
        "axial force above this is 'absurd' (50x the dynamic load rating of the reference screw)")

    # ---- segmentation (segmentation.py), relative to the unit
    nut_speed_on_m_s: float = _p(
        1e-3, "m/s", 1e-7, 1.0,
        "the screw is 'moving' when its speed exceeds the one that moves the nut this fast: "
        "omega_on = max(2 pi v / lead, 9 speed_noise_rad_s) (1.26 rad/s at 5 mm lead)")
    speed_off_ratio: float = _p(
        0.5, "-", 0.01, 1.0,
        "hysteresis: the screw is 'stopped' below speed_off_ratio * omega_on")
    contact_displacement_m: float = _p(
        5e-6, "m", 1e-9, 1e-3,
        "force onset (pads touch) when the axial force exceeds force_on = max(K_b d, 9 force_noise_n) "
        "(K_b d = 208 N with K_b = 4.16e7 N/m of 004 eq. 6; 20x the axial resolution of a 4096-count "
        "encoder). 9 sigma puts the 'released' level (half of it) 4.5 sigma above zero: a noise spike "
        "crosses it about once in 3e5 samples")
    contact_force_n: float = _p(
        200.0, "N", 0.0, 1e6,
        "force-onset threshold used only when the unit file has no actuator block (no K_b)")
    force_off_ratio: float = _p(
        0.5, "-", 0.01, 1.0,
        "hysteresis: force is 'released' below force_off_ratio * force_on")
    rest_dwell_s: float = _p(
        0.05, "s", 0.0, 60.0,
        "the unit is 'at rest' (application ended) once stopped and released for this long")
    rest_angle_samples: int = _p(
        32, "-", 1, 100000,
        "the release rest position is the median screw angle of the last this-many rest samples")

    # ---- clearance observation and filter (observation.py, kalman.py)
    motor_encoder_counts: int = _p(
        4096, "counts/rev", 1, 1 << 30,
        "motor encoder resolution (1024 lines x4 quadrature); screw angle resolution "
        "q = 2 pi / (counts * gear_ratio)")
    force_noise_n: float = _p(
        50.0, "N", 0.0, 1e5,
        "1-sigma axial-force sensor noise (0.1 % of a 50 kN load cell); scales the force thresholds "
        "and the observation noise")
    speed_noise_rad_s: float = _p(
        0.05, "rad/s", 0.0, 1e3,
        "1-sigma screw-speed sensor noise; scales the speed thresholds")
    clearance_repeatability_m: float = _p(
        1e-6, "m", 0.0, 1e-3,
        "1-sigma cycle-to-cycle scatter of the true travel to force onset: 1 K of temperature swing over "
        "~0.1 m of steel in the caliper (alpha = 12e-6 /K) moves it ~1.2 um")
    initial_clearance_std_m: float = _p(
        1e-4, "m", 1e-9, 1e-2,
        "1-sigma prior on the unit's clearance before the first observation (assembly tolerance)")
    initial_factor_std: float = _p(
        1.0, "-", 1e-6, 100.0,
        "1-sigma prior of the model component's wear-rate factor (kalman.py; mean 1 = model right): the "
        "model may be off by its own size; also the factor's variance opened at a growth change")
    growth_scatter: float = _p(
        0.5, "-", 0.0, 10.0,
        "1-sigma relative scatter of one application's clearance growth around the model "
        "(cycle-to-cycle spread of the Archard coefficient)")
    factor_drift_per_cycle: float = _p(
        1e-3, "-", 0.0, 1.0,
        "random-walk 1-sigma of the model component's factor per application: lets it wander by ~1 over "
        "1e6 applications (run-in, lubricant ageing)")
    model_prior_weight: float = _p(
        0.5, "-", 1e-3, 0.999,
        "prior probability that the wear model is right up to its factor (kalman.py): 1/2, no preference; "
        "the data-driven growth hypotheses share the rest. Applies from the start of a unit's history")
    accelerating_prior_weight: float = _p(
        0.1, "-", 0.0, 0.5,
        "prior probability of accelerating growth (exponential on a grid of e-folding rates, or a steadily "
        "climbing rate), taken from the data-driven share: one growing unit in ten is in accelerated wear "
        "(ASSUMED). Applies from the start of a unit's history")
    rate_wander_per_cycle: float = _p(
        0.01, "-", 0.0, 0.5,
        "random walk of the growth rate per application, relative to itself, of the wandering half of "
        "the data-driven hypotheses: the rate may drift by ~10 % over 100 applications")
    regime_change_per_cycle: float = _p(
        1e-6, "-", 0.0, 0.01,
        "probability per application that the unit changes its wear regime (weights are mixed by it, so "
        "no hypothesis is ever ruled out for good): about once in an EMBU's life")
    innovation_gate_sigma: float = _p(
        5.0, "-", 1.0, 1e6,
        "an observation further than this many sigma of the innovation sqrt(P_cc + R) from the "
        "prediction of every hypothesis is counted 'observation_rejected' and not fused (a Gaussian "
        "innovation exceeds 5 sigma once in 1.7e6 applications)")
    reset_after_rejections: int = _p(
        3, "-", 1, 1 << 30,
        "this many rejected observations in a row on the same side mean the clearance itself stepped "
        "(adjustment, maintenance, fracture): the step is placed at the first of them and the filter "
        "re-run with it (tracker.py); one alone is an outlier")
    change_window_cycles: int = _p(
        30, "-", 5, 10000,
        "applications over which a step of the clearance or a change of its growth rate is searched "
        "(generalised likelihood ratio, tracker.py), and kept for re-filtering once found")
    change_false_alarm_per_cycle: float = _p(
        1e-4, "-", 1e-12, 0.1,
        "false detections of a step or rate change per application the change test allows (sets its "
        "chi-square thresholds with a Bonferroni split over the window)")
    noise_scale_prior_cycles: float = _p(
        10.0, "-", 0.1, 1e9,
        "weight, in observations, of the prior 'the error budget of observation.py is right' in the "
        "measured scale of the observation noise (kalman.py)")

    # ---- remaining life (life.py)
    min_cycles_for_life: int = _p(
        10, "-", 1, 1 << 40,
        "no remaining life before this many clearance observations; also the fastest growth the filter "
        "expects consumes the whole margin (limit - nominal clearance) in this many applications")
    life_confidence_z: float = _p(
        1.6448536269514722, "-", 0.0, 10.0,
        "normal quantile of the reported band: 1.645 gives p05 / p95")

    # ---- persistence
    checkpoint_every_cycles: int = _p(
        100, "-", 1, 1 << 40,
        "save the state every this many completed applications (and at shutdown)")

    def validate(self) -> MonitorConfig:
        """Raise :class:`InputError` (one line) when a value is of the wrong type or out of range."""
        for f in fields(self):
            value = getattr(self, f.name)
            choices = f.metadata.get("choices")
            if choices is not None:
                if value not in choices:
                    raise InputError(f"monitor parameter {f.name}: must be one of {', '.join(choices)}, "
                                     f"got {value!r}")
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise InputError(f"monitor parameter {f.name}: expected a number, got {value!r}")
            if f.type == "int" and float(value) != int(value):
                raise InputError(f"monitor parameter {f.name}: expected a whole number, got {value!r}")
            lo, hi = f.metadata["range"]
            if not math.isfinite(value) or (lo is not None and value < lo) or (hi is not None and value > hi):
                raise InputError(f"monitor parameter {f.name}: {value!r} outside [{lo:g}, {hi:g}] "
                                 f"{f.metadata['unit']}".rstrip())
        return self

    def updated(self, **changes: Any) -> MonitorConfig:
        """A validated copy with ``changes`` applied (run-time parameter changes of the node)."""
        unknown = set(changes) - {f.name for f in fields(self)}
        if unknown:
            raise InputError(f"unknown monitor parameter(s): {', '.join(sorted(unknown))}")
        return replace(self, **changes).validate()

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    def resolve(self, unit: UnitParams) -> Thresholds:
        """Absolute thresholds for ``unit`` (see the field docs for the conversions)."""
        lead = unit.ball_screw.lead
        omega_on = max(2.0 * math.pi * self.nut_speed_on_m_s / lead, _NOISE_MULTIPLE * self.speed_noise_rad_s)
        act = unit.actuator
        force_on = act.stiffness * self.contact_displacement_m if act is not None else self.contact_force_n
        force_on = max(force_on, _NOISE_MULTIPLE * self.force_noise_n)
        gear = act.gear_ratio if act is not None else 1.0
        return Thresholds(
            omega_on=omega_on,
            omega_off=self.speed_off_ratio * omega_on,
            force_on=force_on,
            force_off=self.force_off_ratio * force_on,
            angle_resolution=2.0 * math.pi / (self.motor_encoder_counts * gear),
            meters_per_rad=lead / (2.0 * math.pi),
        )


@dataclass(frozen=True)
class Thresholds:
    """Absolute values resolved from a :class:`MonitorConfig` and a unit."""

    omega_on: float  # screw speed above which it moves [rad/s]
    omega_off: float  # screw speed below which it is stopped [rad/s]
    force_on: float  # force onset (pads touch) [N]
    force_off: float  # force released [N]
    angle_resolution: float  # screw angle quantum q [rad]
    meters_per_rad: float  # nut travel per screw radian, lead / (2 pi) [m/rad]


def parameter_specs() -> list[dict[str, Any]]:
    """One dict per field (name, default, unit, range (lo, hi), choices, doc) to declare ROS parameters."""
    out = []
    for f in fields(MonitorConfig):
        lo, hi = f.metadata["range"]
        out.append({"name": f.name, "default": f.default, "unit": f.metadata["unit"], "range": (lo, hi),
                    "choices": f.metadata.get("choices"), "doc": f.metadata["doc"],
                    "type": type(f.default).__name__})
    return out
