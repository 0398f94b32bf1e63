"""Shared test fixtures: paths to the test data."""
from __future__ import annotations

from pathlib import Path

import pytest

from swarmpath.data.movingai import MOVINGAI

DATA = MOVINGAI


@pytest.fixture
def data_dir() -> Path:
    return DATA
