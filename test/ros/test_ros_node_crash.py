"""Crash safety of the live node (issue 5 item 7): kill -9 at random points, then resume.

Truth is the monitor core run offline on the same bag: after k applications its
cumulative wear is W_k. A killed node must have left a state that is exactly
one of its checkpoints (k a multiple of ``checkpoint_every_cycles``, wear W_k:
never more than the true value, never a torn write), no older than the last
checkpoint before the last application the listener saw, and a restarted node
must resume from it.
"""

from __future__ import annotations

import math
import signal
import time

import numpy as np
import pytest

from ebm_wear_monitor.bagio.reader import read_bags
from ebm_wear_monitor.monitor import MonitorConfig, MonitorCore, load_state
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.ros.node import STATE_FILE

pytestmark = pytest.mark.ros

EVERY = 2  # checkpoint_every_cycles of the node under test
N_CYCLES = 8
SPEED = 5.0  # playback speed: one 1.6 s application every 0.32 s


def wear_after_each_cycle(bag) -> list[float]:
    """Offline truth: screw-raceway wear [m] after 0, 1, 2, ... applications (core fed in 0.1 s chunks)."""
    core = MonitorCore(load_unit(), MonitorConfig(), None)
    sig = read_bags([bag]).units["/embu"].signals
    wear = [0.0]
    n = len(sig["angle"].stamps)
    for i in range(0, n, 50):
        for name, s in sig.items():
            core.add(name, s.stamps_ns[i:i + 50], s.values[i:i + 50])
        done = core.process()
        assert len(done) <= 1
        wear += [core.snapshot().screw_raceway_m] * len(done)
    return wear


@pytest.mark.timeout(120)
def test_kill_9_at_random_points_leaves_an_exact_checkpoint_and_resumes(procs, make_bag, tmp_path) -> None:
    bag, _ = make_bag(n_cycles=N_CYCLES, rate_hz=500.0)
    truth = wear_after_each_cycle(bag)
    assert len(truth) == N_CYCLES + 1 and np.all(np.diff(truth) > 0)
    kill_after = np.random.default_rng(20261121).uniform(0.5, N_CYCLES * 1.6 / SPEED, size=3)
    lines = procs.listener()
    for trial, delay in enumerate(kill_after):
        state_dir = tmp_path / f"state{trial}"
        lines.seen.clear()
        node = procs.node("-r", "__ns:=/embu", state_dir=state_dir,
                          params={"checkpoint_every_cycles": EVERY, "qos_reliability": "reliable"})
        player = procs.player(bag, "--reliable", "--speed", str(SPEED))
        lines.wait_until(lambda s: any(m["topic"] == "remaining_life" for m in s), 30)  # node is up
        time.sleep(delay)
        node.send_signal(signal.SIGKILL)
        node.wait(timeout=10)
        seen = [m["msg"]["duty_cycles"] for m in lines.collect() if m["topic"] == "wear"]
        last_seen = max(seen, default=0)
        player.kill()
        state, _problems = load_state(state_dir / STATE_FILE)
        k = 0 if state is None else state.duty_cycles
        wear = 0.0 if state is None else state.screw_raceway_m
        assert k % EVERY == 0, (trial, k)
        assert last_seen // EVERY * EVERY <= k <= last_seen + 1, (trial, k, last_seen)
        assert math.isclose(wear, truth[k], rel_tol=1e-9, abs_tol=0.0), (trial, k, wear, truth[k])
    # the last killed node's state resumes: a new node starts from it and republishes it (latched)
    lines.collect()
    lines.seen.clear()
    node = procs.node("-r", "__ns:=/embu", state_dir=state_dir)
    life = lines.wait_until(lambda s: any(m["topic"] == "remaining_life" for m in s), 30)
    resumed = MonitorCore(load_unit(), MonitorConfig(), state).snapshot()
    got = next(m["msg"] for m in life if m["topic"] == "remaining_life")
    assert math.isclose(got["clearance_estimate_m"], resumed.clearance_estimate_m, rel_tol=1e-12)
    node.send_signal(signal.SIGTERM)
    assert node.wait(timeout=20) == 0
    again, _ = load_state(state_dir / STATE_FILE)
    assert again is not None and again.duty_cycles == k and again.screw_raceway_m == wear
