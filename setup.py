"""ament_python package of ebm_wear_monitor.

Installed with pip (``install.sh``) the console scripts land in ``.venv/bin``;
built by colcon in a ROS 2 workspace, setup.cfg sends them to
``lib/ebm_wear_monitor`` so that ``ros2 run ebm_wear_monitor wear_monitor`` works.
"""

from pathlib import Path

from setuptools import find_packages, setup

PACKAGE = "ebm_wear_monitor"
HERE = Path(__file__).parent


def _config_files() -> list[str]:
    return sorted(str(p.relative_to(HERE)) for p in (HERE / "config").glob("*.yaml"))


setup(
    name=PACKAGE,
    version="0.1.0",
    packages=find_packages(exclude=["test", "test.*", "bench"]),
    package_data={PACKAGE: ["params/reference/*.yaml", "validation/foreign/README.md",
                            "reports/templates/*.html", "reports/style.css",
                            "schema/json/*.schema.json"]},
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{PACKAGE}"]),
        (f"share/{PACKAGE}", ["package.xml"]),
        (f"share/{PACKAGE}/config", _config_files()),
    ],
    python_requires=">=3.10",
    install_requires=[
        "numpy>=1.26",
        "scipy>=1.11",
        "filterpy>=2.0.0",
        "rosbags>=0.11.9",
        "pyyaml>=6.0",
        "dask[distributed]>=2024.1",
        "pandas>=2.1",
        "pyarrow>=14",
        "matplotlib>=3.8",
        "tqdm>=4.66",
        "Jinja2>=3.1",
        "plotly>=5.20",
    ],
    zip_safe=True,
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
