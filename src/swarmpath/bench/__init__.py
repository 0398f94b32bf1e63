"""bench"""
from swarmpath.bench.sweep.store import load  # noqa: F401  (swarmpath.bench.load: a results store's rows)
