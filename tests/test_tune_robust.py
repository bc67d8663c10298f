"""A tune starts from the config's own design, never ends worse than it, and (``--robust K``) scores designs on the
same K hand-made builds (agents.tune, issue 25 §2). Tiny budgets: 3 frames at a 1 ms step (COARSE)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from aero_env.config import load_config
from aero_env.reward import reward
from aero_env.robustness.draws import build
from aero_env.robustness.tolerances import DEFAULT_TOLERANCES
from aero_env.simulation import simulate
from agents.tune import TuneSettings, tune

from .conftest import COARSE, PAPER

FAST = {"scene.frames": 3, **COARSE}
QUIET = dict(progress=False)


def _trials(name: str, url: str):
    import optuna

    study = optuna.load_study(study_name=name, storage=url)
    return sorted(study.trials, key=lambda t: t.number)


def test_a_fresh_study_starts_from_the_configs_own_design_and_a_resumed_one_not_again(tmp_path):
    cfg = load_config(PAPER, FAST)
    url = f"sqlite:///{tmp_path / 's.db'}"
    tune(cfg, TuneSettings(sampler="random", trials=2, storage=url, study="s", **QUIET))
    first = _trials("s", url)[0]
    own = {k: cfg.value(k) for k in first.user_attrs["design"]}
    assert set(own) == {"design.m3", "design.h", "design.La", "design.spring_k", "design.mu_s", "design.mu_k"}
    assert first.user_attrs["design"] == own and first.user_attrs["start"] is True  # exactly, not to rounding
    tune(cfg, TuneSettings(sampler="random", trials=4, storage=url, study="s", **QUIET))
    assert [bool(t.user_attrs.get("start")) for t in _trials("s", url)] == [True, False, False, False]


def test_a_tune_that_cannot_beat_the_start_writes_the_configs_design_and_says_so(tmp_path):
    # the prototype completes the 3-frame row; two trials cannot do strictly better. With CMA-ES seed 29 the second
    # trial, another design (m3 8.4 g, h 6.1 mm, La 44.1 mm, mu_s 0.37), completes it too: a tie, which must not
    # displace the config's design. Seed 29 is the only one of seeds 0-39 whose second trial ties on the parts-built
    # robot (seeds 1, 11, 24, 31, 34, 36 reach 1 traversal, the rest 0; seed 3, the earlier pick, now 0)
    out = tmp_path / "b.yaml"
    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "tune", str(PAPER), "--set", "scene.frames=3",
                           "--set", "sim.dt=0.001", "--trials", "2", "--seed", "29", "--out", str(out),
                           "--no-progress"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert "best 2/2 (mean reward 2.00) vs the config's own 2/2 (2.00): kept the config's design" in done.stdout
    assert "first never" not in done.stdout
    cfg, best = load_config(PAPER, FAST), load_config(out)
    for key in ("design.m3", "design.h", "design.La", "design.spring_k", "design.mu_s", "design.mu_k"):
        assert best.value(key) == cfg.value(key), key
    # the same study in this process: the tie is there, and the result says the start was kept
    result = tune(cfg, TuneSettings(sampler="cmaes", trials=2, seed=29, **QUIET))
    assert result.history == [(0, 2.0), (1, 2.0)]
    assert (result.best_trial, result.start_trial, result.improved) == (0, 0, False)
    assert (result.start_reward, result.start_traversals) == (2.0, [2])


def test_robust_trials_share_the_same_builds_and_score_their_mean(tmp_path):
    cfg = load_config(PAPER, FAST)
    url = f"sqlite:///{tmp_path / 'r.db'}"
    result = tune(cfg, TuneSettings(sampler="random", trials=3, robust=4, seed=5, storage=url, study="r", **QUIET))
    assert result.robust == 4 and result.start_robust_full is not None
    trials = _trials("r", url)
    designs = [t.user_attrs["design"] for t in trials]
    assert designs[1] != designs[2]  # two different designs ...
    factors = [t.user_attrs["robust_factors"] for t in trials]
    assert np.shape(factors[0]) == (4, len(DEFAULT_TOLERANCES))
    assert factors[0] == factors[1] == factors[2]  # ... on the same builds
    for t in trials[1:]:
        # the score: the mean reward of the K builds of this design, simulated here on their own
        paid = []
        for u in t.user_attrs["robust_factors"]:
            b = build(cfg.with_values(t.user_attrs["design"]), DEFAULT_TOLERANCES, u)
            paid.append(0.0 if b.config is None else reward(simulate(b.config), b.config))
        assert t.value == pytest.approx(np.mean(paid), rel=0, abs=1e-12)
        assert len(t.user_attrs["traversals"]) == 4


@pytest.mark.parametrize("value", ["-1", "1.5"])
def test_robust_must_be_a_whole_number(tmp_path, value):
    db = tmp_path / "s.db"
    done = subprocess.run([sys.executable, "-m", "aero_env.cli", "tune", str(PAPER), f"--robust={value}",
                           "--storage", f"sqlite:///{db}", "--study", "s", "--no-progress"],
                          capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and f"--robust {value if value == '-1' else repr(value)}" in done.stderr
    assert "[0, 10000]" in done.stderr and not db.exists()  # refused before any study was made


def test_the_summary_says_who_traversed_the_whole_row():
    from agents.tune import TuneResult, summary_lines

    base = dict(study="s", storage="memory", sampler="cmaes", trials=3, trials_run=3, best_reward=5.5, best_design={},
                best_action=[], best_trial=2, best_score=dict(rewards=[], traversals=[0, 7], outcomes=[]),
                first_full_row_trial=None, full_row=7, wall_time=1.0, start_trial=0, start_reward=0.0,
                start_traversals=[0, 0], improved=True)
    assert summary_lines(TuneResult(**base))[1].endswith("; no trial traversed the whole row")
    own_did = summary_lines(TuneResult(**{**base, "start_traversals": [7, 7]}))[1]
    assert own_did.endswith("; no trial besides the config's own design traversed the whole row")
    found = summary_lines(TuneResult(**{**base, "first_full_row_trial": 2}))
    assert found[1].endswith("; the whole row first at trial 2")
    assert found[2] == "best 3.5/7 (mean reward 5.50) vs the config's own 0/7 (0.00): trial 2 beats it"
