"""Run a scene along its row: events (catch, detach, stop, fall) and the run's outcome.

A run starts with the hook caught on frame 0 at its rest angle (t = 0 is that catch, as in
the paper). A traversal succeeds when the robot, having left frame i, is caught by frame
i+1. The run ends at the first failure or when the last frame catches the robot, and names
its outcome:

==============  =====================================================================
``completed``   caught by the last frame of the row
``no_detach``   the hook still holds ``stop_hold`` after the frame reached its stop, or the frame
                turned back from near its stop with the hook holding (friction too high)
``stalled``     the frame turned back well before its stop, or the swing outlasted ``swing_timeout``
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
from dataclasses import asdict, dataclass, field

import numpy as np

from .. import units
from ..config import Config
from .world import World

TURN_BACK_DEG = 20.0  # a hooked frame this far below its peak angle has turned back
NEAR_STOP_DEG = 10.0  # a turn-back this close to the stop is the high-friction failure (no_detach)
TRACE_COLUMNS = ("t", "frame", "theta1", "theta2", "alpha", "omega1", "omega2", "alpha_rate", "contact", "energy")


@dataclass
class Swing:
    frame: int
    t_catch: float
    theta1_catch_deg: float
    theta2_catch_deg: float
    t_detach: float | None = None
    theta1_detach_deg: float | None = None
    swing_duration: float | None = None
    alpha_detach_deg: float | None = None
    theta2_min_deg: float | None = None
    theta2_max_deg: float | None = None


@dataclass
class SimResult:
    traversals: int
    frames: int
    outcome: str
    reason: str
    swings: list[Swing]
    energy: dict
    sim_time: float
    wall_time: float
    miss_distance: float | None = None  # m: closest the hook came to the next handrail's seat in the failed transfer
    health: dict = field(default_factory=dict)  # largest joint drift (m), limit overshoot (deg), penetration (m)
    trace: dict | None = field(default=None, repr=False)
    poses: list | None = field(default=None, repr=False)
    geometry: dict | None = field(default=None, repr=False)

    def to_json_dict(self) -> dict:
        """The fields of ``aero-env simulate --json`` (no trace or poses)."""
        return dict(traversals=self.traversals, frames=self.frames, outcome=self.outcome, reason=self.reason,
                    swings=[asdict(s) for s in self.swings], energy=dict(self.energy),
                    sim_time=self.sim_time, wall_time=self.wall_time, miss_distance=self.miss_distance,
                    health=dict(self.health))


class _Flight:
    """What happened since the hook last touched frame ``origin``: tentative until contact has been
    lost for ``sim.contact_hold``, so every measurement starts at the true detach."""

    def __init__(self, origin: int, t_detach: float, alpha_detach: float, release_height: float):
        self.origin = origin
        self.t_detach = t_detach
        self.alpha_detach = alpha_detach
        self.height = release_height  # hook height above the next frame's seat when it let go
        self.first_touch: float | None = None
        self.crossing: tuple[float, float] | None = None  # (hook x - seat x, alpha) as the hook sinks below the seat
        self.t_cross: float | None = None
        self.t_snap: float | None = None  # when the arm had swung through half its range

    def observe(self, t: float, robot, seat, snapped_alpha: float) -> None:
        if self.t_snap is None and robot.alpha < snapped_alpha:
            self.t_snap = t - self.t_detach
        if self.crossing is None:
            hook = robot.hook_world()
            if hook.y < seat.y:
                self.crossing = (hook.x - seat.x, robot.alpha)
                self.t_cross = t - self.t_detach


def simulate(cfg: Config, trace: bool = False, poses_every: float | None = None) -> SimResult:
    """Simulate ``cfg`` until the robot completes the row or fails. Deterministic for a config."""
    wall0 = time.perf_counter()
    world = World(cfg)
    sim, d = cfg.sim, cfg.design
    p = world.p
    frames, robot, contact = world.frames, world.robot, world.contact
    n_frames = len(frames)
    hold = sim.contact_hold
    half_range = 0.5 * (p.alpha_max - p.alpha_min)
    snapped_alpha = p.alpha_min + half_range
    # The energy scale of the machine: the robot and counterbalance falling the frame's length, plus
    # what the fully bent spring stores (a stiff spring moves far more energy than gravity does).
    e_tol = sim.energy_tolerance * ((d.m2 + d.m3) * units.GRAVITY * (d.La + d.Lb) + world.spring_capacity())
    worst = [0.0, 0.0, 0.0]  # joint drift (m), limit overshoot (rad), penetration (m)
    limits = (sim.max_joint_drift, math.radians(sim.max_limit_overshoot_deg),
              sim.max_penetration * units.length_to_si(p.hook_radius + p.rail_radius))

    rows: list[tuple] = []
    pose_steps = max(1, round(poses_every / sim.dt)) if poses_every else 0
    poses: list = [(0.0, *world.pose())] if pose_steps else []
    e0 = world.energy()
    max_gain, e_min, max_rise = 0.0, e0, 0.0
    swings = [Swing(0, 0.0, math.degrees(frames[0].theta), math.degrees(robot.theta2()))]
    th2_lo = th2_hi = swings[0].theta2_catch_deg
    flight: _Flight | None = None  # committed: the hook has let go of frame world.active
    pending: _Flight | None = None  # contact lost, not yet for contact_hold
    touch = (0.0, frames[0].theta, robot.alpha, robot.hook_world().y)  # t, theta1, alpha, hook y at last touch
    t_stop: float | None = None
    theta1_peak = frames[0].theta
    outcome, reason = "timeout", f"reached sim.t_max = {sim.t_max} s"
    n_max = int(math.ceil(sim.t_max / sim.dt))
    next_seat = frames[1].hook_seat_world() if n_frames > 1 else None
    closest = math.inf  # engine units: hook to next_seat since the last catch, on the check cadence

    for n in range(1, n_max + 1):
        world.step()
        t = world.t
        cur = frames[world.active]

        if flight is None:  # ---- hanging on frame world.active ----
            if contact.touches(cur.index):
                touch = (t, cur.theta, robot.alpha, robot.hook_world().y)
                pending = None  # a brief loss of contact was a bounce, not a detach
            else:
                if pending is None:
                    pending = _Flight(cur.index, touch[0], touch[2], touch[3] - next_seat.y)
                pending.observe(t, robot, next_seat, snapped_alpha)
                if t - touch[0] >= hold:
                    sw = swings[-1]
                    sw.t_detach, sw.theta1_detach_deg = touch[0], math.degrees(touch[1])
                    sw.swing_duration = touch[0] - sw.t_catch
                    sw.alpha_detach_deg = math.degrees(touch[2])
                    sw.theta2_min_deg, sw.theta2_max_deg = th2_lo, th2_hi
                    flight, pending = pending, None
            if flight is None:
                theta1_peak = max(theta1_peak, cur.theta)
                if cur.at_stop():
                    t_stop = t if t_stop is None else t_stop
                    if t - t_stop >= sim.stop_hold:
                        outcome, reason = "no_detach", (
                            f"hook still on frame {cur.index} {sim.stop_hold} s after it reached its stop "
                            f"({math.degrees(p.stop_angle):.0f} deg){contact.holding_note}")
                        break
                else:
                    t_stop = None
                    if cur.theta < theta1_peak - math.radians(TURN_BACK_DEG):
                        peak = math.degrees(theta1_peak)
                        if theta1_peak >= p.stop_angle - math.radians(NEAR_STOP_DEG):
                            outcome, reason = "no_detach", (f"frame {cur.index} reached {peak:.1f} deg, near its stop, "
                                                            f"and turned back under the robot{contact.holding_note}")
                        else:
                            outcome, reason = "stalled", (f"frame {cur.index} turned back at {peak:.1f} deg, short of "
                                                          f"its stop, with the robot hooked: too little moment imbalance")
                        break
                if t - swings[-1].t_catch > sim.swing_timeout:
                    outcome, reason = "stalled", f"swing on frame {cur.index} lasted over {sim.swing_timeout} s"
                    break
        else:  # ---- in flight from frame flight.origin ----
            nxt = flight.origin + 1
            if contact.touches(nxt):
                flight.first_touch = t if flight.first_touch is None else flight.first_touch
                if t - flight.first_touch >= hold:  # caught
                    world.set_active(nxt)
                    cur = frames[nxt]
                    swings.append(Swing(nxt, flight.first_touch, math.degrees(cur.theta),
                                        math.degrees(robot.theta2())))
                    th2_lo = th2_hi = swings[-1].theta2_catch_deg
                    flight, t_stop, theta1_peak = None, None, cur.theta
                    touch = (t, cur.theta, robot.alpha, robot.hook_world().y)
                    if nxt == n_frames - 1:
                        outcome, reason = "completed", f"caught by the last frame ({nxt})"
                        break
                    next_seat = frames[nxt + 1].hook_seat_world()
                    closest = math.inf
                    continue
            else:
                flight.first_touch = None
            flight.observe(t, robot, next_seat, snapped_alpha)
            com = robot.com_world()
            if com.y < world.floor_y(com.x) or t - flight.t_detach > sim.flight_timeout:
                outcome, reason = _classify_miss(flight, nxt, half_range, p, sim.min_release_height * units.LENGTH)
                break

        e = None
        if n % sim.check_every == 0:
            e = world.energy()
            th2 = robot.theta2()
            if not (math.isfinite(e) and math.isfinite(th2)) or world.max_speed() > p.max_speed:
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
            closest = min(closest, (robot.hook_world() - next_seat).length)
            bad = _health_check(world.health(), worst, limits)
            if bad:
                outcome, reason = "unstable", bad
                break
            if flight is None:
                th2d = math.degrees(th2)
                th2_lo, th2_hi = min(th2_lo, th2d), max(th2_hi, th2d)
        if trace and n % sim.trace_every == 0:
            rows.append(_trace_row(world, t, robot.theta2(), world.energy() if e is None else e))
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


def _trace_row(world: World, t: float, th2: float, e: float) -> tuple:
    robot, cur = world.robot, world.frames[world.active]
    touching = sorted(world.contact.touching)
    return (t, cur.index, cur.theta, th2, robot.alpha, cur.omega, robot.theta2_rate(), robot.alpha_rate,
            touching[0] if touching else -1, e)


def _classify_miss(flight: _Flight, nxt: int, half_range: float, p, min_release_height: float) -> tuple[str, str]:
    """Name a failed transfer by its cause, in this order:

    1. the arm had less than half its range left at detach -> ``missed_catch`` (spring too stiff:
       it never bent, so it has no motion left);
    2. the hook left the handrail less than ``sim.min_release_height`` above the next handrail ->
       ``fell_short`` (it slipped off before the frame had lifted the robot);
    3. the arm was still swinging when the hook came down to the next handrail -> ``missed_catch``
       (spring too weak for the fall);
    4. the arm was ready: the hook passed behind the handrail -> ``fell_short``, ahead -> ``missed_catch``.
    """
    mm = 1e3 / units.LENGTH
    where = f"after leaving frame {flight.origin}"
    room = flight.alpha_detach - p.alpha_min
    if room < half_range:
        return "missed_catch", (f"{where}: the arm was at {math.degrees(flight.alpha_detach):.0f} deg when the hook "
                                f"let go, with no swing left to reach frame {nxt} (spring too stiff to bend)")
    if flight.height < min_release_height:
        level = (f"only {flight.height * mm:.1f} mm above" if flight.height >= 0
                 else f"{-flight.height * mm:.1f} mm below")
        return "fell_short", (f"{where}: the hook slipped off {level} frame {nxt}'s handrail, before the frame had "
                              f"lifted the robot high enough")
    if flight.crossing is None:
        return "missed_catch", f"{where}: the hook never came down to frame {nxt}'s handrail"
    dx, alpha_cross = flight.crossing
    if flight.t_snap is None or flight.t_snap > flight.t_cross:
        return "missed_catch", (f"{where}: the arm had swung only {math.degrees(flight.alpha_detach - alpha_cross):.0f}"
                                f" deg forward when the hook came down to frame {nxt}'s handrail (spring too weak)")
    if dx < 0:
        return "fell_short", f"{where}: the hook passed {-dx * mm:.1f} mm behind frame {nxt}'s handrail"
    return "missed_catch", f"{where}: the hook passed {dx * mm:.1f} mm ahead of frame {nxt}'s handrail or bounced off"
