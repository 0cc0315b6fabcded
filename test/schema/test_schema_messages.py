"""ROS messages and /diagnostics generated from the schema: every message field filled, values as declared."""

import math

from ebm_wear_msgs.msg import DutyCycle, RemainingLife, WearState

from ebm_wear_monitor.ros.messages import duty_cycle, remaining_life, wear_state
from ebm_wear_monitor.schema import diagnostic_values, quantities
from ebm_wear_monitor.schema.monitor import CycleSummary, MonitorSnapshot

CYCLE = CycleSummary(index=7, start_ns=1_700_000_000_123_456_789, end_ns=1_700_000_002_000_000_001,
                     phase_durations_s=(0.1, 0.2, 0.3, 0.4), peak_force_n=2.5e4, peak_speed_rad_s=31.0,
                     stroke_rad=1.25, screw_wear_m=(1e-12, 2e-12, 3e-12, 4e-12), nut_wear_m=(5e-13,) * 4,
                     ball_wear_m=(1e-13,) * 4, clearance_observed_m=2.1e-4, clearance_observed_std_m=1e-6,
                     clearance_model_m=2e-4, clearance_estimate_m=2.05e-4, clearance_std_m=9e-7,
                     growth_rate_m_per_cycle=1e-9, growth_rate_std_m_per_cycle=2e-10, wear_rate_factor=1.1,
                     wear_rate_factor_std=0.2)


def snapshot(status: str = "warn") -> MonitorSnapshot:
    values = {name: 0.5 + i for i, (name, _) in enumerate(quantities(MonitorSnapshot))}
    ints = ("duty_cycles", "observations", "clearance_steps", "growth_changes", "pending_samples")
    values |= {k: int(values[k]) for k in ints}
    values |= {"cycles_p95": None, "life_status": status, "limiting_mechanism": "wear",
               "last_stamp_ns": 3_000_000_007, "input_faults": {"late": 2}, "segments": {"cycle": 7},
               "input_faults_by_signal": {}, "input_rates_hz": {}}
    return MonitorSnapshot(**values)


def leaf_fields(msg) -> set[str]:
    """Every field of a message type, nested ones dotted (header.stamp), frame_id left out."""
    out = set()
    for name, kind in msg.get_fields_and_field_types().items():
        if kind == "std_msgs/Header":
            out.add(f"{name}.stamp")
        else:
            out.add(name)
    return out


def targets(cls, message: str) -> set[str]:
    out = set()
    for _, q in quantities(cls):
        t = q.msg.get(message)
        out |= set(t) if isinstance(t, tuple) else {t} if t else set()
    return out


def test_every_message_field_is_declared_once():
    assert targets(CycleSummary, "DutyCycle") == leaf_fields(DutyCycle())
    assert targets(MonitorSnapshot, "WearState") == leaf_fields(WearState())
    assert targets(MonitorSnapshot, "RemainingLife") == leaf_fields(RemainingLife())


def test_duty_cycle_values_stamps_and_arrays():
    msg = duty_cycle(CYCLE)
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (1_700_000_002, 1)
    assert (msg.start.sec, msg.start.nanosec) == (1_700_000_000, 123_456_789)
    assert (msg.clearance_elimination_s, msg.force_release_s) == (0.1, 0.4)
    assert list(msg.screw_wear_m) == list(CYCLE.screw_wear_m) and msg.index == 7
    assert msg.clearance_observed_std_m == CYCLE.clearance_observed_std_m


def test_snapshot_messages_status_constants_and_nan_for_unknown():
    for status, constant in (("ok", RemainingLife.STATUS_OK), ("warn", RemainingLife.STATUS_WARN),
                             ("due", RemainingLife.STATUS_DUE),
                             ("insufficient_data", RemainingLife.STATUS_INSUFFICIENT_DATA)):
        assert remaining_life(snapshot(status)).status == constant
    snap = snapshot()
    life, wear = remaining_life(snap), wear_state(snap)
    assert math.isnan(life.cycles_p95) and life.cycles_p05 == snap.cycles_p05
    assert (wear.header.stamp.sec, wear.header.stamp.nanosec) == (3, 7)
    assert wear.screw_raceway_m == snap.screw_raceway_m and wear.duty_cycles == snap.duty_cycles


def test_diagnostic_keys_are_the_declared_ones():
    values = diagnostic_values(snapshot())
    assert values["wear_screw_raceway_m"] == snapshot().screw_raceway_m
    assert math.isnan(values["remaining_cycles_p95"]) and values["remaining_life_status"] == "warn"
    assert values["fault_late"] == 2 and values["segments_cycle"] == 7
    declared = {q.diag for _, q in quantities(MonitorSnapshot) if q.diag and "{}" not in q.diag}
    assert declared == set(values) - {"fault_late", "segments_cycle"}
