"""Driver: runs one recording's brake applications on the plant under its ECU.

Output is a dense record on the plant grid (step h): time [s], motor angle [rad], screw angle
[rad] (from the load-side body), motor speed [rad/s], current [A], voltage [V], clamp force [N].
Idle periods in which the de-energised actuator is at rest are filled without stepping.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .controller import CONTROLLERS, ProfilePosition
from .effects import realise
from .plant import Actuator, Nominal


@dataclass
class Dense:
    """Dense true signals on the plant grid and the application log."""

    h: float
    t: np.ndarray
    th_motor: np.ndarray
    th_screw: np.ndarray
    w: np.ndarray
    i: np.ndarray
    u: np.ndarray
    F: np.ndarray
    apps: list[dict]
    ctrl_every: int


def simulate(case, nom: Nominal) -> Dense:
    """Simulate ``case`` (cases.Case) and return the dense true record."""
    rng = np.random.default_rng(case.seed + 7)
    sched = case.schedule
    T_plan = sum(a["hold"] + a["idle"] + 0.6 for a in sched)
    real = realise(case.effect, case.magnitude or 0.0, nom, n_app=len(sched), T_rec=T_plan, rng=rng)
    h = case.h
    plant = Actuator(nom, real.mods, h)
    cp = case.ctrl
    n_c = round(1.0 / (cp["rate_hz"] * h))
    dt = n_c * h
    kw = {}
    if cp["name"] == ProfilePosition.name:
        kw["th_contact"] = nom.x_ag / nom.c_x + cp["contact_err"]
    ctrl = CONTROLLERS[cp["name"]](nom, dt, cp["U_bus"], cp["i_lim"], cp["params"], **kw)
    q_enc = 2 * math.pi / 4096.0  # drive's commutation encoder on the motor [rad]
    a_F = 1.0 - math.exp(-dt / 1e-3)  # ECU force input filter, 1 ms
    T_, TH, THS, W, I_, U, F_ = ([] for _ in range(7))
    st = {"k": 0, "u": 0.0, "Fc": 0.0, "th_prev": 0.0, "w_est": 0.0}
    a_w = 1.0 - math.exp(-dt / 1.5e-3)

    def run(n_max: int, stop=None) -> None:
        for _ in range(n_max):
            if st["k"] % n_c == 0:
                th_q = math.floor(plant.th / q_enc) * q_enc
                st["w_est"] += a_w * ((th_q - st["th_prev"]) / dt - st["w_est"])
                st["th_prev"] = th_q
                st["Fc"] += a_F * (real.force_gain * plant.force + rng.normal(0, 5.0) - st["Fc"])
                st["u"] = ctrl.update(th_q, st["w_est"], st["Fc"], plant.i + rng.normal(0, 0.01))
                if stop is not None and stop():
                    return
            plant.step(st["u"])
            st["k"] += 1
            T_.append(plant.t)
            TH.append(plant.th)
            THS.append(plant.thL / nom.i_g)
            W.append(plant.w)
            I_.append(plant.i)
            U.append(st["u"])
            F_.append(plant.force)

    apps = []
    run(int(0.2 / h))  # settle at rest, bridge off
    for k, a in enumerate(sched):
        plant.x_c = real.clearance[k]
        t0 = plant.t
        ctrl.start_apply(a["F_d"])
        run(int(1.5 / h), lambda: ctrl.reached)
        t_hold = plant.t
        run(int(a["hold"] / h))
        t_rel = plant.t
        ctrl.start_release(a["rest"])
        run(int(1.5 / h), lambda: ctrl.settled)
        t_end = plant.t
        ctrl.disable()
        n_idle = int(a["idle"] / h)
        n0 = len(T_)
        run(n_idle, lambda: plant.w == 0.0 and plant.wL == 0.0 and abs(plant.i) < 1e-4)
        n_fill = n_idle - (len(T_) - n0)
        if n_fill > 0:
            t_last = plant.t
            T_.extend(t_last + h * np.arange(1, n_fill + 1))
            for arr, v in (
                (TH, plant.th),
                (THS, plant.thL / nom.i_g),
                (W, 0.0),
                (I_, plant.i),
                (U, 0.0),
                (F_, plant.force),
            ):
                arr.extend([v] * n_fill)
            plant.t = t_last + h * n_fill
            st["k"] += n_fill
        apps.append(
            {
                "t_start": round(t0, 4),
                "t_hold": round(t_hold, 4),
                "t_release": round(t_rel, 4),
                "t_rest": round(t_end, 4),
                "F_demand_N": round(a["F_d"], 1),
                "F_held_N": round(float(np.mean(F_[int(t_hold / h) : int(t_rel / h)] or [0.0])), 1),
                "x_contact_m": real.clearance[k],
            }
        )
    return Dense(
        h,
        np.asarray(T_),
        np.asarray(TH),
        np.asarray(THS),
        np.asarray(W),
        np.asarray(I_),
        np.asarray(U),
        np.asarray(F_),
        apps,
        n_c,
    )
