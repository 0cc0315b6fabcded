"""What each install of ebm_wear_monitor needs from PyPI: one list, read by setup.py, the tools and the tests.

* ``pip install .``: the onboard node (``ebm-wear-monitor``, the monitor core, ``ebm-wear calc``,
  the listener) with :data:`ONBOARD` only: numpy, scipy, PyYAML, filterpy (which pulls
  matplotlib), threadpoolctl.
* ``pip install '.[tools]'``: adds :data:`TOOLS`, what ``ebm-wear replay|fleet|diagnose|simulate``,
  the reports, the bag player and the foreign-world generator import.
* ``pip install '.[test]'``: the tools plus :data:`TEST`, what the test suite imports or runs.

ROS 2 itself (rclpy, the message packages and ``ebm_wear_msgs`` built from ``msg_defs/``) is never
pip metadata: it comes from a ROS 2 installation or the PyPI wheels of
``requirements/ros-kilted.txt`` and is declared in ``package.xml`` (with the rosdep keys of the
distributions below). ``test/test_dependencies.py`` checks these lists, setup.py, package.xml and
requirements/python.txt against the imports of the code.

setup.py executes this file before the package is installed, so it imports the standard library only.
"""

from __future__ import annotations

import importlib.util
import sys
from typing import NamedTuple


class Requirement(NamedTuple):
    """One distribution: its PEP 508 name and version floor and the top-level modules it provides."""

    name: str  #: distribution name with extras, e.g. ``dask[distributed]``
    floor: str  #: version specifier, e.g. ``>=2024.1``
    modules: tuple[str, ...]  #: import names it provides (checked at start by :func:`missing`)
    python_below: tuple[int, int] | None = None  #: needed only on Python versions below this one

    @property
    def spec(self) -> str:
        """The requirement as setup.py's ``install_requires`` / ``extras_require`` take it."""
        if self.python_below is None:
            return f"{self.name}{self.floor}"
        major, minor = self.python_below
        return f'{self.name}{self.floor}; python_version < "{major}.{minor}"'

    @property
    def needed(self) -> bool:
        """Whether this interpreter needs it (False for a backport the standard library replaces)."""
        return self.python_below is None or sys.version_info[:2] < self.python_below


#: the onboard node and the core: ``install_requires``
ONBOARD: tuple[Requirement, ...] = (
    Requirement("numpy", ">=1.26", ("numpy",)),
    Requirement("scipy", ">=1.11", ("scipy",)),
    Requirement("pyyaml", ">=6.0", ("yaml",)),
    # the monitor's bank of Kalman filters (monitor/kalman.py); filterpy 2.0.0 declares matplotlib as an
    # install requirement, so pip brings matplotlib too (no module of this package imports it)
    Requirement("filterpy", ">=2.0.0", ("filterpy",)),
    # the bank filters with BLAS on one thread (kalman.one_blas_thread): its stacked products are
    # small, and threads waiting for a busy core made them a hundred times slower
    Requirement("threadpoolctl", ">=3.1", ("threadpoolctl",)),
)

#: replay, fleet, diagnose, simulate, reports, player, foreign-world generator: the ``tools`` extra
TOOLS: tuple[Requirement, ...] = (
    Requirement("rosbags", ">=0.11.9", ("rosbags",)),
    Requirement("lz4", ">=4.0", ("lz4",)),  # mcap chunks (bagio.storage)
    Requirement("backports.zstd", ">=1.0", ("backports.zstd",), python_below=(3, 14)),  # mcap chunks
    Requirement("dask[distributed]", ">=2024.1", ("dask", "distributed")),
    Requirement("pandas", ">=2.1", ("pandas",)),
    Requirement("pyarrow", ">=14", ("pyarrow",)),  # pandas' Parquet engine (fleet tables)
    Requirement("tqdm", ">=4.66", ("tqdm",)),
    Requirement("Jinja2", ">=3.1", ("jinja2",)),
    Requirement("plotly", ">=5.20", ("plotly",)),
)

#: what the tests import or run besides the tools: the ``test`` extra (which includes the tools)
TEST: tuple[Requirement, ...] = (
    Requirement("pytest", ">=8", ("pytest",)),
    Requirement("pytest-timeout", ">=2.3", ("pytest_timeout",)),  # pytest.ini: timeout
    Requirement("hypothesis", ">=6.100", ("hypothesis",)),
    Requirement("mcap", ">=1.2", ("mcap",)),  # an independent MCAP writer for the reader tests
    Requirement("jsonschema", ">=4.20", ("jsonschema",)),  # the JSON Schema files against real outputs
    Requirement("playwright", ">=1.40", ("playwright",)),  # the reports' browser test
    Requirement("ruff", ">=0.6", ("ruff",)),  # test_package_layout runs it
    Requirement("mypy", ">=1.18", ("mypy",)),  # test_types runs it, with these stubs (no import names)
    Requirement("types-PyYAML", ">=6.0", ()),
    Requirement("types-tqdm", ">=4.66", ()),
    Requirement("scipy-stubs", ">=1.15", ()),
    Requirement("pandas-stubs", ">=2.2", ()),
)

EXTRAS: dict[str, tuple[Requirement, ...]] = {"tools": TOOLS, "test": TOOLS + TEST}


class MissingExtraError(Exception):
    """A command needs an extra that is not installed; the message is one line for people."""


def missing(extra: str) -> list[str]:
    """Distributions of ``extra`` whose modules cannot be found (imports nothing)."""
    gone = []
    for req in EXTRAS[extra]:
        for module in req.modules if req.needed else ():
            try:
                found = importlib.util.find_spec(module) is not None
            except ModuleNotFoundError:  # the parent of a dotted name (``backports``) is missing
                found = False
            if not found:
                gone.append(req.name)
                break
    return gone


def require(extra: str) -> None:
    """Raise :class:`MissingExtraError` naming the extra and the missing distributions, if any."""
    gone = missing(extra)
    if gone:
        raise MissingExtraError(missing_message(extra, gone))


def provider(module: str | None) -> tuple[str, str] | None:
    """(extra, distribution) providing a (possibly dotted) module name; None for onboard or unknown ones."""
    for extra in ("tools", "test"):
        for req in EXTRAS[extra]:
            if any(module == m or (module or "").startswith(m + ".") for m in req.modules):
                return extra, req.name
    return None


def missing_message(extra: str, gone: list[str]) -> str:
    """``needs the 'tools' extra (not installed: rosbags, pandas): pip install 'ebm_wear_monitor[tools]'``."""
    return (f"needs the '{extra}' extra (not installed: {', '.join(gone)}): "
            f"pip install 'ebm_wear_monitor[{extra}]'")
