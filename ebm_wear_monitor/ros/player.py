"""A bag player for the input topics: publishes a bag's samples with the bag's header stamps.

``ros2 bag play`` is not available as a wheel, and it restamps nothing anyway;
this player reads the input topics of interface.md section 2 with
:func:`ebm_wear_monitor.bagio.read_bags` and publishes each sample as one
``ebm_wear_msgs/msg/Float64Stamped`` carrying its recorded ``header.stamp``,
serialised in bulk (``monitor.wire``, stamps exact in ns) and published as raw CDR bytes, so the
player costs little beside the node it feeds (tests, benchmark).

Order and pacing: the reader gives each signal in recording order. The
signals are merged on an "unrolled" time key: the header stamp plus every
backward jump seen so far in that signal (a bag played in a loop, or a late
sample), so the merge keeps each signal's own order, interleaves the signals
as they were sampled and never races ahead through a loop. With ``speed > 0``
a sample is published at ``t0 + key / speed`` (``speed = 1``: real time);
``speed = 0`` publishes as fast as the middleware allows.

Command line (``python -m ebm_wear_monitor.ros.player BAG... [--speed S] ...``)::

    --namespace NS     publish the bag's (only) unit under NS instead of its own namespace
    --speed S          multiple of real time; 0 = as fast as possible (default 1)
    --reliable         reliable, keep-all QoS (default: best effort, the sensor-data profile)
    --signals LIST     signals to publish, comma-separated, or ``all`` (default: what the wear monitor
                       subscribes to, angle,velocity,axial_force; ``motor/current`` is for the twin only)
    --subscribers N    wait until each of the monitor's input topics has N subscribers (default 1)
    --wait-timeout S   give up waiting for them after S seconds (default 60)
    --no-progress      no progress bar on stderr

It waits only for subscriptions on the topics the wear monitor reads (a published
``motor/current`` has no such subscriber). Exit status: 0 when everything was published, 2 on
bad input or when no subscriber appeared (one line on stderr, naming the topics it waited for),
130 when interrupted (Ctrl-C). It reads bags, so it needs the ``tools`` extra (one line, exit 2,
without it); the node and the listener run on the onboard install.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Mapping, Sequence

import numpy as np
import rclpy
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.signals import SignalHandlerOptions

from ebm_wear_monitor.domain.signals import INPUT_TOPICS, MONITOR_SIGNALS, check_namespace
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.extras import MissingExtraError, require
from ebm_wear_monitor.monitor.wire import encode_records, seconds_to_ns
from ebm_wear_monitor.ros.qos import input_qos

PROG = "ebm-wear-player"


def unrolled_time(stamps: np.ndarray) -> np.ndarray:
    """Non-decreasing time key of one signal [s]: each backward jump of the stamps is added back.

    ``key_i = t_i + sum_{j <= i} max(0, t_{j-1} - t_j)``, so ``key`` never decreases
    and equals ``t`` for a well-ordered signal.
    """
    stamps = np.asarray(stamps, dtype=np.float64)
    back = np.maximum(0.0, -np.diff(stamps, prepend=stamps[:1]))
    return stamps + np.cumsum(back)


def publish_order(signals: Mapping[str, tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """Merge order of several signals: (signal index per message, time key [s] per message), sorted by key.

    Each signal keeps its own recording order (its keys never decrease and the sort is stable).
    """
    keys = [unrolled_time(stamps) for stamps, _ in signals.values()]
    which = np.concatenate([np.full(len(k), i) for i, k in enumerate(keys)] or [np.empty(0, int)])
    key = np.concatenate(keys or [np.empty(0)])
    order = np.argsort(key, kind="stable")
    return which[order], key[order] - (key[order][0] if len(key) else 0.0)


class Player:
    """Publishes per-signal (stamps [ns] int64 or [s] float, values) on ``<namespace>/<input topic>``."""

    def __init__(self, node: Node, namespace: str, signals: Mapping[str, tuple[np.ndarray, np.ndarray]],
                 reliable: bool = False) -> None:
        unknown = set(signals) - set(INPUT_TOPICS)
        if unknown:
            raise InputError(f"unknown signals {sorted(unknown)}; use {', '.join(INPUT_TOPICS)}")
        ns = "/" + namespace.strip("/")
        qos = input_qos(reliable, 1000)
        self._node = node
        self.publishers: list[Publisher] = [
            node.create_publisher(_float64_stamped(), f"{ns.rstrip('/')}/{INPUT_TOPICS[s]}", qos)
            for s in signals]
        #: the publishers whose topics the wear monitor subscribes to (the ones worth waiting for)
        self.monitored = [p for s, p in zip(signals, self.publishers, strict=True) if s in MONITOR_SIGNALS]
        self._signals = [(st if np.asarray(st).dtype.kind in "iu" else seconds_to_ns(st), v)
                         for st, v in signals.values()]
        seconds = {s: (st * 1e-9, v) for s, (st, v) in zip(signals, self._signals, strict=True)}
        self._which, self._key = publish_order(seconds)  # pacing only: seconds are fine

    @property
    def messages(self) -> int:
        """Number of messages :meth:`play` publishes."""
        return int(self._which.size)

    def unmatched(self, count: int) -> list[str]:
        """Monitor input topics with fewer than ``count`` matched subscriptions."""
        return [p.topic_name for p in self.monitored if p.get_subscription_count() < count]

    def wait_for_subscribers(self, count: int, timeout_s: float) -> bool:
        """Wait until each monitor input topic has ``count`` matched subscriptions (discovery: 60-250 ms)."""
        deadline = time.monotonic() + timeout_s
        while self.unmatched(count):
            if time.monotonic() > deadline:
                return False
            time.sleep(0.01)
        return True

    def _records(self, stamp_offset_s: float) -> list[bytes]:
        """Serialised messages in publishing order, header stamps shifted by ``stamp_offset_s``."""
        offset_ns = round(stamp_offset_s * 1e9)
        per_signal = [encode_records(st + offset_ns, v) for st, v in self._signals]
        position = np.zeros(len(per_signal), dtype=np.int64)
        records = []
        for w in self._which.tolist():
            records.append(per_signal[w][position[w]])
            position[w] += 1
        return records

    def play(self, speed: float = 1.0, stamp_offset_s: float = 0.0, start_wall_s: float | None = None,
             progress: Callable[[int], object] | None = None) -> int:
        """Publish every sample (paced at ``speed`` x real time, or unpaced when 0); returns the count.

        ``stamp_offset_s`` shifts every header stamp; ``start_wall_s`` (``time.time()`` scale) is the
        instant of the first message (default: at once). The benchmark uses both to stamp each
        message with its wall-clock publish time. ``progress(n)`` is told of every ``n`` published.
        """
        records = self._records(stamp_offset_s)
        pubs = [p.publish for p in self.publishers]
        which = self._which.tolist()
        start = time.monotonic()
        if start_wall_s is not None:
            start += start_wall_s - time.time()
        due = self._key / speed if speed > 0 else None
        i, n = 0, len(which)
        while i < n:
            if due is None:
                end = n
            else:
                end = int(np.searchsorted(due, time.monotonic() - start, side="right"))
                if end <= i:
                    time.sleep(min(0.001, max(0.0, due[i] - (time.monotonic() - start))))
                    continue
            for k in range(i, end):
                pubs[which[k]](records[k])
            if progress is not None:
                progress(end - i)
            i = end
        return n

    def wait_for_delivery(self, timeout_s: float) -> None:
        """Keep the writers alive until delivery completes (reliable: acknowledged; best effort: 0.3 s)."""
        time.sleep(0.3)  # best-effort writers send asynchronously: exiting at once drops the tail
        for p in self.publishers:
            p.wait_for_all_acked(rclpy.duration.Duration(seconds=timeout_s))


def _float64_stamped() -> type:
    from ebm_wear_msgs.msg import Float64Stamped
    return Float64Stamped


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m ebm_wear_monitor.ros.player",
                                description="publish the input topics of rosbag2 bags live, with their "
                                            "recorded header stamps (ebm_wear_msgs/msg/Float64Stamped)")
    p.add_argument("bags", nargs="+", metavar="BAG", help="rosbag2 bag directories (sqlite3 or mcap)")
    p.add_argument("--namespace", metavar="NS", help="publish the bag's only unit under this namespace")
    p.add_argument("--speed", type=float, default=1.0, help="multiple of real time; 0 = as fast as possible")
    p.add_argument("--reliable", action="store_true", help="reliable keep-all QoS instead of best effort")
    p.add_argument("--signals", metavar="LIST",
                   help="comma-separated signals to publish, or 'all' (default: what the wear monitor "
                        f"reads: {','.join(MONITOR_SIGNALS)})")
    p.add_argument("--subscribers", type=int, default=1, metavar="N",
                   help="subscribers to wait for on each of the monitor's input topics (default 1)")
    p.add_argument("--wait-timeout", type=float, default=60.0, metavar="S",
                   help="seconds to wait for them (default 60)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")
    return p


def _chosen(args: argparse.Namespace) -> set[str]:
    """The signals to publish (InputError on an unknown name or bad numbers)."""
    if args.speed < 0 or not np.isfinite(args.speed):
        raise InputError("--speed must be a finite number >= 0")
    if args.subscribers < 0 or not args.wait_timeout >= 0:
        raise InputError("--subscribers and --wait-timeout must be >= 0")
    if args.namespace is not None:
        args.namespace = check_namespace(args.namespace)
    if args.signals in (None, ""):
        return set(MONITOR_SIGNALS)
    chosen = set(INPUT_TOPICS) if args.signals == "all" else set(args.signals.split(","))
    if chosen - set(INPUT_TOPICS):
        raise InputError(f"--signals: unknown {sorted(chosen - set(INPUT_TOPICS))}; "
                         f"use {', '.join(INPUT_TOPICS)} or all")
    return chosen


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point: play bags; exit 0, 2 (one line on bad input or no subscriber) or 130 (interrupted)."""
    args = _parser().parse_args(argv)
    try:
        require("tools")
        return _play(args)
    except (InputError, MissingExtraError) as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130


def _play(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from ebm_wear_monitor.bagio.reader import read_bags

    chosen = _chosen(args)
    recording = read_bags(args.bags)
    if args.namespace and len(recording.units) != 1:
        raise InputError(f"--namespace needs a bag with one unit, found {len(recording.units)}")
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)  # Ctrl-C: KeyboardInterrupt, exit 130
    node = rclpy.create_node("bag_player")
    try:
        players = [Player(node, args.namespace or unit,
                          {s: (sig.stamps_ns, sig.values) for s, sig in data.signals.items() if s in chosen},
                          args.reliable)
                   for unit, data in recording.units.items()]
        waiting = sorted({t for player in players for t in player.unmatched(args.subscribers)})
        if waiting:
            print(f"{PROG}: waiting for subscriptions on {', '.join(waiting)} (is ebm-wear-monitor running "
                  "under that namespace?)", file=sys.stderr, flush=True)
        for player in players:
            if not player.wait_for_subscribers(args.subscribers, args.wait_timeout):
                raise InputError(f"no subscriber on {', '.join(player.unmatched(args.subscribers))} within "
                                 f"{args.wait_timeout:g} s (start ebm-wear-monitor under that namespace, "
                                 "or give the player --namespace)")
        total = sum(player.messages for player in players)
        with tqdm(total=total, unit="msg", desc="publish", file=sys.stderr,
                  disable=args.no_progress or None) as bar:
            for player in players:
                player.play(args.speed, progress=bar.update)
        for player in players:
            player.wait_for_delivery(10.0)
        print(f"published {total}", flush=True)
        return 0
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
