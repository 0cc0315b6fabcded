"""``ebm-wear fleet``: a generated fleet on an existing scheduler; exit 2 and nothing written on bad input."""

from __future__ import annotations

import json
import logging

import pandas as pd
import pytest

from ebm_wear_monitor.cli.main import main


@pytest.fixture(scope="module")
def scheduler():
    """An existing Dask cluster on loopback (threads: cheap to start), reached by its address."""
    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, protocol="tcp", host="127.0.0.1",
                      dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR) as cluster:
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
        yield cluster.scheduler_address


def test_generate_and_run_on_an_existing_scheduler(tmp_path, scheduler, capsys):
    fleet, out, doc = tmp_path / "fleet", tmp_path / "out", tmp_path / "fleet.json"
    argv = ["fleet", str(fleet), "--generate", "3", "--cycles-per-bag", "2", "--bags-per-unit", "1", "--rate",
            "100", "--scheduler", scheduler, "--out", str(out), "--json", str(doc), "--no-progress"]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "3 units: 3 processed, 0 unchanged" in text
    units = json.loads(doc.read_text())["units"]
    names = ["train00/car0/embu0", "train00/car0/embu1", "train00/car1/embu0"]
    assert sorted(u["unit"] for u in units) == names
    assert len(pd.read_parquet(out / "units.parquet")) == 3
    assert [p.name for p in (out / "report").iterdir()] == ["index.html"]  # the self-contained dashboard
    page = (out / "report" / "index.html").read_text()
    assert all(f'data-unit="{name}"' in page for name in names)
    assert (fleet / "params.yaml").exists()
    # host:port without a protocol, as Dask itself accepts it (issue 13)
    bare = scheduler.removeprefix("tcp://")
    assert main(["fleet", str(fleet), "--scheduler", bare, "--out", str(out), "--no-progress"]) == 0
    assert "0 processed, 3 unchanged" in capsys.readouterr().out  # same bags, same unit file: skipped


def test_bad_input_exits_2(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("ebm_wear_monitor.fleet.cluster.CONNECT_TIMEOUT_S", 1.0)
    (tmp_path / "exists").mkdir()
    (tmp_path / "empty").mkdir()
    (tmp_path / "afile").write_text("a file, not a directory")
    out = tmp_path / "out"
    cases = [["fleet", str(tmp_path / "missing"), "--out", str(out)],
             ["fleet", str(tmp_path / "exists"), "--generate", "2", "--out", str(out)],
             ["fleet", str(tmp_path / "exists"), "--scheduler", "127.0.0.1:1", "--out", str(out)],
             ["fleet", str(tmp_path / "exists"), "--scheduler", "tcp://127.0.0.1:1", "--out", str(out)],
             ["fleet", str(tmp_path / "empty"), "--workers", "0", "--out", str(out)],
             ["fleet", str(tmp_path / "exists"), "--json", str(tmp_path / "exists"), "--out", str(out)],
             ["fleet", str(tmp_path / "new"), "--generate", "1", "--out", str(tmp_path / "afile" / "out")]]
    for argv in cases:
        assert main([*argv, "--no-progress"]) == 2, argv
        err = capsys.readouterr().err.strip()
        assert err.startswith("ebm-wear fleet: error:"), err
        assert "\n" not in err
    assert not out.exists() and not (tmp_path / "new").exists()


@pytest.mark.timeout(180)
def test_ctrl_c_stops_the_fleet_with_130_and_one_line(tmp_path):
    """Ctrl-C signals the whole foreground process group, Dask's worker processes included: only the
    fleet command answers (exit 130, one line), no worker prints a KeyboardInterrupt traceback."""
    import os
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    fleet = tmp_path / "fleet"
    ebm_wear = str(Path(sys.executable).parent / "ebm-wear")
    proc = subprocess.Popen([ebm_wear, "fleet", str(fleet), "--generate", "8", "--workers", "2", "--out",
                             str(tmp_path / "out"), "--no-progress"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 120
    while not (fleet / "params.yaml").exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.1)  # the cluster is up once the generation writes its unit file
    assert proc.poll() is None, proc.communicate()
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert err == "ebm-wear fleet: interrupted\n"
