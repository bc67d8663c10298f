"""Every design field over its whole schema range, at its edges and inside: a design either loads and runs (in the
single env, the vector env and tune's scoring, which its workers run) or is refused in one line naming a design
field and what is allowed. Nothing reaches Chipmunk's hard asserts, which abort the process (SIGABRT: Python cannot
catch it, so a training run or every tuning worker died with it), and no run returns a NaN."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
from dataclasses import fields

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import aero_env  # noqa: F401  (registers the environments)
from aero_env.config import ConfigError, Design, load_config
from aero_env.physics import World

from .conftest import COARSE, PAPER

DESIGN_FIELDS = {f"design.{f.name}": f.metadata for f in fields(Design) if f.type in (float, "float")}
SHORT = {**COARSE, "scene.frames": 2, "sim.t_max": 4.0}  # one transfer at the coarse step: the cheapest run


def _values(key: str):
    """A field's values: its two edges (the open one approached from inside), and inside its range, uniformly
    and (for a positive range) log-uniformly, so that small masses and lengths are tried as often as large."""
    m = DESIGN_FIELDS[key]
    lo, hi = m["lo"], m["hi"]
    low_edge = math.nextafter(lo, math.inf) if m["lo_open"] else lo
    inside = [st.floats(low_edge, hi)]
    if lo >= 0:
        tiny = max(low_edge, 1e-9)
        inside.append(st.floats(math.log(tiny), math.log(hi)).map(lambda x: min(hi, max(tiny, math.exp(x)))))
    return st.one_of(st.sampled_from([low_edge, hi]), *inside)


DESIGNS = st.lists(st.sampled_from(sorted(DESIGN_FIELDS)), min_size=1, max_size=4, unique=True).flatmap(
    lambda keys: st.fixed_dictionaries({k: _values(k) for k in keys}))


def _refused_well(message: str) -> bool:
    """One line naming a design field (``design.X = value``, or ``design (fields)`` from the bodies' last guard)
    and what it allows."""
    return "\n" not in message and message.startswith("design") and ("allowed" in message or "positive" in message)


def _load(overrides: dict):
    """The prototype with ``overrides`` at the cheapest step, or None where it is refused as it must be."""
    try:
        return load_config(PAPER, {**overrides, **SHORT})
    except ConfigError as exc:
        assert _refused_well(str(exc)), str(exc)
        return None


@pytest.mark.filterwarnings("ignore::aero_env.config.UnitSlipWarning")  # edges lie far from the prototype
@settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])  # examples from the profile: 300 in CI
@given(overrides=DESIGNS)
def test_every_design_the_config_accepts_builds_bodies_with_mass_and_inertia(overrides):
    cfg = _load(overrides)
    if cfg is None:
        return
    world = World(cfg)
    bodies = [b for b in world.space.bodies if b.body_type == b.DYNAMIC]
    assert len(bodies) >= 3  # the robot's torso and arm, and a frame at least
    for b in bodies:  # read back from pymunk: what Chipmunk was given
        assert math.isfinite(b.mass) and b.mass > 0 and math.isfinite(b.moment) and b.moment > 0, overrides


def _with_a_tunable_not_in(overrides: dict) -> dict:
    """One tunable on a field the example leaves alone, so that the action changes nothing the example set."""
    key = next(k for k in ("design.Cd", "design.rho", "design.robot_width") if k not in overrides)
    hi = DESIGN_FIELDS[key]["hi"]
    return {"tunable": [{"name": key, "low": 0.0, "high": hi}]}


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::aero_env.config.UnitSlipWarning")
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(overrides=DESIGNS)
def test_every_design_runs_whole_in_the_single_env_and_in_tunes_scoring(overrides):
    from agents.design_eval import DesignEvaluator

    cfg = _load(overrides)
    event("refused" if cfg is None else "ran")
    if cfg is None:
        return
    cfg = cfg.replace(_with_a_tunable_not_in(overrides))
    env = gym.make("aero_env/AerialAcrobat-v0", config=cfg)
    obs, _ = env.reset(seed=0)
    obs, reward, terminated, _, info = env.step(np.zeros(1, np.float32))
    assert terminated and math.isfinite(reward) and np.all(np.isfinite(obs)) and isinstance(info["outcome"], str)
    assert reward == (0.0 if info["outcome"] == "unstable" else info["traversals"])
    score = DesignEvaluator(cfg, seeds=[0, 1]).score(np.zeros(1))  # what each of tune's workers runs per trial
    assert score.rewards == (reward, reward)


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::aero_env.config.UnitSlipWarning")
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(overrides=DESIGNS, fidelity=st.sampled_from(["mbd", "reduced"]))
def test_every_design_runs_whole_in_the_vector_env_at_either_model(overrides, fidelity):
    cfg = _load(overrides)
    event("refused" if cfg is None else "ran")
    if cfg is None:
        return
    cfg = cfg.replace({**_with_a_tunable_not_in(overrides), "sim.fidelity": fidelity})
    envs = gym.make_vec("aero_env/AerialAcrobat-v0", num_envs=2, vectorization_mode="vector_entry_point", config=cfg)
    envs.reset(seed=0)
    obs, rewards, terminated, _, info = envs.step(np.array([[-1.0], [1.0]], np.float32))
    assert np.all(terminated) and np.all(np.isfinite(rewards)) and np.all(np.isfinite(obs))
    envs.close()


@pytest.mark.slow
def test_tunes_worker_processes_survive_a_design_at_every_edge(tmp_path):
    """A real ``aero-env tune --workers 2`` on the lightest arm, frame and torso the config allows and a frame
    moment at its limit: the workers (separate processes, where Chipmunk's abort killed every one) finish."""
    from aero_env.config.sections import frame_moment_limit, lightest_torso_card
    from aero_env.parts import build

    d = load_config(PAPER).design
    # the tunables move La over 0.75-1.35 x the config's: the frame at its longest is the heaviest lightest one, and
    # at its shortest holds its centre nearest the axis; every corner of the space must stay buildable
    longest, shortest = dataclasses.replace(d, La=1.35 * d.La), dataclasses.replace(d, La=0.75 * d.La)
    edges = {"design.arm_mass": build.lightest_plate(build.arm_net_length(d)) * 1.0001,
             "design.m1": 2 * build.lightest_plate(build.side_card_length(longest)) * 1.0001}
    edges["design.dT"] = frame_moment_limit(dataclasses.replace(shortest, m1=edges["design.m1"])) * 0.9999
    edges["design.m2"] = (edges["design.arm_mass"] + d.coin_mass + d.handrail_mass
                          + lightest_torso_card(d)) * 1.0001
    edges["design.m3"] = 0.005  # inside the tunable's 0.5-1.6 x m2 (5.7 g now), a multiple of its 0.1 g
    sets = [a for k, v in {**edges, **SHORT}.items() for a in ("--set", f"{k}={float(v) if k in edges else v!r}")]
    r = subprocess.run([sys.executable, "-m", "aero_env.cli", "tune", str(PAPER), *sets, "--trials", "4",
                        "--workers", "2", "--seeds-per-design", "1", "--no-progress", "--out",
                        str(tmp_path / "best.yaml")], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "study " in r.stdout and (tmp_path / "best.yaml").is_file()
