"""A real onboard install (issue 14 deliverable 4): ``install.sh --onboard DIR`` builds a fresh venv with the
ROS 2 wheels, msg_defs and ``pip install .`` (its run dependencies only); it holds no distribution of the
tools or test extras, and its node, fed live by the player of the development venv, gives the replay's
numbers (its listener prints them)."""

from __future__ import annotations

import json
import re
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from ebm_wear_monitor import extras
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.replay.run import replay_bags

REPO = Path(__file__).resolve().parents[2]


def _normalise(name: str) -> str:
    return re.sub(r"[-_.]+", "-", re.sub(r"\[.*\]", "", name)).lower()


@pytest.mark.slow
@pytest.mark.ros
@pytest.mark.timeout(600)
def test_a_real_onboard_venv_runs_the_node(tmp_path, procs) -> None:
    """``install.sh --onboard``: no tool distribution; its node, fed live, gives the replay's numbers."""
    venv = tmp_path / "onboard"
    build = subprocess.run(["./install.sh", "--onboard", str(venv)], cwd=REPO, capture_output=True, text=True,
                           timeout=540, check=False)
    assert build.returncode == 0, build.stderr[-3000:]
    python, outside = venv / "bin/python", tmp_path  # run outside the repository: no source tree on sys.path
    listing = subprocess.run([python, "-m", "pip", "list", "--format=json"], capture_output=True, text=True,
                             cwd=outside, timeout=120, check=True)
    installed = {_normalise(d["name"]) for d in json.loads(listing.stdout)}
    tools = {_normalise(r.name) for r in extras.TOOLS + extras.TEST} | {"distributed"}
    assert sorted(installed & tools) == []
    assert {_normalise(r.name) for r in extras.ONBOARD} <= installed
    where = subprocess.run([python, "-c", "import ebm_wear_monitor; print(ebm_wear_monitor.__file__)"],
                           capture_output=True, text=True, cwd=outside, timeout=60, check=True)
    assert where.stdout.startswith(str(venv))  # the installed copy, not the repository's
    tool = subprocess.run([venv / "bin/ebm-wear", "replay", str(REPO / "bags/healthy")], capture_output=True,
                          text=True, cwd=outside, timeout=60, check=False)
    assert tool.returncode == 2 and "needs the 'tools' extra" in tool.stderr

    procs.env["XDG_STATE_HOME"] = str(tmp_path / "state")
    node = procs.start([venv / "bin/ebm-wear-monitor", "--ros-args", "--params-file",
                        str(REPO / "config/wear_monitor.yaml")], cwd=outside)
    lines = procs.watch(procs.start([python, "-m", "ebm_wear_monitor.ros.listener", "/embu"], cwd=outside))
    lines.wait_for("READY", 30)
    player = procs.start([sys.executable, "-m", "ebm_wear_monitor.ros.player", str(REPO / "bags/healthy"),
                          "--no-progress"], cwd=REPO)
    assert player.wait(timeout=120) == 0, player.stderr.read()
    expected = replay_bags([REPO / "bags/healthy"], load_unit()).units[0].snapshot.to_json_dict()
    seen = lines.wait_until(lambda s: any(m["topic"] == "wear" and m["msg"]["duty_cycles"] == 8
                                          for m in s), 30)
    wear = next(m["msg"] for m in reversed(seen) if m["topic"] == "wear")
    assert expected["duty_cycles"] == 8
    # best-effort QoS as in the README's tour: a lost sample may move the wear slightly, never by 2 %
    assert wear["screw_raceway_m"] == pytest.approx(expected["wear"]["screw_raceway_m"], rel=0.02)
    node.send_signal(signal.SIGINT)
    assert node.wait(timeout=30) == 130
