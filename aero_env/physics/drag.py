"""Quadratic air drag, an effect a scene switches on (the paper finds it negligible).

Each dragged body carries a strip (a line segment in body coordinates with a projected
width w). The drag on an element dl is dF = -rho·Cd/2 · w · |v_n|·v_n dl, v_n the velocity
normal to the strip there. On a rigid body v_n is linear along the strip, so the integral is
split where v_n changes sign (the brief's remark on tau2: the paper expands it for one sign
only) and each piece, a cubic, is integrated exactly by 2-point Gauss-Legendre quadrature.
For a frame turning about its axis this gives exactly tau1 = -(1/8)·rho·Cd·A·w|w|·(La⁴+Lb⁴).
The force and torque are added through the body's velocity function; bodies without drag
keep pymunk's own C update and pay nothing.
"""

from __future__ import annotations

import pymunk

_G = 0.5773502691896257  # 2-point Gauss-Legendre nodes are +-1/sqrt(3), weights 1


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
        axis = (p1w - p0w) / length
        normal = axis.perpendicular()
        cog = b.local_to_world(b.center_of_gravity)
        v0 = b.velocity_at_world_point(p0w).dot(normal)
        v1 = b.velocity_at_world_point(p1w).dot(normal)
        cuts = [0.0, length]
        if v0 * v1 < 0.0:  # v_n changes sign inside the strip: integrate each side on its own
            cuts.insert(1, length * v0 / (v0 - v1))
        r0 = (p0w - cog).cross(normal)  # lever of a normal force at the strip's start
        force = torque = 0.0
        for a, c in zip(cuts[:-1], cuts[1:]):
            half, mid = (c - a) / 2.0, (c + a) / 2.0
            for l in (mid - half * _G, mid + half * _G):
                vn = v0 + (v1 - v0) * l / length
                f = -self.k * vn * abs(vn) * half
                force += f
                torque += (r0 + l * axis.cross(normal)) * f
        return normal * force, torque

    def _update_velocity(self, body, gravity, damping, dt):
        f, t = self.force_and_torque()
        body.force += f
        body.torque += t
        pymunk.Body.update_velocity(body, gravity, damping, dt)


class AirDrag:
    """Adds a drag strip to each frame (handrail end to counterbalance end) and to torso and arm."""

    def __init__(self, frames, robot, p):
        self.strips = [DragStrip(f.body, (-p.Lb, 0.0), (p.La, 0.0), p.frame_width, p.drag_coeff) for f in frames]
        self.strips.append(DragStrip(robot.torso, (0.0, 0.0), (0.0, -2.0 * p.torso_com), p.robot_width, p.drag_coeff))
        self.strips.append(DragStrip(robot.arm, (0.0, 0.0), (p.arm_length, 0.0), p.robot_width, p.drag_coeff))
