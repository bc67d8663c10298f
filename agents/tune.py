"""Black-box design tuning on Optuna: CMA-ES, TPE, or random search as the baseline.

One trial is one design: Optuna proposes a point of the environment's action box (one
parameter per tunable, named by its field, in [-1, 1] so log-scaled fields are searched on
their log scale), :class:`~agents.design_eval.DesignEvaluator` scores it as the mean env
reward over ``seeds_per_design`` episode seeds (the same seeds for every trial), and the
study maximises that mean. With build tolerances in the scene, several seeds per design make
the robust design win.

Storage decides who can share a study:

| storage                     | shared by                         | resumable |
|-----------------------------|-----------------------------------|-----------|
| ``memory``                  | this process                      | no        |
| ``sqlite:///FILE.db``       | processes on this machine         | yes       |
| ``postgresql://USER@HOST/DB`` | processes on many machines      | yes       |

``trials`` is the study's target: a run on a study that already has finished trials runs only
the rest, so a study resumed by name (same ``storage`` and ``study``) continues where it
stopped. ``workers`` local processes split the remaining trials between them; each records
its name in the trials it ran (``user_attrs["worker"]``). Runs on other machines against the
same study stop once the study holds ``trials`` finished trials (each may overshoot by the
trials it had in flight).

A study records the scene it was made for (a fingerprint of the config), the seeds per design
and the sampler: resuming it with another scene, seed count or ``--sampler`` is refused (CMA-ES
and TPE read their state from the study's trials; another sampler would silently restart the
search inside it). Ctrl-C raises :class:`TuneInterrupted` carrying the best design of the trials
finished so far; a study in a database keeps them and resumes by rerunning the same command.

With one worker and a fixed ``seed`` a study is reproducible; with several, the order in which
trials finish (and so what the sampler learns when) depends on timing.

Multi-fidelity tuning (``screen="reduced"``): before a new study's first trial, ``screen_designs``
random designs (seeded by ``seed``) are scored at the cheap fidelity on the same episode draws,
as one batch; the best ``trials`` of them, ranked by that score (ties in draw order), are
enqueued, and the study confirms them at the config's own fidelity. The sampler then only
proposes trials beyond those. What the screen cost and found is kept in the study, so a resumed
study reports it without screening again.
"""

from __future__ import annotations

import hashlib
import json
import logging
import multiprocessing as mp
import os
import socket
import time
import warnings
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from aero_env.config import FIDELITY_PRESETS, Config, ConfigError, from_dict
from aero_env.design_space import DesignSpace

from .design_eval import DesignEvaluator
from .options import SAMPLERS, check_choice, check_ints

DEFAULT_FILE_STORAGE = "sqlite:///aero-env-tune.db"  # used when a study must outlive the process
HEARTBEAT_S = 10          # a trial's process marks it alive this often (RDB storages) ...
GRACE_S = 60              # ... and a trial silent this long is failed when the study resumes
FINISHED = ("COMPLETE", "PRUNED", "FAIL")


@dataclass(frozen=True)
class TuneSettings:
    """What ``aero-env tune`` was asked to do; every field is checked by :meth:`check`."""

    sampler: str = "cmaes"
    trials: int = 100
    seeds_per_design: int = 1
    seed: int = 0
    storage: str | None = None      # None: memory with one worker and no study name, else DEFAULT_FILE_STORAGE
    study: str | None = None        # None: "<config stem>-<sampler>-s<seed>"
    workers: int = 1
    progress: bool = True
    screen: str | None = None       # a cheaper fidelity to screen random designs with (e.g. reduced)
    screen_designs: int = 20000     # designs the screen scores

    def check(self) -> "TuneSettings":
        check_choice("sampler", self.sampler, SAMPLERS)
        check_ints(self, (("trials", 1, 10**7), ("seeds_per_design", 1, 10**4), ("workers", 1, 512),
                          ("seed", 0, 2**31 - 1), ("screen_designs", 1, 10**8)))
        if self.screen is not None:
            check_choice("screen", self.screen, tuple(FIDELITY_PRESETS))
        if self.storage is not None and self.storage != "memory" and "://" not in self.storage:
            raise ConfigError(f"--storage {self.storage!r}: must be 'memory' or a database URL "
                              f"(sqlite:///FILE.db, postgresql://USER@HOST:PORT/DB)")
        if self.storage == "memory" and self.workers > 1:
            raise ConfigError(f"--storage memory with --workers {self.workers}: processes cannot share an "
                              f"in-memory study; give --storage sqlite:///FILE.db or a postgresql:// URL")
        return self

    def resolved_storage(self) -> str:
        if self.storage is not None:
            return self.storage
        return "memory" if self.workers == 1 and self.study is None else DEFAULT_FILE_STORAGE

    def study_name(self, config_name: str) -> str:
        return self.study or f"{config_name}-{self.sampler}-s{self.seed}"

    @property
    def eval_seeds(self) -> tuple[int, ...]:
        """The episode seeds every design is scored on (the same for every trial and every tuning seed)."""
        return tuple(range(self.seeds_per_design))


@dataclass
class TuneResult:
    study: str
    storage: str
    sampler: str
    trials: int                       # finished trials in the study
    trials_run: int                   # ... of which this call ran
    best_reward: float
    best_design: dict
    best_action: list                 # the best design as a point of the env's action box
    best_trial: int
    best_score: dict
    first_full_row_trial: int | None  # first trial whose every seed traversed the whole row
    full_row: int
    wall_time: float
    workers: list = field(default_factory=list)
    history: list = field(default_factory=list)   # (trial number, value) in trial order
    screen: dict | None = None        # the multi-fidelity screen: fidelity, designs, wall_time, scores
    fidelity: str = "mbd"             # the fidelity every trial was scored at

    def to_json_dict(self) -> dict:
        d = asdict(self)
        d["storage"] = redact(self.storage)
        del d["history"]
        return d


def redact(url: str) -> str:
    """A storage URL without its password, fit to print."""
    if "://" in url and "@" in url.split("://", 1)[1]:
        scheme, rest = url.split("://", 1)
        cred, host = rest.rsplit("@", 1)
        if ":" in cred:
            return f"{scheme}://{cred.split(':', 1)[0]}:***@{host}"
    return url


# ---- Optuna pieces ----

class _QuietInterrupts(logging.Filter):
    """Ctrl-C fails the running trial, which Optuna logs as a warning with a traceback (and then its value,
    None); :class:`TuneInterrupted` says it in one line instead. Other failures are logged as before."""

    def __init__(self):
        super().__init__()
        self.trial: str | None = None

    def filter(self, record: logging.LogRecord) -> bool:
        if record.exc_info and isinstance(record.exc_info[1], KeyboardInterrupt):
            self.trial = record.getMessage().split(" ", 2)[1]  # "Trial N failed with parameters: ..."
            return False
        if self.trial is not None and record.getMessage().startswith(f"Trial {self.trial} failed with value"):
            self.trial = None
            return False
        return True


_QUIET = _QuietInterrupts()


def _optuna():
    try:
        import optuna
    except ImportError:
        raise ConfigError("aero-env tune needs Optuna: pip install -e '.[tune]'") from None
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    trials_log = logging.getLogger("optuna.study._optimize")
    if _QUIET not in trials_log.filters:
        trials_log.addFilter(_QUIET)
    return optuna


def make_sampler(name: str, seed: int):
    """The Optuna sampler for ``name``, seeded."""
    optuna = _optuna()
    if name == "cmaes":
        # Optuna's defaults (mean at the box's centre, sigma0 a sixth of the box) on the cmaes
        # package; Optuna 5 deprecates x0/sigma0 and dropped IPOP restarts, so none is set here.
        return optuna.samplers.CmaEsSampler(seed=seed, warn_independent_sampling=False)
    if name == "tpe":
        return optuna.samplers.TPESampler(seed=seed, multivariate=True, constant_liar=True)
    return optuna.samplers.RandomSampler(seed=seed)


def open_storage(url: str):
    optuna = _optuna()
    if url == "memory":
        return optuna.storages.InMemoryStorage()
    try:
        with warnings.catch_warnings():  # heartbeats are marked experimental; they are what fails dead trials
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            return optuna.storages.RDBStorage(url, heartbeat_interval=HEARTBEAT_S, grace_period=GRACE_S)
    except ImportError as exc:  # the URL's driver is missing (psycopg: SQLAlchemy's for postgresql://)
        raise ConfigError(f"--storage {redact(url)}: its database driver is missing ({exc}); for PostgreSQL: "
                          f"pip install -e '.[postgres]'") from None
    except Exception as exc:  # sqlalchemy's connection errors: name the URL, not the stack
        raise ConfigError(f"--storage {redact(url)}: cannot open ({type(exc).__name__}: "
                          f"{str(exc).splitlines()[0]})") from None


def config_fingerprint(cfg: Config) -> str:
    """Identifies the scene and design space a study was made for."""
    return hashlib.sha256(json.dumps(cfg.to_dict(), sort_keys=True).encode()).hexdigest()[:16]


def _load_study(cfg: Config, settings: TuneSettings, storage, name: str, sampler):
    optuna = _optuna()
    study = optuna.create_study(storage=storage, study_name=name, sampler=sampler, direction="maximize",
                                load_if_exists=True)
    mark = study.user_attrs.get("config_fingerprint")
    fp = config_fingerprint(cfg)
    made_with = study.user_attrs.get("sampler")  # absent in studies made before it was recorded
    if mark is None:
        study.set_user_attr("config_fingerprint", fp)
        study.set_user_attr("config", cfg.to_dict())
        study.set_user_attr("seeds_per_design", settings.seeds_per_design)
        study.set_user_attr("sampler", settings.sampler)
    elif made_with is not None and made_with != settings.sampler:
        raise ConfigError(f"--sampler {settings.sampler}: study {name!r} was run with --sampler {made_with}; "
                          f"resume it with --sampler {made_with}, or give a new --study name")
    elif mark != fp:
        raise ConfigError(f"--study {name!r}: this study was made for another scene or design space "
                          f"(fingerprint {mark}, this config {fp}); give a new --study name")
    elif study.user_attrs.get("seeds_per_design") != settings.seeds_per_design:
        raise ConfigError(f"--seeds-per-design {settings.seeds_per_design}: study {name!r} scores designs on "
                          f"{study.user_attrs.get('seeds_per_design')} seeds; its rewards would not compare")
    return study


def _finished(study) -> list:
    optuna = _optuna()
    states = tuple(getattr(optuna.trial.TrialState, s) for s in FINISHED)
    return study.get_trials(deepcopy=False, states=states)


def _complete(study) -> list:
    return [t for t in _finished(study) if t.state.name == "COMPLETE"]


def objective_for(evaluator: DesignEvaluator, worker: str) -> Callable:
    names = evaluator.param_names

    def objective(trial) -> float:
        action = np.array([trial.suggest_float(n, -1.0, 1.0) for n in names])
        score = evaluator.score(action)
        for key, value in score.to_json_dict().items():
            trial.set_user_attr(key, value)
        trial.set_user_attr("worker", worker)
        return score.mean_reward

    return objective


def _worker_name(index: int) -> str:
    return f"{socket.gethostname()}:{os.getpid()}:w{index}"


def _run_trials(cfg: Config, settings: TuneSettings, storage, name: str, quota: int, index: int,
                on_trial: Callable | None = None, ran: list[int] | None = None) -> list[int]:
    """Run ``quota`` trials of the study in this process; the trial numbers it ran (appended to ``ran``
    as they finish, so that a caller interrupted meanwhile knows them)."""
    optuna = _optuna()
    evaluator = DesignEvaluator(cfg, settings.eval_seeds)
    # each worker its own sampler stream: two processes with one seed would propose the same designs
    sampler = make_sampler(settings.sampler, settings.seed + 7919 * index)
    study = _load_study(cfg, settings, storage, name, sampler)
    ran = [] if ran is None else ran

    def record(study_, trial):
        ran.append(trial.number)
        if on_trial is not None:
            on_trial(study_, trial)

    stop = optuna.study.MaxTrialsCallback(settings.trials)  # other machines may be filling the same study
    study.optimize(objective_for(evaluator, _worker_name(index)), n_trials=quota, callbacks=[record, stop])
    evaluator.close()
    return ran


def _worker_main(cfg_dict: dict, settings: TuneSettings, url: str, name: str, quota: int, index: int, queue) -> None:
    try:
        ran = _run_trials(from_dict(cfg_dict), settings, open_storage(url), name, quota, index)
        queue.put((index, _worker_name(index), ran, None))
    except BaseException as exc:  # reported by the parent, which names the worker
        queue.put((index, _worker_name(index), [], f"{type(exc).__name__}: {exc}"))


# ---- the tuning run ----

class TuneInterrupted(Exception):
    """Ctrl-C during tuning. ``result``: the study's best so far (None before its first finished trial);
    ``storage``, ``study``: where its trials are (an in-memory study ends with the process)."""

    def __init__(self, result: "TuneResult | None", storage: str, study: str, finished: int, target: int):
        super().__init__(f"interrupted after {finished} of {target} trials")
        self.result, self.storage, self.study, self.finished, self.target = result, storage, study, finished, target


def tune(cfg: Config, settings: TuneSettings, config_name: str = "config") -> TuneResult:
    """Run (or resume) the study; returns its best design and what this call did.

    Ctrl-C raises :class:`TuneInterrupted` with the best design of the trials finished so far."""
    settings.check()
    url = settings.resolved_storage()
    name = settings.study_name(config_name)
    storage = open_storage(url)
    study = _load_study(cfg, settings, storage, name, make_sampler(settings.sampler, settings.seed))
    t0 = time.perf_counter()
    workers: list[dict] = []
    try:
        if settings.screen and not study.trials:
            screened = screen(cfg, settings)
            for action in screened.pop("actions"):
                study.enqueue_trial({t.name: float(a) for t, a in zip(cfg.tunable, action)})
            study.set_user_attr("screen", screened)
        done = len(_complete(study))
        remaining = max(0, settings.trials - done)
        with _Progress(settings.trials, done, enabled=settings.progress and remaining > 0) as bar:
            if remaining and settings.workers == 1:
                ran: list[int] = []
                workers.append(dict(worker=_worker_name(0), trials=ran))
                _run_trials(cfg, settings, storage, name, remaining, 0, on_trial=lambda s, t: bar.update(s), ran=ran)
            elif remaining:
                workers = _run_workers(cfg, settings, url, name, remaining, study, bar)
    except KeyboardInterrupt:
        wall = time.perf_counter() - t0
        try:
            partial = _result(cfg, study, settings, url, name, wall, workers)
        except RuntimeError:  # no trial finished yet
            partial = None
        raise TuneInterrupted(partial, url, name, len(_complete(study)), settings.trials) from None
    wall = time.perf_counter() - t0
    return _result(cfg, study, settings, url, name, wall, workers)


def _run_workers(cfg, settings, url, name, remaining, study, bar) -> list[dict]:
    ctx = mp.get_context("spawn")  # a clean interpreter per worker: no inherited sockets or threads
    queue = ctx.Queue()
    n = min(settings.workers, remaining)
    quotas = [remaining // n + (1 if i < remaining % n else 0) for i in range(n)]
    procs = [ctx.Process(target=_worker_main, args=(cfg.to_dict(), settings, url, name, q, i, queue), daemon=True)
             for i, q in enumerate(quotas)]
    for p in procs:
        p.start()
    reports = []
    try:
        while len(reports) < n:
            try:
                reports.append(queue.get(timeout=0.5))
            except Exception:  # queue.Empty: nothing yet; refresh the bar from the shared storage
                if not any(p.is_alive() for p in procs) and queue.empty():
                    break
            bar.update(study)
    except KeyboardInterrupt:  # Ctrl-C reaches the workers too; stop any that is still running
        for p in procs:
            p.terminate()
        for p in procs:
            p.join()
        raise
    for p in procs:
        p.join()
    failed = [(w, err) for _, w, _, err in reports if err]
    lost = n - len(reports)
    if failed or lost:
        why = "; ".join(f"worker {w}: {err}" for w, err in failed) or f"{lost} worker(s) died without a report"
        raise RuntimeError(f"tuning workers failed: {why}")
    return [dict(worker=w, trials=ran) for _, w, ran, _ in sorted(reports)]


def screen(cfg: Config, settings: TuneSettings) -> dict:
    """Score ``screen_designs`` random designs at fidelity ``screen`` on the evaluator's episode draws;
    the best ``trials`` actions first. One vectorised batch when the fidelity is ``reduced``."""
    from gymnasium.utils import seeding

    from aero_env.simulation import simulate

    t0 = time.perf_counter()
    cheap = cfg.replace({"sim.fidelity": settings.screen})
    space = DesignSpace(cheap)
    rng = np.random.default_rng(settings.seed)
    actions = rng.uniform(-1.0, 1.0, (settings.screen_designs, space.dim))
    seeds = settings.eval_seeds if space.draws_anything else settings.eval_seeds[:1]
    draws = [space.draw(seeding.np_random(s)[0]) for s in seeds]  # what env.reset(seed=s) draws
    cfgs = [space.episode_config(space.values(a), d)[0] for a in actions for d in draws]
    if cheap.sim.model == "reduced":
        from aero_env.models.reduced import simulate_batch

        res = simulate_batch(cfgs)
        rewards = np.where(np.asarray(res.outcome) == "unstable", 0.0, np.asarray(res.traversals, float))
    else:
        rewards = np.array([0.0 if r.outcome == "unstable" else float(r.traversals) for r in map(simulate, cfgs)])
    scores = rewards.reshape(len(actions), len(draws)).mean(axis=1)
    order = np.argsort(-scores, kind="stable")[:settings.trials]  # ties: in draw order (seeded)
    full_row = cfg.scene.frames - 1
    return dict(fidelity=settings.screen, designs=len(actions), seeds=len(draws),
                wall_time=time.perf_counter() - t0, best_score=float(scores.max()),
                full_row_designs=int((scores >= full_row).sum()),
                enqueued=len(order), enqueued_scores=[float(scores[i]) for i in order],
                actions=[actions[i].tolist() for i in order])


def _result(cfg, study, settings, url, name, wall, workers) -> TuneResult:
    done = sorted(_complete(study), key=lambda t: t.number)
    if not done:
        raise RuntimeError(f"study {name!r} has no completed trial")
    best = max(done, key=lambda t: (t.value, -t.number))  # the first trial to reach the best value
    full_row = cfg.scene.frames - 1
    first_full = next((t.number for t in done if min(t.user_attrs["traversals"]) >= full_row), None)
    return TuneResult(study=name, storage=url, sampler=settings.sampler, trials=len(done),
                      trials_run=sum(len(w["trials"]) for w in workers), best_reward=float(best.value),
                      best_design=dict(best.user_attrs["design"]), best_trial=best.number,
                      best_action=[best.params[t.name] for t in cfg.tunable],
                      best_score={k: best.user_attrs[k] for k in ("rewards", "traversals", "outcomes")},
                      first_full_row_trial=first_full, full_row=full_row, wall_time=wall, workers=workers,
                      history=[(t.number, float(t.value)) for t in done], screen=study.user_attrs.get("screen"),
                      fidelity=cfg.sim.fidelity)


class _Progress:
    """A tqdm bar of finished trials with the best reward so far (on stderr; silent when disabled)."""

    def __init__(self, total: int, done: int, enabled: bool):
        self.bar = None
        if enabled:
            from tqdm import tqdm

            self.bar = tqdm(total=total, initial=done, desc="trials", unit="trial", dynamic_ncols=True)

    def update(self, study) -> None:
        if self.bar is None:
            return
        done = _complete(study)
        self.bar.n = len(done)
        if done:
            self.bar.set_postfix_str(f"best {max(t.value for t in done):.3g}", refresh=False)
        self.bar.refresh()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.bar is not None:
            self.bar.close()


# ---- outputs ----

def best_config(cfg: Config, result: TuneResult) -> Config:
    return cfg.with_values(result.best_design)


def write_best_yaml(cfg: Config, result: TuneResult, path: str | Path) -> None:
    """The tuned design as a complete config that ``load_config`` reads back."""
    header = (f"# Tuned by `aero-env tune` ({result.sampler}, study {result.study!r}, trial {result.best_trial} "
              f"of {result.trials}):\n# mean reward {result.best_reward:.4g}, traversals per seed "
              f"{result.best_score['traversals']} of {result.full_row}.\n")
    Path(path).write_text(header + best_config(cfg, result).to_yaml())


def plot_history(result: TuneResult, path: str | Path, title: str = "") -> None:
    """Reward of each trial and the best so far (the optimisation history)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n, v = (np.array(x) for x in zip(*result.history))
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.scatter(n, v, s=10, alpha=0.5, label="trial")
    ax.step(n, np.maximum.accumulate(v), where="post", color="C3", label="best so far")
    ax.axhline(result.full_row, ls=":", color="0.4", label=f"whole row ({result.full_row})")
    ax.set(xlabel="trial", ylabel="mean reward (traversals)", ylim=(-0.2, result.full_row + 0.8),
           title=title or f"{result.study}: {result.sampler}")
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary_lines(result: TuneResult) -> list[str]:
    first = "never" if result.first_full_row_trial is None else f"at trial {result.first_full_row_trial}"
    lines = [f"study {result.study!r} ({redact(result.storage)}): {result.trials} trials, {result.trials_run} run "
             f"now in {result.wall_time:.1f} s ({result.sampler})",
             f"best mean reward {result.best_reward:.4g} at trial {result.best_trial}; traversals per seed "
             f"{result.best_score['traversals']} of {result.full_row}; the whole row first {first}",
             "best design:"]
    lines += [f"  {k} = {v:.6g}" for k, v in result.best_design.items()]
    if result.screen:
        s = result.screen
        lines.insert(1, f"screened {s['designs']} designs at fidelity {s['fidelity']} in {s['wall_time']:.1f} s "
                        f"({s['full_row_designs']} scored the whole row there); confirmed the best {s['enqueued']} "
                        f"at {result.fidelity}")
    return lines
