"""The fleet run's manifest: which bags (by content hash) produced which unit result.

``OUT/manifest.json`` records, per bag, its fingerprint (size, newest mtime)
and SHA-256, and per unit the ordered list of its bag hashes, the parameter
digest it ran with, its status and its result file. A unit whose bags and
parameters are unchanged is skipped on the next run; a bag whose fingerprint
is unchanged is not re-hashed. The manifest is rewritten atomically every
couple of seconds while units finish, after every resumed unit, at the end and
when the run is interrupted (``fleet.pipeline``), so an interrupted run loses
at most the units in flight (a hard kill: those of the last two seconds, which
then simply run again).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

from ebm_wear_monitor.errors import InputError
from ebm_wear_monitor.fleet.discover import BagFile
from ebm_wear_monitor.outputs import write_json

MANIFEST_FILE = "manifest.json"
FORMAT = 1


@dataclass
class Manifest:
    """In-memory manifest; :meth:`save` writes it atomically."""

    path: Path
    bags: dict[str, dict] = field(default_factory=dict)
    units: dict[str, dict] = field(default_factory=dict)

    @classmethod
    def load(cls, out_dir: Path) -> Manifest:
        """The manifest in ``out_dir``, or an empty one."""
        path = out_dir / MANIFEST_FILE
        if not path.exists():
            return cls(path)
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            if data.get("format") != FORMAT:
                raise ValueError(f"format {data.get('format')!r}, expected {FORMAT}")
            return cls(path, dict(data["bags"]), dict(data["units"]))
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise InputError(f"{path}: unreadable fleet manifest ({exc}); remove it to start afresh") from exc

    def save(self) -> None:
        """Write atomically."""
        write_json(self.path, {"format": FORMAT, "bags": self.bags, "units": self.units})

    def known_hash(self, bag: BagFile) -> str | None:
        """The stored SHA-256 of ``bag`` if its fingerprint is unchanged, else None."""
        entry = self.bags.get(bag.relpath)
        if entry and entry["size"] == bag.size and entry["mtime_ns"] == bag.mtime_ns:
            return entry["sha256"]
        return None

    def remember(self, bag: BagFile, sha256: str) -> None:
        """Store ``bag``'s fingerprint and hash."""
        self.bags[bag.relpath] = {"size": bag.size, "mtime_ns": bag.mtime_ns, "sha256": sha256}

    def is_done(self, unit: str, hashes: list[str], params_digest: str, out_dir: Path) -> bool:
        """True if ``unit`` already ran on exactly these bags and parameters and its result file exists."""
        entry = self.units.get(unit)
        return bool(entry and entry["hashes"] == hashes and entry["params_digest"] == params_digest
                    and (out_dir / entry["file"]).exists())
