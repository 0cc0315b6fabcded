"""Residuals that measure the twin, not accumulated drift: torque balance and force-angle law per block.

Why not simply run the twin on the recorded current and compare?  The twin of
004 is current driven: 004 eq. 1, J_me dw_m/dt = K_T I_a - l F_cl / (2 pi i_g) - T_f,
integrates every torque error twice, and the stiff clamp (004 eq. 5) turns a
0.05 N m friction mismatch into radians of angle and kilonewtons of force within
one recording.  A free simulation therefore reports drift, not the model.  This
module compares the model with the recording in two *algebraic* channels that
need no integration across more than one short block:

**Torque channel (004 eq. 1, 7, 9), re-anchored every block.**  Blocks are
``block_s`` long (20 ms by default), never straddle a phase or cycle boundary,
and start from the *recorded* state.  Integrating eq. 1 over a block
[t0, t1] along the recorded speed and force gives the twin's speed at t1,

    w_sim(t1) = w(t0) + (1/J_me) * int_{t0}^{t1} (K_T I - T_L(F) - T_f(w, F)) dt,

(T_L = l F / (2 pi i_g), the load torque at the motor of 004 eq. 1) and the
block residual is the speed the twin gains over the recording, expressed as the
mean torque it takes:

    R_T = [int (K_T I - T_L - T_f) dt - J_me (w(t1) - w(t0))] / (t1 - t0)   [N m].

R_T is "recorded motor torque minus the torque the model needs for the recorded
motion and force"; positive means the real unit needed more torque (e.g. more
friction) than the twin.  Being an integral of the recorded current and a
difference of recorded speeds, it needs no numerical differentiation.
J_me is 004 eq. 2.  The same block gives the twin's velocity error
w_sim - w at t1 (= R_T (t1 - t0) / J_me) and its angle error at t1 (the
integral of that velocity error over the block): the *re-anchored short-horizon
simulation* of the velocity and angle signals.

Friction follows 004 eq. 9, evaluated on the recorded state. Moving
(|w_m| > eps):  T_f = (T_fc + G F) sgn(w_m) + B w_m.  At rest (the stick
branch) eq. 9 only bounds the friction, |T_f| <= T_fs + G F, and the friction
takes whatever value balances K_T I - T_L - J_me dw_m/dt.  The residual model
takes it so, i.e. blocks at rest carry no torque residual and the static level
T_fs is not identified from the torque balance.  (A dead-zone residual, the
excess of the recorded balance over the band, was tried: sensor noise crossing
the band edge is clipped on one side only, which biases the static level
upwards and made "larger T_fs" look significant on noise-only data.)

**Force channel (004 eq. 4-5).**  The nut travel x = l theta_s / (2 pi) (screw
angle from the recording, counted from the released position) predicts the clamp
force F = K_b max(0, x - x_ag); the block mean of recorded minus predicted force
is R_F [N] (the angle is counted from the rest position, the median angle of
the idle samples, so an encoder offset does not read as clearance).
It sees clearance, stiffness and force-sensor errors, which the
torque channel (evaluated at the *recorded* force) does not.

**Current timing.**  A sampled current is ambiguous by up to a sample
interval: a drive may log the current at the start of its control period while
the torque acts over the period (its mean), and topics may be stamped with a
skew.  A shift of half a sample turns the motor's current transients into a
systematic, speed-correlated torque residual.  The shift tau (current read at
t + tau) is therefore a nuisance parameter of every fit, the nominal twin's
included (:mod:`.ranking`); it is a property of the data acquisition, not an
effect of the unit.

**Quadrature rule of the load.**  The recording gives the force only at the
samples; how the load torque T_L = l F / (2 pi i_g) acts *between* them is not
in the data.  A sampled continuous plant follows the trapezoid rule used here;
a simulator or drive that holds the force over each step of length h (an
explicit integrator, e.g. the twin's simulator run at the recording rate)
integrates the left rectangle, sum T_L(F_k) h, which differs from the trapezoid
by -(h/2)(T_L(t1) - T_L(t0)) per block, i.e. by the trapezoid of T_L read
h/2 earlier.  In contact dT_L/dt = (l / (2 pi i_g))^2 K_b w_m, so this
difference is a viscous-looking torque -(h/2) K_eff w_m: left unmodelled, it
made "viscous_friction" significant on no-effect recordings of the twin at
0.5-1 kHz (7 of 18).  The load is therefore read at t + tau_M with tau_M a
second acquisition nuisance, bounded by the rectangle rules to [-dt/2, dt/2]
(dt the sample interval; h <= dt) and refitted with every model, the nominal
one included (:mod:`.ranking`).  The price is honest: a viscous change that
acts only in contact, of at most K_eff dt / 2 (7 % of 004's B at 1 kHz,
14 % at 500 Hz), is not separable from the quadrature rule; a viscous effect
is identified by what it does outside contact (clearance elimination, the
end of the release).  The same error of the current (recorded at the start of
a period whose mean current drives the motor) telescopes to a multiple of
I(t1) - I(t0) per block and is the current timing tau.

**Sliding or stuck.**  A sample slides where both the smoothed speed (5 ms
window) and the raw speed leave their 3-sigma rest bands: the smoothing alone
widens every motion by half its window and charged T_fc to the samples at rest
around each start and stop (up to 0.03 N m per 20 ms block at 1 kHz).

Unmodelled effects enter as an :class:`Augment` (corrections to the nominal
parameters and functional forms); :mod:`.catalog` maps each effect's few
parameters onto it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import uniform_filter1d

from ebm_wear_monitor.diagnosis.noise import signal_noise
from ebm_wear_monitor.diagnosis.phases import IDLE, Segmentation
from ebm_wear_monitor.diagnosis.recording import Recording
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.twin.clamp import STIFFENING_REFERENCE_FORCE, ClampLaw
from ebm_wear_monitor.twin.dynamics import actuator_model
from ebm_wear_monitor.twin.friction import FrictionLaw, sliding_friction


@dataclass(frozen=True)
class Nominal:
    """Parameters of the nominal twin (004 Table 1 and eq. 9 as given by the unit file), motor side."""

    J_me: float  # equivalent inertia at the motor, 004 eq. 2 [kg m^2]
    K_T: float  # torque constant, 004 eq. 7 [N m / A]
    i_g: float  # gear ratio, motor turns per screw turn [-]
    lead: float  # l [m]
    T_fs: float  # static friction torque [N m]
    T_fc: float  # Coulomb friction torque [N m]
    B: float  # viscous coefficient [N m s / rad]
    G: float  # load coefficient [N m / N]
    K_b: float  # clamp stiffness, 004 eq. 6 [N/m]
    x_ag: float  # brake clearance [m]

    @classmethod
    def from_unit(cls, unit: UnitParams) -> Nominal:
        """Nominal twin of a unit file (the twin's :func:`~ebm_wear_monitor.twin.dynamics.actuator_model`;
        InputError without an ``actuator`` block)."""
        m = actuator_model(unit)
        f, c = m.friction, m.clamp
        return cls(m.inertia, m.torque_constant, m.gear_ratio, m.lead, f.static, f.coulomb, f.viscous,
                   f.load_coefficient, c.stiffness, c.clearance)

    @property
    def load_ratio(self) -> float:
        """l / (2 pi i_g): load torque at the motor per newton of clamp force, 004 eq. 1 [m/rad]."""
        return self.lead / (2.0 * math.pi * self.i_g)


@dataclass(frozen=True)
class Augment:
    """Corrections to the nominal twin; every field zero is the nominal twin itself.

    Friction terms are at the motor shaft (004 eq. 9), force terms at the nut (004 eq. 5).
    """

    dB: float = 0.0  # viscous coefficient change [N m s / rad]
    dG: float = 0.0  # load coefficient change [N m / N]
    dT_fs: float = 0.0  # static friction change [N m]
    dT_fc: float = 0.0  # Coulomb friction change [N m]
    eff_base: float = 0.0  # a_0: change of the loss factor 1/eta - 1 at standstill [-]
    eff_speed: float = 0.0  # a_w: its change per unit motor speed, d(1/eta)/d|w_m| [s/rad]
    stribeck_torque: float = 0.0  # extra friction at zero speed, decaying with speed [N m]
    stribeck_speed: float = 1.0  # Stribeck speed w_s of exp(-(|w_m|/w_s)^2) [rad/s], > 0
    stiffness_quad: float = 0.0  # k_2 of F = K_b d + k_2 d^2 [N/m^2]
    clearance: float = 0.0  # extra clearance dx_ag [m]
    force_bias: float = 0.0  # force-sensor offset b: F_meas = (1 + g) F + b [N]
    force_gain: float = 0.0  # force-sensor gain error g [-]
    current_shift: float = 0.0  # timing of the current samples relative to the motion samples [s]
    load_shift: float = 0.0  # timing of the load and friction torque (quadrature-rule nuisance) [s]


NOMINAL = Augment()


def kinetic_friction(n: Nominal, aug: Augment, w_m: np.ndarray, F: np.ndarray, *,
                     sign: np.ndarray | None = None, speed: np.ndarray | None = None) -> np.ndarray:
    """Moving branch of 004 eq. 9 with the corrections of ``aug`` [N m].

    T_f = (T_fc + dT_fc + (G + dG) F) s + (B + dB) w_m + s T_L (a_0 + a_w |w_m|)
    + s T_S exp(-(|w_m| / w_S)^2), s = sgn(w_m), T_L = l F / (2 pi i_g);
    the eq. 9 part is the twin's :func:`ebm_wear_monitor.twin.friction.sliding_friction`.
    ``sign`` and ``speed`` default to sgn(w_m) and |w_m|; the residual model passes smoothed ones.
    """
    s = np.sign(w_m) if sign is None else sign
    speed = np.abs(w_m) if speed is None else speed
    T_L = n.load_ratio * F
    law = FrictionLaw(static=n.T_fs + aug.dT_fs, coulomb=n.T_fc + aug.dT_fc, viscous=n.B + aug.dB,
                      load_coefficient=n.G + aug.dG)
    T = s * (sliding_friction(law, speed, F, T_L) + T_L * (aug.eff_base + aug.eff_speed * speed))
    if aug.stribeck_torque:
        T = T + s * aug.stribeck_torque * np.exp(-(speed / aug.stribeck_speed) ** 2)
    return T


def force_from_travel(n: Nominal, aug: Augment, x: np.ndarray) -> np.ndarray:
    """Clamp force read by the sensor at nut travel ``x`` [m]: 004 eq. 5 with the corrections of ``aug`` [N].

    F_meas = (1 + g) (K_b d + k_2 d^2) + b with d = max(0, x - x_ag - dx); the spring is the twin's
    :class:`~ebm_wear_monitor.twin.clamp.ClampLaw`, whose stiffening s = 2 k_2 delta_ref / K_b.
    """
    spring = ClampLaw(n.K_b, n.x_ag + aug.clearance,
                      2.0 * aug.stiffness_quad * STIFFENING_REFERENCE_FORCE / n.K_b**2)
    return (1.0 + aug.force_gain) * spring.force(x) + aug.force_bias


def rest_angle(rec: Recording, seg: Segmentation) -> float:
    """Rest (released) screw angle [rad]: the median angle of all idle samples (else the first sample).

    One value for the recording: the controller returns to the same rest position every cycle,
    and a per-cycle estimate would add a noise shared by all blocks of a cycle.
    """
    idle = seg.phase == IDLE
    return float(np.median(rec.angle[idle])) if idle.any() else float(rec.angle[0])


@dataclass(frozen=True)
class Blocks:
    """Blocks of samples [start, stop] (end points shared by neighbours) inside one phase run of one cycle."""

    start: np.ndarray
    stop: np.ndarray
    phase: np.ndarray  # phase code (-1 idle)
    cycle: np.ndarray  # brake-cycle index
    run: np.ndarray  # id of the phase run the block belongs to (for noise differences)
    moving: np.ndarray  # bool: the screw moves over most of the block
    speed: np.ndarray  # mean |screw speed| [rad/s]
    force: np.ndarray  # mean recorded axial force [N]

    @property
    def size(self) -> int:
        return int(self.start.size)


def make_blocks(seg: Segmentation, speed: np.ndarray, force: np.ndarray, moving: np.ndarray,
                n_per_block: int) -> Blocks:
    """Cut every run of equal (cycle, phase) into blocks of about ``n_per_block`` samples."""
    key = seg.cycle.astype(np.int64) * 8 + (seg.phase.astype(np.int64) + 1)
    run_start = np.flatnonzero(np.concatenate(([True], key[1:] != key[:-1])))
    run_stop = np.append(run_start[1:], key.size) - 1  # last sample of each run
    starts, stops, runs = [], [], []
    for r, (a, b) in enumerate(zip(run_start, run_stop, strict=True)):
        span = int(b - a)
        if span < 2:
            continue
        nb = max(1, span // n_per_block)
        edges = np.round(np.linspace(a, b, nb + 1)).astype(np.int64)
        starts.append(edges[:-1])
        stops.append(edges[1:])
        runs.append(np.full(nb, r))
    start = np.concatenate(starts)
    stop = np.concatenate(stops)
    cum = lambda y: np.concatenate(([0.0], np.cumsum(y, dtype=float)))  # noqa: E731
    n = (stop - start + 1).astype(float)
    mean = lambda c: (c[stop + 1] - c[start]) / n  # noqa: E731
    return Blocks(start, stop, seg.phase[start], seg.cycle[start], np.concatenate(runs),
                  mean(cum(moving)) >= 0.5, mean(cum(np.abs(speed))), mean(cum(force)))


class ResidualModel:
    """Torque- and force-channel block residuals of one recording for any :class:`Augment`.

    Construction measures the sample noise, the rest band and the blocks once;
    :meth:`residuals` is then a few vectorised passes over the samples.
    """

    def __init__(self, rec: Recording, seg: Segmentation, nominal: Nominal, block_s: float = 0.02,
                 smooth_s: float = 0.005) -> None:
        self.rec, self.seg, self.nominal = rec, seg, nominal
        w = max(1, round(smooth_s / rec.dt))
        self.w_m = nominal.i_g * rec.velocity  # motor speed, 004 eq. 3 [rad/s]
        w_smooth = uniform_filter1d(self.w_m, w, mode="nearest")
        sigma_w = signal_noise(self.w_m)
        #: rest band of the motor speed (004 eq. 9 epsilon): 3 sigma of the smoothed speed noise
        self.eps = max(3.0 * sigma_w / math.sqrt(w), nominal.i_g * 0.5 * seg.eps_velocity)
        # sliding where both the smoothed and the raw speed leave their 3-sigma rest bands: the smoothing
        # alone would widen every motion by half its window and charge the Coulomb torque to samples at rest
        smooth_moving = np.abs(w_smooth) > self.eps
        raw_moving = np.abs(self.w_m) > max(3.0 * sigma_w, self.eps)
        self.moving = smooth_moving & raw_moving
        self.sign = np.sign(w_smooth) * self.moving
        self.speed = np.abs(w_smooth)
        #: J_me dw_m/dt from the recorded speed (central differences, whose trapezoid integral over
        #: a block telescopes to the block's speed change): the inertia torque of samples at rest
        self.inertia_torque = nominal.J_me * np.gradient(self.w_m, rec.t)
        self.x = nominal.lead * (rec.angle - rest_angle(rec, seg)) / (2.0 * math.pi)  # nut travel, eq. 4 [m]
        self.drive_torque = nominal.K_T * rec.current  # motor torque, 004 eq. 7 [N m]
        self.blocks = make_blocks(seg, rec.velocity, rec.axial_force, self.moving,
                                  max(2, round(block_s / rec.dt)))
        if self.blocks.size < 4:
            raise InputError(f"{rec.unit}: too short for the diagnosis ({self.blocks.size} blocks)")
        self._dt_block = rec.t[self.blocks.stop] - rec.t[self.blocks.start]
        self._dw_block = self.w_m[self.blocks.stop] - self.w_m[self.blocks.start]
        self.unresolved_torque = self._unresolved_torque()

    def _unresolved_torque(self) -> np.ndarray:
        """Per-block uncertainty of the motor-torque integral from current changes between samples [N m].

        The armature current settles within tau_e = L_a / R_a (004 eq. 8; 0.9 ms for
        004's motor), often faster than the sample interval: at the start of a move
        the current jumps within the first interval and the trapezoid rule does not
        know when.  For a monotone change dI over an interval dt, the integral lies
        within +-|dI| dt / 2 of the trapezoid value; taken as uniform, its standard
        deviation is |dI| dt / (2 sqrt 3).  Only the part of |dI| above three
        standard deviations of the sensor noise (sqrt 2 sigma_I per difference) counts;
        the errors of consecutive intervals of one transient share a sign, so they
        add linearly within a block.  This enters the block's noise, so blocks whose
        current the sampling does not resolve weigh little instead of being dropped
        by a threshold.  (The curvature estimate |trapezoid - Simpson| = |d^2 I| dt / 12
        was tried instead: for a current step sampled at 500 Hz (dt = 2.2 tau_e) the
        trapezoid's true error is 0.17 |dI| dt against 0.07 |dI| dt estimated, and an
        independently integrated recording with a fast continuous current loop at 500 Hz
        then read as a Stribeck effect in 3 of 8 no-effect cases; this bound gives 0.29.)
        """
        rec, b = self.rec, self.blocks
        noise = 3.0 * math.sqrt(2.0) * signal_noise(rec.current)
        jump = np.maximum(np.abs(np.diff(rec.current)) - noise, 0.0)
        err = np.concatenate(([0.0], np.cumsum(jump * np.diff(rec.t) / (2.0 * math.sqrt(3.0)))))
        return self.nominal.K_T * (err[b.stop] - err[b.start]) / self._dt_block

    # ----------------------------------------------------------------- model terms per sample
    def true_force(self, aug: Augment) -> np.ndarray:
        """Clamp force behind the recorded one when the sensor reads F_meas = (1 + g) F + b [N]."""
        return (self.rec.axial_force - aug.force_bias) / (1.0 + aug.force_gain)

    def friction(self, aug: Augment) -> tuple[np.ndarray, np.ndarray]:
        """(friction torque T_f per sample [N m], load torque T_L per sample [N m]): 004 eq. 9 + ``aug``.

        At rest the friction is taken as whatever balances the drive (the stick branch of eq. 9
        without its band test, see the module docstring).
        """
        n = self.nominal
        F = self.true_force(aug)
        if aug.load_shift:  # quadrature timing of the load (module docstring)
            F = np.interp(self.rec.t + aug.load_shift, self.rec.t, F)
        T_L = n.load_ratio * F
        kinetic = kinetic_friction(n, aug, self.w_m, F, sign=self.sign, speed=self.speed)
        stuck = self.drive(aug) - T_L - self.inertia_torque  # whatever holds the drive (module doc)
        return np.where(self.moving, kinetic, stuck), T_L

    def drive(self, aug: Augment) -> np.ndarray:
        """Motor torque K_T I [N m] (004 eq. 7), the current read ``aug.current_shift`` seconds later."""
        if aug.current_shift == 0.0:
            return self.drive_torque
        t = self.rec.t
        return self.nominal.K_T * np.interp(t + aug.current_shift, t, self.rec.current)

    def force_model(self, aug: Augment) -> np.ndarray:
        """Axial force the model predicts from the recorded nut travel, as the sensor would read it [N]."""
        return force_from_travel(self.nominal, aug, self.x)

    # ----------------------------------------------------------------- block residuals
    def _net_integral(self, aug: Augment) -> np.ndarray:
        """Cumulative trapezoid integral of the net torque K_T I - T_L - T_f from the first sample [N m s]."""
        T_f, T_L = self.friction(aug)
        net = self.drive(aug) - T_L - T_f
        return np.concatenate(([0.0], np.cumsum(0.5 * (net[1:] + net[:-1]) * np.diff(self.rec.t))))

    def residuals(self, aug: Augment = NOMINAL) -> dict[str, np.ndarray]:
        """Block residuals ``torque`` (R_T [N m]) and ``force`` (R_F [N]), see the module docstring."""
        return self._block_residuals(aug, self._net_integral(aug))

    def _block_residuals(self, aug: Augment, C: np.ndarray) -> dict[str, np.ndarray]:
        """:meth:`residuals` given the net-torque integral ``C`` of ``aug``."""
        b = self.blocks
        torque = (C[b.stop] - C[b.start] - self.nominal.J_me * self._dw_block) / self._dt_block
        df = self.rec.axial_force - self.force_model(aug)
        cf = np.concatenate(([0.0], np.cumsum(df)))
        force = (cf[b.stop + 1] - cf[b.start]) / (b.stop - b.start + 1)
        return {"torque": torque, "force": force}

    def signal_residuals(self, aug: Augment = NOMINAL) -> dict[str, np.ndarray]:
        """Per-block residual of each recorded signal, twin minus recording where the twin predicts it.

        ``current``: recorded current minus the current the model needs [A] (R_T / K_T, sign flipped
        so that positive means the twin needs more); ``velocity``: re-anchored twin screw speed minus
        recorded at block end [rad/s]; ``angle``: re-anchored twin screw angle minus recorded at block
        end [rad]; ``axial_force``: force predicted from the nut travel minus recorded [N].
        """
        n, b, t = self.nominal, self.blocks, self.rec.t
        C = self._net_integral(aug)
        res = self._block_residuals(aug, C)
        # velocity error inside each block e(t) = w(t0) - w(t) + (C(t) - C(t0)) / J; its integral:
        g = C / n.J_me - self.w_m
        D = np.concatenate(([0.0], np.cumsum(0.5 * (g[1:] + g[:-1]) * np.diff(t))))
        angle_err = (D[b.stop] - D[b.start]) + (self.w_m[b.start] - C[b.start] / n.J_me) * self._dt_block
        return {
            "current": -res["torque"] / n.K_T,
            "velocity": res["torque"] * self._dt_block / n.J_me / n.i_g,
            "angle": angle_err / n.i_g,
            "axial_force": -res["force"],
        }
