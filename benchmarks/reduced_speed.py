"""Throughput of the reduced model (aero_env.models.reduced): designs per second, on one core or all.

    python benchmarks/reduced_speed.py [CONFIG] [--designs 10000] [--repeats 3] [--seed 0] [--threads N]

Draws ``--designs`` uniformly random actions from the design environment's action space
(``DesignSpace(cfg).values``: the config's ``tunable`` ranges) and runs them as one batch,
``--repeats`` times. Prints JSON: the median wall time and designs per second of the fast path
(``simulate_values``: parameter arrays, no Config per design), the time to build the same batch
as Config objects (``with_values``, the ``simulate_batch`` path), where the run's time goes
(the swing steps while most of the batch is live vs the long tail of slow designs), and the
outcomes. The compiled kernel spreads the designs over ``--threads`` cores (default: all); it is
compiled (or loaded from its disk cache) before any timing, and that one-time cost is reported as
``compile_s``. Run nothing else alongside it.
"""

from __future__ import annotations

import argparse
import collections
import json
import statistics
import time
from pathlib import Path

import numba
import numpy as np

from aero_env.config import load_config
from aero_env.design_space import DesignSpace
from aero_env.models import reduced

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config", nargs="?", default=str(ROOT / "configs" / "paper.yaml"))
    ap.add_argument("--designs", type=int, default=10000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=numba.config.NUMBA_NUM_THREADS)
    args = ap.parse_args()
    if not 1 <= args.threads <= numba.config.NUMBA_NUM_THREADS:
        ap.error(f"--threads = {args.threads}: allowed 1 to {numba.config.NUMBA_NUM_THREADS} (this machine's cores)")
    compile_s = reduced.compile_kernels()
    numba.set_num_threads(args.threads)
    cfg = load_config(args.config)
    space = DesignSpace(cfg)
    actions = np.random.default_rng(args.seed).uniform(-1.0, 1.0, (args.designs, space.dim))
    designs = [space.values(a) for a in actions]
    values = {k: np.array([d[k] for d in designs]) for k in designs[0]}

    walls, result = [], None
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        result = reduced.simulate_values(cfg, values)
        walls.append(time.perf_counter() - t0)
    t0 = time.perf_counter()
    [cfg.with_values(d) for d in designs]  # what building the configs alone costs
    build = time.perf_counter() - t0
    wall = statistics.median(walls)
    end = np.sort(result.sim_time)
    print(json.dumps(dict(
        config=args.config, designs=args.designs, repeats=args.repeats, step_s=reduced.STEP, threads=args.threads,
        compile_s=round(compile_s, 3), designs_per_s_per_thread=round(args.designs / wall / args.threads, 1),
        median_wall_s=round(wall, 3), designs_per_s=round(args.designs / wall, 1),
        walls_s=[round(w, 3) for w in walls],
        build_configs_s=round(build, 3), designs_per_s_with_configs=round(args.designs / (wall + build), 1),
        simulated_s=dict(median=round(float(np.median(end)), 3), p99=round(float(end[int(0.99 * len(end))]), 3),
                         max=round(float(end[-1]), 3)),
        outcomes=dict(collections.Counter(result.outcome.tolist())),
        mean_traversals=round(float(np.mean(result.traversals)), 3),
    ), indent=2))


if __name__ == "__main__":
    main()
