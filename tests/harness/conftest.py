"""Fixtures of the harness tests."""

from __future__ import annotations

import pytest

from contracts import load_contract
from contracts.stage import StageContract


@pytest.fixture
def l2() -> StageContract:
    """The packaged L2 material contract."""
    return load_contract("L2")
