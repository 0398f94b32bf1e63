"""swarmpath: plan, simulate, compare and visualise many robots with swarm intelligence.

Heavy subpackages are imported lazily, so ``import swarmpath`` stays fast.
"""
from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

_SUBPACKAGES = {"world", "search", "optim", "planning", "control", "sim", "metrics", "runner", "viz",
                "bench", "testing", "env"}
_SHORTCUTS = {
    "World": "swarmpath.world",
    "load_scenario": "swarmpath.world",
    "SwarmpathError": "swarmpath.errors",
    "run_world": "swarmpath.runner",
    "simulate": "swarmpath.runner",
}


def __getattr__(name: str) -> Any:
    if name in _SUBPACKAGES:
        return importlib.import_module(f"swarmpath.{name}")
    if name in _SHORTCUTS:
        return getattr(importlib.import_module(_SHORTCUTS[name]), name)
    raise AttributeError(f"module 'swarmpath' has no attribute {name!r}")


__all__ = sorted(_SUBPACKAGES | set(_SHORTCUTS) | {"__version__"})
