"""Start-up (issue 12): ``ebm-wear --help`` and ``ebm-wear calc`` load none of the heavy libraries.

Checked on the modules loaded in a fresh interpreter after running the command through the real
entry point (the wall-time ratios are in bench/bench_startup.py, not timed here).
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("scipy.signal", "pandas", "dask", "distributed", "matplotlib", "rosbags", "rclpy")

SCRIPT = r"""
import contextlib, io, json, sys
from ebm_wear_monitor.cli.main import main
with contextlib.redirect_stdout(io.StringIO()):
    try:
        rc = main(sys.argv[1:])
    except SystemExit as exc:
        rc = exc.code
print(json.dumps({"rc": rc, "modules": sorted(sys.modules)}))
"""


@pytest.mark.parametrize("argv", [
    ["--help"],
    ["replay", "--help"],
    ["calc", "contact", "--params", "embu_000", "--axial-force", "20000"],
    ["calc", "wear", "--params", "embu_000", "--axial-force", "20000", "--speed", "20"],
    ["calc", "actuator", "--params", "embu_000", "--clamp-force", "30000"],
])
def test_help_and_calc_load_no_heavy_library(argv):
    run = subprocess.run([sys.executable, "-c", SCRIPT, *argv], capture_output=True, text=True, timeout=120,
                         check=False)
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert out["rc"] in (0, None), run.stderr
    loaded = [m for m in out["modules"] if any(m == h or m.startswith(h + ".") for h in HEAVY)]
    assert loaded == []
