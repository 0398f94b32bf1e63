"""Gymnasium spaces of one agent: its observation and its action (imports gymnasium)."""
from __future__ import annotations

import numpy as np
from gymnasium import spaces

from swarmpath.env.core import EnvCore
from swarmpath.env.options import GRID


def observation_space(core: EnvCore) -> spaces.Space:
    """Grid: ``Dict(patch=Box(0, 1, (5, 2 view + 1, 2 view + 1)), goal=Box(-1, 1, (3,)))``;
    continuous: ``Box(-1, 1, (size,))``; float32."""
    if core.mode == GRID:
        return spaces.Dict({
            "patch": spaces.Box(0.0, 1.0, core.patch_shape, np.float32),
            "goal": spaces.Box(-1.0, 1.0, (3,), np.float32),
        })
    return spaces.Box(-1.0, 1.0, (core.vector_size,), np.float32)


def action_space(core: EnvCore) -> spaces.Space:
    """Grid: ``Discrete(9)`` (or 5); continuous: ``Box(-1, 1, (2,), float64)`` (float64 so
    that an expert's move is reproduced exactly)."""
    if core.mode == GRID:
        return spaces.Discrete(core.n_actions)
    return spaces.Box(-1.0, 1.0, (2,), np.float64)
