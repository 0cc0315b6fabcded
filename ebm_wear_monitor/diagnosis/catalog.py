"""The catalog of unmodelled effects (interface.md section 4), each a small parametric augmentation.

Every effect maps a parameter vector ``theta`` (one or two numbers with a
physical meaning and a unit) onto an :class:`~.residuals.Augment` of the
nominal twin of 004.  Most effects are linear in their parameters, so their fit
is a linear least-squares problem; :mod:`.ranking` solves all of them with the
same bounded Gauss-Newton solver, together with the acquisition nuisances of the
channels the effect acts in.

==========================  ==============================================================  =============
name                        augmentation (motor shaft, s = sgn(w_m); nut side for forces)   parameters
==========================  ==============================================================  =============
viscous_friction            T_f += dB w_m, dB >= 0 (004 eq. 9, reason 1: lubricant drag     dB [N m s/rad]
                            left out; a drag larger than modelled)
load_friction               G -> G + dG, dG >= 0, in the moving branch of 004 eq. 9         dG [N m/N]
                            (reasons 2 and 5: roughness, lubrication, coaxiality)
efficiency_variation        T_f += s T_L (a_0 + a_w |w_m|): the loss factor 1/eta - 1 of   a_0 [-],
                            004 eq. 29 varying with speed                                   a_w [s/rad]
                            (reason 3); a_0 alone equals a change of G, so this effect
                            nests load_friction and must earn its extra parameter
preload_change              T_fs += dT, T_fc += dT (004 eq. 28-29, reason 4: the preload    dT [N m]
                            torque shifts both; only T_fc is seen while moving)
stribeck                    T_f += s T_S exp(-(|w_m| / w_S)^2), T_S >= 0: friction falling  T_S [N m],
                            from static towards Coulomb over a speed range (a friction      w_S [rad/s]
                            rising with speed is no Stribeck curve; the twin's own effect
                            is a hump above T_fc too)
stiffness_nonlinearity      F = K_b d + k_2 d^2, d = x - x_ag (004 eq. 5 made progressive)   k_2 [N/m^2]
clearance_growth            x_ag -> x_ag + dx (004 eq. 5; wear of balls and raceways)         dx [m]
force_sensor_bias           F_read = b + (1 + g) F; the offset b is the tare, estimated from  g [-]
                            the pads-open reading (:mod:`.conventions`), so the effect is
                            the gain error g that no tare removes
==========================  ==============================================================  =============

Each effect also has a **size**: one number in the unit people judge it by (a
fraction of the nominal parameter it changes, metres of clearance), which
:mod:`.tolerance` compares with the effect's detectability floor:

* viscous_friction |dB| / B; load_friction |dG| / G; preload_change |dT| / T_fc;
* efficiency_variation: how much the extra friction *varies* over the recorded speed
  range, as a fraction of the load torque, |a_w| (w_hi - w_lo): its speed-independent
  part a_0 is a load-friction change, so only the variation is this effect's own;
* stribeck: how much the extra friction falls from zero speed to the top recorded speed, as a
  fraction of T_fc, |T_S| (1 - exp(-(w_hi / w_S)^2)) / T_fc: an extra friction that does not fall
  within the recorded speeds is a preload change, so only the fall is this effect's own;
* stiffness_nonlinearity: the change of the tangent stiffness at the recording's
  largest clamp deflection d_max, |2 k_2 d_max| / K_b;
* clearance_growth: |dx| [m]; force_sensor_bias: |g| (a fraction of the reading).

**Look-alikes.**  One cause outside the catalog is, with the four recorded signals, the same
data as a catalog effect, so the diagnosis names the effect and says what else it can be:

* clearance_growth: a play (backlash) between the motor and the screw, when the angle is measured
  on the motor side.  004 eq. 5 sees the nut travel only through the recorded angle, so any lost
  motion between the angle sensor and the pads delays contact by the same angle; what tells a play
  apart is the friction downstream of it that the motor does not feel while crossing it, some
  milliseconds at the start of an application and after contact is lost, which the block residuals
  do not resolve.  The lost-motion test (:mod:`.play`) asks it after contact is lost in the release,
  where the sampling puts at least two samples (one interval) in each window across the play; where
  it cannot, or finds the clearance's friction, the summary says which.

**Limits.** Parameters that would make the twin unphysical, or the effect another than its name, are out
of reach of the fit: 004 eq. 9's friction stays dissipative (T_fc + dT >= 0: a negative coefficient
would drive the motion it opposes), the viscous drag and the load-dependent friction only grow (dB >= 0,
dG >= 0), a clearance growth only widens the clearance of eq. 5 (dx >= 0) and the clamp's tangent
stiffness stays positive up to the largest recorded force (K_b + 2 k_2 d_max >= 0). The two friction
limits are the effects' definitions (interface.md section 4: "lubricant viscous drag larger than
modelled", "load-dependent friction larger than modelled"; 004's reasons 1, 2 and 5 are friction the
model leaves out): a drag or a load friction below the twin's is no such effect, and naming it so would
report a viscous drag of minus a quarter of B. It is what the sampling makes of some healthy units: the
speed the inertia term takes from the angle lags where the acceleration changes within a window (README,
"Speed windows"), and four healthy units of the foreign and third worlds (none_r018 and none_x012 at 250
Hz, third-world seed 9 ``healthy_11`` and seed 15 ``healthy_03``) read as viscous drags of -24 % to -64
% of B before these limits (README, "One-sided friction"). Before them the limits were the dissipative
ones (B + dB >= 0, G + dG >= 0), which a preload relieved by the load, read as a viscous drag of -230 %
of B, reached. The clearance's limit is the effect's definition (interface.md section 4: "axial
clearance larger than nominal", the wear of balls and raceways, which removes material and never closes
the gap): a contact reached after less travel than the unit file's x_ag is no wear (an ECU that parks
the nut closer to the pads than the unit file says, a thicker pad), and naming it as this effect would
report a wear of minus some micrometres (a third, independently written world's healthy units, whose
force loop parks within its angle tolerance short of its rest target, read -7.5 and -8.4 um of
"clearance growth" before this limit; README "Third world"). On the foreign draws the same limit removes
a second effect that was listed beside nearly every foreign bilinear clamp stiffness (a soft first
segment, then a stiffer one): a negative clearance change standing in for the soft segment's later rise,
listed with the stiffness in 27 of 30 such recordings of the fifteen mixed draws and in the Stribeck +
stiffness pairs, where the pair is now named exactly. An effect whose fit sits on such a limit is not
named (:attr:`.ranking.EffectFit.nameable`): the data want more of it than it can physically give, or
the opposite of what it names, so its form is not what they show.
(The efficiency's loss factor is kept non-negative by no box on its two parameters and is left free.)

``scale`` gives a typical magnitude per parameter (the solver's scaling);
``starts`` lists starting points (several for the non-linear Stribeck speed; the one-sided frictions
start one scale inside their limit: a start on a bound of zero gives scipy's trust-region solver a first
radius of the start's norm, and a fit of the effect alone, as the drift test's halves, stopped there).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.diagnosis.residuals import Augment
from ebm_wear_monitor.schema.diagnose import Magnitude
from ebm_wear_monitor.twin.dynamics import ActuatorModel

#: a fitted parameter within this share of its scale of a bound is on it (:meth:`Effect.on_bound`)
ON_BOUND = 1e-3


@dataclass(frozen=True)
class Effect:
    """One catalog entry: parameters with units, their map onto an :class:`Augment`, and its size."""

    name: str
    meaning: str
    params: tuple[str, ...]
    units: tuple[str, ...]
    to_augment: Callable[[np.ndarray], Augment]
    scale: tuple[float, ...]
    starts: tuple[tuple[float, ...], ...]  # starting points of the fit
    lower: tuple[float, ...] | None = None  # bounds (None: unbounded)
    upper: tuple[float, ...] | None = None
    #: limit below which a parameter makes the twin unphysical or the effect another than its name
    #: (module docstring, "Limits"), -inf where none; the fit is bounded there too
    limits: tuple[float, ...] | None = None
    channels: tuple[str, ...] = ("torque",)  # residual channels the effect acts in
    #: size of a parameter vector in the unit people judge it by (module docstring), >= 0
    size: Callable[[np.ndarray], float] = lambda p: float(np.abs(p[0]))
    size_unit: str = "-"
    size_meaning: str = ""
    #: per parameter: (name of the nominal quantity it changes, its nominal value) or None
    nominal: tuple[tuple[str, float] | None, ...] = ()
    #: a physical cause outside the catalog that the sensors cannot tell from this effect (module
    #: docstring, "Look-alikes"); "" when none is known
    look_alike: str = ""

    @property
    def k(self) -> int:
        """Number of fitted parameters."""
        return len(self.params)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The fit's box: ``lower`` raised to the physical ``limits``, and ``upper``."""
        lo = np.maximum(_or_open(self.lower, self.k, -np.inf), _or_open(self.limits, self.k, -np.inf))
        return np.asarray(lo, dtype=float), np.asarray(_or_open(self.upper, self.k, np.inf), dtype=float)

    @property
    def one_sided(self) -> bool:
        """Every limit is zero: the effect only grows by its definition (module docstring, "Limits"), so a
        fit on its limit means the data want the opposite of what it names, not an unphysical twin."""
        return self.limits is not None and all(lim == 0.0 for lim in self.limits)

    def at_limit(self, theta: np.ndarray) -> bool:
        """A parameter sits on its physical limit (within ``ON_BOUND`` of its scale): the data want more
        than the effect can physically give (module docstring, "Limits")."""
        if self.limits is None:
            return False
        return bool(np.any(np.asarray(theta) - np.asarray(self.limits) <= ON_BOUND * np.asarray(self.scale)))

    def on_bound(self, theta: np.ndarray) -> np.ndarray:
        """Per parameter: it sits on a bound of the fit's box (:meth:`bounds`, within ``ON_BOUND`` of its
        scale), where the solver held it."""
        lo, hi = self.bounds()
        tol = ON_BOUND * np.abs(np.asarray(self.scale, dtype=float))
        theta = np.asarray(theta, dtype=float)
        on: np.ndarray = (theta - lo <= tol) | (hi - theta <= tol)
        return on

    def magnitude(self, theta: np.ndarray, stderr: np.ndarray) -> dict[str, Magnitude]:
        """Parameters in physical units, each also as a fraction of the nominal quantity it changes."""
        out = {}
        for i, (p, u) in enumerate(zip(self.params, self.units, strict=True)):
            ref = self.nominal[i] if i < len(self.nominal) else None
            if ref is not None and ref[1] != 0.0:
                out[p] = Magnitude(float(theta[i]), float(stderr[i]), u, ref[0], ref[1],
                                   float(theta[i] / ref[1]), float(stderr[i] / abs(ref[1])))
            else:
                out[p] = Magnitude(float(theta[i]), float(stderr[i]), u)
        return out


def build_catalog(nom: ActuatorModel, max_speed: float = 200.0, max_force: float = 3.0e4,
                  speed_range: tuple[float, float] = (0.0, 200.0)) -> dict[str, Effect]:
    """The eight effects of interface.md section 4 for a nominal twin.

    ``max_speed`` (motor, [rad/s]) and ``max_force`` [N] of the recording set the
    parameter scales (a 10 % change of the affected quantity at the recording's range);
    ``speed_range`` (motor, [rad/s]) the speeds over which the efficiency effect's size is taken.
    """
    f, c = nom.friction, nom.clamp  # 004 eq. 9 and eq. 5-6 of the nominal twin
    x_ag = float(c.clearance)  # one unit: a scalar [m]
    d_max = max_force / c.stiffness  # clamp deflection at the largest force [m]
    s_grid = [max_speed * f for f in (0.02, 0.08, 0.3)]
    w_lo, w_hi = speed_range
    # scales of dB and dG, and the one-sided frictions' starts (one scale inside their limit)
    s_b, s_g = 0.1 * max(f.viscous, 1e-4), 0.1 * max(f.load_coefficient, 1e-6)
    effects = [
        Effect("viscous_friction", "lubricant viscous drag larger than modelled (004 reason 1)",
               ("dB",), ("N m s/rad",), lambda p: Augment(dB=p[0]), (s_b,), ((s_b,),), limits=(0.0,),
               size=lambda p: abs(p[0]) / f.viscous, size_meaning="fraction of B",
               nominal=(("B", f.viscous),)),
        Effect("load_friction", "load-dependent friction larger than modelled (004 reasons 2, 5)",
               ("dG",), ("N m/N",), lambda p: Augment(dG=p[0]), (s_g,), ((s_g,),), limits=(0.0,),
               size=lambda p: abs(p[0]) / f.load_coefficient, size_meaning="fraction of G",
               nominal=(("G", f.load_coefficient),)),
        Effect("efficiency_variation", "ball-screw efficiency changing with speed and load (004 reason 3)",
               ("a_0", "a_w"), ("-", "s/rad"), lambda p: Augment(eff_base=p[0], eff_speed=p[1]),
               (0.1, 0.1 / max_speed), ((0.0, 0.0),),
               size=lambda p: abs(p[1]) * (w_hi - w_lo),
               size_meaning="variation of the extra friction over the recorded speeds, fraction of the load "
                            "torque",
               nominal=(None, None)),
        Effect("preload_change", "preload different from design: static and Coulomb shift (004 reason 4)",
               ("dT",), ("N m",), lambda p: Augment(dT_fs=p[0], dT_fc=p[0]), (0.1 * f.coulomb,), ((0.0,),),
               limits=(-f.coulomb,), size=lambda p: abs(p[0]) / f.coulomb, size_meaning="fraction of T_fc",
               nominal=(("T_fc", f.coulomb),)),
        Effect("stribeck", "friction falling from static to Coulomb over a speed range",
               ("T_S", "w_S"), ("N m", "rad/s"),
               lambda p: Augment(stribeck_torque=p[0], stribeck_speed=p[1]),
               (0.1 * f.coulomb, 0.1 * max_speed), tuple((0.0, s) for s in s_grid),
               (0.0, 0.2), (np.inf, 2.0 * max_speed),  # T_S >= 0: friction that *falls* with speed
               size=lambda p: abs(p[0]) * (1.0 - np.exp(-((w_hi / p[1]) ** 2))) / f.coulomb,
               size_meaning="fall of the extra friction from zero to the top recorded speed, "
                            "fraction of T_fc",
               nominal=(("T_fc", f.coulomb), None)),
        Effect("stiffness_nonlinearity", "clamp stiffness growing with force (004 eq. 5 progressive)",
               ("k_2",), ("N/m^2",), lambda p: Augment(stiffness_quad=p[0]), (0.1 * c.stiffness / d_max,),
               ((0.0,),), limits=(-0.5 * c.stiffness / d_max,), channels=("force",),
               size=lambda p: abs(2.0 * p[0] * d_max) / c.stiffness,
               size_meaning="tangent-stiffness change at the largest recorded force, fraction of K_b",
               nominal=(None,)),
        Effect("clearance_growth", "axial clearance larger than nominal (wear)", ("dx",), ("m",),
               lambda p: Augment(clearance=p[0]), (0.1 * x_ag,), ((0.0,),), limits=(0.0,),
               channels=("force",),
               size_unit="m", size_meaning="extra clearance", nominal=(("x_ag", x_ag),),
               look_alike="a play of the same size between the motor and the screw, if the angle is "
                          "measured on the motor side (the force-angle law sees only the lost motion): "
                          "check the gear and the screw coupling before the pads"),
        Effect("force_sensor_bias", "gain error of the axial-force measurement (the offset is the tare)",
               ("g",), ("-",), lambda p: Augment(force_gain=p[0]), (0.01,), ((0.0,),), (-0.5,), (1.0,),
               channels=("torque", "force"), size_meaning="gain error, fraction of the reading",
               nominal=(None,)),
    ]
    return {e.name: e for e in effects}


def friction_refit(nom: ActuatorModel) -> Effect:
    """The moving-branch parameters of 004 eq. 9 (T_fc, B, G) corrected at once, as behind 004 Table 4.

    (T_fs is not identified by the torque balance at rest, see :mod:`.residuals`.)

    Not a catalog entry (it nests viscous_friction, load_friction and preload_change and
    would explain any friction effect at the price of three parameters); the diagnosis
    reports it beside the ranking as the unit's refitted friction law, within the physical limits
    only (module docstring, "Limits": T_fc, B and G not below zero): a law may have less drag or load
    friction than the twin, which the one-sided catalog effects do not name.
    """
    f = nom.friction
    return Effect("friction_refit", "T_fc, B and G of 004 eq. 9 refitted together",
                  ("dT_fc", "dB", "dG"), ("N m", "N m s/rad", "N m/N"),
                  lambda p: Augment(dT_fc=p[0], dB=p[1], dG=p[2]),
                  (0.1 * f.coulomb, 0.1 * max(f.viscous, 1e-4), 0.1 * max(f.load_coefficient, 1e-6)),
                  ((0.0, 0.0, 0.0),), limits=(-f.coulomb, -f.viscous, -f.load_coefficient),
                  nominal=(("T_fc", f.coulomb), ("B", f.viscous), ("G", f.load_coefficient)))


def _or_open(bound: tuple[float, ...] | None, k: int, fill: float) -> tuple[float, ...]:
    """A per-parameter bound, or ``k`` open ones (``fill``: -inf below, +inf above) where there is none."""
    return bound if bound is not None else (fill,) * k


def combine(a: Effect, b: Effect) -> Effect:
    """Two effects fitted together (forward selection): parameters side by side, augments merged."""
    ka = a.k

    def to_augment(p: np.ndarray) -> Augment:
        pa, pb = a.to_augment(p[:ka]), b.to_augment(p[ka:])
        merged = {f: getattr(pb, f) if getattr(pb, f) != getattr(Augment(), f) else getattr(pa, f)
                  for f in Augment.__dataclass_fields__}
        return Augment(**merged)

    lo = _or_open(a.lower, ka, -np.inf) + _or_open(b.lower, b.k, -np.inf)
    hi = _or_open(a.upper, ka, np.inf) + _or_open(b.upper, b.k, np.inf)
    limits = _or_open(a.limits, ka, -np.inf) + _or_open(b.limits, b.k, -np.inf)
    return Effect(f"{a.name}+{b.name}", f"{a.meaning}; {b.meaning}", a.params + b.params, a.units + b.units,
                  to_augment, a.scale + b.scale, tuple((*sa, *sb) for sa in a.starts for sb in b.starts),
                  lo, hi, limits, tuple(dict.fromkeys(a.channels + b.channels)),
                  nominal=a.nominal + b.nominal)
