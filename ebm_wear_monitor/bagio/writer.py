"""Write the input topics of interface.md section 2 into a rosbag2 bag (sqlite3 or mcap) from numpy arrays.

Each sample becomes one ``ebm_wear_msgs/msg/Float64Stamped`` whose
``header.stamp`` is its sample time; the bag (receive) timestamp is the sample
time too unless receive times are given (to record late, interleaved or
duplicated delivery). Messages of all topics are written in receive-time order,
as a recorder would (within each block given to :meth:`BagWriter.write`).
Serialisation is bulk (:mod:`ebm_wear_monitor.monitor.wire`); the writing itself
is rosbags', so the files are rosbag2 files of an independent writer. The bag is
built in a temporary sibling directory and renamed into place, so a failed write
never leaves a half-written bag behind.

Times: int64 arrays are nanoseconds (exact); float arrays are seconds (rounded to 1 ns).
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import NamedTuple

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer

from ebm_wear_monitor.bagio.sidecar import GROUND_TRUTH_FILE
from ebm_wear_monitor.bagio.types import typestore
from ebm_wear_monitor.domain.signals import FLOAT64_STAMPED, INPUT_TOPICS, check_namespace, topic_name
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor.wire import encode

#: storage names accepted by the writer (the ``storage_identifier`` of rosbag2)
STORAGES: dict[str, StoragePlugin] = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}


def _ns(times: np.ndarray) -> np.ndarray:
    """int64 ns from int64 ns (as is) or float seconds (rounded)."""
    times = np.asarray(times)
    return times.astype(np.int64) if times.dtype.kind in "iu" else np.rint(times * 1e9).astype(np.int64)


class Series(NamedTuple):
    """One signal with its own sample times: header stamps, values [SI], optional receive times.

    Times as int64 ns or float s (module docstring)."""

    stamps: np.ndarray
    values: np.ndarray
    received: np.ndarray | None = None


def _series(value: np.ndarray | Series, t: np.ndarray | None, where: str) -> Series:
    series = value if isinstance(value, Series) else Series(t, value) if t is not None else None
    if series is None:
        raise InputError(f"{where}: no sample times (give t or a Series)")
    stamps, values = np.asarray(series.stamps), np.asarray(series.values, float)
    received = stamps if series.received is None else np.asarray(series.received)
    if not stamps.shape == values.shape == received.shape or stamps.ndim != 1:
        raise InputError(f"{where}: stamps, values and receive times must be 1-D arrays of one length")
    finite = all(t.dtype.kind in "iu" or np.all(np.isfinite(t)) for t in (stamps, received))
    if not finite or stamps.min(initial=0) < 0 or np.abs(received).max(initial=0) > 9.2e18:
        raise InputError(f"{where}: sample and receive times must be finite and >= 0 s")
    return Series(_ns(stamps), values, _ns(received))


class BagWriter:
    """A bag written block by block (bounded memory for long recordings); ``close()`` puts it in place.

    ``BagWriter(path, topics, storage="mcap", frame_id="")`` with ``topics`` the (namespace, signal)
    pairs it will hold; ``write({(namespace, signal): Series})`` writes one block in receive-time
    order; ``close(ground_truth=None)`` finishes and renames it into place, returning the message count.
    """

    def __init__(self, path: str | os.PathLike, topics: list[tuple[str, str]], *, storage: str = "mcap",
                 frame_id: str = "") -> None:
        self.path = Path(path)
        if storage not in STORAGES:
            raise InputError(f"unknown bag storage {storage!r}; use one of {', '.join(STORAGES)}")
        if self.path.exists():
            raise InputError(f"{self.path} exists already; not overwriting a bag")
        for ns, signal in topics:
            check_namespace(ns)
            if signal not in INPUT_TOPICS:
                raise InputError(f"unknown signal {signal!r}; use one of {', '.join(INPUT_TOPICS)}")
        self.frame_id = frame_id
        self.messages = 0
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._tmp = Path(tempfile.mkdtemp(prefix=f".{self.path.name}.", dir=self.path.parent))
        except OSError as exc:
            raise InputError(f"{self.path}: cannot write a bag there ({exc.strerror or exc})") from exc
        try:
            self._writer = Writer(self._tmp / self.path.name, version=9, storage_plugin=STORAGES[storage])
            self._writer.open()
            self._conns = {key: self._writer.add_connection(topic_name(*key), FLOAT64_STAMPED,
                                                            typestore=typestore()) for key in topics}
        except BaseException:
            shutil.rmtree(self._tmp, ignore_errors=True)
            raise

    def write(self, block: Mapping[tuple[str, str], Series]) -> None:
        """Write one block of samples, all its topics merged by receive time (stable)."""
        block = {k: _series(v, None, f"{k[0]} {k[1]}") for k, v in block.items()}
        keys = list(block)
        received = np.concatenate([block[k].received for k in keys] or [np.empty(0, np.int64)])
        which = np.concatenate([np.full(len(block[k].values), i) for i, k in enumerate(keys)]
                               or [np.empty(0, int)])
        buffers = [encode(block[k].stamps, block[k].values, self.frame_id) for k in keys]
        starts = np.concatenate([[0], np.cumsum([len(block[k].values) for k in keys])])
        order = np.argsort(received, kind="stable")
        write, conns = self._writer.write, [self._conns[k] for k in keys]
        for i, stamp in zip(order.tolist(), received[order].tolist(), strict=True):
            w = int(which[i])
            buf, size = buffers[w]
            j = i - int(starts[w])
            write(conns[w], stamp, buf[j * size:(j + 1) * size])
        self.messages += int(order.size)

    def close(self, ground_truth: Mapping | None = None) -> int:
        """Finish the bag (with ``ground_truth.json`` if given) and rename it into place."""
        try:
            self._writer.close()
            if ground_truth is not None:
                (self._tmp / self.path.name / GROUND_TRUTH_FILE).write_text(json.dumps(ground_truth),
                                                                           encoding="utf-8")
            (self._tmp / self.path.name).rename(self.path)
        finally:
            shutil.rmtree(self._tmp, ignore_errors=True)
        return self.messages

    def abort(self) -> None:
        """Drop the half-written bag."""
        with contextlib.suppress(Exception):  # already broken: nothing to keep anyway
            self._writer.abort()
        shutil.rmtree(self._tmp, ignore_errors=True)


def write_unit_bag(
    path: str | os.PathLike,
    t: np.ndarray | Mapping[str, np.ndarray] | None,
    signals_by_namespace: Mapping[str, Mapping[str, np.ndarray | Series]],
    *,
    storage: str = "mcap",
    frame_id: str = "",
    ground_truth: Mapping | None = None,
) -> int:
    """Write one bag holding the input topics of one or more units; returns the number of messages.

    Args:
        path: bag directory to create (must not exist).
        t: sample times (float s or int64 ns) shared by every signal, or a mapping namespace ->
            sample times, or None when every signal is a :class:`Series`.
        signals_by_namespace: ``{namespace: {signal: values | Series}}`` with signal names
            ``angle`` [rad], ``velocity`` [rad/s], ``axial_force`` [N], ``current`` [A].
        storage: ``"mcap"`` or ``"sqlite3"``.
        frame_id: ``header.frame_id`` of every message.
        ground_truth: optional JSON-able simulator ground truth stored beside the data
            (``ground_truth.json`` in the bag directory, schema in ``bagio.sidecar``).
    """
    block: dict[tuple[str, str], Series] = {}
    for ns, signals in signals_by_namespace.items():
        check_namespace(ns)
        unit_t = t.get(ns) if isinstance(t, Mapping) else t
        for signal, value in signals.items():
            if signal not in INPUT_TOPICS:
                raise InputError(f"unknown signal {signal!r}; use one of {', '.join(INPUT_TOPICS)}")
            block[(ns, signal)] = _series(value, unit_t, f"{ns} {signal}")
    writer = BagWriter(path, list(block), storage=storage, frame_id=frame_id)
    try:
        writer.write(block)
    except BaseException:
        writer.abort()
        raise
    return writer.close(ground_truth)
