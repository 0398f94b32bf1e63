"""Suite files: the issue's form loads, the built-in suites load and expand, every kind of
bad input is one line naming the file and the field (exit code 2 on the command line), and
the committed JSON Schema is the one generated from the models."""
from __future__ import annotations

import json
from pathlib import Path

import pytest
from sweep_support import swarmpath

from swarmpath.bench.sweep.jobs import expand
from swarmpath.bench.sweep.suite import SuiteError, builtin_suites, load_suite, suite_json_schema
from swarmpath.data.movingai import MOVINGAI

ROOT = Path(__file__).parents[2]


def write(tmp_path: Path, text: str, name: str = "suite.yaml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def test_the_documented_form_loads_with_files_relative_to_the_suite(tmp_path: Path) -> None:
    (tmp_path / "worlds").mkdir()
    (tmp_path / "maps").mkdir()
    (tmp_path / "worlds" / "warehouse.yaml").write_text(
        "schema_version: 1\nname: warehouse\nbounds: {type: rectangle, width: 10, height: 10}\n"
        "robots:\n  - {start: [1.5, 1.5], goal: [8.5, 8.5]}\n  - {start: [8.5, 1.5], goal: [1.5, 8.5]}\n")
    for f in ("random-32-32-10.map", "random-32-32-10-random-1.scen"):
        (tmp_path / "maps" / f).write_bytes((MOVINGAI / f).read_bytes())
    p = write(tmp_path, """\
name: my-sweep
scenarios:
  - jaleel2016                      # a built-in name
  - worlds/warehouse.yaml           # a file, relative to the suite file
  - {map: maps/random-32-32-10.map, scen: maps/random-32-32-10-random-1.scen, agents: [25, 50, 100]}
planners: [none, astar]
controllers: [cat-swarm, {name: pso-predictive, params: {swarm: {n_particles: 10}}}]
seeds: [0, 1, 2]                    # or {count: 10}
max_steps: 500
timeout_s: 60                       # per job
""")
    suite = load_suite(p)
    assert suite.name == "my-sweep" and suite.seeds() == [0, 1, 2]
    e = expand(suite)
    scenarios = {j.scenario for j in e.jobs}
    assert scenarios == {"jaleel2016", "warehouse", "random-32-32-10"}
    assert sorted({j.n_agents for j in e.jobs if j.scenario == "random-32-32-10"}) == [25, 50, 100]
    assert {(j.planner, j.controller) for j in e.jobs} <= {(p, c) for p in ("none", "astar")
                                                          for c in ("cat-swarm", "pso-predictive")}
    pso = [j for j in e.jobs if j.controller == "pso-predictive"]
    assert pso and all(j.controller_params == {"swarm": {"n_particles": 10}} for j in pso)
    # jaleel2016's point robots suit cat-swarm; nothing is skipped for it
    assert {j.controller for j in e.jobs if j.scenario == "jaleel2016"} == {"cat-swarm", "pso-predictive"}


def test_seed_count_and_agent_ranges(tmp_path: Path) -> None:
    p = write(tmp_path, "name: s\nscenarios:\n  - {map: empty-8-8.map, scen: empty-8-8-even-10.scen, "
                        "agents: {from: 4, to: 12, step: 4}, first_row: 2}\ncontrollers: [pibt]\n"
                        "seeds: {count: 3, start: 5}\n")
    suite = load_suite(p)
    assert suite.seeds() == [5, 6, 7]
    e = expand(suite)
    assert sorted({j.n_agents for j in e.jobs}) == [4, 8, 12] and len(e.jobs) == 9


@pytest.mark.parametrize("name", sorted(builtin_suites()))
def test_every_builtin_suite_loads_and_expands(name: str) -> None:
    e = expand(load_suite(name))
    assert len(e.jobs) >= 100
    assert len({j.key for j in e.jobs}) == len(e.jobs)


def test_builtin_suites_are_the_issue_s_four() -> None:
    assert set(builtin_suites()) == {"mapf-static", "dynamic", "crowd", "papers"}


BAD = [
    ("name: s\nscenarios: [karim2014]\ncontrolers: [pibt]\n", "controlers", "unknown field"),
    ("scenarios: [karim2014]\n", "name", "required field is missing"),
    ("name: s\nscenarios: [karim2014]\ncontrollers: [pibbt]\n", "controllers[0]", "unknown controller 'pibbt'"),
    ("name: s\nscenarios: [karim2014]\ncontrollers: [{name: pso-predictive, params: {particlez: 3}}]\n",
     "controllers[0].params", "unknown parameter 'particlez' of controller pso-predictive"),
    ("name: s\nscenarios: [karim2014]\ncontrollers: [{name: pso-predictive, params: {sensing_factor: 0.5}}]\n",
     "controllers[0].params", "sensing_factor"),
    ("name: s\nscenarios: [karim2014]\ncontrollers: [{name: pso-predictive, params: {swarm: {particles: 3}}}]\n",
     "controllers[0].params", "swarm (n_particles"),
    ("name: s\nscenarios: [nowhere.yaml]\ncontrollers: [pibt]\n", "scenarios[0]", "no such scenario file"),
    ("name: s\nscenarios:\n  - {map: empty-8-8.map, scen: empty-8-8-even-10.scen, agents: [50]}\n"
     "controllers: [pibt]\n", "scenarios[0].agents", "has 32 rows"),
    ("name: s\nscenarios:\n  - {map: empty-8-8.map}\ncontrollers: [pibt]\n", "scenarios[0].scen", "map goes with scen"),
    ("name: s\nscenarios:\n  - {scenario: karim2014, agents: [3]}\ncontrollers: [pibt]\n", "scenarios[0].agents",
     "only used with map"),
    ("name: s\nscenarios:\n  - {generator: antipodal, params: {n: 4, size: 3}}\ncontrollers: [orca]\n",
     "scenarios[0].params.size", "unknown parameter"),
    ("name: s\nscenarios:\n  - {generator: spiral}\ncontrollers: [orca]\n", "scenarios[0].generator",
     "unknown generator"),
    ("name: s\nscenarios: [karim2014]\ncontrollers: [pibt]\nmethods: [{controller: pibt}]\n", "methods",
     "give controllers or methods, not both"),
    ("name: s\nscenarios: [karim2014]\ncontrollers: [pibt]\nseeds: [1, 1]\n", "seeds", "a seed appears twice"),
    ("name: s\nscenarios: [karim2014]\ncontrollers: [pibt]\nseeds: {count: 0}\n", "seeds.count", "greater than"),
    ("name: s\nscenarios: [karim2014]\ncontrollers: [pibt]\ntimeout_s: -1\n", "timeout_s", "greater than 0"),
    ("name: s\nscenarios: [karim2014]\ncontrollers: [pibt]\nmax_steps: true\n", "max_steps", "integer"),
    ("name: s\nname: t\nscenarios: [karim2014]\n", "", "appears twice"),
    ("a: &a [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a, *a]\n"
     "c: &c [*b, *b, *b, *b, *b, *b, *b, *b, *b, *b]\nd: &d [*c, *c, *c, *c, *c, *c, *c, *c, *c, *c]\n"
     "e: &e [*d, *d, *d, *d, *d, *d, *d, *d, *d, *d]\nf: &f [*e, *e, *e, *e, *e, *e, *e, *e, *e, *e]\n"
     "g: &g [*f, *f, *f, *f, *f, *f, *f, *f, *f, *f]\n", "", "aliases are expanded"),
    ("- just\n- a list\n", "", "must be a mapping"),
    ("name: s\nscenarios: [karim2014]\npeers: [pymapf-cbs]\n", "peers[0]", "unknown peer"),
    ("name: s\nscenarios: [karim2014]\n", "controllers", "the suite runs nothing"),
]


@pytest.mark.parametrize("text, field, words", BAD, ids=[f"{b[1] or 'document'}-{k}" for k, b in enumerate(BAD)])
def test_bad_suites_are_one_clear_error(tmp_path: Path, text: str, field: str, words: str) -> None:
    p = write(tmp_path, text)
    with pytest.raises(SuiteError) as info:
        expand(load_suite(p))
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(str(p)), message
    if field:
        assert f": {field}: " in message, message
    assert words in message, message


def test_the_command_line_says_it_in_one_line_with_exit_code_2(tmp_path: Path) -> None:
    p = write(tmp_path, BAD[2][0])
    r = swarmpath("bench", str(p), "--store", str(tmp_path / "r.db"), "--workers", "1")
    assert r.returncode == 2, r.stderr
    lines = [x for x in r.stderr.splitlines() if x.strip()]
    assert len(lines) == 1 and "controllers[0]" in lines[0] and "suite.yaml" in lines[0], r.stderr
    assert not (tmp_path / "r.db").exists()          # nothing made before the suite is known to be good
    r = swarmpath("bench", str(tmp_path / "missing.yaml"), "--store", str(tmp_path / "r.db"))
    assert r.returncode == 2 and "no such file, and no built-in suite" in r.stderr


def test_committed_json_schema_is_generated_from_the_model() -> None:
    committed = json.loads((ROOT / "docs" / "suite.schema.json").read_text())
    assert committed == suite_json_schema(), "run: python docs/regenerate.py"
