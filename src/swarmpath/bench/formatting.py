"""Formatting numbers and Markdown tables for the reports, and filling the reports'
Markdown templates (package data in ``swarmpath/bench/templates/``)."""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from importlib import resources
from string import Template

import numpy as np


def fmt(x: float | None, digits: int = 2, missing: str = "-") -> str:
    """``x`` with ``digits`` decimals; ``missing`` for None, NaN and infinities."""
    if x is None or not np.isfinite(x):
        return missing
    return f"{x:.{digits}f}"


def sig(x: float) -> str:
    """Three significant digits, scientific notation from 1e4 on (optimiser results that span
    many orders of magnitude)."""
    return f"{x:.3g}" if abs(x) < 1e4 else f"{x:.2e}"


def pct(x: float | None, missing: str = "-") -> str:
    """A fraction as a whole percentage ("83%")."""
    return missing if x is None or not np.isfinite(x) else f"{100 * x:.0f}%"


def point(p: Sequence[float]) -> str:
    """A 2-D point as "(x, y)" with short numbers."""
    return f"({p[0]:g}, {p[1]:g})"


def table(header: Sequence[str], rows: Iterable[Sequence[object]], align: str | Sequence[str] = "---") -> list[str]:
    """A Markdown table as lines: a header row, an alignment row (``align`` for every column,
    or one entry per column, e.g. "---:"), then the rows (cells converted with ``str``; an
    empty cell is written "| |")."""
    aligns = [align] * len(header) if isinstance(align, str) else list(align)
    return [_row(header), "|" + "|".join(aligns) + "|", *(_row(row) for row in rows)]


def _row(cells: Sequence[object]) -> str:
    """One table row; an empty cell is written "| |"."""
    return "|" + "|".join(f" {c} " if str(c) else " " for c in cells) + "|"


def render(template: str, **fields: object) -> str:
    """The report template ``templates/<template>.md`` with its ``$name`` fields filled in
    (every field must be given; ``$$`` is a literal dollar). Lists of lines are joined with
    newlines."""
    text = resources.files("swarmpath.bench").joinpath("templates", f"{template}.md").read_text(encoding="utf-8")
    values = {k: "\n".join(v) if isinstance(v, list) else str(v) for k, v in fields.items()}
    return Template(text).substitute(values)
