"""Grid search: A* (8-connected octile without corner cutting, or 4-connected), distance
fields from a goal to every cell, and line of sight. All agree on costs."""
from swarmpath.search.astar import GridPath, astar, path_cost
from swarmpath.search.distance_field import DistanceFieldCache, descend, distance_field
from swarmpath.search.line_of_sight import line_of_sight

__all__ = ["GridPath", "astar", "path_cost", "DistanceFieldCache", "descend", "distance_field", "line_of_sight"]
