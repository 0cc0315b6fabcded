"""The rosidl-generated ebm_wear_msgs classes import in rclpy and match msg_defs/ field by field."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

MSG_DIR = Path(__file__).resolve().parents[2] / "msg_defs" / "msg"
FIELD = re.compile(r"^\s*([A-Za-z0-9_/]+(?:\[\d*\])?)\s+([a-z][a-z0-9_]*)\s*(?:#.*)?$")


def _declared_fields(name: str) -> list[str]:
    """Field names of a .msg file, read with a regex independent of rosidl and rosbags."""
    names = []
    for line in (MSG_DIR / f"{name}.msg").read_text().splitlines():
        m = FIELD.match(line)
        if m and "=" not in line.split("#")[0]:
            names.append(m.group(2))
    return names


@pytest.mark.parametrize("name", sorted(p.stem for p in MSG_DIR.glob("*.msg")))
def test_generated_class_has_every_declared_field(name: str) -> None:
    import ebm_wear_msgs.msg as msgs

    cls = getattr(msgs, name)
    assert list(cls.get_fields_and_field_types()) == _declared_fields(name)


def test_float64stamped_is_exactly_the_spec() -> None:
    from ebm_wear_msgs.msg import Float64Stamped

    assert Float64Stamped.get_fields_and_field_types() == {"header": "std_msgs/Header", "data": "double"}


def test_messages_serialize_through_rclpy() -> None:
    from ebm_wear_msgs.msg import DutyCycle, Float64Stamped
    from rclpy.serialization import deserialize_message, serialize_message

    msg = Float64Stamped(data=-1.25)
    msg.header.stamp.sec, msg.header.stamp.nanosec, msg.header.frame_id = 12, 345, "embu"
    back = deserialize_message(serialize_message(msg), Float64Stamped)
    assert (back.data, back.header.stamp.sec, back.header.stamp.nanosec, back.header.frame_id) == (
        -1.25, 12, 345, "embu")
    cycle = DutyCycle(index=7)
    cycle.screw_wear_m[2] = 3.5e-11
    assert deserialize_message(serialize_message(cycle), DutyCycle).screw_wear_m[2] == 3.5e-11
