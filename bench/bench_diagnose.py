"""Benchmark: sim-to-real diagnosis of a 20-cycle 1 kHz bag against the full catalog, on one core.

Prints wall times and ratios against a baseline measured in the same run: one
current-driven simulation of the twin over the same recording (the cost a
simulation-based diagnosis would pay per candidate parameter set; this one
needs none, it evaluates the twin's torque balance instead).  Target: the
whole diagnosis under 60 s.

    .venv/bin/python bench/bench_diagnose.py
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

from ebm_wear_monitor.bagio import read_bags, write_unit_bag  # noqa: E402
from ebm_wear_monitor.diagnosis import recording_from_signals  # noqa: E402
from ebm_wear_monitor.diagnosis import residuals as residuals_module  # noqa: E402
from ebm_wear_monitor.diagnosis.pipeline import diagnose_recording  # noqa: E402
from ebm_wear_monitor.params import load_unit  # noqa: E402
from ebm_wear_monitor.twin import simulate_current_driven, simulate_unit  # noqa: E402


def main() -> None:
    unit = load_unit()
    sim = simulate_unit(unit, 20, demands=(8e3, 14e3, 20e3, 26e3), effects={"load_friction": 0.5}, seed=1,
                        rate_hz=4000.0, wear=False, hold_s=(0.5, 1.0), rest_s=0.5)
    s = slice(None, None, 4)  # 1 kHz recording of a 4 kHz plant
    sig = {"angle": sim.angle[s], "velocity": sim.velocity[s], "axial_force": sim.axial_force[s],
           "current": sim.current[s]}
    with tempfile.TemporaryDirectory() as tmp:
        bag = Path(tmp) / "bag"
        write_unit_bag(bag, sim.t[s], {"/embu": sig})
        t0 = time.perf_counter()
        data = read_bags([bag])
        ud = data.units["/embu"]
        rec = recording_from_signals({k: (v.stamps, v.values) for k, v in ud.signals.items()})
        t_read = time.perf_counter() - t0

    # time spent evaluating the twin (its torque balance and force law) inside the diagnosis
    spent = {"twin": 0.0, "calls": 0}
    original = residuals_module.ResidualModel.residuals

    def timed(self, aug=residuals_module.NOMINAL):
        a = time.perf_counter()
        out = original(self, aug)
        spent["twin"] += time.perf_counter() - a
        spent["calls"] += 1
        return out

    residuals_module.ResidualModel.residuals = timed
    t0 = time.perf_counter()
    res = diagnose_recording(rec, unit)
    t_diag = time.perf_counter() - t0
    residuals_module.ResidualModel.residuals = original

    t0 = time.perf_counter()
    simulate_current_driven(unit, rec.t, rec.current)
    t_base = time.perf_counter() - t0

    print(f"recording: {rec.t.size} samples, {res['cycles']['total']} cycles, 1 kHz; "
          f"verdict {res['verdict']} "
          f"({res['effect']})")
    print(f"baseline: one current-driven twin simulation of the recording   {t_base:8.3f} s  (1.00)")
    print(f"bag read + resample                                            {t_read:8.3f} s  "
          f"({t_read / t_base:.2f})")
    print(f"diagnosis, full catalog + refit                                {t_diag:8.3f} s  "
          f"({t_diag / t_base:.2f})   target < 60 s")
    print(f"  of which twin evaluation ({spent['calls']} torque/force balances)   {spent['twin']:8.3f} s  "
          f"= {100 * spent['twin'] / t_diag:.0f} % of the diagnosis; forward simulation: 0 %")


if __name__ == "__main__":
    main()
