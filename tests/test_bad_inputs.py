"""The smaller slips a hostile but honest user met (issue 50): each is one line naming what is wrong, or a word
before a long wait, never a raw error."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import aero_env  # noqa: F401  (registers the environments)
from aero_env.cli import main
from aero_env.config import ConfigError

from .conftest import PAPER


@pytest.fixture(scope="module")
def env():
    return gym.make("aero_env/AerialAcrobat-v0", config=str(PAPER))


@pytest.mark.parametrize("value, refusal", [
    (float("nan"), "design.m3 = nan: must be finite, in (0.0, 0.1] kg"),
    (float("inf"), "design.m3 = inf: must be finite, in (0.0, 0.1] kg"),
    (None, "design.m3 = None: must be a number (float) in (0.0, 0.1] kg"),
    ([1], "design.m3 = [1]: must be a number (float) in (0.0, 0.1] kg"),
    ("seven", "design.m3 = 'seven': must be a number (float) in (0.0, 0.1] kg"),
    (0.5, "design.m3 = 0.5: out of range, allowed (0.0, 0.1] kg"),
])
def test_action_for_reads_a_value_as_the_config_does(env, value, refusal):
    with pytest.raises(ConfigError) as err:
        env.unwrapped.action_for({"design.m3": value})
    assert str(err.value).startswith(refusal) and "\n" not in str(err.value)


def test_action_for_takes_a_value_with_its_unit(env):
    # 7.2 g written with its unit is the prototype's 0.0072 kg: the same action, bit for bit
    assert np.array_equal(env.unwrapped.action_for({"design.m3": "7.2 g"}), env.unwrapped.action_for())
    assert np.array_equal(env.unwrapped.action_for({"design.m3": 0.0072}), env.unwrapped.action_for())


@pytest.mark.parametrize("options, refusal", [
    ("abc", "reset(options='abc'): must be a dict or None"),
    ([("reset_mask", True)], "reset(options=[('reset_mask', True)]): must be a dict or None"),
    ({"seed": 3}, "reset(options=...): 'seed' is not an option of this env (it reads none)"),
])
def test_reset_refuses_options_it_would_ignore(env, options, refusal):
    with pytest.raises(ConfigError) as err:
        env.reset(options=options)
    assert str(err.value) == refusal
    env.reset(options={})  # an empty dict and None are no options
    env.reset(options=None)


def test_the_vector_env_reads_its_reset_mask_and_refuses_the_rest():
    envs = gym.make_vec("aero_env/AerialAcrobat-v0", num_envs=2, vectorization_mode="vector_entry_point")
    with pytest.raises(ConfigError, match=r"^reset\(options='abc'\): must be a dict or None$"):
        envs.reset(options="abc")
    with pytest.raises(ConfigError, match=r"'mask' is not an option of this env \(it reads 'reset_mask'\)$"):
        envs.reset(options={"mask": np.array([True, False])})
    envs.reset(seed=0)
    envs.reset(options={"reset_mask": np.array([True, False])})
    envs.close()


def test_the_first_reduced_run_on_an_empty_cache_says_it_compiles(tmp_path, monkeypatch, capsys):
    from aero_env.models import reduced

    monkeypatch.setattr(reduced, "_loaded", False)  # as in a new process
    monkeypatch.setattr(reduced, "kernel_cache_dir", lambda source=None: tmp_path)  # nothing compiled there
    reduced.compile_kernels()
    err = capsys.readouterr().err
    assert err.startswith("aero-env: compiling the reduced model for this version") and str(tmp_path) in err
    assert err.count("\n") == 1
    # a cache that holds the batch kernel's index: loaded, not compiled, and nothing said
    (tmp_path / "reduced_0123").mkdir()
    (tmp_path / "reduced_0123" / "run.run_batch-240.py311.nbi").write_bytes(b"")
    monkeypatch.setattr(reduced, "_loaded", False)
    reduced.compile_kernels()
    assert capsys.readouterr().err == ""


def test_a_measured_trace_that_is_not_text_is_one_line(tmp_path, capsys):
    trace = tmp_path / "swing.csv"
    trace.write_bytes(bytes(range(256)) * 8)  # a binary file named .csv
    assert main(["calibrate", str(PAPER), "--trace", str(trace)]) == 2
    assert capsys.readouterr().err == (f"aero-env: error: --trace {str(trace)!r}: not a text file; expected a CSV "
                                       f"with columns t, theta1_deg\n")


def test_the_tune_summary_names_the_card_pair_the_tuned_design_holds(paper_cfg):
    """A tuned white/white pair (0.507/0.337) on the prototype's config (white/gray, 0.542/0.409) is white/white,
    0 % off: the summary once read mu_k as the study config's ratio times mu_s (0.383) and named white/gray."""
    from agents.tune import TuneResult, summary_lines

    result = TuneResult(study="s", storage="memory", sampler="cmaes", trials=1, trials_run=1, best_reward=7.0,
                        best_design={"design.mu_s": 0.507, "design.mu_k": 0.337}, best_action=[], best_trial=0,
                        best_score=dict(rewards=[7.0], traversals=[7], outcomes=["completed"]),
                        first_full_row_trial=0, full_row=7, wall_time=1.0)
    lines = summary_lines(result, paper_cfg)
    assert "  design.mu_s = 0.507   (nearest card pair: white arm on white handrail, 0 % off)" in lines


def test_workers_that_cannot_go_on_end_the_tune_in_one_line(tmp_path, monkeypatch, capsys):
    """A worker's error (a study file damaged in the middle of a run, say) or too many deaths: one line saying so
    and where the finished trials are, status 1; it was a RuntimeError traceback."""
    from agents import tune
    from agents.tune_workers import WorkersFailed

    def failing(*_args, **_kwargs):
        raise WorkersFailed("tuning workers failed: worker h:1:w0: DatabaseError: database disk image\nis malformed")

    monkeypatch.setattr(tune, "tune", failing)
    monkeypatch.chdir(tmp_path)
    assert main(["tune", str(PAPER), "--storage", "sqlite:///s.db", "--workers", "2", "--no-progress"]) == 1
    assert capsys.readouterr().err == ("aero-env tune: stopped: tuning workers failed: worker h:1:w0: DatabaseError: "
                                       "database disk image is malformed; the study's finished trials are kept in "
                                       "study 'paper-cmaes-s0' (sqlite:///s.db)\n")
