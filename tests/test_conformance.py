"""Every registered planner, controller and optimiser passes the public conformance checks
(STYLE habit 5: a new algorithm is tested the moment it is registered)."""
from __future__ import annotations

import pytest

from swarmpath.registry import CONTROLLERS, MOTIONS, OPTIMIZERS, PLANNERS, REPRODUCTIONS
from swarmpath.testing import check_controller, check_motion, check_optimizer, check_planner


@pytest.mark.parametrize("name", [n for n in PLANNERS.names() if n != "none"])
def test_planner_conforms(name: str) -> None:
    assert check_planner(PLANNERS.get(name)) == []


def test_none_planner_plans_nothing() -> None:
    from swarmpath.testing import conformance_worlds

    assert PLANNERS.get("none")().plan(conformance_worlds()[0], rng=0).robots == ()


@pytest.mark.parametrize("name", CONTROLLERS.names())
def test_controller_conforms(name: str) -> None:
    cls = CONTROLLERS.get(name)
    planner = "astar" if cls.capabilities.needs_plan else None
    assert check_controller(cls, planner=planner) == []


@pytest.mark.parametrize("name", OPTIMIZERS.names())
def test_optimizer_conforms(name: str) -> None:
    assert check_optimizer(OPTIMIZERS.get(name)) == []


@pytest.mark.parametrize("name", MOTIONS.names())
def test_motion_conforms(name: str) -> None:
    assert check_motion(MOTIONS.get(name).example()) == []


def test_the_stable_names_are_registered() -> None:
    assert {"astar", "apf", "hybrid-apf", "amopso-path", "amopso-path-paper", "lacam", "none"} <= set(PLANNERS.names())
    assert {"follow", "cat-swarm", "pso-predictive", "pso-reactive", "fish-swarm", "amopso-follow", "pibt",
            "orca"} <= set(CONTROLLERS.names())
    paper_pure = {"cat-swarm-paper", "pso-predictive-paper", "pso-reactive-paper", "amopso-follow-paper"}
    assert paper_pure <= set(CONTROLLERS.names())
    assert {"pso", "amopso1", "amopso2", "amopso3", "amopso4", "mopso", "cso", "afsa"} <= set(OPTIMIZERS.names())
    assert {"jaleel2016", "prediction2013", "karim2014", "amopso-benchmarks", "amopso-paths"} <= set(REPRODUCTIONS.names())
    assert {"bounce", "bounce8", "turn-every", "random-walk", "redraw", "waypoints"} <= set(MOTIONS.names())
