"""A live publish/subscribe round trip of Float64Stamped between two processes over real DDS."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

pytestmark = pytest.mark.ros

N_MESSAGES = 50

SUBSCRIBER = textwrap.dedent(f"""
    import json, rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy, HistoryPolicy
    from ebm_wear_msgs.msg import Float64Stamped
    rclpy.init()
    node = rclpy.create_node("roundtrip_listener")
    got = []
    qos = QoSProfile(depth={N_MESSAGES}, reliability=ReliabilityPolicy.RELIABLE,
                     history=HistoryPolicy.KEEP_ALL)
    node.create_subscription(Float64Stamped, "/embu/axial_force",
        lambda m: got.append([m.header.stamp.sec, m.header.stamp.nanosec, m.header.frame_id, m.data]), qos)
    print("READY", flush=True)
    while len(got) < {N_MESSAGES}:
        rclpy.spin_once(node, timeout_sec=0.2)
    print(json.dumps(got), flush=True)
    node.destroy_node(); rclpy.shutdown()
""")

PUBLISHER = textwrap.dedent(f"""
    import time, rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy, HistoryPolicy
    from ebm_wear_msgs.msg import Float64Stamped
    rclpy.init()
    node = rclpy.create_node("roundtrip_talker")
    qos = QoSProfile(depth={N_MESSAGES}, reliability=ReliabilityPolicy.RELIABLE,
                     history=HistoryPolicy.KEEP_ALL)
    pub = node.create_publisher(Float64Stamped, "/embu/axial_force", qos)
    deadline = time.monotonic() + 20
    while pub.get_subscription_count() == 0 and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
    for k in range({N_MESSAGES}):
        m = Float64Stamped(data=1000.0 * k + 0.5)
        m.header.stamp.sec, m.header.stamp.nanosec, m.header.frame_id = 100 + k, 1000 * k, "pad_sensor"
        pub.publish(m)
    time.sleep(1.0)  # keep the writer alive while reliable delivery completes
    node.destroy_node(); rclpy.shutdown()
""")


def test_float64stamped_crosses_processes(ros_env: dict[str, str]) -> None:
    listener = subprocess.Popen([sys.executable, "-c", SUBSCRIBER], env=ros_env,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert listener.stdout is not None
        assert listener.stdout.readline().strip() == "READY"
        talker = subprocess.run([sys.executable, "-c", PUBLISHER], env=ros_env,
                                capture_output=True, text=True, timeout=60, check=False)
        assert talker.returncode == 0, talker.stderr
        out, err = listener.communicate(timeout=30)
    finally:
        listener.kill()
    assert listener.returncode == 0, err
    got = json.loads(out.strip().splitlines()[-1])
    expected = [[100 + k, 1000 * k, "pad_sensor", 1000.0 * k + 0.5] for k in range(N_MESSAGES)]
    assert got == expected
