"""Shared fixtures: an isolated ROS 2 environment per test (own domain id, localhost discovery)."""

from __future__ import annotations

import itertools
import os
import signal
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
VENV_BIN = Path(sys.executable).parent
_domains = itertools.count()


def pytest_configure(config: pytest.Config) -> None:
    """Give Ctrl-C back to the children when the suite itself was started with SIGINT ignored.

    A command run in the background of a non-interactive shell (``cmd &``, e.g. ``nohup cmd &`` in a
    script) starts with SIGINT ignored, and exec keeps an ignored signal ignored: the tests that
    interrupt a child (exit 130, one line) would then see it never stop. A handler installed here is
    reset to the default at exec, so every child starts with SIGINT at its default, as under a terminal
    or a CI runner. (The suite itself then stops on a SIGINT, as it does when started in a terminal.)
    """
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


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
