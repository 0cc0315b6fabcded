"""ROS parameters of the wear-monitor node: declaration, validation, run-time changes.

Every parameter is declared with a description and, for numbers, a range
(``FloatingPointRange`` / ``IntegerRange``), so ``ros2 param describe`` tells an
operator what it means and the middleware rejects out-of-range values. The
shipped parameter file ``config/wear_monitor.yaml`` holds the same defaults
(a test keeps the two equal); it is found at run time by :func:`shipped_config_path`.

Parameters that shape the node's wiring (files, QoS, executor, timers) are
read-only after start; the health thresholds of the diagnostics and the
checkpoint interval can be changed at run time (``ros2 param set``), each new
value validated by :meth:`NodeParameters.on_set` before it is accepted.
"""

from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    ParameterType,
    SetParametersResult,
)
from rclpy.node import Node
from rclpy.parameter import Parameter

from ebm_wear_monitor.errors import InputError

PACKAGE = "ebm_wear_monitor"
CONFIG_NAME = "wear_monitor.yaml"
AGGREGATOR_CONFIG_NAME = "diagnostic_aggregator.yaml"


@dataclass(frozen=True)
class ParamSpec:
    """One declared parameter: default, meaning, range or choices, and whether it may change at run time."""

    name: str
    default: Any
    description: str
    lo: float | None = None
    hi: float | None = None
    choices: tuple[str, ...] = ()
    runtime: bool = False


#: Every parameter of the node (also the content of config/wear_monitor.yaml).
SPECS: tuple[ParamSpec, ...] = (
    ParamSpec("unit_params_file", "",
              "unit parameter YAML of interface.md section 3; empty = the package's reference EMBU"),
    ParamSpec("state_dir", "",
              "directory of the persisted monitor state; empty = $XDG_STATE_HOME (or ~/.local/state)"
              "/ebm_wear_monitor/<node fully qualified name>"),
    ParamSpec("wear_method", "surrogate", "wear-rate evaluation of the physics core",
              choices=("surrogate", "direct")),
    ParamSpec("qos_reliability", "best_effort",
              "input QoS reliability: best_effort (sensor-data profile) or reliable",
              choices=("best_effort", "reliable")),
    ParamSpec("qos_depth", 1000, "input subscription history depth (keep last N) [messages]", 1, 100000),
    ParamSpec("executor", "events",
              "events = rclpy EventsExecutor (cheapest), single_threaded = SingleThreadedExecutor",
              choices=("events", "single_threaded")),
    ParamSpec("process_rate_hz", 25.0,
              "rate at which buffered inputs are pushed through the monitor core [Hz]", 1.0, 500.0),
    ParamSpec("diagnostics_period_s", 1.0, "period of the /diagnostics status [s]", 0.05, 60.0),
    ParamSpec("checkpoint_every_cycles", 10,
              "persist the state atomically every N completed brake applications [-]", 1, 1_000_000,
              runtime=True),
    ParamSpec("stale_timeout_s", 1.0,
              "an input silent for longer than this makes the status STALE [s]", 0.001, 86400.0,
              runtime=True),
    ParamSpec("min_input_rate_hz", 50.0,
              "an input arriving slower than this makes the status WARN [Hz]", 0.0, 1.0e6, runtime=True),
    ParamSpec("clearance_warn_fraction", 0.8,
              "WARN when the clearance estimate exceeds this fraction of the unit's clearance limit [-]",
              0.0, 1.0, runtime=True),
    ParamSpec("remaining_cycles_warn", 10000.0,
              "WARN when the p05 remaining brake applications fall below this [-]", 0.0, 1.0e12,
              runtime=True),
)
SPEC_BY_NAME = {s.name: s for s in SPECS}


def _descriptor(spec: ParamSpec) -> ParameterDescriptor:
    desc = ParameterDescriptor(name=spec.name, description=spec.description, read_only=not spec.runtime)
    if isinstance(spec.default, str):
        desc.type = ParameterType.PARAMETER_STRING
        if spec.choices:
            desc.additional_constraints = "one of: " + ", ".join(spec.choices)
    elif isinstance(spec.default, bool):
        desc.type = ParameterType.PARAMETER_BOOL
    elif isinstance(spec.default, int):
        desc.type = ParameterType.PARAMETER_INTEGER
        desc.integer_range = [IntegerRange(from_value=int(spec.lo), to_value=int(spec.hi), step=1)]
    else:
        desc.type = ParameterType.PARAMETER_DOUBLE
        desc.floating_point_range = [FloatingPointRange(from_value=float(spec.lo), to_value=float(spec.hi),
                                                        step=0.0)]
    return desc


def check_value(name: str, value: Any) -> str | None:
    """Reason why ``value`` is not acceptable for parameter ``name``, or None when it is."""
    spec = SPEC_BY_NAME.get(name)
    if spec is None:
        return None
    if isinstance(spec.default, str):
        if not isinstance(value, str):
            return f"{name}: expected a string, got {value!r}"
        if spec.choices and value not in spec.choices:
            return f"{name}: must be one of {', '.join(spec.choices)}, got {value!r}"
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return f"{name}: expected a number, got {value!r}"
    if isinstance(spec.default, int) and not isinstance(value, int):
        return f"{name}: expected an integer, got {value!r}"
    if not math.isfinite(float(value)) or not spec.lo <= value <= spec.hi:
        return f"{name}: must be within [{spec.lo:g}, {spec.hi:g}], got {value!r}"
    return None


def node_state_dir(fully_qualified_name: str, environ: dict[str, str] | None = None) -> Path:
    """Default per-user state directory of one node: ``$XDG_STATE_HOME/ebm_wear_monitor/<fqn>``.

    The fully qualified name ``/train7/car3/embu2/wear_monitor`` becomes
    ``train7__car3__embu2__wear_monitor``: ROS names never contain ``__``, so
    two nodes never share a directory.
    """
    env = os.environ if environ is None else environ
    base = Path(env.get("XDG_STATE_HOME") or Path(env.get("HOME", str(Path.home()))) / ".local" / "state")
    return base / PACKAGE / fully_qualified_name.strip("/").replace("/", "__")


def shipped_config_path(name: str = CONFIG_NAME) -> Path:
    """Path of a shipped ``config/`` file: the source tree first, then the install's share/ directory.

    ``setup.py`` installs ``config/*.yaml`` to ``<prefix>/share/ebm_wear_monitor/config``;
    an editable install (this repository) reads them from ``<repo>/config``.
    """
    candidates = [Path(__file__).resolve().parents[2] / "config" / name,
                  Path(sys.prefix) / "share" / PACKAGE / "config" / name]
    candidates += [Path(p) / "share" / PACKAGE / "config" / name
                   for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    for path in candidates:
        if path.is_file():
            return path
    raise InputError(f"shipped config {name} not found in {', '.join(str(c) for c in candidates)}")


class NodeParameters:
    """The node's parameters, declared on ``node``, with current values as attributes.

    Start-up validation failures raise :class:`InputError` (one line); run-time
    changes go through :meth:`on_set` and are rejected with a reason when invalid.
    """

    def __init__(self, node: Node) -> None:
        self._node = node
        self.values: dict[str, Any] = {}
        node.add_on_set_parameters_callback(self.on_set)
        for spec in SPECS:
            try:
                value = node.declare_parameter(spec.name, spec.default, _descriptor(spec)).value
            except Exception as exc:  # rclpy raises several unrelated types for a bad override
                raise InputError(f"parameter {_one_line(exc)}") from None
            reason = check_value(spec.name, value)
            if reason:
                raise InputError(f"parameter {reason}")
            self.values[spec.name] = value

    def __getattr__(self, name: str) -> Any:
        try:
            return self.__dict__["values"][name]
        except KeyError:
            raise AttributeError(name) from None

    def on_set(self, params: list[Parameter]) -> SetParametersResult:
        """Validate a change (declaration or ``ros2 param set``); apply it only if every value is valid."""
        for p in params:
            reason = check_value(p.name, p.value)
            if reason:
                return SetParametersResult(successful=False, reason=reason)
        for p in params:
            if p.name in SPEC_BY_NAME:
                self.values[p.name] = p.value
        return SetParametersResult(successful=True)

    def state_dir(self) -> Path:
        """Configured state directory, or the per-user default keyed by the node's fully qualified name."""
        return Path(self.values["state_dir"]) if self.values["state_dir"] else node_state_dir(
            self._node.get_fully_qualified_name())


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__
