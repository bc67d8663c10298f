"""Hard cases stay numerically stable, or say they are not: corners of the action space, extreme
springs, masses and friction, large time steps, a 100-frame row, the hook on the handrail's edge;
the golden record of the prototype's run."""

import copy
import itertools
import json
import math
from unittest import mock

import gymnasium as gym
import numpy as np
import pymunk
import pytest

import aero_env  # noqa: F401
from aero_env.config import load_config
from aero_env.physics import simulate
from aero_env.physics import run as run_module
from aero_env.physics import body_state, check_kernel, monitors
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


@pytest.mark.slow
def test_every_corner_of_the_action_space_stays_sane():
    env = gym.make("aero_env/AerialAcrobat-v0", **{"scene.frames": 3})
    outcomes = set()
    for corner in CORNERS:
        obs, _ = env.reset(seed=0)
        with observing(keep_rows=False) as seen:
            obs, reward, terminated, truncated, info = env.step(np.array(corner, np.float32))
        # an episode ends by itself: nothing truncates it (the env's Episode End)
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
# With the Table 1 robot the landing sank the hook 1.3 mm into the card, past sim.max_penetration: unstable
# too; built from the kit's parts, the hook goes through frame 2's card on the 3-frame row, and the tunnelling
# watch calls it. At 1 ms the hook moves 1.5 mm per step and stays on its side.
@pytest.mark.parametrize("dt", [0.00025, 0.001, 0.002, 0.005, 0.01])
def test_large_time_steps_agree_or_say_unstable(paper_cfg, dt):
    hold = {"sim.dt": dt, "sim.contact_hold": max(0.01, 5 * dt), "scene.frames": 3}
    for design, reference in (({}, "completed"), ({"design.spring_k": 8.77e-5}, "missed_catch")):  # brief: too weak
        cfg = paper_cfg.replace({**hold, **design})
        result, observer = observed_run(cfg, keep_rows=False)
        check_run(result, observer, cfg)
        assert result.outcome in (reference, "unstable"), f"dt={dt}: {result.outcome} ({result.reason})"


# ---- the tunnelling watch, on a crossing no other monitor sees ----
# At dt = 1-10 ms above, every run the watch would call unstable is caught first by the energy or penetration
# monitor, so those runs cannot show the watch works. Here the crossing is made by hand: the hook is put on the
# far side of a card's middle line between two steps, where it does not touch the card (no contact, no
# penetration) and lower than it was (no energy gained). The geometry is pymunk's own (each handrail Segment's
# a-b in its body's coordinates, the hook Circle's offset on the arm), not the watch's face table.
def _mirror_across(rail, centre):
    """(signed distance of world point ``centre`` from ``rail``'s middle line, its fraction along the segment,
    the world point mirrored across that line): pymunk geometry only."""
    p = rail.body.world_to_local(centre)
    u = (rail.b - rail.a).normalized()
    n = pymunk.Vec2d(u.y, -u.x)
    d = (p - rail.a).dot(n)
    return d, (p - rail.a).dot(u) / (rail.b - rail.a).length, rail.body.local_to_world(p - 2.0 * d * n)


def test_the_tunnel_watch_sees_a_hook_centre_cross_a_cards_middle_line(paper_cfg):
    """TunnelWatch on points set by hand: the hook's centre placed 3 mm before and 3 mm behind the middle of each
    of frame 1's two card faces (beyond the 1.5 mm the contact keeps, so nothing touches) is a crossing;
    the same moves that stay on one side, or cross the line beyond the card's end, are not."""
    world = world_module.World(paper_cfg.replace({"scene.frames": 2}))
    arm, hook, frame = world.robot.arm, world.robot.tip, world.frames[1]

    def put_hook(local):  # the hook's centre at frame-1-local ``local``: the arm moved as one piece
        target = frame.body.local_to_world(local)
        arm.position += target - arm.local_to_world(hook.offset)

    def watch_over(path):  # a fresh watch, stepped once at each point of ``path``: what it said each time
        watch = monitors.TunnelWatch(world, frame)
        said = []
        for local in path:
            put_hook(local)
            said.append(watch.step())
        return said, watch

    assert len(frame.shapes) == 2
    for rail in frame.shapes:
        u = (rail.b - rail.a).normalized()
        n = pymunk.Vec2d(u.y, -u.x)
        mid, length = (rail.a + rail.b) / 2, (rail.b - rail.a).length
        front, back = mid + 3.0 * n, mid - 3.0 * n
        said, watch = watch_over([front, back])
        assert said[0] is None and said[1] is not None and watch.crossed, said
        assert said[1].startswith("the hook's centre went through frame 1's handrail card between two steps")
        assert "moved 6.00 mm in one step" in said[1] and "sim.dt" in said[1]
        # the way back is a crossing too; moves on one side, or past the card's end, are not
        assert watch_over([back, front])[0][1] is not None
        assert watch_over([front, front + 2.0 * u])[0] == [None, None]
        beyond = rail.b + (0.5 * length) * u
        said, watch = watch_over([beyond + 3.0 * n, beyond - 3.0 * n])
        assert said == [None, None] and not watch.crossed
    # a crossing sank the hook at least its radius plus half the card (the config's values)
    assert watch.depth() == pytest.approx(paper_cfg.design.hook_radius + 0.5 * paper_cfg.design.handrail_thickness)


def _jumped_world(moves: list):
    """A World that, once, at the first step its hook's centre is 0-3 mm outside the contact's reach of one of frame
    1's card faces, within the face's middle 60 %, moves the robot (both bodies, velocities kept) so that the centre
    lands mirrored across that face's middle line: through the card in one step. Records (t, the centre's distance
    from the line, the robot's move in y) in ``moves``."""

    class Jumped(world_module.World):
        def step(self):
            super().step()
            if moves or len(self.frames) < 2:
                return
            hook = self.robot.tip
            centre = hook.body.local_to_world(hook.offset)
            for rail in self.frames[1].shapes:
                d, along, mirrored = _mirror_across(rail, centre)
                reach = hook.radius + rail.radius
                if 0.2 < along < 0.8 and reach < abs(d) < reach + 3.0:
                    for b in self.robot.bodies:
                        b.position += mirrored - centre
                    moves.append((self.t, abs(d), (mirrored - centre).y))
                    return

    return Jumped


def test_a_hook_moved_through_a_card_between_two_steps_is_unstable_by_the_tunnel_watch(paper_cfg):
    cfg = paper_cfg.replace({"scene.frames": 2})
    d = cfg.design
    moves = []
    with mock.patch.object(run_module, "World", _jumped_world(moves)):
        result = run_module.simulate(cfg)
    assert len(moves) == 1 and moves[0][2] < 0.0, moves  # one jump, downward: the robot gained no energy by it
    assert result.outcome == "unstable", result.reason
    assert result.reason.startswith("the hook's centre went through frame 1's handrail card between two steps")
    assert result.sim_time == pytest.approx(moves[0][0])  # ended at the step it happened
    # the health record books the crossing as a sink of the hook's radius plus half the card (config values)
    assert result.health["penetration"] == pytest.approx(d.hook_radius + 0.5 * d.handrail_thickness)
    # and no other monitor sees this crossing: with the watch silenced the same jump runs on to a miss
    moves.clear()
    with mock.patch.object(run_module, "World", _jumped_world(moves)), \
            mock.patch.object(monitors.TunnelWatch, "step", lambda self: None):
        blind = run_module.simulate(cfg)
    assert len(moves) == 1 and blind.outcome != "unstable", (blind.outcome, blind.reason)


def test_the_default_time_step_has_a_margin(paper_cfg):
    # half the default step, twice it and four times it (the largest sim.contact_hold allows) agree with it. (With
    # the flat side cards' smaller frame inertia, 42.7 g·cm² against the hollow frame's 66.9, four times it was
    # reported unstable.)
    runs = {dt: simulate(paper_cfg.replace({"sim.dt": dt})) for dt in (0.00025, 0.001, 0.002)}
    assert {dt: (r.outcome, r.traversals) for dt, r in runs.items()} == {dt: ("completed", 7) for dt in runs}


# ---- a long row: no drift, no cost growing with the row ----
@pytest.mark.slow
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


def _record(cfg, overrides):
    """The run of ``cfg`` with ``overrides`` as the golden record holds it (through the same JSON round trip)."""
    r = simulate(cfg.replace(overrides), trace=True)
    return json.loads(json.dumps({**r.to_json_dict(), "trace_rows": len(r.trace["t"])}))


def test_the_golden_tolerances_absorb_last_bit_changes_and_catch_physical_ones(golden, paper_cfg):
    expected, _ = golden
    d = paper_cfg.design

    def record(overrides):
        return _record(paper_cfg, overrides)

    # a libm's worth of difference (m1 one part in 1e15): the run differs in its last bits, within tolerance
    nudged = record({"design.m1": d.m1 * (1 + 1e-15)})
    assert nudged["swings"] != expected["swings"]  # the run did change: the hash test alone would refuse it
    assert tolerances.departures(nudged, expected, _seconds_per_row()) == []
    # a physical change: the counterbalance 1 % heavier moves the detaches (measured 7.5 ms, 1.0 deg)
    heavier = tolerances.departures(record({"design.m3": d.m3 * 1.01}), expected, _seconds_per_row())
    assert any(".t_detach" in line for line in heavier), heavier


# A plausible physical change of each whole-run quantity alone, in the record's units: each must be a departure
# of that quantity and of nothing else (tests/golden/tolerances.py says why each tolerance has its size).
WHOLE_RUN_CHANGES = {
    "sim_time": lambda x: x + 0.1,  # the last catch 100 ms later (a last-bit change can move it 24 ms)
    "energy.initial": lambda x: x * (1 + 1e-6),  # a start one part in a million off (a mass, a height)
    "energy.final": lambda x: x * 1.05,  # 5 % more energy left at the end (less dissipated)
    "energy.max_rise": lambda x: x + 3e-7,  # a rise of 3e-7 J somewhere: far under sim.energy_tolerance
    "energy.max_gain": lambda x: x + 3e-7,  # the run rose 3e-7 J above its start
    "health.joint_drift": lambda x: x * 1.4,  # the axle gives 40 % more at a catch
    "health.limit_overshoot_deg": lambda x: x + 0.6,  # the arm snaps 0.6 deg further past its stop
    # the hook lands 0.5 mm deeper: a last-bit change of this robot moves the deepest landing by up to 0.19 mm, so a
    # 40 % deeper landing (0.08 mm) is no longer told from one (tests/golden/tolerances.py)
    "health.penetration": lambda x: x + 5e-4,
}


def _set(record: dict, dotted: str, change) -> dict:
    out = copy.deepcopy(record)
    *path, last = dotted.split(".")
    inner = out
    for part in path:
        inner = inner[part]
    inner[last] = change(inner[last])
    return out


@pytest.mark.parametrize("key", sorted(WHOLE_RUN_CHANGES))
def test_the_golden_whole_run_tolerances_catch_a_physical_change_of_each_quantity(golden, key):
    expected, _ = golden
    assert set(WHOLE_RUN_CHANGES) == set(tolerances.RUN)  # every whole-run quantity has its change here
    changed = _set(expected, key, WHOLE_RUN_CHANGES[key])
    lines = tolerances.departures(changed, expected, _seconds_per_row())
    assert len(lines) == 1 and lines[0].startswith(f"{key}: "), lines


def test_the_golden_whole_run_tolerances_absorb_a_last_bit_change_that_moves_an_event(golden, paper_cfg):
    """theta2's start one part in 1e15 lower: the catches move by steps (sim_time 24 ms later, the energy left
    0.3 % lower: within tolerances.py's largest measured departures), which the whole-run tolerances must take.
    Some single swings move past their own tolerances (tolerances.py says so)."""
    expected, _ = golden
    nudged = _record(paper_cfg, {"scene.theta2_start_deg": paper_cfg.scene.theta2_start_deg * (1 - 1e-15)})
    assert nudged["sim_time"] != expected["sim_time"]  # an event did move
    assert nudged["energy"]["final"] != pytest.approx(expected["energy"]["final"], rel=0.001)
    assert [line for line in tolerances.departures(nudged, expected, _seconds_per_row())
            if not line.startswith("swings")] == []


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
