"""Bulk reader of the input topics (interface.md section 2) from rosbag2 bags, sqlite3 or mcap.

The result is, per unit (namespace, derived from the topic names:
``/ns/screw/angle`` -> unit ``/ns``) and per signal (``angle``, ``velocity``,
``axial_force``, ``current``), two numpy arrays: header stamps [s] and values
[SI], in the order the messages were recorded (receive order; the monitor core
deals with late, duplicated and interleaved samples itself). Several bags of a
unit are concatenated in time order of their first message.

Speed: raw records are pulled from rosbags in blocks and decoded in bulk with
``bagio.cdr`` (no Python object per message). Python's cyclic garbage collector
is paused while records stream in: each block holds 65,536 fresh tuples, which
would trigger a collection every 700 allocations and cost about 40 % of the read
time, while nothing in this loop can form a reference cycle.

Errors (all :class:`~ebm_wear_monitor.errors.InputError`, one line, naming the bag):
a path that is not a rosbag2 bag, an unknown storage plugin, a truncated or
corrupt file, a bag with no input topic of type ``ebm_wear_msgs/msg/Float64Stamped``.
An input topic name carrying another type (or another definition of that type)
is not fatal when other input topics are fine: its messages are skipped and
counted in :attr:`Recording.rejected`, which the replay reports.
"""

from __future__ import annotations

import gc
import os
import threading
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from itertools import islice
from pathlib import Path

import numpy as np
import yaml
from rosbags.rosbag2 import Reader

from ebm_wear_monitor.bagio.cdr import decode_float64_stamped
from ebm_wear_monitor.bagio.topics import split_topic
from ebm_wear_monitor.bagio.types import FLOAT64_STAMPED, typestore
from ebm_wear_monitor.bagio.writer import STORAGES
from ebm_wear_monitor.errors import InputError

#: messages pulled from rosbags per bulk decode (bounds the memory of raw records)
BLOCK = 1 << 16


@dataclass(frozen=True)
class Signal:
    """One input signal of one unit: header stamps [s] and values [SI unit of the topic]."""

    stamps: np.ndarray
    values: np.ndarray


@dataclass
class UnitData:
    """Everything read for one unit (namespace): its signals and the bags they came from (time order)."""

    unit: str
    signals: dict[str, Signal]
    bags: list[Path]

    @property
    def messages(self) -> int:
        """Number of input messages of this unit."""
        return sum(len(s.stamps) for s in self.signals.values())


@dataclass
class Recording:
    """The input topics of one or more bags, per unit; plus what was skipped and why."""

    units: dict[str, UnitData] = field(default_factory=dict)
    #: "<bag>: <topic>" -> reason, for input topic names with a wrong type (messages skipped)
    rejected: dict[str, str] = field(default_factory=dict)

    @property
    def messages(self) -> int:
        """Number of input messages read."""
        return sum(u.messages for u in self.units.values())


@dataclass
class _BagData:
    path: Path
    start_ns: int
    chunks: dict[tuple[str, str], list[tuple[np.ndarray, np.ndarray]]]


def _open(path: Path) -> Reader:
    try:
        exists, has_meta = path.exists(), (path / "metadata.yaml").is_file()
    except OSError as exc:  # e.g. a chmod 000 bag directory
        raise InputError(f"{path}: cannot read the bag ({exc.strerror or exc})") from None
    if not exists:
        raise InputError(f"{path}: no such bag")
    meta = path / "metadata.yaml"
    if has_meta:
        storage = _storage_identifier(meta)
        if storage not in STORAGES:
            raise InputError(f"{path}: unknown bag storage {storage!r} (readable: {', '.join(STORAGES)})")
    try:
        reader = Reader(path)
        reader.open()
    except FileNotFoundError:
        raise InputError(f"{path}: not a rosbag2 bag (no metadata.yaml)") from None
    except Exception as exc:  # rosbags, sqlite, yaml and OS errors alike mean an unreadable bag
        raise InputError(f"{path}: unreadable bag: {_reason(exc)}") from exc
    return reader


def _storage_identifier(meta: Path) -> str:
    try:
        data = yaml.safe_load(meta.read_text(encoding="utf-8"))
    except Exception as exc:  # unreadable file or malformed YAML: not a usable rosbag2 metadata file
        raise InputError(f"{meta}: invalid rosbag2 metadata: {_reason(exc)}") from exc
    info = data.get("rosbag2_bagfile_information") if isinstance(data, dict) else None
    if not isinstance(info, dict) or "storage_identifier" not in info:
        raise InputError(f"{meta}: not a rosbag2 metadata file "
                         "(no rosbag2_bagfile_information.storage_identifier)")
    return str(info["storage_identifier"])


def _reason(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) < 200 else text[:197] + "..."


def _select(reader: Reader, path: Path, rejected: dict[str, str]) -> dict[int, tuple[str, str]]:
    """Connection id -> (unit, signal) of the acceptable input connections; wrong types go to ``rejected``."""
    digest = typestore().hash_rihs01(FLOAT64_STAMPED)
    chosen: dict[int, tuple[str, str]] = {}
    for conn in reader.connections:
        key = split_topic(conn.topic)
        if key is None:
            continue
        where = f"{path}: {conn.topic}"
        if conn.msgtype != FLOAT64_STAMPED:
            rejected[where] = f"type {conn.msgtype}, expected {FLOAT64_STAMPED}"
        elif conn.digest and conn.digest.startswith("RIHS01_") and conn.digest != digest:
            rejected[where] = f"{FLOAT64_STAMPED} with another definition ({conn.digest[:15]}...)"
        elif conn.ext.serialization_format != "cdr":
            rejected[where] = f"serialization {conn.ext.serialization_format!r}, expected cdr"
        else:
            chosen[conn.id] = key
    if not chosen:
        found = "; ".join(f"{c.topic} ({c.msgtype})" for c in reader.connections) or "no topics"
        raise InputError(f"{path}: no input topic of type {FLOAT64_STAMPED} (found: {found})")
    return chosen


_gc_lock = threading.Lock()
_gc_pausers = 0
_gc_was_enabled = False


@contextmanager
def _cyclic_gc_paused() -> Iterator[None]:
    """Pause the cyclic garbage collector; thread-safe (re-enabled when the last reader leaves)."""
    global _gc_pausers, _gc_was_enabled  # noqa: PLW0603 -- process-wide like the collector itself
    with _gc_lock:
        if _gc_pausers == 0:
            _gc_was_enabled = gc.isenabled()
            gc.disable()
        _gc_pausers += 1
    try:
        yield
    finally:
        with _gc_lock:
            _gc_pausers -= 1
            if _gc_pausers == 0 and _gc_was_enabled:
                gc.enable()


def _read_bag(path: Path, rejected: dict[str, str], progress: Callable[[int], object] | None) -> _BagData:
    reader = _open(path)
    try:
        chosen = _select(reader, path, rejected)
        conns = [c for c in reader.connections if c.id in chosen]
        chunks: dict[tuple[str, str], list[tuple[np.ndarray, np.ndarray]]] = {k: [] for k in chosen.values()}
        with _cyclic_gc_paused():
            messages = reader.messages(conns)
            while block := list(islice(messages, BLOCK)):
                ids = np.fromiter((m[0].id for m in block), dtype=np.int64, count=len(block))
                stamps, values = decode_float64_stamped([m[2] for m in block])
                for cid, key in chosen.items():
                    mask = ids == cid
                    if mask.any():
                        chunks[key].append((stamps[mask], values[mask]))
                if progress is not None:
                    progress(len(block))
        return _BagData(path, reader.start_time, chunks)
    except InputError:
        raise
    except Exception as exc:  # any failure while reading records: truncated or corrupt storage
        raise InputError(f"{path}: corrupt or truncated bag: {_reason(exc)}") from exc
    finally:
        reader.close()


def read_bags(paths: Iterable[str | os.PathLike], progress: Callable[[int], object] | None = None,
              failed: dict[str, str] | None = None) -> Recording:
    """Read the input topics of ``paths`` (rosbag2 directories or .mcap/.db3 files) per unit.

    Bags are concatenated per unit in order of their first message. ``progress(n)``
    is called after every block of ``n`` messages (e.g. ``tqdm.update``). Without
    ``failed`` the first bad bag raises :class:`InputError`; with it, bad bags are
    skipped and their one-line reasons stored in ``failed[str(path)]``.
    """
    recording = Recording()
    bags = []
    seen: set[Path] = set()
    for p in paths:
        if Path(p).resolve() in seen:  # its messages would be fed twice, as duplicates and late ones
            raise InputError(f"{p}: bag given twice")
        seen.add(Path(p).resolve())
        try:
            bags.append(_read_bag(Path(p), recording.rejected, progress))
        except InputError as exc:
            if failed is None:
                raise
            failed[str(p)] = str(exc)
    bags.sort(key=lambda b: b.start_ns)
    keys = sorted({k for b in bags for k in b.chunks})
    for unit in sorted({u for u, _ in keys}):
        signals: dict[str, Signal] = {}
        for _, signal in (k for k in keys if k[0] == unit):
            parts = [c for b in bags for c in b.chunks.get((unit, signal), [])]
            signals[signal] = Signal(np.concatenate([p[0] for p in parts] or [np.empty(0)]),
                                     np.concatenate([p[1] for p in parts] or [np.empty(0)]))
        sources = [b.path for b in bags if any(k[0] == unit for k in b.chunks)]
        recording.units[unit] = UnitData(unit, signals, sources)
    return recording


def bag_message_count(paths: Sequence[str | os.PathLike]) -> int:
    """Total number of messages of ``paths`` from their metadata (for progress bars)."""
    total = 0
    for p in paths:
        reader = _open(Path(p))
        try:
            total += reader.message_count
        finally:
            reader.close()
    return total
