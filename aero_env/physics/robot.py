"""The robot: a torso (with its coin weights) and one arm on an axle, with the hook at the arm tip.

Torso-local coordinates: origin at the axle, the torso hangs along -y to its centre of mass
at (0, -torso_com). Arm-local coordinates: origin at the axle, +x along the arm to the hook
tip at (arm_length, 0). The arm angle alpha is the interior angle at the axle between the
torso and the arm (see :func:`aero_env.parts.bodies.part_layout`); the stopper limits it to
[alpha_min, alpha_max] and the leaf spring (a separate part) pushes it toward alpha_min.

Hanging makes the robot's weight open alpha against the spring until the alpha_max limit
(the "fully bent" spring); in flight the spring snaps the arm forward to alpha_min.

Masses, centres and inertias are the parts' own (:class:`aero_env.parts.bodies.RobotParts`): a card
torso plate with the coins on it, and the arm, a plate from behind the axle to the hook. ``axle_friction`` > 0 adds the
axle's dry friction as a capped motor (:func:`swing_frame.coulomb_friction`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import pymunk

from ..parts.bodies import part_layout
from .engine_params import EngineParams, rigid_body
from .swing_frame import HOOK, coulomb_friction

_ROBOT = pymunk.ShapeFilter(group=2)


class RobotMeasure(NamedTuple):
    hook: tuple[float, float]  # engine units
    com: tuple[float, float]
    alpha: float  # rad (NaN for the rigid robot)
    drift: float  # axle separation, engine units
    overshoot: float  # alpha past its stopper, rad


class Robot:
    def __init__(self, p: EngineParams):
        self.p = p
        self.torso = rigid_body(p.m_torso, p.I_torso, "torso", "design.m2, design.coin_mass, design.Ld")
        self.torso.center_of_gravity = (0.0, -p.torso_com)
        self.arm = rigid_body(p.m_arm, p.I_arm, "arm", "design.arm_mass, design.arm_length")
        self.arm.center_of_gravity = (p.arm_com, 0.0)
        self.hook_local = pymunk.Vec2d(p.arm_length, 0.0)
        self.tip = pymunk.Circle(self.arm, p.hook_radius, self.hook_local)
        self.tip.collision_type = HOOK
        self.tip.filter = _ROBOT
        self.tip.friction = 1.0
        # The arm's body angle minus the torso's is alpha - 90 deg (arm +x vs torso -y).
        self.axle = pymunk.PivotJoint(self.torso, self.arm, (0.0, 0.0), (0.0, 0.0))
        self.arm_stop = pymunk.RotaryLimitJoint(self.torso, self.arm, p.alpha_min - math.pi / 2,
                                                p.alpha_max - math.pi / 2)
        self.joints = [self.axle, self.arm_stop]
        if p.axle_friction > 0.0:
            self.joints.append(coulomb_friction(self.torso, self.arm, p.axle_friction))

    def add_to(self, space: pymunk.Space) -> None:
        space.add(self.torso, self.arm, self.tip, *self.joints)

    def place_hanging(self, hook_world: pymunk.Vec2d, theta2: float, alpha: float) -> None:
        """Put the hook tip at ``hook_world`` with the robot line (centre -> hook) at angle theta2."""
        p = self.p
        hook, _, _, com = part_layout(p.arm_length, p.torso_com, p.m_arm, p.m_torso, alpha, p.arm_com)
        local_line = pymunk.Vec2d(hook[0] - com[0], hook[1] - com[1])
        rot = theta2 - local_line.angle
        self.torso.angle = rot
        self.torso.position = hook_world - pymunk.Vec2d(*hook).rotated(rot)
        self.arm.angle = rot + alpha - math.pi / 2
        self.arm.position = self.torso.position
        for b in (self.torso, self.arm):
            b.velocity = (0.0, 0.0)
            b.angular_velocity = 0.0

    # -- state --
    @property
    def alpha(self) -> float:
        return self.arm.angle - self.torso.angle + math.pi / 2

    @property
    def alpha_rate(self) -> float:
        return self.arm.angular_velocity - self.torso.angular_velocity

    def hook_world(self) -> pymunk.Vec2d:
        return self.arm.local_to_world(self.hook_local)

    def com_world(self) -> pymunk.Vec2d:
        t, a = self.torso, self.arm
        return (t.local_to_world(t.center_of_gravity) * t.mass + a.local_to_world(a.center_of_gravity) * a.mass) / (
            t.mass + a.mass)

    def com_velocity(self) -> pymunk.Vec2d:
        t, a = self.torso, self.arm
        return (t.velocity * t.mass + a.velocity * a.mass) / (t.mass + a.mass)

    def theta2(self) -> float:
        """Angle of the robot line from its centre of mass to the hook (90 deg: hanging straight down)."""
        return (self.hook_world() - self.com_world()).angle

    def theta2_rate(self) -> float:
        r = self.hook_world() - self.com_world()
        v = self.arm.velocity_at_local_point(self.hook_local) - self.com_velocity()
        return r.cross(v) / r.length_squared

    @property
    def bodies(self):
        return (self.torso, self.arm)

    def drag_strips(self):
        """(body, start, end) of each link that feels air drag: the torso card strip and the arm."""
        return [(self.torso, (0.0, 0.0), (0.0, -self.p.torso_length)), (self.arm, (0.0, 0.0), (self.p.arm_length, 0.0))]

    def pose(self):
        """(axle position, torso angle, arm angle), engine units."""
        return self.torso.position, self.torso.angle, self.arm.angle

    # -- from one read of its bodies --
    def measure(self, states) -> RobotMeasure:
        """Hook, centre of mass, alpha and health from the read states of (torso, arm)."""
        tx, ty, ta = states[0][:3]
        ax, ay, aa = states[1][:3]
        p = self.p
        ca, sa = math.cos(aa), math.sin(aa)
        hook = (ax + p.arm_length * ca, ay + p.arm_length * sa)
        # torso cog at (0, -torso_com) and arm cog at (arm_com, 0) in their bodies' frames
        mt, ma = p.m_torso, p.m_arm
        com = ((mt * (tx + p.torso_com * math.sin(ta)) + ma * (ax + p.arm_com * ca)) / (mt + ma),
               (mt * (ty - p.torso_com * math.cos(ta)) + ma * (ay + p.arm_com * sa)) / (mt + ma))
        alpha = aa - ta + math.pi / 2
        # the axle: both bodies have their origin there; the stopper: alpha within its limits
        return RobotMeasure(hook, com, alpha, math.hypot(tx - ax, ty - ay),
                            max(0.0, alpha - p.alpha_max, p.alpha_min - alpha))


class RigidRobot:
    """The two-link model's robot for the pinned-hook scene: one rigid body with the parts' mass,
    centre and inertia held at alpha_max (two_link's ``robot="parts"`` convention; the handrail's
    card stays on the frame). No arm, no spring (alpha is not modelled)."""

    def __init__(self, p: EngineParams):
        self.p = p
        self.body = rigid_body(p.m_robot, p.I2, "rigid robot", "design.m2, design.Ld, design.arm_length")
        self.body.center_of_gravity = (-p.Lc, 0.0)  # local +x points from the centre to the hook
        self.hook_local = pymunk.Vec2d(0.0, 0.0)
        self.alpha = math.nan
        self.alpha_rate = math.nan

    def add_to(self, space: pymunk.Space) -> None:
        space.add(self.body)

    def place_hanging(self, hook_world: pymunk.Vec2d, theta2: float, _alpha: float) -> None:
        self.body.angle = theta2
        self.body.position = hook_world
        self.body.velocity, self.body.angular_velocity = (0.0, 0.0), 0.0

    def hook_world(self) -> pymunk.Vec2d:
        return self.body.position

    def com_world(self) -> pymunk.Vec2d:
        return self.body.local_to_world(self.body.center_of_gravity)

    def theta2(self) -> float:
        return self.body.angle

    def theta2_rate(self) -> float:
        return self.body.angular_velocity

    @property
    def bodies(self):
        return (self.body,)

    def drag_strips(self):
        """The two-link model's robot drag: the link from the joint (hook) to the centre, l in [0, Lc]."""
        return [(self.body, (0.0, 0.0), (-self.p.Lc, 0.0))]

    def pose(self):
        """Drawn as a torso hanging from the hook towards the centre of mass."""
        return self.body.position, self.body.angle + 1.5 * math.pi, self.body.angle

    def measure(self, states) -> RobotMeasure:
        """Hook and centre of mass from the body's read state; one rigid body has no joint or stopper."""
        x, y, a = states[0][:3]
        com = (x - self.p.Lc * math.cos(a), y - self.p.Lc * math.sin(a))
        return RobotMeasure((x, y), com, math.nan, 0.0, 0.0)
