"""The artificial fish swarm of Karim (2014), Algorithm 1, as small pure functions: food
concentration, the fish a robot sees, the choice of behaviour and the prey, follow and swarm
moves. Cells are integer (x, y) arrays, food values floats (lower is better)."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

PREY, FOLLOW, SWARM, WAIT, ARRIVED = "prey", "follow", "swarm", "wait", "arrived"
FOOD_MODELS = ("euclidean", "distance-field")

#: The 8 neighbour offsets (dx, dy) of a cell.
NEIGHBOURS = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], dtype=np.int64)

_TIE = 1e-12


def food_euclidean(points: ArrayLike, goal: ArrayLike) -> FloatArray:
    """Food concentration Y(X) = ||X - goal|| (section "Structure of AFSA": Y = f(X), the
    objective; lower is better). ``points`` (k, 2) world units -> (k,)."""
    return np.linalg.norm(np.asarray(points, float).reshape(-1, 2) - np.asarray(goal, float), axis=1)


def food_from_field(cells: ArrayLike, field: FloatArray) -> FloatArray:
    """Food concentration Y(X) read from a distance field (shape (H, W), cells outside the
    grid or unreachable -> inf); ``cells`` (k, 2) integer (x, y) -> (k,)."""
    c = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    h, w = field.shape
    inside = (c[:, 0] >= 0) & (c[:, 0] < w) & (c[:, 1] >= 0) & (c[:, 1] < h)
    out = np.full(len(c), np.inf)
    out[inside] = field[c[inside, 1], c[inside, 0]]
    return out


def chebyshev(a: ArrayLike, b: ArrayLike) -> IntArray:
    """Chebyshev (king-move) distance between cells, broadcasting over leading axes."""
    return np.max(np.abs(np.asarray(a, np.int64) - np.asarray(b, np.int64)), axis=-1)


def visible_fish(robot_cell: ArrayLike, fish_cells: ArrayLike, visual: int = 1) -> NDArray[np.bool_]:
    """Algorithm 1, Step 2: which fish are in the visual range, i.e. within Chebyshev distance
    ``visual`` of the robot's cell (``visual = 1``: its 8-neighbourhood), excluding the robot's
    own cell. ``fish_cells`` (m, 2) -> (m,) bool; ``nf`` is its sum."""
    c = np.asarray(fish_cells, np.int64).reshape(-1, 2)
    d = chebyshev(c, np.asarray(robot_cell, np.int64)[None])
    return (d >= 1) & (d <= visual)


def select_behaviour(nf: int, w: int) -> str:
    """Algorithm 1, Step 3: ``prey`` when no fish is visible, ``follow`` when ``0 < nf < w``,
    ``swarm`` when ``nf >= w`` (the paper writes ``nf > w`` and leaves ``nf == w`` open; its
    Step 6 says "more than 3" with w = 3; we read ``nf >= w``; docs/papers/karim-2014.md, choice 6)."""
    if nf <= 0:
        return PREY
    return FOLLOW if nf < w else SWARM


def not_crowded(nf: int, n_fish: int, delta: float) -> bool:
    """The crowd test of Steps 5 and 6: ``nf / n < delta`` (n = number of other fish)."""
    return n_fish > 0 and nf / n_fish < delta


def _first_best(values: FloatArray, mask: NDArray[np.bool_]) -> int | None:
    """Index of the smallest value among ``mask`` (the first one on ties), None if empty."""
    if not mask.any():
        return None
    v = np.where(mask, values, np.inf)
    best = float(v.min())
    if not np.isfinite(best):
        return int(np.flatnonzero(mask)[0])
    return int(np.flatnonzero(mask & (v <= best + _TIE * max(1.0, abs(best))))[0])


def prey_choice(candidate_food: ArrayLike) -> int | None:
    """Algorithm 1, Step 4 (prey): the candidate neighbour with the minimum food value (nearest
    to the goal), even when it is farther than the current cell; None without candidates.
    Ties go to the first candidate (the controller shuffles candidates with its seeded stream)."""
    f = np.asarray(candidate_food, float)
    return _first_best(f, np.ones(len(f), dtype=bool))


def follow_choice(robot_cell: ArrayLike, robot_food: float, candidate_cells: ArrayLike,
                  candidate_food: ArrayLike, fish_cells: ArrayLike, fish_food: ArrayLike,
                  n_fish: int, delta: float) -> int | None:
    """Algorithm 1, Step 5 (follow): among the visible fish ``X_j`` (cells (nf, 2), food (nf,))
    keep those with ``Y(X_j) < Y(R)``; if there is one and ``nf / n < delta``, move to the best
    (minimum food) candidate cell next to such a fish. The paper moves R onto ``X_j`` itself,
    which the fish occupies; we move next to it: Chebyshev distance to ``X_j`` at most
    ``max(1, d(R, X_j) - 1)`` (the cells around ``X_j`` for the 8-neighbourhood, a step toward
    it for a wider visual range). Returns a candidate index, None when the behaviour fails
    (the caller then preys)."""
    fish_cells = np.asarray(fish_cells, np.int64).reshape(-1, 2)
    fish_food = np.asarray(fish_food, float).reshape(-1)
    nf = len(fish_cells)
    if nf == 0 or not not_crowded(nf, n_fish, delta):
        return None
    leaders = fish_cells[fish_food < robot_food]
    if len(leaders) == 0:
        return None
    cand = np.asarray(candidate_cells, np.int64).reshape(-1, 2)
    reach = np.maximum(1, chebyshev(leaders, np.asarray(robot_cell, np.int64)[None]) - 1)   # (L,)
    near = chebyshev(cand[:, None, :], leaders[None, :, :]) <= reach[None, :]              # (k, L)
    return _first_best(np.asarray(candidate_food, float), near.any(axis=1))


def swarm_choice(robot_food: float, candidate_points: ArrayLike, candidate_food: ArrayLike,
                 fish_points: ArrayLike, n_fish: int, delta: float) -> int | None:
    """Algorithm 1, Step 6 (swarm): the centre ``X_c`` of the visible fish (points (nf, 2));
    if ``nf / n < delta``, move to the candidate nearest to ``X_c`` among those with
    ``Y < Y(R)`` (ties: better food, then the first). None when the behaviour fails."""
    fish_points = np.asarray(fish_points, float).reshape(-1, 2)
    nf = len(fish_points)
    if nf == 0 or not not_crowded(nf, n_fish, delta):
        return None
    food = np.asarray(candidate_food, float)
    pts = np.asarray(candidate_points, float).reshape(-1, 2)
    better = food < robot_food
    if not better.any():
        return None
    centre = fish_points.mean(axis=0)
    d = np.linalg.norm(pts - centre, axis=1)
    dmin = float(np.min(d[better]))
    closest = better & (d <= dmin + 1e-9)
    return _first_best(food, closest)


def fish_decision(robot_cell: ArrayLike, robot_food: float, candidate_cells: ArrayLike,
                  candidate_points: ArrayLike, candidate_food: ArrayLike, fish_cells: ArrayLike,
                  fish_points: ArrayLike, fish_food: ArrayLike, *, n_fish: int, w: int = 3,
                  delta: float = 0.5) -> tuple[int | None, str]:
    """One step of Algorithm 1 for one robot: (candidate index or None, behaviour executed).

    ``candidate_*`` describe the neighbour cells the robot may enter (k of them); ``fish_*`` the
    visible fish (nf of them). The behaviour is chosen by ``nf`` (Step 3); a failed follow or
    swarm falls back to prey; with no candidate at all the robot waits (index None)."""
    fish_cells = np.asarray(fish_cells, np.int64).reshape(-1, 2)
    behaviour = select_behaviour(len(fish_cells), w)
    k = None
    if behaviour == FOLLOW:
        k = follow_choice(robot_cell, robot_food, candidate_cells, candidate_food, fish_cells, fish_food,
                          n_fish, delta)
    elif behaviour == SWARM:
        k = swarm_choice(robot_food, candidate_points, candidate_food, fish_points, n_fish, delta)
    if k is None:
        behaviour = PREY
        k = prey_choice(candidate_food)
    if k is None:
        return None, WAIT
    return k, behaviour
