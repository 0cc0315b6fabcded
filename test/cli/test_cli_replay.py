"""``ebm-wear replay``: outputs on success; exit 2, one line, nothing written on bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ebm_wear_monitor.bagio import write_unit_bag
from ebm_wear_monitor.cli.main import main
from ebm_wear_monitor.fleet.synthetic import UnitScenario, write_unit
from ebm_wear_monitor.params import load_unit


@pytest.fixture(scope="module")
def bag(tmp_path_factory):
    scenario = UnitScenario(unit="u", seed=5, bags=1, cycles_per_bag=4, demands_n=(15e3,), hold_s=0.3,
                            rest_s=0.2, wear_acceleration=1.0, prior_cycles=0, rate_hz=100.0,
                            storage="sqlite3")
    (path,) = write_unit(tmp_path_factory.mktemp("cli_replay"), scenario, load_unit())
    return path


def test_replay_prints_and_writes_json_and_report(tmp_path, bag, capsys):
    out, report = tmp_path / "out.json", tmp_path / "report"
    assert main(["replay", str(bag), "--json", str(out), "--report", str(report), "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "/embu: 4 brake applications" in text
    doc = json.loads(out.read_text())
    assert [u["unit"] for u in doc["units"]] == ["/embu"]
    assert doc["units"][0]["duty_cycles"] == 4
    assert (report / "index.html").exists()


def test_bad_input_exits_2_with_one_line_and_writes_nothing(tmp_path, bag, capsys):
    t = np.arange(3.0)
    write_unit_bag(tmp_path / "no_inputs", t, {"/embu": {"current": t}})
    (tmp_path / "adir").mkdir()
    out = tmp_path / "out.json"
    a_file = tmp_path / "no_inputs" / "metadata.yaml"
    cases = [["replay", str(tmp_path / "missing"), "--json", str(out)],
             ["replay", str(bag), str(tmp_path / "adir"), "--json", str(out)],
             ["replay", str(bag), "--json", str(tmp_path / "adir")],
             ["replay", str(bag), "--json", str(a_file / "x.json")],
             ["replay", str(bag), "--json", str(out), "--report", str(a_file)],
             ["replay", str(bag), "--params", str(tmp_path / "nope.yaml"), "--json", str(out)]]
    for argv in cases:
        assert main([*argv, "--no-progress"]) == 2, argv
        err = capsys.readouterr().err.strip()
        assert err.startswith("ebm-wear replay: error:"), err
        assert "\n" not in err
        assert not out.exists()
