"""The worker process: ``python -m swarmpath.bench.sweep.child`` reads jobs on its standard
input and writes results on its standard output (pickled frames of
:class:`multiprocessing.connection.Connection`), one job at a time, until the input closes.

Its standard output is kept for the frames only: anything a job prints goes to standard
error. It ignores Ctrl-C (the parent decides what an interruption means) and exits when its
parent dies, so a killed sweep leaves no worker behind.
"""
from __future__ import annotations

import os
import signal
import sys
import threading
import time


def _watch_parent(parent: int) -> None:
    """Exit as soon as the parent process is gone (polled twice a second)."""
    while True:
        time.sleep(0.5)
        if os.getppid() != parent:
            os._exit(3)


def main() -> None:
    from multiprocessing.connection import Connection

    out_fd = os.dup(1)
    os.dup2(2, 1)                     # stray prints go to stderr, never into the frames
    sys.stdout = sys.stderr
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_watch_parent, args=(os.getppid(),), daemon=True).start()
    rx = Connection(0, writable=False)
    tx = Connection(out_fd, readable=False)

    from swarmpath.bench.sweep.execute import run_job
    from swarmpath.registry import CONTROLLERS, PLANNERS

    CONTROLLERS.names()               # load the registries before the first job's clock starts
    PLANNERS.names()
    tx.send(("ready", os.getpid()))
    while True:
        try:
            job = rx.recv()
        except (EOFError, OSError):
            break
        if job is None:
            break
        tx.send(run_job(job))


if __name__ == "__main__":
    main()
