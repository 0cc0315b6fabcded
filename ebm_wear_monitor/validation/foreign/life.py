"""Clearance schedules of the life histories: the true clearance set per application, no wear model.

A schedule is a JSON-able tuple ``(form, x0, ...)`` giving the clearance ``x(n)`` [m] in force
during application ``n`` (0-based, counted from the first application of the recording):

* ``("linear", x0, r)``:            ``x(n) = x0 + r n``                      (r [m/application])
* ``("exponential", x0, r0, k)``:   ``x(n) = x0 + r0 (exp(k n) - 1) / k``    (rate ``r0 exp(k n)``)
* ``("step", x0, h, n_s)``:         ``x(n) = x0 + h [n >= n_s]``             (a step, then flat)
* ``("flat", x0)``:                 ``x(n) = x0``

The end of life is the (fractional) application index at which ``x`` reaches the limit ``L``,
solved from the schedule itself and extrapolated beyond the recording if needed: linear
``(L - x0) / r``; exponential ``ln(1 + k (L - x0) / r0) / k``; step ``n_s`` if ``x0 + h >= L``;
``0`` if ``x0 >= L``; ``None`` when the schedule never reaches ``L``. The true remaining life at
application ``n`` is ``eol - n``.
"""

from __future__ import annotations

import math

import numpy as np

FORMS = ("linear", "exponential", "step", "flat")


def clearance(spec: tuple, n: int) -> np.ndarray:
    """``x(k)`` for ``k = 0 .. n-1`` [m]."""
    form, x0, *p = spec
    k = np.arange(n, dtype=float)
    if form == "linear":
        return x0 + p[0] * k
    if form == "exponential":
        return x0 + p[0] * np.expm1(p[1] * k) / p[1]
    if form == "step":
        return x0 + p[0] * (k >= p[1])
    if form == "flat":
        return np.full(n, float(x0))
    raise ValueError(f"unknown clearance schedule {form!r}; known: {', '.join(FORMS)}")


def end_of_life(spec: tuple, limit: float) -> float | None:
    """Application index at which the schedule reaches ``limit`` (see the module docstring)."""
    form, x0, *p = spec
    if x0 >= limit:
        return 0.0
    if form == "linear":
        return (limit - x0) / p[0] if p[0] > 0 else None
    if form == "exponential":
        return math.log1p(p[1] * (limit - x0) / p[0]) / p[1]
    if form == "step":
        return float(p[1]) if x0 + p[0] >= limit else None
    return None
