"""Import contract (issue 12): the onboard node and the monitor core carry nothing they do not need.

Checked on the set of modules actually loaded, in a fresh interpreter: every module of
``ebm_wear_monitor.ros``, ``.domain``, ``.monitor``, ``.physics`` and ``.params`` is imported, then the node's
input path runs (raw records, one of them undecodable so the general deserializer is tried, into a
Feeder driving a MonitorCore). None of rosbags, dask, distributed, pandas or matplotlib may appear.
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

FORBIDDEN = ("rosbags", "dask", "distributed", "pandas", "matplotlib")

SCRIPT = r"""
import importlib, json, pkgutil, sys
import numpy as np
import ebm_wear_monitor
for package in ("ros", "domain", "monitor", "physics", "params"):
    pkg = importlib.import_module(f"ebm_wear_monitor.{package}")
    for info in pkgutil.walk_packages(pkg.__path__, f"{pkg.__name__}."):
        importlib.import_module(info.name)
from ebm_wear_monitor.monitor import Batch, Feeder, MonitorCore
from ebm_wear_monitor.monitor.wire import encode_records
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.ros.inputs import InputBuffer
feeder = Feeder(MonitorCore(load_unit()))
batch = Batch()
t = 10**18 + np.arange(3000, dtype=np.int64) * 1_000_000
for s in ("angle", "velocity", "axial_force"):
    buf = InputBuffer(s)
    buf.pending += encode_records(t, np.zeros(t.size), "frame") + [b"\x00\x01\x00\x00garbage"]
    buf.drain(batch)
feeder.feed(batch)
feeder.finish()
assert feeder.core.snapshot().input_faults.get("undecodable") == 3
print(json.dumps(sorted(sys.modules)))
"""


def test_node_and_core_never_import_bag_or_fleet_libraries():
    run = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=120,
                         check=False)
    assert run.returncode == 0, run.stderr
    loaded = json.loads(run.stdout.strip().splitlines()[-1])
    bad = sorted(m for m in loaded if m.split(".")[0] in FORBIDDEN)
    assert bad == []
    assert "ebm_wear_monitor.ros.node" in loaded and "ebm_wear_monitor.monitor.feeder" in loaded


#: runtime modules that are validation by nature: the diagnosis self-test (``diagnose --selftest``)
VALIDATION_BY_NATURE = ("ebm_wear_monitor/diagnosis/selftest.py",
                        "ebm_wear_monitor/diagnosis/foreign_selftest.py")


def test_runtime_never_imports_the_paper_reproductions_or_the_validation_data():
    """No module outside ``validation/`` imports it, except the self-test (issue 14 item 3)."""
    package = Path(__file__).resolve().parents[1] / "ebm_wear_monitor"
    offenders = []
    for path in sorted(package.rglob("*.py")):
        rel = path.relative_to(package.parent).as_posix()
        if rel.startswith("ebm_wear_monitor/validation/") or rel in VALIDATION_BY_NATURE:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            offenders += [f"{rel}: {n}" for n in names if n.startswith("ebm_wear_monitor.validation")]
    assert offenders == []
