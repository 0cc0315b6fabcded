"""``ebm-wear diagnose --json`` validates against the shipped diagnose JSON Schema (interface.md section 4 and
the diagnosis contract): a healthy recording (bags/healthy) and a unit with an effect (extra clearance)."""

import json
from pathlib import Path

import jsonschema
import pytest

from ebm_wear_monitor.bagio import write_unit_bag
from ebm_wear_monitor.cli.main import main
from ebm_wear_monitor.diagnosis.selftest import Case, simulate_case
from ebm_wear_monitor.params import load_unit
from ebm_wear_monitor.schema.documents import load

REPO = Path(__file__).resolve().parents[2]


def diagnose(tmp_path: Path, bag: Path) -> dict:
    out = tmp_path / "d.json"
    assert main(["diagnose", str(bag), "--params", "embu_000", "--json", str(out), "--no-progress"]) == 0
    doc = json.loads(out.read_text())
    jsonschema.Draft202012Validator(load("diagnose")).validate(doc)
    return doc


@pytest.mark.slow
def test_diagnose_output_of_a_healthy_recording(tmp_path):
    doc = diagnose(tmp_path, REPO / "bags" / "healthy")
    assert doc["units"][0]["unit"] == doc["unit"]


@pytest.mark.slow
def test_diagnose_output_with_an_effect(tmp_path):
    rec = simulate_case(load_unit(), Case({"clearance_growth": 6e-5}, 0.3, 5, 0))
    bag = tmp_path / "bag"
    signals = {name: getattr(rec, name) for name in ("angle", "velocity", "axial_force", "current")}
    write_unit_bag(bag, {"/embu": rec.t}, {"/embu": signals}, storage="sqlite3")
    doc = diagnose(tmp_path, bag)
    assert doc["verdict"] == "effect" and doc["effects"] and doc["ranking"][0]["magnitude"]
