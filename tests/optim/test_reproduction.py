"""The amopso-benchmarks reproduction, on a small budget (the full one is run on demand)."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.bench.amopso_benchmarks import ALGORITHMS, PAPER_TABLE3
from swarmpath.bench.stats import wilcoxon_vs
from swarmpath.errors import ConfigError
from swarmpath.registry import REPRODUCTIONS


def test_small_reproduction_writes_report_and_plots(tmp_path):
    calls = []
    reproduce = REPRODUCTIONS.get("amopso-benchmarks")
    report = reproduce(
        tmp_path / "out",
        runs=4,
        seed=3,
        progress=lambda done, total: calls.append((done, total)),
        budgets=((8, 15), (10, 20)),
        functions=("sphere", "quartic-noise"),
        dim=5,
    )
    assert report == tmp_path / "out" / "report.md"
    text = report.read_text()
    for needle in ["8 particles x 15 iterations", "10 particles x 20 iterations", "Wilcoxon", "f1 sphere",
                   "f3 quartic-noise", "AMOPSO4", "The paper's Table 3", "0.26797"]:
        assert needle in text
    for png in ["convergence-8x15.png", "convergence-10x20.png"]:
        data = (tmp_path / "out" / png).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    total = 2 * 2 * len(ALGORITHMS) * 4
    assert calls[0] == (0, total) and calls[-1] == (total, total)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)


def test_bad_runs(tmp_path):
    with pytest.raises(ConfigError, match="runs"):
        REPRODUCTIONS.get("amopso-benchmarks")(tmp_path, runs=0)


def test_wilcoxon_verdicts():
    rng = np.random.default_rng(0)
    base = rng.random(40)
    assert wilcoxon_vs(base - 0.5, base)[1] == "better"
    assert wilcoxon_vs(base + 0.5, base)[1] == "worse"
    assert wilcoxon_vs(base, base) == (1.0, "no difference")
    p, verdict = wilcoxon_vs(base + rng.normal(scale=1e-3, size=40), base)
    assert verdict == "no difference" and p > 0.05


def test_paper_table_is_complete():
    assert set(PAPER_TABLE3) == {"f1", "f2", "f3", "f4", "f5", "f6"}
    for row in PAPER_TABLE3.values():
        assert set(row) == set(ALGORITHMS)
