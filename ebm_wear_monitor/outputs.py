"""Writing results so that nothing is ever half-written: temporary sibling, then an atomic rename.

Shared by every command that writes files (JSON, Parquet, reports, unit files). The policy
(issue 13): a destination is checked before any work (:func:`check_destination`: its parent
directory must exist and be writable; only the last component is ever created); files are
created with the user's umask (``0666 & ~umask``, 0644 typically), like any other program's
output; ``--json -`` writes the JSON to standard output (:func:`write_json` with
:data:`STDOUT`), and then every line meant for people goes to standard error
(:func:`human_output_to_stderr`). A destination that cannot be written is an
:class:`~ebm_wear_monitor.errors.InputError` with a one-line reason, so the CLI exits with status 2.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import sys
import tempfile
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any, TextIO, overload

import numpy as np

from ebm_wear_monitor.errors import InputError

#: the ``--json`` value that means standard output
STDOUT = "-"
#: where :func:`write_json` sends ``-`` while :func:`human_output_to_stderr` is active
_data_stream: list[TextIO] = []


def _unwritable(path: Path, exc: OSError) -> InputError:
    return InputError(f"{path}: cannot write there ({exc.strerror or exc})")


def umask() -> int:
    """The process's file-mode creation mask (read from /proc where possible: no set-and-restore race)."""
    with contextlib.suppress(OSError, ValueError):
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def use_umask(path: str | os.PathLike, mode: int = 0o666) -> None:
    """Give ``path`` the permissions a plain ``open()``/``mkdir()`` would: ``mode & ~umask``.

    ``tempfile.mkstemp``/``mkdtemp`` create 0600/0700 entries; renamed into place they would keep
    that mode, unlike every other program's output.
    """
    os.chmod(path, mode & ~umask())


def _probe(directory: Path, option: str, path: Path) -> None:
    """InputError unless a file can be created in the existing ``directory`` now."""
    try:
        fd, name = tempfile.mkstemp(prefix=".write-test-", dir=directory)
    except OSError as exc:
        raise InputError(f"{option} {path}: cannot write in {directory} ({exc.strerror or exc})") from None
    os.close(fd)
    os.unlink(name)


def check_destination(path: str | os.PathLike | None, option: str, *, directory: bool = False) -> None:
    """Before any work is done: InputError (one line) unless ``path`` can become a file (with
    ``directory``: a directory, created if missing) right now.

    Refused: ``path`` exists as the other kind; its parent directory does not exist (parents are
    never created: a typo must not leave a directory tree behind); the parent, or an existing
    destination directory, is not writable. ``-`` (standard output) is always fine for a file.
    """
    if path is None or (not directory and str(path) == STDOUT):
        return
    path = Path(path)
    wanted, other = ("directory", "file") if directory else ("file path", "directory")
    try:
        exists, is_dir = path.exists(), path.is_dir()
        parent_is_dir = path.parent.is_dir()
        parent_exists = path.parent.exists()
    except OSError as exc:  # an ancestor is unreadable
        raise InputError(f"{option} {path}: cannot reach it ({exc.strerror or exc})") from None
    if exists and is_dir != directory:
        raise InputError(f"{option} {path}: is a {other}, expected a {wanted}")
    if not parent_is_dir:
        what = "is a file, not a directory" if parent_exists else "does not exist"
        raise InputError(f"{option} {path}: {path.parent} {what}")
    _probe(path if exists and directory else path.parent, option, path)


def human_output_to_stderr(json_path: str | os.PathLike | None) -> contextlib.AbstractContextManager:
    """With ``--json -``: send ``print()`` output to stderr so that stdout carries only the JSON."""
    if json_path is None or str(json_path) != STDOUT:
        return contextlib.nullcontext()
    return _redirected()


@contextlib.contextmanager
def _redirected() -> Iterator[None]:
    _data_stream.append(sys.stdout)
    try:
        with contextlib.redirect_stdout(sys.stderr):
            yield
    finally:
        _data_stream.pop()


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
        use_umask(tmp)
        tmp.replace(path)
    except OSError as exc:
        raise _unwritable(path, exc) from exc
    finally:
        tmp.unlink(missing_ok=True)
    return path


@overload
def jsonable(value: Mapping[Any, Any]) -> dict[str, Any]: ...
@overload
def jsonable(value: list[Any] | tuple[Any, ...] | np.ndarray) -> list[Any]: ...
@overload
def jsonable(value: object) -> object: ...
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


def write_json(path: str | os.PathLike, data: object) -> Path | None:
    """Write ``data`` as indented JSON (numpy-aware, NaN -> null), atomically; ``-``: to standard output."""
    text = json.dumps(jsonable(data), indent=2, allow_nan=False) + "\n"
    if str(path) == STDOUT:
        stream = _data_stream[-1] if _data_stream else sys.stdout
        stream.write(text)
        stream.flush()
        return None
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
