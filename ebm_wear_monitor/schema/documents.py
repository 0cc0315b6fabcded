"""The JSON Schema (draft 2020-12) of every ``--json`` output, shipped in ``schema/json/``.

Generated from the declarations: ``replay`` (:class:`~.replay.ReplayDocument`), ``fleet``
(:class:`~.replay.FleetDocument`), ``calc_contact``/``calc_wear``/``calc_actuator``
(:mod:`.calc`), ``diagnose`` (:class:`~.diagnose.DiagnoseDocument`) and ``selftest``
(``diagnose --selftest``, :class:`~.diagnose.SelftestResult`): every key the tools write is
declared and required (unless declared left out when unknown), no other key is allowed.

``python -m ebm_wear_monitor.schema`` rewrites the files; ``--check`` exits 1 when one is stale.
A test validates real outputs of every CLI against them.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ebm_wear_monitor.schema.calc import ActuatorResult, ContactResult, WearResult
from ebm_wear_monitor.schema.diagnose import DiagnoseDocument, SelftestResult
from ebm_wear_monitor.schema.fields import DIALECT, Record, json_schema
from ebm_wear_monitor.schema.replay import FleetDocument, ReplayDocument

#: where the files live (package data)
DIRECTORY = Path(__file__).with_name("json")


def _generated(record: type[Record]) -> Callable[[], dict[str, Any]]:
    return lambda: json_schema(record)


#: name -> (title, builder)
DOCUMENTS: dict[str, tuple[str, Callable[[], dict[str, Any]]]] = {
    "replay": ("ebm-wear replay --json", _generated(ReplayDocument)),
    "fleet": ("ebm-wear fleet --json (and OUT/fleet.json)", _generated(FleetDocument)),
    "calc_contact": ("ebm-wear calc contact --json", _generated(ContactResult)),
    "calc_wear": ("ebm-wear calc wear --json", _generated(WearResult)),
    "calc_actuator": ("ebm-wear calc actuator --json", _generated(ActuatorResult)),
    "diagnose": ("ebm-wear diagnose --json", _generated(DiagnoseDocument)),
    "selftest": ("ebm-wear diagnose --selftest --json", _generated(SelftestResult)),
}


def document(name: str) -> dict[str, Any]:
    """The JSON Schema named ``name`` (a key of :data:`DOCUMENTS`), as it is built now."""
    title, build = DOCUMENTS[name]
    return {"$schema": DIALECT, "$id": f"urn:ebm-wear-monitor:schema:{name}", "title": title, **build()}


def path(name: str) -> Path:
    """The shipped file of the JSON Schema ``name``."""
    return DIRECTORY / f"{name}.schema.json"


def text(name: str) -> str:
    """The file content of the JSON Schema ``name`` (stable: indented, keys in declaration order)."""
    return json.dumps(document(name), indent=1, ensure_ascii=False) + "\n"


def load(name: str) -> dict[str, Any]:
    """The shipped JSON Schema ``name``."""
    result: dict[str, Any] = json.loads(path(name).read_text(encoding="utf-8"))
    return result


def stale() -> list[str]:
    """Names whose shipped file differs from what the declarations give now."""
    return [n for n in DOCUMENTS if not path(n).is_file() or path(n).read_text(encoding="utf-8") != text(n)]


def write_all() -> list[Path]:
    """(Re)write every file; returns their paths."""
    DIRECTORY.mkdir(exist_ok=True)
    for name in DOCUMENTS:
        path(name).write_text(text(name), encoding="utf-8")
    return [path(n) for n in DOCUMENTS]
