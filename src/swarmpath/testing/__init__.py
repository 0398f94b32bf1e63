"""Public validators and conformance checks (users run them on their own plug-ins too)."""
from swarmpath.testing.conformance import check_controller, check_planner, conformance_worlds, unreachable_world
from swarmpath.testing.timed_plans import validate_timed_plan
from swarmpath.testing.validators import Violation, validate_paths, validate_trajectory

__all__ = ["check_controller", "check_motion", "check_optimizer", "check_planner", "conformance_worlds",
           "unreachable_world", "Violation", "validate_paths", "validate_timed_plan", "validate_trajectory"]


def __getattr__(name: str):
    # the optimiser checks live beside the optimisers; imported on first use to keep this light
    if name == "check_optimizer":
        from swarmpath.optim.conformance import check_optimizer

        return check_optimizer
    if name == "check_motion":
        from swarmpath.testing.motions import check_motion

        return check_motion
    raise AttributeError(f"module 'swarmpath.testing' has no attribute {name!r}")
