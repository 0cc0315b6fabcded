"""The fleet pipeline: every unit's bags through the monitor core, one Dask task per unit.

Flow (``run_fleet``): discover the units' bags (``fleet.discover``); hash the
bags whose fingerprint changed (Dask tasks); skip units whose bag hashes and
parameters match the manifest; submit one task per remaining unit (largest
first, for load balance); as each finishes, write its result files and the
manifest atomically (so an interrupted run resumes where it stopped); finally
assemble the fleet tables, JSON and report from every unit's result file.

Incremental: when a unit's bags are the ones already processed plus new ones
(a new day's recording), only the new bags are read: the monitor core
continues from the saved state of each namespace (``MonitorState``), exactly
as the live node continues after a restart, and the new applications are
appended to the unit's history. A bag boundary is then an end of data (an
application cut by it is closed as interrupted, the time gap between bags is
not counted as a 'gap'), the only difference to processing all bags at once.
If the new data start before the processed data end, the unit is processed
again from its first bag.

What a task receives: the fleet root, the unit's bag paths (workers read the
bags from a shared file system) and the unit parameters (scattered once to
every worker). What it returns: the section 4 entries and the per-application
table (a few hundred bytes per brake application). A unit that fails (all its
bags unreadable, or any exception) is reported with its reason and the fleet
continues; a bad bag among good ones is skipped and reported, the unit runs on
the rest.
"""

from __future__ import annotations

import hashlib
import json
import os
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ebm_wear_monitor import __version__
from ebm_wear_monitor.bagio import BagRecordings, read_bags
from ebm_wear_monitor.fleet.discover import BagFile, content_hash, discover
from ebm_wear_monitor.fleet.manifest import Manifest
from ebm_wear_monitor.monitor import MonitorConfig, MonitorState
from ebm_wear_monitor.outputs import atomic_write, write_json
from ebm_wear_monitor.params import UnitParams
from ebm_wear_monitor.replay.report import slug
from ebm_wear_monitor.replay.result import UnitReplay
from ebm_wear_monitor.replay.run import judge, replay_unit, truth_by_namespace

UNITS_DIR = "units"
#: the manifest is rewritten at most this often while units finish (and at the end, or when
#: interrupted): rewriting it after each of thousands of units would cost O(units^2) [s]
MANIFEST_EVERY_S = 2.0


@dataclass
class UnitOutcome:
    """What one unit's task returns."""

    unit: str                                   # folder relative to the fleet root
    entries: list[UnitReplay] = field(default_factory=list)
    namespaces: list[str] = field(default_factory=list)         # namespace of each entry
    resumed: bool = False                       # continued from saved states over the new bags only
    failed_bags: dict[str, str] = field(default_factory=dict)   # bag relpath -> reason
    rejected: dict[str, str] = field(default_factory=dict)      # "<bag>: <topic>" -> reason
    error: str | None = None                    # why the whole unit failed, or None


def entry_name(folder: str, namespace: str, namespaces: int) -> str:
    """Unit name in the fleet output: the folder, plus the namespace when a folder holds several units."""
    return folder if namespaces == 1 else f"{folder}{namespace}"


def _continues(recording: BagRecordings, states: dict[str, dict]) -> bool:
    """True if ``recording`` holds the same namespaces as ``states`` and starts after each state's end."""
    if set(recording.units) != set(states):
        return False
    for ns, data in recording.units.items():
        end_ns = states[ns].get("last_stamp_ns")
        first = min((float(np.nanmin(s.stamps)) for s in data.signals.values() if len(s.stamps)),
                    default=np.inf)
        if end_ns is not None and not first > end_ns * 1e-9:
            return False
    return True


def process_unit(root: str, folder: str, relpaths: list[str], params: UnitParams, *,
                 previous: dict | None = None, config: MonitorConfig | None = None) -> UnitOutcome:
    """Read one unit's bags (time order) and run the monitor core over them; never raises.

    ``previous``: ``{"bags": n, "states": {namespace: MonitorState dict}}`` when the first ``n``
    bags were processed before; then only the others are read, continuing from those states.
    """
    outcome = UnitOutcome(folder)
    try:
        paths = [Path(root) / r for r in relpaths]
        failed: dict[str, str] = {}
        states: dict[str, dict] = {}
        recording = None
        if previous is not None:
            recording = read_bags(paths[previous["bags"]:], failed=failed, read_ahead=0)
            if _continues(recording, previous["states"]):
                outcome.resumed, states = True, previous["states"]
            else:
                recording, failed = None, {}
        if recording is None:  # no read-ahead thread: the fleet runs one worker process per core
            recording = read_bags(paths, failed=failed, read_ahead=0)
        outcome.failed_bags = {Path(p).relative_to(root).as_posix(): why for p, why in failed.items()}
        outcome.rejected = recording.rejected
        truths = truth_by_namespace(recording)
        for ns, data in recording.units.items():
            state = MonitorState.from_dict(states[ns]) if ns in states else None
            result = replay_unit(data, params, truths.get(ns), config=config, state=state)
            result.unit = entry_name(folder, ns, len(recording.units))
            result.bags = [Path(b).relative_to(root).as_posix() for b in data.bags]
            outcome.entries.append(result)
            outcome.namespaces.append(ns)
        if not outcome.entries:
            outcome.error = "; ".join(outcome.failed_bags.values()) or "no input data"
    except Exception as exc:  # a fleet task must report, not crash the fleet
        outcome.error = f"{type(exc).__name__}: {exc} (at {traceback.extract_tb(exc.__traceback__)[-1].name})"
    return outcome


def unit_file(folder: str) -> str:
    """Result file of a unit folder, relative to OUT (slug + short hash: distinct folders never collide)."""
    return f"{UNITS_DIR}/{slug(folder)}-{hashlib.sha1(folder.encode()).hexdigest()[:8]}.json"


def _merge_previous(out: Path, outcome: UnitOutcome, rel: str) -> None:
    """Prepend the earlier run's history to a resumed outcome (bags, messages, applications, failures)."""
    before = json.loads((out / rel).read_text(encoding="utf-8"))
    parquet = out / rel.replace(".json", ".parquet")
    old_apps = pd.read_parquet(parquet) if parquet.exists() else pd.DataFrame(columns=["unit"])
    old = {e["unit"]: e for e in before["entries"]}
    for entry in outcome.entries:
        prev = old.get(entry.unit, {})
        entry.bags = prev.get("bags", []) + entry.bags
        entry.messages += prev.get("messages", 0)
        rows = old_apps[old_apps["unit"] == entry.unit].drop(columns="unit")
        entry.applications = pd.concat([rows, entry.applications], ignore_index=True) if len(rows) else \
            entry.applications
        if entry.truth is not None and prev.get("ground_truth"):
            entry.truth = {**entry.truth, "cycles_at_start": prev["ground_truth"]["cycles_at_start"]}
        entry.prognostics = judge(entry.applications, entry.truth)
    outcome.failed_bags = {**before["failed_bags"], **outcome.failed_bags}
    outcome.rejected = {**before["rejected"], **outcome.rejected}


def save_outcome(out: Path, outcome: UnitOutcome) -> str:
    """Write a unit's JSON (and its per-application Parquet table) atomically; returns the JSON's relpath.

    A resumed outcome is first merged with the unit's earlier result files.
    """
    rel = unit_file(outcome.unit)
    if outcome.resumed:
        _merge_previous(out, outcome, rel)
    tables = [e.applications.assign(unit=e.unit) for e in outcome.entries if len(e.applications)]
    parquet = out / rel.replace(".json", ".parquet")
    if tables:
        atomic_write(parquet, lambda tmp: pd.concat(tables).to_parquet(tmp, index=False))
    else:
        parquet.unlink(missing_ok=True)
    write_json(out / rel, {"unit": outcome.unit, "error": outcome.error, "failed_bags": outcome.failed_bags,
                           "rejected": outcome.rejected,
                           "entries": [e.to_json_dict() for e in outcome.entries],
                           "states": {ns: e.state for ns, e in zip(outcome.namespaces, outcome.entries,
                                                                   strict=True)}})
    return rel


@dataclass
class FleetRun:
    """Bookkeeping of one ``run_fleet`` call."""

    units: dict[str, list[BagFile]]
    processed: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    resumed: list[str] = field(default_factory=list)


def _hashes(client, root: Path, units: dict[str, list[BagFile]], manifest: Manifest) -> dict[str, str]:
    bags = [b for bs in units.values() for b in bs]
    todo = [b for b in bags if manifest.known_hash(b) is None]
    fresh = client.gather(client.map(content_hash, [str(root)] * len(todo), [b.relpath for b in todo],
                                     pure=False)) if todo else []
    for bag, sha in zip(todo, fresh, strict=True):
        manifest.remember(bag, sha)
    return {b.relpath: manifest.bags[b.relpath]["sha256"] for b in bags}


def _previous(manifest: Manifest, folder: str, hashes: list[str], digest: str, out: Path) -> dict | None:
    """What a unit may continue from: its earlier bags are a prefix of its bags now, same parameters."""
    entry = manifest.units.get(folder)
    if not (entry and entry["status"] == "ok" and entry["params_digest"] == digest and entry["hashes"]
            and hashes[: len(entry["hashes"])] == entry["hashes"] and (out / entry["file"]).exists()):
        return None
    states = json.loads((out / entry["file"]).read_text(encoding="utf-8")).get("states")
    return {"bags": len(entry["hashes"]), "states": states} if states else None


def run_fleet(client, root: str | os.PathLike, out: str | os.PathLike, params: UnitParams, *,
              config: MonitorConfig | None = None, on_unit: Callable[[UnitOutcome], object] | None = None,
              on_start: Callable[[int], object] | None = None) -> FleetRun:
    """Process every unit under ``root`` not already done into ``out`` on the Dask ``client``.

    ``config``: monitor-core thresholds (defaults when None); part of what makes a unit "done".

    ``on_start(n)`` is called once the ``n`` units to process are known, ``on_unit(outcome)`` as
    each finishes (progress bars). The fleet tables are assembled afterwards with
    :func:`fleet.tables.assemble`.
    """
    from dask.distributed import as_completed

    root, out = Path(root).resolve(), Path(out)
    units = discover(root)
    manifest = Manifest.load(out)
    config = config or MonitorConfig()
    config_digest = hashlib.sha256(json.dumps(config.to_dict(), sort_keys=True).encode()).hexdigest()[:16]
    digest = f"{params.digest()}/{config_digest}/{__version__}"
    hashes = _hashes(client, root, units, manifest)
    run = FleetRun(units)
    pending = {}
    params_future = client.scatter(params, broadcast=True, hash=False)  # a fresh key for every run
    order = sorted(units, key=lambda u: -sum(b.size for b in units[u]))
    for folder in order:
        unit_hashes = [hashes[b.relpath] for b in units[folder]]
        if manifest.is_done(folder, unit_hashes, digest, out):
            run.skipped.append(folder)
            continue
        future = client.submit(process_unit, str(root), folder, [b.relpath for b in units[folder]],
                               params_future, previous=_previous(manifest, folder, unit_hashes, digest, out),
                               config=config, pure=False)
        pending[future] = (folder, unit_hashes)
    manifest.save()  # the hashes, even if the run is interrupted now
    if on_start is not None:
        on_start(len(pending))
    saved = time.monotonic()
    try:
        for future in as_completed(list(pending)):
            folder, unit_hashes = pending.pop(future)
            recorded: list[str] | None = unit_hashes
            try:
                outcome = future.result()
            except Exception as exc:  # the worker died or the task could not run: report, retry next run
                outcome = UnitOutcome(folder, error=f"task failed: {type(exc).__name__}: {exc}")
                recorded = None
            manifest.units[folder] = {"hashes": recorded, "params_digest": digest,
                                      "status": "failed" if outcome.error else "ok",
                                      "file": save_outcome(out, outcome)}
            # a merged (resumed) result must never be merged twice: record it at once
            if outcome.resumed or time.monotonic() - saved > MANIFEST_EVERY_S:
                manifest.save()
                saved = time.monotonic()
            run.processed.append(folder)
            if outcome.resumed:
                run.resumed.append(folder)
            if on_unit is not None:
                on_unit(outcome)
    finally:
        manifest.save()
        if pending:  # interrupted: leave no task of this run behind on a shared cluster
            client.cancel(list(pending))
    return run
