"""Online controllers: per-step policies that move the robots (registered by name)."""
from swarmpath.control.base import Controller, Decision

__all__ = ["Controller", "Decision"]
