"""The jobs of a suite: the product of its worlds, planner/controller pairs (and peers) and
seeds, each with a stable key; pairs that cannot run together are skipped and listed.

A job's key is the SHA-256 of its resolved inputs (the world's identity, with files named by
their content hash; planner and controller with their parameters, or the peer with its
package's version; the seed; the step budget) and swarmpath's version. The per-job time
limit is not part of it: it bounds the work, it does not change a result.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from swarmpath.bench.sweep.suite import MAX_JOBS, Suite, SuiteError, named
from swarmpath.bench.sweep.worlds import Instance, build_world, digest, instances
from swarmpath.errors import ConfigError, SwarmpathError

#: The ``planner`` column of a peer's jobs (a peer plans and executes by itself).
PEER_PLANNER = "-"


@dataclass(frozen=True)
class Job:
    """One run: everything a worker needs (picklable, plain data) and the columns the store
    keeps about its inputs."""

    key: str
    suite: str
    scenario: str
    detail: str
    spec: dict[str, Any]
    world_key: str
    seeded_world: bool
    n_agents: int
    n_moving: int
    motion: str
    planner: str
    planner_params: dict[str, Any]
    controller: str
    controller_params: dict[str, Any]
    peer: bool
    seed: int
    max_steps: int | None
    timeout_s: float
    cost: float = 1.0

    @property
    def method(self) -> str:
        """``planner+controller`` with parameters, or the peer's name: one label per method."""
        ctrl = self.controller + _params_text(self.controller_params)
        if self.peer:
            return ctrl
        return f"{self.planner}{_params_text(self.planner_params)}+{ctrl}"


def _params_text(params: dict[str, Any]) -> str:
    if not params:
        return ""
    return "(" + ",".join(f"{k}={params[k]}" for k in sorted(params)) + ")"


@dataclass(frozen=True)
class Skipped:
    """A planner/controller pair (or a peer) that cannot run on a world, and why."""

    scenario: str
    detail: str
    planner: str
    controller: str
    reason: str
    n_jobs: int


@dataclass(frozen=True)
class Expansion:
    """The jobs of a suite (in a stable order) and the pairs skipped."""

    jobs: list[Job]
    skipped: list[Skipped] = field(default_factory=list)


def incompatible(world: Any, planner: str, controller: str) -> str | None:
    """Why ``planner`` + ``controller`` cannot run on ``world`` (None when they can): the
    runner's pairing rule (a controller that needs a plan needs a planner) and, for grid
    controllers, the grid robots' rule (reach a neighbouring cell centre in one step, be at
    most half a cell wide)."""
    from swarmpath.control.grid_robots import check_grid_robots
    from swarmpath.registry import CONTROLLERS
    from swarmpath.runner import choose_pair

    try:
        choose_pair(world, planner, controller)
        if CONTROLLERS.get(controller).capabilities.grid_based:
            check_grid_robots(world, controller)
    except ConfigError as exc:
        return str(exc)
    return None


def _motion(world: Any) -> str:
    names = sorted({getattr(ob.motion, "registered_name", "") or type(ob.motion).__name__.lower()
                    for ob in world.moving_obstacles})
    return ",".join(names)


def pairs(suite: Suite, inst: Instance) -> list[tuple[Any, Any]]:
    """The planner/controller pairs of one world: the entry's ``methods``, else its (or the
    suite's) planners x controllers, else the suite's ``methods``."""
    m, o = suite.model, inst.overrides
    if "methods" in o:
        return [(p.planner, p.controller) for p in o["methods"]]
    if "planners" in o or "controllers" in o or m.methods is None:
        return [(p, c) for p in o.get("planners", m.planners) for c in o.get("controllers", m.controllers)]
    return [(p.planner, p.controller) for p in m.methods]


def expand(suite: Suite) -> Expansion:
    """All jobs of ``suite``; raises :class:`SuiteError` (naming the suite file and the
    entry) for a file that is missing or a world that cannot be built."""
    try:
        return _expand(suite)
    except SuiteError as exc:
        raise exc.with_source(suite.source) from None


def _expand(suite: Suite) -> Expansion:
    from swarmpath import __version__
    from swarmpath.bench.sweep.params import construct
    from swarmpath.bench.sweep.peers import PEERS
    from swarmpath.sim.simulator import default_max_steps

    m = suite.model
    seeds = suite.seeds()
    jobs: dict[str, Job] = {}
    skipped: list[Skipped] = []
    for inst in instances(suite):
        where = f"scenarios[{inst.entry}]"
        try:
            world = build_world(inst.spec, seeds[0])
        except SwarmpathError as exc:
            raise SuiteError(f"{inst.detail}: {exc}", field=where) from None
        max_steps = inst.overrides.get("max_steps", m.max_steps)
        budget = max_steps or default_max_steps(world)
        common = dict(suite=m.name, scenario=inst.label, detail=inst.detail, spec=inst.spec,
                      world_key=inst.world_key, seeded_world=inst.seeded, n_agents=world.n_robots,
                      n_moving=len(world.moving_obstacles), motion=_motion(world), max_steps=max_steps,
                      timeout_s=m.timeout_s, cost=float(max(1, world.n_robots) * budget))
        for p_item, c_item in pairs(suite, inst):
            planner, p_params = named(p_item)
            controller, c_params = named(c_item)
            reason = incompatible(world, planner, controller)
            if reason is not None:
                skipped.append(Skipped(inst.label, inst.detail, planner, controller, reason, len(seeds)))
                continue
            for seed in seeds:
                ident = {"swarmpath": __version__, "world": inst.identity, "planner": [planner, p_params],
                         "controller": [controller, c_params], "seed": seed, "max_steps": max_steps}
                key = digest(ident)
                jobs.setdefault(key, Job(key=key, planner=planner, planner_params=p_params, controller=controller,
                                         controller_params=c_params, peer=False, seed=seed, **common))
                _check_size(len(jobs))
        for peer_item in inst.overrides.get("peers", m.peers):
            name, params = named(peer_item)
            peer = construct(PEERS[name], params)
            reason = peer.supports(world)
            if reason is None:
                reason = peer.missing()
            if reason is not None:
                skipped.append(Skipped(inst.label, inst.detail, PEER_PLANNER, name, reason, len(seeds)))
                continue
            for seed in seeds:
                ident = {"swarmpath": __version__, "world": inst.identity, "peer": [name, params, peer.version()],
                         "seed": seed, "max_steps": max_steps}
                key = digest(ident)
                jobs.setdefault(key, Job(key=key, planner=PEER_PLANNER, planner_params={}, controller=name,
                                         controller_params=params, peer=True, seed=seed, **common))
                _check_size(len(jobs))
    return Expansion(list(jobs.values()), skipped)


def _check_size(n: int) -> None:
    if n > MAX_JOBS:
        raise SuiteError(f"the suite expands to more than {MAX_JOBS:,} jobs; split it", field="scenarios")


def schedule(jobs: list[Job]) -> list[Job]:
    """The order jobs are handed out: the costliest first (so the last jobs to finish are
    short and the workers end together), then by world (a worker reuses a world it built)."""
    return sorted(jobs, key=lambda j: (-j.cost, j.world_key, j.seed, j.key))


__all__ = ["Expansion", "Instance", "Job", "PEER_PLANNER", "Skipped", "expand", "incompatible", "schedule"]
