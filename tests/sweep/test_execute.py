"""One job in a worker: the same outcome as swarmpath.runner.run_world, failures as results,
peers re-checked by swarmpath's own checker, and the lower bound held to a brute-force BFS."""
from __future__ import annotations

import math
from collections import deque
from pathlib import Path

import numpy as np
import pytest

from swarmpath.bench.sweep.bounds import lower_bound
from swarmpath.bench.sweep.execute import TIMING_FIELDS, run_job
from swarmpath.bench.sweep.jobs import expand
from swarmpath.bench.sweep.suite import load_suite
from swarmpath.runner import run_world
from swarmpath.world import load_scenario, world_from_movingai
from swarmpath.world.generators import antipodal


def jobs_of(tmp_path: Path, text: str):
    p = tmp_path / "suite.yaml"
    p.write_text(text)
    return expand(load_suite(p)).jobs


def without_timings(doc: dict) -> dict:
    return {k: v for k, v in doc.items() if k not in TIMING_FIELDS}


@pytest.mark.parametrize("scenario, planner, controller", [("karim2014", "none", "fish-swarm"),
                                                            ("karim2014", "astar", "follow"),
                                                            ("prediction2013", "none", "orca")])
def test_a_job_gives_what_run_world_gives(tmp_path: Path, scenario: str, planner: str, controller: str) -> None:
    (job,) = jobs_of(tmp_path, f"name: t\nscenarios: [{scenario}]\nplanners: [{planner}]\n"
                               f"controllers: [{controller}]\nseeds: [4]\nmax_steps: 60\n")
    result = run_job(job)
    assert result["status"] == "ok", result["error"]
    expected = run_world(load_scenario(scenario), planner=planner, controller=controller, seed=4, max_steps=60)
    assert result["outcome"] == without_timings(expected.summary.to_dict())
    assert set(result["timings"]) == {*TIMING_FIELDS, "wall_s", "setup_s"}
    assert run_job(job)["timings"]["setup_s"] == 0.0          # the world is built once per worker


def test_parameters_take_the_same_path_to_the_same_outcome(tmp_path: Path) -> None:
    """Explicit default parameters go through configured instances, not run_world: the
    outcome must not change."""
    plain, explicit = jobs_of(tmp_path, "name: t\nscenarios: [karim2014]\nmethods:\n  - {controller: cat-swarm}\n"
                                        "  - {planner: {name: none}, controller: {name: cat-swarm, params: "
                                        "{mixture_ratio: 0.4, lookahead: 5}}}\nseeds: [2]\n")
    assert plain.key != explicit.key
    a, b = run_job(plain), run_job(explicit)
    assert a["status"] == b["status"] == "ok"
    assert a["outcome"] == b["outcome"]


def test_nested_parameters_reach_the_controller(tmp_path: Path) -> None:
    (job,) = jobs_of(tmp_path, "name: t\nscenarios:\n  - {generator: antipodal, params: {n: 3}}\n"
                               "controllers: [{name: pso-reactive, params: {swarm: {n_particles: 3, "
                               "n_iterations: 2}}}]\n"
                               "max_steps: 5\n")
    result = run_job(job)
    assert result["status"] == "ok", result["error"]


def test_a_failing_job_is_a_result(tmp_path: Path) -> None:
    (job,) = jobs_of(tmp_path, "name: t\nscenarios: [karim2014]\n"
                               "controllers: [{name: cat-swarm, params: {mixture_ratio: 2.0}}]\n")
    result = run_job(job)
    assert result["status"] == "error" and result["outcome"] is None
    assert result["error"] == "cat-swarm: mixture_ratio must be in [0, 1], got 2.0"


def test_the_lower_bound_is_the_sum_of_single_robot_bfs_steps() -> None:
    world = world_from_movingai("random-32-32-10.map", "random-32-32-10-random-1.scen", 12)
    blocked = world.grid().blocked
    h, w = blocked.shape

    def bfs(start, goal):   # 8-connected, no corner cutting, written out once more
        dist = {start: 0}
        queue = deque([start])
        while queue:
            x, y = queue.popleft()
            if (x, y) == goal:
                return dist[(x, y)]
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    nx, ny = x + dx, y + dy
                    if (dx or dy) and 0 <= nx < w and 0 <= ny < h and not blocked[ny, nx] and (nx, ny) not in dist:
                        if dx and dy and (blocked[y, nx] or blocked[ny, x]):
                            continue
                        dist[(nx, ny)] = dist[(x, y)] + 1
                        queue.append((nx, ny))
        return math.inf

    cells = [(tuple(int(v) for v in np.floor(r.start)), tuple(int(v) for v in np.floor(r.goal))) for r in world.robots]
    assert lower_bound(world) == sum(bfs(s, g) for s, g in cells)


def test_the_lower_bound_in_continuous_space_is_the_straight_line() -> None:
    world = antipodal(6)
    expected = sum(math.ceil(math.dist(r.start, r.goal) / (r.max_speed * world.dt) - 1e-9) for r in world.robots)
    assert lower_bound(world) == expected


def test_pymapf_peers_land_in_the_same_fields(tmp_path: Path) -> None:
    pytest.importorskip("pymapf")
    jobs = jobs_of(tmp_path, "name: t\nscenarios:\n  - {map: empty-8-8.map, scen: empty-8-8-even-10.scen, "
                             "agents: [8]}\ncontrollers: []\npeers: [pymapf-lacam, pymapf-pibt]\n")
    assert sorted(j.controller for j in jobs) == ["pymapf-lacam", "pymapf-pibt"]
    for job in jobs:
        result = run_job(job)
        assert result["status"] == "ok", result["error"]
        o = result["outcome"]
        assert o["controller"] == job.controller and o["n_robots"] == 8 and len(o["robots"]) == 8
        assert o["success"] and result["violations"] == 0
        assert result["source"].startswith("pymapf ")
        assert o["sum_of_arrival_steps"] >= result["lower_bound"]


def test_pyrvo_contacts_are_found_by_our_checker(tmp_path: Path) -> None:
    """RVO2 with steps of one time unit lets discs overlap on the antipodal circle: our
    checker counts the contacts and validate_trajectory agrees."""
    pytest.importorskip("pyrvo")
    (job,) = jobs_of(tmp_path, "name: t\nscenarios:\n  - {generator: antipodal, params: {n: 12}}\n"
                               "controllers: []\npeers: [pyrvo-orca]\nmax_steps: 60\n")
    result = run_job(job)
    assert result["status"] == "ok", result["error"]
    contacts = sum(result["outcome"]["collisions"].values())
    assert contacts > 0 and result["violations"] >= contacts
    assert not result["outcome"]["success"]
