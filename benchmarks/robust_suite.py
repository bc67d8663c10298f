"""Designs that survive the scissors, on every scene of the suite: the prototype, the stored (plain-tuned)
solution and a robust tune, each built by hand ``--draws`` times on seeds the tune never used.

    python benchmarks/robust_suite.py [--dir configs/scenes] [--robust 8] [--trials 40] [--draws 100]
                                      [--check-seeds 7 11] [--workers 2] [--json]

For each scene: ``aero-env tune SCENE --robust K --trials T`` (CMA-ES, seed 0: every trial scored as its mean
over the same K hand-made builds, drawn from seed 0), then ``aero-env robustness`` of the scene's prototype,
of its stored solution (``configs/scenes/solutions/``, tuned without builds) and of the robust design, with
``--draws`` builds on each of ``--check-seeds``. Prints the share of builds that complete the row, pooled over
the check seeds.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from aero_env.bench.scenes import scene_paths, solution_path
from aero_env.config import load_config
from aero_env.robustness.study import completed_builds
from aero_env.robustness.tolerances import DEFAULT_TOLERANCES
from agents.tune import best_config, tune
from agents.tune_settings import TuneSettings

ROOT = Path(__file__).resolve().parents[1]


def share(cfg, draws: int, seeds, workers: int) -> float:
    done = sum(completed_builds(cfg, DEFAULT_TOLERANCES, draws, seed, workers=workers) for seed in seeds)
    return done / (draws * len(seeds))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dir", default=str(ROOT / "configs" / "scenes"))
    ap.add_argument("--robust", type=int, default=8)
    ap.add_argument("--trials", type=int, default=40)
    ap.add_argument("--draws", type=int, default=100)
    ap.add_argument("--check-seeds", type=int, nargs="+", default=[7, 11])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    rows = []
    for scene in scene_paths(a.dir):
        t0 = time.perf_counter()
        cfg = load_config(scene)
        result = tune(cfg, TuneSettings(trials=a.trials, robust=a.robust, progress=False).check(), scene.stem)
        robust_cfg = best_config(cfg, result)
        rows.append(dict(
            scene=scene.stem,
            prototype=share(cfg, a.draws, a.check_seeds, a.workers),
            plain_solution=share(load_config(solution_path(scene)), a.draws, a.check_seeds, a.workers),
            robust=share(robust_cfg, a.draws, a.check_seeds, a.workers),
            robust_tune_score=result.best_reward / result.full_row,
            wall_s=time.perf_counter() - t0))
    if a.json:
        print(json.dumps(dict(robust=a.robust, trials=a.trials, draws=a.draws, check_seeds=a.check_seeds,
                              scenes=rows), indent=2))
        return
    n = a.draws * len(a.check_seeds)
    print(f"share of {n} hand-made builds (seeds {', '.join(map(str, a.check_seeds))}) completing the row")
    print(f"{'scene':18} {'prototype':>9} {'plain':>7} {'robust':>7}   robust tune: --robust {a.robust} --trials {a.trials}")
    for r in rows:
        print(f"{r['scene']:18} {r['prototype']:>9.0%} {r['plain_solution']:>7.0%} {r['robust']:>7.0%}   "
              f"{r['wall_s']:.0f} s")


if __name__ == "__main__":
    main()
