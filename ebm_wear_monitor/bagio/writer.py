"""Write the input topics of interface.md section 2 into a rosbag2 bag (sqlite3 or mcap) from numpy arrays.

Each sample becomes one ``ebm_wear_msgs/msg/Float64Stamped`` whose
``header.stamp`` is its sample time; the bag (receive) timestamp is the sample
time too unless receive times are given (to record late, interleaved or
duplicated delivery). Messages of all topics are written in receive-time order,
as a recorder would. Serialisation is bulk (``bagio.cdr``); the bag is built in
a temporary sibling directory and renamed into place, so a failed write never
leaves a half-written bag behind.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import NamedTuple

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer

from ebm_wear_monitor.bagio.cdr import encode_float64_stamped
from ebm_wear_monitor.bagio.sidecar import GROUND_TRUTH_FILE
from ebm_wear_monitor.bagio.topics import INPUT_TOPICS, check_namespace, topic_name
from ebm_wear_monitor.bagio.types import FLOAT64_STAMPED, typestore
from ebm_wear_monitor.errors import InputError

#: storage names accepted by the writer (the ``storage_identifier`` of rosbag2)
STORAGES: dict[str, StoragePlugin] = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}


class Series(NamedTuple):
    """One signal with its own sample times: header stamps [s], values [SI], optional receive times [s]."""

    stamps: np.ndarray
    values: np.ndarray
    received: np.ndarray | None = None


def _series(value: np.ndarray | Series, t: np.ndarray | None, where: str) -> Series:
    series = value if isinstance(value, Series) else Series(t, value) if t is not None else None
    if series is None:
        raise InputError(f"{where}: no sample times (give t or a Series)")
    stamps, values = np.asarray(series.stamps, float), np.asarray(series.values, float)
    received = stamps if series.received is None else np.asarray(series.received, float)
    if not stamps.shape == values.shape == received.shape or stamps.ndim != 1:
        raise InputError(f"{where}: stamps, values and receive times must be 1-D arrays of one length")
    if not (np.all(np.isfinite(stamps)) and np.all(np.isfinite(received))) or stamps.min(initial=0) < 0:
        raise InputError(f"{where}: sample and receive times must be finite and >= 0 s")
    return Series(stamps, values, received)


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
        t: sample times [s] shared by every signal, or a mapping namespace -> sample times,
            or None when every signal is a :class:`Series`.
        signals_by_namespace: ``{namespace: {signal: values | Series}}`` with signal names
            ``angle`` [rad], ``velocity`` [rad/s], ``axial_force`` [N], ``current`` [A].
        storage: ``"mcap"`` or ``"sqlite3"``.
        frame_id: ``header.frame_id`` of every message.
        ground_truth: optional JSON-able simulator ground truth stored beside the data
            (``ground_truth.json`` in the bag directory, schema in ``bagio.sidecar``).
    """
    path = Path(path)
    if storage not in STORAGES:
        raise InputError(f"unknown bag storage {storage!r}; use one of {', '.join(STORAGES)}")
    if path.exists():
        raise InputError(f"{path} exists already; not overwriting a bag")
    topics: list[tuple[str, Series]] = []
    for ns, signals in signals_by_namespace.items():
        check_namespace(ns)
        unit_t = t.get(ns) if isinstance(t, Mapping) else t
        for signal, value in signals.items():
            if signal not in INPUT_TOPICS:
                raise InputError(f"unknown signal {signal!r}; use one of {', '.join(INPUT_TOPICS)}")
            topics.append((topic_name(ns, signal), _series(value, unit_t, f"{ns} {signal}")))
    order = np.argsort(np.concatenate([s.received for _, s in topics] or [np.empty(0)]), kind="stable")
    which = np.concatenate([np.full(len(s.values), i) for i, (_, s) in enumerate(topics)]
                           or [np.empty(0, int)])
    records = [r for _, s in topics for r in encode_float64_stamped(s.stamps, s.values, frame_id)]
    received_ns = np.concatenate([np.rint(s.received * 1e9).astype(np.int64) for _, s in topics]
                                 or [np.empty(0, np.int64)])
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
    except OSError as exc:
        raise InputError(f"{path}: cannot write a bag there ({exc.strerror or exc})") from exc
    try:
        with Writer(tmp / path.name, version=9, storage_plugin=STORAGES[storage]) as writer:
            conns = [writer.add_connection(name, FLOAT64_STAMPED, typestore=typestore())
                     for name, _ in topics]
            for i, stamp in zip(order.tolist(), received_ns[order].tolist(), strict=True):
                writer.write(conns[which[i]], stamp, records[i])
        if ground_truth is not None:
            (tmp / path.name / GROUND_TRUTH_FILE).write_text(json.dumps(ground_truth), encoding="utf-8")
        (tmp / path.name).rename(path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return len(records)
