"""Pydantic validation errors as the one-line messages swarmpath prints: the dotted field a
user wrote (``robots[3].start``, never pydantic's internal names of union members) and the
problem in words, with a short preview of the offending value. Scenario files and sweep
suites share it."""
from __future__ import annotations

from typing import Any, Callable

from pydantic import ValidationError

from swarmpath.world.limits import preview

#: Says whether a location part is pydantic's own name of a union member: (part, previous part).
SkipPart = Callable[[Any, Any], bool]


def field_path(loc: tuple[Any, ...], skip: SkipPart) -> str:
    """The user's dotted field path of a pydantic error location."""
    out = ""
    prev: Any = None
    for part in loc:
        if skip(part, prev):
            pass
        elif isinstance(part, int):
            out += f"[{part}]"
        else:
            out += f".{part}" if out else str(part)
        prev = part
    return out or "(top level)"


def describe(err: dict[str, Any], docs_page: str) -> str:
    """The problem of one pydantic error in words (``docs_page`` describes the format)."""
    kind = err["type"]
    if kind == "extra_forbidden":
        return f"unknown field (check the spelling; see {docs_page})"
    if kind == "missing":
        return "required field is missing"
    if kind == "literal_error" and err["loc"] and err["loc"][-1] == "schema_version":
        return f"must be 1, got {preview(err.get('input'))}"
    msg = err["msg"]
    if "input" in err and kind != "union_tag_invalid" and not isinstance(err["input"], dict):
        msg += f" (got {preview(err['input'])})"
    return msg


def located_errors(exc: ValidationError, error: type, docs_page: str, skip: SkipPart) -> list:
    """Every error of ``exc`` as an ``error(problem, field=...)`` (ScenarioError, SuiteError)."""
    return [error(describe(e, docs_page), field=field_path(tuple(e["loc"]), skip)) for e in exc.errors()]


def first_error(exc: ValidationError, error: type, docs_page: str, skip: SkipPart):
    """The first error of ``exc``, saying how many more there are."""
    errors = exc.errors()
    more = f" (and {len(errors) - 1} more problem{'s' if len(errors) > 2 else ''})" if len(errors) > 1 else ""
    e = errors[0]
    return error(describe(e, docs_page) + more, field=field_path(tuple(e["loc"]), skip))
