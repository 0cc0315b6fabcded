"""Benchmark of the live wear-monitor node against a bare rclpy subscriber, in the same run.

For each input rate (per topic; three topics ``screw/angle``, ``screw/velocity``,
``axial_force``) this script publishes closed-form brake applications for a few
seconds (header stamps = wall-clock publish times, best effort = the node's
default sensor-data QoS) to, one after the other:

* a bare subscriber: the same three subscriptions on the same executor
  (EventsExecutor, ``spin_once(timeout_sec=0.2)`` loop) whose callback only
  appends ``(receive time, message)`` to a list;
* the node (``.venv/bin/ebm-wear-monitor``), with a listener process recording
  when each ``duty_cycle`` message arrives.

Printed per rate: messages published vs processed (loss), CPU share of the
subscriber process (user + system time / wall time, from 0.2 s before the first
message to 0.3 s after the last), the bare subscriber's stamp-to-callback latency, and the node's
input-to-publish latency: receive time of a ``duty_cycle`` minus the publish
time of the input sample that completed that application. Which sample
completes an application is found offline by feeding the same arrays to the
monitor core in 1 ms chunks. The ratio node CPU / bare CPU is the figure to
compare with the target (<= 2 at 3 x 1 kHz, no loss).

Run: ``.venv/bin/python bench/bench_node.py [--rates 1000,2000,4000,8000] [--seconds 6]``
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ebm_wear_monitor.domain.signals import MONITOR_SIGNALS

REPO = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent


def _test_helpers():
    """The node tests' helpers (test/ros/conftest.py: closed-form brake applications, Lines), not copied."""
    spec = importlib.util.spec_from_file_location("ros_test_conftest", REPO / "test" / "ros" / "conftest.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


HELPERS = _test_helpers()


# ----------------------------------------------------------------------------- bare subscriber process
def bare_subscriber(executor_kind: str) -> int:
    """Child mode: three subscriptions doing nothing but recording; prints counts and latencies on SIGINT."""
    import rclpy
    from rclpy.signals import SignalHandlerOptions

    from ebm_wear_monitor.domain.signals import INPUT_TOPICS
    from ebm_wear_monitor.ros.node import make_executor
    from ebm_wear_monitor.ros.qos import input_qos

    stop: list[int] = []
    signal.signal(signal.SIGINT, lambda s, _f: stop.append(s))
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    from ebm_wear_msgs.msg import Float64Stamped
    node = rclpy.create_node("bare_subscriber", namespace="/embu")
    logs: dict[str, list] = {s: [] for s in MONITOR_SIGNALS}
    for s in MONITOR_SIGNALS:
        log = logs[s]
        node.create_subscription(Float64Stamped, INPUT_TOPICS[s],
                                 lambda m, log=log: log.append((time.time(), m)), input_qos(False, 1000))
    executor = make_executor(executor_kind)
    executor.add_node(node)
    print("READY", flush=True)
    while not stop:
        executor.spin_once(timeout_sec=0.2)
    lat = np.array([r - (m.header.stamp.sec + m.header.stamp.nanosec * 1e-9) for log in logs.values()
                    for r, m in log])
    print(json.dumps({"received": {s: len(v) for s, v in logs.items()},
                      "lat_p50": float(np.percentile(lat, 50)) if len(lat) else None,
                      "lat_p99": float(np.percentile(lat, 99)) if len(lat) else None}), flush=True)
    return 0


# ----------------------------------------------------------------------------- orchestration
def cpu_seconds(pid: int) -> float:
    """User + system CPU time of a process so far [s] (/proc/<pid>/stat fields 14, 15)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def publish(rate_hz: float, seconds: float, pid: int
            ) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], int, float, float]:
    """Publish brake applications at ``rate_hz`` per topic, stamped with their wall-clock publish time.

    Returns (signals, messages published, publishing time [s], CPU share of process ``pid`` from the
    first message to 0.3 s after the last).
    """
    import rclpy

    from ebm_wear_monitor.ros.player import Player

    t, values = HELPERS.brake_applications(max(1, round(seconds / 1.6)), rate_hz)
    rclpy.init()
    node = rclpy.create_node("bench_publisher")
    try:
        player = Player(node, "/embu", {s: (t, values[s]) for s in MONITOR_SIGNALS})
        if not player.wait_for_subscribers(1, 30.0):
            raise TimeoutError("subscriber never matched")
        offset = time.time() + 0.2 - t[0]  # header stamps = wall-clock publish times
        signals = {s: (t + offset, values[s]) for s in MONITOR_SIGNALS}
        cpu0, started = cpu_seconds(pid), time.monotonic()
        n = player.play(1.0, offset, start_wall_s=t[0] + offset)
        elapsed = time.monotonic() - started
        player.wait_for_delivery(2.0)  # 0.3 s for best effort
        cpu = (cpu_seconds(pid) - cpu0) / (time.monotonic() - started)
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return signals, n, elapsed, cpu


def completing_stamps(signals: dict[str, tuple[np.ndarray, np.ndarray]]) -> list[float]:
    """Stamp of the input sample after which the monitor core reports each application (1 ms chunks)."""
    from ebm_wear_monitor.monitor import MonitorCore
    from ebm_wear_monitor.params import load_unit

    core = MonitorCore(load_unit())
    stamps = signals["angle"][0]
    edges = np.arange(stamps[0], stamps[-1] + 0.002, 0.001)
    idx = {s: np.searchsorted(signals[s][0], edges, side="right") for s in MONITOR_SIGNALS}
    done = []
    for k in range(1, len(edges)):
        for s in MONITOR_SIGNALS:
            a, b = idx[s][k - 1], idx[s][k]
            if b > a:
                core.add(s, signals[s][0][a:b], signals[s][1][a:b])
        done += [edges[k]] * len(core.process(False))
    return done


def run_once(kind: str, rate_hz: float, seconds: float, executor: str, process_rate: float) -> dict:
    env = dict(os.environ)  # main() set an isolated domain for this process and its children
    tmp = tempfile.mkdtemp(prefix="bench_node_")
    listener = None
    if kind == "bare":
        argv = [sys.executable, __file__, "--bare-subscriber", "--executor", executor]
    else:
        argv = [str(BIN / "ebm-wear-monitor"), "--ros-args", "-r", "__ns:=/embu", "-p", f"state_dir:={tmp}",
                "-p", f"executor:={executor}", "-p", f"process_rate_hz:={process_rate}"]
        listener = subprocess.Popen([sys.executable, "-m", "ebm_wear_monitor.ros.listener", "/embu"], env=env,
                                    stdout=subprocess.PIPE, text=True)
        listener_lines = HELPERS.Lines(listener)
        listener_lines.wait_for("READY", 30)
    proc = subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    lines = HELPERS.Lines(proc)
    try:
        if kind == "bare":
            lines.wait_for("READY", 30)
        else:  # the node publishes remaining_life (latched) once its core is built
            listener_lines.wait_until(lambda s: any(m["topic"] == "remaining_life" for m in s), 60)
        signals, published, elapsed, cpu = publish(rate_hz, seconds, proc.pid)
        result = {"kind": kind, "rate_hz": rate_hz, "published": published, "cpu": cpu,
                  "publish_rate": published / elapsed}
        if kind == "bare":
            proc.send_signal(signal.SIGINT)
            proc.wait(timeout=30)
            time.sleep(0.2)
            out = lines.collect()[-1]
            result |= {"processed": sum(out["received"].values()), "lat_p50": out["lat_p50"],
                       "lat_p99": out["lat_p99"]}
        else:
            time.sleep(1.2)  # one more diagnostics period: final received counts
            msgs = listener_lines.collect()
            diag = [m for m in msgs if m["topic"] == "diagnostics"][-1]["msg"]["status"][0]
            kv = {v["key"]: v["value"] for v in diag["values"]}
            recv = [m["recv"] for m in msgs if m["topic"] == "duty_cycle"]
            done = completing_stamps(signals)
            lat = np.array(recv[: len(done)]) - np.array(done[: len(recv)])
            result |= {"processed": sum(int(kv[f"received_{s}"]) for s in MONITOR_SIGNALS),
                       "cycles": len(recv),
                       "cycles_expected": len(done),
                       "lat_p50": float(np.percentile(lat, 50)) if len(lat) else None,
                       "lat_p99": float(np.percentile(lat, 99)) if len(lat) else None}
        return result
    finally:
        for p in (proc, listener):
            if p is not None and p.poll() is None:
                p.send_signal(signal.SIGINT)
                try:
                    p.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    p.kill()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rates", default="1000,2000,3000,4000,6000", help="input rates per topic [Hz]")
    parser.add_argument("--seconds", type=float, default=6.0, help="publishing time per run [s]")
    parser.add_argument("--executor", default="events", choices=("events", "single_threaded"))
    parser.add_argument("--process-rate", type=float, default=25.0, help="node process_rate_hz [Hz]")
    parser.add_argument("--bare-subscriber", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.bare_subscriber:
        return bare_subscriber(args.executor)
    os.environ.update(ROS_DOMAIN_ID=str(150 + os.getpid() % 50), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
                      PYTHONUNBUFFERED="1")
    print(f"executor {args.executor}, node process_rate_hz {args.process_rate}, {args.seconds} s per run, "
          f"3 topics, best effort")
    header = (f"{'rate/topic':>10} {'who':>5} {'published':>9} {'processed':>9} {'loss':>7} {'CPU':>6} "
              f"{'xbare':>6} {'lat p50':>9} {'lat p99':>9}")
    print(header)
    for rate in (float(r) for r in args.rates.split(",")):
        bare = run_once("bare", rate, args.seconds, args.executor, args.process_rate)
        node = run_once("node", rate, args.seconds, args.executor, args.process_rate)
        for r in (bare, node):
            loss = 1.0 - r["processed"] / r["published"]
            lat = (f"{r['lat_p50'] * 1e3:8.2f}ms {r['lat_p99'] * 1e3:8.2f}ms" if r["lat_p50"] is not None
                   else f"{'-':>9} {'-':>9}")
            print(f"{rate:10.0f} {r['kind']:>5} {r['published']:9d} {r['processed']:9d} {loss:7.2%} "
                  f"{r['cpu']:6.1%} {r['cpu'] / bare['cpu']:6.2f} {lat}", flush=True)
        print(f"{'':10} publisher achieved {bare['publish_rate']:.0f} / {node['publish_rate']:.0f} msg/s "
              f"(bare / node run); node published {node['cycles']} duty_cycle messages, offline core "
              f"completes {node['cycles_expected']}")
    print("lat: bare = header stamp to callback; "
          "node = publish of the completing input to duty_cycle receipt")
    return 0


if __name__ == "__main__":
    sys.exit(main())
