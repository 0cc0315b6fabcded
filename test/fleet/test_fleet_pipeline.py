"""Fleet pipeline on a real Dask LocalCluster (2 worker processes, loopback) over a synthetic fleet."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pandas as pd
import pytest
from rosbags.rosbag2 import Writer

from ebm_wear_monitor.bagio import Series, read_bags, typestore, write_unit_bag
from ebm_wear_monitor.bagio.writer import STORAGES
from ebm_wear_monitor.fleet.cluster import dask_client
from ebm_wear_monitor.fleet.discover import discover
from ebm_wear_monitor.fleet.manifest import Manifest
from ebm_wear_monitor.fleet.pipeline import process_unit, run_fleet, unit_file
from ebm_wear_monitor.fleet.synthetic import generate_fleet, scenarios
from ebm_wear_monitor.fleet.tables import assemble, write_tables
from ebm_wear_monitor.params import load_unit

pytestmark = pytest.mark.timeout(240)  # a hung cluster fails fast instead of eating the CI budget

N_UNITS = 20
TRUNCATED_UNIT = "train00/car0/embu1"
WRONG_TYPE_UNIT = "train99/car0/embu0"


class SimulatedInterruptError(Exception):
    """Stands in for Ctrl-C in the middle of a fleet run."""


def _wrong_type_bag(path) -> None:
    store, name = typestore(), "std_msgs/msg/Float64"
    with Writer(path, version=9, storage_plugin=STORAGES["mcap"]) as writer:
        for topic in ("/embu/screw/angle", "/embu/axial_force"):
            conn = writer.add_connection(topic, name, typestore=store)
            for i in range(5):
                writer.write(conn, i, bytes(store.serialize_cdr(store.types[name](data=1.0), name)))


@pytest.fixture(scope="module")
def client():
    with dask_client(None, n_workers=2) as c:  # LocalCluster, 2 processes, 127.0.0.1
        assert len(c.scheduler_info()["workers"]) == 2
        assert c.scheduler.address.startswith("tcp://127.0.0.1:")
        yield c


@pytest.fixture(scope="module")
def generated(tmp_path_factory, client):
    """20 synthetic units (2 bags of 3 applications each, 100 Hz), a truncated extra bag in one unit
    and a unit whose only bag carries the wrong message type; and the fleet's unit parameters."""
    root = tmp_path_factory.mktemp("fleet") / "fleet"
    units = scenarios(N_UNITS, seed=11, cycles_per_bag=3, bags_per_unit=2, rate_hz=100.0)
    params, _ = generate_fleet(root, units, load_unit(), client=client)
    good = root / TRUNCATED_UNIT / "2026-11-20.bag"
    bad = root / TRUNCATED_UNIT / "2026-11-30.bag"
    shutil.copytree(good, bad)
    (data,) = (p for p in bad.iterdir() if p.suffix in (".mcap", ".db3"))
    data.write_bytes(data.read_bytes()[: data.stat().st_size // 3])
    _wrong_type_bag(root / WRONG_TYPE_UNIT / "2026-11-20.bag")
    return root, params


@pytest.fixture(scope="module")
def fleet_dir(generated):
    return generated[0]


@pytest.fixture(scope="module")
def params(generated):
    assert generated[1].digest() == load_unit(generated[0] / "params.yaml").digest()  # the fleet unit file
    return generated[1]


@pytest.fixture(scope="module")
def serial(fleet_dir, params):
    """The reference: every unit processed in this process, one after the other."""
    units = discover(fleet_dir)
    return {u: process_unit(str(fleet_dir), u, [b.relpath for b in bags], params)
            for u, bags in units.items()}


def _result(out, unit: str) -> dict:
    (entry,) = json.loads((out / unit_file(unit)).read_text())["entries"]
    return entry


def _applications(out, unit: str) -> pd.DataFrame:
    return pd.read_parquet(out / unit_file(unit).replace(".json", ".parquet"))


def _entries(outcome) -> list[dict]:
    return json.loads(json.dumps([e.to_json_dict() for e in outcome.entries]))


def test_dask_fleet_equals_serial_and_reports_bad_bags(tmp_path, fleet_dir, client, serial, params):
    out = tmp_path / "out"
    run = run_fleet(client, fleet_dir, out, params)
    assert len(run.units) == N_UNITS + 1
    assert sorted(run.processed) == sorted(serial)
    tables = assemble(out, list(run.units), Manifest.load(out))
    write_tables(out, tables)
    by_unit = {e["unit"]: e for e in tables.document["units"]}
    for unit, outcome in serial.items():
        if unit == WRONG_TYPE_UNIT:
            continue
        assert by_unit[unit] == _entries(outcome)[0]  # same numbers on 2 worker processes as in series
    failures = {(f["unit"], f["bag"]): f["reason"] for f in tables.document["failures"]}
    truncated, wrong = f"{TRUNCATED_UNIT}/2026-11-30.bag", f"{WRONG_TYPE_UNIT}/2026-11-20.bag"
    assert set(failures) == {(TRUNCATED_UNIT, truncated), (WRONG_TYPE_UNIT, wrong)}
    assert "unreadable bag" in failures[TRUNCATED_UNIT, truncated]
    assert "no input topic of type ebm_wear_msgs/msg/Float64Stamped" in failures[WRONG_TYPE_UNIT, wrong]
    assert "std_msgs/msg/Float64" in failures[WRONG_TYPE_UNIT, wrong]
    assert by_unit[TRUNCATED_UNIT]["bags"] == [f"{TRUNCATED_UNIT}/2026-11-2{d}.bag" for d in (0, 1)]
    units = pd.read_parquet(out / "units.parquet")
    assert units["rank"].tolist() == list(range(1, N_UNITS + 2))
    assert units.iloc[-1]["unit"] == WRONG_TYPE_UNIT and units.iloc[-1]["status"] == "failed"
    apps = pd.read_parquet(out / "applications.parquet")
    assert apps.groupby("unit").size().to_dict() == {u: e["duty_cycles"] for u, e in by_unit.items()}
    assert (out / "fleet_summary.csv").read_text().startswith("rank,unit,status,cycles_p05")


def test_incremental_and_resumable(tmp_path, fleet_dir, client, params):
    out = tmp_path / "out"
    done = []

    def stop_after_three(outcome):
        done.append(outcome.unit)
        if len(done) == 3:
            raise SimulatedInterruptError

    with pytest.raises(SimulatedInterruptError):
        run_fleet(client, fleet_dir, out, params, on_unit=stop_after_three)
    resumed = run_fleet(client, fleet_dir, out, params)
    assert sorted(resumed.skipped) == sorted(done)
    assert sorted(resumed.processed + resumed.skipped) == sorted(resumed.units)
    again = run_fleet(client, fleet_dir, out, params)
    assert again.processed == []
    unit = "train01/car2/embu0"
    before = _result(out, unit)
    # a bag whose data lie before what was processed: the unit runs again from its first bag
    extra = fleet_dir / unit / "2026-11-22.bag"
    shutil.copytree(fleet_dir / unit / "2026-11-21.bag", extra)
    rerun = run_fleet(client, fleet_dir, out, params)
    assert (rerun.processed, rerun.resumed) == ([unit], [])
    shutil.rmtree(extra)
    assert run_fleet(client, fleet_dir, out, params).processed == [unit]
    assert _result(out, unit) == before
    # a new day's recording: only the new bag is read, the core continues from the saved state
    day = read_bags([fleet_dir / unit / "2026-11-21.bag"]).units["/embu"].signals
    next_day = {k: Series(s.stamps_ns + 86_400 * 10**9, s.values) for k, s in day.items()}
    write_unit_bag(extra, None, {"/embu": next_day})
    try:
        resumed = run_fleet(client, fleet_dir, out, params)
        assert (resumed.processed, resumed.resumed) == ([unit], [unit])
        after = _result(out, unit)
        assert after["bags"] == [*before["bags"], f"{unit}/2026-11-22.bag"]
        assert after["duty_cycles"] > before["duty_cycles"]
        apps = _applications(out, unit)  # the earlier history, then the new applications
        assert apps["index"].tolist() == list(range(1, after["duty_cycles"] + 1))
        assert after["wear"]["screw_raceway_m"] > before["wear"]["screw_raceway_m"]
    finally:
        shutil.rmtree(extra)


def test_ranking_by_p05_puts_urgent_first_and_unknown_last(tmp_path):
    """Three result files with known p05 (one without measurable growth) rank 2 < 7 < None."""
    from ebm_wear_monitor.outputs import write_json

    manifest = Manifest.load(tmp_path)
    for unit, p05 in (("a", 7.0), ("b", None), ("c", 2.0)):
        wear = {"screw_raceway_m": 0, "nut_raceway_m": 0, "ball_m": 0}
        entry = {"unit": unit, "duty_cycles": 1, "wear": wear,
                 "clearance": {"model_m": 2e-4, "estimate_m": 2e-4, "std_m": 1e-6},
                 "remaining_life": {"limit_m": 5e-4, "cycles_p05": p05, "cycles_p50": p05, "cycles_p95": p05},
                 "input_faults": {"late": 1}}
        result = {"unit": unit, "error": None, "failed_bags": {}, "rejected": {}, "entries": [entry]}
        write_json(tmp_path / unit_file(unit), result)
        manifest.units[unit] = {"hashes": [], "params_digest": "", "status": "ok", "file": unit_file(unit)}
    tables = assemble(tmp_path, ["a", "b", "c"], manifest)
    assert tables.units["unit"].tolist() == ["c", "a", "b"]
    assert [u["unit"] for u in tables.document["units"]] == ["c", "a", "b"]
    assert np.isnan(tables.units["cycles_p05"].iloc[-1])
