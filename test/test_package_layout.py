"""The ament_python skeleton is whole and consistent (what ros2/examples' linter tests check, with ruff)."""

from __future__ import annotations

import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_package_xml_is_format3_ament_python_with_runtime_deps() -> None:
    root = ET.parse(REPO / "package.xml").getroot()
    assert root.get("format") == "3"
    assert root.findtext("name") == "ebm_wear_monitor"
    assert root.find("export/build_type").text == "ament_python"
    deps = {d.text for d in root.findall("depend")} | {d.text for d in root.findall("exec_depend")}
    assert {"rclpy", "diagnostic_msgs", "ebm_wear_msgs"} <= deps  # exactly: test_dependencies.py
    assert "std_msgs" in {d.text for d in root.findall("test_depend")}  # only a test imports it


def test_ament_resource_marker_and_versions_agree() -> None:
    import ebm_wear_monitor

    assert (REPO / "resource" / "ebm_wear_monitor").is_file()
    root = ET.parse(REPO / "package.xml").getroot()
    msgs = ET.parse(REPO / "msg_defs" / "package.xml").getroot()
    assert root.findtext("version") == ebm_wear_monitor.__version__
    assert msgs.findtext("name") == "ebm_wear_msgs"
    assert msgs.findtext("member_of_group") == "rosidl_interface_packages"


def test_console_scripts_are_installed_and_answer() -> None:
    bindir = Path(sys.executable).parent
    for script in ("ebm-wear", "ebm-wear-monitor", "wear_monitor"):
        assert (bindir / script).is_file(), script
    out = subprocess.run([bindir / "ebm-wear", "--help"], capture_output=True, text=True,
                         timeout=60, check=False)
    assert out.returncode == 0
    for command in ("replay", "fleet", "diagnose", "simulate", "calc"):
        assert command in out.stdout


def test_ruff_is_clean() -> None:
    ruff = shutil.which("ruff", path=str(Path(sys.executable).parent))
    assert ruff, "ruff is installed by install.sh"
    result = subprocess.run([ruff, "check", "ebm_wear_monitor", "test", "bench"], cwd=REPO,
                            capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stdout[-3000:]
