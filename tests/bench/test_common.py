"""The shared plumbing of the reproductions: the one paired test, the batch runner, progress
(callback, plain lines, time by stage), formatting and templates, and ladder outcomes."""
from __future__ import annotations

import io

import numpy as np
import pytest

from swarmpath.bench.formatting import fmt, pct, render, table
from swarmpath.bench.ladder import Rung, ladder_table, merge_outcomes, run_ladder, side_by_side
from swarmpath.bench.progress import Progress
from swarmpath.bench.runner import run_batch
from swarmpath.bench.stats import describe, paired_counts, wilcoxon_vs
from swarmpath.control.follow import FollowController
from swarmpath.registry import PLANNERS
from swarmpath.testing import conformance_worlds


# ---------------------------------------------------------------------------- statistics
def test_wilcoxon_drops_pairs_with_a_nan_and_reads_the_median_difference():
    rng = np.random.default_rng(1)
    base = rng.random(30)
    better = base - 0.3
    assert wilcoxon_vs(better, base)[1] == "better" and wilcoxon_vs(base, better)[1] == "worse"
    with_nan = better.copy()
    with_nan[:5] = np.nan
    p_nan, verdict = wilcoxon_vs(with_nan, base)
    assert verdict == "better" and p_nan == wilcoxon_vs(better[5:], base[5:])[0]  # same as the finite pairs alone


@pytest.mark.parametrize("a, b", [([1.0, 2.0, 3.0], [1.0, 2.0, 3.0]), ([1.0], [2.0]), ([np.nan, 1.0], [1.0, 2.0]),
                                  ([np.inf, np.nan], [0.0, 0.0])])
def test_wilcoxon_without_evidence_says_no_difference(a, b):
    assert wilcoxon_vs(np.array(a), np.array(b)) == (1.0, "no difference")


def test_describe_and_paired_counts_skip_nan():
    v = np.array([1.0, np.nan, 3.0])
    assert describe(v, "mean") == 2.0 and describe(v, "max") == 3.0 and np.isnan(describe([np.nan], "median"))
    assert paired_counts([1, 2, np.nan, 5], [2, 2, 1, 4]) == (1, 1, 1)


# ---------------------------------------------------------------------------- runner and progress
def test_batch_runner_is_seeded_and_ticks_once_per_run():
    world = conformance_worlds()[0]
    plan = PLANNERS.get("astar")().plan(world, rng=0)
    calls = []
    bar = Progress("test", 3, lambda d, t: calls.append((d, t)), stream=None)
    a = run_batch(world, FollowController, range(3), lambda traj, cpu: traj.positions, plan=plan, keep=1,
                  progress=bar)
    b = run_batch(world, FollowController, range(3), lambda traj, cpu: traj.positions, plan=plan)
    assert a.seeds == (0, 1, 2) and len(a.kept) == 1 and len(b.kept) == 0
    assert all(np.array_equal(x, y) for x, y in zip(a.records, b.records))
    assert calls == [(0, 3), (1, 3), (2, 3), (3, 3)]


def test_progress_writes_stages_and_where_the_time_went():
    out = io.StringIO()
    bar = Progress("demo", 4, lambda d, t: None, stream=out, every_s=0.0)
    bar.stage("first", 2)
    bar.tick()
    bar.tick()
    bar.stage("second", 2)
    bar.tick(2)
    stages = bar.finish()
    text = out.getvalue()
    assert "[demo] stage 1: first, 2 runs (50 % of all)" in text and "4/4 runs in 'second'" in text
    assert "time by stage" in text and [s.runs for s in stages] == [2, 2]


def test_progress_prints_nothing_without_a_callback(capsys):
    bar = Progress("quiet", 2)
    bar.stage("a", 2)
    bar.tick(2)
    bar.finish()
    assert capsys.readouterr().err == ""


def test_ticker_follows_a_count_from_zero():
    calls = []
    bar = Progress("t", 5, lambda d, t: calls.append(d), stream=None)
    bar.tick()
    advance = bar.ticker()
    advance(2, 4)
    advance(4, 4)
    assert bar.done == 5 and calls[-1] == 5


# ---------------------------------------------------------------------------- formatting and templates
def test_formatting_and_tables():
    assert fmt(float("nan")) == "-" and fmt(1.234, 1) == "1.2" and fmt(None, missing="n/a") == "n/a"
    assert pct(0.25) == "25%"
    assert table(["", "a"], [["x", ""]], ["---", "---:"]) == ["| | a |", "|---|---:|", "| x | |"]


def test_every_template_renders_and_a_missing_field_is_an_error():
    with pytest.raises(KeyError):
        render("karim2014")
    text = render("prediction2013-start", px=(1, 2), pos=(0.5, 1), fig="fig15", table=["| a |"], moving=1, robot=2,
                  static=3, with_total=0)
    assert "utd_robots_fig15.png" in text and "| a |" in text


# ---------------------------------------------------------------------------- ladders
def test_ladder_rows_are_cumulative_and_outcomes_merge():
    world = conformance_worlds()[0]
    plan = PLANNERS.get("astar")().plan(world, rng=0)
    rungs = [Rung("paper", "-", FollowController), Rung("again", "nothing", FollowController)]
    outcomes = run_ladder(world, rungs, range(2), plan=plan)
    lines = ladder_table(rungs, outcomes)
    assert lines[2].startswith("| 0 | paper | - |") and lines[3].startswith("| 1 | + again | nothing |")
    merged = merge_outcomes("both", outcomes)
    assert merged.n_runs == 4 and merged.contacts.shape == (4, 3)
    assert side_by_side(outcomes)[0] == "| | ladder: paper | ladder: again |"
    assert outcomes[0].runs_with_contact == 2  # follow has no avoidance: the crossing robots meet


def test_off_a_terminal_progress_names_stages_and_leaves_counting_to_the_command_line(capsys):
    bar = Progress("auto", 2, lambda d, t: None, every_s=0.0)   # pytest's stdout is not a terminal
    bar.stage("only", 2)
    bar.tick(2)
    bar.finish()
    err = capsys.readouterr().err
    assert "[auto] stage 1: only" in err and "time by stage" in err and "2/2 runs" not in err
