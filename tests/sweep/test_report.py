"""``bench report``: jobs.csv holds the stored rows; the summary tables and the plotted points
are recomputed here from those rows by the definitions in docs/bench.md (CSR, ISR, sum of
costs, SOC / lower bound, makespan, flowtime, contacts, wall time) and must agree."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pytest
from sweep_support import swarmpath

from swarmpath.bench.sweep.report import PLOTS, write_report
from swarmpath.bench.sweep.run import run_sweep
from swarmpath.bench.sweep.store import Store
from swarmpath.bench.sweep.suite import load_suite

SUITE = """\
name: report-check
scenarios:
  - {map: empty-8-8.map, scen: empty-8-8-even-10.scen, agents: [2, 6]}
  - karim2014
methods:
  - {planner: lacam, controller: follow}
  - {planner: astar, controller: follow}                       # collides: no success with every robot home
  - {controller: pibt}
  - {controller: {name: cat-swarm, params: {mixture_ratio: 2.0}}}   # fails: an error row
seeds: [0, 1, 2]
max_steps: 8                                                   # short: some runs end unsolved
"""


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> tuple[list[dict], Path]:
    folder = tmp_path_factory.mktemp("report")
    (folder / "s.yaml").write_text(SUITE)
    run_sweep(load_suite(folder / "s.yaml"), folder / "r.db", workers=2)
    with Store(folder / "r.db").open() as s:
        rows = s.rows()
    write_report(folder / "r.db", folder / "out")
    return rows, folder / "out"


def read_csv(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as fh:
        return list(csv.DictReader(fh))


def num(text: str) -> float | None:
    return None if text == "" else float(text)


def mean(values) -> float | None:
    values = [v for v in values if v is not None]
    return sum(values) / len(values) if values else None


def expected(jobs: list[dict]) -> dict[str, float | None]:
    """The measures of one group, from the stored rows, by the documented definitions."""
    ran = [r for r in jobs if r["status"] == "ok"]
    solved = [r for r in ran if all(x["arrival_step"] is not None for x in json.loads(r["outcome"])["robots"])]
    flow = []
    for r in ran:
        o = json.loads(r["outcome"])
        flow.append(sum(x["arrival_step"] if x["arrival_step"] is not None else o["steps"] for x in o["robots"]))
    return {
        "jobs": len(jobs), "ok": len(ran), "errors": sum(r["status"] == "error" for r in jobs), "solved": len(solved),
        "success_rate": sum(1 for r in ran if r["success"] == 1) / len(jobs),
        "isr": sum(r["reached"] / r["n_robots"] for r in ran) / len(jobs),
        "sum_of_costs": mean(json.loads(r["outcome"])["sum_of_arrival_steps"] for r in solved),
        "soc_over_lb": mean(json.loads(r["outcome"])["sum_of_arrival_steps"] / r["lower_bound"] for r in solved),
        "makespan": mean(json.loads(r["outcome"])["makespan"] for r in solved),
        "flowtime": mean(flow),
        "contacts": mean(sum(json.loads(r["outcome"])["collisions"].values()) for r in ran),
        "wall_s": mean(r["wall_s"] for r in jobs),
    }


def close(a: float | None, b: float | None) -> bool:
    return (a is None and b is None) or (a is not None and b is not None and math.isclose(a, b, rel_tol=1e-9))


def test_the_sweep_has_every_kind_of_row(report) -> None:
    rows, _ = report
    statuses = {r["status"] for r in rows}
    assert statuses == {"ok", "error"}
    ok = [r for r in rows if r["status"] == "ok"]
    assert any(r["success"] for r in ok) and any(not r["success"] for r in ok)
    assert any(r["sum_of_costs"] is None for r in ok)          # unsolved runs exist


def test_jobs_csv_is_the_stored_rows(report) -> None:
    rows, out = report
    jobs = read_csv(out / "jobs.csv")
    required = ["key", "scenario", "planner", "controller", "seed", "n_agents", "status", "success", "reached",
                "sum_of_lengths", "makespan", "contacts", "wall_s"]
    assert all(c in jobs[0] for c in required)
    by_key = {r["key"]: r for r in rows}
    assert sorted(j["key"] for j in jobs) == sorted(by_key)
    for j in jobs:
        r = by_key[j["key"]]
        for c in ("scenario", "planner", "controller", "status"):
            assert j[c] == r[c]
        for c in ("seed", "n_agents", "success", "reached", "makespan", "contacts", "sum_of_lengths", "wall_s"):
            assert num(j[c]) == (None if r[c] is None else float(r[c])), (c, j[c], r[c])


@pytest.mark.parametrize("by", [("scenario", "n_agents", "method"), ("controller",), ("planner", "n_agents")])
def test_summary_tables_agree_with_the_rows(report, tmp_path: Path, by: tuple[str, ...]) -> None:
    rows, out = report
    if by != ("scenario", "n_agents", "method"):
        out = tmp_path
        write_report(report[1].parent / "r.db", out, by)
    table = read_csv(out / "summary.csv")
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault(tuple(str(r[f]) for f in by), []).append(r)
    assert sorted(tuple(t[f] for f in by) for t in table) == sorted(groups)
    md = (out / "summary.md").read_text()
    for t in table:
        want = expected(groups[tuple(t[f] for f in by)])
        for k, v in want.items():
            assert close(num(t[k]), v), (by, t, k, v)
        cells = [t[f] for f in by] + [str(want["jobs"]), f"{want['success_rate']:.3f}", f"{want['isr']:.3f}"]
        assert any(all(f"| {c} |" in line or line.startswith(f"| {c} |") for c in cells) for line in md.splitlines())


def test_plotted_points_agree_with_the_rows(report) -> None:
    rows, out = report
    points = read_csv(out / "plot_data.csv")
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault((r["scenario"], r["method"], str(r["n_agents"])), []).append(r)
    seen = set()
    for p in points:
        want = expected(groups[(p["scenario"], p["method"], p["n_agents"])])
        assert close(float(p["value"]), want[p["measure"]]), p
        seen.add((p["measure"], p["scenario"], p["method"], p["n_agents"]))
    # every group with a value has its point on every plot
    for key, jobs in groups.items():
        for _, measure, _ in PLOTS:
            if expected(jobs)[measure] is not None:
                assert (measure, *key) in seen


def test_the_plots_are_pictures(report) -> None:
    from PIL import Image

    _, out = report
    for name, _, _ in PLOTS:
        with Image.open(out / name) as im:
            assert im.format == "PNG" and im.width > 300 and im.height > 200
            assert len(im.convert("RGB").getcolors(maxcolors=1 << 16) or range(1 << 16)) > 5


def test_the_command_line_report(report, tmp_path: Path) -> None:
    db = report[1].parent / "r.db"
    r = swarmpath("bench", "report", str(db), "--by", "controller,n_agents", "--out", str(tmp_path / "rep"))
    assert r.returncode == 0, r.stderr
    header = (tmp_path / "rep" / "summary.csv").read_text().splitlines()[0]
    assert header.startswith("controller,n_agents,jobs,")
    bad = swarmpath("bench", "report", str(db), "--by", "colour", "--out", str(tmp_path / "x"))
    assert bad.returncode == 2 and "unknown field 'colour'" in bad.stderr and len(bad.stderr.strip().splitlines()) == 1
    missing = swarmpath("bench", "report", str(tmp_path / "none.db"))
    assert missing.returncode == 2 and "no such results store" in missing.stderr
