"""Measures of plans and runs: lengths, times, success, collisions, clearance (plain functions)."""
from swarmpath.metrics.paths import arrival_steps, at_goal, executed_lengths, path_length, waiting_steps

__all__ = ["arrival_steps", "at_goal", "executed_lengths", "path_length", "waiting_steps"]
