"""The scripts in examples/ run and print what they promise."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).parents[1] / "examples"


@pytest.mark.parametrize("script, expect", [
    ("quickstart.py", "independent re-check: no violations"),
    ("custom_controller.py", "conformance problems: []"),
    ("optimize.py", "amopso3"),
    ("env_rollouts.py", "replay written"),
])
def test_example_runs(script: str, expect: str) -> None:
    out = subprocess.run([sys.executable, str(EXAMPLES / script)], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    assert expect in out.stdout, out.stdout


def test_every_example_is_run() -> None:
    listed = {"quickstart.py", "custom_controller.py", "optimize.py", "env_rollouts.py"}
    assert {p.name for p in EXAMPLES.glob("*.py")} == listed
