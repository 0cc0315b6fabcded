"""ament_python package of ebm_wear_monitor.

Installed with pip (``install.sh``) the console scripts land in ``.venv/bin``;
built by colcon in a ROS 2 workspace, setup.cfg sends them to
``lib/ebm_wear_monitor`` so that ``ros2 run ebm_wear_monitor wear_monitor`` works.
"""

import runpy
from pathlib import Path

from setuptools import find_packages, setup

PACKAGE = "ebm_wear_monitor"
HERE = Path(__file__).parent
#: the dependency lists (ebm_wear_monitor/extras.py: standard library only, so it runs before installation)
EXTRAS = runpy.run_path(str(HERE / PACKAGE / "extras.py"))


def _config_files() -> list[str]:
    return sorted(str(p.relative_to(HERE)) for p in (HERE / "config").glob("*.yaml"))


setup(
    name=PACKAGE,
    version="0.1.0",
    packages=find_packages(exclude=["test", "test.*", "bench"]),
    package_data={PACKAGE: ["params/reference/*.yaml", "validation/foreign/README.md",
                            "reports/templates/*.html", "reports/style.css",
                            "schema/json/*.schema.json", "py.typed"]},
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{PACKAGE}"]),
        (f"share/{PACKAGE}", ["package.xml"]),
        (f"share/{PACKAGE}/config", _config_files()),
    ],
    python_requires=">=3.10",
    install_requires=[r.spec for r in EXTRAS["ONBOARD"]],  # the onboard node: pip install .
    extras_require={name: [r.spec for r in reqs] for name, reqs in EXTRAS["EXTRAS"].items()},
    zip_safe=False,  # PEP 561: type checkers read py.typed packages from directories only
    maintainer="ebm_wear_monitor maintainers",
    maintainer_email="maintainers@ebm-wear-monitor.org",
    description="Ball-screw wear and remaining-life monitor for railway electro-mechanical brake units",
    license="Apache-2.0",
    entry_points={
        "console_scripts": [
            f"ebm-wear = {PACKAGE}.cli.main:main",
            f"ebm-wear-monitor = {PACKAGE}.ros.node:main",
            f"wear_monitor = {PACKAGE}.ros.node:main",
        ],
    },
)
