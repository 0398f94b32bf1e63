"""Motion models of moving obstacles: one module each, registered by name
(:data:`swarmpath.registry.MOTIONS`); a new model is one new module here (see
:mod:`swarmpath.world.motions.base` for the protocol)."""
from swarmpath.world.motions.base import FORECASTS, Motion, StepContext
from swarmpath.world.motions.bounce import Bounce
from swarmpath.world.motions.bounce8 import Bounce8
from swarmpath.world.motions.random_walk import RandomWalk
from swarmpath.world.motions.redraw import Redraw
from swarmpath.world.motions.turn_every import TurnEvery
from swarmpath.world.motions.waypoints import Waypoints

__all__ = ["FORECASTS", "Motion", "StepContext", "Bounce", "Bounce8", "RandomWalk", "Redraw", "TurnEvery", "Waypoints"]


def motions_markdown() -> str:
    """The list of registered motion models for docs/scenarios.md, from each model's module
    docstring (first paragraph) and declared parameters: the docs regenerate from the
    registry, and a test keeps the committed page in sync."""
    import sys
    import textwrap

    from swarmpath.registry import MOTIONS

    lines = []
    for name, cls in MOTIONS.items():
        doc = (sys.modules[cls.__module__].__doc__ or "").strip().split("\n\n")[0]
        text = " ".join(doc.split()).replace("``", "`")
        prefix = f"`{name}`:"
        text = text[len(prefix):].strip() if text.startswith(prefix) else text
        params = ", ".join(f"`{p}`" for p in cls.parameters)
        item = f"- `{name}`{f' (with {params})' if params else ''}: {text}"
        lines.append(textwrap.fill(item, width=96, subsequent_indent="  "))
    return "\n".join(lines)
