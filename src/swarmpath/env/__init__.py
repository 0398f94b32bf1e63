"""Learning environments over the simulator: a PettingZoo Parallel environment with one agent
per robot (:func:`parallel_env`) and the Gymnasium single-robot environment
``swarmpath/Navigate-v0`` (:class:`NavigateEnv`); experts from any registered controller.

gymnasium and pettingzoo (the ``[env]`` extra) are imported only when an environment is
built: ``import swarmpath.env`` stays light. When gymnasium is already imported, importing
this package registers ``swarmpath/Navigate-v0``; :func:`register_envs` does it at any time.
"""
from __future__ import annotations

import importlib
import sys
from typing import Any

_LAZY = {
    "parallel_env": "swarmpath.env.parallel",
    "SwarmpathParallelEnv": "swarmpath.env.parallel",
    "NavigateEnv": "swarmpath.env.navigate",
    "register_envs": "swarmpath.env.registration",
    "ENV_ID": "swarmpath.env.registration",
    "EnvOptions": "swarmpath.env.options",
    "Rewards": "swarmpath.env.options",
    "WorldStepper": "swarmpath.sim.stepper",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        try:
            module = importlib.import_module(_LAZY[name])
        except ModuleNotFoundError as exc:
            if exc.name in ("gymnasium", "pettingzoo"):
                raise ImportError(f"swarmpath.env.{name} needs {exc.name}: pip install 'swarmpath[env]'") from None
            raise
        return getattr(module, name)
    raise AttributeError(f"module 'swarmpath.env' has no attribute {name!r}")


__all__ = sorted(_LAZY)

if sys.modules.get("gymnasium") is not None:
    from swarmpath.env.registration import register_envs as _register

    _register()
