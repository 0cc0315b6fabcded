"""Bag I/O: types from msg_defs, sqlite3/mcap round trips, bulk decode vs rosbags' deserializer, errors."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag2 import Reader, Writer

from ebm_wear_monitor.bagio import (
    Series,
    msg_dir,
    read_bags,
    read_ground_truth,
    typestore,
    write_unit_bag,
)
from ebm_wear_monitor.domain.signals import FLOAT64_STAMPED, INPUT_TOPICS, topic_name
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.monitor.wire import BAD_STAMP_NS, decode_records, encode_records, seconds_to_ns

REPO = Path(__file__).resolve().parents[2]


def _signals(t: np.ndarray, scale: float = 1.0) -> dict[str, np.ndarray]:
    return {"angle": scale * np.sin(t), "velocity": scale * np.cos(t), "axial_force": 1e4 * t,
            "current": -t}


def _message(stamp_s: float, value: float, frame_id: str):
    store = typestore()
    t = store.types["builtin_interfaces/msg/Time"]
    h = store.types["std_msgs/msg/Header"]
    sec = int(np.floor(stamp_s))
    return store.types[FLOAT64_STAMPED](
        header=h(stamp=t(sec=sec, nanosec=round((stamp_s - sec) * 1e9)), frame_id=frame_id), data=value)


def test_types_come_from_msg_defs_and_hash_like_rosidl():
    """The registered types hash (RIHS01) exactly as rosidl hashed the same .msg files at build time."""
    assert msg_dir() == REPO / "msg_defs" / "msg"
    names = sorted(n for n in typestore().fielddefs if n.startswith("ebm_wear_msgs/"))
    assert FLOAT64_STAMPED in names
    assert len(names) == len(list(msg_dir().glob("*.msg")))
    installed = Path(sys.prefix) / "share" / "ebm_wear_msgs" / "msg"
    for name in names:
        rosidl = json.loads((installed / f"{name.rsplit('/', 1)[1]}.json").read_text())
        hashes = {h["type_name"]: h["hash_string"] for h in rosidl["type_hashes"]}
        assert typestore().hash_rihs01(name) == hashes[name]
    fields = [f[0] for f in typestore().fielddefs[FLOAT64_STAMPED][1]]
    assert fields == ["header", "data"]


@pytest.mark.parametrize("frame_id", ["", "a", "base_link", "sensor_frame_with_a_long_name"])
def test_encode_matches_rosbags_serializer_byte_for_byte(frame_id):
    stamps = np.array([0, 1_500_000_000, 1_700_000_000_123_456_789, 12_999_999_999], dtype=np.int64)
    values = np.array([0.0, -2.5, 3.25e-7, np.inf])
    records = encode_records(stamps, values, frame_id)
    for s, v, r in zip(stamps, values, records, strict=True):
        expected = typestore().serialize_cdr(typestore().deserialize_cdr(r, FLOAT64_STAMPED), FLOAT64_STAMPED)
        assert bytes(expected) == r
        msg = typestore().deserialize_cdr(r, FLOAT64_STAMPED)
        assert msg.header.frame_id == frame_id
        assert msg.data == v
        assert msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec == s  # exact, no float on the way


def test_bulk_decode_handles_any_frame_id_and_big_endian():
    """Mixed frame_id lengths and big-endian records decode like rosbags' general deserializer."""
    store = typestore()
    msgs = [_message(10.0 + i * 0.25, i * 1.5 - 3, "x" * (i % 11)) for i in range(40)]
    raws = [bytes(store.serialize_cdr(m, FLOAT64_STAMPED, little_endian=i % 3 != 0))
            for i, m in enumerate(msgs)]
    got = decode_records(raws)
    assert got.ok.all()
    assert np.array_equal(got.values, [m.data for m in msgs])
    assert got.stamps_ns.tolist() == [m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for m in msgs]
    assert len(decode_records([])) == 0


def test_bulk_decode_flags_garbage_and_invalid_stamps():
    """Records whose layout does not check out are flagged (the adapters then try a general deserializer);
    nanosec >= 1e9 is no builtin_interfaces/Time: the stamp becomes BAD_STAMP_NS (counted 'bad_stamp')."""
    good = encode_records(np.array([5 * 10**9]), np.array([1.0]))[0]
    bad_nanosec = good[:8] + (10**9).to_bytes(4, "little") + good[12:]
    got = decode_records([b"\x00\x01\x00\x00\x01\x02\x03", good, good[:27], bad_nanosec,
                          b"\x00\x03" + good[2:]])
    assert got.ok.tolist() == [False, True, False, True, False]
    assert got.stamps_ns.tolist()[1] == 5 * 10**9 and got.stamps_ns[3] == BAD_STAMP_NS


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
@pytest.mark.parametrize("frame_id", ["", "embu_frame"])
def test_round_trip_two_units_four_topics(tmp_path, storage, frame_id):
    t = 1.7e9 + np.arange(0, 2.0, 0.005)
    units = {"/train7/car3/embu2": _signals(t), "/embu": _signals(t, scale=2.0)}
    bag = tmp_path / "bag"
    n = write_unit_bag(bag, t, units, storage=storage, frame_id=frame_id)
    assert n == 2 * 4 * len(t)
    with Reader(bag) as reader:  # what a ROS 2 tool sees
        topics = {topic_name(u, s) for u in units for s in INPUT_TOPICS}
        assert {c.topic for c in reader.connections} == topics
        assert {c.msgtype for c in reader.connections} == {FLOAT64_STAMPED}
        assert reader.message_count == n
        expected = {}
        for conn, stamp, raw in reader.messages():
            msg = typestore().deserialize_cdr(raw, conn.msgtype)
            expected.setdefault(conn.topic, []).append(
                (msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec, msg.data, stamp))
    rec = read_bags([bag])
    assert rec.rejected == {}
    assert rec.messages == n
    assert set(rec.units) == set(units)
    for unit, signals in units.items():
        assert rec.units[unit].bags == [bag]
        for name, values in signals.items():
            got = rec.units[unit].signals[name]
            ref = expected[topic_name(unit, name)]
            assert np.array_equal(got.values, values)
            assert np.array_equal(got.values, [r[1] for r in ref])  # bulk decode == general deserializer
            assert got.stamps_ns.tolist() == [r[0] for r in ref]  # exact ns
            assert np.array_equal(got.stamps_ns, seconds_to_ns(t))
            assert [r[2] for r in ref] == seconds_to_ns(t).tolist()  # bag time = sample time by default


def test_receive_order_is_kept_and_bags_of_a_unit_concatenate_in_time_order(tmp_path):
    t = np.arange(10.0, 11.0, 0.01)
    received = t + np.where(np.arange(len(t)) % 7 == 0, 0.05, 0.0)  # every 7th sample arrives late
    late = Series(t, np.arange(len(t), dtype=float), received)
    write_unit_bag(tmp_path / "b_late", None, {"/u": {"axial_force": late}}, storage="sqlite3")
    write_unit_bag(tmp_path / "a_early", t - 10.0, {"/u": {"axial_force": -np.ones_like(t)}})
    rec = read_bags([tmp_path / "b_late", tmp_path / "a_early"])
    sig = rec.units["/u"].signals["axial_force"]
    assert rec.units["/u"].bags == [tmp_path / "a_early", tmp_path / "b_late"]
    assert np.all(sig.values[: len(t)] == -1)
    order = np.argsort(seconds_to_ns(received), kind="stable")  # receive times as stored: whole ns
    assert np.array_equal(sig.values[len(t):], order.astype(float))
    assert np.allclose(sig.stamps[len(t):], t[order], rtol=0, atol=1e-9)  # stamps carry whole ns
    with pytest.raises(InputError, match="given twice"):  # the same bag under another spelling
        read_bags([tmp_path / "a_early", tmp_path / "b_late" / ".." / "a_early"])


def _raw_bag(path: Path, topics: dict[str, tuple[str, list[bytes]]], storage: str = "sqlite3") -> None:
    from ebm_wear_monitor.bagio.writer import STORAGES

    with Writer(path, version=9, storage_plugin=STORAGES[storage]) as writer:
        for topic, (msgtype, raws) in topics.items():
            conn = writer.add_connection(topic, msgtype, typestore=typestore())
            for i, raw in enumerate(raws):
                writer.write(conn, i * 1000, raw)


def _float64(values) -> list[bytes]:
    store = typestore()
    name = "std_msgs/msg/Float64"
    return [bytes(store.serialize_cdr(store.types[name](data=float(v)), name)) for v in values]


def test_wrong_type_on_one_topic_is_skipped_and_reported(tmp_path):
    good = encode_records(np.arange(5) * 10**9, np.arange(5.0))
    _raw_bag(tmp_path / "bag", {"/embu/screw/angle": (FLOAT64_STAMPED, good),
                                "/embu/axial_force": ("std_msgs/msg/Float64", _float64(range(5))),
                                "/embu/wear": ("std_msgs/msg/Float64", _float64(range(2)))})
    rec = read_bags([tmp_path / "bag"])
    assert list(rec.units["/embu"].signals) == ["angle"]
    assert list(rec.rejected) == [f"{tmp_path / 'bag'}: /embu/axial_force"]
    assert "std_msgs/msg/Float64" in rec.rejected[f"{tmp_path / 'bag'}: /embu/axial_force"]


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_bad_bags_raise_one_line_input_errors(tmp_path, storage):
    t = np.arange(0, 20.0, 0.001)
    bag = tmp_path / "ok"
    write_unit_bag(bag, t, {"/embu": _signals(t)}, storage=storage)
    (data_file,) = (p for p in bag.iterdir() if p.name != "metadata.yaml")
    data_file.write_bytes(data_file.read_bytes()[: data_file.stat().st_size // 2])  # truncated copy
    wrong = tmp_path / "wrong"
    _raw_bag(wrong, {"/embu/screw/angle": ("std_msgs/msg/Float64", _float64(range(3)))}, storage)
    corrupt = tmp_path / "corrupt"
    _raw_bag(corrupt, {"/embu/screw/angle": (FLOAT64_STAMPED, [b"\x00\x01\x00\x00\x07"] * 3)}, storage)
    unknown = tmp_path / "unknown"
    _raw_bag(unknown, {"/embu/screw/angle": (FLOAT64_STAMPED, encode_records([10**9], [2.0]))}, storage)
    meta = unknown / "metadata.yaml"
    meta.write_text(meta.read_text().replace(f"storage_identifier: {storage}", "storage_identifier: zip"))
    (tmp_path / "empty").mkdir()
    garbage = tmp_path / "garbage"
    garbage.mkdir()
    (garbage / "metadata.yaml").write_text("- a list, not rosbag2 metadata\n")
    cases = {bag: "truncated", wrong: "no input topic", corrupt: "corrupt", unknown: "unknown bag storage",
             tmp_path / "empty": "not a rosbag2 bag", tmp_path / "missing": "no such bag",
             garbage: "not a rosbag2 metadata file"}
    if storage == "mcap":  # chunks before the cut are intact: read; the rest counted 'lost' (strict: error)
        del cases[bag]
        rec = read_bags([bag])
        faults = rec.units["/embu"].faults
        for name, sig in rec.units["/embu"].signals.items():
            assert 0 < sig.values.size < t.size
            assert faults[name] == {"lost": t.size - sig.values.size}
        assert any("lost" in p for p in rec.problems)
        with pytest.raises(InputError, match=r"lost|truncated|skipped"):
            read_bags([bag], strict=True)
    for path, words in cases.items():
        with pytest.raises(InputError) as err:
            read_bags([path])
        text = str(err.value)
        assert str(path) in text
        assert "\n" not in text
        assert words in text or (words == "truncated" and "unreadable" in text), text


def test_writer_refuses_existing_and_leaves_nothing_on_bad_input(tmp_path):
    t = np.arange(3.0)
    truth = {"units": {"/e": {"eol_cycles": 9}}}
    write_unit_bag(tmp_path / "bag", t, {"/e": {"angle": t}}, ground_truth=truth)
    assert read_ground_truth(tmp_path / "bag") == truth
    with pytest.raises(InputError, match="exists"):
        write_unit_bag(tmp_path / "bag", t, {"/e": {"angle": t}})
    for bad in ({"/e": {"torque": t}}, {"/e": {"angle": t[:2]}}, {"/bad ns": {"angle": t}},
                {"/car/2embu": {"angle": t}}, {"/a//b": {"angle": t}}):
        with pytest.raises(InputError):
            write_unit_bag(tmp_path / "new", t, bad, storage="sqlite3")
    with pytest.raises(InputError, match="storage"):
        write_unit_bag(tmp_path / "new", t, {"/e": {"angle": t}}, storage="rosbag1")
    with pytest.raises(InputError, match="cannot write"):
        write_unit_bag(tmp_path / "bag" / "metadata.yaml" / "new", t, {"/e": {"angle": t}})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bag"]
    assert read_ground_truth(tmp_path / "bag-none") is None


def test_bad_bags_can_be_collected_instead_of_raised(tmp_path):
    t = np.arange(0, 1.0, 0.01)
    write_unit_bag(tmp_path / "good", t, {"/embu": _signals(t)})
    failed: dict[str, str] = {}
    rec = read_bags([tmp_path / "good", tmp_path / "missing"], failed=failed)
    assert rec.messages == 4 * len(t)
    assert list(failed) == [str(tmp_path / "missing")]
    assert "no such bag" in failed[str(tmp_path / "missing")]


def test_several_threads_can_read_at_once(tmp_path):
    """The fleet reads bags from threads: every read is complete and independent."""
    from concurrent.futures import ThreadPoolExecutor

    t = np.arange(0, 2.0, 0.001)
    write_unit_bag(tmp_path / "bag", t, {"/embu": _signals(t)}, storage="sqlite3")
    with ThreadPoolExecutor(4) as pool:
        counts = list(pool.map(lambda _: read_bags([tmp_path / "bag"]).messages, range(8)))
    assert counts == [4 * len(t)] * 8
    with pytest.raises(InputError):
        read_bags([tmp_path / "bag", tmp_path / "missing"])


@pytest.mark.parametrize("text", ['{"units": {"/e": 5}}', '{"units": {"/e": {"eol_cycles": "soon"}}}',
                                  '{"units": {"/e": {"cycles_at_start": true}}}', '{"units": []}', "{"])
def test_malformed_ground_truth_is_a_one_line_input_error(tmp_path, text):
    (tmp_path / "bag").mkdir()
    (tmp_path / "bag" / "ground_truth.json").write_text(text)
    with pytest.raises(InputError, match=r"ground_truth\.json") as err:
        read_ground_truth(tmp_path / "bag")
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_records_the_bulk_path_does_not_recognise_go_through_the_general_deserializers(tmp_path, storage):
    """A record with non-zero encapsulation options (a valid CDR header the bulk layout check does not
    take) is decoded by rosbags in the reader and by rclpy in the node, to the same stamp and value;
    bulk-recognised records around it (any frame_id length) are untouched."""
    from ebm_wear_monitor.monitor.wire import Batch
    from ebm_wear_monitor.ros.inputs import InputBuffer

    stamps = 1_700_000_000_000_000_000 + np.arange(30, dtype=np.int64) * 1_000_000
    values = np.arange(30) * 0.5
    raws = [encode_records(stamps[i:i + 1], values[i:i + 1], "f" * (i % 9))[0] for i in range(30)]
    odd = {3, 17, 18}
    raws = [b"\x00\x01\x00\x04" + r[4:] if i in odd else r for i, r in enumerate(raws)]
    assert decode_records(raws).ok.tolist() == [i not in odd for i in range(30)]
    _raw_bag(tmp_path / "bag", {"/embu/screw/angle": (FLOAT64_STAMPED, raws)}, storage)
    sig = read_bags([tmp_path / "bag"]).units["/embu"].signals["angle"]
    assert np.array_equal(sig.stamps_ns, stamps) and np.array_equal(sig.values, values)
    buffer, batch = InputBuffer("angle"), Batch()
    buffer.pending += raws
    buffer.drain(batch)
    got_stamps, got_values = batch.signals["angle"]
    assert np.array_equal(got_stamps, stamps) and np.array_equal(got_values, values)
    assert batch.faults == {}
