"""Jobs: the product of worlds, pairs and seeds; keys that name the resolved inputs (file
contents, not paths) and swarmpath's version; pairs that cannot run together skipped and
listed with the reason."""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from swarmpath.bench.sweep.jobs import expand, incompatible, schedule
from swarmpath.bench.sweep.suite import load_suite
from swarmpath.world import load_scenario

WORLD = """\
schema_version: 1
name: corridor
bounds: {type: rectangle, width: 12, height: 4}
robots:
  - {start: [1.5, 1.5], goal: [10.5, 1.5]}
  - {start: [10.5, 2.5], goal: [1.5, 2.5]}
"""


def suite_in(folder: Path, text: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "corridor.yaml").write_text(WORLD)
    p = folder / "suite.yaml"
    p.write_text(text)
    return p


SUITE = "name: k\nscenarios: [corridor.yaml, karim2014]\nplanners: [none, astar]\ncontrollers: [pibt, follow]\n" \
        "seeds: {count: 3}\nmax_steps: 50\n"


def test_product_and_skips(tmp_path: Path) -> None:
    e = expand(load_suite(suite_in(tmp_path, SUITE)))
    # none + follow cannot run (follow needs a plan): skipped and listed for both worlds
    assert {(s.scenario, s.planner, s.controller) for s in e.skipped} == {("corridor", "none", "follow"),
                                                                         ("karim2014", "none", "follow")}
    assert all("needs an offline plan" in s.reason and s.n_jobs == 3 for s in e.skipped)
    assert len(e.jobs) == 2 * 3 * 3                      # 2 worlds x 3 runnable pairs x 3 seeds
    assert len({j.key for j in e.jobs}) == len(e.jobs)
    assert {j.n_agents for j in e.jobs if j.scenario == "corridor"} == {2}


def test_keys_follow_contents_not_paths(tmp_path: Path) -> None:
    a = expand(load_suite(suite_in(tmp_path / "a", SUITE)))
    b = expand(load_suite(suite_in(tmp_path / "elsewhere" / "b", SUITE)))
    assert [j.key for j in a.jobs] == [j.key for j in b.jobs]
    (tmp_path / "a" / "corridor.yaml").write_text(WORLD.replace("10.5, 1.5]}", "9.5, 1.5]}"))
    c = expand(load_suite(tmp_path / "a" / "suite.yaml"))
    changed = {j.key for j in c.jobs} ^ {j.key for j in a.jobs}
    assert changed and all(j.scenario == "corridor" for j in a.jobs + c.jobs if j.key in changed)
    # the time limit bounds the work, it is not an input of the result
    d = expand(load_suite(suite_in(tmp_path / "d", SUITE + "timeout_s: 5\n")))
    assert [j.key for j in d.jobs] == [j.key for j in a.jobs]
    # the step budget is
    e = expand(load_suite(suite_in(tmp_path / "e", SUITE.replace("max_steps: 50", "max_steps: 51"))))
    assert not {j.key for j in e.jobs} & {j.key for j in a.jobs}


def test_keys_change_with_the_version(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import swarmpath

    a = expand(load_suite(suite_in(tmp_path, SUITE)))
    monkeypatch.setattr(swarmpath, "__version__", "99.0")
    b = expand(load_suite(tmp_path / "suite.yaml"))
    assert not {j.key for j in a.jobs} & {j.key for j in b.jobs}


def test_parameters_are_part_of_the_method_and_the_key(tmp_path: Path) -> None:
    text = "name: p\nscenarios: [karim2014]\ncontrollers: [fish-swarm, {name: fish-swarm, params: {w: 3}}, " \
           "{name: fish-swarm, params: {food: distance-field}}]\n"
    e = expand(load_suite(suite_in(tmp_path, text)))
    assert sorted(j.method for j in e.jobs) == ["none+fish-swarm", "none+fish-swarm(food=distance-field)",
                                                "none+fish-swarm(w=3)"]
    assert len({j.key for j in e.jobs}) == 3


def test_grid_controllers_skip_worlds_they_cannot_move_in() -> None:
    world = load_scenario("prediction2013")              # discs wider than half a cell
    assert "cell to cell" in incompatible(world, "none", "pibt")
    assert incompatible(world, "none", "orca") is None
    assert "needs an offline plan" in incompatible(world, "none", "follow")


def test_generators_and_obstacles_expand(tmp_path: Path) -> None:
    text = """\
name: g
scenarios:
  - {generator: crowd-crossing, params: {n_obstacles: [2, 4], motion: bounce}}
  - {generator: antipodal, params: {n: 4}, obstacles: {motion: [bounce, redraw], count: [0, 2]}}
controllers: [orca]
seeds: [0, 1]
"""
    e = expand(load_suite(suite_in(tmp_path, text)))
    crowd = [j for j in e.jobs if j.scenario == "crowd-crossing"]
    assert sorted({j.n_moving for j in crowd}) == [2, 4] and all(j.seeded_world for j in crowd)
    anti = [j for j in e.jobs if j.scenario == "antipodal"]
    # count 0 is the bare world once; 2 obstacles of each motion
    assert sorted((j.n_moving, j.motion) for j in anti if j.seed == 0) == [(0, ""), (2, "bounce"), (2, "redraw")]


def test_the_costliest_jobs_go_first(tmp_path: Path) -> None:
    text = "name: c\nscenarios:\n  - {map: empty-8-8.map, scen: empty-8-8-even-10.scen, agents: [2, 16, 8]}\n" \
           "controllers: [pibt]\nseeds: [0, 1]\n"
    order = [j.n_agents for j in schedule(expand(load_suite(suite_in(tmp_path, text))).jobs)]
    assert order == sorted(order, reverse=True)


def test_a_copied_builtin_movingai_file_gives_the_same_keys(tmp_path: Path) -> None:
    from swarmpath.data.movingai import MOVINGAI

    text = "name: m\nscenarios:\n  - {map: MAP, scen: SCEN, agents: [4]}\ncontrollers: [pibt]\n"
    builtin = expand(load_suite(suite_in(tmp_path / "a", text.replace("MAP", "empty-8-8.map")
                                         .replace("SCEN", "empty-8-8-even-10.scen"))))
    (tmp_path / "b").mkdir()
    for f in ("empty-8-8.map", "empty-8-8-even-10.scen"):
        shutil.copy(MOVINGAI / f, tmp_path / "b" / f"copy-{f}")
    copied = expand(load_suite(suite_in(tmp_path / "b", text.replace("MAP", "copy-empty-8-8.map")
                                        .replace("SCEN", "copy-empty-8-8-even-10.scen"))))
    assert [j.key for j in builtin.jobs] == [j.key for j in copied.jobs]


def test_files_are_relative_to_the_suite_not_the_current_folder(tmp_path: Path, monkeypatch) -> None:
    (tmp_path / "here").mkdir()
    (tmp_path / "here" / "karim2014").write_text(WORLD)     # a file named like a built-in scenario
    monkeypatch.chdir(tmp_path / "here")
    suite = suite_in(tmp_path / "suite", "name: r\nscenarios: [karim2014, corridor.yaml]\ncontrollers: [pibt]\n")
    e = expand(load_suite(suite))
    assert sorted(j.scenario for j in e.jobs) == ["corridor", "karim2014"]
    assert {j.spec["kind"] for j in e.jobs} == {"builtin", "file"}


def test_the_random_grid_among_movers_is_a_seeded_generator(tmp_path: Path) -> None:
    text = """\
name: grid
scenarios:
  - {generator: random-grid-movers, params: {n_robots: [10, 20], n_moving: 4, size: 24, motions: bounce+redraw}}
controllers: [pibt]
seeds: [0, 1]
"""
    e = expand(load_suite(suite_in(tmp_path, text)))
    assert sorted((j.n_agents, j.n_moving, j.seed) for j in e.jobs) == [(10, 4, 0), (10, 4, 1), (20, 4, 0), (20, 4, 1)]
    assert all(j.seeded_world for j in e.jobs) and {j.motion for j in e.jobs} == {"bounce,redraw"}


@pytest.mark.parametrize("params, field", [
    ("{motions: bounce+waypoints}", "params.motions"),
    ("{density: 0.95}", "params.density"),
    ("{n_robots: 5000, size: 16}", "scenarios[0]"),
])
def test_random_grid_parameters_that_cannot_work_name_their_field(tmp_path: Path, params: str, field: str) -> None:
    from swarmpath.bench.sweep.suite import SuiteError

    text = f"name: bad\nscenarios:\n  - {{generator: random-grid-movers, params: {params}}}\ncontrollers: [pibt]\n" \
           "seeds: [0]\n"
    with pytest.raises(SuiteError, match=field.replace("[", r"\[").replace("]", r"\]")):
        expand(load_suite(suite_in(tmp_path, text)))
