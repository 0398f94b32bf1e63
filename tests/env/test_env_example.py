"""examples/env_rollouts.py runs and prints what it promises (it needs the [env] extra)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("gymnasium")
pytest.importorskip("pettingzoo")

EXAMPLE = Path(__file__).parents[2] / "examples" / "env_rollouts.py"


def test_env_rollouts_example(tmp_path: Path) -> None:
    out = subprocess.run([sys.executable, str(EXAMPLE), str(tmp_path)], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "pibt: success rate 100%" in out.stdout, out.stdout
    assert "random: success rate" in out.stdout
    assert "expert episode re-checked: no violations" in out.stdout
    assert (tmp_path / "expert-replay.html").stat().st_size > 1000
