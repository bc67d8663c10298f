"""Ctrl-C that keeps a run whole: files written atomically, saves that a second Ctrl-C cannot cut, and worker
processes that leave Ctrl-C to the process that started them.

A terminal's Ctrl-C, and ``timeout -s INT``, send SIGINT to the whole process group: the command and every
worker process it spawned. Three things then go wrong unless guarded against, each seen with ``aero-env train``
(issue 36):

* a worker (SB3's ``SubprocVecEnv``) dies with its own ``KeyboardInterrupt`` traceback, printed on the
  terminal beside the command's one line; :func:`children_ignore_sigint` starts workers with SIGINT ignored,
  so only the command hears it and closes them;
* the save the interrupt starts is cut by a second one (a second Ctrl-C, ``timeout``'s second signal, or the
  first landing during the save at the end of training), leaving a truncated ``model.zip``; :class:`SigintOnce`
  raises KeyboardInterrupt for the first SIGINT only, holds every other while a save runs, and says so in one
  line;
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


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()  # only it may change a signal's handler


@contextlib.contextmanager
def children_ignore_sigint() -> Iterator[None]:
    """Processes spawned in this block (multiprocessing's ``spawn``) are born with SIGINT ignored, for life.

    A spawned child inherits SIGINT's disposition at its ``exec`` only if it is SIG_IGN (a handler is reset), and a
    Python started with SIGINT ignored never installs its KeyboardInterrupt handler. So SIGINT is ignored here
    for the instant of each launch only (``Popen._launch``, which forks and execs the child), not for the whole
    block: a Ctrl-C while the children import (a second or two) still reaches this process."""
    from multiprocessing import popen_spawn_posix

    launch = popen_spawn_posix.Popen._launch
    if not _main_thread():
        yield
        return

    def launch_ignoring_sigint(self, process_obj):
        old = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            return launch(self, process_obj)
        finally:
            signal.signal(signal.SIGINT, old)

    popen_spawn_posix.Popen._launch = launch_ignoring_sigint
    try:
        yield
    finally:
        popen_spawn_posix.Popen._launch = launch


class SigintOnce:
    """Ctrl-C for a run that saves what it did, installed for the whole run (``with SigintOnce(line) as sigint``).

    The first SIGINT raises KeyboardInterrupt where the run is, unless a save is under way (``with
    sigint.saving():``), which it never cuts. Every SIGINT after the first, and one during a save, is held: the
    first of those prints ``line`` on stderr, the rest nothing. Holding the later ones matters even for a single
    Ctrl-C: ``timeout -s INT`` sends SIGINT twice, to the command and then to its process group, so the second
    lands while the first one's handler is saving. ``came`` says whether any SIGINT arrived."""

    def __init__(self, line: str, stream=None):
        self.line, self.stream = line, stream
        self.came = self._said = self._saving = False
        self._old = None

    def _handle(self, _signum, _frame):
        first = not self.came
        self.came = True
        if first and not self._saving:
            raise KeyboardInterrupt
        if not self._said:
            self._said = True
            print(self.line, file=self.stream or sys.stderr, flush=True)

    def __enter__(self) -> "SigintOnce":
        if _main_thread():
            self._old = signal.signal(signal.SIGINT, self._handle)
        return self

    def __exit__(self, *exc) -> None:
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)

    @contextlib.contextmanager
    def saving(self) -> Iterator[None]:
        self._saving = True
        try:
            yield
        finally:
            self._saving = False
