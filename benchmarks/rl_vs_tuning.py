"""A policy (context -> design) against the best single design, on the maker's contexts.

    python benchmarks/rl_vs_tuning.py [--timesteps 40960] [--holdout 200] [--holdout-seed 0] [--seed 0]
                                      [--methods prototype,single,ppo] [--policy DIR]
                                      [--tune-trials 400] [--seeds-per-design 32] [--curve-every 4000]
                                      [--plot FILE.png] [--json]

The scene is ``aero_env/AerialAcrobatContexts-v0`` (``configs/contexts.yaml``): every reset draws the
row's rise and pitch, the robot's mass and the card pair (observed) and the build's cutting error (not
observed), on a 5-frame row (whole row = 4 traversals). Methods:

* ``prototype``: the paper's design for every context, no search.
* ``single``: the best single design, stored in ``configs/contexts_single.yaml``: a robust tune over the
  context draws with a generous budget (CMA-ES, 1,200 designs, each scored on the same 32 episode seeds,
  so 38,400 episodes; the file's header gives the command). Re-scored here, not re-tuned.
* ``tuned``: the same tune run here with ``--tune-trials`` x ``--seeds-per-design`` episodes (its wall time
  is then measured in this run).
* ``ppo``: a policy trained through the native vector env for ``--timesteps`` episodes (32 designs a step
  over a pool of one process per core): exactly ``aero-env train configs/contexts.yaml`` with
  :data:`PPO_ARGS`. The policy trained to the end is scored; the learning curve (hold-out share against
  training episodes) is only watched, never used to pick a policy. ``--policy DIR`` scores a run that
  ``aero-env train`` wrote instead of training one here.

Every method is scored on the same ``--holdout`` contexts: episode seeds ``10^6·(S+1)`` onward for
``--holdout-seed S``, never seen in tuning or training (which draw from seeds below 10^5). The table gives
each method's episodes, wall time, hold-out whole-row share and mean traversals; then the policy's
learning curve (drawn with ``--plot``) and, for each design field, the context field the policy's choice
follows most (Spearman correlation over the hold-out contexts).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

SCENE = "aero_env/AerialAcrobatContexts-v0"
CONFIG = "configs/contexts.yaml"
SINGLE = "configs/contexts_single.yaml"  # the best single design (its header: the tune that wrote it)
METHODS = ("prototype", "single", "tuned", "ppo")
HOLDOUT_BASE = 1_000_000
# aero-env train configs/contexts.yaml --timesteps T --n-envs 32 --vector --eval-every 0 --hp n_steps=32
#   --hp batch_size=256: 32 designs a step, a PPO update every 1024 episodes
N_ENVS = 32
PPO_HP = dict(n_steps=32, batch_size=256)
PPO_ARGS = f"--n-envs {N_ENVS} --vector --eval-every 0 " + " ".join(f"--hp {k}={v}" for k, v in PPO_HP.items())


def holdout_seeds(holdout_seed: int, n: int) -> list[int]:
    start = HOLDOUT_BASE * (holdout_seed + 1)
    return list(range(start, start + n))


class HoldoutScorer:
    """Plays a map obs -> action on the hold-out contexts, every design of a batch in one call of the vector
    env (a pool of one process per core)."""

    def __init__(self, cfg, seeds: list[int]):
        from aero_env.envs import AerialAcrobatVectorEnv

        self.seeds = seeds
        self.envs = AerialAcrobatVectorEnv(len(seeds), cfg, workers=os.cpu_count() or 1)
        self.full_row = cfg.scene.frames - 1

    def play(self, choose) -> dict:
        obs, info = self.envs.reset(seed=self.seeds)
        actions = np.clip(np.asarray(choose(obs), dtype=np.float64), -1.0, 1.0)
        _, _, _, _, info = self.envs.step(actions)
        done = info["final_info"]  # every episode ends in its one step; the vector env resets it in the same step
        traversals = np.asarray(done["traversals"])
        design = {k: np.asarray(v) for k, v in done["design"].items() if not k.startswith("_")}
        return dict(obs=obs, actions=actions, traversals=traversals.tolist(),
                    full_row_fraction=float(np.mean(traversals >= self.full_row)),
                    mean_traversals=float(np.mean(traversals)), design=design)

    def close(self) -> None:
        self.envs.close()


def stored_single(space) -> tuple[np.ndarray, int]:
    """The action of the stored best single design and the episodes its tune spent (trials x seeds, from the
    header ``aero-env tune`` wrote: "trial N of TRIALS", "traversals per seed [...]")."""
    import re

    from aero_env.config import load_config

    single = load_config(SINGLE)
    head = Path(SINGLE).read_text()
    trials = int(re.search(r"trial \d+ of (\d+)", head).group(1))
    seeds = len(re.search(r"traversals per seed \[([^\]]*)\]", head).group(1).split(","))
    action = space.action_for({t.name: single.value(t.name) for t in space.tunables}, dtype=np.float64)
    return action, trials * seeds


def run_single(cfg, trials: int, k: int, seed: int):
    from agents.tune import tune
    from agents.tune_settings import TuneSettings

    r = tune(cfg, TuneSettings(sampler="cmaes", trials=trials, seeds_per_design=k, seed=seed, progress=False),
             config_name="contexts")
    return np.array(r.best_action), r.trials * k, r


def run_ppo(cfg, timesteps: int, seed: int, scorer: HoldoutScorer, curve_every: int, out: str):
    from stable_baselines3.common.callbacks import BaseCallback

    from agents.rl import TrainSettings, load_run, train

    curve: list[tuple[int, float, float]] = []

    class HoldoutCurve(BaseCallback):  # watches only: deterministic predictions, no RNG drawn
        def __init__(self):
            super().__init__()
            self.next = 0

        def _on_step(self) -> bool:
            if curve_every and self.num_timesteps >= self.next:
                self.next += curve_every
                res = scorer.play(lambda obs: self.model.predict(obs, deterministic=True)[0])
                curve.append((int(self.num_timesteps), res["full_row_fraction"], res["mean_traversals"]))
            return True

    settings = TrainSettings(algo="ppo", timesteps=timesteps, n_envs=N_ENVS, seed=seed, eval_every=0, vector=True,
                             hyperparameters=PPO_HP, progress=False)
    run = train(cfg, settings, out, callbacks=[HoldoutCurve()])
    model, _, _ = load_run(out)
    if curve_every:  # the policy after the last update (the callback last saw it before that update)
        res = scorer.play(lambda obs: model.predict(obs, deterministic=True)[0])
        if curve and curve[-1][0] == int(run["timesteps_done"]):
            curve.pop()
        curve.append((int(run["timesteps_done"]), res["full_row_fraction"], res["mean_traversals"]))
    return (lambda obs: model.predict(obs, deterministic=True)[0]), int(run["timesteps_done"]), run, curve


def load_ppo(cfg, run_dir: str):
    """A policy ``aero-env train`` wrote, trained on this scene."""
    from aero_env.config import ConfigError

    from agents.rl import load_run

    model, trained_on, run = load_run(run_dir)
    if trained_on != cfg:
        raise ConfigError(f"--policy {run_dir}: trained on another scene than {CONFIG} (its config.yaml)")
    return (lambda obs: model.predict(obs, deterministic=True)[0]), int(run.get("timesteps_done", run["timesteps"])), \
        run


def context_table(cfg, res: dict) -> list[dict]:
    """For each design field: the context field its choice follows most (Spearman rho over the hold-out)."""
    from scipy.stats import spearmanr

    ctx_names = [c.name for c in cfg.context]
    rows = []
    for i, t in enumerate(cfg.tunable):
        a = res["actions"][:, i]
        # how far the choice moves over the contexts: the 10-90 % span of the action, as a share of the box
        # (a rank correlation alone would call the faint, smooth tilt of an untrained network "following")
        spread = float(np.percentile(a, 90) - np.percentile(a, 10)) / 2.0
        if np.ptp(a) == 0:
            rows.append(dict(design=t.name, context=None, rho=0.0, spread=0.0))
            continue
        rhos = [float(spearmanr(res["obs"][:, j], a).statistic) for j in range(len(ctx_names))]
        j = int(np.argmax(np.abs(rhos)))
        rows.append(dict(design=t.name, context=ctx_names[j], rho=rhos[j], spread=spread,
                         all={n: r for n, r in zip(ctx_names, rhos)}))
    return rows


def plot_curve(curve, rows, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    t, share = [c[0] for c in curve], [100 * c[1] for c in curve]
    ax.plot(t, share, "o-", color="C3", label="ppo policy (deterministic)")
    for r, colour in zip(rows, ("C0", "C2", "C4")):
        if r["method"] != "ppo":
            ax.axhline(100 * r["full_row_fraction"], ls="--", color=colour, label=r["method"])
    ax.set(xlabel="training episodes (= designs tried)", ylabel="hold-out contexts, whole row (%)",
           title=f"{SCENE}: {len(rows) and rows[0]['holdout']} hold-out contexts", ylim=(0, 100))
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--timesteps", type=int, default=40_960, help="PPO's training episodes (40 updates of 1,024)")
    ap.add_argument("--tune-trials", type=int, default=400, help="designs the robust tune scores")
    ap.add_argument("--seeds-per-design", type=int, default=32, help="contexts (episode seeds) per tuned design")
    ap.add_argument("--holdout", type=int, default=200, help="hold-out contexts")
    ap.add_argument("--holdout-seed", type=int, default=0, help="which hold-out contexts: seeds 10^6·(S+1) onward")
    ap.add_argument("--seed", type=int, default=0, help="the tune's and the policy's seed")
    ap.add_argument("--methods", default="prototype,single,ppo", help=f"comma-separated, of {', '.join(METHODS)}")
    ap.add_argument("--policy", metavar="DIR", help="score the policy aero-env train wrote in DIR (no training here)")
    ap.add_argument("--curve-every", type=int, default=4000, help="training episodes between curve points (0: none)")
    ap.add_argument("--plot", metavar="FILE.png", help="draw the policy's learning curve")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    from aero_env.config import ConfigError, load_config
    from aero_env.design_space import DesignSpace

    methods = args.methods.split(",")
    bad = [m for m in methods if m not in METHODS]
    for name, value, lo in (("--timesteps", args.timesteps, 1), ("--tune-trials", args.tune_trials, 1),
                            ("--seeds-per-design", args.seeds_per_design, 1), ("--holdout", args.holdout, 1),
                            ("--holdout-seed", args.holdout_seed, 0), ("--curve-every", args.curve_every, 0)):
        if value < lo:
            sys.exit(f"rl_vs_tuning: {name} = {value}: must be at least {lo}")
    if bad:
        sys.exit(f"rl_vs_tuning: --methods {bad[0]!r}: allowed {', '.join(METHODS)}")
    if args.policy and not Path(args.policy, "run.json").is_file():
        sys.exit(f"rl_vs_tuning: --policy {args.policy}: no run.json there; give a folder aero-env train wrote")
    cfg = load_config(CONFIG)
    space = DesignSpace(cfg)
    scorer = HoldoutScorer(cfg, holdout_seeds(args.holdout_seed, args.holdout))
    rows, curve, chosen = [], [], None
    one_design = (lambda a: lambda obs: np.tile(a, (len(obs), 1)))
    try:
        for method in methods:
            t0 = time.perf_counter()
            extra = {}
            if method == "prototype":
                action, used = space.action_for(dtype=np.float64), 0
                choose, wall = one_design(action), 0.0
            elif method == "single":
                action, used = stored_single(space)
                choose, wall = one_design(action), None  # tuned once, not in this run
                extra = dict(design=space.values(action), config=SINGLE)
            elif method == "tuned":
                action, used, r = run_single(cfg, args.tune_trials, args.seeds_per_design, args.seed)
                choose, wall = one_design(action), time.perf_counter() - t0
                extra = dict(design=space.values(action), tune_mean_reward=r.best_reward)
            elif args.policy:
                choose, used, run = load_ppo(cfg, args.policy)
                wall, extra = run.get("wall_time"), dict(policy=args.policy)
            else:
                with tempfile.TemporaryDirectory(prefix="aero-ppo-") as out:
                    choose, used, run, curve = run_ppo(cfg, args.timesteps, args.seed, scorer, args.curve_every,
                                                       out)
                    wall = float(run["wall_time"])
            res = scorer.play(choose)
            if method == "ppo":
                chosen = res
            rows.append(dict(method=method, episodes=used, wall_s=wall, holdout=args.holdout,
                             full_row_fraction=res["full_row_fraction"], mean_traversals=res["mean_traversals"],
                             **extra))
    except ConfigError as exc:
        sys.exit(f"rl_vs_tuning: {exc}")
    finally:
        scorer.close()
    follows = context_table(cfg, chosen) if chosen is not None else []
    by = {r["method"]: r for r in rows}
    gain = (by["ppo"]["full_row_fraction"] - by["single"]["full_row_fraction"]) if {"ppo", "single"} <= set(by) \
        else None
    if args.plot and curve:
        plot_curve(curve, rows, args.plot)
    if args.json:
        print(json.dumps(dict(scene=SCENE, config=CONFIG, frames=cfg.scene.frames, holdout=args.holdout,
                              holdout_seed=args.holdout_seed, seed=args.seed, rows=rows,
                              ppo_minus_single=gain, curve=[dict(episodes=t, full_row_fraction=f, mean_traversals=m)
                                                            for t, f, m in curve],
                              design_follows=follows), indent=2))
        return
    seeds = holdout_seeds(args.holdout_seed, args.holdout)
    print(f"{SCENE} ({CONFIG}), whole row = {cfg.scene.frames - 1} traversals; {args.holdout} hold-out contexts "
          f"(seeds {seeds[0]}..{seeds[-1]})")
    print("| method | episodes | wall | hold-out whole row | mean traversals |")
    print("|---|---|---|---|---|")
    for r in rows:
        wall = "tuned once (its header)" if r["wall_s"] is None else f"{r['wall_s']:.0f} s"
        print(f"| {r['method']} | {r['episodes']} | {wall} | {100 * r['full_row_fraction']:.1f} % | "
              f"{r['mean_traversals']:.2f} |")
    if gain is not None:
        print(f"ppo - single: {100 * gain:+.1f} points of hold-out whole rows")
    if curve:
        print("learning curve (hold-out whole row against training episodes): " +
              ", ".join(f"{t}: {100 * f:.0f} %" for t, f, _ in curve))
    if follows:
        print("| design field | its range used (10-90 % of contexts) | follows most | Spearman rho |")
        print("|---|---|---|---|")
        for f in follows:
            print(f"| {f['design']} | {100 * f['spread']:.0f} % | {f['context'] or '-'} | {f['rho']:+.2f} |")
    if args.plot and curve:
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
