"""A brute-force reference for the robot-robot move rules, written without any swarmpath code:
sample the step densely in time, measure centre distances, and read cells off the end points.

It is the oracle the move-rules kernel (and through it the simulator's checker) is held to:
when the samples say two discs overlap by a clear margin, the kernel must report a contact;
when they never come close, it must not. Between the two (a near-touch the samples cannot
resolve) the reference abstains.
"""
from __future__ import annotations

import math

SAMPLES = 512  # the step is cut into this many equal pieces (both ends included)


def _cell(p: tuple[float, float], resolution: float) -> tuple[int, int]:
    return (math.floor(p[0] / resolution + 1e-9), math.floor(p[1] / resolution + 1e-9))


def sampled_min_distance(a0, a1, b0, b1) -> float:
    """The smallest centre distance over the sampled times of the step."""
    best = math.inf
    for k in range(SAMPLES + 1):
        t = k / SAMPLES
        ax, ay = a0[0] + t * (a1[0] - a0[0]), a0[1] + t * (a1[1] - a0[1])
        bx, by = b0[0] + t * (b1[0] - b0[0]), b0[1] + t * (b1[1] - b0[1])
        best = min(best, math.hypot(ax - bx, ay - by))
    return best


def reference_verdict(a0, a1, b0, b1, ra: float, rb: float, resolution: float, margin: float) -> bool | None:
    """True: a contact; False: surely none; None: too close to call by sampling.

    Discs: a contact when the sampled distance is below ``ra + rb - margin``; none when it is
    above ``ra + rb + margin + (max relative travel) / SAMPLES`` (the most the true minimum
    can hide between two samples). Two point robots: a contact when they end in the same
    cell, exchange cells, or pass within ``margin`` of each other at some sample; none when
    the sampled distance stays above the hiding bound."""
    rel = math.hypot((a1[0] - a0[0]) - (b1[0] - b0[0]), (a1[1] - a0[1]) - (b1[1] - b0[1]))
    hide = rel / SAMPLES
    d = sampled_min_distance(a0, a1, b0, b1)
    if ra == 0 and rb == 0:
        ca0, ca1, cb0, cb1 = (_cell(p, resolution) for p in (a0, a1, b0, b1))
        if ca1 == cb1 or (ca1 == cb0 and cb1 == ca0 and ca0 != cb0):
            return True
        if d <= 1e-12:
            return True
        return False if d > hide + margin else None
    need = ra + rb
    if d < need - margin:
        return True
    if d > need + margin + hide:
        return False
    return None
