"""Input topics of interface.md section 2 and how a namespaced topic name maps to (unit, signal).

Signal names are the ones of interface.md section 4 (``angle``, ``velocity``,
``axial_force``, ``current``); a unit is the namespace of its topics, e.g. the
topic ``/train7/car3/embu2/screw/angle`` belongs to unit ``/train7/car3/embu2``
and a topic with no namespace (``/screw/angle``) to unit ``/``.
"""

from __future__ import annotations

import re

from ebm_wear_monitor.errors import InputError

#: signal name -> topic name relative to the unit's namespace
INPUT_TOPICS: dict[str, str] = {
    "angle": "screw/angle",          # rad, unwrapped, positive in the apply direction
    "velocity": "screw/velocity",    # rad/s
    "axial_force": "axial_force",    # N, compressive positive
    "current": "motor/current",      # A (optional input)
}


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
    ns = namespace_of(unit)
    return f"{ns.rstrip('/')}/{INPUT_TOPICS[signal]}"


def split_topic(topic: str) -> tuple[str, str] | None:
    """(unit, signal) of an input topic name, or None for any other topic."""
    name = namespace_of(topic)
    for signal, relative in INPUT_TOPICS.items():
        if name == f"/{relative}":
            return "/", signal
        if name.endswith(f"/{relative}"):
            return name[: -len(relative) - 1], signal
    return None
