"""Seeded random streams: one seed per run, one named stream per component.

A run's integer seed becomes a :class:`numpy.random.SeedSequence`; every component derives
its own :class:`numpy.random.Generator` from that seed and a stable name ("obstacles",
"controller", a robot id), so adding a robot or a component does not shift any other stream.
Nothing in swarmpath reads numpy's or Python's global random state.
"""
from __future__ import annotations

import hashlib

import numpy as np

SeedLike = "int | np.random.Generator | None"


def _name_key(name: str) -> int:
    """A stable 64-bit integer for ``name`` (Python's ``hash`` is salted per process)."""
    return int.from_bytes(hashlib.blake2b(name.encode("utf-8"), digest_size=8).digest(), "little")


def seed_sequence(seed: int, *names: str) -> np.random.SeedSequence:
    """The seed sequence of the stream ``names`` (a path of component names) under ``seed``."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        from swarmpath.errors import ConfigError

        raise ConfigError(f"seed must be a non-negative integer, got {seed!r}")
    return np.random.SeedSequence(int(seed), spawn_key=tuple(_name_key(n) for n in names))


def make_rng(seed: "int | np.random.Generator | None", *names: str) -> np.random.Generator:
    """A generator for the component ``names`` of the run ``seed``.

    ``seed`` may already be a Generator (returned as is when no names are given, otherwise a
    child stream is drawn from it deterministically); ``None`` means seed 0, so that an
    entry point called without a seed is still reproducible.
    """
    if isinstance(seed, np.random.Generator):
        if not names:
            return seed
        child_seed = int(seed.integers(0, 2**63 - 1))
        return np.random.default_rng(seed_sequence(child_seed, *names))
    return np.random.default_rng(seed_sequence(0 if seed is None else seed, *names))
