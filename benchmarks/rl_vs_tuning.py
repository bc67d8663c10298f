"""Context -> design: RL, black-box maps, nearest neighbour and the per-context oracle against the best
single design, on the maker's contexts, over training seeds, with intervals.

    python benchmarks/rl_vs_tuning.py [--task contexts|hard] [--holdout-seed S] [--holdout 200] [--methods M,...]
                                      [--seeds 0-9]
                                      [--policies policies/contexts] [--policy DIR] [--no-flips]
                                      [--retrain [--timesteps 40960] [--finish-episodes 3072] [--map-episodes 40960]
                                       [--nn-contexts 128]]
                                      [--plot FILE.png] [--json]

The scene is ``aero_env/AerialAcrobatContexts-v0`` (``configs/contexts.yaml``): every reset draws the row's rise
and pitch, the robot's mass and the card pair (observed) and the build's cutting error (not observed), on a
5-frame row (whole row = 4 traversals). By default nothing is trained: the policies and maps shipped in
``--policies`` (``benchmarks/rl_policies.py`` wrote them; each file records its command) are re-scored on the
hold-out contexts of ``--holdout-seed S`` (episode seeds ``10^6·(S+1)`` onward, never seen in training or
tuning, nor by the learning curves). ``--retrain`` trains them all again first (the table's last line says how
long that took, by the shipped runs' records).

Methods (:data:`METHODS`):

* ``prototype``: the paper's design for every context. ``single``: the best single design,
  ``configs/contexts_single.yaml`` (a robust tune, 38,400 episodes; its header gives the command).
* ``linear-map``, ``mlp-map``: ``design = map(context)``, tuned black-box by CMA-ES at ``reduced`` from the
  single design (:mod:`agents.context_maps`). ``nearest-neighbour``: the design a per-context search found
  for the nearest of 128 training contexts.
* ``ppo``, ``sac``: trained at ``mbd`` through the native vector env, 40,960 episodes. ``ppo-reduced``: PPO
  trained at ``reduced`` (the fast rung), scored at ``mbd`` like every method. ``ppo-multifidelity``: that
  policy finished at ``mbd`` for 3,072 episodes (``aero-env train --init-from``); its episodes and wall time
  count both stages.
* ``oracle``: a search per hold-out context on that very episode (its context and its build), from the
  single design, until a design makes the whole row (193 episodes at most): the ceiling this benchmark can
  measure, not a bound (a method may make a row its budget did not find). It runs here.

Each method is scored at ``mbd`` on every seed it was trained with, every seed on the same hold-out contexts: its
outcomes are a matrix, seeds x contexts (1 = a whole row), in the JSON. The table gives the mean whole-row share
with a 95 % interval from a bootstrap over seeds, then contexts (:func:`aero_env.intervals.seeds_then_contexts`),
mean traversals, the episodes and wall time of one seed's training, and the share of the gap from the single
design to the oracle that it closes; then each seed's share with the IQM of the seeds (rliable), and the
differences between methods with their intervals, paired on the contexts
(:func:`aero_env.intervals.difference_interval`; every pair in the JSON). The
knife-edge columns give the share of hold-out outcomes (whole row or not) that flip when every action moves
by one float32 ulp, each component up or down at random (the smallest change an action can make: the share that
flips is the benchmark's resolution), and when every context is built again by hand (a fresh draw of the cutting
error).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import time
from pathlib import Path

import numpy as np

from aero_env.intervals import BOOTSTRAP_REPS, difference_interval, iqm_interval, seeds_then_contexts

from rl_holdout import TASKS, Task, holdout_seeds, single_action, watch_seeds
from rl_policies import (FINISH_EPISODES, MAP_METHODS, METHODS as TRAINED, RL_METHODS, check_pretrained, check_training_ranges,
                         checked_args)

METHODS = ("prototype", "single", *MAP_METHODS, "nearest-neighbour", "ppo", "sac", "ppo-reduced", "ppo-multifidelity",
           "oracle")
HARD_METHODS = ("prototype", "linear-map", "mlp-map", "nearest-neighbour", "ppo-reduced", "oracle")  # shipped there
ORACLE_RESTART = dict(max_evals=600, popsize=12)  # each of a task's oracle_restarts
IQM_SEEDS = 4      # the fewest seeds an IQM of seeds is given for (it keeps the middle half of them)


def single_record(task: Task) -> dict:
    """The episodes and wall time the stored single design's tune spent, from its header."""
    head = Path(task.single).read_text()
    trials = int(re.search(r"trial \d+ of (\d+)", head).group(1))
    seeds = len(re.search(r"traversals per seed \[([^\]]*)\]", head).group(1).split(","))
    minutes = re.search(r"\((\d+) min on one core", head)
    return dict(episodes=trials * seeds, wall_s=60.0 * int(minutes.group(1)) if minutes else None)


def rl_player(folder, seed: int | None = None) -> dict:
    """The deterministic policy a run folder holds (``aero-env train``'s or a shipped one), with its record;
    ``seed``: the run's index among a method's seeds (default its ``--seed``)."""
    from agents.rl import load_run, policy_actions

    model, trained_on, run = load_run(folder)
    stages, start = [], run.get("init_from")
    while start:  # every stage it started from (aero-env train --init-from), the first first
        stages.insert(0, start)
        start = start.get("init_from")
    stages.append(dict(fidelity=trained_on.sim.fidelity, timesteps_done=int(run.get("timesteps_done", run["timesteps"])),
                       wall_time=run.get("wall_time")))
    episodes = sum(int(st["timesteps_done"]) for st in stages)
    walls = [st.get("wall_time") for st in stages]
    wall = None if None in walls else float(sum(walls))
    at = stages[0]["fidelity"] if len(stages) == 1 else \
        ", then ".join(f"{st['fidelity']} {st['timesteps_done']}" for st in stages)
    return dict(seed=run.get("seed") if seed is None else seed,
                act=lambda obs: policy_actions(model, obs), episodes=episodes, wall_s=wall,
                trained_at=at, folder=str(folder))


def check_start_unchanged(method: str, seed: int, folder: Path, root: Path) -> None:
    """A finished pretraining is scored only beside the pretrained policy it started from: one trained again since
    would count another stage's episodes and time. Refused in one line, naming the command that mends it."""
    from agents.rl import policy_sha256

    start = json.loads((folder / "run.json").read_text()).get("init_from")
    if not start or "init_from" not in RL_METHODS[method]:
        return
    shipped = root / RL_METHODS[method]["init_from"] / f"seed{seed}" / "model.zip"
    if not shipped.is_file() or policy_sha256(shipped.parent) != start.get("sha256"):
        sys.exit(f"rl_vs_tuning: {folder} was finished from another {RL_METHODS[method]['init_from']} policy than "
                 f"{shipped.parent}'s; train it again: python benchmarks/rl_policies.py --methods {method} --seeds "
                 f"{seed}")


def load_players(method: str, seeds: list[int], root: Path, space) -> list[dict]:
    """Each seed's map obs -> actions of ``method`` as shipped in ``root``, with its training record."""
    out = []
    for seed in seeds:
        folder = root / method / f"seed{seed}"
        if method in RL_METHODS:
            if not (folder / "model.zip").is_file():
                raise FileNotFoundError(f"{folder}: no model.zip; train it with python benchmarks/rl_policies.py "
                                        f"--methods {method} --seeds {seed}, or run this with --retrain")
            check_start_unchanged(method, seed, folder, root)
            out.append(rl_player(folder, seed))
            continue
        path = folder / "policy.json"
        if not path.is_file():
            raise FileNotFoundError(f"{path}: missing; fit it with python benchmarks/rl_policies.py --methods "
                                    f"{method} --seeds {seed}, or run this with --retrain")
        rec = json.loads(path.read_text())
        from agents.context_maps import NearestNeighbour, ParamMap

        player = ParamMap.from_json_dict(rec["map"]) if "map" in rec else NearestNeighbour.from_json_dict(rec["table"])
        out.append(dict(seed=seed, act=player.act, episodes=int(rec["episodes"]), wall_s=float(rec["wall_time"]),
                        trained_at=rec["fidelity"], folder=str(folder)))
    return out


def score_rows(methods, seeds: dict, root: Path, runner, fast, draws, flips: bool, holdout_seed: int,
               policy_dir: str | None, task: Task = TASKS["contexts"]) -> tuple[list[dict], dict]:
    """Every method's hold-out rows; and the actions each seed chose (for the design table). ``fast``: a runner
    at ``reduced``, which replays each method's designs to show where the fast rung parts from ``mbd`` on them."""
    from agents.episode_runner import fresh_builds

    space = runner.space
    obs = runner.observations(draws)
    rebuilt = fresh_builds(space, draws, seed=7919 + holdout_seed)
    ulp_up = np.random.default_rng(4242 + holdout_seed).random((len(draws), space.dim)) < 0.5
    start = single_action(space, task)
    rows, chosen, tried = [], {}, []
    for method in methods:
        t0 = time.perf_counter()
        if method == "prototype":
            players = [dict(seed=None, act=lambda o, a=space.action_for(dtype=np.float64): np.tile(a, (len(o), 1)),
                            episodes=0, wall_s=0.0, trained_at="-")]
        elif method == "single":
            rec = single_record(task)
            players = [dict(seed=None, act=lambda o: np.tile(start, (len(o), 1)), episodes=rec["episodes"],
                            wall_s=rec["wall_s"], trained_at="mbd")]
        elif method == "oracle":
            before = runner.episodes
            found = oracle_search(runner, draws, start, task, tried)
            players = [dict(seed=0, act=lambda o, a=found.actions: a, episodes=runner.episodes - before,
                            wall_s=time.perf_counter() - t0, trained_at="mbd (each hold-out episode)",
                            solved=int(found.solved.sum()), evaluations=found.evaluations.tolist())]
        elif method == "policy":
            players = [rl_player(policy_dir)]
        else:
            players = load_players(method, seeds[method], root, space)
        whole, trav, flip_ulp, flip_build, at_fast = [], [], [], [], []
        parted_as: dict[str, int] = {}
        for p in players:
            actions = np.asarray(p["act"](obs), dtype=np.float64)
            t, outcomes = runner.run(draws, actions)
            w = t >= runner.full_row
            whole.append(w)
            trav.append(t)
            at_fast.append(fast.whole_rows(draws, actions))
            for i in np.flatnonzero(at_fast[-1] & ~w):  # a whole row at reduced that mbd refuses: what mbd says
                parted_as[outcomes[i]] = parted_as.get(outcomes[i], 0) + 1
            if flips:
                flip_ulp.append(float(np.mean(runner.whole_rows(draws, one_ulp_nudge(actions, ulp_up)) != w)))
                flip_build.append(float(np.mean(runner.whole_rows(rebuilt, actions) != w)))
            chosen.setdefault(method, []).append(actions)
            tried.append((actions, t))
        whole, at_fast = np.array(whole), np.array(at_fast)
        mean, ci = seeds_then_contexts(whole)
        ci_apart = seeds_then_contexts(whole, contexts="per seed")[1]  # for comparison (docs/agents.md)
        per_seed = [float(w.mean()) for w in whole]
        walls = [p["wall_s"] for p in players if p["wall_s"] is not None]
        row = dict(method=method, seeds=len(players), seed_list=[p["seed"] for p in players], mean=mean, ci=ci,
                   ci_contexts_per_seed=ci_apart, per_seed=per_seed, outcomes=whole.astype(int).tolist(),
                   mean_traversals=float(np.mean(trav)), episodes=int(np.mean([p["episodes"] for p in players])),
                   wall_s=float(np.mean(walls)) if walls else None, wall_per_seed=walls,
                   trained_at=players[0]["trained_at"],
                   holdout=len(draws), at_reduced=float(at_fast.mean()),
                   reduced_parts=float(np.mean(at_fast != whole)),
                   reduced_false_rows=float(np.mean(at_fast & ~whole)), parted_as=dict(sorted(parted_as.items())),
                   design_median={k: float(np.median(v)) for k, v in runner.space.values_columns(
                       np.clip(np.concatenate(chosen[method]), -1.0, 1.0)).items()})
        if len(players) >= IQM_SEEDS:
            row["iqm_seeds"], row["iqm_seeds_ci"] = iqm_interval(np.array(per_seed)[:, None])
        if flips:
            row.update(flips_ulp=float(np.mean(flip_ulp)), flips_build=float(np.mean(flip_build)))
        if "solved" in players[0]:  # the oracle: contexts solved, and the episodes it spent on each
            row["solved"], row["evaluations"] = players[0]["solved"], players[0]["evaluations"]
        rows.append(row)
    by = {r["method"]: r for r in rows}
    if {"single", "oracle"} <= set(by) and by["oracle"]["mean"] > by["single"]["mean"]:
        gap = by["oracle"]["mean"] - by["single"]["mean"]
        for r in rows:
            r["gap_closed"] = (r["mean"] - by["single"]["mean"]) / gap
    return rows, chosen


def oracle_search(runner, draws, start: np.ndarray, task: Task, tried: list):
    """The per-context oracle: a search on each hold-out episode itself. On a task with a single design, from it
    (193 episodes at most). On one without, from the best design any method scored before it chose for that context
    (most traversals; the first such), so that the oracle makes every row a method made; then ``task.oracle_restarts``
    searches from the box's centre (:data:`ORACLE_RESTART`) on the contexts still unsolved, each keeping what did
    best."""
    from agents.context_maps import search_contexts

    if task.single is not None or not tried:
        found = search_contexts(runner, draws, start, seed=0)
    else:
        acts, trav = np.stack([a for a, _ in tried]), np.stack([t for _, t in tried])
        found = search_contexts(runner, draws, acts[np.argmax(trav, axis=0), np.arange(len(draws))], seed=0)
    for restart in range(1, task.oracle_restarts + 1):
        left = np.flatnonzero(~found.solved)
        if not len(left):
            break
        again = search_contexts(runner, [draws[i] for i in left], np.zeros(runner.space.dim), seed=restart,
                                **ORACLE_RESTART)
        better = again.traversals > found.traversals[left]
        for name in ("actions", "solved", "traversals"):
            getattr(found, name)[left[better]] = getattr(again, name)[better]
        found.evaluations[left] += again.evaluations
    return found


def one_ulp_nudge(actions: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Every component of the actions moved by one float32 ulp (the action space's precision), up where ``up``."""
    a = actions.astype(np.float32)
    return np.nextafter(a, np.where(up, np.float32(np.inf), np.float32(-np.inf))).astype(np.float64)


def differences(rows: list[dict]) -> list[dict]:
    """Every pair of methods (a listed before b): the difference of their means, a - b, with its 95 % interval
    paired on the hold-out contexts; ``apart``: the interval excludes 0."""
    out = []
    for i, a in enumerate(rows):
        for b in rows[i + 1:]:
            d, ci = difference_interval(a["outcomes"], b["outcomes"])
            out.append(dict(a=a["method"], b=b["method"], diff=d, ci=ci, apart=bool(ci[0] > 0 or ci[1] < 0)))
    return out


def difference(diffs: list[dict], a: str, b: str) -> tuple[float, list[float]]:
    """a - b and its interval, read from :func:`differences`' pairs (stored in either order)."""
    for d in diffs:
        if (d["a"], d["b"]) == (a, b):
            return d["diff"], d["ci"]
        if (d["a"], d["b"]) == (b, a):
            return -d["diff"], [-d["ci"][1], -d["ci"][0]]
    raise KeyError(f"no pair {a}, {b}")


def recipe(rows: list[dict], diffs: list[dict]) -> dict | None:
    """The multi-fidelity recipe against PPO trained at mbd: its mean, the difference with its paired interval, and
    its wall time (both stages) as a share of PPO's (the goal: PPO's share in at most a third of its time). The wall times are medians over seeds: a seed
    trained beside another job on the 2 cores would pull a mean."""
    by = {r["method"]: r for r in rows}
    if not {"ppo", "ppo-multifidelity"} <= set(by) or not (by["ppo"]["wall_per_seed"] and
                                                            by["ppo-multifidelity"]["wall_per_seed"]):
        return None
    mf, ppo = by["ppo-multifidelity"], by["ppo"]
    ours, theirs = float(np.median(mf["wall_per_seed"])), float(np.median(ppo["wall_per_seed"]))
    diff, diff_ci = difference(diffs, "ppo-multifidelity", "ppo")
    return dict(mean=mf["mean"], ci=mf["ci"], ppo_mean=ppo["mean"], ppo_ci=ppo["ci"], reached=mf["mean"] >= ppo["mean"],
                diff=diff, diff_ci=diff_ci, wall_s=ours, ppo_wall_s=theirs, wall_ratio=ours / theirs)


def design_follows(cfg, obs: np.ndarray, actions: list[np.ndarray]) -> list[dict]:
    """For each design field: the context field the choice follows most (Spearman rho, median over seeds), and
    how much of its range the choice spans over the hold-out contexts (10-90 %, median over seeds)."""
    from scipy.stats import spearmanr

    ctx = [c.name for c in cfg.context]
    rows = []
    for i, t in enumerate(cfg.tunable):
        rhos, spreads = [], []
        for a in actions:
            col = a[:, i]
            spreads.append(float(np.percentile(col, 90) - np.percentile(col, 10)) / 2.0)
            rhos.append([0.0 if np.ptp(col) == 0 else float(spearmanr(obs[:, j], col).statistic)
                         for j in range(len(ctx))])
        med = np.median(np.array(rhos), axis=0)
        j = int(np.argmax(np.abs(med)))
        rows.append(dict(design=t.name, context=ctx[j] if med[j] else None, rho=float(med[j]),
                         spread=float(np.median(spreads))))
    return rows


def common_points(runs: list[list[dict]]) -> tuple[list[int], np.ndarray]:
    """The curve points every seed has (by episodes learnt from), and each seed's whole-row share there."""
    common = sorted(set.intersection(*[{p["episodes"] for p in c} for c in runs]))
    shares = np.array([[{p["episodes"]: p["full_row_fraction"] for p in c}[t] for t in common] for c in runs])
    return common, shares


def curves(methods, seeds, root: Path) -> dict:
    """Each RL method's learning curves on the watch contexts, one per seed, as shipped."""
    out = {}
    for method in methods:
        if method not in RL_METHODS:
            continue
        got = []
        for seed in seeds:
            path = root / method / f"seed{seed}" / "curve.json"
            if path.is_file():
                got.append(json.loads(path.read_text())["curve"])
        if got:
            out[method] = got
    return out


def retrain_seconds(root: Path) -> float:
    """What training every shipped policy and map took, by their own records (an RL run's curve included)."""
    total = 0.0
    for f in sorted(root.glob("*/seed*/run.json")):
        run = json.loads(f.read_text())
        total += float(run.get("wall_time_with_curve", run["wall_time"]))
    for f in sorted(root.glob("*/seed*/policy.json")):
        total += float(json.loads(f.read_text())["wall_time"])
    return total


def plot_curves(found: dict, single_watch: float | None, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    for (method, runs), colour in zip(found.items(), ("C3", "C0", "C2", "C4")):
        t, y = common_points(runs)
        y = 100 * y
        after = ", mbd episodes after its pretraining at reduced" if "init_from" in RL_METHODS[method] else ""
        ax.plot(t, y.mean(axis=0), "o-", ms=3, color=colour, label=f"{method} (mean of {len(runs)} seeds{after})")
        ax.fill_between(t, y.min(axis=0), y.max(axis=0), color=colour, alpha=0.15)
    if single_watch is not None:
        ax.axhline(100 * single_watch, ls="--", color="k", label="best single design")
    ax.set(xlabel="training episodes (= designs tried)", ylabel="watch contexts, whole row (%)", ylim=(0, 100),
           title="learning curves at mbd on the watch contexts (band: min-max over seeds)")
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def retrain(methods, seeds, root: Path, args, task: Task) -> None:
    from rl_policies import fit_baseline, train_rl

    for method in [m for m in TRAINED if m in methods]:  # a pretraining before the run that finishes it
        for seed in seeds:
            dest = root / method / f"seed{seed}"
            if method in RL_METHODS:
                train_rl(method, seed, args.timesteps, dest, args.watch, args.curve_every, args.finish_episodes,
                         task)
            elif method in TRAINED:
                fit_baseline(method, seed, dest, args.map_episodes, args.nn_contexts, task)


def pct_ci(value: float, ci: list[float]) -> str:
    return f"{100 * value:.1f} % [{100 * ci[0]:.1f}, {100 * ci[1]:.1f}]"


def points_ci(diff: float, ci: list[float], unit: str = "") -> str:
    """A paired difference in shares as signed points with its interval: "+4.8 [+1.2, +8.5]" (``unit`` after the
    value: " points")."""
    return f"{100 * diff:+.1f}{unit} [{100 * ci[0]:+.1f}, {100 * ci[1]:+.1f}]"


def print_table(rep: dict) -> None:
    seeds = holdout_seeds(rep["holdout_seed"], rep["holdout"])
    print(f"{rep['scene']} ({rep['config']}), whole row = {rep['frames'] - 1} traversals; {rep['holdout']} hold-out "
          f"contexts (seeds {seeds[0]}..{seeds[-1]}), every method scored at mbd")
    print("| method | seeds | trained at | episodes / seed | wall / seed | whole row: mean [95 % CI] | "
          "mean traversals | flips: 1 ulp / rebuilt | gap closed |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rep["rows"]:
        wall = "-" if r["wall_s"] is None else f"{r['wall_s']:.0f} s"
        flips = f"{100 * r['flips_ulp']:.1f} / {100 * r['flips_build']:.1f} %" if "flips_ulp" in r else "-"
        gap = f"{100 * r['gap_closed']:.0f} %" if "gap_closed" in r else "-"
        print(f"| {r['method']} | {r['seeds']} | {r['trained_at']} | {r['episodes']} | {wall} | "
              f"{pct_ci(r['mean'], r['ci'])} | {r['mean_traversals']:.2f} | {flips} | {gap} |")
    for r in rep["rows"]:
        if r["seeds"] > 1:
            iqm = f"; IQM of the seeds {pct_ci(r['iqm_seeds'], r['iqm_seeds_ci'])}" if "iqm_seeds" in r else ""
            print(f"{r['method']} per seed: " + ", ".join(f"{100 * s:.1f} %" for s in r["per_seed"]) + iqm)
    # each method against the references: the single design and PPO, or on a task without them the linear map
    refs = [m for m in ("single", "ppo") if m in {r["method"] for r in rep["rows"]}] or ["linear-map"]
    shown = [d for d in rep["differences"] if d["b"] in refs or d["a"] == refs[-1]]
    if shown:
        print("differences in whole-row share, paired on the hold-out contexts (every pair in the JSON):")
        print("| a - b | difference [95 % CI] | apart |")
        print("|---|---|---|")
        for d in shown:
            a, b = (d["a"], d["b"]) if d["b"] in refs else (d["b"], d["a"])
            diff, (lo, hi) = difference(rep["differences"], a, b)
            print(f"| {a} - {b} | {points_ci(diff, (lo, hi), ' points')} | "
                  f"{'yes' if d['apart'] else 'no'} |")
    print("each method's own designs replayed at reduced (the fast rung):")
    print("| method | whole row at reduced | at mbd | outcomes that part | rows reduced grants, mbd refuses | "
          "mbd's outcome there |")
    print("|---|---|---|---|---|---|")
    for r in rep["rows"]:
        said = ", ".join(f"{k} {v}" for k, v in r["parted_as"].items()) or "-"
        print(f"| {r['method']} | {100 * r['at_reduced']:.1f} % | {100 * r['mean']:.1f} % | "
              f"{100 * r['reduced_parts']:.1f} % | {100 * r['reduced_false_rows']:.1f} % | {said} |")
    by = {r["method"]: r for r in rep["rows"]}
    if {"ppo", "ppo-reduced"} <= set(by):
        print("the designs chosen (median over hold-out contexts and seeds):")
        print("| field | single | ppo | ppo-reduced |")
        print("|---|---|---|---|")
        for k, v in by["ppo"]["design_median"].items():
            unit, scale = ("g", 1e3) if k.endswith(("m3",)) else ("N·mm/rad", 1e3) if "spring" in k else \
                ("", 1.0) if k.startswith("design.mu") else ("mm", 1e3)
            cells = [by[m]["design_median"][k] * scale if m in by else float("nan") for m in ("single", "ppo",
                                                                                               "ppo-reduced")]
            print(f"| {k} | " + " | ".join(f"{c:.4g} {unit}".strip() for c in cells) + " |")
    if rep.get("recipe"):
        r = rep["recipe"]
        print(f"the multi-fidelity recipe (ppo-multifidelity): {100 * r['mean']:.1f} % against ppo's "
              f"{100 * r['ppo_mean']:.1f} % ({'reached' if r['reached'] else 'not reached'}; the difference "
              f"{points_ci(r['diff'], r['diff_ci'], ' points')}), "
              f"in {r['wall_s']:.0f} s a "
              f"seed against ppo's {r['ppo_wall_s']:.0f} s (medians over seeds): {r['wall_ratio']:.2f} of its wall "
              f"time (the goal: at most 1/3)")
    print(f"training every policy and map in {rep['policies']} again (python benchmarks/rl_policies.py) took "
          f"{rep['retrain_s'] / 60:.0f} min by their records")
    for method, runs in rep["curves"].items():
        t, y = common_points(runs)
        pts = list(zip(t, y.mean(axis=0)))
        print(f"{method} learning curve (watch contexts, mean of {len(runs)} seeds): " +
              ", ".join(f"{e}: {100 * f:.0f} %" for e, f in pts[::2] + ([pts[-1]] if len(pts) % 2 == 0 else [])))
    if rep["design_follows"]:
        print(f"{rep['follows_method']}'s designs (median over seeds):")
        print("| design field | its range used (10-90 % of contexts) | follows most | Spearman rho |")
        print("|---|---|---|---|")
        for f in rep["design_follows"]:
            print(f"| {f['design']} | {100 * f['spread']:.0f} % | {f['context'] or '-'} | {f['rho']:+.2f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--holdout", type=int, default=200, help="hold-out contexts")
    ap.add_argument("--holdout-seed", type=int, default=0, help="which hold-out contexts: seeds 10^6·(S+1) onward")
    ap.add_argument("--task", default="contexts", choices=tuple(TASKS),
                    help="the maker's contexts (default), or the hard task: wider shelves on the 8-frame row")
    ap.add_argument("--methods", help=f"comma-separated, of {', '.join(METHODS)}; default all (--task hard: "
                                      f"{', '.join(HARD_METHODS)}, the ones shipped for it)")
    ap.add_argument("--seeds", help="the training seeds scored (0-9 or 0,2,5); default every seed 0-9 that "
                                    "--policies holds (--retrain: 0-9)")
    ap.add_argument("--policies", help="the shipped policies and maps (DIR/METHOD/seedS); default the task's, "
                                       "policies/contexts or policies/contexts-hard")
    ap.add_argument("--policy", metavar="DIR", help="also score the policy aero-env train wrote in DIR")
    ap.add_argument("--skip-missing", action="store_true",
                    help="with --seeds: score the ones a method has in --policies (the table says how many)")
    ap.add_argument("--no-flips", action="store_true", help="skip the knife-edge columns (two thirds of the episodes)")
    ap.add_argument("--retrain", action="store_true", help="train every method's seeds again into --policies first")
    ap.add_argument("--timesteps", type=int, default=40_960, help="with --retrain: an RL policy's training episodes")
    ap.add_argument("--finish-episodes", type=int, default=FINISH_EPISODES,
                    help="with --retrain: ppo-multifidelity's episodes at mbd")
    ap.add_argument("--map-episodes", type=int, default=40_960, help="with --retrain: a map's CMA-ES episodes")
    ap.add_argument("--nn-contexts", type=int, default=128, help="with --retrain: nearest neighbour's contexts")
    ap.add_argument("--watch", type=int, default=200, help="with --retrain: contexts the learning curves watch")
    ap.add_argument("--curve-every", type=int, default=4096, help="with --retrain: episodes between curve points")
    ap.add_argument("--plot", metavar="FILE.png", help="draw the RL learning curves (watch contexts)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    task = TASKS[args.task]
    args.methods = args.methods or ",".join(METHODS if task.single else HARD_METHODS)
    args.policies = args.policies or task.policies
    shipped = args.seeds is None and not args.retrain  # the default: whichever of seeds 0-9 are shipped
    if args.seeds is None:
        args.seeds = "0-9"
    methods, seeds = checked_args("rl_vs_tuning", args, METHODS, (
        ("--timesteps", args.timesteps, 1), ("--finish-episodes", args.finish_episodes, 1),
        ("--map-episodes", args.map_episodes, 1),
        ("--nn-contexts", args.nn_contexts, 1), ("--holdout", args.holdout, 1),
        ("--holdout-seed", args.holdout_seed, 0), ("--watch", args.watch, 1), ("--curve-every", args.curve_every, 0)))
    if "single" in methods and task.single is None:
        sys.exit(f"rl_vs_tuning: --methods single: the {task.name} task has no stored single design; leave it out")
    if args.retrain:
        check_training_ranges("rl_vs_tuning", methods, seeds, args.map_episodes, args.nn_contexts, task)
        check_pretrained("rl_vs_tuning", [m for m in TRAINED if m in methods], seeds, Path(args.policies))
    if args.policy and not Path(args.policy, "run.json").is_file():
        sys.exit(f"rl_vs_tuning: --policy {args.policy}: no run.json there; give a folder aero-env train wrote")
    root = Path(args.policies)
    have = {m: seeds for m in methods}  # each method's seeds to score
    if not args.retrain:
        missing = [(m, s) for m in methods if m in TRAINED for s in seeds if not (root / m / f"seed{s}").is_dir()]
        if missing and not (args.skip_missing or shipped):
            m, k = missing[0]
            sys.exit(f"rl_vs_tuning: --policies {root}: no {root / m / f'seed{k}'}; run with --retrain to train it "
                     f"(or --skip-missing to score the seeds there)")
        if missing:
            for m in {m for m, _ in missing}:
                if all((m, k) in missing for k in seeds):
                    sys.exit(f"rl_vs_tuning: --policies {root}: no seed of {m} among --seeds {args.seeds}")
            have = {m: [k for k in seeds if (m, k) not in missing] for m in methods}
    from aero_env.config import ConfigError, load_config
    from agents.episode_runner import EpisodeRunner, draws_for_seeds

    cfg = load_config(task.config)
    if args.policy:
        from agents.rl import load_run

        _, trained_on, _ = load_run(args.policy)
        if trained_on.replace({"sim.fidelity": cfg.sim.fidelity}) != cfg:  # any fidelity of this scene
            sys.exit(f"rl_vs_tuning: --policy {args.policy}: trained on another scene than {task.config} (its "
                     f"config.yaml)")
        methods.append("policy")
    if args.retrain:
        retrain(methods, seeds, root, args, task)
    runner = EpisodeRunner(cfg)
    fast = EpisodeRunner(load_config(task.config, {"sim.fidelity": "reduced"}))
    try:
        draws = draws_for_seeds(runner.space, holdout_seeds(args.holdout_seed, args.holdout))
        rows, chosen = score_rows(methods, have, root, runner, fast, draws, not args.no_flips, args.holdout_seed,
                                  args.policy, task)
        found = curves(methods, seeds, root)
        single_watch = None
        if args.plot and found:
            wd = draws_for_seeds(runner.space, watch_seeds(args.watch))
            single_watch = float(np.mean(runner.whole_rows(wd, np.tile(single_action(runner.space, task),
                                                                        (len(wd), 1)))))
    except ConfigError as exc:
        sys.exit(f"rl_vs_tuning: {exc}")
    finally:
        runner.close()
        fast.close()
    follows_method = next((m for m in ("ppo", "policy", "sac", "ppo-reduced") if m in chosen), None)
    follows = design_follows(cfg, runner.observations(draws), chosen[follows_method]) if follows_method else []
    if args.plot and found:
        plot_curves(found, single_watch, args.plot)
    diffs = differences(rows)
    rep = dict(task=task.name, scene=task.scene, config=task.config, frames=cfg.scene.frames, holdout=args.holdout,
               holdout_seed=args.holdout_seed, retrain_s=retrain_seconds(root), policies=str(root), rows=rows,
               curves=found, recipe=recipe(rows, diffs), differences=diffs,
               follows_method=follows_method, design_follows=follows, nudge="1 float32 ulp",
               bootstrap_reps=BOOTSTRAP_REPS)
    if args.json:
        print(json.dumps(rep, indent=1))
        return
    print_table(rep)
    if args.plot and found:
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
