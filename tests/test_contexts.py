"""The maker's contexts (configs/contexts.yaml): a linked context, the stored single design, a policy against it."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from aero_env.config import ConfigError, load_config
from aero_env.design_space import DesignSpace
from aero_env.envs import AerialAcrobatEnv
from aero_env.registration import ENVIRONMENTS
from agents.rl import TrainSettings, evaluate, train

from .conftest import PAPER, benchmark_module

CONTEXTS = PAPER.parent / "contexts.yaml"
SINGLE = PAPER.parent / "contexts_single.yaml"
HARD = PAPER.parent / "contexts_hard.yaml"
ROOT = PAPER.parent.parent


def test_the_contexts_config_is_the_registered_scene():
    cfg = load_config(CONTEXTS)
    assert cfg == load_config(None, ENVIRONMENTS["aero_env/AerialAcrobatContexts-v0"])
    assert [c.name for c in cfg.context] == ["scene.rise", "scene.pitch", "design.m2", "design.mu_s"]
    assert "design.Lb" in [t.name for t in cfg.tunable] and "design.mu_s" not in [t.name for t in cfg.tunable]


def test_the_hard_config_is_the_registered_hard_scene():
    """The hard task is the maker's contexts widened, with the same choices and cutting error, on the 8-frame row: the
    numbers its docs and header state."""
    hard, cfg = load_config(HARD), load_config(CONTEXTS)
    assert hard == load_config(None, ENVIRONMENTS["aero_env/AerialAcrobatContexts-Hard-v0"])
    assert hard.scene.frames == 8
    assert [(c.name, c.low, c.high) for c in hard.context] == [
        ("scene.rise", -0.006, 0.014), ("scene.pitch", 0.064, 0.094), ("design.m2", 0.0065, 0.012),
        ("design.mu_s", 0.283, 0.542)]
    assert hard.tunable == cfg.tunable and hard.tolerance == cfg.tolerance
    for wide, narrow in zip(hard.context, cfg.context):  # every range of the maker's contexts lies inside
        assert wide.name == narrow.name and wide.low <= narrow.low and narrow.high <= wide.high


def test_a_linked_context_moves_its_follower_by_the_same_factor():
    cfg = load_config(CONTEXTS)
    paper = load_config(PAPER)
    space = DesignSpace(cfg)
    env = AerialAcrobatEnv(cfg)
    for seed in range(5):
        _, info = env.reset(seed=seed)
        mu_s = info["context"]["design.mu_s"]
        values, _ = space.episode_values(space.values(np.zeros(space.dim)), space.draw_for_seed(seed))
        # the white/gray pair's ratio, from the paper's config, not from the code that applies it
        assert values["design.mu_k"] == pytest.approx(mu_s * paper.design.mu_k / paper.design.mu_s, rel=1e-12)
    # the simulated config carries it: gray/gray's mu_s with white/gray's mu_k would be another card
    built, _ = space.episode_config(space.values(np.zeros(space.dim)), space.draw_for_seed(0))
    assert built.design.mu_k / built.design.mu_s == pytest.approx(0.409 / 0.542)


def _links_below_the_base_mu_k(paper, contexts):
    """How many of ``contexts`` (each a drawn context dict) have mu_s below the base config's mu_k: with the link
    dropped, such an episode would keep mu_k above its mu_s, a friction pair the model refuses."""
    return sum(c["design.mu_s"] < paper.design.mu_k for c in contexts)


def test_the_arrays_give_each_episode_what_its_own_values_give_on_a_linked_context():
    """DesignSpace.episode_columns (the vector env's arrays) against episode_values (the single env's, one episode at a
    time), episode by episode and field by field, bit for bit, on the maker's contexts: mu_k follows the drawn mu_s."""
    cfg, paper = load_config(CONTEXTS), load_config(PAPER)
    space = DesignSpace(cfg)
    draws = [space.draw_for_seed(s) for s in range(12)]
    actions = np.random.default_rng(5).uniform(-1.0, 1.0, (len(draws), space.dim))
    columns, built = space.episode_columns(space.values_columns(actions), draws)
    assert _links_below_the_base_mu_k(paper, [d.context for d in draws]) >= 2  # a sample a dropped link shows on
    for i, draw in enumerate(draws):
        values, built_i = space.episode_values(space.values(actions[i]), draw)
        assert sorted(columns) == sorted(values) and sorted(built) == sorted(built_i)
        for key, v in values.items():
            assert columns[key][i] == v and str(columns[key][i]) == str(v), (i, key, columns[key][i], v)
        for key, v in built_i.items():
            assert built[key][i] == v, (i, key)
        # the link, from the paper's ratio rather than the code that applies it
        assert columns["design.mu_k"][i] == pytest.approx(draw.context["design.mu_s"] * paper.design.mu_k
                                                          / paper.design.mu_s, rel=1e-12)


def test_the_contexts_scene_at_reduced_steps_through_the_arrays_and_equals_the_per_episode_path(monkeypatch):
    """The registered contexts scene at sim.fidelity reduced: a step goes from the actions to the model in arrays
    (AerialAcrobatVectorEnv._run_columns), never falling back to the per-episode path, even with episodes whose
    drawn mu_s is below the base mu_k; and what it gives equals the per-episode path on the same episodes."""
    import gymnasium as gym

    from aero_env.envs import AerialAcrobatVectorEnv

    from .test_vector_env import _same

    paper = load_config(PAPER)
    envs = gym.make_vec("aero_env/AerialAcrobatContexts-v0", num_envs=8, vectorization_mode="vector_entry_point",
                        **{"sim.fidelity": "reduced"})
    try:
        env = envs.unwrapped if hasattr(envs, "unwrapped") else envs
        assert isinstance(env, AerialAcrobatVectorEnv) and env.reduced
        _, info = envs.reset(seed=11)
        contexts = [{k: v[i] for k, v in info["context"].items() if not k.startswith("_")} for i in range(8)]
        assert _links_below_the_base_mu_k(paper, contexts) >= 2  # the episodes a dropped link would send elsewhere
        # action seed 4: the first of seeds 0-29 whose rewards here take more than one value (0 and 1 traversals; seed
        # 0, the earlier pick, took 0 and 4 until a slide's rate reaching zero came to rest in the model, and now
        # leaves all eight at 0; seed 2 before it)
        actions = np.random.default_rng(4).uniform(-1.0, 1.0, (8, env.space.dim)).astype(np.float32)
        expected_rewards, expected_info = env._run_episodes(env._plan(actions))  # the per-episode path, same draws
        took = []
        run_columns = AerialAcrobatVectorEnv._run_columns

        def arrays(self, a):
            out = run_columns(self, a)
            took.append(out is not None)
            return out

        def per_episode(self, episodes):
            raise AssertionError("the step fell back to the per-episode path")

        monkeypatch.setattr(AerialAcrobatVectorEnv, "_run_columns", arrays)
        monkeypatch.setattr(AerialAcrobatVectorEnv, "_run_episodes", per_episode)
        _, rewards, _, _, step_info = envs.step(actions)
    finally:
        envs.close()
    assert took == [True]
    _same(rewards, expected_rewards, "rewards")
    _same(step_info["final_info"], expected_info, "final_info")
    assert len(set(rewards.tolist())) > 1, rewards  # a sample the comparison can fail on


@pytest.mark.parametrize("context, match", [
    ([{"name": "design.mu_s", "low": 0.3, "high": 0.5, "linked": ["design.m3"]}],
     r"context\[0\].linked: 'design.m3' is itself tunable or context"),
    ([{"name": "design.mu_s", "low": 0.3, "high": 0.5, "linked": "design.mu_k"}],
     r"context\[0\].linked = 'design.mu_k': must be a list"),
    ([{"name": "design.mu_s", "low": 0.3, "high": 0.5, "linked": ["design.mu_s"]}],
     r"context\[0\].linked\[0\] = 'design.mu_s': a field cannot be linked to itself"),
])
def test_a_bad_context_link_is_one_line_naming_it(context, match):
    tunable = [{"name": "design.m3", "low": 0.5, "high": 1.6, "relative_to": "design.m2"}]
    with pytest.raises(ConfigError, match=match):
        load_config(PAPER, {"context": context, "tunable": tunable})


def test_a_context_that_names_a_field_a_tunable_links_is_refused_at_the_context():
    # the default tunables link design.mu_k to the card pair; a context naming mu_k is the entry in the wrong, and the
    # line starts with it (found by tests/test_properties.py's random sections)
    with pytest.raises(ConfigError, match=r"^context\[0\].name = 'design.mu_k': tunable\[4\] links it to design.mu_s"):
        load_config(PAPER, {"context": [{"name": "design.mu_k"}]})


def test_a_context_link_and_a_tunable_link_cannot_share_a_follower():
    with pytest.raises(ConfigError, match=r"context\[0\].linked: 'design.mu_k' already follows design.m3"):
        load_config(PAPER, {"tunable": [{"name": "design.m3", "low": 0.004, "high": 0.01, "linked": ["design.mu_k"]}],
                            "context": [{"name": "design.mu_s", "low": 0.3, "high": 0.5, "linked": ["design.mu_k"]}]})


def _played(cfg, action, seeds) -> list[int]:
    env = AerialAcrobatEnv(cfg)
    out = []
    for s in seeds:
        env.reset(seed=s)
        out.append(env.step(action)[4]["traversals"])
    return out


@pytest.mark.slow
def test_the_stored_single_design_is_one_design_for_the_scene_and_covers_few_contexts():
    """No single design suits the maker's contexts: the stored best single design of a robust tune completes
    the row on at most 60 % of fresh contexts (here 200 of them, away from every seed the tune used)."""
    from aero_env.design_space import changes_outside_tunables

    cfg, single = load_config(CONTEXTS), load_config(SINGLE)
    drawn = {"scene.rise", "scene.pitch", "design.m2", "design.mu_s", "design.mu_k"}
    assert [k for k in changes_outside_tunables(cfg, single) if k not in drawn] == []
    space = DesignSpace(cfg)
    action = space.action_for({t.name: single.value(t.name) for t in space.tunables}, dtype=np.float64)
    traversals = _played(cfg, action, range(3_000_000, 3_000_200))
    share = np.mean(np.array(traversals) >= cfg.scene.frames - 1)
    assert 0.1 <= share <= 0.6, share  # it works somewhere (a real design), and not on most contexts


@pytest.mark.slow
def test_evaluate_against_a_design_plays_it_on_the_same_episodes(tmp_path):
    cfg = load_config(CONTEXTS, {"scene.frames": 3})
    train(cfg, TrainSettings(algo="ppo", timesteps=16, seed=0, eval_every=0, progress=False,
                             hyperparameters={"n_steps": 16, "batch_size": 16, "n_epochs": 1}), tmp_path / "run")
    single = load_config(SINGLE)  # a 5-frame file: only its design is played, on the 3-frame scene
    rep = evaluate(tmp_path / "run", episodes=6, seed=40, against=single)
    space = DesignSpace(cfg)
    action = space.action_for({t.name: single.value(t.name) for t in space.tunables}, dtype=np.float64)
    traversals = _played(cfg, action, range(40, 46))
    assert rep["against"]["rewards"] == [float(t) for t in traversals]
    assert rep["against"]["full_row_fraction"] == pytest.approx(np.mean(np.array(traversals) >= 2))
    # the CLI says it in one more line, and refuses a design for another scene in one line
    args = [sys.executable, "-m", "aero_env.cli", "evaluate", str(tmp_path / "run"), "--episodes", "6", "--seed",
            "40"]
    done = subprocess.run([*args, "--against", str(SINGLE)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    line = next(ln for ln in done.stdout.splitlines() if ln.startswith("against"))
    assert f"whole row in {100 * rep['against']['full_row_fraction']:.0f} %" in line and "the policy" in line
    done = subprocess.run([*args, "--against", str(PAPER.parent / "scenes" / "solutions" / "six_coins.yaml")],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "outside its tunables (design.coin_mass)" in done.stderr, \
        done.stderr


def test_a_policys_action_for_a_context_does_not_depend_on_the_contexts_asked_with_it():
    """agents.rl.policy_actions, the one inference path of aero-env evaluate and the benchmark: row by row, so a
    context's design is the same asked alone or among others (a batch of 64 gives other round-off on this
    machine's torch kernels; not asserted, as another processor's kernels may not)."""
    from agents.rl import load_run, policy_actions

    cfg = load_config(CONTEXTS)
    env = AerialAcrobatEnv(cfg)
    obs = np.array([env.reset(seed=s)[0] for s in range(4_000_000, 4_000_064)])
    model, _, _ = load_run(ROOT / "policies" / "contexts" / "ppo" / "seed0")
    rows = policy_actions(model, obs)
    assert rows.shape == (64, env.action_space.shape[0])
    for k in (0, 17, 63):
        assert np.array_equal(rows[k], policy_actions(model, obs[k:k + 1])[0])
        assert np.array_equal(rows[k], model.predict(obs[k], deterministic=True)[0])


@pytest.mark.slow
def test_rl_vs_tuning_rescores_the_shipped_policies_on_the_holdout_contexts_it_names():
    """Without training: each row is its designs played on the hold-out seeds it names, checked here through the
    env itself (the prototype, the single design, each shipped PPO seed), as a matrix of outcomes whose mean lies
    inside its interval, and every pair's difference."""
    from agents.rl import load_run

    args = [sys.executable, "benchmarks/rl_vs_tuning.py", "--holdout", "6", "--holdout-seed", "3", "--json",
            "--seeds", "0-1", "--methods", "prototype,single,linear-map,ppo,ppo-reduced,oracle"]
    done = subprocess.run(args, capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr
    rep = json.loads(done.stdout)
    by = {r["method"]: r for r in rep["rows"]}
    assert list(by) == ["prototype", "single", "linear-map", "ppo", "ppo-reduced", "oracle"]
    cfg, single = load_config(CONTEXTS), load_config(SINGLE)
    space = DesignSpace(cfg)
    seeds = range(4_000_000, 4_000_006)
    assert by["prototype"]["mean_traversals"] == pytest.approx(np.mean(_played(cfg, space.action_for(), seeds)))
    kept = _played(cfg, space.action_for({t.name: single.value(t.name) for t in space.tunables}), seeds)
    assert by["single"]["mean_traversals"] == pytest.approx(np.mean(kept))
    assert by["single"]["episodes"] == 1200 * 32 and by["ppo"]["seeds"] == 2 and by["ppo"]["trained_at"] == "mbd"
    env = AerialAcrobatEnv(cfg)
    obs = np.array([env.reset(seed=s)[0] for s in seeds])
    per_seed = []
    for k in (0, 1):
        model, _, _ = load_run(ROOT / "policies" / "contexts" / "ppo" / f"seed{k}")
        actions = [model.predict(o, deterministic=True)[0] for o in obs]  # one at a time, as aero-env evaluate asks
        whole = []
        for s, a in zip(seeds, actions):
            env.reset(seed=s)
            whole.append(env.step(a)[4]["traversals"] >= 4)
        assert by["ppo"]["per_seed"][k] == pytest.approx(np.mean(whole))
        per_seed.append(whole)
    # the outcome matrix is those whole rows, seed by seed; the mean is its mean, inside its interval, inside [0, 1]
    assert by["ppo"]["outcomes"] == [[int(w) for w in whole] for whole in per_seed]
    for row in by.values():
        lo, hi = row["ci"]
        assert row["mean"] == np.mean(row["outcomes"]) and 0.0 <= lo <= row["mean"] <= hi <= 1.0, row["method"]
        assert np.shape(row["outcomes"]) == (row["seeds"], 6), row["method"]
    # every pair's difference, a listed before b, is the difference of their means
    pairs = {(d["a"], d["b"]): d for d in rep["differences"]}
    assert len(pairs) == 15 and ("single", "ppo") in pairs
    for (a, b), d in pairs.items():
        assert d["diff"] == pytest.approx(by[a]["mean"] - by[b]["mean"], abs=1e-12)
        assert d["ci"][0] <= d["diff"] <= d["ci"][1] and d["apart"] == (d["ci"][0] > 0 or d["ci"][1] < 0)
    # the search starts from the single design and keeps only what beats it, on these very episodes
    assert by["oracle"]["mean"] >= by["single"]["mean"] and by["oracle"]["solved"] == round(6 * by["oracle"]["mean"])
    bad = subprocess.run([sys.executable, "benchmarks/rl_vs_tuning.py", "--holdout", "0"], capture_output=True,
                         text=True, cwd=ROOT, timeout=600)
    assert bad.returncode != 0 and bad.stderr.strip() == "rl_vs_tuning: --holdout = 0: must be at least 1"
    bad = subprocess.run([sys.executable, "benchmarks/rl_vs_tuning.py", "--policies", "nowhere", "--methods", "ppo"],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert bad.returncode != 0 and bad.stderr.strip() == "rl_vs_tuning: --policies nowhere: no seed of ppo among " \
        "--seeds 0-9"
    bad = subprocess.run([sys.executable, "benchmarks/rl_vs_tuning.py", "--policies", "nowhere", "--methods", "ppo",
                          "--seeds", "1"], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert bad.returncode != 0 and bad.stderr.count("\n") == 1 and "no nowhere/ppo/seed1;" in bad.stderr


@pytest.mark.slow
def test_rl_vs_tuning_retrains_every_kind_of_method_into_a_folder(tmp_path):
    """--retrain with tiny budgets: each method writes its files where it is scored from, the RL curve ends on the
    policy that was scored, and a policy aero-env train wrote scores as its own row."""
    args = [sys.executable, "benchmarks/rl_vs_tuning.py", "--holdout", "6", "--holdout-seed", "3", "--json",
            "--retrain", "--policies", str(tmp_path / "p"), "--seeds", "0", "--no-flips",
            "--methods", "linear-map,nearest-neighbour,ppo,ppo-reduced,ppo-multifidelity", "--timesteps", "64",
            "--finish-episodes", "32", "--map-episodes", "1500",
            "--nn-contexts", "3", "--watch", "4", "--curve-every", "32"]
    done = subprocess.run(args, capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr
    rep = json.loads(done.stdout)
    assert [r["method"] for r in rep["rows"]] == ["linear-map", "nearest-neighbour", "ppo", "ppo-reduced",
                                                  "ppo-multifidelity"]
    assert (tmp_path / "p" / "ppo" / "seed0" / "model.zip").is_file()
    for m in ("linear-map", "nearest-neighbour"):
        rec = json.loads((tmp_path / "p" / m / "seed0" / "policy.json").read_text())
        assert rec["command"].startswith(f"python benchmarks/rl_policies.py --methods {m}")
    by = {r["method"]: r for r in rep["rows"]}
    assert by["linear-map"]["episodes"] <= 1500 and by["linear-map"]["trained_at"] == "reduced"
    run = json.loads((tmp_path / "p" / "ppo" / "seed0" / "run.json").read_text())
    assert run["command"].startswith("aero-env train configs/contexts.yaml --algo ppo --timesteps 64")
    # the recipe finishes at mbd the ppo-reduced policy of its seed, and counts both stages
    pre = json.loads((tmp_path / "p" / "ppo-reduced" / "seed0" / "run.json").read_text())
    fin = json.loads((tmp_path / "p" / "ppo-multifidelity" / "seed0" / "run.json").read_text())
    assert fin["init_from"]["dir"] == str(tmp_path / "p" / "ppo-reduced" / "seed0")
    assert fin["init_from"]["fidelity"] == "reduced"
    assert f"--init-from {tmp_path / 'p' / 'ppo-reduced' / 'seed0'} " in fin["command"]
    mf = by["ppo-multifidelity"]
    assert mf["episodes"] == pre["timesteps_done"] + fin["timesteps_done"] and mf["trained_at"].startswith("reduced")
    assert mf["wall_s"] == pytest.approx(pre["wall_time"] + fin["wall_time"])
    assert rep["recipe"]["wall_ratio"] == pytest.approx((pre["wall_time"] + fin["wall_time"]) / run["wall_time"])
    curve = rep["curves"]["ppo"][0]
    assert len(curve) >= 2 and curve[-1]["episodes"] == by["ppo"]["episodes"] == run["timesteps_done"]
    assert {f["design"] for f in rep["design_follows"]} == {t.name for t in load_config(CONTEXTS).tunable}
    again = subprocess.run([sys.executable, "benchmarks/rl_vs_tuning.py", "--holdout", "6", "--holdout-seed", "3",
                            "--json", "--no-flips", "--methods", "single", "--policy",
                            str(tmp_path / "p" / "ppo" / "seed0")], capture_output=True, text=True, cwd=ROOT,
                           timeout=600)
    assert again.returncode == 0, again.stderr
    mine = {r["method"]: r for r in json.loads(again.stdout)["rows"]}["policy"]
    assert mine["mean_traversals"] == by["ppo"]["mean_traversals"] and mine["episodes"] == by["ppo"]["episodes"]
    for argv, line in ((["--methods", "dqn"], "rl_policies: --methods 'dqn': allowed ppo, ppo-reduced, sac, "
                                              "ppo-multifidelity, linear-map, mlp-map, nearest-neighbour"),
                       (["--methods", "ppo-multifidelity", "--seeds", "0", "--out", str(tmp_path / "none")],
                        f"rl_policies: ppo-multifidelity seed 0 starts from {tmp_path / 'none' / 'ppo-reduced' / 'seed0'}, "
                        f"which holds no policy; train it first (--methods ppo-reduced,ppo-multifidelity)"),
                       (["--seeds", "two"], "rl_policies: --seeds 'two': give seeds (0 or more) as 0-4 or 0,2,5"),
                       (["--map-episodes", "0"], "rl_policies: --map-episodes = 0: must be at least 1")):
        bad = subprocess.run([sys.executable, "benchmarks/rl_policies.py", *argv], capture_output=True, text=True,
                             cwd=ROOT, timeout=600)
        assert bad.returncode != 0 and bad.stderr.strip() == line and not bad.stdout
    # a pretraining trained again after the finish that started from it: the pair is refused, not mixed
    done = subprocess.run([sys.executable, "benchmarks/rl_policies.py", "--methods", "ppo-reduced", "--seeds", "0",
                           "--timesteps", "2048", "--curve-every", "0", "--out", str(tmp_path / "p")],
                          capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr
    stale = subprocess.run([sys.executable, "benchmarks/rl_vs_tuning.py", "--holdout", "2", "--no-flips", "--methods",
                            "ppo-multifidelity", "--policies", str(tmp_path / "p"), "--seeds", "0"],
                           capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert stale.returncode != 0 and stale.stderr.count("\n") == 1, stale.stderr
    assert stale.stderr.startswith(f"rl_vs_tuning: {tmp_path / 'p' / 'ppo-multifidelity' / 'seed0'} was finished "
                                   f"from another ppo-reduced policy"), stale.stderr


@pytest.mark.slow
def test_rl_vs_tuning_scores_the_hard_task_on_its_own_scene_and_its_oracle_makes_every_row_a_method_made():
    """--task hard re-scores the maps shipped for the hard task on the hard scene (checked through the registered
    id itself), and its oracle, which starts each context from the best design a method chose for it, makes every
    whole row any seed of any method made there."""
    import gymnasium as gym

    args = [sys.executable, "benchmarks/rl_vs_tuning.py", "--task", "hard", "--holdout", "5", "--holdout-seed", "3",
            "--json", "--seeds", "0-1", "--no-flips", "--methods", "prototype,linear-map,nearest-neighbour,oracle"]
    done = subprocess.run(args, capture_output=True, text=True, cwd=ROOT, timeout=900)
    assert done.returncode == 0, done.stderr
    rep = json.loads(done.stdout)
    assert (rep["task"], rep["scene"], rep["config"], rep["frames"]) == (
        "hard", "aero_env/AerialAcrobatContexts-Hard-v0", "configs/contexts_hard.yaml", 8)
    by = {r["method"]: r for r in rep["rows"]}
    env = gym.make("aero_env/AerialAcrobatContexts-Hard-v0")
    seeds = range(4_000_000, 4_000_005)
    played = []
    for s in seeds:
        env.reset(seed=s)
        played.append(env.step(env.unwrapped.space.action_for())[4]["traversals"])
    assert by["prototype"]["mean_traversals"] == pytest.approx(np.mean(played))
    assert by["prototype"]["outcomes"] == [[int(t >= 7) for t in played]]
    made = np.zeros(5, bool)
    for m in ("linear-map", "nearest-neighbour"):
        assert np.shape(by[m]["outcomes"]) == (2, 5) and by[m]["trained_at"] in ("reduced", "mbd")
        made |= np.array(by[m]["outcomes"], bool).any(axis=0)
    oracle = np.array(by["oracle"]["outcomes"][0], bool)
    assert (oracle >= made).all() and by["oracle"]["solved"] == oracle.sum()
    assert made.any() and all(by["oracle"]["evaluations"][i] == 1 for i in np.flatnonzero(made))  # its first try
    assert sum(by["oracle"]["evaluations"]) == by["oracle"]["episodes"]
    bad = subprocess.run([sys.executable, "benchmarks/rl_vs_tuning.py", "--task", "hard", "--methods", "single"],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert bad.returncode != 0 and bad.stderr.strip() == ("rl_vs_tuning: --methods single: the hard task has no "
                                                          "stored single design; leave it out")


def test_the_beyond_range_scene_is_the_makers_scene_with_the_hard_tasks_context_ranges():
    """benchmarks/beyond_range.py scores the maker's policies on their own 5-frame scene, choices and cutting error,
    with only the contexts' ranges widened to the hard task's."""
    import dataclasses

    beyond_range = benchmark_module("beyond_range")
    cfg, hard = load_config(CONTEXTS), load_config(HARD)
    assert beyond_range.beyond_scene() == dataclasses.replace(cfg, context=hard.context)
    assert beyond_range.beyond_scene() != cfg
    for args, says in ((["--methods", "sac", "--seeds", "10-12"], "sac is shipped for seeds 0-9 only"),
                       (["--holdout", "0"], "--holdout = 0: must be at least 1")):
        done = subprocess.run([sys.executable, "benchmarks/beyond_range.py", *args], capture_output=True, text=True,
                              cwd=ROOT, timeout=300)
        assert done.returncode == 1 and done.stderr.count("\n") == 1 and says in done.stderr, done.stderr


@pytest.mark.slow
def test_beyond_range_reads_each_context_as_the_methods_learnt_it_and_plays_it_on_the_wide_scene():
    """A context beyond the training range reaches a shipped map as the training range normalises it (past +-1,
    worked here by hand from the two files' ranges), and its outcome is the env's on the widened scene."""
    from agents.context_maps import ParamMap

    args = [sys.executable, "benchmarks/beyond_range.py", "--holdout", "6", "--holdout-seed", "3", "--seeds", "1",
            "--methods", "single,linear-map", "--json"]
    done = subprocess.run(args, capture_output=True, text=True, cwd=ROOT, timeout=900)
    assert done.returncode == 0, done.stderr
    rep = json.loads(done.stdout)
    wide = load_config(HARD, {"scene.frames": 5})
    env = AerialAcrobatEnv(wide)
    shipped = ROOT / "policies" / "contexts" / "linear-map" / "seed1" / "policy.json"
    m = ParamMap.from_json_dict(json.loads(shipped.read_text())["map"])
    ranges = {"scene.rise": (0.0, 0.010), "scene.pitch": (0.070, 0.086), "design.m2": (0.0065, 0.010),
              "design.mu_s": (0.283, 0.542)}  # configs/contexts.yaml's
    made, inside = [], []
    for s in range(4_000_000, 4_000_006):
        ctx = env.reset(seed=s)[1]["context"]
        x = np.array([[2.0 * (ctx[k] - lo) / (hi - lo) - 1.0 for k, (lo, hi) in ranges.items()]])
        inside.append(bool(np.all(np.abs(x) <= 1.0)))
        made.append(int(env.step(m.act(x)[0].astype(np.float32))[4]["traversals"] >= 4))
    assert rep["inside"] == sum(inside) and rep["beyond"] == 6 - sum(inside) and rep["beyond"] > 0
    by = {r["method"]: r for r in rep["rows"]}
    assert by["linear-map"]["outcomes"] == [made]
    assert by["single"]["seeds"] == 1 and "beyond_minus_single" in by["linear-map"]
