"""The modified cat swarm of Jaleel & Hassan (2016), online collision avoidance on the grid.

- :mod:`.kernels`: Algorithm 2-4's steps as small pure functions over arrays (eq. 10-13);
- :mod:`.cells`: the grid, the distance fields and the robots' paths as cells (shared);
- :mod:`.paper`: the registered ``cat-swarm-paper`` controller, the paper's rules alone;
- :mod:`.ranking`: the swarm's rules as each robot's ranking of its candidates for the PIBT
  core (:mod:`swarmpath.control.pibt`), which decides for all robots at once;
- :mod:`.deadlock`: detecting and reporting robots that stopped making progress;
- :mod:`.controller`: the registered ``cat-swarm`` controller (the paper plus our additions).
"""
from swarmpath.control.cat_swarm.controller import CatSwarmController
from swarmpath.control.cat_swarm.paper import CatSwarmPaperController

__all__ = ["CatSwarmController", "CatSwarmPaperController"]
