"""The replay and fleet results (``ebm-wear replay|fleet --json``), declared once like the monitor's.

A replay's JSON is :class:`ReplayDocument`: one :class:`ReplayEntry` per unit (interface.md
section 4: the unit's :class:`~ebm_wear_monitor.schema.monitor.MonitorSnapshot` keys plus the
bags read, the message count and, with ground truth, :class:`Prognostics` and
:class:`GroundTruth`). The fleet's is :class:`FleetDocument`: the same entries (``unit`` the
folder relative to DIR) plus :class:`FleetFailure` rows. ``replay.result.UnitReplay`` carries an
entry's values with the per-application table; ``replay.prognostics`` computes the metrics.
"""

from __future__ import annotations

from dataclasses import dataclass

from ebm_wear_monitor.schema.fields import Record, quantity
from ebm_wear_monitor.schema.monitor import MonitorSnapshot


@dataclass(frozen=True)
class Prognostics(Record):
    """Prognostics metrics of the median remaining life against ground truth (replay/prognostics.py)."""

    eol_cycles: float = quantity("-", "true application count at end of life k_EOL", json="eol_cycles",
                                 columns={"units": "prognostics_eol_cycles"})
    predictions: int = quantity("-", "applications with a bounded median prediction", json="predictions",
                                columns={"units": "prognostics_predictions"})
    alpha: float = quantity("-", "half-width of the alpha-lambda cone, fraction of the true remaining life",
                            json="alpha", columns={"units": "prognostics_alpha"})
    lam: float = quantity("-", "where alpha-lambda and RA are judged, fraction from first prediction to EOL",
                          json="lambda", columns={"units": "prognostics_lambda"})
    alpha_ph: float = quantity("-", "width of the prognostic-horizon band, fraction of k_EOL",
                               json="alpha_ph",
                               columns={"units": "prognostics_alpha_ph"})
    prognostic_horizon_cycles: float | None = quantity(
        "-", "prognostic horizon k_EOL - k_a (null: the last prediction is outside the band)",
        json="prognostic_horizon_cycles", columns={"units": "prognostics_prognostic_horizon_cycles"})
    alpha_lambda_pass: bool | None = quantity(
        "", "the prediction at k_lambda inside the alpha cone (null: recording ends before k_lambda)",
        json="alpha_lambda_pass", columns={"units": "prognostics_alpha_lambda_pass"})
    alpha_lambda_fraction: float | None = quantity("-", "share of predictions inside the alpha cone",
                                                   json="alpha_lambda_fraction",
                                                   columns={"units": "prognostics_alpha_lambda_fraction"})
    relative_accuracy: float | None = quantity("-", "relative accuracy RA at k_lambda (1 = perfect)",
                                               json="relative_accuracy",
                                               columns={"units": "prognostics_relative_accuracy"})
    cumulative_relative_accuracy: float | None = quantity(
        "-", "mean RA over the predictions before end of life", json="cumulative_relative_accuracy",
        columns={"units": "prognostics_cumulative_relative_accuracy"})
    first_prediction_cycles: float | None = quantity("-", "application k_P of the first prediction",
                                                     json="first_prediction_cycles",
                                                     columns={"units": "prognostics_first_prediction_cycles"})
    coverage: float | None = quantity("-", "share of p05..p95 bands holding the truth (calibrated: 0.9)",
                                      json="coverage", columns={"units": "prognostics_coverage"})
    predictions_with_band: int = quantity("-", "predictions giving both bounds", json="predictions_with_band",
                                          columns={"units": "prognostics_predictions_with_band"})


@dataclass(frozen=True)
class GroundTruth(Record):
    """What the replay took from the simulator's ground-truth sidecar (bagio/sidecar.py)."""

    eol_cycles: float | None = quantity("-", "application count since new at which x_ag reaches the limit "
                                        "(null: never)", json="eol_cycles")
    cycles_at_start: int | None = quantity("-", "applications since new before the first bag",
                                           json="cycles_at_start")


@dataclass(frozen=True)
class ReplayEntry(Record):
    """One unit's result: interface.md section 4's entry (replay and fleet alike)."""

    unit: str = quantity("", "the unit: its namespace (replay) or its folder relative to DIR (fleet)",
                         json="unit", columns={"units": "unit"})
    snapshot: MonitorSnapshot = quantity("", "the monitor core's totals at the end of the data", json="")
    bags: list[str] = quantity("", "the bags read, in time order", json="bags")
    messages: int = quantity("-", "input messages read", json="messages", columns={"units": "messages"})
    prognostics: Prognostics | None = quantity("", "metrics against ground truth (only with an end of life)",
                                               json="prognostics", omit_none=True)
    ground_truth: GroundTruth | None = quantity("", "the ground truth judged against (with prognostics)",
                                                json="ground_truth", omit_none=True)


@dataclass(frozen=True)
class ReplayDocument(Record):
    """``ebm-wear replay --json``."""

    units: list[ReplayEntry] = quantity("", "one entry per unit (namespace), in name order", json="units")
    rejected_topics: dict[str, str] = quantity("", "input topics skipped, with the reason (a wrong type)",
                                               json="rejected_topics")
    storage_problems: list[str] = quantity("", "one line per damaged place in a storage file",
                                           json="storage_problems")


@dataclass(frozen=True)
class FleetFailure(Record):
    """A unit or bag the fleet could not process, and why."""

    unit: str = quantity("", "unit folder relative to DIR", json="unit")
    bag: str | None = quantity("", "the bag relative to DIR (null: the unit as a whole)", json="bag")
    reason: str = quantity("", "one line", json="reason")


@dataclass(frozen=True)
class FleetDocument(Record):
    """``ebm-wear fleet --json`` (and OUT/fleet.json): the replay layout, ranked by urgency."""

    units: list[ReplayEntry] = quantity("", "one entry per unit, most urgent first (fleet/tables.py)",
                                        json="units")
    failures: list[FleetFailure] = quantity("", "units and bags that failed", json="failures")
