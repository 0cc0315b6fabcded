"""The foreign world imports nothing from the project outside its own package (brief A)."""

from __future__ import annotations

import ast
from pathlib import Path

from ebm_wear_monitor.validation import foreign

PACKAGE = "ebm_wear_monitor.validation.foreign"
ALLOWED_THIRD_PARTY = {"numpy", "scipy", "yaml", "rosbags"}


def _imports(path: Path) -> list[tuple[int, str]]:
    """(relative level, module) of every import statement in a module."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            out += [(0, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            out.append((node.level, node.module or ""))
    return out


def test_every_module_imports_only_itself_and_allowed_libraries() -> None:
    root = Path(foreign.__file__).parent
    modules = sorted(root.glob("*.py"))
    assert len(modules) >= 8
    stdlib = __import__("sys").stdlib_module_names
    for path in modules:
        for level, name in _imports(path):
            where = f"{path.name}: import {'.' * level}{name}"
            assert level <= 1, where  # "from .. import" would leave the package
            if level == 1:
                continue
            top = name.split(".")[0]
            if top == "ebm_wear_monitor":
                assert name == PACKAGE or name.startswith(PACKAGE + "."), where
            else:
                assert top in stdlib or top in ALLOWED_THIRD_PARTY, where


def test_the_message_text_is_the_interface_definition(repo: Path) -> None:
    from ebm_wear_monitor.validation.foreign.bag import MSG_TEXT

    assert MSG_TEXT.split() == (repo / "msg_defs" / "msg" / "Float64Stamped.msg").read_text().split()
