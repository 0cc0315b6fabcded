"""The live wear-monitor node (``wear_monitor``, console script ``ebm-wear-monitor``): a thin rclpy adapter.

Everything that computes lives in the ROS-free monitor core
(:mod:`ebm_wear_monitor.monitor`); ``ebm-wear replay`` drives the same core,
so the node and the offline replay give identical numbers. The node only:

1. subscribes to ``screw/angle``, ``screw/velocity`` and ``axial_force``
   (interface.md section 2; sensor-data QoS by default) with raw callbacks that
   append the serialised record to a list (:mod:`.inputs`);
2. at ``process_rate_hz`` decodes each list in bulk (``monitor.wire``) into one
   batch of (header stamp [ns], value) per topic and hands it to the core's
   :class:`~ebm_wear_monitor.monitor.Feeder`, the component ``ebm-wear replay``
   drives with storage chunks; alignment, duty-cycle segmentation, wear
   integration, the Kalman filter and the remaining life all happen in the core;
3. publishes one ``duty_cycle`` and one ``wear`` message per completed brake
   application, ``remaining_life`` (latched) after each (from the snapshot the
   core takes right after it), and ``/diagnostics`` at ``diagnostics_period_s``
   (:mod:`.diagnostics`);
4. persists the state atomically (the core's ``save_state``: temp file, fsync,
   rename) every ``checkpoint_every_cycles`` applications and at shutdown
   (SIGINT or SIGTERM: last inputs processed, state saved, exit 0), and resumes
   it at start, only if it belongs to the unit: a state saved under another unit
   file (``unit_digest`` differs) is refused (exit 2) or, with
   ``on_unit_change:=archive``, moved aside and a new one started; never
   silently continued (:func:`state_for_unit`).

Namespace: the node runs under ``/embu`` (interface.md section 2) unless remapped
with ``--ros-args -r __ns:=/train7/car3/embu2``.

Executor: the EventsExecutor, spun in ``spin_once(timeout_sec=0.2)`` steps
(spun without a timeout it hangs in rclpy 9.1.2); ``executor:=single_threaded``
switches to the SingleThreadedExecutor. Bad input never stops the node: the
core counts and discards bad samples; an exception inside the core on one
batch is logged, counted as ``core_errors`` and shown as ERROR in diagnostics.

Start-up errors (bad parameter, unreadable unit file) print one line
``ebm-wear-monitor: error: ...`` and exit with status 2.
"""

from __future__ import annotations

import os
import signal
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from rclpy.executors import Executor, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from ebm_wear_monitor.domain.signals import DEFAULT_NAMESPACE, FLOAT64_STAMPED, INPUT_TOPICS, MONITOR_SIGNALS
from ebm_wear_monitor.errors import InputError, exit_status
from ebm_wear_monitor.monitor import Batch, Feeder, MonitorCore, MonitorState, load_state
from ebm_wear_monitor.monitor.kalman import load_filterpy
from ebm_wear_monitor.monitor.persistence import backup_path
from ebm_wear_monitor.params import UnitParams, load_unit
from ebm_wear_monitor.reports.life import life_view
from ebm_wear_monitor.ros import messages
from ebm_wear_monitor.ros.diagnostics import (
    Health,
    Thresholds,
    assess,
    diagnostic_array,
    namespace_parts,
    unit_status,
)
from ebm_wear_monitor.ros.inputs import InputBuffer
from ebm_wear_monitor.ros.parameters import MONITOR_NAMES, NodeParameters
from ebm_wear_monitor.ros.qos import event_qos, input_qos, latched_qos
from ebm_wear_monitor.schema import diagnostic_values

NODE_NAME = "wear_monitor"
STATE_FILE = "monitor_state.json"
#: fault kinds of the core that are normal operation, not a reason to WARN (still shown as key-values)
BENIGN_FAULTS = frozenset({"out_of_order"})
#: the remaining life is logged at most this often when its status does not change [s]
LIFE_LOG_PERIOD_S = 600.0


def _check_writable(directory: Path) -> None:
    """Create the state directory and prove it writable now, not at the first checkpoint."""
    try:
        directory.mkdir(parents=True, exist_ok=True)
        probe = directory / f".write-test-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        raise InputError(f"state directory {directory}: not writable ({exc.strerror or exc})") from None


def state_for_unit(path: Path, state: MonitorState | None, unit: UnitParams, policy: str
                   ) -> tuple[MonitorState | None, str]:
    """The loaded ``state`` if it was saved under ``unit`` (same ``unit_digest``), with a note.

    Otherwise ``policy`` ``refuse``: InputError (one line, exit 2); ``archive``: the state file and
    its backup are renamed ``<name>.unit-<their digest>-<UTC>`` and the monitor starts anew.
    A state without a digest (never written by this monitor) is taken as it is.
    """
    if state is None or not state.unit_digest or state.unit_digest == unit.digest():
        return state, ""
    what = (f"state {path} was saved under another unit file (unit '{state.unit_name}', digest "
            f"{state.unit_digest}) than the one given (unit '{unit.name}', digest {unit.digest()})")
    if policy != "archive":
        raise InputError(f"{what}; not continuing it: give the unit file it was made with, another "
                         "state_dir, or on_unit_change:=archive to keep it aside and start anew")
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    moved = []
    for file in (path, backup_path(path)):
        if file.exists():
            aside = file.with_name(f"{file.name}.unit-{state.unit_digest}-{stamp}")
            try:
                os.replace(file, aside)
            except OSError as exc:
                raise InputError(f"{file}: cannot archive the state ({exc.strerror or exc})") from None
            moved.append(aside.name)
    return None, f"{what}; archived as {', '.join(moved)}, starting anew"


class WearMonitorNode:
    """The adapter between one rclpy ``Node`` and one ``MonitorCore`` (one EMBU)."""

    def __init__(self, node: Node, params: NodeParameters) -> None:
        self.node = node
        self.params = params
        self.unit = load_unit(params.unit_params_file or None)
        self.state_path = params.state_dir() / STATE_FILE
        _check_writable(self.state_path.parent)
        state, problems = load_state(self.state_path)
        state, archived = state_for_unit(self.state_path, state, self.unit, params.on_unit_change)
        problems += [archived] if archived else []
        for problem in problems:
            node.get_logger().warning(problem)
        self.state_note = "; ".join(problems)
        # the core saves the state atomically every checkpoint_every_cycles applications, before
        # returning them: a published application is never newer than what a restart resumes from
        self.core = MonitorCore(self.unit, params.monitor_config, state, state_path=self.state_path)
        load_filterpy()  # the Kalman filters' library now, not in the timer at the first application
        self.feeder = Feeder(self.core)
        params.listeners.append(self.on_parameters)
        self.core_errors = 0
        self.core_error = ""
        self.faults_reported = 0
        self.wrong_type_publishers = 0
        self.life_status_logged = ""

        qos = input_qos(params.qos_reliability == "reliable", params.qos_depth)
        msg_type = messages.Float64Stamped
        self.inputs = {s: InputBuffer(s) for s in MONITOR_SIGNALS}
        # raw=True hands the callback the serialised bytes, which rclpy's annotation does not cover
        self._subs = [node.create_subscription(msg_type, INPUT_TOPICS[s],
                                               self.inputs[s].pending.append,  # type: ignore[arg-type]
                                               qos, raw=True) for s in MONITOR_SIGNALS]
        self.pub_wear = node.create_publisher(messages.WearState, "wear", event_qos())
        self.pub_cycle = node.create_publisher(messages.DutyCycle, "duty_cycle", event_qos())
        self.pub_life = node.create_publisher(messages.RemainingLife, "remaining_life", latched_qos())
        self.pub_diag = node.create_publisher(DiagnosticArray, "/diagnostics", 10)
        # (step takes no argument: rclpy hands a TimerInfo to timer callbacks that accept one)
        node.create_timer(1.0 / params.process_rate_hz, self.step)
        node.create_timer(params.diagnostics_period_s, self.publish_diagnostics)
        self.publish_remaining_life()
        node.get_logger().info(
            f"monitoring unit {self.unit.name} ({params.unit_params_file or 'reference'}), "
            f"state {self.state_path}, {self.core.snapshot().duty_cycles} applications so far")

    # ------------------------------------------------------------------ processing
    def step(self) -> None:
        """Push every buffered input through the feeder; publish each application it completed (the core
        checkpoints): one ``duty_cycle``, one ``wear`` and the latched ``remaining_life`` per application,
        from the snapshot taken right after it (the replay records the same snapshots)."""
        try:
            batch = Batch()
            for buffer in self.inputs.values():
                buffer.drain(batch)
            events = self.feeder.feed(batch)
        except Exception as exc:  # bad input must never stop the node
            self.core_errors += 1
            self.core_error = " ".join(str(exc).split())[:200] or type(exc).__name__
            self.node.get_logger().error(f"monitor core failed on a batch: {self.core_error}",
                                         throttle_duration_sec=5.0)
            return
        for event in events:
            self.pub_cycle.publish(messages.duty_cycle(event.cycle))
            self.pub_wear.publish(messages.wear_state(event.snapshot))
            self.publish_remaining_life(event.snapshot)
        if events:
            self.log_remaining_life(events[-1].snapshot)

    def on_parameters(self, names: set[str]) -> None:
        """A validated parameter change: hand changed core thresholds to the core."""
        if names & MONITOR_NAMES:
            self.core.configure(self.params.monitor_config)

    def publish_remaining_life(self, snap=None) -> None:
        self.pub_life.publish(messages.remaining_life(snap or self.core.snapshot()))

    def log_remaining_life(self, snap) -> None:
        """Remaining life for people (applications, hours, days): at once when the status changes,
        else at most every ``LIFE_LOG_PERIOD_S``."""
        text = (f"{snap.duty_cycles} applications, clearance {snap.clearance_estimate_m * 1e3:.4f} mm; "
                f"remaining life {_life_line(snap)}")
        if snap.life_status != self.life_status_logged:
            self.life_status_logged = snap.life_status
            self.node.get_logger().info(text)
        else:
            self.node.get_logger().info(text, throttle_duration_sec=LIFE_LOG_PERIOD_S)

    def close(self) -> None:
        """Shutdown: process what is buffered, then save the state (atomic: temp file, fsync, rename)."""
        self.step()
        self.core.save()

    # ------------------------------------------------------------------ diagnostics
    def _count_wrong_type_publishers(self) -> int:
        count = 0
        for sub in self._subs:
            for info in self.node.get_publishers_info_by_topic(sub.topic_name):
                count += info.topic_type != FLOAT64_STAMPED
        return count

    def publish_diagnostics(self) -> None:
        snap = self.core.snapshot()
        self.wrong_type_publishers = self._count_wrong_type_publishers()
        faults = {k: v for k, v in snap.input_faults.items() if k not in BENIGN_FAULTS}
        faults.setdefault("undecodable", 0)  # counted by the core (inputs.py); shown even when zero
        faults["wrong_type_publishers"] = self.wrong_type_publishers
        faults["core_errors"] = self.core_errors
        total = sum(faults.values())
        rates = {s: b.rate_hz() for s, b in self.inputs.items()}
        ages = {s: b.age_s() for s, b in self.inputs.items()}
        p = self.params
        level, text = assess(
            Health(life_status=snap.life_status,
                   life_text=_life_line(snap),
                   input_rate_hz=rates, input_age_s=ages,
                   new_faults=total - self.faults_reported, core_error=self.core_error),
            Thresholds(p.stale_timeout_s, p.min_input_rate_hz))
        self.faults_reported = total
        self.core_error = ""  # ERROR for the period(s) with a failure; the count stays in core_errors
        ns = self.node.get_namespace()
        values = diagnostic_values(snap) | {f"rate_{s}_hz": r for s, r in rates.items()}
        values |= {f"received_{s}": b.received for s, b in self.inputs.items()}
        values |= {f"age_{s}_s": a for s, a in ages.items()}
        values |= {f"fault_{k}": v for k, v in faults.items() if k not in snap.input_faults}
        values |= {"state_file": str(self.state_path), "state_note": self.state_note} | namespace_parts(ns)
        status = unit_status(self.node.get_fully_qualified_name(), ns.strip("/") or "/", level, text, values)
        self.pub_diag.publish(diagnostic_array(self.node.get_clock().now().to_msg(), [status]))


def _life_line(snap) -> str:
    """The remaining life as people read it (the replay and fleet CLIs print the same line)."""
    entry = snap.to_json_dict()
    return life_view(entry["remaining_life"], entry["clearance"]).line()


def make_executor(kind: str) -> Executor:
    """``events`` -> rclpy's EventsExecutor (spin it with a timeout!), else the SingleThreadedExecutor."""
    if kind == "events":
        from rclpy.experimental import EventsExecutor
        return EventsExecutor()
    return SingleThreadedExecutor()


def usage() -> str:
    """``--help`` text: how to run the node and every parameter with its default and meaning."""
    from ebm_wear_monitor.ros.parameters import SPECS
    lines = ["usage: ebm-wear-monitor [--ros-args [-r __ns:=/train7/car3/embu2] [-p NAME:=VALUE]... "
             "[--params-file FILE]]", "",
             "The live wear monitor of one EMBU (ROS 2 node 'wear_monitor'). Parameters:"]
    for spec in SPECS:
        lines.append(f"  {spec.name} (default {spec.default!r}{'' if spec.runtime else ', read-only'}): "
                     f"{spec.description}")
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    """Run the node until SIGINT/SIGTERM and save the state; exit 130 after SIGINT (Ctrl-C: interrupted,
    the CLI policy), 0 after SIGTERM (a service manager's normal stop), 2 on a start-up error."""
    args = list(sys.argv if argv is None else argv)
    own = args[1:args.index("--ros-args")] if "--ros-args" in args else args[1:]
    if "-h" in own or "--help" in own:
        sys.stdout.write(usage())
        return 0
    stop: list[int] = []

    def request_stop(signum: int, _frame: object) -> None:
        stop.append(signum)

    signal.signal(signal.SIGINT, request_stop)
    signal.signal(signal.SIGTERM, request_stop)
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    try:
        node = Node(NODE_NAME, namespace=DEFAULT_NAMESPACE)  # -r __ns:=... overrides it
        try:
            params = NodeParameters(node)
            monitor = WearMonitorNode(node, params)
        except InputError as exc:
            print(f"ebm-wear-monitor: error: {exc}", file=sys.stderr)
            return 2
        executor = make_executor(params.executor)
        executor.add_node(node)
        while not stop:
            executor.spin_once(timeout_sec=0.2)
        monitor.close()
        executor.shutdown(timeout_sec=1.0)
        node.get_logger().info(f"stopped by signal {stop[0]}; state saved to {monitor.state_path}")
        return exit_status(stop[0])
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
