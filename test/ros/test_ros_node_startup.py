"""Start-up validation, run-time parameter changes and state recovery of the live node."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from ebm_wear_monitor.ros.node import STATE_FILE

pytestmark = pytest.mark.ros

NODE = str(Path(sys.executable).parent / "ebm-wear-monitor")


@pytest.mark.timeout(60)
@pytest.mark.parametrize(("args", "needle"), [
    (["-p", "process_rate_hz:=0.0"], "process_rate_hz"),
    (["-p", "executor:=multi_threaded"], "executor"),
    (["-p", "rest_dwell_s:=-1.0"], "rest_dwell_s"),
    (["-p", "unit_params_file:=/nonexistent/unit.yaml"], "/nonexistent/unit.yaml"),
])
def test_bad_start_up_parameters_exit_2_with_one_line(ros_env, tmp_path, args, needle) -> None:
    run = subprocess.run([NODE, "--ros-args", "-p", f"state_dir:={tmp_path}", *args], env=ros_env,
                         capture_output=True, text=True, timeout=45, check=False)
    assert run.returncode == 2, run.stderr
    errors = [line for line in run.stderr.splitlines() if line.startswith("ebm-wear-monitor: error:")]
    assert len(errors) == 1 and needle in errors[0], run.stderr


SET_PARAMS = textwrap.dedent("""
    import json, rclpy
    from rclpy.parameter import Parameter
    from rclpy.parameter_client import AsyncParameterClient
    rclpy.init()
    node = rclpy.create_node("param_setter")
    client = AsyncParameterClient(node, "/embu/wear_monitor")
    assert client.wait_for_services(timeout_sec=20.0)
    out = []
    for name, value in [("min_input_rate_hz", -1.0), ("min_input_rate_hz", 20.0),
                        ("rest_dwell_s", -1.0), ("rest_dwell_s", 0.1), ("executor", "single_threaded")]:
        future = client.set_parameters([Parameter(name, value=value)])
        rclpy.spin_until_future_complete(node, future, timeout_sec=10.0)
        r = future.result().results[0]
        out.append([name, value, r.successful, r.reason])
    future = client.get_parameters(["min_input_rate_hz", "rest_dwell_s"])
    rclpy.spin_until_future_complete(node, future, timeout_sec=10.0)
    out.append([v.double_value for v in future.result().values])
    print(json.dumps(out), flush=True)
""")


@pytest.mark.timeout(60)
def test_thresholds_change_at_run_time_only_to_valid_values(procs, tmp_path) -> None:
    node = procs.node("-r", "__ns:=/embu", state_dir=tmp_path)
    setter = procs.start([sys.executable, "-c", SET_PARAMS])
    out, err = setter.communicate(timeout=45)
    assert setter.returncode == 0, err
    *results, current = json.loads(out.strip().splitlines()[-1])
    accepted = [r[2] for r in results]
    assert accepted == [False, True, False, True, False], results
    assert "min_input_rate_hz" in results[0][3] and "rest_dwell_s" in results[2][3]
    assert current == [20.0, 0.1]
    assert node.poll() is None


@pytest.mark.timeout(60)
def test_a_corrupt_state_file_is_reported_kept_aside_and_the_node_starts_fresh(procs, tmp_path) -> None:
    (tmp_path / STATE_FILE).write_text('{"format": "ebm_wear_monitor.monitor_state", "sta')  # torn write
    lines = procs.listener()
    node = procs.node("-r", "__ns:=/train7/car3/embu2", state_dir=tmp_path)
    seen = lines.wait_until(lambda s: any(m["topic"] == "diagnostics" for m in s), 30)
    status = next(m for m in seen if m["topic"] == "diagnostics")["msg"]["status"][0]
    kv = {v["key"]: v["value"] for v in status["values"]}
    assert "corrupt state" in kv["state_note"] and kv["duty_cycles"] == "0"
    assert status["name"] == "/train7/car3/embu2/wear_monitor"
    assert status["hardware_id"] == "train7/car3/embu2"
    assert (kv["train"], kv["car"], kv["embu"]) == ("train7", "car3", "embu2")
    assert list(tmp_path.glob(f"{STATE_FILE}.corrupt-*"))
    node.send_signal(signal.SIGINT)
    assert node.wait(timeout=20) == 130
    assert (tmp_path / STATE_FILE).is_file()  # a fresh, valid state was saved at shutdown


@pytest.mark.timeout(90)
def test_a_state_saved_under_another_unit_file_is_refused_or_archived(procs, ros_env, tmp_path, repo) -> None:
    """Deliverable 7 of issue 13: the state belongs to its unit; never silently continued."""
    from ebm_wear_monitor.monitor import MonitorCore
    from ebm_wear_monitor.monitor.persistence import load_state
    from ebm_wear_monitor.params import load_unit

    reference, accelerated = load_unit(), load_unit(repo / "bags" / "accelerated_unit.yaml")
    assert reference.digest() != accelerated.digest()
    MonitorCore(reference, state_path=tmp_path / STATE_FILE).save()  # a state of the reference unit
    other = ["-p", f"unit_params_file:={repo / 'bags' / 'accelerated_unit.yaml'}"]
    run = subprocess.run([NODE, "--ros-args", "-p", f"state_dir:={tmp_path}", *other], env=ros_env,
                         capture_output=True, text=True, timeout=60, check=False)
    assert run.returncode == 2, run.stderr
    errors = [line for line in run.stderr.splitlines() if line.startswith("ebm-wear-monitor: error:")]
    assert len(errors) == 1 and "saved under another unit file" in errors[0], run.stderr
    assert reference.digest() in errors[0] and accelerated.digest() in errors[0]
    assert load_state(tmp_path / STATE_FILE)[0].unit_digest == reference.digest()  # untouched

    node = procs.node(*other, "-p", "on_unit_change:=archive", state_dir=tmp_path)
    lines = procs.listener()
    seen = lines.wait_until(lambda s: any(m["topic"] == "diagnostics" for m in s), 30)
    kv = {v["key"]: v["value"] for v in next(m for m in seen if m["topic"] == "diagnostics")
          ["msg"]["status"][0]["values"]}
    assert "archived as" in kv["state_note"] and kv["duty_cycles"] == "0"
    node.send_signal(signal.SIGINT)
    assert node.wait(timeout=20) == 130
    (archived,) = tmp_path.glob(f"{STATE_FILE}.unit-{reference.digest()}-*")
    assert json.loads(archived.read_text())  # kept whole, aside
    assert load_state(tmp_path / STATE_FILE)[0].unit_digest == accelerated.digest()
