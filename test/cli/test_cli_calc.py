"""``ebm-wear calc contact | wear | actuator``: JSON keys of interface.md section 4 and exit-2 errors."""

import json

import pytest
import yaml

from ebm_wear_monitor.cli.main import main
from ebm_wear_monitor.params import reference_path

CONTACT_KEYS = {"normal_load_N", "semi_major_m", "semi_minor_m", "max_pressure_Pa", "deformation_m",
                "contact_type", "contact_area_m2", "contact_angle_deg"}
WEAR_KEYS = {"normal_load_N", "contact_angle_deg", "sliding_velocity_m_s", "contact_area_m2",
             "contact_type", "wear_rate_m_s"}
ACTUATOR_KEYS = {"load_torque_Nm", "friction_torque_Nm", "motor_torque_Nm", "torque_transfer_ratio"}


def run_json(tmp_path, *args):
    out = tmp_path / "out.json"
    assert main(["calc", *args, "--json", str(out)]) == 0
    return json.loads(out.read_text())


def test_calc_contact_axial_force_reproduces_003_table_4(tmp_path):
    res = run_json(tmp_path, "contact", "--params", "screw_003", "--axial-force", "1480")
    assert set(res) == {"screw", "nut"}
    for side in res.values():
        assert set(side) >= CONTACT_KEYS
        assert side["contact_type"] in ("elastic", "elastic-plastic")
    assert res["screw"]["semi_major_m"] == pytest.approx(0.4611e-3, rel=0.01)
    assert res["nut"]["max_pressure_Pa"] == pytest.approx(1058.2e6, rel=0.01)


def test_calc_contact_normal_load(tmp_path):
    res = run_json(tmp_path, "contact", "--params", "embu_000", "--normal-load", "200")
    assert res["screw"]["normal_load_N"] == res["nut"]["normal_load_N"] == 200.0
    assert res["screw"]["contact_angle_deg"] == 45.0


def test_calc_wear(tmp_path, capsys):
    res = run_json(tmp_path, "wear", "--params", "embu_000", "--axial-force", "20000", "--speed", "-15")
    for side in ("screw", "nut"):
        assert set(res[side]) >= WEAR_KEYS
        assert res[side]["wear_rate_m_s"] > 0.0
    assert res["screw"]["wear_rate_m_s"] > res["nut"]["wear_rate_m_s"]
    assert "wear_rate_m_s" in capsys.readouterr().out
    rolling = run_json(tmp_path, "wear", "--params", "embu_000", "--axial-force", "20000", "--speed", "15",
                       "--kinematics", "rolling")
    assert rolling["nut"]["sliding_velocity_m_s"] == 0.0


def test_calc_actuator(tmp_path):
    res = run_json(tmp_path, "actuator", "--params", "embu_000", "--clamp-force", "30000")
    assert set(res) >= ACTUATOR_KEYS
    assert 0.0 < res["torque_transfer_ratio"] < 1.0


def write_unit(tmp_path, edit):
    data = yaml.safe_load(reference_path("embu_000").read_text())
    edit(data)
    path = tmp_path / "unit.yaml"
    path.write_text(yaml.safe_dump(data))
    return str(path)


@pytest.mark.parametrize(("edit", "message"), [
    (lambda d: d["ball_screw"].__setitem__("screw_conformity", 0.5), "screw_conformity"),
    (lambda d: d["ball_screw"].__setitem__("nut_conformity", 0.45), "nut_conformity"),
    (lambda d: d["materials"]["ball"].__setitem__("elastic_modulus", -2e11), "elastic_modulus"),
    (lambda d: d["materials"]["screw"].pop("hardness"), "hardness"),
    (lambda d: d.pop("lubricant"), "lubricant"),
    (lambda d: d.pop("actuator"), "actuator"),
    (lambda d: d["wear"].__setitem__("boundary_friction", -1e-301), "boundary_friction: must be >= 0"),
    (lambda d: d["wear"].__setitem__("boundary_friction", 1.5), "boundary_friction: must be <= 0.3"),
])
def test_bad_parameter_files_exit_2_with_one_line(tmp_path, capsys, edit, message):
    params = write_unit(tmp_path, edit)
    out = tmp_path / "never.json"
    calc = "actuator" if message == "actuator" else "wear"
    load = ["--clamp-force", "1000"] if calc == "actuator" else ["--axial-force", "1000", "--speed", "1"]
    assert main(["calc", calc, "--params", params, *load, "--json", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err
    assert not out.exists()


@pytest.mark.parametrize("args", [
    ["contact", "--params", "embu_000", "--axial-force", "-100"],
    ["contact", "--params", "embu_000", "--normal-load", "0"],
    ["wear", "--params", "embu_000", "--axial-force", "-5", "--speed", "3"],
    ["wear", "--params", "embu_000", "--axial-force", "nan", "--speed", "3"],
    ["actuator", "--params", "embu_000", "--clamp-force", "-1"],
    ["contact", "--params", "no_such_unit.yaml", "--axial-force", "100"],
])
def test_bad_inputs_exit_2(tmp_path, capsys, args):
    out = tmp_path / "never.json"
    assert main(["calc", *args, "--json", str(out)]) == 2
    assert capsys.readouterr().err.startswith("ebm-wear calc: error:")
    assert not out.exists()


@pytest.mark.parametrize("where", ["a_file/out.json", "a_dir"])
def test_unwritable_json_destination_exits_2_with_one_line(tmp_path, capsys, where):
    (tmp_path / "a_file").write_text("not a directory")
    (tmp_path / "a_dir").mkdir()
    target = tmp_path / where
    argv = ["calc", "contact", "--params", "embu_000", "--axial-force", "100", "--json", str(target)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("ebm-wear calc: error:") and str(target) in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_dir", "a_file"]  # no temporary file left
    assert list((tmp_path / "a_dir").iterdir()) == []


def test_json_into_missing_directory_creates_it(tmp_path):
    assert run_json(tmp_path / "new" / "sub", "contact", "--params", "embu_000", "--normal-load", "200")


def test_binary_unit_file_exits_2_with_one_line(tmp_path, capsys):
    unit = tmp_path / "unit.yaml"
    unit.write_bytes(b"\xff\xfe\x00garbage")
    assert main(["calc", "contact", "--params", str(unit), "--axial-force", "100"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(unit) in err
