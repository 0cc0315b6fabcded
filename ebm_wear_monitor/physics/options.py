"""Readings of the ambiguous parts of paper 000 that the model lets the caller choose.

Every option is documented where it is used; README.md ("Reading the papers critically",
paper 000) compares their per-cycle wear side by side. Defaults are the readings the reference
parameters are calibrated with.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.physics.kinematics import GYROSCOPIC_ANGLE, KINEMATICS
from ebm_wear_monitor.physics.plasticity import KAPPA_READINGS, RADIUS_READINGS


@dataclass(frozen=True)
class ModelOptions:
    """Reading options of 000 (see :mod:`kinematics`, :mod:`plasticity`, :mod:`equilibrium`)."""

    kinematics: str = "literal"  # eq. 10-11, 19: "literal" (as printed) or "rolling" (signs repaired)
    radius: str = "hertz"  # R in eq. 6-7: "hertz" (2/sum_rho), "asperity" (asperity radius), "roughness"
    kappa: str = "b/a"  # kappa in Horng's f1..f3 of eq. 7: "b/a" (Horng) or "a/b" (000 eq. 4)
    gyroscopic_angle_deg: float = math.degrees(GYROSCOPIC_ANGLE)  # beta_b, 000 Sec. 3.2
    rel_tol: float = 1e-10  # Fig. 6 stop: max change of deformations (relative) and angles (rad)
    max_iter: int = 60

    def __post_init__(self) -> None:
        readings = (("kinematics", KINEMATICS), ("radius", RADIUS_READINGS), ("kappa", KAPPA_READINGS))
        for name, allowed in readings:
            if getattr(self, name) not in allowed:
                raise InputError(f"physics option {name} must be one of {', '.join(allowed)}, "
                                 f"got {getattr(self, name)!r}")
        if not 0.0 < self.gyroscopic_angle_deg < 90.0:
            raise InputError(f"gyroscopic_angle_deg must be in (0, 90), got {self.gyroscopic_angle_deg}")

    @property
    def beta(self) -> float:
        return math.radians(self.gyroscopic_angle_deg)

    def key(self) -> tuple[tuple[str, object], ...]:
        return tuple(sorted(asdict(self).items()))


def make_options(**reading_options: object) -> ModelOptions:
    """ModelOptions from keyword arguments, unknown names rejected with one line."""
    known = set(ModelOptions.__dataclass_fields__)
    unknown = sorted(set(reading_options) - known)
    if unknown:
        raise InputError(f"unknown physics option(s) {', '.join(unknown)} "
                         f"(known: {', '.join(sorted(known))})")
    return ModelOptions(**reading_options)  # type: ignore[arg-type]
