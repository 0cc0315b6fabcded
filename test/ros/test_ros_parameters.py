"""Parameters, shipped config files and diagnostic levels of the node (in-process, no DDS traffic)."""

from __future__ import annotations

import math
import re

import pytest
import yaml

from ebm_wear_monitor.ros import diagnostics as diag
from ebm_wear_monitor.ros.parameters import (
    AGGREGATOR_CONFIG_NAME,
    NODE_SPECS,
    SPEC_BY_NAME,
    SPECS,
    check_value,
    node_state_dir,
    render_config,
    shipped_config_path,
)


def test_rendered_parameter_file_reads_back_every_default_with_its_type() -> None:
    params = yaml.safe_load(render_config())["/**"]["ros__parameters"]
    assert set(params) == {s.name for s in SPECS}
    for spec in SPECS:
        assert params[spec.name] == spec.default, spec.name
        assert type(params[spec.name]) is type(spec.default), spec.name  # ROS rejects int for double
        assert check_value(spec.name, spec.default) is None


def test_shipped_parameter_file_never_overrides_a_default_with_a_stale_value() -> None:
    """Every value in config/wear_monitor.yaml is the current default (regenerate: render_config)."""
    params = yaml.safe_load(shipped_config_path().read_text())["/**"]["ros__parameters"]
    assert {s.name for s in NODE_SPECS} <= set(params)
    stale = {k: v for k, v in params.items() if k not in SPEC_BY_NAME or SPEC_BY_NAME[k].default != v}
    assert not stale, "run: python -m ebm_wear_monitor.ros.parameters > config/wear_monitor.yaml"


@pytest.mark.parametrize(("name", "value"), [
    ("process_rate_hz", 0.0), ("process_rate_hz", math.inf), ("process_rate_hz", "fast"),
    ("qos_depth", 0), ("qos_depth", 2.5), ("executor", "multi_threaded"), ("wear_method", 3),
    ("min_input_rate_hz", -1.0), ("checkpoint_every_cycles", True), ("model_prior_weight", 1.0),
])
def test_out_of_range_or_wrong_type_values_are_rejected_with_the_name(name: str, value: object) -> None:
    reason = check_value(name, value)
    assert reason is not None and reason.startswith(name)


def test_state_dirs_of_different_nodes_never_coincide() -> None:
    env = {"XDG_STATE_HOME": "/s", "HOME": "/h"}
    names = ["/embu/wear_monitor", "/a_b/c/wear_monitor", "/a/b_c/wear_monitor", "/a/b/c_wear_monitor"]
    dirs = [node_state_dir(n, env) for n in names]
    assert len(set(dirs)) == len(names)
    assert all(str(d).startswith("/s/ebm_wear_monitor/") for d in dirs)
    assert node_state_dir("/embu/wear_monitor", {"HOME": "/h"}).parts[:4] == ("/", "h", ".local", "state")


def test_aggregator_config_groups_train_car_embu_namespaces() -> None:
    data = yaml.safe_load(shipped_config_path(AGGREGATOR_CONFIG_NAME).read_text())
    analyzers = data["analyzers"]["ros__parameters"]
    by_train = re.compile(analyzers["wear_by_train"]["regex"][0])
    other = re.compile(analyzers["wear_other"]["regex"][0])
    assert by_train.match("/train7/car3/embu2/wear_monitor")
    assert not by_train.match("/embu/wear_monitor") and other.match("/embu/wear_monitor")
    assert not other.match("/train7/car3/embu2/wear_monitor")
    assert diag.namespace_parts("/train7/car3/embu2") == {"train": "train7", "car": "car3", "embu": "embu2"}
    assert diag.namespace_parts("/embu") == {"embu": "embu"}


THRESH = diag.Thresholds(stale_timeout_s=1.0, min_input_rate_hz=50.0)


def _health(**kw) -> diag.Health:
    base = dict(life_status="ok", life_text="ok: p05 1e6 applications",
                input_rate_hz={"angle": 1000.0}, input_age_s={"angle": 0.01}, new_faults=0)
    return diag.Health(**(base | kw))


@pytest.mark.parametrize(("kw", "level"), [
    ({}, diag.OK),
    ({"input_age_s": {"angle": math.inf}}, diag.STALE),
    ({"input_age_s": {"angle": 2.0}}, diag.STALE),
    ({"life_status": "due"}, diag.ERROR),  # the remaining-life status sets the level: due -> ERROR
    ({"life_status": "due", "input_age_s": {"angle": 2.0}}, diag.ERROR),  # ... even with stopped inputs
    ({"core_error": "boom"}, diag.ERROR),
    ({"life_status": "warn"}, diag.WARN),
    ({"input_rate_hz": {"angle": 10.0}}, diag.WARN),
    ({"new_faults": 3}, diag.WARN),
    ({"life_status": "insufficient_data"}, diag.OK),  # insufficient data is no fault, but it is said
])
def test_levels_follow_the_documented_rules(kw: dict, level: bytes) -> None:
    got, message = diag.assess(_health(**kw), THRESH)
    assert got == level, message
    if kw.get("life_status", "ok") != "ok" and "input_age_s" not in kw:
        assert message.startswith("remaining life "), message
