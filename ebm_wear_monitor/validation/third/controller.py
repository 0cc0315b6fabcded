"""ECU designs of the third world. Each knows only the NOMINAL unit (it cannot see effects).

All run at the control period ``dt`` [s] on the drive's own measurements (motor angle [rad]
from the commutation encoder, motor speed [rad/s], clamp force [N] as the ECU sees it, current
[A]) and return an armature voltage [V], clipped to +-U_bus, with the current reference clipped
to +-i_lim. Phases: ``apply`` -> ``hold`` (``reached``) -> ``release`` -> ``rest``
(``settled``) -> ``off`` (bridge disabled, u = 0). The driver (world.py) does the timing.
"""

from __future__ import annotations

import math

from .plant import Nominal


class _Drive:
    """Common parts: nominal knowledge, limits, inner current loop, speed PI, rest detection."""

    name = "base"

    def __init__(self, nom: Nominal, dt: float, U_bus: float, i_lim: float, p: dict) -> None:
        self.nom, self.dt, self.U, self.i_lim, self.p = nom, dt, U_bus, i_lim, p
        self.kF = nom.K_b * nom.c_x  # nominal clamp force per motor radian [N/rad]
        self.kp_i = nom.L * 2 * math.pi * p.get("f_i", 150.0)  # current P gain [V/A]
        f_w = p.get("f_w", 18.0)
        self.kp_w = nom.J_me * 2 * math.pi * f_w / nom.K_T  # speed PI [A s/rad]
        self.ki_w = self.kp_w * 2 * math.pi * f_w / 5.0
        self.integ = 0.0
        self.phase, self.reached, self.settled = "off", False, False
        self.F_d, self.th_rest, self._still = 0.0, 0.0, 0.0

    def volt(self, i_ref: float, i_m: float, w: float) -> float:
        """Inner current loop: feed-forward R i + K_E w (eq. 8 at steady state) + P [V]."""
        n = self.nom
        i_ref = max(-self.i_lim, min(self.i_lim, i_ref))
        u = n.R * i_ref + n.K_E * w + self.kp_i * (i_ref - i_m)
        return max(-self.U, min(self.U, u))

    def speed_pi(self, w_ref: float, w: float, ff: float = 0.0, freeze: bool = False) -> float:
        """Speed PI -> current reference [A], conditional integration as anti-windup."""
        e = w_ref - w
        i_ref = self.kp_w * e + self.integ + ff
        if not freeze and abs(i_ref) < self.i_lim:
            self.integ += self.ki_w * e * self.dt
        return i_ref

    def start_apply(self, F_d: float) -> None:
        """Begin an application to the demanded clamp force F_d [N]."""
        self.F_d, self.phase, self.reached, self.settled = F_d, "apply", False, False

    def start_release(self, th_rest: float) -> None:
        """Release and return to the rest motor angle th_rest [rad]."""
        self.th_rest, self.phase, self._still = th_rest, "release", 0.0

    def disable(self) -> None:
        """Open the bridge (u = 0), clear the integrator."""
        self.phase, self.integ = "off", 0.0

    def _rest_check(self, th: float, w: float) -> bool:
        ok = abs(th - self.th_rest) < self.p.get("rest_tol", 0.03) and abs(w) < 0.5
        self._still = self._still + self.dt if ok else 0.0
        if self._still > 0.04:
            self.settled, self.phase = True, "rest"
        return ok

    def update(self, th: float, w: float, F: float, i: float) -> float:  # pragma: no cover
        raise NotImplementedError


class CascadeForcePI(_Drive):
    """Force P -> speed PI -> current, with load-torque feed-forward from the measured force.

    Apply/hold: w_ref = clip(kFo (F_d - F), +-w_max), a dead band of +-tol F_d (no integration,
    w_ref = 0) against friction hunting. Release: force to ~0 at full speed, then angle P to rest."""

    name = "cascade_force_pi"

    def __init__(self, *a, **k) -> None:
        super().__init__(*a, **k)
        self.kFo = 2 * math.pi * self.p.get("f_F", 4.0) / self.kF  # [(rad/s)/N]
        self.kth = 2 * math.pi * self.p.get("f_th", 3.0)  # [1/s]

    def update(self, th: float, w: float, F: float, i: float) -> float:
        n, p = self.nom, self.p
        if self.phase == "off":
            return 0.0
        w_max, ff = p.get("w_max", 28.0), p.get("ff", 0.8) * n.c_x * max(F, 0.0) / n.K_T
        freeze = False
        if self.phase in ("apply", "hold"):
            e = self.F_d - F
            if self.phase == "apply" and e < p.get("tol", 0.02) * self.F_d:
                self.phase, self.reached = "hold", True
            if self.phase == "hold" and abs(e) < p.get("tol", 0.02) * self.F_d:
                w_ref, freeze = 0.0, True
            else:
                w_ref = max(-w_max, min(w_max, self.kFo * e))
        elif p.get("F_thr", 300.0) < F:
            w_ref = -w_max
        else:
            ok = self._rest_check(th, w)
            w_ref, freeze = (
                (0.0, True) if ok else (max(-w_max, min(w_max, self.kth * (self.th_rest - th))), False)
            )
        return self.volt(self.speed_pi(w_ref, w, ff, freeze), i, w)


class ProfilePosition(_Drive):
    """Force-to-angle map + trapezoidal profile + position P / speed PI.

    Target motor angle th_c + F_d / kF, with the contact angle th_c learned on each apply where
    the measured force crosses F_learn (nominal linear map); optional slow force trim in hold."""

    name = "profile_position"

    def __init__(self, *a, th_contact: float = 0.0, **k) -> None:
        super().__init__(*a, **k)
        self.th_c, self.th_ref, self.v_ref, self.th_t = th_contact, 0.0, 0.0, 0.0
        self.kth = 2 * math.pi * self.p.get("f_th", 8.0)
        self._learned = False

    def start_apply(self, F_d: float) -> None:
        super().start_apply(F_d)
        self.th_t, self._learned = self.th_c + F_d / self.kF, False

    def start_release(self, th_rest: float) -> None:
        super().start_release(th_rest)
        self.th_t = th_rest

    def _profile(self) -> None:
        """Rate- and acceleration-limited reference toward th_t (trapezoidal velocity)."""
        p, dt = self.p, self.dt
        d = self.th_t - self.th_ref
        a = p.get("a_max", 2500.0)
        v_goal = math.copysign(min(p.get("v_max", 25.0), math.sqrt(2 * a * abs(d))), d)
        self.v_ref += max(-a * dt, min(a * dt, v_goal - self.v_ref))
        step = self.v_ref * dt
        if abs(step) >= abs(d):
            self.th_ref, self.v_ref = self.th_t, 0.0
        else:
            self.th_ref += step

    def update(self, th: float, w: float, F: float, i: float) -> float:
        n, p = self.nom, self.p
        if self.phase == "off":
            self.th_ref, self.v_ref = th, 0.0
            return 0.0
        freeze = False
        if self.phase in ("apply", "hold"):
            F_l = p.get("F_learn", 800.0)
            if not self._learned and F_l < F:
                self.th_c += 0.5 * (th - F_l / self.kF - self.th_c)
                self.th_t, self._learned = self.th_c + self.F_d / self.kF, True
            if self.phase == "apply" and (
                0.97 * self.F_d < F or (self.v_ref == 0.0 and abs(self.th_t - th) < 0.02)
            ):
                self.phase, self.reached = "hold", True
            if self.phase == "hold":
                self.th_t += p.get("k_trim", 0.0) * self.dt * (self.F_d - F) / self.kF
        elif p.get("F_thr", 300.0) > F and self._rest_check(th, w):
            freeze = True
        self._profile()
        w_ref = self.v_ref + self.kth * (self.th_ref - th)
        ff = p.get("ff", 0.7) * n.c_x * max(F, 0.0) / n.K_T
        return self.volt(self.speed_pi(w_ref, w, ff, freeze), i, w)


class BangBangHold(_Drive):
    """Current-limited bang-bang apply with a braking switch, proportional force hold.

    Apply at +k_app i_lim until the nominal stopping force F + kF w^2/(2 a_br) reaches F_d, brake
    at -i_lim to standstill, then i_ref = (c_x F_d + bias)/K_T + kpF (F_d - F) - kd w. Release at
    -k_rel i_lim down to F_thr, then angle PD to rest."""

    name = "bang_bang_p_hold"

    def update(self, th: float, w: float, F: float, i: float) -> float:
        n, p = self.nom, self.p
        if self.phase == "off":
            return 0.0
        kd = p.get("kd", 0.12)
        if self.phase == "apply":
            a_br = (n.K_T * self.i_lim + n.T_fc) / n.J_me
            if F + self.kF * max(w, 0.0) ** 2 / (2 * a_br) >= (1 - p.get("margin", 0.03)) * self.F_d:
                self.phase = "brake"
            i_ref = p.get("k_app", 0.9) * self.i_lim
        if self.phase == "brake":
            i_ref = -self.i_lim
            if w < 0.5:
                self.phase, self.reached = "hold", True
        if self.phase == "hold":
            self.integ = 0.0
            i_ref = (n.c_x * self.F_d + p.get("bias", 0.1) * n.T_fc) / n.K_T
            i_ref += p.get("kpF", 6e-4) * (self.F_d - F) - kd * w
        elif self.phase in ("release", "rest"):
            if p.get("F_thr", 300.0) < F:
                i_ref = -p.get("k_rel", 0.6) * self.i_lim
            elif self._rest_check(th, w):
                i_ref = 0.0
            else:  # PID to rest: the slow integral creeps out of the friction band
                lim, e = 0.5 * self.i_lim, self.th_rest - th
                self.integ = max(-lim, min(lim, self.integ + 8.0 * p.get("kp_th", 8.0) * e * self.dt))
                i_ref = max(-lim, min(lim, p.get("kp_th", 8.0) * e + self.integ - kd * w))
        return self.volt(i_ref, i, w)


CONTROLLERS = {c.name: c for c in (CascadeForcePI, ProfilePosition, BangBangHold)}
