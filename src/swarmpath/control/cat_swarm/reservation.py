"""Conflict-free joint moves on a grid: every robot picks one of its candidate cells, in
priority order, so that no two robots end in the same cell, swap cells, or cross diagonals.

Each robot brings two preference lists of candidate indices (into its 9 candidate cells):
``own`` — what it does on its own turn (the cat swarm's choice, ending with staying) — and
``pushed`` — where it goes when it must leave its cell (best first, never staying).
A robot may enter a cell that another robot is leaving this step (following; a swap is
refused). When the cell it wants is occupied by a robot that has not decided yet:

- a robot allowed to push (urgent or endangered, see :mod:`swarmpath.control.deadlock`)
  makes the occupant yield: the occupant must move to one of its ``pushed`` cells, pushing
  further if needed (priority inheritance); it prefers cells that are not further along the
  pusher's way (so it steps aside into a niche rather than being herded down a corridor);
  if it cannot move, it stays and the pusher tries its next candidate;
- any other robot asks the occupant to move first along its ``own`` list without staying;
  if it will not, nothing changes and the asker tries its next candidate.

Robots far from every other robot (no robot within two cells) cannot interact and are
resolved at once (vectorised) by the caller; only the rest goes through this loop.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

MAX_DEPTH = 128
OWN, ASK, PUSH = 0, 1, 2


def reserve_moves(order: Sequence[int], cur: Sequence[int], cand_cell: Sequence[Sequence[int]],
                  cand_block: Sequence[Sequence[int]], own: Sequence[Sequence[int]],
                  pushed: Sequence[Sequence[int]], can_push: Sequence[bool], stay: int = 0,
                  distance: Callable[[int, int], float] | None = None) -> tuple[list[int], list[bool]]:
    """Choose one candidate index per robot listed in ``order`` (others keep -1).

    cur[i] : flat id of robot i's current cell; cand_cell[i][k] : flat id of its k-th
    candidate cell (``stay`` indexes the current cell); cand_block[i][k] : id of the 2x2 block
    a diagonal move crosses, -1 for other moves. Preference lists end at their first -1
    (``pushed`` lists skip -1 entries). ``distance(i, cell)`` is robot i's remaining path
    length from a cell (used to keep yielding robots off the pusher's way). Returns (choice
    per robot, whether the robot was made to yield)."""
    n = len(cur)
    choice = [-1] * n
    yielded = [False] * n
    occupant = {cur[i]: i for i in order}
    taken: dict[int, int] = {}
    blocks: dict[int, int] = {}

    def attempt(i: int, how: int, depth: int, pusher: int = -1) -> bool:
        if how == PUSH:
            prefs = pushed[i]
            if distance is not None and pusher >= 0:
                limit = distance(pusher, cur[i])
                cells_i = cand_cell[i]
                prefs = sorted((k for k in prefs if k >= 0),
                               key=lambda k: cells_i[k] < 0 or distance(pusher, cells_i[k]) < limit)
        else:
            prefs = own[i]
        cells = cand_cell[i]
        blks = cand_block[i]
        here = cur[i]
        for k in prefs:
            if k < 0:
                if how == PUSH:
                    continue  # the pushed list has a hole where staying was
                break
            if how == ASK and k == stay:
                break  # asked robots only move if they would move anyway
            v = cells[k]
            if v < 0 or v in taken:
                continue
            b = blks[k]
            if b >= 0 and b in blocks:
                continue
            j = occupant.get(v, -1) if k != stay else -1
            if j >= 0:
                cj = choice[j]
                if cj >= 0:
                    if cand_cell[j][cj] == here:
                        continue  # would swap
                else:
                    if depth >= MAX_DEPTH:
                        continue
                    sub = PUSH if (how == PUSH or (how == OWN and can_push[i])) else ASK
                    taken[v] = i
                    choice[i] = k
                    if b >= 0:
                        blocks[b] = i
                    if attempt(j, sub, depth + 1, i):
                        if how == PUSH:
                            yielded[i] = True
                        return True
                    choice[i] = -1
                    if b >= 0:
                        del blocks[b]
                    if taken.get(v) == i:
                        del taken[v]
                    continue
            taken[v] = i
            choice[i] = k
            if b >= 0:
                blocks[b] = i
            if how == PUSH:
                yielded[i] = True
            return True
        if how == ASK:
            return False
        choice[i] = stay
        taken[here] = i
        return False

    for i in order:
        if choice[i] < 0:
            attempt(i, OWN, 0)
    return choice, yielded
