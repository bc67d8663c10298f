"""``aero-env bench throughput``: designs per second at every fidelity rung, batched and one at a time.

One step of the design environment is one whole episode (a design run along the row). Every row
runs the same seeded random designs (random designs differ 10x in cost), each episode a reset with
seed ``seed + i`` and one step, and reports the median over ``repeats`` of its wall time:

* ``fidelities``: every rung of the ladder through one single env, one design at a time; at
  ``reduced`` also ``batch`` designs in one call of the model alone, on one core and on all (``model batch``:
  the episodes' values as arrays, what the tuner's screen runs; its one-core ``vs_mbd`` is the per-core
  ratio of the model's cost), and through the vector env (``vectorization_mode="vector_entry_point"``)
  in one step, on one core and on all; at the config's pymunk fidelity (``mbd`` when the
  config is at ``reduced``) also the vector env with its process pool over the cores (``pool_workers``
  processes). ``vs_single``: a batched row's designs/s over the single env's at its fidelity (the batch
  runs ``batch`` designs, the single env the first ``episodes`` of them);
  ``vs_mbd``: any row's designs/s over the single env's at ``mbd``, both measured in this run.
  ``vs_model_batch`` (``vs batch``): a reduced vector env row's designs/s over the model batch's on as many
  cores (what the env's own Python costs around the kernel). ``pool_efficiency``: the pool's designs/s over
  its process count times the single env's (1.0: every process as fast as one alone).
  ``first_call_s``: a row's first call, made untimed before its timed ones (at ``reduced`` it loads or
  compiles the model; for the pool it starts the workers): never inside a timed figure.
* ``workers``: ``gymnasium.vector`` environments over the single env at the config's fidelity:
  ``SyncVectorEnv`` with one environment, and ``AsyncVectorEnv`` with one process per extra worker
  (``autoreset_mode=SAME_STEP``, so every step is a fresh episode), and the speed-up over one.
* ``reduced_fallbacks``: the reduced batches that fell back from arrays to configs
  (:data:`aero_env.models.reduced.batch.FALLBACKS`): 0, or the reduced rows timed the slow path.

Workers share the machine's cores: on two cores two workers can at best double the rate.
"""

from __future__ import annotations

import contextlib
import functools
import math
import os

import gymnasium as gym
import numba
import numpy as np

from ..config import FIDELITY_PRESETS, Config
from ..design_space import DesignSpace
from ..envs import AerialAcrobatEnv, AerialAcrobatVectorEnv
from ..envs.aerial_acrobat import plan_episode
from ..models.reduced.batch import FALLBACKS, reduced_batch
from .designs import check_counts, median_time

BASELINE = "mbd"  # vs_mbd: the default fidelity, the one a user of the env gets
REDUCED = "reduced"


def _fidelity(cfg: Config, name: str) -> Config:
    return cfg.replace({"sim.fidelity": name})


def _single_row(cfg: Config, actions: np.ndarray, repeats: int, seed: int) -> dict:
    """One single env, one design at a time: reset(seed + i), step(action i)."""
    env = AerialAcrobatEnv(cfg)

    def run():
        rewards = []
        for i, a in enumerate(actions):
            env.reset(seed=seed + i)
            rewards.append(env.step(a)[1])
        return rewards

    first = median_time(lambda: (env.reset(seed=seed), env.step(actions[0])), 1)[0]
    wall, rewards = median_time(run, repeats)
    env.close()
    return dict(name=cfg.sim.fidelity, how="single env", designs=len(actions), wall_s=wall,
                designs_per_s=len(actions) / wall, first_call_s=first, mean_reward=float(np.mean(rewards)))


@contextlib.contextmanager
def _threads(n: int | None):
    """The reduced model's batch on ``n`` threads (None: all), restored after."""
    before = numba.get_num_threads()
    numba.set_num_threads(before if n is None else n)
    try:
        yield numba.get_num_threads()
    finally:
        numba.set_num_threads(before)


def _cores(n: int) -> str:
    return f"{n} core{'s' if n > 1 else ''}"


def _vector_row(cfg: Config, actions: np.ndarray, repeats: int, seed: int, workers: int | None,
                threads: int | None = None) -> dict:
    """The vector env, all designs in one step: reset(seed) gives sub-env i seed + i, as the single rows. At
    ``reduced`` its one call runs on ``threads`` cores (None: all)."""
    envs = AerialAcrobatVectorEnv(len(actions), cfg, workers=workers)
    try:
        def run():
            envs.reset(seed=seed)
            return envs.step(actions)[1]

        with _threads(threads) as cores:
            first = median_time(run, 1)[0]
            wall, rewards = median_time(run, repeats)
    finally:
        envs.close()
    processes = min(envs.workers, len(actions))
    how = f"vector env, {_cores(cores)}" if envs.reduced else f"vector env, pool of {processes}"
    return dict(name=cfg.sim.fidelity, how=how, designs=len(actions), wall_s=wall, designs_per_s=len(actions) / wall,
                first_call_s=first, mean_reward=float(np.mean(rewards)),
                **({"cores": cores} if envs.reduced else {"processes": processes}))


def _model_row(cfg: Config, actions: np.ndarray, repeats: int, seed: int, threads: int | None = 1) -> dict:
    """The reduced model alone on ``threads`` cores (None: all): the episodes the vector env's reset(seed) and
    step(actions) run, as one ``reduced_batch`` call of their values (what the tuner's screen calls), without the
    env around it."""
    space, clip = DesignSpace(cfg), cfg.env.action_out_of_box == "clip"
    episodes = [plan_episode(space, space.draw_for_seed(seed + i), a, clip).values
                for i, a in enumerate(actions)]
    with _threads(threads) as cores:
        first = median_time(lambda: reduced_batch(cfg, episodes), 1)[0]
        wall, (_, rewards) = median_time(lambda: reduced_batch(cfg, episodes), repeats)
    return dict(name=cfg.sim.fidelity, how=f"model batch, {_cores(cores)}", cores=cores, designs=len(actions), wall_s=wall,
                designs_per_s=len(actions) / wall, first_call_s=first, mean_reward=float(np.mean(rewards)))


def _ratios(rows: list[dict]) -> None:
    single = {r["name"]: r["designs_per_s"] for r in rows if r["how"] == "single env"}
    # the model batch by cores: the vector env on as many cores is measured against it
    model = {r["cores"]: r["designs_per_s"] for r in rows if r["how"].startswith("model batch")}
    for r in rows:
        if "processes" in r:  # the pool's rate over as many single envs' (one per process)
            r["pool_efficiency"] = r["designs_per_s"] / (r["processes"] * single[r["name"]])
        base = single.get(BASELINE)
        r["vs_mbd"] = r["designs_per_s"] / base if base else None
        if r["how"] != "single env":
            r["vs_single"] = r["designs_per_s"] / single[r["name"]]
        if r["name"] == REDUCED and r["how"].startswith("vector env"):
            r["vs_model_batch"] = r["designs_per_s"] / model[r["cores"]] if r["cores"] in model else None


def fidelity_rows(cfg: Config, designs: np.ndarray, episodes: int, batch: int, repeats: int, seed: int,
                  pool_workers: int | None) -> list[dict]:
    """Every rung through the single env (the first ``episodes`` designs), the reduced vector env (``batch``
    designs in one call) and the pymunk vector env with its pool (``episodes`` designs)."""
    rows = []
    # reduced first, its batch before its single env: the first call of the model (load, compile) is the batch's
    low = _fidelity(cfg, REDUCED)
    rows.append(_model_row(low, designs[:batch], repeats, seed))
    rows.append(_vector_row(low, designs[:batch], repeats, seed, None, threads=1))
    if numba.get_num_threads() > 1:
        rows.append(_model_row(low, designs[:batch], repeats, seed, threads=None))
        rows.append(_vector_row(low, designs[:batch], repeats, seed, None))
    for name in FIDELITY_PRESETS:
        rows.append(_single_row(_fidelity(cfg, name), designs[:episodes], repeats, seed))
    pool_fidelity = cfg.sim.fidelity if cfg.sim.model != REDUCED else BASELINE
    # the pool asked for explicitly (the vector env's default runs in this process): None, one process per core
    rows.append(_vector_row(_fidelity(cfg, pool_fidelity), designs[:episodes], repeats, seed,
                            pool_workers or os.cpu_count() or 1))
    _ratios(rows)
    return rows


def _vector_env(cfg: Config, workers: int):
    fns = [functools.partial(AerialAcrobatEnv, cfg)] * workers
    mode = gym.vector.AutoresetMode.SAME_STEP
    if workers == 1:
        return gym.vector.SyncVectorEnv(fns, autoreset_mode=mode)
    return gym.vector.AsyncVectorEnv(fns, autoreset_mode=mode, context="spawn")


def worker_rows(cfg: Config, designs: np.ndarray, episodes: int, repeats: int, seed: int, workers) -> list[dict]:
    rows = []
    dim = designs.shape[1]
    for w in workers:
        envs = _vector_env(cfg, w)
        try:
            envs.reset(seed=seed)
            steps = math.ceil(episodes / w)
            # every worker count runs the same designs
            actions = np.resize(designs[:episodes], (steps * w, dim)).reshape(steps, w, dim)

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
    return rows


def throughput(cfg: Config, episodes: int = 40, repeats: int = 3, seed: int = 0, workers=(1, 2), batch: int = 1000,
               pool_workers: int | None = None) -> dict:
    check_counts(episodes=episodes, repeats=repeats, batch=batch)
    if pool_workers is not None:
        check_counts(pool_workers=pool_workers)
    designs = np.random.default_rng(seed).uniform(-1, 1, (max(episodes, batch), len(cfg.tunable))).astype(np.float32)
    before = FALLBACKS.count
    return dict(fidelity=cfg.sim.fidelity, repeats=repeats, seed=seed, episodes=episodes, batch=batch,
                fidelities=fidelity_rows(cfg, designs, episodes, batch, repeats, seed, pool_workers),
                workers=worker_rows(cfg, designs, episodes, repeats, seed, workers),
                reduced_fallbacks=FALLBACKS.count - before)


def _percent(x) -> str:
    return "-" if x is None else f"{100 * x:.0f}%"


def _ratio(x) -> str:
    return "-" if x is None else f"{x:.2f}x"


def table(report: dict) -> str:
    lines = [f"median of {report['repeats']} runs; the same random designs in every row (seed {report['seed']})",
             f"{'fidelity':>9} {'how':<24} {'designs':>7} {'designs/s':>10} {'vs single':>9} {'vs mbd':>9} "
             f"{'vs batch':>8} {'first call s':>12} {'mean reward':>11}"]
    for r in report["fidelities"]:
        lines.append(f"{r['name']:>9} {r['how']:<24} {r['designs']:>7} {r['designs_per_s']:10.1f} "
                     f"{_ratio(r.get('vs_single')):>9} {_ratio(r['vs_mbd']):>9} {_percent(r.get('vs_model_batch')):>8} "
                     f"{r['first_call_s']:12.3f} "
                     f"{r['mean_reward']:11.3f}")
    for r in report["fidelities"]:
        if "pool_efficiency" in r:
            lines.append(f"the pool at {r['name']}: {r['designs_per_s']:.1f} designs/s = {r['pool_efficiency']:.2f} x "
                         f"its {r['processes']} processes x the single env's rate")
    lines += ["", f"gymnasium.vector over the single env at fidelity {report['fidelity']}",
              f"{'workers':>7} {'episodes':>8} {'wall s':>8} {'episodes/s':>10} {'speed-up':>8}"]
    for r in report["workers"]:
        lines.append(f"{r['workers']:>7} {r['episodes']:>8} {r['wall']:8.2f} {r['episodes_per_second']:10.1f} "
                     f"{r['speedup_vs_1']:7.2f}x")
    if report.get("reduced_fallbacks"):
        lines += ["", f"reduced: {report['reduced_fallbacks']} batches fell back from arrays to configs: the reduced "
                      f"rows timed the slow path"]
    return "\n".join(lines)
