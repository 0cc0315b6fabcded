"""Numbers in the units people read: mm and µm, kN, hours and days, counts; status lights.

The data and JSON stay SI (m, N, s); every function here takes SI and returns text, or
:data:`NA` ("not available") for None/NaN, never a made-up number.
"""

from __future__ import annotations

import math
from typing import TypeGuard

NA = "not available"
DAY_S = 86400.0  # [s]

#: remaining-life status (interface.md section 4, plus the fleet's "failed") -> (words, CSS class)
STATUS: dict[str, tuple[str, str]] = {
    "ok": ("OK", "ok"),
    "warn": ("warning", "warn"),
    "due": ("maintenance due", "due"),
    "limit_reached": ("maintenance due", "due"),  # the status name before issue 11
    "insufficient_data": ("no measurable trend yet", "nodata"),
    "failed": ("analysis failed", "failed"),
}


def known(value: object) -> TypeGuard[float]:
    """True for a finite number (an int or a float, not a bool)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _sig(value: float, digits: int = 3) -> str:
    """``value`` with ``digits`` significant digits, thousands separated, no exponent below 1e9."""
    if value == 0:
        return "0"
    decimals = max(0, digits - 1 - math.floor(math.log10(abs(value))))
    return f"{value:,.{decimals}f}"


def mm(metres: object, digits: int = 3) -> str:
    """A length [m] in millimetres, e.g. 3.856e-4 -> '0.386 mm'."""
    return f"{metres * 1e3:.{digits}f} mm" if known(metres) else NA


def um(metres: object) -> str:
    """A length [m] in micrometres, e.g. 2.04e-5 -> '20.4 µm'."""
    return f"{_sig(metres * 1e6)} µm" if known(metres) else NA


def kn(newtons: object) -> str:
    """A force [N] in kilonewtons, e.g. 20000 -> '20.0 kN'."""
    return f"{_sig(newtons / 1e3)} kN" if known(newtons) else NA


def count(value: object) -> str:
    """A count of applications: whole numbers below a million, then '1.23 million'."""
    if not known(value):
        return NA
    if abs(value) >= 1e6:
        return f"{_sig(value / 1e6)} million"
    return f"{round(value):,}"


def duration(seconds: object) -> str:
    """A time span [s] as people say it: minutes, hours, days or years (3 significant digits)."""
    if not known(seconds):
        return NA
    for limit, size, name in ((120.0, 1.0, "s"), (2 * 3600.0, 60.0, "min"), (2 * DAY_S, 3600.0, "h"),
                              (2 * 365.25 * DAY_S, DAY_S, "days")):
        if abs(seconds) < limit:
            return f"{_sig(seconds / size)} {name}"
    return f"{_sig(seconds / (365.25 * DAY_S))} years"


def percent(fraction: object, digits: int = 0) -> str:
    """A fraction as a percentage, e.g. 0.771 -> '77 %'."""
    return f"{100 * fraction:.{digits}f} %" if known(fraction) else NA


def status(name: object) -> tuple[str, str]:
    """(words, CSS class) of a status name; unknown names are shown as they are, grey."""
    return STATUS.get(str(name), (str(name), "nodata"))
