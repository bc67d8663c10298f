"""What the runner watches besides the events: energy, the health of the constraints, a
finite state, the hook tunnelling through a handrail card between two steps, and the recording
of the trace and the animation poses.

Every check reads the world once (:meth:`World.sample`) and compares it with limits that
:mod:`engine_params` converted from the config; nothing here converts units.
"""

from __future__ import annotations

import math

from .. import units
from .body_state import handle, pose
from .world import World

TRACE_COLUMNS = ("t", "frame", "theta1", "theta2", "alpha", "omega1", "omega2", "alpha_rate", "contact", "energy")

_HEALTH_WORDS = (
    ("joint drift", "sim.max_joint_drift", 1e3, "mm", "a skewer or the arm's axle came apart"),
    ("limit overshoot", "sim.max_limit_overshoot_deg", 180 / math.pi, "deg", "a body turned through its stopper"),
    ("penetration", "sim.max_penetration (as a depth)", 1e3, "mm", "the hook sank into (or through) a handrail card"),
)


class Monitors:
    """The energy and health of a run, checked on the check cadence; the first breach ends it."""

    def __init__(self, world: World, sim):
        self.world = world
        d = world.cfg.design
        # The energy scale of the machine: the robot and counterbalance falling the frame's length, plus
        # what the fully bent spring stores (a stiff spring moves far more energy than gravity does).
        self.e_tol = sim.energy_tolerance * ((d.m2 + d.m3) * units.GRAVITY * (d.La + d.Lb) + world.spring_capacity())
        # the sample's health is in SI, so are its limits (penetration: a fraction of hook + half the card)
        self.limits = (sim.max_joint_drift, math.radians(sim.max_limit_overshoot_deg),
                       sim.max_penetration * (d.hook_radius + 0.5 * d.handrail_thickness))
        self.max_speed = world.p.max_speed
        self.e0 = world.energy()
        self.e_min, self.max_gain, self.max_rise = self.e0, 0.0, 0.0
        self.worst = [0.0, 0.0, 0.0]  # joint drift (m), limit overshoot (rad), penetration (m)

    def check(self, sample) -> str | None:
        """Why the run is unstable, or None."""
        e, th2 = sample.energy, sample.theta2
        if not (math.isfinite(e) and math.isfinite(th2)) or sample.max_speed > self.max_speed:
            return "non-finite or exploding state (a body exceeded sim.max_speed)"
        self.max_gain = max(self.max_gain, e - self.e0)
        self.e_min = min(self.e_min, e)
        self.max_rise = max(self.max_rise, e - self.e_min)
        if self.max_rise > self.e_tol:
            return (f"mechanical energy rose by {self.max_rise:.3g} J, above the tolerance {self.e_tol:.3g} J "
                    f"(sim.energy_tolerance): numerical error (try a smaller sim.dt or more sim.iterations)")
        return self._health(sample.health)

    def went_through(self, depth: float) -> None:
        """The hook went through a card between two checks: it sank at least ``depth`` (m) into it."""
        self.worst[2] = max(self.worst[2], depth)

    def _health(self, measured: tuple) -> str | None:
        """Update the worst values; name the first constraint that gave more than its tolerance."""
        for i, (v, lim) in enumerate(zip(measured, self.limits)):
            if v > self.worst[i]:
                self.worst[i] = v
            if v > lim:
                what, key, scale, unit, meaning = _HEALTH_WORDS[i]
                return (f"{what} {v * scale:.3g} {unit} above {key} = {lim * scale:.3g} {unit}: {meaning}; "
                        f"the engine could not hold the constraint (try a smaller sim.dt or more sim.iterations)")
        return None

    def energy(self, e_final: float) -> dict:
        return dict(initial=self.e0, final=e_final, max_gain=max(self.max_gain, e_final - self.e0),
                    max_rise=self.max_rise)

    def health(self) -> dict:
        return dict(joint_drift=self.worst[0], limit_overshoot_deg=math.degrees(self.worst[1]),
                    penetration=self.worst[2])


class TunnelWatch:
    """Whether the hook's centre crossed the middle line of a handrail card between two runner steps.

    The contact keeps the hook's centre at least ``hook_radius`` + half the card from the card's middle line,
    so a centre on the other side of that line went through the card: in one step the hook moved farther than
    the contact can see (pymunk finds contacts from the bodies' positions at each step's end, and a card
    1 mm thick with a 1 mm hook leaves 3 mm across which the centre is in contact). The penetration monitor
    cannot show it: it reads the depth after the step, and a hook that went through reads as shallow on the far
    side. Watched every runner step from the detach until the next frame's catch commits (the flight and the
    catch: where the hook meets a card at speed), against the next frame's two faces, in that frame's own
    coordinates at each step (it may be turning), with the hook's centre read from the arm's body."""

    def __init__(self, world: World, frame):
        self.frame = frame
        self.arm_c, self.frame_c = handle(world.robot.arm), handle(frame.body)  # read every step (body_state)
        self.tip = tuple(world.robot.hook_local)
        self.faces = frame.faces  # (start x, y, unit direction x, y, length), the card's middle line, frame-local
        self.clearance = world.p.hook_radius + frame.rail_radius
        self.prev: tuple[float, float] | None = None
        self.hook = (math.nan, math.nan)  # the hook's centre (world, engine units) at the last step
        self.crossed = False

    def step(self) -> str | None:
        """After a runner step: why the run is unstable (the hook went through a card), or None."""
        ax, ay, a = pose(self.arm_c)
        tx, ty = self.tip
        ca, sa = math.cos(a), math.sin(a)
        hx, hy = self.hook = ca * tx - sa * ty + ax, sa * tx + ca * ty + ay  # the hook's centre, world
        fx, fy, b = pose(self.frame_c)
        cb, sb = math.cos(b), math.sin(b)
        lx, ly = cb * (hx - fx) + sb * (hy - fy), -sb * (hx - fx) + cb * (hy - fy)  # ... in the frame
        prev, self.prev = self.prev, (lx, ly)
        if prev is None:
            return None
        px, py = prev
        for x0, y0, ux, uy, length in self.faces:
            d0 = (px - x0) * uy - (py - y0) * ux  # signed distance from the card's middle line
            d1 = (lx - x0) * uy - (ly - y0) * ux
            if d0 * d1 < 0.0:
                f = d0 / (d0 - d1)
                along = (px + f * (lx - px) - x0) * ux + (py + f * (ly - py) - y0) * uy
                if 0.0 <= along <= length:
                    self.crossed = True
                    moved = math.hypot(lx - px, ly - py)
                    return (f"the hook's centre went through frame {self.frame.index}'s handrail card between two "
                            f"steps: it moved {units.length_to_si(moved) * 1e3:.2f} mm in one step and crossed the "
                            f"card's middle line, from which the contact keeps it hook_radius + half the card = "
                            f"{units.length_to_si(self.clearance) * 1e3:.2f} mm away; the contact never saw it "
                            f"(the step is too large: try a smaller sim.dt)")
        return None

    def depth(self) -> float:
        """How deep (m) a hook whose centre reached the card's middle line sank into the card: its penetration."""
        return units.length_to_si(self.clearance)


class Recorder:
    """The trace (every ``sim.trace_every`` runner steps, and the run's last step) and the animation poses."""

    def __init__(self, world: World, trace: bool, trace_every: int, pose_steps: int):
        self.world = world
        self.trace, self.trace_every, self.pose_steps = trace, trace_every, pose_steps
        self.recording = bool(trace or pose_steps)  # False: after_step would do nothing, the runner skips it
        self.rows: list[tuple] = []
        self.poses: list = [(0.0, *world.pose())] if pose_steps else []

    def after_step(self, n: int, t: float, sample) -> None:
        if self.trace and n % self.trace_every == 0:
            self.rows.append(self._row(t, sample or self.world.sample()))
        if self.pose_steps and n % self.pose_steps == 0:
            self.poses.append((t, *self.world.pose()))

    def finish(self) -> None:
        # the run's last moment, whatever the cadence: the state its ending was decided on (a catch that carried
        # the robot, a committed detach) is in the record
        if self.trace and (not self.rows or self.rows[-1][0] < self.world.t):
            self.rows.append(self._row(self.world.t, self.world.sample()))
        if self.pose_steps and self.poses[-1][0] < self.world.t:
            self.poses.append((self.world.t, *self.world.pose()))

    def _row(self, t: float, sample) -> tuple:
        world = self.world
        robot, cur = world.robot, world.frames[world.active]
        touching = sorted(world.contact.touching)
        return (t, cur.index, cur.theta, sample.theta2, robot.alpha, cur.omega, robot.theta2_rate(), robot.alpha_rate,
                touching[0] if touching else -1, sample.energy)

    def trace_dict(self):
        import numpy as np

        if not (self.trace and self.rows):
            return None
        return {c: np.array(v) for c, v in zip(TRACE_COLUMNS, zip(*self.rows))}
