"""Blind self-test on recordings of a world the diagnosis was not built from (issue 10 item 1).

The recordings come from :mod:`ebm_wear_monitor.validation.foreign`, a second generator written
independently of the twin and of the diagnosis (its own plant integration, three ECU variants, its
own sensor models and acquisition conventions, each catalog effect in two functional forms that
differ from the catalog's, four effects outside the catalog).  Each case is written as a rosbag2
bag to a temporary directory and diagnosed from disk like any user's bag
(:func:`.bags.recordings_from_bags`), against the *nominal* unit file; the answer is then compared
with the bag's ``ground_truth.json``.

Scores (the in-world self-test's keys, plus those of the open set):

* ``top1_accuracy``: single-effect cases whose effect changes its quantity by at least 10 % (the
  generator's relative change): the verdict names the true effect;
  ``top1_accuracy_small``: the same for the 5-10 % cases, below or near some floors
  (:mod:`.tolerance`), reported apart;
* ``top2_accuracy``: a true effect among the two best-ranked (single and two-effect cases);
* ``false_positive_rate``: verdict other than ``none`` on a no-effect recording;
* ``median_shrink``: 1 - gap_after / gap_before over the single- and two-effect cases;
* ``unexplained_accuracy``: effects outside the catalog reported ``unexplained``;
  ``catalog_unexplained_rate``: catalog cases (single and two-effect) reported ``unexplained``;
* ``pair_accuracy``: two-effect cases with both effects named (``effects``);
* ``confusion``: true label -> answer (the named effect, ``none`` or ``unexplained``).
"""

from __future__ import annotations

import json
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.params import UnitParams, load_unit
from ebm_wear_monitor.schema.diagnose import (
    ForeignCaseResult,
    ForeignCounts,
    ForeignSelftest,
    confusion_matrix,
)

if TYPE_CHECKING:
    from ebm_wear_monitor.validation.foreign import Case

SMALL = 0.1  # single-effect cases below this relative change are scored apart (``top1_accuracy_small``)


def _truth(bag: Path) -> dict:
    """What the generator put into one recording (its sidecar), in the scorer's terms."""
    gt = json.loads((bag / "ground_truth.json").read_text(encoding="utf-8"))
    unit, entry = next(iter(gt["units"].items()))
    foreign = entry["foreign"]
    effects = entry.get("effects") or {}
    return {"unit": unit, "kind": foreign["kind"], "truth": sorted(effects),
            "relative_change": {k: v.get("relative_change") for k, v in effects.items()},
            "outside": sorted(d["name"] for d in foreign.get("effects_detail", []) if not d.get("catalog"))}


def diagnose_case(case: Case, workdir: str, unit: UnitParams | None = None) -> ForeignCaseResult:
    """Write one foreign case as a bag, diagnose it from disk, and score the answer against its truth."""
    from ebm_wear_monitor.validation.foreign import write_case

    t0 = time.perf_counter()
    bag = Path(write_case(case, Path(workdir)))
    return diagnose_bag(bag, _truth(bag), unit, bag.name, t0)


def third_truth(case_dir: Path) -> dict:
    """The third world's ``truth.json`` (:mod:`ebm_wear_monitor.validation.third`) in the scorer's terms:
    one effect per recording, a catalog effect (``kind`` ``effect``) or one outside the catalog."""
    gt = json.loads((case_dir / "truth.json").read_text(encoding="utf-8"))
    effect, kind = gt.get("effect"), gt["kind"]
    return {"unit": None, "kind": kind, "truth": [effect] if kind == "effect" else [],
            "relative_change": {effect: gt.get("magnitude")} if kind == "effect" else {},
            "outside": [effect] if kind == "outside" else []}


def diagnose_bag(bag: Path, truth: dict, unit: UnitParams | None = None, name: str | None = None,
                 t0: float | None = None) -> ForeignCaseResult:
    """Diagnose one bag from disk against the nominal unit file (or ``unit``) and score the answer
    against ``truth`` (keys of :func:`_truth`; ``unit`` None: the bag's only unit)."""
    from ebm_wear_monitor.diagnosis.bags import recordings_from_bags
    from ebm_wear_monitor.diagnosis.pipeline import diagnose_recording

    unit = load_unit() if unit is None else unit
    t0 = time.perf_counter() if t0 is None else t0
    name = bag.name if name is None else name
    try:
        units = recordings_from_bags([bag])
        rec = (units[truth["unit"]] if truth["unit"] is not None else next(iter(units.values()))).recording
        res = diagnose_recording(rec, unit)
    except InputError as exc:  # a recording the diagnosis refuses is a failed case, not an aborted test
        return ForeignCaseResult(
            case=name, kind=truth["kind"], true="+".join(truth["truth"]) or truth["kind"],
            effects_true=truth["truth"], relative_change=truth["relative_change"],
            verdict="error", diagnosed="error", error=str(exc), effects=[], top2=[],
            gap_before=0.0, gap_after=0.0, shrink=0.0, top1_ok=False, top2_ok=False,
            pair_ok=False, where=[None, None], seconds=time.perf_counter() - t0)
    ranked = [r.effect for r in res.ranking]
    expected = set(truth["truth"])
    kind = truth["kind"]
    return ForeignCaseResult(
        case=name, kind=kind, true="+".join(truth["truth"]) or ("none" if kind == "none"
                                                                else "+".join(truth["outside"])),
        effects_true=truth["truth"], relative_change=truth["relative_change"],
        verdict=res.verdict, diagnosed=(res.effect if res.verdict == "effect" else None) or res.verdict,
        error=None, effects=res.effects, top2=ranked[:2],
        gap_before=res.gap_before, gap_after=res.gap_after, shrink=res.shrink,
        top1_ok=bool(expected) and res.effect in expected,
        top2_ok=bool(expected) and bool(expected & set(ranked[:2])),
        pair_ok=kind == "pair" and set(res.effects) == expected,
        where=[res.where.phase, res.where.signal],
        seconds=time.perf_counter() - t0, sampling_caution=bool(res.sampling_caution))


def _third_case(case_dir: str, unit: UnitParams | None) -> ForeignCaseResult:
    d = Path(case_dir)
    return diagnose_bag(d / "bag", third_truth(d), unit, d.name)


def run_third(bags: Path, jobs: int = 1, unit: UnitParams | None = None,
              on_case: Callable[[int, int], object] | None = None) -> ForeignSelftest:
    """Score the diagnosis on the recordings of the third world written to ``bags``
    (``python -m ebm_wear_monitor.validation.third write --out BAGS``: ``BAGS/<case>/bag`` and
    ``BAGS/<case>/truth.json``), with the foreign self-test's scores (:func:`score`)."""
    dirs = sorted(str(p) for p in bags.iterdir() if (p / "truth.json").is_file())
    if not dirs:
        raise InputError(f"no third-world recordings (<case>/truth.json) under {bags}")
    t0 = time.perf_counter()
    return score(_scored(_third_case, [(d, unit) for d in dirs], jobs, on_case), time.perf_counter() - t0)


def _scored(fn: Callable[..., ForeignCaseResult], calls: list[tuple], jobs: int,
            on_case: Callable[[int, int], object] | None) -> list[ForeignCaseResult]:
    """``fn(*args)`` for every ``args`` of ``calls``, on ``jobs`` processes (in this one when 1), reporting
    each finished case to ``on_case(done, total)``; the rows sorted by case."""
    rows: list[ForeignCaseResult] = []

    def done(row: ForeignCaseResult) -> None:
        rows.append(row)
        if on_case is not None:
            on_case(len(rows), len(calls))

    if jobs <= 1:
        for args in calls:
            done(fn(*args))
    else:
        with ProcessPoolExecutor(jobs) as pool:
            for fut in as_completed([pool.submit(fn, *args) for args in calls]):
                done(fut.result())
    rows.sort(key=lambda r: r.case)
    return rows


def run_foreign(quick: bool = False, max_cases: int | None = None, jobs: int = 1,
                unit: UnitParams | None = None, on_case: Callable[[int, int], object] | None = None,
                *, case_set_name: str | None = None) -> ForeignSelftest:
    """The foreign-world self-test: every case of the generator's quick or full set (module docstring),
    or of the set named ``case_set_name`` (e.g. ``full_b``, the full set's second draw)."""
    from ebm_wear_monitor.validation.foreign import case_set

    cases = case_set(case_set_name or ("quick" if quick else "full"))[:max_cases]
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="ebm-foreign-") as tmp:
        rows = _scored(diagnose_case, [(case, tmp, unit) for case in cases], jobs, on_case)
    return score(rows, time.perf_counter() - t0)


def score(rows: list[ForeignCaseResult], seconds: float) -> ForeignSelftest:
    """Scores of the foreign self-test rows (module docstring)."""
    def rate(sel: list[ForeignCaseResult], ok: Callable[[ForeignCaseResult], bool]) -> float | None:
        return float(np.mean([ok(r) for r in sel])) if sel else None

    def small(r: ForeignCaseResult) -> bool:
        return max(abs(v or 0.0) for v in r.relative_change.values()) < SMALL

    single = [r for r in rows if r.kind == "effect"]
    pairs = [r for r in rows if r.kind == "pair"]
    null = [r for r in rows if r.kind == "none"]
    outside = [r for r in rows if r.kind == "outside"]
    shrink = [r.shrink for r in single + pairs]
    return ForeignSelftest(
        cases=len(rows),
        top1_accuracy=rate([r for r in single if not small(r)], lambda r: r.top1_ok),
        top1_accuracy_small=rate([r for r in single if small(r)], lambda r: r.top1_ok),
        top2_accuracy=rate(single + pairs, lambda r: r.top2_ok),
        false_positive_rate=rate(null, lambda r: r.verdict != "none"),
        median_shrink=float(np.median(shrink)) if shrink else None,
        unexplained_accuracy=rate(outside, lambda r: r.verdict == "unexplained"),
        catalog_unexplained_rate=rate(single + pairs, lambda r: r.verdict == "unexplained"),
        pair_accuracy=rate(pairs, lambda r: r.pair_ok),
        counts=ForeignCounts(none=len(null), single=len(single), single_small=sum(map(small, single)),
                             pairs=len(pairs), outside=len(outside)),
        confusion=confusion_matrix((r.true, r.diagnosed) for r in rows),
        seconds=seconds,
        case_results=rows)
