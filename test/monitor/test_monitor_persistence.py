"""Crash-safe state: atomic save, corrupt and truncated files, leftovers, kill -9 at random points."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from ebm_wear_monitor.monitor import MonitorConfig, MonitorCore, MonitorState, load_state, save_state
from ebm_wear_monitor.monitor.persistence import backup_path

from monitor_synth import linear_rates, screw_growth, synth_cycles

KW = {"wear_rates": linear_rates(1e-9), "clearance_growth": screw_growth}


def _core_after(unit, synth, until_s=None, **kw):
    core = MonitorCore(unit, **KW, **kw)
    for s, (t, v) in synth.signals().items():
        keep = slice(None) if until_s is None else t < until_s
        core.add(s, t[keep], v[keep])
    core.process(final=True)
    return core


def test_round_trip_is_exact(unit, tmp_path):
    state = _core_after(unit, synth_cycles(4, noise=True)).state
    save_state(tmp_path / "s.json", state)
    got, problems = load_state(tmp_path / "s.json")
    assert got == state and problems == []
    assert not backup_path(tmp_path / "s.json").exists()
    save_state(tmp_path / "s.json", MonitorState(duty_cycles=9))
    assert load_state(backup_path(tmp_path / "s.json"))[0] == state  # previous checkpoint kept


def test_missing_file_is_reported(tmp_path):
    state, problems = load_state(tmp_path / "none" / "s.json")
    assert state is None and len(problems) == 1 and "no state file" in problems[0]


@pytest.mark.parametrize("damage", ["garbage", "flipped_digit", "wrong_version"])
def test_corrupt_file_is_kept_aside_and_backup_used(tmp_path, damage):
    path = tmp_path / "s.json"
    good = MonitorState(duty_cycles=5, screw_raceway_m=1e-9)
    newer = MonitorState(duty_cycles=6, screw_raceway_m=2e-9)
    save_state(path, good)
    save_state(path, newer)
    text = path.read_text()
    if damage == "garbage":
        path.write_bytes(os.urandom(64))
    elif damage == "flipped_digit":
        path.write_text(text.replace('"duty_cycles": 6', '"duty_cycles": 7'))
    else:
        doc = json.loads(text)
        doc["state"]["version"] = 99
        path.write_text(json.dumps(doc))
    state, problems = load_state(path)
    assert state == good
    assert any("corrupt" in p for p in problems) and any("backup" in p for p in problems)
    aside = list(tmp_path.glob("s.json.corrupt-*"))
    assert len(aside) == 1 and not path.exists()


def test_every_truncation_of_a_non_atomic_write_is_survived(tmp_path):
    path = tmp_path / "s.json"
    good, newer = MonitorState(duty_cycles=5), MonitorState(duty_cycles=6, nut_raceway_m=3e-10)
    save_state(path, good)
    save_state(path, newer)
    full = path.read_bytes()
    for n in range(0, len(full), 7):
        for p in tmp_path.glob("s.json.corrupt-*"):
            p.unlink()
        save_state(path, good)  # main = good, backup = previous
        save_state(path, newer)  # main = newer, backup = good
        path.write_bytes(full[:n])  # a writer without temp file + rename, killed after n bytes
        state, problems = load_state(path)
        assert state == good, n
    # an interrupted *atomic* save leaves only a temp file: main is untouched and still loads
    save_state(path, newer)
    (tmp_path / "s.json.tmp-12345").write_bytes(full[: len(full) // 2])
    state, problems = load_state(path)
    assert state == newer and any("temp file" in p for p in problems)
    assert not (tmp_path / "s.json.tmp-12345").exists()


_CHILD = r"""
import sys, time
sys.path.insert(0, {testdir!r})
from monitor_synth import linear_rates, screw_growth, synth_cycles
from ebm_wear_monitor.monitor import MonitorConfig, MonitorCore
from ebm_wear_monitor.params import load_unit
synth = synth_cycles({cycles}, noise=True, seed=7)
core = MonitorCore(load_unit(), MonitorConfig(checkpoint_every_cycles=1), state_path={path!r},
                   wear_rates=linear_rates(1e-9), clearance_growth=screw_growth)
print("ready", flush=True)
n = synth.t.size
for a in range(0, n, 40):
    for s, (t, v) in synth.signals().items():
        core.add(s, t[a:a + 40], v[a:a + 40])
    core.process()
    time.sleep(0.002)
print("done", flush=True)
"""


def test_kill_minus_nine_at_random_points(unit, tmp_path):
    cycles = 30
    synth = synth_cycles(cycles, noise=True, seed=7)
    full = _core_after(unit, synth)
    rng = np.random.default_rng(42)
    seen = set()
    for trial in range(4):
        path = tmp_path / f"run{trial}" / "state.json"
        child = subprocess.Popen(
            [sys.executable, "-c", _CHILD.format(testdir=str(Path(__file__).parent), cycles=cycles,
                                                 path=str(path))],
            stdout=subprocess.PIPE, text=True)
        assert child.stdout.readline().strip() == "ready"
        # kill at a random point after the first checkpoint (on a slow machine a fixed delay from
        # start-up can land every kill before it) or, in one trial of four, at any point at all
        if trial:
            deadline = time.monotonic() + 120.0
            while not path.exists() and child.poll() is None and time.monotonic() < deadline:
                time.sleep(0.005)
        time.sleep(float(rng.uniform(0.0, 0.6)))
        child.send_signal(signal.SIGKILL)
        child.wait()
        state, problems = load_state(path)
        if state is None:  # killed before the first checkpoint
            assert all("no state file" in p or "temp file" in p for p in problems)
            continue
        k = state.duty_cycles
        seen.add(k)
        # the checkpoint holds exactly the wear of the first k applications: never more than the truth
        ref = _core_after(unit, synth, until_s=synth.marks[k - 1]["release_end"] + 0.1)
        assert ref.state.duty_cycles == k
        assert (state.screw_raceway_m, state.sum_rot_rad) == \
            (ref.state.screw_raceway_m, ref.state.sum_rot_rad)
        assert state.screw_raceway_m <= full.state.screw_raceway_m
        # resumed and fed the whole recording again: nothing counted twice, nothing lost
        resumed = MonitorCore(unit, MonitorConfig(), state, **KW)
        for s, (t, v) in synth.signals().items():
            resumed.add(s, t, v)
        resumed.process(final=True)
        assert resumed.state.duty_cycles == cycles
        assert resumed.state.screw_raceway_m == pytest.approx(full.state.screw_raceway_m, rel=1e-12)
    assert seen, "every kill landed before the first checkpoint"
