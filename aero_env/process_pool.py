"""Process pools whose workers end with the process that made them.

A pool's workers wait on its task queue, and each holds both ends of that queue, so the queue never
closes under them: when the process that made the pool dies without closing it (``kill -9``, the
kernel's out-of-memory killer, a job scheduler's SIGTERM, none of which runs Python's cleanup), its
workers wait on, orphaned, each holding a loaded interpreter's memory, until someone kills them by
hand. Every pool in aero-env is made by :func:`worker_pool`: each worker watches its parent's pid
from a daemon thread and ends itself within :data:`PARENT_POLL_S` once the parent has gone.
"""

from __future__ import annotations

import os
import threading
import time
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context

PARENT_POLL_S = 0.5  # how often a worker looks for its parent: a thread that wakes twice a second costs nothing


def worker_pool(workers: int, start_method: str = "spawn") -> ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` of ``workers`` processes (``spawn``: each a fresh interpreter) that end with
    this process, however it ends."""
    return ProcessPoolExecutor(workers, mp_context=get_context(start_method), initializer=watch_parent,
                               initargs=(os.getpid(),))


def watch_parent(parent: int) -> None:
    """In a worker, before its first task: end this process once ``parent`` is no longer its parent (an orphan
    is adopted by another process, so its parent pid changes). ``os._exit``: an orphan has no one to report to,
    and a normal exit would wait on the queue's feeder thread."""
    if os.getppid() != parent:  # the parent died while this worker was starting
        os._exit(1)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_POLL_S)
        os._exit(1)

    threading.Thread(target=watch, name="aero-env-parent-watch", daemon=True).start()
