"""The paper-pure ``amopso-path-paper`` planner: the paper's set-up (random swarm by eq. 31,
8 particles x 120 iterations, no mutation) on the shared path problem, and the mutation
switch of ``amopso-path``."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.errors import ConfigError
from swarmpath.planning.amopso_path import AMOPSOPathPlanner
from swarmpath.planning.amopso_path_paper import AMOPSOPathPaperPlanner
from swarmpath.registry import PLANNERS
from swarmpath.testing import validate_paths
from swarmpath.world import load_scenario


def test_registered_with_the_papers_set_up():
    assert PLANNERS.get("amopso-path-paper") is AMOPSOPathPaperPlanner
    p = AMOPSOPathPaperPlanner().params()
    assert (p["particles"], p["iterations"], p["init"], p["mutation_rate"]) == (8, 120, "random", 0.0)
    assert AMOPSOPathPaperPlanner().optimizer().mutation_rate == 0.0


@pytest.mark.parametrize("kw", [{"update": "pso"}, {"update": "amopso9"}, {"mode": "lexicographic"},
                                {"danger_objective": "max"}, {"weights": (0.3, 0.3)}])
def test_bad_configuration_is_refused(kw):
    with pytest.raises(ConfigError, match="amopso-path-paper"):
        AMOPSOPathPaperPlanner(**kw)


def test_it_is_the_improved_planner_without_its_additions():
    # same random streams, same problem: with A* seeding, 30 particles and mutation switched
    # off, amopso-path plans exactly what the paper-pure planner plans
    world = load_scenario("abbas-case1")
    for seed in (0, 3):
        a = AMOPSOPathPaperPlanner().plan(world, rng=seed).robots[0]
        b = AMOPSOPathPlanner(init="random", particles=8, mutation_rate=0.0).plan(world, rng=seed).robots[0]
        np.testing.assert_array_equal(a.path, b.path)
        assert validate_paths(world, [a.path]) == []


def test_mutation_switch_changes_the_run_and_is_checked():
    world = load_scenario("abbas-case1")
    on = AMOPSOPathPlanner(init="random", particles=8).plan(world, rng=1).robots[0].path
    off = AMOPSOPathPlanner(init="random", particles=8, mutation_rate=0.0).plan(world, rng=1).robots[0].path
    assert not np.array_equal(on, off)
    for bad in (-0.1, 1.5, "x"):
        with pytest.raises(ConfigError, match="mutation_rate"):
            AMOPSOPathPlanner(mutation_rate=bad)
