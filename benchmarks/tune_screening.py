"""Multi-fidelity tuning: does screening with the reduced model save time? (``aero-env tune --screen``)

    python benchmarks/tune_screening.py [CONFIG] [--seeds 3] [--trials 200] [--screen-designs 5000] [--confirm 20]

On the same scene and tuning seeds, compares

* ``cmaes``: CMA-ES with ``--trials`` trials, every one in the pymunk world (mbd);
* ``screened``: ``--screen-designs`` random designs scored by the reduced model in one batch, then
  the best ``--confirm`` of them confirmed in the pymunk world.

For each: the best reward, the trial at which a design first traversed the whole row, and the
wall time to that point (the screen's time included; a trial's time taken as the run's mean),
and the total wall time. Prints JSON with the medians over seeds and their ratio.
"""

from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

from aero_env.config import load_config
from aero_env.models.reduced import compile_kernels
from aero_env.physics.kernels import load_kernels
from agents.tune import tune
from agents.tune_settings import TuneSettings

ROOT = Path(__file__).resolve().parents[1]


def time_to_row(result, screen_wall: float = 0.0) -> float | None:
    if result.first_full_row_trial is None:
        return None
    per_trial = (result.wall_time - screen_wall) / max(1, result.trials_run)
    return screen_wall + per_trial * (result.first_full_row_trial + 1)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config", nargs="?", default=str(ROOT / "configs" / "steep.yaml"))
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--trials", type=int, default=200)
    ap.add_argument("--screen-designs", type=int, default=5000)
    ap.add_argument("--confirm", type=int, default=20)
    args = ap.parse_args()
    cfg = load_config(args.config)
    # the reduced kernel's and the pymunk world's one-time compile (or cache load) is not a tuning cost
    compile_s = compile_kernels() + load_kernels()
    runs = {"cmaes": [], "screened": []}
    for seed in range(args.seeds):
        plain = tune(cfg, TuneSettings(sampler="cmaes", trials=args.trials, seed=seed, progress=False))
        runs["cmaes"].append(dict(seed=seed, best_reward=plain.best_reward, first_full_row_trial=plain.first_full_row_trial,
                                  time_to_full_row=time_to_row(plain), wall=plain.wall_time, trials=plain.trials))
        scr = tune(cfg, TuneSettings(sampler="cmaes", trials=args.confirm, seed=seed, progress=False, screen="reduced",
                                     screen_designs=args.screen_designs))
        sw = scr.screen["wall_time"]
        runs["screened"].append(dict(seed=seed, best_reward=scr.best_reward, first_full_row_trial=scr.first_full_row_trial,
                                     time_to_full_row=time_to_row(scr, sw), wall=scr.wall_time, screen_wall=sw,
                                     trials=scr.trials, screen_full_rows=scr.screen["full_row_designs"]))
    summary = {}
    for name, rs in runs.items():
        ttr = [r["time_to_full_row"] for r in rs if r["time_to_full_row"] is not None]
        summary[name] = dict(found_full_row=f"{len(ttr)} of {len(rs)}",
                             median_time_to_full_row=statistics.median(ttr) if ttr else None,
                             median_best_reward=statistics.median(r["best_reward"] for r in rs),
                             median_wall=statistics.median(r["wall"] for r in rs))
    a, b = summary["cmaes"]["median_time_to_full_row"], summary["screened"]["median_time_to_full_row"]
    summary["time_to_full_row_ratio"] = a / b if a and b else None
    print(json.dumps(dict(config=args.config, trials=args.trials, screen_designs=args.screen_designs, compile_s=compile_s,
                          confirm=args.confirm, summary=summary, runs=runs), indent=2))


if __name__ == "__main__":
    main()
