"""A synthetic fleet for tests and demos, recorded through the digital twin's simulator.

Accelerated life: the fleet's unit file is the given one with its wear
coefficient k_slip (000 eq. 23) multiplied by ``wear_scale`` (default 2e4: the
reference unit then goes from the nominal clearance to the 0.5 mm limit in a
few hundred applications), so a recording of tens of applications covers a
measurable share of the life. It is written to ``DIR/params.yaml``; the twin
and the monitor both use it, so the monitor's wear model is right on average.

Each unit gets its own scenario drawn from one seeded generator: usage
(demanded clamp forces, hold and rest times, applications per day), wear (a
per-unit factor around 1 on the twin's wear, which the monitor's filter has to
learn; a few applications made before the recording), an unmodelled physical
effect of the catalog in some units, and input faults in some recordings
(duplicated, late and non-finite messages, a gap on one topic) of the kinds
the monitor core must survive. Every bag carries the simulator's ground truth
(``bagio.sidecar``), so the fleet report can judge the remaining-life
estimates. Layout: ``DIR/trainTT/carC/embuE/<date>.bag`` (rosbag2 directories,
mcap or sqlite3 alternately), plus ``DIR/params.yaml`` and ``DIR/scenarios.json``.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ebm_wear_monitor.bagio import Series, write_unit_bag
from ebm_wear_monitor.outputs import write_json
from ebm_wear_monitor.params import UnitParams, accelerated, save_unit

#: default factor on the wear coefficient k_slip of a synthetic fleet's unit file [-]
WEAR_SCALE = 2e4
#: first recording day, 2026-11-20 06:00 UTC [s since the epoch]
EPOCH_S = 1_795_154_400.0
DAY_S = 86_400.0
NAMESPACE = "/embu"
#: effects of the twin's catalog given to some units, with a typical magnitude each
EFFECTS = {"viscous_friction": 0.5, "load_friction": 0.5, "clearance_growth": 50e-6,
           "force_sensor_bias": 200.0}
#: input faults injected into some recordings: kind -> share of samples (gap: seconds dropped once)
FAULTS = {"duplicate": 0.01, "late": 0.005, "non_finite": 0.002, "gap_s": 0.3}


@dataclass(frozen=True)
class UnitScenario:
    """One synthetic unit: where it lives in the fleet tree and how it is used, worn and recorded."""

    unit: str                        # folder relative to the fleet root
    seed: int
    bags: int                        # recordings (days)
    cycles_per_bag: int              # brake applications per recording
    demands_n: tuple[float, ...]     # demanded clamp forces, cycled [N]
    hold_s: float                    # force-maintenance time [s]
    rest_s: float                    # idle time after each release [s]
    wear_acceleration: float         # this unit's factor on the twin's wear increments [-]
    prior_cycles: int                # applications before the first recording [-]
    rate_hz: float                   # sample rate [Hz]
    storage: str                     # "mcap" or "sqlite3"
    effects: dict[str, float] = field(default_factory=dict)
    faults: bool = False             # inject FAULTS into the recordings


def scenarios(n_units: int, seed: int = 0, *, cycles_per_bag: int = 12, bags_per_unit: int = 2,
              rate_hz: float = 200.0) -> list[UnitScenario]:
    """``n_units`` varied scenarios (8 units per train, 2 per car), reproducible from ``seed``."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n_units):
        k = int(rng.integers(1, 4))
        effect = {} if rng.random() < 0.6 else dict([list(EFFECTS.items())[int(rng.integers(len(EFFECTS)))]])
        out.append(UnitScenario(
            unit=f"train{i // 8:02d}/car{(i // 2) % 4}/embu{i % 2}", seed=int(rng.integers(2**31)),
            bags=bags_per_unit, cycles_per_bag=max(2, round(cycles_per_bag * rng.uniform(0.7, 1.3))),
            demands_n=tuple(float(d) for d in rng.choice([6e3, 10e3, 15e3, 20e3], size=k, replace=False)),
            hold_s=float(rng.uniform(0.3, 1.0)), rest_s=float(rng.uniform(0.2, 0.6)),
            wear_acceleration=float(np.exp(rng.uniform(-0.5, 0.5))),
            prior_cycles=int(rng.integers(0, 40)), rate_hz=rate_hz,
            storage=("mcap", "sqlite3")[i % 2], effects=effect, faults=bool(rng.random() < 0.4)))
    return out


def inject_faults(t: np.ndarray, signals: dict[str, np.ndarray], rng: np.random.Generator
                  ) -> dict[str, Series]:
    """Input faults of FAULTS on a recording: duplicates, late arrivals, non-finite values, a gap."""
    out = {}
    n = len(t)
    gap_topic = "velocity"
    gap_start = int(rng.integers(n // 4, max(n // 4 + 1, 3 * n // 4)))
    for name, values in signals.items():
        values = values.copy()
        values[rng.random(n) < FAULTS["non_finite"]] = np.nan
        received = t + np.where(rng.random(n) < FAULTS["late"], 0.05, 0.0)
        keep = np.ones(n, bool)
        if name == gap_topic:
            keep[gap_start:gap_start + int(FAULTS["gap_s"] * 1 / max(t[1] - t[0], 1e-9))] = False
        dup = np.flatnonzero(keep & (rng.random(n) < FAULTS["duplicate"]))
        index = np.concatenate([np.flatnonzero(keep), dup])
        rx = np.concatenate([received[keep], received[dup] + 1e-4])
        out[name] = Series(t[index], values[index], rx)
    return out


def write_unit(root: str | os.PathLike, scenario: UnitScenario, params: UnitParams) -> list[Path]:
    """Simulate one unit's recordings with the twin and write them as bags; returns the bag paths."""
    from ebm_wear_monitor.twin import simulate_unit

    total = scenario.bags * scenario.cycles_per_bag
    sim = simulate_unit(params, total, demands=list(scenario.demands_n), effects=scenario.effects,
                        seed=scenario.seed, rate_hz=scenario.rate_hz,
                        wear_acceleration=scenario.wear_acceleration, hold_s=scenario.hold_s,
                        rest_s=scenario.rest_s, prior_cycles=scenario.prior_cycles)
    truth = sim.ground_truth()
    rng = np.random.default_rng(scenario.seed)
    paths = []
    for day in range(scenario.bags):
        lo, hi = day * scenario.cycles_per_bag, (day + 1) * scenario.cycles_per_bag
        mask = (sim.cycle >= lo) & (sim.cycle < hi)
        t = sim.t[mask] - sim.t[mask][0] + EPOCH_S + day * DAY_S
        signals = {k: v[mask] for k, v in sim.signals().items()}
        data = inject_faults(t, signals, rng) if scenario.faults else signals
        day_truth = {**truth, "cycles_at_start": scenario.prior_cycles + lo,
                     "clearance_m": truth["clearance_m"][lo:hi],
                     "cycle_start_s": truth["cycle_start_s"][lo:hi]}
        path = Path(root) / scenario.unit / f"2026-11-{20 + day:02d}.bag"
        write_unit_bag(path, t if not scenario.faults else None, {NAMESPACE: data}, storage=scenario.storage,
                       ground_truth={"units": {NAMESPACE: day_truth}})
        paths.append(path)
    return paths


def generate_fleet(root: str | os.PathLike, units: list[UnitScenario], params: UnitParams, *,
                   client=None, wear_scale: float = WEAR_SCALE,
                   on_unit: Callable[[], object] | None = None) -> tuple[UnitParams, list[Path]]:
    """Write every unit's bags under ``root`` (in parallel on a Dask ``client`` if given),
    ``root/params.yaml`` (``params`` accelerated by ``wear_scale``) and ``root/scenarios.json``.

    Returns the accelerated unit parameters (to process the fleet with) and all bag paths.
    ``on_unit()`` is called as each unit's bags are written (progress bars).
    """
    root = Path(root)
    params = accelerated(params, wear_scale)
    root.mkdir(parents=True, exist_ok=True)
    save_unit(root / "params.yaml", params, f"synthetic fleet: {params.name}")
    done = on_unit or (lambda: None)
    if client is None:
        paths = []
        for s in units:
            paths.append(write_unit(root, s, params))
            done()
    else:
        from dask.distributed import as_completed

        futures = client.map(write_unit, [str(root)] * len(units), units, params=params, pure=False)
        for _ in as_completed(futures):
            done()
        paths = client.gather(futures)
    write_json(root / "scenarios.json", [dataclasses.asdict(s) for s in units])
    return params, [p for unit_paths in paths for p in unit_paths]
