"""Crash-safe persistence of :class:`MonitorState`: atomic save, careful load.

Save (``save_state``), so that a kill at any instant leaves a loadable file:

1. write the JSON (with a SHA-256 of its payload) to ``<name>.tmp-<pid>`` in the same directory,
   flush and ``fsync`` it;
2. keep the current file as the backup ``<name>.bak`` (hard link, or a synced copy where the file
   system has none; atomic ``rename`` over the old backup), so the previous checkpoint survives
   whatever happens next;
3. ``rename`` the temp file over ``<name>`` (atomic on POSIX) and ``fsync`` the directory so the
   rename itself is durable.

Load (``load_state``): the main file, else the backup. A file that cannot be parsed, fails its
checksum or its validation is reported, renamed aside to ``<name>.corrupt-<UTC time>`` (kept for
inspection, never silently deleted) and the next candidate is tried; leftover temp files of an
interrupted save are removed and reported. Returns ``(state or None, problems)``.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import time
from pathlib import Path
from typing import Any

from ebm_wear_monitor.monitor.state import MonitorState, StateError

FORMAT = "ebm_wear_monitor.monitor_state"


def _payload_digest(state: dict[str, Any]) -> str:
    text = json.dumps(state, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()


def _fsync_dir(directory: Path) -> None:
    fd = os.open(directory, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def backup_path(path: str | Path) -> Path:
    path = Path(path)
    return path.with_name(path.name + ".bak")


def save_state(path: str | Path, state: MonitorState) -> None:
    """Atomically write ``state`` to ``path`` (see module doc); the previous file becomes ``.bak``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    body = state.to_dict()
    doc = {"format": FORMAT, "sha256": _payload_digest(body), "state": body}
    text = json.dumps(doc, indent=1, sort_keys=True, allow_nan=False)
    tmp = path.with_name(f"{path.name}.tmp-{os.getpid()}")
    with open(tmp, "w", encoding="utf-8") as fh:
        fh.write(text)
        fh.flush()
        os.fsync(fh.fileno())
    if path.exists():
        bak, bak_tmp = backup_path(path), path.with_name(f"{path.name}.bak-tmp-{os.getpid()}")
        bak_tmp.unlink(missing_ok=True)
        try:
            os.link(path, bak_tmp)
        except OSError:  # file systems without hard links (FAT): copy, durably
            shutil.copyfile(path, bak_tmp)
            with open(bak_tmp, "rb") as fh:
                os.fsync(fh.fileno())
        os.replace(bak_tmp, bak)
    os.replace(tmp, path)
    _fsync_dir(path.parent)


def _read(path: Path) -> MonitorState:
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except UnicodeDecodeError as exc:
        raise StateError(f"not text ({exc.reason})") from None
    except json.JSONDecodeError as exc:
        raise StateError(f"not valid JSON ({exc.msg} at line {exc.lineno})") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT or "state" not in doc:
        raise StateError("not a monitor state file")
    if doc.get("sha256") != _payload_digest(doc["state"]):
        raise StateError("checksum mismatch")
    try:
        return MonitorState.from_dict(doc["state"])
    except TypeError as exc:
        raise StateError(str(exc)) from None


def load_state(path: str | Path) -> tuple[MonitorState | None, list[str]]:
    """Last good state at ``path`` (or its backup) and a list of one-line problems met on the way."""
    path = Path(path)
    problems: list[str] = []
    for leftover in sorted(path.parent.glob(f"{path.name}.*tmp-*")) if path.parent.is_dir() else []:
        leftover.unlink(missing_ok=True)
        problems.append(f"{leftover}: removed unfinished temp file of an interrupted save")
    for candidate in (path, backup_path(path)):
        if not candidate.exists():
            if candidate == path:
                problems.append(f"{path}: no state file")
            continue
        try:
            state = _read(candidate)
        except (OSError, StateError) as exc:
            stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
            aside = candidate.with_name(f"{candidate.name}.corrupt-{stamp}")
            problems.append(f"{candidate}: corrupt state ({exc}); kept aside as {aside.name}")
            try:
                os.replace(candidate, aside)
            except OSError as err:
                problems.append(f"{candidate}: could not move aside ({err.strerror})")
            continue
        if candidate != path:
            problems.append(f"{path}: resumed from backup {candidate.name}")
        return state, problems
    return None, problems
