"""Declared once, generated everywhere: per-field metadata of result records and the generators.

A result record is a dataclass deriving from :class:`Record` whose output fields are declared
with :func:`quantity`: the field's one name (the Python attribute, interface.md's JSON name where
the contract names it), its SI unit, its meaning, and where it appears in every output:

* ``json``: the path of its key in the JSON object (``"wear/screw_raceway_m"``; ``""`` merges a
  nested record's keys into the parent; absent: not in the JSON);
* ``msg``: ``{message type: field}`` of ``msg_defs/msg/*.msg`` (a tuple of fields spreads a tuple
  value over several fields; ``header.stamp`` a nested field);
* ``diag``: the ``/diagnostics`` key (``"fault_{}"``: one key per entry of a mapping);
* ``columns``: ``{table: column}`` of the tables (``units``: fleet ``units.parquet``,
  ``applications``: the per-application table of replay and fleet), optionally converted.

The adapters (JSON writers, ROS messages, ``/diagnostics``, Parquet/CSV tables, JSON Schema files)
call the generators below and name no quantity themselves. Plain Python, no ROS or storage import:
the monitor core imports it.
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from collections.abc import Callable, Iterator, Mapping
from typing import Any, ClassVar, Union

from ebm_wear_monitor.outputs import jsonable

_KEY = "ebm_wear_monitor.quantity"
#: JSON Schema dialect of every schema generated here
DIALECT = "https://json-schema.org/draft/2020-12/schema"


@dataclasses.dataclass(frozen=True)
class Column:
    """A table column of a quantity: its name and an optional conversion of the value."""

    name: str
    convert: Callable[[Any], object] | None = None


@dataclasses.dataclass(frozen=True)
class Quantity:
    """Metadata of one output quantity (module docstring)."""

    unit: str  # SI unit ("m", "N", "s", "rad/s", "1/h", "ns"; "-" dimensionless or a count; "" text)
    doc: str  # what it is, in a few words
    json: tuple[str, ...] | None = None  # path in the JSON object; () = merged into the parent
    msg: Mapping[str, str | tuple[str, ...]] = dataclasses.field(default_factory=dict)
    diag: str = ""
    columns: Mapping[str, tuple[Column, ...]] = dataclasses.field(default_factory=dict)
    enum: tuple[str, ...] = ()  # the values a text quantity takes
    omit_none: bool = False  # the JSON key is left out (not null) when the value is None

    def describe(self) -> str:
        """``doc [unit]``: column descriptions, JSON Schema descriptions."""
        return f"{self.doc} [{self.unit}]" if self.unit else self.doc


def quantity(unit: str, doc: str, *, json: str | None = None,
             msg: Mapping[str, str | tuple[str, ...]] | None = None,
             diag: str = "", columns: Mapping[str, str | Column | tuple[Column, ...]] | None = None,
             enum: tuple[str, ...] = (),
             omit_none: bool = False, default: object = dataclasses.MISSING) -> Any:
    """A dataclass field carrying its :class:`Quantity` (``json="a/b"``: path a -> b; ``""``: merged)."""
    meta = Quantity(unit, doc, None if json is None else tuple(p for p in json.split("/") if p),
                    dict(msg or {}), diag,
                    {t: _as_columns(c) for t, c in (columns or {}).items()},
                    enum, omit_none)
    return dataclasses.field(default=default, metadata={_KEY: meta})


def _as_columns(c: str | Column | tuple[Column, ...]) -> tuple[Column, ...]:
    return (Column(c),) if isinstance(c, str) else (c,) if isinstance(c, Column) else c


class Record:
    """Base of the result records: the generators as methods (the dataclass fields declare it all)."""

    __dataclass_fields__: ClassVar[dict[str, dataclasses.Field[Any]]]

    def to_json_dict(self) -> dict[str, Any]:
        """The record's JSON object (keys at their declared paths; NaN/inf -> null)."""
        return to_json(self)


def quantities(cls: type[Record] | Record) -> Iterator[tuple[str, Quantity]]:
    """(field name, Quantity) of every declared field of a record (class or instance), in order."""
    for f in dataclasses.fields(cls):
        if _KEY in f.metadata:
            yield f.name, f.metadata[_KEY]


# ---------------------------------------------------------------------------------------- JSON
def to_json(record: Record) -> dict[str, Any]:
    """The JSON object of ``record``: every field with a ``json`` path at that path, in field order
    (records nested directly, in lists or as mapping values, written as their objects)."""
    out: dict[str, Any] = {}
    for name, q in quantities(record):
        if q.json is None:
            continue
        value = getattr(record, name)
        if value is None and q.omit_none:
            continue
        if isinstance(value, Record):
            value = to_json(value)
        elif isinstance(value, list):
            value = [to_json(v) if isinstance(v, Record) else v for v in value]
        elif isinstance(value, Mapping):
            value = {k: to_json(v) if isinstance(v, Record) else v for k, v in value.items()}
        if not q.json:  # merged: the nested record's keys at this level
            out.update(value)
            continue
        node = out
        for part in q.json[:-1]:
            node = node.setdefault(part, {})
        node[q.json[-1]] = jsonable(value)
    return out


R = typing.TypeVar("R", bound=Record)


def from_json(cls: type[R], obj: Mapping[str, Any]) -> R:
    """The record of class ``cls`` read back from its JSON object (flat records: one key per field).

    A missing key or null is None, or NaN for a plain ``float`` field (how it was written).
    """
    kwargs: dict[str, Any] = {}
    for name, q in quantities(cls):
        value = obj.get(q.json[-1]) if q.json else None
        if value is None and _hints(cls)[name] is float:
            value = math.nan
        kwargs[name] = value
    return cls(**kwargs)


# ---------------------------------------------------------------------------------------- ROS
def message_fields(record: Record, message: str) -> list[tuple[str, object]]:
    """``(field, value)`` of message type ``message`` (``msg_defs/msg/<message>.msg``), tuples spread."""
    out: list[tuple[str, object]] = []
    for name, q in quantities(record):
        target = q.msg.get(message)
        if target is None:
            continue
        value = getattr(record, name)
        if isinstance(target, tuple):
            out += zip(target, value, strict=True)
        else:
            out.append((target, value))
    return out


def diagnostic_values(record: Record) -> dict[str, object]:
    """The ``/diagnostics`` key-values of ``record``; unknown numbers (None) as NaN, never left out."""
    out: dict[str, object] = {}
    for name, q in quantities(record):
        if not q.diag:
            continue
        value = getattr(record, name)
        if isinstance(value, Mapping):
            out.update({q.diag.format(k): v for k, v in value.items()})
        elif value is None:
            out[q.diag] = math.nan
        else:
            out[q.diag] = float(value) if _kind(type(record), name) == "number" else value
    return out


# ---------------------------------------------------------------------------------------- tables
def _columns(table: str,
             records: tuple[type[Record], ...]) -> Iterator[tuple[type[Record], str, Quantity, Column]]:
    for cls in records:
        for name, q in quantities(cls):
            for col in q.columns.get(table, ()):
                yield cls, name, q, col


def table_columns(table: str, *records: type[Record]) -> dict[str, str]:
    """``{column: description [unit]}`` of ``table`` made from ``records`` (their field order)."""
    return {col.name: q.describe() for _cls, _name, q, col in _columns(table, records)}


def table_row(table: str, *records: Record | None) -> dict[str, object]:
    """One row of ``table`` from ``records`` (of the classes given to :func:`table_columns`, same order).

    Numbers that are unknown (None, or the record itself None) are NaN; text is None.
    """
    row: dict[str, object] = {}
    for record in records:
        if record is None:
            continue
        for _cls, name, _q, col in _columns(table, (type(record),)):
            value = getattr(record, name)
            if col.convert is not None:
                value = col.convert(value)
            if _kind(type(record), name) == "number":
                value = math.nan if value is None else float(value)
            row[col.name] = value
    return row


def json_row(table: str, record: type[Record], entry: Mapping[str, Any]) -> dict[str, object]:
    """One row of ``table`` read from a JSON object of ``record`` (missing keys: None)."""
    row: dict[str, object] = {}
    for _cls, name, q, col in _columns(table, (record,)):
        value: Any = entry
        for part in q.json or ():
            value = value.get(part) if isinstance(value, Mapping) else None
        origin: object = typing.get_origin(_hints(record)[name])
        if value is None and origin is dict:
            value = {}  # a missing mapping is an empty one
        row[col.name] = value if col.convert is None or value is None else col.convert(value)
    return row


# ---------------------------------------------------------------------------------------- types
_HINTS: dict[type, dict[str, Any]] = {}


def _hints(cls: type) -> dict[str, Any]:
    """The resolved annotations of a record class (cached)."""
    if cls not in _HINTS:
        _HINTS[cls] = typing.get_type_hints(cls)
    return _HINTS[cls]


def _kind(cls: type, name: str) -> str:
    """``number`` for float fields (``float`` or ``float | None``), else ``other``."""
    tp = _hints(cls)[name]
    args = set(typing.get_args(tp)) - {type(None)} if _is_union(tp) else {tp}
    return "number" if args == {float} else "other"


def _is_union(tp: Any) -> bool:
    return typing.get_origin(tp) in (Union, types.UnionType)


def type_schema(tp: Any) -> dict[str, Any]:
    """JSON Schema of a Python annotation (floats may be null: NaN and inf are written as null)."""
    if tp is float:
        return {"type": ["number", "null"]}
    if tp is bool:
        return {"type": "boolean"}
    if tp is int:
        return {"type": "integer"}
    if tp is str:
        return {"type": "string"}
    if tp is Any or tp is object:
        return {}
    if isinstance(tp, type) and issubclass(tp, Record):
        return json_schema(tp)
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if _is_union(tp):
        inner = [type_schema(a) for a in args if a is not type(None)]
        schema = inner[0] if len(inner) == 1 else {"anyOf": inner}
        if type(None) in args and "type" in schema:
            kinds = schema["type"] if isinstance(schema["type"], list) else [schema["type"]]
            schema = {**schema, "type": [*dict.fromkeys([*kinds, "null"])]}
        elif type(None) in args:
            schema = {"anyOf": [schema, {"type": "null"}]}
        return schema
    if origin in (dict, Mapping):
        return {"type": "object", "additionalProperties": type_schema(args[1])}
    if origin in (list, tuple):
        if origin is tuple and args and args[-1] is not Ellipsis:
            return {"type": "array", "prefixItems": [type_schema(a) for a in args], "items": False}
        return {"type": "array", "items": type_schema(args[0])}
    raise TypeError(f"no JSON Schema for {tp!r}")


def json_schema(record: type[Record]) -> dict[str, Any]:
    """JSON Schema of ``record``'s JSON object: every declared key required, no other key."""
    root: dict[str, Any] = {"type": "object", "properties": {}, "required": [], "additionalProperties": False}
    for name, q in quantities(record):
        if q.json is None:
            continue
        tp = _hints(record)[name]
        if not q.json:  # merged record
            sub = json_schema(tp)
            root["properties"].update(sub["properties"])
            root["required"] += sub["required"]
            continue
        node = root
        for part in q.json[:-1]:
            if part not in node["properties"]:
                node["properties"][part] = {"type": "object", "properties": {}, "required": [],
                                            "additionalProperties": False}
                node["required"].append(part)
            node = node["properties"][part]
        leaf = type_schema(tp)
        if q.omit_none:
            leaf = type_schema(typing.get_args(tp)[0]) if _is_union(tp) else leaf
        if q.enum:
            leaf = {**leaf, "enum": [*q.enum, *([None] if "null" in leaf.get("type", []) else [])]}
        node["properties"][q.json[-1]] = {"description": q.describe(), **leaf}
        if not q.omit_none:
            node["required"].append(q.json[-1])
    return root
