"""Duty-cycle simulator: the twin of 004 under its brake controller, coupled to the wear core of 000.

A run is a sequence of brake applications (one per demanded clamp force), each
the four phases of 000 Fig. 2 followed by an idle rest (:mod:`.controller`).
Wear coupling, per application:

1. the true axial force F_cl(t) and screw speed ω_s(t) = ω_m / i_g feed
   ``ebm_wear_monitor.physics.wear_model(unit).rates(F, ω_s)`` (000 eq. 5-23),
   whose wear-depth rates [m/s] are integrated over the samples (rectangle
   rule at the sample rate) and multiplied by the **wear-acceleration factor**
   ``wear_acceleration`` (1 = real wear; > 1 compresses an endurance test
   into fewer simulated applications; the factor is recorded in the ground
   truth and in the bag sidecar);
2. the axial clearance is ``x_ag = x_ag,0 + physics.clearance_growth(unit,
   screw, nut, ball)`` (+ the ``clearance_growth`` effect), so the clamp
   contact of later applications moves out and long runs show the growth.

The brake controller runs at ``rate_hz`` or, for recordings slower than
1 kHz, at the smallest multiple of it that reaches 1 kHz, and the recording keeps
every k-th step (a data logger sampling a faster drive).

Applications that start from rest are independent given the clearance, so
they are simulated in parallel batches (vectorised over the batch axis); the
clearance of the i-th application of a batch is the clearance at the batch
start plus i times the growth per application measured on the previous batch
(a linear extrapolation within the batch, exact when growth per application is
steady; the first application runs alone to measure it). Where the extrapolation
misses by more than :data:`CLEARANCE_TOLERANCE_M` (demands of unequal wear under
accelerated wear), the batch runs once more with each application's clearance
taken from the wear of the applications before it, so the plant and the wear
ground truth agree. Each application
starts at the exact rest angle; the release leaves the drive within
``rest_tolerance`` (0.01 rad at the motor, 1.6 µm of nut travel for a 5 mm
lead) of it, which is dropped at the idle boundary between applications.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.domain.phases import PHASE_NAMES
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.twin.controller import (
    CONTROL_RATE_HZ,
    BrakeController,
    ClosedLoopRecord,
    run_duty_cycles,
)
from ebm_wear_monitor.twin.dynamics import ActuatorModel, actuator_model
from ebm_wear_monitor.twin.effects import ForceSensorError, apply_effects, check_effects, force_sensor_error
from ebm_wear_monitor.twin.sensors import SensorNoise, measure

#: default demand sequence [N]: service applications of a railway EMBU cycling through three levels
DEFAULT_DEMANDS = (10.0e3, 15.0e3, 20.0e3)
SURFACES = ("screw", "nut", "ball")
DEFAULT_NOISE = SensorNoise()
DEFAULT_CONTROLLER = BrakeController()
#: largest in-batch clearance extrapolation error accepted without a corrective pass [m]
#: (a tenth of the 1 kHz clearance observation noise, monitor/observation.py)
CLEARANCE_TOLERANCE_M = 0.05e-6


@dataclass
class SimResult:
    """Recorded-like signals of a run, their truth, and the ground truth of wear and clearance.

    Sample arrays have shape (n,); ``angle``/``velocity`` are screw-side (interface.md
    section 2); ``phase`` holds codes into :data:`PHASE_NAMES`; ``cycle`` the application index.
    """

    t: np.ndarray  # sample times [s]
    angle: np.ndarray  # measured screw angle from rest [rad]
    velocity: np.ndarray  # measured screw speed [rad/s]
    axial_force: np.ndarray  # measured axial force [N]
    current: np.ndarray  # measured armature current [A]
    phase: np.ndarray  # phase code per sample (int8)
    cycle: np.ndarray  # application index per sample (int32)
    clean: dict[str, np.ndarray]  # noise-free truth: angle, velocity, axial_force, current,
    # voltage [V], motor_torque and friction_torque [N m] (motor shaft)
    truth: dict  # per-application ground truth (see :func:`simulate_unit`)
    phases: tuple[str, ...] = PHASE_NAMES

    def signals(self) -> dict[str, np.ndarray]:
        """The four input signals by name, as ``bagio.write_unit_bag`` takes them."""
        return {"angle": self.angle, "velocity": self.velocity, "axial_force": self.axial_force,
                "current": self.current}

    def ground_truth(self) -> dict:
        """The unit entry of the bag sidecar (``bagio.sidecar`` schema plus the twin's own keys)."""
        tr = self.truth
        return {
            "clearance_limit_m": tr["clearance_limit_m"],
            "eol_cycles": tr["eol_cycles"],
            "cycles_at_start": tr["cycles_at_start"],
            "clearance_m": [float(v) for v in tr["clearance_after_m"]],
            "effects": dict(tr["effects"]),
            "wear_acceleration": tr["wear_acceleration"],
            "wear_m": ({k: [float(v) for v in tr["wear_m"][k]] for k in SURFACES}
                       if tr["wear_m"] is not None else None),
            "demands_N": [float(v) for v in tr["demands_N"]],
            "hold_s": [float(v) for v in tr["hold_s"]],
            "noise_std": dict(tr["noise_std"]),
            "rate_hz": tr["rate_hz"],
            "seed": tr["seed"],
            "phase_names": list(PHASE_NAMES),
            "cycle_start_s": [float(v) for v in tr["cycle_start_s"]],
            "phase_start_s": [[None if math.isnan(v) else float(v) for v in row]
                              for row in tr["phase_start_s"].tolist()],
        }


def _cycled(values: float | Sequence[float] | np.ndarray | None, default: Sequence[float], n: int,
            name: str) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(default if values is None else values, float))
    if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise InputError(f"{name}: need positive finite values, got {values!r}")
    return np.resize(arr, n)


def _wear_core(unit: UnitParams, method: str):
    from ebm_wear_monitor.physics import clearance_growth, wear_model
    return wear_model(unit, method=method), clearance_growth


def _cycle_wear(rates_model, record: ClosedLoopRecord, gear_ratio: float, dt: float) -> np.ndarray:
    """Wear-depth increments of each application of a batch [m], shape (3, batch) (screw, nut, ball)."""
    n, batch = record.force.shape
    inside = np.arange(n)[:, None] < record.length[None, :]
    rates = rates_model.rates(record.force[inside], record.motor_speed[inside] / gear_ratio)
    which = np.broadcast_to(np.arange(batch), (n, batch))[inside]
    return np.stack([np.bincount(which, weights=np.asarray(getattr(rates, s)) * dt, minlength=batch)
                     for s in SURFACES])


def simulate_unit(  # noqa: PLR0917 (the positional order of the issue's API)
        unit: UnitParams, cycles: int, demands: float | Sequence[float] | None = None,
                  effects: Mapping[str, float] | None = None, seed: int = 0, rate_hz: float = 1000.0,
                  wear_acceleration: float = 1.0, *, hold_s: float | Sequence[float] = 1.0,
                  rest_s: float = 0.5, noise: SensorNoise = DEFAULT_NOISE, prior_cycles: int = 0,
                  wear: bool = True, wear_method: str = "surrogate",
                  controller: BrakeController = DEFAULT_CONTROLLER, batch: int = 64,
                  progress: bool = False) -> SimResult:
    """Simulate ``cycles`` brake applications of one unit at ``rate_hz`` (1 kHz default).

    Args:
        unit: the unit (needs its ``actuator`` block).
        cycles: number of brake applications.
        demands: demanded clamp force(s) [N], cycled over the applications
            (default :data:`DEFAULT_DEMANDS`).
        effects: catalog effects {name: magnitude} present in the "real" unit (:mod:`.effects`).
        seed: seed of the sensor noise.
        rate_hz: recorded sample rate [Hz] (the controller runs at >= 1 kHz, see above).
        wear_acceleration: factor on every wear increment (accelerated-life scenarios) [-].
        hold_s: force-maintenance time(s) [s], cycled; rest_s: idle time after each release [s].
        noise: sensor noise (:class:`.sensors.SensorNoise`; ``sensors.NOISELESS`` for none).
        prior_cycles: applications the unit made before this run; their wear (at the
            per-application wear of this run's first batch, unaccelerated) is the initial wear.
        wear: couple to the wear core (False: constant clearance, no wear ground truth).
        wear_method: ``"surrogate"`` or ``"direct"`` (physics core).
        batch: applications simulated in parallel.
        progress: show a tqdm progress bar.

    Ground truth (``result.truth``): ``wear_m`` {screw, nut, ball: cumulative wear depth after
    each application [m]}, ``clearance_m`` (x_ag during each application) and
    ``clearance_after_m`` [m], ``effects``, ``wear_acceleration``, ``demands_N``, ``hold_s``,
    ``cycle_start_s``, ``phase_start_s`` (application x phase start times [s], phases as
    :data:`PHASE_NAMES`), ``noise_std``, ``eol_cycles`` (applications since new at which x_ag reaches
    the unit's ``monitor.clearance_limit``, extrapolated linearly; None without growth).
    """
    if isinstance(cycles, bool) or int(cycles) != cycles or cycles < 1:
        raise InputError(f"cycles must be a whole number >= 1, got {cycles!r}")
    if not 10.0 <= rate_hz <= 20_000.0:
        raise InputError(f"rate must be within 10 Hz .. 20 kHz, got {rate_hz:g}")
    if not (math.isfinite(wear_acceleration) and wear_acceleration > 0.0):
        raise InputError(f"wear acceleration must be > 0, got {wear_acceleration:g}")
    if prior_cycles < 0 or rest_s < 0.0 or batch < 1:
        raise InputError("prior_cycles and rest_s must be >= 0 and batch >= 1")
    cycles = int(cycles)
    effects = check_effects(effects)
    demand_seq = _cycled(demands, DEFAULT_DEMANDS, cycles, "demands")
    hold_seq = _cycled(hold_s, (1.0,), cycles, "hold_s")
    plant = apply_effects(actuator_model(unit), effects)
    sensor = force_sensor_error(effects)
    base_clearance = plant.clamp.clearance
    keep = max(1, math.ceil(CONTROL_RATE_HZ / rate_hz - 1e-9))  # control steps per recorded sample
    dt = 1.0 / (rate_hz * keep)
    core = _wear_core(unit, wear_method) if wear else None

    def growth(total: np.ndarray) -> np.ndarray:
        """Clearance growth [m] from wear depths [m] (screw, nut, ball) of shape (3,) or (3, k)."""
        return core[1](unit, *total) if core is not None else np.zeros(np.shape(total)[1:])

    def run(model: ActuatorModel, lo: int, hi: int) -> ClosedLoopRecord:
        return run_duty_cycles(model, demand_seq[lo:hi], hold_seq[lo:hi], rest=rest_s, rate_hz=1.0 / dt,
                               controller=controller, force_offset=sensor.offset,
                               force_gain_error=sensor.gain)

    def with_clearance(clearance: np.ndarray) -> ActuatorModel:
        return dataclasses.replace(plant, clamp=dataclasses.replace(plant.clamp, clearance=clearance))

    total = np.zeros(3)
    if core is not None and prior_cycles > 0:
        first = run(plant, 0, 1)
        total = _cycle_wear(core[0], first, plant.gear_ratio, dt)[:, 0] * prior_cycles
    wear_after = np.zeros((3, cycles))
    clearance_during, clearance_after = np.zeros(cycles), np.zeros(cycles)
    records: list[tuple[ClosedLoopRecord, int]] = []
    step = 0.0  # growth per application, from the previous batch [m]
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=cycles, unit="cycle", desc="simulate")
    # with wear on, the first application runs alone to measure the growth per application
    bounds = [0, 1] if core is not None else [0]
    bounds = sorted({*bounds, *range(bounds[-1] + batch, cycles, batch), cycles})
    for lo, hi in itertools.pairwise(bounds):
        start = base_clearance + float(growth(total))
        clearance = start + step * np.arange(hi - lo)
        record = run(with_clearance(clearance), lo, hi)
        if core is not None:
            increments = _cycle_wear(core[0], record, plant.gear_ratio, dt) * wear_acceleration
            # the clearance each application really starts with, from the wear of the ones before it
            before = total[:, None] + np.cumsum(increments, axis=1) - increments
            exact = base_clearance + growth(before)
            if np.max(np.abs(exact - clearance)) > CLEARANCE_TOLERANCE_M:
                clearance = exact  # the extrapolation missed (demands of unequal wear): one corrective pass
                record = run(with_clearance(clearance), lo, hi)
                increments = _cycle_wear(core[0], record, plant.gear_ratio, dt) * wear_acceleration
            wear_after[:, lo:hi] = total[:, None] + np.cumsum(increments, axis=1)
        clearance_during[lo:hi] = clearance
        if core is not None:
            total = wear_after[:, hi - 1].copy()
            clearance_after[lo:hi] = base_clearance + growth(wear_after[:, lo:hi])
            step = (clearance_after[hi - 1] - start) / (hi - lo)
        else:
            clearance_after[lo:hi] = clearance
        records.append((record, lo))
        if bar is not None:
            bar.update(hi - lo)
    if bar is not None:
        bar.close()
    return _assemble(plant, records, dict(
        effects=effects, wear_acceleration=float(wear_acceleration), demands_N=demand_seq, hold_s=hold_seq,
        noise_std=noise.as_dict(), rate_hz=float(rate_hz), seed=int(seed), cycles_at_start=int(prior_cycles),
        wear_m={s: wear_after[i] for i, s in enumerate(SURFACES)} if core is not None else None,
        clearance_m=clearance_during, clearance_after_m=clearance_after,
        nominal_clearance_m=float(unit.require_actuator().clearance),
        clearance_limit_m=float(unit.monitor.clearance_limit)), noise=noise, sensor=sensor, dt=dt, keep=keep)


def _assemble(plant: ActuatorModel, records: list[tuple[ClosedLoopRecord, int]], truth: dict, *,
              noise: SensorNoise, sensor: ForceSensorError, dt: float, keep: int) -> SimResult:
    """Concatenate the batches' applications in order, keep every ``keep``-th control step as a
    recorded sample, and add the sensors."""
    i_g = plant.gear_ratio
    pieces: dict[str, list[np.ndarray]] = {k: [] for k in (
        "angle", "velocity", "axial_force", "current", "voltage", "motor_torque", "friction_torque",
        "phase", "cycle")}
    starts = []
    offset = 0
    for record, lo in records:
        for i, n in enumerate(record.length.tolist()):
            starts.append(offset * dt)
            offset += n
            pieces["angle"].append(record.motor_angle[:n, i] / i_g)
            pieces["velocity"].append(record.motor_speed[:n, i] / i_g)
            pieces["axial_force"].append(record.force[:n, i])
            pieces["current"].append(record.current[:n, i])
            pieces["voltage"].append(record.voltage[:n, i])
            pieces["motor_torque"].append(record.motor_torque[:n, i])
            pieces["friction_torque"].append(record.friction_torque[:n, i])
            pieces["phase"].append(record.phase[:n, i])
            pieces["cycle"].append(np.full(n, lo + i, np.int32))
    clean = {k: np.concatenate(v) for k, v in pieces.items()}
    phase, cycle = clean.pop("phase").astype(np.int8), clean.pop("cycle")
    truth["cycle_start_s"] = np.array(starts)
    # start time of each phase of each application [s] (NaN if a phase never came)
    first = np.full((len(starts), len(PHASE_NAMES)), np.nan)
    index = np.arange(offset)
    key = cycle.astype(np.int64) * len(PHASE_NAMES) + phase
    keys, where = np.unique(key, return_index=True)
    first.flat[keys] = index[where] * dt
    truth["phase_start_s"] = first
    recorded = slice(None, None, keep)
    clean = {k: v[recorded] for k, v in clean.items()}
    measured = measure(clean, noise, sensor, np.random.default_rng(truth["seed"]))
    after = truth["clearance_after_m"]
    growth_per_cycle = (after[-1] - truth["clearance_m"][0]) / len(after) if len(after) else 0.0
    limit = truth["clearance_limit_m"]
    truth["eol_cycles"] = (truth["cycles_at_start"] + len(after) + (limit - after[-1]) / growth_per_cycle
                           if growth_per_cycle > 0.0 else None)
    return SimResult(t=index[recorded] * dt, angle=measured["angle"], velocity=measured["velocity"],
                     axial_force=measured["axial_force"], current=measured["current"],
                     phase=phase[recorded], cycle=cycle[recorded], clean=clean, truth=truth)
