"""The simulator, sensing, the independent collision checker and trajectories."""
from swarmpath.sim.collisions import Contact, step_contacts
from swarmpath.sim.simulator import Simulator, default_max_steps
from swarmpath.sim.trajectory import Termination, Trajectory

__all__ = ["Contact", "step_contacts", "Simulator", "default_max_steps", "Termination", "Trajectory"]
