"""Read a foreign-world bag with plain rosbags (test helper; no project code involved)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

REPO = Path(__file__).resolve().parents[2]


def read_bag(path: Path) -> tuple[dict, dict]:
    """``({topic: {"stamp", "log", "value", "frames", "msgtype"}}, ground truth)``; times in s."""
    ts = get_typestore(Stores.ROS2_KILTED)
    text = (REPO / "msg_defs" / "msg" / "Float64Stamped.msg").read_text()
    ts.register(get_types_from_msg(text, "ebm_wear_msgs/msg/Float64Stamped"))
    out = {}
    with AnyReader([path], default_typestore=ts) as reader:
        for conn in reader.connections:
            stamp, log, value, frames = [], [], [], set()
            for c, t, raw in reader.messages(connections=[conn]):
                m = reader.deserialize(raw, c.msgtype)
                stamp.append(m.header.stamp.sec + m.header.stamp.nanosec * 1e-9)
                log.append(t * 1e-9)
                value.append(m.data)
                frames.add(m.header.frame_id)
            out[conn.topic] = {"stamp": np.array(stamp), "log": np.array(log),
                               "value": np.array(value), "frames": frames,
                               "msgtype": conn.msgtype}
    truth = json.loads((path / "ground_truth.json").read_text())
    return out, truth
