"""The layers of the package hold: no module imports one from a higher layer, and no two
modules import each other in a circle. Every import counts: inside functions and under
``if TYPE_CHECKING:`` too. (docs/architecture.md describes the layers.)"""
from __future__ import annotations

import ast
from pathlib import Path

import swarmpath

ROOT = Path(swarmpath.__file__).parent
#: Lower number = lower layer; a module may import from its own layer or below.
LAYERS = {
    "errors": 0, "types": 0, "rng": 0, "registry": 0, "capabilities": 0, "data": 0,
    "world": 1,
    "search": 2, "optim": 2, "perception": 2,
    "planning": 3, "control": 3,
    "sim": 4,
    "metrics": 5,
    "runner": 6, "viz": 6, "testing": 6, "env": 6,
    "bench": 7, "cli": 7, "__main__": 7,
}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in ROOT.rglob("*.py")}


def imports_of(name: str, path: Path, known: set[str]) -> set[str]:
    """swarmpath modules imported by one module (names resolved to the longest known module)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            candidates = [target] + [f"{target}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            candidates = [a.name for a in node.names]
        else:
            continue
        for c in candidates:
            while c and c not in known:
                c = c.rpartition(".")[0]
            if c.startswith("swarmpath") and c != name:
                found.add(c)
    return found


def layer(name: str) -> int | None:
    parts = name.split(".")
    return LAYERS.get(parts[1]) if len(parts) > 1 else None


def graph() -> dict[str, set[str]]:
    mods = modules()
    return {name: imports_of(name, path, set(mods)) for name, path in mods.items()}


def test_every_top_level_module_has_a_layer() -> None:
    tops = {name.split(".")[1] for name in modules() if "." in name}
    assert tops <= set(LAYERS), sorted(tops - set(LAYERS))


def test_no_module_imports_from_a_higher_layer() -> None:
    upward = [f"{a} -> {b}" for a, deps in graph().items() for b in deps
              if layer(a) is not None and layer(b) is not None and layer(b) > layer(a)]
    assert upward == []


def test_no_import_cycles() -> None:
    g = graph()
    # a package's __init__ re-exporting its children is not a cycle
    edges = {a: {b for b in deps if not a.startswith(b + ".")} for a, deps in g.items()
             if not str(modules()[a]).endswith("__init__.py")}
    edges = {a: {b for b in deps if b in edges} for a, deps in edges.items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []

    def visit(v: str) -> None:   # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    assert cycles == []


def test_the_check_sees_an_upward_import(tmp_path: Path) -> None:
    """The walker finds imports inside functions and under TYPE_CHECKING."""
    f = tmp_path / "m.py"
    f.write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from swarmpath.sim import trajectory\n"
                 "def f():\n    from swarmpath.runner import run_world\n")
    known = set(modules())
    found = imports_of("swarmpath.world.m", f, known)
    assert {"swarmpath.sim.trajectory", "swarmpath.runner"} <= found
    assert any(layer(b) > layer("swarmpath.world.m") for b in found)
