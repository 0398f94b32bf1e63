"""Running a sweep's jobs on a Dask distributed cluster (the ``[dask]`` extra, imported only
here): ``local`` starts a LocalCluster of single-threaded worker processes (pogema-toolbox's
set-up), an address connects to a running scheduler.

Each task runs one job in the Dask worker's own sweep worker process
(:func:`swarmpath.bench.sweep.pool.run_in_worker_process`), so time limits, isolation and
results are those of the local pool; results come back to this process, which alone writes
the store. At most a few jobs per worker are in flight at once, so an interrupted sweep
loses little work and the costliest jobs still go first.
"""
from __future__ import annotations

import time
from typing import Iterable

from swarmpath.bench.sweep.jobs import Job
from swarmpath.bench.sweep.pool import OnResult, run_in_worker_process
from swarmpath.errors import ConfigError

#: Jobs in flight per Dask worker thread.
IN_FLIGHT = 2


def dask_missing() -> str | None:
    """Why ``--dask`` cannot be used here (dask or distributed not installed), or None."""
    import importlib.util

    for name in ("dask", "distributed"):
        try:
            spec = importlib.util.find_spec(name)
        except (ImportError, ValueError):     # a broken or blocked installation counts as none
            spec = None
        if spec is None:
            return f"--dask needs dask and distributed, and {name} is not installed (pip install \"swarmpath[dask]\")"
    return None


class DaskEngine:
    """Jobs as Dask tasks on a LocalCluster (``address="local"``) or a running scheduler."""

    name = "dask"

    def __init__(self, address: str, workers: int):
        if workers < 1:
            raise ConfigError(f"--workers must be at least 1, got {workers}")
        self.address = address
        self.workers = workers

    def _client(self):
        import dask
        from distributed import Client, LocalCluster

        if self.address == "local":
            with dask.config.set({"distributed.worker.daemon": False, "logging.distributed": "error"}):
                cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=50)
            return Client(cluster), cluster
        try:
            return Client(self.address, timeout="10s"), None
        except (OSError, TimeoutError, ValueError) as exc:
            raise ConfigError(f"--dask {self.address}: cannot reach a Dask scheduler there ({exc})") from None

    def run(self, jobs: Iterable[Job], on_result: OnResult) -> None:
        """Run every job on the cluster, calling ``on_result(job, result)`` here as each ends."""
        from distributed import as_completed

        pending = list(jobs)
        pending.reverse()
        if not pending:
            return
        client, cluster = self._client()
        try:
            threads = max(1, sum(client.nthreads().values()))
            by_key: dict[str, Job] = {}
            batch = as_completed()

            def submit(job: Job) -> None:
                future = client.submit(run_in_worker_process, job, key=f"swarmpath-job-{job.key}-{time.time_ns()}",
                                       pure=False, retries=0)
                by_key[future.key] = job
                batch.add(future)

            for _ in range(min(len(pending), IN_FLIGHT * threads)):
                submit(pending.pop())
            for future in batch:
                job = by_key.pop(future.key)
                if future.status == "error":
                    from swarmpath.bench.sweep.execute import describe_error

                    exc = future.exception()
                    result = {"key": job.key, "status": "error",
                              "error": f"the Dask task failed: {describe_error(exc)}", "outcome": None,
                              "lower_bound": None, "violations": None, "source": "", "timings": {"wall_s": 0.0}}
                else:
                    result = future.result()
                future.release()
                on_result(job, result)
                if pending:
                    submit(pending.pop())
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
