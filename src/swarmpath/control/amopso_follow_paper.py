"""The ``amopso-follow-paper`` controller: the three principles of Abbas & Abdulsahab
(section 2.2) as printed, for the offline paths of case 2.

1. the robot's next position is aligned with its goal: a full step along its planned path;
2. if another robot would take the same position (the move conflicts with another robot's
   move by the simulator checker's own rules: no extra margin), or an obstacle lies there,
   the robot turns left or right by the threshold (a side step, the free one nearest to its
   next path vertex) at once; with no free side step it waits;
3. otherwise it moves to the aligned position.

It shares everything but the way of giving way with ``amopso-follow``
(:class:`~swarmpath.control.amopso_follow.PathFollowing`): the order of decisions (the
longest remaining route first, an interpretation: the paper does not say who goes first),
the conflict test and the side step. It has none of ``amopso-follow``'s shorter moves,
waiting or separation margin.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from swarmpath.control.amopso_follow import FloatArray, PathFollowing
from swarmpath.registry import register_controller


@register_controller("amopso-follow-paper")
class AMOPSOFollowPaperController(PathFollowing):
    """Follow the offline paths; on a conflict turn at once (principle 2), else wait.

    Parameters
    ----------
    sidestep : float, optional
        Length of the turn (the paper's threshold), world units; default: the robot's
        largest step ``max_speed * dt``.
    """

    def __init__(self, sidestep: float | None = None):
        super().__init__(sidestep, separation=0.0)

    def _give_way(self, i: int, pos: FloatArray, new: FloatArray, decided: NDArray[np.bool_], aligned: FloatArray,
                  budget: float, events: list[dict]) -> tuple[FloatArray, str]:
        return self._side_step(i, pos, new, decided, aligned, budget, events)
