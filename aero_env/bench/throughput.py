"""``aero-env bench throughput``: environment episodes per second, with 1 and 2 vector workers.

One step of the design environment is one whole episode (a design run along the row). The
benchmark steps ``gymnasium.vector`` environments with the same seeded random actions:
``SyncVectorEnv`` with one environment, and ``AsyncVectorEnv`` with one process per extra
worker (``autoreset_mode=SAME_STEP``, so every step is a fresh episode), on the same designs
for every worker count. It reports the
median episodes per second over ``repeats`` and the speed-up of each worker count over one.
Workers share the machine's cores: on two cores two workers can at best double the rate.
"""

from __future__ import annotations

import functools
import math

import gymnasium as gym
import numpy as np

from ..config import Config
from ..envs import AerialAcrobatEnv
from .designs import check_counts, median_time


def _vector_env(cfg: Config, workers: int):
    fns = [functools.partial(AerialAcrobatEnv, cfg)] * workers
    mode = gym.vector.AutoresetMode.SAME_STEP
    if workers == 1:
        return gym.vector.SyncVectorEnv(fns, autoreset_mode=mode)
    return gym.vector.AsyncVectorEnv(fns, autoreset_mode=mode, context="spawn")


def throughput(cfg: Config, episodes: int = 40, repeats: int = 3, seed: int = 0, workers=(1, 2)) -> dict:
    check_counts(episodes=episodes, repeats=repeats)
    rows = []
    dim = len(cfg.tunable)
    designs = np.random.default_rng(seed).uniform(-1, 1, (episodes, dim)).astype(np.float32)
    for w in workers:
        envs = _vector_env(cfg, w)
        try:
            envs.reset(seed=seed)
            steps = math.ceil(episodes / w)
            # every worker count runs the same designs (random designs differ 10x in cost)
            actions = np.resize(designs, (steps * w, dim)).reshape(steps, w, dim)

            def run():
                rewards = []
                for a in actions:
                    _, r, _, _, _ = envs.step(a)
                    rewards.extend(r.tolist())
                return rewards

            wall, rewards = median_time(run, repeats)
        finally:
            envs.close()
        rows.append(dict(workers=w, episodes=steps * w, wall=wall, episodes_per_second=steps * w / wall,
                         mean_reward=float(np.mean(rewards))))
    base = rows[0]["episodes_per_second"]
    for r in rows:
        r["speedup_vs_1"] = r["episodes_per_second"] / base
    return dict(fidelity=cfg.sim.fidelity, repeats=repeats, seed=seed, workers=rows)


def table(report: dict) -> str:
    lines = [f"fidelity {report['fidelity']}, median of {report['repeats']} runs",
             f"{'workers':>7} {'episodes':>8} {'wall s':>8} {'episodes/s':>10} {'speed-up':>8}"]
    for r in report["workers"]:
        lines.append(f"{r['workers']:>7} {r['episodes']:>8} {r['wall']:8.2f} {r['episodes_per_second']:10.1f} "
                     f"{r['speedup_vs_1']:7.2f}x")
    return "\n".join(lines)
