"""Real outputs of the CLIs validate against the shipped JSON Schema files (draft 2020-12)."""

import json
from pathlib import Path

import jsonschema
import pytest

from ebm_wear_monitor.cli.main import main
from ebm_wear_monitor.schema.documents import load

REPO = Path(__file__).resolve().parents[2]


def run(tmp_path: Path, name: str, *argv: str) -> dict:
    """``ebm-wear ARGV --json OUT`` (exit 0 required), its JSON validated against schema ``name``."""
    out = tmp_path / f"{name}.json"
    assert main([*argv, "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    jsonschema.Draft202012Validator(load(name)).validate(doc)
    return doc


def test_replay_outputs(tmp_path):
    doc = run(tmp_path, "replay", "replay", str(REPO / "bags" / "healthy"), "--no-progress")
    assert doc["units"][0]["prognostics"]["predictions"] >= 0  # the optional block is checked too
    worn = run(tmp_path, "replay", "replay", str(REPO / "bags" / "worn"), "--params",
               str(REPO / "bags" / "accelerated_unit.yaml"), "--no-progress")
    assert worn["units"][0]["duty_cycles"] > 0


@pytest.mark.parametrize(("name", "argv"), [
    ("calc_contact", ["calc", "contact", "--params", "screw_003", "--axial-force", "1480"]),
    ("calc_contact", ["calc", "contact", "--params", "embu_000", "--normal-load", "500"]),
    ("calc_wear", ["calc", "wear", "--params", "embu_000", "--axial-force", "20000", "--speed", "20"]),
    ("calc_actuator", ["calc", "actuator", "--params", "embu_000", "--clamp-force", "30000"]),
])
def test_calc_outputs(tmp_path, name, argv):
    run(tmp_path, name, *argv)


@pytest.mark.slow
def test_fleet_output(tmp_path):
    """The sample fleet (bags/fleet, three units) on a one-worker local Dask cluster."""
    doc = run(tmp_path, "fleet", "fleet", str(REPO / "bags" / "fleet"), "--out", str(tmp_path / "out"),
              "--workers", "1", "--no-progress")
    assert len(doc["units"]) == 3 and doc["failures"] == []
    assert json.loads((tmp_path / "out" / "fleet.json").read_text()) == doc
