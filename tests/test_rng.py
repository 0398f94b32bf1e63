"""Seeded streams are stable: the numbers a (seed, name) pair yields are pinned, so a change
to how streams are derived (which would silently move every stored result) fails here, and
streams of different names do not depend on each other."""
from __future__ import annotations

import numpy as np
import pytest

from swarmpath.errors import ConfigError
from swarmpath.rng import make_rng, seed_sequence


def test_streams_are_pinned() -> None:
    assert make_rng(0, "controller").random(3).tolist() == [0.2842953566007149, 0.2683871335148035,
                                                            0.9007318691710686]
    assert make_rng(7, "obstacles").integers(0, 1000, 4).tolist() == [225, 553, 122, 327]
    assert make_rng(7, "robot", "r12").random(2).tolist() == [0.5370389879199411, 0.5863064416302695]
    assert make_rng(None).random(2).tolist() == [0.6369616873214543, 0.2697867137638703]
    assert make_rng(np.random.default_rng(5), "x").random(2).tolist() == [0.4818800115679427, 0.7101050882882182]


def test_names_and_seeds_give_independent_streams() -> None:
    a = make_rng(3, "controller").random(8)
    assert not np.allclose(a, make_rng(3, "obstacles").random(8))
    assert not np.allclose(a, make_rng(4, "controller").random(8))
    assert np.array_equal(a, make_rng(3, "controller").random(8))
    # drawing from one stream never moves another
    make_rng(3, "obstacles").random(1000)
    assert np.array_equal(a, make_rng(3, "controller").random(8))


@pytest.mark.parametrize("bad", [-1, 1.5, True, "3"])
def test_bad_seeds_are_refused(bad) -> None:
    with pytest.raises(ConfigError, match="seed"):
        seed_sequence(bad, "x")
