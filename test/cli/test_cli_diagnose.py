"""``ebm-wear diagnose``: bags in, spec JSON out; bad input exits 2 with one line; self-test JSON."""

import json
from pathlib import Path

import jsonschema
import pytest

from ebm_wear_monitor.bagio import write_unit_bag
from ebm_wear_monitor.cli.main import main
from ebm_wear_monitor.diagnosis.selftest import Case, simulate_case
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.schema.documents import load

SPEC_KEYS = {"verdict", "effect", "ranking", "where", "gap_before", "gap_after", "metric"}
SELFTEST_KEYS = {"cases", "top1_accuracy", "top2_accuracy", "false_positive_rate", "median_shrink",
                 "confusion"}


@pytest.fixture(scope="module")
def bag(tmp_path_factory):
    """A two-unit bag: /embu with extra clearance (6e-5 m), /embu2 nominal."""
    unit = load_unit()
    path = tmp_path_factory.mktemp("diag") / "bag"
    recs = {"/embu": simulate_case(unit, Case({"clearance_growth": 6e-5}, 0.3, 5, 0)),
            "/embu2": simulate_case(unit, Case({}, 0.0, 6, 1))}
    sig = {ns: {"angle": r.angle, "velocity": r.velocity, "axial_force": r.axial_force, "current": r.current}
           for ns, r in recs.items()}
    write_unit_bag(path, {ns: r.t for ns, r in recs.items()}, sig, storage="sqlite3")
    return path


def test_diagnose_bag_writes_spec_json_and_report(bag, tmp_path, capsys):
    out = tmp_path / "d.json"
    assert main(["diagnose", str(bag), "--params", "embu_000", "--json", str(out),
                 "--report", str(tmp_path / "rep")]) == 0
    res = json.loads(out.read_text())
    assert res.keys() >= SPEC_KEYS
    units = {u["unit"]: u for u in res["units"]}
    assert units["/embu"]["verdict"] == "effect" and units["/embu"]["effect"] == "clearance_growth"
    assert units["/embu"]["where"]["signal"] == "axial_force"
    assert units["/embu"]["gap_after"] < 0.3 * units["/embu"]["gap_before"]
    dx = units["/embu"]["ranking"][0]["parameters"]["dx"]
    assert abs(dx["value"] - 6e-5) < max(4 * dx["stderr"], 3e-6)
    assert units["/embu2"]["verdict"] == "none" and units["/embu2"]["effect"] is None
    assert res["where"]["phase"] in (
        "clearance_elimination", "force_generation", "force_maintenance", "force_release")
    assert (tmp_path / "rep" / "index.html").is_file()
    assert "clearance_growth" in capsys.readouterr().out


@pytest.mark.parametrize("argv, msg", [
    (["diagnose", "/nonexistent/bag", "--params", "embu_000"], "bag"),
    (["diagnose", "--params", "embu_000"], "no BAG"),
    (["diagnose", "BAG"], "--params"),
    (["diagnose", "--selftest", "--cases", "0"], "--cases"),
])
def test_bad_input_exits_2_with_one_line(argv, msg, capsys, tmp_path):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and msg in err


def test_unusable_destination_exits_2_before_any_work(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("")
    # the self-test would take seconds: the destinations are checked first
    assert main(["diagnose", "--selftest", "--quick", "--report", str(blocker)]) == 2
    assert main(["diagnose", "--selftest", "--quick", "--json", str(tmp_path)]) == 2
    err = capsys.readouterr()
    assert "--report" in err.err and "--json" in err.err and "self-test:" not in err.out


def test_bag_without_current_exits_2(tmp_path, capsys):
    r = simulate_case(load_unit(), Case({}, 0.0, 7, 0))
    path = tmp_path / "nocur"
    sig = {"angle": r.angle, "velocity": r.velocity, "axial_force": r.axial_force}
    write_unit_bag(path, r.t, {"/embu": sig})
    out = tmp_path / "x.json"
    assert main(["diagnose", str(path), "--params", "embu_000", "--json", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "motor/current" in err and err.count("\n") == 0
    assert not out.exists()


def test_bad_params_file_exits_2(bag, tmp_path, capsys):
    p = tmp_path / "bad.yaml"
    p.write_text("ball_screw: [1, 2]\n")
    out = tmp_path / "x.json"
    assert main(["diagnose", str(bag), "--params", str(p), "--json", str(out)]) == 2
    assert not out.exists()


def test_selftest_json(tmp_path):
    out = tmp_path / "s.json"
    assert main(["diagnose", "--selftest", "--cases", "2", "--json", str(out)]) == 0
    res = json.loads(out.read_text())
    # the shipped JSON Schema (test/schema validates the other CLIs' outputs; this run is shared)
    jsonschema.Draft202012Validator(load("selftest")).validate(res)
    assert res.keys() >= SELFTEST_KEYS and res["cases"] == 2
    assert sum(sum(row.values()) for row in res["confusion"].values()) == 2
    # the foreign world under its own key, with the in-world keys and those of the open set
    foreign = res["foreign"]
    open_set = {"unexplained_accuracy", "pair_accuracy", "catalog_unexplained_rate"}
    assert foreign.keys() >= SELFTEST_KEYS | open_set
    assert foreign["cases"] == 2 and len(foreign["case_results"]) == 2


def test_life_level_on_the_committed_healthy_bag(tmp_path):
    bag = Path(__file__).resolve().parents[2] / "bags" / "healthy"
    out = tmp_path / "life.json"
    assert main(["diagnose", str(bag), "--params", "embu_000", "--life", "--json", str(out)]) == 0
    res = json.loads(out.read_text())
    assert res.keys() >= SPEC_KEYS | {"life"}
    # a no-effect recording of the twin: no actuator-level gap either (it once read viscous_friction)
    assert res["verdict"] == "none" and res["effect"] is None
    life = res["life"]
    assert life["summaries"] >= 8 and life["verdict"] == "none"  # a new unit: no wear-level gap
    assert {r["effect"] for r in life["ranking"]} >= {"wear_coefficient", "running_in", "ball_share"}
