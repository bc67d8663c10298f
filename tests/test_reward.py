"""The reward (aero_env.reward): shaping pays only real flights, one function for the env and the
tuner's screen, and an adversary (CMA-ES on the shaped reward) whose designs an independent audit
(benchmarks/shaping_adversary.py) backs with seated catches, falling energy and healthy constraints."""

from __future__ import annotations

import dataclasses
import importlib.util

import numpy as np
import pytest

from aero_env.config import ConfigError, load_config
from aero_env.envs import AerialAcrobatEnv
from aero_env.models.reduced import simulate_batch
from aero_env.simulation import simulate
from aero_env.reward import batch_reward, reward, rewards

from .conftest import COARSE, PAPER, ROOT
from .test_physics import CATCH_LETS_GO

W = 0.5
FLIGHT_MISSES = ("fell_short", "missed_catch")
HUNG = ("stalled", "no_detach")


def _adversary_module():
    spec = importlib.util.spec_from_file_location("shaping_adversary", ROOT / "benchmarks" / "shaping_adversary.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


ADV = _adversary_module()


def _random_steps(fidelity: dict, designs: int, seed: int = 3):
    """(outcome, traversals, miss_distance, reward) of random designs on a 3-frame prototype scene at ``fidelity``
    (config overrides)."""
    env = AerialAcrobatEnv(PAPER, {"scene.frames": 3, **fidelity, "env.reward_shaping": W})
    out = []
    for a in np.random.default_rng(seed).uniform(-1, 1, (designs, env.space.dim)):
        env.reset(seed=0)
        _, r, _, _, info = env.step(a)
        out.append((info["outcome"], info["traversals"], info["miss_distance"], r))
    return out


# ---- 1. shaping pays only real flights ----
def test_a_hook_that_never_let_go_earns_no_partial_credit():
    runs = _random_steps(COARSE, 40)
    hung = [(o, t, m, r) for o, t, m, r in runs if o in HUNG]
    flown = [(o, t, m, r) for o, t, m, r in runs if o in FLIGHT_MISSES]
    # the hung runs have a miss distance the old rule paid for (w·(1 - miss/pitch) > 0) ...
    pitch = load_config(PAPER).scene.pitch
    assert sum(m is not None and m < pitch for _, _, m, _ in hung) >= 5, hung
    # ... and earn their traversals, nothing more
    assert all(r == t for _, t, _, r in hung), [(o, r - t) for o, t, _, r in hung if r != t]
    # a flight that missed earns w·(1 - miss/pitch) on top of its traversals, less than one more
    assert len(flown) >= 5
    for o, t, m, r in flown:
        assert r == pytest.approx(t + W * max(0.0, 1 - m / pitch), abs=1e-12) and t <= r < t + W, (o, t, m, r)
    assert sum(r > t for _, t, _, r in flown) >= 5


def test_reward_rules_and_bad_input():
    # unstable pays nothing; completed and hung runs pay their traversals; a flight its credit
    r = rewards(["unstable", "completed", "stalled", "fell_short"], [2, 2, 1, 1], [True, False, False, True],
                [0.01, np.nan, 0.001, 0.041], 0.082, 0.5)
    assert list(r) == [0.0, 2.0, 1.0, 1.0 + 0.5 * (1 - 0.041 / 0.082)]
    with pytest.raises(ConfigError, match="one length"):
        rewards(["stalled", "stalled"], [1, 2, 3], False, np.nan, 0.082, 0.5)
    with pytest.raises(ConfigError, match="2 configs for a batch of 3"):
        batch_reward(simulate_batch([load_config(PAPER, {"sim.fidelity": "reduced"})] * 3),
                     [load_config(PAPER)] * 2)


# ---- 2. one reward function: the screen scores what env.step pays ----
@pytest.mark.parametrize("fidelity, designs", [("reduced", 16), ("mbd", 8)])
def test_screen_scores_every_design_as_env_step_pays_it(fidelity, designs):
    from agents.tune import TuneSettings, screen

    varied = {"context": [{"name": "scene.rise", "low": 0.0, "high": 0.004}, {"name": "scene.pitch"},
                          {"name": "design.m2", "low": 0.0070, "high": 0.0085}],
              "tolerance": [{"name": "design.m3", "relative": 0.02}]}
    cfg = load_config(PAPER, {"scene.frames": 3, "env.reward_shaping": W, **varied})
    settings = TuneSettings(trials=designs, seeds_per_design=2, seed=1, screen=fidelity, screen_designs=designs,
                            progress=False).check()
    screened = screen(cfg, settings)
    env = AerialAcrobatEnv(cfg, {"sim.fidelity": fidelity})
    paid, outcomes = [], []
    for a in screened["actions"]:
        step = []
        for seed in settings.eval_seeds:
            env.reset(seed=seed)
            _, r, _, _, info = env.step(np.array(a))
            step.append(r)
            outcomes.append(info["outcome"])
        paid.append(float(np.mean(step)))
    assert screened["enqueued_scores"] == pytest.approx(paid, rel=0, abs=1e-12)
    assert any(s % 1 > 0 for s in paid)  # shaping paid somewhere: a screen without it would differ there
    if fidelity == "reduced":
        assert set(outcomes) >= {"stalled", "no_detach", "fell_short", "missed_catch"}


# ---- 3. the adversary ----
def test_the_audit_rejects_a_reward_no_run_backs():
    cfg = load_config(PAPER, {"scene.frames": 3, **COARSE, "env.reward_shaping": W})
    env = AerialAcrobatEnv(cfg)
    runs = {}
    for a in np.random.default_rng(3).uniform(-1, 1, (40, env.space.dim)):
        ecfg = env.space.episode_config(env.space.values(a), env.space.nominal_draw())[0]
        result = simulate(ecfg, trace=True)
        runs.setdefault(result.outcome, (result, ecfg))
        if "stalled" in runs and runs.keys() & set(FLIGHT_MISSES):
            break
    hung, hcfg = runs["stalled"]
    assert ADV.audit(reward(hung, hcfg), hung, hcfg) == []
    assert "no flight" in " ".join(ADV.audit(ADV.reward_before(hung, hcfg), hung, hcfg))  # the old rule's credit
    flown, fcfg = runs.get("fell_short") or runs["missed_catch"]
    assert ADV.audit(reward(flown, fcfg), flown, fcfg) == []
    assert "credit" in " ".join(ADV.audit(reward(flown, fcfg) + 0.01, flown, fcfg))  # more than the miss earns
    # the prototype completes the short row: 2 seated catches; a catch 5 mm off its seat is no traversal
    proto = simulate(cfg, trace=True)
    assert proto.outcome == "completed" and ADV.audit(2.0, proto, cfg) == []
    unseated = dataclasses.replace(proto, swings=proto.swings[:1] + [
        dataclasses.replace(s, catch_seat_mm=5.0) for s in proto.swings[1:]])
    assert "seated catches" in " ".join(ADV.audit(2.0, unseated, cfg))
    # a seated catch that let go before its frame carried the robot is no traversal (test_physics.CATCH_LETS_GO)
    lcfg = load_config(PAPER, {**CATCH_LETS_GO, "scene.frames": 3, "env.reward_shaping": W})
    let_go = simulate(lcfg, trace=True)
    assert let_go.outcome == "missed_catch" and let_go.swings[1].t_detach is not None, let_go.reason
    assert ADV.audit(reward(let_go, lcfg), let_go, lcfg) == []
    assert "seated catches" in " ".join(ADV.audit(1.0, let_go, lcfg))  # what counting the catch at once paid
    hot = dataclasses.replace(hung, health={**hung.health, "penetration": 1.0})
    assert "health penetration" in " ".join(ADV.audit(reward(hung, hcfg), hot, hcfg))
    rising = hung.trace["energy"] + np.where(np.arange(len(hung.trace["t"])) > 50, 1e-3, 0.0)
    pumped = dataclasses.replace(hung, trace=dict(hung.trace, energy=rising))
    assert "energy rose" in " ".join(ADV.audit(reward(hung, hcfg), pumped, hcfg))


def test_cma_es_on_the_shaped_reward_finds_nothing_the_audit_rejects():
    """CMA-ES (as aero-env tune runs it) on the prototype scene at a 1 ms step (COARSE), 36 trials; then every design it
    tried, its best first, re-run with its trace and audited apart from aero_env.reward."""
    cfg = load_config(PAPER, {**COARSE, "env.reward_shaping": W})
    trials = ADV.adversary(cfg, 36, seed=1)
    audited = ADV.audit_top(cfg, trials, top=len(trials))
    assert [a["problems"] for a in audited if a["problems"]] == []
    best = audited[0]
    assert best["reward"] >= 2 and best["seated_catches"] == int(best["reward"])  # it learnt to traverse
    # shaping was in play on both sides: flights credited, and hung runs the old rule would have paid
    assert any(a["flight"] and a["reward"] % 1 > 0 for a in audited)
    assert any(not a["flight"] and a["miss_distance_mm"] is not None and a["miss_distance_mm"] < 82 for a in audited)
