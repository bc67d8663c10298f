"""What one episode of aero_env/AerialAcrobat-v0 costs: median wall time of ``step``.

    python benchmarks/env_step.py [--designs 60] [--repeats 5] [--seed 0]

Prints JSON: the median step time over uniformly random designs (and their outcomes), and over
repeats of the prototype's design (the full 8-frame row).
"""

from __future__ import annotations

import argparse
import collections
import json
import statistics
import time

import gymnasium as gym
import numpy as np

import aero_env  # noqa: F401  (registers the environments)


def timed_step(env, action):
    env.reset()  # each design its own episode (a step after the end warns); outside the clock
    t0 = time.perf_counter()
    _, reward, _, _, info = env.step(action)
    return time.perf_counter() - t0, reward, info


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=60)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    env = gym.make("aero_env/AerialAcrobat-v0")
    env.reset(seed=args.seed)
    rng = np.random.default_rng(args.seed)
    random_runs = [timed_step(env, rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
                   for _ in range(args.designs)]
    proto_runs = [timed_step(env, env.unwrapped.action_for()) for _ in range(args.repeats)]
    print(json.dumps(dict(
        random=dict(designs=args.designs, median_step_s=statistics.median(r[0] for r in random_runs),
                    mean_reward=float(np.mean([r[1] for r in random_runs])),
                    outcomes=dict(collections.Counter(r[2]["outcome"] for r in random_runs))),
        prototype=dict(repeats=args.repeats, median_step_s=statistics.median(r[0] for r in proto_runs),
                       reward=proto_runs[0][1], sim_time=proto_runs[0][2]["sim_time"]),
    ), indent=2))


if __name__ == "__main__":
    main()
