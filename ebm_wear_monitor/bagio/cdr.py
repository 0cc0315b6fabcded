"""Bulk CDR encoding and decoding of ``ebm_wear_msgs/msg/Float64Stamped`` with numpy.

A ROS 2 message on the wire (and in a rosbag2 bag) is XCDR1-serialised: a
4-byte encapsulation header (``00 01 00 00`` = little-endian CDR, ``00 00`` =
big-endian) followed by the fields, each aligned to its own size counted from
the end of that header. For ``Float64Stamped`` (interface.md section 1)::

    offset  size  field
    0       4     header.stamp.sec       int32
    4       4     header.stamp.nanosec   uint32
    8       4     len(frame_id) + 1      uint32 (the string is NUL-terminated)
    12      L     frame_id bytes + NUL   (L = len(frame_id) + 1)
    d       8     data                   float64, d = ceil((12 + L) / 8) * 8

so with an empty ``frame_id`` (L = 1, d = 16) every record is 4 + 16 + 8 = 28
bytes and a whole bag's records decode as one numpy structured array. Records
of any other frame_id length still have their fields at computable offsets, so
they are decoded by vectorised gathers; only records that fail these layout
checks (big-endian, or corrupt) go through rosbags' general deserializer, which
raises on real corruption.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ebm_wear_monitor.bagio.types import FLOAT64_STAMPED, typestore

#: the CDR encapsulation header of little-endian plain CDR (XCDR1)
CDR_LE_HEADER = b"\x00\x01\x00\x00"
#: record size with an empty frame_id [bytes]
EMPTY_FRAME_RECORD = 28
#: the 28-byte record as a numpy structured type
RECORD_28 = np.dtype([("enc", "<u4"), ("sec", "<i4"), ("nanosec", "<u4"), ("strlen", "<u4"),
                      ("frame", "<u4"), ("data", "<f8")])
_NS_PER_S = 1_000_000_000


def _data_offset(frame_len: np.ndarray | int) -> np.ndarray | int:
    """Offset of ``data`` after the encapsulation header for a frame_id of ``frame_len`` bytes (no NUL)."""
    return (12 + frame_len + 1 + 7) // 8 * 8


def split_stamps(stamps_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Times [s] -> (sec int32, nanosec uint32) as in ``builtin_interfaces/Time``, nanosec in [0, 1e9)."""
    stamps_s = np.asarray(stamps_s, dtype=np.float64)
    sec = np.floor(stamps_s)
    nanosec = np.rint((stamps_s - sec) * _NS_PER_S).astype(np.int64)
    carry = nanosec >= _NS_PER_S
    return (sec + carry).astype(np.int32), np.where(carry, nanosec - _NS_PER_S, nanosec).astype(np.uint32)


def encode_float64_stamped(stamps_s: np.ndarray, values: np.ndarray, frame_id: str = "") -> list[bytes]:
    """Serialise many ``Float64Stamped`` at once: one CDR record (bytes) per (stamp [s], value)."""
    sec, nanosec = split_stamps(stamps_s)
    values = np.asarray(values, dtype=np.float64)
    frame = frame_id.encode("utf-8") + b"\x00"
    data_at = _data_offset(len(frame) - 1)
    size = 4 + data_at + 8
    layout = np.dtype({"names": ["enc", "sec", "nanosec", "strlen", "frame", "data"],
                       "formats": ["S4", "<i4", "<u4", "<u4", f"S{len(frame)}", "<f8"],
                       "offsets": [0, 4, 8, 12, 16, 4 + data_at], "itemsize": size})
    records = np.zeros(len(values), dtype=layout)
    records["enc"] = CDR_LE_HEADER
    records["sec"], records["nanosec"], records["strlen"] = sec, nanosec, len(frame)
    records["frame"] = frame
    records["data"] = values
    buf = records.tobytes()
    return [buf[i:i + size] for i in range(0, len(buf), size)]


def _gather(u8: np.ndarray, pos: np.ndarray, dtype: str) -> np.ndarray:
    """Values of little-endian ``dtype`` starting at byte positions ``pos`` of ``u8``."""
    width = np.dtype(dtype).itemsize
    return u8[pos[:, None] + np.arange(width)].view(dtype).ravel()


def decode_float64_stamped(raws: Sequence[bytes]) -> tuple[np.ndarray, np.ndarray]:
    """Decode CDR records of ``Float64Stamped`` -> (header stamps [s] float64, data float64).

    Raises rosbags' ``SerdeError`` (or ``struct.error``/``IndexError``) on records
    that are neither valid little-endian layouts nor decodable by rosbags.
    """
    n = len(raws)
    buf = b"".join(raws)
    if len(buf) == EMPTY_FRAME_RECORD * n:
        rec = np.frombuffer(buf, dtype=RECORD_28)
        # all 28 bytes long only if every record also says so (little-endian header, 1-byte frame_id)
        if n == 0 or (np.all(rec["enc"] == 0x100) and np.all(rec["strlen"] == 1)):
            return rec["sec"] + rec["nanosec"] * 1e-9, rec["data"].copy()
    lens = np.fromiter(map(len, raws), dtype=np.int64, count=n)
    starts = np.cumsum(lens) - lens
    u8 = np.frombuffer(buf + bytes(16), dtype=np.uint8)  # zero tail: the head checks below stay in range
    ok = lens >= EMPTY_FRAME_RECORD - 8  # room for the fixed head up to the string
    head = np.where(ok, starts, 0)
    ok &= (u8[head] == 0) & (u8[head + 1] == 1)
    strlen = np.where(ok, _gather(u8, head + 12, "<u4"), 1).astype(np.int64)
    data_at = 4 + (12 + strlen + 7) // 8 * 8
    ok &= (strlen >= 1) & (data_at + 8 == lens)
    stamps = np.empty(n)
    values = np.empty(n)
    good = np.flatnonzero(ok)
    stamps[good] = _gather(u8, starts[good] + 4, "<i4") + _gather(u8, starts[good] + 8, "<u4") * 1e-9
    values[good] = _gather(u8, starts[good] + data_at[good], "<f8")
    store = typestore()
    for i in np.flatnonzero(~ok):
        msg = store.deserialize_cdr(raws[i], FLOAT64_STAMPED)
        stamps[i] = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        values[i] = msg.data
    return stamps, values
