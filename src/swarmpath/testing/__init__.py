"""Public validators and conformance checks (users run them on their own plug-ins too)."""
from swarmpath.testing.conformance import check_controller, check_planner, conformance_worlds, unreachable_world
from swarmpath.testing.validators import Violation, validate_paths, validate_trajectory

__all__ = ["check_controller", "check_planner", "conformance_worlds", "unreachable_world", "Violation",
           "validate_paths", "validate_trajectory"]
