"""Model-tolerance budget: how far a healthy unit may differ from its unit file, and the floors it sets.

The nominal twin is built from the unit file (004 Table 1 and the calculated friction
of 004 Table 3).  Even a unit with no unmodelled effect differs from it within the
bounds below; the diagnosis must not call such a difference an effect.

====================================  =========  =========================================================
quantity                              bound      reason
====================================  =========  =========================================================
K_T times the current-sensor gain     +-2 %      NdFeB torque constant -0.12 %/K over +-10 K (1.2 %) and a
                                                 1 % current-sensor gain, added in quadrature (1.6 %)
equivalent inertia J_me (004 eq. 2)   +-2 %      rotor and gear inertia of a datasheet, grease in the gear
friction direction asymmetry          004 T. 3   the twin uses the apply-direction law both ways; 004 Table 3
                                                 computes T_fc 7.43 % and G 2.93 % lower in reverse
viscous coefficient B                 +-10 %     lubricant viscosity falls ~2.5 %/K; the twin runs at its
                                                 reference temperature, a unit within +-4 K of it (beyond
                                                 that the temperature must be given to the twin)
clamp stiffness K_b (004 eq. 6)       +-3 %      pad modulus with temperature and pad wear
brake clearance x_ag                  +-r_x      thermal expansion of ~0.1 m of caliper steel over +-4 K
                                                 (12e-6 /K), 4.8 um, taken as 5 um, and where the
                                                 ECU parks, measured: r_x = hypot(5 um, h), below
load-cell gain                        +-1 %      a class-0.5 load cell with its amplifier
====================================  =========  =========================================================

**The twin within its tolerance.**  Every model the diagnosis fits, the nominal one
included, may move each of these quantities within its bound (bounded least squares,
:mod:`.ranking`); an effect is fitted *on top of* that, so a deviation a healthy unit
may have is never charged to an effect, however precisely the data show it (the
inertia alone, +-2 %, is worth 0.16 N m while the motor accelerates: left out of
the budget it would read as the viscous coefficient's size).  An effect's own
quantity is not also a tolerance when that effect is fitted (``OWN``).  Each
tolerance's change of the normalised residual is linear in the deviation, so it
enters the fits as a fixed response column (:func:`responses`), not a re-evaluation.

**Detectability floors** (issue 10, practical significance).  An effect is *material*
only when its fitted size (:mod:`.catalog`, in the unit people judge it by) exceeds
the deviation the budget allows in that same quantity (the entries it is made of are held at zero
while the effect is fitted, ``OWN``, so they are not counted twice):

==========================  ========================  ==============================================
effect                      floor                     from the budget
==========================  ========================  ==============================================
viscous_friction            10 % of B                 B +-10 %
load_friction               3 % of G                  direction asymmetry of G, 2.93 %
efficiency_variation        2 % of the load torque    K_T x current gain +-2 % acts on T_L alike
                            over the speed range
preload_change              4 % of T_fc               direction asymmetry of T_fc, 7.43 %, averaged
                                                      over both directions
stribeck                    5 % of T_fc, its fall     half the twin's own static excess
                                                      (T_fs - T_fc = 10.7 % of T_fc)
stiffness_nonlinearity      3 % of K_b                K_b +-3 %
clearance_growth            r_x = hypot(5 um, h)      x_ag +-r_x
force_sensor_bias           3 % gain                  load-cell gain +-1 %, plus K_T x current gain
                                                      +-2 %: in the force channel a gain is K_b's
                                                      signature (+-3 %), in the torque channel K_T's
==========================  ========================  ==============================================

**Where the ECU parks, per recording.** The clearance counts from where the ECU parks the nut, and a
healthy unit's ECU parks within a tolerance of its own, off its target by any amount inside it:
position-loop error, a loop that stops inside its tolerance on one side of its target. The recording
shows the band its parks cover; its half-width h (:mod:`.conventions`, the interquartile range of the
rest angles, in nut travel) estimates how far their mean lies from the band's end, where the target may
be (low for few applications: :mod:`.conventions`). It is added to the thermal entry in quadrature
(independent sources, like the K_T entry): r_x = hypot(5 um, h), both the tolerance the fits may use and
the clearance growth's floor. An ECU that parks in the same place every time gives 5 um (the twin's).
The fixed +-5 um this replaced bounded the thermal part only, and a third-world ECU whose parks wander
over some 7 um read as a clearance growth of 7.3 +- 1.1 um. The price: the wider an ECU's band, the
larger a clearance growth must be to be named (a growth of 5-7 um beside a 5 um band).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ebm_wear_monitor.diagnosis.residuals import Augment
from ebm_wear_monitor.twin.dynamics import ActuatorModel


@dataclass(frozen=True)
class Tolerance:
    """One entry of the budget: a healthy unit's deviation at the bound, and why."""

    name: str
    #: the model change at the bound, of the nominal twin and the ECU's park half-band [m]
    deviation: Callable[[ActuatorModel, float], Augment]
    reason: str


THERMAL_CLEARANCE = 5e-6  # ~0.1 m of caliper steel, 12e-6 /K, +-4 K: 4.8 um, the budget's 5 um [m]


def clearance_bound(park_half_band: float) -> float:
    """r_x = hypot(thermal, h) [m] of the ECU's park half-band h = ``park_half_band`` [m] (module
    docstring)."""
    return math.hypot(THERMAL_CLEARANCE, park_half_band)


BUDGET: tuple[Tolerance, ...] = (
    Tolerance("torque_constant", lambda n, h: Augment(drive_gain=0.02),
              "K_T x current-sensor gain +-2 %: -0.12 %/K over +-10 K and a 1 % current-sensor gain"),
    Tolerance("inertia", lambda n, h: Augment(inertia_gain=0.02),
              "J_me +-2 %: datasheet rotor and gear inertia"),
    Tolerance("direction_asymmetry",
              lambda n, h: Augment(reverse_dT_fc=-0.0743 * n.friction.coulomb,
                                reverse_dG=-0.0293 * n.friction.load_coefficient),
              "004 Table 3: T_fc 7.43 % and G 2.93 % lower in reverse"),
    Tolerance("viscous", lambda n, h: Augment(dB=0.10 * n.friction.viscous),
              "B +-10 %: +-4 K of lubricant temperature"),
    Tolerance("stiffness", lambda n, h: Augment(stiffness_gain=0.03), "K_b +-3 %: pad modulus"),
    Tolerance("clearance", lambda n, h: Augment(clearance=clearance_bound(h)),
              "x_ag +-r_x: thermal 5 um, where the ECU parks measured"),
    Tolerance("load_cell", lambda n, h: Augment(force_gain=0.01), "load-cell gain +-1 %: class 0.5"),
)

#: effect -> the budget entries its floor is made of (module docstring's second table): held at zero while
#: that effect is fitted, since the floor already accounts for them; the friction refit of 004 Table 4
#: (:func:`.catalog.friction_refit`) owns every friction entry
OWN = {"viscous_friction": ("viscous",), "load_friction": ("direction_asymmetry",),
       "efficiency_variation": ("torque_constant",), "preload_change": ("direction_asymmetry",),
       "stiffness_nonlinearity": ("stiffness",), "clearance_growth": ("clearance",),
       "force_sensor_bias": ("load_cell", "torque_constant"),
       "friction_refit": ("viscous", "direction_asymmetry")}

#: a channel's model error is material above this share of what it predicts: the budget's bound on the
#: channel's scale (torque: K_T x current gain, 2 %; force: the load-cell gain, 1 %)
MATERIAL_SHARE = {"torque": 0.02, "force": 0.01}


def torque_floor(drive: np.ndarray) -> float:
    """Materiality bound of a torque the model misses [N m]: ``MATERIAL_SHARE['torque']`` of the RMS of
    ``drive``, the block-mean motor torque over the moving blocks [N m] (an RMS against an RMS)."""
    return MATERIAL_SHARE["torque"] * float(np.sqrt(np.mean(drive**2)))

#: effect -> detectability floor of its size (module docstring; units as :mod:`.catalog`'s sizes); the
#: clearance growth's depends on the recording (:func:`floor`)
FLOORS = {"viscous_friction": 0.10, "load_friction": 0.03, "efficiency_variation": 0.02,
          "preload_change": 0.04, "stribeck": 0.05, "stiffness_nonlinearity": 0.03,
          "force_sensor_bias": 0.03}


def floor(effect_name: str, park_half_band: float) -> float:
    """Detectability floor of an effect's size (:data:`FLOORS`; the clearance growth's is r_x of the
    ECU's park half-band [m], :func:`clearance_bound`)."""
    if effect_name == "clearance_growth":
        return clearance_bound(park_half_band)
    return FLOORS.get(effect_name, 0.0)


def apply(base: Augment, deviation: Augment) -> Augment:
    """``base`` (a fitted model) with the non-zero fields of ``deviation`` added."""
    zero = Augment()
    return dataclasses.replace(base, **{f: getattr(base, f) + getattr(deviation, f)
                                        for f in Augment.__dataclass_fields__
                                        if getattr(deviation, f) != getattr(zero, f)})


def at_bounds(aug: Augment, nominal: ActuatorModel, park_half_band: float) -> list[Augment]:
    """``aug`` with each entry of the budget at its bound, in the order of ``BUDGET`` (the residuals are
    linear in the deviations, so a residual's change at the bound is its response to the entry);
    ``park_half_band`` the recording's (:mod:`.conventions`) in nut travel [m]."""
    return [apply(aug, t.deviation(nominal, park_half_band)) for t in BUDGET]


def free(effect_names: list[str]) -> list[bool]:
    """Which budget entries are tolerances while the named effects are fitted."""
    own = {name for e in effect_names for name in OWN.get(e, ())}
    return [t.name not in own for t in BUDGET]
