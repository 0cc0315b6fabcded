"""Streaming reader of the input topics (interface.md section 2) from rosbag2 bags, sqlite3 or mcap.

:class:`BagReader` opens every bag (``metadata.yaml`` and its storage files,
:mod:`.storage`), picks the input topics per unit (namespace, derived from the
topic names: ``/ns/screw/angle`` -> unit ``/ns``) and yields, chunk by chunk,
one :class:`~ebm_wear_monitor.monitor.wire.Batch` per unit: per signal the
header stamps [ns] (int64, exact) or, with ``stamps="log"``, the bag's log
times, and the values, in storage order (the order the recorder received them:
late, duplicated and interleaved samples reach the core as they were
recorded). Memory is bounded by a few storage chunks, whatever the length:
sqlite3 storage is read a few chunks ahead by a worker thread (:mod:`.ahead`).

Storage files are read one after the other in order of their first log time.
When the files of a unit overlap in log time (two recorders), they are merged
by log time instead, record by record: every file is read a chunk ahead and
what all of them have passed is emitted in log-time order.

Records decode in bulk through :mod:`ebm_wear_monitor.monitor.wire` (the
node's decoder); a record whose layout the bulk path does not recognise goes
through rosbags' general deserializer, and one that neither decodes is counted
``undecodable`` (the node does the same). What the storage lost is counted as
well: the reader compares what it read per topic with ``metadata.yaml``'s and
the storage index's message counts and counts the difference ``lost`` (one
line per damaged place in :attr:`BagReader.problems`); ``strict=True`` makes
any such damage an :class:`~ebm_wear_monitor.errors.InputError` instead.

Errors (all :class:`InputError`, one line, naming the bag): a path that is not
a rosbag2 bag, an unknown storage or compression, an unreadable storage file,
a bag with no input topic of type ``ebm_wear_msgs/msg/Float64Stamped``, a bag
none of whose input records decodes. An input topic name carrying another type
(or another definition of that type) is not fatal when other input topics are
fine: it is skipped and listed in :attr:`BagReader.rejected`.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Generator, Iterable, Iterator, Sequence
from contextlib import ExitStack, closing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from ebm_wear_monitor.bagio.ahead import read_ahead, spare_core
from ebm_wear_monitor.bagio.storage import Chunk, Records, Storage, open_storage
from ebm_wear_monitor.domain.recording import Recording, Signal
from ebm_wear_monitor.domain.signals import FLOAT64_STAMPED, INPUT_TOPICS, split_topic
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor.wire import Batch, Decoded, decode_uniform, stamp_ns

STORAGE_SUFFIX = {".db3": "sqlite3", ".mcap": "mcap"}


def _reason(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) < 200 else text[:197] + "..."


@dataclass
class _Bag:
    path: Path
    storage: str
    files: list[Path]
    expected: dict[str, int]  # topic -> message count of metadata.yaml


#: libyaml's safe loader when PyYAML was built with it (5.8 -> 0.65 ms on a foreign bag's metadata.yaml), else
#: the pure-Python one: both construct plain Python objects only
_YAML_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def _metadata(path: Path) -> _Bag:
    """The bag at ``path``: a rosbag2 directory (its metadata.yaml) or a bare .db3/.mcap file."""
    meta = path / "metadata.yaml"
    try:
        exists, is_file, has_meta = path.exists(), path.is_file(), meta.is_file()
    except OSError as exc:  # e.g. a chmod 000 bag directory
        raise InputError(f"{path}: cannot read the bag ({exc.strerror or exc})") from None
    if not exists:
        raise InputError(f"{path}: no such bag")
    if is_file and path.suffix in STORAGE_SUFFIX:
        return _Bag(path, STORAGE_SUFFIX[path.suffix], [path], {})
    if not has_meta:
        raise InputError(f"{path}: not a rosbag2 bag (no metadata.yaml)")
    try:
        data = yaml.load(meta.read_text(encoding="utf-8"), Loader=_YAML_LOADER)
    except Exception as exc:  # unreadable file or malformed YAML: not a usable rosbag2 metadata file
        raise InputError(f"{meta}: invalid rosbag2 metadata: {_reason(exc)}") from exc
    info = data.get("rosbag2_bagfile_information") if isinstance(data, dict) else None
    if not isinstance(info, dict) or "storage_identifier" not in info:
        raise InputError(f"{meta}: not a rosbag2 metadata file "
                         "(no rosbag2_bagfile_information.storage_identifier)")
    storage = str(info["storage_identifier"])
    if storage not in STORAGE_SUFFIX.values():
        raise InputError(f"{path}: unknown bag storage {storage!r} (readable: sqlite3, mcap)")
    if info.get("compression_mode"):
        raise InputError(f"{path}: compressed bag (compression_mode {info['compression_mode']!r}) "
                         "not supported; decompress it first (chunk compression of mcap is fine)")
    files = [path / str(f) for f in info.get("relative_file_paths") or []]
    expected = {}
    for entry in info.get("topics_with_message_count") or []:
        try:
            expected[str(entry["topic_metadata"]["name"])] = int(entry["message_count"])
        except (KeyError, TypeError, ValueError):
            continue
    if not files:
        raise InputError(f"{meta}: lists no storage file")
    return _Bag(path, storage, files, expected)


@dataclass
class _Source:
    """One opened storage file and the input connections chosen from it."""

    bag: _Bag
    store: Storage
    chosen: dict[int, tuple[str, str]]  # connection id -> (unit, signal)


def _type_digest() -> str:
    from ebm_wear_monitor.bagio.types import typestore

    return typestore().hash_rihs01(FLOAT64_STAMPED)


class BagReader:
    """Open ``paths`` (rosbag2 directories or .mcap/.db3 files) and stream their input topics per unit.

    Args:
        paths: bags; several bags of a unit are read in order of their first message.
        signals: signals to read (default: all four input topics).
        stamps: ``"header"`` (header.stamp, the sample time: interface.md section 2) or ``"log"``
            (the bag's log/receive time, for recordings with unusable header stamps).
        strict: damage found in a storage (lost messages) raises instead of being counted.
        failed: when given, bags that cannot be opened are skipped and their one-line reasons
            stored here (``failed[str(path)]``); otherwise the first one raises.
        read_ahead: chunks each storage is read ahead by a worker thread (:mod:`.ahead`) where its
            reads run outside the interpreter lock (sqlite3) and the process may use a second core;
            0 reads in the caller's thread (for a process that already has every core busy: a fleet
            worker).
    """

    def __init__(self, paths: Iterable[str | os.PathLike], *, signals: Iterable[str] | None = None,
                 stamps: str = "header", strict: bool = False, failed: dict[str, str] | None = None,
                 read_ahead: int = 2):
        if stamps not in ("header", "log"):
            raise InputError(f"stamps must be 'header' or 'log', got {stamps!r}")
        self.signals = set(INPUT_TOPICS if signals is None else signals)
        self.log_stamps = stamps == "log"
        self.strict = strict
        self.read_ahead = read_ahead
        #: "<bag>: <topic>" -> reason, for input topic names with a wrong type (skipped)
        self.rejected: dict[str, str] = {}
        #: one line per damaged place found in a storage, and per topic with lost messages
        self.problems: list[str] = []
        self.sources: list[_Source] = []
        self._streams: list[Generator[Chunk, None, None]] = []  # read-ahead streams opened by batches()
        seen: set[Path] = set()
        try:
            for p in paths:
                path = Path(p)
                if path.resolve() in seen:  # its messages would be fed twice, as duplicates and late ones
                    raise InputError(f"{p}: bag given twice")
                seen.add(path.resolve())
                try:
                    self.sources += self._open(path)
                except InputError as exc:
                    if failed is None:
                        raise
                    failed[str(p)] = str(exc)
        except BaseException:
            self.close()
            raise
        self.sources.sort(key=lambda s: s.store.start_ns)
        #: unit -> bags holding its topics, in time order
        self.units: dict[str, list[Path]] = {}
        for src in self.sources:
            for unit, _ in src.chosen.values():
                bags = self.units.setdefault(unit, [])
                if src.bag.path not in bags:
                    bags.append(src.bag.path)
        self.units = dict(sorted(self.units.items()))
        #: progress units of all storages (row ids or indexed messages), known before reading
        self.total = sum(s.store.total for s in self.sources)
        self._read: dict[tuple[Path, str], int] = {}  # (bag, topic) -> records read
        self._decoded: dict[Path, int] = {}

    # ------------------------------------------------------------------ opening
    def _open(self, path: Path) -> list[_Source]:
        bag = _metadata(path)
        sources = []
        try:
            for file in bag.files:
                store = open_storage(file, bag.storage)
                sources.append(_Source(bag, store, {}))
            digest = _type_digest()
            chosen_any = False
            for src in sources:
                src.chosen = self._select(src.store, path, digest)
                chosen_any |= bool(src.chosen)
            if not chosen_any:
                found = "; ".join(sorted({f"{c.topic} ({c.msgtype})" for s in sources
                                          for c in s.store.connections})) or "no topics"
                raise InputError(f"{path}: no input topic of type {FLOAT64_STAMPED} (found: {found})")
        except BaseException:
            for src in sources:
                src.store.close()
            raise
        return sources

    def _select(self, store: Storage, path: Path, digest: str) -> dict[int, tuple[str, str]]:
        chosen = {}
        for conn in store.connections:
            key = split_topic(conn.topic)
            if key is None or key[1] not in self.signals:
                continue
            where = f"{path}: {conn.topic}"
            if conn.msgtype != FLOAT64_STAMPED:
                self.rejected[where] = f"type {conn.msgtype}, expected {FLOAT64_STAMPED}"
            elif conn.digest.startswith("RIHS01_") and conn.digest != digest:
                self.rejected[where] = f"{FLOAT64_STAMPED} with another definition ({conn.digest[:15]}...)"
            elif conn.serialization != "cdr":
                self.rejected[where] = f"serialization {conn.serialization!r}, expected cdr"
            else:
                chosen[conn.id] = key
        return chosen

    def close(self) -> None:
        """Stop the read-ahead workers still running (a ``batches`` iteration left unfinished), then close
        every storage file (a worker never reads a closed one)."""
        for stream in self._streams:
            stream.close()
        self._streams = []
        for src in self.sources:
            src.store.close()

    def __enter__(self) -> BagReader:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------ reading
    def batches(self, progress: Callable[[int], object] | None = None) -> Iterator[dict[str, Batch]]:
        """Yield ``{unit: Batch}`` chunk by chunk; the last one carries the ``lost`` counts of each topic."""
        for group in self._groups():
            chunks = self._merged(group) if len(group) > 1 else self._plain(group[0])
            for batches, n in chunks:
                if progress is not None and n:
                    progress(n)
                if batches:
                    yield batches
        lost = self._reconcile()
        for bag, decoded in self._decoded.items():
            read = sum(n for (b, _), n in self._read.items() if b == bag)
            if read and not decoded:
                raise InputError(f"{bag}: corrupt: none of its {read} input records decodes")
        if self.strict and self.problems:
            n = sum(k for b in lost.values() for per in b.faults.values() for k in per.values())
            more = f" (and {len(self.problems) - 1} more problems)" if len(self.problems) > 1 else ""
            raise InputError(f"damaged storage, {n} messages lost: {self.problems[0]}{more}")
        if lost:
            yield lost

    def _groups(self) -> list[list[_Source]]:
        """Sources in time order; those overlapping in log time (and sharing a unit) grouped for merging."""
        groups: list[list[_Source]] = []
        for src in self.sources:
            units = {u for u, _ in src.chosen.values()}
            last = groups[-1] if groups else None
            if (last and units & {u for s in last for u, _ in s.chosen.values()}
                    and src.store.start_ns <= max(s.store.end_ns for s in last)):
                last.append(src)
            else:
                groups.append([src])
        return groups

    def _stream(self, src: _Source, log_time: bool) -> Generator[Chunk, None, None]:
        """The chunks of ``src``, read ahead where that helps (:meth:`_depth`); :meth:`close` stops it."""
        stream = read_ahead(src.store.chunks(set(src.chosen), log_time), self._depth(src))
        self._streams.append(stream)
        return stream

    def _plain(self, src: _Source) -> Iterator[tuple[dict[str, Batch], int]]:
        with closing(self._stream(src, self.log_stamps)) as chunks:  # an early stop stops the worker
            for chunk in chunks:
                yield self._decode_chunk(src, chunk)[0], chunk.progress
        self.problems += src.store.problems
        src.store.problems = []

    def _depth(self, src: _Source) -> int:
        """Chunks to read ahead of the caller: only where the storage reads outside the interpreter lock
        and a second core can do it (:func:`~.ahead.spare_core`)."""
        return self.read_ahead if src.store.reads_outside_lock and spare_core() else 0

    def _merged(self, group: list[_Source]) -> Iterator[tuple[dict[str, Batch], int]]:
        """Records of overlapping sources, merged by log time (each source's own order kept)."""
        with ExitStack() as stack:  # an early stop of the caller stops every read-ahead worker
            streams = [stack.enter_context(closing(self._stream(s, True))) for s in group]
            yield from self._merge(group, streams)
        for src in group:
            self.problems += src.store.problems
            src.store.problems = []

    def _merge(self, group: list[_Source], streams: Sequence[Iterator[Chunk]]
               ) -> Iterator[tuple[dict[str, Batch], int]]:
        """The merge of :meth:`_merged` over each source's chunk stream."""
        pending: list[dict[tuple[str, str], tuple[np.ndarray, ...]]] = [{} for _ in group]
        newest = [np.iinfo(np.int64).min] * len(group)
        alive = [True] * len(group)
        while any(alive):
            progress = 0
            out: dict[str, Batch] = {}
            for i, src in enumerate(group):
                if alive[i] and not any(a[0].size for a in pending[i].values()):
                    chunk = next(streams[i], None)
                    if chunk is None:
                        alive[i] = False
                        continue
                    progress += chunk.progress
                    batches, decoded = self._decode_chunk(src, chunk)
                    for unit, batch in batches.items():  # undecodable counts go out at once
                        for signal, per in batch.faults.items():
                            for kind, n in per.items():
                                out.setdefault(unit, Batch()).count(signal, kind, n)
                    for key, arrays in decoded.items():
                        pending[i][key] = arrays
                        if arrays[0].size:
                            newest[i] = max(newest[i], int(arrays[2].max()))
            # everything at or before the oldest newest log time of the live sources is complete
            horizon = min((newest[i] for i in range(len(group)) if alive[i]), default=np.iinfo(np.int64).max)
            parts: dict[tuple[str, str], list[tuple[np.ndarray, ...]]] = {}
            for i in range(len(group)):
                for key, (stamps, values, log) in pending[i].items():
                    take = log <= horizon
                    parts.setdefault(key, []).append((stamps[take], values[take], log[take]))
                    pending[i][key] = (stamps[~take], values[~take], log[~take])
            for (unit, signal), pieces in parts.items():
                order = np.argsort(np.concatenate([a[2] for a in pieces]), kind="stable")
                out.setdefault(unit, Batch()).add(signal, np.concatenate([a[0] for a in pieces])[order],
                                                  np.concatenate([a[1] for a in pieces])[order])
            yield out, progress

    def _decode_chunk(self, src: _Source, chunk: Chunk
                      ) -> tuple[dict[str, Batch], dict[tuple[str, str], tuple[np.ndarray, ...]]]:
        """Decode a chunk: per unit a Batch, and per (unit, signal) (stamps, values, log times)."""
        batches: dict[str, Batch] = {}
        arrays: dict[tuple[str, str], tuple[np.ndarray, ...]] = {}
        for cid, records in chunk.records.items():
            unit, signal = src.chosen[cid]
            decoded = self._decode(records)
            topic = next(c.topic for c in src.store.connections if c.id == cid)
            key = (src.bag.path, topic)
            self._read[key] = self._read.get(key, 0) + records.count
            good = decoded.ok
            self._decoded[src.bag.path] = self._decoded.get(src.bag.path, 0) + int(good.sum())
            log = records.log_ns if records.log_ns is not None else np.zeros(good.size, np.int64)
            stamps = log if self.log_stamps else decoded.stamps_ns  # (log times are read when asked for)
            batch = batches.setdefault(unit, Batch())
            batch.add(signal, stamps[good], decoded.values[good])
            batch.count(signal, "undecodable", int(good.size - good.sum()))
            arrays[(unit, signal)] = (stamps[good], decoded.values[good], log[good])
        return batches, arrays

    @staticmethod
    def _decode(records: Records) -> Decoded:
        """Decode every record (bulk; rosbags' general deserializer for what bulk does not recognise)."""
        parts = [(pos, decode_uniform(rows.reshape(-1), rows.shape[1]), rows) for pos, rows in records.groups]
        if len(parts) == 1 and parts[0][0].size == records.count:
            pos, out, rows = parts[0]
            _fallback(out, rows)
            return out
        n = records.count
        out = Decoded(np.empty(n, np.int64), np.empty(n), np.empty(n, bool))
        for pos, part, rows in parts:
            _fallback(part, rows)
            out.stamps_ns[pos], out.values[pos], out.ok[pos] = part.stamps_ns, part.values, part.ok
        return out

    def _reconcile(self) -> dict[str, Batch]:
        """``lost`` per unit and signal: messages metadata.yaml or the storage index promise but not read."""
        lost: dict[str, Batch] = {}
        by_bag: dict[Path, list[_Source]] = {}
        for src in self.sources:
            by_bag.setdefault(src.bag.path, []).append(src)
        for path, sources in by_bag.items():
            bag = sources[0].bag
            for topic, (unit, signal) in {c.topic: src.chosen[c.id] for src in sources
                                           for c in src.store.connections if c.id in src.chosen}.items():
                indexed = [c.indexed for s in sources for c in s.store.connections
                           if c.topic == topic and c.indexed is not None]
                promised = [n for n in (bag.expected.get(topic), sum(indexed) if indexed else None)
                            if n is not None]
                read = self._read.get((path, topic), 0)
                missing = max(promised, default=read) - read
                if len(set(promised)) > 1:
                    self.problems.append(f"{path}: {topic}: metadata.yaml counts {promised[0]} messages, the "
                                         f"storage index {promised[1]}")
                if missing > 0:
                    self.problems.append(f"{path}: {topic}: {missing} of {max(promised)} messages lost")
                    lost.setdefault(unit, Batch()).count(signal, "lost", missing)
        return lost


def _fallback(decoded: Decoded, rows: np.ndarray) -> None:
    """Records the bulk decoder did not recognise, through rosbags' general deserializer (in place)."""
    if decoded.ok.all():
        return
    from ebm_wear_monitor.bagio.types import typestore

    store = typestore()
    for i in np.flatnonzero(~decoded.ok).tolist():
        try:
            msg: Any = store.deserialize_cdr(rows[i].tobytes(), FLOAT64_STAMPED)  # a class made at run time
        except Exception:  # any deserializer failure means an undecodable record
            continue
        decoded.stamps_ns[i] = int(stamp_ns(msg.header.stamp.sec, msg.header.stamp.nanosec))
        decoded.values[i] = msg.data
        decoded.ok[i] = True


def bag_message_count(paths: Iterable[str | os.PathLike]) -> int:
    """Progress units of ``paths`` from the storages' own indexes (no counting pass): the total to give
    a progress bar fed by :meth:`BagReader.batches` or :func:`read_bags`."""
    with BagReader(paths) as reader:
        return reader.total


# ---------------------------------------------------------------------------------------------- whole
@dataclass
class BagRecordings:
    """The input topics of one or more bags, one :class:`~ebm_wear_monitor.domain.recording.Recording`
    per unit; plus what was skipped and why."""

    units: dict[str, Recording] = field(default_factory=dict)
    #: "<bag>: <topic>" -> reason, for input topic names with a wrong type (messages skipped)
    rejected: dict[str, str] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)

    @property
    def messages(self) -> int:
        """Number of input messages read."""
        return sum(u.messages for u in self.units.values())


def read_bags(paths: Iterable[str | os.PathLike], progress: Callable[[int], object] | None = None,
              failed: dict[str, str] | None = None, **options: object) -> BagRecordings:
    """Read the input topics of ``paths`` whole, per unit (for the diagnosis, the player and tests).

    ``options`` are those of :class:`BagReader` (``signals``, ``stamps``, ``strict``, ``read_ahead``).
    The replay streams instead (:class:`BagReader`), in bounded memory.
    """
    with BagReader(paths, failed=failed, **options) as reader:  # type: ignore[arg-type]
        parts: dict[str, dict[str, list[tuple[np.ndarray, np.ndarray]]]] = {u: {} for u in reader.units}
        for src in reader.sources:  # every input topic of the bags, even one without messages
            for unit, signal in src.chosen.values():
                parts[unit].setdefault(signal, [(np.empty(0, np.int64), np.empty(0))])
        faults: dict[str, dict[str, dict[str, int]]] = {u: {} for u in reader.units}
        for batches in reader.batches(progress):
            for unit, batch in batches.items():
                for signal, arrays in batch.signals.items():
                    parts[unit].setdefault(signal, []).append(arrays)
                for signal, per in batch.faults.items():
                    for kind, n in per.items():
                        mine = faults[unit].setdefault(signal, {})
                        mine[kind] = mine.get(kind, 0) + n
        recording = BagRecordings(rejected=dict(reader.rejected), problems=list(reader.problems))
        for unit, bags in reader.units.items():
            signals = {s: Signal(np.concatenate([a[0] for a in p]), np.concatenate([a[1] for a in p]))
                       for s, p in sorted(parts[unit].items())}
            recording.units[unit] = Recording(unit, signals, bags, faults[unit])
    return recording
