"""The world model: bounds, static obstacles, danger zones, moving obstacles, robots, grids,
scenario files and MovingAI benchmark files."""
from swarmpath.world.bounds import Bounds, CircleBounds, RectBounds
from swarmpath.world.entities import DangerZone, Robot
from swarmpath.world.grid import OccupancyGrid, rasterize
from swarmpath.world.moving import (Bounce, Bounce8, MovingObstacle, ObstacleState, RandomWalk, Redraw,
                                    TurnEvery, Waypoints, advance_obstacles, initial_obstacle_state)
from swarmpath.world.movingai import (MovingAIMap, ScenEntry, parse_map, parse_scen, read_map, read_scen,
                                      world_from_movingai, write_map)
from swarmpath.world.scenario import (builtin_scenarios, load_scenario, scenario_json_schema, scenario_problems,
                                      world_from_dict)
from swarmpath.world.shapes import Circle, Polygon, Rect, Shape
from swarmpath.world.static_map import StaticMap
from swarmpath.world.world import World

__all__ = [
    "Bounds", "CircleBounds", "RectBounds", "DangerZone", "Robot", "OccupancyGrid", "rasterize",
    "Bounce", "Bounce8", "MovingObstacle", "ObstacleState", "RandomWalk", "Redraw", "TurnEvery", "Waypoints",
    "advance_obstacles", "initial_obstacle_state", "MovingAIMap", "ScenEntry", "parse_map", "parse_scen",
    "read_map", "read_scen", "world_from_movingai", "write_map", "builtin_scenarios", "load_scenario",
    "scenario_json_schema", "scenario_problems", "world_from_dict", "Circle", "Polygon", "Rect", "Shape",
    "StaticMap", "World",
]
