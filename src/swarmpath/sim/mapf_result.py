"""A grid run as LaCAM's ``result.txt`` (read by mapf-visualizer and LaCAM's tools):

    agents=N
    map_file=random-32-32-10.map
    solver=swarmpath-<planner>+<controller>
    solved=1
    soc=...  (sum of costs: steps until each agent last arrives at its goal)
    makespan=...
    comp_time=... (ms)
    starts=(x,y),(x,y),...
    goals=(x,y),...
    solution=
    0:(x,y),(x,y),...
    1:(x,y),...

Cells are (x = column, y = row) as in MovingAI files; one solution row per time step, from
the executed trajectory (for ``lacam`` + ``follow`` that is the plan itself).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from swarmpath.errors import ConfigError
from swarmpath.sim.trajectory import Trajectory


def mapf_result_text(traj: Trajectory, *, map_file: str = "", solver: str = "swarmpath",
                     comp_time_ms: float = 0.0) -> str:
    """The result.txt text of a trajectory whose robots stand on cell centres at every step."""
    res = traj.resolution
    cells = np.floor(traj.positions / res + 1e-9).astype(np.int64)
    centred = np.abs(traj.positions - (cells + 0.5) * res) <= 1e-6 * res
    if not centred.all():
        t, i = np.argwhere(~centred.all(axis=2))[0]
        raise ConfigError(f"--plan-out writes grid runs only: robot {traj.robot_ids[i]!r} is off a cell centre at "
                          f"step {t} ({traj.positions[t, i, 0]:g}, {traj.positions[t, i, 1]:g})")
    at_goal = np.all(np.abs(traj.positions - traj.goals[None]) <= 1e-9, axis=2)
    solved = bool(at_goal[-1].all())
    arrivals = []
    for i in range(traj.n_robots):
        away = np.flatnonzero(~at_goal[:, i])
        arrivals.append(int(away[-1]) + 1 if len(away) else 0)

    def row(c: np.ndarray) -> str:
        return ",".join(f"({x},{y})" for x, y in c.tolist())

    lines = [f"agents={traj.n_robots}", f"map_file={map_file}", f"solver={solver}", f"solved={int(solved)}",
             f"soc={sum(arrivals) if solved else 0}", f"makespan={max(arrivals, default=0) if solved else 0}",
             f"comp_time={comp_time_ms:.0f}", f"starts={row(cells[0])}",
             f"goals={row(np.floor(traj.goals / res + 1e-9).astype(np.int64))}", "solution="]
    lines += [f"{t}:{row(cells[t])}" for t in range(len(cells))]
    return "\n".join(lines) + "\n"


def write_mapf_result(path: str | Path, traj: Trajectory, **kwargs) -> Path:
    """Write :func:`mapf_result_text` to ``path``."""
    path = Path(path)
    path.write_text(mapf_result_text(traj, **kwargs), encoding="ascii")
    return path
