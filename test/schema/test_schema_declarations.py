"""The result schema: shipped JSON Schema files current and valid, the contract's keys required, wrong
documents rejected, every adapter's names generated from the declarations (issue 14 item 2)."""

import copy
import json
import math
from dataclasses import fields

import jsonschema
import pytest

from ebm_wear_monitor.schema import from_json, json_row, quantities, table_row, to_json
from ebm_wear_monitor.schema.documents import DOCUMENTS, load, stale
from ebm_wear_monitor.schema.monitor import STATUSES, CycleSummary, MonitorSnapshot
from ebm_wear_monitor.schema.replay import Prognostics

#: interface.md section 4, as printed there (an independent list: the contract, not the declarations)
SPEC_REPLAY = {"unit", "duty_cycles", "wear/screw_raceway_m", "wear/nut_raceway_m", "wear/ball_m",
               "clearance/model_m", "clearance/estimate_m", "clearance/std_m", "remaining_life/limit_m",
               "remaining_life/cycles_p05", "remaining_life/cycles_p50", "remaining_life/cycles_p95",
               "remaining_life/status", "input_faults"}
SPEC_CONTACT = {"normal_load_N", "semi_major_m", "semi_minor_m", "max_pressure_Pa", "deformation_m",
                "contact_type", "contact_area_m2", "contact_angle_deg"}
SPEC_WEAR = {"normal_load_N", "contact_angle_deg", "sliding_velocity_m_s", "contact_area_m2", "contact_type",
             "wear_rate_m_s"}
SPEC_ACTUATOR = {"load_torque_Nm", "friction_torque_Nm", "motor_torque_Nm", "torque_transfer_ratio"}


def required_paths(schema: dict, prefix: str = "") -> set[str]:
    """Every required key of an object schema, as slash paths (nested objects followed)."""
    out = set()
    for key in schema.get("required", []):
        out.add(prefix + key)
        sub = schema.get("properties", {}).get(key, {})
        if sub.get("type") == "object":
            out |= required_paths(sub, f"{prefix}{key}/")
    return out


def snapshot(**changes) -> MonitorSnapshot:
    """A snapshot with every field set (numbers 1.5 .. by field, None where allowed when asked)."""
    values = {}
    for i, f in enumerate(fields(MonitorSnapshot)):
        hint = str(f.type)
        values[f.name] = (i if hint.startswith("int") else f"v{i}" if hint == "str" else {"late": i}
                          if hint.startswith("dict") else 1.5 + i)
    values["life_status"], values["limiting_mechanism"] = "warn", "wear"
    values["input_faults_by_signal"] = {"angle": {"late": 2}}
    return MonitorSnapshot(**(values | changes))


def test_shipped_files_are_what_the_declarations_give_and_valid_json_schema():
    assert stale() == [], "run: python -m ebm_wear_monitor.schema"
    for name in DOCUMENTS:
        doc = load(name)
        jsonschema.Draft202012Validator.check_schema(doc)
        assert doc["$schema"] == "https://json-schema.org/draft/2020-12/schema"


def test_the_contracts_keys_are_required():
    entry = load("replay")["properties"]["units"]["items"]
    assert required_paths(entry) >= SPEC_REPLAY
    assert required_paths(load("fleet")["properties"]["units"]["items"]) == required_paths(entry)
    assert {"units"} <= required_paths(load("replay"))
    for side in ("screw", "nut"):
        assert required_paths(load("calc_contact")["properties"][side]) >= SPEC_CONTACT
        assert required_paths(load("calc_wear")["properties"][side]) >= SPEC_WEAR
    assert required_paths(load("calc_actuator")) >= SPEC_ACTUATOR
    assert {"verdict", "effect", "effects", "ranking", "where", "gap_before", "gap_after", "metric",
            "nuisances"} <= set(load("diagnose")["properties"]["units"]["items"]["required"])
    unit = load("diagnose")["properties"]["units"]["items"]
    assert set(load("diagnose")["required"]) == {"units"} | set(unit["required"])
    assert {"cases", "top1_accuracy", "top2_accuracy", "false_positive_rate", "median_shrink",
            "confusion"} <= set(load("selftest")["required"])


@pytest.mark.parametrize("mutate", [
    lambda e: e["wear"].update(wear_screw_m=e["wear"].pop("screw_raceway_m")),  # an old name
    lambda e: e["remaining_life"].pop("status"),
    lambda e: e["remaining_life"].update(status="limit_reached"),  # gone in issue 11
    lambda e: e.update(duty_cycles=2.5),
    lambda e: e["clearance"].update(estimate_um=1.0),  # an undeclared key
    lambda e: e.pop("input_faults"),
])
def test_the_replay_schema_rejects_a_wrong_entry(mutate):
    doc = {"units": [{"unit": "/embu", **snapshot().to_json_dict(), "bags": ["b"], "messages": 3}],
           "rejected_topics": {}, "storage_problems": []}
    validator = jsonschema.Draft202012Validator(load("replay"))
    validator.validate(doc)
    bad = copy.deepcopy(doc)
    mutate(bad["units"][0])
    assert not validator.is_valid(bad)


def test_json_nulls_unknowns_and_status_is_one_of_the_contracts():
    snap = snapshot(cycles_p05=None, wear_rate_factor=math.nan, life_status=STATUSES[3])
    doc = json.loads(json.dumps(snap.to_json_dict(), allow_nan=False))
    assert doc["remaining_life"]["cycles_p05"] is None and doc["clearance"]["wear_rate_factor"] is None
    assert doc["remaining_life"]["status"] == "insufficient_data"
    assert doc["wear"] == {"screw_raceway_m": snap.screw_raceway_m, "nut_raceway_m": snap.nut_raceway_m,
                           "ball_m": snap.ball_m}
    assert "pending_samples" not in doc  # declared without a JSON path


def test_units_table_row_is_the_same_from_the_record_and_from_its_json():
    snap = snapshot(cycles_p95=None)
    from_record = table_row("units", snap)
    from_file = json_row("units", MonitorSnapshot, snap.to_json_dict())
    assert from_record.keys() == from_file.keys()
    for key, value in from_record.items():
        other = from_file[key]
        assert value == other or (math.isnan(value) and other is None), key
    assert from_record["status"] == "warn" and from_record["input_faults_total"] == snap.input_faults["late"]


def test_applications_row_converts_as_declared():
    cycle = CycleSummary(
        index=3, start_ns=10**9, end_ns=2_500_000_000, phase_durations_s=(0.1, 0.2, 0.3, 0.4),
        peak_force_n=2e4, peak_speed_rad_s=30.0, stroke_rad=1.0, screw_wear_m=(1e-12, 2e-12, 3e-12, 4e-12),
        nut_wear_m=(0.0,) * 4,
        ball_wear_m=(1e-13,) * 4, clearance_observed_m=math.nan, clearance_observed_std_m=math.nan,
        clearance_model_m=2e-4, clearance_estimate_m=2e-4, clearance_std_m=1e-6, growth_rate_m_per_cycle=1e-9,
        growth_rate_std_m_per_cycle=1e-10, wear_rate_factor=1.0, wear_rate_factor_std=0.1)
    row = table_row("applications", cycle, snapshot(cycles_p50=None))
    assert row["stamp_s"] == 2.5 and row["index"] == 3
    assert row["screw_wear_increment_m"] == pytest.approx(1e-11, rel=1e-12)
    assert math.isnan(row["cycles_p50"]) and row["life_status"] == "warn"
    assert "peak_speed_rad_s" not in row  # declared for the message only


def test_prognostics_round_trip_with_the_lambda_key():
    metrics = {f"{q.json[-1]}": (i + 0.5 if "float" in str(t) else i) for i, ((_, q), t) in
               enumerate(zip(quantities(Prognostics), [f.type for f in fields(Prognostics)], strict=True))}
    metrics["alpha_lambda_pass"] = True
    record = from_json(Prognostics, metrics)
    assert record.lam == metrics["lambda"]
    assert to_json(record) == metrics


def test_every_quantity_has_a_unit_and_a_meaning():
    for cls in (CycleSummary, MonitorSnapshot, Prognostics):
        for name, q in quantities(cls):
            text = name in ("life_status", "limiting_mechanism", "alpha_lambda_pass")
            assert q.doc and (q.unit or text), name
