"""Plan and simulate the default scenario, then re-check the result independently.

    python examples/quickstart.py [SEED]
"""
import sys

from swarmpath.planning import plan
from swarmpath.runner import run_world
from swarmpath.testing import validate_paths, validate_trajectory
from swarmpath.world import load_scenario

seed = int(sys.argv[1]) if len(sys.argv) > 1 else 0
world = load_scenario("jaleel2016")

offline = plan(world, "astar")
assert validate_paths(world, offline.paths) == [], "A* paths must be collision-free"

result = run_world(world, planner="hybrid-apf", controller="cat-swarm", seed=seed)
s = result.summary
print(f"{s.scenario}: {s.verdict()}, {s.steps} steps, collisions {dict(s.collisions)}")
for robot in s.robots:
    print(f"  {robot.id:>4}: planned {robot.planned_length:6.2f}, executed {robot.path_length:6.2f}")
violations = validate_trajectory(world, result.trajectory)
print("independent re-check:", "no violations" if not violations else violations[:3])
