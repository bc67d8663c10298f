"""Hard cases stay numerically stable, or say they are not: corners of the action space, extreme
springs, masses and friction, large time steps, a 100-frame row, the hook on the handrail's edge;
the golden record of the prototype's run."""

import itertools
import json
import math
from unittest import mock

import gymnasium as gym
import numpy as np
import pytest

import aero_env  # noqa: F401
from aero_env.config import load_config
from aero_env.physics import simulate
from aero_env.physics import run as run_module
from aero_env.physics import body_state, check_kernel
from aero_env.physics import world as world_module
from aero_env.physics.swing_frame import FLOOR

from .conftest import PAPER
from .golden import tolerances
from .golden.regenerate import GOLDEN, golden_record
from .invariants import OUTCOMES, check_run, finite_everywhere, observed_run, observing

# Every run here is judged by tests/invariants.py (check_run): energy, joint drift, stopper overshoot,
# penetration and speed recounted from pymunk's bodies after every step, against the config's limits. A run
# the runner calls healthy stayed within them; a run it calls unstable broke one.


# ---- the action space's corners (tuners live there) ----
CORNERS = list(itertools.product((-1.0, 1.0), repeat=5))


def test_every_corner_of_the_action_space_stays_sane():
    env = gym.make("aero_env/AerialAcrobat-v0", **{"scene.frames": 3})
    outcomes = set()
    for corner in CORNERS:
        obs, _ = env.reset(seed=0)
        with observing(keep_rows=False) as seen:
            obs, reward, terminated, truncated, info = env.step(np.array(corner, np.float32))
        assert np.all(np.isfinite(obs)) and math.isfinite(reward) and terminated and not truncated
        finite_everywhere(info)
        cfg, _ = env.unwrapped.space.episode_config(info["design"], env.unwrapped._draw)
        assert len(seen) == 1 and seen[0].world.cfg == cfg
        check_run(env.unwrapped.last_run, seen[0], cfg)
        if info["outcome"] == "unstable":
            assert reward == 0.0
        outcomes.add(info["outcome"])
    assert len(outcomes) >= 3  # the corners are not all one failure


# ---- extreme designs ----
EXTREMES = {
    # 100x the prototype's spring on the 1.5 g arm: the arm's tip would move 7 mm per step at dt = 0.5 ms
    "spring x100": ({"design.spring_k": 0.0877}, {"unstable"}),
    "spring x100, dt 50 us": ({"design.spring_k": 0.0877, "sim.dt": 5e-5}, {"missed_catch"}),
    "masses x0.1": ({"design.m1": 0.0004, "design.m2": 0.000771, "design.m3": 0.00072, "design.arm_mass": 0.00015,
                     "design.coin_mass": 0.0004, "design.handrail_mass": 0.000021}, OUTCOMES - {"unstable"}),
    "masses x10": ({"design.m1": 0.04, "design.m2": 0.0771, "design.m3": 0.072, "design.arm_mass": 0.015,
                    "design.coin_mass": 0.04, "design.handrail_mass": 0.0021}, OUTCOMES - {"unstable"}),
    "friction 0": ({"design.mu_s": 0.0, "design.mu_k": 0.0}, {"fell_short"}),
    "friction 2": ({"design.mu_s": 2.0, "design.mu_k": 2.0}, {"no_detach"}),
    # the arm held against its stopper by the stiffest spring the action space allows
    "arm on its stop": ({"design.spring_k": 4e-3}, OUTCOMES - {"unstable"}),
}


@pytest.mark.parametrize("name", sorted(EXTREMES))
def test_extreme_designs_stay_sane_or_say_unstable(paper_cfg, name):
    overrides, allowed = EXTREMES[name]
    cfg = paper_cfg.replace({**overrides, "scene.frames": 3})
    result, observer = observed_run(cfg, keep_rows=False)
    check_run(result, observer, cfg)
    assert result.outcome in allowed, result.reason
    if result.outcome == "unstable":
        assert "sim.dt" in result.reason  # and says what to do about it


# ---- time steps: a step too large is reported, never a wrong result ----
# At 2 ms the hook falls about 3 mm per step, as wide as the band (its 1 mm radius and the 1 mm card's half
# each side of the card's middle) in which the contact sees a card. With the earlier fitted robot, twice Table
# 1's size, its centre crossed frame 1's front card in one step and was called a graze that no monitor saw
# (strict xfails here); the runner's tunnelling watch (monitors.TunnelWatch) now calls such a step unstable.
# With the Table 1 robot the landing sinks the hook 1.3 mm into the card, past sim.max_penetration: unstable
# too. At 1 ms the hook moves 1.5 mm per step and stays on its side.
@pytest.mark.parametrize("dt", [0.00025, 0.001, 0.002, 0.005, 0.01])
def test_large_time_steps_agree_or_say_unstable(paper_cfg, dt):
    hold = {"sim.dt": dt, "sim.contact_hold": max(0.01, 5 * dt), "scene.frames": 3}
    for design, reference in (({}, "completed"), ({"design.spring_k": 8.77e-5}, "missed_catch")):  # brief: too weak
        cfg = paper_cfg.replace({**hold, **design})
        result, observer = observed_run(cfg, keep_rows=False)
        check_run(result, observer, cfg)
        assert result.outcome in (reference, "unstable"), f"dt={dt}: {result.outcome} ({result.reason})"


def test_the_default_time_step_has_a_margin(paper_cfg):
    # half the default step and twice it agree with it; four times it is reported unstable
    outcomes = {dt: simulate(paper_cfg.replace({"sim.dt": dt})).outcome for dt in (0.00025, 0.001, 0.002)}
    assert outcomes == {0.00025: "completed", 0.001: "completed", 0.002: "unstable"}


# ---- a long row: no drift, no cost growing with the row ----
def test_a_100_frame_row_does_not_drift_or_slow_down(paper_cfg, paper_run, monkeypatch):
    calls = {"n": 0}
    read_state = body_state.state  # what Python reads a body with
    read_world = check_kernel.read_world  # what a check reads the world with, compiled (World.sample)

    def counted(b):
        calls["n"] += 1
        return read_state(b)

    def counted_world(addresses, props, live, *rest):
        calls["n"] += len(live) + 2  # the live frames and the robot's two bodies
        return read_world(addresses, props, live, *rest)

    monkeypatch.setattr(body_state, "state", counted)
    monkeypatch.setattr(check_kernel, "read_world", counted_world)
    cfg = paper_cfg.replace({"scene.frames": 100, "sim.t_max": 120.0})  # 99 swings of ~0.63 s
    # measured every 7th step (off the runner's 10-step check cadence; the 8-frame row is measured every
    # step in test_invariants): 63 s of row take four times as long measured every step
    long, observer = observed_run(cfg, every=7, keep_rows=False)
    per_step_long = calls["n"] / (long.sim_time / cfg.sim.dt)
    calls["n"] = 0
    short = simulate(paper_cfg)
    per_step_short = calls["n"] / (short.sim_time / cfg.sim.dt)
    assert long.outcome == "completed" and long.traversals == 99
    check_run(long, observer, cfg)
    # the checks read the live bodies only: their cost per step does not grow with the row
    assert per_step_short > 0.3 and per_step_long == pytest.approx(per_step_short, rel=0.1)
    # the motion settles into a cycle instead of drifting: late swings look like early ones
    detach = [s.theta1_detach_deg for s in long.swings if s.theta1_detach_deg is not None]
    duration = [s.swing_duration for s in long.swings[1:] if s.swing_duration is not None]
    assert max(detach[-20:]) - min(detach[-20:]) < 5.0 and abs(np.mean(detach[-20:]) - np.mean(detach[1:8])) < 3.0
    assert abs(np.mean(duration[-20:]) - np.mean(duration[:6])) < 0.02
    assert long.health["joint_drift"] <= 1.5 * paper_run.health["joint_drift"]


# ---- the hook on the handrail's edge ----
def test_the_hook_landing_anywhere_on_the_next_handrail_stays_sane(paper_cfg):
    # moving the next frame changes where the falling hook meets its handrail: in the notch's
    # corner, on a face, on the face's free edge, or past it
    outcomes = set()
    for pitch in np.linspace(0.072, 0.094, 9):
        cfg = paper_cfg.replace({"scene.pitch": float(pitch), "scene.frames": 2})
        result, observer = observed_run(cfg, keep_rows=False)
        check_run(result, observer, cfg)
        outcomes.add(result.outcome)
    assert "completed" in outcomes and len(outcomes) >= 2


def test_the_stoppers_hold(paper_run, paper_cfg):
    # after the hook lets go at about 4 rad/s, the emptied frame swings on and hits its stopper; the
    # arm hits its own stopper as the spring snaps it forward. Both give by little, and by less at a finer
    # step: the give is the solver's (first order in the step), not the machine's. Measured: 1.12 deg at the
    # default 0.5 ms (the Table 1 robot's light torso lets the arm snap onto alpha_min fast), 0.46 at
    # mbd-fine, 0.09 at reference (the corner test above checks the action space's extremes).
    first_swing = paper_run.trace["t"] < paper_run.swings[0].t_detach
    assert np.abs(paper_run.trace["omega1"][first_swing]).max() > 3.0  # measured 4.1 rad/s
    assert 0.0 < paper_run.health["limit_overshoot_deg"] < 1.5
    fine = simulate(paper_cfg.replace({"sim.fidelity": "mbd-fine"}))
    assert fine.health["limit_overshoot_deg"] < 0.6 * paper_run.health["limit_overshoot_deg"]


# ---- determinism: the golden record ----
@pytest.fixture(scope="module")
def golden():
    """(the record on file, this build's record), both through the same JSON round trip."""
    return json.loads(GOLDEN.read_text()), json.loads(json.dumps(golden_record()))


def test_the_prototype_reproduces_its_golden_record_bit_for_bit(golden):
    """On this platform (this libm, this pymunk build): every number and every trace row's hash."""
    expected, actual = golden
    assert actual == expected, "the physics changed: if on purpose, run python tests/golden/regenerate.py"


def _seconds_per_row():
    sim = load_config(PAPER).sim
    return sim.dt * sim.substeps * sim.trace_every


def test_the_prototype_agrees_with_its_golden_record_within_stated_tolerances(golden):
    """What must hold on any platform: exact outcome, traversals and catching frames; every event and
    energy within the tolerances tests/golden/tolerances.py measured (a libm's last-bit differences)."""
    expected, actual = golden
    assert tolerances.departures(actual, expected, _seconds_per_row()) == []


def test_the_golden_tolerances_absorb_last_bit_changes_and_catch_physical_ones(golden, paper_cfg):
    expected, _ = golden
    d = paper_cfg.design

    def record(overrides):
        r = simulate(paper_cfg.replace(overrides), trace=True)
        return json.loads(json.dumps({**r.to_json_dict(), "trace_rows": len(r.trace["t"])}))

    # a libm's worth of difference (m1 one part in 1e15): the run differs in its last bits, within tolerance
    nudged = record({"design.m1": d.m1 * (1 + 1e-15)})
    assert nudged["swings"] != expected["swings"]  # the run did change: the hash test alone would refuse it
    assert tolerances.departures(nudged, expected, _seconds_per_row()) == []
    # a physical change: the counterbalance 1 % heavier moves the detaches (measured 7.5 ms, 1.0 deg)
    heavier = tolerances.departures(record({"design.m3": d.m3 * 1.01}), expected, _seconds_per_row())
    assert any(".t_detach" in line for line in heavier), heavier


def test_a_fall_ends_when_the_hook_reaches_the_floor_before_the_floors_impact(paper_cfg):
    """Found by the property test (tests/test_properties.py): a stiff spring misses frame 1 and the robot falls
    until its hook strikes the floor; the solver answers that impact by giving 0.34 mJ back within two steps,
    above sim.energy_tolerance, between two of the runner's 5 ms checks. A fall is over when the hook touches
    the floor, so the run ends there, at the first step pymunk reports the hook on the floor segment, and every
    step it ran stays within every limit (the observer reads each one)."""
    cfg = paper_cfg.replace({"scene.frames": 2, "design.m3": 0.0107458125, "design.h": 0.012980625,
                             "design.La": 0.050715, "design.spring_k": 0.002706221736673107,
                             "design.mu_s": 0.5477225575051662, "design.mu_k": 0.4133183136893228})
    on_floor = []

    class Watched(world_module.World):
        def step(self):
            super().step()
            hits = []
            self.robot.arm.each_arbiter(lambda arb: hits.append(arb.shapes[1].collision_type == FLOOR))
            if any(hits) and not on_floor:
                on_floor.append(self.t)

    result, observer = observed_run(cfg, keep_rows=False)
    check_run(result, observer, cfg)
    with mock.patch.object(run_module, "World", Watched):
        watched = run_module.simulate(cfg)
    assert (watched.outcome, watched.sim_time) == (result.outcome, result.sim_time)  # the same run, watched
    assert result.outcome == "missed_catch" and on_floor, result.reason
    assert result.sim_time == pytest.approx(on_floor[0], abs=cfg.sim.dt)
