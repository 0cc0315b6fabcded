"""Node and replay feed the one Feeder in different orders; for every stamp fault they must agree (issue 12).

The same records (three topics at their own rates, each record with its header
stamp and a log/arrival time) reach the core two ways:

* as the node receives them: per topic in arrival order, drained at timer ticks
  of random length (what ``ros/inputs.py`` hands the feeder);
* as the replay reads them: all topics merged by log time, cut into storage
  chunks of random size (what ``bagio.BagReader`` hands the feeder).

Hypothesis draws the stamp faults: glitches into the future and the past,
nanosec >= 1e9, duplicated records, arrival shuffled within a few ms, log time
lagging the header stamp. Records are serialised and decoded by
``monitor.wire`` both ways. The events (applications with their snapshots), the
final snapshot and the persisted state must be equal, bit for bit.
"""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ebm_wear_monitor.monitor import Batch, Feeder, MonitorCore
from ebm_wear_monitor.monitor.wire import decode_records, encode_records
from ebm_wear_monitor.params import load_unit

from multirate_synth import RATES, recording


def encoded(rec: dict) -> dict[str, tuple[list[bytes], np.ndarray]]:
    """Per topic: raw CDR records (non-empty frame_id) and their log times, in arrival order."""
    return {s: (encode_records(r["stamps"], r["values"], frame_id=f"embu2_{s}"), r["log"])
            for s, r in rec.items()}


def feed_as_node(unit, records, ticks_ns: int, rng) -> tuple:
    """Per topic, arrival order, drained at ticks of random length (mean ``ticks_ns``)."""
    feeder = Feeder(MonitorCore(unit))
    events = []
    start = min(int(log.min()) for _, log in records.values())
    end = max(int(log.max()) for _, log in records.values())
    pos = dict.fromkeys(records, 0)
    t = start
    while t <= end:
        t += int(rng.integers(1, 2 * ticks_ns))
        batch = Batch()
        for signal, (raws, log) in records.items():
            upto = int(np.searchsorted(log, t, side="right"))
            if upto > pos[signal]:
                got = decode_records(raws[pos[signal]:upto])
                batch.add(signal, got.stamps_ns[got.ok], got.values[got.ok])
                batch.count(signal, "undecodable", int((~got.ok).sum()))
                pos[signal] = upto
        events += feeder.feed(batch)
    events += feeder.finish()
    return events, feeder


def feed_as_replay(unit, records, chunk: int) -> tuple:
    """All topics merged by log time (stable), cut into storage chunks of ``chunk`` records."""
    names = list(records)
    which = np.concatenate([np.full(len(records[s][0]), i) for i, s in enumerate(names)])
    raws = [r for s in names for r in records[s][0]]
    order = np.argsort(np.concatenate([records[s][1] for s in names]), kind="stable")
    feeder = Feeder(MonitorCore(unit))
    events = []
    for a in range(0, order.size, chunk):
        part = order[a:a + chunk]
        batch = Batch()
        for i, signal in enumerate(names):
            mine = part[which[part] == i]
            if mine.size:
                got = decode_records([raws[k] for k in mine.tolist()])
                batch.add(signal, got.stamps_ns[got.ok], got.values[got.ok])
                batch.count(signal, "undecodable", int((~got.ok).sum()))
        events += feeder.feed(batch)
    events += feeder.finish()
    return events, feeder


#: snapshot keys that tell how far input processing has got, not the state after an application
PROGRESS_KEYS = ("input_faults", "input_faults_by_signal", "input_rates_hz")


def fingerprint(events, feeder) -> tuple:
    """Applications with their snapshots (all but the progress counters), final snapshot, final state."""
    core = feeder.core
    snaps = [{k: v for k, v in e.snapshot.to_json_dict().items() if k not in PROGRESS_KEYS} for e in events]
    cycles = [repr(asdict(e.cycle)) + json.dumps(s, sort_keys=True)
              for e, s in zip(events, snaps, strict=True)]
    final = json.dumps(core.to_json_dict(), sort_keys=True)
    return cycles, final, json.dumps(core.state.to_dict(), sort_keys=True)


FAULTS = st.lists(st.tuples(st.sampled_from(["future", "past", "nanosec", "duplicate", "shuffle"]),
                            st.sampled_from(sorted(RATES)), st.floats(0.0, 1.0), st.floats(1.5, 1e4)),
                  min_size=1, max_size=6)


def inject(rec: dict, faults, rng) -> None:
    """Apply stamp faults in place (header stamps and arrival; values untouched)."""
    for kind, signal, where, size in faults:
        r = rec[signal]
        i = int(where * (r["stamps"].size - 1))
        if kind == "future":
            r["stamps"][i] += int(size * 1e9)
        elif kind == "past":
            r["stamps"][i] -= int(size * 1e9)
        elif kind == "nanosec":  # made invalid on the wire below (nanosec >= 1e9)
            r.setdefault("bad_nanosec", []).append(i)
        elif kind == "duplicate":
            for key in ("stamps", "values", "log"):
                r[key] = np.insert(r[key], i + 1, r[key][i])
        else:  # arrival shuffled over a few ms (out of order within the reorder window)
            j = min(i + int(rng.integers(2, 8)), r["stamps"].size)
            perm = i + rng.permutation(j - i)
            for key in ("stamps", "values"):
                r[key][i:j] = r[key][perm]


def break_nanosec(records: dict, rec: dict) -> None:
    for signal, (raws, _log) in records.items():
        for i in rec[signal].get("bad_nanosec", []):
            raws[i] = raws[i][:8] + (1_000_000_000 + i).to_bytes(4, "little") + raws[i][12:]


@pytest.fixture(scope="module")
def unit():
    return load_unit()


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(faults=FAULTS, seed=st.integers(0, 2**16), tick_ms=st.integers(20, 200), chunk=st.integers(100, 20000))
def test_node_and_replay_orders_agree_for_any_stamp_fault(unit, faults, seed, tick_ms, chunk):
    rng = np.random.default_rng(seed)
    rec = recording(3, seed)
    inject(rec, faults, rng)
    records = encoded(rec)
    break_nanosec(records, rec)
    node = fingerprint(*feed_as_node(unit, records, tick_ms * 1_000_000, rng))
    replay = fingerprint(*feed_as_replay(unit, records, chunk))
    assert node == replay


@pytest.mark.parametrize("kind", ["future", "past"])
def test_one_glitch_costs_no_application(unit, kind):
    """The multi-rate recording (2 kHz / 1 kHz, own phases, jitter, drops, log lag, frame_id) gives every
    application, with or without one angle stamp 1000 s off, in both orders."""
    clean = recording(5, 11)
    ref_events, ref = feed_as_replay(unit, encoded(clean), 4096)
    assert len(ref_events) == 5
    faults = ref.core.snapshot().input_faults
    assert set(faults) <= {"missing"} and faults.get("missing", 0) <= 2  # only the very edges
    rec = recording(5, 11)
    inject(rec, [(kind, "angle", 0.3, 1000.0)], np.random.default_rng(0))
    for events, feeder in (feed_as_replay(unit, encoded(rec), 4096),
                           feed_as_node(unit, encoded(rec), 40_000_000, np.random.default_rng(1))):
        assert len(events) == 5
        got = feeder.core.snapshot().input_faults
        assert got.get("stamp_glitch" if kind == "future" else "stamp_backwards") == 1


def test_the_glitch_of_the_issue_in_bags_worn(unit, tmp_path):
    """Issue 12's case: one angle sample of bags/worn stamped 1000 s in the future (replay used to count
    5,653 samples late and find 5 of 16 applications). Replay from the damaged bag and the node's order
    of the same records (per topic, 40 ms ticks of arrival time) give the clean result's applications."""
    import shutil
    import sqlite3

    from rosbags.rosbag2 import Reader

    from ebm_wear_monitor.domain.signals import split_topic
    from ebm_wear_monitor.params import load_unit as load
    from ebm_wear_monitor.replay.run import replay_bags

    repo = Path(__file__).resolve().parents[2]
    params = load(repo / "bags" / "accelerated_unit.yaml")
    bag = tmp_path / "worn"
    shutil.copytree(repo / "bags" / "worn", bag)
    with sqlite3.connect(bag / "worn.db3") as db:
        (angle,) = db.execute("SELECT id FROM topics WHERE name LIKE '%/screw/angle'").fetchone()
        rows = db.execute("SELECT id, data FROM messages WHERE topic_id = ? ORDER BY id", (angle,)).fetchall()
        row_id, data = rows[int(0.3 * len(rows))]
        sec = int.from_bytes(data[4:8], "little", signed=True) + 1000
        glitched = data[:4] + sec.to_bytes(4, "little") + data[8:]
        db.execute("UPDATE messages SET data = ? WHERE id = ?", (glitched, row_id))
    clean = replay_bags([repo / "bags" / "worn"], params).units[0]
    (replayed,) = replay_bags([bag], params).units
    assert replayed.snapshot.duty_cycles == clean.snapshot.duty_cycles == 16
    assert replayed.snapshot.input_faults == {**clean.snapshot.input_faults, "stamp_glitch": 1}
    records: dict[str, tuple[list[bytes], list[int]]] = {}
    with Reader(bag) as reader:  # an independent reader gives the records in arrival (log time) order
        for conn, log, raw in reader.messages():
            raws, logs = records.setdefault(split_topic(conn.topic)[1], ([], []))
            raws.append(bytes(raw))
            logs.append(log)
    records = {s: (r, np.array(t, np.int64)) for s, (r, t) in records.items()}
    events, feeder = feed_as_node(params, records, 40_000_000, np.random.default_rng(2))
    node = feeder.core.to_json_dict()
    assert node["duty_cycles"] == 16
    for key in ("wear", "clearance", "remaining_life", "duty_cycles"):
        assert node[key] == replayed.snapshot.to_json_dict()[key], key
    assert [e.cycle.index for e in events] == replayed.applications["index"].tolist()
