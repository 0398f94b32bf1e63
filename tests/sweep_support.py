"""What the sweep tests (tests/sweep/) share: the command line in a subprocess, and the
200-job acceptance suite (mixed grid and continuous worlds, some jobs failing on purpose)."""
from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

#: 200 tiny jobs: grid worlds with and without moving obstacles, continuous disc worlds, a
#: crowd whose layout follows the seed; failing on purpose: a parameter the controller refuses
#: when it starts (status error), a plan followed blindly into collisions, a step budget too
#: short to arrive.
ACCEPTANCE_SUITE = """\
name: acceptance-200
description: mixed grid and continuous jobs, some failing on purpose
scenarios:
  - scenario: karim2014                       # grid, 10 moving obstacles
    controllers: [fish-swarm, pibt, orca, cat-swarm]
  - scenario: karim2014                       # error: cat-swarm refuses this parameter when it starts
    name: karim2014-bad-parameter
    controllers: [{name: cat-swarm, params: {mixture_ratio: 2.0}}]
  - scenario: karim2014                       # a plan followed blindly runs into moving obstacles
    name: karim2014-blind
    methods: [{planner: astar, controller: follow}]
  - map: empty-8-8.map                        # grid, static: astar + follow collides on purpose
    scen: empty-8-8-even-10.scen
    agents: [4, 8]
    methods:
      - {planner: lacam, controller: follow}
      - {planner: none, controller: pibt}
      - {planner: astar, controller: follow}
  - map: random-32-32-10.map
    scen: random-32-32-10-random-1.scen
    agents: [10, 20]
    methods: [{controller: pibt}]
  - generator: antipodal                      # continuous discs
    params: {n: [4, 6]}
  - generator: antipodal
    name: antipodal-pso
    params: {n: 4}
    controllers: [pso-reactive]
  - generator: antipodal                      # 5 steps cannot bring anyone home
    name: antipodal-short
    params: {n: 4}
    max_steps: 5
  - generator: crowd-crossing                 # one robot among moving discs, a layout per seed
    params: {n_obstacles: 3}
  - generator: antipodal
    name: antipodal-obstacles
    params: {n: 4}
    obstacles: {motion: bounce, count: 2}
planners: [none]
controllers: [orca]
seeds: {count: 10}
max_steps: 80
timeout_s: 120
"""

TINY_SUITE = "name: tiny\nscenarios: [karim2014]\nplanners: [none]\ncontrollers: [fish-swarm]\nseeds: [0, 1]\n" \
             "max_steps: 100\ntimeout_s: 60\n"


def swarmpath_argv() -> list[str]:
    exe = shutil.which("swarmpath", path=str(Path(sys.executable).parent))
    return [exe] if exe else [sys.executable, "-m", "swarmpath.cli"]


def swarmpath(*args: str, cwd: Path | None = None, timeout: float = 600) -> subprocess.CompletedProcess:
    return subprocess.run([*swarmpath_argv(), *args], capture_output=True, text=True, timeout=timeout, cwd=cwd)
