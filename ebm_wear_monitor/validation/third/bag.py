"""rosbag2 writing (interface.md section 2): Float64Stamped topics, sqlite3 or mcap storage.

Messages are CDR-encoded directly (little-endian, checked against the rosbags typestore in the
self-checks) because the serialiser dominates the write time otherwise.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

MSGTYPE = "ebm_wear_msgs/msg/Float64Stamped"
MSG_FILE = Path(__file__).resolve().parents[3] / "msg_defs" / "msg" / "Float64Stamped.msg"
MSG_TEXT_FALLBACK = "std_msgs/Header header\nfloat64 data\n"
TOPICS = {
    "angle": "screw/angle",
    "velocity": "screw/velocity",
    "force": "axial_force",
    "current": "motor/current",
}


def typestore():
    """ROS 2 Humble typestore with ebm_wear_msgs/msg/Float64Stamped registered from its .msg text."""
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    ts = get_typestore(Stores.ROS2_HUMBLE)
    text = MSG_FILE.read_text() if MSG_FILE.exists() else MSG_TEXT_FALLBACK
    ts.register(get_types_from_msg(text, MSGTYPE))
    return ts


def cdr(sec: int, nsec: int, frame_id: str, value: float) -> bytes:
    """CDR (little-endian) bytes of one Float64Stamped message."""
    fid = frame_id.encode() + b"\0"
    head = struct.pack("<4siiI", b"\x00\x01\x00\x00", sec, nsec, len(fid)) + fid
    return head + b"\0" * ((-(len(head) - 4)) % 8) + struct.pack("<d", value)


def write_bag(
    path: Path,
    namespace: str,
    series: dict[str, tuple[np.ndarray, np.ndarray]],
    *,
    frames: dict[str, str],
    storage: str,
    epoch_s: float,
    log_lag_max_s: float,
    rng: np.random.Generator,
) -> int:
    """Write the topics of ``series`` (key -> (stamps [s] from start, values)) to a new bag at ``path``.

    header.stamp = epoch + stamp; the log time lags it by U(0, log_lag_max_s). Returns the count."""
    from rosbags.rosbag2 import StoragePlugin, Writer

    ts = typestore()
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    ep_ns = round(epoch_s * 1e9)
    rows = []
    for key, (t, v) in series.items():
        st = ep_ns + np.round(t * 1e9).astype(np.int64)
        lt = st + (rng.uniform(0, log_lag_max_s, t.size) * 1e9).astype(np.int64)
        rows.append((key, st, lt, v))
    order_t = np.concatenate([r[2] for r in rows])
    which = np.concatenate([np.full(r[1].size, j) for j, r in enumerate(rows)])
    pos = np.concatenate([np.arange(r[1].size) for r in rows])
    perm = np.argsort(order_t, kind="stable")
    with Writer(path, version=9, storage_plugin=plugin) as w:
        conns = [
            w.add_connection(f"{namespace.rstrip('/')}/{TOPICS[r[0]]}", MSGTYPE, typestore=ts) for r in rows
        ]
        for j, p in zip(which[perm].tolist(), pos[perm].tolist(), strict=True):
            key, st, lt, v = rows[j]
            s = int(st[p])
            w.write(
                conns[j], int(lt[p]), cdr(s // 1_000_000_000, s % 1_000_000_000, frames[key], float(v[p]))
            )
    return int(perm.size)
