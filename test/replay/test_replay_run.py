"""Replay over the monitor core: equals the node's way of feeding, several units and bags, JSON, report."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from rosbags.rosbag2 import Reader

from ebm_wear_monitor.bagio import Series, read_bags, write_unit_bag
from ebm_wear_monitor.domain.signals import split_topic
from ebm_wear_monitor.fleet.synthetic import UnitScenario, write_unit
from ebm_wear_monitor.monitor import MonitorCore
from ebm_wear_monitor.monitor.wire import decode_records
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.replay.report import write_replay_report
from ebm_wear_monitor.replay.run import replay_bags

SECTION4_KEYS = {"unit", "duty_cycles", "wear", "clearance", "remaining_life", "input_faults"}


@pytest.fixture(scope="module")
def unit():
    return load_unit()


@pytest.fixture(scope="module")
def sim_bag(tmp_path_factory, unit):
    """A twin recording: 8 brake applications at 100 Hz with ground truth, duplicated/late/NaN messages."""
    root = tmp_path_factory.mktemp("replay")
    scenario = UnitScenario(unit="u", seed=3, bags=1, cycles_per_bag=8, demands_n=(10e3, 20e3),
                            hold_s=0.3, rest_s=0.2, wear_acceleration=2e4, prior_cycles=100, rate_hz=100.0,
                            storage="mcap", faults=True)
    (bag,) = write_unit(root, scenario, unit)
    return bag


def test_replay_equals_the_node_feeding_one_message_at_a_time(sim_bag, unit):
    """The node decodes each arriving record with monitor.wire and feeds the core in arrival order; the
    replay feeds whole storage chunks. Same core, same decoder: identical numbers, bit for bit."""
    result = replay_bags([sim_bag], unit)
    core = MonitorCore(unit)
    node_cycles = []
    with Reader(sim_bag) as reader:
        for i, (conn, _, raw) in enumerate(reader.messages()):
            got = decode_records([raw])
            core.add(split_topic(conn.topic)[1], got.stamps_ns, got.values)
            if i % 7 == 0:  # the node's processing timer fires every few messages
                node_cycles += core.process()
    node_cycles += core.process(final=True)
    (replayed,) = result.units
    assert replayed.snapshot.to_json_dict() == core.snapshot().to_json_dict()
    assert 6 <= replayed.snapshot.duty_cycles <= 8  # the injected gap may cut an application
    app = replayed.applications
    assert app["index"].tolist() == [c.index for c in node_cycles]
    assert app["clearance_estimate_m"].tolist() == [c.clearance_estimate_m for c in node_cycles]
    observed = [c.clearance_observed_m for c in node_cycles]
    assert np.array_equal(app["clearance_observed_m"].to_numpy(), observed, equal_nan=True)
    assert sum(replayed.snapshot.input_faults.values()) > 0  # the injected faults reached the core


def test_several_units_in_one_bag_and_several_bags_per_unit(tmp_path, sim_bag, unit):
    """Unit /a split over two bags (given out of order) gives the same result as one bag of it all."""
    rec = read_bags([sim_bag]).units["/embu"]
    sig = rec.signals
    cut = sig["angle"].stamps[len(sig["angle"].stamps) // 2]

    def part(first: bool) -> dict[str, Series]:
        return {k: Series(s.stamps[(s.stamps < cut) == first], s.values[(s.stamps < cut) == first])
                for k, s in sig.items()}

    whole = {k: Series(s.stamps, s.values) for k, s in sig.items()}
    write_unit_bag(tmp_path / "day1", None, {"/a": part(True), "/b": whole}, storage="sqlite3")
    write_unit_bag(tmp_path / "day2", None, {"/a": part(False)})
    write_unit_bag(tmp_path / "all", None, {"/a": whole})
    split = replay_bags([tmp_path / "day2", tmp_path / "day1"], unit)
    single = replay_bags([tmp_path / "all"], unit)
    assert [u.unit for u in split.units] == ["/a", "/b"]
    a, b = split.units
    assert a.bags == [str(tmp_path / "day1"), str(tmp_path / "day2")]
    assert a.snapshot.to_json_dict() == single.units[0].snapshot.to_json_dict()
    assert b.snapshot.duty_cycles == a.snapshot.duty_cycles > 0


def test_json_layout_and_prognostics_against_ground_truth(sim_bag, unit):
    doc = json.loads(json.dumps(replay_bags([sim_bag], unit).to_json_dict()))
    (entry,) = doc["units"]
    assert set(entry) >= SECTION4_KEYS
    assert set(entry["wear"]) >= {"screw_raceway_m", "nut_raceway_m", "ball_m"}
    assert set(entry["clearance"]) >= {"model_m", "estimate_m", "std_m"}
    assert set(entry["remaining_life"]) >= {"limit_m", "cycles_p05", "cycles_p50", "cycles_p95"}
    prog = entry["prognostics"]
    assert prog["eol_cycles"] > 108  # truth: the unit had 100 applications before and 8 in the bag
    assert set(prog) >= {"prognostic_horizon_cycles", "alpha_lambda_pass", "relative_accuracy"}


def test_report_is_one_self_contained_page_with_its_figures(tmp_path, sim_bag, unit):
    result = replay_bags([sim_bag], unit)
    out = write_replay_report(tmp_path / "report", result.units, {"bag: /x/axial_force": "type std_msgs"})
    assert [p.name for p in out.iterdir()] == ["index.html"]
    page = (out / "index.html").read_text()
    figures = re.findall(r'Plotly.newPlot\("([a-z]+)-1"', page)
    assert set(figures) >= {"clearance", "wear"}  # (the browser test checks them drawn)
    assert "<script src=" not in page and "http" not in page.split("</script>")[-1]  # nothing fetched
    assert "std_msgs" in page
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary left behind
