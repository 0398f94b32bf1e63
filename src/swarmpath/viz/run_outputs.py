"""What ``swarmpath run --out DIR`` writes: the summary, the trajectory and the pictures."""
from __future__ import annotations

import json
from pathlib import Path


def write_run_outputs(out_dir: str | Path, result) -> list[Path]:
    """Write summary.json and trajectory.npz for a :class:`~swarmpath.sim.RunResult`."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    summary_path = out / "summary.json"
    summary_path.write_text(json.dumps(result.summary, indent=2), encoding="utf-8")
    written.append(summary_path)
    written.append(result.trajectory.save(out / "trajectory.npz"))
    return written
