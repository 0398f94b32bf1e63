"""Whether robots still make progress: the simulator ends a run that stalled, and the run
summary counts the robots that stalled at the end."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def distinct_positions(window: NDArray[np.float64]) -> NDArray[np.int64]:
    """Number of distinct positions each robot took in ``window`` (shape (k, n, 2))."""
    keys = np.round(window * 1e6).astype(np.int64)
    keys = keys[..., 0] * 4_000_000_007 + keys[..., 1]
    keys.sort(axis=0)
    return 1 + np.count_nonzero(np.diff(keys, axis=0), axis=0)
