"""Damaged storage never loses messages silently (issue 12 item 7).

Every message metadata.yaml (and the storage's own index) promises is either delivered or counted:
``lost`` for what the storage no longer holds, ``undecodable`` for records that do not decode. With
``strict`` the damage is an error instead. MCAP files written by an independent writer (the ``mcap``
package, chunk CRCs on, zstd and lz4) additionally never deliver a changed value: a chunk failing its
CRC is dropped whole and counted.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from ebm_wear_monitor.bagio import read_bags, write_unit_bag
from ebm_wear_monitor.cli.main import main
from ebm_wear_monitor.domain.signals import FLOAT64_STAMPED, SIGNALS, topic_name
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor.wire import encode_records

REPO = Path(__file__).resolve().parents[2]


def expected_counts(bag: Path) -> dict[str, int]:
    info = yaml.safe_load((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    return {t["topic_metadata"]["name"].rsplit("/embu/", 1)[1]: t["message_count"]
            for t in info["topics_with_message_count"]}


def accounted(rec, unit: str = "/embu") -> dict[str, int]:
    """Per topic (relative name): delivered + lost + undecodable."""
    data = rec.units[unit]
    out = {}
    for signal, sig in data.signals.items():
        faults = data.faults.get(signal, {})
        relative = topic_name("/embu", signal).rsplit("/embu/", 1)[1]
        out[relative] = sig.values.size + faults.get("lost", 0) + faults.get("undecodable", 0)
    return out


def damage(file: Path, offset: int, data: bytes) -> None:
    with file.open("r+b") as f:
        f.seek(offset)
        f.write(data)


def test_zeroed_block_of_the_healthy_bag_is_counted_and_strict_refuses(tmp_path, capsys):
    """The issue's case: 4096 zero bytes at offset 1,500,000 of bags/healthy's .mcap."""
    bag = tmp_path / "healthy"
    shutil.copytree(REPO / "bags" / "healthy", bag)
    damage(bag / "healthy.mcap", 1_500_000, bytes(4096))
    rec = read_bags([bag])
    lost = {s: f.get("lost", 0) for s, f in rec.units["/embu"].faults.items()}
    assert sum(lost.values()) >= 4096 // 59  # at least the records wholly inside the zeroed block
    assert accounted(rec) == expected_counts(bag)
    assert rec.problems
    assert main(["replay", str(bag), "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "lost" in out.split("input faults:")[1].splitlines()[0]
    with pytest.raises(InputError, match="lost"):
        read_bags([bag], strict=True)
    assert main(["replay", str(bag), "--no-progress", "--strict"]) == 2


def test_forty_random_corruptions_drop_nothing_silently(tmp_path):
    rng = np.random.default_rng(12)
    clean = tmp_path / "clean"
    shutil.copytree(REPO / "bags" / "healthy", clean)
    expected = expected_counts(clean)
    size = (clean / "healthy.mcap").stat().st_size
    outcomes = {"clean": 0, "counted": 0, "refused": 0}
    for k in range(40):
        bag = tmp_path / f"c{k}"
        shutil.copytree(clean, bag)
        n = int(rng.integers(1, 4097))
        noise = rng.integers(0, 256, n).astype(np.uint8).tobytes()
        damage(bag / "healthy.mcap", int(rng.integers(0, size - n)), noise)
        try:
            rec = read_bags([bag])
        except InputError as exc:  # the file as a whole is unreadable (e.g. its header): one line, exit 2
            assert "\n" not in str(exc)
            outcomes["refused"] += 1
            continue
        got = accounted(rec)
        for topic, count in expected.items():
            assert got.get(topic, 0) >= count, (k, topic, got, rec.problems)
        outcomes["counted" if rec.problems else "clean"] += 1
    assert outcomes["counted"] > 0


def write_mcap_bag(path: Path, compression: str, t_ns: np.ndarray) -> dict[str, np.ndarray]:
    """A rosbag2 mcap bag written by the ``mcap`` package (chunk CRCs), 4 topics, and its values."""
    from mcap.writer import CompressionType, Writer

    path.mkdir()
    values = {s: np.sin(np.arange(t_ns.size) * (i + 1) * 1e-3) for i, s in enumerate(SIGNALS)}
    with (path / "bag.mcap").open("wb") as f:
        writer = Writer(f, chunk_size=64 * 1024, compression=getattr(CompressionType, compression.upper()),
                        enable_crcs=True)
        writer.start(profile="ros2", library="test")
        schema = writer.register_schema(FLOAT64_STAMPED, "ros2msg", b"")
        channels = [writer.register_channel(topic_name("/embu", s), "cdr", schema) for s in SIGNALS]
        records = [encode_records(t_ns, values[s], "frame") for s in SIGNALS]
        for i in range(t_ns.size):
            for c, recs in zip(channels, records, strict=True):
                writer.add_message(c, int(t_ns[i]), recs[i], int(t_ns[i]))
        writer.finish()
    topics = [{"message_count": int(t_ns.size),
               "topic_metadata": {"name": topic_name("/embu", s), "type": FLOAT64_STAMPED,
                                  "serialization_format": "cdr", "offered_qos_profiles": []}}
              for s in SIGNALS]
    meta = {"rosbag2_bagfile_information": {
        "version": 9, "storage_identifier": "mcap", "relative_file_paths": ["bag.mcap"],
        "message_count": 4 * int(t_ns.size), "topics_with_message_count": topics,
        "compression_format": "", "compression_mode": ""}}
    (path / "metadata.yaml").write_text(yaml.safe_dump(meta))
    return values


@pytest.mark.parametrize("compression", ["zstd", "lz4"])
def test_crc_protected_chunks_never_deliver_a_changed_value(tmp_path, compression):
    t_ns = 1_700_000_000_000_000_000 + np.arange(20_000, dtype=np.int64) * 1_000_000
    bag = tmp_path / "clean"
    values = write_mcap_bag(bag, compression, t_ns)
    rec = read_bags([bag])
    assert not rec.problems
    for s in SIGNALS:  # read exactly as written (bulk path through the message indexes)
        sig = rec.units["/embu"].signals[s]
        assert np.array_equal(sig.stamps_ns, t_ns) and np.array_equal(sig.values, values[s])
    size = (bag / "bag.mcap").stat().st_size
    rng = np.random.default_rng(3)
    for k in range(10):
        damaged = tmp_path / f"d{k}"
        shutil.copytree(bag, damaged)
        n = int(rng.integers(1, 64))
        damage(damaged / "bag.mcap", int(rng.integers(size // 10, size * 8 // 10)),
               rng.integers(0, 256, n).astype(np.uint8).tobytes())
        try:
            rec = read_bags([damaged])
        except InputError:
            continue
        for s in SIGNALS:
            sig = rec.units["/embu"].signals[s]
            pos = np.searchsorted(t_ns, sig.stamps_ns)  # every delivered sample is an original one
            assert np.array_equal(t_ns[np.minimum(pos, t_ns.size - 1)], sig.stamps_ns)
            assert np.array_equal(values[s][pos], sig.values), (k, s)
            assert sig.values.size + rec.units["/embu"].faults.get(s, {}).get("lost", 0) == t_ns.size


def test_malformed_records_are_dropped_and_counted_not_refused(tmp_path, capsys):
    """58 malformed records among 115 k: replay drops and counts them (as the node does), exit 0."""
    t = 1_700_000_000 + np.arange(0, 38.4, 1e-3)
    bag = tmp_path / "bag"
    write_unit_bag(bag, t, {"/embu": {"angle": np.zeros(t.size), "velocity": np.zeros(t.size),
                                      "axial_force": np.zeros(t.size)}}, storage="sqlite3")
    import sqlite3

    rng = np.random.default_rng(8)
    with sqlite3.connect(bag / "bag.db3") as db:
        n = db.execute("SELECT count(*) FROM messages").fetchone()[0]
        bad = rng.choice(np.arange(1, n + 1), 58, replace=False).tolist()
        db.executemany("UPDATE messages SET data = ? WHERE id = ?",
                       [(rng.integers(0, 256, int(rng.integers(1, 40))).astype(np.uint8).tobytes(), i)
                        for i in bad])
    assert n == 3 * t.size > 115_000
    rec = read_bags([bag])
    undecodable = sum(f.get("undecodable", 0) for f in rec.units["/embu"].faults.values())
    assert 50 <= undecodable <= 58  # a random record may happen to deserialize: then the core judges it
    assert rec.messages + undecodable == n
    assert main(["replay", str(bag), "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "undecodable" in out
