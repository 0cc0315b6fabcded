"""rosbag2 output of the foreign world, written with rosbags' Writer and typestore directly.

``Float64Stamped`` is registered from its message text (identical to ``msg_defs/msg``; a test checks
that). Messages are serialised in bulk: one record is serialised by the typestore as a template,
then stamps and values are written into copies of it with numpy (little-endian CDR: 4-byte
encapsulation header, ``int32 sec``, ``uint32 nanosec``, the frame_id string, padding, ``float64``).
Every message goes to the bag at its log time (stamp plus the acquisition lag), all topics merged
in log-time order. rosbags (the ``tools`` extra) is imported only when a bag is written.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np

MSGTYPE = "ebm_wear_msgs/msg/Float64Stamped"
#: The message definition of interface.md section 1, exactly.
MSG_TEXT = "std_msgs/Header header\nfloat64 data\n"
#: storage name -> rosbags' StoragePlugin member
STORAGES = {"sqlite3": "SQLITE3", "mcap": "MCAP"}


def storage_plugin(storage: str):
    """rosbags' ``StoragePlugin`` of a storage name (``sqlite3``, ``mcap``)."""
    from rosbags.rosbag2 import StoragePlugin
    return StoragePlugin[STORAGES[storage]]


def typestore():
    """A ROS 2 typestore with ``ebm_wear_msgs/msg/Float64Stamped`` registered from its text."""
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    ts = get_typestore(Stores.ROS2_KILTED)
    ts.register(get_types_from_msg(MSG_TEXT, MSGTYPE))
    return ts


def serialize(ts, stamps_ns: np.ndarray, values: np.ndarray, frame_id: str) -> np.ndarray:
    """CDR records (``n x record length`` uint8) for stamps [ns] and values, one frame_id."""
    cls = ts.types[MSGTYPE]
    header_cls = ts.types["std_msgs/msg/Header"]
    time_cls = ts.types["builtin_interfaces/msg/Time"]
    template = ts.serialize_cdr(cls(header=header_cls(stamp=time_cls(sec=0, nanosec=0),
                                                      frame_id=frame_id), data=0.0), MSGTYPE)
    rec = np.tile(np.frombuffer(bytes(template), dtype=np.uint8), (len(stamps_ns), 1))
    stamps_ns = np.asarray(stamps_ns, dtype=np.int64)
    rec[:, 4:8] = (stamps_ns // 1_000_000_000).astype("<i4").view(np.uint8).reshape(-1, 4)
    rec[:, 8:12] = (stamps_ns % 1_000_000_000).astype("<u4").view(np.uint8).reshape(-1, 4)
    rec[:, -8:] = np.asarray(values, dtype="<f8").view(np.uint8).reshape(-1, 8)
    return rec


def write_bag(path: Path, storage: str, topics: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                  str]],
              truth: dict, extra: dict[str, str] | None = None) -> Path:
    """Write a rosbag2 directory atomically (temporary name, then rename) with its sidecar.

    ``topics`` maps a full topic name to ``(stamps_ns, log_ns, values, frame_id)``; ``extra``
    maps further file names (inside the bag directory) to their text.
    """
    from rosbags.rosbag2 import Writer
    path = Path(path)
    work = path.with_name(f".{path.name}.partial")
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    tmp = work / path.name  # the storage file is named after the bag directory
    ts = typestore()
    names = list(topics)
    recs, logs, idx, which = [], [], [], []
    for k, name in enumerate(names):
        stamps, log, values, frame = topics[name]
        recs.append(serialize(ts, stamps, values, frame))
        logs.append(np.asarray(log, dtype=np.int64))
        idx.append(np.arange(len(stamps)))
        which.append(np.full(len(stamps), k))
    log_all, idx_all, which_all = (np.concatenate(x) for x in (logs, idx, which))
    order = np.argsort(log_all, kind="stable")
    with Writer(tmp, version=9, storage_plugin=storage_plugin(storage)) as writer:
        conns = [writer.add_connection(name, MSGTYPE, typestore=ts) for name in names]
        rows = [[r.tobytes() for r in rec] for rec in recs]
        for j in order:
            k = which_all[j]
            writer.write(conns[k], int(log_all[j]), rows[k][idx_all[j]])
    (tmp / "ground_truth.json").write_text(json.dumps(truth, indent=1, allow_nan=False))
    for name, text in (extra or {}).items():
        (tmp / name).write_text(text)
    if path.exists():
        shutil.rmtree(path)
    os.replace(tmp, path)
    work.rmdir()
    return path
