"""Random and expert rollouts through the PettingZoo environment: success rates, contacts, an
imitation data set's size, and an HTML replay of one expert episode.

    python examples/env_rollouts.py [OUT_DIR]

Needs the [env] extra (gymnasium, pettingzoo).
"""
import sys
import tempfile
from pathlib import Path

import numpy as np

from swarmpath.env import parallel_env
from swarmpath.testing import validate_trajectory
from swarmpath.viz.html_replay import write_replay_html

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="swarmpath-env-"))
out.mkdir(parents=True, exist_ok=True)
SEEDS = (0, 1, 2)


def rollout(env, seed, expert=None, dataset=None):
    """One episode: masked random actions, or the expert's. Returns (share of robots on their
    goals at the end, contacts, trajectory)."""
    obs, infos = env.reset(seed=seed)
    for k, agent in enumerate(env.possible_agents):
        env.action_space(agent).seed(1000 * seed + k)
    while env.agents:
        if expert is None:
            masked = env.mode == "grid"
            actions = {a: env.action_space(a).sample(mask=infos[a]["action_mask"]) if masked
                       else env.action_space(a).sample() for a in env.agents}
        else:
            actions = env.expert_actions(expert)
            if dataset is not None:                  # (observation, expert action) pairs
                dataset.extend((obs[a], actions[a]) for a in env.agents)
        obs, rewards, terminated, truncated, infos = env.step(actions)
    traj = env.trajectory()
    at_goal = np.linalg.norm(traj.positions[-1] - traj.goals, axis=1) <= 1e-9
    return at_goal.mean(), len(traj.contacts), traj


# stay_arrived: robots stay agents after they arrive, so an expert may move one out of another's
# way (as in `swarmpath run`); the episode ends when all stand on their goals, or at max_steps
grid = parallel_env("random-32-32-10.map", scen="random-32-32-10-random-1.scen", agents=16, max_steps=150,
                    stay_arrived=True)
continuous = parallel_env("prediction2013", max_steps=150, stay_arrived=True)
dataset = []
best = None
for name, env, experts in (("grid random-32-32-10, 16 robots", grid, ("pibt", "cat-swarm")),
                           ("continuous prediction2013, 6 robots", continuous, ("orca",))):
    print(f"{name}:")
    for expert in (None, *experts):
        results = [rollout(env, seed, expert, dataset if expert == "pibt" else None) for seed in SEEDS]
        success = np.mean([r[0] for r in results])
        contacts = sum(r[1] for r in results)
        print(f"  {expert or 'random':>10}: success rate {success:.0%} over {len(SEEDS)} seeds, "
              f"{contacts} contacts")
        if expert == "pibt":
            best = results[0][2]

world = grid.world
print(f"imitation data: {len(dataset)} (observation, expert action) pairs from pibt")
print("expert episode re-checked:", "no violations" if not validate_trajectory(world, best) else "violations")
page = write_replay_html(best, out / "expert-replay.html")
print(f"replay written: {page}")
