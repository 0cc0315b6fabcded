"""The foreign plant against closed forms of paper 004 (eq. 1-9, 13-14, 17) and energy balances."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.validation.foreign.plant import Plant
from ebm_wear_monitor.validation.foreign.unit import load_actuator

ACT = load_actuator()
DT = 1e-4


def _free_plant(n: int = 1) -> Plant:
    """A plant whose clamp is never reached (clearance of a kilometre)."""
    return Plant(ACT, np.full(n, 1e3), DT)


def test_no_load_speed_and_time_constant_follow_004_eq_13_14() -> None:
    E = np.array([24.0, 36.0, 48.0])
    p = _free_plant(3)
    w = []
    for _ in range(int(0.2 / DT)):
        p.step(E)
        w.append(p.w.copy())
    w = np.array(w)
    a = ACT
    K = (a.K_T * E - a.T_fc * a.R) / (a.B * a.R + a.K_E * a.K_T)  # eq. 14
    T = a.J_me * a.R / (a.B * a.R + a.K_E * a.K_T)
    assert w[-1] == pytest.approx(K, rel=1e-6)
    # eq. 13 neglects L (L/R = 0.9 ms vs T = 6.9 ms): compare at t = 3T within 3 %
    k3 = round(3 * T / DT)
    assert w[k3] == pytest.approx(K * (1 - np.exp(-3)), rel=0.03)


def _hold_at(force: float, n: int) -> Plant:
    """A stuck plant holding ``force`` (angle from the clamp law, 004 eq. 5) with the current
    that balances the load torque."""
    p = Plant(ACT, np.full(n, ACT.x_ag), DT)
    theta = np.full(n, (ACT.x_ag + force / ACT.K_b) / ACT.r_g)
    i = np.full(n, ACT.r_g * force / ACT.K_T)
    p.set_state(theta, theta, np.zeros(n), i, f_cell=np.zeros(n), t=0.0)
    return p


@pytest.mark.parametrize("force", [5e3, 15e3, 28e3])
def test_breakaway_current_at_a_held_force_is_004_eq_9_static_level(force: float) -> None:
    """Forward breakaway at K_T i = r_g F + T_fs + G F; backward at K_T i = r_g F - T_fs - G F."""
    a = ACT
    T_L = a.r_g * force
    fwd = (T_L + a.T_fs + a.G * force) / a.K_T
    bwd = (T_L - a.T_fs - a.G * force) / a.K_T
    for target, sign in ((fwd, 1.0), (bwd, -1.0)):
        p = _hold_at(force, 1)
        # current ramped slowly by voltage (L di/dt negligible): i = E / R while stuck
        start = T_L / a.K_T
        for k in range(int(0.5 / DT)):
            i_cmd = start + sign * (abs(target - start) * 1.2) * k * DT / 0.5
            p.step(np.array([i_cmd * a.R]))
            if p.w[0] != 0.0:
                break
        assert np.sign(p.w[0]) == sign
        assert p.i[0] == pytest.approx(target, rel=2e-3)


def test_static_force_angle_law_004_eq_5() -> None:
    p = Plant(ACT, np.full(4, ACT.x_ag), DT)
    q = np.array([0.0, ACT.x_ag / ACT.r_g, (ACT.x_ag + 1e-4) / ACT.r_g, (ACT.x_ag + 6e-4) / ACT.r_g])
    assert p.clamp_force(q) == pytest.approx([0.0, 0.0, ACT.K_b * 1e-4, ACT.K_b * 6e-4])


def test_energy_balances_of_an_apply_and_release() -> None:
    """Mechanical: work of K_T i = kinetic + clamp + friction work (004 eq. 1, 9);
    electrical: supplied = resistive + magnetic + back-EMF power (004 eq. 8)."""
    a = ACT
    p = Plant(a, np.full(1, a.x_ag), DT)
    n = int(0.6 / DT)
    E = np.where(np.arange(n) < int(0.3 / DT), 40.0, -30.0)
    rec = {k: np.zeros(n) for k in ("i", "w", "w0", "F", "theta")}
    for k in range(n):
        rec["w0"][k], rec["F"][k] = p.w[0], p.F[0]
        p.step(E[k:k + 1])
        rec["i"][k], rec["w"][k], rec["theta"][k] = p.i[0], p.w[0], p.theta[0]
    i, w, F = rec["i"], rec["w"], rec["F"]
    assert F.max() > 5e3 and w.min() < 0  # it clamped and came back
    friction = np.where(w != 0, (a.T_fc + a.G * F) * np.sign(w) + a.B * w, 0.0)
    motor = np.sum(a.K_T * i * w) * DT
    kinetic = 0.5 * a.J_me * w[-1] ** 2
    clamp = np.sum(a.r_g * F * w) * DT
    lost = np.sum(friction * w) * DT
    # the implicit step dissipates 1/2 J (dw)^2 per step (J (w+ - w) w+ = d(J w^2 / 2) + J dw^2 / 2),
    # including the kinetic energy an impulsive stop removes
    scheme = 0.5 * a.J_me * np.sum(np.diff(w, prepend=0.0) ** 2)
    assert motor == pytest.approx(kinetic + clamp + lost + scheme, rel=1e-9)
    assert lost > 0 and scheme < 0.01 * motor
    # the clamp work over a closed path is its stored energy at the end (about zero at rest)
    final = 0.5 * a.K_b * max(rec["theta"][-1] * a.r_g - a.x_ag, 0.0) ** 2
    assert clamp == pytest.approx(final, abs=0.01 * np.sum(np.abs(a.r_g * F * w)) * DT)
    supplied = np.sum(E * i) * DT
    resist = np.sum(a.R * i**2) * DT
    emf = np.sum(a.K_E * rec["w0"] * i) * DT  # the current step uses the speed at its start
    magnetic = 0.5 * a.L * i[-1] ** 2
    scheme_e = 0.5 * a.L * np.sum(np.diff(i, prepend=0.0) ** 2)  # backward Euler, as above
    assert supplied == pytest.approx(resist + emf + magnetic + scheme_e, rel=1e-9)
    assert scheme_e < 0.01 * supplied


def test_stuck_plant_satisfies_the_static_friction_inequality() -> None:
    p = _hold_at(20e3, 50)
    rng = np.random.default_rng(0)
    i = rng.uniform(0, 5, 50)
    p.i = i.copy()
    p.step(i * ACT.R)
    a = ACT
    stays = np.abs(a.K_T * p.i - a.r_g * 20e3) <= a.T_fs + a.G * 20e3
    assert np.all((p.w == 0) == stays)
    assert stays.any() and (~stays).any()


def test_inside_a_backlash_play_the_motor_carries_only_its_side() -> None:
    """Crossing the play the motor accelerates against J_m + J_g and (1 - f_s) of the friction only
    (no clamp load, the screw side decoupled): from rest under a constant current i the first speed
    step is dt (K_T i - (1 - f_s) T_fc) / (J_m + J_g + dt (1 - f_s) B), and the screw stays put."""
    from ebm_wear_monitor.validation.foreign.plant import Physics

    b, share = 0.2, 0.6  # play [rad] (motor side), screw-side friction share [-]
    p = Plant(ACT, np.full(1, 1e3), DT, physics=Physics(backlash=b, screw_friction_share=share),
              gap0=np.full(1, 0.5 * b))  # start in the middle of the play
    a = ACT
    i_target = 2.0  # [A]
    E = np.array([i_target * a.R])  # steady-state voltage for that current at rest
    p.i = np.full(1, i_target)
    p.step(E)
    i_new = float(p.i[0])
    keep = 1.0 - share
    expected = DT * (a.K_T * i_new - keep * a.T_fc) / (a.J_m + a.J_g + DT * keep * a.B)
    assert p.w[0] == pytest.approx(expected, rel=1e-9)
    assert p.q[0] == 0.0  # the screw has not moved
    # the lumped drive (no play) carries the whole friction and J_me: its first step is smaller
    lumped = Plant(ACT, np.full(1, 1e3), DT)
    lumped.i = np.full(1, i_target)
    lumped.step(E)
    assert lumped.w[0] < p.w[0]
