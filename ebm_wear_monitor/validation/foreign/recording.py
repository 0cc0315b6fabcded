"""A case becomes a rosbag2 directory with its ground truth: simulate, acquire, write."""

from __future__ import annotations

import hashlib
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np
import yaml

from . import life, sensors
from .bag import write_bag
from .cases import Case, Recipe, realize
from .effects import Context, build
from .plant import Physics
from .simulate import PLANT_RATE, Trajectory, onset_times, simulate
from .unit import REFERENCE_UNIT, Actuator, load_actuator

GENERATOR = "ebm_wear_monitor.validation.foreign"
UNIT_YAML = "unit.yaml"  # unit file written beside a life history (inside its bag directory)
VERSION = 2  # 2: stable tracking observer at every rate, asynchronous instant current sampling
#: Carrier phase of a current sample by sampling convention (``sensors.current``).
CARRIER_PHASE = {
    "instant": "asynchronous: frac(phi_0 + pwm_hz t + psi(t)), pwm_hz / rate = integer + golden "
               "fraction, psi a random walk; the ripple is zero-mean noise",
    "centered": "PWM centre (triggered by the carrier): no ripple",
    "average": "mean over the control period: no ripple"}


def physics_of(case: Case, act: Actuator, recipe: Recipe, rng: np.random.Generator
               ) -> tuple[Physics, list[dict]]:
    """Effect hooks of ``case`` and their truth records (``effects.py``)."""
    onset, duration = onset_times(recipe.schedule, recipe.ecu)
    return build(case.forms, Context(act=act, onset=onset, duration=duration, rng=rng))


def acquire(act: Actuator, recipe: Recipe, tr: Trajectory, rng: np.random.Generator
            ) -> dict[str, dict]:
    """Sample every topic by its clock and sensor convention.

    Returns topic -> ``{"t": sample instants [s], "stamp_ns", "log_ns", "value"}``.
    """
    acq = recipe.acq
    duration = tr.t[-1] + 1.0 / PLANT_RATE
    out = {}
    for topic in sensors.TOPICS:
        clock = acq.clocks[topic]
        ticks, delivered = sensors.sample_times(clock, duration, rng)
        t = ticks[delivered]
        if topic == "screw/angle":
            value = sensors.encoder(acq, tr, t, act.i_g)
        elif topic == "screw/velocity":  # estimated on the device at every tick, then dropped
            value = sensors.velocity(acq, sensors.encoder(acq, tr, ticks, act.i_g),
                                     clock.rate)[delivered]
        elif topic == "axial_force":
            value = sensors.force(acq, tr, t, rng)
        else:
            value = sensors.current(acq, tr, t, v_bus=recipe.ecu.V_bus, inductance=act.L,
                                    control_rate=recipe.ecu.rate, rng=rng)
        stamp = recipe.start_ns + np.round(t * 1e9).astype(np.int64)
        lag = np.round(rng.uniform(acq.lag_min, acq.lag_max, t.size) * 1e9).astype(np.int64)
        log = np.maximum.accumulate(stamp + lag)  # one topic is received in order (FIFO)
        out[topic] = {"t": t, "stamp_ns": stamp, "log_ns": log, "value": value}
    return out


def _sensor_rest(act: Actuator, recipe: Recipe, tr: Trajectory) -> np.ndarray:
    """True (unquantised) encoder reading at each application's rest, screw angle [rad]."""
    acq = recipe.acq
    idx = np.round(tr.onset * PLANT_RATE).astype(int)
    if acq.encoder_side == "screw":
        return tr.q[idx] / act.i_g + acq.encoder_offset
    return (tr.theta[idx] + acq.encoder_offset) / act.i_g


def ground_truth(case: Case, act: Actuator, recipe: Recipe, tr: Trajectory, *, clearance: np.ndarray,
                 effects: list[dict], samples: dict[str, dict], unit: Path) -> dict:
    """The sidecar: the project's schema per unit, everything else under ``"foreign"``."""
    acq, sched, start = recipe.acq, recipe.schedule, recipe.start_ns * 1e-9
    limit = recipe.limit
    spec = case.option("clearance")
    if spec:
        eol = life.end_of_life(spec, limit)
    else:
        over = np.flatnonzero(clearance >= limit)
        eol = float(over[0]) if over.size else None
    catalog = {e["name"]: e for e in effects if e["catalog"]}
    topics = {}
    for topic, s in samples.items():
        c = acq.clocks[topic]
        topics[f"{recipe.namespace}/{topic}"] = {
            "rate_hz": c.rate, "phase_s": c.phase, "jitter_std_s": c.jitter, "dropped": c.drops,
            "frame_id": c.frame_id, "messages": int(s["t"].size)}

    def stamps(x: np.ndarray) -> list[float]:
        return [float(start + v) for v in x]

    foreign = {
        "case_id": case.case_id, "kind": case.kind, "seed": case.seed, "case": case.to_json(),
        "catalog_effects": list(case.effects),
        "effects_detail": effects,
        "unit_file": unit.name,
        "unit_sha256": hashlib.sha256(unit.read_bytes()).hexdigest(),
        "controller": asdict(recipe.ecu),
        "namespace": recipe.namespace, "storage": recipe.storage, "start_stamp_s": start,
        "topics": topics,
        "log_time_lag_s": {"min": acq.lag_min, "max": acq.lag_max,
                           "meaning": "bag log time = header stamp + U(min, max)"},
        "encoder": {"side": acq.encoder_side, "bits": acq.encoder_bits,
                    "offset_rad": acq.encoder_offset,
                    "offset_frame": "screw" if acq.encoder_side == "screw" else "motor",
                    "quantum_screw_rad": 2 * np.pi / 2**acq.encoder_bits
                    / (1.0 if acq.encoder_side == "screw" else act.i_g)},
        "rest_angle_sensor_rad": _sensor_rest(act, recipe, tr).tolist(),
        "rest_angle_screw_rad": (tr.rest / act.i_g).tolist(),
        "velocity": {"estimator": acq.velocity_kind, "parameter": acq.velocity_param,
                     "parameter_meaning": {"derivative": "low-pass time constant [s]",
                                           "moving_average": "window length [samples]",
                                           "tracking": "observer natural frequency [rad/s]"}
                     [acq.velocity_kind],
                     "lag_s": acq.velocity_lag(acq.clocks["screw/velocity"].rate)},
        "force": {"tare_N": acq.tare, "lag_s": recipe.cell_lag, "noise_std_N": acq.noise_F,
                  "lsb_N": acq.lsb_F},
        "current": {"sampling": acq.current_kind, "pwm_hz": acq.f_pwm, "noise_std_A": acq.noise_I,
                    "lsb_A": acq.lsb_I, "average_period_s": 1.0 / recipe.ecu.rate,
                    "carrier_phase": CARRIER_PHASE[acq.current_kind],
                    "phase_drift_cycles_per_sqrt_s": sensors.PWM_PHASE_DIFFUSION
                    if acq.current_kind == "instant" else None},
        "applications": {
            "demand_N": sched.demand.tolist(), "hold_s": sched.hold.tolist(),
            "reference_error_screw_rad": sched.eps.tolist(),
            "onset_stamp_s": stamps(tr.onset), "contact_stamp_s": stamps(tr.contact),
            "release_stamp_s": stamps(tr.release), "unload_stamp_s": stamps(tr.unload),
            "motor_off_stamp_s": stamps(tr.off), "peak_force_N": tr.peak_force.tolist(),
            "held_force_N": tr.held_force.tolist(), "clearance_m": clearance.tolist()},
        "clearance_schedule": None if spec is None else {
            "spec": list(spec), "meaning": "see life.py: clearance in force during application n",
            "eol_meaning": "application index (from the first of this recording) at which the "
                           "schedule reaches the limit; remaining life at n = eol - n"},
        "unit_yaml": UNIT_YAML if spec else None,
        "plant_rate_hz": PLANT_RATE,
        "stitch_error": tr.stitch_error,
        "nominal": asdict(act),
    }
    unit_entry = {"clearance_limit_m": limit, "eol_cycles": eol, "cycles_at_start": 0,
                  "clearance_m": clearance.tolist(), "effects": catalog, "foreign": foreign}
    return {"units": {recipe.namespace: unit_entry},
            "generator": {"name": GENERATOR, "version": VERSION}}


def unit_yaml(unit: Path, limit: float) -> str:
    """The unit file's values with only ``monitor.clearance_limit`` set to ``limit`` [m]."""
    doc = yaml.safe_load(unit.read_text())
    doc["monitor"] = {"clearance_limit": float(limit)}
    return yaml.safe_dump(doc, sort_keys=False)


def _seeds(case: Case) -> list[np.random.SeedSequence]:
    """Seeds of the effects, the simulation and the acquisition of ``case``."""
    return np.random.SeedSequence([case.seed, 0x5EED]).spawn(3)


def simulate_case(case: Case, unit: str | Path = REFERENCE_UNIT
                  ) -> tuple[Actuator, Recipe, Physics, list[dict], Trajectory]:
    """Draw the world of ``case`` and simulate its true trajectory (the first stage of
    :func:`write_case`): ``(actuator, recipe, effect hooks, effect records, trajectory)``."""
    act = load_actuator(Path(unit))
    recipe = realize(case, act)
    act = act.with_(clearance_limit=recipe.limit)
    seeds = _seeds(case)
    phys, effects = physics_of(case, act, recipe, np.random.default_rng(seeds[0]))
    tr = simulate(act, phys, recipe.ecu, recipe.schedule, cell_lag=recipe.cell_lag,
                  seed=int(np.random.default_rng(seeds[1]).integers(2**31)))
    return act, recipe, phys, effects, tr


def write_case(case: Case, out_dir: str | Path, unit: str | Path = REFERENCE_UNIT,
               timings: dict[str, float] | None = None) -> Path:
    """Generate ``case`` into ``out_dir/<case_id>`` (rosbag2 + ``ground_truth.json``, and
    ``unit.yaml`` for life histories); returns that directory.

    ``timings``, if given, receives the seconds spent in ``simulate``, ``acquire`` and ``write``
    and the number of ``messages`` written.
    """
    t0 = time.perf_counter()
    unit = Path(unit)
    act, recipe, phys, effects, tr = simulate_case(case, unit)
    t1 = time.perf_counter()
    clearance = recipe.schedule.x_ag + (0.0 if phys.clearance_extra is None else phys.clearance_extra)
    samples = acquire(act, recipe, tr, np.random.default_rng(_seeds(case)[2]))
    truth = ground_truth(case, act, recipe, tr, clearance=np.asarray(clearance, dtype=float),
                         effects=effects, samples=samples, unit=unit)
    topics = {f"{recipe.namespace}/{topic}": (s["stamp_ns"], s["log_ns"], s["value"],
                                              recipe.acq.clocks[topic].frame_id)
              for topic, s in samples.items()}
    t2 = time.perf_counter()
    extra = {UNIT_YAML: unit_yaml(unit, recipe.limit)} if case.option("clearance") else {}
    path = write_bag(Path(out_dir) / case.case_id, recipe.storage, topics, truth, extra)
    if timings is not None:
        timings.update(simulate=t1 - t0, acquire=t2 - t1, write=time.perf_counter() - t2,
                       messages=float(sum(s["t"].size for s in samples.values())))
    return path
