"""What a planner or controller handles, as data (OMPL's planner specs, scikit-learn's tags).

The command line, the conformance checks and the benchmarks read these flags to pick a
sensible default, to say why a planner/controller pair cannot run together, and to decide
which promises (zero contacts, moving obstacles avoided) a check may hold an algorithm to.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Capabilities:
    """What a planner or controller handles; the CLI, checkers and benchmarks consult it."""

    needs_plan: bool = False          # controllers: needs an offline plan
    grid_based: bool = False          # moves between grid cell centres
    continuous: bool = False          # moves anywhere within its speed
    moving_obstacles: bool = False    # avoids moving obstacles
    multi_robot: bool = True          # avoids other robots
    randomized: bool = False          # result depends on the seed
    multi_objective: bool = False     # planners: optimises several objectives
    contact_free: bool = True         # promises zero contacts in what it handles (the two flags
                                      # above); a paper-pure variant that only tries says False
