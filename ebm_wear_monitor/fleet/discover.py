"""Find the units' bags in a fleet directory tree and fingerprint them.

A bag is a rosbag2 directory (it holds ``metadata.yaml``) or a bare ``.mcap`` /
``.db3`` storage file outside such a directory. A unit is the folder that holds
its bags, named relative to the fleet root (interface.md section 5), e.g.
``train1/car2/embu0`` for ``DIR/train1/car2/embu0/2026-11-20.bag``; bags lying
directly in the root (or a root that is itself a bag) are a unit each, named
after the bag. Bag directories are not searched further.
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

from ebm_wear_monitor.errors import InputError

BAG_FILE_SUFFIXES = (".mcap", ".db3")
_HASH_BLOCK = 1 << 20


@dataclass(frozen=True)
class BagFile:
    """One bag of the fleet: path relative to the root, and a cheap fingerprint (bytes, newest mtime [ns])."""

    relpath: str
    size: int
    mtime_ns: int


def _bag_files(bag: Path) -> list[Path]:
    return sorted(p for p in bag.rglob("*") if p.is_file()) if bag.is_dir() else [bag]


def _fingerprint(root: Path, bag: Path) -> BagFile:
    stats = [p.stat() for p in _bag_files(bag)]
    return BagFile(bag.relative_to(root).as_posix(), sum(s.st_size for s in stats),
                   max((s.st_mtime_ns for s in stats), default=0))


def discover(root: str | os.PathLike) -> dict[str, list[BagFile]]:
    """Unit name -> its bags (sorted by path) under fleet directory ``root``."""
    root = Path(root)
    if not root.is_dir():
        raise InputError(f"{root}: not a directory")
    units: dict[str, list[BagFile]] = {}

    def unreadable(exc: OSError) -> None:  # os.walk would skip the folder, and its units, silently
        raise InputError(f"{exc.filename}: cannot read this fleet folder ({exc.strerror or exc})")

    for folder, dirs, files in os.walk(root, onerror=unreadable):
        here = Path(folder)
        if "metadata.yaml" in files:
            dirs.clear()
            unit = here.parent.relative_to(root).as_posix() if here != root else "."
            units.setdefault(here.name if unit == "." else unit, []).append(_fingerprint(root, here))
            continue
        dirs.sort()
        for name in sorted(files):
            if name.endswith(BAG_FILE_SUFFIXES):
                unit = here.relative_to(root).as_posix()
                units.setdefault(Path(name).stem if unit == "." else unit, []).append(
                    _fingerprint(root, here / name))
    if not units:
        raise InputError(f"{root}: no rosbag2 bags found (directories with metadata.yaml, .mcap/.db3 files)")
    return {u: sorted(b, key=lambda x: x.relpath) for u, b in sorted(units.items())}


def content_hash(root: str | os.PathLike, relpath: str) -> str:
    """SHA-256 over a bag's files (names and bytes, sorted by name), hex."""
    bag = Path(root) / relpath
    digest = hashlib.sha256()
    for path in _bag_files(bag):
        digest.update(path.relative_to(bag).as_posix().encode() if bag.is_dir() else b"")
        with path.open("rb") as fh:
            while block := fh.read(_HASH_BLOCK):
                digest.update(block)
    return digest.hexdigest()
