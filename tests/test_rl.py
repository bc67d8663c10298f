"""RL on the design environment (agents.rl, ``aero-env train`` / ``evaluate``): tiny budgets."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys

import numpy as np
import pytest
import torch

from aero_env.config import ConfigError, load_config
from aero_env.envs import AerialAcrobatEnv
from stable_baselines3 import PPO

from agents.rl import TrainSettings, evaluate, load_run, make_env, train

from .conftest import COARSE, PAPER

VARIED_SHORT = {"scene.frames": 3, "context": [{"name": "scene.rise", "low": 0.0, "high": 0.004},
                                               {"name": "design.m2", "low": 0.0065, "high": 0.009}]}


@pytest.fixture(scope="module")
def scene():
    return load_config(PAPER, VARIED_SHORT)


def params(model) -> list[np.ndarray]:
    return [p.detach().cpu().numpy().copy() for p in model.policy.parameters()]


@pytest.mark.slow
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


# A varied scene cut down to one choice that must follow one observation: the robot's mass is drawn
# (6.2-11 g) and observed, the counterbalance is chosen (5-12 g). Measured before writing the test
# (a 1 ms step, 3 frames, m3 swept over 3-15 g by 0.5 g): the whole row needs 6-7.5 g for a 6.2 g robot,
# 7-9.5 g for 7.7 g and 9.5-11.5 g for 11 g, so no single counterbalance suits every draw.
BALANCE = {"scene.frames": 3, **COARSE,
           "tunable": [{"name": "design.m3", "low": 0.005, "high": 0.012}],
           "context": [{"name": "design.m2", "low": 0.0062, "high": 0.011}]}


@pytest.mark.slow
def test_training_makes_the_design_follow_the_context_the_way_that_scores(tmp_path):
    cfg = load_config(PAPER, BALANCE)
    train(cfg, TrainSettings(algo="ppo", timesteps=512, seed=0, eval_every=0, progress=False,
                             hyperparameters={"learning_rate": 3e-3}), tmp_path)
    model, _, _ = load_run(tmp_path)
    env = AerialAcrobatEnv(cfg)
    seeds = range(1000, 1012)  # contexts the policy never trained on

    def run(seed, action=None):
        obs, info = env.reset(seed=seed)
        action = model.predict(obs, deterministic=True)[0] if action is None else action
        return action, info["context"]["design.m2"], env.step(action)

    own = [run(s) for s in seeds]
    actions = [a for a, _, _ in own]
    m2 = np.array([m for _, m, _ in own])
    m3 = np.array([step[4]["design"]["design.m3"] for _, _, step in own])
    # the design follows the robot: a heavier robot gets a heavier counterbalance (an untrained policy's
    # choice moves by about 1e-3 of the range across all contexts)
    slope = np.polyfit(m2, m3, 1)[0]
    assert slope > 0.3, (slope, m2, m3)
    # ... and that direction is what scores: each context with its own design against the design the policy
    # chose for the mirrored context (the lightest robot gets the heaviest's counterbalance, and so on)
    order = np.argsort(m2)
    partner = {order[k]: order[-1 - k] for k in range(len(order))}
    own_reward = sum(step[1] for _, _, step in own)
    swapped_reward = sum(run(s, actions[partner[i]])[2][1] for i, s in enumerate(seeds))
    assert own_reward >= 1.5 * len(seeds) > swapped_reward, (own_reward, swapped_reward)


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


def test_a_sac_model_leaves_the_hyperparameters_it_was_given_as_they_were():
    """SAC adds use_sde to the policy_kwargs it is given: a second SAC run in the process recorded other
    hyper-parameters than the first, and its --resume was refused."""
    from stable_baselines3 import SAC

    settings = TrainSettings(algo="sac", hyperparameters={"batch_size": 4}).check()
    SAC("MlpPolicy", make_env(load_config(PAPER).to_dict()), device="cpu", **settings.algo_kwargs())
    assert settings.algo_kwargs() == dict(learning_rate=3e-4, buffer_size=100_000, learning_starts=100, batch_size=4,
                                          gamma=0.0, train_freq=1, gradient_steps=1,
                                          policy_kwargs=dict(net_arch=[64, 64]))


def test_evaluate_refuses_a_directory_that_is_not_a_run(tmp_path):
    with pytest.raises(ConfigError, match="no run.json"):
        evaluate(tmp_path)


@pytest.mark.slow
def test_cli_train_two_vector_envs_then_evaluate(tmp_path):
    args = [sys.executable, "-m", "aero_env.cli"]
    varied = str(PAPER.parent / "varied.yaml")  # trained on the varied scene: the observation means something
    done = subprocess.run([*args, "train", varied, "--set", "scene.frames=3", "--timesteps", "32", "--n-envs",
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
    # on another scene (8 frames instead of 3, its rise and robot mass drawn as in training), the designs
    # listed per context
    done = subprocess.run([*args, "evaluate", "run", "--episodes", "4", "--config", varied, "--set", "scene.frames=4",
                           "--json"], capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert done.returncode == 0, done.stderr
    rep = json.loads(done.stdout)
    rises = [e["context"]["scene.rise"] for e in rep["per_episode"]]
    assert rep["varied_context"] == ["scene.rise", "design.m2"] and len(set(rises)) == 4
    assert all(0.0 <= r <= 0.004 for r in rises) and all(set(e["design"]) == {
        "design.m3", "design.h", "design.La", "design.spring_k", "design.mu_s", "design.mu_k"} for e in rep["per_episode"])
    table = subprocess.run([*args, "evaluate", "run", "--episodes", "4", "--config", varied, "--set", "scene.frames=4"],
                           capture_output=True, text=True, cwd=tmp_path, timeout=600).stdout.splitlines()
    head = table.index(next(line for line in table if line.startswith("designs chosen per context")))
    assert table[head + 1].split()[:4] == ["seed", "rise", "[mm]", "m2"] and len(table) == head + 2 + 4
    assert float(table[head + 2].split()[1]) == pytest.approx(1e3 * rises[0], rel=1e-3)  # shown in mm
    # a scene that poses another problem (steep.yaml does not tune the friction pair) is refused in one line
    done = subprocess.run([*args, "evaluate", "run", "--config", str(PAPER.parent / "steep.yaml")],
                          capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "its tunable is" in done.stderr, done.stderr
    # the observation is each context value's place in the range trained on: another range is refused, and so is
    # a --set of a field the scene draws at every reset (it would never be used)
    for extra, needle in ((["--config", str(PAPER)], "context scene.rise ranges over [None, None]"),
                          (["--config", varied, "--set", "context=[{name: scene.rise, low: 0, high: 0.008}, "
                                                         "{name: scene.pitch}, {name: design.m2, low: 0.0065, "
                                                         "high: 0.009}]"], "context scene.rise ranges over [0.0, 0.008]"),
                          (["--config", varied, "--set", "scene.rise=4mm"], "--set scene.rise: the scene draws")):
        done = subprocess.run([*args, "evaluate", "run", *extra], capture_output=True, text=True, cwd=tmp_path,
                              timeout=600)
        assert done.returncode == 2 and done.stderr.count("\n") == 1 and needle in done.stderr, done.stderr


def test_the_varied_config_is_the_registered_varied_scene():
    from aero_env.registration import ENVIRONMENTS

    varied = load_config(PAPER.parent / "varied.yaml")
    assert varied == load_config(PAPER, ENVIRONMENTS["aero_env/AerialAcrobatVaried-v0"])
    assert [c.name for c in varied.context if c.low is not None] == ["scene.rise", "design.m2"]


@pytest.mark.slow
def test_rl_zoo_trains_on_the_env_as_it_is(tmp_path):
    # The command docs/agents.md gives, at a tiny budget: the Zoo imports aero_env, makes the registered env
    # and trains on it, with no wrapper or hyper-parameter file of ours
    done = subprocess.run([sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", "aero_env/AerialAcrobat-v0",
                           "--gym-packages", "aero_env", "-n", "64", "--seed", "0", "--log-folder", "logs",
                           "-params", "n_steps:32", "batch_size:32"], capture_output=True, text=True, cwd=tmp_path,
                          timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    run = tmp_path / "logs" / "ppo" / "aero_env-AerialAcrobat-v0_1"
    model = PPO.load(run / "aero_env-AerialAcrobat-v0.zip", device="cpu")
    assert model.action_space.shape == (5,) and model.num_timesteps == 64
    rewards = [float(line.split(",")[0]) for line in (run / "0.monitor.csv").read_text().splitlines()[2:]]
    assert len(rewards) == 64 and all(0 <= r <= 7 for r in rewards)  # one design per episode, scored in traversals


def test_torch_is_the_cpu_build():
    assert torch.__version__.startswith("2.13.0") and not torch.cuda.is_available()


def test_train_through_the_native_vector_env_learns_the_context(tmp_path):
    """--vector: 16 designs per call of the reduced model (one kernel call), trained through the SB3 adapter;
    the policy must learn what the single-env test above asks of it, the counterbalance following the robot."""
    cfg = load_config(PAPER, {**BALANCE, "sim.fidelity": "reduced"})
    run = train(cfg, TrainSettings(algo="ppo", timesteps=2048, n_envs=16, seed=0, eval_every=0, progress=False,
                                   vector=True, hyperparameters={"learning_rate": 3e-3, "n_steps": 16}), tmp_path)
    assert run["vector"] is True and run["timesteps_done"] == 2048
    # one monitor file for the vector env, one row per episode (a design scored)
    lines = (tmp_path / "vector.monitor.csv").read_text().splitlines()
    assert len(lines) == 2 + 2048
    model, _, _ = load_run(tmp_path)
    env = AerialAcrobatEnv(cfg)
    m2, m3 = [], []
    for seed in range(1000, 1012):
        obs, info = env.reset(seed=seed)
        design = env.unwrapped.design_for(model.predict(obs, deterministic=True)[0])
        m2.append(info["context"]["design.m2"])
        m3.append(design["design.m3"])
    slope = np.polyfit(m2, m3, 1)[0]
    assert slope > 0.3, (slope, m2, m3)
    with pytest.raises(ConfigError, match="--vector"):
        train(cfg, TrainSettings(algo="ppo", timesteps=4096, n_envs=16, seed=0, eval_every=0, progress=False,
                                 vector=False, hyperparameters={"learning_rate": 3e-3, "n_steps": 16}), tmp_path,
              resume=True)


def _episode(seed, rise=0.0, m3=0.0072, reward=7.0, outcome="completed"):
    return dict(seed=seed, context={"scene.rise": rise} if rise else {}, design={"design.m3": m3}, reward=reward,
                outcome=outcome)


def test_evaluate_table_of_a_scene_without_context_is_one_row_with_its_count():
    from agents.commands import design_table

    same = design_table(dict(per_episode=[_episode(s) for s in range(20)], varied_context=[]))
    assert same[0] == "the design chosen (the scene draws no context: one design for all 20 episodes):"
    assert len(same) == 3 and same[1].split()[0] == "episodes"
    assert same[2].split() == ["20", "7.2", "7", "completed"]  # 20 episodes, m3 in g, reward, outcome
    # the same design can meet another outcome (tolerances draw the as-built machine): one row per result
    mixed = design_table(dict(per_episode=[_episode(s) for s in range(3)] + [_episode(3, reward=2.0,
                                                                                      outcome="missed_catch")],
                              varied_context=[]))
    assert [ln.split()[0] for ln in mixed[2:]] == ["3", "1"]
    # a drawn context keeps one row per episode, with its seed
    varied = design_table(dict(per_episode=[_episode(s, rise=0.001 * (s + 1)) for s in range(4)],
                               varied_context=["scene.rise"]))
    assert len(varied) == 6 and [ln.split()[0] for ln in varied[2:]] == ["0", "1", "2", "3"]


def test_the_progress_bar_counts_the_whole_rollouts_ppo_takes(tmp_path, monkeypatch, capsys):
    # PPO learns in whole rollouts (n_steps x n_envs): 40 steps asked, 48 taken; the bar must count to 48, not "48/40"
    from stable_baselines3.common import callbacks as sb3_callbacks

    from agents.rl import progress_plan

    bars = []

    class Bar:
        def __init__(self, total, desc):
            self.total, self.desc, self.n = total, desc, 0
            bars.append(self)

        def update(self, n):
            self.n += n

        def refresh(self):
            pass

        def close(self):
            pass

    monkeypatch.setattr(sb3_callbacks, "tqdm", Bar)
    settings = TrainSettings(algo="ppo", timesteps=40, seed=0, eval_every=0, progress=True,
                             hyperparameters={"n_steps": 16, "batch_size": 16}).check()
    cfg = load_config(PAPER, {"scene.frames": 2, **COARSE})
    run = train(cfg, settings, tmp_path)
    assert run["timesteps_done"] == 48 and progress_plan(settings, 40)[0] == 48
    (bar,) = bars
    assert bar.total == bar.n == 48 and bar.desc == "steps (16 a round)"
    assert "PPO trains in whole rollouts of n_steps x n_envs = 16 x 1 = 16 steps: 40 steps to go become 48" in \
        capsys.readouterr().err
    assert progress_plan(settings, 48)[2] is None  # a budget of whole rollouts needs no word


def test_a_policy_runs_the_reduced_models_batches_on_one_thread_unless_numba_is_told(monkeypatch):
    """numba's OpenMP workers spin between a training run's small batches and take a busy machine's cores
    (issue 36): training and evaluation use one thread, and NUMBA_NUM_THREADS, where set, wins."""
    import numba

    from agents.rl import _sb3

    cores = numba.config.NUMBA_NUM_THREADS
    before = numba.get_num_threads()
    try:
        monkeypatch.delenv("NUMBA_NUM_THREADS", raising=False)
        numba.set_num_threads(cores)
        _sb3()
        assert numba.get_num_threads() == 1
        monkeypatch.setenv("NUMBA_NUM_THREADS", str(cores))
        numba.set_num_threads(cores)
        _sb3()
        assert numba.get_num_threads() == cores
    finally:
        numba.set_num_threads(before)


def test_training_at_reduced_says_what_it_risks_and_how_to_check_it(tmp_path, capsys):
    """At sim.fidelity reduced, aero-env train says in one line that a policy can learn the fast model's errors,
    and the check it names runs: the same policy scored at mbd. At mbd it says nothing of the kind."""
    from aero_env import cli

    base = ["train", str(PAPER.parent / "varied.yaml"), "--set", "scene.frames=3", "--timesteps", "32", "--n-envs",
            "16", "--vector", "--eval-every", "0", "--hp", "n_steps=2", "--hp", "batch_size=16", "--no-progress"]
    assert cli.main([*base, "--set", "sim.fidelity=reduced", "--out", str(tmp_path / "fast")]) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "sim.fidelity = reduced" in err and "a policy can learn to pick them" in err
    check = err.split("score it where it will be used: ")[1].split("; finish it there")[0].split()
    assert check == ["aero-env", "evaluate", str(tmp_path / "fast"), "--set", "sim.fidelity=mbd"]
    assert f"with --init-from {tmp_path / 'fast'}, a new --out" in err
    assert cli.main([*check[1:], "--episodes", "2", "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert (rep["fidelity"], rep["trained_at"]) == ("mbd", "reduced")
    plain = [a for a in base if a != "--vector"]  # in this process: no pool at a pymunk fidelity
    plain[plain.index("--n-envs") + 1] = "1"
    plain[plain.index("n_steps=2")] = "n_steps=16"
    # the finish it names (the same command at mbd, from the fast run) runs, and says nothing of the kind
    assert cli.main([*plain, "--set", "sim.fidelity=mbd", "--init-from", str(tmp_path / "fast"), "--out",
                     str(tmp_path / "world")]) == 0, capsys.readouterr().err
    assert "reduced" not in capsys.readouterr().err
    assert json.loads((tmp_path / "world" / "run.json").read_text())["init_from"]["fidelity"] == "reduced"


def test_init_from_starts_a_run_at_mbd_from_a_policy_pretrained_at_reduced(tmp_path, capsys):
    """--init-from: the multi-fidelity recipe. The new run at mbd starts from the pretrained run's weights and
    optimiser state (seen by a callback before the first update), with its own seed and settings, the same way
    twice, and records where it started; the command that started it resumes it; a start that cannot name the
    same designs is refused in one line before any work."""
    from stable_baselines3.common.callbacks import BaseCallback

    varied = load_config(PAPER.parent / "varied.yaml", {"scene.frames": 3})
    hp = {"n_steps": 16, "batch_size": 16, "n_epochs": 1}
    fast = varied.replace({"sim.fidelity": "reduced"})
    pre = train(fast, TrainSettings(algo="ppo", timesteps=64, n_envs=16, seed=3, eval_every=0, vector=True,
                                    progress=False, hyperparameters={**hp, "n_steps": 4}), tmp_path / "pre")
    pretrained_model = load_run(tmp_path / "pre")[0]
    pretrained = params(pretrained_model)
    moments = [v["exp_avg"].numpy().copy() for v in pretrained_model.policy.optimizer.state_dict()["state"].values()]
    fresh = params(PPO("MlpPolicy", make_env(varied.to_dict()), seed=5, device="cpu",
                       **TrainSettings(hyperparameters=hp).algo_kwargs()))
    seen = []

    class AtStart(BaseCallback):
        def _on_training_start(self) -> None:
            state = self.model.policy.optimizer.state_dict()["state"]
            seen.append((params(self.model), [v["exp_avg"].numpy().copy() for v in state.values()]))

        def _on_step(self) -> bool:
            return True

    settings = TrainSettings(algo="ppo", timesteps=16, n_envs=1, seed=5, eval_every=0, progress=False,
                             hyperparameters=hp)
    run = train(varied, settings, tmp_path / "finish", callbacks=[AtStart()], init_from=tmp_path / "pre")
    weights, adam = seen[0]
    assert all(np.array_equal(a, b) for a, b in zip(weights, pretrained))
    assert any(not np.array_equal(a, b) for a, b in zip(weights, fresh))
    assert len(adam) == len(moments) > 0 and all(np.array_equal(a, b) for a, b in zip(adam, moments))
    assert run["init_from"]["fidelity"] == "reduced" and run["init_from"]["timesteps_done"] == pre["timesteps_done"]
    assert json.loads((tmp_path / "finish" / "run.json").read_text())["init_from"] == run["init_from"]
    assert run["timesteps_done"] == 16 and load_run(tmp_path / "finish")[1].sim.fidelity == "mbd"
    train(varied, settings, tmp_path / "twin", init_from=tmp_path / "pre")  # the same start and seed: the same run
    finished = params(load_run(tmp_path / "finish")[0])
    assert all(np.array_equal(a, b) for a, b in zip(finished, params(load_run(tmp_path / "twin")[0])))
    assert any(not np.array_equal(a, b) for a, b in zip(finished, pretrained))
    # the command that started it resumes it, and keeps the record; another start is refused
    more = dataclasses.replace(settings, timesteps=32)
    assert train(varied, more, tmp_path / "twin", resume=True, init_from=tmp_path / "pre")["init_from"] == \
        run["init_from"]
    with pytest.raises(ConfigError, match="started from"):
        train(varied, dataclasses.replace(settings, timesteps=48), tmp_path / "twin", resume=True,
              init_from=tmp_path / "finish")
    # refused before any work, naming the option: SAC, another scene (the action's scale, the row), its own folder,
    # not a run
    tunable = varied.to_dict()["tunable"]
    logged = next(i for i, t in enumerate(tunable) if t.get("scale") == "log")
    tunable[logged] = dict(tunable[logged], scale="linear")
    bad = [(dict(algo="sac"), {}, tmp_path / "pre", "allowed with --algo ppo only"),
           ({}, {"tunable": tunable}, tmp_path / "pre", "(tunable differs; only sim.fidelity may)"),
           ({}, {"scene.frames": 4}, tmp_path / "pre", "(scene.frames differs; only sim.fidelity may)"),
           ({}, {}, tmp_path / "no-such-run", "no run.json, model.zip, config.yaml there")]
    for change, override, start, words in bad:
        cfg = varied.replace(override) if override else varied
        with pytest.raises(ConfigError, match="--init-from") as e:
            train(cfg, TrainSettings(**{**dict(algo="ppo", timesteps=16, eval_every=0, progress=False), **change}),
                  tmp_path / "refused", init_from=start)
        assert words in str(e.value) and "\n" not in str(e.value)
        assert not (tmp_path / "refused").exists()
    kept = (tmp_path / "pre" / "run.json").read_text()
    with pytest.raises(ConfigError, match="own --out"):
        train(varied, settings, tmp_path / "pre", overwrite=True, init_from=tmp_path / "pre")
    assert (tmp_path / "pre" / "run.json").read_text() == kept
    assert all(np.array_equal(a, b) for a, b in zip(params(load_run(tmp_path / "pre")[0]), pretrained))
    from aero_env import cli

    line = ["train", str(PAPER.parent / "varied.yaml"), "--set", "scene.frames=3", "--timesteps", "16", "--eval-every",
            "0", "--hp", "n_steps=16", "--hp", "batch_size=16", "--hp", "n_epochs=1", "--no-progress"]
    capsys.readouterr()
    assert cli.main([*line, "--init-from", str(tmp_path / "finish" / "x"), "--out", str(tmp_path / "c")]) != 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--init-from" in err and "Traceback" not in err and not (tmp_path / "c").exists()
    assert cli.main([*line, "--init-from", str(tmp_path / "pre"), "--out", str(tmp_path / "cli")]) == 0
    assert f"from the policy in {tmp_path / 'pre'} (64 steps at reduced)" in capsys.readouterr().out
    assert json.loads((tmp_path / "cli" / "run.json").read_text())["init_from"]["dir"] == str(tmp_path / "pre")
