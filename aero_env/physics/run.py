"""Run a scene along its row: events (catch, detach, stop, fall) and the run's outcome.

A run starts with the hook caught on frame 0 at its rest angle (t = 0 is that catch, as in
the paper). A traversal succeeds when the robot, having left frame i, is caught by frame
i+1. The run ends at the first failure or when the last frame catches the robot, and names
its outcome:

==============  =====================================================================
``completed``   caught by the last frame of the row
``no_detach``   the hook still holds ``stop_hold`` after the frame reached its stop, or the frame
                turned back from near its stop with the hook holding (friction too high)
``stalled``     the frame never left its rest angle (``rest_timeout``), turned back well before its
                stop, or the swing outlasted ``swing_timeout``
``fell_short``  the hook slipped off too low (friction too low), or passed behind the next handrail
``missed_catch`` the arm did not swing forward in time (spring too weak or too stiff), or the
                hook passed ahead of / bounced off the next handrail
``unstable``    a non-finite or exploding state, or mechanical energy rose above tolerance
``timeout``     the run reached ``sim.t_max`` (should not happen: every phase has a limit)
==============  =====================================================================
"""

from __future__ import annotations

import math
import time
import numpy as np

from .. import results as say
from .. import units
from ..config import Config
from ..results import NEAR_STOP_DEG, REST_MOVE, STOP_TOLERANCE, TURN_BACK_DEG, SimResult, Swing
from .world import World

__all__ = ["simulate", "SimResult", "Swing", "TRACE_COLUMNS"]

TRACE_COLUMNS = ("t", "frame", "theta1", "theta2", "alpha", "omega1", "omega2", "alpha_rate", "contact", "energy")


class _Flight:
    """What happened since the hook last touched frame ``origin``: tentative until contact has been
    lost for ``sim.contact_hold``, so every measurement starts at the true detach."""

    def __init__(self, origin: int, t_detach: float, theta1_detach: float, alpha_detach: float,
                 release_height: float):
        self.origin = origin
        self.t_detach = t_detach
        self.theta1_detach = theta1_detach
        self.alpha_detach = alpha_detach
        self.height = release_height  # hook height above the next frame's seat when it let go
        self.first_touch: float | None = None
        self.crossing: tuple[float, float] | None = None  # (hook x - seat x, alpha) as the hook sinks below the seat
        self.t_cross: float | None = None
        self.t_snap: float | None = None  # when the arm had swung through half its range
        self.watching = True  # until both the snap and the crossing are seen

    def observe(self, t: float, robot, seat, snapped_alpha: float) -> None:
        if self.t_snap is None and robot.alpha < snapped_alpha:
            self.t_snap = t - self.t_detach
        if self.crossing is None:
            hook = robot.hook_world()
            if hook.y < seat.y:
                self.crossing = (hook.x - seat.x, robot.alpha)
                self.t_cross = t - self.t_detach
        self.watching = self.t_snap is None or self.crossing is None


def simulate(cfg: Config, trace: bool = False, poses_every: float | None = None) -> SimResult:
    """Simulate ``cfg`` in the pymunk world until the robot completes the row or fails.
    Deterministic for a config.

    Per runner step the loop does only what must be per step: the contact bookkeeping (catch
    and detach times are step-exact) and, in flight, the watch for the arm's snap and the
    hook's descent past the next seat. The frame's peak, its stop, the floor, the time limits,
    the energy and the health monitors are read every ``sim.check_interval`` (5 ms), far finer
    than the thresholds they test (a 20 deg turn-back, a 0.3 s stop hold, a 1 s rest timeout).
    """
    wall0 = time.perf_counter()
    world = World(cfg)
    sim, d = cfg.sim, cfg.design
    p = world.p
    frames, robot, contact = world.frames, world.robot, world.contact
    touches = contact.touches
    n_frames = len(frames)
    hold = sim.contact_hold
    half_range = 0.5 * (p.alpha_max - p.alpha_min)
    snapped_alpha = p.alpha_min + half_range
    near_stop = p.stop_angle - STOP_TOLERANCE
    turn_back, near_stop_turn = math.radians(TURN_BACK_DEG), p.stop_angle - math.radians(NEAR_STOP_DEG)
    # The energy scale of the machine: the robot and counterbalance falling the frame's length, plus
    # what the fully bent spring stores (a stiff spring moves far more energy than gravity does).
    e_tol = sim.energy_tolerance * ((d.m2 + d.m3) * units.GRAVITY * (d.La + d.Lb) + world.spring_capacity())
    worst = [0.0, 0.0, 0.0]  # joint drift (m), limit overshoot (rad), penetration (m)
    limits = (sim.max_joint_drift, math.radians(sim.max_limit_overshoot_deg),
              sim.max_penetration * units.length_to_si(p.hook_radius + p.rail_radius))

    rows: list[tuple] = []
    step_s = sim.dt * sim.substeps  # one runner step
    check_every = max(1, round(sim.check_interval / step_s))
    pose_steps = max(1, round(poses_every / step_s)) if poses_every else 0
    poses: list = [(0.0, *world.pose())] if pose_steps else []
    e0 = world.energy()
    max_gain, e_min, max_rise = 0.0, e0, 0.0
    swings = [Swing(0, 0.0, math.degrees(frames[0].theta), math.degrees(robot.theta2()))]
    th2_lo = th2_hi = swings[0].theta2_catch_deg
    flight: _Flight | None = None  # committed: the hook has let go of frame world.active
    pending: _Flight | None = None  # contact lost, not yet for contact_hold
    t_touch = 0.0  # the last runner step at which the hook touched its frame
    t_stop: float | None = None
    theta1_peak = frames[0].theta
    outcome, reason = "timeout", say.reached_t_max(sim.t_max)
    n_max = int(math.ceil(sim.t_max / step_s))
    next_seat = frames[1].hook_seat_world() if n_frames > 1 else None
    closest = math.inf  # engine units: hook to next_seat since the last catch, on the check cadence
    cur = frames[0]

    for n in range(1, n_max + 1):
        world.step()
        t = world.t
        check = n % check_every == 0

        if flight is None:  # ---- hanging on frame cur ----
            if touches(cur.index):
                t_touch = t
                pending = None  # a brief loss of contact was a bounce, not a detach
            else:
                if pending is None:  # the first step without contact: the state at the detach
                    pending = _Flight(cur.index, t_touch, cur.theta, robot.alpha,
                                      robot.hook_world().y - next_seat.y)
                if pending.watching:
                    pending.observe(t, robot, next_seat, snapped_alpha)
                if t - t_touch >= hold:
                    sw = swings[-1]
                    sw.t_detach, sw.theta1_detach_deg = t_touch, math.degrees(pending.theta1_detach)
                    sw.swing_duration = t_touch - sw.t_catch
                    sw.alpha_detach_deg = math.degrees(pending.alpha_detach)
                    sw.theta2_min_deg, sw.theta2_max_deg = th2_lo, th2_hi
                    flight, pending = pending, None
            if flight is None and check:
                theta1 = cur.theta
                theta1_peak = max(theta1_peak, theta1)
                if theta1 >= near_stop:
                    t_stop = t if t_stop is None else t_stop
                    if t - t_stop >= sim.stop_hold:
                        outcome, reason = "no_detach", say.held_at_stop(cur.index, sim.stop_hold,
                                                                        math.degrees(p.stop_angle), contact.holding_note)
                        break
                else:
                    t_stop = None
                    if theta1 < theta1_peak - turn_back:
                        peak = math.degrees(theta1_peak)
                        if theta1_peak >= near_stop_turn:
                            outcome, reason = "no_detach", say.turned_back_near_stop(cur.index, peak,
                                                                                     contact.holding_note)
                        else:
                            outcome, reason = "stalled", say.turned_back(cur.index, peak)
                        break
                if theta1_peak < p.rest_angle + REST_MOVE and t - swings[-1].t_catch > sim.rest_timeout:
                    outcome, reason = "stalled", say.never_left_rest(cur.index, sim.rest_timeout)
                    break
                if t - swings[-1].t_catch > sim.swing_timeout:
                    outcome, reason = "stalled", say.swing_too_long(cur.index, sim.swing_timeout)
                    break
        else:  # ---- in flight from frame flight.origin ----
            nxt = flight.origin + 1
            if touches(nxt):
                check = True  # every step of a catch: the hook's landing is where it sinks deepest
                if flight.first_touch is None:
                    flight.first_touch = t
                if t - flight.first_touch >= hold:  # caught
                    world.set_active(nxt)
                    cur = frames[nxt]
                    swings.append(Swing(nxt, flight.first_touch, math.degrees(cur.theta),
                                        math.degrees(robot.theta2())))
                    th2_lo = th2_hi = swings[-1].theta2_catch_deg
                    flight, t_stop, theta1_peak, t_touch = None, None, cur.theta, t
                    if nxt == n_frames - 1:
                        outcome, reason = "completed", say.completed(nxt)
                        break
                    next_seat = frames[nxt + 1].hook_seat_world()
                    closest = math.inf
                    continue
            else:
                flight.first_touch = None
            if flight.watching:
                flight.observe(t, robot, next_seat, snapped_alpha)
            if check:
                com = robot.com_world()
                if com.y < world.floor_y(com.x) or t - flight.t_detach > sim.flight_timeout:
                    outcome, reason = _classify_miss(flight, half_range, p, sim.min_release_height * units.LENGTH)
                    break

        sample = None
        if check:
            sample = world.sample()
            e, th2 = sample.energy, sample.theta2
            if not (math.isfinite(e) and math.isfinite(th2)) or sample.max_speed > p.max_speed:
                outcome, reason = "unstable", "non-finite or exploding state (a body exceeded sim.max_speed)"
                break
            max_gain = max(max_gain, e - e0)
            e_min = min(e_min, e)
            max_rise = max(max_rise, e - e_min)
            if max_rise > e_tol:
                outcome, reason = "unstable", (f"mechanical energy rose by {max_rise:.3g} J, above the tolerance "
                                               f"{e_tol:.3g} J (sim.energy_tolerance): numerical error (try a smaller sim.dt "
                                               f"or more sim.iterations)")
                break
            closest = min(closest, math.hypot(sample.hook[0] - next_seat.x, sample.hook[1] - next_seat.y))
            bad = _health_check(sample.health, worst, limits)
            if bad:
                outcome, reason = "unstable", bad
                break
            if flight is None:
                th2d = math.degrees(th2)
                th2_lo, th2_hi = min(th2_lo, th2d), max(th2_hi, th2d)
        if trace and n % sim.trace_every == 0:
            rows.append(_trace_row(world, t, sample or world.sample()))
        if pose_steps and n % pose_steps == 0:
            poses.append((t, *world.pose()))

    if pose_steps and poses[-1][0] < world.t:  # the run's last moment, whatever the pose cadence
        poses.append((world.t, *world.pose()))
    traversals = len(swings) - 1
    if flight is None and swings[-1].theta2_min_deg is None:
        swings[-1].theta2_min_deg, swings[-1].theta2_max_deg = th2_lo, th2_hi
    e_final = world.energy()
    return SimResult(
        traversals=traversals, frames=n_frames, outcome=outcome, reason=reason, swings=swings,
        energy=dict(initial=e0, final=e_final, max_gain=max(max_gain, e_final - e0), max_rise=max_rise),
        sim_time=world.t, wall_time=time.perf_counter() - wall0,
        miss_distance=None if outcome == "completed" or not math.isfinite(closest) else units.length_to_si(closest),
        health=dict(joint_drift=worst[0], limit_overshoot_deg=math.degrees(worst[1]), penetration=worst[2]),
        trace={c: np.array(v) for c, v in zip(TRACE_COLUMNS, zip(*rows))} if trace and rows else None,
        poses=poses if pose_steps else None,
        geometry=world.geometry() if pose_steps else None,
        fidelity=sim.fidelity,
    )


_HEALTH_WORDS = (
    ("joint drift", "sim.max_joint_drift", 1e3, "mm", "a skewer or the arm's axle came apart"),
    ("limit overshoot", "sim.max_limit_overshoot_deg", 180 / math.pi, "deg", "a body turned through its stopper"),
    ("penetration", "sim.max_penetration (as a depth)", 1e3, "mm", "the hook sank into (or through) a handrail card"),
)


def _health_check(measured: tuple, worst: list, limits: tuple) -> str | None:
    """Update the worst values; name the first constraint that gave more than its tolerance."""
    for i, (v, lim) in enumerate(zip(measured, limits)):
        if v > worst[i]:
            worst[i] = v
        if v > lim:
            what, key, scale, unit, meaning = _HEALTH_WORDS[i]
            return (f"{what} {v * scale:.3g} {unit} above {key} = {lim * scale:.3g} {unit}: {meaning}; "
                    f"the engine could not hold the constraint (try a smaller sim.dt or more sim.iterations)")
    return None


def _trace_row(world: World, t: float, sample) -> tuple:
    robot, cur = world.robot, world.frames[world.active]
    touching = sorted(world.contact.touching)
    return (t, cur.index, cur.theta, sample.theta2, robot.alpha, cur.omega, robot.theta2_rate(), robot.alpha_rate,
            touching[0] if touching else -1, sample.energy)


def _classify_miss(flight: _Flight, half_range: float, p, min_release_height: float) -> tuple[str, str]:
    """Name a failed transfer by its cause, in this order:

    1. the arm had less than half its range left at detach -> ``missed_catch`` (spring too stiff:
       it never bent, so it has no motion left);
    2. the hook left the handrail less than ``sim.min_release_height`` above the next handrail ->
       ``fell_short`` (it slipped off before the frame had lifted the robot);
    3. the arm was still swinging when the hook came down to the next handrail -> ``missed_catch``
       (spring too weak for the fall);
    4. the arm was ready: the hook passed behind the handrail -> ``fell_short``, ahead -> ``missed_catch``.
    """
    si = units.length_to_si
    room = flight.alpha_detach - p.alpha_min
    if room < half_range:
        return "missed_catch", say.spring_too_stiff(flight.origin, math.degrees(flight.alpha_detach))
    if flight.height < min_release_height:
        return "fell_short", say.released_low(flight.origin, si(flight.height))
    if flight.crossing is None:
        return "missed_catch", say.never_came_down(flight.origin)
    dx, alpha_cross = flight.crossing
    if flight.t_snap is None or flight.t_snap > flight.t_cross:
        return "missed_catch", say.spring_too_weak(flight.origin, math.degrees(flight.alpha_detach - alpha_cross))
    if dx < 0:
        return "fell_short", say.passed_behind(flight.origin, si(-dx))
    return "missed_catch", say.passed_ahead(flight.origin, si(dx))
