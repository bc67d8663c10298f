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
stopped. ``workers`` local processes split the remaining trials between them
(:mod:`agents.tune_workers`). On an RDB storage a run rides out a worker that dies, a lost
database, Ctrl-C and runs of the same study on other machines, and the study ends with exactly
``trials`` COMPLETE trials (:mod:`agents.study_faults`; the Optuna storage and study are
:mod:`agents.study_storage`).

A study records the scene it was made for (a fingerprint of the config), the seeds per design, ``robust``,
the sampler and its seed: resuming it with another of them is refused (CMA-ES and TPE read their state from
the study's trials; another sampler would silently restart the search inside it, and another seed draws other
builds). Ctrl-C (or SIGTERM) raises :class:`TuneInterrupted` carrying the best design of the trials finished so
far; a study in a database keeps them and resumes by rerunning the same command, which first runs again every
trial the stop left unfinished (the config's own design among them), as it does a killed process's.

A new study's first trial is the config's own design (scored from its values, exactly); the best design is
that one unless a trial earns a strictly higher mean reward, so a tune never ends worse than it started, and
:class:`TuneResult` says whether a trial beat it (``improved``). With ``robust`` K > 0 every design is scored on
the same K hand-made builds within :data:`aero_env.robustness.DEFAULT_TOLERANCES`, drawn once from ``seed``
(:meth:`DesignEvaluator.score_design <agents.design_eval.DesignEvaluator.score_design>`).

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

import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from aero_env.config import Config
from aero_env.design_space import DesignSpace
from aero_env.files import save_figure, write_text_atomically

from .design_eval import start_params
from .study_faults import Reconnect, is_db_error, redact
from .study_storage import (complete_trials, fail_dead_trials, load_study, make_sampler, open_storage, release_orphans,
                            requeue_unfinished)
from .tune_settings import TuneSettings
from .tune_workers import run_trials, run_workers, worker_name

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
    start_trial: int | None = None    # the trial that scored the config's own design (None: a study without one)
    start_reward: float | None = None  # ... its mean reward
    start_traversals: list | None = None  # ... its traversals per seed (per build with robust)
    improved: bool | None = None      # whether a trial beat the config's design (strictly higher mean reward)
    robust: int = 0                   # hand-made builds each design was scored on (0: none)
    best_robust_full: int | None = None   # robust: runs of the best design that completed the whole row
    start_robust_full: int | None = None  # ... of the config's own design, on the same builds

    def to_json_dict(self) -> dict:
        d = asdict(self)
        d["storage"] = redact(self.storage)
        del d["history"]
        return d


# ---- the tuning run ----

class TuneInterrupted(Exception):
    """Ctrl-C (or SIGTERM) during tuning. ``result``: the study's best so far (None before its first finished trial);
    ``storage``, ``study``: where its trials are (an in-memory study ends with the process); ``by``: the
    KeyboardInterrupt that stopped it (:class:`aero_env.signals.Terminated` for SIGTERM)."""

    def __init__(self, result: "TuneResult | None", storage: str, study: str, finished: int, target: int,
                 by: KeyboardInterrupt | None = None):
        super().__init__(f"interrupted after {finished} of {target} trials")
        self.result, self.storage, self.study, self.finished, self.target = result, storage, study, finished, target
        self.by = KeyboardInterrupt() if by is None else by


def tune(cfg: Config, settings: TuneSettings, config_name: str = "config") -> TuneResult:
    """Run (or resume) the study; returns its best design and what this call did.

    Ctrl-C raises :class:`TuneInterrupted` with the best design of the trials finished so far; a database
    lost for longer than ``settings.reconnect_s`` raises :class:`StorageUnavailable`. Either way the
    study resumes by calling this again."""
    settings.check()
    space = DesignSpace(cfg)  # a design problem that cannot be posed is refused before a study is opened or made
    if settings.robust:
        from aero_env.robustness.tolerances import DEFAULT_TOLERANCES, check_against

        check_against(cfg, DEFAULT_TOLERANCES)
    url = settings.resolved_storage()
    name = settings.study_name(config_name)
    storage = open_storage(url)
    study = load_study(cfg, settings, storage, name, make_sampler(settings.sampler, settings.seed))
    reconnect = Reconnect(settings.reconnect_s, "tune", url, name, reset=storage.remove_session)
    t0 = time.perf_counter()
    workers: list[dict] = []
    try:
        if not study.trials:  # a fresh study starts from the config's own design (not again on resume)
            start = start_params(space)
            if start is None:
                print("aero-env tune: the config's own design lies outside its tunable ranges: the study starts "
                      "without it", file=sys.stderr, flush=True)
            # screened before anything is queued: a study stopped during the screen is still new when resumed
            screened = screen(cfg, settings, slots=settings.trials - (start is not None)) if settings.screen else None
            if start is not None:
                study.enqueue_trial(start)
            if screened:
                for action in screened.pop("actions"):
                    study.enqueue_trial({t.name: float(a) for t, a in zip(cfg.tunable, action)})
                study.set_user_attr("screen", screened)
        failed = reconnect(lambda: fail_dead_trials(study))  # resuming: not after the heartbeat's grace
        if failed:
            print(f"aero-env tune: trial(s) {', '.join(map(str, failed))} were left RUNNING by processes gone from "
                  f"this host: failed, and their designs queued again", file=sys.stderr, flush=True)
        stopped = reconnect(lambda: requeue_unfinished(study))
        if stopped:
            print(f"aero-env tune: trial(s) {', '.join(map(str, stopped))} were stopped before they finished: their "
                  f"designs queued again", file=sys.stderr, flush=True)
        done = len(reconnect(lambda: complete_trials(study)))
        remaining = max(0, settings.trials - done)
        with _Progress(settings.trials, done, enabled=settings.progress and remaining > 0) as bar:
            if remaining and settings.workers == 1:
                ran: list[int] = []
                workers.append(dict(worker=worker_name(0), trials=ran))
                run_trials(cfg, settings, storage, name, remaining, 0, on_trial=lambda s, t: bar.update(s), ran=ran)
            elif remaining:
                workers = run_workers(cfg, settings, url, name, remaining, study, bar)
    except KeyboardInterrupt as stop:
        wall = time.perf_counter() - t0
        partial, finished = None, 0
        try:
            storage.remove_session()  # not the session Ctrl-C may have cut half-way through a transaction
            release_orphans(study, storage)  # a trial Ctrl-C cut while Optuna was recording it
            finished = len(complete_trials(study))
            partial = _result(cfg, study, settings, url, name, wall, workers)
        except RuntimeError:  # no trial finished yet
            pass
        except Exception as exc:  # the database is gone too: the study still holds what it held
            if not is_db_error(exc):
                raise
        raise TuneInterrupted(partial, url, name, finished, settings.trials, stop) from None
    wall = time.perf_counter() - t0
    return reconnect(lambda: _result(cfg, study, settings, url, name, wall, workers))


def screen(cfg: Config, settings: TuneSettings, slots: int | None = None) -> dict:
    """Score ``screen_designs`` random designs at fidelity ``screen`` on the evaluator's episode draws;
    the best ``slots`` (default ``trials``) actions first. The design is scored as drawn: ``robust`` builds are
    not screened, only confirmed. One vectorised batch when the fidelity is ``reduced``. A design's
    score is the mean env reward over the draws (:mod:`aero_env.reward`, shaping included), what
    ``env.step`` would pay at that fidelity, so the screen ranks by the study's own objective."""
    from aero_env.reward import reward
    from aero_env.simulation import simulate

    t0 = time.perf_counter()
    cheap = cfg.replace({"sim.fidelity": settings.screen})
    space = DesignSpace(cheap)
    rng = np.random.default_rng(settings.seed)
    actions = rng.uniform(-1.0, 1.0, (settings.screen_designs, space.dim))
    seeds = settings.eval_seeds if space.draws_anything else settings.eval_seeds[:1]
    draws = [space.draw_for_seed(s) for s in seeds]
    values = [space.values(a) for a in actions]
    if cheap.sim.model == "reduced":
        from aero_env.models.reduced.batch import reduced_batch

        # one batch of every (design, draw) episode, without a Config per design where the model reads every field
        paid = reduced_batch(cheap, [space.episode_values(v, d)[0] for v in values for d in draws])[1]
    else:
        cfgs = [space.episode_config(v, d)[0] for v in values for d in draws]
        paid = np.array([reward(simulate(c), c) for c in cfgs])
    scores = paid.reshape(len(actions), len(draws)).mean(axis=1)
    order = np.argsort(-scores, kind="stable")[:settings.trials if slots is None else slots]  # ties: in draw order (seeded)
    full_row = cfg.scene.frames - 1
    return dict(fidelity=settings.screen, designs=len(actions), seeds=len(draws),
                wall_time=time.perf_counter() - t0, best_score=float(scores.max()),
                full_row_designs=int((scores >= full_row).sum()),
                enqueued=len(order), enqueued_scores=[float(scores[i]) for i in order],
                actions=[actions[i].tolist() for i in order])


def _result(cfg, study, settings, url, name, wall, workers) -> TuneResult:
    done = sorted(complete_trials(study), key=lambda t: t.number)
    if not done:
        raise RuntimeError(f"study {name!r} has no completed trial")
    best = max(done, key=lambda t: (t.value, -t.number))  # the first trial to reach the best value
    start = next((t for t in done if t.user_attrs.get("start")), None)
    if start is not None and not best.value > start.value:
        best = start  # nothing beat the config's own design: it stays the best, never a design that only ties it
    full_row = cfg.scene.frames - 1
    first_full = next((t.number for t in done if t is not start and min(t.user_attrs["traversals"]) >= full_row),
                      None)
    return TuneResult(study=name, storage=url, sampler=settings.sampler, trials=len(done),
                      trials_run=sum(len(w["trials"]) for w in workers), best_reward=float(best.value),
                      best_design=dict(best.user_attrs["design"]), best_trial=best.number,
                      best_action=[best.params[t.name] for t in cfg.tunable],
                      best_score={k: best.user_attrs[k] for k in ("rewards", "traversals", "outcomes")},
                      first_full_row_trial=first_full, full_row=full_row, wall_time=wall, workers=workers,
                      history=[(t.number, float(t.value)) for t in done], screen=study.user_attrs.get("screen"),
                      fidelity=cfg.sim.fidelity,
                      start_trial=None if start is None else start.number,
                      start_reward=None if start is None else float(start.value),
                      start_traversals=None if start is None else list(start.user_attrs["traversals"]),
                      improved=None if start is None else best is not start,
                      robust=settings.robust,
                      best_robust_full=best.user_attrs.get("robust_full") if settings.robust else None,
                      start_robust_full=(start.user_attrs.get("robust_full") if settings.robust and start is not None
                                         else None))


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
        done = complete_trials(study)
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
    kept = ", the config's own design: no trial beat it" if result.improved is False else ""
    per = f"per build ({result.robust} builds)" if result.robust else "per seed"
    header = (f"# Tuned by `aero-env tune` ({result.sampler}, study {result.study!r}, trial {result.best_trial} "
              f"of {result.trials}{kept}):\n# mean reward {result.best_reward:.4g}, traversals {per} "
              f"{result.best_score['traversals']} of {result.full_row}.\n")
    write_text_atomically(path, header + best_config(cfg, result).to_yaml(), "config file")


def plot_history(result: TuneResult, path: str | Path, title: str = "") -> None:
    """Reward of each trial and the best so far (the optimisation history)."""
    import matplotlib.pyplot as plt

    fig = history_figure(result, title)
    try:
        save_figure(fig, path, dpi=110)
    finally:
        plt.close(fig)


def history_figure(result: TuneResult, title: str = ""):
    """:func:`plot_history`'s figure, laid out, not saved."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n, v = (np.array(x) for x in zip(*result.history))
    fig, ax = plt.subplots(figsize=(8, 4))  # 1 in wider than before: the legend beside the axes
    ax.scatter(n, v, s=10, alpha=0.5, label="trial")
    ax.step(n, np.maximum.accumulate(v), where="post", color="C3", label="best so far")
    ax.axhline(result.full_row, ls=":", color="0.4", label=f"whole row ({result.full_row})")
    ax.set(xlabel="trial", ylabel="mean reward (traversals)", ylim=(-0.2, result.full_row + 0.8),
           title=title or f"{result.study}: {result.sampler}")
    # outside the axes, right of them: inside, any corner may hold trials (lower right covered the last twenty of
    # a 40-trial run, which scored 0 to 2)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    return fig


def _row(traversals, full_row: int) -> str:
    """Traversals of the whole row reached, as 'k/N' (the mean over the runs where they differ)."""
    return f"{float(np.mean(traversals)):.3g}/{full_row}"


def comparison_line(result: TuneResult) -> str | None:
    """The best design against the config's own design (None where the study has no trial of it)."""
    if result.start_trial is None:
        return None
    f = result.full_row
    if result.robust:
        runs = len(result.best_score["traversals"])
        share = lambda k: f"{100.0 * k / runs:.0f} %"
        best = (f"best {_row(result.best_score['traversals'], f)} (robust {share(result.best_robust_full)}, mean "
                f"reward {result.best_reward:.2f})")
        own = (f"the config's {_row(result.start_traversals, f)} ({share(result.start_robust_full)}, "
               f"{result.start_reward:.2f}) on the same {runs} builds")
    else:
        best = f"best {_row(result.best_score['traversals'], f)} (mean reward {result.best_reward:.2f})"
        own = f"the config's own {_row(result.start_traversals, f)} ({result.start_reward:.2f})"
    verdict = (f"trial {result.best_trial} beats it" if result.improved
               else "kept the config's design (no trial beat it)")
    return f"{best} vs {own}: {verdict}"


def _design_line(key: str, value: float, cfg: Config | None) -> str:
    """One tuned value, SI as the config stores it, and as a maker reads it (mm, g, coins and clay, card pair)."""
    from aero_env.sheet.parts import workbench

    reading = workbench(key, value, cfg) if cfg is not None else ""
    return f"  {key} = {value:.6g}" + (f"   ({reading})" if reading else "")


def summary_lines(result: TuneResult, cfg: Config | None = None) -> list[str]:
    """The tune's report; with the study's ``cfg``, each best value also as a maker reads it (in the tuned design,
    where a card pair's mu_k is the pair's own, not the study config's ratio)."""
    tuned = None if cfg is None else best_config(cfg, result)
    first = ("no trial traversed the whole row" if result.first_full_row_trial is None
             else f"the whole row first at trial {result.first_full_row_trial}")
    if (result.first_full_row_trial is None and result.start_trial is not None
            and min(result.start_traversals) >= result.full_row):
        first = "no trial besides the config's own design traversed the whole row"
    per = f"per build ({result.robust} builds)" if result.robust else "per seed"
    lines = [f"study {result.study!r} ({redact(result.storage)}): {result.trials} trials, {result.trials_run} run "
             f"now in {result.wall_time:.1f} s ({result.sampler})",
             f"best mean reward {result.best_reward:.4g} at trial {result.best_trial}; traversals {per} "
             f"{result.best_score['traversals']} of {result.full_row}; {first}"]
    compared = comparison_line(result)
    if compared:
        lines.append(compared)
    lines.append("best design:")
    lines += [_design_line(k, v, tuned) for k, v in result.best_design.items()]
    if result.screen:
        s = result.screen
        lines.insert(1, f"screened {s['designs']} designs at fidelity {s['fidelity']} in {s['wall_time']:.1f} s "
                        f"({s['full_row_designs']} scored the whole row there); confirmed the best {s['enqueued']} "
                        f"at {result.fidelity}")
    return lines
