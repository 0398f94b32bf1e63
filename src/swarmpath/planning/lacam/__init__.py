"""LaCAM (Okumura, AAAI 2023): configuration-space search with PIBT as successor generator
(:mod:`.search`) and the registered ``lacam`` planner (:mod:`.planner`)."""
from swarmpath.planning.lacam.planner import LaCAMPlanner
from swarmpath.planning.lacam.search import lacam_search

__all__ = ["LaCAMPlanner", "lacam_search"]
