"""The ``amopso-path`` planner: AMOPSO path planning with danger zones (Abbas & Abdulsahab,
sections 2.1 and 5.3, case 1), one robot at a time.

Encoding: a particle is K intermediate waypoints (2K numbers) and its path is the polyline
``start, w1, ..., wK, goal``; the search box is the workspace's bounding box shrunk by the
robot's radius. Objectives (:mod:`swarmpath.planning.path_objectives`, all minimised): the
path length (the paper's f2 once every path ends at the goal) and the danger exposure, either
the paper's f1 = 1 / sum_j d_j (eq. 1, d_j = the closest approach of the polyline to danger
zone j, exact) or minus the clearance to the nearest danger zone. Static obstacles are a
constraint: a path that enters one (``World.static_hits`` with the robot's radius, the
validator's test) gets a penalty larger than any feasible objective plus its penetration depth,
so every feasible path dominates every infeasible one.

The optimiser is :class:`swarmpath.optim.MOPSO` with the chosen velocity rule (``spso``, ``pso`` or
``amopso1`` .. ``amopso4``, Table 1) in one of two modes:

- ``mode="pareto"`` (eq. 14): the external archive is the front. The returned path is chosen
  from it by the rule "the shortest member whose clearance from every danger zone (distance
  to the centre minus the zone's radius) is at least ``danger_margin``; when no member keeps
  that clearance, the member with the largest clearance". The whole front (paths, objective
  vectors, lengths, danger distances) is kept in the robot's diagnostics.
- ``mode="weighted-sum"`` (eq. 13): the optimiser minimises ``W_length * length + W_danger *
  danger`` (``weights``, summing to 1; equal by default) and the best path is returned; the
  archive of everything it evaluated is still reported as the front.

Initialisation (``init``): ``"random"`` draws every particle uniformly in the box (eq. 31);
``"astar"`` (the default) puts one particle on the A* path of the world's grid (inflated for the
robot's radius), string-pulled with the exact geometry and resampled to K waypoints that keep
its corners; the other particles are random. Without danger zones the danger objective is 0
and the planner minimises length alone.

Statuses: EXACT with a collision-free path; INVALID_START / INVALID_GOAL when the robot's disc
does not fit there; otherwise, if no evaluated path was collision-free, TIMEOUT (the budget
ran out; A* on the grid did find a path) or INFEASIBLE (A* on the world's conservative grid
found none either). The returned path always passes ``validate_paths`` when the status is
EXACT: it is checked again with ``World.static_hits`` before it is returned.

Robots are planned independently (robot-robot conflicts are resolved online by the
``amopso-follow`` controller, :mod:`swarmpath.control.amopso_follow`).
"""
from __future__ import annotations

import time
from typing import Any, Sequence

import numpy as np
from numpy.typing import NDArray

from swarmpath.errors import ConfigError
from swarmpath.optim.mopso import MODES, MOPSO, UPDATE_RULES, check_weights
from swarmpath.optim.problem import Problem
from swarmpath.capabilities import Capabilities
from swarmpath.planning.base import Plan, Planner, PlanStatus, RobotPlan
from swarmpath.planning.path_objectives import (
    danger_clearance,
    danger_distances,
    danger_inverse_sum,
    decode_paths,
    encode_waypoints,
    obstacle_violation,
    path_lengths,
    penalised_objectives,
    penalty_offset,
    resample_polyline,
    segment_hits,
    static_collisions,
)
from swarmpath.planning.reference_paths import astar_polyline
from swarmpath.registry import register_planner
from swarmpath.rng import make_rng
from swarmpath.search.smoothing import dedupe
from swarmpath.types import SeedLike

FloatArray = NDArray[np.float64]

INITS = ("astar", "random")
DANGER_OBJECTIVES = ("inverse-sum", "clearance")
CHOICE_RULE = ("shortest front member with clearance >= danger_margin from every danger zone "
               "(else the member with the largest clearance)")


def choose_from_front(lengths: FloatArray, clearance: FloatArray, margin: float) -> int:
    """The choice rule of Pareto mode: index of the shortest member whose danger clearance is
    at least ``margin``; when none is, the member with the largest clearance (ties: shorter).

    lengths, clearance : ndarrays of shape (n_front,), n_front >= 1.
    """
    lengths = np.asarray(lengths, float)
    clearance = np.asarray(clearance, float)
    safe = np.flatnonzero(clearance >= margin)
    if len(safe):
        return int(safe[np.argmin(lengths[safe])])
    best = clearance.max()
    cand = np.flatnonzero(clearance == best)
    return int(cand[np.argmin(lengths[cand])])


def astar_initial_path(world, robot, n_waypoints: int) -> tuple[FloatArray | None, float | None]:
    """K waypoints (K, 2) from the A* path of the world's grid for ``robot`` (string-pulled
    with the exact geometry, corners kept: :func:`~swarmpath.planning.reference_paths.astar_polyline`),
    and that path's length; (None, None) when the grid has no path."""
    poly = astar_polyline(world, robot, world.grid(radius=robot.radius))
    if poly is None:
        return None, None
    return resample_polyline(poly, n_waypoints), float(path_lengths(poly[None])[0])


def path_problem(world, robot, n_waypoints: int, danger_objective: str = "inverse-sum") -> Problem:
    """The optimisation problem of one robot: 2K variables in the workspace's box (shrunk by
    the radius), objectives (length, danger) with the obstacle penalty folded in."""
    start = np.asarray(robot.start, float)
    goal = np.asarray(robot.goal, float)
    r = float(robot.radius)
    lo, hi = _box(world, r)
    centers = np.array([z.center for z in world.danger_zones], float).reshape(-1, 2)
    radii = np.array([z.radius for z in world.danger_zones], float)
    offset = penalty_offset(lo, hi, n_waypoints)

    def objectives(X: FloatArray) -> FloatArray:
        paths = decode_paths(X, start, goal)
        length = path_lengths(paths)
        d = danger_distances(paths, centers)
        if danger_objective == "inverse-sum":
            danger = danger_inverse_sum(d)
        else:
            danger = -danger_clearance(d, radii) if len(radii) else np.zeros(len(X))
        F = np.column_stack([length, danger])
        hits = segment_hits(world, paths, r)
        infeasible = hits.any(axis=1)
        if not infeasible.any():
            return F
        violation = np.zeros(len(X))
        violation[infeasible] = obstacle_violation(world, paths[infeasible], r, hits[infeasible])
        return penalised_objectives(F, violation, infeasible, offset)

    return Problem(objectives, np.tile(lo, n_waypoints), np.tile(hi, n_waypoints), n_objectives=2,
                   name=f"amopso-path {robot.id}")


def _box(world, radius: float) -> tuple[FloatArray, FloatArray]:
    """Search box of one waypoint: the workspace's bounding box shrunk by ``radius``."""
    b = world.bounds
    if hasattr(b, "width"):
        lo, hi = np.array([0.0, 0.0]), np.array([b.width, b.height], float)
    else:
        c = np.asarray(b.center, float)
        lo, hi = c - b.radius, c + b.radius
    lo, hi = lo + radius, hi - radius
    if np.any(lo >= hi):  # a robot as wide as the workspace: keep a tiny box, the penalty decides
        mid = (lo + hi) / 2
        lo, hi = mid - 1e-6, mid + 1e-6
    return lo, hi


@register_planner("amopso-path")
class AMOPSOPathPlanner(Planner):
    """AMOPSO (or SPSO) over K waypoints, Pareto archive or weighted sum (see the module doc).

    Parameters
    ----------
    update : str
        Velocity rule: ``"spso"`` (the paper's SPSO), ``"pso"`` (constriction) or ``"amopso1"`` .. ``"amopso4"`` (Table 1).
    mode : str
        ``"pareto"`` (eq. 14, archive + choice rule) or ``"weighted-sum"`` (eq. 13).
    weights : sequence of two floats, optional
        (W_length, W_danger) of eq. 13, in [0, 1], summing to 1; equal by default. In Pareto
        mode they are not used for the choice (the rule above is).
    waypoints : int
        K, the number of intermediate waypoints (a particle has 2K numbers).
    particles, iterations : int
        The swarm's budget per robot (particles x iterations evaluations).
    init : str
        ``"astar"`` (one particle on the string-pulled A* path) or ``"random"`` (eq. 31).
    danger_objective : str
        ``"inverse-sum"`` (the paper's f1, eq. 1) or ``"clearance"`` (minus the clearance to
        the nearest danger zone).
    danger_margin : float
        Clearance (world units beyond each zone's radius) the Pareto choice rule requires.
    archive_size : int
        Largest Pareto archive.
    mutation_rate : float
        Fraction of the run during which Coello's mutation acts (0.2, the MOPSO default; 0
        switches it off, as in the paper's MOPSO of Figure 2).
    """

    capabilities = Capabilities(continuous=True, multi_robot=False, randomized=True, multi_objective=True)

    def __init__(self, update: str = "amopso4", mode: str = "pareto", weights: Sequence[float] | None = None,
                 waypoints: int = 4, particles: int = 30, iterations: int = 120, init: str = "astar",
                 danger_objective: str = "inverse-sum", danger_margin: float = 0.0, archive_size: int = 100,
                 mutation_rate: float = 0.2):
        self.update = update
        self.mode = mode
        self.weights = None if weights is None else tuple(float(w) for w in weights)
        self.waypoints = waypoints
        self.particles = particles
        self.iterations = iterations
        self.init = init
        self.danger_objective = danger_objective
        self.danger_margin = danger_margin
        self.archive_size = archive_size
        self.mutation_rate = mutation_rate
        self._check()

    def _check(self) -> None:
        owner = "amopso-path"
        if self.update not in UPDATE_RULES:
            raise ConfigError(f"{owner}: update must be one of {', '.join(UPDATE_RULES)}; got {self.update!r}")
        if self.mode not in MODES:
            raise ConfigError(f"{owner}: mode must be one of {', '.join(MODES)}; got {self.mode!r}")
        if self.init not in INITS:
            raise ConfigError(f"{owner}: init must be one of {', '.join(INITS)}; got {self.init!r}")
        if self.danger_objective not in DANGER_OBJECTIVES:
            raise ConfigError(f"{owner}: danger_objective must be one of {', '.join(DANGER_OBJECTIVES)}; "
                              f"got {self.danger_objective!r}")
        if self.weights is not None:
            check_weights(owner, self.weights, 2)
        for name, low in (("waypoints", 1), ("particles", 2), ("iterations", 1), ("archive_size", 1)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < low:
                raise ConfigError(f"{owner}: {name} must be an integer >= {low}, got {v!r}")
        if not (isinstance(self.danger_margin, (int, float)) and np.isfinite(self.danger_margin)):
            raise ConfigError(f"{owner}: danger_margin must be a finite number, got {self.danger_margin!r}")
        if not (isinstance(self.mutation_rate, (int, float)) and 0.0 <= self.mutation_rate <= 1.0):
            raise ConfigError(f"{owner}: mutation_rate must be a number in [0, 1], got {self.mutation_rate!r}")

    def optimizer(self) -> MOPSO:
        """The configured MOPSO (update rule, mode, weights, archive)."""
        return MOPSO(update=self.update, mode=self.mode, weights=self.weights, archive_size=self.archive_size,
                     mutation_rate=self.mutation_rate)

    def params(self) -> dict[str, Any]:
        """The hyperparameters, for reports."""
        return {"update": self.update, "mode": self.mode, "weights": self.weights, "waypoints": self.waypoints,
                "particles": self.particles, "iterations": self.iterations, "init": self.init,
                "danger_objective": self.danger_objective, "danger_margin": self.danger_margin,
                "archive_size": self.archive_size, "mutation_rate": self.mutation_rate}

    def plan(self, world, *, rng: SeedLike = None) -> Plan:
        return plan_robots(self, world, rng)

    def plan_robot(self, world, robot, *, rng: np.random.Generator) -> RobotPlan:
        """One robot's plan (see the module docstring for statuses and diagnostics)."""
        return swarm_path(world, robot, self.optimizer(), mode=self.mode, waypoints=self.waypoints,
                          particles=self.particles, iterations=self.iterations, init=self.init,
                          danger_objective=self.danger_objective, danger_margin=self.danger_margin, rng=rng)


def plan_robots(planner, world, rng: SeedLike) -> Plan:
    """Plan every robot of ``world`` alone with ``planner.plan_robot`` (robot i draws from the
    stream ("amopso-path", robot id) of the seed), as one :class:`Plan`."""
    t0 = time.perf_counter()
    robots = tuple(planner.plan_robot(world, robot, rng=make_rng(rng, "amopso-path", robot.id))
                   for robot in world.robots)
    diag = {"evaluations": sum(int(r.diagnostics.get("evaluations", 0)) for r in robots),
            "params": planner.params(), "choice_rule": CHOICE_RULE if planner.mode == "pareto" else "weighted sum"}
    return Plan(getattr(planner, "registered_name", "") or "amopso-path", robots, time.perf_counter() - t0, diag)


def swarm_path(world, robot, optimizer: MOPSO, *, mode: str, waypoints: int, particles: int, iterations: int,
               init: str, danger_objective: str, danger_margin: float, rng: np.random.Generator) -> RobotPlan:
    """One robot's path by ``optimizer`` over K = ``waypoints`` waypoints (the module
    docstring gives the statuses and diagnostics): the start and goal checked, the swarm
    initialised (``init``: one A* particle or all random, eq. 31), run for ``particles`` x
    ``iterations``, and the path chosen from the front (``mode="pareto"``, the choice rule)
    or the best weighted sum."""
    t0 = time.perf_counter()
    r = float(robot.radius)
    for which, status in (("start", PlanStatus.INVALID_START), ("goal", PlanStatus.INVALID_GOAL)):
        p = np.asarray(getattr(robot, which), float)
        where = world.obstacle_at(p, r)
        if not world.bounds.contains(p, r) or where is not None:
            reason = f"{which} {p.tolist()} " + (f"lies inside {where}" if where else "leaves the workspace")
            return RobotPlan(robot.id, status, None, {"reason": reason, "time_s": time.perf_counter() - t0})
    K = int(waypoints)
    problem = path_problem(world, robot, K, danger_objective)
    diag: dict[str, Any] = {"update": optimizer.update, "mode": mode, "waypoints": K}
    initial = None
    astar_done = False
    astar_found = False
    if init == "astar":
        wps, a_len = astar_initial_path(world, robot, K)
        astar_done, astar_found = True, wps is not None
        diag["astar_length"] = a_len
        if wps is not None:
            initial = np.clip(encode_waypoints(wps), problem.lower, problem.upper)[None]
    diag["init"] = "astar" if initial is not None else ("random (no A* path)" if init == "astar" else "random")
    res = optimizer.minimize(problem, iterations=iterations, particles=particles, rng=rng,
                                    initial=initial)
    diag.update({"evaluations": res.n_evaluations, "optimizer_time_s": res.wall_time_s})
    start, goal = np.asarray(robot.start, float), np.asarray(robot.goal, float)
    centers = np.array([z.center for z in world.danger_zones], float).reshape(-1, 2)
    radii = np.array([z.radius for z in world.danger_zones], float)

    fx = res.pareto_x if res.pareto_x is not None else res.x[None]
    paths = decode_paths(fx, start, goal)
    ok = ~static_collisions(world, paths, r)
    paths = paths[ok]
    front_f = np.asarray(res.pareto_f if res.pareto_f is not None else res.objectives[None])[ok]
    order = np.argsort(path_lengths(paths), kind="stable")
    paths, front_f = paths[order], front_f[order]
    lengths = path_lengths(paths)
    dist = danger_distances(paths, centers)
    clear = danger_clearance(dist, radii)
    diag.update({"front_paths": paths, "front_objectives": front_f, "front_lengths": lengths,
                 "front_danger_distances": dist, "front_clearance": clear})

    if mode == "pareto":
        chosen_path = paths[choose_from_front(lengths, clear, float(danger_margin))] if len(paths) else None
        diag["choice_rule"] = CHOICE_RULE
    else:
        best = decode_paths(res.x[None], start, goal)
        chosen_path = None if static_collisions(world, best, r)[0] else best[0]
        diag["choice_rule"] = "weighted sum (eq. 13)"
    if chosen_path is not None:  # the validator's own test, once more, on the returned path
        p = dedupe(chosen_path)
        if len(p) > 1 and world.static_hits(p[:-1], p[1:], np.full(len(p) - 1, r)).any():  # pragma: no cover
            chosen_path = None
    if chosen_path is None:
        if not astar_done:
            astar_found = astar_initial_path(world, robot, K)[0] is not None
        status = PlanStatus.TIMEOUT if astar_found else PlanStatus.INFEASIBLE
        diag["reason"] = ("no collision-free path among the swarm's evaluations"
                          + ("" if astar_found else "; A* on the world's grid found none either"))
        diag["best_infeasible_path"] = decode_paths(res.x[None], start, goal)[0]
        diag["time_s"] = time.perf_counter() - t0
        return RobotPlan(robot.id, status, None, diag)
    path = dedupe(chosen_path)
    d = danger_distances(path[None], centers)
    diag.update({"length": float(path_lengths(path[None])[0]), "danger_distances": d[0],
                 "f1": float(danger_inverse_sum(d)[0]), "danger_clearance": float(danger_clearance(d, radii)[0]),
                 "front_size": int(len(paths)), "time_s": time.perf_counter() - t0})
    return RobotPlan(robot.id, PlanStatus.EXACT, path, diag)


__all__ = ["AMOPSOPathPlanner", "CHOICE_RULE", "astar_initial_path", "choose_from_front", "path_problem",
           "plan_robots", "swarm_path"]
