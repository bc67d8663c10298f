"""The pymunk world of one scene, composed from parts the way dm_control composes entities.

Always built: the row of :class:`SwingFrame` s, the :class:`Robot`, its leaf spring (the
scene's spring law picks the part), the :class:`HookContact` (the scene's friction law picks
its callback) and the floor. Built only when the scene names it: :class:`AirDrag`. The
``hook: pin`` scene swaps robot, spring and contact for the two-link model's parts
(:class:`RigidRobot`, :class:`NoSpring`, :class:`PinnedHook`).

Frames are simulated only inside a live window around the robot's frame: the one it just
left (still turning to its stopper), its own, and ``effects.live_frames`` ahead. Frames
further back have reached their stop and are retired from the space; frames further ahead
wait at rest and are not in the space yet. The step loop itself has no per-effect branches.
"""

from __future__ import annotations

import pymunk

from .. import units
from ..config import Config
from .drag import AirDrag
from .engine_params import EngineParams, to_engine
from .hook_contact import HookContact, PinnedHook, friction_law
from .leaf_spring import SPRING_LAWS, NoSpring
from .robot import RigidRobot, Robot
from .swing_frame import FLOOR, SwingFrame


class World:
    def __init__(self, cfg: Config):
        self.cfg = cfg
        p: EngineParams = to_engine(cfg)
        self.p = p
        fx = cfg.scene.effects
        space = pymunk.Space()
        space.gravity = (0.0, -p.gravity)
        space.iterations = p.iterations
        space.collision_slop = p.collision_slop
        self.space = space

        self.frames = [SwingFrame(i, p) for i in range(p.frames)]
        if fx.hook == "pin":  # the two-link model built in pymunk
            self.robot = RigidRobot(p)
            self.spring = NoSpring()
            self.contact = PinnedHook(self.robot, self.frames[0])
        else:
            self.robot = Robot(p)
            self.spring = SPRING_LAWS[fx.spring_law](self.robot, p.spring_k, p.alpha_min)
            self.contact = HookContact(self.robot.tip, self.frames,
                                       friction_law(fx.friction, p.mu_s, p.mu_k, p.slip_speed))
        self.robot.add_to(space)
        self.spring.add_to(space)
        self.drag = AirDrag(self.frames, self.robot, p) if fx.drag else None
        self.live_ahead = fx.live_frames
        # The floor follows the row's incline, floor_drop below the frame axes.
        x0, x1 = -2.0 * p.pitch, (p.frames + 1) * p.pitch
        self.floor_a = pymunk.Vec2d(x0, x0 / p.pitch * p.rise - p.floor_drop)
        self.floor_b = pymunk.Vec2d(x1, x1 / p.pitch * p.rise - p.floor_drop)
        floor = pymunk.Segment(space.static_body, self.floor_a, self.floor_b, 1.0)
        floor.collision_type = FLOOR
        space.add(floor)

        self.active = -1
        self._live: list[SwingFrame] = []  # every frame starts parked, at rest
        self._parked_energy = sum(self._body_energy(f.body) for f in self.frames)
        self.set_active(0)
        self.robot.place_hanging(self.frames[0].hook_seat_world(), p.theta2_start, p.alpha_max)
        self.contact.add_to(space)  # after placing: a pin joint anchors where the bodies are
        self.t = 0.0
        self.steps = 0

    # -- live window --
    def set_active(self, i: int) -> None:
        """Make frame i the robot's frame: keep i-1 (still turning), i and live_ahead frames ahead."""
        self.active = i
        lo, hi = max(0, i - 1), min(len(self.frames) - 1, i + self.live_ahead)
        # Frames out of the space do not move: their energy is booked once as they park or leave the
        # park, so neither a check nor a catch costs more on a longer row.
        window = self.frames[lo:hi + 1]
        for f in self._live:
            if not lo <= f.index <= hi:
                f.retire(self.space)
                self._parked_energy += self._body_energy(f.body)
        for f in window:
            if not f.live:
                self._parked_energy -= self._body_energy(f.body)
                f.attach(self.space)
        self._live = window

    def live_frames(self):
        return list(self._live)

    # -- stepping --
    def step(self) -> None:
        self.space.step(self.p.dt)
        self.steps += 1
        self.t = self.steps * self.p.dt  # no accumulated round-off in the clock

    # -- measurements (engine units inside, SI where it says so) --
    def floor_y(self, x: float) -> float:
        a, b = self.floor_a, self.floor_b
        return a.y + (x - a.x) * (b.y - a.y) / (b.x - a.x)

    def energy(self) -> float:
        """Total mechanical energy in joules: kinetic + gravitational + spring, over every frame and the robot.

        Frames outside the space are at rest (ahead) or at their stop (behind): their potential
        energy is constant and still counted, so the total is comparable across window moves.
        """
        e = self.spring.energy() + self._parked_energy
        for f in self._live:
            e += self._body_energy(f.body)
        for b in self.robot.bodies:
            e += self._body_energy(b)
        return units.energy_to_si(e)

    def _body_energy(self, b: pymunk.Body) -> float:
        v = b.velocity
        w = b.angular_velocity
        return (0.5 * (b.mass * (v.x * v.x + v.y * v.y) + b.moment * w * w)
                + b.mass * self.p.gravity * b.local_to_world(b.center_of_gravity).y)

    def spring_capacity(self) -> float:
        """Energy (J) the spring stores fully bent, at alpha_max."""
        return units.energy_to_si(self.spring.capacity(self.p.alpha_max))

    def max_speed(self) -> float:
        return max(b.velocity.length for b in (*self.robot.bodies, *(f.body for f in self._live)))

    def health(self) -> tuple[float, float, float]:
        """How far the solver lets the machine's constraints give, in SI: (joint drift in m: frame
        skewers, robot axle, pinned hook; limit overshoot in rad: frame stoppers, arm stopper;
        hook penetration into a handrail card in m). Near zero in a healthy run."""
        drift = max(self.robot.joint_drift(), self.contact.joint_drift(),
                    max(f.pivot_drift() for f in self._live))
        over = max(self.robot.limit_overshoot(), max(f.limit_overshoot() for f in self._live))
        pen = self.contact.penetration(self._live)
        return units.length_to_si(drift), over, units.length_to_si(pen)

    def geometry(self) -> dict:
        """The machine's fixed geometry in SI, for drawing."""
        s = 1.0 / units.LENGTH
        p = self.p
        return dict(
            axes=[(f.axis.x * s, f.axis.y * s) for f in self.frames],
            faces_local=[[((a.x * s, a.y * s), (b.x * s, b.y * s)) for a, b in self.frames[0].faces_local]],
            La=p.La * s, Lb=p.Lb * s, h=p.h * s, rest_angle=p.rest_angle, stop_angle=p.stop_angle,
            arm_length=p.arm_length * s, torso_com=p.torso_com * s,
            floor=((self.floor_a.x * s, self.floor_a.y * s), (self.floor_b.x * s, self.floor_b.y * s)),
        )

    def pose(self) -> tuple:
        """Current pose in SI: frame angles, torso position and angle, arm angle."""
        s = 1.0 / units.LENGTH
        axle, torso_angle, arm_angle = self.robot.pose()
        return [f.body.angle for f in self.frames], (axle.x * s, axle.y * s), torso_angle, arm_angle
