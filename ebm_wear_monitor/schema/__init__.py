"""One result schema: every output quantity declared once, every output generated from it.

* :mod:`.fields`: the metadata (:class:`Quantity`: unit, JSON path, message field, diagnostics key,
  table columns) and the generators (JSON, message fields, ``/diagnostics`` key-values, table rows
  and columns, JSON Schema);
* :mod:`.monitor`: the monitor core's records ``CycleSummary`` and ``MonitorSnapshot``;
* :mod:`.replay`: the replay and fleet results;
* :mod:`.diagnose`: the diagnosis and self-test results (``ebm-wear diagnose [--selftest] --json``);
* :mod:`.documents`: the JSON Schema (draft 2020-12) of every ``--json`` output, written to
  ``schema/json/*.schema.json`` (package data) by ``python -m ebm_wear_monitor.schema``.

Plain Python: no ROS, storage or table library is imported here (the core imports it).
"""

from ebm_wear_monitor.schema.fields import (
    Column,
    Quantity,
    Record,
    diagnostic_values,
    from_json,
    json_row,
    json_schema,
    message_fields,
    quantities,
    quantity,
    table_columns,
    table_row,
    to_json,
)

__all__ = ["Column", "Quantity", "Record", "diagnostic_values", "from_json", "json_row", "json_schema",
           "message_fields", "quantities", "quantity", "table_columns", "table_row", "to_json"]
