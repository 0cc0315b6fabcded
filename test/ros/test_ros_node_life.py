"""Issue 11 item 5: a growing unit reaches ``warn`` on /diagnostics, live (node, player, listener).

Three processes over Fast DDS: the player publishes a closed-form bag whose clearance grows by
0.2 um per application (0.2 mm at the start, limit 0.5 mm: about 1,480 applications left after
the bag), the node runs the monitor core, the listener prints /diagnostics and remaining_life.
The unit file (the reference EMBU with a fleet's own thresholds in its ``monitor`` block: warn
at p05 <= 1,000,000 applications, due at <= 10) makes this unit ``warn``: 24 applications of
data cannot rule out that the growth accelerates over the next 1,500, so its p05 is a few
hundred. The status is the core's, the same the offline replay gives on the bag.
"""

from __future__ import annotations

import pytest
import yaml

from ebm_wear_monitor.bagio.reader import read_bags
from ebm_wear_monitor.monitor import MonitorConfig, MonitorCore
from ebm_wear_monitor.params import load_unit, reference_path

pytestmark = pytest.mark.ros

GROWTH = 0.2e-6  # clearance growth per application [m]
APPLICATIONS = 24
WARN_LEVEL, OK_LEVEL = 1, 0  # diagnostic_msgs/DiagnosticStatus levels (the listener prints ints)
STATUS_WARN = 3  # ebm_wear_msgs/RemainingLife.STATUS_WARN


def _unit_file(tmp_path):
    data = yaml.safe_load(reference_path("embu_000").read_text())
    data["monitor"] |= {"warn_cycles": 1e6, "due_cycles": 10}
    path = tmp_path / "unit.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def _offline(bag, unit_file) -> str:
    core = MonitorCore(load_unit(unit_file), MonitorConfig())
    for name, sig in read_bags([bag]).units["/embu"].signals.items():
        if name != "current":
            core.add(name, sig.stamps_ns, sig.values)
    core.process(final=True)
    snap = core.snapshot()
    assert snap.duty_cycles == APPLICATIONS
    return snap.life_status


def _unit_status(message: dict) -> dict | None:
    return next((s for s in message["msg"]["status"] if s["name"] == "/embu/wear_monitor"), None)


@pytest.mark.timeout(120)
def test_a_growing_unit_reaches_warn_on_diagnostics(procs, make_bag, tmp_path) -> None:
    bag, _ = make_bag(APPLICATIONS, rate_hz=500.0, growth_m=GROWTH)
    unit_file = _unit_file(tmp_path)
    assert _offline(bag, unit_file) == "warn"
    lines = procs.listener()
    procs.node("-r", "__ns:=/embu", state_dir=tmp_path / "state",
               params={"qos_reliability": "reliable", "diagnostics_period_s": 0.2,
                       "unit_params_file": str(unit_file)})
    seen = lines.wait_until(lambda s: any(m["topic"] == "diagnostics" and _unit_status(m) for m in s), 30)
    first = _unit_status(next(m for m in seen if m["topic"] == "diagnostics" and _unit_status(m)))
    assert first["level"] != WARN_LEVEL  # not before the data say so
    player = procs.player(bag, "--reliable", "--speed", "5")
    assert player.wait(timeout=60) == 0, player.stderr.read()

    def values(m: dict) -> dict:
        return {kv["key"]: kv["value"] for kv in _unit_status(m)["values"]}

    def warned(m: dict) -> bool:  # the status after the whole bag
        u = _unit_status(m) if m["topic"] == "diagnostics" else None
        return bool(u and u["level"] == WARN_LEVEL and u["message"].startswith("remaining life")
                    and values(m)["duty_cycles"] == str(APPLICATIONS))

    seen = lines.wait_until(lambda s: any(map(warned, s)), 30)
    values = values(next(m for m in seen if warned(m)))
    assert values["remaining_life_status"] == "warn"
    p05 = float(values["remaining_cycles_p05"])
    true_left = (0.5e-3 - 0.2e-3 - GROWTH * (APPLICATIONS - 1)) / GROWTH
    assert 10.0 < p05 < true_left < float(values["remaining_cycles_p95"])
    life = [m["msg"] for m in seen if m["topic"] == "remaining_life"]
    assert life[-1]["status"] == STATUS_WARN
    assert life[-1]["seconds_p50"] > 0 and life[-1]["usage_span_s"] > 0
