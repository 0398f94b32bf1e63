"""Fixtures of the sweep tests: suite files written into the test's folder."""
from __future__ import annotations

from pathlib import Path

import pytest
from sweep_support import ACCEPTANCE_SUITE, TINY_SUITE


@pytest.fixture
def acceptance_suite(tmp_path: Path) -> Path:
    p = tmp_path / "acceptance.yaml"
    p.write_text(ACCEPTANCE_SUITE)
    return p


@pytest.fixture
def tiny_suite(tmp_path: Path) -> Path:
    p = tmp_path / "suite.yaml"
    p.write_text(TINY_SUITE)
    return p
