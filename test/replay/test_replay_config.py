"""Monitor-core thresholds for replay from the node's ROS parameter file."""

from __future__ import annotations

import pytest

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.fleet.synthetic import UnitScenario, write_unit
from ebm_wear_monitor.monitor import MonitorConfig
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.replay.config import load_monitor_config
from ebm_wear_monitor.replay.run import replay_bags


def test_ros_parameter_file_sets_core_thresholds_and_ignores_node_keys(tmp_path):
    path = tmp_path / "node.yaml"
    path.write_text("/**:\n  ros__parameters:\n    qos_depth: 10\n    gap_s: 0.5\n"
                    "/train1/embu:\n  ros__parameters:\n    max_force_n: 5.0e4\n")
    config = load_monitor_config(path)
    assert config.gap_s == 0.5
    assert config.max_force_n == 5.0e4
    assert config.reorder_window_s == MonitorConfig().reorder_window_s
    flat = tmp_path / "flat.yaml"
    flat.write_text("gap_s: 0.25\n")
    assert load_monitor_config(flat).gap_s == 0.25


@pytest.mark.parametrize("text", ["gap_s: -1\n", "gap_s: fast\n", "- 1\n", "a: [\n"])
def test_bad_values_name_the_file(tmp_path, text):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(InputError, match=str(path)):
        load_monitor_config(path)


def test_thresholds_reach_the_core(tmp_path):
    """With a force bound below the clamp forces every force sample is 'absurd': no application."""
    unit = load_unit()
    scenario = UnitScenario(unit="u", seed=2, bags=1, cycles_per_bag=2, demands_n=(15e3,), hold_s=0.3,
                            rest_s=0.2, wear_acceleration=1.0, prior_cycles=0, rate_hz=100.0, storage="mcap")
    (bag,) = write_unit(tmp_path, scenario, unit)
    (path := tmp_path / "c.yaml").write_text("max_force_n: 1000.0\n")
    default = replay_bags([bag], unit).units[0].snapshot.to_json_dict()
    strict = replay_bags([bag], unit, config=load_monitor_config(path)).units[0].snapshot.to_json_dict()
    assert default["duty_cycles"] == 2
    assert strict["duty_cycles"] == 0
    assert strict["input_faults"]["absurd"] > 0


def test_binary_file_is_a_named_input_error(tmp_path):
    path = tmp_path / "binary.yaml"
    path.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(InputError, match=str(path)):
        load_monitor_config(path)


def test_a_unit_file_given_as_config_is_refused(tmp_path):
    """A flat file without a single monitor parameter is not silently taken for the defaults."""
    from ebm_wear_monitor.params import reference_path

    with pytest.raises(InputError, match="no monitor parameter"):
        load_monitor_config(reference_path("embu_000"))
