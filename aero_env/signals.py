"""SIGTERM stops a command as Ctrl-C does.

A job scheduler (SLURM's ``scancel``, Kubernetes, systemd, ``timeout``) asks a process to stop with SIGTERM and
kills it a grace period later. Python's default for SIGTERM ends the process at once, without ``finally`` blocks
or saves: a training run left its config and monitor without a model. While :func:`sigterm_as_interrupt` is in
force, SIGTERM raises :class:`Terminated` instead, a ``KeyboardInterrupt``, so that every path that keeps a
Ctrl-C'd run whole (the saves, the study's cleanup, the one line) keeps a terminated one whole too; the command
line ends it with status 143 (128 + SIGTERM), as a shell reports a process SIGTERM ended.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from typing import Iterator

TERMINATED = 128 + signal.SIGTERM  # 143: the shell's status for a process ended by SIGTERM
INTERRUPTED = 128 + signal.SIGINT  # 130: ... by SIGINT (Ctrl-C)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the program is, as Ctrl-C raises KeyboardInterrupt."""


def raise_terminated(_signum=None, _frame=None) -> None:
    """A SIGTERM handler: raise :class:`Terminated`."""
    raise Terminated


def exit_status(stop: KeyboardInterrupt) -> int:
    """The shell's status for a run that ``stop`` ended: 143 for SIGTERM, 130 for Ctrl-C."""
    return TERMINATED if isinstance(stop, Terminated) else INTERRUPTED


def signal_name(stop: KeyboardInterrupt) -> str:
    """How a one-line message names what stopped the run."""
    return "terminated (SIGTERM)" if isinstance(stop, Terminated) else "interrupted"


@contextlib.contextmanager
def sigterm_as_interrupt() -> Iterator[None]:
    """SIGTERM raises :class:`Terminated` inside this block (in the main thread only: no other may set a handler;
    elsewhere the block changes nothing). A handler the program set before, other than the default, is kept."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.getsignal(signal.SIGTERM)
    if old not in (signal.SIG_DFL, None):
        yield  # somebody (a test harness, an embedding program) handles SIGTERM already
        return
    signal.signal(signal.SIGTERM, raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)
