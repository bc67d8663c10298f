"""Train the policies and maps that ``benchmarks/rl_vs_tuning.py`` scores, and ship them.

    python benchmarks/rl_policies.py [--task contexts|hard]
                                     [--methods ppo,ppo-reduced,sac,ppo-multifidelity,linear-map,...] [--seeds 0-4] [--out policies/contexts] [--timesteps 40960] [--finish-episodes 3072]
                                     [--map-episodes 40960] [--nn-contexts 128] [--watch 200]

Every method learns a map context -> design on ``configs/contexts.yaml`` (``--task hard``:
``configs/contexts_hard.yaml``, shipped in ``policies/contexts-hard``, every search from the box's centre, there
being no tuned single design) from training contexts only (episode seeds below 10^5), once per seed, and writes
``OUT/METHOD/seedS/``:

* **RL** (``ppo``, ``sac``, ``ppo-reduced``, ``ppo-multifidelity``): ``aero-env train`` through the native vector env (32 designs a
  step over a pool of one process per core) with :data:`RL_METHODS`' settings; ``run.json`` records the
  exact command. Shipped: ``model.zip`` (``PPO.load`` / ``SAC.load``), ``run.json``, ``config.yaml`` and
  ``curve.json``, the learning curve: the whole-row share on the **watch** contexts
  (``rl_holdout.WATCH_BASE``) at ``mbd`` every ``--curve-every`` training episodes (a finish: after every PPO
  update). The curve only watches: the final scores come from hold-out sets no curve sees, and no point of it
  picks a policy. ``wall_time``
  is the training's own time (the curve's episodes are timed apart and taken out). ``ppo-reduced`` trains
  at ``sim.fidelity: reduced``, the fast rung, and is watched at ``mbd``, where its designs are used.
  ``ppo-multifidelity`` is the multi-fidelity recipe: it starts from the shipped ``ppo-reduced`` policy of the
  same seed (``aero-env train --init-from``) and finishes it at ``mbd`` for ``--finish-episodes``
  (:data:`FINISH_EPISODES`; docs/agents.md says how that was chosen). Its ``run.json`` counts the finish;
  ``init_from`` records the pretraining's episodes and wall time.
* **Maps tuned black-box** (``linear-map``, ``mlp-map``): :func:`agents.context_maps.fit_map`, CMA-ES at
  ``reduced`` for ``--map-episodes`` episodes, from the best single design (``configs/contexts_single.yaml``).
  Shipped: ``policy.json`` (the map's numbers, its episodes and wall time).
* **Nearest neighbour** (``nearest-neighbour``): a search per training context at ``mbd`` (``--nn-contexts``
  contexts, :func:`agents.context_maps.search_contexts`, from the single design); ``policy.json`` holds the
  table of contexts and the designs that made their whole row.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from rl_holdout import TASKS, Task, single_action, watch_seeds

CONTEXTS = TASKS["contexts"]

N_ENVS = 32
TIMESTEPS = 40_960  # 40 PPO updates of 1,024 episodes
MAP_EPISODES = 40_960
NN_CONTEXTS = 128
NN_BASE = 60_000  # nearest neighbour's training contexts: seeds NN_BASE + 1000·seed onward (training range)
TRAINING_LIMIT = 100_000  # every training context's episode seed lies below this
PPO_HP = dict(n_steps=32, batch_size=256)  # 32 designs a step, a PPO update every 1,024 episodes
# SAC: one gradient step per episode (32 per vector step) on batches of 256, after 1,024 random designs
SAC_HP = dict(batch_size=256, gradient_steps=32, learning_starts=1024)
RL_METHODS = {
    "ppo": dict(algo="ppo", hp=PPO_HP, overrides={}),
    "ppo-reduced": dict(algo="ppo", hp=PPO_HP, overrides={"sim.fidelity": "reduced"}),
    "sac": dict(algo="sac", hp=SAC_HP, overrides={}),
    "ppo-multifidelity": dict(algo="ppo", hp=PPO_HP, overrides={}, init_from="ppo-reduced"),
}
FINISH_EPISODES = 3072  # ppo-multifidelity's episodes at mbd: 3 PPO updates (docs/agents.md: chosen on the watch set)
MAP_METHODS = {"linear-map": "linear", "mlp-map": "mlp"}
METHODS = (*RL_METHODS, *MAP_METHODS, "nearest-neighbour")
SHIPPED = ("model.zip", "run.json", "config.yaml", "curve.json")


def training_seed(seed: int) -> int:
    """The ``--seed`` of run ``seed``: sub-env i of a vector env made with ``--seed s`` draws its contexts from a
    generator seeded ``s + i``, so runs seeded 0, 1, 2, ... would share 31 of their 32 streams of contexts; run k
    takes ``32·k`` and no two runs share one (run 0 is ``--seed 0``)."""
    return seed * N_ENVS


def method_timesteps(method: str, timesteps: int, finish: int) -> int:
    """A run's own episodes: ``--timesteps``, or ``--finish-episodes`` for a run that finishes a pretrained one."""
    return finish if "init_from" in RL_METHODS[method] else timesteps


def pretrained(method: str, seed: int, root: Path) -> Path | None:
    """The shipped run a method starts from (None: it starts from scratch)."""
    spec = RL_METHODS[method]
    return Path(root, spec["init_from"], f"seed{seed}") if "init_from" in spec else None


def train_command(method: str, seed: int, timesteps: int, finish: int, out: str, root: Path,
                  task: Task = CONTEXTS) -> str:
    spec = RL_METHODS[method]
    sets = "".join(f" --set {k}={v}" for k, v in spec["overrides"].items())
    hps = "".join(f" --hp {k}={v}" for k, v in spec["hp"].items())
    start = pretrained(method, seed, root)
    init = f" --init-from {start}" if start else ""
    return (f"aero-env train {task.config}{sets} --algo {spec['algo']} --timesteps {method_timesteps(method, timesteps, finish)} "
            f"--n-envs {N_ENVS} --vector --eval-every 0{hps} --seed {training_seed(seed)}{init} --out {out}")


def train_rl(method: str, seed: int, timesteps: int, dest: Path, watch: int, curve_every: int,
             finish: int = FINISH_EPISODES, task: Task = CONTEXTS) -> dict:
    """Train one policy and write its shipped files to ``dest`` (``OUT/METHOD/seedS``); returns its run.json."""
    from stable_baselines3.common.callbacks import BaseCallback

    from aero_env.config import load_config
    from agents.episode_runner import EpisodeRunner, draws_for_seeds
    from agents.rl import TrainSettings, load_run, train

    spec = RL_METHODS[method]
    if "init_from" in spec and curve_every:  # a short finish: a point after each PPO update
        curve_every = min(curve_every, N_ENVS * PPO_HP["n_steps"])
    cfg = load_config(task.config, spec["overrides"])
    scorer = EpisodeRunner(load_config(task.config))  # watched where the policy is used: mbd
    draws = draws_for_seeds(scorer.space, watch_seeds(watch))
    obs = scorer.observations(draws)
    curve: list[dict] = []
    watched = [0.0]

    def point(model, episodes: int) -> None:
        t0 = time.perf_counter()
        t = scorer.traversals(draws, model.predict(obs, deterministic=True)[0])
        watched[0] += time.perf_counter() - t0
        curve.append(dict(episodes=episodes, full_row_fraction=float(np.mean(t >= scorer.full_row)),
                          mean_traversals=float(np.mean(t))))

    class WatchCurve(BaseCallback):  # watches only: deterministic predictions, no RNG drawn
        """Scores the policy every ``curve_every`` episodes, labelled with the episodes it has learnt from: those
        of the rollouts whose update has run (PPO updates after each rollout of 1,024 episodes, SAC after each
        vector step), not the episodes collected so far."""

        def __init__(self):
            super().__init__()
            self.next = 0
            self.learnt = 0

        def _on_rollout_end(self) -> None:  # the update on this rollout runs next, before the next rollout
            self.learnt = int(self.num_timesteps)

        def _on_step(self) -> bool:
            if curve_every and self.num_timesteps >= self.next:
                self.next += curve_every
                if not curve or curve[-1]["episodes"] != self.learnt:  # no update since the last point: the same policy
                    point(self.model, self.learnt)
            return True

    root = dest.parent.parent
    start = pretrained(method, seed, root)
    settings = TrainSettings(algo=spec["algo"], timesteps=method_timesteps(method, timesteps, finish), n_envs=N_ENVS,
                             seed=training_seed(seed), eval_every=0, vector=True, hyperparameters=spec["hp"],
                             progress=False)
    try:
        with tempfile.TemporaryDirectory(prefix="aero-policy-") as tmp:
            run = train(cfg, settings, tmp, callbacks=[WatchCurve()], init_from=start)
            model, _, _ = load_run(tmp)
            point(model, int(run["timesteps_done"]))  # the policy after its last update
            run["wall_time_with_curve"] = run["wall_time"]
            run["wall_time"] = run["wall_time"] - watched[0]
            run["episodes_per_second"] = run["timesteps_done"] / run["wall_time"]
            run["command"] = train_command(method, seed, timesteps, finish, str(dest), root, task)
            run.update(method=method, run=seed)
            Path(tmp, "run.json").write_text(json.dumps(run, indent=1) + "\n")
            Path(tmp, "curve.json").write_text(json.dumps(dict(watch_seeds=[watch_seeds(watch)[0], watch],
                                                               fidelity="mbd", curve=curve), indent=1) + "\n")
            _replace(dest, [Path(tmp, name) for name in SHIPPED])
    finally:
        scorer.close()
    return run


def fit_baseline(method: str, seed: int, dest: Path, map_episodes: int, nn_contexts: int,
                 task: Task = CONTEXTS) -> dict:
    """Fit a black-box map or a nearest-neighbour table on ``task`` and write ``dest/policy.json``; returns its
    record. Both start from the task's best single design, or from the box's centre where it has none."""
    from aero_env.config import load_config
    from agents.context_maps import NearestNeighbour, fit_map, search_contexts
    from agents.episode_runner import EpisodeRunner, draws_for_seeds

    t0 = time.perf_counter()
    if method in MAP_METHODS:
        runner = EpisodeRunner(load_config(task.config, {"sim.fidelity": "reduced"}))
        m, history = fit_map(runner, MAP_METHODS[method], seed, map_episodes,
                             start=single_action(runner.space, task))
        record = dict(method=method, fidelity="reduced", map=m.to_json_dict(), history=history)
    else:
        runner = EpisodeRunner(load_config(task.config))
        try:
            start = NN_BASE + 1000 * seed
            found = search_contexts(runner, draws_for_seeds(runner.space, range(start, start + nn_contexts)),
                                    single_action(runner.space, task), seed)
        finally:
            runner.close()
        record = dict(method=method, fidelity="mbd", table=NearestNeighbour.from_search(found).to_json_dict(),
                      contexts=nn_contexts, solved=int(found.solved.sum()), seeds=[start, nn_contexts])
    record.update(seed=seed, episodes=runner.episodes, wall_time=time.perf_counter() - t0,
                  start=task.single or "the box's centre",
                  command=f"python benchmarks/rl_policies.py{task_option(task)} --methods {method} --seeds {seed}")
    with tempfile.TemporaryDirectory(prefix="aero-policy-") as tmp:
        Path(tmp, "policy.json").write_text(json.dumps(record, indent=1) + "\n")
        _replace(dest, [Path(tmp, "policy.json")])
    return record


def task_option(task: Task) -> str:
    """The option that names ``task`` on a command line (none for the default task)."""
    return "" if task.name == "contexts" else f" --task {task.name}"


def _replace(dest: Path, files: list[Path]) -> None:
    """``dest`` holds exactly ``files`` (a run's folder is replaced whole)."""
    if dest.exists():
        shutil.rmtree(dest)
    dest.mkdir(parents=True)
    for f in files:
        shutil.copy2(f, dest / f.name)


def parse_seeds(text: str) -> list[int]:
    out = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out += list(range(int(lo), int(hi or lo) + 1))
    if not out or min(out) < 0:
        raise ValueError(text)
    return out


def checked_args(prog: str, args, allowed, minimums) -> tuple[list[str], list[int]]:
    """``args.methods`` and ``args.seeds`` parsed, after ``minimums`` ((option, value, least) each) are checked:
    the first bad one ends the script with one line naming it."""
    for name, value, lo in minimums:
        if value < lo:
            sys.exit(f"{prog}: {name} = {value}: must be at least {lo}")
    methods = args.methods.split(",")
    bad = [m for m in methods if m not in allowed]
    if bad:
        sys.exit(f"{prog}: --methods {bad[0]!r}: allowed {', '.join(allowed)}")
    try:
        return methods, parse_seeds(args.seeds)
    except ValueError:
        sys.exit(f"{prog}: --seeds {args.seeds!r}: give seeds (0 or more) as 0-4 or 0,2,5")


def check_training_ranges(prog: str, methods, seeds, map_episodes: int, nn_contexts: int,
                          task: Task = CONTEXTS) -> None:
    """Every map and nearest-neighbour seed draws its training contexts from its own block of episode seeds, below
    nearest neighbour's block (maps) or below 10^5 (nearest neighbour), so no two seeds and no two methods share
    a context, and none reaches the watch or hold-out sets; a setting that would is refused in one line."""
    from aero_env.config import load_config
    from aero_env.design_space import DesignSpace
    from agents.context_maps import MAP_SEEDS, map_block_size, map_seed_span

    space = DesignSpace(load_config(task.config))
    for method in methods:
        if method in MAP_METHODS:
            if max(seeds) >= MAP_SEEDS:
                sys.exit(f"{prog}: --seeds {max(seeds)}: a map's training seeds are 0-{MAP_SEEDS - 1} (each has its "
                         f"own block of training contexts)")
            for seed in seeds:
                first, last = map_seed_span(MAP_METHODS[method], space.dim, space.obs_dim, seed, map_episodes)
                if last < first:
                    sys.exit(f"{prog}: --map-episodes = {map_episodes}: too few for one CMA-ES generation of "
                             f"{method} (64 contexts x its population)")
                end = min(first + map_block_size(), NN_BASE)  # the next seed's block, or nearest neighbour's
                if last >= end:
                    sys.exit(f"{prog}: --seeds {seed} with --map-episodes {map_episodes}: {method} would draw "
                             f"training contexts {first}..{last}, past its block (below {end})")
        elif method == "nearest-neighbour":
            if nn_contexts > 1000:
                sys.exit(f"{prog}: --nn-contexts = {nn_contexts}: at most 1000 (each seed's block of contexts)")
            if NN_BASE + 1000 * max(seeds) + nn_contexts > TRAINING_LIMIT:
                top = (TRAINING_LIMIT - NN_BASE) // 1000 - 1
                sys.exit(f"{prog}: --seeds {max(seeds)}: nearest neighbour's contexts would reach {TRAINING_LIMIT} "
                         f"(the watch and hold-out sets lie above); allowed seeds 0-{top}")


def check_pretrained(prog: str, methods, seeds, root: Path) -> None:
    """A method that finishes a pretrained policy needs that policy in ``root``, or its method earlier in
    ``methods`` (trained first); a missing one is refused in one line before any training."""
    for method in methods:
        start = RL_METHODS.get(method, {}).get("init_from")
        if start is None or start in methods:  # trained first (methods run in METHODS' order)
            continue
        for seed in seeds:
            if not (pretrained(method, seed, root) / "model.zip").is_file():
                sys.exit(f"{prog}: {method} seed {seed} starts from {pretrained(method, seed, root)}, which holds no "
                         f"policy; train it first (--methods {start},{method})")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--methods", default=",".join(METHODS), help=f"comma-separated, of {', '.join(METHODS)}")
    ap.add_argument("--seeds", default="0-4", help="training seeds: 0-4 or 0,2,5")
    ap.add_argument("--task", default="contexts", choices=tuple(TASKS),
                    help="the maker's contexts, or the hard task (wider shelves, 8 frames)")
    ap.add_argument("--out", help="where they go (OUT/METHOD/seedS); default the task's policies/ folder")
    ap.add_argument("--timesteps", type=int, default=TIMESTEPS, help="an RL policy's training episodes")
    ap.add_argument("--finish-episodes", type=int, default=FINISH_EPISODES,
                    help="ppo-multifidelity's episodes at mbd, after its pretraining at reduced")
    ap.add_argument("--map-episodes", type=int, default=MAP_EPISODES, help="a map's CMA-ES episodes (at reduced)")
    ap.add_argument("--nn-contexts", type=int, default=NN_CONTEXTS, help="nearest neighbour's training contexts")
    ap.add_argument("--watch", type=int, default=200, help="contexts the learning curves watch")
    ap.add_argument("--curve-every", type=int, default=4096, help="training episodes between curve points (0: none)")
    args = ap.parse_args()
    methods, seeds = checked_args("rl_policies", args, METHODS, (
        ("--timesteps", args.timesteps, 1), ("--finish-episodes", args.finish_episodes, 1),
        ("--map-episodes", args.map_episodes, 1),
        ("--nn-contexts", args.nn_contexts, 1), ("--watch", args.watch, 1), ("--curve-every", args.curve_every, 0)))
    methods = [m for m in METHODS if m in methods]  # a pretraining before the run that finishes it
    task = TASKS[args.task]
    args.out = args.out or task.policies
    check_training_ranges("rl_policies", methods, seeds, args.map_episodes, args.nn_contexts, task)
    check_pretrained("rl_policies", methods, seeds, Path(args.out))
    t0 = time.perf_counter()
    for method in methods:
        for seed in seeds:
            dest = Path(args.out, method, f"seed{seed}")
            if method in RL_METHODS:
                run = train_rl(method, seed, args.timesteps, dest, args.watch, args.curve_every, args.finish_episodes,
                               task)
                print(f"{method} seed {seed}: {run['timesteps_done']} episodes in {run['wall_time']:.0f} s "
                      f"(+{run['wall_time_with_curve'] - run['wall_time']:.0f} s watching)", flush=True)
            else:
                rec = fit_baseline(method, seed, dest, args.map_episodes, args.nn_contexts, task)
                print(f"{method} seed {seed}: {rec['episodes']} episodes in {rec['wall_time']:.0f} s", flush=True)
    print(f"all in {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
