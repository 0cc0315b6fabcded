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


def test_json_into_a_missing_directory_is_refused_and_creates_nothing(tmp_path, capsys):
    target = tmp_path / "new" / "sub" / "out.json"
    argv = ["calc", "contact", "--params", "embu_000", "--normal-load", "200", "--json", str(target)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "does not exist" in err
    assert list(tmp_path.iterdir()) == []


def test_json_dash_writes_only_the_json_to_stdout(capsys):
    assert main(["calc", "contact", "--params", "embu_000", "--axial-force", "20000", "--json", "-"]) == 0
    out, err = capsys.readouterr()
    doc = json.loads(out)  # nothing else on stdout
    assert set(doc) == {"screw", "nut"} and set(doc["screw"]) >= CONTACT_KEYS
    assert "deformation_m" in err  # the lines for people went to stderr


def test_json_file_gets_the_users_umask(tmp_path):
    import os
    old = os.umask(0o022)
    try:
        run_json(tmp_path, "contact", "--params", "embu_000", "--axial-force", "20000")
        os.umask(0o027)
        (tmp_path / "b").mkdir()
        run_json(tmp_path / "b", "contact", "--params", "embu_000", "--axial-force", "20000")
    finally:
        os.umask(old)
    assert (tmp_path / "out.json").stat().st_mode & 0o777 == 0o644
    assert (tmp_path / "b" / "out.json").stat().st_mode & 0o777 == 0o640


def test_each_calculator_reads_only_the_blocks_it_uses(tmp_path, capsys):
    """Paper 003's ball screw has no lubricant and no actuator data (interface.md section 3)."""
    full = yaml.safe_load(reference_path("embu_000").read_text())
    contact_only = tmp_path / "screw.yaml"
    contact_only.write_text(yaml.safe_dump({k: full[k] for k in ("ball_screw", "materials")}))
    actuator_only = tmp_path / "actuator.yaml"
    actuator_only.write_text(yaml.safe_dump({k: full[k] for k in ("ball_screw", "actuator")}))
    ref = run_json(tmp_path, "contact", "--params", "embu_000", "--axial-force", "20000")
    assert run_json(tmp_path, "contact", "--params", str(contact_only), "--axial-force", "20000") == ref
    ref = run_json(tmp_path, "actuator", "--params", "embu_000", "--clamp-force", "20000")
    assert run_json(tmp_path, "actuator", "--params", str(actuator_only), "--clamp-force", "20000") == ref
    for calc, params, missing in (("wear", contact_only, "lubricant"), ("actuator", contact_only, "actuator"),
                                  ("contact", actuator_only, "materials")):
        load = ["--clamp-force", "1000"] if calc == "actuator" else ["--axial-force", "1000"]
        load += ["--speed", "1"] if calc == "wear" else []
        assert main(["calc", calc, "--params", str(params), *load]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and f"section '{missing}'" in err, err


@pytest.mark.parametrize(("args", "message"), [
    (["contact", "--axial-force", "1e30"], "outside the physical envelope"),
    (["contact", "--axial-force", "80001"], "at most 8e+04 N"),
    (["contact", "--normal-load", "1e9"], "outside the physical envelope"),
    (["wear", "--axial-force", "2e4", "--speed", "201"], "at most 200 rad/s"),
    (["wear", "--axial-force", "2e4", "--speed=-1e6"], "at most 200 rad/s"),
    (["wear", "--axial-force", "1e7", "--speed", "20"], "outside the physical envelope"),
    (["actuator", "--clamp-force", "1e30"], "outside the physical envelope"),
])
def test_forces_and_speeds_outside_the_envelope_are_refused(tmp_path, capsys, args, message):
    out = tmp_path / "never.json"
    assert main(["calc", args[0], "--params", "embu_000", *args[1:], "--json", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err, err
    assert not out.exists()


def test_envelope_edges_are_accepted(tmp_path):
    """The edges themselves are inside: 80 kN, 200 rad/s, and the per-ball load 80 kN gives (000 eq. 5)."""
    at_max = run_json(tmp_path, "contact", "--params", "embu_000", "--axial-force", "80000")
    q = at_max["screw"]["normal_load_N"]
    assert run_json(tmp_path, "contact", "--params", "embu_000", "--normal-load", f"{q * (1 - 1e-12)!r}")
    assert run_json(tmp_path, "wear", "--params", "embu_000", "--axial-force", "20000", "--speed=-200")


def test_binary_unit_file_exits_2_with_one_line(tmp_path, capsys):
    unit = tmp_path / "unit.yaml"
    unit.write_bytes(b"\xff\xfe\x00garbage")
    assert main(["calc", "contact", "--params", str(unit), "--axial-force", "100"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(unit) in err
