"""Residuals that measure the twin, not accumulated drift: torque balance and force-angle law per block.

Why not simply run the twin on the recorded current and compare?  The twin of
004 is current driven: 004 eq. 1, J_me dw_m/dt = K_T I_a - l F_cl / (2 pi i_g) - T_f,
integrates every torque error twice, and the stiff clamp (004 eq. 5) turns a
0.05 N m friction mismatch into radians of angle and kilonewtons of force within
one recording.  A free simulation therefore reports drift, not the model.  This
module compares the model with the recording in two *algebraic* channels that
need no integration across more than one short block.

**Torque channel (004 eq. 1, 7, 9), re-anchored every block.**  Blocks are
``block_s`` long (20 ms by default), never straddle a phase or cycle boundary,
and start from the *recorded* state.  Integrating eq. 1 over a block [t0, t1]
along the recorded speed and force gives the twin's speed at t1,

    w_sim(t1) = w(t0) + (1/J_me) * int_{t0}^{t1} (K_T I - T_L(F) - T_f(w, F)) dt,

(T_L = l F / (2 pi i_g), the load torque at the motor of 004 eq. 1) and the block
residual is the speed the twin gains over the recording, expressed as the mean
torque it takes:

    R_T = [int (K_T I - T_L - T_f) dt - J_me (w(t1) - w(t0))] / (t1 - t0)   [N m].

R_T is "recorded motor torque minus the torque the model needs for the recorded
motion and force"; positive means the real unit needed more torque (e.g. more
friction) than the twin.  The speed w is the angle's own derivative
(:mod:`.conventions`: a drive's velocity estimate lags, and at 8 N m of inertia
torque a 1 ms lag is a friction-sized error), taken within each phase run so that
the block end points never sit on a kink.  J_me is 004 eq. 2.  The same block gives
the twin's velocity error w_sim - w at t1 (= R_T (t1 - t0) / J_me) and its angle
error at t1 (the integral of that velocity error over the block): the re-anchored
short-horizon simulation of the velocity and angle signals.

Friction follows 004 eq. 9, evaluated on the recorded state. Moving
(|w_m| > eps):  T_f = (T_fc + G F) sgn(w_m) + B w_m.  At rest (the stick branch)
eq. 9 only bounds the friction, |T_f| <= T_fs + G F, and the friction takes
whatever value balances K_T I - T_L - J_me dw_m/dt: blocks at rest carry no
torque residual and T_fs is not identified from the torque balance.

**Force channel (004 eq. 4-5).**  The nut travel x = l (theta - theta_rest,c) / (2 pi),
counted from the released rest angle of its application c (:mod:`.conventions`),
predicts the clamp force F = K_b max(0, x - x_ag); the sensor reads it through its
tare b_c (:mod:`.conventions`), its gain and its lag.  The block mean of recorded
minus predicted reading is R_F [N].  It sees clearance, stiffness and force-sensor
gain errors, which the torque channel (evaluated at the *recorded* force) does not.

**Acquisition nuisances** (fitted with every model, the nominal one included, by
:mod:`.ranking`; reported under ``nuisances``; never an effect):

* ``current_shift`` tau_I: the current is read at t + tau_I.  A drive may log the
  current at the start of its control period while the torque acts over the period
  (its mean), and topics may be stamped with a skew; bounded by one native current
  sample interval.
* ``current_offset`` i_0: the current sensor's zero, K_T (I - i_0).  At rest it is
  absorbed by the stick branch; while moving it is a torque of the same sign in
  both directions, which no friction effect (all odd in w_m) can imitate.
* ``force_skew`` s_F and ``force_lag`` tau_F: the force reading at stamp t is the
  force of t - s_F seen through a first-order lag tau_F >= 0 (a load cell's
  amplifier, a topic stamped late).  In the force channel the model is
  F_read = b_c + (1 + g) L_tau(F(t - s_F)) with L_tau the backward-Euler lag
  y_k = y_(k-1) + dt/(tau + dt) (u_k - y_(k-1)) (its slope in tau is 1/dt at tau = 0,
  so the fit can leave zero); in the torque channel the load is read at
  t + s_F + tau_F (a lag is a delay to first order).
* ``load_shift`` tau_M: the quadrature rule of the load between samples.  The
  recording gives the force only at the samples; a sampled continuous plant
  follows the trapezoid rule used here, a drive or simulator holding the force
  over each step of length h the left rectangle, which differs from the trapezoid
  by the trapezoid of T_L read h/2 earlier.  So the load is read a further tau_M
  later, within one sample interval (the quadrature's half interval, and what the force
  channel's timing misses of the torque channel's).  The price is honest: a viscous change that acts only
  in contact, of at most K_eff dt / 2 (7 % of 004's B at 1 kHz), is not separable
  from the quadrature rule; a viscous effect is identified by what it does outside
  contact (clearance elimination, the end of the release).

Unmodelled effects enter as an :class:`Augment` (corrections to the nominal
parameters and functional forms); :mod:`.catalog` maps each effect's few
parameters onto it.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Callable, Hashable
from dataclasses import dataclass, fields

import numpy as np
from scipy.signal import lfilter

from ebm_wear_monitor.diagnosis.conventions import Conventions
from ebm_wear_monitor.diagnosis.noise import signal_noise
from ebm_wear_monitor.diagnosis.phases import Segmentation
from ebm_wear_monitor.diagnosis.recording import Resampled
from ebm_wear_monitor.diagnosis.speed import window_half
from ebm_wear_monitor.domain.segmentation import run_ids, run_starts
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.twin.clamp import STIFFENING_REFERENCE_FORCE, ClampLaw
from ebm_wear_monitor.twin.dynamics import ActuatorModel
from ebm_wear_monitor.twin.friction import FrictionLaw, sliding_friction

CHANNELS = ("torque", "force")


@dataclass(frozen=True)
class Augment:
    """Corrections to the nominal twin and the acquisition nuisances; all zero is the nominal twin.

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
    force_gain: float = 0.0  # force-sensor gain error g: F_read = b + (1 + g) F [-]
    # ---- acquisition nuisances (module docstring)
    current_shift: float = 0.0  # tau_I: current read this much later [s]
    current_offset: float = 0.0  # i_0: current-sensor zero [A]
    force_skew: float = 0.0  # s_F: force stamped this much late [s]
    force_lag: float = 0.0  # tau_F: first-order lag of the force reading [s], >= 0
    load_shift: float = 0.0  # tau_M: quadrature rule of the load between samples [s]
    # ---- model tolerances (never fitted; :mod:`.tolerance` perturbs them to derive detectability floors)
    drive_gain: float = 0.0  # relative error of K_T times the current-sensor gain [-]
    inertia_gain: float = 0.0  # relative error of J_me [-]
    stiffness_gain: float = 0.0  # relative error of K_b [-]
    reverse_dT_fc: float = 0.0  # extra Coulomb friction in the release direction only [N m]
    reverse_dG: float = 0.0  # extra load coefficient in the release direction only [N m/N]


NOMINAL = Augment()
#: the Augment fields that are acquisition nuisances, per channel they act in
NUISANCES = {"torque": ("current_shift", "current_offset", "load_shift"),
             "force": ("force_skew", "force_lag")}
NUISANCE_UNITS = {"current_shift": "s", "current_offset": "A", "load_shift": "s", "force_skew": "s",
                  "force_lag": "s"}
#: the Augment fields of the model corrections that act in each channel (force_gain acts in both)
TORQUE_FIELDS = ("dB", "dG", "dT_fs", "dT_fc", "eff_base", "eff_speed", "stribeck_torque", "stribeck_speed",
                 "force_gain")
FORCE_FIELDS = ("stiffness_quad", "clearance", "force_gain")
#: every Augment field each channel's residual reads (model corrections, nuisances, tolerances): the key
#: under which :class:`ResidualModel` remembers a residual
TORQUE_INPUTS = (*TORQUE_FIELDS, "current_shift", "current_offset", "force_skew", "force_lag", "load_shift",
                 "drive_gain", "inertia_gain", "reverse_dT_fc", "reverse_dG")
FORCE_INPUTS = (*FORCE_FIELDS, "force_skew", "force_lag", "stiffness_gain")


def moves(field: str) -> tuple[str, ...]:
    """The channels whose residual the :class:`Augment` field ``field`` changes (:data:`TORQUE_INPUTS`,
    :data:`FORCE_INPUTS`)."""
    inputs = (TORQUE_INPUTS, FORCE_INPUTS)
    return tuple(ch for ch, read in zip(CHANNELS, inputs, strict=True) if field in read)


def nuisances_of(aug: Augment) -> dict[str, float]:
    """The nuisance values of ``aug`` by name."""
    return {f.name: getattr(aug, f.name) for f in fields(aug) if f.name in NUISANCE_UNITS}


def kinetic_friction(n: ActuatorModel, aug: Augment, w_m: np.ndarray, F: np.ndarray, *,
                     sign: np.ndarray | None = None, speed: np.ndarray | None = None) -> np.ndarray:
    """Moving branch of 004 eq. 9 with the corrections of ``aug`` [N m].

    T_f = (T_fc + dT_fc + (G + dG) F) s + (B + dB) w_m + s T_L (a_0 + a_w |w_m|)
    + s T_S exp(-(|w_m| / w_S)^2), s = sgn(w_m), T_L = l F / (2 pi i_g);
    the eq. 9 part is the twin's :func:`ebm_wear_monitor.twin.friction.sliding_friction`.
    """
    s = np.sign(w_m) if sign is None else sign
    speed = np.abs(w_m) if speed is None else speed
    T_L = n.load_torque(F)
    f = n.friction
    law = FrictionLaw(static=f.static + aug.dT_fs, coulomb=f.coulomb + aug.dT_fc, viscous=f.viscous + aug.dB,
                      load_coefficient=f.load_coefficient + aug.dG)
    T = s * (sliding_friction(law, speed, F, T_L) + T_L * (aug.eff_base + aug.eff_speed * speed))
    if aug.reverse_dT_fc or aug.reverse_dG:
        T = T + np.minimum(s, 0.0) * (aug.reverse_dT_fc + aug.reverse_dG * F)
    if aug.stribeck_torque:
        T = T + s * aug.stribeck_torque * np.exp(-(speed / aug.stribeck_speed) ** 2)
    return T


def clamp_spring(n: ActuatorModel, aug: Augment) -> ClampLaw:
    """004 eq. 5 with the clearance and stiffening of ``aug`` (the twin's :class:`ClampLaw`, whose
    stiffening s = 2 k_2 delta_ref / K_b, so that F = K_b d + k_2 d^2)."""
    K_b = n.clamp.stiffness * (1.0 + aug.stiffness_gain)
    stiffening = 2.0 * aug.stiffness_quad * STIFFENING_REFERENCE_FORCE / K_b**2
    return ClampLaw(K_b, n.clamp.clearance + aug.clearance, stiffening)


def first_order_lag(u: np.ndarray, tau: float, dt: float) -> np.ndarray:
    """Backward-Euler first-order lag y_k = y_(k-1) + dt/(tau + dt) (u_k - y_(k-1)), y_0 = u_0."""
    if tau <= 0.0:
        return u
    a = tau / (tau + dt)
    return lfilter([1.0 - a], [1.0, -a], u, zi=[a * u[0]])[0]


def block_mean(y: np.ndarray, start: np.ndarray, stop: np.ndarray) -> np.ndarray:
    """Mean of the per-sample ``y`` over the samples ``start .. stop`` (inclusive) of each block."""
    c = np.concatenate(([0.0], np.cumsum(y, dtype=float)))
    mean: np.ndarray = (c[stop + 1] - c[start]) / (stop - start + 1).astype(float)
    return mean


@dataclass(frozen=True)
class Blocks:
    """Blocks of samples [start, stop] (end points shared by neighbours) inside one phase run of one cycle."""

    start: np.ndarray
    stop: np.ndarray
    phase: np.ndarray  # Phase code
    cycle: np.ndarray  # brake-cycle index
    run: np.ndarray  # id of the phase run the block belongs to (for noise differences)
    moving: np.ndarray  # bool: the screw moves over most of the block
    speed: np.ndarray  # mean |screw speed| [rad/s]
    force: np.ndarray  # mean tared axial force [N]

    @property
    def size(self) -> int:
        return int(self.start.size)

    def mean(self, y: np.ndarray) -> np.ndarray:
        """Block mean of the per-sample ``y`` (:func:`block_mean`)."""
        return block_mean(y, self.start, self.stop)

    def cycle_max(self, y: np.ndarray) -> np.ndarray:
        """Largest per-block ``y`` of each brake cycle, indexed by cycle (-inf for a cycle with no block)."""
        out = np.full(int(self.cycle.max()) + 1, -np.inf)
        np.maximum.at(out, self.cycle, y)
        return out


def make_blocks(seg: Segmentation, speed: np.ndarray, force: np.ndarray, moving: np.ndarray,
                n_per_block: int) -> Blocks:
    """Cut every run of equal (cycle, phase) into blocks of about ``n_per_block`` samples."""
    run_start = run_starts(run_ids(seg.phase, seg.cycle))
    run_stop = np.append(run_start[1:], seg.phase.size) - 1  # last sample of each run
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
    if not starts:
        raise InputError("no phase run long enough for the diagnosis")
    start = np.concatenate(starts)
    stop = np.concatenate(stops)
    return Blocks(start, stop, seg.phase[start], seg.cycle[start], np.concatenate(runs),
                  block_mean(moving, start, stop) >= 0.5, block_mean(np.abs(speed), start, stop),
                  block_mean(force, start, stop))


class Memo:
    """The values of an expensive function for the ``size`` keys used last (read-only arrays)."""

    def __init__(self, size: int) -> None:
        self.size = size
        self._values: OrderedDict[Hashable, np.ndarray] = OrderedDict()

    def get(self, key: Hashable, compute: Callable[[], np.ndarray]) -> np.ndarray:
        """The value remembered for ``key``, else ``compute()`` (remembered; the least recently used goes)."""
        if key in self._values:
            self._values.move_to_end(key)
            return self._values[key]
        value = compute()
        value.flags.writeable = False  # shared by every caller of the key
        self._values[key] = value
        if len(self._values) > self.size:
            self._values.popitem(last=False)
        return value


class ResidualModel:
    """Torque- and force-channel block residuals of one recording for any :class:`Augment`.

    Construction takes the conventions (speed from the angle, rest angles, tares) and cuts the
    blocks once; :meth:`residuals` is then a few vectorised passes over the samples.  The fits
    evaluate the same residual many times (a finite-difference column moves one parameter, which
    leaves the channel it does not act in unchanged; a fitted model is scored several times), so
    each channel's residual is remembered for the Augment fields it reads (:data:`TORQUE_INPUTS`,
    :data:`FORCE_INPUTS`), and each signal read later for its shift.
    """

    #: residuals remembered (the last evaluations of either channel: a finite-difference column of a
    #: parameter of one channel finds the other's there), and shifted signals (one per-sample array each,
    #: held as long as the model)
    MEMO_RESIDUALS, MEMO_SIGNALS = 8, 4

    def __init__(self, rec: Resampled, seg: Segmentation, conv: Conventions, nominal: ActuatorModel,
                 block_s: float = 0.02) -> None:
        self.rec, self.seg, self.conv, self.nominal = rec, seg, conv, nominal
        self.w_m = nominal.gear_ratio * conv.speed  # motor speed, 004 eq. 3 [rad/s]
        #: 1-sigma noise of the motor speed per sample [rad/s]
        self.sigma_w = nominal.gear_ratio * conv.sigma_angle * np.sqrt(np.minimum(conv.speed_factor, 1e30))
        #: rest band of the motor speed (004 eq. 9 epsilon): 3 sigma of its noise, at least the phase rule's
        self.eps = max(3.0 * float(np.median(self.sigma_w)), nominal.gear_ratio * 0.5 * seg.eps_velocity)
        self.moving = np.abs(self.w_m) > np.maximum(self.eps, 3.0 * self.sigma_w)
        self.sign = np.sign(self.w_m) * self.moving
        self.speed = np.abs(self.w_m)
        #: J_me dw_m/dt from the speed: the inertia torque of samples at rest (stick branch)
        self.inertia_torque = nominal.inertia * np.gradient(self.w_m, rec.t)
        rest, tare = conv.per_sample(seg)
        self.tare = tare
        self.force = rec.axial_force - tare  # tared force reading [N]
        self.x = nominal.nut_travel(rec.angle - rest)  # nut travel, 004 eq. 4 [m]
        #: half the band the ECU parks in, in nut travel [m] (:mod:`.conventions`, :mod:`.tolerance`)
        self.park_half_band = float(nominal.nut_travel(np.asarray(conv.park_half_band)))
        self.blocks = make_blocks(seg, self.w_m, self.force, self.moving, max(2, round(block_s / rec.dt)))
        if self.blocks.size < 4:
            raise InputError(f"{rec.unit}: too short for the diagnosis ({self.blocks.size} blocks)")
        b = self.blocks
        self._dt_block = rec.t[b.stop] - rec.t[b.start]
        self._dw_block = self.w_m[b.stop] - self.w_m[b.start]
        self.unresolved_torque = self._unresolved_torque()
        self.ambiguous_torque = self._ambiguous_torque()
        self.drive_torque_nominal = nominal.torque_constant * rec.current  # 004 eq. 7 [N m]
        self._h = np.diff(rec.t)  # sample intervals [s]
        self._signals = {"force": self.force, "current": rec.current, "travel": self.x}
        self._residuals, self._shifted = Memo(self.MEMO_RESIDUALS), Memo(self.MEMO_SIGNALS)

    def _current_jumps(self) -> np.ndarray:
        """|dI| of each sample interval beyond three standard deviations of its noise [A] (zero otherwise)."""
        noise = 3.0 * math.sqrt(2.0) * signal_noise(self.rec.current)
        return np.maximum(np.abs(np.diff(self.rec.current)) - noise, 0.0)

    def _unresolved_torque(self) -> np.ndarray:
        """Per-block uncertainty of the torque balance where the sampling does not resolve a transient [N m].

        Two terms, added in quadrature.  **The current integral.**  The armature current settles
        within tau_e = L_a / R_a (004 eq. 8; 0.9 ms for 004's motor), often faster than the sample
        interval: at the start of a move the current jumps within the first interval and the
        trapezoid rule does not know when.  For a monotone change dI over an interval dt, the
        integral lies within +-|dI| dt / 2 of the trapezoid value; taken as uniform, its standard
        deviation is |dI| dt / (2 sqrt 3).  The errors of consecutive intervals of one transient
        share a sign, so they add linearly within a block.  **The speed at the block's ends.**  The
        angle's speed is a regression over a window of half-length h (:mod:`.speed`); a step dA of
        the acceleration inside the window, which a current jump dI makes (dA = K_T dI / J_me, 004
        eq. 1), biases that speed by up to dA h / 4: the block's J_me dw / dt_b then carries
        J_me (dA h / 4) / dt_b at each end, i.e. K_T dI h / (4 dt_b).  Only the part of each |dI|
        above three standard deviations of the current noise counts (sqrt 2 sigma_I per difference).
        A motion that stops makes such a step too: the stick branch of eq. 9 takes over and the
        deceleration the rotor had, J_me |dw/dt| on the moving side (the largest within the window),
        drops to zero at once; where and how a drive sticks is the simulator's or the drive's own
        convention, not an effect (a start comes with its own current jump).
        Both enter the block's noise, so blocks the sampling does not resolve weigh little instead of
        being dropped by a threshold.
        """
        rec, b, n = self.rec, self.blocks, self.nominal
        jump = self._current_jumps()
        h = np.maximum(np.diff(rec.t), rec.interval("current"))
        err = np.concatenate(([0.0], np.cumsum(jump * h / (2.0 * math.sqrt(3.0)))))
        integral = n.torque_constant * (err[b.stop] - err[b.start]) / self._dt_block
        half = window_half(rec.dt)

        def window_max(y: np.ndarray) -> np.ndarray:  # max of y over the speed window around each sample
            padded = np.concatenate((np.zeros(half), y, np.zeros(half + 1 + rec.t.size - y.size)))
            return np.max(np.lib.stride_tricks.sliding_window_view(padded, 2 * half + 1), axis=1)[:rec.t.size]

        # acceleration steps as torques J_me dA: a current jump (K_T dI), and a motion that stops, where
        # the stick branch of eq. 9 takes over from the sliding friction and the acceleration drops by
        # the one the rotor had on its moving side (J_me |dw/dt| there)
        switch = self.moving[:-1] & ~self.moving[1:]  # stops only: a start comes with its current jump
        stick = np.where(switch, window_max(np.abs(self.inertia_torque))[:-1], 0.0)
        largest = window_max(np.maximum(n.torque_constant * jump, stick))
        h_s = half * rec.dt
        end = largest * h_s / 4.0  # torque-equivalent speed bias J_me dw [N m s]
        speed = np.hypot(end[b.start], end[b.stop]) / self._dt_block
        return np.hypot(integral, speed)

    def _ambiguous_torque(self) -> np.ndarray:
        """Per-block uncertainty of the friction where stick and slip cannot be told apart [N m].

        004 eq. 9 switches between sliding friction (T_fc + G F) sgn(w_m) + B w_m and the stick
        branch, where the friction is anything within +-(T_fs + G F).  At low speed a drive
        may creep by stick-slip (a position loop pushing against breakaway), faster than any speed
        estimate resolves: a block that moves on average may hold intervals in which the screw
        did not move at all.  Such a block moves *irregularly*: its angle increments scatter about
        their trend (a straight line in time) by more than the angle noise allows, three times
        sqrt(2) sigma_theta (or the encoder's quantum, whichever is larger).  In its intervals that
        cannot be told from standstill, |d theta| <= that same bound, the friction is only known
        to lie in the stick band, uniformly: standard deviation (T_fs + G F) / sqrt(3).  The errors
        of one creep share a sign, so such a block's uncertainty is the share of those intervals
        among its moving ones times that standard deviation.  A block that moves less than one count of
        a quantised angle per interval on average is unresolved too: its increments are 0 or 1 count,
        within the scatter a steady creep has, so a steady creep and a stick-slip look alike.  (A
        healthy foreign unit of the blind draw ``full_j`` with a 12-bit motor-side encoder, none_j003,
        held the force by creeping at 0.2-0.6 rad/s of the motor, one count every 3-8 ms, and its
        blocks there missed the sliding friction by +-0.1 N m.)  With a continuous angle the increments
        of every interval carry the motion and only the scatter decides; the noise bound is no measure
        of resolution (at 250 Hz the second differences count the trajectory's own curvature into the
        angle noise, and a bound of 18 counts took the slow blocks that showed a foreign Stribeck
        friction for creep).  Smoothly moving blocks (a slow but steady creep resolved by the angle
        included) keep their full weight.
        """
        rec, b, n = self.rec, self.blocks, self.nominal
        dtheta = np.diff(rec.angle)
        adt = np.abs(dtheta)
        count = self.conv.angle_count
        bound = max(3.0 * math.sqrt(2.0) * self.conv.sigma_angle, 1.01 * count)
        moving_interval = self.moving[1:] | self.moving[:-1]
        cum = lambda y: np.concatenate(([0.0], np.cumsum(y)))  # noqa: E731
        k = np.arange(dtheta.size, dtype=float)
        # per block (intervals start..stop-1): least-squares line of the increments against their index
        S0, S1, S2 = (cum(k**p)[b.stop] - cum(k**p)[b.start] for p in (0, 1, 2))
        Y0, Y1, Y2 = (cum(v)[b.stop] - cum(v)[b.start] for v in (dtheta, k * dtheta, dtheta**2))
        den = np.maximum(S0 * S2 - S1**2, 1e-300)
        slope = (S0 * Y1 - S1 * Y0) / den
        icpt = (Y0 - slope * S1) / np.maximum(S0, 1.0)
        sse = Y2 - icpt * Y0 - slope * Y1
        scatter = np.sqrt(np.maximum(sse, 0.0) / np.maximum(S0 - 2.0, 1.0))
        # a creep by less than one count per interval is unresolved: a staircase of 0 and 1 counts
        unresolved = np.abs(Y0) < count * np.maximum(S0, 1.0)
        irregular = (scatter > bound) | unresolved
        amb = cum(((adt <= bound) & moving_interval).astype(float))
        mov = cum(moving_interval.astype(float))
        share = (amb[b.stop] - amb[b.start]) / np.maximum(mov[b.stop] - mov[b.start], 1.0)
        band = (n.friction.static + n.friction.load_coefficient * np.abs(b.force)) / math.sqrt(3.0)
        return share * band * (b.moving & irregular)

    # ----------------------------------------------------------------- model terms per sample
    def _read_later(self, signal: str, shift: float) -> np.ndarray:
        """The per-sample ``signal`` (``force``, ``current`` or ``travel``) read ``shift`` seconds later
        (linear interpolation, held at the ends)."""
        y = self._signals[signal]
        if shift == 0.0:
            return y
        t = self.rec.t
        return self._shifted.get((signal, shift), lambda: np.interp(t + shift, t, y))

    def load_force(self, aug: Augment) -> np.ndarray:
        """Clamp force behind the reading for the load torque: tared, gain removed, lag and skew undone."""
        shift = aug.force_skew + aug.force_lag + aug.load_shift
        return self._read_later("force", shift) / (1.0 + aug.force_gain)

    def friction(self, aug: Augment, drive: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(friction torque T_f per sample [N m], load torque T_L per sample [N m]): 004 eq. 9 + ``aug``.

        At rest the friction is taken as whatever balances the drive (the stick branch of eq. 9
        without its band test, see the module docstring); ``drive`` is :meth:`drive` of ``aug``.
        """
        n = self.nominal
        F = self.load_force(aug)
        T_L = n.load_torque(F)
        kinetic = kinetic_friction(n, aug, self.w_m, F, sign=self.sign, speed=self.speed)
        stuck = drive - T_L - (1.0 + aug.inertia_gain) * self.inertia_torque  # module docstring
        return np.where(self.moving, kinetic, stuck), T_L

    def drive(self, aug: Augment) -> np.ndarray:
        """Motor torque K_T (I - i_0) [N m] (004 eq. 7), the current read ``aug.current_shift`` later."""
        K_T = self.nominal.torque_constant * (1.0 + aug.drive_gain)
        return K_T * (self._read_later("current", aug.current_shift) - aug.current_offset)

    def force_model(self, aug: Augment) -> np.ndarray:
        """Tared force reading the model predicts from the nut travel: (1 + g) L_tau(F(t - s_F)) [N]."""
        x = self._read_later("travel", -aug.force_skew)
        spring = clamp_spring(self.nominal, aug).force(x)
        return (1.0 + aug.force_gain) * first_order_lag(spring, aug.force_lag, self.rec.dt)

    def drive_block(self) -> np.ndarray:
        """Block mean of the motor torque K_T I [N m] (the scale of the torque channel)."""
        return self.blocks.mean(self.drive_torque_nominal)

    # ----------------------------------------------------------------- block residuals
    def _net_integral(self, aug: Augment, *, friction: bool = True) -> np.ndarray:
        """Cumulative trapezoid integral of the net torque K_T I - T_L - T_f from the first sample [N m s]
        (without ``friction``: of K_T I - T_L)."""
        drive = self.drive(aug)
        if friction:
            T_f, T_L = self.friction(aug, drive)
            net = drive - T_L - T_f
        else:
            net = drive - self.nominal.load_torque(self.load_force(aug))
        return self._cumulative(net)

    def _cumulative(self, y: np.ndarray) -> np.ndarray:
        """Cumulative trapezoid integral of the per-sample ``y`` from the first sample [unit of y x s]."""
        return np.concatenate(([0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * self._h)))

    def held_torque(self, aug: Augment) -> np.ndarray:
        """Per block, the torque the friction must take for the recorded motion and force [N m]: R_T with
        no friction, K_T I - T_L - J_me dw/dt averaged over the block (at rest 004 eq. 9 bounds it by the
        breakaway torque, :mod:`.stick`)."""
        return self.torque_residual(aug, self._net_integral(aug, friction=False))

    def torque_residual(self, aug: Augment, C: np.ndarray | None = None) -> np.ndarray:
        """R_T per block [N m] (module docstring); ``C`` the net-torque integral when already known
        (else remembered for the :data:`TORQUE_INPUTS` of ``aug``)."""
        if C is None:
            key = ("torque", *(getattr(aug, f) for f in TORQUE_INPUTS))
            return self._residuals.get(key, lambda: self.torque_residual(aug, self._net_integral(aug)))
        b = self.blocks
        return self._span_residual(aug, C[b.stop] - C[b.start], self._dw_block, self._dt_block)

    def span_torque_residual(self, aug: Augment, start: np.ndarray, stop: np.ndarray) -> np.ndarray:
        """R_T over the sample spans ``start .. stop`` of any windows, not only the blocks [N m] (the
        formula of the module docstring)."""
        dw, dt = self.w_m[stop] - self.w_m[start], self.rec.t[stop] - self.rec.t[start]
        C = self._net_integral(aug)
        return self._span_residual(aug, C[stop] - C[start], dw, dt)

    def _span_residual(self, aug: Augment, dC: np.ndarray, dw: np.ndarray, dt: np.ndarray) -> np.ndarray:
        """R_T from the net-torque integral ``dC`` [N m s], speed change ``dw`` [rad/s] and duration ``dt``
        [s] of each span."""
        J = self.nominal.inertia * (1.0 + aug.inertia_gain)
        result: np.ndarray = (dC - J * dw) / dt
        return result

    def force_residual(self, aug: Augment) -> np.ndarray:
        """R_F per block: mean tared reading minus the model's [N] (remembered for the :data:`FORCE_INPUTS`
        of ``aug``)."""
        key = ("force", *(getattr(aug, f) for f in FORCE_INPUTS))
        return self._residuals.get(key, lambda: self.blocks.mean(self.force - self.force_model(aug)))

    def residuals(self, aug: Augment = NOMINAL) -> dict[str, np.ndarray]:
        """Block residuals ``torque`` (R_T [N m]) and ``force`` (R_F [N])."""
        return {"torque": self.torque_residual(aug), "force": self.force_residual(aug)}

    def signal_residuals(self, aug: Augment = NOMINAL) -> dict[str, np.ndarray]:
        """Per-block residual of each recorded signal, twin minus recording where the twin predicts it.

        ``current``: recorded current minus the current the model needs [A] (R_T / K_T, sign flipped
        so that positive means the twin needs more); ``velocity``: re-anchored twin screw speed minus
        recorded at block end [rad/s]; ``angle``: re-anchored twin screw angle minus recorded at block
        end [rad]; ``axial_force``: force predicted from the nut travel minus recorded [N].
        """
        n, b = self.nominal, self.blocks
        C = self._net_integral(aug)
        torque = self.torque_residual(aug, C)
        # velocity error inside each block e(t) = w(t0) - w(t) + (C(t) - C(t0)) / J; its integral:
        D = self._cumulative(C / n.inertia - self.w_m)
        angle_err = (D[b.stop] - D[b.start]) + (self.w_m[b.start] - C[b.start] / n.inertia) * self._dt_block
        return {
            "current": -torque / n.torque_constant,
            "velocity": torque * self._dt_block / n.inertia / n.gear_ratio,
            "angle": angle_err / n.gear_ratio,
            "axial_force": -self.force_residual(aug),
        }
