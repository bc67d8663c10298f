"""Ctrl-C and SIGTERM that keep a run whole: files written atomically, saves that a second signal cannot cut,
and worker processes that leave both signals to the process that started them.

A terminal's Ctrl-C, and ``timeout -s INT``, send SIGINT to the whole process group: the command and every
worker process it spawned. A job scheduler (SLURM's ``scancel``, Kubernetes, ``timeout``) sends SIGTERM the same
way, to the command or to its process group, and kills it a grace period later; SIGTERM stops a run as Ctrl-C
does (:mod:`aero_env.signals`). Three things then go wrong unless guarded against, each seen with ``aero-env
train`` (issues 36 and 50):

* a worker (SB3's ``SubprocVecEnv``) dies with its own ``KeyboardInterrupt`` traceback, printed on the
  terminal beside the command's one line, or silently by SIGTERM; :func:`children_ignore_sigint` starts workers
  with SIGINT and SIGTERM ignored, so only the command hears them and closes its workers;
* the save the interrupt starts is cut by a second signal (a second Ctrl-C, ``timeout``'s second signal, a
  scheduler's SIGTERM to the command and then to its group, or the first landing during the save at the end
  of training), leaving a truncated ``model.zip`` or a run with no policy; :class:`SigintOnce` raises for the
  first signal only, outside a save, holds every other, and says so in one line;
* a file cut half-way by the interrupt itself; :func:`aero_env.files.write_atomically` writes a temporary file
  beside it and renames it over the old one, so a reader sees the old file or the new one, never part of
  one.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from typing import Iterator

from aero_env.signals import Terminated

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)  # what stops a run: Ctrl-C, and a scheduler's (or a user's) stop


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()  # only it may change a signal's handler


@contextlib.contextmanager
def children_ignore_sigint() -> Iterator[None]:
    """Processes spawned in this block (multiprocessing's ``spawn``) are born with SIGINT and SIGTERM ignored, for
    life: a signal sent to the whole process group (a terminal's Ctrl-C, SLURM's SIGTERM) leaves them to the process
    that started them, which closes them.

    A spawned child inherits a signal's disposition at its ``exec`` only if it is SIG_IGN (a handler is reset), and a
    Python started with SIGINT ignored never installs its KeyboardInterrupt handler. So both are ignored here
    for the instant of each launch only (``Popen._launch``, which forks and execs the child), not for the whole
    block: a Ctrl-C or SIGTERM while the children import (a second or two) still reaches this process. A child
    that ignores SIGTERM outlives ``Process.terminate()``: whoever starts them here must close them."""
    from multiprocessing import popen_spawn_posix

    launch = popen_spawn_posix.Popen._launch
    if not _main_thread():
        yield
        return

    def launch_ignoring_stops(self, process_obj):
        old = [(signum, signal.signal(signum, signal.SIG_IGN)) for signum in STOP_SIGNALS]
        try:
            return launch(self, process_obj)
        finally:
            for signum, handler in old:
                signal.signal(signum, handler)

    popen_spawn_posix.Popen._launch = launch_ignoring_stops
    try:
        yield
    finally:
        popen_spawn_posix.Popen._launch = launch


class SigintOnce:
    """Ctrl-C and SIGTERM for a run that saves what it did, installed for the whole run (``with SigintOnce(line) as
    sigint``).

    The first SIGINT or SIGTERM raises where the run is (KeyboardInterrupt, or :class:`~aero_env.signals.Terminated`
    for SIGTERM, so that the command can say which and end with its status), unless a save is under way (``with
    sigint.saving():``), which it never cuts. Every signal after the first, of either kind, and one during a save,
    is held: the first of those prints ``line`` on stderr, the rest nothing. Holding the later ones matters even
    for a single stop: ``timeout -s INT`` sends SIGINT twice, to the command and then to its process group, and a
    scheduler may send SIGTERM so, so the second lands while the first one's handler is saving. ``came`` says
    whether any such signal arrived."""

    def __init__(self, line: str, stream=None):
        self.line, self.stream = line, stream
        self.came = self._said = self._saving = False
        self._old: dict = {}  # each signal's handler before this one's (none set outside the main thread)

    def _handle(self, signum, _frame):
        first = not self.came
        self.came = True
        if first and not self._saving:
            raise Terminated if signum == signal.SIGTERM else KeyboardInterrupt
        if not self._said:
            self._said = True
            print(self.line, file=self.stream or sys.stderr, flush=True)

    def __enter__(self) -> "SigintOnce":
        if _main_thread():
            self._old = {signum: signal.signal(signum, self._handle) for signum in STOP_SIGNALS}
        return self

    def __exit__(self, *exc) -> None:
        for signum, handler in self._old.items():
            signal.signal(signum, handler)

    @contextlib.contextmanager
    def saving(self) -> Iterator[None]:
        self._saving = True
        try:
            yield
        finally:
            self._saving = False
