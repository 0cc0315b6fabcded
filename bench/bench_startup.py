"""Start-up benchmark: wall time of short ``ebm-wear`` commands as ratios to ``python -c "import numpy"``.

Each command runs ``--runs`` times in a fresh process (median taken), interleaved with the
baseline in the same run, from the venv of this interpreter:

* ``ebm-wear --help``                       target <= 2x the baseline (issue 12)
* ``ebm-wear calc contact ...``             (no scipy.signal, pandas, dask or matplotlib loaded)
* ``ebm-wear replay bags/healthy``          a small replay without --report (34 k messages)

Run: ``.venv/bin/python bench/bench_startup.py [--runs 7]``
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
COMMANDS = {
    'python -c "import numpy"': [sys.executable, "-c", "import numpy"],
    "ebm-wear --help": [str(BIN / "ebm-wear"), "--help"],
    "ebm-wear calc contact": [str(BIN / "ebm-wear"), "calc", "contact", "--params", "embu_000",
                              "--axial-force", "20000"],
    "ebm-wear replay bags/healthy": [str(BIN / "ebm-wear"), "replay", str(REPO / "bags" / "healthy"),
                                     "--no-progress"],
}


def wall(argv: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=REPO)
    return time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7)
    args = parser.parse_args()
    times: dict[str, list[float]] = {name: [] for name in COMMANDS}
    for argv in COMMANDS.values():
        wall(argv)  # warm the page cache
    for _ in range(args.runs):
        for name, argv in COMMANDS.items():
            times[name].append(wall(argv))
    base_name = next(iter(COMMANDS))
    base = statistics.median(times[base_name])
    print(f"{base_name}: {base:.3f} s (median of {args.runs})")
    for name in list(COMMANDS)[1:]:
        t = statistics.median(times[name])
        target = " (target <= 2)" if name == "ebm-wear --help" else ""
        print(f"{name}: {t:.3f} s = {t / base:.2f} x the baseline{target}")


if __name__ == "__main__":
    main()
