"""Every reference to a repository file or module in docstrings, comments and the README resolves.

Issue 14 item 3.

Scanned: the docstrings and ``#`` comments of every tracked Python file, the ``#`` comments of the
other tracked text files (YAML, shell, requirements, CMake, ini/cfg/toml), the ``.msg`` files and
README.md. Two kinds of reference are checked:

* a file name or path with a source extension (``.py .md .msg .sh .txt .ini .cfg .toml .xml .css``),
  or any path whose first component is a directory of the repository (``config/wear_monitor.yaml``,
  ``bags/accelerated_unit.yaml``): some tracked file must be that path or end with ``/`` + it. Names of
  files the tools *write* (``units.parquet``, ``report/index.html``, ``metadata.yaml``) are not
  repository paths and are not checked;
* a dotted name (the package, then modules, then a name) or a relative role target (:mod:`.x`,
  :func:`.x.f`): its longest module prefix must be a module or package of the tree and the
  next name must be defined at its top level (a def, class, assignment or import), a method or
  attribute after a class in that class's body.

The one document outside the repository that the code cites is the external contract,
``interface.md`` (``../shared/spec/interface.md``, README.md says so); it is named in EXTERNAL.
"""

from __future__ import annotations

import ast
import io
import re
import subprocess
import tokenize
from functools import cache
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PACKAGE = "ebm_wear_monitor"
EXTERNAL = {"interface.md": "the external contract, ../shared/spec/interface.md (README.md)"}
SOURCE_EXT = ("py", "md", "msg", "sh", "txt", "ini", "cfg", "toml", "xml", "css")
PATH = re.compile(r"(?<![\w./:-])((?:\.\.?/)*[\w.-]+(?:/[\w.-]+)*\.(\w+))(?![\w/-])")
DOTTED = re.compile(rf"(?<![\w.]){PACKAGE}(?:\.\w+)+")
ROLE = re.compile(r":(?:mod|func|class|meth|data|attr|exc|obj):`~?(\.[\w.]+)`")
COMMENTED = (".yaml", ".yml", ".sh", ".txt", ".ini", ".cfg", ".toml", "CMakeLists.txt")


@cache
def tracked() -> tuple[str, ...]:
    out = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard"], cwd=REPO,
                         capture_output=True, text=True, check=True).stdout
    return tuple(p for p in out.split() if (REPO / p).exists())


def _texts(path: str) -> list[str]:
    """The docstrings and comments of ``path`` (README.md and .msg files: all of it)."""
    text = (REPO / path).read_text(encoding="utf-8", errors="replace")
    if path.endswith((".md", ".msg")):
        return [text]
    if path.endswith(".py"):
        chunks = [t.string for t in tokenize.generate_tokens(io.StringIO(text).readline)
                  if t.type == tokenize.COMMENT]
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
                doc = ast.get_docstring(node, clean=False)
                if doc:
                    chunks.append(doc)
        return chunks
    return [line for line in text.splitlines() if line.lstrip().startswith("#")]


def _scanned() -> list[str]:
    return [p for p in tracked() if p == "README.md" or p.endswith((".py", ".msg")) or p.endswith(COMMENTED)]


def _file_resolves(token: str) -> bool:
    name = re.sub(r"^(\.\.?/)+", "", token)
    return any(p == name or p.endswith("/" + name) or p.startswith(name + "/") for p in tracked())


def _is_repository_path(token: str, ext: str) -> bool:
    if ext in SOURCE_EXT:
        return True
    first = re.sub(r"^(\.\.?/)+", "", token).split("/", 1)
    return len(first) == 2 and any(p.startswith(first[0] + "/") or f"/{first[0]}/" in p for p in tracked())


@cache
def _top_names(module_file: str) -> dict[str, set[str]]:
    """Top-level names of a module -> the names defined in a class body (empty set otherwise)."""
    tree = ast.parse((REPO / module_file).read_text(encoding="utf-8"))
    names: dict[str, set[str]] = {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            names[node.name] = set()
        elif isinstance(node, ast.ClassDef):
            members = {n.name for n in node.body if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef,
                                                                   ast.ClassDef))}
            members |= {t.id for n in node.body if isinstance(n, ast.AnnAssign) and isinstance(t := n.target,
                                                                                              ast.Name)}
            members |= {t.id for n in node.body if isinstance(n, ast.Assign) for t in n.targets
                        if isinstance(t, ast.Name)}
            names[node.name] = members
        elif isinstance(node, ast.Assign):
            names |= {t.id: set() for t in node.targets if isinstance(t, ast.Name)}
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names[node.target.id] = set()
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names |= {(a.asname or a.name).split(".")[0]: set() for a in node.names}
        elif isinstance(node, ast.If | ast.Try):  # TYPE_CHECKING blocks, optional imports
            for sub in ast.walk(node):
                if isinstance(sub, (ast.Import, ast.ImportFrom)):
                    names |= {(a.asname or a.name).split(".")[0]: set() for a in sub.names}
    return names


def _module_file(parts: list[str]) -> str | None:
    base = "/".join(parts)
    for candidate in (f"{base}.py", f"{base}/__init__.py"):
        if candidate in tracked():
            return candidate
    return None


def _dotted_resolves(dotted: str) -> bool:
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        module = _module_file(parts[:cut])
        if module is None:
            continue
        rest = parts[cut:]
        if not rest:
            return True
        names = _top_names(module)
        if rest[0] not in names:
            return False
        return len(rest) == 1 or rest[1] in names[rest[0]] or not names[rest[0]]
    return False


def _relative(path: str, target: str) -> str:
    """``.x.f`` written in ``path`` -> the absolute dotted name, relative to the module's package as in a
    relative import: each further leading dot goes one package up (``..x.f``)."""
    name = target.lstrip(".")
    up = len(target) - len(name) - 1
    package = Path(path).with_suffix("").parts[:-1]
    return ".".join((*package[:len(package) - up], name))


def test_every_file_and_module_reference_resolves() -> None:
    broken = []
    for path in _scanned():
        for text in _texts(path):
            for match in PATH.finditer(text):
                token, ext = match.group(1), match.group(2)
                if token.split("/")[-1] in EXTERNAL or not _is_repository_path(token, ext):
                    continue
                if not _file_resolves(token):
                    broken.append(f"{path}: {token}")
            dotted = DOTTED.findall(text)
            if path.endswith(".py") and path.startswith(PACKAGE + "/"):
                dotted += [_relative(path, m) for m in ROLE.findall(text)]
            broken += [f"{path}: {name}" for name in dotted if not _dotted_resolves(name.rstrip("."))]
    assert not broken, "references that do not resolve in the repository:\n" + "\n".join(sorted(set(broken)))


def test_the_checker_catches_what_it_should() -> None:
    """The resolution rules themselves, on known good and bad references."""
    assert _file_resolves("bags/healthy")  # a bag is a directory
    assert _file_resolves("twin/holding.py") and _file_resolves("config/wear_monitor.yaml")
    assert not _file_resolves("build/notes/twin.md") and not _file_resolves("twin/closedforms.py")
    assert _is_repository_path("build/notes/twin.md", "md")
    assert not _is_repository_path("units.parquet", "parquet")
    assert _is_repository_path("config/missing.yaml", "yaml")
    assert _dotted_resolves("ebm_wear_monitor.monitor.kalman.Bank.update")
    assert _dotted_resolves("ebm_wear_monitor.validation.papers.paper004.paper_unit")
    assert not _dotted_resolves("ebm_wear_monitor.twin.closedforms")
    assert not _dotted_resolves("ebm_wear_monitor.monitor.kalman.Bank.no_such_method")
    assert not _dotted_resolves("ebm_wear_monitor.monitor.kalman.NoSuchName")


def test_relative_references_go_up_one_package_per_further_dot() -> None:
    """``.x`` is relative to the module's package, ``..x`` to its parent (as a relative import)."""
    here = f"{PACKAGE}/diagnosis/ranking/verdict.py"
    assert _relative(here, ".scorer.fit") == f"{PACKAGE}.diagnosis.ranking.scorer.fit"
    assert _relative(here, "..phases") == f"{PACKAGE}.diagnosis.phases"
    package_init = f"{PACKAGE}/diagnosis/ranking/__init__.py"
    assert _relative(package_init, "..tolerance") == f"{PACKAGE}.diagnosis.tolerance"
    assert _dotted_resolves(_relative(here, "..tolerance.MATERIAL_SHARE"))
    assert not _dotted_resolves(_relative(here, ".tolerance.MATERIAL_SHARE"))
