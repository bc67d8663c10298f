"""RL on the design environment (agents.rl, ``aero-env train`` / ``evaluate``): tiny budgets."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import torch

from aero_env.config import ConfigError, load_config
from stable_baselines3 import PPO

from agents.rl import TrainSettings, evaluate, load_run, make_env, train

from .conftest import PAPER

VARIED_SHORT = {"scene.frames": 3, "context": [{"name": "scene.rise", "low": 0.0, "high": 0.004},
                                               {"name": "design.m2", "low": 0.0065, "high": 0.009}]}


@pytest.fixture(scope="module")
def scene():
    return load_config(PAPER, VARIED_SHORT)


def params(model) -> list[np.ndarray]:
    return [p.detach().cpu().numpy().copy() for p in model.policy.parameters()]


def test_short_ppo_trains_saves_loads_and_evaluates_deterministically(scene, tmp_path):
    settings = TrainSettings(algo="ppo", timesteps=64, seed=1, eval_every=32, progress=False,
                             hyperparameters={"n_steps": 32, "batch_size": 32, "n_epochs": 2})
    run = train(scene, settings, tmp_path / "a")
    assert run["timesteps"] == 64 and run["algo"] == "ppo"
    for name in ("model.zip", "config.yaml", "run.json", "evaluations.npz", "learning_curve.png"):
        assert (tmp_path / "a" / name).is_file(), name
    evals = np.load(tmp_path / "a" / "evaluations.npz")
    assert list(evals["timesteps"]) == [32, 64] and evals["results"].shape == (2, 10)
    # the saved scene is the one trained on, and the model reloads
    model, cfg, _ = load_run(tmp_path / "a")
    assert cfg == scene
    # training changed the policy, and the same seed trains the same policy again
    untrained = params(PPO("MlpPolicy", make_env(scene.to_dict()), seed=1, device="cpu", **settings.algo_kwargs()))
    trained = params(model)
    assert any(not np.array_equal(u, t) for u, t in zip(untrained, trained))
    train(scene, settings, tmp_path / "b")
    again, _, _ = load_run(tmp_path / "b")
    assert all(np.array_equal(t, u) for t, u in zip(trained, params(again)))
    # evaluation: deterministic, over the seeds asked for, and the same for the twin run
    first = evaluate(tmp_path / "a", episodes=6, seed=5)
    assert first == evaluate(tmp_path / "a", episodes=6, seed=5) == evaluate(tmp_path / "b", episodes=6, seed=5)
    assert first["seeds"] == [5, 10] and len(first["rewards"]) == 6
    assert first["mean_reward"] == pytest.approx(np.mean(first["rewards"]))
    assert first["std_reward"] == pytest.approx(np.std(first["rewards"]))
    assert 0 <= first["min_reward"] <= first["max_reward"] <= 2


def test_the_policy_chooses_its_design_from_the_context(scene, tmp_path):
    """A contextual policy: different drawn scenes give different designs (the point of RL here)."""
    train(scene, TrainSettings(algo="ppo", timesteps=32, seed=0, eval_every=0, progress=False,
                               hyperparameters={"n_steps": 32, "batch_size": 32, "n_epochs": 1}), tmp_path)
    model, _, _ = load_run(tmp_path)
    light_flat = model.predict(np.array([-1.0, -1.0], dtype=np.float32), deterministic=True)[0]
    heavy_steep = model.predict(np.array([1.0, 1.0], dtype=np.float32), deterministic=True)[0]
    assert light_flat.shape == (5,) and not np.allclose(light_flat, heavy_steep)


def test_sac_trains_and_evaluates(scene, tmp_path):
    train(scene, TrainSettings(algo="sac", timesteps=48, seed=0, eval_every=0, progress=False,
                               hyperparameters={"learning_starts": 16, "batch_size": 16}), tmp_path)
    rep = evaluate(tmp_path, episodes=3)
    assert rep["algo"] == "sac" and len(rep["rewards"]) == 3 and all(np.isfinite(rep["rewards"]))


@pytest.mark.parametrize("kwargs, words", [
    (dict(algo="dqn"), ["--algo", "'dqn'", "ppo, sac"]),
    (dict(timesteps=0), ["--timesteps", "0"]),
    (dict(n_envs=-1), ["--n-envs", "-1"]),
    (dict(hyperparameters={"n_stepz": 8}), ["n_stepz", "n_steps"]),
])
def test_bad_settings_name_the_option(kwargs, words):
    with pytest.raises(ConfigError) as err:
        TrainSettings(**kwargs).check()
    for w in words:
        assert w in str(err.value)


def test_evaluate_refuses_a_directory_that_is_not_a_run(tmp_path):
    with pytest.raises(ConfigError, match="no run.json"):
        evaluate(tmp_path)


def test_cli_train_two_vector_envs_then_evaluate(tmp_path):
    args = [sys.executable, "-m", "aero_env.cli"]
    done = subprocess.run([*args, "train", str(PAPER), "--set", "scene.frames=3", "--timesteps", "32", "--n-envs",
                           "2", "--eval-every", "16", "--hp", "n_steps=16", "--hp", "batch_size=16",
                           "--out", "run", "--no-progress", "--json"], capture_output=True, text=True, cwd=tmp_path,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    run = json.loads(done.stdout)
    assert run["n_envs"] == 2 and run["hyperparameters"]["n_steps"] == 16
    # both vector envs ran episodes (one monitor file each)
    assert sorted(p.name for p in (tmp_path / "run").glob("*.monitor.csv")) == ["0.monitor.csv", "1.monitor.csv"]
    done = subprocess.run([*args, "evaluate", "run", "--episodes", "3", "--json"], capture_output=True, text=True,
                          cwd=tmp_path, timeout=600)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["episodes"] == 3


def test_torch_is_the_cpu_build():
    assert torch.__version__.startswith("2.13.0") and not torch.cuda.is_available()
