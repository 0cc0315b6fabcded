"""The signal and topic contract of interface.md sections 1-2 and 4, in one place.

A unit (one EMBU) publishes its input signals under its namespace (default ``/embu``), each as
``ebm_wear_msgs/msg/Float64Stamped`` (``std_msgs/Header header`` + ``float64 data``, the sample
time in ``header.stamp``). Signal names (interface.md section 4) and their topics relative to
the namespace are :data:`INPUT_TOPICS`; the wear monitor reads the first three
(:data:`MONITOR_SIGNALS`), the diagnosis all four (the twin is driven by the motor current).

Plain Python: the node, the bag reader and writer, the player, the monitor core, the twin's
bags and the diagnosis name signals and topics through this module.
"""

from __future__ import annotations

import re

from ebm_wear_monitor.errors import InputError

#: the input type of interface.md section 1: ``std_msgs/Header header`` + ``float64 data``
FLOAT64_STAMPED = "ebm_wear_msgs/msg/Float64Stamped"
#: signal name -> topic name relative to the unit's namespace (interface.md section 2)
INPUT_TOPICS: dict[str, str] = {
    "angle": "screw/angle",          # rad, unwrapped, positive in the apply direction
    "velocity": "screw/velocity",    # rad/s
    "axial_force": "axial_force",    # N, compressive positive
    "current": "motor/current",      # A (optional input, not used by the wear monitor)
}
#: the signal names of interface.md section 4, in this order
SIGNALS: tuple[str, ...] = tuple(INPUT_TOPICS)
#: the signals the wear monitor uses (screw angle, screw velocity, axial force)
MONITOR_SIGNALS: tuple[str, ...] = ("angle", "velocity", "axial_force")
#: the namespace of a unit when none is given (interface.md section 2)
DEFAULT_NAMESPACE = "/embu"


def namespace_of(unit: str) -> str:
    """Normalised namespace: leading '/', no trailing '/' (the root namespace is '/')."""
    return "/" + unit.strip("/")


#: a ROS 2 namespace: '/' or '/'-separated tokens of letters, digits and '_', none starting with a digit
_NAMESPACE = re.compile(r"/|(/[A-Za-z_][A-Za-z0-9_]*)+")


def check_namespace(unit: str) -> str:
    """``unit`` normalised by :func:`namespace_of`; InputError unless it is a valid ROS 2 namespace."""
    ns = namespace_of(unit)
    if not _NAMESPACE.fullmatch(ns):
        raise InputError(f"{unit!r} is not a ROS 2 namespace (tokens of letters, digits and '_', "
                         "not starting with a digit, separated by '/')")
    return ns


def topic_name(unit: str, signal: str) -> str:
    """Absolute topic of ``signal`` under ``unit``: ('/embu', 'angle') -> '/embu/screw/angle'."""
    return f"{namespace_of(unit).rstrip('/')}/{INPUT_TOPICS[signal]}"


def split_topic(topic: str) -> tuple[str, str] | None:
    """(unit, signal) of an input topic name, or None for any other topic."""
    name = namespace_of(topic)
    for signal, relative in INPUT_TOPICS.items():
        if name == f"/{relative}":
            return "/", signal
        if name.endswith(f"/{relative}"):
            return name[: -len(relative) - 1], signal
    return None
