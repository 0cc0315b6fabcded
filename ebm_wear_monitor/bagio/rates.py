"""Sample rates of recorded input topics against the contract's minimum (interface.md section 2).

Bags may hold 100 Hz to 2 kHz per topic. Below 100 Hz the clearance observation (a regression of
angle on force over the first force rise, which lasts tens of milliseconds) has too few samples and
its error budget no longer holds: a 10 Hz recording of the worn sample unit gave 13 of 16
applications and a clearance of 0.282 mm against 0.386 mm, with no fault counted. Such a
recording is refused with one line naming the topic and its rate, never analysed silently.

The rate of a topic is 1 / median of its positive stamp steps: robust to jitter, gaps,
duplicates and a bag played in a loop (one backward jump).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from ebm_wear_monitor.domain.recording import Recording
from ebm_wear_monitor.domain.signals import INPUT_TOPICS
from ebm_wear_monitor.errors import InputError

#: lowest sample rate of the contract [Hz] (interface.md section 2: "bags may hold 100 Hz to 2 kHz")
MIN_RATE_HZ = 100.0
#: tolerated shortfall [-]: stamps of a 100 Hz source with clock jitter may give a median step a
#: little above 10 ms; 1 % is far above any clock error and far below a real lower rate
RATE_TOLERANCE = 0.01


def sample_rate_hz(stamps: np.ndarray) -> float | None:
    """1 / median positive step of ``stamps`` [s] -> [Hz]; None with fewer than two distinct stamps."""
    steps = np.diff(np.asarray(stamps, dtype=np.float64))
    steps = steps[np.isfinite(steps) & (steps > 0.0)]
    return float(1.0 / np.median(steps)) if steps.size else None


def check_rates(data: Recording, signals: Iterable[str]) -> dict[str, float]:
    """Rates [Hz] of ``signals`` of one unit; InputError (one line) if one is below :data:`MIN_RATE_HZ`.

    Signals with fewer than two samples are left to the caller (no rate to judge).
    """
    rates = {}
    for name in signals:
        sig = data.signals.get(name)
        rate = None if sig is None else sample_rate_hz(sig.stamps)
        if rate is None:
            continue
        if rate < MIN_RATE_HZ * (1.0 - RATE_TOLERANCE):
            raise InputError(f"{data.unit}: {INPUT_TOPICS[name]} is sampled at {rate:.3g} Hz, below the "
                             f"{MIN_RATE_HZ:g} Hz minimum of interface.md section 2")
        rates[name] = rate
    return rates
