"""Bulk access to the two rosbag2 storages, sqlite3 and mcap: raw records in chunks, straight into numpy.

A :class:`Storage` is one storage file of a bag. ``connections`` lists its
topics; :meth:`Storage.chunks` yields, in storage order (the order the recorder
received the messages), :class:`Chunk` s holding each wanted connection's raw
records as one byte matrix per record length, plus their log times [ns] when
asked. No Python object is made per message:

* sqlite3: one query per connection and block of row ids, ``group_concat(data)``
  of the block in row-id order (the table's own B-tree order: no sort, no
  counting pass); log times, when asked, as fixed-width hex in the same query.
* mcap: per chunk of the summary's chunk index, the compressed records are read
  and decompressed (``''``, ``zstd``, ``lz4``), the chunk CRC checked when the
  writer stored one, and the message records located through the chunk's
  MessageIndex records (log time and offset of each message per channel), then
  sliced with numpy gathers; a chunk without message index is walked record by
  record. A file without a summary (or with a damaged one) is scanned for its
  Channel and Chunk records.

Damage never stops the stream: a chunk that cannot be read, fails its CRC, or
whose indexed records do not check out is skipped (records that do check out
in an index-verified chunk are kept) and described in :attr:`Storage.problems`;
the reader compares what it got with the message counts of ``metadata.yaml``
and the storage's own index and counts the difference as ``lost``.

Progress: :attr:`Storage.total` (row-id span or message count of the index)
and :attr:`Chunk.progress`, known before reading, never by a counting pass.
"""

from __future__ import annotations

import contextlib
import sqlite3
import struct
import zlib
from collections.abc import Iterator
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path

import numpy as np

from ebm_wear_monitor.errors import InputError

#: rows per sqlite3 block, messages per mcap chunk are the writer's choice (about 1 MiB)
SQLITE_BLOCK = 1 << 15
MCAP_MAGIC = b"\x89MCAP0\r\n"
_OP_HEADER, _OP_FOOTER, _OP_SCHEMA, _OP_CHANNEL, _OP_MESSAGE = 0x01, 0x02, 0x03, 0x04, 0x05
_OP_CHUNK, _OP_MESSAGE_INDEX, _OP_CHUNK_INDEX, _OP_STATISTICS, _OP_DATA_END = 0x06, 0x07, 0x08, 0x0B, 0x0F
_MSG_HEAD = 22  # channel id u16, sequence u32, log time u64, publish time u64 [bytes]


@dataclass
class Connection:
    """One topic of a storage file: id, name, type, serialization, type hash, messages per its index."""

    id: int
    topic: str
    msgtype: str
    serialization: str
    digest: str = ""
    indexed: int | None = None  # message count according to the storage's own index (None: unknown)


@dataclass
class Records:
    """Raw records of one connection in one chunk, in storage order."""

    groups: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)  # (positions, (n, size) u8)
    log_ns: np.ndarray | None = None  # log time of each record [ns], storage order (when asked)
    count: int = 0

    def add(self, rows: np.ndarray, positions: np.ndarray | None = None) -> None:
        """Append a (n, size) byte matrix of equal-length records (positions: their storage order)."""
        if positions is None:
            positions = np.arange(self.count, self.count + rows.shape[0])
        self.groups.append((positions, rows))
        self.count += rows.shape[0]


@dataclass
class Chunk:
    """Records of one storage chunk per connection id, and the progress units it covers."""

    records: dict[int, Records]
    progress: int


def _by_length(buf: np.ndarray, starts: np.ndarray, lengths: np.ndarray, out: Records) -> None:
    """Slice records ``buf[starts[i]:starts[i] + lengths[i]]`` into equal-length byte matrices."""
    sizes = np.unique(lengths)
    for size in sizes.tolist():
        idx = np.flatnonzero(lengths == size) if sizes.size > 1 else np.arange(lengths.size)
        rows = buf[starts[idx, None] + np.arange(size)] if size else np.zeros((idx.size, 0), np.uint8)
        out.add(rows, idx)
    out.count = int(lengths.size)


class Storage:
    """One storage file of a bag (base class): connections, chunks, problems found on the way."""

    path: Path
    connections: list[Connection]
    total: int  # progress units of the whole file
    start_ns: int  # first log time [ns] (0 when unknown)
    end_ns: int  # last log time [ns]
    #: reading a chunk runs mostly outside Python's interpreter lock, so reading ahead in a thread
    #: overlaps it with the caller's work (:mod:`.ahead`)
    reads_outside_lock = False

    def __init__(self) -> None:
        self.problems: list[str] = []

    def chunks(self, wanted: set[int], log_time: bool) -> Iterator[Chunk]:
        raise NotImplementedError

    def close(self) -> None:
        """Release the file."""


# ---------------------------------------------------------------------------------------------- sqlite3
class SqliteStorage(Storage):
    """A rosbag2 ``.db3`` file read with one ``group_concat`` query per connection and block of row ids.

    The queries run in sqlite3's C code with the interpreter lock released (``reads_outside_lock``):
    read ahead, the replay of a 1.2 M message bag took 0.92-1.05 s of wall time against 1.34-1.37 s
    (``bench/bench_replay.py``, two cores).
    """

    reads_outside_lock = True

    def __init__(self, path: Path) -> None:
        super().__init__()
        self.path = path
        try:
            # immutable: no locking or change checks per query (as rosbags opens bags; a bag being
            # recorded is not replayed)
            self.db = sqlite3.connect(f"file:{path}?mode=ro&immutable=1", uri=True, check_same_thread=False)
            self.db.text_factory = bytes
            columns = {r[1] for r in self.db.execute("PRAGMA table_info(topics)")}
            digest = "type_description_hash" if b"type_description_hash" in columns else "''"
            rows = self.db.execute(f"SELECT id, name, type, serialization_format, {digest} FROM topics "
                                   "ORDER BY id").fetchall()
            # first and last row (one B-tree descent each, no scan, no index needed); their log times
            # stand for the file's time span (rows are stored in arrival order)
            lo, hi, first, last = self.db.execute(
                "SELECT (SELECT min(id) FROM messages), (SELECT max(id) FROM messages), "
                "(SELECT timestamp FROM messages ORDER BY id LIMIT 1), "
                "(SELECT timestamp FROM messages ORDER BY id DESC LIMIT 1)").fetchone()
        except sqlite3.Error as exc:
            raise InputError(f"{path}: unreadable bag: sqlite3 storage: {exc}") from exc
        self.connections = [Connection(int(i), n.decode(), t.decode(), s.decode(), d.decode() if d else "")
                            for i, n, t, s, d in rows]
        self._ids = (0, -1) if lo is None else (int(lo), int(hi))
        self.total = self._ids[1] - self._ids[0] + 1
        self.start_ns, self.end_ns = int(first or 0), int(last or 0)

    def chunks(self, wanted: set[int], log_time: bool) -> Iterator[Chunk]:
        lo, hi = self._ids
        if not wanted:
            yield Chunk({}, self.total)
            return
        stamp = ", group_concat(printf('%016x', timestamp), '')" if log_time else ""
        # the aggregate visits the rows in the order of the row-id range search: storage order
        query = (f"SELECT count(*), max(length(data)), group_concat(data, x''){stamp} FROM messages "
                 "WHERE id >= ? AND id < ? AND topic_id = ?")
        for start in range(lo, hi + 1, SQLITE_BLOCK):
            end = min(start + SQLITE_BLOCK, hi + 1)
            records = {}
            for cid in sorted(wanted):
                try:
                    row = self.db.execute(query, (start, end, cid)).fetchone()
                    out = self._records(row, (start, end, cid), log_time)
                except (sqlite3.Error, ValueError) as exc:
                    self.problems.append(f"{self.path}: rows {start}-{end - 1} of topic id {cid} "
                                         f"unreadable ({exc})")
                    continue
                if out is not None:
                    records[cid] = out
            yield Chunk(records, end - start)

    def _records(self, row: tuple, where: tuple[int, int, int], log_time: bool) -> Records | None:
        count, longest, data = row[:3]
        if not count:
            return None
        out = Records()
        if len(data) == count * longest:  # every record as long as the longest: all of one length
            out.add(np.frombuffer(data, np.uint8).reshape(count, longest))
        else:  # records of several lengths (frame_ids of several lengths): positions from the lengths
            lengths = np.array([r[0] for r in self.db.execute(
                "SELECT length(data) FROM messages WHERE id >= ? AND id < ? AND topic_id = ?", where)],
                dtype=np.int64)
            buf = np.frombuffer(data, np.uint8)
            if lengths.sum() != buf.size:
                raise ValueError("record lengths do not add up")
            _by_length(buf, np.cumsum(lengths) - lengths, lengths, out)
        if log_time:
            out.log_ns = np.frombuffer(bytes.fromhex(row[3].decode()), ">i8").astype(np.int64)
        return out

    def close(self) -> None:
        self.db.close()


# ---------------------------------------------------------------------------------------------- mcap
class _Cursor:
    """Little-endian fields of one MCAP record's content."""

    def __init__(self, data: bytes, at: int = 0) -> None:
        self.data, self.at = data, at

    def take(self, fmt: str) -> int:
        (value,) = struct.unpack_from(fmt, self.data, self.at)
        self.at += struct.calcsize(fmt)
        return value

    def string(self) -> bytes:
        size = self.take("<I")
        self.at += size
        if self.at > len(self.data):
            raise ValueError("string beyond its record")
        return self.data[self.at - size:self.at]


@dataclass
class _ChunkIndex:
    start_ns: int
    end_ns: int
    offset: int  # of the Chunk record in the file
    length: int  # of the Chunk record
    message_indexes: dict[int, int]  # channel id -> file offset of its MessageIndex record
    index_length: int
    messages: int | None  # messages of this chunk per its message indexes (None: unknown)


def _decompress(data: bytes, compression: str, size: int) -> bytes:
    if compression == "":
        return data
    if compression == "zstd":
        try:
            from compression import zstd  # type: ignore[import-not-found]  # Python >= 3.14
        except ImportError:
            from backports import zstd
        return zstd.decompress(data)
    if compression == "lz4":
        from lz4.frame import decompress
        return decompress(data)
    raise ValueError(f"unsupported chunk compression {compression!r}")


class McapStorage(Storage):
    """A rosbag2 ``.mcap`` file read chunk by chunk through its summary (or a scan when it has none).

    Its chunks are parsed record by record in Python, under the interpreter lock: read ahead in a
    thread, the replay of a 1.2 M message bag took as long (1.14-1.54 s against 1.15-1.33 s) for 30 %
    more CPU time, so it is read in the caller's thread (compressed chunks, whose decompression would
    overlap, were not measured).
    """

    def __init__(self, path: Path) -> None:
        super().__init__()
        self.path = path
        try:
            self.file = path.open("rb")
            self.size = self.file.seek(0, 2)
            self.file.seek(0)
            head = self.file.read(8)
        except OSError as exc:
            raise InputError(f"{path}: unreadable bag: mcap storage: {exc.strerror or exc}") from exc
        if head != MCAP_MAGIC:
            self.file.close()
            raise InputError(f"{path}: unreadable bag: not an mcap file (bad magic)")
        self._schemas: dict[int, bytes] = {}
        self._channels: dict[int, Connection] = {}
        self._chunks: list[_ChunkIndex] = []
        self._stats: dict[int, int] | None = None
        try:
            indexed = self._read_summary()
        except (ValueError, struct.error, OSError) as exc:
            self.problems.append(f"{path}: summary unreadable ({exc}); scanned the file instead")
            indexed = False
        if not indexed:
            self._schemas, self._channels, self._chunks, self._stats = {}, {}, [], None
            self._scan()
        self.connections = list(self._channels.values())
        for conn in self.connections:
            conn.indexed = None if self._stats is None else self._stats.get(conn.id, 0)
        known = [c.messages for c in self._chunks]
        self.total = (sum(self._stats.values()) if self._stats is not None
                      else sum(k or 0 for k in known))
        self.start_ns = min((c.start_ns for c in self._chunks), default=0)
        self.end_ns = max((c.end_ns for c in self._chunks), default=0)

    # ---------------------------------------------------------------------- structure
    def _record_at(self, offset: int) -> tuple[int, bytes]:
        self.file.seek(offset)
        head = self.file.read(9)
        if len(head) < 9:
            raise ValueError(f"truncated record at offset {offset}")
        op, length = head[0], struct.unpack_from("<Q", head, 1)[0]
        if offset + 9 + length > self.size:
            raise ValueError(f"record at offset {offset} runs past the end of the file")
        return op, self.file.read(length)

    def _meta_record(self, op: int, content: bytes) -> None:
        """Schema, Channel, ChunkIndex and Statistics records (from the summary or a scan)."""
        cur = _Cursor(content)
        if op == _OP_SCHEMA:
            sid = cur.take("<H")
            self._schemas[sid] = cur.string()
        elif op == _OP_CHANNEL:
            cid, sid = cur.take("<H"), cur.take("<H")
            topic, encoding = cur.string(), cur.string()
            self._channels[cid] = Connection(cid, topic.decode(), self._schemas.get(sid, b"").decode(),
                                             encoding.decode())
        elif op == _OP_CHUNK_INDEX:
            start, end, offset, length = (cur.take("<Q") for _ in range(4))
            table = cur.string()
            indexes = dict(struct.iter_unpack("<HQ", table))
            index_length = cur.take("<Q")
            # each MessageIndex record: 9 bytes of record head, channel u16, length u32, 16 per message
            bounds = [*sorted(indexes.values()), offset + length + index_length]
            messages = sum(max(b - a - 15, 0) // 16 for a, b in pairwise(bounds))
            self._chunks.append(_ChunkIndex(start, end, offset, length, indexes, index_length, messages))
        elif op == _OP_STATISTICS:
            cur.at = 8 + 2 + 4 * 4 + 8 + 8
            table = cur.string()
            self._stats = dict(struct.iter_unpack("<HQ", table))

    def _read_summary(self) -> bool:
        """Read the summary section through the footer; False when the file has none."""
        self.file.seek(self.size - 37)
        footer = self.file.read(37)
        if len(footer) != 37 or footer[-8:] != MCAP_MAGIC or footer[0] != _OP_FOOTER:
            raise ValueError("no valid footer (truncated file?)")
        summary_start = struct.unpack_from("<Q", footer, 9)[0]
        if not summary_start:
            return False
        offset = summary_start
        while offset < self.size - 37:
            op, content = self._record_at(offset)
            if op == _OP_FOOTER:
                break
            self._meta_record(op, content)
            offset += 9 + len(content)
        if not self._chunks:
            return False
        self._chunks.sort(key=lambda c: c.offset)
        return True

    def _scan(self) -> None:
        """Walk the data section record by record (no summary): channels and chunk positions."""
        offset = 8
        while offset + 9 <= self.size:
            try:
                op, content = self._record_at(offset)
            except ValueError as exc:
                self.problems.append(f"{self.path}: {exc}; the rest of the file is unreadable")
                break
            if op in (_OP_FOOTER, _OP_DATA_END):
                break
            if op == _OP_CHUNK:
                start, end = struct.unpack_from("<QQ", content, 0)
                self._chunks.append(_ChunkIndex(start, end, offset, 9 + len(content), {}, 0, None))
                with contextlib.suppress(ValueError):  # the chunk itself is checked when read
                    self._scan_chunk_meta(content)
            elif op in (_OP_SCHEMA, _OP_CHANNEL):
                self._meta_record(op, content)
            offset += 9 + len(content)

    def _scan_chunk_meta(self, content: bytes) -> None:
        """Schema and Channel records written inside a chunk (rosbags writes them there)."""
        records = self._chunk_records(content)[0]
        for op, at, length in self._walk(records):
            if op in (_OP_SCHEMA, _OP_CHANNEL):
                self._meta_record(op, records[at:at + length])

    # ---------------------------------------------------------------------- chunks
    @staticmethod
    def _chunk_records(content: bytes) -> tuple[bytes, int]:
        """(uncompressed records, stored CRC) of a Chunk record's content; ValueError when damaged."""
        cur = _Cursor(content)
        cur.take("<Q")
        cur.take("<Q")
        size, crc = cur.take("<Q"), cur.take("<I")
        compression = cur.string().decode()
        compressed = cur.take("<Q")
        if cur.at + compressed > len(content):
            raise ValueError("compressed records run past the chunk")
        try:
            records = _decompress(content[cur.at:cur.at + compressed], compression, size)
        except Exception as exc:  # zstd/lz4 raise their own errors on damaged data
            raise ValueError(f"{compression} decompression failed ({exc})") from exc
        if len(records) != size:
            raise ValueError(f"chunk holds {len(records)} bytes, its header says {size}")
        if crc and zlib.crc32(records) != crc:
            raise ValueError("chunk CRC mismatch")
        return records, crc

    @staticmethod
    def _walk(records: bytes) -> Iterator[tuple[int, int, int]]:
        """(opcode, content offset, content length) of each record of a chunk."""
        at = 0
        while at + 9 <= len(records):
            op, length = records[at], struct.unpack_from("<Q", records, at + 1)[0]
            if at + 9 + length > len(records):
                raise ValueError(f"record at chunk offset {at} runs past the chunk")
            yield op, at + 9, length
            at += 9 + length

    def _indexed_offsets(self, chunk: _ChunkIndex, cid: int) -> np.ndarray:
        """(log time, offset) pairs of channel ``cid`` in ``chunk`` from its MessageIndex record."""
        op, content = self._record_at(chunk.message_indexes[cid])
        if op != _OP_MESSAGE_INDEX or struct.unpack_from("<H", content, 0)[0] != cid:
            raise ValueError("message index record damaged")
        size = struct.unpack_from("<I", content, 2)[0]
        if size % 16 or 6 + size > len(content):
            raise ValueError("message index record damaged")
        return np.frombuffer(content, "<u8", size // 8, 6).reshape(-1, 2)

    def chunks(self, wanted: set[int], log_time: bool) -> Iterator[Chunk]:
        for chunk in self._chunks:
            try:
                op, content = self._record_at(chunk.offset)
                if op != _OP_CHUNK:
                    raise ValueError("not a chunk record")
                data, _crc = self._chunk_records(content)
            except (ValueError, struct.error, OSError) as exc:
                self.problems.append(f"{self.path}: chunk at offset {chunk.offset} "
                                     f"({chunk.start_ns}-{chunk.end_ns} ns) skipped: {exc}")
                yield Chunk({}, chunk.messages or 0)
                continue
            buf = np.frombuffer(data, np.uint8)
            records = {}
            try:
                located = self._locate(chunk, buf, data, wanted)
            except (ValueError, struct.error) as exc:
                self.problems.append(f"{self.path}: chunk at offset {chunk.offset} skipped: {exc}")
                located = {}
            n = 0
            for cid, (starts, lengths, log_ns) in located.items():
                out = Records()
                _by_length(buf, starts + 9 + _MSG_HEAD, lengths - _MSG_HEAD, out)
                out.log_ns = log_ns if log_time else None
                records[cid] = out
                n += int(starts.size)
            yield Chunk(records, chunk.messages or n)

    def _locate(self, chunk: _ChunkIndex, buf: np.ndarray, data: bytes, wanted: set[int]
                ) -> dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Per wanted channel: (record offsets, content lengths, log times) of its messages, storage order.

        Indexed records are verified (opcode, length inside the chunk, channel id, log time equal to
        the index's); those that fail are dropped and reported.
        """
        out = {}
        if not chunk.message_indexes:  # no index: walk the records
            found: dict[int, list[tuple[int, int, int]]] = {}
            for op, at, length in self._walk(data):
                if op == _OP_MESSAGE and length >= _MSG_HEAD:
                    cid, _seq, log = struct.unpack_from("<HIQ", data, at)
                    if cid in wanted:
                        found.setdefault(cid, []).append((at - 9, length, log))
            for cid, rows in found.items():
                arr = np.array(rows, dtype=np.int64).reshape(-1, 3)
                out[cid] = (arr[:, 0], arr[:, 1], arr[:, 2])
            return out
        limit = buf.size
        for cid in wanted & set(chunk.message_indexes):
            pairs = self._indexed_offsets(chunk, cid)
            offsets = pairs[:, 1].astype(np.int64)
            order = np.argsort(offsets, kind="stable")
            offsets, index_log = offsets[order], pairs[order, 0].astype(np.int64)
            ok = (offsets >= 0) & (offsets + 9 + _MSG_HEAD <= limit)
            safe = np.where(ok, offsets, 0)
            lengths = _gather(buf, safe + 1, "<u8").astype(np.int64)
            ok &= (buf[safe] == _OP_MESSAGE) & (lengths >= _MSG_HEAD) & (safe + 9 + lengths <= limit)
            ok &= _gather(buf, safe + 9, "<u2") == cid
            ok &= _gather(buf, safe + 15, "<u8").astype(np.int64) == index_log
            if not ok.all():
                self.problems.append(f"{self.path}: chunk at offset {chunk.offset}: {np.count_nonzero(~ok)} "
                                     f"indexed records of channel {cid} damaged, skipped")
            out[cid] = (offsets[ok], lengths[ok], index_log[ok])
        return out

    def close(self) -> None:
        self.file.close()


def _gather(u8: np.ndarray, pos: np.ndarray, fmt: str) -> np.ndarray:
    """Values of ``fmt`` starting at byte positions ``pos`` of ``u8`` (positions must be in range)."""
    width = np.dtype(fmt).itemsize
    return u8[pos[:, None] + np.arange(width)].view(fmt).ravel()


def open_storage(path: Path, storage: str) -> Storage:
    """The storage file ``path`` of a bag whose metadata names ``storage`` (sqlite3 or mcap)."""
    if not path.is_file():
        raise InputError(f"{path}: storage file missing")
    return SqliteStorage(path) if storage == "sqlite3" else McapStorage(path)
