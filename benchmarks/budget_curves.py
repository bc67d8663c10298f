"""Success against training budget for every learner, each tuned on the watch contexts, and a leaderboard.

    python benchmarks/budget_curves.py [--task hard] [--learners random,cmaes,linear-map,mlp-map,ppo,sac]
                                       [--budgets 1024,4096,16384,40960] [--seeds 0-9] [--holdout 200]
                                       [--holdout-seed 0] [--results FILE] [--plot FILE] [--json]

Six learners, each at the fidelity it trains on, scored at ``mbd`` on the same hold-out contexts (and builds) as
``benchmarks/rl_vs_tuning.py`` scores, with the mean whole-row share and its interval from a bootstrap over seeds,
then contexts (:func:`aero_env.intervals.seeds_then_contexts`):

* ``random``: a search per hold-out episode at ``mbd``, uniform designs in the box until one makes the whole row.
* ``cmaes``: the oracle's search (:func:`agents.context_maps.search_contexts`, at ``mbd``, from the task's start).
  A per-context search spends its budget on the scored episodes themselves: budget B over N hold-out contexts is
  ``B // N`` episodes a context (40,960 over 200: 204), and it must search again for every new context. A context
  solved after e episodes is solved by every budget of at least e a context and by none below (the budget only
  stops a search), so one search to the largest budget gives every budget's outcome.
* ``linear-map``, ``mlp-map``: :func:`agents.context_maps.fit_map` at ``reduced`` from the task's start; one fit to
  the largest budget gives every smaller budget's map exactly (``benchmarks/map_budgets.py``).
* ``ppo``, ``sac``: ``aero-env train``'s training at ``reduced`` with ``benchmarks/rl_policies.py``'s settings; the
  policy after the last update within B episodes is read (through ``agents.rl.policy_actions``, the scoring
  path); where B is a whole number of rollouts (PPO: 1,024 episodes, SAC: 32) it is the policy a run of B episodes
  ends with (constant learning rates), so one run gives every budget's policy. SAC learns from episode 1,056 on
  (``learning_starts`` 1,024): at 1,024 it is its untrained network.

**Settings.** Each learner's main setting (:data:`SETTINGS`; the first value listed is the shipped one) is chosen on
the **watch** contexts (``rl_holdout.WATCH_BASE``, never scored here) at :data:`TUNE_BUDGET` episodes, over
:data:`TUNE_SEEDS`: the value with the highest mean watch share (the shipped value on a tie); ``random`` has none.

**Cost.** An episode's wall time at each fidelity is measured in the same run (the median of three batches of the
watch contexts); the wall column is the learner's own time to the largest budget (scoring taken out), the median
over seeds. ``--results FILE`` keeps every finished (learner, seed) as it goes; a run stopped (Ctrl-C, SIGTERM) goes
on from there when started again with the same options.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from aero_env.intervals import difference_interval, seeds_then_contexts

from map_budgets import check_block, check_seeds, map_at_budgets
from rl_holdout import TASKS, holdout_seeds, single_action, watch_seeds
from rl_policies import N_ENVS, PPO_HP, SAC_HP, parse_seeds, training_seed
from rl_vs_tuning import pct_ci, points_ci

LEARNERS = ("random", "cmaes", "linear-map", "mlp-map", "ppo", "sac")
SEARCHES = ("random", "cmaes")           # a search per scored episode, at mbd
MAPS = {"linear-map": "linear", "mlp-map": "mlp"}
RL = {"ppo": PPO_HP, "sac": SAC_HP}
BUDGETS = (1024, 4096, 16384, 40960)
TUNE_BUDGET = 4096
TUNE_SEEDS = (0, 1)
WATCH = 200  # watch contexts the settings are chosen on
SETTINGS = {  # each learner's main setting and the values tried on the watch contexts; the first is the shipped one
    "random": {},
    "cmaes": {"sigma": (0.3, 0.1, 0.6)},          # the first step, in action units
    "linear-map": {"sigma": (0.1, 0.03, 0.3)},
    "mlp-map": {"sigma": (0.1, 0.03, 0.3)},
    "ppo": {"learning_rate": (3e-4, 1e-4, 1e-3)},
    "sac": {"learning_rate": (3e-4, 1e-4, 1e-3)},
}
CMAES_POPSIZE = 8  # designs a generation of a per-context CMA-ES search (the oracle's)
SEARCH_BATCH = 8  # a random search's designs per context per round (the pool's batch); the count is per design
FIDELITY = {"random": "mbd", "cmaes": "mbd", "linear-map": "reduced", "mlp-map": "reduced", "ppo": "reduced",
            "sac": "reduced"}


class Budgets:
    """What one (learner, setting, seed) reached at each budget: the outcomes on the scored contexts (None: the
    budget is below the learner's first step), the episodes it spent and its own wall time (None: not separable)."""

    def __init__(self):
        self.whole: dict[int, list[int] | None] = {}
        self.episodes: dict[int, int] = {}
        self.wall: dict[int, float | None] = {}

    def to_json(self) -> dict:
        return {str(b): dict(whole=self.whole[b], episodes=self.episodes[b], wall_s=self.wall[b]) for b in self.whole}


def random_search(runner, draws, seed: int, max_evals: int) -> tuple[np.ndarray, float]:
    """Each episode's count of uniform designs tried until one made the whole row (0: none within ``max_evals``),
    and the wall time. Context i's designs are drawn from its own generator, so its answer does not depend on the
    batching or on the other contexts."""
    n, d = len(draws), runner.space.dim
    designs = [np.random.default_rng([seed, i]).uniform(-1.0, 1.0, (max_evals, d)) for i in range(n)]
    first = np.zeros(n, dtype=np.int64)
    tried = np.zeros(n, dtype=np.int64)
    t0 = time.perf_counter()
    open_ = list(range(n))
    while open_:
        take = {i: min(SEARCH_BATCH, max_evals - int(tried[i])) for i in open_}
        batch_draws = [draws[i] for i in open_ for _ in range(take[i])]
        batch = np.concatenate([designs[i][tried[i]:tried[i] + take[i]] for i in open_])
        whole = runner.whole_rows(batch_draws, batch)
        k = 0
        for i in open_:
            hits = np.flatnonzero(whole[k:k + take[i]])
            k += take[i]
            if hits.size:
                first[i] = tried[i] + hits[0] + 1
            tried[i] += take[i]
        open_ = [i for i in open_ if first[i] == 0 and tried[i] < max_evals]
    return first, time.perf_counter() - t0


def cmaes_search(runner, draws, seed: int, max_evals: int, start, sigma: float) -> tuple[np.ndarray, float]:
    """Each episode's episodes until the search made the whole row (0: not within ``max_evals``), and the wall."""
    from agents.context_maps import search_contexts

    t0 = time.perf_counter()
    found = search_contexts(runner, draws, start, seed, max_evals=max_evals, popsize=CMAES_POPSIZE, sigma=sigma)
    return np.where(found.solved, found.evaluations, 0), time.perf_counter() - t0


def cmaes_spent(per: int) -> int:
    """Episodes a CMA-ES search given ``per`` a context spends on a context it leaves unsolved: the start design,
    then whole generations of :data:`CMAES_POPSIZE`."""
    return 1 + CMAES_POPSIZE * ((per - 1) // CMAES_POPSIZE) if per >= 1 else 0


def search_budgets(first: np.ndarray, budgets, n: int, wall: float, spent=lambda per: per) -> Budgets:
    """A per-context search's outcome at each budget (``b // n`` episodes a context; none below one a context) from
    when it first made the row. Its episodes: a solved context's count, and ``spent(per)`` for one left unsolved
    (a random search tries every design it may; CMA-ES only whole generations)."""
    out = Budgets()
    for b in budgets:
        per = b // n
        solved = (first > 0) & (first <= per)
        out.whole[b] = solved.astype(int).tolist() if per else None
        out.episodes[b] = int(np.where(solved, first, spent(per)).sum())
        out.wall[b] = wall if b == max(budgets) else None
    return out


def map_actions(fast, learner: str, seed: int, budgets, start, sigma: float, obs) -> dict:
    """Each budget's map's actions on ``obs`` and the fit's wall time to it (a budget below one generation: none)."""
    from agents.context_maps import ParamMap

    kind = MAPS[learner]
    return {b: (ParamMap(kind, fast.space.obs_dim, fast.space.dim, params=params).act(obs), wall, used)
            for b, (params, wall, used) in map_at_budgets(fast, kind, seed, budgets, start, sigma=sigma).items()}


def rl_actions(task, learner: str, seed: int, budgets, learning_rate: float, obs) -> dict:
    """Each budget's policy's actions on ``obs`` (after the last update within b episodes), the training's wall time
    to it (the snapshots' inference taken out) and the episodes it learnt from."""
    from stable_baselines3.common.callbacks import BaseCallback

    from aero_env.config import load_config
    from agents.rl import TrainSettings, policy_actions, train

    cfg = load_config(task.config, {"sim.fidelity": "reduced"})
    out: dict[int, tuple] = {}
    spent = [0.0]  # the snapshots' own inference, taken out of the training's time
    t0 = [time.perf_counter()]

    def snapshot(model, learnt: int, below: int, wall: float | None = None) -> None:
        """The policy now (after the update on the first ``learnt`` episodes) for every budget in [learnt, below)."""
        for b in budgets:
            if learnt <= b < below and b not in out:
                t = time.perf_counter()
                out[b] = (policy_actions(model, obs), (t - t0[0] if wall is None else wall) - spent[0], learnt)
                spent[0] += time.perf_counter() - t

    class Snapshots(BaseCallback):  # reads the policy only (deterministic predictions: no RNG drawn)
        def __init__(self):
            super().__init__()
            self.learnt = 0

        def _on_training_start(self) -> None:  # the clock train()'s wall_time reads starts here too
            t0[0] = time.perf_counter()

        def _on_step(self) -> bool:
            return True

        def _on_rollout_end(self) -> None:
            # the updates on the episodes before this rollout have run; the update on this one runs next
            snapshot(self.model, self.learnt, int(self.num_timesteps))
            self.learnt = int(self.num_timesteps)

    settings = TrainSettings(algo=learner, timesteps=max(budgets), n_envs=N_ENVS, seed=training_seed(seed),
                             eval_every=0, vector=True, progress=False,
                             hyperparameters=dict(RL[learner], learning_rate=learning_rate))
    with tempfile.TemporaryDirectory(prefix="aero-budget-") as tmp:
        run = train(cfg, settings, tmp, callbacks=[Snapshots()])
        from agents.rl import load_run

        # after its last update; its time is the training's own (saving the run is not training)
        snapshot(load_run(tmp)[0], int(run["timesteps_done"]), max(budgets) + 1, wall=float(run["wall_time"]))
    return out


def learn(learner: str, value, seed: int, budgets, task, mbd, fast, draws, obs, start) -> Budgets:
    """One (learner, setting value, seed) at every budget, scored on ``draws`` at ``mbd``."""
    if learner in SEARCHES:
        per = max(budgets) // len(draws)
        if learner == "random":
            first, wall = random_search(mbd, draws, seed, per)
            return search_budgets(first, budgets, len(draws), wall)
        first, wall = cmaes_search(mbd, draws, seed, per, start, value)
        return search_budgets(first, budgets, len(draws), wall, spent=cmaes_spent)
    got = map_actions(fast, learner, seed, budgets, start, value, obs) if learner in MAPS else \
        rl_actions(task, learner, seed, budgets, value, obs)
    out = Budgets()
    for b in budgets:
        if b in got:
            actions, wall, episodes = got[b]
            out.whole[b] = mbd.whole_rows(draws, actions).astype(int).tolist()
            out.episodes[b], out.wall[b] = int(episodes), float(wall)
        else:
            out.whole[b], out.episodes[b], out.wall[b] = None, 0, None
    return out


def episode_cost(runner, draws, reps: int = 3) -> float:
    """Seconds an episode at ``runner``'s fidelity: the median over ``reps`` batches of ``draws`` (the box's
    centre), the batch as the learners run it."""
    actions = np.zeros((len(draws), runner.space.dim))
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        runner.traversals(draws, actions)
        times.append((time.perf_counter() - t0) / len(draws))
    return float(np.median(times))


def setting_name(learner: str) -> str | None:
    return next(iter(SETTINGS[learner]), None)


class Results:
    """The run so far, kept in ``path`` (atomically, after each finished piece); a file from a run with other
    options is refused in one line."""

    def __init__(self, path: str | None, meta: dict):
        from aero_env.config import ConfigError
        from aero_env.files import read_text

        self.path, self.data = path, dict(meta=meta, tuning={}, runs={})
        if path and Path(path).exists():
            try:
                old = json.loads(read_text(path, "--results", "this script's JSON"))
            except ConfigError as exc:
                sys.exit(f"budget_curves: {exc}")
            except json.JSONDecodeError as exc:
                sys.exit(f"budget_curves: --results {path}: not this script's JSON ({exc.msg}); remove it or name "
                         f"another file")
            if not isinstance(old, dict) or old.get("meta") != meta:
                got = old.get("meta") if isinstance(old, dict) else old
                sys.exit(f"budget_curves: --results {path}: holds a run with other options ({got}); remove it or "
                         f"name another file")
            self.data = old

    def get(self, part: str, key: str):
        return self.data.get(part, {}).get(key)

    def put(self, part: str, key: str, value) -> None:
        from aero_env.files import write_text_atomically

        self.data.setdefault(part, {})[key] = value
        if self.path:
            write_text_atomically(self.path, json.dumps(self.data, indent=1) + "\n", "--results")


def tune(learners, task, mbd, fast, results: Results, log, budget: int = TUNE_BUDGET, watch: int = WATCH) -> dict:
    """Each learner's setting chosen on ``watch`` watch contexts at ``budget`` episodes (module docstring)."""
    draws = watch_draws(mbd, watch)
    obs = mbd.observations(draws)
    start = single_action(fast.space, task)
    chosen = {}
    for learner in learners:
        name = setting_name(learner)
        if name is None:
            chosen[learner] = None
            continue
        shares = []
        for value in SETTINGS[learner][name]:
            key = f"{learner} {name}={value}"
            rec = results.get("tuning", key)
            if rec is None:
                got = [learn(learner, value, s, [budget], task, mbd, fast, draws, obs, start) for s in TUNE_SEEDS]
                whole = [g.whole[budget] for g in got]
                rec = dict(value=value, share=None if None in whole else float(np.mean(whole)))
                results.put("tuning", key, rec)
            log(f"tuning {key}: watch share {rec['share']}")
            shares.append(rec)
        best = max(shares, key=lambda r: -1.0 if r["share"] is None else r["share"])  # the first on a tie
        chosen[learner] = best["value"]
    return chosen


def watch_draws(runner, watch: int = WATCH):
    from agents.episode_runner import draws_for_seeds

    return draws_for_seeds(runner.space, watch_seeds(watch))


def checked(args) -> tuple[list[str], list[int], list[int]]:
    learners = args.learners.split(",")
    bad = [x for x in learners if x not in LEARNERS]
    if bad:
        sys.exit(f"budget_curves: --learners {bad[0]!r}: allowed {', '.join(LEARNERS)}")
    try:
        budgets = sorted({int(b) for b in args.budgets.split(",")})
        seeds = sorted(set(parse_seeds(args.seeds)))
    except ValueError:
        sys.exit(f"budget_curves: --budgets {args.budgets!r} / --seeds {args.seeds!r}: give whole numbers, e.g. "
                 f"1024,40960 and 0-9")
    if budgets[0] < 1:
        sys.exit(f"budget_curves: --budgets {budgets[0]}: at least 1")
    check_seeds("budget_curves", seeds)
    if not 1 <= args.holdout <= max(budgets):
        sys.exit(f"budget_curves: --holdout {args.holdout}: 1 to the largest budget ({max(budgets)}), so a "
                 f"per-context search has an episode a context")
    if args.holdout_seed < 0:
        sys.exit(f"budget_curves: --holdout-seed {args.holdout_seed}: at least 0")
    if not 1 <= args.watch <= args.tune_budget:
        sys.exit(f"budget_curves: --watch {args.watch}: 1 to --tune-budget ({args.tune_budget})")
    for option, path, kinds in (("--plot", args.plot, (".png", ".svg", ".pdf")),
                                ("--results", args.results, (".json",))):
        if path is None:
            continue
        if Path(path).suffix.lower() not in kinds or Path(path).is_dir():
            sys.exit(f"budget_curves: {option} {path}: a file ending {', '.join(kinds)}")
        if not Path(path).resolve().parent.is_dir():
            sys.exit(f"budget_curves: {option} {path}: its folder {Path(path).resolve().parent} does not exist")
    return [x for x in LEARNERS if x in learners], budgets, seeds


def check_map_blocks(learners, budgets, tune_budget: int, space) -> None:
    """Every map fit's contexts inside its seed's block (``benchmarks/map_budgets.py``'s), the tuning's too; refused
    in one line."""
    for learner in [x for x in learners if x in MAPS]:
        for option, budget in (("--budgets", max(budgets)), ("--tune-budget", tune_budget)):
            check_block("budget_curves", option, MAPS[learner], space, budget)


def rows_from(learners, budgets, seeds, results: Results, chosen: dict) -> list[dict]:
    rows = []
    for learner in learners:
        runs = [results.get("runs", f"{learner} seed{s}") for s in seeds]
        for b in budgets:
            at = [r[str(b)] for r in runs]
            row = dict(learner=learner, fidelity=FIDELITY[learner], setting=setting_name(learner),
                       value=chosen[learner], budget=b, seeds=len(seeds),
                       episodes=float(np.median([a["episodes"] for a in at])))
            walls = [a["wall_s"] for a in at]
            row["wall_s"] = None if None in walls else float(np.median(walls))
            if any(a["whole"] is None for a in at):
                row.update(mean=None, ci=None, per_seed=None, outcomes=None)
            else:
                whole = np.array([a["whole"] for a in at])
                mean, ci = seeds_then_contexts(whole)
                row.update(mean=mean, ci=ci, per_seed=[float(w.mean()) for w in whole], outcomes=whole.tolist())
            rows.append(row)
    return rows


def plot(rows, budgets, path: str, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from aero_env.files import save_figure

    fig, ax = plt.subplots(figsize=(7.5, 4.4))
    for k, learner in enumerate(dict.fromkeys(r["learner"] for r in rows)):
        pts = [r for r in rows if r["learner"] == learner and r["mean"] is not None]
        x = [r["budget"] for r in pts]
        y = [100 * r["mean"] for r in pts]
        ax.plot(x, y, "o-", ms=3, color=f"C{k}", label=f"{learner} ({pts[0]['fidelity']})" if pts else learner)
        ax.fill_between(x, [100 * r["ci"][0] for r in pts], [100 * r["ci"][1] for r in pts], color=f"C{k}",
                        alpha=0.12)
    ax.set_xscale("log", base=2)
    ax.set_xticks(budgets, [f"{b:,}" for b in budgets])
    ax.set(xlabel="training episodes (a per-context search: spent on the scored contexts)",
           ylabel="hold-out contexts at mbd, whole row (%)", ylim=(0, 100), title=title)
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    save_figure(fig, path, "--plot", dpi=110)
    plt.close(fig)


def print_tables(rep: dict) -> None:
    budgets = rep["budgets"]
    print(f"{rep['config']}: {rep['holdout']} hold-out contexts (--holdout-seed {rep['holdout_seed']}) at mbd, "
          f"seeds {rep['seeds']}; an episode costs {1e3 * rep['episode_s']['mbd']:.2f} ms at mbd and "
          f"{1e3 * rep['episode_s']['reduced']:.3f} ms at reduced (this run)")
    print(f"\nSettings, chosen on {rep['watch']} watch contexts at {rep['tune_budget']:,} episodes (seeds "
          f"{list(TUNE_SEEDS)}):")
    print("| learner | setting | watch share per value | chosen |")
    print("|---|---|---|---|")
    for learner in rep["learners"]:
        name = setting_name(learner)
        if name is None:
            print(f"| {learner} | none | - | - |")
            continue
        tried = [rep["tuning"][f"{learner} {name}={v}"] for v in SETTINGS[learner][name]]
        cells = ", ".join(f"{t['value']:g}: " + ("-" if t["share"] is None else f"{100 * t['share']:.1f} %")
                          for t in tried)
        print(f"| {learner} | {name} | {cells} | {rep['chosen'][learner]:g} |")
    print("\n| learner | trains at | " + " | ".join(f"{b:,} episodes" for b in budgets) + " |")
    print("|---|---|" + "---|" * len(budgets))
    for learner in rep["learners"]:
        rows = [r for r in rep["rows"] if r["learner"] == learner]
        cells = ["-" if r["mean"] is None else f"{100 * r['mean']:.1f} [{100 * r['ci'][0]:.1f}, {100 * r['ci'][1]:.1f}]"
                 for r in rows]
        print(f"| {learner} | {rows[0]['fidelity']} | " + " | ".join(cells) + " |")
    top = max(budgets)
    print(f"\nAt {top:,} episodes (medians over seeds):")
    print("| learner | whole row: mean [95 % CI] | seeds: lowest-highest | episodes spent | own wall |")
    print("|---|---|---|---|---|")
    board = sorted([r for r in rep["rows"] if r["budget"] == top and r["mean"] is not None],
                   key=lambda r: -r["mean"])
    for r in board:
        wall = "-" if r["wall_s"] is None else f"{r['wall_s']:.0f} s"
        print(f"| {r['learner']} | {pct_ci(r['mean'], r['ci'])} | "
              f"{100 * min(r['per_seed']):.1f}-{100 * max(r['per_seed']):.1f} % | {r['episodes']:,.0f} | {wall} |")
    base = next((r for r in board if r["learner"] == "linear-map"), None)
    if base is not None:
        print(f"against the linear map at {top:,} episodes, paired on the hold-out contexts: " + "; ".join(
            f"{r['learner']} {points_ci(d, ci)}"
            for r in board if r is not base for d, ci in [difference_interval(r["outcomes"], base["outcomes"])]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--task", default="hard", choices=tuple(TASKS))
    ap.add_argument("--learners", default=",".join(LEARNERS), help=f"comma-separated, of {', '.join(LEARNERS)}")
    ap.add_argument("--budgets", default=",".join(str(b) for b in BUDGETS), help="training episodes, comma-separated")
    ap.add_argument("--seeds", default="0-9", help="seeds, 0-9 or 0,2,5")
    ap.add_argument("--holdout", type=int, default=200)
    ap.add_argument("--holdout-seed", type=int, default=0)
    ap.add_argument("--tune-budget", type=int, default=TUNE_BUDGET, help="episodes each setting is tried with")
    ap.add_argument("--watch", type=int, default=WATCH, help="watch contexts the settings are chosen on")
    ap.add_argument("--results", help="a JSON file that keeps the run as it goes (and lets a stopped run go on)")
    ap.add_argument("--plot", help="write the curves here (PNG or SVG)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    learners, budgets, seeds = checked(args)
    from aero_env.config import ConfigError, load_config
    from aero_env.files import WriteFailed
    from aero_env.signals import exit_status, signal_name, sigterm_as_interrupt
    from agents.episode_runner import EpisodeRunner
    from agents.rl import TrainInterrupted

    task = TASKS[args.task]
    fast = EpisodeRunner(load_config(task.config, {"sim.fidelity": "reduced"}))
    check_map_blocks(learners, budgets, args.tune_budget, fast.space)
    meta = dict(task=task.name, learners=learners, budgets=budgets, seeds=seeds, holdout=args.holdout,
                holdout_seed=args.holdout_seed, tune_budget=args.tune_budget, watch=args.watch,
                settings={k: {n: list(v) for n, v in d.items()} for k, d in SETTINGS.items() if k in learners})
    results = Results(args.results, meta)
    try:
        with sigterm_as_interrupt():  # SIGTERM stops the run as Ctrl-C does; --results keeps what is finished
            cost, chosen = run(args, task, learners, budgets, seeds, fast, results)
    except (KeyboardInterrupt, TrainInterrupted) as exc:
        stop = exc.by if isinstance(exc, TrainInterrupted) else exc
        kept = f"the finished pieces are in {args.results}" if args.results else \
            "nothing kept (give --results FILE to keep a run as it goes)"
        print(f"budget_curves: {signal_name(stop)}; {kept}", file=sys.stderr)
        sys.exit(exit_status(stop))
    except (ConfigError, WriteFailed) as exc:
        sys.exit(f"budget_curves: {exc}")
    finally:
        fast.close()
    rep = dict(meta, config=task.config, episode_s=cost, chosen=chosen, tuning=results.data["tuning"],
               rows=rows_from(learners, budgets, seeds, results, chosen))
    if args.json:
        print(json.dumps(rep, indent=1))
    else:
        print_tables(rep)
    if args.plot:  # after the tables: a plot that cannot be written loses nothing printed
        try:
            plot(rep["rows"], budgets, args.plot, f"{task.name} task: whole row against training budget "
                                                  f"(band: 95 % CI, {len(seeds)} seeds)")
        except WriteFailed as exc:
            sys.exit(f"budget_curves: {exc}")


def run(args, task, learners, budgets, seeds, fast, results: Results) -> tuple[dict, dict]:
    """The episode costs, the tuning and every (learner, seed), each kept in ``results`` as it finishes."""
    from aero_env.config import load_config
    from agents.episode_runner import EpisodeRunner, draws_for_seeds

    mbd = EpisodeRunner(load_config(task.config))
    log = (lambda m: print(m, file=sys.stderr, flush=True))
    try:
        for name, runner in (("mbd", mbd), ("reduced", fast)):  # measured once, kept with the run
            if results.get("episode_s", name) is None:
                results.put("episode_s", name, episode_cost(runner, watch_draws(runner, args.watch)))
        chosen = tune(learners, task, mbd, fast, results, log, args.tune_budget, args.watch)
        draws = draws_for_seeds(mbd.space, holdout_seeds(args.holdout_seed, args.holdout))
        obs = mbd.observations(draws)
        start = single_action(fast.space, task)
        for learner in learners:
            for seed in seeds:
                key = f"{learner} seed{seed}"
                if results.get("runs", key) is None:
                    got = learn(learner, chosen[learner], seed, budgets, task, mbd, fast, draws, obs, start)
                    results.put("runs", key, got.to_json())
                top = results.get("runs", key)[str(max(budgets))]
                log(f"{key}: {np.mean(top['whole']) if top['whole'] is not None else '-'} at {max(budgets)}")
    finally:
        mbd.close()
    return results.data["episode_s"], chosen


if __name__ == "__main__":
    main()
