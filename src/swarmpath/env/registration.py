"""Registration of ``swarmpath/Navigate-v0`` with Gymnasium (imports gymnasium)."""
from __future__ import annotations

ENV_ID = "swarmpath/Navigate-v0"


def register_envs() -> None:
    """Register ``swarmpath/Navigate-v0`` (once; later calls do nothing). ``import
    swarmpath.env`` calls it when gymnasium is already imported, and so does building any
    swarmpath environment."""
    import gymnasium

    if ENV_ID not in gymnasium.registry:
        gymnasium.register(id=ENV_ID, entry_point="swarmpath.env.navigate:NavigateEnv")
