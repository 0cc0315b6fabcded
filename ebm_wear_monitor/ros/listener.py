"""Print a wear monitor's outputs as JSON lines (``ros2 topic echo`` is not available as a wheel).

``python -m ebm_wear_monitor.ros.listener [NAMESPACE]`` subscribes to
``NAMESPACE/wear``, ``NAMESPACE/duty_cycle``, ``NAMESPACE/remaining_life`` and
``/diagnostics`` (default namespace ``/embu``) and prints one JSON object per
message: ``{"topic": ..., "recv": <wall time [s]>, "msg": {field: value}}``,
after a first line ``READY`` once the subscriptions exist. Stops on SIGINT/SIGTERM (exit 0: the
listener has no work to cut short). A NAMESPACE that is not a ROS 2 namespace (``--help``
is not one) is one line on stderr and exit status 2. Used by the node's tests and benchmark as
the third process, and by people in the README's live tour.
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from rclpy.signals import SignalHandlerOptions

from ebm_wear_monitor.domain.signals import DEFAULT_NAMESPACE, check_namespace
from ebm_wear_monitor.errors import InputError, exit_status
from ebm_wear_monitor.ros.qos import event_qos, latched_qos

PROG = "ebm-wear-listener"


def to_plain(msg: Any) -> Any:
    """A ROS message as nested dicts/lists of plain Python values (bytes levels as ints)."""
    if hasattr(msg, "get_fields_and_field_types"):
        return {name: to_plain(getattr(msg, name)) for name in msg.get_fields_and_field_types()}
    if isinstance(msg, (list, tuple)):
        return [to_plain(v) for v in msg]
    if isinstance(msg, np.ndarray):
        return msg.tolist()
    if isinstance(msg, bytes):
        return int.from_bytes(msg, "little")
    if isinstance(msg, float) and not np.isfinite(msg):
        return repr(msg)  # JSON has no NaN/inf; "nan", "inf" round-trip through float()
    return msg


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m ebm_wear_monitor.ros.listener",
                                description="print a wear monitor's outputs (wear, duty_cycle, remaining_life"
                                            " under NAMESPACE, and /diagnostics) as JSON lines")
    p.add_argument("namespace", nargs="?", default=DEFAULT_NAMESPACE, metavar="NAMESPACE",
                   help="the monitor's namespace (default /embu, the node's default)")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Print the outputs until SIGINT (exit 130) or SIGTERM (exit 0); exit 2 with one line on a bad
    namespace."""
    args = _parser().parse_args(argv)
    try:
        ns = check_namespace(args.namespace)
    except InputError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    stop: list[int] = []
    signal.signal(signal.SIGINT, lambda s, _f: stop.append(s))
    signal.signal(signal.SIGTERM, lambda s, _f: stop.append(s))
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    from ebm_wear_msgs.msg import DutyCycle, RemainingLife, WearState

    node = rclpy.create_node("wear_listener")

    def printer(topic: str):
        def show(msg: Any) -> None:
            line = {"topic": topic, "recv": time.time(), "msg": to_plain(msg)}
            sys.stdout.write(json.dumps(line) + "\n")
            sys.stdout.flush()
        return show

    for name, mtype, qos in (("wear", WearState, event_qos()), ("duty_cycle", DutyCycle, event_qos()),
                             ("remaining_life", RemainingLife, latched_qos())):
        node.create_subscription(mtype, f"{ns.rstrip('/')}/{name}", printer(name), qos)
    node.create_subscription(DiagnosticArray, "/diagnostics", printer("diagnostics"), 10)
    print("READY", flush=True)
    try:
        while not stop:
            rclpy.spin_once(node, timeout_sec=0.1)
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return exit_status(stop[0])


if __name__ == "__main__":
    sys.exit(main())
