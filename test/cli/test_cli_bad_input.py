"""Issue 13's bad inputs, one test each: one line on stderr and exit 2 (or a counted fault), never a
traceback or a silently wrong answer; and the CLI policy (``--json -``, umask, Dask address forms)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ebm_wear_monitor.bagio import read_bags, write_unit_bag
from ebm_wear_monitor.bagio.rates import MIN_RATE_HZ, sample_rate_hz
from ebm_wear_monitor.cli.main import main
from ebm_wear_monitor.diagnosis.selftest import Case, simulate_case
from ebm_wear_monitor.fleet.synthetic import UnitScenario, write_unit
from ebm_wear_monitor.params import load_unit

EBM_WEAR = str(Path(sys.executable).parent / "ebm-wear")
#: root reads and writes anything: drop the capabilities that let it ignore file modes
NO_DAC = ["setpriv", "--bounding-set=-dac_override,-dac_read_search"] if os.geteuid() == 0 else []


def one_line_error(err: str, command: str) -> str:
    err = err.strip()
    assert err.startswith(f"ebm-wear {command}: error:"), err
    assert "\n" not in err and "Traceback" not in err, err
    return err


def run_unprivileged(*argv: str, cwd: Path) -> subprocess.CompletedProcess:
    if NO_DAC and shutil.which("setpriv") is None:
        pytest.skip("running as root without setpriv: file modes cannot be enforced")
    return subprocess.run([*NO_DAC, EBM_WEAR, *argv], capture_output=True, text=True, timeout=300,
                          check=False, cwd=cwd)


@pytest.fixture(scope="module")
def public_tmp(tmp_path_factory) -> Path:
    """A scratch directory every user may enter (pytest's own is 0700 for its owner only)."""
    path = tmp_path_factory.mktemp("bad_input")
    for p in (path, *path.parents[:2]):
        if p.stat().st_uid == os.geteuid():
            p.chmod(p.stat().st_mode | 0o755)
    return path


@pytest.fixture
def healthy(repo: Path) -> Path:
    return repo / "bags" / "healthy"


def test_unreadable_bag_directory_exits_2_in_replay_and_diagnose(public_tmp, healthy):
    bag = public_tmp / "locked_bag"
    shutil.copytree(healthy, bag)
    bag.chmod(0)
    try:
        for argv in (["replay", str(bag), "--no-progress"], ["diagnose", str(bag), "--params", "embu_000"]):
            run = run_unprivileged(*argv, cwd=public_tmp)
            assert run.returncode == 2, run.stderr
            assert "Permission denied" in one_line_error(run.stderr, argv[0])
    finally:
        bag.chmod(0o755)


def test_unreadable_fleet_directory_or_unit_folder_exits_2(public_tmp, repo):
    fleet = public_tmp / "locked_fleet"
    shutil.copytree(repo / "bags" / "fleet", fleet)
    for locked in (fleet, fleet / "train1" / "car2"):  # a unit folder os.walk would skip silently
        locked.chmod(0)
        try:
            run = run_unprivileged("fleet", str(fleet), "--out", str(public_tmp / "never"), "--workers", "1",
                                   "--no-progress", cwd=public_tmp)
        finally:
            locked.chmod(0o755)
        assert run.returncode == 2, run.stderr
        assert str(locked.name) in one_line_error(run.stderr, "fleet")
    assert not (public_tmp / "never").exists()


def test_read_only_destinations_exit_2_before_any_work(public_tmp, repo):
    ro = public_tmp / "read_only"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        for argv in (["fleet", str(repo / "bags" / "fleet"), "--out", str(ro / "out"), "--workers", "1"],
                     ["fleet", str(repo / "bags" / "fleet"), "--out", str(ro)],
                     ["fleet", str(repo / "bags" / "fleet"), "--out", str(public_tmp / "o"), "--report",
                      str(ro / "r")],
                     ["replay", str(repo / "bags" / "healthy"), "--json", str(ro / "x.json")],
                     ["diagnose", str(repo / "bags" / "healthy"), "--params", "embu_000", "--report",
                      str(ro / "r")]):
            run = run_unprivileged(*argv, "--no-progress", cwd=public_tmp)
            assert run.returncode == 2, run.stderr
            err = one_line_error(run.stderr, argv[0])
            assert "cannot write" in err and "Permission denied" in err
            assert "distributed" not in run.stderr  # no Dask was started: nothing computed for nothing
    finally:
        ro.chmod(0o755)
    assert list(ro.iterdir()) == [] and not (public_tmp / "o").exists()


def test_diagnose_on_topics_without_messages_exits_2(tmp_path, capsys):
    bag = tmp_path / "empty"
    write_unit_bag(bag, np.empty(0), {"/embu": {k: np.empty(0) for k in
                                                ("angle", "velocity", "axial_force", "current")}})
    assert main(["diagnose", str(bag), "--params", "embu_000", "--no-progress"]) == 2
    assert "fewer than 2 valid samples" in one_line_error(capsys.readouterr().err, "diagnose")


def test_diagnose_drops_and_counts_absurd_samples_as_the_monitor_does(tmp_path):
    """1e30 on every 200th angle sample: the replay rejects them as absurd, so must the diagnosis."""
    rec = simulate_case(load_unit(), Case({"clearance_growth": 6e-5}, 0.3, 5, 0))
    angle = rec.angle.copy()
    angle[::200] = 1e30
    bag, out = tmp_path / "absurd", tmp_path / "d.json"
    write_unit_bag(bag, rec.t, {"/embu": {"angle": angle, "velocity": rec.velocity,
                                          "axial_force": rec.axial_force, "current": rec.current}})
    assert main(["diagnose", str(bag), "--params", "embu_000", "--json", str(out), "--no-progress"]) == 0
    res = json.loads(out.read_text())
    n_bad = len(range(0, rec.t.size, 200))
    assert res["input_faults_by_signal"] == {"angle": {"absurd": n_bad}}
    assert res["input_faults"] == {"absurd": n_bad}
    # the answer test_cli_diagnose asserts on the clean recording (the injected 60 µm found)
    assert res["verdict"] == "effect" and res["effect"] == "clearance_growth"
    assert res["gap_after"] < 0.3 * res["gap_before"]
    dx = res["ranking"][0]["parameters"]["dx"]
    assert abs(dx["value"] - 6e-5) < max(4 * dx["stderr"], 3e-6)


@pytest.fixture(scope="module")
def bag_10hz(tmp_path_factory) -> Path:
    scenario = UnitScenario(unit="u", seed=5, bags=1, cycles_per_bag=4, demands_n=(15e3,), hold_s=0.3,
                            rest_s=0.2, wear_acceleration=1.0, prior_cycles=0, rate_hz=10.0,
                            storage="sqlite3", faults=False)
    (path,) = write_unit(tmp_path_factory.mktemp("rate10"), scenario, load_unit())
    return path


def test_a_10_hz_bag_is_refused_by_replay_and_diagnose(bag_10hz, tmp_path, capsys):
    assert read_bags([bag_10hz]).units  # a valid bag, only too slow
    for argv in (["replay", str(bag_10hz)], ["diagnose", str(bag_10hz), "--params", "embu_000"]):
        assert main([*argv, "--json", str(tmp_path / "x.json"), "--no-progress"]) == 2
        err = one_line_error(capsys.readouterr().err, argv[0])
        assert "sampled at 10 Hz, below the 100 Hz minimum" in err
        assert not (tmp_path / "x.json").exists()


def test_sample_rate_is_robust_to_jitter_gaps_duplicates_and_a_loop():
    rng = np.random.default_rng(3)
    t = np.arange(2000) / 100.0 + rng.normal(0.0, 2e-4, 2000)  # 100 Hz, 0.2 ms jitter
    t = np.concatenate([t[:500], t[700:], t[:300]])  # a gap and the start played again
    t = np.sort(np.concatenate([t, t[::50]]))[::-1][::-1]  # duplicates
    assert sample_rate_hz(t) == pytest.approx(100.0, rel=0.01)
    assert sample_rate_hz(np.array([5.0])) is None and sample_rate_hz(np.array([1.0, 1.0])) is None
    assert MIN_RATE_HZ == 100.0  # interface.md section 2


def test_json_dash_replay_writes_only_json_on_stdout(repo, capsys):
    assert main(["replay", str(repo / "bags" / "healthy"), "--json", "-", "--no-progress"]) == 0
    out, err = capsys.readouterr()
    doc = json.loads(out)
    assert [u["unit"] for u in doc["units"]] == ["/embu"]
    assert "/embu: 8 brake applications" in err


def test_outputs_follow_the_umask(repo, tmp_path):
    old = os.umask(0o022)
    try:
        assert main(["replay", str(repo / "bags" / "healthy"), "--json", str(tmp_path / "r.json"),
                     "--report", str(tmp_path / "rep"), "--no-progress"]) == 0
    finally:
        os.umask(old)
    for path in (tmp_path / "r.json", tmp_path / "rep", *(tmp_path / "rep").iterdir()):
        assert path.stat().st_mode & 0o777 == (0o755 if path.is_dir() else 0o644), path


@pytest.mark.parametrize(("address", "message"), [
    ("tls://127.0.0.1:8786", "TLS needs certificates"),
    ("inproc://127.0.0.1/1/2", "in-process address"),
    ("ucx://127.0.0.1:8786", "UCX transport"),
    ("ftp://127.0.0.1:8786", "unknown protocol"),
    ("127.0.0.1:99999", "port 1..65535"),
])
def test_dask_addresses_that_cannot_work_here_are_refused_before_any_work(tmp_path, capsys, address, message):
    assert main(["fleet", str(tmp_path), "--generate", "2", "--scheduler", address, "--out",
                 str(tmp_path / "o"), "--no-progress"]) == 2
    assert message in one_line_error(capsys.readouterr().err, "fleet")


def test_json_into_the_report_directory_being_created_is_fine(repo, tmp_path):
    """The README's first command: ``--report report --json report/replay.json`` on a fresh clone."""
    report = tmp_path / "report"
    assert main(["replay", str(repo / "bags" / "healthy"), "--report", str(report), "--json",
                 str(report / "replay.json"), "--no-progress"]) == 0
    assert sorted(p.name for p in report.iterdir()) == ["index.html", "replay.json"]
