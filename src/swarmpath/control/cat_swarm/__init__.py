"""The modified cat swarm of Jaleel & Hassan (2016), online collision avoidance on the grid.

- :mod:`.kernels`: Algorithm 4's steps as small pure functions over arrays (eq. 10-13);
- :mod:`.deadlock`: detecting robots that stopped making progress, and their priority;
- :mod:`.reservation`: conflict-free joint moves in priority order, with yielding;
- :mod:`.controller`: the registered ``cat-swarm`` controller that wires them together.
"""
from swarmpath.control.cat_swarm.controller import CatSwarmController

__all__ = ["CatSwarmController"]
