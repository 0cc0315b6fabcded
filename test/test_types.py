"""Types (issue 14 item 5): mypy finds no error, the core strict and the rest at default settings.

``mypy.ini`` holds the policy: the core (``ebm_wear_monitor.domain``, ``.physics``, ``.monitor``,
``.params``, ``.schema``, ``.arrays``) with every flag ``mypy --strict`` turns on, everything else at
mypy's default settings, the stubs of numpy, scipy, pandas, PyYAML and tqdm (pinned in
requirements/lock.txt), the rosidl message packages read from their sources. The second test runs
``mypy --strict`` itself over the core, so the config's list of flags cannot fall behind what --strict means.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
CORE = ("ebm_wear_monitor.domain", "ebm_wear_monitor.physics", "ebm_wear_monitor.monitor",
        "ebm_wear_monitor.params", "ebm_wear_monitor.schema")


def _mypy(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "mypy", *args], cwd=REPO, capture_output=True, text=True,
                          timeout=600, check=False)


def test_mypy_finds_no_error_core_strict_rest_default() -> None:
    run = _mypy()  # files, flags and per-module sections from mypy.ini
    assert run.returncode == 0, run.stdout[-4000:]
    assert "Success: no issues found" in run.stdout, run.stdout


def test_the_core_passes_mypy_strict_itself() -> None:
    packages = [a for p in CORE for a in ("-p", p)]
    run = _mypy("--strict", "--follow-imports=silent", "--no-warn-unused-configs",
                "--cache-dir=build/mypy_cache_strict", *packages,
                "-m", "ebm_wear_monitor.arrays")
    assert run.returncode == 0, run.stdout[-4000:]
    assert "Success: no issues found" in run.stdout, run.stdout
