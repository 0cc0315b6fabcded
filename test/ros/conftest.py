"""Fixtures of the live-node tests: real processes, synthetic bags, Fast DDS shared-memory cleanup."""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import queue
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from ebm_wear_monitor.bagio.writer import write_unit_bag

SHM = Path("/dev/shm")

# --------------------------------------------------------------------------- synthetic brake applications
LEAD = 5.0e-3  # l [m], reference EMBU (ebm_wear_monitor/params/reference/embu_000.yaml)
CLEARANCE = 0.2e-3  # x_ag [m], same file
STIFFNESS = 4.16e7  # K_b [N/m], same file


def brake_applications(n_cycles: int, rate_hz: float, peak_force_n: float = 20.0e3, rest_s: float = 0.4,
                       *, growth_m: float = 0.0) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Closed-form duty cycles of 000 Fig. 2 sampled at ``rate_hz``: (t [s], {signal: values}).

    Each application: rest, clearance elimination at constant screw speed (no force),
    force generation (F = K_b (x - x_ag), x = l theta / 2 pi, 004 eq. 6), force
    maintenance at standstill, force release back to the rest angle, rest.
    Durations: 0.1, 0.2, 0.3, 0.2 s; signals are exact functions of time. The clearance of
    application k (0-based) is x_ag = CLEARANCE + k ``growth_m``.
    """
    knots_t = np.cumsum([0.0, rest_s, 0.1, 0.2, 0.3, 0.2, rest_s])
    to_contact = np.array([0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0])  # share of theta_c at each knot
    to_peak = np.array([0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0])  # share of the compression at each knot
    period = knots_t[-1]
    t = np.arange(round(n_cycles * period * rate_hz)) / rate_hz + 1000.0  # stamps from 1000 s
    k, phase_t = np.divmod(t - 1000.0, period)
    x_ag = CLEARANCE + growth_m * k
    theta_c = 2 * np.pi * x_ag / LEAD  # screw angle at contact [rad]
    squeeze = 2 * np.pi * peak_force_n / STIFFNESS / LEAD  # screw angle from contact to peak force [rad]
    theta = theta_c * np.interp(phase_t, knots_t, to_contact) + squeeze * np.interp(phase_t, knots_t, to_peak)
    seg = np.clip(np.searchsorted(knots_t, phase_t, side="right") - 1, 0, len(knots_t) - 2)
    dt = np.diff(knots_t)[seg]
    omega = (theta_c * np.diff(to_contact)[seg] + squeeze * np.diff(to_peak)[seg]) / dt
    force = np.maximum(0.0, STIFFNESS * (LEAD * theta / (2 * np.pi) - x_ag))
    return t, {"angle": theta, "velocity": omega, "axial_force": force}


@pytest.fixture
def make_bag(tmp_path: Path):
    """``make_bag(n_cycles, rate_hz, name, namespace='/embu', mutate=None, growth_m=0) -> (bag, signals)``.

    ``mutate(t, signals) -> {signal: Series | values}`` lets a test corrupt the samples.
    """
    def _make(n_cycles: int, rate_hz: float = 500.0, name: str = "bag", namespace: str = "/embu",
              mutate=None, *, growth_m: float = 0.0):
        t, signals = brake_applications(n_cycles, rate_hz, growth_m=growth_m)
        data = mutate(t, signals) if mutate else signals
        path = tmp_path / name
        write_unit_bag(path, t, {namespace: data}, storage="sqlite3")
        return path, (t, signals)
    return _make


# --------------------------------------------------------------------------- processes
class Lines:
    """A child's stdout lines, read by a thread (waiting never blocks the pipe); JSON lines parsed."""

    def __init__(self, proc: subprocess.Popen) -> None:
        self.q: queue.Queue[str] = queue.Queue()
        self.seen: list[dict] = []
        threading.Thread(target=self._pump, args=(proc,), daemon=True).start()

    def _pump(self, proc: subprocess.Popen) -> None:
        for line in proc.stdout:
            self.q.put(line.rstrip("\n"))

    def wait_for(self, text: str, timeout: float) -> None:
        """Wait for a line equal to ``text``."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with contextlib.suppress(queue.Empty):
                if self.q.get(timeout=0.05) == text:
                    return
        raise TimeoutError(f"no line {text!r} within {timeout} s")

    def collect(self) -> list[dict]:
        """Every JSON line received so far (accumulated in ``seen``)."""
        while not self.q.empty():
            line = self.q.get()
            if line.startswith("{"):
                self.seen.append(json.loads(line))
        return self.seen

    def wait_until(self, predicate, timeout: float) -> list[dict]:
        """Collect until ``predicate(seen)`` holds; raises TimeoutError otherwise."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if predicate(self.collect()):
                return self.seen
            time.sleep(0.05)
        raise TimeoutError(f"condition not met within {timeout} s; last: {self.seen[-3:]}")


class Procs:
    """Child processes of one test; every one is killed (by its own pid) when the test ends."""

    def __init__(self, env: dict[str, str]) -> None:
        self.env = env
        self.children: list[subprocess.Popen] = []

    def start(self, argv: list[str], **kw) -> subprocess.Popen:
        proc = subprocess.Popen(argv, env=self.env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, **kw)
        self.children.append(proc)
        return proc

    def node(self, *ros_args: str, state_dir: Path, params: dict[str, object] | None = None
             ) -> subprocess.Popen:
        """``.venv/bin/ebm-wear-monitor`` with ``state_dir`` and extra ``-p name:=value`` parameters."""
        argv = [str(Path(sys.executable).parent / "ebm-wear-monitor"), "--ros-args",
                "-p", f"state_dir:={state_dir}"]
        for k, v in (params or {}).items():
            argv += ["-p", f"{k}:={v}"]
        return self.start(argv + list(ros_args))

    def player(self, bag: Path, *args: str) -> subprocess.Popen:
        return self.start([sys.executable, "-m", "ebm_wear_monitor.ros.player", str(bag), *args])

    @staticmethod
    def watch(proc: subprocess.Popen) -> Lines:
        """The stdout lines of a child started with :meth:`start`."""
        return Lines(proc)

    def listener(self, namespace: str = "/embu", timeout: float = 30.0) -> Lines:
        """The JSON-lines listener of the node's outputs, subscribed and ready."""
        lines = Lines(self.start([sys.executable, "-m", "ebm_wear_monitor.ros.listener", namespace]))
        lines.wait_for("READY", timeout)
        return lines

    def kill_all(self) -> None:
        for proc in self.children:
            if proc.poll() is None:
                proc.send_signal(signal.SIGKILL)
            with contextlib.suppress(subprocess.TimeoutExpired, ValueError):
                proc.communicate(timeout=10)


def _orphaned_segments(before: set[str]) -> list[Path]:
    """Fast DDS shared-memory files created since ``before`` whose owner lock is free (owner dead).

    Fast DDS keeps an exclusive or shared ``flock`` on ``<segment>_el`` while a
    participant uses the segment; if we can take an exclusive lock, no process
    uses it (what ``fastdds shm clean`` checks). Segments of other live processes stay.
    """
    stale = []
    for lock in SHM.glob("fastdds_*_el"):
        segment = lock.with_name(lock.name[:-3])
        if segment.name in before:
            continue
        try:
            fd = os.open(lock, os.O_RDWR)
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            continue  # held: a live participant
        finally:
            os.close(fd)
        stale += [segment, lock, SHM / f"sem.{segment.name}_mutex"]
    return stale


@pytest.fixture
def procs(ros_env: dict[str, str]) -> Iterator[Procs]:
    """Start child processes in an isolated ROS domain; kill them and clean their shm segments after."""
    before = {p.name for p in SHM.glob("fastdds_*")}
    p = Procs(ros_env)
    try:
        yield p
    finally:
        p.kill_all()
        time.sleep(0.05)
        for path in _orphaned_segments(before):
            path.unlink(missing_ok=True)
