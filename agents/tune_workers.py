"""The processes that run a study's trials.

:func:`run_trials` runs trials in this process until its share is COMPLETE or the study is full;
:func:`run_workers` (the coordinator) starts ``workers`` spawned processes (:func:`_worker_main`) that
split the remaining trials, starts a new worker for the share of one that dies, and stops them all
on Ctrl-C or a failure. Each records its name in the trials it ran (``user_attrs["worker"]``);
:func:`objective_for` scores a trial and prunes one that is surplus to the study's ``trials``.
"""

from __future__ import annotations

import functools
import multiprocessing as mp
import os
import queue as queue_mod
import signal
import socket
import sys
import threading
import time
import warnings
from collections import Counter
from typing import Callable

import numpy as np

from aero_env.config import Config, from_dict
from aero_env.signals import Terminated, signal_name

from .design_eval import DesignEvaluator
from .study_faults import Reconnect, StorageUnavailable, is_db_error
from .study_storage import (complete_trials, fail_dead_trials, finished_elsewhere, import_optuna, load_study,
                            make_sampler, open_storage, release_orphans)
from .tune_settings import TuneSettings

MAX_DEATHS = 8            # workers that may die in one run before the run stops (a design that kills them)
POLL_S = 0.5              # a worker with nothing to start looks again this often
STOP_S = 15.0             # Ctrl-C: how long the workers get to fail their trials before they are killed
STOPPED = ("interrupt", "terminated", "storage", "error")  # how a worker's report ends the run


# ---- a worker: trials in this process ----

def objective_for(evaluator: DesignEvaluator, worker: str, target: int | None = None) -> Callable:
    """The study's objective; with ``target``, a trial that finds ``target`` live trials (COMPLETE, RUNNING or
    WAITING) numbered before it, at its start or before it reports, is PRUNED as surplus: a study filled
    by several runs at once never ends with more than ``target`` COMPLETE trials."""
    names = evaluator.param_names
    start = evaluator.start_params

    def objective(trial) -> float:
        _drop_surplus(trial, target)
        action = np.array([trial.suggest_float(n, -1.0, 1.0) for n in names])
        is_start = start is not None and trial.params == start  # enqueued (or queued again) as the start
        # the config's own design (enqueued first): scored from its values, exactly, not its action's rounding
        score = evaluator.score(action, evaluator.start_design if is_start else None)
        for key, value in score.to_json_dict().items():
            trial.set_user_attr(key, value)
        if is_start:
            trial.set_user_attr("start", True)
        if evaluator.factors is not None:  # the hand-made builds it was scored on (the same for every trial)
            trial.set_user_attr("robust_factors", evaluator.factors.tolist())
            trial.set_user_attr("robust_full", sum(t >= evaluator.full_row for t in score.traversals))
        trial.set_user_attr("worker", worker)
        _drop_surplus(trial, target)
        return score.mean_reward

    return objective


def _drop_surplus(trial, target: int | None) -> None:
    if target is None:
        return
    optuna = import_optuna()
    S = optuna.trial.TrialState
    live = trial.study.get_trials(deepcopy=False, states=(S.COMPLETE, S.RUNNING, S.WAITING))
    if sum(t.number < trial.number for t in live) >= target:
        trial.set_user_attr("surplus", True)
        raise optuna.TrialPruned(f"the study's {target} trials are taken by trials before this one")


def worker_name(index: int) -> str:
    return f"{socket.gethostname()}:{os.getpid()}:w{index}"


def run_trials(cfg: Config, settings: TuneSettings, storage, name: str, quota: int, index: int,
                on_trial: Callable | None = None, ran: list[int] | None = None) -> list[int]:
    """Run trials in this process until ``quota`` of them are COMPLETE or the study holds ``trials``
    COMPLETE trials; the numbers of its COMPLETE trials (appended to ``ran`` as they finish, so that a
    caller interrupted meanwhile knows them). Before each trial it fails the trials of processes gone from
    this host and those a lost connection cut here; it starts one only while the study's COMPLETE, RUNNING
    and WAITING trials fall short of ``trials``, else waits (a running trial may yet die). A lost database
    is retried for ``settings.reconnect_s``, then :class:`StorageUnavailable`. A worker whose coordinator
    is gone stops after its trial."""
    optuna = import_optuna()
    S = optuna.trial.TrialState
    evaluator = DesignEvaluator(cfg, settings.eval_seeds, settings.build_factors())
    # each worker its own sampler stream: two processes with one seed would propose the same designs
    sampler = make_sampler(settings.sampler, settings.seed + 7919 * index)
    reconnect = Reconnect(settings.reconnect_s, f"worker w{index} (pid {os.getpid()})",
                           settings.resolved_storage(), name, reset=getattr(storage, "remove_session", None))
    study = reconnect(lambda: load_study(cfg, settings, storage, name, sampler))
    objective = objective_for(evaluator, worker_name(index), settings.trials)
    ran = [] if ran is None else ran
    parent = os.getppid() if mp.parent_process() is not None else None

    def record(study_, trial):
        if trial.state == S.COMPLETE:
            ran.append(trial.number)
        if on_trial is not None:
            on_trial(study_, trial)

    def step() -> bool:  # False: the study is full
        take_kept_interrupt()  # a Ctrl-C that landed in a garbage-collection callback stops here
        release_orphans(study, storage)
        fail_dead_trials(study)
        count = Counter(t.state for t in study.get_trials(deepcopy=False))
        if count[S.COMPLETE] >= settings.trials:
            return False
        if not count[S.WAITING] and count[S.COMPLETE] + count[S.RUNNING] >= settings.trials:
            with warnings.catch_warnings():  # the rest is running elsewhere: wait, failing any that goes silent
                warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
                optuna.storages.fail_stale_trials(study)
            time.sleep(POLL_S)
            return True
        try:
            study.optimize(objective, n_trials=1, callbacks=[record])
        except Exception as exc:
            if not finished_elsewhere(exc):
                raise
            print(f"aero-env tune: worker w{index} (pid {os.getpid()}): its trial was failed by another process "
                  f"(its heartbeat was late); the design was queued again", file=sys.stderr, flush=True)
        return True

    hook = sys.unraisablehook
    sys.unraisablehook = functools.partial(keep_swallowed_interrupts, passed_on=hook)
    try:
        while len(ran) < quota and (parent is None or os.getppid() == parent) and reconnect(step):
            pass
    finally:
        sys.unraisablehook = hook
        stop_stray_heartbeats()
        evaluator.close()
    return ran


def stop_stray_heartbeats(timeout: float = 5.0) -> int:
    """Stop the Optuna heartbeat threads this process left running; how many it stopped.

    Optuna beats for each trial from a thread (not a daemon) started and stopped by a ``with`` block around the
    objective. A Ctrl-C that lands while the block enters (``Thread.start`` waits for the thread to begin) or
    leaves skips the stop, and the thread beats on: the run printed its interrupt line, and then the process
    waited for that thread at exit, forever (seen once in about 25 interrupted tunes). Every trial's own
    thread has been stopped by the time :func:`run_trials` returns, so any still running here is such a stray.
    A Ctrl-C inside ``Thread.start`` can also leave the thread not yet begun (listed, but ``join`` refuses it:
    "cannot join thread before it is started": seen twice as an interrupted tune's traceback and exit status 1
    in the real-Ctrl-C test): it is waited for to begin, then joined; one that never begins has its stop set
    and is left, as it ends on its first look at it.
    """
    from optuna.storages._heartbeat import HeartbeatThread

    stopped = 0
    for thread in threading.enumerate():
        # the thread's target and arguments (trial id, storage, stop event), as HeartbeatThread.start made it
        if getattr(thread, "_target", None) is HeartbeatThread._record_heartbeat:
            thread._args[2].set()
            begun = getattr(thread, "_started", None)  # CPython's Event that Thread.start waits on
            if begun is None or begun.wait(timeout):
                thread.join(timeout)
            stopped += 1
    return stopped


# A Ctrl-C whose KeyboardInterrupt is raised while Python runs a garbage-collection callback (a weakref's, e.g.
# SQLAlchemy's) cannot propagate: Python prints it as "Exception ignored in ..." with a traceback and goes on, and
# the run would go on (a worker with Ctrl-C already ignored). While trials run, this hook keeps it instead, and
# the next trial raises it, of its kind (a SIGTERM's Terminated ends the run with 143, not Ctrl-C's 130).
_KEPT_INTERRUPTS: list[KeyboardInterrupt] = []


def keep_swallowed_interrupts(unraisable, passed_on: Callable | None = None) -> None:
    """``sys.unraisablehook`` while :func:`run_trials` runs: keep a KeyboardInterrupt Python could not raise (see
    above), without a word; pass everything else on to ``passed_on``, the hook it replaced (default: Python's)."""
    if isinstance(unraisable.exc_value, KeyboardInterrupt):
        _KEPT_INTERRUPTS.append(unraisable.exc_value)
        return
    (passed_on or sys.__unraisablehook__)(unraisable)


def take_kept_interrupt() -> None:
    """Raise the KeyboardInterrupt (or :class:`Terminated`) :func:`keep_swallowed_interrupts` kept first, once."""
    if _KEPT_INTERRUPTS:
        kept = type(_KEPT_INTERRUPTS[0])
        _KEPT_INTERRUPTS.clear()
        raise kept


def stop_once_on_signals() -> None:
    """A worker's Ctrl-C and SIGTERM from now on: the first raises (:func:`_interrupt_once`), the rest do nothing."""
    signal.signal(signal.SIGINT, _interrupt_once)
    signal.signal(signal.SIGTERM, _interrupt_once)  # Python's default would end it at once, its trial RUNNING


def _interrupt_once(signum, frame):
    """Ctrl-C or SIGTERM in a worker: KeyboardInterrupt (:class:`Terminated` for SIGTERM), and every later one of
    either ignored. A terminal's Ctrl-C, or a scheduler's SIGTERM to the whole job (SLURM), reaches the worker and
    then the coordinator's own (:func:`_stop_workers`): the second would cut Optuna failing the trial."""
    signal.signal(signal.SIGINT, _ignore_signal)
    signal.signal(signal.SIGTERM, _ignore_signal)
    raise Terminated if signum == signal.SIGTERM else KeyboardInterrupt


def _ignore_signal(signum, frame):
    """A later Ctrl-C or SIGTERM in a worker: nothing. Not SIG_IGN: one that arrived with the first (the job's SIGTERM
    and the coordinator's SIGINT) is still pending when the first's handler runs, and Python reports a pending
    signal whose handler became SIG_IGN as "Signal 15 ignored due to race condition", with a traceback."""


def _worker_main(cfg_dict: dict, settings: TuneSettings, url: str, name: str, quota: int, index: int, queue) -> None:
    stop_once_on_signals()  # it started with Ctrl-C ignored (run_workers)
    ran: list[int] = []
    kind, err = "ok", None
    try:
        reconnect = Reconnect(settings.reconnect_s, f"worker w{index} (pid {os.getpid()})", url, name)
        run_trials(from_dict(cfg_dict), settings, reconnect(lambda: open_storage(url)), name, quota, index, ran=ran)
    except KeyboardInterrupt as stop:
        kind, err = ("terminated" if isinstance(stop, Terminated) else "interrupt"), signal_name(stop)
    except StorageUnavailable as exc:
        kind, err = "storage", exc.why
    except BaseException as exc:  # reported by the parent, which names the worker
        kind, err = "error", f"{type(exc).__name__}: {exc}"
    queue.put((index, worker_name(index), ran, kind, err))


# ---- the coordinator: worker processes ----

class WorkersFailed(RuntimeError):
    """The workers could not go on (one reported an error, or too many died): one line saying which and why; the
    study keeps every trial they finished."""



def _quiet_db(fn: Callable):
    """``fn()``, or None where the database cannot be reached just now (the workers retry; this can wait)."""
    try:
        return fn()
    except Exception as exc:
        if not is_db_error(exc):
            raise
        return None


class _SigintIgnored:
    """Ctrl-C ignored while a worker process starts: it inherits that until :func:`_worker_main` runs, so
    that a Ctrl-C while it imports stops it through the coordinator rather than with a traceback."""

    def __enter__(self):
        self.old = None
        if threading.current_thread() is threading.main_thread():
            self.old = signal.signal(signal.SIGINT, signal.SIG_IGN)

    def __exit__(self, *exc):
        if self.old is not None:
            signal.signal(signal.SIGINT, self.old)


def _drain(queue, timeout: float) -> list:
    got = []
    try:
        got.append(queue.get(timeout=timeout))
        while True:
            got.append(queue.get_nowait())
    except queue_mod.Empty:
        return got


def _stop_workers(procs: list) -> None:
    """Ctrl-C each worker (Optuna fails its trial), wait up to ``STOP_S`` for all, then kill the rest."""
    alive = [p for p in procs if p.is_alive()]
    for p in alive:
        try:
            os.kill(p.pid, signal.SIGINT)
        except ProcessLookupError:
            pass
    deadline = time.monotonic() + STOP_S
    try:
        for p in alive:
            p.join(max(0.0, deadline - time.monotonic()))
    except KeyboardInterrupt:  # a second Ctrl-C: wait no longer
        pass
    for p in alive:
        if p.is_alive():
            p.kill()
        p.join()


def run_workers(cfg, settings, url, name, remaining, study, bar) -> list[dict]:
    """``settings.workers`` processes share the ``remaining`` trials. One that dies without a report (SIGKILL,
    OOM) has its RUNNING trial failed and queued again, and a new worker takes the rest of its share; on
    Ctrl-C or SIGTERM (to this process, to a worker or to all), or when one reports an error, all are stopped and
    what they left RUNNING is failed; the run then raises what stopped it (:class:`Terminated` for SIGTERM)."""
    ctx = mp.get_context("spawn")  # a clean interpreter per worker: no inherited sockets or threads
    reports = ctx.Queue()
    n = min(settings.workers, remaining)
    quotas = [remaining // n + (1 if i < remaining % n else 0) for i in range(n)]
    procs: dict[int, tuple] = {}    # index -> (process, its share of trials)
    ended: dict[int, dict] = {}     # index -> worker, trials (COMPLETE), kind, err
    next_index, deaths = n, 0

    def start(index: int, quota: int) -> None:
        p = ctx.Process(target=_worker_main, args=(cfg.to_dict(), settings, url, name, quota, index, reports),
                        daemon=True)
        with _SigintIgnored():
            p.start()
        procs[index] = (p, quota)

    def collect(timeout: float) -> None:
        for index, worker, ran, kind, err in _drain(reports, timeout):
            ended[index] = dict(worker=worker, trials=ran, kind=kind, err=err)

    try:
        for i, q in enumerate(quotas):
            start(i, q)
        while procs:
            collect(POLL_S)
            for index, (p, quota) in list(procs.items()):
                if index not in ended and not p.is_alive():
                    collect(0.2)  # a report sent just before it exited
                if index in ended:
                    p.join()
                    del procs[index]
                elif not p.is_alive():
                    p.join()
                    del procs[index]
                    deaths += 1
                    worker = f"{socket.gethostname()}:{p.pid}:w{index}"
                    failed = _quiet_db(lambda: fail_dead_trials(study)) or []
                    mine = _quiet_db(lambda: [t.number for t in complete_trials(study)
                                              if t.user_attrs.get("worker") == worker]) or []
                    ended[index] = dict(worker=worker, trials=mine, kind="died", err=None)
                    left = quota - len(mine)
                    code = p.exitcode
                    how = f"killed by {signal.Signals(-code).name}" if code and code < 0 else f"exit status {code}"
                    if deaths > MAX_DEATHS:
                        raise WorkersFailed(f"tuning workers failed: {deaths} workers died ({how} the last); "
                                           f"see the study's FAIL trials for the designs they ran")
                    print(f"aero-env tune: worker {worker} died ({how}) after {len(mine)} trial(s)"
                          + (f"; trial(s) {', '.join(map(str, failed))} failed and queued again" if failed else "")
                          + (f"; a new worker runs its {left} remaining" if left > 0 else ""),
                          file=sys.stderr, flush=True)
                    if left > 0:
                        start(next_index, left)
                        next_index += 1
            if any(e["kind"] in STOPPED for e in ended.values()):
                break
            _quiet_db(lambda: bar.update(study))
    except BaseException:  # Ctrl-C (it reaches the workers too, from a terminal) or a failure here
        _stop_workers([p for p, _ in procs.values()])
        _quiet_db(lambda: fail_dead_trials(study))
        raise
    if procs:  # one reported a failure: stop the others
        _stop_workers([p for p, _ in procs.values()])
        collect(0.2)
    _quiet_db(lambda: fail_dead_trials(study))  # anything a stopped or dead worker left RUNNING
    bad = [e for e in ended.values() if e["kind"] in STOPPED]
    if any(e["kind"] == "storage" for e in bad):
        why = next(e["err"] for e in bad if e["kind"] == "storage")
        raise StorageUnavailable(url, name, settings.reconnect_s, why)
    if any(e["kind"] == "error" for e in bad):
        why = "; ".join(f"worker {e['worker']}: {e['err']}" for e in bad if e["kind"] == "error")
        raise WorkersFailed(f"tuning workers failed: {why}")
    if bad:  # Ctrl-C or SIGTERM reached the workers before this process (or only them): stop as they did
        raise Terminated if any(e["kind"] == "terminated" for e in bad) else KeyboardInterrupt
    return [dict(worker=e["worker"], trials=e["trials"]) for _, e in sorted(ended.items())]
