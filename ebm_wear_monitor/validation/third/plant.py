"""Actuator plant of the third validation world: the EMB actuator of paper 004.

Single rotational degree of freedom referred to the motor shaft (004 eq. 1-2), rigid gear and
ball-screw kinematics (eq. 3-4), piecewise clamp law (eq. 5), DC motor (eq. 7-8) and the
load-dependent stick/slip friction of eq. 9. The ``play`` modifier (outside effect ``backlash``)
splits the rigid chain into a motor-side and a load-side body joined by a dead zone.

Integration (our choice): fixed step ``h`` (default 0.25 ms, 4 kHz). The armature current is
advanced with the exact solution of eq. 8 for a voltage and speed held over the step (exponential
Euler, unconditionally stable for any L/R); the mechanics with semi-implicit (symplectic) Euler,
the linear viscous term implicit. Stick/slip: a body at rest (omega == 0 exactly) stays at rest
while the torque that would move it is within the static limit (eq. 9, second branch); a moving
body whose speed would change sign within a step is brought to rest and re-tested against the
static limit (velocity-reversal test instead of eq. 9's band |omega| < epsilon).

Units: rad, rad/s, A, V, N, N m, m, s. Angles are motor-shaft angles unless named ``screw``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import yaml

DEFAULT_UNIT_FILE = Path(__file__).resolve().parents[2] / "params" / "reference" / "embu_000.yaml"

# Share of the system friction that sits on the motor side of the gear, used only when the chain
# is split by backlash: 004 Table 2 (motor alone) over 004 Table 3 (system, forward rotation).
MOTOR_SHARE_STATIC = 0.189 / 0.362
MOTOR_SHARE_COULOMB = 0.154 / 0.327
MOTOR_SHARE_VISCOUS = 1.77 / 1.8


@dataclass(frozen=True)
class Nominal:
    """Healthy-unit parameters, all SI, taken from the unit file's ``actuator`` and ``ball_screw``."""

    i_g: float  # gear ratio, motor turns per screw turn [-]
    K_T: float  # torque constant [N m/A]
    K_E: float  # back-emf constant [V s/rad]
    R: float  # armature resistance [ohm]
    L: float  # armature inductance [H]
    J_m: float  # motor inertia [kg m^2]
    J_s: float  # screw inertia [kg m^2]
    J_g: float  # gear inertia referred to the motor [kg m^2]
    m_n: float  # nut (+ pad) mass [kg]
    x_ag: float  # clearance [m]
    K_b: float  # clamp stiffness [N/m]
    T_fs: float  # static friction [N m]
    T_fc: float  # Coulomb friction [N m]
    B: float  # viscous coefficient [N m s/rad]
    G: float  # load coefficient [N m/N]
    lead: float  # ball-screw lead [m]

    @property
    def c_x(self) -> float:
        """Nut travel per motor radian l/(2 pi i_g) [m/rad] (004 eq. 3-4)."""
        return self.lead / (2.0 * math.pi * self.i_g)

    @property
    def J_me(self) -> float:
        """Equivalent inertia at the motor shaft [kg m^2] (004 eq. 2)."""
        return self.J_m + self.J_g + self.J_s / self.i_g**2 + self.c_x**2 * self.m_n

    @property
    def k_theta(self) -> float:
        """Clamp stiffness seen at the motor shaft, K_b c_x^2 [N m/rad]."""
        return self.K_b * self.c_x**2


def load_nominal(path: str | Path | None = None) -> Nominal:
    """Read the unit file (YAML data only) and return the healthy parameters."""
    doc = yaml.safe_load(Path(path or DEFAULT_UNIT_FILE).read_text())
    a, mo, fr = doc["actuator"], doc["actuator"]["motor"], doc["actuator"]["friction"]
    return Nominal(
        i_g=float(a["gear_ratio"]),
        K_T=float(mo["torque_constant"]),
        K_E=float(mo["back_emf_constant"]),
        R=float(mo["resistance"]),
        L=float(mo["inductance"]),
        J_m=float(mo["inertia"]),
        J_s=float(a["screw_inertia"]),
        J_g=float(a["gear_inertia"]),
        m_n=float(a["nut_mass"]),
        x_ag=float(a["clearance"]),
        K_b=float(a["stiffness"]),
        T_fs=float(fr["static"]),
        T_fc=float(fr["coulomb"]),
        B=float(fr["viscous"]),
        G=float(fr["load_coefficient"]),
        lead=float(doc["ball_screw"]["lead"]),
    )


@dataclass
class Modifiers:
    """Physical deviations from the nominal unit; the defaults are the healthy unit.

    Every field is used by :class:`Actuator`; effects.py sets them (README table)."""

    visc_s: float = 0.0  # extra shear-thinning grease drag at omega_r, fraction of B omega_r
    visc_omega_r: float = 20.0  # [rad/s]
    visc_n: float = 0.8  # power-law fluid index
    load_s: float = 0.0  # extra load friction at F_ref, fraction of G F_ref
    load_F_ref: float = 20e3  # [N]
    load_p: float = 1.5  # power of the extra load friction
    eff_s: float = 0.0  # screw efficiency loss at eff_F_ref and standstill [-]
    eff_F_ref: float = 30e3  # [N]
    eff_a: float = 0.7  # load exponent
    eff_omega_c: float = 20.0  # speed at which the loss falls by 1/e [rad/s]
    pre_s: float = 0.0  # preload change, fraction of T_fc (signed)
    pre_F_lift: float = 15e3  # load that relieves half the preload torque [N]
    strib_s: float = 0.0  # extra breakaway torque, fraction of T_fc
    strib_omega_s: float = 4.0  # Stribeck speed [rad/s]
    stiff_s: float = 0.0  # stiffening at delta_r [-]
    stiff_F_ref: float = 20e3  # defines delta_r = F_ref / K_b [N]
    x_c: float | None = None  # contact position of the pads [m] (None: nominal x_ag)
    kt_scale: float = 1.0  # K_T and K_E scale (demagnetisation)
    play: float = 0.0  # half the total motor-referred backlash [rad]
    ripple_a: float = 0.0  # cogging amplitude [N m]
    ripple_n: int = 12  # cogging periods per motor revolution
    ripple_phase: float = 0.0  # [rad]
    drift_s: float = 0.0  # relative friction change over the recording (signed)
    drift_T: float = 1.0  # recording duration [s]
    extra: dict = field(default_factory=dict)


class Actuator:
    """Fixed-step simulation of the 004 actuator (state: current, motor angle and speed)."""

    def __init__(self, nom: Nominal, mods: Modifiers | None = None, h: float = 2.5e-4) -> None:
        self.nom, self.mods, self.h = nom, mods or Modifiers(), h
        m = self.mods
        self.KT, self.KE = nom.K_T * m.kt_scale, nom.K_E * m.kt_scale
        self.ea = math.exp(-h * nom.R / nom.L)
        self.x_c = nom.x_ag if m.x_c is None else m.x_c
        self.delta_r = m.stiff_F_ref / nom.K_b
        self.J = nom.J_me
        # split chain (backlash): motor side J_m + J_g, load side screw + nut
        self.J1 = nom.J_m + nom.J_g
        self.J2 = nom.J_s / nom.i_g**2 + nom.c_x**2 * nom.m_n
        self.i = 0.0
        self.th = 0.0  # motor angle [rad], 0 at the nominal rest position (nut at x = 0)
        self.w = 0.0
        self.thL, self.wL = 0.0, 0.0  # load-side angle/speed referred to the motor (backlash only)
        self.contact = -1  # backlash: +1 apply flank, -1 release flank, 0 in the play
        self.t = 0.0
        self.Tf = 0.0  # friction torque of the last step (incl. viscous) [N m]

    # --- constitutive laws -------------------------------------------------------------------
    def clamp_force(self, x: float) -> float:
        """Clamp force [N] at nut travel x [m]: 004 eq. 5, hardened by ``stiff_s`` (README E6)."""
        d = x - self.x_c
        if d <= 0.0:
            return 0.0
        return self.nom.K_b * d * (1.0 + self.mods.stiff_s * d / self.delta_r)

    def drift(self, t: float) -> float:
        """Friction scale of the outside effect ``friction_drift`` at time t [s]."""
        m = self.mods
        if m.drift_s == 0.0:
            return 1.0
        tau = 0.4 * m.drift_T
        return 1.0 + m.drift_s * (1.0 - math.exp(-t / tau)) / (1.0 - math.exp(-m.drift_T / tau))

    def friction(self, w: float, F: float, TL: float, t: float) -> tuple[float, float, float]:
        """Slip torque magnitude at speed w (without B w), static limit, and B (004 eq. 9 + effects)."""
        n, m = self.nom, self.mods
        f = self.drift(t)
        Tc = f * (n.T_fc + n.G * F)
        Ts = f * (n.T_fs + n.G * F)
        if m.load_s:
            e = m.load_s * n.G * m.load_F_ref * (F / m.load_F_ref) ** m.load_p
            Tc += e
            Ts += e
        if m.pre_s:
            e = m.pre_s * n.T_fc * (1.0 - 0.5 * min(1.0, F / m.pre_F_lift))
            Tc += e
            Ts += e
        if m.strib_s:
            Tc += (n.T_fs - n.T_fc + m.strib_s * n.T_fc) * math.exp(-((w / m.strib_omega_s) ** 2))
            Ts += m.strib_s * n.T_fc
        if m.eff_s and F > 0.0:
            lam = m.eff_s * (F / m.eff_F_ref) ** m.eff_a * math.exp(-abs(w) / m.eff_omega_c)
            Tc += TL * lam / (1.0 - lam) if w >= 0.0 else TL * lam
            Ts += TL * lam
        if m.visc_s:
            Tc += m.visc_s * n.B * m.visc_omega_r * (abs(w) / m.visc_omega_r) ** m.visc_n
        return Tc, Ts, f * n.B

    def motor_torque(self, i: float, th: float) -> float:
        """Air-gap torque [N m]: eq. 7 plus cogging (outside effect ``torque_ripple``)."""
        m = self.mods
        T = self.KT * i
        if m.ripple_a:
            T += m.ripple_a * math.sin(m.ripple_n * th + m.ripple_phase)
        return T

    # --- integration ------------------------------------------------------------------------
    @staticmethod
    def _slide(J: float, w: float, Tnet: float, Tc: float, Ts: float, B: float, h: float) -> float:  # noqa: PLR0917
        """One semi-implicit step of a body with stick/slip friction; returns the new speed."""
        if w == 0.0:
            if abs(Tnet) <= Ts:
                return 0.0
            return h * (Tnet - math.copysign(Tc, Tnet)) / (J + h * B)
        s = 1.0 if w > 0.0 else -1.0
        wn = (J * w + h * (Tnet - s * Tc)) / (J + h * B)
        if wn * s <= 0.0:  # speed would reverse within the step: rest, then the static test
            if abs(Tnet) <= Ts:
                return 0.0
            wn = h * (Tnet - math.copysign(Tc, Tnet)) / (J + h * B)
        return wn

    def step(self, u: float) -> None:
        """Advance one step h with armature voltage u [V] held over the step."""
        h, n = self.h, self.nom
        i_inf = (u - self.KE * self.w) / n.R  # eq. 8 with frozen speed, exact in time
        self.i = i_inf + (self.i - i_inf) * self.ea
        Tm = self.motor_torque(self.i, self.th)
        if self.mods.play > 0.0:
            self._step_play(Tm)
        else:
            F = self.clamp_force(n.c_x * self.th)
            TL = n.c_x * F  # load torque at the motor shaft (eq. 1)
            Tc, Ts, B = self.friction(self.w, F, TL, self.t)
            Tnet = Tm - TL
            wn = self._slide(self.J, self.w, Tnet, Tc, Ts, B, h)
            self.Tf = Tnet - self.J * (wn - self.w) / h
            self.w = wn
            self.th += h * wn
            self.thL, self.wL = self.th, wn
        self.t += h

    def _step_play(self, Tm: float) -> None:
        """Two bodies joined by a dead zone of +-play (motor-referred); nominal friction split."""
        h, n, b = self.h, self.nom, self.mods.play
        F = self.clamp_force(n.c_x * self.thL)
        TL = n.c_x * F
        Tc, Ts, B = self.friction(self.wL, F, TL, self.t)
        Tc1, Ts1, B1 = MOTOR_SHARE_COULOMB * n.T_fc, MOTOR_SHARE_STATIC * n.T_fs, MOTOR_SHARE_VISCOUS * B
        Tc2, Ts2, B2 = Tc - Tc1, Ts - Ts1, B - B1
        if self.contact:
            J = self.J1 + self.J2
            wn = self._slide(J, self.w, Tm - TL, Tc, Ts, B, h)
            Tf2 = (math.copysign(Tc2, wn) + B2 * wn) if wn else 0.0
            C = self.J2 * (wn - self.w) / h + TL + Tf2  # torque passed from motor to load side
            if wn == 0.0:  # chain at rest: does one side alone break away from the flank?
                keep = not ((self.contact * Tm < 0.0 and abs(Tm) > Ts1) or (self.contact < 0 and Ts2 < TL))
            else:
                keep = C * self.contact >= 0.0
            if keep:
                self.Tf = Tm - TL - J * (wn - self.w) / h
                self.w = self.wL = wn
                self.th += h * wn
                self.thL = self.th - self.contact * b
                return
            self.contact = 0
        w1 = self._slide(self.J1, self.w, Tm, Tc1, Ts1, B1, h)
        w2 = self._slide(self.J2, self.wL, -TL, Tc2, Ts2, B2, h)
        self.Tf = Tm - TL - (self.J1 * (w1 - self.w) + self.J2 * (w2 - self.wL)) / h
        self.th += h * w1
        self.thL += h * w2
        self.w, self.wL = w1, w2
        d = self.th - self.thL
        if abs(d) >= b:  # flank reached: inelastic impact, the bodies move together
            self.contact = 1 if d > 0 else -1
            self.thL = self.th - self.contact * b
            wc = (self.J1 * w1 + self.J2 * w2) / (self.J1 + self.J2)
            self.w = self.wL = wc

    @property
    def x(self) -> float:
        """Nut travel [m] (0 at the nominal rest position)."""
        return self.nom.c_x * self.thL

    @property
    def force(self) -> float:
        """Clamp force [N]."""
        return self.clamp_force(self.x)
