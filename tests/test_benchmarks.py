"""Every script in benchmarks/ runs at a tiny size, so none can rot unnoticed. Nothing here times anything:
each run is checked for what it reports (counts, the designs it ran, the physics it must show)."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

from aero_env.intervals import wilson_interval

from .conftest import benchmark_module

ROOT = Path(__file__).resolve().parents[1]
PAPER = str(ROOT / "configs" / "paper.yaml")


def _bench(script: str, *args: str, expect: int = 0, cwd: Path = ROOT):
    out = subprocess.run([sys.executable, str(ROOT / "benchmarks" / script), *args], capture_output=True, text=True,
                         timeout=600, cwd=cwd)
    assert out.returncode == expect, out.stderr[-3000:]
    return json.loads(out.stdout) if expect == 0 else out.stderr


def test_env_step():
    r = _bench("env_step.py", "--designs", "3", "--repeats", "1")
    assert r["random"]["designs"] == 3 and sum(r["random"]["outcomes"].values()) == 3
    assert r["prototype"]["reward"] == 7.0  # the prototype completes its row through env.step


@pytest.mark.slow
def test_reduced_speed():
    r = _bench("reduced_speed.py", "--designs", "40", "--repeats", "1", "--threads", "1")
    assert r["designs"] == 40 and r["threads"] == 1 and sum(r["outcomes"].values()) == 40
    assert r["compile_s"] >= 0.0 and r["simulated_s"]["max"] >= r["simulated_s"]["median"] > 0.0
    err = _bench("reduced_speed.py", "--threads", "0", expect=2)
    assert "--threads = 0" in err


@pytest.mark.slow
def test_reduced_agreement_caches_the_pymunk_runs(tmp_path):
    cache = tmp_path / "runs.json"
    first = _bench("reduced_agreement.py", "--designs", "6", "--seed", "3", "--cache", str(cache))
    assert first["designs"] == 6 and first["near"] is None
    # the same six designs (uniform actions of seed 3, the nominal draw) run here one at a time, in the pymunk world
    # and in the reduced model, not as the benchmark's batch: its shares are these counts
    world, model = _one_at_a_time(6, 3)
    assert first["same_traversals"] == np.mean(world == model)
    assert (first["pymunk_full_row"], first["reduced_full_row"], first["full_row_in_both"]) == (
        int((world == 7).sum()), int((model == 7).sum()), int(((world == 7) & (model == 7)).sum()))
    assert len(json.loads(cache.read_text())) == 1
    # the second call reruns only the reduced model: the pymunk runs (their wall times included) come back as stored
    again = _bench("reduced_agreement.py", "--designs", "6", "--seed", "3", "--cache", str(cache))
    assert again["pymunk_wall_s"] == first["pymunk_wall_s"] and again["same_traversals"] == first["same_traversals"]
    near = _bench("reduced_agreement.py", "--designs", "4", "--seed", "3", "--cache", str(cache), "--near", PAPER)
    assert near["near"] == PAPER and near["spread"] == 0.1 and len(json.loads(cache.read_text())) == 2
    # the same path, seed and count with another design in the file are other runs, not the stored ones
    edited = tmp_path / "paper.yaml"
    edited.write_text(Path(PAPER).read_text())
    _bench("reduced_agreement.py", "--designs", "4", "--seed", "3", "--cache", str(cache), "--near", str(edited))
    assert len(json.loads(cache.read_text())) == 2  # the same designs as PAPER's, whatever the file's name
    edited.write_text(Path(PAPER).read_text().replace("  La: 0.0483\n", "  La: 0.0490\n"))
    _bench("reduced_agreement.py", "--designs", "4", "--seed", "3", "--cache", str(cache), "--near", str(edited))
    assert len(json.loads(cache.read_text())) == 3


def _one_at_a_time(n: int, seed: int):
    """reduced_agreement.py's designs on paper.yaml, each simulated alone: (pymunk traversals, reduced traversals)."""
    from aero_env.config import load_config
    from aero_env.design_space import DesignSpace
    from aero_env.models.reduced import simulate_reduced
    from aero_env.simulation import simulate

    cfg = load_config(PAPER)
    space = DesignSpace(cfg)
    actions = np.random.default_rng(seed).uniform(-1.0, 1.0, (n, space.dim))
    cfgs = [space.episode_config(space.values(a), space.nominal_draw())[0] for a in actions]
    return (np.array([simulate(c).traversals for c in cfgs]),
            np.array([simulate_reduced(c.replace({"sim.fidelity": "reduced"})).traversals for c in cfgs]))


def _screened_full_rows(n: int, seed: int) -> int:
    """How many of tune's screen's ``n`` random designs (its seed's uniform actions) complete paper.yaml's row at
    ``reduced``, each played through the env at that fidelity. paper.yaml draws nothing (fixed context, no
    tolerance), so the screen scores each design on one episode (seed 0) and its reward is its traversals
    (reward_shaping 0)."""
    from aero_env.config import load_config
    from aero_env.envs import AerialAcrobatEnv

    cfg = load_config(PAPER)
    env = AerialAcrobatEnv(cfg, {"sim.fidelity": "reduced"})
    actions = np.random.default_rng(seed).uniform(-1.0, 1.0, (n, env.action_space.shape[0]))
    done = 0
    for a in actions:
        env.reset(seed=0)
        done += env.step(a.astype(np.float32))[4]["traversals"] == cfg.scene.frames - 1
    return done


def test_shaping_adversary():
    r = _bench("shaping_adversary.py", "--trials", "4", "--survey", "4", "--json")
    assert r["survey"]["designs"] == 4 and r["audit"]["designs"] == 4
    assert r["audit"]["failed"] == 0  # the env's reward credits nothing the audit refuses


@pytest.mark.parametrize("script, args, key", [
    ("tune_samplers.py", [PAPER, "--trials", "4", "--seeds", "1", "--samplers", "random,cmaes", "--jobs", "1",
                          "--json"], "samplers"),
    ("tune_screening.py", [PAPER, "--seeds", "1", "--trials", "3", "--screen-designs", "50", "--confirm", "2"],
     "runs"),
])
def test_tuning_benchmarks(script, args, key):
    r = _bench(script, *args)
    if key == "samplers":
        assert [s["sampler"] for s in r["samplers"]] == ["random", "cmaes"] and all(
            s["studies"] == 1 and len(s["best_rewards"]) == 1 for s in r["samplers"])
    else:
        (plain,), (screened,) = r["runs"]["cmaes"], r["runs"]["screened"]
        # the screened run scores 50 designs in the reduced model and only its --confirm best in the pymunk world:
        # fewer pymunk trials than the plain run's --trials (a count; the times are the benchmark's to report)
        assert plain["trials"] == 3 and screened["trials"] == 2 < plain["trials"]
        assert r["screen_designs"] == 50 and screened["screen_full_rows"] == _screened_full_rows(50, seed=0)


@pytest.mark.slow
def test_step_agreement_scores_each_setting_against_the_reference_on_its_converged_designs():
    # a setting given as the reference's own step and iterations is the reference by another route: it must agree
    # on every converged design; the coarse one's misses are the designs it counts differently, each listed with
    # its count at every setting, and the agreement is taken over the designs reference/2 confirms
    r = _bench("step_agreement.py", PAPER, "--designs", "6", "--seed", "3", "--settings",
               "2/5,0.0625/120,reduced,reduced/4,reduced/0.5", "--jobs", "2", "--json")
    rows = {row["setting"]: row for row in r["rows"]}
    assert list(rows) == ["reference", "reference/2", "2/5", "0.0625/120", "reduced", "reduced/4", "reduced/0.5"]
    assert r["designs"] == 6
    assert rows["0.0625/120"]["wrong"] == [] and rows["reference"]["agreement_converged"] == 1.0
    coarse = rows["2/5"]
    assert coarse["wrong"], "2 ms at 5 iterations should miss a design of this sample: pick another seed"
    for i in coarse["wrong"]:
        counts = r["missed"][str(i)]
        assert counts["2/5"] != counts["reference"] == counts["reference/2"]
    assert coarse["agreement_converged"] == 1.0 - len(coarse["wrong"]) / r["converged_designs"]
    # with its 95 % interval over the same designs (none for the two rows that agree by construction)
    lo, hi = coarse["agreement_converged_interval_95"]
    assert (lo, hi) == pytest.approx(wilson_interval(r["converged_designs"] - len(coarse["wrong"]),
                                                     r["converged_designs"])) and lo <= coarse["agreement_converged"] <= hi
    assert rows["reference"]["agreement_converged_interval_95"] is None is rows["reference/2"]["agreement_converged_interval_95"]
    assert "--settings: '2/x'" in _bench("step_agreement.py", "--settings", "2/x", expect=2)
    # reduced/DT_MS is the reduced model at that step: at its preset's 4 ms it is the reduced rung itself; at 0.5 ms
    # design 5 of this near sample counts 4 where the rung counts 7 (the reference's 7), each the model's own run
    from aero_env.bench.designs import draw_designs
    from aero_env.config import load_config
    from aero_env.simulation import simulate

    assert rows["reduced/4"]["wrong"] == rows["reduced"]["wrong"]
    near = ("--near", PAPER, "--spread", "0.15")
    five = _bench("step_agreement.py", PAPER, "--designs", "100", "--seed", "4", *near, "--only", "5", "--settings",
                  "reduced,reduced/4,reduced/0.5", "--jobs", "2", "--json")["missed"]["5"]
    cfg = draw_designs(load_config(PAPER), 100, 4, near=load_config(PAPER), spread=0.15).configs[5]
    ours = {dt: simulate(cfg.replace({"sim.fidelity": "reduced", "sim.dt": dt})).traversals for dt in (0.004, 0.0005)}
    assert five["reduced"] == five["reduced/4"] == ours[0.004] != five["reduced/0.5"] == ours[0.0005]
    for bad in ("reduced/9", "reduced/x", "reduced/"):
        assert f"--settings: '{bad}'" in _bench("step_agreement.py", "--settings", bad, expect=2)
    # --only runs those designs of the same sample, and only them: the counts the whole run listed
    some = ",".join(str(i) for i in coarse["wrong"])
    part = _bench("step_agreement.py", PAPER, "--designs", "6", "--seed", "3", "--settings", "2/5", "--only", some,
                  "--jobs", "2", "--json")
    assert part["only"] == coarse["wrong"] and part["converged_designs"] == len(coarse["wrong"])
    assert {i: {k: c for k, c in row.items()} for i, row in part["missed"].items()} == {
        i: {k: r["missed"][i][k] for k in ("reference", "reference/2", "2/5")} for i in part["missed"]}
    assert [c is None for c in part["reference_counts"]] == [i not in coarse["wrong"] for i in range(6)]
    for bad in ("6", "1,1", "x"):
        assert "--only" in _bench("step_agreement.py", "--designs", "6", "--only", bad, expect=2)


@pytest.mark.slow
def test_step_agreement_splits_the_agreement_by_whether_the_makers_tolerances_change_a_designs_count():
    # --builds K: a converged design is robust when all K builds keep its count at the config's fidelity. The
    # builds are aero-env robustness's own draws (its default table, the same seed), recomputed here through it,
    # and the robust/fragile agreements are the converged agreement over those two groups
    from aero_env.bench.designs import draw_designs
    from aero_env.config import load_config
    from aero_env.robustness.draws import INVALID
    from aero_env.robustness.study import assess
    from aero_env.robustness.tolerances import DEFAULT_TOLERANCES

    # six designs near the prototype (a uniform sample of six rarely holds a design the reduced model misses; seed 147:
    # the test needs the builds to keep different designs' counts at reduced than at mbd and the reduced model to miss
    # one, which seeds 2, 54, 61, 93, then 133 lost as the reduced model's contacts were rebuilt and the frames made
    # hollow; 147 on the hollow frames, where 134-146 lacked a miss or a robust set that the rung changes)
    near = ("--near", PAPER, "--spread", "0.15")
    r = _bench("step_agreement.py", PAPER, "--designs", "6", "--seed", "147", *near, "--settings", "2/5,reduced",
               "--builds", "4", "--jobs", "2", "--json")
    sample = draw_designs(load_config(PAPER), 6, 147, near=load_config(PAPER), spread=0.15)
    assert r["converged_designs"] == 6, "a design of this sample no longer converges: pick another seed"
    converged = list(range(6))

    def keeps_its_count(cfg):  # aero-env robustness --draws 4 (its default seed): every build at the nominal's count
        study = assess(cfg, DEFAULT_TOLERANCES, draws=4, seed=0)
        return all(run.outcome != INVALID and run.traversals == study.nominal.traversals for run in study.runs)

    robust = [i for i in converged if keeps_its_count(sample.configs[i])]
    assert r["builds"] == 4 and r["robust_designs"] == robust
    assert 0 < len(robust) < len(converged), "the sample should hold robust and fragile designs: pick another seed"
    coarse = next(row for row in r["rows"] if row["setting"] == "2/5")
    fragile = [i for i in converged if i not in robust]
    assert coarse["agreement_robust"] == sum(i not in coarse["wrong"] for i in robust) / len(robust)
    assert coarse["agreement_fragile"] == sum(i not in coarse["wrong"] for i in fragile) / len(fragile)
    for group, members in (("robust", robust), ("fragile", fragile)):
        right = sum(i not in coarse["wrong"] for i in members)
        assert coarse[f"agreement_{group}_interval_95"] == pytest.approx(wilson_interval(right, len(members)))
    # the table the docs print: the split's line and, per setting, three agreements with their intervals
    spec = importlib.util.spec_from_file_location("step_agreement", ROOT / "benchmarks" / "step_agreement.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    lines = script.table(r).splitlines()
    assert lines[1].startswith(f"robust: the {len(robust)} of them") and f"the other {len(fragile)}" in lines[1]
    row = next(line.split() for line in lines if line.split()[:1] == ["2/5"])
    lo, hi = coarse["agreement_fragile_interval_95"]
    assert row[5:7] == [f"{100 * coarse['agreement_fragile']:.1f}%", f"{100 * lo:.1f}-{100 * hi:.1f}"]
    # a setting named reduced is the reduced model's rung, on the same designs
    from aero_env.simulation import simulate

    mine = [simulate(sample.configs[i].replace({"sim.fidelity": "reduced"})).traversals for i in converged]
    by_reduced = next(row for row in r["rows"] if row["setting"] == "reduced")
    assert by_reduced["wrong"] == [i for i, t in zip(converged, mine) if t != r["reference_counts"][i]] != [], \
        "the reduced model should miss a design of this sample: pick another seed"
    assert "--builds -1" in _bench("step_agreement.py", "--builds", "-1", expect=2)
    # --builds-at runs the builds at another rung: the robust designs are then those robustness finds there
    at = _bench("step_agreement.py", PAPER, "--designs", "6", "--seed", "147", *near, "--settings", "reduced",
                "--builds", "4", "--builds-at", "reduced", "--jobs", "2", "--json")
    there = [i for i in converged if keeps_its_count(sample.configs[i].replace({"sim.fidelity": "reduced"}))]
    assert at["builds_at"] == "reduced" and at["robust_designs"] == there != robust
    assert "--builds-at 'nope'" in _bench("step_agreement.py", "--builds", "2", "--builds-at", "nope", expect=2)
    assert "only with --builds" in _bench("step_agreement.py", "--builds-at", "reference", expect=2)
    assert "equals --seed" in _bench("step_agreement.py", "--seed", "0", "--builds", "2", expect=2)


@pytest.mark.slow
def test_step_agreement_near_a_design_runs_the_designs_bench_accuracy_draws_there():
    # --near draws around the config's design, as bench accuracy --near does: the reference's counts are those of
    # draw_designs' near sample run here at the reference. At ±0.2 the three designs of seed 13 count 0, 1 and 7
    # traversals, so the counts tell this sample from others: the same seed at the default ±0.1 counts 7, 1, 7, at
    # ±0.05 all three complete (7, 7, 7), uniform draws count 0, 0, 2, seeds 12 and 15 at ±0.2 give 0, 0, 0 and
    # 0, 0, 1 (measured at the reference on the parts-built robot), and the designs in another order give another
    # list. Seed 13 is the first of seeds 0-15 at ±0.2 whose three counts differ (seed 4, the earlier pick, now
    # counts 0, 1, 1; seed 14 gives 7, 4, 0).
    from aero_env.bench.designs import draw_designs
    from aero_env.config import load_config
    from aero_env.simulation import simulate

    r = _bench("step_agreement.py", PAPER, "--designs", "3", "--seed", "13", "--near", PAPER, "--spread", "0.2",
               "--settings", "0.5/30", "--jobs", "2", "--json")
    base = load_config(PAPER)
    sample = draw_designs(base, 3, 13, near=base, spread=0.2)
    assert r["sample"] == f"near {PAPER} ±0.2"
    counts = [simulate(c.replace({"sim.fidelity": "reference"})).traversals for c in sample.configs]
    assert len(set(counts)) == 3, counts  # a sample the comparison can fail on: no two designs alike
    assert r["reference_counts"] == counts
    assert "only with --near" in _bench("step_agreement.py", "--spread", "0.2", expect=2)


def test_the_knife_edge_nudge_moves_every_action_component_by_one_float32_ulp():
    one_ulp_nudge = benchmark_module("rl_vs_tuning").one_ulp_nudge
    actions = np.array([[0.5, -0.25, 0.0, 1.0 / 3.0], [-1.0, 0.7, 1e-9, -0.1]])
    up = np.array([[True, False, True, False], [True, True, False, True]])
    nudged = one_ulp_nudge(actions, up)
    a32 = actions.astype(np.float32)
    # one step of float32, counted on the float32 grid the action space reads: up where asked, down elsewhere
    for x, y, u in zip(a32.ravel(), nudged.astype(np.float32).ravel(), up.ravel()):
        assert y == np.nextafter(x, np.float32(np.inf if u else -np.inf)) and y != x
    # worked by hand: float32's step is 2^-24 in [0.5, 1) and 2^-25 in [0.25, 0.5)
    assert nudged[0, 0] == 0.5 + 2.0 ** -24 and nudged[0, 1] == -0.25 - 2.0 ** -25


def test_one_map_fit_gives_every_smaller_budgets_map_exactly():
    """map_budgets fits once to the largest budget: the map it keeps for a smaller budget is the very map a fit with
    that budget returns (same seed, same contexts), and a fit's contexts start where it is told."""
    from aero_env.config import load_config
    from agents.context_maps import fit_map
    from agents.episode_runner import EpisodeRunner

    map_at_budgets = benchmark_module("map_budgets").map_at_budgets
    runner = EpisodeRunner(load_config(ROOT / "configs" / "contexts.yaml", {"sim.fidelity": "reduced"}))
    start = np.zeros(runner.space.dim)
    got = map_at_budgets(runner, "linear", 3, [900, 1664, 2000, 3000], start)  # 832 episodes a generation
    for budget in (900, 1664, 2000, 3000):
        alone, history = fit_map(runner, "linear", 3, budget, start=start, first_context=260_000)
        assert np.array_equal(got[budget][0], alone.params), budget
        assert history[-1]["episodes"] == 832 * (budget // 832)
    other, _ = fit_map(runner, "linear", 3, 900, start=start, first_context=250_000)
    assert not np.array_equal(other.params, got[900][0])  # other contexts, another map
    assert "past a seed's block of 20000" in _bench("map_budgets.py", "--budgets", "400000", expect=1)
    assert "too few for one CMA-ES generation" in _bench("map_budgets.py", "--budgets", "100", expect=1)


def test_one_search_to_the_largest_budget_gives_every_smaller_budgets_outcome():
    """budget_curves searches each context once, to the largest budget: a context counts as solved at budget b
    exactly when a search given b episodes a context solves it (CMA-ES), and a random search's count is the one a
    search that tries its designs one at a time finds (the batching does not move it)."""
    from aero_env.config import load_config
    from agents.context_maps import search_contexts
    from agents.episode_runner import EpisodeRunner, draws_for_seeds

    bc = benchmark_module("budget_curves")
    runner = EpisodeRunner(load_config(ROOT / "configs" / "contexts_hard.yaml", {"sim.fidelity": "reduced"}))
    draws = draws_for_seeds(runner.space, range(700_000, 700_030))
    start = np.zeros(runner.space.dim)
    first, _ = bc.cmaes_search(runner, draws, 4, 41, start, 0.3)
    assert 0 < (first > 0).sum() < len(draws) and len(set(first[first > 0])) > 2  # a check that can fail
    budgets = (1, 5, 9, 12, 17, 33, 41)  # episodes a context: 5 and 12 end within a generation
    got = bc.search_budgets(first, [30 * b for b in budgets], 30, wall=1.0, spent=bc.cmaes_spent)
    for b in budgets:  # each budget searched on its own: what it solves, and the episodes it spends
        alone = search_contexts(runner, draws, start, 4, max_evals=b, sigma=0.3)
        assert got.whole[30 * b] == alone.solved.astype(int).tolist(), b
        assert got.episodes[30 * b] == alone.evaluations.sum(), b
    assert got.wall == {30 * b: (1.0 if b == 41 else None) for b in budgets}
    assert bc.search_budgets(first, [29], 30, wall=1.0).whole[29] is None  # under one episode a context: no score

    tries, _ = bc.random_search(runner, draws[:12], 7, 20)
    for i, d in enumerate(draws[:12]):  # one design at a time, drawn as the search draws them
        designs = np.random.default_rng([7, i]).uniform(-1.0, 1.0, (20, runner.space.dim))
        made = [bool(runner.whole_rows([d], designs[k:k + 1])[0]) for k in range(20)]
        assert tries[i] == (made.index(True) + 1 if True in made else 0), i
    assert 0 < (tries > 0).sum() < 12 and (tries > 7).any()
    fewer, _ = bc.random_search(runner, draws[:12], 7, 7)  # a smaller budget: the same designs, cut short
    assert np.array_equal(fewer, np.where(tries <= 7, tries, 0))


@pytest.mark.slow
def test_one_training_run_gives_every_smaller_budgets_policy():
    """The policy budget_curves reads after the update on the first b episodes is the one a run of b episodes ends
    with (PPO and SAC, at reduced), and the policies at two budgets differ."""
    from aero_env.config import load_config
    from agents.episode_runner import EpisodeRunner, draws_for_seeds

    from agents.rl import TrainSettings, load_run, policy_actions, train

    bc = benchmark_module("budget_curves")
    task = bc.TASKS["hard"]
    cfg = load_config(task.config, {"sim.fidelity": "reduced"})
    runner = EpisodeRunner(cfg)
    obs = runner.observations(draws_for_seeds(runner.space, range(700_000, 700_020)))
    for learner, small, large in (("ppo", 1024, 3072), ("sac", 1088, 1152)):
        both = bc.rl_actions(task, learner, 2, [small, large], 1e-3, obs)
        with tempfile.TemporaryDirectory() as tmp:  # a run of the smaller budget, trained and read on its own
            train(cfg, TrainSettings(algo=learner, timesteps=small, n_envs=32, seed=64, eval_every=0, vector=True,
                                     progress=False, hyperparameters=dict(bc.RL[learner], learning_rate=1e-3)), tmp)
            alone = policy_actions(load_run(tmp)[0], obs)
        assert np.array_equal(both[small][0], alone), learner
        assert both[small][2] == small and both[large][2] == large
        assert not np.allclose(both[small][0], both[large][0]), learner


def test_budget_curves_refuses_bad_options_in_one_line(tmp_path):
    def refused(*args: str) -> str:
        err = _bench("budget_curves.py", *args, expect=1)
        assert err.count("\n") == 1 and err.startswith("budget_curves: "), err
        return err

    assert "--learners 'dqn'" in refused("--learners", "random,dqn")
    assert "--seeds 10: at most 9" in refused("--seeds", "0-10")
    assert "--holdout 0" in refused("--holdout", "0")
    assert "--watch 9000" in refused("--watch", "9000")
    assert "past a seed's block of 20000" in refused("--budgets", "400000")
    assert "--tune-budget 900000" in refused("--tune-budget", "900000")
    assert "--plot curves.txt: a file ending .png" in refused("--plot", "curves.txt")
    assert "does not exist" in refused("--results", str(tmp_path / "no" / "run.json"))
    other = tmp_path / "run.json"
    other.write_text(json.dumps(dict(meta=dict(task="contexts"), tuning={}, runs={})))
    assert "holds a run with other options" in refused("--results", str(other))
    other.write_text("[1, 2]")
    assert "holds a run with other options" in refused("--results", str(other))
    other.write_text("{not json")
    assert "not this script's JSON" in refused("--results", str(other))
