"""The JSON Schema (draft 2020-12) of every ``--json`` output, shipped in ``schema/json/``.

Generated from the declarations: ``replay`` (:class:`~.replay.ReplayDocument`), ``fleet``
(:class:`~.replay.FleetDocument`), ``calc_contact``/``calc_wear``/``calc_actuator``
(:mod:`.calc`): every key the tools write is declared and required, no other key is allowed.
Written from interface.md section 4 and the diagnosis contract (README.md, "Sim-to-real gap
diagnosis": the diagnosis result belongs to the diagnosis, which is not declared here): ``diagnose`` and
``selftest`` (``diagnose --selftest``): the contract's keys required, more allowed.

``python -m ebm_wear_monitor.schema`` rewrites the files; ``--check`` exits 1 when one is stale.
A test validates real outputs of every CLI against them.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ebm_wear_monitor.schema.calc import ActuatorResult, ContactResult, WearResult
from ebm_wear_monitor.schema.fields import DIALECT, Record, json_schema
from ebm_wear_monitor.schema.replay import FleetDocument, ReplayDocument

#: where the files live (package data)
DIRECTORY = Path(__file__).with_name("json")

_NUMBER = {"type": "number"}
_MAYBE_NUMBER = {"type": ["number", "null"]}
_FRACTION = {"type": ["number", "null"], "minimum": 0, "maximum": 1}
_COUNTS = {"type": "object", "additionalProperties": {"type": "integer", "minimum": 0}}
_ESTIMATE: dict[str, Any] = {"type": "object", "required": ["value", "std", "unit"],
             "properties": {"value": _MAYBE_NUMBER, "std": _MAYBE_NUMBER, "unit": {"type": "string"}}}
#: interface.md section 4 names
_PHASES = ["clearance_elimination", "force_generation", "force_maintenance", "force_release"]
_SIGNALS = ["angle", "velocity", "axial_force", "current"]


def _diagnosis() -> dict[str, Any]:
    """One unit's diagnosis: interface.md section 4 and the diagnosis contract (issue 10)."""
    magnitude = {**_ESTIMATE, "properties": {
        **_ESTIMATE["properties"], "nominal_name": {"type": ["string", "null"]},
        "nominal_value": _MAYBE_NUMBER, "fraction": _MAYBE_NUMBER}}
    ranking = {"type": "object", "required": ["effect", "score", "gap_after", "magnitude"], "properties": {
        "effect": {"type": "string", "description": "catalog name (interface.md section 4)"},
        "score": _NUMBER, "gap_after": _NUMBER, "shrink": _MAYBE_NUMBER, "p_value": _MAYBE_NUMBER,
        "material": {"type": "boolean"},
        "magnitude": {"type": "object", "additionalProperties": magnitude,
                      "description": "fitted size per parameter, in physical units of the unit"}}}
    return {
        "type": "object",
        "required": ["verdict", "effect", "effects", "ranking", "where", "gap_before", "gap_after", "metric",
                     "nuisances"],
        "properties": {
            "unit": {"type": "string", "description": "the unit's namespace"},
            "verdict": {"enum": ["effect", "none", "unexplained"]},
            "effect": {"type": ["string", "null"], "description": "the single most likely unmodelled effect"},
            "effects": {"type": "array", "items": {"type": "string"},
                        "description": "every effect the data support; [] for none / unexplained"},
            "summary": {"type": "string", "description": "one plain-words sentence"},
            "ranking": {"type": "array", "items": ranking},
            "where": {"type": "object", "required": ["phase", "signal"], "properties": {
                "phase": {"enum": [*_PHASES, None]}, "signal": {"enum": [*_SIGNALS, None]}}},
            "gap_before": {**_NUMBER, "description": "on held-out data, same metric as gap_after"},
            "gap_after": {**_NUMBER, "description": "on held-out data, with that effect added and fitted"},
            "metric": {"type": "string", "description": "name of the gap metric"},
            "nuisances": {"type": "object", "additionalProperties": _ESTIMATE,
                          "description": "acquisition conventions estimated from the data: never an effect"},
            "input_faults": _COUNTS,
            "input_faults_by_signal": {"type": "object", "additionalProperties": _COUNTS},
        },
    }


def _diagnose() -> dict[str, Any]:
    """``ebm-wear diagnose --json``: the first unit's diagnosis at the top level, every unit in ``units``."""
    return {"$defs": {"diagnosis": _diagnosis()}, "$ref": "#/$defs/diagnosis",
            "required": ["units"],
            "properties": {"units": {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/diagnosis"}}}}


def _selftest() -> dict[str, Any]:
    """``ebm-wear diagnose --selftest --json``: interface.md section 4's keys at least."""
    return {"type": "object",
            "required": ["cases", "top1_accuracy", "top2_accuracy", "false_positive_rate", "median_shrink",
                         "confusion"],
            "properties": {
                "cases": {"type": "integer", "minimum": 0},
                "top1_accuracy": _FRACTION, "top2_accuracy": _FRACTION, "false_positive_rate": _FRACTION,
                "median_shrink": {**_MAYBE_NUMBER, "maximum": 1,
                                  "description": "median held-out shrink 1 - gap_after / gap_before"},
                "confusion": {"type": "object", "additionalProperties": _COUNTS,
                              "description": "true effect -> diagnosed effect or none -> count"}}}


def _generated(record: type[Record]) -> Callable[[], dict[str, Any]]:
    return lambda: json_schema(record)


#: name -> (title, builder)
DOCUMENTS: dict[str, tuple[str, Callable[[], dict[str, Any]]]] = {
    "replay": ("ebm-wear replay --json", _generated(ReplayDocument)),
    "fleet": ("ebm-wear fleet --json (and OUT/fleet.json)", _generated(FleetDocument)),
    "calc_contact": ("ebm-wear calc contact --json", _generated(ContactResult)),
    "calc_wear": ("ebm-wear calc wear --json", _generated(WearResult)),
    "calc_actuator": ("ebm-wear calc actuator --json", _generated(ActuatorResult)),
    "diagnose": ("ebm-wear diagnose --json", _diagnose),
    "selftest": ("ebm-wear diagnose --selftest --json", _selftest),
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
