"""Optuna's side of tuning: the sampler, the storage, the study and the trials of dead processes.

:func:`open_storage` opens a study's database. SQLite studies run in WAL mode with a 60 s busy timeout,
so local workers do not meet "database is locked". On an RDB storage the process that runs a trial is
stamped on it (``system_attrs["aero_process"]``: host, boot, pid namespace, pid and start time) in the
transaction that makes it RUNNING; :func:`fail_dead_trials` fails the RUNNING trials whose process is
gone from this host or never beat, and :func:`requeue_trial` (also the heartbeat's callback) queues
their designs again; :func:`requeue_unfinished` queues again those that Ctrl-C or SIGTERM stopped.
:func:`load_study` refuses to resume a study with another scene, seed count, robust builds, sampler or
seed. A SQLite file that is not a database, or is damaged, is refused in one line before it is opened.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import time
import warnings
from datetime import datetime, timedelta

from aero_env.config import Config, ConfigError, MissingExtra

from .study_faults import exception_chain, interrupted, is_db_error, process_gone, process_stamp, redact
from .tune_settings import TuneSettings, sqlite_file

HEARTBEAT_S = 10          # a trial's process marks it alive this often (RDB storages) ...
GRACE_S = 60              # ... and a trial silent this long is failed by the next trial's start
MAX_RETRY = 2             # a design whose worker died is queued again at most this many times
PROCESS_ATTR = "aero_process"
FINISHED = ("COMPLETE", "PRUNED", "FAIL")


# ---- Optuna pieces ----

class _QuietInterrupts(logging.Filter):
    """Ctrl-C fails the running trial, which Optuna logs as a warning with a traceback (and then its value,
    None); :class:`TuneInterrupted` says it in one line instead. So does a lost database connection
    (:class:`Reconnect` says it). Other failures are logged as before."""

    def __init__(self):
        super().__init__()
        self.trial: str | None = None

    def filter(self, record: logging.LogRecord) -> bool:
        if record.exc_info and (interrupted(record.exc_info[1]) or is_db_error(record.exc_info[1])
                                or finished_elsewhere(record.exc_info[1])):
            self.trial = record.getMessage().split(" ", 2)[1]  # "Trial N failed with parameters: ..."
            return False
        if self.trial is not None and record.getMessage().startswith(f"Trial {self.trial} failed with value"):
            self.trial = None
            return False
        return True


_QUIET = _QuietInterrupts()


def _quiet_fallback(record: logging.LogRecord) -> bool:
    """Optuna's RDB storage logs a lost connection while reading trials as a many-line warning ("Caught an
    error from sqlalchemy ... Falling back to a slower alternative") before the error itself is raised;
    :class:`Reconnect` says it in one line."""
    return not record.getMessage().startswith("Caught an error from sqlalchemy")


def quiet_cut_cursor(record: logging.LogRecord) -> bool:
    """SQLAlchemy's connection pool logs a cursor that Ctrl-C (or SIGTERM) cut while it fetched, and that then would
    not close, as "Error closing cursor" with two tracebacks (1 in 40 SIGTERMs inside a trial); the run's own line
    says it stopped. Other errors are logged as before."""
    return not (record.exc_info and interrupted(record.exc_info[1]))


def import_optuna():
    try:
        import optuna
    except ImportError:
        raise MissingExtra("aero-env tune", "Optuna", "tune") from None
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    for name, quiet in (("optuna.study._optimize", _QUIET), ("optuna.storages._rdb.storage", _quiet_fallback),
                        ("sqlalchemy.pool.impl.QueuePool", quiet_cut_cursor)):  # the pool of every engine opened here
        log = logging.getLogger(name)
        if quiet not in log.filters:
            log.addFilter(quiet)
    return optuna


def make_sampler(name: str, seed: int):
    """The Optuna sampler for ``name``, seeded."""
    optuna = import_optuna()
    if name == "cmaes":
        # Optuna's defaults (mean at the box's centre, sigma0 a sixth of the box) on the cmaes
        # package; Optuna 5 deprecates x0/sigma0 and dropped IPOP restarts, so none is set here.
        return optuna.samplers.CmaEsSampler(seed=seed, warn_independent_sampling=False)
    if name == "tpe":
        return optuna.samplers.TPESampler(seed=seed, multivariate=True, constant_liar=True)
    return optuna.samplers.RandomSampler(seed=seed)


def open_storage(url: str):
    optuna = import_optuna()
    if url == "memory":
        return optuna.storages.InMemoryStorage()
    if url.startswith("sqlite"):  # a busy database waits (up to 60 s) instead of failing "database is locked"
        check_sqlite_file(url)
        engine_kwargs: dict = {"connect_args": {"timeout": 60}}
    else:  # a connection dropped by a server restart is replaced, not used; an unreachable host fails in 10 s
        engine_kwargs = {"pool_pre_ping": True}
        if url.startswith("postgresql"):
            engine_kwargs["connect_args"] = {"connect_timeout": 10}
    try:
        for attempt in range(5):
            try:
                with warnings.catch_warnings():  # heartbeats are marked experimental; they fail dead trials
                    warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
                    storage = _storage_class()(url, engine_kwargs=engine_kwargs, heartbeat_interval=HEARTBEAT_S,
                                               grace_period=GRACE_S, heartbeat_stale_trial_callback=requeue_trial)
                break
            except Exception as exc:
                # processes opening a new database at once each make Optuna's tables, and collide: a table made twice
                # ("table studies already exists", one tune of two started together failed so) or its version's row
                # written twice (IntegrityError); the next try finds them made
                made_meanwhile = type(exc).__name__ == "IntegrityError" or "already exists" in str(exc)
                if attempt == 4 or not made_meanwhile:
                    raise
                time.sleep(0.2 * (attempt + 1))
        if url.startswith("sqlite"):
            _use_wal(storage.engine)
        return storage
    except ImportError as exc:  # the URL's driver is missing (psycopg: SQLAlchemy's for postgresql://)
        raise ConfigError(f"--storage {redact(url)}: its database driver is missing ({exc}); for PostgreSQL: "
                          f"pip install -e '.[postgres]'") from None
    except Exception as exc:  # sqlalchemy's connection errors: name the URL, not the stack
        raise ConfigError(f"--storage {redact(url)}: cannot open ({type(exc).__name__}: "
                          f"{str(exc).splitlines()[0]})") from exc  # the cause: a worker retries a lost one


def _use_wal(engine, tries: int = 50) -> None:
    """Put a SQLite study in WAL mode (readers never block the writer; the mode stays with the file). Switching
    needs the file to itself, and SQLite answers "database is locked" at once, without its busy timeout, while
    another process holds its write lock: one of four tunes started together on a new file failed so. The switch is
    retried (up to about 10 s); a file another process switched meanwhile is left as it is."""
    for attempt in range(tries):
        try:
            with engine.connect() as conn:
                if conn.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal":
                    return
                conn.exec_driver_sql("PRAGMA journal_mode=WAL")
                return
        except Exception as exc:
            if "database is locked" not in str(exc) or attempt == tries - 1:
                raise
            time.sleep(0.2)


def check_sqlite_file(url: str) -> None:
    """Refuse, in one line, a SQLite file that is not a database or is damaged (pages overwritten), before Optuna
    opens it: read through it raised a 108-line traceback, or failed every trial forever where the damage hid the
    study's direction. ``PRAGMA quick_check`` reads every page (milliseconds for a study of thousands of trials)."""
    import sqlite3
    from contextlib import closing

    path = sqlite_file(url)
    if not path or not os.path.isfile(path) or os.path.getsize(path) == 0:  # a new file: nothing to check
        return
    try:
        with closing(sqlite3.connect(path, timeout=60)) as conn:
            found = [row[0] for row in conn.execute("PRAGMA quick_check")]
    except sqlite3.DatabaseError as exc:
        if exc.sqlite_errorname == "SQLITE_NOTADB":
            raise ConfigError(f"study file {path!r} (--storage {url}): not a SQLite database (or its header is "
                              f"damaged); give the study's file, or a new file name to start a study there") from None
        if not exc.sqlite_errorname.startswith("SQLITE_CORRUPT"):
            raise  # locked, unreadable: open_storage names it
        found = [str(exc)]
    if found != ["ok"]:
        # quick_check's first finding, without its "*** in database main ***" heading
        why = next((line for f in found for line in f.splitlines() if not line.startswith("***")), found[0])
        raise ConfigError(f"study file {path!r} (--storage {url}): damaged ({why}); its trials cannot be read: "
                          f"move it aside (or restore it from a backup) and rerun to start the study afresh")


_STORAGE_CLASS = None


def _storage_class():
    """Optuna's RDBStorage, which stamps the trials this process makes RUNNING with the process (in the
    same transaction for a new trial), remembers them (``owned``), and keeps its heartbeat thread alive
    through a lost connection (it beats again at the next interval)."""
    global _STORAGE_CLASS
    if _STORAGE_CLASS is not None:
        return _STORAGE_CLASS
    optuna = import_optuna()
    from optuna.trial import FrozenTrial, TrialState

    class TuneStorage(optuna.storages.RDBStorage):
        def __init__(self, *args, **kwargs):
            self.owned: set[int] = set()
            super().__init__(*args, **kwargs)

        def _create_new_trial(self, study_id, template_trial=None):
            if template_trial is None:  # a trial the sampler fills, run here: stamped as it is made
                template_trial = FrozenTrial(
                    number=-1, state=TrialState.RUNNING, value=None, datetime_start=datetime.now(),
                    datetime_complete=None, params={}, distributions={}, user_attrs={},
                    system_attrs={PROCESS_ATTR: process_stamp()}, intermediate_values={}, trial_id=-1)
            frozen = super()._create_new_trial(study_id, template_trial)
            if frozen.state == TrialState.RUNNING:
                self.owned.add(frozen._trial_id)
            return frozen

        def set_trial_state_values(self, trial_id, state, values=None):
            if state == TrialState.RUNNING and values is None:
                changed = self._take_waiting(trial_id)
            else:
                changed = super().set_trial_state_values(trial_id, state, values)
            if changed and state == TrialState.RUNNING:  # a queued trial taken (and stamped) by this process
                self.owned.add(trial_id)
            elif state.is_finished():
                self.owned.discard(trial_id)
            return changed

        def _take_waiting(self, trial_id) -> bool:
            """Take a queued trial: WAITING -> RUNNING in one conditional UPDATE, True for the one process whose
            update found it WAITING. Optuna reads the state, then writes it, under ``SELECT ... FOR UPDATE``,
            which SQLite ignores: two workers could both read WAITING and both run the trial (four threads
            claiming one queued trial of a SQLite study: two or more took it in 15 rounds of 20). The process
            stamp is written in the same transaction: a kill between the two writes left a RUNNING trial with no
            process, failed only after the heartbeat's grace (a resume waited a minute for it)."""
            from optuna.storages._rdb import models
            from optuna.storages._rdb.storage import _create_scoped_session

            trial = models.TrialModel
            with _create_scoped_session(self.scoped_session) as session:
                taken = (session.query(trial)
                         .filter(trial.trial_id == trial_id, trial.state == TrialState.WAITING)
                         .update({trial.state: TrialState.RUNNING}, synchronize_session=False))
                if taken == 1:  # the update holds the row (SQLite: the database) until this transaction commits
                    trial.find_or_raise_by_id(trial_id, session).datetime_start = datetime.now()  # as Optuna's own
                    self._set_trial_attr_without_commit(session, models.TrialSystemAttributeModel, trial_id,
                                                        PROCESS_ATTR, process_stamp())
            return taken == 1

        def unbeaten_trial_ids(self, study_id: int) -> set[int]:
            """RUNNING trials with no heartbeat yet: the heartbeat never fails one whose process died before it
            began beating (see :func:`fail_dead_trials`)."""
            from optuna.storages._rdb import models
            from optuna.storages._rdb.storage import _create_scoped_session

            with _create_scoped_session(self.scoped_session) as session:
                rows = (session.query(models.TrialModel.trial_id)
                        .outerjoin(models.TrialHeartbeatModel,
                                   models.TrialHeartbeatModel.trial_id == models.TrialModel.trial_id)
                        .filter(models.TrialModel.study_id == study_id,
                                models.TrialModel.state == TrialState.RUNNING,
                                models.TrialHeartbeatModel.trial_id.is_(None)).all())
            return {r[0] for r in rows}

        def record_heartbeat(self, trial_id):
            try:
                super().record_heartbeat(trial_id)
            except Exception as exc:
                if not is_db_error(exc):
                    raise
                self.remove_session()  # this thread's session: a fresh one for the next beat

    _STORAGE_CLASS = TuneStorage
    return TuneStorage


def finished_elsewhere(exc: BaseException | None) -> bool:
    """The running trial was finished by another process (failed as stale): Optuna's error in recording it."""
    optuna = import_optuna()
    return not interrupted(exc) and any(
        isinstance(e, optuna.exceptions.UpdateFinishedTrialError)
        or (isinstance(e, ValueError) and str(e).startswith("Cannot tell a")) for e in exception_chain(exc))


# ---- dead processes' trials ----

def requeue_trial(study, trial, bounded: bool = True) -> bool:
    """A failed trial's design queued again (WAITING, same params and system attrs but the process stamp),
    at most ``MAX_RETRY`` times unless not ``bounded``; Optuna's RetryHeartbeatStaleTrialCallback without carrying
    the stamp. Whether it was queued."""
    optuna = import_optuna()
    attrs = {k: v for k, v in trial.system_attrs.items() if k != PROCESS_ATTR}
    history = [*attrs.get("retry_history", []), trial.number]
    if bounded and len(history) > MAX_RETRY:
        return False
    attrs.update(failed_trial=attrs.get("failed_trial", trial.number), retry_history=history)
    study.add_trial(optuna.create_trial(state=optuna.trial.TrialState.WAITING, params=trial.params,
                                        distributions=trial.distributions, system_attrs=attrs))
    return True


def _fail_and_requeue(study, storage, trial_id: int) -> bool:
    optuna = import_optuna()
    try:
        if not storage.set_trial_state_values(trial_id, state=optuna.trial.TrialState.FAIL):
            return False
    except optuna.exceptions.UpdateFinishedTrialError:  # it finished meanwhile, or another process failed it
        return False
    requeue_trial(study, storage.get_trial(trial_id))
    return True


def fail_dead_trials(study) -> list[int]:
    """Fail (and queue again) the RUNNING trials whose stamped process is gone from this host, and those that
    never beat for longer than the heartbeat's grace; their numbers. Nothing to do for an in-memory study,
    whose trials die with their process."""
    storage = getattr(study._storage, "_backend", study._storage)
    if not hasattr(storage, "owned"):
        return []
    optuna = import_optuna()
    running = study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.RUNNING,))
    since = datetime.now() - timedelta(seconds=storage.grace_period or GRACE_S)
    old = {t._trial_id for t in running if t.datetime_start is not None and t.datetime_start < since}
    silent = old & storage.unbeaten_trial_ids(study._study_id) if old else set()
    return [t.number for t in running
            if (process_gone(t.system_attrs.get(PROCESS_ATTR)) or t._trial_id in silent)
            and _fail_and_requeue(study, storage, t._trial_id)]


def requeue_unfinished(study) -> list[int]:
    """Queue again the design of every FAIL trial that no trial retries; their numbers. Ctrl-C or SIGTERM in a trial's
    objective has Optuna fail it and nothing queued it again (the config's own design, trial 0, was then never
    scored), and a kill between failing a trial and queueing its copy leaves one so too. Called as a run starts,
    so a resumed study reruns each once more, however often it was stopped before (``MAX_RETRY`` bounds the
    copies within one run, so a design that kills its process is tried a few times per run, not forever). A FAIL
    trial that another run has just failed and not yet queued may be queued twice: its design is scored twice."""
    optuna = import_optuna()
    trials = study.get_trials(deepcopy=False)
    retried = {n for t in trials for n in t.system_attrs.get("retry_history", ())}
    return [t.number for t in trials if t.state == optuna.trial.TrialState.FAIL and t.number not in retried
            and requeue_trial(study, t, bounded=False)]


def release_orphans(study, storage) -> list[int]:
    """Fail (and queue again) the trials this process made RUNNING and no longer runs: a lost connection
    cut them, or Ctrl-C came while Optuna was recording them. Called between trials only."""
    released = []
    for trial_id in sorted(getattr(storage, "owned", ())):
        trial = storage.get_trial(trial_id)  # the database's state, not a cache's
        if trial.state.name == "RUNNING" and _fail_and_requeue(study, storage, trial_id):
            released.append(trial.number)
        storage.owned.discard(trial_id)
    return released


# ---- the study ----

def config_fingerprint(cfg: Config) -> str:
    """Identifies the scene and design space a study was made for."""
    return hashlib.sha256(json.dumps(cfg.to_dict(), sort_keys=True).encode()).hexdigest()[:16]


def load_study(cfg: Config, settings: TuneSettings, storage, name: str, sampler):
    """Make study ``name``, or load it and refuse settings that would change what it means: the scene, the seeds
    per design, ``robust``, the sampler and its seed (the builds ``robust`` scores on and the screen's designs are
    drawn from it too; with one worker the seed makes the study reproducible). ``trials`` (the target),
    ``workers``, ``reconnect_s`` may differ on resume, and so may ``screen``, which acts on a new study only."""
    optuna = import_optuna()
    study = optuna.create_study(storage=storage, study_name=name, sampler=sampler, direction="maximize",
                                load_if_exists=True)
    mark = study.user_attrs.get("config_fingerprint")
    fp = config_fingerprint(cfg)
    attrs = study.user_attrs
    if mark is None:
        study.set_user_attr("config", cfg.to_dict())
        study.set_user_attr("seeds_per_design", settings.seeds_per_design)
        study.set_user_attr("sampler", settings.sampler)
        study.set_user_attr("robust", settings.robust)
        study.set_user_attr("seed", settings.seed)
        # the mark last: a study cut short before it is made again, not refused for a setting not yet recorded
        study.set_user_attr("config_fingerprint", fp)
    elif mark != fp:
        raise ConfigError(f"--study {name!r}: this study was made for another scene or design space "
                          f"(fingerprint {mark}, this config {fp}); give a new --study name")
    else:
        # (option, the study's value, this run's); sampler and seed are absent in studies made before they were kept
        for option, stored, given in (("--sampler", attrs.get("sampler", settings.sampler), settings.sampler),
                                      ("--seeds-per-design", attrs.get("seeds_per_design"), settings.seeds_per_design),
                                      ("--robust", attrs.get("robust", 0), settings.robust),
                                      ("--seed", attrs.get("seed", settings.seed), settings.seed)):
            if stored != given:
                raise ConfigError(f"{option} {given}: study {name!r} was run with {option} {stored}; resume it "
                                  f"with {option} {stored}, or give a new --study name")
    return study


def _finished(study) -> list:
    optuna = import_optuna()
    states = tuple(getattr(optuna.trial.TrialState, s) for s in FINISHED)
    return study.get_trials(deepcopy=False, states=states)


def complete_trials(study) -> list:
    return [t for t in _finished(study) if t.state.name == "COMPLETE"]
