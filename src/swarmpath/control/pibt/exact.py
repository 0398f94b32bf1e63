"""The exact check behind the core's cell reasoning: moves that start or end off a cell centre.

The conflict table of :func:`~swarmpath.control.pibt.core.pibt_step` covers moves between
cell centres. A robot that starts off a centre (an exact start) or ends off one (an exact goal
on a cell corner, say) is checked here with the checker's own predicate
(:func:`swarmpath.world.move_rules.move_conflicts`) against the robots near it; a robot in
conflict is held where it is, and so, in turn, is every robot whose move conflicts with a held
robot staying. Staying robots never conflict with each other (they did not at the step
before), so the holds end in a contact-free step. Shared by the grid controllers on the core
(``pibt``, ``cat-swarm``, ``fish-swarm``).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.world.move_rules import move_conflicts

FloatArray = NDArray[np.float64]


def hold_conflicts(pos: FloatArray, new: FloatArray, radii: FloatArray, resolution: float,
                   check: NDArray[np.int64], reach: float) -> list[int]:
    """Robots to hold in place so that no move conflicts, checking robots ``check`` (their
    indices) against every robot within ``reach`` (Chebyshev, world units) of them.

    pos, new : (n, 2) positions now and the proposed next positions; radii (n,).
    Returns the held robots in the order they were held (each at most a few times; the loop
    has a budget of 4 n + 4 checks)."""
    if len(check) == 0:
        return []
    final = new.copy()
    held: list[int] = []
    todo = list(np.asarray(check).tolist())
    budget = 4 * len(pos) + 4
    while todo and budget > 0:
        budget -= 1
        i = todo.pop()
        near = np.flatnonzero(np.max(np.abs(pos - pos[i]), axis=1) <= reach)
        near = near[near != i]
        if len(near) == 0:
            continue
        kind = move_conflicts(pos[i], final[i], pos[near], final[near], radii[i], radii[near], resolution)
        if not np.any(kind != 0):
            continue
        if np.any(final[i] != pos[i]):
            final[i] = pos[i]
            held.append(i)
            todo.append(i)        # check the robots near it against its staying
            continue
        # i stays (held or by choice) and a neighbour's move hits it: hold that neighbour
        for j in near[kind != 0].tolist():
            if np.any(final[j] != pos[j]):
                final[j] = pos[j]
                held.append(j)
                todo.append(j)
    return held
