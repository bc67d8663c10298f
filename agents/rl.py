"""Reinforcement learning of designs with stable-baselines3 (PPO or SAC, on torch's CPU build).

The environment is a contextual bandit: one step per episode, the observation is the drawn
scene (context), the action is the design. On a scene whose context is drawn at every reset
(``aero_env/AerialAcrobatVaried-v0``, or any config with ``context`` ranges) the policy learns
a map from context to design, which one black-box design cannot be.

A training run writes to its directory ``DIR``:

| file              | what                                                                 |
|-------------------|----------------------------------------------------------------------|
| ``model.zip``     | the trained policy (``PPO.load`` / ``SAC.load``)                     |
| ``config.yaml``   | the scene it was trained on, complete (``load_config`` reads it)     |
| ``run.json``      | algorithm, hyper-parameters, seed, timesteps, wall time              |
| ``evaluations.npz`` | the periodic evaluations (SB3's ``EvalCallback``)                  |
| ``monitor.csv``   | every training episode's reward (SB3's ``Monitor``)                  |
| ``learning_curve.png`` | training reward (rolling mean) and the periodic evaluations     |

``evaluate(DIR)`` runs the deterministic policy on fresh episode seeds and reports the mean and
spread of its reward. Hyper-parameters are the documented defaults below, overridden by name.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace
from typing import Any, Mapping

import numpy as np

from aero_env.config import Config, ConfigError, from_dict, load_config

from .options import check_choice, check_ints

ALGOS = ("ppo", "sac")

# Every step is a whole episode, so there is nothing to discount or bootstrap: gamma is moot and
# small rollouts/batches suit the few thousand (slow) episodes a design study can afford. PPO's
# first designs spread with std e^-1 = 0.37 about the box's centre, as CMA-ES's first population
# does (a third of the box); SB3's default std of 1 would throw a third of them onto the box's faces.
ALGO_DEFAULTS: dict[str, dict[str, Any]] = {
    "ppo": dict(learning_rate=3e-4, n_steps=64, batch_size=64, n_epochs=10, gamma=0.0, gae_lambda=1.0,
                ent_coef=0.0, clip_range=0.2, policy_kwargs=dict(net_arch=[64, 64], log_std_init=-1.0)),
    "sac": dict(learning_rate=3e-4, buffer_size=100_000, learning_starts=100, batch_size=64, gamma=0.0,
                train_freq=1, gradient_steps=1, policy_kwargs=dict(net_arch=[64, 64])),
}
EVAL_EPISODES = 10         # episodes per periodic evaluation
EVAL_SEED_OFFSET = 10_000  # evaluation seeds start here, away from the training envs' seeds


@dataclass(frozen=True)
class TrainSettings:
    algo: str = "ppo"
    timesteps: int = 2000
    n_envs: int = 1
    seed: int = 0
    eval_every: int = 500          # timesteps between periodic evaluations (0: none)
    hyperparameters: Mapping[str, Any] | None = None
    progress: bool = True

    def check(self) -> "TrainSettings":
        check_choice("algo", self.algo, ALGOS)
        check_ints(self, (("timesteps", 1, 10**9), ("n_envs", 1, 256), ("eval_every", 0, 10**9),
                          ("seed", 0, 2**31 - 1)))
        unknown = set(self.hyperparameters or {}) - set(ALGO_DEFAULTS[self.algo])
        if unknown:
            raise ConfigError(f"--hp {sorted(unknown)}: not a {self.algo} hyper-parameter here; allowed: "
                              f"{', '.join(ALGO_DEFAULTS[self.algo])}")
        return self

    def algo_kwargs(self) -> dict[str, Any]:
        return {**ALGO_DEFAULTS[self.algo], **(self.hyperparameters or {})}


def _sb3():
    try:
        import stable_baselines3
        import torch
    except ImportError:
        raise ConfigError("aero-env train needs stable-baselines3 and torch: pip install -e '.[rl]'") from None
    torch.set_num_threads(1)  # the networks are tiny: one thread is fastest and keeps runs bit-identical
    return stable_baselines3


def make_env(cfg_dict: dict, monitor_file: str | None = None):
    """One environment of the scene (module-level, so that worker processes can build it)."""
    from stable_baselines3.common.monitor import Monitor

    from aero_env.envs import AerialAcrobatEnv

    return Monitor(AerialAcrobatEnv(from_dict(cfg_dict)), monitor_file)


def _vec_env(cfg: Config, n_envs: int, seed: int, monitor_dir: Path | None):
    from functools import partial

    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    fns = [partial(make_env, cfg.to_dict(), str(monitor_dir / f"{i}") if monitor_dir else None) for i in range(n_envs)]
    venv = SubprocVecEnv(fns, start_method="spawn") if n_envs > 1 else DummyVecEnv(fns)
    venv.seed(seed)
    return venv


def train(cfg: Config, settings: TrainSettings, out: str | Path) -> dict:
    """Train a policy on ``cfg``'s scene and write the run's directory; returns run.json's content."""
    settings.check()
    sb3 = _sb3()
    from stable_baselines3.common.callbacks import EvalCallback

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "config.yaml").write_text(cfg.to_yaml())
    cls = {"ppo": sb3.PPO, "sac": sb3.SAC}[settings.algo]
    venv = _vec_env(cfg, settings.n_envs, settings.seed, out)
    callbacks = []
    if settings.eval_every:
        eval_env = _vec_env(cfg, 1, settings.seed + EVAL_SEED_OFFSET, None)
        callbacks.append(EvalCallback(eval_env, n_eval_episodes=EVAL_EPISODES, log_path=str(out), verbose=0,
                                      eval_freq=max(1, settings.eval_every // settings.n_envs), warn=False))
    model = cls("MlpPolicy", venv, seed=settings.seed, device="cpu", verbose=0, **settings.algo_kwargs())
    t0 = time.perf_counter()
    model.learn(settings.timesteps, callback=callbacks, progress_bar=settings.progress)
    wall = time.perf_counter() - t0
    model.save(out / "model.zip")
    venv.close()
    run = dict(algo=settings.algo, timesteps=settings.timesteps, n_envs=settings.n_envs, seed=settings.seed,
               eval_every=settings.eval_every, hyperparameters=_jsonable(settings.algo_kwargs()), wall_time=wall,
               episodes_per_second=settings.timesteps / wall)
    (out / "run.json").write_text(json.dumps(run, indent=2))
    plot_learning_curve(out, out / "learning_curve.png")
    return run


def _jsonable(x):
    return json.loads(json.dumps(x, default=str))


def load_run(run_dir: str | Path):
    """The trained model and its scene from a training directory."""
    sb3 = _sb3()
    run_dir = Path(run_dir)
    for name in ("run.json", "model.zip", "config.yaml"):
        if not (run_dir / name).is_file():
            raise ConfigError(f"{run_dir}: no {name}; expected the directory `aero-env train --out DIR` wrote")
    run = json.loads((run_dir / "run.json").read_text())
    cls = {"ppo": sb3.PPO, "sac": sb3.SAC}[run["algo"]]
    return cls.load(run_dir / "model.zip", device="cpu"), load_config(run_dir / "config.yaml"), run


def evaluate(run_dir: str | Path, episodes: int = 20, seed: int = 0, config: Config | None = None) -> dict:
    """The deterministic policy's reward on ``episodes`` episode seeds ``seed, seed+1, ...``."""
    check_ints(SimpleNamespace(episodes=episodes, seed=seed), (("episodes", 1, 10**6), ("seed", 0, 2**31 - 1)))
    from aero_env.envs import AerialAcrobatEnv

    model, trained_on, run = load_run(run_dir)
    env = AerialAcrobatEnv(config or trained_on)
    if env.observation_space != model.observation_space or env.action_space != model.action_space:
        raise ConfigError(f"the scene's spaces ({env.observation_space}, {env.action_space}) are not the policy's "
                          f"({model.observation_space}, {model.action_space})")
    rewards, traversals, outcomes = [], [], []
    for s in range(seed, seed + episodes):
        obs, _ = env.reset(seed=s)
        action, _ = model.predict(obs, deterministic=True)
        _, r, _, _, info = env.step(np.clip(action, -1.0, 1.0))
        rewards.append(float(r))
        traversals.append(int(info["traversals"]))
        outcomes.append(info["outcome"])
    rw = np.array(rewards)
    return dict(algo=run["algo"], episodes=episodes, seeds=[seed, seed + episodes - 1], mean_reward=float(rw.mean()),
                std_reward=float(rw.std()), min_reward=float(rw.min()), max_reward=float(rw.max()),
                full_row=env.config.scene.frames - 1,
                full_row_fraction=float(np.mean(np.array(traversals) >= env.config.scene.frames - 1)),
                outcomes={o: outcomes.count(o) for o in sorted(set(outcomes))}, rewards=rewards)


def plot_learning_curve(run_dir: str | Path, path: str | Path) -> None:
    """Training episodes' reward (rolling mean over 50) and the periodic evaluations (mean ± std)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    run_dir = Path(run_dir)
    fig, ax = plt.subplots(figsize=(7, 4))
    ep = _monitor_rewards(run_dir)
    if len(ep):
        k = min(50, len(ep))
        roll = np.convolve(ep, np.ones(k) / k, mode="valid")
        ax.plot(np.arange(k, len(ep) + 1), roll, color="C0", label=f"training episodes (mean of {k})")
    ev = run_dir / "evaluations.npz"
    if ev.is_file():
        data = np.load(ev)
        m, s = data["results"].mean(axis=1), data["results"].std(axis=1)
        ax.errorbar(data["timesteps"], m, yerr=s, fmt="o-", color="C3", capsize=3,
                    label=f"evaluation ({data['results'].shape[1]} episodes, deterministic)")
    ax.set(xlabel="timesteps (= episodes = designs tried)", ylabel="reward (traversals)", title=run_dir.name)
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _monitor_rewards(run_dir: Path) -> np.ndarray:
    """Every training episode's reward, ordered by its end time across the vector's envs."""
    rows = []
    for f in sorted(run_dir.glob("*.monitor.csv")):
        lines = f.read_text().splitlines()[2:]  # a JSON comment line, then the header r,l,t
        rows += [(float(t), float(r)) for r, _, t in (ln.split(",")[:3] for ln in lines if ln)]
    return np.array([r for _, r in sorted(rows)])
