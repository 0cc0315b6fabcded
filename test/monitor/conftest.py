"""Fixtures of the monitor tests."""

import pytest

from ebm_wear_monitor.params import load_unit


@pytest.fixture
def unit():
    """The reference EMBU of paper 000 (package reference file)."""
    return load_unit()
