"""Which bags a fleet directory holds and how their units are named (interface.md section 5)."""

from __future__ import annotations

import numpy as np
import pytest

from ebm_wear_monitor.bagio import write_unit_bag
from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.fleet.discover import content_hash, discover


def _bag(path, storage="mcap"):
    t = np.arange(3.0)
    write_unit_bag(path, t, {"/embu": {"angle": t}}, storage=storage)


def test_units_are_folders_relative_to_the_root(tmp_path):
    _bag(tmp_path / "t1" / "c1" / "e1" / "2026-11-20.bag")
    _bag(tmp_path / "t1" / "c1" / "e1" / "2026-11-21.bag", "sqlite3")
    _bag(tmp_path / "t1" / "c2" / "e1" / "day.bag")
    _bag(tmp_path / "loose")                               # a bag right in the root: its own unit
    (tmp_path / "t2" / "c1").mkdir(parents=True)
    (tmp_path / "t2" / "c1" / "e9.mcap").write_bytes((tmp_path / "loose" / "loose.mcap").read_bytes())
    (tmp_path / "notes.txt").write_text("not a bag")
    units = discover(tmp_path)
    assert list(units) == ["loose", "t1/c1/e1", "t1/c2/e1", "t2/c1"]
    assert [b.relpath for b in units["t1/c1/e1"]] == ["t1/c1/e1/2026-11-20.bag", "t1/c1/e1/2026-11-21.bag"]
    assert [b.relpath for b in units["t2/c1"]] == ["t2/c1/e9.mcap"]
    one = units["t1/c2/e1"][0]
    assert one.size == sum(p.stat().st_size for p in (tmp_path / one.relpath).iterdir())


def test_content_hash_follows_the_bytes(tmp_path):
    _bag(tmp_path / "a" / "x.bag")
    before = content_hash(tmp_path, "a/x.bag")
    assert before == content_hash(tmp_path, "a/x.bag") and len(before) == 64
    meta = tmp_path / "a" / "x.bag" / "metadata.yaml"
    meta.write_text(meta.read_text() + "\n")
    assert content_hash(tmp_path, "a/x.bag") != before


def test_no_bags_is_bad_input(tmp_path):
    with pytest.raises(InputError, match="no rosbag2 bags"):
        discover(tmp_path)
    with pytest.raises(InputError, match="not a directory"):
        discover(tmp_path / "missing")
