"""How the cat swarm's rules become each robot's ranking of its 9 candidate moves, the input of
the PIBT core (:func:`swarmpath.control.pibt.core.pibt_step`), which decides for all robots
at once.

The core takes, per robot and candidate, a number (lower is better), the allowed set, and
random keys for exact ties. It gives each robot, in priority order, its best candidate that
no robot decided before it blocks, pushing an undecided robot out of the way (priority
inheritance) or backtracking. We hand it *ranks*: :func:`dense_ranks` turns the swarm's
lexicographic keys into 0, 1, 2, ... per robot, equal keys sharing a rank (the core then
prefers a free cell to an occupied one, then the random key).

The keys (:func:`swarm_keys`), one list per kind of robot:

- **follow, trace** (Algorithm 4 steps 3 and 7): the next cell of the robot's path, then
  staying ("wait when it is taken"), then every other copy in seek order (used when the
  robot is pushed: a pushed robot cannot stay);
- **seek** (step 6.4-6.5), robots that must or should leave their cell (moving obstacles),
  and the cat swarm's own copies: cells no obstacle can reach soon first (leave early), then
  eq. 12's fitness plus the warning term, then eq. 13;
- **parked** (at the goal) and **walled in** (no path to the goal): staying, then seek order;
- **distance first** (the robot of highest priority, and robots without progress for
  ``patience`` steps): the exact distance of the copy to the goal first, the swarm's order
  only among copies of equal distance. This is PIBT's own ranking, so the core's
  reachability argument (Okumura et al. 2022, Theorem 1: the robot of highest priority gets
  its best candidate every step) makes that robot walk a shortest path to its goal; its
  priority stays the highest until it arrives, so every robot arrives in turn.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

STAY = 0
#: Rank given to candidates that are not allowed (the core never looks at them).
NOT_ALLOWED = 99.0


def dense_ranks(keys: list[FloatArray], valid: BoolArray) -> FloatArray:
    """Rank of every candidate (n, 9) by the lexicographic ``keys`` (each (n, 9), the first
    the most significant, lower first): 0 for the best, equal keys sharing a rank;
    :data:`NOT_ALLOWED` where ``valid`` (n, 9) is False."""
    n = valid.shape[0]
    if n == 0:
        return np.zeros(valid.shape)
    stack = [np.where(valid, np.asarray(k, float), np.inf) for k in keys]
    order = np.lexsort(stack[::-1], axis=-1)
    new = np.zeros((n, valid.shape[1]), bool)
    for k in stack:
        s = np.take_along_axis(k, order, axis=1)
        new[:, 1:] |= s[:, 1:] != s[:, :-1]
    ranks = np.empty(valid.shape)
    np.put_along_axis(ranks, order, np.cumsum(new, axis=1).astype(float), axis=1)
    return np.where(valid, ranks, NOT_ALLOWED)


def swarm_keys(fitness: FloatArray, score: FloatArray, tie13: FloatArray, safety: NDArray | None,
               path_next: IntArray, follow: BoolArray, path_ok: BoolArray, stay_first: BoolArray,
               distance_first: BoolArray, keep_present: bool = True, decimals: int = 6) -> list[FloatArray]:
    """The lexicographic keys (each (n, 9), most significant first) of every robot's ranking.

    fitness : eq. 12, the exact path length from each copy to the goal (n, 9)
    score : eq. 12 plus the warning term (n, 9)
    tie13 : eq. 13, the straight-line distance from each copy's target to the goal (n, 9)
    safety : how many steps each copy stays clear of every obstacle, capped (n, 9), or None
    path_next : offset index of the next cell of each robot's path (n,)
    follow : robots that follow or trace their path (n,); ``path_ok``: their next cell is
        allowed and not less safe than staying
    stay_first : robots that rank staying first (parked, walled in)
    distance_first : robots that rank by exact distance first (see the module docs)
    keep_present : SPC; False ranks staying last for robots that seek
    """
    n = fitness.shape[0]
    idx = np.arange(9)[None, :]
    safe = np.zeros((n, 9)) if safety is None else -np.asarray(safety, float)
    exact = np.round(fitness, 9)
    score = np.round(score, decimals)
    tie = np.round(tie13, 9)
    cls = np.zeros((n, 9))
    if not keep_present:
        cls = np.where(idx == STAY, 1.0, cls)
    on_path = follow & path_ok
    cls = np.where(on_path[:, None], np.where(idx == path_next[:, None], 0.0, np.where(idx == STAY, 1.0, 2.0)), cls)
    waiting = (follow & ~path_ok) | stay_first
    cls = np.where(waiting[:, None], np.where(idx == STAY, 0.0, 1.0), cls)
    first = distance_first[:, None]
    cls = np.where(first, 0.0, cls)
    k1 = np.where(first, exact, safe)
    k2 = np.where(first, safe, score)
    k3 = np.where(first, score, tie)
    k4 = np.where(first, tie, 0.0)
    return [cls, k1, k2, k3, k4]
