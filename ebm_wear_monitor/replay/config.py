"""Monitor-core thresholds for replay and fleet from the node's parameter file, so offline runs can use
exactly the thresholds the live node ran with.

Accepted: a ROS 2 parameter file as the node takes it (``config/wear_monitor.yaml``:
``<node name or /**>: {ros__parameters: {...}}``, sections merged in file order) or a flat mapping.
Keys that are monitor-core parameters (``monitor.config.MonitorConfig``) are used; the node's own
parameters (QoS, rates, state directory, ...) are ignored, they do not change the core's numbers.
"""

from __future__ import annotations

import os
from dataclasses import fields
from pathlib import Path

import yaml

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor import MonitorConfig


def _number(value: object, default: float) -> object:
    """PyYAML reads ``5.0e4`` (no exponent sign, YAML 1.1) as a string; the ROS parameter parser reads
    a number: do the same (whole numbers stay ints where the default is an int)."""
    if isinstance(value, str):
        try:
            number = float(value)
        except ValueError:
            return value
        return int(number) if isinstance(default, int) and number.is_integer() else number
    return value


def load_monitor_config(path: str | os.PathLike) -> MonitorConfig:
    """Validated :class:`MonitorConfig` from ``path`` (defaults for keys not given)."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise InputError(f"{path}: unreadable config: {' '.join(str(exc).split())}") from exc
    if not isinstance(data, dict):
        raise InputError(f"{path}: expected a mapping of parameters")
    sections = [v["ros__parameters"] for v in data.values()
                if isinstance(v, dict) and isinstance(v.get("ros__parameters"), dict)]
    values: dict = {}
    for section in sections or [data]:
        values.update(section)
    names = {f.name for f in fields(MonitorConfig)}
    if not sections and values and not names & set(values):
        # a flat file none of whose keys is a monitor parameter: another kind of file (a unit file?)
        raise InputError(f"{path}: no monitor parameter in it (e.g. {', '.join(sorted(names)[:3])}, ...); "
                         "expected the node's parameter file")
    defaults = MonitorConfig()
    core = {k: _number(v, getattr(defaults, k)) if isinstance(getattr(defaults, k), (int, float)) else v
            for k, v in values.items() if k in names}
    try:
        return defaults.updated(**core)
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from exc
