"""Benchmark of the twin: simulated seconds per wall-clock second at 1 kHz, against scipy solve_ivp.

Run: ``.venv/bin/python bench/bench_twin.py [--cycles N]`` (one core: set OMP/MKL threads to 1).

1. The twin: ``simulate_unit`` over N brake applications of the reference unit at 1 kHz,
   with the wear core coupled (surrogate) and sensor noise: simulated / wall seconds.
2. Baseline, same run, same model: the armature voltage the twin's controller applied is replayed
   (zero-order hold per 1 ms sample) into eq. 1, 5, 8, 9 integrated by ``scipy.integrate.solve_ivp``
   (RK45), the usual first coding of such a model; stick-slip needs a smooth friction there,
   ``tanh(ω / 0.05 rad/s)``. Its speed and its agreement with the twin (force RMS) are printed.
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import numpy as np
from scipy.integrate import solve_ivp

from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.twin import NOISELESS, actuator_model, simulate_unit


def baseline(unit, voltage: np.ndarray, rate: float) -> tuple[np.ndarray, float]:
    """solve_ivp (RK45) of the same model driven by ``voltage`` (ZOH); returns force samples and wall s."""
    m = actuator_model(unit)
    law = m.friction
    dt = 1.0 / rate

    def rhs(t, y):
        angle, speed, current = y
        e = voltage[min(int(t / dt), voltage.size - 1)]
        force = m.clamp_force(angle)
        load = m.transmission * force
        friction = np.tanh(speed / 0.05) * (law.coulomb + law.load_coefficient * force) + law.viscous * speed
        return [speed, (m.torque_constant * current - load - friction) / m.inertia,
                (e - m.resistance * current - m.back_emf_constant * speed) / m.inductance]

    t_eval = np.arange(voltage.size) * dt
    start = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, t_eval[-1]), [0.0, 0.0, 0.0], t_eval=t_eval, max_step=dt, rtol=1e-6,
                    atol=1e-9)
    wall = time.perf_counter() - start
    return m.clamp_force(sol.y[0]), wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=200)
    parser.add_argument("--baseline-cycles", type=int, default=4)
    args = parser.parse_args()
    unit = load_unit("embu_000")
    kw = {"hold_s": 1.0, "rest_s": 0.5, "rate_hz": 1000.0}
    simulate_unit(unit, 2, **kw)  # warm the wear surrogate's cache
    start = time.perf_counter()
    run = simulate_unit(unit, args.cycles, **kw)
    wall = time.perf_counter() - start
    simulated = run.t.size / kw["rate_hz"]
    twin_rate = simulated / wall
    print(f"twin, {args.cycles} applications at 1 kHz with wear coupling: {simulated:.1f} s simulated in "
          f"{wall:.2f} s wall -> {twin_rate:.0f}x real time (target >= 50x)")

    short = simulate_unit(unit, args.baseline_cycles, noise=NOISELESS, wear=False, **kw)
    start = time.perf_counter()
    simulate_unit(unit, args.baseline_cycles, noise=NOISELESS, wear=False, **kw)
    short_wall = time.perf_counter() - start
    force, base_wall = baseline(unit, short.clean["voltage"], kw["rate_hz"])
    short_sim = short.t.size / kw["rate_hz"]
    rms = float(np.sqrt(np.mean((force - short.clean["axial_force"]) ** 2)))
    print(f"same {args.baseline_cycles} applications ({short_sim:.1f} s): "
          f"twin {short_sim / short_wall:.0f}x, "
          f"solve_ivp RK45 {short_sim / base_wall:.1f}x real time; twin / solve_ivp speed ratio "
          f"{base_wall / short_wall:.0f}x (same-run, batched twin vs per-sample adaptive RK45)")
    peak = short.clean["axial_force"].max()
    print(f"agreement: force RMS difference {rms:.0f} N over a peak of {peak:.0f} N "
          f"(smooth friction vs switched stick-slip)")
    print(f"twin at {args.cycles} applications vs solve_ivp: {twin_rate / (short_sim / base_wall):.0f}x")


if __name__ == "__main__":
    main()
