"""The signal and topic contract (domain.signals) against interface.md sections 1, 2 and 4."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ebm_wear_monitor.domain.signals import (
    DEFAULT_NAMESPACE,
    FLOAT64_STAMPED,
    INPUT_TOPICS,
    MONITOR_SIGNALS,
    SIGNALS,
    check_namespace,
    split_topic,
    topic_name,
)
from ebm_wear_monitor.errors import InputError

REPO = Path(__file__).resolve().parents[2]
SPEC = REPO.parent.parent / "shared" / "spec" / "interface.md"


def test_names_and_topics_are_the_interfaces():
    # interface.md section 4: "Signal names: angle, velocity, axial_force, current"; section 2's table
    assert SIGNALS == ("angle", "velocity", "axial_force", "current")
    assert INPUT_TOPICS == {"angle": "screw/angle", "velocity": "screw/velocity",
                            "axial_force": "axial_force", "current": "motor/current"}
    assert SIGNALS[:3] == MONITOR_SIGNALS and DEFAULT_NAMESPACE == "/embu"
    assert FLOAT64_STAMPED == "ebm_wear_msgs/msg/Float64Stamped"
    assert (REPO / "msg_defs" / "msg" / "Float64Stamped.msg").is_file()
    if SPEC.is_file():  # the shared spec beside the repository (not in a fresh clone)
        text = SPEC.read_text(encoding="utf-8")
        row = r"^\| `([a-z_/]+)`(?: \(optional\))? \| ebm_wear_msgs/msg/Float64Stamped"
        assert re.findall(row, text, re.M) == list(INPUT_TOPICS.values())
        assert "Signal names: `angle`, `velocity`, `axial_force`, `current`" in " ".join(text.split())


def test_topic_names_map_to_units():
    assert split_topic("/train7/car3/embu2/screw/angle") == ("/train7/car3/embu2", "angle")
    assert split_topic("/embu/motor/current") == ("/embu", "current")
    assert split_topic("/screw/velocity") == ("/", "velocity")
    assert split_topic("/embu/my_axial_force") is None
    assert split_topic("/embu/wear") is None
    for unit in ("/", "/a", "/a/b/c"):
        for signal in INPUT_TOPICS:
            assert split_topic(topic_name(unit, signal)) == (unit, signal)


def test_namespaces_are_checked():
    assert check_namespace("train7/car3/embu2/") == "/train7/car3/embu2"
    assert check_namespace("/") == "/"
    for bad in ("/3car", "/a b", "/a//b", "/ä"):
        with pytest.raises(InputError, match="not a ROS 2 namespace"):
            check_namespace(bad)
