"""The ``amopso-follow`` controller: robots follow their offline (AMOPSO) paths and resolve
robot-robot conflicts online with the three principles of Abbas & Abdulsahab, section 2.2:

1. each robot first picks its next position aligned with its goal: the point ``max_speed *
   dt`` further along its planned path (:func:`swarmpath.control.path_tracking.advance_along`);
2. if that move would bring it into conflict with another robot ("more than one robot tries to
   take the same position"), it turns: side steps of length ``sidestep`` (the paper's
   threshold) turned right or left by 45 and 90 degrees from its heading, the free one that
   leaves it closest to its next path vertex (right wins ties); if none is free it waits;
3. otherwise it moves to the aligned position.

``amopso-follow`` (:class:`AMOPSOFollowController`) adds, before the turn of principle 2,
shorter moves along the path (1/2, 1/4 of the step) and up to ``max_waits`` steps of waiting,
and keeps ``separation`` of extra room; ``amopso-follow-paper``
(:mod:`swarmpath.control.amopso_follow_paper`) turns at once and keeps no extra room. Both
share :class:`PathFollowing`.

Robots decide one after the other each step, the one with the longest remaining route first
(ties by index). A robot's move is checked against the moves already decided this step and
against the current positions of the robots still to decide (who may stay): since every
decided move avoided the current positions of the others, staying is always conflict-free,
so the rule never creates a collision it could have avoided. A conflict is, for robots i and
j moving in straight lines during the step (:func:`moves_conflict`): coming closer than the
sum of their radii plus ``separation`` at any time of the step (or than their current
distance, if that is already smaller); and for two point robots, which occupy grid cells
(docs/scenarios.md, "Coordinates"), ending in the same cell of the world's grid or swapping cells. These are the
simulator checker's rules with a margin, so a run without invalid moves has no robot-robot
contact.

After a side step the robot rejoins its path at the next vertex along a straight segment if
that segment is free of static obstacles (exact, ``World.static_hits``), else it first steps
back to where it left the path; every move therefore lies on a collision-free segment.
``amopso-follow-paper`` ignores moving obstacles.

``amopso-follow`` adds, by default, what every improved continuous controller has (our
additions, each a switch): *guidance* (a robot whose straight move along its path would touch
a wall, having been pushed off it, steers at the guidance's point instead: a visible vertex
of its plan, else the goal's distance field, :class:`~swarmpath.control.orca.Guidance`), the
deterministic side preference and priority yielding with deadlock events
(:class:`~swarmpath.control.orca.coordination.Coordination`), and the ORCA *safety layer*
(:class:`~swarmpath.control.orca.SafetyLayer`): the follower's choice becomes the closest
safe move, so moving obstacles of every motion model are avoided too.
"""
from __future__ import annotations

import abc
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from swarmpath.control.base import Controller, Decision
from swarmpath.control.observation import Observation
from swarmpath.control.orca.coordination import Coordination
from swarmpath.control.orca.guidance import Guidance, velocity_toward
from swarmpath.control.orca.safety import SafetyLayer
from swarmpath.control.path_tracking import advance_along
from swarmpath.errors import ConfigError
from swarmpath.capabilities import Capabilities
from swarmpath.registry import register_controller
from swarmpath.world.move_rules import NO_CONFLICT, move_conflicts, swept_gap
from swarmpath.planning.base import Plan
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]

#: Turn angles of the side steps, in the order tried (degrees; + is left, - is right).
TURNS_DEG = (-45.0, 45.0, -90.0, 90.0)
#: Shorter moves along the path tried before side stepping (fractions of the step).
SLOWER = (0.5, 0.25)


def turned(direction: ArrayLike, degrees: ArrayLike) -> FloatArray:
    """Unit vector ``direction`` (2,) rotated by each angle (k,) in degrees (counter-clockwise
    = left): shape (k, 2). Principle 2's "turn left or right"."""
    d = np.asarray(direction, float)
    a = np.radians(np.asarray(degrees, float))
    c, s = np.cos(a), np.sin(a)
    return np.column_stack([c * d[0] - s * d[1], s * d[0] + c * d[1]])


def moves_conflict(a: ArrayLike, b: ArrayLike, q0: ArrayLike, q1: ArrayLike, radius: float, radii: ArrayLike,
                   separation: float, resolution: float) -> NDArray[np.bool_]:
    """Whether robot i moving a -> b conflicts with each robot j moving q0_j -> q1_j.

    a, b : (2,); q0, q1 : (m, 2); radius : robot i's; radii : (m,) the others'.
    Conflict: the smallest distance during the step (both move linearly) is below
    ``min(radius + radii + separation, current distance)`` (never below the sum of radii plus
    1e-6); for two point robots (radius 0) also ending in the same grid cell of size
    ``resolution``, or swapping cells. Returns (m,) booleans.
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    q0 = np.asarray(q0, float).reshape(-1, 2)
    q1 = np.asarray(q1, float).reshape(-1, 2)
    radii = np.asarray(radii, float)
    rsum = radius + radii
    now = np.linalg.norm(a - q0, axis=1)
    need = np.maximum(np.minimum(rsum + separation, now), rsum + 1e-6)
    bad = swept_gap(a[None], b[None], q0, q1) < need - 1e-12
    # and whatever the checker itself calls a contact (for point robots: their grid cells)
    bad |= move_conflicts(a[None], b[None], q0, q1, radius, radii, resolution) != NO_CONFLICT
    return bad


class PathFollowing(Controller):
    """What ``amopso-follow`` and ``amopso-follow-paper`` share: principles 1 and 3 (move
    along the path, aligned with the goal), the order of decisions, the conflict test and the
    side step of principle 2. Subclasses say how a robot gives way (:meth:`_give_way`)."""

    capabilities = Capabilities(needs_plan=True, continuous=True, multi_robot=True)

    def __init__(self, sidestep: float | None = None, separation: float = 0.25):
        name = self.registered_name or "amopso-follow"
        positive = isinstance(sidestep, (int, float)) and sidestep > 0 and math.isfinite(sidestep)
        if sidestep is not None and not positive:
            raise ConfigError(f"{name}: sidestep must be a positive number, got {sidestep!r}")
        if not (isinstance(separation, (int, float)) and separation >= 0 and math.isfinite(separation)):
            raise ConfigError(f"{name}: separation must be a number >= 0, got {separation!r}")
        self.sidestep = sidestep
        self.separation = float(separation)

    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        if plan is None:
            raise ConfigError(f"controller {self.registered_name!r} needs an offline plan (choose a planner)")
        self.world_ = world
        self.routes_ = [np.asarray(p, float) if p is not None else None for p in plan.paths]
        self.next_ = np.ones(world.n_robots, dtype=np.int64)
        self.budget_ = world.max_speeds * world.dt
        self.radii_ = world.radii
        self.waited_ = np.zeros(world.n_robots, dtype=np.int64)

    # ------------------------------------------------------------------ helpers
    def _remaining(self, i: int, p: FloatArray) -> float:
        route = self.routes_[i]
        if route is None:
            return 0.0
        k = int(self.next_[i])
        if k >= len(route):
            return 0.0
        rest = route[k:]
        return float(np.linalg.norm(rest[0] - p) + np.linalg.norm(np.diff(rest, axis=0), axis=1).sum())

    def _free(self, i: int, a: FloatArray, b: FloatArray, pos: FloatArray, new: FloatArray,
              decided: NDArray[np.bool_]) -> bool:
        """Move a -> b of robot i is free of static obstacles and of conflicts with others."""
        if np.any(a != b) and self.world_.static_hits(a[None], b[None], [self.radii_[i]])[0]:
            return False
        others = np.arange(len(pos)) != i
        q1 = np.where(decided[:, None], new, pos)
        bad = moves_conflict(a, b, pos[others], q1[others], float(self.radii_[i]), self.radii_[others],
                             self.separation, self.world_.resolution)
        return not bad.any()

    # ------------------------------------------------------------------ the step
    def act(self, obs: Observation) -> Decision:
        pos = np.asarray(obs.positions, float)
        n = len(pos)
        new = pos.copy()
        decided = np.zeros(n, dtype=bool)
        modes = ["follow"] * n
        events: list[dict] = []
        remaining = np.array([self._remaining(i, pos[i]) for i in range(n)])
        for i in np.lexsort((np.arange(n), -remaining)):
            i = int(i)
            route = self.routes_[i]
            if route is None or obs.at_goal[i] or int(self.next_[i]) >= len(route):
                decided[i] = True
                modes[i] = "arrived" if obs.at_goal[i] else ("no-plan" if route is None else "wait")
                continue
            budget = float(self.budget_[i])
            p, k = self._aligned(i, pos[i], budget)
            if self._free(i, pos[i], p, pos, new, decided):
                new[i], self.next_[i] = p, k
            else:
                new[i], modes[i] = self._give_way(i, pos, new, decided, p, budget, events)
            self.waited_[i] = self.waited_[i] + 1 if modes[i] == "wait" else 0
            decided[i] = True
        return Decision(new, modes, tuple(events))

    def _aligned(self, i: int, p: FloatArray, budget: float) -> tuple[FloatArray, int]:
        """Principle 1: robot i's next position aligned with its goal, ``budget`` further along
        its path from ``p``, and the index of the next path vertex still ahead."""
        return advance_along(self.routes_[i], p, int(self.next_[i]), budget)

    @abc.abstractmethod
    def _give_way(self, i: int, pos: FloatArray, new: FloatArray, decided: NDArray[np.bool_], aligned: FloatArray,
                  budget: float, events: list[dict]) -> tuple[FloatArray, str]:
        """Robot i's move when the aligned one conflicts: (position, mode)."""

    def _side_step(self, i: int, pos: FloatArray, new: FloatArray, decided: NDArray[np.bool_], aligned: FloatArray,
                   budget: float, events: list[dict]) -> tuple[FloatArray, str]:
        """Principle 2's turn: the free side step (45 and 90 degrees right and left of the
        heading, length ``sidestep``) that ends closest to the next path vertex; the robot
        then rejoins its path. None free: wait."""
        route = self.routes_[i]
        a = pos[i]
        heading = aligned - a
        norm = float(np.linalg.norm(heading))
        if norm <= 1e-12:
            return a.copy(), "wait"
        length = min(budget, self.sidestep if self.sidestep is not None else budget)
        target = route[int(self.next_[i])]
        best, best_score = None, math.inf
        for q in a + turned(heading / norm, TURNS_DEG) * length:
            if not self.world_.bounds.contains(q, self.radii_[i]) or not self._free(i, a, q, pos, new, decided):
                continue
            score = float(np.linalg.norm(target - q))
            if score < best_score - 1e-12:
                best, best_score = q, score
        if best is None:
            return a.copy(), "wait"
        # rejoin: straight to the next vertex if that segment is free, else back via a
        k = int(self.next_[i])
        direct = not self.world_.static_hits(best[None], target[None], [self.radii_[i]])[0]
        head = [best[None]] if direct else [best[None], a[None]]
        self.routes_[i] = np.concatenate(head + [route[k:]])
        self.next_[i] = 1
        events.append({"robot": i, "kind": "sidestep", "detail": f"to {np.round(best, 3).tolist()}"})
        return best, "sidestep"


@register_controller("amopso-follow")
class AMOPSOFollowController(PathFollowing):
    """Follow the offline paths behind the ORCA safety layer, with guidance along the plan and
    deterministic deadlock breaking; optionally give way by the follower's own rules (slow
    down, wait, side step).

    Parameters
    ----------
    sidestep : float, optional
        Length of a side step (the paper's threshold), world units; default: the robot's
        largest step ``max_speed * dt``. Used with ``give_way``.
    separation : float
        Extra distance kept between robots' discs (world units) at every time of a step.
        Used with ``give_way``.
    max_waits : int
        With ``give_way``: when the aligned move and the shorter moves (1/2, 1/4 of it) all
        conflict, the robot waits, up to ``max_waits`` steps in a row, before it side steps
        (2; 0: side step as soon as the shorter moves fail). The paper's rule, a side step at
        once without shorter moves or a margin, is ``amopso-follow-paper``.
    give_way : bool
        The follower resolves conflicts with other robots itself (principle 2 with our shorter
        moves and waiting, robots deciding one after the other). Off by default: the safety
        layer resolves them (measured: with the layer, the follower's own rules leave robots
        waiting for each other in the doors of dense maps; docs/papers/amopso.md). Needed
        when ``safety`` is off.
    safety : bool
        Put the ORCA safety layer after the follower: each move becomes the closest safe one,
        among robots, walls and moving obstacles of every motion model.
    safety_horizon : float
        The layer's time horizon for robots and moving obstacles, in steps (1: the next step
        is kept safe).
    guidance : bool
        Principle 1 by the guidance (:class:`~swarmpath.control.orca.Guidance`): a full step
        toward the farthest plan vertex in sight among the next few (else along the goal's
        distance field, e.g. after being pushed off the path), instead of exactly along the
        path vertex by vertex.
    side_bias, yield_after, patience
        Deterministic symmetry breaking and deadlock events, as in ``orca``
        (:class:`~swarmpath.control.orca.coordination.Coordination`; 0 turns the first two off).
    """

    capabilities = Capabilities(needs_plan=True, continuous=True, multi_robot=True, moving_obstacles=True)

    def __init__(self, sidestep: float | None = None, separation: float = 0.25, max_waits: int = 2,
                 give_way: bool = False, safety: bool = True, safety_horizon: float = 1.0, guidance: bool = True,
                 side_bias: float = 0.15, yield_after: int = 8, patience: int = 40):
        super().__init__(sidestep, separation)
        if isinstance(max_waits, bool) or not isinstance(max_waits, (int, np.integer)) or max_waits < 0:
            raise ConfigError(f"amopso-follow: max_waits must be an integer >= 0, got {max_waits!r}")
        self.max_waits = int(max_waits)
        if not (isinstance(safety_horizon, (int, float)) and safety_horizon > 0):
            raise ConfigError(f"amopso-follow: safety_horizon must be > 0 steps, got {safety_horizon!r}")
        if not safety and not give_way:
            raise ConfigError("amopso-follow: without the safety layer the follower must give way itself "
                              "(give_way=True)")
        Coordination(side_bias=side_bias, yield_after=yield_after, patience=patience)   # validates them
        self.give_way = bool(give_way)
        self.safety = bool(safety)
        self.safety_horizon = float(safety_horizon)
        self.guidance = bool(guidance)
        self.side_bias = side_bias
        self.yield_after = yield_after
        self.patience = patience

    def reset(self, world: World, plan: Plan | None, rng: np.random.Generator) -> None:
        super().reset(world, plan, rng)
        self.guidance_ = Guidance()
        self.guidance_.reset(world, plan)
        self.coordination_ = Coordination(side_bias=self.side_bias, yield_after=self.yield_after,
                                          patience=self.patience)
        self.coordination_.reset(world, self.guidance_)
        self.layer_ = None
        if self.safety:
            self.layer_ = SafetyLayer(time_horizon=self.safety_horizon * world.dt)
            self.layer_.reset(world)
        self.guided_ = world.starts.copy()

    def _aligned(self, i: int, p: FloatArray, budget: float) -> tuple[FloatArray, int]:
        if self.guidance:
            return self.guided_[i].copy(), int(self.next_[i])
        return super()._aligned(i, p, budget)

    def act(self, obs: Observation) -> Decision:
        pos = np.asarray(obs.positions, float)
        n = len(pos)
        if n == 0:
            return Decision(pos.copy(), [])
        dt = float(obs.dt)
        speeds = self.world_.max_speeds
        if self.guidance:
            target, is_goal = self.guidance_.targets(pos)
            self.guided_ = pos + velocity_toward(pos, target, speeds, dt, is_goal) * dt
        vertex = self.next_.copy()
        routes = list(self.routes_)
        if self.give_way:
            base = super().act(obs)
            sent = np.asarray(base.positions, float)
            modes, events = list(base.modes), list(base.events)
        else:
            sent, modes, events = self._all_aligned(obs)
        proposed = sent.copy()
        pref = (proposed - pos) / dt
        turned = self.coordination_.preferred(pos, pref)
        planless = np.array([r is None for r in self.routes_], bool)     # stays put (and is avoided)
        turned[planless] = pref[planless]
        changed = np.any(turned != pref, axis=1)
        proposed[changed] = pos[changed] + turned[changed] * dt
        final = proposed
        if self.layer_ is not None:
            final, adjusted = self.layer_.safe_positions(obs, proposed, fixed=planless)
            events.extend(self.layer_.events(adjusted))
        if self.layer_ is not None:
            self._track_vertices(final, sent, vertex, routes)
        constrained = np.linalg.norm((final - pos) / dt - turned, axis=1) > 0.05 * np.maximum(speeds, 1e-12)
        events.extend(self.coordination_.record(obs.step, final, constrained))
        at_goal = np.linalg.norm(final - obs.goals, axis=1) <= 1e-9
        modes = ["arrived" if at_goal[i] else ("wait" if not np.any(final[i] != pos[i]) else modes[i])
                 for i in range(n)]
        return Decision(final, modes, tuple(events))

    def _all_aligned(self, obs: Observation) -> tuple[FloatArray, list[str], list[dict]]:
        """Principle 1 for every robot at once (the layer resolves the conflicts)."""
        pos = np.asarray(obs.positions, float)
        new = pos.copy()
        modes = ["follow"] * len(pos)
        for i in range(len(pos)):
            route = self.routes_[i]
            if route is None or obs.at_goal[i] or int(self.next_[i]) >= len(route):
                modes[i] = "arrived" if obs.at_goal[i] else ("no-plan" if route is None else "wait")
                continue
            new[i], self.next_[i] = self._aligned(i, pos[i], float(self.budget_[i]))
        return new, modes, []

    def _track_vertices(self, final: FloatArray, sent: FloatArray, vertex: NDArray[np.int64], routes: list) -> None:
        """Keep each robot's next path vertex honest after the layer: a robot that did not
        end where the follower sent it has not reached the vertex it was heading for (a side
        step's new route starts at its own point, so it is kept); one within its radius (or a
        quarter step) of a vertex before its last has passed it."""
        off = np.any(final != sent, axis=1)
        for i in np.flatnonzero(off):
            if self.routes_[i] is routes[i]:
                self.next_[i] = vertex[i]
        for i, route in enumerate(self.routes_):
            if route is None:
                continue
            tol = max(float(self.radii_[i]), 0.25 * float(self.budget_[i]))
            for _ in range(len(route)):          # bounded by the route's length
                k = int(self.next_[i])
                if k >= len(route) - 1 or np.linalg.norm(route[k] - final[i]) > tol:
                    break
                self.next_[i] = k + 1

    def _give_way(self, i: int, pos: FloatArray, new: FloatArray, decided: NDArray[np.bool_], aligned: FloatArray,
                  budget: float, events: list[dict]) -> tuple[FloatArray, str]:
        """A shorter move along the path (or toward the guidance's point); else wait, up to
        ``max_waits`` steps in a row; else the best side step (principle 2); else wait."""
        route = self.routes_[i]
        a = pos[i]
        for frac in SLOWER:
            if self.guidance:
                p, k = a + frac * (aligned - a), int(self.next_[i])
            else:
                p, k = advance_along(route, a, int(self.next_[i]), budget * frac)
            if self._free(i, a, p, pos, new, decided):
                self.next_[i] = k
                return p, "slow"
        if self.waited_[i] < self.max_waits:
            return a.copy(), "wait"
        return self._side_step(i, pos, new, decided, aligned, budget, events)
