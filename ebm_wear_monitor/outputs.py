"""Writing results so that nothing is ever half-written: temporary sibling, then an atomic rename.

Shared by every command that writes files (JSON, Parquet, reports, unit files). A destination
that cannot be written (its parent is a file, no permission, the path is a directory) is an
:class:`~ebm_wear_monitor.errors.InputError` with a one-line reason, so the CLI exits with status 2.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from ebm_wear_monitor.errors import InputError


def _unwritable(path: Path, exc: OSError) -> InputError:
    return InputError(f"{path}: cannot write there ({exc.strerror or exc})")


def check_destination(path: str | os.PathLike | None, option: str, *, directory: bool = False) -> None:
    """Before any work is done: InputError (one line) if ``path`` cannot become a file (with
    ``directory``: a directory), because it exists as the other kind or an ancestor is a file."""
    if path is None:
        return
    path = Path(path)
    wanted, other = ("directory", "file") if directory else ("file path", "directory")
    if path.exists() and path.is_dir() != directory:
        raise InputError(f"{option} {path}: is a {other}, expected a {wanted}")
    ancestor = next((p for p in path.parents if p.exists()), None)
    if ancestor is not None and not ancestor.is_dir():
        raise InputError(f"{option} {path}: {ancestor} is a file, not a directory")


def atomic_write(path: str | os.PathLike, write: Callable[[Path], object]) -> Path:
    """Call ``write(tmp)`` on a temporary file next to ``path``, then rename it onto ``path``."""
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a directory, expected a file name")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    except OSError as exc:
        raise _unwritable(path, exc) from exc
    os.close(fd)
    tmp = Path(name)
    try:
        write(tmp)
        tmp.replace(path)
    except OSError as exc:
        raise _unwritable(path, exc) from exc
    finally:
        tmp.unlink(missing_ok=True)
    return path


def jsonable(value: object) -> object:
    """``value`` with numpy scalars/arrays as Python numbers/lists and NaN/inf as null (JSON has no NaN)."""
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [jsonable(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return float(value) if np.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def write_json(path: str | os.PathLike, data: object) -> Path:
    """Write ``data`` as indented JSON (numpy-aware, NaN -> null), atomically."""
    text = json.dumps(jsonable(data), indent=2, allow_nan=False) + "\n"
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


def publish_directory(build: Callable[[Path], object], target: str | os.PathLike) -> Path:
    """Build files with ``build(tmpdir)`` in a temporary sibling directory, then move them into ``target``.

    Every file is moved with an atomic rename, ``index.html`` (the entry point) last,
    so a reader never sees a half-written file and the page never links missing images.
    """
    target = Path(target)
    try:
        target.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    except OSError as exc:
        raise _unwritable(target, exc) from exc
    try:
        build(tmp)
        for src in sorted(tmp.iterdir(), key=lambda p: p.name == "index.html"):
            src.replace(target / src.name)
    except OSError as exc:
        raise _unwritable(target, exc) from exc
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return target
