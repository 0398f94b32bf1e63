"""What one input may ask for, and how input is read so that it never asks for more.

Every file swarmpath reads goes through :func:`read_text_bounded` (at most a fixed number of
bytes, so ``/dev/zero`` or a huge file is refused instead of filling memory), every YAML or
JSON document through :func:`parse_document_bounded` (duplicate keys refused, alias bombs and
deep nesting refused before anything is built from them), and every value echoed in an error
message through :func:`preview` (short, one line, no control characters). The limits are
documented in docs/scenarios.md ("Limits").
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any, Callable

#: Largest scenario file (YAML/JSON), bytes.
MAX_SCENARIO_BYTES = 32 * 2**20
#: Largest MovingAI .map or .scen file, bytes (a 8192 x 8192 map is 64 MiB).
MAX_MAP_BYTES = 256 * 2**20
#: Most values (mappings, lists, scalars, aliases counted as what they expand to) in one document.
MAX_DOCUMENT_NODES = 2_000_000
#: Deepest nesting of lists and mappings in one document.
MAX_DOCUMENT_DEPTH = 64
#: Most grid cells of a world's occupancy grid (width x height at its resolution).
MAX_GRID_CELLS = 64 * 2**20
#: Most vertices of one polygon, and of all polygons of a world together.
MAX_POLYGON_POINTS = 10_000
MAX_TOTAL_POLYGON_POINTS = 100_000
#: Most static obstacles, moving obstacles and danger zones of a world (each).
MAX_SHAPES = 100_000
#: Most waypoints of one moving obstacle.
MAX_WAYPOINTS = 10_000
#: Largest absolute coordinate anywhere in a world (world units).
MAX_COORDINATE = 1e7

_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")


def preview(value: Any, limit: int = 60) -> str:
    """A short, one-line, printable rendering of ``value`` for an error message: control
    characters (newlines, ESC, NUL) shown as escapes, cut to ``limit`` characters."""
    text = value if isinstance(value, str) else repr(value)
    if len(text) > 4 * limit:
        text = text[:4 * limit]
    text = _CONTROL.sub(lambda m: m.group(0).encode("unicode_escape").decode("ascii"), text)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def clean_text(text: str) -> str:
    """``text`` with control characters (ESC, NUL, newlines, ...) replaced by spaces: names
    echoed to a terminal cannot move the cursor or split a line."""
    return _CONTROL.sub(" ", text)


def read_text_bounded(path: str | Path, what: str, limit: int, error: Callable[[str], Exception],
                      encoding: str = "utf-8") -> str:
    """The text of ``path``, refusing more than ``limit`` bytes; problems become
    ``error(message)`` with a message that names the file and ``what`` it should be."""
    p = Path(path)
    try:
        if p.is_dir():
            raise error(f"{preview(str(path), 200)}: is a folder, not a {what} file")
        with p.open("rb") as fh:
            data = fh.read(limit + 1)
    except FileNotFoundError:
        raise error(f"{preview(str(path), 200)}: no such {what} file") from None
    except PermissionError:
        raise error(f"{preview(str(path), 200)}: cannot read the {what} file (permission denied)") from None
    except OSError as exc:
        raise error(f"{preview(str(path), 200)}: cannot read the {what} file: {exc.strerror or exc}") from None
    if len(data) > limit:
        raise error(f"{preview(str(path), 200)}: larger than {limit // 2**20} MiB; not a {what} file swarmpath reads")
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        raise error(f"{preview(str(path), 200)}: not a text {what} file (byte {exc.start} is not "
                    f"{'ASCII' if encoding == 'ascii' else 'UTF-8'})") from None


class DocumentError(ValueError):
    """A document too large, too deep, with duplicate keys, or syntactically broken."""


def _check_json_shape(doc: Any) -> None:
    """Refuse a parsed JSON document with too many values or too deep a nesting."""
    count = 0
    stack = [(doc, 1)]
    while stack:
        value, depth = stack.pop()
        count += 1
        if count > MAX_DOCUMENT_NODES:
            raise DocumentError(f"more than {MAX_DOCUMENT_NODES:,} values")
        if depth > MAX_DOCUMENT_DEPTH:
            raise DocumentError(f"nested more than {MAX_DOCUMENT_DEPTH} levels deep")
        if isinstance(value, dict):
            stack.extend((v, depth + 1) for v in value.values())
        elif isinstance(value, list):
            stack.extend((v, depth + 1) for v in value)


def _unique_pairs(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise DocumentError(f"key {preview(key)!s} appears twice in one object")
        out[key] = value
    return out


def parse_json_bounded(text: str) -> Any:
    """Parse JSON: duplicate keys and over-large or over-deep documents refused
    (:class:`DocumentError` with a line number where there is one)."""
    try:
        doc = json.loads(text, object_pairs_hook=_unique_pairs, parse_constant=_refuse_constant)
    except json.JSONDecodeError as exc:
        raise DocumentError(f"line {exc.lineno}, column {exc.colno}: JSON syntax error: {exc.msg}") from None
    except RecursionError:
        raise DocumentError(f"nested more than {MAX_DOCUMENT_DEPTH} levels deep") from None
    _check_json_shape(doc)
    return doc


def _refuse_constant(name: str) -> float:
    raise DocumentError(f"{name} is not a number JSON allows")


_YAML_LOADER: Any = None
#: YAML 1.2 floats: also ``1e6`` and ``2E-3``, which PyYAML's YAML 1.1 rules read as strings.
_FLOAT_1_2 = re.compile(r"^[-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?$|^[-+]?\.(inf|Inf|INF)$|^\.(nan|NaN|NAN)$")


def _yaml_loader() -> Any:
    """PyYAML's safe loader, refusing duplicate keys and reading YAML 1.2 floats (made once)."""
    global _YAML_LOADER
    if _YAML_LOADER is not None:
        return _YAML_LOADER
    import yaml

    class Loader(yaml.SafeLoader):
        def construct_mapping(self, node, deep=False):  # noqa: ANN001 - PyYAML's signature
            seen: dict[Any, int] = {}
            for key_node, _ in node.value:
                key = self.construct_object(key_node, deep=True)
                try:
                    hash(key)
                except TypeError:
                    raise DocumentError(f"line {key_node.start_mark.line + 1}: a mapping key must be a "
                                        "plain value") from None
                if key in seen:
                    raise DocumentError(f"line {key_node.start_mark.line + 1}: key {preview(key)} appears twice "
                                        f"in one mapping (first on line {seen[key]})")
                seen[key] = key_node.start_mark.line + 1
            return super().construct_mapping(node, deep=deep)

    Loader.add_implicit_resolver("tag:yaml.org,2002:float", _FLOAT_1_2, list("-+0123456789."))
    _YAML_LOADER = Loader
    return Loader


def parse_yaml_bounded(text: str) -> Any:
    """Parse YAML safely: duplicate keys refused, and the composed document checked for its
    expanded size (aliases count as what they expand to) and depth before anything is
    built, so an alias bomb costs nothing."""
    import yaml

    Loader = _yaml_loader()
    loader = Loader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        _check_yaml_shape(node)
        return loader.construct_document(node)
    except RecursionError:
        raise DocumentError(f"nested more than {MAX_DOCUMENT_DEPTH} levels deep") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}, column {mark.column + 1}: " if mark is not None else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise DocumentError(f"{where}YAML syntax error: {preview(problem, 120)}") from None
    finally:
        loader.dispose()


def _check_yaml_shape(root: Any) -> None:
    """Expanded size and depth of a composed YAML node graph (a DAG when aliases are used),
    by one pass in post-order with memoised sizes: cost proportional to the distinct nodes."""
    import yaml

    size: dict[int, float] = {}
    depth: dict[int, int] = {}
    open_nodes: set[int] = set()
    stack: list[tuple[Any, bool]] = [(root, False)]
    while stack:
        node, done = stack.pop()
        key = id(node)
        if key in size:
            continue
        if not done and key in open_nodes:
            raise DocumentError("an alias refers to a node that contains it (a recursive document)")
        children = []
        if isinstance(node, yaml.SequenceNode):
            children = node.value
        elif isinstance(node, yaml.MappingNode):
            children = [n for pair in node.value for n in pair]
        if not done:
            open_nodes.add(key)
            stack.append((node, True))
            stack.extend((c, False) for c in children if id(c) not in size)
            if len(stack) > 4 * MAX_DOCUMENT_NODES:
                raise DocumentError(f"more than {MAX_DOCUMENT_NODES:,} values")
            continue
        open_nodes.discard(key)
        size[key] = 1 + math.fsum(size.get(id(c), 0.0) for c in children)
        depth[key] = 1 + max((depth.get(id(c), 0) for c in children), default=0)
        if size[key] > MAX_DOCUMENT_NODES:
            raise DocumentError(f"more than {MAX_DOCUMENT_NODES:,} values once its aliases are expanded")
        if depth[key] > MAX_DOCUMENT_DEPTH:
            raise DocumentError(f"nested more than {MAX_DOCUMENT_DEPTH} levels deep")
