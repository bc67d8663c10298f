"""Quadratic air drag, an effect a scene switches on (the paper finds it negligible).

Each dragged body carries a strip (a line segment in body coordinates with a projected
width w). The drag on an element dl is dF = -rho·Cd/2 · w · |v_n|·v_n dl, v_n the velocity
normal to the strip there; :func:`aero_env.drag_law.strip_drag` integrates it exactly, split
where v_n changes sign. For a frame turning about its axis this is exactly the paper's
tau1 = -(1/8)·rho·Cd·A·w|w|·(La⁴+Lb⁴). The force and torque are added through the body's
velocity function; bodies without drag keep pymunk's own C update and pay nothing.
"""

from __future__ import annotations

import pymunk

from ..drag_law import strip_drag


class DragStrip:
    def __init__(self, body: pymunk.Body, p0, p1, width: float, coeff: float):
        self.body = body
        self.p0, self.p1 = pymunk.Vec2d(*p0), pymunk.Vec2d(*p1)
        self.k = coeff * width
        body.velocity_func = self._update_velocity

    def force_and_torque(self):
        """Drag force (world) and torque about the body's centre of gravity, engine units."""
        b = self.body
        p0w, p1w = b.local_to_world(self.p0), b.local_to_world(self.p1)
        length = (p1w - p0w).length
        normal = ((p1w - p0w) / length).perpendicular()
        v0 = b.velocity_at_world_point(p0w).dot(normal)
        v1 = b.velocity_at_world_point(p1w).dot(normal)
        f, m = strip_drag(v0, v1, length)
        f, m = f * self.k, m * self.k
        cog = b.local_to_world(b.center_of_gravity)
        # moment about the strip start (normal force times distance along the strip), moved to the cog
        return normal * f, m + (p0w - cog).cross(normal) * f

    def _update_velocity(self, body, gravity, damping, dt):
        f, t = self.force_and_torque()
        body.force += f
        body.torque += t
        pymunk.Body.update_velocity(body, gravity, damping, dt)


class AirDrag:
    """Adds a drag strip to each frame (handrail end to counterbalance end) and to the robot's links."""

    def __init__(self, frames, robot, p):
        self.strips = [DragStrip(f.body, (-p.Lb, 0.0), (p.La, 0.0), p.frame_width, p.drag_coeff) for f in frames]
        self.strips += [DragStrip(body, a, b, p.robot_width, p.drag_coeff) for body, a, b in robot.drag_strips()]
