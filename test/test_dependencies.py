"""Declared dependencies = used dependencies (issue 14 deliverable 4): the minimal onboard install.

``ebm_wear_monitor/extras.py`` is the one list (setup.py's install_requires and extras come from it);
these tests hold it, the installed metadata, ``package.xml`` and ``requirements/`` against the code:

* the imports of every module (parsed with ast, function-level imports and code in string constants
  included) name only declared distributions, and every declared one is imported (pyarrow, pandas'
  Parquet engine, excepted by name);
* what the onboard node loads on import (module-level imports from its entry points, followed
  through the package) is ONBOARD + ROS 2 only, and each ONBOARD distribution is used there;
* with every module of the ``tools`` and ``test`` extras made unimportable, the onboard entry points
  run (``ebm-wear-monitor --help``, ``ebm-wear --help``, the three calculators, the listener) and
  every tool ends with one line naming the extra, exit 2;
* a real onboard venv: test/ros/test_ros_onboard_install.py.
"""

from __future__ import annotations

import ast
import contextlib
import json
import os
import re
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET
from importlib import metadata
from pathlib import Path

import pytest

from ebm_wear_monitor import extras

REPO = Path(__file__).resolve().parents[1]
PACKAGE = REPO / "ebm_wear_monitor"

#: entry points that run on the onboard install (console scripts and ``python -m`` modules)
ONBOARD_ROOTS = ("ebm_wear_monitor.ros.node", "ebm_wear_monitor.ros.listener", "ebm_wear_monitor.cli.main",
                 "ebm_wear_monitor.cli.calc")
#: declared although never imported by name, with the reason
INDIRECT = {"pyarrow": "pandas' Parquet engine (fleet tables)"}
#: rosdep keys (ros/rosdistro rosdep/python.yaml); None: the distribution has none (pip only)
ROSDEP = {
    "numpy": "python3-numpy", "scipy": "python3-scipy", "pyyaml": "python3-yaml",
    "rosbags": "python3-rosbags-pip", "pandas": "python3-pandas",
    "tqdm": "python3-tqdm", "Jinja2": "python3-jinja2", "lz4": None, "backports.zstd": None,
    "dask[distributed]": None, "pyarrow": None, "plotly": None, "threadpoolctl": None,
    "pytest": "python3-pytest", "pytest-timeout": "python3-pytest-timeout",
    "hypothesis": "python3-hypothesis", "filterpy": "python3-filterpy-pip", "ruff": "python3-ruff-pip",
    "mcap": None, "playwright": None, "mypy": "python3-mypy", "jsonschema": "python3-jsonschema",
    "types-PyYAML": None, "types-tqdm": None, "scipy-stubs": None, "pandas-stubs": None,
}


def _imports_of(tree: ast.AST) -> set[str]:
    """Absolute imported module names in a syntax tree, and in string constants that parse as code."""
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names |= {node.module} | {f"{node.module}.{a.name}" for a in node.names}
        elif isinstance(node, ast.Constant | ast.JoinedStr):  # a script run in a child process
            text = node.value if isinstance(node, ast.Constant) else "".join(
                v.value if isinstance(v, ast.Constant) else "_" for v in node.values)
            if isinstance(text, str) and "import " in text:
                with contextlib.suppress(SyntaxError):
                    names |= _imports_of(ast.parse(textwrap.dedent(text)))
    return names


def _imports_under(folder: Path) -> set[str]:
    return set().union(*(_imports_of(ast.parse(p.read_text())) for p in folder.rglob("*.py")))


def _module_name(path: Path) -> str:
    parts = path.relative_to(REPO).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _module_level_imports(path: Path) -> set[str]:
    """Modules a module loads when imported: its top-level statements (not function bodies), made absolute."""
    name = _module_name(path)
    package = (name if path.name == "__init__.py" else name.rsplit(".", 1)[0]).split(".")
    out: set[str] = set()
    body = list(ast.parse(path.read_text()).body)
    while body:
        node = body.pop()
        if isinstance(node, ast.If | ast.Try):  # guarded imports still run at import time
            body += node.body + node.orelse + getattr(node, "finalbody", [])
            body += [s for h in getattr(node, "handlers", []) for s in h.body]
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package[:len(package) - node.level + 1] + ([base] if base else []))
            out.add(base)
            out |= {f"{base}.{a.name}" for a in node.names}  # `from pkg import module`
    return out


def _third_party(names: set[str]) -> set[str]:
    """Top-level names outside the standard library and this package (ROS 2 packages included)."""
    tops = {n.split(".")[0] for n in names}
    # _typeshed: the standard library's type-checking-only stubs (imported under TYPE_CHECKING)
    return tops - set(sys.stdlib_module_names) - {"ebm_wear_monitor", "__future__", "_typeshed"}


def _ros_packages() -> set[str]:
    """Packages in the ament index of this venv (and of a sourced ROS 2): rclpy, the message packages, ..."""
    prefixes = [Path(sys.prefix), *(Path(p) for p in os.environ.get("AMENT_PREFIX_PATH", "").split(":") if p)]
    return {f.name for pre in prefixes for f in (pre / "share/ament_index/resource_index/packages").glob("*")}


def _import_names(names: set[str]) -> set[str]:
    """Top-level import names, ``backports.zstd`` kept whole (``backports`` is a namespace package)."""
    tops = {n.split(".")[0] for n in names} - {"backports"}
    return tops | {"backports.zstd" for n in names if n.startswith("backports.zstd")}


def _declared(reqs: tuple[extras.Requirement, ...]) -> set[str]:
    return {m for r in reqs for m in r.modules}


def _normalise(name: str) -> str:
    return re.sub(r"[-_.]+", "-", re.sub(r"\[.*\]", "", name)).lower()


def test_every_imported_distribution_is_declared_and_every_declared_one_imported() -> None:
    used = _import_names(_imports_under(PACKAGE))
    used = {n for n in used if n == "backports.zstd" or _third_party({n})} - _ros_packages()
    used -= {"compression"}  # compression.zstd: the standard library's from Python 3.14 (bagio.storage)
    declared = _declared(extras.ONBOARD + extras.TOOLS)
    assert sorted(used - declared) == [], "imported, but in no list of ebm_wear_monitor/extras.py"
    assert sorted(declared - used - set(INDIRECT)) == [], "declared in extras.py, never imported"


def test_the_onboard_node_loads_only_onboard_and_ros_packages() -> None:
    sources = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    seen: set[str] = set()
    third: set[str] = set()
    todo = list(ONBOARD_ROOTS)
    while todo:
        name = todo.pop()
        if name in seen or name not in sources:
            continue
        seen.add(name)
        names = _module_level_imports(sources[name])
        third |= _third_party(names)
        parents = {".".join(n.split(".")[:k]) for n in names for k in range(1, n.count(".") + 2)}
        todo += sorted(n for n in parents if n.startswith("ebm_wear_monitor"))
    assert {f"ebm_wear_monitor.{m}" for m in ("ros.node", "monitor.core", "params.unit")} <= seen
    ros = _ros_packages()
    onboard = _declared(extras.ONBOARD)
    assert sorted(third - ros - onboard) == [], "the node's imports need more than the onboard install"
    # filterpy is imported on the first filter step (kalman.load_filterpy; the node calls it at start)
    lazy = _third_party(_imports_of(ast.parse((PACKAGE / "monitor" / "kalman.py").read_text())))
    assert sorted(onboard - third - lazy) == [], "declared ONBOARD, but not loaded by the node"
    assert {"rclpy", "ebm_wear_msgs", "diagnostic_msgs"} <= third & ros


def test_installed_metadata_is_extras_py() -> None:
    """setup.py turns extras.py into the installed metadata (install.sh reinstalls when extras.py changes)."""
    requires = metadata.requires("ebm_wear_monitor") or []
    onboard = [r for r in requires if "extra ==" not in r]
    assert sorted(map(_normalise, onboard)) == sorted(_normalise(r.spec) for r in extras.ONBOARD)
    for extra, reqs in extras.EXTRAS.items():
        got = [r.split(";")[0] for r in requires if f'extra == "{extra}"' in r]
        assert sorted(map(_normalise, got)) == sorted(_normalise(r.name + r.floor) for r in reqs), extra
    assert (PACKAGE / "py.typed").is_file()


def test_requirements_install_every_declared_distribution_pinned() -> None:
    """install.sh (development and CI) installs everything: requirements/*.txt name every distribution."""
    def names(path: Path) -> set[str]:
        lines = (line.split("#")[0].split(";")[0].strip() for line in path.read_text().splitlines())
        return {_normalise(re.split(r"[<>=!~ ]", s)[0]) for s in lines if s and not s.startswith("-")}

    listed = names(REPO / "requirements/python.txt") | names(REPO / "requirements/build.txt")
    lock = (REPO / "requirements/lock.txt").read_text().splitlines()
    pinned = {_normalise(line.split("==")[0]) for line in lock if "==" in line}
    declared = {_normalise(r.name) for r in extras.ONBOARD + extras.TOOLS + extras.TEST}
    assert sorted(declared - listed) == []
    assert sorted(declared - pinned) == []


def test_package_xml_lists_exactly_the_run_and_test_dependencies() -> None:
    parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True))
    root = ET.parse(REPO / "package.xml", parser).getroot()
    ros = _ros_packages()
    run_ros = _third_party(_imports_under(PACKAGE)) & ros
    test_ros = (_third_party(_imports_under(REPO / "test")) & ros) - run_ros
    run_keys = {ROSDEP[r.name] for r in extras.ONBOARD + extras.TOOLS} - {None}
    test_keys = {ROSDEP[r.name] for r in extras.TEST} - {None}
    assert {d.text for d in root.findall("exec_depend")} == run_ros | run_keys
    assert {d.text for d in root.findall("test_depend")} == test_ros | test_keys
    assert root.findall("depend") == [] and root.findall("build_depend") == []
    comments = " ".join(c.text or "" for c in root.iter(ET.Comment))
    for r in extras.ONBOARD + extras.TOOLS + extras.TEST:
        assert ROSDEP[r.name] is not None or r.name in comments, f"{r.name}: no rosdep key and not named"


#: a script that hides every module of the tools and test extras from the import system (as if not
#: installed: find_spec answers None, import raises ModuleNotFoundError), then runs a module as __main__
BLOCK = r"""
import sys
BLOCKED = {blocked!r}
class _Hide:
    def __init__(self, finder):
        self.finder = finder
    def __getattr__(self, name):
        return getattr(self.finder, name)
    def find_spec(self, name, path=None, target=None):
        if any(name == b or name.startswith(b + ".") for b in BLOCKED):
            return None
        return self.finder.find_spec(name, path, target)
sys.meta_path[:] = [_Hide(f) for f in sys.meta_path]
import runpy
sys.argv = {argv!r}
runpy.run_module({module!r}, run_name="__main__", alter_sys=True)
"""


def _run_without_tools(module: str, *args: str) -> subprocess.CompletedProcess[str]:
    blocked = sorted(_declared(extras.TOOLS + extras.TEST))
    code = BLOCK.format(blocked=blocked, argv=[module, *args], module=module)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=REPO,
                          check=False)


@pytest.mark.parametrize("argv", [
    ["ebm_wear_monitor.ros.node", "--help"],
    ["ebm_wear_monitor.ros.listener", "--help"],
    ["ebm_wear_monitor.cli.main", "--help"],
    ["ebm_wear_monitor.cli.main", "replay", "--help"],
    ["ebm_wear_monitor.cli.main", "calc", "contact", "--params", "embu_000", "--axial-force", "20000"],
    ["ebm_wear_monitor.cli.main", "calc", "wear", "--params", "embu_000", "--axial-force", "20000",
     "--speed", "20", "--json", "-"],
    ["ebm_wear_monitor.cli.main", "calc", "actuator", "--params", "embu_000", "--clamp-force", "30000"],
])
def test_onboard_entry_points_run_without_the_tools(argv) -> None:
    run = _run_without_tools(*argv)
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.strip()
    if "--json" in argv:
        assert json.loads(run.stdout)["clearance_growth_rate_m_s"] > 0  # the calculator's real output


@pytest.mark.parametrize("argv", [
    ["ebm_wear_monitor.cli.main", "replay", "bags/healthy"],
    ["ebm_wear_monitor.cli.main", "fleet", "bags", "--out", "/nonexistent/out"],
    ["ebm_wear_monitor.cli.main", "diagnose", "bags/healthy", "--params", "embu_000"],
    ["ebm_wear_monitor.cli.main", "simulate", "--cycles", "2", "--out", "/nonexistent/x"],
    ["ebm_wear_monitor.ros.player", "bags/healthy"],
    ["ebm_wear_monitor.validation.foreign", "write", "--set", "quick", "--out", "/nonexistent/ff"],
])
def test_every_tool_says_in_one_line_that_it_needs_the_tools_extra(argv) -> None:
    run = _run_without_tools(*argv)
    assert run.returncode == 2, run.stderr[-2000:]
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in run.stderr, run.stderr[-2000:]
    assert "needs the 'tools' extra" in lines[0] and "pip install 'ebm_wear_monitor[tools]'" in lines[0]
    assert run.stdout == ""
    # checked up front, before any work: every missing distribution named (the generator needs rosbags only)
    named = lines[0].split("not installed: ")[1].split(")")[0].split(", ")
    assert named == (["rosbags"] if "foreign" in argv[0] else [r.name for r in extras.TOOLS if r.needed])
