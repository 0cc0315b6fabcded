"""The README's live quick tour run as written: node, player and listener as three real processes over
real DDS (issue 13 deliverable 1), and ``--help`` on every entry point."""

from __future__ import annotations

import re
import shlex
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.replay.run import replay_bags

pytestmark = pytest.mark.ros


def live_commands(readme: Path) -> list[list[str]]:
    """The commands of the fenced block under the README's "Live quick tour" heading, comments dropped."""
    text = readme.read_text(encoding="utf-8")
    section = text.split("### Live quick tour", 1)[1]
    block = re.search(r"```bash\n(.*?)```", section, re.S).group(1)
    return [shlex.split(line, comments=True) for line in block.splitlines() if line.strip()]


@pytest.mark.timeout(150)
def test_the_readme_live_tour_works_verbatim(procs, repo, tmp_path) -> None:
    node_cmd, player_cmd, listener_cmd = live_commands(repo / "README.md")
    assert node_cmd[0].endswith("ebm-wear-monitor") and "__ns" not in " ".join(node_cmd)
    assert "ebm_wear_monitor.ros.player" in player_cmd and "ebm_wear_monitor.ros.listener" in listener_cmd
    procs.env["XDG_STATE_HOME"] = str(tmp_path / "state")  # the node's default state_dir, kept out of ~

    def start(cmd: list[str]) -> subprocess.Popen:
        # .venv/bin/X: X of the venv running the tests (the README's .venv in a fresh clone)
        assert cmd[0].startswith(".venv/bin/"), cmd
        name = Path(cmd[0]).name
        return procs.start([sys.executable if name == "python" else str(Path(sys.executable).parent / name),
                            *cmd[1:]], cwd=repo)

    node = start(node_cmd)  # terminal 1
    player = start(player_cmd)  # terminal 2: may start before the node is up; it waits for it
    lines = procs.watch(start(listener_cmd))  # terminal 3
    lines.wait_for("READY", 30)
    assert player.wait(timeout=90) == 0, player.stderr.read()
    assert player.stdout.read().startswith("published ")
    expected = replay_bags([repo / "bags" / "healthy"], load_unit()).units[0].snapshot.to_json_dict()
    assert expected["duty_cycles"] == 8  # README: "one per brake application: 8 here"
    seen = lines.wait_until(lambda s: sum(m["topic"] == "duty_cycle" for m in s) >= 8
                            and any(m["topic"] == "wear" and m["msg"]["duty_cycles"] == 8 for m in s), 30)
    assert sum(m["topic"] == "duty_cycle" for m in seen) == 8
    wear = next(m["msg"] for m in reversed(seen) if m["topic"] == "wear")
    # best-effort QoS as in the README: a lost sample may move the wear slightly, never by 2 %
    assert wear["screw_raceway_m"] == pytest.approx(expected["wear"]["screw_raceway_m"], rel=0.02)
    assert any(m["topic"] == "remaining_life" for m in seen)
    diag = [m for m in seen if m["topic"] == "diagnostics"]
    assert diag and diag[-1]["msg"]["status"][0]["name"] == "/embu/wear_monitor"
    node.send_signal(signal.SIGINT)
    assert node.wait(timeout=30) == 130
    assert list((tmp_path / "state").rglob("monitor_state.json"))


ENTRY_POINTS = [["ebm-wear"], ["ebm-wear", "replay"], ["ebm-wear", "fleet"], ["ebm-wear", "diagnose"],
                ["ebm-wear", "simulate"], ["ebm-wear", "calc"], ["ebm-wear", "calc", "contact"],
                ["ebm-wear-monitor"], ["-m", "ebm_wear_monitor.ros.player"],
                ["-m", "ebm_wear_monitor.ros.listener"]]


@pytest.mark.parametrize("entry", ENTRY_POINTS, ids=" ".join)
def test_help_on_every_entry_point(entry) -> None:
    bin_dir = Path(sys.executable).parent
    argv = [sys.executable, *entry] if entry[0] == "-m" else [str(bin_dir / entry[0]), *entry[1:]]
    run = subprocess.run([*argv, "--help"], capture_output=True, text=True, timeout=60, check=False)
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("usage:") and run.stderr == ""


@pytest.mark.parametrize("module", ["player", "listener"])
def test_player_and_listener_refuse_a_bad_namespace_with_one_line(module, repo) -> None:
    args = [str(repo / "bags" / "healthy"), "--namespace", "/9bad"] if module == "player" else ["/9bad"]
    run = subprocess.run([sys.executable, "-m", f"ebm_wear_monitor.ros.{module}", *args],
                         capture_output=True, text=True, timeout=60, check=False)
    assert run.returncode == 2
    assert run.stderr.count("\n") == 1 and "not a ROS 2 namespace" in run.stderr


@pytest.mark.timeout(60)
def test_player_exits_130_when_interrupted_and_2_when_nobody_subscribes(procs, repo) -> None:
    bag = str(repo / "bags" / "healthy")
    player = procs.start([sys.executable, "-m", "ebm_wear_monitor.ros.player", bag, "--no-progress"])
    assert player.stderr.readline().startswith("ebm-wear-player: waiting for subscriptions on /embu/")
    player.send_signal(signal.SIGINT)
    assert player.wait(timeout=20) == 130
    assert player.stderr.read().strip() == "ebm-wear-player: interrupted"
    run = subprocess.run([sys.executable, "-m", "ebm_wear_monitor.ros.player", bag, "--wait-timeout", "0.5",
                          "--no-progress"], env=procs.env, capture_output=True, text=True, timeout=60,
                         check=False)
    assert run.returncode == 2
    err = run.stderr.strip().splitlines()
    assert err[-1].startswith("ebm-wear-player: error: no subscriber on /embu/")
    assert "motor/current" not in run.stderr  # it waits only for what the monitor reads
