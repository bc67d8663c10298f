"""A swing frame: a pivoted body with its stopper, counterbalance and notched handrail.

Frame-local coordinates: origin at the rotation axis, +x towards the counterbalance, so
the body angle *is* theta1 (the brief's convention). The handrail (hook seat) is at
(-Lb, 0); the counterbalance is a point mass at (La, h). The stopper skewer is a rotary
limit: the frame turns only between the rest angle (held there by the counterbalance) and
the end stop.

The handrail is the L-shaped card (⌟ in the article's figures) whose inside corner holds the
arm's hook: two card faces meeting at ``notch_opening`` (90 deg for an L). At the rest angle the
corner's bisector points along ``notch_angle`` (world); the hook sits in the corner. As the frame
turns, the L tilts with it, the normal force drops and the hook slides along a face and off its
end: that is the detach (brief, steps 3-4). docs/physics.md says where each value comes from.

The handrail's card (``handrail_mass``) is a point mass at the seat. The skewer's friction in
the card's shaft hole (``pivot_friction``) is a :class:`pymunk.SimpleMotor` at rate 0 whose
torque is capped at the Coulomb torque: the solver holds the frame still up to that torque and
lets it turn against exactly that torque beyond it, with no Python per step. Zero builds no part.
"""

from __future__ import annotations

import math

import pymunk

from ..parts.bodies import frame_body
from ..parts.build import notch_faces
from .engine_params import EngineParams, rigid_body

HOOK = 1  # collision types
HANDRAIL = 2
FLOOR = 3
_NO_SELF = pymunk.ShapeFilter(group=1)  # handrails of different frames never collide with each other


def coulomb_friction(a: pymunk.Body, b: pymunk.Body, torque: float) -> pymunk.SimpleMotor:
    """Dry friction between two bodies turning on a shared axis: a motor that drives their
    relative rate to zero with at most ``torque`` (pymunk caps the impulse at max_force·dt)."""
    motor = pymunk.SimpleMotor(a, b, 0.0)
    motor.max_force = torque
    return motor


class SwingFrame:
    def __init__(self, index: int, p: EngineParams):
        self.index = index
        self.axis = pymunk.Vec2d(index * p.pitch, index * p.rise)
        # frame card (its centre where dT puts it), counterbalance at (La, h), handrail card at the seat: one body
        # (the rule's one home: aero_env/parts/bodies.py, here in engine units)
        m, centre, I_axis = frame_body(p.m_frame, p.frame_com_x, p.I_frame_axis, p.m_cb, p.La, p.h, p.m_handrail,
                                       p.Lb)
        cog = pymunk.Vec2d(*centre)
        body = rigid_body(m, I_axis - m * cog.length_squared, "swing frame",
                          "design.m1, design.dT, design.m3, design.La, design.Lb")
        # Order matters in pymunk: centre of gravity, then angle, then position (angle turns about the cog).
        body.center_of_gravity = cog
        body.angle = p.rest_angle
        body.position = self.axis
        self.body = body
        self.rest_angle, self.stop_angle = p.rest_angle, p.stop_angle

        self.hook_seat_local = pymunk.Vec2d(-p.Lb, 0.0)  # where the hook's centre sits in the corner
        # the L's two faces, each from the corner along the other face's normal (one home: aero_env/parts/build.py)
        faces = notch_faces(p.Lb, p.notch_angle, p.notch_opening, p.rest_angle, p.notch_back_face,
                            p.notch_front_face, p.rail_radius + p.hook_radius)
        self.faces_local = tuple((pymunk.Vec2d(*a), pymunk.Vec2d(*b)) for a, b in faces)
        self.rail_radius = p.rail_radius
        # each face as (start x, start y, unit direction x, y, length), for the penetration monitor and
        # the friction switch
        self.faces = tuple((a.x, a.y, *((b - a) / (b - a).length), (b - a).length) for a, b in self.faces_local)
        self.shapes = []
        for a, b in self.faces_local:
            seg = pymunk.Segment(body, a, b, p.rail_radius)
            seg.collision_type = HANDRAIL
            seg.filter = _NO_SELF
            seg.friction = 1.0  # the hook contact sets the pair's coefficient (see hook_contact)
            self.shapes.append(seg)
        # The frame owns the static anchor (the skewers) so it can join and leave a space whole.
        self.anchor = pymunk.Body(body_type=pymunk.Body.STATIC)
        self.constraints = [
            pymunk.PivotJoint(self.anchor, body, self.axis, (0.0, 0.0)),
            pymunk.RotaryLimitJoint(self.anchor, body, p.rest_angle, p.stop_angle),
        ]
        if p.pivot_friction > 0.0:
            self.constraints.append(coulomb_friction(self.anchor, body, p.pivot_friction))
        self.live = False

    # -- presence in the space (frames outside the live window cost nothing) --
    def attach(self, space: pymunk.Space) -> None:
        if not self.live:
            space.add(self.anchor, self.body, *self.shapes, *self.constraints)
            self.live = True

    def retire(self, space: pymunk.Space) -> None:
        if self.live:
            space.remove(self.anchor, self.body, *self.shapes, *self.constraints)
            self.live = False

    # -- state --
    @property
    def theta(self) -> float:
        return self.body.angle

    @property
    def omega(self) -> float:
        return self.body.angular_velocity

    def hook_seat_at(self, state: tuple) -> tuple[float, float]:
        """The hook seat in the world from a read state (x, y, angle, ...): ``hook_seat_world`` without
        a call into pymunk, in the double operations of Munk2D's cpTransformPoint (the body's transform
        is (cos, -sin, x; sin, cos, y) at its angle), so the two agree bit for bit."""
        x, y, a = state[0], state[1], state[2]
        c, s = math.cos(a), math.sin(a)
        sx, sy = self.hook_seat_local
        return c * sx - s * sy + x, s * sx + c * sy + y

    def hook_seat_world(self) -> pymunk.Vec2d:
        return self.body.local_to_world(self.hook_seat_local)

    # -- health: how far the solver lets the skewers give (engine units, radians) --
    def health(self, state: tuple) -> tuple[float, float]:
        """(pivot drift, limit overshoot) from a read state (x, y, angle, ...): how far the frame's
        axis point has left its skewer, and how far it has turned past its stopper or below its
        rest angle."""
        x, y, a = state[0], state[1], state[2]
        return math.hypot(x - self.axis.x, y - self.axis.y), max(0.0, a - self.stop_angle, self.rest_angle - a)

    def penetration(self, state: tuple, point: tuple[float, float], radius: float) -> float:
        """How deep a circle at world ``point`` sits inside this frame's handrail card (0 when
        outside), from the frame's read state; pure geometry in the frame's own coordinates."""
        x, y, a = state[0], state[1], state[2]
        c, s = math.cos(a), math.sin(a)
        dx, dy = point[0] - x, point[1] - y
        px, py = c * dx + s * dy, -s * dx + c * dy  # the point in frame-local coordinates
        depth = 0.0
        for (ax, ay, ux, uy, length) in self.faces:
            along = min(max((px - ax) * ux + (py - ay) * uy, 0.0), length)
            depth = max(depth, radius + self.rail_radius - math.hypot(px - ax - along * ux, py - ay - along * uy))
        return depth
