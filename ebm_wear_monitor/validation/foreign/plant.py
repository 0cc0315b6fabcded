"""The actuator of 004 as a batched plant, stepped with a time-stepping scheme of its own.

States per application (arrays of shape ``(n,)``, one entry per brake application simulated side
by side): motor angle ``theta`` counted from the released rest position of *that* application
[rad], motor speed ``w`` [rad/s], armature current ``i`` [A], the screw-side angle ``q`` (equal to
``theta`` unless a backlash effect is on) and a lagged load-cell state ``f_cell`` [N].

Equations (004):

* motor, eq. 7-8:      L di/dt = E - R i - K_E w,      T_m = K_T i
* dynamics, eq. 1-2:   J_me dw/dt = T_m - r_g F - T_f,   r_g = l / (2 pi i_g)   (eq. 3-4)
* clamp, eq. 5:        F = K_b max(0, x - x_ag),   x = r_g q   (travel from this application's rest)
* friction, eq. 9:     sliding   T_f = (T_fc + G F) sgn(w) + B w
                       sticking  |T_m - r_g F| <= T_fs + G F  ->  w = 0

Integration (not a regularised friction law): a Moreau-type implicit step of length ``dt``.
The current is advanced by backward Euler, ``i+ = (L i + dt (E - K_E w)) / (L + dt R)``. With the
drive torque ``T_d = K_T i+ - r_g F + T_extra`` and the impulse ``p = J w + dt T_d``:

* stuck (``w = 0``): stays stuck while ``|T_d| <= C_s`` (static level ``T_fs + G F``), else breaks
  away: ``w+ = (p - dt C_k sgn T_d) / (J + dt B)`` with the kinetic level ``C_k = T_fc + G F``;
* sliding: ``w+ = (p - dt C_k sgn w) / (J + dt B)``; if that changes sign the motion stops
  (``w+ = 0``) and must break away again against ``C_s``: friction never reverses a motion.

The viscous term is implicit, so the step is unconditionally stable in ``B``; the spring is
explicit (symplectic Euler ``theta+ = theta + dt w+``), stable for ``dt`` far below
``2 sqrt(J_me / (K_b r_g^2))`` (about 90 ms here). Effects (``effects.py``) add to the friction
levels, the drive torque, the clamp law and the load cell through the hooks of :class:`Physics`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .unit import Actuator


@dataclass
class Physics:
    """Effect hooks of one recording (defaults: the nominal 004 plant).

    Hooks receive arrays over the applications of the batch and return arrays: torques in N m at
    the motor, forces in N, speeds in rad/s, ``th`` the *absolute* motor angle (this
    application's rest angle ``origin`` plus its travel from there) [rad]. Per-application
    parameters live in the hooks' closures, in batch order.
    """

    kinetic_extra: list = field(default_factory=list)  # f(F, w, th) -> added to C_k
    static_extra: list = field(default_factory=list)  # f(F, th) -> added to C_s
    drive_extra: list = field(default_factory=list)  # f(th) -> signed torque added to T_d
    # f(penetration [m], K_b) -> F; None: K_b * penetration
    clamp: Callable[[np.ndarray, float], np.ndarray] | None = None
    cell: Callable[[np.ndarray], np.ndarray] | None = None  # f(F) -> cell output before lag; None: identity
    kt_factor: float = 1.0  # motor torque (and back-EMF) constant factor
    backlash: float = 0.0  # play between motor and screw, motor-side [rad]
    #: share of the no-load friction (T_fs, T_fc, B) acting downstream of the play (screw-nut, support
    #: bearing): inside the play the motor turns against the rest only, with its own and the gear's inertia
    screw_friction_share: float = 0.0
    clearance_extra: object = None  # per-application extra clearance [m] or None
    absolute: bool = False  # hooks depend on the absolute angle (origin must be known)

    @property
    def needs_history(self) -> bool:
        """Whether an application depends on where the previous one left the drive."""
        return self.absolute or self.backlash > 0.0


class Plant:
    """``n`` applications of one unit stepped in lock-step (see module docstring).

    ``origin``: absolute motor angle of each application's rest (used by angle-periodic hooks);
    ``gap0``: play ``theta - q`` at rest (backlash only): the motor starts that far ahead of the nut.
    """

    def __init__(self, act: Actuator, x_ag: np.ndarray, dt: float, physics: Physics | None = None,
                 *, cell_lag: float = 0.0, origin: np.ndarray | None = None,
                 gap0: np.ndarray | None = None) -> None:
        self.act = act
        self.phys = physics or Physics()
        self.dt = dt
        n = len(x_ag)
        self.x_ag = np.asarray(x_ag, dtype=float)
        if self.phys.clearance_extra is not None:
            self.x_ag = self.x_ag + np.asarray(self.phys.clearance_extra, dtype=float)
        self.origin = np.zeros(n) if origin is None else np.asarray(origin, dtype=float)
        self.q = np.zeros(n)  # the nut at this application's rest
        self.theta = np.zeros(n) if gap0 is None else np.asarray(gap0, dtype=float).copy()
        self.w = np.zeros(n)
        self.i = np.zeros(n)
        self.F = np.zeros(n)
        self.f_cell = self.cell_output(self.F)
        self.t = 0.0
        self._J = act.J_me
        self._J_motor = act.J_m + act.J_g  # what the motor carries inside a backlash play [kg m^2]
        self._kt = act.K_T * self.phys.kt_factor
        self._ke = act.K_E * self.phys.kt_factor
        self._cell_a = 1.0 - np.exp(-dt / cell_lag) if cell_lag > 0 else 1.0
        # the implicit steps of the module docstring, divided through by dt
        self._L_dt = act.L / dt
        self._inv_i = 1.0 / (act.L / dt + act.R)
        self._J_dt = self._J / dt
        self._inv_w = 1.0 / (self._J / dt + act.B)

    def set_state(self, theta: np.ndarray, q: np.ndarray, w: np.ndarray, i: np.ndarray, *,
                  f_cell: np.ndarray, t: float) -> None:
        """Restart from a saved state (copies)."""
        self.theta, self.q, self.w, self.i = theta.copy(), q.copy(), w.copy(), i.copy()
        self.f_cell, self.t = f_cell.copy(), t
        self.F = self.clamp_force(self.q)

    def state(self) -> tuple[np.ndarray, ...]:
        """(theta, q, w, i, f_cell) copies."""
        return self.theta.copy(), self.q.copy(), self.w.copy(), self.i.copy(), self.f_cell.copy()

    def clamp_force(self, q: np.ndarray) -> np.ndarray:
        """True clamp force [N] at screw-side angle ``q`` (004 eq. 5 or an effect's law)."""
        pen = np.maximum(q * self.act.r_g - self.x_ag, 0.0)
        if self.phys.clamp is None:
            return self.act.K_b * pen
        return self.phys.clamp(pen, self.act.K_b)

    def cell_output(self, F: np.ndarray) -> np.ndarray:
        """Load-cell output before its lag [N] for true clamp force ``F`` (identity by default)."""
        return np.array(F, dtype=float) if self.phys.cell is None else self.phys.cell(F)

    def step(self, E: np.ndarray) -> None:
        """Advance every application by ``dt`` under armature voltage ``E`` [V] (PWM average)."""
        a, ph = self.act, self.phys
        w, F = self.w, self.F
        i = (self._L_dt * self.i + E - self._ke * w) * self._inv_i
        load = a.G * F
        c_s = a.T_fs + load
        c_k = a.T_fc + load
        if ph.kinetic_extra or ph.static_extra or ph.drive_extra:
            th = self.theta + self.origin
            for f in ph.kinetic_extra:
                c_k = c_k + f(F, w, th)
            for f in ph.static_extra:
                c_s = c_s + f(F, th)
        t_d = self._kt * i - a.r_g * F
        for f in ph.drive_extra:
            t_d = t_d + f(th)
        J_dt: float | np.ndarray = self._J_dt
        inv_w: float | np.ndarray = self._inv_w
        if ph.backlash > 0.0:
            free = self._in_play()  # no flank engaged: no clamp load, screw-side friction and inertia
            t_d = np.where(free, self._kt * i, t_d)
            keep = np.where(free, 1.0 - ph.screw_friction_share, 1.0)
            c_k, c_s = c_k * keep, c_s * keep
            J_dt = np.where(free, self._J_motor / self.dt, self._J_dt)
            inv_w = 1.0 / (J_dt + a.B * keep)
        stuck = w == 0.0
        slide = np.where(stuck, t_d, w)  # the direction friction opposes
        w_new = (J_dt * w + t_d - np.copysign(c_k, slide)) * inv_w
        w_new[np.where(stuck, np.abs(t_d) <= c_s, w_new * w <= 0.0)] = 0.0
        self.w = w_new
        self.i = i
        self.theta = self.theta + self.dt * w_new
        self.q = self._screw_side(self.theta) if ph.backlash > 0.0 else self.theta
        self.F = self.clamp_force(self.q)
        cell = self.F if ph.cell is None else ph.cell(self.F)
        self.f_cell += self._cell_a * (cell - self.f_cell)
        self.t += self.dt

    # --- backlash (an out-of-catalog effect): a play operator between motor and screw ---------
    def _screw_side(self, theta: np.ndarray) -> np.ndarray:
        """Screw follows the motor through a play ``b``: ``theta - b <= q <= theta``.

        Under clamp load the screw rests on the forward flank (``q = theta - b``); unloaded it
        stays where it is until a flank drags it.
        """
        b = self.phys.backlash
        q = np.clip(self.q, theta - b, theta)
        loaded = self.clamp_force(theta - b) > 0.0
        return np.where(loaded, theta - b, q)

    def _in_play(self) -> np.ndarray:
        """Applications whose motor is inside the play (neither flank engaged)."""
        gap = self.theta - self.q
        return (gap > 1e-12) & (gap < self.phys.backlash - 1e-12)
