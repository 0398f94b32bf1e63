"""Each paper's ladder starts at its paper-pure variant and ends at the improved default, so
the generated tables really measure the way from one to the other."""
from __future__ import annotations

from swarmpath.bench import amopso_paths, jaleel2016, karim2014, prediction2013
from swarmpath.control.amopso_follow import AMOPSOFollowController
from swarmpath.control.amopso_follow_paper import AMOPSOFollowPaperController
from swarmpath.control.cat_swarm import CatSwarmController, CatSwarmPaperController
from swarmpath.control.pso_predictive import PaperPredictivePSOController, PredictivePSOController
from swarmpath.planning.amopso_path import AMOPSOPathPlanner
from swarmpath.planning.amopso_path_paper import AMOPSOPathPaperPlanner


def same(a, b) -> bool:
    return type(a) is type(b) and vars(a) == vars(b)


def test_controller_ladders_run_from_the_paper_to_the_default():
    for rungs, paper, ours in ((jaleel2016.ladder_rungs(), CatSwarmPaperController(), CatSwarmController()),
                               (prediction2013.ladder_rungs(), PaperPredictivePSOController(), PredictivePSOController())):
        assert same(rungs[0].controller(), paper) and same(rungs[-1].controller(), ours)
        built = [r.controller() for r in rungs]
        assert all(not same(a, b) for a, b in zip(built, built[1:]))  # every rung changes something


def test_karim_ladder_changes_only_the_redraw():
    paper, ours = karim2014.ladder_rungs()
    assert not paper.world.moving_obstacles[0].motion.avoid_robots
    assert ours.world.moving_obstacles[0].motion.avoid_robots
    assert ours.world.name == karim2014.karim_world(10).name == "karim2014"
    assert same(paper.controller(), ours.controller())


def test_amopso_ladders_run_from_the_paper_to_the_default():
    case1 = amopso_paths.case1_rungs()
    assert case1[0].planner().params() == AMOPSOPathPaperPlanner().params()
    assert case1[-1].planner().params() == AMOPSOPathPlanner().params()
    case2 = amopso_paths.case2_rungs()
    assert (case2[0].plans, case2[-1].plans) == ("paper", "ours")
    assert same(case2[0].follower(), AMOPSOFollowPaperController())
    assert same(case2[-1].follower(), AMOPSOFollowController())
