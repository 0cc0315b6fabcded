"""ROS parameters of the wear-monitor node: declaration, validation, run-time changes.

Every parameter is declared with a description and, for numbers, a range
(``FloatingPointRange`` / ``IntegerRange``), so ``ros2 param describe`` tells an
operator what it means and the middleware rejects out-of-range values. The
shipped parameter file ``config/wear_monitor.yaml`` holds the same defaults
(a test keeps the two equal); it is found at run time by :func:`shipped_config_path`.

Two groups: the node's own parameters (:data:`NODE_SPECS`: files, QoS,
executor, timers, input-health thresholds; the remaining-life thresholds are the unit file's
``monitor`` block) and every field of the monitor
core's :class:`~ebm_wear_monitor.monitor.config.MonitorConfig` under the same
name (:func:`monitor_specs`, from the core's own documentation and ranges), so
node and ``ebm-wear replay`` share one set of thresholds. Parameters that shape
the node's wiring (files, QoS, executor, timers, the wear method) are read-only
after start; all thresholds can be changed at run time (``ros2 param set``),
each change validated by :meth:`NodeParameters.on_set` (core thresholds through
``MonitorConfig.updated``) before it is accepted and handed to the listeners.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Callable
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


#: The node's own parameters.
NODE_SPECS: tuple[ParamSpec, ...] = (
    ParamSpec("unit_params_file", "",
              "unit parameter YAML of interface.md section 3; empty = the package's reference EMBU"),
    ParamSpec("state_dir", "",
              "directory of the persisted monitor state; empty = $XDG_STATE_HOME (or ~/.local/state)"
              "/ebm_wear_monitor/<node fully qualified name>"),
    ParamSpec("on_unit_change", "refuse",
              "a saved state made under another unit file (its unit_digest differs from this one's): "
              "refuse = exit 2 with a message; archive = move it aside as <state>.unit-<digest>-<UTC> "
              "and start anew", choices=("refuse", "archive")),
    ParamSpec("qos_reliability", "best_effort",
              "input QoS reliability: best_effort (sensor-data profile) or reliable",
              choices=("best_effort", "reliable")),
    ParamSpec("qos_depth", 1000,
              "input history depth of best-effort inputs (keep last N; reliable inputs keep all, the "
              "publisher waits) [messages]", 1, 100000),
    ParamSpec("executor", "events",
              "events = rclpy EventsExecutor (cheapest), single_threaded = SingleThreadedExecutor",
              choices=("events", "single_threaded")),
    ParamSpec("process_rate_hz", 25.0,
              "rate at which buffered inputs are pushed through the monitor core [Hz]", 1.0, 500.0),
    ParamSpec("diagnostics_period_s", 1.0, "period of the /diagnostics status [s]", 0.05, 60.0),
    ParamSpec("stale_timeout_s", 1.0,
              "an input silent for longer than this makes the status STALE [s]", 0.001, 86400.0,
              runtime=True),
    ParamSpec("min_input_rate_hz", 50.0,
              "an input arriving slower than this makes the status WARN [Hz]", 0.0, 1.0e6, runtime=True),
)
#: core parameters fixed at start (the core is built once)
MONITOR_READ_ONLY = frozenset({"wear_method"})


def monitor_specs() -> tuple[ParamSpec, ...]:
    """One ParamSpec per ``MonitorConfig`` field: the core's default, unit, range, choices and reasoning."""
    from ebm_wear_monitor.monitor.config import parameter_specs
    return tuple(
        ParamSpec(d["name"], d["default"], f"{d['doc']} [{d['unit'] or '-'}]", d["range"][0], d["range"][1],
                  tuple(d["choices"] or ()), runtime=d["name"] not in MONITOR_READ_ONLY)
        for d in parameter_specs())


#: Every parameter of the node (also the content of config/wear_monitor.yaml).
SPECS: tuple[ParamSpec, ...] = NODE_SPECS + monitor_specs()
SPEC_BY_NAME = {s.name: s for s in SPECS}
MONITOR_NAMES = frozenset(s.name for s in SPECS) - {s.name for s in NODE_SPECS}


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
        if spec.lo is not None and spec.hi is not None:
            desc.integer_range = [IntegerRange(from_value=int(spec.lo), to_value=int(spec.hi), step=1)]
    else:
        desc.type = ParameterType.PARAMETER_DOUBLE
        if spec.lo is not None and spec.hi is not None:
            desc.floating_point_range = [FloatingPointRange(from_value=float(spec.lo),
                                                            to_value=float(spec.hi), step=0.0)]
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
    lo = -math.inf if spec.lo is None else spec.lo
    hi = math.inf if spec.hi is None else spec.hi
    if not math.isfinite(float(value)) or not lo <= value <= hi:
        return f"{name}: must be within [{lo:g}, {hi:g}], got {value!r}"
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

    ``monitor_config`` is the core's validated ``MonitorConfig``. Start-up
    validation failures raise :class:`InputError` (one line); run-time changes go
    through :meth:`on_set`, are rejected with a reason when invalid, and once
    accepted are passed to every callable in ``listeners`` (``listener(names)``).
    """

    def __init__(self, node: Node) -> None:
        from ebm_wear_monitor.monitor.config import MonitorConfig

        self._node = node
        self.values: dict[str, Any] = {}
        self.monitor_config = MonitorConfig()
        self.listeners: list[Callable[[set[str]], None]] = []
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
        core = {p.name: p.value for p in params if p.name in MONITOR_NAMES}
        try:
            config = self.monitor_config.updated(**core) if core else self.monitor_config
        except InputError as exc:
            return SetParametersResult(successful=False, reason=str(exc))
        self.monitor_config = config
        names = {p.name for p in params if p.name in SPEC_BY_NAME}
        self.values.update({p.name: p.value for p in params if p.name in SPEC_BY_NAME})
        for listener in self.listeners:
            listener(names)
        return SetParametersResult(successful=True)

    def state_dir(self) -> Path:
        """Configured state directory, or the per-user default keyed by the node's fully qualified name."""
        return Path(self.values["state_dir"]) if self.values["state_dir"] else node_state_dir(
            self._node.get_fully_qualified_name())


def _yaml_value(value: Any) -> str:
    """A default as YAML that rcl and PyYAML both read back with the same type (floats keep a '.')."""
    if isinstance(value, str):
        return f'"{value}"' if value == "" else value
    text = repr(value)
    if isinstance(value, float) and "." not in text and "inf" not in text and "nan" not in text:
        mantissa, _, exponent = text.partition("e")
        text = f"{mantissa}.0" + (f"e{exponent}" if exponent else "")
    return text


def render_config() -> str:
    """Text of ``config/wear_monitor.yaml``: every parameter with its default, range and meaning.

    Regenerate the shipped file after a change of :data:`NODE_SPECS` or of ``MonitorConfig``:
    ``python -m ebm_wear_monitor.ros.parameters > config/wear_monitor.yaml``.
    """
    lines = [
        "# ROS 2 parameters of the wear_monitor node (ebm-wear-monitor), with their defaults.",
        "# Generated by `python -m ebm_wear_monitor.ros.parameters` from ebm_wear_monitor/ros/parameters.py",
        "# (node) and ebm_wear_monitor/monitor/config.py (core, shared with ebm-wear replay); both",
        "# document each parameter and its unit; `ros2 param describe` shows the same text.",
        "# Use: ebm-wear-monitor --ros-args --params-file config/wear_monitor.yaml",
        "# [rw] = changeable at run time (ros2 param set), validated; [ro] = read at start only.",
        "/**:",
        "  ros__parameters:",
    ]
    for title, group in (("node", NODE_SPECS), ("monitor core", SPECS[len(NODE_SPECS):])):
        lines.append(f"    # ---- {title}")
        for spec in group:
            where = " | ".join(spec.choices) if spec.choices else (
                f"[{spec.lo:g}, {spec.hi:g}]" if spec.lo is not None and spec.hi is not None else "")
            lines.append(f"    {spec.name}: {_yaml_value(spec.default)}".ljust(46)
                         + f"# {'rw' if spec.runtime else 'ro'} {where}".rstrip())
    return "\n".join(lines) + "\n"


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


if __name__ == "__main__":
    sys.stdout.write(render_config())
