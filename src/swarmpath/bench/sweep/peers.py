"""Other libraries' solvers in the same store: pymapf's PIBT and LaCAM on static grids, and
RVO2's ORCA (through pyrvo) in continuous space.

Each adapter turns the peer's output into a swarmpath :class:`~swarmpath.sim.trajectory.Trajectory`
(positions at every step) whose contacts are found by swarmpath's own checker
(``swarmpath.sim.collisions.step_contacts``) and which is re-checked by
``swarmpath.testing.validate_trajectory`` (steps over a robot's speed count too), so a peer's
row carries the same fields, measured the same way, as a swarmpath run: one report compares
like with like. The peers are optional (the ``[bench]`` extra) and imported only when a job
runs; a suite that names a missing one skips its jobs and says how to install it.

An adapter's constructor stores its parameters only; ``supports(world)`` says why a world is
out of its reach (None when it is not), ``solve`` returns the positions and timings.
"""
from __future__ import annotations

import abc
import importlib.util
import time
from importlib import metadata
from typing import Any

import numpy as np

from swarmpath.errors import ConfigError

#: A robot of a continuous peer within this distance of its goal, relative to the largest
#: goal coordinate, is placed on it: RVO2 computes in single precision (about 1e-7 relative),
#: so its robots end near, not exactly on, their goals; swarmpath's arrival test is exact.
SNAP = 1e-5


class Peer(abc.ABC):
    """Base of the adapters: the package it needs and what it reports about itself."""

    package = ""        # import name
    dist = ""           # distribution name on the package index
    label = ""          # registered name in suites

    def missing(self) -> str | None:
        """Why the peer cannot run here (its package is not installed), or None."""
        try:
            spec = importlib.util.find_spec(self.package)
        except (ImportError, ValueError):     # a broken or blocked installation counts as none
            spec = None
        if spec is None:
            return f"{self.package} is not installed (pip install \"swarmpath[bench]\" or pip install {self.dist})"
        return None

    def version(self) -> str:
        """The installed version of the peer's package ("" when it is missing)."""
        try:
            return metadata.version(self.dist)
        except metadata.PackageNotFoundError:
            return ""

    @abc.abstractmethod
    def supports(self, world: Any) -> str | None:
        """None when the peer can run ``world``, else why not (the job is skipped)."""

    @abc.abstractmethod
    def solve(self, world: Any, *, seed: int, max_steps: int, time_limit: float) -> tuple[np.ndarray, dict[str, float]]:
        """Positions (steps + 1, n, 2) of the peer's run of ``world`` and its timings."""


class _PymapfPeer(Peer):
    package = dist = "pymapf"
    solver = ""

    def __init__(self, *, allow_diagonals: bool = False, time_limit: float | None = None):
        self.allow_diagonals = allow_diagonals
        self.time_limit = time_limit

    def supports(self, world: Any) -> str | None:
        from swarmpath.control.grid_robots import check_grid_robots

        if world.moving_obstacles:
            return f"{self.label} solves static grids: the world has moving obstacles"
        try:
            check_grid_robots(world, self.label)
        except ConfigError as exc:
            return str(exc)
        grid = world.grid()
        for points in (world.starts, world.goals):
            cells = grid.cell_of(points)
            if not np.allclose(grid.centers(cells), points, atol=1e-9 * world.resolution):
                return f"{self.label} moves between cell centres: a start or goal is off a cell centre"
            if not grid.is_free(cells).all():
                return f"{self.label} needs every start and goal on a free cell of the grid"
        return None

    @abc.abstractmethod
    def _solver(self, seed: int, max_steps: int, time_limit: float):
        """The pymapf solver object for one run."""

    def solve(self, world: Any, *, seed: int, max_steps: int, time_limit: float) -> tuple[np.ndarray, dict[str, float]]:
        from pymapf.core.grid import GridMap
        from pymapf.core.solver import Agent, MAPFProblem

        grid = world.grid()
        starts, goals = grid.cell_of(world.starts), grid.cell_of(world.goals)
        agents = [Agent(f"a{i}", (int(s[1]), int(s[0])), (int(g[1]), int(g[0])))
                  for i, (s, g) in enumerate(zip(starts.tolist(), goals.tolist()))]
        problem = MAPFProblem(GridMap(grid.blocked.astype(int).tolist()), agents,
                              allow_diagonals=self.allow_diagonals)
        limit = self.time_limit if self.time_limit is not None else time_limit
        t0 = time.perf_counter()
        solution = self._solver(seed, max_steps, limit).solve(problem)
        wall = time.perf_counter() - t0
        n = world.n_robots
        if solution is None:
            return world.starts[None].copy(), {"planning_time_s": wall, "solved": 0.0}
        horizon = min(max((len(p) for p in solution.paths.values()), default=1), max_steps + 1)
        cells = np.empty((horizon, n, 2), np.int64)
        for i, agent in enumerate(agents):
            path = solution.paths[agent.name]
            for t in range(horizon):
                r, c = path[t] if t < len(path) else path[-1]
                cells[t, i] = (c, r)
        return grid.centers(cells), {"planning_time_s": wall, "solved": 1.0}


class PymapfLaCAM(_PymapfPeer):
    """pymapf's LaCAM (4-connected unless ``allow_diagonals``; ``time_limit`` default: the job's)."""

    label = "pymapf-lacam"

    def __init__(self, *, allow_diagonals: bool = False, time_limit: float | None = None,
                 max_expansions: int = 200_000):
        super().__init__(allow_diagonals=allow_diagonals, time_limit=time_limit)
        self.max_expansions = max_expansions

    def _solver(self, seed: int, max_steps: int, time_limit: float):
        from pymapf.algorithms.lacam import LaCAM

        return LaCAM(time_limit=time_limit, seed=seed, max_expansions=self.max_expansions)


class PymapfPIBT(_PymapfPeer):
    """pymapf's PIBT, at most ``max_steps`` timesteps."""

    label = "pymapf-pibt"

    def _solver(self, seed: int, max_steps: int, time_limit: float):
        from pymapf.algorithms.pibt import PIBT

        return PIBT(max_timestep=max_steps, seed=seed, time_limit=time_limit)


class PyrvoORCA(Peer):
    """RVO2's ORCA through pyrvo: preferred velocity straight at the goal at full speed,
    ``substeps`` RVO2 steps per simulator step; static obstacles as RVO2 polygons (a circle
    as the 16-gon around it). Worlds with moving obstacles or a raster map are out of reach
    (RVO2 sees neither)."""

    package = dist = "pyrvo"
    label = "pyrvo-orca"

    def __init__(self, *, neighbor_dist: float = 8.0, max_neighbors: int = 10, time_horizon: float = 4.0,
                 obstacle_time_horizon: float = 2.0, substeps: int = 1):
        self.neighbor_dist = neighbor_dist
        self.max_neighbors = max_neighbors
        self.time_horizon = time_horizon
        self.obstacle_time_horizon = obstacle_time_horizon
        self.substeps = substeps

    def supports(self, world: Any) -> str | None:
        if world.moving_obstacles:
            return "pyrvo-orca: RVO2 does not see moving obstacles"
        if world.static_map is not None:
            return "pyrvo-orca: RVO2 takes polygon obstacles, not a raster map"
        if not isinstance(self.substeps, int) or self.substeps < 1:
            return "pyrvo-orca: substeps must be a positive integer"
        return None

    def solve(self, world: Any, *, seed: int, max_steps: int, time_limit: float) -> tuple[np.ndarray, dict[str, float]]:
        import pyrvo

        from swarmpath.world.shapes import Circle, Polygon, Rect

        dt = world.dt / self.substeps
        sim = pyrvo.RVOSimulator()
        sim.set_time_step(dt)
        for r in world.robots:
            sim.add_agent((float(r.start[0]), float(r.start[1])), self.neighbor_dist, self.max_neighbors,
                          self.time_horizon, self.obstacle_time_horizon, float(r.radius), float(r.max_speed))
        for ob in world.obstacles:
            if isinstance(ob, Rect):
                (x0, y0), (x1, y1) = ob.min, ob.max
                vertices = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
            elif isinstance(ob, Circle):
                k = np.arange(16)
                rr = ob.radius / np.cos(np.pi / 16)
                vertices = [(ob.center[0] + rr * np.cos(a), ob.center[1] + rr * np.sin(a)) for a in 2 * np.pi * k / 16]
            elif isinstance(ob, Polygon):
                pts = np.asarray(ob.points, float)
                area = np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1])
                vertices = [tuple(p) for p in (pts if area > 0 else pts[::-1])]
            else:
                raise ConfigError(f"pyrvo-orca: obstacle {type(ob).__name__} has no RVO2 form")
            sim.add_obstacle([(float(x), float(y)) for x, y in vertices])
        if world.obstacles:
            sim.process_obstacles()
        goals = world.goals
        snap = SNAP * max(1.0, float(np.abs(goals).max(initial=0.0)))
        speeds = world.max_speeds
        pos = world.starts.copy()
        rows = [pos.copy()]
        t0 = time.perf_counter()
        for _ in range(max_steps):
            for _ in range(self.substeps):
                d = goals - pos
                dist = np.linalg.norm(d, axis=1)
                pref = d / np.maximum(dist, 1e-300)[:, None] * np.minimum(speeds, dist / dt)[:, None]
                for i in range(world.n_robots):
                    sim.set_agent_pref_velocity(i, (float(pref[i, 0]), float(pref[i, 1])))
                sim.do_step()
                pos = np.array([sim.get_agent_position(i).to_tuple() for i in range(world.n_robots)], float)
                near = np.linalg.norm(goals - pos, axis=1) <= snap
                for i in np.flatnonzero(near & np.any(pos != goals, axis=1)):
                    sim.set_agent_position(int(i), (float(goals[i, 0]), float(goals[i, 1])))
                    pos[i] = goals[i]
            rows.append(pos.copy())
            if np.all(pos == goals):
                break
        return np.stack(rows), {"sim_time_s": time.perf_counter() - t0}


#: Peers a suite can name (``peers: [pymapf-lacam, ...]``).
PEERS: dict[str, type[Peer]] = {cls.label: cls for cls in (PymapfLaCAM, PymapfPIBT, PyrvoORCA)}
