"""An independent integration of 004's actuator, to test the diagnosis on data the twin did not make.

The twin's simulator (:mod:`ebm_wear_monitor.twin`) integrates 004 eq. 1 and 8
with fixed steps at the controller rate, holds the armature voltage over each
control period and records the current at the start of each step.  A
diagnosis tested only on such data could learn that integrator's
discretisation.  This module simulates the same physics with none of those
choices, for the self-test (:mod:`.selftest`) and the tests:

* **plant** (004 eq. 1, 5, 8): states motor angle theta_m, speed w_m and
  armature current I;
  J_me dw_m/dt = K_T I - l F / (2 pi i_g) - T_f,  L dI/dt = E - R I - K_E w_m,
  F = K_b max(0, l theta_m / (2 pi i_g) - x_ag);
* **friction**: 004 eq. 9 regularised, T_f = (T_fc + G F) tanh(w_m / w_r) + B w_m
  with w_r = 0.2 rad/s (no stick-slip switching: another functional form
  near zero speed than the twin's switched law);
* **controller**: continuous in time (no sample-and-hold): while applying,
  E = k_F (F_d - F) - k_w w_m, which saturates at the supply voltage during
  clearance elimination and regulates the force afterwards; while releasing,
  E = k_theta (theta_0 - theta_m) - k_w w_m back to the rest angle; the drive's
  current limit as in the twin (E within K_E w_m +- R I_max);
* **integrator**: ``scipy.integrate.solve_ivp`` (RK45, adaptive, step at most a
  quarter of the sample interval), all brake applications integrated side by
  side as one system (they start from rest and are independent);
* **sampling**: every signal at the sample instants, the current either
  instantaneous (``current_sampling="instant"``) or as its mean over the
  preceding sample period (``"mean"``, an integrating converter: a delay of half
  a period), white noise of :class:`ebm_wear_monitor.twin.SensorNoise` levels.

Effects (``effects`` = {name: magnitude}) in forms of this module:
``viscous_friction`` B (1 + m), ``load_friction`` G (1 + m), ``preload_change``
T_fc + m [N m], ``clearance_growth`` x_ag + m [m], ``force_sensor_bias`` +m [N].
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from ebm_wear_monitor.diagnosis.recording import Resampled
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.twin import actuator_model
from ebm_wear_monitor.twin.sensors import SensorNoise

REFERENCE_EFFECTS = ("viscous_friction", "load_friction", "preload_change", "clearance_growth",
                     "force_sensor_bias")
W_REG = 0.2  # speed of the tanh regularisation of Coulomb friction [rad/s, motor]
K_F = 53.0 / 2000.0  # force gain: full supply voltage at 2 kN force error [V/N]
K_W = 0.05  # speed damping [V s/rad]
K_THETA = 400.0  # release angle gain [V/rad]: settles in ~20 ms against the creep damping


def simulate_reference(unit: UnitParams, demands: tuple[float, ...], *, cycles: int = 20,
                       apply_s: float = 0.5, release_s: float = 0.4, rate_hz: float = 1000.0,
                       current_sampling: str = "instant", effects: dict[str, float] | None = None,
                       noise: SensorNoise | None = None, seed: int = 0, label: str = "/reference"
                       ) -> Resampled:
    """Recording of ``cycles`` brake applications (demands [N] cycled), module docstring.

    Each application: ``apply_s`` seconds applying towards its demand, then ``release_s``
    seconds back to the rest angle (and idle there).
    """
    if current_sampling not in ("instant", "mean"):
        raise InputError(f"current_sampling must be 'instant' or 'mean', got {current_sampling!r}")
    effects = dict(effects or {})
    unknown = set(effects) - set(REFERENCE_EFFECTS)
    if unknown:
        raise InputError(f"reference simulator: unknown effect(s) {sorted(unknown)}")
    m = actuator_model(unit)
    law = m.friction
    B = law.viscous * (1.0 + effects.get("viscous_friction", 0.0))
    G = law.load_coefficient * (1.0 + effects.get("load_friction", 0.0))
    T_c = law.coulomb + effects.get("preload_change", 0.0)
    x_ag = m.clamp.clearance + effects.get("clearance_growth", 0.0)
    tr, J, K_T, K_E, R, L = (m.transmission, m.inertia, m.torque_constant, m.back_emf_constant,
                             m.resistance, m.inductance)
    F_d = np.resize(np.asarray(demands, float), cycles)
    n = cycles

    def force(theta: np.ndarray) -> np.ndarray:
        return m.clamp.stiffness * np.maximum(tr * theta - x_ag, 0.0)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        theta, w, i = y[:n], y[n:2 * n], y[2 * n:3 * n]
        F = force(theta)
        e = K_F * (F_d - F) - K_W * w if t < apply_s else K_THETA * (0.0 - theta) - K_W * w
        e = np.clip(e, -m.supply_voltage, m.supply_voltage)
        e = np.clip(e, K_E * w - R * m.current_limit, K_E * w + R * m.current_limit)
        T_f = (T_c + G * F) * np.tanh(w / W_REG) + B * w
        return np.concatenate((w, (K_T * i - tr * F - T_f) / J, (e - R * i - K_E * w) / L, i))

    dt = 1.0 / rate_hz
    t_cycle = np.arange(0.0, apply_s + release_s, dt)
    sol = solve_ivp(rhs, (0.0, t_cycle[-1]), np.zeros(4 * n), t_eval=t_cycle, max_step=0.25 * dt,
                    rtol=1e-7, atol=1e-10)
    theta, w, i, q = (sol.y[k * n:(k + 1) * n].ravel() for k in range(4))  # cycle after cycle
    if current_sampling == "mean":  # mean over the preceding period from the charge integral
        qc = q.reshape(n, -1)  # charge per cycle, one row each
        i = np.concatenate((qc[:, :1] * 0.0, np.diff(qc, axis=1) / dt), axis=1).ravel()
    noise = SensorNoise() if noise is None else noise
    rng = np.random.default_rng(seed)
    size = theta.size
    t = np.arange(size) * dt
    return Resampled(
        t,
        theta / m.gear_ratio + rng.normal(0.0, noise.angle, size),
        w / m.gear_ratio + rng.normal(0.0, noise.velocity, size),
        force(theta) + effects.get("force_sensor_bias", 0.0) + rng.normal(0.0, noise.axial_force, size),
        i + rng.normal(0.0, noise.current, size),
        unit=label)
