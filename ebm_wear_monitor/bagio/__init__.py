"""Bag I/O of the input topics (interface.md section 2) with rosbags: types, bulk writer, bulk reader.

Public API (all lengths/times SI; signals named as in interface.md section 4)::

    from ebm_wear_monitor.bagio import (
        write_unit_bag, Series, read_bags, Recording, UnitData, Signal, read_ground_truth,
        typestore, FLOAT64_STAMPED, INPUT_TOPICS, split_topic, topic_name)

    n = write_unit_bag(path, t, signals_by_namespace, *, storage="mcap", frame_id="",
                       ground_truth=None) -> int
        path: new bag directory (must not exist; written to a temp dir, then renamed)
        t: sample times [s] shared by all signals | {namespace: times} | None
        signals_by_namespace: {"/embu": {"angle": rad, "velocity": rad/s,
                                         "axial_force": N, "current": A}}
            each value an array aligned with t, or Series(stamps_s, values, received_s=None)
            (received_s = bag/receive time, to record late or duplicated delivery)
        storage: "mcap" | "sqlite3"; frame_id: header.frame_id of every message
        ground_truth: JSON-able simulator truth -> <bag>/ground_truth.json (schema: bagio.sidecar)

    rec = read_bags(paths, progress=None) -> Recording
        rec.units["/embu"].signals["angle"].stamps   # header stamps [s], float64, receive order
        rec.units["/embu"].signals["angle"].values   # data [rad]
        rec.units["/embu"].bags                      # bags of that unit, time order
        rec.rejected  # {"<bag>: <topic>": reason} input topic names with a wrong type (skipped)
        raises InputError (one line) for missing/unreadable/truncated/corrupt bags,
        unknown storage, or a bag with no input topic of type ebm_wear_msgs/msg/Float64Stamped

    read_ground_truth(bag) -> dict | None

    typestore() -> rosbags Typestore with ebm_wear_msgs/msg/* registered from msg_defs/msg/*.msg
"""

from ebm_wear_monitor.bagio.reader import Recording, Signal, UnitData, bag_message_count, read_bags
from ebm_wear_monitor.bagio.sidecar import GROUND_TRUTH_FILE, read_ground_truth
from ebm_wear_monitor.bagio.topics import INPUT_TOPICS, split_topic, topic_name
from ebm_wear_monitor.bagio.types import FLOAT64_STAMPED, message_types, msg_dir, typestore
from ebm_wear_monitor.bagio.writer import STORAGES, Series, write_unit_bag

__all__ = [
    "FLOAT64_STAMPED",
    "GROUND_TRUTH_FILE",
    "INPUT_TOPICS",
    "STORAGES",
    "Recording",
    "Series",
    "Signal",
    "UnitData",
    "bag_message_count",
    "message_types",
    "msg_dir",
    "read_bags",
    "read_ground_truth",
    "split_topic",
    "topic_name",
    "typestore",
    "write_unit_bag",
]
