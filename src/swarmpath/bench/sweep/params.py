"""Constructor parameters from a suite file: ``construct(cls, params)`` is ``cls(**params)``,
except that a mapping given for a parameter whose declared type is a dataclass becomes that
dataclass (``pso-predictive``'s ``swarm: {n_particles: 10}`` is a ``SwarmSettings``), at any
depth. A suite file can then set every parameter a constructor takes, in plain YAML.
"""
from __future__ import annotations

import dataclasses
import typing
from typing import Any


def _hints(target: Any) -> dict[str, Any]:
    init = target.__init__ if isinstance(target, type) else target
    try:
        return typing.get_type_hints(init)
    except Exception:   # noqa: BLE001 - an annotation that does not resolve is just not a dataclass
        return {}


def _dataclass_of(annotation: Any) -> type | None:
    """The dataclass an annotation names (``X``, ``X | None``, ``Optional[X]``), or None."""
    if isinstance(annotation, type) and dataclasses.is_dataclass(annotation):
        return annotation
    for arg in typing.get_args(annotation):
        if isinstance(arg, type) and dataclasses.is_dataclass(arg):
            return arg
    return None


def construct(cls: Any, params: dict[str, Any]) -> Any:
    """``cls(**params)`` with mappings turned into the dataclasses the constructor declares."""
    hints = _hints(cls)
    kwargs = {}
    for name, value in params.items():
        target = _dataclass_of(hints.get(name))
        kwargs[name] = construct(target, value) if target is not None and isinstance(value, dict) else value
    return cls(**kwargs)


def describe(cls: Any) -> str:
    """The keyword parameters ``cls`` takes, a dataclass parameter with its fields:
    ``eps, swarm (n_particles, n_iterations, ...)``."""
    import inspect

    try:
        sig = inspect.signature(cls)
    except (TypeError, ValueError):
        return "unknown"
    hints = _hints(cls)
    out = []
    for p in sig.parameters.values():
        if p.kind not in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD) or p.name == "self":
            continue
        target = _dataclass_of(hints.get(p.name))
        fields = f" ({', '.join(f.name for f in dataclasses.fields(target))})" if target is not None else ""
        out.append(p.name + fields)
    return ", ".join(out) or "none"
