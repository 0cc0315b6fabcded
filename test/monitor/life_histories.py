"""Life histories that are not the wear model, at the observation level (issue 11 item 2).

Used by test/monitor/test_monitor_life_validation.py (targets) and bench/bench_life.py (metrics
against the naive baseline).

**The noise the monitor actually measures** (:func:`calibrate`). A few real twin recordings
(``twin.simulate_unit``, the reference EMBU at 1 kHz, 250 Hz and 100 Hz, four demand levels, with
wear) are written to rosbag2 by the bag writer, read back and replayed through the monitor core
(``replay.replay_bags``). Per application this gives the observation error (observed minus the
twin's true clearance) and the error budget sigma the core reported with it; the pairs of a rate
form its :class:`NoisePool`. The wear model's clearance growth per application at that usage comes
from the same replay (``clearance_model_m``).

**Histories** (:func:`histories`): the true clearance of every application follows a schedule
written here, never the wear model: linear growth 0.1-2 um per application (20 units, log-spaced
rates, random start), accelerating growth (exponential with e-folding over 2-4 lives, and a rate
climbing linearly), a step then flat, steady slow growth whose true remaining life at the end of
the record is beyond 10,000 applications, and flat units of different usage (sample rate, hence
noise; applications per hour). Growing units are recorded to their end of life, the others over
2,000 applications.

**Observations** (:func:`observe`): application k of a unit recorded at rate f reads
``truth_k + e`` with (e, sigma) drawn at random, with replacement, from the pool of rate f, and
hands sigma^2 to the filter as the budget: the errors are the twin's, their pairing with the
budget is the core's.

**Tracking** (:func:`track`): the monitor's own code path after an application (tracker.py
``ClearanceTracker.step``, life.py ``wear_life``), as ``MonitorCore`` runs it, with the pool's model
growth; :func:`baseline` is the naive least-squares line of replay/prognostics.py.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ebm_wear_monitor.monitor import MonitorConfig
from ebm_wear_monitor.monitor.life import wear_life
from ebm_wear_monitor.monitor.tracker import ClearanceTracker
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.replay.prognostics import line_forecast

LIMIT = 0.5e-3  # clearance limit of the reference EMBU [m]
NOMINAL = 0.2e-3  # its nominal clearance [m]
RATES_HZ = (1000.0, 250.0, 100.0)  # recording rates of the calibration and of the histories [Hz]
FLAT_APPLICATIONS = 2000  # record length of units that never reach the limit [-]
RESOLVED_SIGMAS = 3.0  # growth is resolvable once it has accumulated this many observation sigmas


@dataclass(frozen=True)
class NoisePool:
    """Observation errors and their budgets at one recording rate, from twin recordings."""

    rate_hz: float
    error_m: np.ndarray  # observed - true clearance, per application [m]
    budget_std_m: np.ndarray  # the error budget the core reported with it [m]
    model_growth_m: float  # the wear model's clearance growth per application at this usage [m]

    @property
    def sigma_m(self) -> float:
        """Measured standard deviation of the observation error [m]."""
        return float(np.std(self.error_m, ddof=1))


def calibrate(workdir: Path, applications: int = 36, seed: int = 20) -> dict[float, NoisePool]:
    """Twin recordings -> bag writer -> replay through the core: one noise pool per rate."""
    from ebm_wear_monitor.bagio.writer import write_unit_bag
    from ebm_wear_monitor.replay.run import replay_bags
    from ebm_wear_monitor.twin import simulate_unit

    unit = load_unit()
    pools = {}
    for i, rate in enumerate(RATES_HZ):
        sim = simulate_unit(unit, applications, demands=(8e3, 12e3, 16e3, 20e3), seed=seed + i, rate_hz=rate,
                            hold_s=0.3, rest_s=0.3)
        bag = Path(workdir) / f"calibration_{rate:.0f}hz"
        signals = {k: v for k, v in sim.signals().items() if k != "current"}
        write_unit_bag(bag, sim.t, {"/embu": signals}, storage="sqlite3")
        apps = replay_bags([bag], unit).units[0].applications
        seen = np.isfinite(apps["clearance_observed_m"].to_numpy())
        truth = np.asarray(sim.truth["clearance_m"])[apps["index"].to_numpy() - 1]
        model = apps["clearance_model_m"].to_numpy()
        pools[rate] = NoisePool(rate, (apps["clearance_observed_m"].to_numpy() - truth)[seen],
                                apps["clearance_observed_std_m"].to_numpy()[seen],
                                float((model[-1] - NOMINAL) / len(model)))
    return pools


@dataclass(frozen=True)
class History:
    """One unit's true clearance per application and how it is recorded."""

    name: str
    kind: str  # linear | exponential | climbing | slow | step | flat
    truth_m: np.ndarray  # true clearance of applications 1..n [m]
    eol: float  # application count (fractional) at which the truth reaches the limit; inf: never
    rate_hz: float  # recording rate: selects the noise pool
    applications_per_hour: float  # usage [1/h]

    @property
    def grows(self) -> bool:
        return math.isfinite(self.eol)


def _to_limit(x0: float, rate_at, eol: float) -> np.ndarray:
    """Truth of applications 1..floor(eol) (the last below the limit) of a schedule x0 + rate_at(k)."""
    k = np.arange(1, math.floor(eol) + 1, dtype=float)
    return x0 + rate_at(k)


def histories(seed: int = 11) -> list[History]:
    """The validation set (module docstring): 20 linear, 5 accelerating, 3 slow, 4 step, 6 flat units."""
    rng = np.random.default_rng(seed)
    out = []

    def usage() -> tuple[float, float]:
        return float(rng.choice(RATES_HZ)), float(rng.uniform(20.0, 400.0))

    for i, r in enumerate(np.geomspace(0.1e-6, 2e-6, 20)):
        x0 = rng.uniform(0.18e-3, 0.26e-3)
        eol = (LIMIT - x0) / r
        truth = _to_limit(x0, lambda k, r=r: r * k, eol)
        out.append(History(f"linear_{i:02d}_{r * 1e6:.2f}um", "linear", truth, eol, *usage()))
    for i, (lives, n) in enumerate(((2.0, 300), (3.0, 400), (4.0, 250), (3.0, 1200))):
        lam = lives / n  # the growth rate e-folds `lives` times over the life of n applications
        x0 = NOMINAL
        a = (LIMIT - x0) / math.expm1(lives)
        truth = _to_limit(x0, lambda k, a=a, lam=lam: a * np.expm1(lam * k), n)
        out.append(History(f"exponential_{i}_{lives:.0f}x{n}", "exponential", truth, float(n), *usage()))
    r0, n = 0.1e-6, 800  # a rate climbing linearly from 0.1 um: x0 + r0 k + c k^2 / 2 reaches the limit at n
    c = 2.0 * (LIMIT - NOMINAL - r0 * n) / n ** 2
    out.append(History("climbing_rate", "climbing", _to_limit(NOMINAL, lambda k: r0 * k + 0.5 * c * k * k, n),
                       float(n), *usage()))
    for i, (r, x0) in enumerate(((0.02e-6, 0.2e-3), (0.012e-6, 0.3e-3), (0.018e-6, 0.24e-3))):
        k = np.arange(1, FLAT_APPLICATIONS + 1, dtype=float)
        out.append(History(f"slow_{i}_{r * 1e9:.0f}nm", "slow", x0 + r * k, (LIMIT - x0) / r, *usage()))
    for i, (step, at) in enumerate(((30e-6, 150), (-40e-6, 600), (8e-6, 1000), (3e-6, 400))):
        k = np.arange(1, FLAT_APPLICATIONS + 1)
        truth = 0.25e-3 + step * (k >= at)
        out.append(History(f"step_{i}_{step * 1e6:+.0f}um", "step", truth, math.inf, *usage()))
    for i, (x0, rate, per_hour) in enumerate(((0.20e-3, 1000.0, 400.0), (0.26e-3, 250.0, 60.0),
                                              (0.31e-3, 100.0, 20.0), (0.40e-3, 1000.0, 200.0),
                                              (0.45e-3, 100.0, 30.0), (0.22e-3, 250.0, 150.0))):
        out.append(History(f"flat_{i}_{x0 * 1e3:.2f}mm_{rate:.0f}hz", "flat", np.full(FLAT_APPLICATIONS, x0),
                           math.inf, rate, per_hour))
    return out


def observe(history: History, pools: dict[float, NoisePool], seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(observed clearance [m], budget variance [m^2]) per application (module docstring)."""
    pool = pools[history.rate_hz]
    pick = np.random.default_rng(seed).integers(0, pool.error_m.size, history.truth_m.size)
    return history.truth_m + pool.error_m[pick], pool.budget_std_m[pick] ** 2


@dataclass
class Forecast:
    """Remaining-life predictions after each application (NaN: none, or unbounded for p05/p95)."""

    k: np.ndarray  # application count [-]
    p05: np.ndarray
    p50: np.ndarray
    p95: np.ndarray
    clearance_m: np.ndarray = field(default_factory=lambda: np.empty(0))  # estimate after each [m]
    steps: int = 0
    changes: int = 0

    def finite(self) -> np.ndarray:
        """Applications with all three quantiles finite."""
        return np.isfinite(self.p05) & np.isfinite(self.p50) & np.isfinite(self.p95)


def _nan(v: float | None) -> float:
    return math.nan if v is None else float(v)


def checkpoints(history: History, sigma_m: float, every: int) -> set[int]:
    """Applications at which the remaining life is evaluated: every ``every``-th, each of the 40 after
    growth becomes resolvable, at 50 % and 80 % of the record and the last one."""
    n, res = history.truth_m.size, resolvable_at(history, sigma_m)
    return (set(range(every, n + 1, every)) | set(range(res, min(res + 40, n) + 1))
            | {int(0.5 * n), int(0.8 * n), n})


def track(history: History, z: np.ndarray, var: np.ndarray, model_growth_m: float, *,
          config: MonitorConfig | None = None, at: set[int] | None = None) -> Forecast:
    """The monitor's filter and remaining life over one history; life evaluated after the applications
    ``at`` (1-based; default: every one)."""
    cfg = config or MonitorConfig()
    tracker = ClearanceTracker.start(cfg, NOMINAL, cfg.initial_clearance_std_m ** 2, LIMIT)
    n = z.size
    out = Forecast(np.arange(1, n + 1, dtype=float), *(np.full(n, np.nan) for _ in range(4)))
    for i in range(n):
        result = tracker.step(model_growth_m, z[i], var[i])
        out.steps += result.steps
        out.changes += result.changes
        out.clearance_m[i] = tracker.live.clearance()[0]
        k = i + 1
        if at is None or k in at:
            life = wear_life(tracker.hyp, tracker.live, LIMIT, model_growth_m, observations=k,
                             min_observations=cfg.min_cycles_for_life, z=cfg.life_confidence_z,
                             warn_cycles=1e4, due_cycles=1e3)
            out.p05[i], out.p50[i], out.p95[i] = (_nan(v) for v in (life.cycles_p05, life.cycles_p50,
                                                                    life.cycles_p95))
    return out


def baseline(z: np.ndarray) -> Forecast:
    """The naive least-squares line (replay/prognostics.py) after each application."""
    k = np.arange(1, z.size + 1, dtype=float)
    q = line_forecast(k, z, LIMIT)
    return Forecast(k, q[:, 0], q[:, 1], q[:, 2])


def resolvable_at(history: History, sigma_m: float) -> int:
    """First application whose true growth since the first exceeds RESOLVED_SIGMAS sigma of the noise."""
    grown = np.abs(history.truth_m - history.truth_m[0]) > RESOLVED_SIGMAS * sigma_m
    return int(np.argmax(grown)) + 1 if grown.any() else history.truth_m.size + 1
