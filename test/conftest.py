"""Shared fixtures: an isolated ROS 2 environment per test (own domain id, localhost discovery)."""

from __future__ import annotations

import itertools
import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
VENV_BIN = Path(sys.executable).parent
_domains = itertools.count()


def _fresh_domain_id() -> int:
    """A ROS_DOMAIN_ID unlikely to collide with parallel test runs on this machine (1..200)."""
    return 1 + (os.getpid() * 7 + next(_domains)) % 200


@pytest.fixture
def ros_env() -> dict[str, str]:
    """Environment for child processes that speak DDS: isolated domain, localhost-only discovery.

    ``ROS_LOCALHOST_ONLY`` does nothing in Kilted; ``ROS_AUTOMATIC_DISCOVERY_RANGE`` does.
    """
    env = dict(os.environ)
    env["ROS_DOMAIN_ID"] = str(_fresh_domain_id())
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    env["PYTHONUNBUFFERED"] = "1"
    env.pop("ROS_LOCALHOST_ONLY", None)
    return env


@pytest.fixture
def repo() -> Path:
    """Root of the repository (bags/, msg_defs/, config/ live here)."""
    return REPO


@pytest.fixture
def venv_bin() -> Path:
    """``.venv/bin`` of the interpreter running the tests (console scripts live here)."""
    return VENV_BIN
