"""The simulator, sensing, the independent collision checker and trajectories."""
from swarmpath.sim.collisions import Contact, step_contacts
from swarmpath.sim.observation import Observation
from swarmpath.sim.run import RunResult, choose_pair, run_world, simulate
from swarmpath.sim.sensing import SensingConfig
from swarmpath.sim.simulator import Simulator, default_max_steps
from swarmpath.sim.trajectory import Trajectory

__all__ = ["Contact", "step_contacts", "Observation", "RunResult", "choose_pair", "run_world", "simulate",
           "SensingConfig", "Simulator", "default_max_steps", "Trajectory"]
