"""Run the command line as a user would, and check that bad input fails as it should."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path



def swarmpath(*args: str, cwd: Path | None = None, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "swarmpath.cli", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=timeout)


def one_error_line(p: subprocess.CompletedProcess, *words: str) -> str:
    """The run failed as bad input should: exit 2, one line on stderr naming ``words``."""
    assert p.returncode == 2, (p.returncode, p.stderr[-2000:])
    assert "Traceback" not in p.stderr
    lines = [line for line in p.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, p.stderr[-2000:]
    assert len(lines[0]) <= 1100
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]

