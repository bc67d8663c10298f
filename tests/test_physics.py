"""The pymunk world against the paper: traversal, first swing, failure modes, energy, effects."""

import math
from unittest import mock

import numpy as np
import pymunk
import pytest

from aero_env import units
from aero_env.physics import World, simulate
from aero_env.physics.drag import DragStrip
from aero_env.physics.leaf_spring import LinearLeafSpring
from aero_env.physics.robot import Robot
from aero_env.simulation import simulate as simulate_any

from .invariants import kinetic_energy


# ---------------------------------------------------------------- the prototype
def test_prototype_traverses_every_frame(paper_run, paper_cfg):
    r = paper_run
    assert r.outcome == "completed", r.reason
    assert r.traversals == paper_cfg.scene.frames - 1 == r.frames - 1
    assert [s.frame for s in r.swings] == list(range(paper_cfg.scene.frames))
    # every catch is on a frame waiting at its rest angle, every detach late in the swing
    for s in r.swings:
        assert s.theta1_catch_deg == pytest.approx(55.0, abs=1.0)
    for s in r.swings[:-1]:
        assert 150.0 <= s.theta1_detach_deg <= 175.0


def test_first_swing_looks_like_the_paper(paper_run):
    s = paper_run.swings[0]
    assert 150.0 <= s.theta1_detach_deg <= 175.0  # paper: ~165 deg
    assert 0.5 <= s.swing_duration <= 0.8  # paper: 0.62 s
    # the robot is placed at theta2 = 81 deg at rest; 20 ms later it has not jumped (a consistent start)
    tr = paper_run.trace
    early = tr["t"] <= 0.02
    assert np.degrees(tr["theta2"][early]) == pytest.approx(81.0, abs=1.0)  # paper: ~80-81 deg
    assert s.theta2_min_deg < 90.0 < s.theta2_max_deg  # the robot swings about the vertical
    assert s.theta2_max_deg - s.theta2_min_deg < 40.0


def test_theta1_rises_monotonically_and_the_spring_is_fully_bent_at_the_bottom(paper_run, paper_cfg):
    tr = paper_run.trace
    first = tr["t"] <= paper_run.swings[0].t_detach
    # The start settles first: the hook, placed on the seat with the arm on its stop, seats 0.02 mm into the notch
    # within 3 steps, the arm comes 0.06 deg off its stop and the frame gives back 9.7e-4 deg (measured at
    # t = 1.5 ms; the build before the kit's parts did the same at 1.0 ms, before the trace's first row). Bound
    # that settle, then the swing: the frame never turns back (paper, Fig. 40)
    rest = math.radians(paper_cfg.design.rest_angle_deg)
    assert np.all(tr["theta1"][first] > rest - math.radians(0.002))
    th1 = tr["theta1"][first & (tr["t"] >= paper_cfg.sim.check_interval)]
    assert np.all(np.diff(th1) > -1e-6)
    near_bottom = (tr["t"] > 0.25) & (tr["t"] < 0.35)  # paper Fig. 12: t ~ 0.3 s, alpha ~ 120 deg
    assert np.degrees(tr["alpha"][near_bottom]).max() > 118.0


def test_arm_snaps_forward_in_flight(paper_run):
    tr = paper_run.trace
    s0, s1 = paper_run.swings[:2]
    flight = (tr["t"] > s0.t_detach) & (tr["t"] < s1.t_catch)
    assert np.degrees(tr["alpha"][flight]).min() < s0.alpha_detach_deg - 30.0


# ---------------------------------------------------------------- a traversal is a catch that holds
# Draw 154 of 1500 uniform draws (seed 1) over configs/paper.yaml's action box on a 3-frame row, its
# counterbalance 5 % heavier (m3 6.11 -> 6.41 g): frame 1 catches the hook 0.3 mm from its seat (a seated catch),
# and the hook falls out 0.06 s later with the frame at 61 deg. Counting the catch at once paid a traversal for
# it. (With the parts built as the kit draws them, the draw itself no longer lets go: frame 1 carries the robot,
# and on 3 frames the hook slips off 3.4 mm below frame 2's handrail. In a grid about the draw, m3 x0.9-1.1,
# h x0.9-1.05, La x0.95-1.05, spring_k x0.95-1.25 and mu_s x0.99-1.1, 205 of 960 designs let go of a seated
# catch so.)
CATCH_LETS_GO = {"design.m3": 0.00641, "design.h": 0.016193256984484376,
                 "design.La": 0.062445386095275904, "design.spring_k": 0.00020727552273168634,
                 "design.mu_s": 0.2039521421829815, "design.mu_k": 0.15390484530044174}


def carried_in_trace(result, frame: int) -> bool:
    """From the trace alone: did ``frame``, touching the hook, turn through 90 deg (the robot at its lowest)?"""
    tr = result.trace
    rows = (tr["frame"] == frame) & (tr["contact"] == frame)
    return bool(np.any(np.degrees(tr["theta1"][rows]) >= 90.0))


def test_carried_is_the_robots_lowest_point_as_the_calibration_names_it():
    from aero_env.calibration.swing_metrics import LOWEST_THETA1_DEG
    from aero_env.physics.swing_rules import CARRIED_THETA1_DEG

    assert CARRIED_THETA1_DEG == LOWEST_THETA1_DEG == 90.0  # the handrail straight below the axis


def test_every_traversal_is_a_frame_that_carried_the_robot(paper_run):
    r = paper_run
    carried = [carried_in_trace(r, s.frame) for s in r.swings]
    assert all(carried) and r.traversals == sum(carried[1:]) == 7
    assert all(s.t_catch < s.t_carried < (s.t_detach or math.inf) for s in r.swings)
    # the last frame completes the row by the same rule: its catch alone ends nothing; the run goes on until
    # that frame has carried the robot through its lowest point, which takes as long as on any other frame
    last = r.swings[-1]
    assert r.sim_time == pytest.approx(last.t_carried) and r.sim_time - last.t_catch > 0.1
    took = [s.t_carried - s.t_catch for s in r.swings[1:]]
    assert max(took) - min(took) < 0.15
    tail = r.trace["t"] > last.t_carried - 0.02
    assert np.all(r.trace["contact"][tail] == last.frame)


def test_a_catch_that_lets_go_before_it_carried_the_robot_is_no_traversal(paper_cfg):
    cfg = paper_cfg.replace(CATCH_LETS_GO)
    r = simulate(cfg, trace=True)
    first, caught = r.swings
    seat_mm = caught.catch_seat_mm
    assert seat_mm <= cfg.sim.catch_seat * 1e3  # a seated catch: the old rule counted it
    assert caught.t_detach is not None and caught.t_carried is None and not carried_in_trace(r, 1)
    assert (r.outcome, r.traversals) == ("missed_catch", 0), r.reason
    assert r.reason == (f"after leaving frame 0: frame 1 caught the hook {seat_mm:.1f} mm from its seat but it let go "
                        f"after {caught.swing_duration:.2f} s at theta1 = {caught.theta1_detach_deg:.0f} deg, before "
                        f"the frame carried the robot through its lowest point (a catch that did not hold)")
    # the run ends when the let-go is committed; the transfer it failed came within the catch's distance
    assert r.sim_time == pytest.approx(caught.t_detach + cfg.sim.contact_hold)
    assert r.flew and r.miss_distance == pytest.approx(seat_mm * 1e-3)


# ---------------------------------------------------------------- failure modes
FAILURES = {
    "weak_spring": ({"design.spring_k": 8.77e-5}, "missed_catch"),
    "stiff_spring": ({"design.spring_k": 8.77e-3}, "missed_catch"),
    "low_friction": ({"design.mu_s": 0.1, "design.mu_k": 0.075}, "fell_short"),
    "high_friction": ({"design.mu_s": 4.0, "design.mu_k": 3.0}, "no_detach"),
}


@pytest.mark.parametrize("name", sorted(FAILURES))
def test_each_failure_mode_ends_the_run_at_the_first_transfer(paper_cfg, name):
    overrides, outcome = FAILURES[name]
    r = simulate(paper_cfg.replace(overrides))
    assert r.traversals == 0, (name, r.outcome, r.reason)
    assert r.outcome == outcome, (name, r.reason)


@pytest.mark.parametrize("name", ["weak_spring", "low_friction", "catch_lets_go"])
def test_the_miss_distance_is_the_hooks_closest_approach_to_the_next_seat(paper_cfg, name):
    """SimResult.miss_distance against the hook's path read from pymunk after every step (the runner samples it
    on its 5 ms check cadence, every step while the hook touches the next handrail): the hook's centre from the
    arm's circle shape, the seat at (-Lb, 0) on frame 1's body. Each of these runs fails its first transfer, so
    the transfer is the whole run. The runner's value can be no nearer than the closest step, and no farther than
    the farthest step within half a check interval of it (one of those steps is a check)."""
    import aero_env.physics.run as run_module

    overrides = CATCH_LETS_GO if name == "catch_lets_go" else FAILURES[name][0]
    cfg = paper_cfg.replace({**overrides, "scene.frames": 3})
    path = []  # (t, hook centre to frame 1's seat, m)

    class Watched(World):
        def step(self):
            super().step()
            hook = next(sh for b in self.robot.bodies for sh in b.shapes if isinstance(sh, pymunk.Circle))
            gap = hook.body.local_to_world(hook.offset) - self.frames[1].body.local_to_world((-cfg.design.Lb * 1e3, 0))
            path.append((self.t, gap.length * 1e-3))

    with mock.patch.object(run_module, "World", Watched):
        r = run_module.simulate(cfg)
    assert r.traversals == 0 and r.flew and r.miss_distance is not None, r.reason
    t_min, closest = min(path, key=lambda row: row[1])
    near = [gap for t, gap in path if abs(t - t_min) <= 0.5 * cfg.sim.check_interval + 1e-9]
    assert closest <= r.miss_distance <= max(near)
    assert r.miss_distance < 0.02  # these runs came near (the catch that did not hold: 0.2 mm)


def test_low_and_high_friction_fail_differently_and_the_prototype_sits_between(paper_cfg, paper_run):
    low = simulate(paper_cfg.replace(FAILURES["low_friction"][0]))
    high = simulate(paper_cfg.replace(FAILURES["high_friction"][0]))
    assert low.outcome != high.outcome
    # low friction lets go earlier than the prototype; high friction never lets go
    assert low.swings[0].theta1_detach_deg < paper_run.swings[0].theta1_detach_deg - 10.0
    assert high.swings[0].t_detach is None
    assert paper_run.outcome == "completed"


def test_stiff_spring_keeps_the_arm_forward_while_hanging(paper_cfg):
    r = simulate(paper_cfg.replace({"design.spring_k": 8.77e-3}), trace=True)
    hanging = r.trace["t"] <= r.swings[0].t_detach
    # placed at 120 deg, the stiff spring pulls the arm straight to ~60 deg while the hook still holds (the
    # Table 1 robot's short torso lets the hook go 27 ms later): on release it has no swing left (the paper)
    assert np.degrees(r.trace["alpha"][hanging][-1]) < 62.0 and r.swings[0].alpha_detach_deg < 62.0
    assert r.outcome == "missed_catch" and "too stiff" in r.reason


def test_too_little_moment_imbalance_stalls(paper_cfg):
    # a counterbalance nearly as heavy as the robot: the frame turns back long before its stop
    r = simulate(paper_cfg.replace({"design.m3": 0.0079, "design.h": -0.01}))
    assert r.outcome == "stalled", r.reason
    assert r.traversals == 0


# ---------------------------------------------------------------- energy
def test_energy_never_rises_above_its_start(paper_run):
    # The run aborts as `unstable` above sim.energy_tolerance (0.5% of (m2+m3)·g·(La+Lb) = 7.3e-5 J).
    # The prototype measures max_gain 0 and max_rise 1.05e-5 J (the robot's height by 0.14 mm):
    # hold it at 3e-5 J so a solver change that triples the numerical error fails here.
    e = paper_run.energy
    assert e["max_gain"] < 3e-5
    assert e["max_rise"] < 3e-5
    # stoppers, sliding friction and the inelastic arm stop take out most of what the frames gave
    assert e["final"] < 0.5 * e["initial"]


def test_swing_before_sliding_conserves_energy(paper_cfg):
    # without the skewer's and the axle's dry friction nothing takes energy out before the hook slides
    r = simulate(paper_cfg.replace({"design.pivot_friction": 0.0, "design.axle_friction": 0.0}), trace=True)
    tr = r.trace
    early = tr["t"] < 0.2  # the hook sits in the notch, no stop reached, no impacts
    scale = 0.00771 * 9.81 * 0.03  # robot weight times its fall over the first swing
    assert np.abs(tr["energy"][early] - r.energy["initial"]).max() < 0.005 * scale


def test_skewer_friction_takes_out_the_work_it_does(paper_cfg):
    # Coulomb friction at the skewer does work tau·|angle turned|. In the pinned-hook scene (no contact
    # friction, no spring) the energy the trace loses is exactly that work, summed from its own angles.
    tau = 1e-4
    cfg = paper_cfg.replace({"scene.effects.hook": "pin", "design.pivot_friction": tau, "scene.frames": 2,
                             "sim.trace_every": 1})
    tr = simulate(cfg, trace=True).trace
    turning = tr["t"] < 0.6  # before the frame reaches its stop
    th1, e = tr["theta1"][turning], tr["energy"][turning]
    work = tau * np.concatenate([[0.0], np.cumsum(np.abs(np.diff(th1)))])
    lost = e[0] - e
    assert work[-1] > 1e-4  # the friction did work worth checking (tau times ~100 deg)
    assert np.abs(lost - work).max() < 0.02 * work[-1]


# ---------------------------------------------------------------- determinism
def test_same_config_same_result_in_process(paper_cfg, paper_run):
    again = simulate(paper_cfg, trace=True)
    a, b = paper_run.to_json_dict(), again.to_json_dict()
    a.pop("wall_time"), b.pop("wall_time")
    assert a == b
    assert np.array_equal(paper_run.trace["theta2"], again.trace["theta2"])


# ---------------------------------------------------------------- parts
def test_leaf_spring_sign_snaps_a_free_arm_to_alpha_min(paper_cfg):
    # pymunk's rotary spring and rotary limit measure relative angles with opposite signs;
    # a free robot (no gravity, no handrail) must see its arm snap from alpha_max to alpha_min.
    p = World(paper_cfg).p
    space = pymunk.Space()
    robot = Robot(p)
    robot.place_hanging(pymunk.Vec2d(0.0, 0.0), math.pi / 2, p.alpha_max)
    robot.add_to(space)
    LinearLeafSpring(robot, p.spring_k, p.alpha_min).add_to(space)
    alphas = []
    for _ in range(100):
        space.step(0.0005)
        alphas.append(math.degrees(robot.alpha))
    closed = int(np.argmin(alphas))
    assert alphas[0] < 120.0 and closed > 10 and np.all(np.diff(alphas[:closed + 1]) < 0)  # at once and steadily
    assert min(alphas) < 60.5  # and reaches the straight-spring stop within 50 ms
    assert max(alphas[70:]) < 65.0  # where it stays: the stop is inelastic


@pytest.mark.parametrize("law", ["linear", "stiffening"])
def test_spring_constraint_applies_the_torque_of_its_energy(paper_cfg, law):
    # The torque pymunk actually applies (the constraint's impulse per step) must be -dE/dalpha of
    # the energy the world books, for the arm at 100 deg.
    world = World(paper_cfg.replace({"scene.effects.spring_law": law}))
    robot, spring = world.robot, world.spring
    robot.place_hanging(pymunk.Vec2d(0.0, 0.0), math.pi / 2, math.radians(100.0))
    fresh = pymunk.Space()  # the robot and its spring alone, no gravity, no contact
    world.space.remove(*world.space.constraints)
    world.space.remove(*[sh for b in robot.bodies for sh in b.shapes], *robot.bodies)
    robot.add_to(fresh)
    spring.add_to(fresh)
    h = 1e-7
    e0 = spring.energy()
    robot.arm.angle += h
    dE = (spring.energy() - e0) / h
    robot.arm.angle -= h
    dt = 1e-4
    fresh.step(dt)
    # chipmunk's spring impulse is its torque function times dt, applied +j to the arm
    assert spring.constraint.impulse / dt == pytest.approx(-dE, rel=1e-3)
    assert dE > 0


def test_frame_drag_torque_matches_the_papers_tau1():
    rho_cd_half, width, la, lb, w = 0.65, 10.0, 48.3, 51.7, -2.5
    body = pymunk.Body(1.0, 10.0)
    body.angular_velocity = w
    strip = DragStrip(body, (-lb, 0.0), (la, 0.0), width, rho_cd_half)
    force, torque = strip.force_and_torque()
    tau1 = -(1.0 / 8.0) * (2 * rho_cd_half) * width * w * abs(w) * (la**4 + lb**4)
    assert torque == pytest.approx(tau1, rel=1e-12)
    # the two ends move in opposite directions: the net force is the difference of the two arms
    assert force.y == pytest.approx(-rho_cd_half * width * w * abs(w) * (la**3 - lb**3) / 3.0, rel=1e-12)


def test_drag_is_negligible_and_only_built_when_asked(paper_cfg, paper_run):
    def dragged_bodies(world):
        return [b for b in world.space.bodies if isinstance(getattr(b.velocity_func, "__self__", None), DragStrip)]

    plain = World(paper_cfg)
    assert plain.drag is None and dragged_bodies(plain) == []  # every body keeps pymunk's C update
    assert len(dragged_bodies(World(paper_cfg.replace({"scene.effects.drag": True})))) == 4  # 2 live frames + robot
    dragged = simulate(paper_cfg.replace({"scene.effects.drag": True}), trace=True)
    assert dragged.outcome == "completed"
    # paper: drag makes no noticeable difference. It does make one: over the first swing the dragged frame lags
    # the plain one at every sample past 0.1 s, and by as much as the two-link model with the same drag law
    # says (same robot of parts, from the same rest; measured 0.92-1.18 of it at 0.35-0.6 s, where the lag has grown
    # past 0.02 deg: before that the robot's own wiggles are a third of it), which is 0.02-0.10 deg. A drag that
    # does nothing, pushes, or is twice too strong fails here.
    plain, tr = paper_run.trace, dragged.trace
    first = (plain["t"] > 0.1) & (plain["t"] < paper_run.swings[0].t_detach)
    lag = plain["theta1"][first] - np.interp(plain["t"][first], tr["t"], tr["theta1"])
    assert np.all(lag > 0)
    from aero_env.models import two_link

    d, start = paper_cfg.design, (math.radians(paper_cfg.design.rest_angle_deg), math.radians(81.0))
    a = two_link.simulate(d, *start, until_theta1=math.radians(165), robot="parts")
    b = two_link.simulate(d, *start, until_theta1=math.radians(165), drag=True, robot="parts")
    for t in (0.35, 0.45, 0.6):
        world_lag = np.interp(t, plain["t"], plain["theta1"]) - np.interp(t, tr["t"], tr["theta1"])
        model_lag = np.interp(t, a.t, a.theta1) - np.interp(t, b.t, b.theta1)
        assert world_lag == pytest.approx(model_lag, rel=0.3), t
    assert 0.0 < dragged.swings[0].t_detach - paper_run.swings[0].t_detach < 0.01  # measured 2 ms


def test_static_friction_holds_longer_than_kinetic(paper_cfg, paper_run):
    static = simulate(paper_cfg.replace({"scene.effects.friction": "static"}))
    kinetic = simulate(paper_cfg.replace({"scene.effects.friction": "kinetic"}))
    both = paper_run.swings[0].theta1_detach_deg
    # mu_s alone holds the hook longest. Slip is read at the contact, so the tip turning in the corner
    # slides on the card: the switching law runs at mu_k for most of the swing and lets go within a
    # degree of mu_k alone (measured 161.2 vs 161.6 deg; mu_s alone 164.9)
    assert both < static.swings[0].theta1_detach_deg - 2.0
    assert both == pytest.approx(kinetic.swings[0].theta1_detach_deg, abs=1.0)
    # a single coefficient needs no per-step work: the C solver does it all
    assert World(paper_cfg.replace({"scene.effects.friction": "kinetic"})).contact.before_step is None
    switching = World(paper_cfg)
    assert switching._before_step == (switching.contact.before_step,)  # the one per-step part of the scene


def test_live_window_keeps_only_nearby_frames_in_the_space(paper_cfg):
    world = World(paper_cfg)
    assert [f.index for f in world.live_frames()] == [0, 1]
    world.set_active(4)
    assert [f.index for f in world.live_frames()] == [3, 4, 5]
    dynamic = [b for b in world.space.bodies if b.body_type == pymunk.Body.DYNAMIC]
    assert len(dynamic) == 2 + 3  # torso, arm and three frames, of eight
    wide = simulate(paper_cfg.replace({"scene.effects.live_frames": 3}))
    base = simulate(paper_cfg)
    assert wide.outcome == base.outcome and wide.traversals == base.traversals
    # more live frames change only the solver's order: each swing lasts as long within 5 ms (measured 4 ms; the
    # catch times add those up along the row, 16 ms by the last frame)
    for a, b in zip(wide.swings, base.swings):
        assert (a.swing_duration is None) == (b.swing_duration is None)
        if a.swing_duration is not None:
            assert a.swing_duration == pytest.approx(b.swing_duration, abs=0.005)


def test_a_long_row_is_traversed_too(paper_cfg):
    r = simulate(paper_cfg.replace({"scene.frames": 16}))
    assert r.outcome == "completed" and r.traversals == 15


TORQUE_PER_NM = 1e9  # the engine's torque unit is g·mm²/s² = 1e-3 kg · 1e-6 m² / s²


def _torque_pymunk_applies(cfg, alpha_deg, dt=1e-4):
    """N·m: the torque the world's spring constraint puts on the arm at interior angle alpha (robot alone in a
    space, no gravity, at rest): chipmunk's spring impulse over one step, divided by the step."""
    world = World(cfg)
    robot, spring = world.robot, world.spring
    robot.place_hanging(pymunk.Vec2d(0.0, 0.0), math.pi / 2, math.radians(alpha_deg))
    world.space.remove(*world.space.constraints)
    world.space.remove(*[sh for b in robot.bodies for sh in b.shapes], *robot.bodies)
    fresh = pymunk.Space()
    robot.add_to(fresh)
    spring.add_to(fresh)
    fresh.step(dt)
    return spring.constraint.impulse / dt / TORQUE_PER_NM


@pytest.mark.parametrize("alpha_deg", [62.0, 75.0, 100.0, 120.0])
def test_the_spring_laws_torque_measured_in_the_world(paper_cfg, alpha_deg):
    """The paper's fit K_T = k·da (linear, the default) and its stiffening reading torque = k/2·da² (da =
    alpha - alpha_min, rad), from the config's k; both close the arm towards alpha_min."""
    k, da = paper_cfg.design.spring_k, math.radians(alpha_deg - paper_cfg.design.alpha_min_deg)
    linear = _torque_pymunk_applies(paper_cfg, alpha_deg)
    stiffening = _torque_pymunk_applies(paper_cfg.replace({"scene.effects.spring_law": "stiffening"}), alpha_deg)
    assert -linear == pytest.approx(k * da, rel=1e-9)  # measured within 2e-15
    assert -stiffening == pytest.approx(0.5 * k * da**2, rel=1e-9)
    assert stiffening / linear == pytest.approx(da / 2, rel=1e-9)  # the two laws' ratio, units aside
    assert World(paper_cfg.replace({"scene.effects.spring_law": "stiffening"})).spring.name == "stiffening"


def test_frame_own_moment_dT_enters_as_in_equation_1(paper_cfg):
    # The gravity torque pymunk's frame body (frame + counterbalance) feels about its axis must be
    # dT·cos(th) - m3·g·La·cos(th) + m3·g·h·sin(th): Eq. (1) without the robot.
    from aero_env import units
    from aero_env.models import quasi_static

    cfg = paper_cfg.replace({"design.dT": 0.001})
    d = cfg.design
    frame = World(cfg).frames[0]
    b = frame.body
    for th in np.radians([0.0, 55.0, 120.0, 180.0]):
        cog = b.center_of_gravity.rotated(th)  # the body's origin is the axis
        torque = cog.x * (-b.mass * 9.81 * units.ACCELERATION) / units.TORQUE
        # the frame carries the handrail's card at the seat; the rest of m2 is the robot
        expected = quasi_static.moment(d, th) - (d.m2 - d.handrail_mass) * 9.81 * d.Lb * np.cos(th)
        assert torque == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("overrides", [{}, {"design.Ld": 0.075, "design.arm_length": 0.025, "design.alpha_max_deg": 110}])
def test_the_built_robot_is_table_1s_torso_bottom_ld_from_the_hook_with_the_coins_on_the_card(paper_cfg, overrides):
    """Measured on the world's bodies at alpha_max: the hook (the arm's tip) to the torso card's bottom is Ld
    (Appendix A), and the coins lie on the card. The torso's length is solved here from the law of cosines
    (hook, axle and the torso's bottom: sides arm_length, T and Ld, the angle alpha_max at the axle), not by
    the builder's own formula."""
    cfg = paper_cfg.replace(overrides)
    d, world = cfg.design, World(cfg)
    robot = world.robot
    robot.place_hanging(world.frames[0].hook_seat_world(), math.radians(90), math.radians(d.alpha_max_deg))
    L, a, Ld = d.arm_length, math.radians(d.alpha_max_deg), d.Ld
    T = L * math.cos(a) + math.sqrt(Ld**2 - (L * math.sin(a)) ** 2)  # Ld² = L² + T² - 2·L·T·cos(a)
    bottom = robot.torso.local_to_world((0.0, -T * units.LENGTH))
    assert (robot.hook_world() - bottom).length / units.LENGTH == pytest.approx(Ld, abs=1e-9)
    assert world.p.torso_length / units.LENGTH == pytest.approx(T, rel=1e-12)
    # the coins, discs of coin_radius centred coin_offset down the card from the axle, stay on the card
    coin_at = world.p.coin_offset / units.LENGTH
    assert d.coin_radius - 1e-12 <= coin_at and coin_at + d.coin_radius <= T + 1e-12
    # ... and sit at its bottom: the torso's centre of mass is the card's and the coins' by hand. The card is the
    # kit's laminated plate (310 g/m² card, the fewest layers at most 26 mm wide) from 4 mm above the axle down to
    # T, less the 2.4 mm axle hole in each layer: the whole rectangle's centre is (T - 4 mm)/2 below the axle and
    # the hole's, at the axle, has no moment about it
    m_card = d.m2 - d.arm_mass - d.coin_mass - d.handrail_mass
    card, end, hole = m_card / 0.310, 4e-3, math.pi * 1.2e-3**2  # m² of card over all layers, m, m² per layer
    layers = math.ceil(card / ((T + end) * 26e-3))
    width = (card / layers + hole) / (T + end)
    rect = 0.310 * layers * width * (T + end)  # kg: the card with its holes filled in
    assert rect - 0.310 * layers * hole == pytest.approx(m_card, rel=1e-12)
    com = (rect * (T - end) / 2 + d.coin_mass * (T - d.coin_radius)) / (m_card + d.coin_mass)
    assert world.p.torso_com / units.LENGTH == pytest.approx(com, rel=1e-12)


@pytest.mark.parametrize("fidelity", ["mbd", "reduced"])
def test_a_swing_that_outlasts_its_timeout_past_the_balance_angle_was_held_by_friction(paper_cfg, fidelity):
    """A sticky hook (mu_s = 4) carries frame 0 past Eq. 1's balance angle (125.3 deg) by 0.7 s and never lets
    go: at the swing timeout that is friction holding the hook (no_detach), whether or not the frame has turned
    back 20 deg by then; a timeout before the balance angle is a stall. (At reference fidelity the prototype's
    high-friction case settles near its peak without turning back 20 deg, and read stalled before.)"""
    sticky = paper_cfg.replace({"design.mu_s": 4.0, "design.mu_k": 3.0, "scene.frames": 3,
                                "sim.fidelity": fidelity})
    late = simulate_any(sticky.replace({"sim.swing_timeout": 0.7}))
    assert late.outcome == "no_detach" and "still held the robot after 0.7 s: friction held the hook" in late.reason
    peak = float(late.reason.split("reached ")[1].split(" deg")[0])
    assert peak > 125.3
    early = simulate_any(sticky.replace({"sim.swing_timeout": 0.3}))
    assert early.outcome == "stalled" and early.reason == "swing on frame 0 lasted over 0.3 s"


def test_the_spring_damping_takes_out_the_dampers_work(paper_cfg):
    """design.spring_damping: a free robot (no gravity, no handrail) whose arm snaps from alpha_max on a damped
    spring loses, before the arm reaches its alpha_min stop, the damper's work: the integral of c·(alpha')²
    with c = 2·zeta·sqrt(k·m_arm·arm_length²/3) computed here from the config; its energy is recounted from
    the bodies (invariants.kinetic_energy) and the spring law written out. Undamped, it keeps its energy."""
    def snap(zeta):
        cfg = paper_cfg.replace({"design.spring_damping": zeta, "design.axle_friction": 0.0})  # the damper alone
        d, p = cfg.design, World(cfg).p
        space = pymunk.Space()
        robot = Robot(p)
        robot.place_hanging(pymunk.Vec2d(0.0, 0.0), math.pi / 2, p.alpha_max)
        robot.add_to(space)
        LinearLeafSpring(robot, p.spring_k, p.alpha_min, p.spring_c).add_to(space)
        c = 2 * zeta * math.sqrt(d.spring_k * d.arm_mass * d.arm_length**2 / 3)  # SI

        def energy():  # J
            da = robot.alpha - math.radians(d.alpha_min_deg)
            return kinetic_energy(robot.bodies) + 0.5 * d.spring_k * da * da

        e0, work, dt = energy(), 0.0, 1e-5
        rate = robot.alpha_rate
        while robot.alpha > math.radians(d.alpha_min_deg + 5.0):  # stop short of the stop's impact
            space.step(dt)
            work += 0.5 * c * (rate**2 + robot.alpha_rate**2) * dt  # trapezoid over the step
            rate = robot.alpha_rate
        return e0 - energy(), work

    lost, work = snap(0.3)
    assert work > 1e-5 and lost == pytest.approx(work, rel=0.01)  # measured 0.06 %
    lost0, work0 = snap(0.0)
    assert work0 == 0.0 and abs(lost0) < 1e-3 * work
