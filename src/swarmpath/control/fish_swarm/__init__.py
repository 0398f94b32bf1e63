"""Artificial fish swarm path planning among moving obstacles (Karim 2014): the behaviours
(:mod:`.behaviours`, Algorithm 1 as pure functions) and the ``fish-swarm`` controller
(:mod:`.controller`)."""
from swarmpath.control.fish_swarm.behaviours import (NEIGHBOURS, fish_decision, follow_choice, food_euclidean,
                                                     food_from_field, not_crowded, prey_choice, select_behaviour,
                                                     swarm_choice, visible_fish)
from swarmpath.control.fish_swarm.controller import FishSwarmController

__all__ = ["FishSwarmController", "food_euclidean", "food_from_field", "visible_fish", "select_behaviour",
           "not_crowded", "prey_choice", "follow_choice", "swarm_choice", "fish_decision", "NEIGHBOURS"]
