"""Out of distribution: the maker's shipped policies and maps, scored on contexts beyond the range they learnt.

    python benchmarks/beyond_range.py [--holdout 400] [--holdout-seed 0] [--methods single,linear-map,...]
                                      [--seeds 0-9] [--json]

The maker's policies (``policies/contexts``) learnt contexts drawn over ``configs/contexts.yaml``'s ranges: rise
0-10 mm a frame, pitch 70-86 mm, 6.5-10 g, the two card pairs. Here every hold-out context is drawn over the hard
task's ranges (``configs/contexts_hard.yaml``: rise -6 to +14 mm, pitch 64-94 mm, 6.5-12 g, the same card pairs)
on the maker's own 5-frame row, with the same five choices and the same cutting error: the scene is
``configs/contexts_hard.yaml`` with ``scene.frames: 5``, which is ``configs/contexts.yaml`` with wider context
ranges (a test checks it). Each method reads a context as it learnt it, normalised over the training ranges, so a
context beyond them reads past +-1: a linear map extends its line, a network its last layer, nearest neighbour
answers with its nearest training context, the single design ignores it.

The hold-out contexts (episode seeds of ``--holdout-seed``, as ``benchmarks/rl_vs_tuning.py`` uses them) split in
two: **inside** (every context within the training range) and **beyond** (at least one outside). Each split has
its own mean whole-row share and interval (bootstrap over seeds, then that split's contexts); the beyond contexts
are also counted by which way they leave the range. The **oracle** searches each beyond episode itself (from the
single design, then twice from the box's centre where that failed, as on the hard task): what the physics allows
there.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path

import numpy as np

from aero_env.config import ConfigError
from aero_env.intervals import difference_interval, seeds_then_contexts

from rl_holdout import TASKS, holdout_seeds, single_action
from rl_policies import checked_args, parse_seeds
from rl_vs_tuning import pct_ci, points_ci

METHODS = ("prototype", "single", "linear-map", "mlp-map", "nearest-neighbour", "ppo", "sac", "ppo-reduced",
           "ppo-multifidelity", "oracle")
SEEDS: dict[str, str] = {}  # the seeds shipped for a method, where not 0-9 (every method ships 0-9 now)
TRAINED = TASKS["contexts"]
WIDE = TASKS["hard"].config


def beyond_scene():
    """The maker's 5-frame scene with the hard task's context ranges."""
    from aero_env.config import load_config

    return load_config(WIDE, {"scene.frames": load_config(TRAINED.config).scene.frames})


def ways_out(train_space, draws) -> dict[str, np.ndarray]:
    """For each context field and side, which draws lie past the training range there."""
    out = {}
    for c in train_space.context:
        x = np.array([d.context[c.name] for d in draws])
        out[f"{c.name} below"] = x < c.low
        out[f"{c.name} above"] = x > c.high
    return {k: v for k, v in out.items() if v.any()}


def players_for(method: str, seeds: list[int], space, start) -> list[dict]:
    from rl_vs_tuning import load_players

    if method == "prototype":
        a = space.action_for(dtype=np.float64)
        return [dict(seed=None, act=lambda o: np.tile(a, (len(o), 1)))]
    if method == "single":
        return [dict(seed=None, act=lambda o: np.tile(start, (len(o), 1)))]
    return load_players(method, seeds, Path(TRAINED.policies), space)


def split_row(method: str, whole: np.ndarray, inside: np.ndarray) -> dict:
    """A method's outcomes (seeds x every hold-out context) and each split's mean, interval and per-seed shares."""
    row = dict(method=method, seeds=len(whole), outcomes=whole.astype(int).tolist())
    for name, cols in (("inside", inside), ("beyond", ~inside)):
        if cols.any():
            mean, ci = seeds_then_contexts(whole[:, cols])
            row[name] = dict(mean=mean, ci=ci, per_seed=[float(w.mean()) for w in whole[:, cols]])
    return row


def oracle_row(runner, draws, inside: np.ndarray, start, tried: list) -> dict:
    """The oracle on the beyond contexts only (its ``outcomes`` are theirs): each searched from the best design a
    method scored before it chose there (the single design where none was scored), then twice from the centre."""
    from rl_vs_tuning import oracle_search

    beyond = np.flatnonzero(~inside)
    task = dataclasses.replace(TRAINED, single=None, oracle_restarts=2)  # searches start from the methods' designs
    found = oracle_search(runner, [draws[i] for i in beyond], start, task, tried)
    mean, ci = seeds_then_contexts(found.solved[None, :])
    return dict(method="oracle", seeds=1, outcomes=[found.solved.astype(int).tolist()], columns="beyond",
                beyond=dict(mean=mean, ci=ci, per_seed=[mean]), evaluations=int(found.evaluations.sum()))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--methods", default=",".join(METHODS), help=f"comma-separated, of {', '.join(METHODS)}")
    ap.add_argument("--seeds", default="0-9", help="each learned method's seeds (sac: those shipped, 0-4)")
    ap.add_argument("--holdout", type=int, default=400)
    ap.add_argument("--holdout-seed", type=int, default=0)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    try:
        report(args)
    except (FileNotFoundError, ConfigError) as exc:  # a policy not shipped, a damaged run
        sys.exit(f"beyond_range: {exc}")


def report(args) -> None:
    methods, seeds = checked_args("beyond_range", args, METHODS, (("--holdout", args.holdout, 1),
                                                                   ("--holdout-seed", args.holdout_seed, 0)))
    methods = [m for m in METHODS if m in methods]
    own = {m: [s for s in seeds if s in parse_seeds(SEEDS.get(m, "0-9"))] for m in methods}
    for m in methods:
        if m not in ("prototype", "single", "oracle") and not own[m]:
            sys.exit(f"beyond_range: --seeds {args.seeds}: {m} is shipped for seeds {SEEDS.get(m, '0-9')} only")
    from aero_env.config import load_config
    from aero_env.design_space import DesignSpace
    from agents.episode_runner import EpisodeRunner, draws_for_seeds

    train_space = DesignSpace(load_config(TRAINED.config))
    runner = EpisodeRunner(beyond_scene())
    rows = []
    try:
        draws = draws_for_seeds(runner.space, holdout_seeds(args.holdout_seed, args.holdout))
        obs = train_space.observations(draws)  # as the methods learnt them: past +-1 beyond the training range
        inside = np.all(np.abs(obs) <= 1.0, axis=1)
        if inside.all():
            sys.exit(f"beyond_range: --holdout {args.holdout}: every context drawn lies inside the training range; "
                     f"draw more")
        out = ways_out(train_space, draws)
        start = single_action(train_space, TRAINED)
        tried = []  # every method's designs and traversals on the beyond contexts, where the oracle starts
        for method in methods:
            if method == "oracle":
                row = oracle_row(runner, draws, inside, start, tried)
                solved = np.zeros(len(draws), dtype=bool)
                solved[~inside] = row["outcomes"][0]
                row["ways_out"] = {k: float(solved[v].mean()) for k, v in out.items()}
            else:
                whole = []
                for p in players_for(method, own[method], runner.space, start):
                    actions = np.asarray(p["act"](obs), dtype=np.float64)
                    t = runner.traversals(draws, actions)
                    whole.append(t >= runner.full_row)
                    tried.append((actions[~inside], t[~inside]))
                whole = np.array(whole)
                row = split_row(method, whole, inside)
                row["ways_out"] = {k: float(whole[:, v].mean()) for k, v in out.items()}
            rows.append(row)
            print(f"{method}: beyond {row['beyond']['mean']:.3f}", file=sys.stderr, flush=True)
    finally:
        runner.close()
    by = {r["method"]: np.array(r["outcomes"])[:, ~inside] for r in rows if r["method"] != "oracle"}
    for r in rows:
        if r["method"] not in ("single", "oracle") and "single" in by:
            d, ci = difference_interval(by[r["method"]], by["single"])
            r["beyond_minus_single"] = dict(diff=d, ci=ci)
    rep = dict(trained_on=TRAINED.config, scored_on=f"{WIDE} with scene.frames {runner.full_row + 1}",
               holdout=args.holdout, holdout_seed=args.holdout_seed, inside=int(inside.sum()),
               beyond=int((~inside).sum()), ways_out={k: int(v.sum()) for k, v in out.items()}, rows=rows)
    if args.json:
        print(json.dumps(rep, indent=1))
        return
    print(f"trained on {rep['trained_on']}, scored at mbd on {rep['scored_on']}: {args.holdout} hold-out contexts "
          f"(--holdout-seed {args.holdout_seed}), {rep['inside']} inside the training range, {rep['beyond']} beyond")
    print("| method | seeds | inside: mean [95 % CI] | beyond: mean [95 % CI] | beyond, against single |")
    print("|---|---|---|---|---|")
    for r in rows:
        cells = [pct_ci(r[k]["mean"], r[k]["ci"]) if k in r else "-" for k in ("inside", "beyond")]
        d = r.get("beyond_minus_single")
        vs = "-" if d is None else points_ci(d["diff"], d["ci"])
        print(f"| {r['method']} | {r['seeds']} | {cells[0]} | {cells[1]} | {vs} |")
    print("beyond, by the way out (contexts; a context may leave by two ways): whole-row share, mean over seeds")
    print("| method | " + " | ".join(f"{k} ({v})" for k, v in rep["ways_out"].items()) + " |")
    print("|---|" + "---|" * len(rep["ways_out"]))
    for r in rows:
        print(f"| {r['method']} | " + " | ".join(f"{100 * v:.0f} %" for v in r["ways_out"].values()) + " |")


if __name__ == "__main__":
    main()
