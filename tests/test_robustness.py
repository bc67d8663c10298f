"""``aero-env robustness``: seeded draws within tolerances, single changes, effects, the Wilson interval.

Fast by construction: the real physics runs only on 3-frame rows (``scene.frames=3``) and a few
draws; the checks of ranking and reporting use a stand-in simulator whose breaking point is known,
so they do not depend on today's physics.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.stats import binomtest

import aero_env.simulation
from aero_env.cli import main
from aero_env.config import load_config
from aero_env.robustness import DEFAULT_TOLERANCES, Tol, assess, parse_tolerances
from aero_env.robustness.progress import RunProgress
from aero_env.robustness.draws import INVALID, build, draw_factors
from aero_env.robustness.report import summarize
from aero_env.robustness.tolerances import check_against

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "configs" / "paper.yaml"
FAST = {"scene.frames": 3}
NOMINAL_M3 = load_config(PAPER).design.m3
BREAK_ABOVE = 1.2  # the stand-in simulator's row breaks when m3 exceeds this multiple of the paper's m3

# m3 listed last, so a ranking that fell back on table order would not put it first
SMALL = [
    {"name": "design.La", "absolute": 0.0005},
    {"name": "design.spring_k", "relative": 0.15},
    {"name": "design.mu_s", "relative": 0.10, "linked": ["design.mu_k"]},
    {"name": "design.m3", "relative": 0.5},
]


def stand_in(cfg):
    """A simulator with a known cliff: the row breaks when the counterbalance is too heavy."""
    full = cfg.scene.frames - 1
    ok = cfg.design.m3 <= BREAK_ABOVE * NOMINAL_M3
    return SimpleNamespace(traversals=full if ok else 0, outcome="completed" if ok else "stalled",
                           reason="stand-in")


def _no_simulation(cfg):
    raise AssertionError("a bad input must be rejected before anything is simulated")


def _without_wall(report: dict) -> dict:
    return {k: v for k, v in report.items() if k != "wall_time"}


def _cli_json(*extra: str, hash_seed: str) -> dict:
    cmd = [sys.executable, "-m", "aero_env.cli", "robustness", str(PAPER), "--draws", "4", "--seed", "3", "--json",
           "--set", "scene.frames=3", *extra]
    env = {**os.environ, "PYTHONHASHSEED": hash_seed}
    out = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    # stderr holds the progress bar only (as tune's); stdout the one JSON object
    assert [ln for ln in out.stderr.replace("\r", "\n").splitlines() if ln.strip()
            and not ln.startswith("robustness:")] == [], out.stderr
    return json.loads(out.stdout)


@pytest.mark.slow
def test_same_json_in_two_processes_and_with_two_workers():
    one = _cli_json("--workers", "1", hash_seed="1")
    two = _cli_json("--workers", "2", hash_seed="2")
    assert one["draws"] == 4 and one["seed"] == 3 and len(one["tolerances"]) == len(DEFAULT_TOLERANCES)
    assert _without_wall(one) == _without_wall(two)


def test_workers_1_and_2_give_the_same_runs_in_draw_order():
    cfg = load_config(PAPER, FAST)
    tols = parse_tolerances(SMALL)
    a = assess(cfg, tols, draws=8, seed=5, workers=1)
    b = assess(cfg, tols, draws=8, seed=5, workers=2)
    assert a.runs == b.runs and a.singles == b.singles and a.nominal == b.nominal
    assert len({r.reason for r in a.runs}) > 1  # the runs differ, so an order change would show
    assert _without_wall(summarize(a, 0.0)) == _without_wall(summarize(b, 0.0))


def test_zero_tolerances_build_the_nominal_machine_every_draw():
    cfg = load_config(PAPER, FAST)
    zero = tuple(Tol(t.name, linked=t.linked) for t in DEFAULT_TOLERANCES)
    study = assess(cfg, zero, draws=3, seed=0)
    for b, r in zip(study.builds, study.runs):
        assert b.config == cfg and all(v == cfg.value(k) for k, v in b.values.items())
        assert r == study.nominal
    assert study.singles == [] and summarize(study, 0.0)["effects"] == []


def test_a_breaking_tolerance_tops_single_changes_and_effects():
    cfg = load_config(PAPER, FAST)
    r = summarize(assess(cfg, parse_tolerances(SMALL), draws=40, seed=1, simulator=stand_in), 0.0)
    top = r["single_changes"][0]
    assert (top["name"], top["end"], top["breaks"]) == ("design.m3", "+", True)
    assert [c for c in r["single_changes"] if c["breaks"]] == [top]
    assert r["effects"][0]["name"] == "design.m3" and r["effects"][0]["difference"] < 0
    assert abs(r["effects"][0]["difference"]) > max(abs(e["difference"]) for e in r["effects"][1:])
    assert r["effects"][0]["share_low"] == 1.0


def test_a_counterbalance_half_again_too_heavy_breaks_the_real_row():
    """Physics, not a stand-in: m3 x 1.5 outweighs the robot (m3·La > m2·Lb), so the first frame stalls with the
    robot on it, whatever the nominal design does today; that change ranks with the worst."""
    cfg = load_config(PAPER, FAST)
    r = summarize(assess(cfg, parse_tolerances(SMALL), draws=1, seed=0), 0.0)
    heavy = next(c for c in r["single_changes"] if (c["name"], c["end"]) == ("design.m3", "+"))
    assert (heavy["traversals"], heavy["outcome"], heavy["breaks"]) == (0, "stalled", True)
    assert r["single_changes"][0]["traversals"] == 0


def test_the_friction_pair_moves_together_and_keeps_mu_k_below_mu_s():
    cfg = load_config(PAPER)
    ratio = cfg.design.mu_k / cfg.design.mu_s
    builds = [build(cfg, DEFAULT_TOLERANCES, u) for u in draw_factors(0, 500, len(DEFAULT_TOLERANCES))]
    mu_s = np.array([b.values["design.mu_s"] for b in builds])
    mu_k = np.array([b.values["design.mu_k"] for b in builds])
    assert np.all(mu_k <= mu_s) and np.allclose(mu_k / mu_s, ratio, rtol=1e-12)
    assert mu_s.min() < 0.92 * cfg.design.mu_s and mu_s.max() > 1.08 * cfg.design.mu_s


def test_the_default_table_builds_only_valid_prototypes():
    """Linked fields (mu_k, coin_offset) keep the config's cross-checks; a failure names the check it broke."""
    cfg = load_config(PAPER)
    errors = [b.error for b in (build(cfg, DEFAULT_TOLERANCES, u)
                                for u in draw_factors(0, 500, len(DEFAULT_TOLERANCES))) if b.error]
    assert errors == [], f"{len(errors)} of 500 invalid, e.g. {errors[0]}"


def test_a_build_outside_the_allowed_design_is_counted_invalid_not_a_crash():
    cfg = load_config(PAPER, FAST)
    unlinked = parse_tolerances([{"name": "design.mu_s", "relative": 0.5}])  # mu_s below mu_k in some builds
    r = summarize(assess(cfg, unlinked, draws=20, seed=0, simulator=stand_in), 0.0)
    assert 0 < r["outcomes"][INVALID] < 20 and r["completed"] == 20 - r["outcomes"][INVALID]
    assert "design.mu_k" in r["invalid_reasons"][0]
    assert [c["outcome"] for c in r["single_changes"]] == [INVALID, "completed"]


BAD_FILES = {
    "not_a_list": ("design.m3: 0.1\n", "non-empty list"),
    "empty": ("[]\n", "non-empty list"),
    "unknown_key": ("- {name: design.m3, relative: 0.1, sigma: 2}\n", "[0].sigma: unknown key"),
    "no_name": ("- {relative: 0.1}\n", "[0].name: missing"),
    "unknown_field": ("- {name: design.nope, relative: 0.1}\n", "[0].name = 'design.nope'"),
    "integer_field": ("- {name: scene.frames, absolute: 1}\n", "[0].name = 'scene.frames'"),
    "relative_too_big": ("- {name: design.m3, relative: 0.7}\n", "[0].relative = 0.7: must be a finite number in [0, 0.5]"),
    "negative_absolute": ("- {name: design.La, absolute: -0.001}\n", "[0].absolute = -0.001"),
    "not_a_number": ("- {name: design.La, absolute: lots}\n", "[0].absolute = 'lots'"),
    "no_amount": ("- {name: design.La}\n", "[0] (design.La): give relative"),
    "linked_not_list": ("- {name: design.mu_s, relative: 0.1, linked: design.mu_k}\n", "[0].linked = 'design.mu_k'"),
    "linked_to_itself": ("- {name: design.mu_s, relative: 0.1, linked: [design.mu_s]}\n", "[0].linked[0]"),
    "twice": ("- {name: design.m3, relative: 0.1}\n- {name: design.m3, relative: 0.2}\n", "[1].name = 'design.m3'"),
    "linked_and_listed": ("- {name: design.mu_s, relative: 0.1, linked: [design.mu_k]}\n"
                          "- {name: design.mu_k, relative: 0.1}\n", "[1].name = 'design.mu_k': already varied"),
    "bad_yaml": ("- {name: design.m3, relative: [0.1\n", "not valid YAML"),
}


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_a_bad_tolerance_file_is_one_line_exit_2_nothing_simulated(case, tmp_path, monkeypatch, capsys):
    text, expected = BAD_FILES[case]
    path = tmp_path / "tol.yaml"
    path.write_text(text)
    monkeypatch.setattr(aero_env.simulation, "simulate", _no_simulation)
    assert main(["robustness", str(PAPER), "--tolerances", str(path), "--draws", "2"]) == 2
    err = capsys.readouterr().err
    kind = "file error" if case == "bad_yaml" else "config error"  # the file unread; a value in it
    assert err.startswith(f"aero-env: {kind}: ") and err.count("\n") == 1, err
    assert expected in err


@pytest.mark.parametrize("args", [["--tolerances", "/nonexistent/tol.yaml"], ["--draws", "0"], ["--workers", "0"]])
def test_a_missing_file_or_bad_count_is_exit_2(args, monkeypatch, capsys):
    monkeypatch.setattr(aero_env.simulation, "simulate", _no_simulation)
    assert main(["robustness", str(PAPER), *args]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_the_report_uses_the_wilson_interval_of_its_counts():
    cfg = load_config(PAPER, FAST)
    r = summarize(assess(cfg, parse_tolerances(SMALL), draws=30, seed=2, simulator=stand_in), 0.0)
    ref = binomtest(r["completed"], r["draws"]).proportion_ci(method="wilson")
    assert r["share_ci95"] == pytest.approx([ref.low, ref.high], abs=1e-12)
    assert sum(r["outcomes"].values()) == r["draws"] == 30


def test_default_table_applies_to_the_prototype_and_covers_the_brief():
    check_against(load_config(PAPER), DEFAULT_TOLERANCES)
    names = {t.name for t in DEFAULT_TOLERANCES}
    assert {"design.La", "design.Lb", "design.h", "design.arm_length", "scene.pitch", "design.m1", "design.m2",
            "design.m3", "design.arm_mass", "design.spring_k", "design.mu_s", "design.rest_angle_deg"} <= names
    assert all(t.reason for t in DEFAULT_TOLERANCES)


def test_the_table_and_the_progress_bar(tmp_path, monkeypatch, capsys):
    path = tmp_path / "tol.yaml"
    path.write_text(json.dumps(SMALL))  # JSON is YAML
    monkeypatch.setattr(aero_env.simulation, "simulate", stand_in)
    argv = ["robustness", str(PAPER), "--draws", "5", "--tolerances", str(path), "--set", "scene.frames=3"]
    assert main([*argv, "--no-progress"]) == 0
    out, err = capsys.readouterr()
    assert "of 5 builds" in out
    assert "single changes" in out and "1 of 8 break the row" in out and "effects in the random draws" in out
    assert err == ""
    # as tune shows its trials: a bar of the runs on stderr, whatever stderr is; --json's stdout stays one object
    assert main([*argv, "--json"]) == 0
    out, err = capsys.readouterr()
    runs = 1 + 8 + 5  # the nominal build, the single changes, the draws
    assert json.loads(out)["draws"] == 5
    assert "robustness" in err and f"{runs}/{runs}" in err and "run" in err, err
    # without tqdm (the core install) the same count as a line rewritten in place
    monkeypatch.setitem(sys.modules, "tqdm", None)
    tty = SimpleNamespace(written=[])
    tty.write, tty.flush = tty.written.append, lambda: None
    progress = RunProgress("robustness", stream=tty)
    progress(1, 2), progress(2, 2)
    assert "".join(tty.written) == "\rrobustness: 1/2 runs\rrobustness: 2/2 runs\n"
