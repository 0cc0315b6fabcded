"""The Float64Stamped codec of interface.md section 1.

The topics and the type name: :mod:`ebm_wear_monitor.domain.signals`.

Plain numpy, no ROS and no bag library: the live node (raw DDS records) and the
bag reader (raw storage records) both decode here, so the core gets the very
same int64 nanosecond stamps and float64 values from either.

A ``Float64Stamped`` on the wire (and in a rosbag2 bag) is XCDR1: a 4-byte
encapsulation header (``00 01 00 00`` little-endian, ``00 00 00 00`` big-endian)
followed by the fields, each aligned to its own size counted from the end of
that header::

    offset  size  field
    0       4     header.stamp.sec       int32
    4       4     header.stamp.nanosec   uint32 (valid: < 1e9)
    8       4     len(frame_id) + 1      uint32 (the string is NUL-terminated)
    12      L     frame_id bytes + NUL   (L = len(frame_id) + 1)
    d       8     data                   float64, d = ceil((12 + L) / 8) * 8

so a record is ``4 + d + 8`` bytes: 28 with an empty ``frame_id``. Records of
one length decode together as an ``(n, size)`` byte matrix (one gather per
field, whatever the frame_id); records of several lengths are grouped by length.
A record whose layout does not check out (another encapsulation, a length that
disagrees with its string length) is flagged ``ok = False``: the adapter hands
it to a general deserializer or counts it ``undecodable``.

Stamps: ``stamp_ns = sec * 1e9 + nanosec`` exactly, as int64. A stamp with
``nanosec >= 1e9`` is not a ``builtin_interfaces/Time``; it becomes
:data:`BAD_STAMP_NS`, which the core counts as ``bad_stamp``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

#: the stamp given to a record whose header.stamp is not a valid time (nanosec >= 1e9) [ns]
BAD_STAMP_NS = int(np.iinfo(np.int64).min)
NS_PER_S = 1_000_000_000
#: encapsulation header of little-endian plain CDR (XCDR1)
CDR_LE_HEADER = b"\x00\x01\x00\x00"
#: record size with an empty frame_id [bytes]
EMPTY_FRAME_RECORD = 28
_HEAD = 16  # encapsulation + sec + nanosec + string length [bytes]


# ---------------------------------------------------------------------------------------------- stamps
def stamp_ns(sec: np.ndarray | int, nanosec: np.ndarray | int) -> np.ndarray:
    """Exact int64 ns of ``builtin_interfaces/Time`` (sec, nanosec); BAD_STAMP_NS where nanosec >= 1e9."""
    sec = np.asarray(sec, dtype=np.int64)
    nanosec = np.asarray(nanosec, dtype=np.int64)
    return np.where((nanosec >= 0) & (nanosec < NS_PER_S), sec * NS_PER_S + nanosec, BAD_STAMP_NS)


def split_ns(stamps_ns: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """int64 ns -> (sec int32, nanosec uint32) of ``builtin_interfaces/Time``, nanosec in [0, 1e9)."""
    sec, nanosec = np.divmod(np.asarray(stamps_ns, dtype=np.int64), NS_PER_S)
    return sec.astype(np.int32), nanosec.astype(np.uint32)


def seconds_to_ns(stamps_s: np.ndarray) -> np.ndarray:
    """Times [s] -> int64 ns rounded to the nearest ns (for generators that think in seconds)."""
    return np.rint(np.asarray(stamps_s, dtype=np.float64) * NS_PER_S).astype(np.int64)


# ---------------------------------------------------------------------------------------------- codec
def _data_offset(frame_len: int) -> int:
    """Offset of ``data`` after the encapsulation header for a frame_id of ``frame_len`` bytes (no NUL)."""
    return (12 + frame_len + 1 + 7) // 8 * 8


def encode(stamps_ns: np.ndarray, values: np.ndarray, frame_id: str = "") -> tuple[bytes, int]:
    """Serialise many ``Float64Stamped`` into one buffer: (records back to back, record size [bytes])."""
    sec, nanosec = split_ns(stamps_ns)
    values = np.asarray(values, dtype=np.float64)
    frame = frame_id.encode("utf-8") + b"\x00"
    data_at = _data_offset(len(frame) - 1)
    size = 4 + data_at + 8
    layout = np.dtype({"names": ["enc", "sec", "nanosec", "strlen", "frame", "data"],
                       "formats": ["S4", "<i4", "<u4", "<u4", f"S{len(frame)}", "<f8"],
                       "offsets": [0, 4, 8, 12, 16, 4 + data_at], "itemsize": size})
    records = np.zeros(values.size, dtype=layout)
    records["enc"] = CDR_LE_HEADER
    records["sec"], records["nanosec"], records["strlen"] = sec, nanosec, len(frame)
    records["frame"] = frame
    records["data"] = values
    return records.tobytes(), size


def encode_records(stamps_ns: np.ndarray, values: np.ndarray, frame_id: str = "") -> list[bytes]:
    """Serialise many ``Float64Stamped``: one CDR record (bytes) per (stamp [ns], value)."""
    buf, size = encode(stamps_ns, values, frame_id)
    return [buf[i:i + size] for i in range(0, len(buf), size)]


@dataclass
class Decoded:
    """Decoded records in their order: header stamps [ns], data [SI unit of the topic], recognised mask."""

    stamps_ns: np.ndarray = field(default_factory=lambda: np.empty(0, np.int64))
    values: np.ndarray = field(default_factory=lambda: np.empty(0))
    ok: np.ndarray = field(default_factory=lambda: np.empty(0, bool))  # False: layout not recognised

    def __len__(self) -> int:
        return int(self.ok.size)


def _layout(size: int) -> np.dtype:
    """Structured view of a record of ``size`` bytes: header bytes, sec, nanosec, string length, data."""
    return np.dtype({"names": ["b0", "b1", "b2", "b3", "sec", "nanosec", "strlen", "data"],
                     "formats": ["u1", "u1", "u1", "u1", "<i4", "<u4", "<u4", "<f8"],
                     "offsets": [0, 1, 2, 3, 4, 8, 12, size - 8], "itemsize": size})


def decode_uniform(buf: bytes | memoryview | np.ndarray, size: int) -> Decoded:
    """Decode records of ``size`` bytes each, back to back in ``buf`` (either byte order, any frame_id)."""
    u8 = np.frombuffer(buf, dtype=np.uint8) if not isinstance(buf, np.ndarray) else buf.reshape(-1)
    n = u8.size // size if size > 0 else 0
    if size < EMPTY_FRAME_RECORD or n * size != u8.size:
        return Decoded(np.full(n, BAD_STAMP_NS, np.int64), np.full(n, np.nan), np.zeros(n, bool))
    rec = u8.view(_layout(size))  # no copy: each field a strided view
    little = rec["b1"] == 1
    ok = (rec["b0"] == 0) & (little | (rec["b1"] == 0)) & (rec["b2"] == 0) & (rec["b3"] == 0)
    sec, nanosec, strlen, data = rec["sec"], rec["nanosec"], rec["strlen"], rec["data"]
    if not little.all():  # big-endian records: the same fields, bytes swapped
        big = ~little
        sec = np.where(big, sec.byteswap(), sec)
        nanosec = np.where(big, nanosec.byteswap(), nanosec)
        strlen = np.where(big, strlen.byteswap(), strlen)
        data = np.where(big, data.byteswap(), data)
    # the string length must put data exactly at the end: 4 + ceil8(12 + strlen) + 8 == size
    ok &= (strlen >= 1) & (4 + (12 + strlen.astype(np.int64) + 7) // 8 * 8 + 8 == size)
    stamps = np.where(ok, stamp_ns(sec, nanosec), BAD_STAMP_NS)
    return Decoded(stamps, np.where(ok, data, np.nan), ok)


def decode_records(raws: Sequence[bytes]) -> Decoded:
    """Decode CDR records of any lengths (grouped by length, each group in bulk), in their order."""
    n = len(raws)
    if n == 0:
        return Decoded()
    lens = np.fromiter(map(len, raws), dtype=np.int64, count=n)
    first = int(lens[0])
    if np.all(lens == first):
        return decode_uniform(b"".join(raws), first)
    out = Decoded(np.empty(n, np.int64), np.empty(n), np.empty(n, bool))
    for size in np.unique(lens).tolist():
        idx = np.flatnonzero(lens == size)
        part = decode_uniform(b"".join([raws[i] for i in idx.tolist()]), size)
        out.stamps_ns[idx], out.values[idx], out.ok[idx] = part.stamps_ns, part.values, part.ok
    return out


# ---------------------------------------------------------------------------------------------- batches
@dataclass
class Batch:
    """What a data source hands the core in one go, per signal, in arrival order.

    ``signals[name] = (header stamps [ns] int64, values [SI])``; ``faults[name][kind] = n`` for
    records lost before decoding (``undecodable``, ``lost``: in a damaged storage chunk).
    """

    signals: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    faults: dict[str, dict[str, int]] = field(default_factory=dict)

    def add(self, signal: str, stamps_ns: np.ndarray, values: np.ndarray) -> None:
        """Append samples of ``signal`` (after those already in the batch)."""
        if signal in self.signals:
            s, v = self.signals[signal]
            stamps_ns, values = np.concatenate([s, stamps_ns]), np.concatenate([v, values])
        self.signals[signal] = (stamps_ns, values)

    def count(self, signal: str, kind: str, n: int) -> None:
        """Record ``n`` samples of ``signal`` that never made it into the batch, as fault ``kind``."""
        if n:
            per = self.faults.setdefault(signal, {})
            per[kind] = per.get(kind, 0) + int(n)
