"""Making way for a robot that a moving obstacle is about to reach: priority inheritance in
continuous space.

After ORCA's velocities have been cut to moves that conflict with no other robot (see
:meth:`~swarmpath.control.orca.core.ORCASolver.make_safe`), a robot in a dense crowd may be
left standing in a moving obstacle's next move: its escape is blocked by neighbours that
had no reason to move. :func:`make_way` gives it one: it tries the robot's escape moves
(a ring of directions at full, half and quarter step that keep clear of static geometry, of the
obstacles' footprints and of their next moves), nearest to the robot's own proposal first;
a move that conflicts with some neighbours' final moves is taken if those neighbours can
in turn be moved out of its way (each to a move that is itself safe and conflicts with no
robot's final move), recursively up to ``depth`` robots deep, within a budget of tried
moves. This is PIBT's priority inheritance (Okumura et al., AIJ 2022) with the simulator's
continuous move rules (:func:`swarmpath.world.move_rules.move_conflicts`). Every accepted
move passes every exact check, so the result never has more conflicts than its input;
a robot for which no way is found stays exposed (and is reported).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.world.move_rules import NO_CONFLICT, move_conflicts

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
IntArray = NDArray[np.int64]

#: Directions of the ring of moves tried per robot (at full, half and quarter step).
DIRECTIONS = 32
#: Moves tried per pushed robot (the root robot tries all of its safe moves).
PUSHED_TRIES = 8
#: A pushed robot's moves: turns (degrees) from straight away from the pusher, and lengths
#: (fractions of its step), tried shortest first, then straightest first.
PUSH_TURNS = (0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0)
PUSH_LENGTHS = (0.25, 0.5, 1.0)


class _Search:
    """One :func:`make_way` call's state: the solver's exact checks and the final moves."""

    def __init__(self, solver, p0: FloatArray, out: FloatArray, fc, budget: int, fixed: BoolArray | None = None):
        self.solver = solver
        self.fixed = np.zeros(len(p0), bool) if fixed is None else np.asarray(fixed, bool)
        self.p0 = p0
        self.out = out
        self.fc = fc
        self.budget = budget
        ang = 2 * np.pi * np.arange(DIRECTIONS) / DIRECTIONS
        ring = np.stack([np.cos(ang), np.sin(ang)], axis=1)
        self.offsets = np.concatenate([ring, 0.5 * ring, 0.25 * ring])
        self.tree = cKDTree(p0)
        self.reach = 2 * float(solver.step_len.max()) + 2 * float(solver.radii.max()) + 1e-6 \
            + (2 * solver.resolution if solver.points.any() else 0.0)
        self.neighbours: dict[int, IntArray] = {}

    def near(self, i: int) -> IntArray:
        if i not in self.neighbours:
            self.neighbours[i] = np.asarray([j for j in self.tree.query_ball_point(self.p0[i], self.reach) if j != i],
                                            np.int64)
        return self.neighbours[i]

    def safe_moves(self, i: int, extra: FloatArray) -> FloatArray:
        """Robot i's ring moves (and the ``extra`` ends) that pass the static, footprint and
        next-move checks, (c, 2)."""
        s = self.solver
        cand = np.concatenate([extra.reshape(-1, 2), self.p0[i] + self.offsets * s.step_len[i]])
        return self._passing(i, cand)

    def pushed_moves(self, j: int, pusher_end: FloatArray) -> FloatArray:
        """Safe moves of robot j pushed by a robot that moves to ``pusher_end``: away from that
        end (within 90 degrees of straight away), shortest first, straightest first."""
        s = self.solver
        away = self.p0[j] - pusher_end
        norm = float(np.hypot(*away))
        away = away / norm if norm > 1e-12 else np.array([1.0, 0.0])
        ang = np.radians(PUSH_TURNS)
        dirs = np.stack([np.cos(ang) * away[0] - np.sin(ang) * away[1],
                         np.sin(ang) * away[0] + np.cos(ang) * away[1]], axis=1)
        cand = (self.p0[j] + (np.asarray(PUSH_LENGTHS)[:, None, None] * s.step_len[j]) * dirs[None]).reshape(-1, 2)
        return self._passing(j, cand)

    def _passing(self, i: int, cand: FloatArray) -> FloatArray:
        """The ends ``cand`` (c, 2) of robot i's moves that pass the static, footprint and
        next-move checks (and keep clear of a redraw's possible places)."""
        s = self.solver
        m = len(cand)
        a = np.repeat(self.p0[i][None], m, axis=0)
        idx = np.full(m, i)
        ok = ~s.static_unsafe(a, cand, idx)
        hard, soft = s.obstacle_unsafe(a, cand, idx, self.fc)
        ok &= ~hard & ~soft
        if s.redraw is not None and ok.any():
            ok[ok] &= ~s.redraw.danger(cand[ok], s.radii[idx[ok]] + 1e-7)
        return cand[ok]

    def blockers(self, i: int, ends: FloatArray) -> list[IntArray]:
        """For each end (c, 2) of robot i, the robots whose final move conflicts with i's move
        to it (by the simulator's rules)."""
        others = self.near(i)
        if not len(others) or not len(ends):
            return [np.zeros(0, np.int64) for _ in range(len(ends))]
        s = self.solver
        c = len(ends)
        cc = np.repeat(np.arange(c), len(others))
        jj = np.tile(others, c)
        ri = s.radii[i] + 1e-7 * (s.radii[i] > 0)
        rj = s.radii[jj] + 1e-7 * (s.radii[jj] > 0)
        bad = move_conflicts(np.repeat(self.p0[i][None], len(cc), 0), ends[cc], self.p0[jj], self.out[jj], ri, rj,
                             s.resolution) != NO_CONFLICT
        bad = bad.reshape(c, len(others))
        return [others[row] for row in bad]

    def place(self, i: int, ends: FloatArray, chain: set[int], depth: int) -> bool:
        """Move robot i to the first of ``ends`` whose blockers can all be moved out of the
        way (recursively, ``depth`` more robots deep); ``self.out`` is updated on success and
        left as it was on failure."""
        blocks = self.blockers(i, ends)
        # fewest robots in the way first (then the order given)
        order = np.argsort([len(b) for b in blocks], kind="stable")
        for k in order:
            end, block = ends[k], blocks[k]
            if self.budget <= 0:
                return False
            self.budget -= 1
            if any(int(j) in chain or self.fixed[j] for j in block):
                continue
            if len(block) == 0:
                self.out[i] = end
                return True
            if depth == 0:
                continue
            saved = self.out.copy()
            self.out[i] = end
            inner = chain | {i} | {int(j) for j in block}
            ok = True
            for j in block:
                j = int(j)
                moves = self.pushed_moves(j, end)
                if not self.place(j, moves[:PUSHED_TRIES], inner - {j}, depth - 1):
                    ok = False
                    break
            if ok and not len(self.blockers(i, end[None])[0]):
                return True
            self.out[:] = saved
        return False


def make_way(solver, p0: FloatArray, p1: FloatArray, out: FloatArray, rows: IntArray, fc, *, depth: int = 4,
             budget: int = 3000, fixed: BoolArray | None = None) -> tuple[FloatArray, BoolArray, BoolArray]:
    """Give robots ``rows`` (left in an obstacle's next move) a safe move, moving neighbours
    out of the way where needed (see the module docstring).

    Parameters
    ----------
    solver : a reset :class:`~swarmpath.control.orca.core.ORCASolver` (its exact checks)
    p0 : (n, 2) positions; p1 : (n, 2) proposed ends; out : (n, 2) final ends so far
    rows : robots to free, in the order they are served
    fc : the obstacles' :class:`~swarmpath.control.orca.obstacles.ObstacleForecast`
    depth : how many robots deep neighbours may be pushed; budget : moves tried per robot and
        depth (iterative deepening: every depth from 0 to ``depth`` gets this budget)
    fixed : (n,) robots that are never pushed

    Returns
    -------
    (final ends (n, 2), which of ``rows`` were freed (k,), which robots were pushed (n,))
    """
    out = out.copy()
    freed = np.zeros(len(rows), bool)
    before = out.copy()
    for k, i in enumerate(rows):
        search = _Search(solver, p0, out, fc, budget, fixed)
        moves = search.safe_moves(int(i), np.zeros((0, 2)))
        if not len(moves):
            continue
        score = np.linalg.norm(moves - p1[i], axis=1)
        if fc.next2 is not None:
            score = score + np.where(solver._viable(moves, np.full(len(moves), i), fc), 0.0, 1e3)
        moves = moves[np.argsort(score, kind="stable")]
        # iterative deepening: a move no robot is in the way of, else one neighbour deep, ...
        for d in range(depth + 1):
            search.budget = budget
            if search.place(int(i), moves, set(), d):
                freed[k] = True
                break
        out = search.out
    pushed = np.any(out != before, axis=1)
    pushed[rows] = False
    return out, freed, pushed
