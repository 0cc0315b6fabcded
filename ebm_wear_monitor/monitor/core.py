"""MonitorCore: the ROS-free wear monitor shared by the live node and the offline replay.

Data flow (each step in its own module)::

    add(signal, stamps, values)            any chunk size, any interleaving of topics
      -> InputAligner.release              validate, de-duplicate, reorder, merge by stamp  (alignment.py)
      -> Segmenter.feed                    four phases of 000 Fig. 2, segments              (segmentation.py:
                                           the causal mode of domain/segmentation/causal.py)
      -> per closed segment:
           wear integral                   sum over moving samples of rate(F - b, omega) * dt (b: rest
                                           level of the force sensor), the physics core's
                                           wear_model(unit, method).rates (000 eq. 20-23), per phase,
                                           for screw raceway, nut raceway and ball
           model clearance                 x_ag,model = x_ag,nominal + clearance_growth(wear)
           fatigue sums                    sum |F|^3 |d theta|, sum |d theta| (ISO 3408-5)
           per completed application:
             clearance observation         observation.py
             filter bank step              kalman.py / tracker.py: predict with the model growth, fuse
                                           the observation (gate, steps, rate changes)
      -> CycleSummary per application; snapshot() for totals, remaining life (life.py), faults
         (both records declared, with every output they generate, in schema/monitor.py).

Identical numbers for node and replay hold by construction: every decision
depends on the per-topic arrival order and the values only, and every float sum
is taken over whole-segment arrays (the same arrays whatever the chunking), so
one message at a time and one whole recording give bit-identical results
(test/monitor/test_monitor_core.py checks it).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple, TypeVar

import numpy as np

from ebm_wear_monitor import physics
from ebm_wear_monitor.monitor.alignment import FAULT_KINDS, InputAligner
from ebm_wear_monitor.monitor.config import MonitorConfig
from ebm_wear_monitor.monitor.life import fatigue_life, limiting_mechanism, wear_life
from ebm_wear_monitor.monitor.observation import observe_clearance, onset_bands, pool_lag
from ebm_wear_monitor.monitor.persistence import save_state
from ebm_wear_monitor.monitor.segmentation import N_LABELS, Segment, Segmenter
from ebm_wear_monitor.monitor.state import MonitorState
from ebm_wear_monitor.monitor.tracker import REJECTED, ClearanceTracker
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.schema.monitor import CycleSummary, MonitorSnapshot

WearRatesFn = Callable[[np.ndarray, np.ndarray], Any]  # (F [N], omega [rad/s]) -> (screw, nut, ball) [m/s]
GrowthFn = Callable[[float, float, float], float]  # (screw, nut, ball wear [m]) -> clearance growth [m]


_T = TypeVar("_T")


class Application(NamedTuple):
    """Event of one completed brake application: its summary and the core's snapshot right after it."""

    cycle: CycleSummary
    snapshot: MonitorSnapshot


def _physics(unit: UnitParams, method: str) -> tuple[WearRatesFn, GrowthFn]:
    model = physics.wear_model(unit, method)
    return model.rates, lambda s, n, b: float(physics.clearance_growth(unit, s, n, b))


class MonitorCore:
    """The wear monitor of one unit. Feed it with :meth:`add`, drive it with :meth:`process`.

    Args:
        unit: the unit's parameters (interface.md section 3).
        config: thresholds (defaults when None); validated.
        state: a state to resume (from :func:`load_state`); data at or before its
            ``last_stamp_ns`` is dropped as late.
        wear_rates: ``(force [N], speed [rad/s]) -> (screw, nut, ball)`` wear-depth rates [m/s];
            default: the physics core's ``wear_model(unit, config.wear_method).rates``.
        clearance_growth: ``(screw, nut, ball) [m] -> growth [m]``; default: the physics core's.
        state_path: if given, the state is saved there atomically every
            ``config.checkpoint_every_cycles`` applications (call :meth:`save` at shutdown).
    """

    def __init__(self, unit: UnitParams, config: MonitorConfig | None = None,
                 state: MonitorState | None = None, *, wear_rates: WearRatesFn | None = None,
                 clearance_growth: GrowthFn | None = None,
                 state_path: str | Path | None = None):
        self.unit = unit
        self.config = (config or MonitorConfig()).validate()
        self._th = self.config.resolve(unit)
        if wear_rates is None or clearance_growth is None:
            default_rates, default_growth = _physics(unit, self.config.wear_method)
            wear_rates = wear_rates or default_rates
            clearance_growth = clearance_growth or default_growth
        self._rates, self._growth = wear_rates, clearance_growth
        self.state_path = Path(state_path) if state_path is not None else None
        self._nominal = unit.actuator.clearance if unit.actuator is not None else 0.0
        st = state or MonitorState()
        self._st = MonitorState(**{**st.to_dict(), "unit_name": unit.name, "unit_digest": unit.digest()})
        self._aligner = InputAligner(self.config, self._th, release_floor_ns=st.last_stamp_ns)
        for signal, counts in st.input_faults.items():
            for kind, n in counts.items():
                self._aligner.count(signal, kind, n)
        self._segmenter = Segmenter(self.config, self._th, st.force_baseline_n)
        self._tracker = self._start_tracker(st.tracker)
        if self._st.model_clearance_at_filter_m is None:
            self._st.model_clearance_at_filter_m = self.model_clearance()

    # ------------------------------------------------------------------ configuration
    def configure(self, config: MonitorConfig) -> None:
        """Change thresholds at run time (ROS parameter callbacks); applies from the next :meth:`process`.

        The wear method cannot change at run time (it would mix two models in one integral).
        """
        config = config.validate()
        if config.wear_method != self.config.wear_method:
            raise ValueError("wear_method cannot change while running; restart with the new method")
        self.config, self._th = config, config.resolve(self.unit)
        self._tracker.configure(config)
        self._aligner.configure(config, self._th)
        self._segmenter.configure(config, self._th)

    # ------------------------------------------------------------------ input and processing
    def add(self, signal: str, stamps: np.ndarray, values: np.ndarray) -> None:
        """Queue samples of one topic: ``signal`` in {"angle", "velocity", "axial_force"} ("current" is
        ignored); ``stamps`` header stamps as int64 ns (exact: what the node and the replay give) or float
        s (rounded to 1 ns, for generators); ``values`` in SI units. Any chunk size; topics may be
        interleaved in any way."""
        self._aligner.add(signal, stamps, values)

    def count(self, signal: str, kind: str, n: int) -> None:
        """Count ``n`` samples of ``signal`` lost before they reached the core (``undecodable``, ``lost``)."""
        if kind not in FAULT_KINDS:
            raise ValueError(f"unknown fault kind {kind!r}")
        self._aligner.count(signal, kind, n)

    def process(self, final: bool = False) -> list[CycleSummary]:
        """Consume everything alignment can release now (everything if ``final``: end of data).

        Returns the brake applications completed on the way, in order.
        """
        return [cycle for cycle, _ in self._run(final, lambda: None)]

    def process_events(self, final: bool = False) -> list[Application]:
        """As :meth:`process`, each application with the snapshot taken right after it (chunk-invariant)."""
        return [Application(cycle, snap) for cycle, snap in self._run(final, self.snapshot)]

    def _run(self, final: bool, after: Callable[[], _T]) -> list[tuple[CycleSummary, _T]]:
        """Completed applications, each with ``after()`` called right after it (a snapshot, or nothing)."""
        batch = self._aligner.release(final)
        out: list[tuple[CycleSummary, _T]] = []
        for seg in self._segmenter.feed(batch, final):
            summary = self._integrate(seg)
            if summary is not None:
                out.append((summary, after()))
                if (self.state_path is not None
                        and self._st.duty_cycles % self.config.checkpoint_every_cycles == 0):
                    self.save()
        return out

    def _integrate(self, seg: Segment) -> CycleSummary | None:
        st = self._st
        phase_wear = np.zeros((3, N_LABELS))
        if seg.dt.size:
            rates = self._rates(seg.force, seg.velocity)
            for j, rate in enumerate(rates):
                inc = np.asarray(rate, dtype=float) * seg.dt
                phase_wear[j] = np.bincount(seg.label, weights=inc, minlength=N_LABELS)
            rot = np.abs(seg.dangle)
            st.sum_f3_rot += float(np.sum(np.abs(seg.force) ** 3 * rot))
            st.sum_rot_rad += float(np.sum(rot))
        for k in range(N_LABELS):
            st.screw_raceway_m += float(phase_wear[0, k])
            st.nut_raceway_m += float(phase_wear[1, k])
            st.ball_m += float(phase_wear[2, k])
        st.segments[seg.kind] = st.segments.get(seg.kind, 0) + 1
        st.last_stamp_ns = seg.end_ns
        if seg.kind == "interrupted":
            self._aligner.count("stream", "interrupted_cycle", 1)
        if seg.kind != "cycle":
            return None

        st.duty_cycles += 1
        st.first_cycle_ns = seg.start_ns if st.first_cycle_ns is None else st.first_cycle_ns
        st.last_cycle_ns = seg.start_ns
        model = self.model_clearance()
        last = st.model_clearance_at_filter_m  # set when the core starts: never None here
        growth = model - (model if last is None else last)
        st.model_clearance_at_filter_m = model
        bands = onset_bands(seg, self._th)
        obs = observe_clearance(seg, bands, self._th, self.config, lag=self.force_lag())
        st.force_lag_weight, st.force_lag_weighted_sum = pool_lag(
            st.force_lag_weight, st.force_lag_weighted_sum, obs.lag_s, obs.lag_var_s2)
        if math.isfinite(obs.lag_s):  # this application's own lag is in the pool now: use it too
            obs = observe_clearance(seg, bands, self._th, self.config, lag=self.force_lag(),
                                    estimate_lag=False)
        observed, observed_std = obs.clearance_m, obs.std_m
        self._fuse(growth, observed, observed_std)
        estimate, estimate_std = self._tracker.live.clearance()
        rate, rate_std, factor, factor_std = self._growth_rate()
        return CycleSummary(
            index=st.duty_cycles, start_ns=seg.start_ns, end_ns=seg.end_ns,
            phase_durations_s=seg.phase_durations_s, peak_force_n=seg.peak_force,
            peak_speed_rad_s=float(np.max(np.abs(seg.velocity))) if seg.velocity.size else 0.0,
            stroke_rad=seg.angle_at_peak_force - seg.rest_angle,
            screw_wear_m=tuple(phase_wear[0, :4].tolist()), nut_wear_m=tuple(phase_wear[1, :4].tolist()),
            ball_wear_m=tuple(phase_wear[2, :4].tolist()),
            clearance_observed_m=observed, clearance_observed_std_m=observed_std, clearance_model_m=model,
            clearance_estimate_m=estimate, clearance_std_m=estimate_std, growth_rate_m_per_cycle=rate,
            growth_rate_std_m_per_cycle=rate_std, wear_rate_factor=factor, wear_rate_factor_std=factor_std)

    def _start_tracker(self, saved: dict[str, Any] | None) -> ClearanceTracker:
        """The clearance tracker: resumed, migrated from a version-1 filter, or at the nominal prior."""
        cfg, limit = self.config, self.unit.monitor.clearance_limit
        if saved is not None and "legacy_filter" in saved:
            x, P = saved["legacy_filter"]["x"], saved["legacy_filter"]["P"]
            return ClearanceTracker.start(cfg, x[0], P[0][0], limit, factor=x[1], factor_var=P[1][1],
                                          clearance_factor_cov=P[0][1])
        if saved is not None:
            return ClearanceTracker.from_dict(saved, cfg, self._nominal, limit)
        return ClearanceTracker.start(cfg, self._nominal, cfg.initial_clearance_std_m ** 2, limit)

    def _fuse(self, growth: float, observed: float, observed_std: float) -> None:
        """One tracker step (kalman.py, tracker.py); count observations, rejections, steps, rate changes."""
        st = self._st
        result = self._tracker.step(growth, observed, observed_std ** 2)
        if math.isfinite(observed):
            st.observations += 1
        if result.outcome == REJECTED:
            self._aligner.count("stream", "observation_rejected", 1)
        st.clearance_steps += result.steps
        st.growth_changes += result.changes

    def _mean_model_growth(self) -> float:
        """The wear model's mean clearance growth per application so far [m] (the future's prior mean)."""
        st = self._st
        return (self.model_clearance() - self._nominal) / st.duty_cycles if st.duty_cycles else 0.0

    def _growth_rate(self) -> tuple[float, float, float, float]:
        """Learned growth per application and its std [m], and both over the model's mean growth [-]."""
        gbar = self._mean_model_growth()
        rate, rate_std = self._tracker.live.growth_rate(self._tracker.hyp, gbar)
        if gbar > 0.0:
            return rate, rate_std, rate / gbar, rate_std / gbar
        return rate, rate_std, math.nan, math.nan

    # ------------------------------------------------------------------ results
    def force_lag(self) -> tuple[float, float]:
        """The force sensor's lag estimated from the applications so far, and its variance [s], [s^2]
        (observation.py; (0, 0) before any estimate)."""
        st = self._st
        if st.force_lag_weight <= 0.0:
            return 0.0, 0.0
        return st.force_lag_weighted_sum / st.force_lag_weight, 1.0 / st.force_lag_weight

    def model_clearance(self) -> float:
        """Axial clearance predicted by the wear model: nominal x_ag + clearance_growth(wear) [m]."""
        st = self._st
        return self._nominal + self._growth(st.screw_raceway_m, st.nut_raceway_m, st.ball_m)

    @property
    def state(self) -> MonitorState:
        """A copy of the persistent state now (save it with :func:`save_state`)."""
        st = self._st
        st.input_faults = self._aligner.fault_counts()
        st.tracker = self._tracker.to_dict()
        st.force_baseline_n = self._segmenter.force_baseline
        return MonitorState.from_dict(st.to_dict())

    def save(self, path: str | Path | None = None) -> None:
        """Save the state atomically to ``path`` (default ``state_path``)."""
        target = Path(path) if path is not None else self.state_path
        if target is None:
            raise ValueError("no state path given")
        save_state(target, self.state)

    def snapshot(self) -> MonitorSnapshot:
        """Totals, clearance, remaining life and input health now."""
        st, cfg, mon = self._st, self.config, self.unit.monitor
        bank = self._tracker.live
        life = wear_life(self._tracker.hyp, bank, mon.clearance_limit, self._mean_model_growth(),
                         observations=st.observations, min_observations=cfg.min_cycles_for_life,
                         z=cfg.life_confidence_z, warn_cycles=mon.warn_cycles, due_cycles=mon.due_cycles)
        fat = fatigue_life(self.unit.ball_screw.dynamic_load_rating, st.sum_f3_rot, st.sum_rot_rad,
                           st.duty_cycles)
        per_hour = span = None
        if (st.duty_cycles >= 2 and st.first_cycle_ns is not None and st.last_cycle_ns is not None
                and st.last_cycle_ns > st.first_cycle_ns):
            span = (st.last_cycle_ns - st.first_cycle_ns) * 1e-9
            per_hour = (st.duty_cycles - 1) / (span / 3600.0)

        def seconds(cycles: float | None) -> float | None:
            return cycles / per_hour * 3600.0 if per_hour and cycles is not None else None

        estimate, estimate_std = bank.clearance()
        rate, rate_std, factor, factor_std = self._growth_rate()
        s50 = seconds(life.cycles_p50)
        return MonitorSnapshot(
            duty_cycles=st.duty_cycles, screw_raceway_m=st.screw_raceway_m, nut_raceway_m=st.nut_raceway_m,
            ball_m=st.ball_m, clearance_model_m=self.model_clearance(),
            clearance_estimate_m=estimate,
            clearance_std_m=estimate_std, growth_rate_m_per_cycle=rate, growth_rate_std_m_per_cycle=rate_std,
            wear_rate_factor=factor, wear_rate_factor_std=factor_std, observations=st.observations,
            clearance_steps=st.clearance_steps, growth_changes=st.growth_changes,
            limit_m=mon.clearance_limit, life_status=life.status,
            cycles_p05=life.cycles_p05, cycles_p50=life.cycles_p50, cycles_p95=life.cycles_p95,
            applications_per_hour=per_hour, usage_span_s=span, seconds_p05=seconds(life.cycles_p05),
            seconds_p50=s50, seconds_p95=seconds(life.cycles_p95),
            hours_p50=None if s50 is None else s50 / 3600.0,
            fatigue_l10_revolutions=fat.l10_revolutions,
            fatigue_cubic_mean_load_n=fat.cubic_mean_load_n, revolutions=fat.revolutions,
            fatigue_remaining_cycles=fat.remaining_cycles, limiting_mechanism=limiting_mechanism(life, fat),
            input_faults=self._aligner.fault_totals(), input_faults_by_signal=self._aligner.fault_counts(),
            input_rates_hz=self._aligner.input_rates_hz(), segments=dict(st.segments),
            last_stamp_ns=st.last_stamp_ns, pending_samples=self._aligner.pending())

    def to_json_dict(self) -> dict[str, Any]:
        """Shortcut: ``snapshot().to_json_dict()``."""
        return self.snapshot().to_json_dict()
