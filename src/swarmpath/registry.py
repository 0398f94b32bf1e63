"""Name -> implementation registries used by the CLI, the benchmarks, the tests and plug-ins.

``@PLANNERS.register("astar")`` on a class makes it available as ``--planner astar``. Built-in
entries live in the modules of one package (every non-private submodule is imported on first
lookup, so a new module registers itself without editing any list); third-party plug-ins
register through the entry-point group ``swarmpath.<kind>``.
"""
from __future__ import annotations

import importlib
import pkgutil
from dataclasses import dataclass, field
from importlib.metadata import entry_points
from typing import Any, Callable, Generic, Iterator, TypeVar

from swarmpath.errors import UnknownNameError

T = TypeVar("T")


@dataclass
class Registry(Generic[T]):
    """Holds the named entries of one kind (``planner``, ``controller``, ...)."""

    kind: str
    package: str
    _entries: dict[str, T] = field(default_factory=dict)
    _loaded: bool = False

    def register(self, name: str) -> Callable[[T], T]:
        """Decorator registering its target under ``name`` (names are unique per kind)."""

        def decorate(obj: T) -> T:
            existing = self._entries.get(name)
            if existing is not None and existing is not obj:
                raise ValueError(f"{self.kind} {name!r} is registered twice")
            self._entries[name] = obj
            try:
                obj.registered_name = name  # type: ignore[attr-defined]
            except (AttributeError, TypeError):
                pass
            return obj

        return decorate

    def _load(self) -> None:
        if self._loaded:
            return
        self._loaded = True
        pkg = importlib.import_module(self.package)
        for info in pkgutil.iter_modules(getattr(pkg, "__path__", [])):
            if not info.name.startswith("_"):
                importlib.import_module(f"{self.package}.{info.name}")
        for ep in entry_points(group=f"swarmpath.{self.kind}s"):
            self.register(ep.name)(ep.load())

    def get(self, name: str) -> T:
        """The entry called ``name``; an unknown name raises with the list of known ones."""
        self._load()
        try:
            return self._entries[name]
        except KeyError:
            known = ", ".join(sorted(self._entries)) or "none"
            raise UnknownNameError(f"unknown {self.kind} {name!r}; choose from: {known}") from None

    def names(self) -> list[str]:
        """Registered names, sorted."""
        self._load()
        return sorted(self._entries)

    def items(self) -> Iterator[tuple[str, T]]:
        self._load()
        return iter(sorted(self._entries.items()))

    def __contains__(self, name: object) -> bool:
        self._load()
        return name in self._entries


PLANNERS: Registry[Any] = Registry("planner", "swarmpath.planning")
CONTROLLERS: Registry[Any] = Registry("controller", "swarmpath.control")
OPTIMIZERS: Registry[Any] = Registry("optimizer", "swarmpath.optim")
FUNCTIONS: Registry[Any] = Registry("function", "swarmpath.optim")
REPRODUCTIONS: Registry[Any] = Registry("reproduction", "swarmpath.bench")
MOTIONS: Registry[Any] = Registry("motion", "swarmpath.world.motions")

register_planner = PLANNERS.register
register_controller = CONTROLLERS.register
register_optimizer = OPTIMIZERS.register
register_function = FUNCTIONS.register
register_reproduction = REPRODUCTIONS.register
register_motion = MOTIONS.register
