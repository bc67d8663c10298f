"""CMA-ES vs TPE vs random search on one scene: same budget, same tuning seeds.

    python benchmarks/tune_samplers.py [configs/steep.yaml] [--trials 300] [--seeds 5]
                                       [--samplers cmaes,tpe,random] [--jobs 2] [--json]

Each (sampler, tuning seed) is one in-memory study of ``--trials`` trials, run in a pool of
``--jobs`` processes. Per sampler it reports, over the tuning seeds: how many studies found a
design that traverses the whole row, the median trial at which the first such design came
(a study that never found one counts as ``trials``, so the median is a lower bound when fewer
than half found one), the median best reward, and the median wall time of a study.
"""

from __future__ import annotations

import argparse
import json
import statistics
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from aero_env.config import load_config
from agents.tune import tune
from agents.tune_settings import TuneSettings


def one_study(config: str, sampler: str, seed: int, trials: int) -> dict:
    r = tune(load_config(config), TuneSettings(sampler=sampler, trials=trials, seed=seed, progress=False))
    return dict(sampler=sampler, seed=seed, best_reward=r.best_reward, first_full_row_trial=r.first_full_row_trial,
                full_row=r.full_row, wall_time=r.wall_time)


def summarise(runs: list[dict], trials: int) -> list[dict]:
    rows = []
    for sampler in dict.fromkeys(r["sampler"] for r in runs):
        rs = [r for r in runs if r["sampler"] == sampler]
        firsts = [r["first_full_row_trial"] for r in rs]
        found = [f for f in firsts if f is not None]
        median_first = statistics.median(trials if f is None else f + 1 for f in firsts)
        rows.append(dict(sampler=sampler, studies=len(rs), found_full_row=len(found),
                         median_trials_to_full_row=median_first if 2 * len(found) > len(rs) else None,
                         median_best_reward=statistics.median(r["best_reward"] for r in rs),
                         best_rewards=[r["best_reward"] for r in rs], first_full_row_trials=firsts,
                         median_wall_s=statistics.median(r["wall_time"] for r in rs)))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config", nargs="?", default=str(Path(__file__).resolve().parents[1] / "configs" / "steep.yaml"))
    ap.add_argument("--trials", type=int, default=300)
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--samplers", default="cmaes,tpe,random")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    jobs = [(args.config, s, seed, args.trials) for seed in range(args.seeds) for s in args.samplers.split(",")]
    with ProcessPoolExecutor(args.jobs) as pool:
        runs = list(pool.map(one_study, *zip(*jobs)))
    rows = summarise(runs, args.trials)
    if args.json:
        print(json.dumps(dict(config=args.config, trials=args.trials, seeds=args.seeds, samplers=rows), indent=2))
        return
    full = runs[0]["full_row"]
    print(f"{args.config}: {args.trials} trials per study, tuning seeds 0..{args.seeds - 1}, whole row = {full}")
    print("| sampler | studies that found the whole row | median trials to the whole row | median best reward "
          "| best reward per seed | median wall per study |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        med = r["median_trials_to_full_row"]
        print(f"| {r['sampler']} | {r['found_full_row']} of {r['studies']} | "
              f"{'> ' + str(args.trials) if med is None else med:} | {r['median_best_reward']:g} | "
              f"{', '.join(f'{v:g}' for v in r['best_rewards'])} | {r['median_wall_s']:.0f} s |")


if __name__ == "__main__":
    main()
