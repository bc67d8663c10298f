"""RL (a context -> design policy) against black-box tuning (one robust design), same budget.

    python benchmarks/rl_vs_tuning.py [--budget 800] [--seeds-per-design 8] [--holdout 60] [--frames 5]
                                      [--methods prototype,cmaes,random,ppo] [--jobs 2] [--json]

The scene is ``aero_env/AerialAcrobatVaried-v0``: every reset draws the rise and the robot's
mass (observed) and the build's cutting error (not observed). Each method may simulate
``--budget`` episodes, on a row of ``--frames`` frames (shorter rows are cheaper per episode):

* ``prototype``: the paper's design, no search (0 episodes);
* ``cmaes`` / ``random``: ``budget / K`` trials, each design scored on the same K seeds; the best
  design is then used for every context;
* ``ppo`` / ``sac``: ``budget`` training steps; the policy chooses a design per context.

All are then scored on the same ``--holdout`` fresh episode seeds (never seen in tuning or
training), overall and split by the robot's mass (light / heavy half of its range), which shows
whether a method adapts its design to the context.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from aero_env.config import load_config
from aero_env.registration import ENVIRONMENTS
from agents.design_eval import DesignEvaluator

SCENE = "aero_env/AerialAcrobatVaried-v0"
HOLDOUT_START = 100_000


FRAMES = 5


def scene(frames: int = FRAMES):
    return load_config(None, {**ENVIRONMENTS[SCENE], "scene.frames": frames})


def holdout_rows(cfg, actions_for, seeds) -> list[dict]:
    """Each hold-out episode: its robot mass and the reward of the design ``actions_for(obs)`` chose."""
    from aero_env.envs import AerialAcrobatEnv

    env = AerialAcrobatEnv(cfg)
    rows = []
    for s in seeds:
        obs, info = env.reset(seed=s)
        _, r, _, _, out = env.step(actions_for(obs))
        rows.append(dict(seed=s, m2=info["context"]["design.m2"], reward=r, traversals=out["traversals"]))
    return rows


def run_method(method: str, budget: int, k: int, holdout: int, seed: int, frames: int) -> dict:
    cfg = scene(frames)
    seeds = range(HOLDOUT_START, HOLDOUT_START + holdout)
    t0 = time.perf_counter()
    if method == "prototype":
        action = DesignEvaluator(cfg, (0,)).env.action_for()
        used, policy = 0, (lambda obs: action)
    elif method in ("cmaes", "random", "tpe"):
        from agents.tune import tune
        from agents.tune_settings import TuneSettings

        r = tune(cfg, TuneSettings(sampler=method, trials=budget // k, seeds_per_design=k, seed=seed,
                                       progress=False))
        action = np.array(r.best_action)
        used, policy = r.trials * k, (lambda obs: action)
    else:
        from agents.rl import TrainSettings, load_run, train

        out = tempfile.mkdtemp(prefix=f"aero-{method}-")
        train(cfg, TrainSettings(algo=method, timesteps=budget, seed=seed, eval_every=0, progress=False), out)
        model, _, _ = load_run(out)
        used, policy = budget, (lambda obs: np.clip(model.predict(obs, deterministic=True)[0], -1, 1))
    search_wall = time.perf_counter() - t0
    return dict(method=method, episodes=used, search_wall_s=search_wall, holdout=holdout_rows(cfg, policy, seeds))


def summarise(res: dict, full_row: int, m2_mid: float) -> dict:
    r = np.array([h["reward"] for h in res["holdout"]])
    light = np.array([h["reward"] for h in res["holdout"] if h["m2"] < m2_mid])
    heavy = np.array([h["reward"] for h in res["holdout"] if h["m2"] >= m2_mid])
    full = np.mean([h["traversals"] >= full_row for h in res["holdout"]])
    return dict(method=res["method"], episodes=res["episodes"], search_wall_s=res["search_wall_s"],
                mean_reward=float(r.mean()), std_reward=float(r.std()), full_row_fraction=float(full),
                light_mean=float(light.mean()), heavy_mean=float(heavy.mean()))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--budget", type=int, default=800)
    ap.add_argument("--seeds-per-design", type=int, default=8)
    ap.add_argument("--holdout", type=int, default=60)
    ap.add_argument("--frames", type=int, default=FRAMES)
    ap.add_argument("--methods", default="prototype,cmaes,random,ppo")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    methods = args.methods.split(",")
    with ProcessPoolExecutor(args.jobs) as pool:
        results = list(pool.map(run_method, methods, *(([x] * len(methods)) for x in
                                                        (args.budget, args.seeds_per_design, args.holdout,
                                                         args.seed, args.frames))))
    cfg = scene(args.frames)
    m2 = next(c for c in cfg.context if c.name == "design.m2")
    mid = 0.5 * (m2.low + m2.high)
    rows = [summarise(r, cfg.scene.frames - 1, mid) for r in results]
    if args.json:
        print(json.dumps(dict(scene=SCENE, frames=args.frames, budget=args.budget, holdout=args.holdout,
                              seed=args.seed, rows=rows),
                         indent=2))
        return
    print(f"{SCENE} on {args.frames} frames: budget {args.budget} episodes, {args.holdout} hold-out seeds, whole row = "
          f"{cfg.scene.frames - 1}, robot light < {mid * 1e3:.2f} g <= heavy")
    print("| method | episodes used | search wall | hold-out reward | whole row | light robot | heavy robot |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['method']} | {r['episodes']} | {r['search_wall_s']:.0f} s | {r['mean_reward']:.2f} ± "
              f"{r['std_reward']:.2f} | {100 * r['full_row_fraction']:.0f} % | {r['light_mean']:.2f} | "
              f"{r['heavy_mean']:.2f} |")


if __name__ == "__main__":
    main()
