"""Bag I/O of the input topics (interface.md section 2): types, bulk writer (rosbags), streaming reader.

Public API (all lengths/times SI; signals named as in interface.md section 4)::

    from ebm_wear_monitor.bagio import (
        write_unit_bag, BagWriter, Series, BagReader, read_bags, BagRecordings,
        read_ground_truth, typestore)
    # topic names, signal names and the message type: ebm_wear_monitor.domain.signals

    n = write_unit_bag(path, t, signals_by_namespace, *, storage="mcap", frame_id="",
                       ground_truth=None) -> int
        path: new bag directory (must not exist; written to a temp dir, then renamed)
        t: sample times (float s or int64 ns) shared by all signals | {namespace: times} | None
        signals_by_namespace: {"/embu": {"angle": rad, "velocity": rad/s,
                                         "axial_force": N, "current": A}}
            each value an array aligned with t, or Series(stamps, values, received=None)
            (received = bag/receive time, to record late or duplicated delivery)
        storage: "mcap" | "sqlite3"; frame_id: header.frame_id of every message
        ground_truth: JSON-able simulator truth -> <bag>/ground_truth.json (schema: bagio.sidecar)

    with BagReader(paths, signals=None, stamps="header", strict=False, failed=None) as reader:
        reader.units      # {unit: [bags]}; reader.total: progress units (storage index, no counting)
        for batches in reader.batches(progress=None):   # {unit: monitor.wire.Batch}, chunk by chunk
            ...           # Batch.signals[s] = (header stamps [ns] int64, values); Batch.faults
        reader.rejected   # {"<bag>: <topic>": reason} input topic names with a wrong type (skipped)
        reader.problems   # one line per damaged storage place / topic with lost messages

    rec = read_bags(paths, progress=None, **reader_options) -> BagRecordings   # the whole, in memory:
        # one ebm_wear_monitor.domain.recording.Recording per unit
        rec.units["/embu"].signals["angle"].stamps_ns  # header stamps [ns], int64, receive order
        rec.units["/embu"].signals["angle"].stamps     # the same in s (float, for plots/diagnosis)
        rec.units["/embu"].signals["angle"].values     # data [rad]
        rec.units["/embu"].bags                        # bags of that unit, time order
    raise InputError (one line) for missing/unreadable/corrupt bags, unknown storage, or a bag
    with no input topic of type ebm_wear_msgs/msg/Float64Stamped

    read_ground_truth(bag) -> dict | None

    typestore() -> rosbags Typestore with ebm_wear_msgs/msg/* registered from msg_defs/msg/*.msg
"""

from ebm_wear_monitor.bagio.reader import BagReader, BagRecordings, bag_message_count, read_bags
from ebm_wear_monitor.bagio.sidecar import GROUND_TRUTH_FILE, read_ground_truth
from ebm_wear_monitor.bagio.types import msg_dir, typestore
from ebm_wear_monitor.bagio.writer import STORAGES, BagWriter, Series, write_unit_bag

__all__ = [
    "GROUND_TRUTH_FILE",
    "STORAGES",
    "BagReader",
    "BagRecordings",
    "BagWriter",
    "Series",
    "bag_message_count",
    "msg_dir",
    "read_bags",
    "read_ground_truth",
    "typestore",
    "write_unit_bag",
]
