"""A tune stopped at any moment and resumed (issue 50 §2): the study ends with every trial it was asked for, the
config's own design among them, scored from its values. The stop is raised at a chosen point in this process: inside
a trial's objective, during the screen, or at every storage call of a small study in turn, as Ctrl-C (its handlers
run) or as a kill (nothing runs after it). Real signals to real processes are in tests/test_tune_faults.py."""

from __future__ import annotations

import subprocess
import sys
import threading

import optuna
import pytest

from aero_env.config import load_config
from aero_env.reward import reward
from aero_env.signals import Terminated
from aero_env.simulation import simulate
from agents import design_eval, study_storage
from agents.study_faults import Reconnect, exception_chain, process_stamp
from agents.study_storage import PROCESS_ATTR
from agents.tune import TuneInterrupted, TuneSettings, tune

from .conftest import COARSE, PAPER, ROOT

FAST = {"scene.frames": 3, **COARSE}


@pytest.fixture(scope="module")
def cfg():
    return load_config(PAPER, FAST)


@pytest.fixture(scope="module")
def own_reward(cfg):
    """What the config's own design earns, simulated here (the study must hold exactly this for its start)."""
    return float(reward(simulate(cfg), cfg))


def settings(tmp_path, trials: int, study: str = "s", **kw) -> TuneSettings:
    return TuneSettings(sampler="random", trials=trials, storage=f"sqlite:///{tmp_path / 's.db'}", study=study,
                        progress=False, **kw)


def trials_in(s: TuneSettings) -> list:
    """The study's trials as Optuna reads them from the file (not through the tuner)."""
    return sorted(optuna.load_study(study_name=s.study, storage=s.storage).trials, key=lambda t: t.number)


def check_whole(trials: list, target: int, cfg, own_reward: float) -> None:
    """``target`` COMPLETE trials and none RUNNING; the config's own design among the COMPLETE ones, with its values
    and the reward it earns; every FAIL trial queued again and run to COMPLETE with the params it had drawn (some,
    where it was stopped while Optuna recorded them); not merely drawn again, as a sampler seeded alike can."""
    done = [t for t in trials if t.state.name == "COMPLETE"]
    assert len(done) == target, [(t.number, t.state.name) for t in trials]
    assert not [t for t in trials if t.state.name == "RUNNING"]
    own = {k: cfg.value(k) for k in done[0].user_attrs["design"]}
    starts = [t for t in done if t.user_attrs["design"] == own]
    assert starts and starts[0].value == own_reward and starts[0].user_attrs.get("start") is True
    for failed in (t for t in trials if t.state.name == "FAIL"):
        assert any(failed.number in t.system_attrs.get("retry_history", ())
                   and failed.params.items() <= t.params.items() for t in done), f"trial {failed.number} never ran again"


@pytest.mark.parametrize("stopped, stop", [(0, KeyboardInterrupt), (2, Terminated)])
def test_a_trial_stopped_in_its_objective_runs_again_when_the_study_resumes(cfg, own_reward, tmp_path, monkeypatch,
                                                                            stopped, stop):
    # Optuna fails a trial whose objective Ctrl-C (or SIGTERM) stops, and nothing queued it again: with trial 0, the
    # config's own design, the resumed study never scored it and could write a worse design as the best
    s = settings(tmp_path, 4)
    score = design_eval.DesignEvaluator.score
    calls = []

    def stopping(self, *args, **kw):
        calls.append(1)
        if len(calls) == stopped + 1:
            raise stop
        return score(self, *args, **kw)

    monkeypatch.setattr(design_eval.DesignEvaluator, "score", stopping)
    with pytest.raises(TuneInterrupted) as caught:
        tune(cfg, s)
    assert type(caught.value.by) is stop and caught.value.finished == stopped
    assert [t.state.name for t in trials_in(s)] == ["COMPLETE"] * stopped + ["FAIL"]
    monkeypatch.undo()
    result = tune(cfg, s)
    assert result.trials == 4 and result.start_reward == own_reward
    check_whole(trials_in(s), 4, cfg, own_reward)


def test_a_sigterm_that_cut_a_database_call_stops_the_run_as_a_sigterm():
    # a driver cut by the signal raises its own error, the signal in its chain; the retry loop stops the run with the
    # signal, of its kind (Ctrl-C's KeyboardInterrupt ended a SIGTERM'd run with 130, not 143)
    import sqlalchemy.exc as sa

    def cut():
        try:
            raise Terminated
        except Terminated:
            raise sa.OperationalError("SELECT 1", {}, Exception("connection invalidated")) from None

    with pytest.raises(KeyboardInterrupt) as stopped:
        Reconnect(5.0, "tune", "sqlite:///s.db", "s")(cut)
    assert type(stopped.value) is Terminated


def test_a_worker_stops_once_for_the_jobs_sigterm_and_the_coordinators_ctrl_c_together():
    """SLURM's SIGTERM reaches a worker and the coordinator at once, and the coordinator then sends the worker its
    Ctrl-C: both pending together, Python runs SIGINT's handler first. The worker stops once, and the other signal
    does nothing; set to SIG_IGN instead, Python printed "Signal 15 ignored due to race condition" and a traceback."""
    script = """
import os, signal, threading
from agents.tune_workers import stop_once_on_signals
stop_once_on_signals()
both = {signal.SIGINT, signal.SIGTERM}
signal.pthread_sigmask(signal.SIG_BLOCK, both)  # held pending by this thread (the only one they are sent to)
signal.pthread_kill(threading.get_ident(), signal.SIGTERM)
signal.pthread_kill(threading.get_ident(), signal.SIGINT)
try:
    signal.pthread_sigmask(signal.SIG_UNBLOCK, both)
    sum(range(1000))
except KeyboardInterrupt as stop:
    print(type(stop).__name__, flush=True)
sum(range(1000))  # the other's handler runs by here
os.kill(os.getpid(), signal.SIGTERM)  # and any later one
sum(range(1000))
print("then nothing", flush=True)
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert (out.returncode, out.stdout, out.stderr) == (0, "KeyboardInterrupt\nthen nothing\n", ""), out


def test_a_cursor_a_stop_cut_is_not_logged_with_a_traceback(caplog):
    # SQLAlchemy's pool logs a cursor that would not close after a signal cut its fetch; its error chain holds the stop
    import logging
    import sqlite3

    study_storage.import_optuna()
    pool = logging.getLogger("sqlalchemy.pool.impl.QueuePool")

    def close_failed(during: BaseException) -> None:
        try:
            try:
                raise during
            except BaseException:
                raise sqlite3.ProgrammingError("Cannot operate on a closed database.")
        except sqlite3.ProgrammingError:
            pool.error("Error closing cursor", exc_info=True)

    with caplog.at_level(logging.ERROR):
        close_failed(Terminated())
        close_failed(KeyboardInterrupt())
        close_failed(OSError("disk I/O error"))  # not a stop: logged as before
    assert [r.exc_info[1].__context__.__class__ for r in caplog.records] == [OSError]


def test_a_tune_stopped_during_its_screen_screens_when_resumed(cfg, tmp_path, monkeypatch):
    # the start used to be queued before the screen ran: a study stopped during the screen held a trial, so the resumed
    # one counted as begun and never screened
    from agents import tune as tune_module

    actions = [[0.5] * len(cfg.tunable), [-0.5] * len(cfg.tunable)]
    screened = []

    def screen(cfg_, settings_, slots=None):  # stopped the first time, the second a screen of two designs
        screened.append(slots)
        if len(screened) == 1:
            raise KeyboardInterrupt
        return dict(fidelity="reduced", designs=2, actions=[list(a) for a in actions])

    monkeypatch.setattr(tune_module, "screen", screen)
    s = settings(tmp_path, 3, screen="reduced")
    with pytest.raises(TuneInterrupted):
        tune(cfg, s)
    tune(cfg, s)
    trials = trials_in(s)
    assert screened == [2, 2] and trials[0].user_attrs["start"] is True
    assert [[t.params[p.name] for p in cfg.tunable] for t in trials[1:]] == actions


# ---- stopped at every storage call in turn ----

class Killed(BaseException):
    """A kill -9 where it is raised: no handler catches it (nothing the tuner catches is a BaseException this one
    is), so nothing is written after it."""


# the storage's calls that read or write the database (Optuna's cache calls the private ones)
DB_CALLS = ("create_new_study", "get_study_id_from_name", "get_study_name_from_id", "get_study_directions",
            "get_study_user_attrs", "get_study_system_attrs", "set_study_user_attr", "set_study_system_attr",
            "_create_new_trial", "_get_trials", "_set_trial_param", "_get_stale_trial_ids", "get_trial",
            "get_all_trials", "set_trial_state_values", "set_trial_user_attr", "set_trial_system_attr",
            "unbeaten_trial_ids")


class StopAt:
    """Counts this thread's storage calls (while installed) and stops the run at the ``at``-th: before it runs or
    after, with ``stop`` raised once."""

    def __init__(self, monkeypatch, at: int | None = None, stop=KeyboardInterrupt, after: bool = False):
        self.at, self.stop, self.after, self.calls = at, stop, after, 0
        cls = study_storage._storage_class()
        for name in DB_CALLS:
            monkeypatch.setattr(cls, name, self.wrap(getattr(cls, name)))

    def wrap(self, call):
        def counted(storage, *args, **kw):
            if threading.current_thread() is not threading.main_thread():  # the heartbeat's
                return call(storage, *args, **kw)
            self.calls += 1
            fire = self.calls == self.at
            if fire and not self.after:
                raise self.stop
            try:
                return call(storage, *args, **kw)
            finally:  # after it returned, or while what it raised (Optuna's DuplicatedStudyError) propagates
                if fire:
                    raise self.stop

        return counted


@pytest.fixture(scope="module")
def dead_stamp():
    """The process stamp of a process that has ended: the stopped run's, as its resume (a new process) sees it."""
    ended = subprocess.Popen(["true"])
    ended.wait()
    return {**process_stamp(), "pid": ended.pid, "start": None}


@pytest.fixture
def cached_scores(monkeypatch):
    """A design scored once per test, its result reused: the test is about the study, not about scoring."""
    score, cache = design_eval.DesignEvaluator.score, {}

    def cached(self, action, design=None):
        key = (tuple(action), None if design is None else tuple(sorted(design.items())))
        if key not in cache:
            cache[key] = score(self, action, design)
        return cache[key]

    monkeypatch.setattr(design_eval.DesignEvaluator, "score", cached)


@pytest.mark.slow
@pytest.mark.parametrize("stop, after", [(KeyboardInterrupt, False), (KeyboardInterrupt, True), (Killed, False)],
                         ids=["ctrl-c before a call", "ctrl-c after a call", "kill"])
def test_a_study_stopped_at_any_storage_call_resumes_whole(cfg, own_reward, tmp_path, monkeypatch, dead_stamp,
                                                          cached_scores, stop, after):
    """Stop a 2-trial tune at its 1st storage call, then (a new study in the same file) at its 2nd, and so on through
    the last; resume each. A kill is a kill between two calls, so it is stopped before each only."""
    with monkeypatch.context() as m:
        counter = StopAt(m)
        tune(cfg, settings(tmp_path, 2, "whole"))
        total = counter.calls
    assert total > 30  # opening, the start's trial and the sampler's, each several reads and writes
    for at in range(1, total + 1):
        s = settings(tmp_path, 2, f"stopped at {at}")
        with monkeypatch.context() as m:
            StopAt(m, at, stop, after)
            m.setattr(study_storage, "process_stamp", lambda: dead_stamp)  # the stopped process ends with the stop
            with pytest.raises(BaseException) as stopped:
                tune(cfg, s)
            # a kill inside Optuna's tell surfaces as the UnboundLocalError of its finally block (a real kill runs
            # nothing after it); a Ctrl-C as TuneInterrupted, or KeyboardInterrupt where no trial had begun
            assert stopped.type in (TuneInterrupted, KeyboardInterrupt) or any(
                isinstance(e, Killed) for e in exception_chain(stopped.value)), stopped.value
        # a trial left RUNNING names its process, so that the resume fails it at once (else after a minute's grace)
        try:
            left = trials_in(s)
        except KeyError:  # stopped before the study was made
            left = []
        assert all(PROCESS_ATTR in t.system_attrs for t in left if t.state.name == "RUNNING"), at
        result = tune(cfg, s)
        assert result.trials == 2, at
        check_whole(trials_in(s), 2, cfg, own_reward)
