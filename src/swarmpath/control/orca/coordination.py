"""Deterministic symmetry breaking and deadlock reporting for continuous controllers.

Reciprocal avoidance alone lets symmetric situations freeze: two robots head-on agree to
stop, and the antipodal circle compresses into a ring in which every robot may only move
outwards. :class:`Coordination` changes a controller's preferred velocities by two fixed
rules, so the same situation always resolves the same way (no random perturbation):

1. *side preference*: a robot whose move was constrained last step turns its preferred
   velocity clockwise (keeps right) by ``side_bias`` times a factor in [0.5, 1.5) spread
   over robots by the golden ratio (no two neighbours turn alike);
2. *priority yielding*: robots that made no progress for ``yield_after`` steps back away at
   full speed from any stalled robot of smaller index within reach until it progresses; a
   robot parked on its goal ranks below every stalled robot (it backs away and returns), and,
   with ``chain`` > 0, a parked robot it backs into backs away in turn (a door with goals on
   both sides).

It also tracks each robot's progress along the guidance's remaining length and reports a
robot without progress for ``patience`` steps with a ``deadlock`` event (and
``deadlock_resolved`` when it moves on): a deadlock that remains is visible, and the
simulator ends runs without progress.

Used by the ``orca`` controller and by every improved continuous controller
(``pso-predictive``, ``pso-reactive``, ``amopso-follow``); see docs/algorithms/orca.md.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from swarmpath.control.orca.guidance import Guidance
from swarmpath.errors import ConfigError
from swarmpath.world.world import World

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: The golden ratio's fractional part: spreads the robots' turn factors over [0, 1).
GOLDEN = 0.6180339887498949


def unit(v: FloatArray) -> FloatArray:
    """Rows of ``v`` (k, 2) scaled to length 1 (zero rows stay zero)."""
    return v / np.maximum(np.linalg.norm(v, axis=1), 1e-12)[:, None]


def rotate(v: FloatArray, angle: FloatArray) -> FloatArray:
    """Vectors (n, 2) turned counter-clockwise by ``angle`` (n,) radians."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]], axis=1)


class Coordination:
    """Side preference, priority yielding and deadlock events (hyperparameters only here;
    run state is made by :meth:`reset`).

    Parameters
    ----------
    side_bias : turn (radians, clockwise) of the preferred velocity of a robot that was
        constrained last step (0 = off)
    yield_after : steps without progress after which a robot backs away from a stalled robot
        of smaller index nearby (0 = off)
    patience : steps without progress before a ``deadlock`` event
    margin : extra distance (world units) within which two stalled robots count as touching
    chain : how many parked robots deep a back-away passes on, each in the way of the one
        before (0 = off; ``pso-predictive`` and ``pso-reactive`` use 4)
    """

    def __init__(self, *, side_bias: float = 0.15, yield_after: int = 8, patience: int = 40, margin: float = 0.02,
                 chain: int = 0):
        if not 0 <= side_bias < np.pi / 2:
            raise ConfigError(f"side_bias must be in [0, pi/2) radians, got {side_bias}")
        if yield_after < 0:
            raise ConfigError(f"yield_after must be >= 0 (0 = off), got {yield_after}")
        if patience < 1:
            raise ConfigError(f"patience must be >= 1, got {patience}")
        if not margin >= 0:
            raise ConfigError(f"margin must be >= 0, got {margin}")
        if isinstance(chain, bool) or not isinstance(chain, (int, np.integer)) or chain < 0:
            raise ConfigError(f"chain must be a whole number >= 0 (0 = off), got {chain!r}")
        self.chain = int(chain)
        self.side_bias = side_bias
        self.yield_after = yield_after
        self.patience = patience
        self.margin = margin

    # ------------------------------------------------------------------ run state
    def reset(self, world: World, guidance: Guidance) -> None:
        """Prepare a run of ``world``; ``guidance`` (a reset
        :class:`~swarmpath.control.orca.guidance.Guidance`) measures progress."""
        self.guidance_ = guidance
        n = world.n_robots
        self.radii_ = world.radii
        self.speeds_ = world.max_speeds
        self.step_len_ = self.speeds_ * float(world.dt)
        self.points_ = self.radii_ == 0
        self.resolution_ = float(world.resolution)
        self.constrained_ = np.zeros(n, bool)
        # each robot's turn: side_bias times a factor in [0.5, 1.5) spread by the golden ratio,
        # so that no two neighbours in a symmetric crowd turn alike
        self.bias_ = self.side_bias * (0.5 + np.mod(np.arange(n) * GOLDEN, 1.0))
        self.best_ = guidance.remaining(world.starts) if n else np.zeros(0)
        self.at_goal_ = self.best_ <= 1e-9              # at its goal now
        self.since_ = np.zeros(n, np.int64)
        self.reported_ = np.zeros(n, bool)

    @property
    def stalled(self) -> BoolArray:
        """Robots not at their goal that made no progress for ``yield_after`` steps (n,); a
        robot that had reached its goal and left it (to make room) only after ``patience``
        steps away (two of them must not keep each other away for good)."""
        if self.yield_after == 0:
            return np.zeros(len(self.since_), bool)
        returning = (self.best_ <= 1e-9) & ~self.at_goal_
        wait = np.where(returning, max(self.patience, self.yield_after), self.yield_after)
        return (self.since_ >= wait) & ~self.at_goal_

    @property
    def parked(self) -> BoolArray:
        """Robots that have reached their goal and are not stalled (n,): they rank below every
        stalled robot, also while they back away from one."""
        return (self.best_ <= 1e-9) & ~self.stalled

    # ------------------------------------------------------------------ each step
    def preferred(self, pos: FloatArray, pref: FloatArray) -> FloatArray:
        """The preferred velocities (n, 2) after the side preference and priority yielding."""
        if self.side_bias > 0:
            pref = np.where(self.constrained_[:, None], rotate(pref, -self.bias_), pref)
        return self._yield(pos, pref)

    def record(self, step: int, final: FloatArray, constrained: BoolArray) -> list[dict]:
        """After the step: remember which robots were ``constrained`` (n,) and update progress
        from the chosen end positions ``final`` (n, 2); the step's deadlock events."""
        self.constrained_ = np.asarray(constrained, bool).copy()
        return self._progress(step, final)

    def _yield(self, pos: FloatArray, pref: FloatArray) -> FloatArray:
        """Deadlock breaking by priority: among robots stalled for ``yield_after`` steps,
        one within reach of a stalled robot of smaller index backs away from it at full
        speed (until that robot makes progress again), so the robot of highest priority in
        every jam gets room; the order is fixed, so two robots never undo each other. A robot
        that has reached its goal ranks below every stalled robot: parked in a door or a
        corridor, it backs away from a stalled robot near it, and returns afterwards. A parked
        robot in the way of one backing away (ahead of it, within reach) backs away from it
        too, up to ``chain`` robots deep: with goals in a door and just behind it, the
        first alone would push into the second and nothing would move."""
        if self.yield_after == 0:
            return pref
        stalled = self.stalled
        if not stalled.any():
            return pref
        parked = self.parked
        group = np.flatnonzero(stalled | parked)
        if len(group) < 2:
            return pref
        reach = 2 * float(self.radii_.max()) + 2 * float(self.step_len_.max()) + self.margin \
            + (np.sqrt(2.0) * self.resolution_ if self.points_.any() else 0.0)
        pairs = cKDTree(pos[group]).query_pairs(reach, output_type="ndarray")
        if not len(pairs):
            return pref
        a, b = group[pairs[:, 0]], group[pairs[:, 1]]
        keep = stalled[a] | stalled[b]                        # two parked robots leave each other be
        # the parked one yields to the stalled one; of two stalled, the larger index yields
        b_yields = parked[b] | (stalled[a] & stalled[b])
        lo = np.where(b_yields, b, a)[keep]
        hi = np.where(b_yields, a, b)[keep]
        push = np.zeros_like(pref)
        np.add.at(push, lo, unit(pos[lo] - pos[hi]))
        # a parked robot backing away into another parked one (a door with goals on both sides)
        # makes that one back away too, robots deep along the chain; the parked pairs, both ways
        src = np.concatenate([a[~keep], b[~keep]])
        dst = np.concatenate([b[~keep], a[~keep]])
        moving = np.linalg.norm(push, axis=1) > 1e-9
        for _ in range(self.chain):
            ahead = moving[src] & ~moving[dst] & (np.einsum("ij,ij->i", push[src], pos[dst] - pos[src]) > 0)
            if not ahead.any():
                break
            np.add.at(push, dst[ahead], unit(pos[dst[ahead]] - pos[src[ahead]]))
            moving = np.linalg.norm(push, axis=1) > 1e-9
        norm = np.linalg.norm(push, axis=1)
        yielding = norm > 1e-9
        out = pref.copy()
        out[yielding] = push[yielding] / norm[yielding, None] * self.speeds_[yielding, None]
        return out

    def _progress(self, step: int, pos: FloatArray) -> list[dict]:
        """Deadlock events: a robot not at its goal whose remaining path did not shrink by a
        tenth of a step's travel for ``patience`` steps is reported once, and again when it
        makes progress."""
        remaining = self.guidance_.remaining(pos)
        arrived = remaining <= 1e-9
        better = remaining < self.best_ - 0.1 * self.step_len_
        self.best_ = np.where(better | arrived, remaining, self.best_)
        self.since_ = np.where(better | arrived, 0, self.since_ + 1)
        self.at_goal_ = arrived
        events = []
        for i in np.flatnonzero((self.since_ >= self.patience) & ~self.reported_):
            events.append({"robot": int(i), "kind": "deadlock",
                           "detail": f"no progress for {self.patience} steps"})
            self.reported_[i] = True
        for i in np.flatnonzero(self.reported_ & (self.since_ == 0)):
            events.append({"robot": int(i), "kind": "deadlock_resolved"})
            self.reported_[i] = False
        return events
