"""What goes wrong in a tuning run, and how a process tells: a lost database and a process gone.

A database error (:func:`is_db_error`, never one that Ctrl-C caused) is retried by :class:`Reconnect`
for ``reconnect_s`` (default ``RECONNECT_S``), then :class:`StorageUnavailable`. A process is named by
its stamp (:func:`process_stamp`: host, boot, pid namespace, pid and start time), and
:func:`process_gone` says when the stamped process has certainly gone from this host.

Faults (RDB storages), so that a study ends with exactly ``trials`` COMPLETE trials:

- a worker that dies (SIGKILL, OOM): its RUNNING trial is failed and its design queued again
  (a WAITING copy, at most ``MAX_RETRY`` times), at once where the stamped process is gone from
  this host (the coordinator, every worker before each trial, and a resumed run check), else by
  the heartbeat after ``GRACE_S``; the coordinator starts a worker for the dead one's share;
- a lost database (server restart, SQLite busy): each process retries with a bounded backoff
  (``reconnect_s`` in all), fails the trials it had RUNNING and goes on, or stops with
  :class:`StorageUnavailable` (the study resumes by rerunning the command);
- Ctrl-C or SIGTERM (to the coordinator, a worker or all): the coordinator interrupts its workers, waits
  for them, fails what they left RUNNING; the trials they stopped are queued again when the run resumes;
- runs on other machines: a trial is started only while COMPLETE + RUNNING + WAITING trials fall
  short of ``trials``, and one that finds, at its start or before it reports, ``trials`` such
  trials numbered before it is PRUNED (``user_attrs["surplus"]``), never COMPLETE.

Failing and queueing again a dead process's trials is :mod:`agents.study_storage`
(:func:`~agents.study_storage.fail_dead_trials`, ``MAX_RETRY``, ``GRACE_S``); the coordinator and the
surplus check are :mod:`agents.tune_workers`. This module imports neither.
"""

from __future__ import annotations

import os
import socket
import sys
import time
from typing import Callable

RECONNECT_S = 120.0       # how long a process retries a lost database before it stops (default)
BACKOFF_S = (0.2, 5.0)    # first and longest wait between two tries


def redact(url: str) -> str:
    """A storage URL without its password, fit to print."""
    if "://" in url and "@" in url.split("://", 1)[1]:
        scheme, rest = url.split("://", 1)
        cred, host = rest.rsplit("@", 1)
        if ":" in cred:
            return f"{scheme}://{cred.split(':', 1)[0]}:***@{host}"
    return url


class StorageUnavailable(RuntimeError):
    """The study's database stayed unreachable for ``reconnect_s``; its finished trials are kept there."""

    def __init__(self, storage: str, study: str, seconds: float, why: str):
        super().__init__(f"the database {redact(storage)} was unreachable for {seconds:g} s ({why})")
        self.storage, self.study, self.seconds, self.why = storage, study, seconds, why


def exception_chain(exc: BaseException | None):
    """``exc``, then what caused it or was being handled when it was raised, and so on."""
    seen: set[int] = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        yield exc
        exc = exc.__cause__ or exc.__context__


def interrupt_in(exc: BaseException | None) -> KeyboardInterrupt | None:
    """The Ctrl-C (or SIGTERM: :class:`aero_env.signals.Terminated`) somewhere in ``exc``'s chain, or None."""
    return next((e for e in exception_chain(exc) if isinstance(e, KeyboardInterrupt)), None)


def interrupted(exc: BaseException | None) -> bool:
    """Ctrl-C somewhere in ``exc``'s chain: Optuna, SQLAlchemy or a driver cut by it raise another error
    (Optuna's own "Should not reach", an UnboundLocalError, a connection invalidated), which must stop the
    run as Ctrl-C does, never be retried as a lost connection."""
    return interrupt_in(exc) is not None


def is_db_error(exc: BaseException | None) -> bool:
    """A lost or refused connection, or a busy SQLite database, anywhere in ``exc``'s chain (Optuna wraps
    SQLAlchemy's errors in StorageInternalError, and an error while handling one may be raised instead);
    never one that Ctrl-C caused."""
    try:
        import sqlalchemy.exc as sa
    except ImportError:
        return False
    if interrupted(exc):
        return False
    return any(isinstance(e, (sa.OperationalError, sa.InterfaceError, sa.DisconnectionError))
               or (isinstance(e, sa.DBAPIError) and e.connection_invalidated) for e in exception_chain(exc))


def _db_reason(exc: BaseException) -> str:
    """The database error in ``exc``'s chain, in one line: the driver's message, not Optuna's wrapper."""
    import sqlalchemy.exc as sa

    found = next((e for e in exception_chain(exc) if isinstance(e, (sa.OperationalError, sa.InterfaceError,
                                                           sa.DisconnectionError))), exc)
    text = str(getattr(found, "orig", None) or found).strip().splitlines()
    return f"{type(found).__name__}: {text[0] if text else ''}"


class Reconnect:
    """Calls ``fn()`` again after a database error, waiting 0.2 s, 0.4 s, ... up to 5 s between tries, for
    ``seconds`` in all; then raises :class:`StorageUnavailable`. Says once, in one line, that it waits."""

    def __init__(self, seconds: float, who: str, storage: str, study: str, reset: Callable | None = None):
        self.seconds, self.who, self.storage, self.study, self.reset = seconds, who, storage, study, reset

    def __call__(self, fn: Callable):
        deadline, delay = None, BACKOFF_S[0]
        while True:
            try:
                return fn()
            except Exception as exc:
                stop = interrupt_in(exc)
                if stop is not None:  # of its kind: SIGTERM's ends the run with 143, not Ctrl-C's 130
                    raise type(stop)() from None
                if not is_db_error(exc):
                    raise
                now = time.monotonic()
                if deadline is None:
                    deadline = now + self.seconds
                    print(f"aero-env tune: {self.who} lost the database ({_db_reason(exc)}); retrying for up to "
                          f"{self.seconds:g} s", file=sys.stderr, flush=True)
                if now >= deadline:
                    raise StorageUnavailable(self.storage, self.study, self.seconds, _db_reason(exc)) from None
                if self.reset is not None:  # no session left half-way through a transaction on a dead connection
                    self.reset()
                time.sleep(min(delay, deadline - now))
                delay = min(2 * delay, BACKOFF_S[1])


def _read(path: str) -> str | None:
    try:
        with open(path) as f:
            return f.read().strip()
    except OSError:
        return None


_HOST_KEY: dict[int, str] = {}


def _host_key() -> str:
    """This machine's name, boot and pid namespace: two processes with one key see each other's pids."""
    if os.getpid() not in _HOST_KEY:
        try:
            ns = os.stat("/proc/self/ns/pid").st_ino
        except OSError:
            ns = None
        _HOST_KEY[os.getpid()] = f"{socket.gethostname()}/{_read('/proc/sys/kernel/random/boot_id')}/{ns}"
    return _HOST_KEY[os.getpid()]


def _start_ticks(pid: int) -> tuple[str, int] | None:
    """``pid``'s state and start time (clock ticks since boot) from /proc; None where there is no /proc."""
    stat = _read(f"/proc/{pid}/stat")
    if stat is None:
        return None
    fields = stat.rsplit(")", 1)[1].split()
    return fields[0], int(fields[19])


def process_stamp() -> dict:
    """What identifies this process for as long as it runs: host key, pid and start time."""
    here = _start_ticks(os.getpid())
    return {"host": _host_key(), "pid": os.getpid(), "start": None if here is None else here[1]}


def process_gone(stamp: dict) -> bool:
    """True only where the stamped process is certainly gone: stamped on this host (same boot and pid
    namespace) and its pid is free, a zombie, or another process's (started at another time)."""
    if not isinstance(stamp, dict) or stamp.get("host") != _host_key() or not isinstance(stamp.get("pid"), int):
        return False
    try:
        os.kill(stamp["pid"], 0)
    except ProcessLookupError:
        return True
    except PermissionError:  # another user's process holds the pid: whose, the start time says
        pass
    now = _start_ticks(stamp["pid"])
    if now is None:  # no /proc: the pid is taken, assume by the worker
        return False
    return now[0] in ("Z", "X") or (stamp.get("start") is not None and now[1] != stamp["start"])
