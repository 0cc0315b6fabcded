"""Benchmark of the 000 wear core: per-sample scipy.optimize baseline vs vectorised direct solve vs surrogate.

    .venv/bin/python bench/bench_wear.py [--samples 1000000] [--baseline-samples 1000]

The baseline is the way such a framework is usually first coded: a Python loop over
samples, each solving the ball equilibrium (000 eq. 1, 5, 8-18 with the axial closure)
with ``scipy.optimize.fsolve`` on the four unknowns (a_s, a_n, Q_s, Q_n), then eq. 6-7
and 23 on scalars. It uses the same physics functions as the package, so its results
are checked against the direct solve. It runs on a subsample and its per-sample rate is
extrapolated. All three are measured in the same run, on one process.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.optimize import fsolve

from ebm_wear_monitor.params import UnitParams, load_unit
from ebm_wear_monitor.physics import ModelOptions, wear_model
from ebm_wear_monitor.physics.archard import wear_rate
from ebm_wear_monitor.physics.contact import area_radius, softer_poisson
from ebm_wear_monitor.physics.equilibrium import _friction
from ebm_wear_monitor.physics.geometry import NUT, SCREW, ScrewGeometry, curvature
from ebm_wear_monitor.physics.hertz import deformation, normal_load
from ebm_wear_monitor.physics.kinematics import ball_motion
from ebm_wear_monitor.physics.plasticity import contact_area


def baseline_rates(unit: UnitParams, force: float, speed: float,
                   options: ModelOptions) -> tuple[float, float]:
    """One sample, solved with fsolve: residuals of eq. 15 (+ closure) and the geometry of eq. 16-18."""
    geo = ScrewGeometry.from_unit(unit)
    p = force / (geo.z * math.cos(geo.phi))
    a2 = geo.centre_distance0 * math.cos(geo.alpha0)

    def state(x):
        a_s, a_n, q_s, q_n = x
        motion = ball_motion(geo, speed, a_s, a_n, reading=options.kinematics, beta=options.beta)
        u = abs(float(motion.omega_r)) * geo.r_b
        mu_s = float(_friction(unit, geo, SCREW, q=np.float64(q_s), alpha=np.float64(a_s), u=np.float64(u)))
        mu_n = float(_friction(unit, geo, NUT, q=np.float64(q_n), alpha=np.float64(a_n), u=np.float64(u)))
        c_s, c_n = curvature(geo, SCREW, a_s), curvature(geo, NUT, a_n)
        d_s = float(deformation(q_s, c_s.sum_rho, c_s.gamma, geo.e_s))
        d_n = float(deformation(q_n, c_n.sum_rho, c_n.gamma, geo.e_n))
        return motion, mu_s, mu_n, d_s, d_n

    def residual(x):
        a_s, a_n, q_s, q_n = x
        motion, mu_s, mu_n, d_s, d_n = state(x)
        ss, cs, sn, cn = math.sin(a_s), math.cos(a_s), math.sin(a_n), math.cos(a_n)
        l_s, l_n = geo.r_s - geo.r_b + d_s, geo.r_n - geo.r_b + d_n
        return [(-q_s * cs + mu_s * q_s * ss + q_n * cn + mu_n * q_n * sn - float(motion.centrifugal)) / p,
                (q_s * ss + mu_s * q_s * cs - q_n * sn + mu_n * q_n * cn) / p,
                (q_s * ss + mu_s * q_s * cs - p) / p,
                (l_s * cs + l_n * cn - a2) / geo.r_b]

    q0 = float(normal_load(force, geo.z, geo.alpha0, geo.phi))
    x = fsolve(residual, [geo.alpha0, geo.alpha0, q0, q0], xtol=1e-12)
    motion, _, _, d_s, d_n = state(x)
    rates = []
    sides = ((SCREW, x[0], x[2], d_s, motion.v_screw), (NUT, x[1], x[3], d_n, motion.v_nut))
    for side, alpha, q, d, v in sides:
        c = curvature(geo, side, alpha)
        mat = getattr(unit.materials, side)
        ca = contact_area(np.array([d]), c.gamma, area_radius(unit, np.array([c.sum_rho]), options.radius),
                          hardness=mat.hardness, poisson_ratio=softer_poisson(unit, side),
                          e_red=geo.modulus(side), kappa_reading=options.kappa)
        rates.append(float(wear_rate(unit.wear.k_slip, q, float(v), mat.yield_strength, ca.area)[0]))
    return rates[0], rates[1]


def best_of(fn, repeats: int) -> tuple[float, object]:
    best, out = math.inf, None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1_000_000)
    ap.add_argument("--baseline-samples", type=int, default=1000)
    ap.add_argument("--params", default="embu_000")
    args = ap.parse_args()
    unit = load_unit(args.params)
    options = ModelOptions()
    rng = np.random.default_rng(0)
    force = rng.uniform(100.0, 30e3, args.samples)  # N, inside the operating envelope
    speed = rng.uniform(-30.0, 30.0, args.samples)  # rad/s, both directions

    nb = args.baseline_samples
    t0 = time.perf_counter()
    base = np.array([baseline_rates(unit, f, w, options)
                     for f, w in zip(force[:nb], speed[:nb], strict=True)])
    t_base = (time.perf_counter() - t0) / nb

    direct = wear_model(unit, "direct")
    t_direct, r_direct = best_of(lambda: direct.rates(force, speed), 2)
    t0 = time.perf_counter()
    surrogate = wear_model(unit, "surrogate")
    t_build = time.perf_counter() - t0
    t_sur, r_sur = best_of(lambda: surrogate.rates(force, speed), 5)

    n = args.samples
    dev_base = np.max(np.abs(base[:, 0] / r_direct.screw[:nb] - 1.0))
    dev_sur = max(float(np.max(np.abs(a / b - 1.0))) for a, b in zip(r_sur, r_direct, strict=True))
    print(f"samples: {n:,} (baseline on {nb:,}, extrapolated per sample)")
    print(f"baseline  per-sample fsolve : {1.0 / t_base:14,.0f} samples/s   "
          f"({t_base * 1e3:.3f} ms/sample)")
    print(f"direct    vectorised Fig. 6 : {n / t_direct:14,.0f} samples/s   "
          f"ratio {t_base * n / t_direct:8.0f}x")
    print(f"surrogate table look-up     : {n / t_sur:14,.0f} samples/s   ratio {t_base * n / t_sur:8.0f}x"
          f"   (table built once in {t_build:.2f} s)")
    print(f"max rel. deviation: baseline vs direct {dev_base:.2e}, surrogate vs direct {dev_sur:.2e}")
    print(f"targets: direct >= 100x baseline: {'met' if t_base * n / t_direct >= 100 else 'MISSED'}; "
          f"surrogate >= 1e7 samples/s: {'met' if n / t_sur >= 1e7 else 'MISSED'}")


if __name__ == "__main__":
    main()
